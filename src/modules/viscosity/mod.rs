//! Monaghan artificial viscosity (thesis (4-47), (4-48); Liu's art_visc), for approaching pairs:
//! μ_ij = h_ij v_ij·x_ij/(|x_ij|² + φ²), φ = etq h_ij; Π_ij = (β μ_ij − α c̄_ij) μ_ij / ρ̄_ij;
//! Dv_i/Dt −= Σ_j m_j Π_ij ∇_i W_ij (m/s²); De_i/Dt += ½ Σ_j m_j Π_ij v_ij·∇_i W_ij (J/kg/s);
//! and mumax_i = max_j |μ_ij| over the approaching pairs (m/s, 0 if none), the signal speed of the
//! β term that the CFL step adds (theory.md §13).
//! With the Morris–Monaghan switch (`viscosity.switch = "morris_monaghan"`; Morris & Monaghan
//! 1997, J. Comput. Phys. 136): every particle carries its own α_i ∈ [α_min, α_max] (α_max the
//! case's `alpha`); a pair uses α_ij = (α_i + α_j)/2 and β_ij = β α_ij/α_max, and the switch stage
//! advances dα_i/dt = −(α_i − α_min)/τ_i + S_i (α_max − α_i), τ_i = h_i/(ℓ c_i) (s),
//! S_i = max(−∇·v_i, 0) (1/s) with −∇·v_i = (1/ρ_i) Σ_j m_j v_ij·∇_i W_ij, over the previous step
//! by one backward-Euler step (α stays in [α_min, α_max] at any step size; theory.md §6).
//! Fortran twin: `fortran/src/sph_viscosity.f90`.

mod ffi;
#[cfg(test)]
mod parity;
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
    /// The switch: α_i of every particle (ntotal, mirrors included), and β_ij = β α_ij/`amax`;
    /// empty = the constant α and β of `coef`.
    pub alpv: &'a [f64],
    pub amax: f64,
    /// Axisymmetric: 1/r* (1/m) per particle (ntotal), and the energy terms of the RZ form
    /// (`force`: v_i − (r_j/r_i) v_j at the i end; Π_ij v_i·∇_i W_ij where j is a mirror across
    /// the axis, 1/r* < 0); empty in plane geometry.
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

/// `sph_viscosity_switch`: α_i of the first `n` particles advanced over `dt` (s) (ntotal =
/// `mass.len()`; the pair list, masses, ρ, v, h, c of every particle).
pub struct Switch<'a> {
    pub dim: usize,
    pub n: usize,
    pub pairs: &'a PairList,
    pub dwdx: &'a [f64],
    pub mass: &'a [f64],
    pub rho: &'a [f64],
    pub v: &'a [f64],
    pub h: &'a [f64],
    pub c: &'a [f64],
    /// α_min, α_max and ℓ of the decay time h/(ℓ c).
    pub amin: f64,
    pub amax: f64,
    pub ell: f64,
    pub dt: f64,
    /// α_i (ntotal; the first n are advanced).
    pub alpv: &'a mut [f64],
    /// Workspace (ntotal): the continuity sum Σ_j m_j v_ij·∇_i W_ij on return.
    pub dv: &'a mut [f64],
}

impl Twin for Switch<'_> {
    fn rust(&mut self) {
        rust::switch(self)
    }
    fn fortran(&mut self) {
        ffi::switch(self)
    }
}

/// The switch's parameters (`[viscosity]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SwitchCoef {
    pub amin: f64,
    pub amax: f64,
    pub ell: f64,
}

/// The Morris–Monaghan switch: α_i of the real particles advanced over the previous step (the
/// step being taken is not known before its rates; the first step keeps the initial α_max).
pub struct SwitchStage {
    coef: SwitchCoef,
    rz: bool,
}

