//! Leapfrog (thesis (2-17)…(2-27); Liu's time_integration) with a variable step, the rate sums
//! and the CFL step. Fortran twin: `sph_integrator.f90`.
//!
//! Staggered variables u ∈ {ρ (continuity), e, v, τ}:
//! predict (after the first step): u_min = u; u(t_n) = u_min + Δt_{n−1}/2 · du(t_{n−1});
//! advance, first step: u(t_{1/2}) = u(t_0) + Δt_0/2 · du(t_0);
//! later: u(t_{n+1/2}) = u_min + (Δt_{n−1} + Δt_n)/2 · du(t_n); then x += Δt (v + av).
//! With a fixed step this is Liu's scheme exactly. CFL (s):
//! Δt = C min_i min(h_i/(c_i + |v_i| + k_v mumax_i), √(h_i/|a_i|)), k_v mumax_i the signal speed
//! of the viscosity's β term (k_v = 1.2 β, Monaghan 1992; `time.viscous_step`) or none.
//! Where a material has a physical viscosity η (Pa s), the step is also at most the diffusion
//! limit Δt ≤ min_i ρ_i h_i²/(8 η_i) = 0.125 h²/ν of Morris, Fox & Zhu (1997), not scaled by C.
//! The floor e_i ← max(e_i, 0) after the advance (`sph.e_floor`) returns the energy it adds,
//! Σ_i m_i max(0, −e_i) (J; per metre of depth in 2D), which the solver books in the energy
//! balance (theory.md §14).
//! The clamp ρ_i ← min(max(ρ_i, ρ_lo), ρ_hi) (kg/m³; `sph.density_clamp`) follows each density
//! update of the leapfrog, the predict and the advance, as the dam-break `time_integration` of
//! G.R. Liu and M.B. Liu (2003) does.
//! Boundary particles (`bnd`, [`crate::case::BoundaryKind`]; Liu & Liu 2003's virtual particles):
//! the advance moves neither kind; a held particle's ρ, e, v, τ keep their values through the
//! predict and the advance (u_min is still saved); the rate sum gives neither kind gravity (an
//! integrated wall would otherwise fall with the fluid it holds). A held particle's rates are
//! computed and never applied.

mod ffi;
#[cfg(test)]
mod parity;
mod rust;

use super::param::NSTR;
use super::{Backend, Contribution, Module, Phase, PlanCtx, Slots, Stage, Twin};
use crate::case::{DensityKind, StepRule};
use crate::state::{Clock, Field, Particles, Work};

/// `sph_integrator_sum_rates`: `out(d,i) = Σ_t acc_t(d,i) + grav(d)` for i < n, without grav(d)
/// for a boundary particle (`bnd(i)` ≠ 0); `acc` stacks `nterm` arrays of `lda` values.
pub struct SumRates<'a> {
    pub dim: usize,
    pub n: usize,
    pub lda: usize,
    pub nterm: usize,
    pub acc: &'a [f64],
    pub grav: &'a [f64],
    pub out: &'a mut [f64],
    /// The boundary-particle kind of each particle (n values), or empty (none).
    pub bnd: &'a [i32],
}

/// The staggered leapfrog variables and their saved half-step values (τ empty without
/// strength).
pub struct Leapfrog<'a> {
    pub rho: &'a mut [f64],
    pub e: &'a mut [f64],
    pub v: &'a mut [f64],
    pub tau: &'a mut [f64],
    pub rho_min: &'a mut [f64],
    pub e_min: &'a mut [f64],
    pub v_min: &'a mut [f64],
    pub tau_min: &'a mut [f64],
}

/// The rates the leapfrog applies.
pub struct Rates<'a> {
    pub drho: &'a [f64],
    pub de: &'a [f64],
    pub dv: &'a [f64],
    pub dtau: &'a [f64],
}

/// `sph_integrator_predict`: the staggered variables of the first `n` particles at t.
pub struct Predict<'a> {
    pub dim: usize,
    pub n: usize,
    /// The previous step (s).
    pub dt_prev: f64,
    /// ρ is staggered (continuity density).
    pub cont: bool,
    pub lf: Leapfrog<'a>,
    pub rates: Rates<'a>,
    /// The boundary-particle kind of each particle (n values), or empty (none).
    pub bnd: &'a [i32],
}

