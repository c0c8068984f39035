//! Internal force (thesis (4-33)…(4-38), sign as docs/theory.md §5 states it; Liu's int_force), with
//! σ = −p δ + τ:
//! Dv_i^α/Dt = Σ_j m_j (σ_i^{αβ}/ρ_i² + σ_j^{αβ}/ρ_j²) ∂W_ij/∂x_i^β (m/s²),
//! De_i/Dt = ½ Σ_j m_j (p_i/ρ_i² + p_j/ρ_j²) v_ij·∇_i W_ij (J/kg/s), or in the asymmetric form
//! (`sph.energy_form = "asymmetric"`) De_i/Dt = Σ_j m_j (p_i/ρ_i²) v_ij·∇_i W_ij: each particle does
//! its own p dV work; the total energy is conserved with the same momentum equation, and e stays
//! ≥ 0 where p ≥ 0 (theory.md §5).
//! The deviatoric work τ:ε̇/ρ comes from the strength module.
//! Axisymmetric (RZ, m the planar masses μ = m/(2πr*), `rinv` = 1/r*): the energy terms read
//! v_i − (r_j/r_i) v_j at the i end and (r_i/r_j) v_i − v_j at the j end in place of v_ij, so that
//! each pair's work on the rings' internal energies (ring mass 2πr μ) is exactly what its forces
//! take from the rings' kinetic energies: the total energy is conserved, and the sum holds the
//! hoop part −(p/ρ) v_r/r of the p dV work (theory.md §16). In a pair across the axis (the other
//! end a mirror, 1/r* < 0) the real end's term is (p_i/ρ_i² + p_j/ρ_j²) v_i·∇_i W_ij: its internal
//! energy takes the work of the mirror's force on it, and the axis does no work (theory.md, "The
//! axis of an RZ run").
//! The interface form (`sph.pressure_form = "interface"`, Colagrossi & Landrini 2003) reads
//! (σ_i + σ_j)/(ρ_i ρ_j) for σ_i/ρ_i² + σ_j/ρ_j², and p_i/(ρ_i ρ_j) for the asymmetric p_i/ρ_i²: at
//! an interface between phases 10³ apart in density the light side's term no longer carries the
//! heavy neighbour's mass over its own density squared. Fortran twin: `sph_force.f90`.
//!
//! The physical (Newtonian) viscosity of Liu & Liu's book (2003, `int_force` with `visc`), a stage of its own (`force.newtonian`) where a material has
//! `dynamic_viscosity_pa_s` η > 0. Per particle the shear strain rate (1/s)
//! ε_i^{αβ} = Σ_j (m_j/ρ_j) (v_j^α − v_i^α) ∂W_ij/∂x_i^β + (α↔β) − (2/3) δ^{αβ} (v_j − v_i)·∇_i W_ij,
//! then Dv_i^α/Dt = Σ_j m_j (η_i ε_i^{αβ}/ρ_i² + η_j ε_j^{αβ}/ρ_j²) ∂W_ij/∂x_i^β (m/s²) and the
//! viscous heating De_i/Dt = (η_i/(2ρ_i)) ε_i^{αβ} ε_i^{αβ} (J/kg/s). Plane geometry only.

mod ffi;
#[cfg(test)]
mod parity;
#[cfg(test)]
mod shear;
pub(crate) mod newtonian;
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
    /// The asymmetric energy form (false: the thesis's symmetric one).
    pub asym: bool,
    /// The interface pressure form (false: the thesis's standard one).
    pub iface: bool,
    /// Axisymmetric: 1/r* (1/m) per particle (ntotal); empty in plane geometry.
    pub rinv: &'a [f64],
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

/// `sph_force_newtonian`: the physical viscosity's acceleration and heating (ntotal =
/// `mass.len()`).
pub struct Newtonian<'a> {
    pub dim: usize,
    pub pairs: &'a PairList,
    pub dwdx: &'a [f64],
    pub mass: &'a [f64],
    pub rho: &'a [f64],
    pub v: &'a [f64],
    /// Dynamic viscosity η (Pa s) per particle, ntotal.
    pub eta: &'a [f64],
    /// Acceleration (m/s²), dim × ntotal.
    pub dvdt: &'a mut [f64],
    /// Energy rate (J/kg/s), ntotal.
    pub dedt: &'a mut [f64],
}

impl Twin for Newtonian<'_> {
    fn rust(&mut self) {
        newtonian::newtonian(self)
    }
    fn fortran(&mut self) {
        ffi::newtonian(self)
    }
}

