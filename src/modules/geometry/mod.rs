//! The axisymmetric (RZ) geometry: `geometry = "axisymmetric"`, dim = 2, x = r ≥ 0 (the radius),
//! y = z (along the axis). Area-weighted RZ SPH (Brookshaw 2003; the form of LLNL Spheral's RZ
//! hydrodynamics; docs/theory.md §16): a particle is a ring of mass m (kg) at radius r; the pair
//! sums of every module are the plane ones with the planar (area) mass μ = m/(2πr) (kg/m) in
//! place of m, so that the 2D kernel, normalised in (r, z), estimates the volumetric density; the
//! hoop terms are added per particle:
//!
//! - continuity: Dρ/Dt += −ρ v_r/r (kg m⁻³ s⁻¹), after the plane rate (and after dh/dt, which
//!   follows the plane spacing);
//! - momentum: Dv_r/Dt += (τ_rr − τ_θθ)/(ρ r), Dv_z/Dt += τ_rz/(ρ r) (m/s²; the pressure has no
//!   hoop term: ρ Dv/Dt = −∇p is the plane gradient in cylindrical coordinates);
//! - energy: De/Dt += −(p/ρ) v_r/r (W/kg) is not a term of its own: the force and viscosity pair
//!   sums read v_i − (r_j/r_i) v_j in place of v_ij, which holds it and conserves the total energy
//!   exactly (the work of each pair's forces on the rings); the deviatoric hoop work τ_θθ v_r/(rρ)
//!   is part of the strength module's τ:ε̇/ρ, whose ε̇_θθ = v_r/r;
//!
//! with 1/r taken as 1/r*, r* = max(|r|, h/4) (the axis is a mirror: reflective ghosts, whose
//! r < 0 and |r| is their source's; a ghost across the axis gets 1/r* < 0, and in its pairs the
//! force and viscosity give the real ring the work of the ghost's force on it, theory.md §16).
//! Fortran twin: `sph_geometry.f90`.

mod ffi;
#[cfg(test)]
mod parity;
mod rust;

use super::param::NSTR;
use super::{Backend, Contribution, Module, Phase, PlanCtx, Slots, Stage, Terms, Twin};
use crate::case::DensityKind;
use crate::state::{Clock, Field, Particles, Work};

/// `sph_geometry_ring`: 1/r* (1/m) and the planar mass μ = m/(2πr*) (kg/m) of every particle
/// (ntotal = `mass.len()`), r* = max(|x_0|, h/4). A mirror across the axis (index ≥ `nreal`,
/// x_0 < 0) gets 1/r* < 0, the sign the energy sums of the force and viscosity read.
pub struct Ring<'a> {
    pub dim: usize,
    /// The real particles, first in the arrays; the mirrors follow them.
    pub nreal: usize,
    pub x: &'a [f64],
    pub h: &'a [f64],
    pub mass: &'a [f64],
    pub rinv: &'a mut [f64],
    pub pmass: &'a mut [f64],
}

/// `sph_geometry_hoop`: the hoop acceleration of the deviatoric stress (m/s², dim × n) of the
/// first n = `dvdt.len()`/dim particles: (τ_rr − τ_θθ)/(ρ r*), τ_rz/(ρ r*).
pub struct Hoop<'a> {
    pub dim: usize,
    pub rho: &'a [f64],
    pub rinv: &'a [f64],
    /// Deviatoric stress, NSTR × ntotal.
    pub tau: &'a [f64],
    pub dvdt: &'a mut [f64],
}

/// `sph_geometry_continuity`: Dρ/Dt −= ρ v_r/r* for the first n = `drho.len()` particles.
pub struct Continuity<'a> {
    pub dim: usize,
    pub v: &'a [f64],
    pub rho: &'a [f64],
    pub rinv: &'a [f64],
    pub drho: &'a mut [f64],
}

impl Twin for Ring<'_> {
    fn rust(&mut self) {
        rust::ring(self)
    }
    fn fortran(&mut self) {
        ffi::ring(self)
    }
}