/// `sph_integrator_advance`: the staggered variables at t + Δt/2 and x at t + Δt.
pub struct Advance<'a> {
    pub dim: usize,
    pub n: usize,
    pub first: bool,
    pub dt_prev: f64,
    pub dt: f64,
    pub cont: bool,
    pub lf: Leapfrog<'a>,
    pub rates: Rates<'a>,
    /// The XSPH correction (dim × n), or empty.
    pub av: &'a [f64],
    pub x: &'a mut [f64],
    /// The boundary-particle kind of each particle (n values), or empty (none).
    pub bnd: &'a [i32],
}

/// `sph_integrator_cfl`: the CFL step of the first `h.len()` particles.
pub struct Cfl<'a> {
    pub dim: usize,
    /// The Courant number C.
    pub cfl: f64,
    pub h: &'a [f64],
    pub c: &'a [f64],
    pub v: &'a [f64],
    pub dv: &'a [f64],
    /// Weight of the viscous signal speed (1.2 β).
    pub kv: f64,
    /// Largest |μ_ij| per particle (m/s), or empty (no viscous signal speed).
    pub mumax: &'a [f64],
    /// The physical viscosity η per material (Pa s), or empty (no viscous diffusion limit).
    pub eta: &'a [f64],
    /// Material index per particle (into `eta`), read only with `eta`.
    pub mat: &'a [i32],
    /// Density per particle (kg/m³), read only with `eta`.
    pub rho: &'a [f64],
    /// The step (s).
    pub dt: &'a mut f64,
}

/// `sph_integrator_efloor`: e = max(e, 0) for the first `e.len()` particles, and the energy added.
pub struct Efloor<'a> {
    pub mass: &'a [f64],
    pub e: &'a mut [f64],
    /// Σ m_i max(0, −e_i) (J).
    pub added: &'a mut f64,
}

/// `sph_integrator_clamp`: ρ = min(max(ρ, lo), hi) for the first `rho.len()` particles (kg/m³);
/// a NaN is left as it is.
pub struct Clamp<'a> {
    pub lo: f64,
    pub hi: f64,
    pub rho: &'a mut [f64],
}

impl Twin for Clamp<'_> {
    fn rust(&mut self) {
        rust::clamp(self)
    }
    fn fortran(&mut self) {
        ffi::clamp(self)
    }
}

impl Twin for SumRates<'_> {
    fn rust(&mut self) {
        rust::sum_rates(self)
    }
    fn fortran(&mut self) {
        ffi::sum_rates(self)
    }
}

impl Twin for Predict<'_> {
    fn rust(&mut self) {
        rust::predict(self)
    }
    fn fortran(&mut self) {
        ffi::predict(self)
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

impl Twin for Efloor<'_> {
    fn rust(&mut self) {
        rust::efloor(self)
    }
    fn fortran(&mut self) {
        ffi::efloor(self)
    }
}

impl Twin for Cfl<'_> {
    fn rust(&mut self) {
        *self.dt = rust::cfl(self)
    }
    fn fortran(&mut self) {
        ffi::cfl(self)
    }
}

/// The leapfrog's staggered variables, their rates, the XSPH correction (empty when off), the
/// positions of the real particles and their boundary-particle kinds, borrowed from the state.
type Parts<'a> = (Leapfrog<'a>, Rates<'a>, &'a [f64], &'a mut [f64], &'a [i32]);

/// See [`Parts`].
fn parts<'a>(p: &'a mut Particles, w: &'a mut Work) -> Parts<'a> {
    let (dim, n) = (p.dim, p.nreal);
    let ntau = if p.tau.is_empty() { 0 } else { NSTR * n };
    let Work { rho_min, e_min, v_min, tau_min, drho, de, dv, dtau, av, .. } = w;
    let lf = Leapfrog {
        rho: &mut p.rho[..n],
        e: &mut p.e[..n],
        v: &mut p.v[..dim * n],
        tau: &mut p.tau[..ntau],
        rho_min,
        e_min,
        v_min,
        tau_min,
    };
    let rates = Rates { drho: &drho[..n], de, dv, dtau: &dtau[..ntau] };
    let av: &[f64] = if av.is_empty() { &[] } else { &av[..dim * n] };
    (lf, rates, av, &mut p.x[..dim * n], &p.bnd)
}

/// Sizes the half-step values and the rates the leapfrog reads.
pub(crate) fn size_leapfrog(p: &Particles, w: &mut Work) {
    let (dim, n) = (p.dim, p.nreal);
    let ntau = if p.tau.is_empty() { 0 } else { NSTR * n };
    w.rho_min.resize(n, 0.0);
    w.e_min.resize(n, 0.0);
    w.v_min.resize(dim * n, 0.0);
    w.tau_min.resize(ntau, 0.0);
    crate::modules::grow(&mut w.drho, n);
}

