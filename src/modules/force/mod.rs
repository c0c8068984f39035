//! Internal force (thesis (4-33)…(4-38), sign as decided in THESIS.md §2; Liu's int_force), with
//! σ = −p δ + τ:
//! Dv_i^α/Dt = Σ_j m_j (σ_i^{αβ}/ρ_i² + σ_j^{αβ}/ρ_j²) ∂W_ij/∂x_i^β (m/s²),
//! De_i/Dt = ½ Σ_j m_j (p_i/ρ_i² + p_j/ρ_j²) v_ij·∇_i W_ij (J/kg/s).
//! The deviatoric work τ:ε̇/ρ comes from the strength module. Fortran twin: `sph_force.f90`.

mod ffi;
#[cfg(test)]
mod parity;
pub(crate) mod compat;
mod rust;

use super::nnps::PairList;
use super::{Backend, Contribution, Module, Phase, PlanCtx, Slots, Stage, Terms, Twin};
use crate::state::{Clock, Field, Particles, Work};

/// `sph_force_internal` over the pair list (ntotal = `mass.len()`).
pub struct Internal<'a> {
    pub dim: usize,
    pub pairs: &'a PairList,
    pub dwdx: &'a [f64],
    pub mass: &'a [f64],
    pub rho: &'a [f64],
    pub p: &'a [f64],
    pub v: &'a [f64],
    /// Deviatoric stress, NSTR × ntotal; empty for fluids.
    pub tau: &'a [f64],
    /// Acceleration (m/s²), dim × ntotal.
    pub dvdt: &'a mut [f64],
    /// Energy rate (J/kg/s), ntotal.
    pub dedt: &'a mut [f64],
}

impl Twin for Internal<'_> {
    fn rust(&mut self) {
        rust::internal(self)
    }
    fn fortran(&mut self) {
        ffi::internal(self)
    }
}

/// The pressure (and stress) terms of the rate sums.
pub struct ForceStage {
    slots: Slots,
    /// Axisymmetric: the pair sums of the planar masses.
    rz: bool,
}

impl Stage for ForceStage {
    fn module(&self) -> Module {
        Module::Force
    }
    fn name(&self) -> &'static str {
        "force.internal"
    }
    fn reads(&self) -> &[Field] {
        if self.rz {
            &[Field::PairI, Field::PairJ, Field::Dwdx, Field::Pmass, Field::Rho, Field::P, Field::V, Field::Tau]
        } else {
            &[Field::PairI, Field::PairJ, Field::Dwdx, Field::Mass, Field::Rho, Field::P, Field::V, Field::Tau]
        }
    }
    fn writes(&self) -> &[Field] {
        &[Field::Acc, Field::Dde]
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        self.slots.size(w, p.dim, p.ntotal);
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, nt) = (p.dim, p.ntotal);
        Internal {
            dim,
            pairs: &w.pairs,
            dwdx: &w.dwdx,
            mass: if self.rz { &w.pmass[..nt] } else { &p.mass[..nt] },
            rho: &p.rho[..nt],
            p: &p.p[..nt],
            v: &p.v[..dim * nt],
            tau: &p.tau,
            dvdt: &mut w.acc[self.slots.acc_range(dim * nt)],
            dedt: &mut w.dde[self.slots.de_range(nt)],
        }
        .run(b);
    }
    fn terms(&self) -> Terms {
        Terms { acc: Some(0), de: Some(0) }
    }
    fn assign(&mut self, slots: Slots) {
        self.slots = slots;
    }
}

/// Every case has the internal force.
pub fn plan(ctx: &PlanCtx) -> Contribution {
    let why = if crate::setup::has_strength(ctx.case) { "sigma = -p I + tau" } else { "pressure only" };
    let rz = ctx.case.axisymmetric();
    Contribution::run(why, vec![(Phase::Rates, Box::new(ForceStage { slots: Slots::default(), rz }))])
}
