//! Averaged velocity (XSPH; Liu's av_vel): av_i = ε Σ_j (m_j/ρ̄_ij)(v_j − v_i) W_ij (m/s).
//! The integrator moves particles with v + av. Fortran twin: `sph_xsph.f90`.

mod ffi;
#[cfg(test)]
mod parity;
mod rust;

use super::nnps::PairList;
use super::{Backend, Contribution, Module, Phase, PlanCtx, Stage, Twin};
use crate::state::{Clock, Field, Particles, Work};

/// `sph_xsph_average` over the pair list (ntotal = `mass.len()`).
pub struct Average<'a> {
    pub dim: usize,
    pub pairs: &'a PairList,
    /// W_ij per pair.
    pub w: &'a [f64],
    pub mass: &'a [f64],
    pub rho: &'a [f64],
    pub v: &'a [f64],
    /// ε (0 < ε ≤ 1).
    pub eps: f64,
    /// The correction (m/s), dim × ntotal.
    pub av: &'a mut [f64],
}

impl Twin for Average<'_> {
    fn rust(&mut self) {
        rust::average(self)
    }
    fn fortran(&mut self) {
        ffi::average(self)
    }
}

/// The XSPH velocity correction.
pub struct XsphStage {
    pub(crate) eps: f64,
    /// Axisymmetric: the planar masses.
    pub(crate) rz: bool,
}

impl Stage for XsphStage {
    fn module(&self) -> Module {
        Module::Xsph
    }
    fn name(&self) -> &'static str {
        "xsph.average"
    }
    fn reads(&self) -> &[Field] {
        if self.rz {
            &[Field::PairI, Field::PairJ, Field::W, Field::Pmass, Field::Rho, Field::V]
        } else {
            &[Field::PairI, Field::PairJ, Field::W, Field::Mass, Field::Rho, Field::V]
        }
    }
    fn writes(&self) -> &[Field] {
        &[Field::Av]
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        w.av.resize(p.dim * p.ntotal, 0.0);
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, nt) = (p.dim, p.ntotal);
        let mass = if self.rz { &w.pmass[..nt] } else { &p.mass[..nt] };
        let (rho, v) = (&p.rho[..nt], &p.v[..dim * nt]);
        Average { dim, pairs: &w.pairs, w: &w.w, mass, rho, v, eps: self.eps, av: &mut w.av }.run(b);
    }
}

/// Runs when `sph.xsph_eps` > 0.
pub fn plan(ctx: &PlanCtx) -> Contribution {
    let eps = ctx.case.sph.xsph_eps;
    let why = format!("eps = {eps}");
    if eps > 0.0 {
        Contribution::run(why, vec![(Phase::Rates, Box::new(XsphStage { eps, rz: ctx.case.axisymmetric() }))])
    } else {
        Contribution::skip(why)
    }
}