/// The stages of the module.
pub(crate) enum Which {
    Sum,
    Predict,
    /// The Courant number, the viscous signal speed's weight (None: without it), and η per material (Pa s; empty
    /// where no material has a physical viscosity).
    Cfl(f64, Option<f64>, Vec<f64>),
    Advance,
    Efloor,
    /// The density clamp's bounds (kg/m³), after the predict (true) or after the advance.
    Clamp(f64, f64, bool),
}

/// A stage of the leapfrog.
pub struct IntegratorStage {
    pub(crate) which: Which,
    /// ρ is staggered (continuity density).
    pub(crate) cont: bool,
    pub(crate) grav: Vec<f64>,
    pub(crate) slots: Slots,
}

const LEAPFROG: [Field; 8] =
    [Field::Rho, Field::E, Field::V, Field::Tau, Field::RhoMin, Field::EMin, Field::VMin, Field::TauMin];

impl Stage for IntegratorStage {
    fn module(&self) -> Module {
        Module::Integrator
    }
    fn name(&self) -> &'static str {
        match self.which {
            Which::Sum => "integrator.sum_rates",
            Which::Predict => "integrator.predict",
            Which::Cfl(..) => "integrator.cfl",
            Which::Advance => "integrator.advance",
            Which::Efloor => "integrator.efloor",
            Which::Clamp(_, _, true) => "integrator.clamp_predict",
            Which::Clamp(_, _, false) => "integrator.clamp",
        }
    }
    fn reads(&self) -> &[Field] {
        match self.which {
            Which::Sum => &[Field::Acc, Field::Dde, Field::Bnd],
            Which::Predict => &[Field::Drho, Field::De, Field::Dv, Field::Dtau, Field::Bnd],
            Which::Cfl(_, None, ref eta) if eta.is_empty() => &[Field::H, Field::C, Field::V, Field::Dv],
            Which::Cfl(_, None, _) => &[Field::H, Field::C, Field::V, Field::Dv, Field::Rho],
            Which::Cfl(_, Some(_), ref eta) if eta.is_empty() => &[Field::H, Field::C, Field::V, Field::Dv, Field::Mumax],
            Which::Cfl(_, Some(_), _) => &[Field::H, Field::C, Field::V, Field::Dv, Field::Rho, Field::Mumax],
            Which::Advance => {
                &[Field::Drho, Field::De, Field::Dv, Field::Dtau, Field::Av, Field::RhoMin, Field::Bnd]
            }
            Which::Efloor => &[Field::Mass, Field::E],
            Which::Clamp(..) => &[Field::Rho],
        }
    }
    fn writes(&self) -> &[Field] {
        match self.which {
            Which::Sum => &[Field::Dv, Field::De],
            Which::Predict => &LEAPFROG,
            Which::Cfl(..) => &[Field::DtCfl],
            Which::Advance => &[Field::Rho, Field::E, Field::V, Field::Tau, Field::X],
            Which::Efloor => &[Field::E, Field::Efloor],
            Which::Clamp(..) => &[Field::Rho],
        }
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        match self.which {
            Which::Sum => {
                w.dv.resize(p.dim * p.nreal, 0.0);
                w.de.resize(p.nreal, 0.0);
            }
            Which::Cfl(..) => w.dt_cfl.resize(1, 0.0),
            Which::Efloor => w.efloor.resize(1, 0.0),
            Which::Predict | Which::Advance => size_leapfrog(p, w),
            Which::Clamp(..) => {}
        }
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, k: &Clock) {
        let (dim, n, nt) = (p.dim, p.nreal, p.ntotal);
        match self.which {
            Which::Sum => {
                let Slots { nacc, nde, .. } = self.slots;
                let (acc, out) = (&w.acc, &mut w.dv);
                let bnd = &p.bnd;
                SumRates { dim, n, lda: dim * nt, nterm: nacc, acc, grav: &self.grav, out, bnd }.run(b);
                let de = &mut w.de;
                SumRates { dim: 1, n, lda: nt, nterm: nde, acc: &w.dde, grav: &[0.0], out: de, bnd: &[] }.run(b);
            }
            Which::Predict => {
                let (lf, rates, _, _, bnd) = parts(p, w);
                Predict { dim, n, dt_prev: k.dt_prev, cont: self.cont, lf, rates, bnd }.run(b);
            }
            Which::Cfl(cfl, kv, ref eta) => {
                let (h, c, v) = (&p.h[..n], &p.c[..n], &p.v[..dim * n]);
                let (kv, mumax) = match kv {
                    Some(k) => (k, &w.mumax[..n]),
                    None => (0.0, &[][..]),
                };
                let (mat, rho) = (&p.mat[..n], &p.rho[..n]);
                Cfl { dim, cfl, h, c, v, dv: &w.dv, kv, mumax, eta, mat, rho, dt: &mut w.dt_cfl[0] }.run(b);
            }
            Which::Efloor => Efloor { mass: &p.mass[..n], e: &mut p.e[..n], added: &mut w.efloor[0] }.run(b),
            Which::Clamp(lo, hi, _) => Clamp { lo, hi, rho: &mut p.rho[..n] }.run(b),
            Which::Advance => {
                let (first, dt_prev, dt, cont) = (k.first, k.dt_prev, k.dt, self.cont);
                let (lf, rates, av, x, bnd) = parts(p, w);
                Advance { dim, n, first, dt_prev, dt, cont, lf, rates, av, x, bnd }.run(b);
            }
        }
    }
    fn assign(&mut self, slots: Slots) {
        self.slots = slots;
    }
}

