//! Monaghan artificial viscosity (thesis (4-47), (4-48); Liu's art_visc), for approaching pairs:
//! μ_ij = h_ij v_ij·x_ij/(|x_ij|² + φ²), φ = etq h_ij; Π_ij = (β μ_ij − α c̄_ij) μ_ij / ρ̄_ij;
//! Dv_i/Dt −= Σ_j m_j Π_ij ∇_i W_ij (m/s²); De_i/Dt += ½ Σ_j m_j Π_ij v_ij·∇_i W_ij (J/kg/s);
//! and mumax_i = max_j |μ_ij| over the approaching pairs (m/s, 0 if none), the signal speed of the
//! β term that the CFL step adds (theory.md §13).
//! Fortran twin: `fortran/src/sph_viscosity.f90`.

mod ffi;
#[cfg(test)]
mod parity;
pub(crate) mod compat;
mod rust;

use super::nnps::PairList;
use super::{Backend, Contribution, Module, Phase, PlanCtx, Slots, Stage, Terms, Twin};
use crate::state::{Clock, Field, Particles, Work};

/// The coefficients α, β and φ/h (etq) of (4-47), (4-48).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coef {
    pub alpha: f64,
    pub beta: f64,
    pub etq: f64,
}

/// `sph_viscosity_monaghan`: the viscous acceleration and energy rate of every particle of the
/// pair list (ntotal = `mass.len()`).
pub struct Monaghan<'a> {
    pub dim: usize,
    pub pairs: &'a PairList,
    /// ∇_i W_ij per pair, dim × npair.
    pub dwdx: &'a [f64],
    pub x: &'a [f64],
    pub v: &'a [f64],
    pub h: &'a [f64],
    pub rho: &'a [f64],
    pub c: &'a [f64],
    pub mass: &'a [f64],
    pub coef: Coef,
    /// Axisymmetric: 1/r* (1/m) per particle (ntotal), and the energy terms of the RZ form
    /// (`force`: v_i − (r_j/r_i) v_j at the i end); empty in plane geometry.
    pub rinv: &'a [f64],
    /// Acceleration (m/s²), dim × ntotal.
    pub dvdt: &'a mut [f64],
    /// Energy rate (J/kg/s), ntotal.
    pub dedt: &'a mut [f64],
    /// Largest |μ_ij| over each particle's approaching pairs (m/s), ntotal.
    pub mumax: &'a mut [f64],
}

impl Twin for Monaghan<'_> {
    fn rust(&mut self) {
        rust::monaghan(self)
    }
    fn fortran(&mut self) {
        ffi::monaghan(self)
    }
}

/// The viscous terms of the rate sums.
pub struct ViscosityStage {
    coef: Coef,
    slots: Slots,
    /// Axisymmetric: the pair sums of the planar masses.
    rz: bool,
    /// The CFL step reads max|μ| (`time.viscous_step`): only then is `mumax` an output of the
    /// stage (compared by the dual run, and required of a legacy routine that stands for it).
    signal: bool,
}

impl ViscosityStage {
    /// The stage of a case (the plan's settings of [`plan`]).
    pub fn of_case(coef: Coef, case: &crate::case::Case, rz: bool) -> Self {
        let signal = case.time.step == crate::case::StepRule::Cfl && case.time.viscous_step;
        ViscosityStage { coef, slots: Slots::default(), rz, signal }
    }
}

impl Stage for ViscosityStage {
    fn module(&self) -> Module {
        Module::Viscosity
    }
    fn name(&self) -> &'static str {
        "viscosity.monaghan"
    }
    fn reads(&self) -> &[Field] {
        if self.rz {
            &[
                Field::PairI,
                Field::PairJ,
                Field::Dwdx,
                Field::X,
                Field::V,
                Field::H,
                Field::Rho,
                Field::C,
                Field::Pmass,
                Field::Rinv,
            ]
        } else {
            &[Field::PairI, Field::PairJ, Field::Dwdx, Field::X, Field::V, Field::H, Field::Rho, Field::C, Field::Mass]
        }
    }
    fn writes(&self) -> &[Field] {
        if self.signal { &[Field::Acc, Field::Dde, Field::Mumax] } else { &[Field::Acc, Field::Dde] }
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        self.slots.size(w, p.dim, p.ntotal);
        w.mumax.resize(p.ntotal, 0.0);
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, nt) = (p.dim, p.ntotal);
        Monaghan {
            dim,
            pairs: &w.pairs,
            dwdx: &w.dwdx,
            x: &p.x[..dim * nt],
            v: &p.v[..dim * nt],
            h: &p.h[..nt],
            rho: &p.rho[..nt],
            c: &p.c[..nt],
            mass: if self.rz { &w.pmass[..nt] } else { &p.mass[..nt] },
            coef: self.coef,
            rinv: if self.rz { &w.rinv[..nt] } else { &[] },
            dvdt: &mut w.acc[self.slots.acc_range(dim * nt)],
            dedt: &mut w.dde[self.slots.de_range(nt)],
            mumax: &mut w.mumax[..nt],
        }
        .run(b);
    }
    fn terms(&self) -> Terms {
        Terms { acc: Some(1), de: Some(1) }
    }
    fn assign(&mut self, slots: Slots) {
        self.slots = slots;
    }
}

/// Runs unless α = β = 0.
pub fn plan(ctx: &PlanCtx) -> Contribution {
    let v = &ctx.case.viscosity;
    let why = format!("alpha = {}, beta = {}", v.alpha, v.beta);
    if v.alpha > 0.0 || v.beta > 0.0 {
        let coef = Coef { alpha: v.alpha, beta: v.beta, etq: v.phi_over_h };
        let rz = ctx.case.axisymmetric();
        Contribution::run(why, vec![(Phase::Rates, Box::new(ViscosityStage::of_case(coef, ctx.case, rz)))])
    } else {
        Contribution::skip(why)
    }
}