impl Stage for SwitchStage {
    fn module(&self) -> Module {
        Module::Viscosity
    }
    fn name(&self) -> &'static str {
        "viscosity.switch"
    }
    fn reads(&self) -> &[Field] {
        if self.rz {
            &[Field::PairI, Field::PairJ, Field::Dwdx, Field::Pmass, Field::Rho, Field::V, Field::H, Field::C, Field::Alpha]
        } else {
            &[Field::PairI, Field::PairJ, Field::Dwdx, Field::Mass, Field::Rho, Field::V, Field::H, Field::C, Field::Alpha]
        }
    }
    fn writes(&self) -> &[Field] {
        &[Field::Alpha]
    }
    fn register(&self, p: &mut Particles) {
        p.alpha = vec![self.coef.amax; p.ntotal];
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        w.divv.resize(p.ntotal, 0.0);
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, k: &Clock) {
        let (dim, n, nt) = (p.dim, p.nreal, p.ntotal);
        let SwitchCoef { amin, amax, ell } = self.coef;
        Switch {
            dim,
            n,
            pairs: &w.pairs,
            dwdx: &w.dwdx,
            mass: if self.rz { &w.pmass[..nt] } else { &p.mass[..nt] },
            rho: &p.rho[..nt],
            v: &p.v[..dim * nt],
            h: &p.h[..nt],
            c: &p.c[..nt],
            amin,
            amax,
            ell,
            dt: k.dt_prev,
            alpv: &mut p.alpha[..nt],
            dv: &mut w.divv[..nt],
        }
        .run(b);
    }
}

/// The viscous terms of the rate sums.
pub struct ViscosityStage {
    pub(crate) coef: Coef,
    pub(crate) slots: Slots,
    /// Axisymmetric: the pair sums of the planar masses.
    rz: bool,
    /// The CFL step reads max|μ| (`time.viscous_step`): only then is `mumax` an output of the
    /// stage (compared by the dual run, and required of a legacy routine that stands for it).
    pub(crate) signal: bool,
    /// The switch's α_max (`Some` with the Morris–Monaghan switch: α_i per particle).
    switch: Option<f64>,
}

impl ViscosityStage {
    /// The stage of a case (the plan's settings of [`plan`]).
    pub fn of_case(coef: Coef, case: &crate::case::Case, rz: bool) -> Self {
        let signal = case.time.step == crate::case::StepRule::Cfl && case.time.viscous_step;
        let switch = (case.viscosity.switch != crate::case::ViscSwitch::None).then_some(coef.alpha);
        ViscosityStage { coef, slots: Slots::default(), rz, signal, switch }
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
        use Field::*;
        match (self.rz, self.switch.is_some()) {
            (true, false) => &[PairI, PairJ, Dwdx, X, V, H, Rho, C, Pmass, Rinv],
            (true, true) => &[PairI, PairJ, Dwdx, X, V, H, Rho, C, Pmass, Rinv, Alpha],
            (false, false) => &[PairI, PairJ, Dwdx, X, V, H, Rho, C, Mass],
            (false, true) => &[PairI, PairJ, Dwdx, X, V, H, Rho, C, Mass, Alpha],
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
            alpv: if self.switch.is_some() { &p.alpha[..nt] } else { &[] },
            amax: self.switch.unwrap_or(self.coef.alpha),
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
        let mut stages: Vec<(Phase, Box<dyn Stage>)> =
            vec![(Phase::Rates, Box::new(ViscosityStage::of_case(coef, ctx.case, rz)))];
        let mut why = why;
        if v.switch == crate::case::ViscSwitch::MorrisMonaghan && v.alpha > 0.0 {
            let sc = SwitchCoef { amin: v.alpha_min, amax: v.alpha, ell: v.switch_decay };
            stages.insert(0, (Phase::Switch, Box::new(SwitchStage { coef: sc, rz })));
            why = format!("{why}, Morris-Monaghan switch: alpha in [{}, {}], decay {}", v.alpha_min, v.alpha, v.switch_decay);
        }
        Contribution::run(why, stages)
    } else {
        Contribution::skip(why)
    }
}
