//! Density (thesis Table 4-1; Liu's sum_density and con_density):
//! summation ρ_i = m_i W_ii + Σ_j m_j W_ij (kg/m³), number-density summation
//! ρ_i = m_i (W_ii + Σ_j W_ij) (Hu & Adams 2006: each particle's density from its own mass, so a
//! light phase beside a heavy one keeps its own density), or the continuity rate
//! Dρ_i/Dt = Σ_j m_j (v_i − v_j)·∇_i W_ij (kg/m³/s, the thesis's mass form), or the volume form
//! Dρ_i/Dt = ρ_i Σ_j (m_j/ρ_j)(v_i − v_j)·∇_i W_ij, which stays consistent across large density
//! ratios (detonation products against soil). Fortran twin: `sph_density.f90`.

mod ffi;
#[cfg(test)]
mod parity;
mod rust;

use super::nnps::PairList;
use super::{Backend, Contribution, Module, Phase, PlanCtx, Stage, Twin};
use crate::case::{ContinuityForm, DensityKind, SmoothingKind};
use crate::state::{Clock, Field, Particles, Work};

/// `sph_density_sum` or `sph_density_number`: ρ of every particle of the pair list (ntotal =
/// `mass.len()`).
pub struct Summation<'a> {
    pub pairs: &'a PairList,
    /// W_ij per pair.
    pub w: &'a [f64],
    /// W(0, h_i) per particle.
    pub w0: &'a [f64],
    pub mass: &'a [f64],
    /// Number density m_i Σ W (else Σ m_j W).
    pub number: bool,
    pub rho: &'a mut [f64],
}

impl Twin for Summation<'_> {
    fn rust(&mut self) {
        rust::summation(self)
    }
    fn fortran(&mut self) {
        ffi::summation(self)
    }
}

/// `sph_density_rate` (mass form) or `sph_density_rate_vol` (volume form): Dρ/Dt of every particle.
pub struct Rate<'a> {
    pub dim: usize,
    /// The volume form (`rho` is read); else the mass form (`rho` is not).
    pub volume: bool,
    pub pairs: &'a PairList,
    pub dwdx: &'a [f64],
    pub mass: &'a [f64],
    pub rho: &'a [f64],
    pub v: &'a [f64],
    /// Dρ/Dt (kg/m³/s), ntotal.
    pub drho: &'a mut [f64],
}

impl Twin for Rate<'_> {
    fn rust(&mut self) {
        rust::rate(self)
    }
    fn fortran(&mut self) {
        ffi::rate(self)
    }
}

/// Summation density of every particle, mirrors included (axisymmetric: of the planar masses).
pub struct SumStage {
    rz: bool,
    number: bool,
}

impl Stage for SumStage {
    fn module(&self) -> Module {
        Module::Density
    }
    fn name(&self) -> &'static str {
        if self.number { "density.number" } else { "density.summation" }
    }
    fn reads(&self) -> &[Field] {
        if self.rz {
            &[Field::PairI, Field::PairJ, Field::W, Field::W0, Field::Pmass]
        } else {
            &[Field::PairI, Field::PairJ, Field::W, Field::W0, Field::Mass]
        }
    }
    fn writes(&self) -> &[Field] {
        &[Field::Rho]
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let nt = p.ntotal;
        let mass = if self.rz { &w.pmass[..nt] } else { &p.mass[..nt] };
        let number = self.number;
        Summation { pairs: &w.pairs, w: &w.w, w0: &w.w0, mass, number, rho: &mut p.rho[..nt] }.run(b);
    }
}

/// The continuity rate of every particle.
pub struct RateStage {
    volume: bool,
    /// Axisymmetric: the plane rate of the planar masses (the hoop term is the geometry module's).
    rz: bool,
}

impl Stage for RateStage {
    fn module(&self) -> Module {
        Module::Density
    }
    fn name(&self) -> &'static str {
        if self.volume { "density.rate_vol" } else { "density.rate" }
    }
    fn reads(&self) -> &[Field] {
        match (self.volume, self.rz) {
            (true, false) => &[Field::PairI, Field::PairJ, Field::Dwdx, Field::Mass, Field::Rho, Field::V],
            (false, false) => &[Field::PairI, Field::PairJ, Field::Dwdx, Field::Mass, Field::V],
            (true, true) => &[Field::PairI, Field::PairJ, Field::Dwdx, Field::Pmass, Field::Rho, Field::V],
            (false, true) => &[Field::PairI, Field::PairJ, Field::Dwdx, Field::Pmass, Field::V],
        }
    }
    fn writes(&self) -> &[Field] {
        &[Field::Drho]
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        w.drho.resize(p.ntotal, 0.0);
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, nt) = (p.dim, p.ntotal);
        let (pairs, dwdx) = (&w.pairs, &w.dwdx);
        let mass = if self.rz { &w.pmass[..nt] } else { &p.mass[..nt] };
        let (rho, v) = (&p.rho[..nt], &p.v[..dim * nt]);
        Rate { dim, volume: self.volume, pairs, dwdx, mass, rho, v, drho: &mut w.drho }.run(b);
    }
}

/// Summation density, or the continuity rate (also when h evolves by dh/dt, which reads it).
pub fn plan(ctx: &PlanCtx) -> Contribution {
    let sph = &ctx.case.sph;
    let volume = sph.continuity_form == ContinuityForm::Volume;
    let rz = ctx.case.axisymmetric();
    let mut stages: Vec<(Phase, Box<dyn Stage>)> = Vec::new();
    let why = match sph.density {
        DensityKind::Summation | DensityKind::Number => {
            let number = sph.density == DensityKind::Number;
            stages.push((Phase::Density, Box::new(SumStage { rz, number })));
            if number { "number density (Hu & Adams)" } else { "summation" }.to_string()
        }
        DensityKind::Continuity => format!("continuity, {:?} form", sph.continuity_form).to_lowercase(),
    };
    if sph.density == DensityKind::Continuity || sph.smoothing == SmoothingKind::Rate {
        stages.push((Phase::DensityRate, Box::new(RateStage { volume, rz })));
    }
    Contribution::run(why, stages)
}