/// The gravity the rate sum adds (m/s², `dim` components): `physics.gravity_ms2`, or none where
/// `physics.gravity_in_forces` says a force stage adds it.
pub fn rate_sum_gravity(ctx: &PlanCtx) -> Vec<f64> {
    match &ctx.case.physics.gravity_ms2 {
        Some(g) if !ctx.case.physics.gravity_in_forces => g.clone(),
        _ => vec![0.0; ctx.dim],
    }
}

/// Every case: the rate sums, the leapfrog, and the CFL step unless the step is fixed.
pub fn plan(ctx: &PlanCtx) -> Contribution {
    let case = ctx.case;
    let cont = case.sph.density == DensityKind::Continuity;
    let grav = rate_sum_gravity(ctx);
    let st = |which| -> Box<dyn Stage> {
        Box::new(IntegratorStage { which, cont, grav: grav.clone(), slots: Slots::default() })
    };
    let clamp = case.sph.density_clamp.as_deref().map(|b| (b[0], b[1]));
    let mut stages = vec![(Phase::Predict, st(Which::Predict))];
    if let Some((lo, hi)) = clamp {
        stages.push((Phase::Predict, st(Which::Clamp(lo, hi, true))));
    }
    stages.push((Phase::Sum, st(Which::Sum)));
    let mut why = format!("leapfrog, {:?} step", case.time.step).to_lowercase();
    let kinds: Vec<_> = case.regions.iter().filter_map(|r| r.boundary_particles).collect();
    if !kinds.is_empty() {
        let held = kinds.contains(&crate::case::BoundaryKind::Held);
        why += if held { ", boundary particles fixed (held: rho, e, v too)" } else { ", boundary particles fixed" };
    }
    if case.physics.gravity_in_forces && case.gravity_on() {
        why += ", gravity left to the force stage that includes it";
    }
    if case.time.step == StepRule::Cfl {
        // the viscous signal speed, where there is a viscosity with a β term
        let v = &case.viscosity;
        let visc = v.alpha > 0.0 || v.beta > 0.0;
        let kv = (case.time.viscous_step && visc).then_some(1.2 * v.beta);
        if kv.is_some() {
            why += " with the viscous signal speed";
        }
        let eta: Vec<f64> = case.materials.iter().map(|m| m.dynamic_viscosity_pa_s.unwrap_or(0.0)).collect();
        let eta = if eta.iter().any(|&e| e > 0.0) {
            why += ", at most rho h^2/(8 eta)";
            eta
        } else {
            Vec::new()
        };
        stages.push((Phase::StepSize, st(Which::Cfl(case.time.cfl, kv, eta))));
    }
    stages.push((Phase::Advance, st(Which::Advance)));
    if let Some((lo, hi)) = clamp {
        why += &format!(", density clamped to [{lo}, {hi}] kg/m3");
        stages.push((Phase::Correct, st(Which::Clamp(lo, hi, false))));
    }
    if case.sph.e_floor {
        why += ", floor e >= 0 booked in the balance";
        stages.push((Phase::Correct, st(Which::Efloor)));
    }
    Contribution::run(why, stages)
}