impl Twin for Hoop<'_> {
    fn rust(&mut self) {
        rust::hoop(self)
    }
    fn fortran(&mut self) {
        ffi::hoop(self)
    }
}

impl Twin for Continuity<'_> {
    fn rust(&mut self) {
        rust::continuity(self)
    }
    fn fortran(&mut self) {
        ffi::continuity(self)
    }
}

/// 1/r* and the planar mass of every particle, after the mirrors.
pub struct RingStage;

impl Stage for RingStage {
    fn module(&self) -> Module {
        Module::Geometry
    }
    fn name(&self) -> &'static str {
        "geometry.ring"
    }
    fn reads(&self) -> &[Field] {
        &[Field::X, Field::H, Field::Mass]
    }
    fn writes(&self) -> &[Field] {
        &[Field::Rinv, Field::Pmass]
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        w.rinv.resize(p.ntotal, 0.0);
        w.pmass.resize(p.ntotal, 0.0);
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, nreal, nt) = (p.dim, p.nreal, p.ntotal);
        let (x, h, mass) = (&p.x[..dim * nt], &p.h[..nt], &p.mass[..nt]);
        Ring { dim, nreal, x, h, mass, rinv: &mut w.rinv[..nt], pmass: &mut w.pmass[..nt] }.run(b);
    }
}

/// The hoop acceleration of the deviatoric stress, a term of the acceleration sum.
pub struct HoopStage {
    slots: Slots,
}

impl Stage for HoopStage {
    fn module(&self) -> Module {
        Module::Geometry
    }
    fn name(&self) -> &'static str {
        "geometry.hoop"
    }
    fn reads(&self) -> &[Field] {
        &[Field::Rho, Field::Rinv, Field::Tau]
    }
    fn writes(&self) -> &[Field] {
        &[Field::Acc]
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        self.slots.size(w, p.dim, p.ntotal);
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, n, nt) = (p.dim, p.nreal, p.ntotal);
        let ra = self.slots.acc_range(dim * nt);
        Hoop {
            dim,
            rho: &p.rho[..nt],
            rinv: &w.rinv[..nt],
            tau: &p.tau[..NSTR * nt],
            dvdt: &mut w.acc[ra.start..ra.start + dim * n],
        }
        .run(b);
    }
    fn terms(&self) -> Terms {
        Terms { acc: Some(4), de: None }
    }
    fn assign(&mut self, slots: Slots) {
        self.slots = slots;
    }
}

/// The hoop term of the continuity equation, added to the plane rate after dh/dt has read it.
pub struct ContinuityStage;

impl Stage for ContinuityStage {
    fn module(&self) -> Module {
        Module::Geometry
    }
    fn name(&self) -> &'static str {
        "geometry.continuity"
    }
    fn reads(&self) -> &[Field] {
        &[Field::V, Field::Rho, Field::Rinv, Field::Drho]
    }
    fn writes(&self) -> &[Field] {
        &[Field::Drho]
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, n, nt) = (p.dim, p.nreal, p.ntotal);
        let (v, rho, rinv) = (&p.v[..dim * nt], &p.rho[..nt], &w.rinv[..nt]);
        Continuity { dim, v, rho, rinv, drho: &mut w.drho[..n] }.run(b);
    }
}

/// Runs in axisymmetric geometry: the ring quantities after the mirrors, the hoop acceleration
/// of the deviatoric stress with the rates (materials with strength), and the continuity hoop
/// term when ρ is integrated.
pub fn plan(ctx: &PlanCtx) -> Contribution {
    if !ctx.case.axisymmetric() {
        return Contribution::skip("plane geometry: no hoop terms");
    }
    let mut stages: Vec<(Phase, Box<dyn Stage>)> = vec![(Phase::Mirrors, Box::new(RingStage))];
    if crate::case::has_strength(ctx.case) {
        stages.push((Phase::Rates, Box::new(HoopStage { slots: Slots::default() })));
    }
    if ctx.case.sph.density == DensityKind::Continuity {
        stages.push((Phase::Rates, Box::new(ContinuityStage)));
    }
    Contribution::run("axisymmetric: ring masses m/(2 pi r), hoop terms", stages)
}
