//! Smoothing-length evolution (thesis (2-15), (2-16); Liu's h_upgrade):
//! from density h_i = h0_i (ρ0_i/ρ_i)^{1/d}; rate dh_i/dt = −(h_i/(ρ_i d)) Dρ_i/Dt (m/s), with
//! Dρ_i/Dt the continuity sum; h_i ← h_i + θ Δt dh_i/dt; both capped at h_max (m; `f64::MAX` = no
//! cap, `sph.h_max_ratio`): a particle left alone in a rarefaction (the centre of a point blast)
//! would otherwise take every particle of the domain as its neighbour. Axisymmetric (RZ) geometry:
//! h follows the particle spacing in the r-z plane, so the rate reads the plane part of Dρ/Dt (the
//! geometry module adds the hoop term −ρ v_r/r after it) and h from density is h0 (η0/η)^{1/2},
//! η = ρ r (∝ the planar density of the ring masses), with ρ0 r0 kept in `rho0`. Fortran twin:
//! `sph_smoothing.f90`.
//! Tier: 0 ULP in 1D and 2D (division, √), and in 3D (`pow`, the same C library on both sides).

mod ffi;
#[cfg(test)]
mod parity;
mod rust;

use super::{Backend, Contribution, Module, Phase, PlanCtx, Stage, Tolerance, Twin};
use crate::case::SmoothingKind;
use crate::state::{Clock, Field, Particles, Work};

/// `sph_smoothing_density`: h = h0 (ρ0/ρ)^{1/d} of the first `h.len()` particles.
pub struct FromDensity<'a> {
    pub dim: usize,
    pub rho: &'a [f64],
    pub h0: &'a [f64],
    /// ρ0 (kg/m³); axisymmetric: ρ0 r0 (kg/m²).
    pub rho0: &'a [f64],
    /// Axisymmetric: 1/r* (1/m) of the geometry module; empty in plane geometry.
    pub rinv: &'a [f64],
    /// Cap on h (m; `f64::MAX` = none).
    pub hmax: f64,
    pub h: &'a mut [f64],
}

/// `sph_smoothing_rate`: dh/dt of the first `dhdt.len()` particles.
pub struct Rate<'a> {
    pub dim: usize,
    pub rho: &'a [f64],
    pub h: &'a [f64],
    pub drho: &'a [f64],
    pub dhdt: &'a mut [f64],
}

/// `sph_smoothing_advance`: h += θ Δt dh/dt for the first `dhdt.len()` particles.
pub struct Advance<'a> {
    pub dt: f64,
    pub theta: f64,
    /// Cap on h (m; `f64::MAX` = none).
    pub hmax: f64,
    pub dhdt: &'a [f64],
    pub h: &'a mut [f64],
}

impl Twin for FromDensity<'_> {
    fn rust(&mut self) {
        rust::from_density(self)
    }
    fn fortran(&mut self) {
        ffi::from_density(self)
    }
}

impl Twin for Rate<'_> {
    fn rust(&mut self) {
        rust::rate(self)
    }
    fn fortran(&mut self) {
        ffi::rate(self)
    }
}

impl Twin for Advance<'_> {
    fn rust(&mut self) {
        rust::advance(self)
    }
    fn fortran(&mut self) {
        ffi::advance(self)
    }
}

/// The three stages of the module.
enum Which {
    FromDensity,
    Rate,
    Advance(f64),
}

/// A stage of the smoothing module (real particles only).
pub struct SmoothingStage {
    which: Which,
    /// Axisymmetric geometry.
    rz: bool,
    /// Cap on h (m; `f64::MAX` = none).
    hmax: f64,
}

impl Stage for SmoothingStage {
    fn module(&self) -> Module {
        Module::Smoothing
    }
    fn name(&self) -> &'static str {
        match self.which {
            Which::FromDensity => "smoothing.from_density",
            Which::Rate => "smoothing.rate",
            Which::Advance(_) => "smoothing.advance",
        }
    }
    fn reads(&self) -> &[Field] {
        match self.which {
            Which::FromDensity if self.rz => &[Field::Rho, Field::Rinv],
            Which::FromDensity => &[Field::Rho],
            Which::Rate => &[Field::Rho, Field::H, Field::Drho],
            Which::Advance(_) => &[Field::Dhdt],
        }
    }
    fn writes(&self) -> &[Field] {
        match self.which {
            Which::FromDensity | Which::Advance(_) => &[Field::H],
            Which::Rate => &[Field::Dhdt],
        }
    }
    fn register(&self, p: &mut Particles) {
        if let Which::FromDensity = self.which {
            let n = p.nreal;
            p.h0 = p.h[..n].to_vec();
            p.rho0 = p.rho[..n].to_vec();
            if self.rz {
                // η0 = ρ0 r0*, r* = max(|r|, h/4) as the geometry module takes it
                for i in 0..n {
                    let mut rs = p.x[2 * i].abs();
                    if rs < 0.25 * p.h[i] {
                        rs = 0.25 * p.h[i];
                    }
                    p.rho0[i] *= rs;
                }
            }
        }
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        if let Which::Rate = self.which {
            w.dhdt.resize(p.nreal, 0.0);
        }
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, k: &Clock) {
        let (dim, n) = (p.dim, p.nreal);
        match self.which {
            Which::FromDensity => {
                let rinv: &[f64] = if self.rz { &w.rinv[..n] } else { &[] };
                let (rho, h0, rho0, hmax) = (&p.rho[..n], &p.h0[..], &p.rho0[..], self.hmax);
                FromDensity { dim, rho, h0, rho0, rinv, hmax, h: &mut p.h[..n] }.run(b)
            }
            Which::Rate => Rate { dim, rho: &p.rho[..n], h: &p.h[..n], drho: &w.drho[..n], dhdt: &mut w.dhdt }.run(b),
            Which::Advance(theta) => {
                Advance { dt: k.dt, theta, hmax: self.hmax, dhdt: &w.dhdt, h: &mut p.h[..n] }.run(b)
            }
        }
    }
    fn tolerance(&self) -> Tolerance {
        Tolerance { ulp: 0, why: "h from density in 3D calls pow: both sides take it from the same C library" }
    }
}

/// h from the density (after it), or dh/dt with the rates and the update after the advance.
pub fn plan(ctx: &PlanCtx) -> Contribution {
    let sph = &ctx.case.sph;
    let mut why = format!("{:?}", sph.smoothing).to_lowercase();
    let rz = ctx.case.axisymmetric();
    // the cap: a multiple of the largest initial h
    let h0max = ctx.h0.iter().cloned().fold(0.0, f64::max);
    let hmax = sph.h_max_ratio.map_or(f64::MAX, |r| r * h0max);
    if let Some(r) = sph.h_max_ratio {
        why += &format!(", h at most {r} h0");
    }
    let st = |which| Box::new(SmoothingStage { which, rz, hmax }) as Box<dyn Stage>;
    match sph.smoothing {
        SmoothingKind::Constant => Contribution::skip(why),
        SmoothingKind::Density => Contribution::run(why, vec![(Phase::Smooth, st(Which::FromDensity))]),
        SmoothingKind::Rate => Contribution::run(
            why,
            vec![(Phase::Rates, st(Which::Rate)), (Phase::Correct, st(Which::Advance(sph.theta)))],
        ),
    }
}