/// The physical viscosity's terms of the rate sums; η per material (Pa s), indexed by `mat`.
pub struct NewtonianStage {
    pub(crate) slots: Slots,
    pub(crate) eta_mat: Vec<f64>,
    /// η per particle, refilled each step (kept to spare the allocation).
    pub(crate) eta: std::sync::Mutex<Vec<f64>>,
}

impl Stage for NewtonianStage {
    fn module(&self) -> Module {
        Module::Force
    }
    fn name(&self) -> &'static str {
        "force.newtonian"
    }
    fn reads(&self) -> &[Field] {
        &[Field::PairI, Field::PairJ, Field::Dwdx, Field::Mass, Field::Mat, Field::Rho, Field::V]
    }
    fn writes(&self) -> &[Field] {
        &[Field::Acc, Field::Dde]
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        self.slots.size(w, p.dim, p.ntotal);
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, nt) = (p.dim, p.ntotal);
        let mut eta = self.eta.lock().unwrap_or_else(|e| e.into_inner());
        eta.clear();
        eta.extend(p.mat[..nt].iter().map(|&m| self.eta_mat[m as usize]));
        Newtonian {
            dim,
            pairs: &w.pairs,
            dwdx: &w.dwdx,
            mass: &p.mass[..nt],
            rho: &p.rho[..nt],
            v: &p.v[..dim * nt],
            eta: &eta,
            dvdt: &mut w.acc[self.slots.acc_range(dim * nt)],
            dedt: &mut w.dde[self.slots.de_range(nt)],
        }
        .run(b);
    }
    fn terms(&self) -> Terms {
        Terms { acc: Some(6), de: Some(4) }
    }
    fn assign(&mut self, slots: Slots) {
        self.slots = slots;
    }
}

/// The pressure (and stress) terms of the rate sums.
pub struct ForceStage {
    pub(crate) slots: Slots,
    /// Axisymmetric: the pair sums of the planar masses.
    pub(crate) rz: bool,
    /// The asymmetric energy form (`sph.energy_form`).
    pub(crate) asym: bool,
    /// The interface pressure form (`sph.pressure_form = "interface"`): the stage is named
    /// `force.internal_interface`.
    pub(crate) iface: bool,
}

impl ForceStage {
    fn internal(&self, b: Backend, p: &mut Particles, w: &mut Work) {
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
            asym: self.asym,
            iface: self.iface,
            rinv: if self.rz { &w.rinv[..nt] } else { &[] },
            dvdt: &mut w.acc[self.slots.acc_range(dim * nt)],
            dedt: &mut w.dde[self.slots.de_range(nt)],
        }
        .run(b);
    }
}

impl Stage for ForceStage {
    fn module(&self) -> Module {
        Module::Force
    }
    fn name(&self) -> &'static str {
        if self.iface { "force.internal_interface" } else { "force.internal" }
    }
    fn reads(&self) -> &[Field] {
        if self.rz {
            &[Field::PairI, Field::PairJ, Field::Dwdx, Field::Pmass, Field::Rinv, Field::Rho, Field::P, Field::V, Field::Tau]
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
        self.internal(b, p, w)
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
    let why = if crate::case::has_strength(ctx.case) { "sigma = -p I + tau" } else { "pressure only" };
    let rz = ctx.case.axisymmetric();
    let asym = ctx.case.sph.energy_form == crate::case::EnergyForm::Asymmetric;
    let iface = ctx.case.sph.pressure_form == crate::case::PressureForm::Interface;
    let why = format!(
        "{why}, {} energy form{}",
        if asym { "asymmetric" } else { "symmetric" },
        if iface { ", interface pressure form (Colagrossi & Landrini)" } else { "" }
    );
    let stage = ForceStage { slots: Slots::default(), rz, asym, iface };
    let eta_mat: Vec<f64> = ctx.case.materials.iter().map(|m| m.dynamic_viscosity_pa_s.unwrap_or(0.0)).collect();
    if eta_mat.iter().any(|&e| e > 0.0) {
        let why = format!("{why}, physical viscosity (eta = {eta_mat:?} Pa s)");
        let visc = NewtonianStage { slots: Slots::default(), eta_mat, eta: Default::default() };
        return Contribution::run(why, vec![(Phase::Rates, Box::new(stage)), (Phase::Rates, Box::new(visc))]);
    }
    Contribution::run(why, vec![(Phase::Rates, Box::new(stage))])
}
