//! Artificial conductivity (Price 2008, J. Comput. Phys. 227, 10040): an energy exchange within each
//! pair that smooths a jump of the specific internal energy e (J/kg), and with it the "wall
//! heating" of shock-capturing schemes:
//!
//! De_i/Dt += Σ_j m_j α_u v_sig (e_i − e_j)/ρ̄_ij (x̂_ij·∇_i W_ij)  (W/kg),
//!
//! ρ̄_ij = (ρ_i + ρ_j)/2, x̂_ij = x_ij/r_ij; the signal speed (m/s) is √(|p_i − p_j|/ρ̄_ij)
//! (`signal = "pressure"`, Price's, for contact discontinuities) or |v_ij·x̂_ij|
//! (`signal = "velocity"`, for shocks and wall heating). x̂·∇W ≤ 0, so heat flows from the hotter
//! particle; the two ends' terms cancel in Σ m_i De_i/Dt (energy is conserved). Coincident
//! particles exchange nothing. Off by default (`[conductivity] alpha = 0`, docs/reference/cases.md).
//!
//! `kind = "noh"`: the artificial heat of Noh (1987) and Monaghan (1992) as Liu & Liu's book code
//! (2003, `art_heat`) computes it. First the velocity divergence (1/s)
//! div_i = Σ_j (m_j/ρ_j)(v_j − v_i)·∇_i W_ij, then per particle the coefficient (m²/s)
//! q_i = g1 h_i c_i + g2 h_i² (|div_i| − div_i), then
//!
//! De_i/Dt += 2 Σ_j m_j q̄_ij/(ρ̄_ij (r_ij² + φ²)) (e_i − e_j) (x_ij·∇_i W_ij)  (W/kg),
//!
//! q̄, ρ̄ and h̄ the pair means, φ² = 0.01 h̄² (φ = 0.1 h̄). The book has no ρ_i in q_i (Monaghan's
//! ρ_i q_i/(ρ_i ρ_j) form reduces to it). x·∇W ≤ 0: heat flows from the hotter particle, and the
//! pair's terms cancel in Σ m_i De_i/Dt. Plane geometry only (validate refuses it in RZ).
//!
//! Fortran twin: `fortran/src/sph_conductivity.f90`. Tier: 0 ULP (+ − × ÷ √ and `abs` only).

mod ffi;
#[cfg(test)]
mod parity;
mod rust;

use super::nnps::PairList;
use super::{Backend, Contribution, Module, Phase, PlanCtx, Slots, Stage, Terms, Twin};
use crate::case::{ConductivityKind, ConductivitySignal};
use crate::state::{Clock, Field, Particles, Work};

/// `sph_conductivity_price`: the conductive energy rate of every particle of the pair list
/// (ntotal = `mass.len()`).
pub struct Price<'a> {
    pub dim: usize,
    pub pairs: &'a PairList,
    /// ∇_i W_ij per pair, dim × npair.
    pub dwdx: &'a [f64],
    pub x: &'a [f64],
    pub v: &'a [f64],
    pub rho: &'a [f64],
    pub p: &'a [f64],
    pub e: &'a [f64],
    pub mass: &'a [f64],
    /// α_u (dimensionless).
    pub alpha: f64,
    /// The signal speed: 0 pressure (Price), 1 velocity.
    pub signal: i32,
    /// Axisymmetric: 1/r* (1/m) per particle (ntotal; `mass` the planar masses): the i end's
    /// term is weighted by r̄/r_i = (1 + r_j/r_i)/2 and the j end's by (1 + r_i/r_j)/2, so that
    /// the rings (mass 2πr μ) exchange 2π μ_i μ_j r̄ q and the energy is conserved. Empty in plane
    /// geometry.
    pub rinv: &'a [f64],
    /// Energy rate (J/kg/s), ntotal.
    pub dedt: &'a mut [f64],
}

impl Twin for Price<'_> {
    fn rust(&mut self) {
        rust::price(self)
    }
    fn fortran(&mut self) {
        ffi::price(self)
    }
}

/// `sph_conductivity_noh`: the artificial heat's energy rate of every particle of the pair list
/// (ntotal = `mass.len()`).
pub struct Noh<'a> {
    pub dim: usize,
    pub pairs: &'a PairList,
    /// ∇_i W_ij per pair, dim × npair.
    pub dwdx: &'a [f64],
    pub x: &'a [f64],
    pub v: &'a [f64],
    pub h: &'a [f64],
    pub rho: &'a [f64],
    pub c: &'a [f64],
    pub e: &'a [f64],
    pub mass: &'a [f64],
    pub coef: HeatCoef,
    /// Energy rate (J/kg/s), ntotal.
    pub dedt: &'a mut [f64],
}

/// The artificial heat's constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeatCoef {
    /// g1 (dimensionless).
    pub g1: f64,
    /// g2 (dimensionless).
    pub g2: f64,
    /// φ²/h̄² (dimensionless): 0.01, the book's `0.01*mhsml**2`.
    pub phi2: f64,
}

impl HeatCoef {
    /// φ²/h̄² = 0.01 (φ = 0.1 h̄).
    pub const PHI2: f64 = 0.01;
}

impl Twin for Noh<'_> {
    fn rust(&mut self) {
        rust::noh(self)
    }
    fn fortran(&mut self) {
        ffi::noh(self)
    }
}

/// The artificial heat's term of the energy-rate sum (the conductivity's slot).
pub struct HeatStage {
    pub coef: HeatCoef,
    pub slots: Slots,
}

impl Stage for HeatStage {
    fn module(&self) -> Module {
        Module::Conductivity
    }
    fn name(&self) -> &'static str {
        "conductivity.noh"
    }
    fn reads(&self) -> &[Field] {
        use Field::*;
        &[PairI, PairJ, Dwdx, X, V, H, Rho, C, E, Mass]
    }
    fn writes(&self) -> &[Field] {
        &[Field::Dde]
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        self.slots.size(w, p.dim, p.ntotal);
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, nt) = (p.dim, p.ntotal);
        Noh {
            dim,
            pairs: &w.pairs,
            dwdx: &w.dwdx,
            x: &p.x[..dim * nt],
            v: &p.v[..dim * nt],
            h: &p.h[..nt],
            rho: &p.rho[..nt],
            c: &p.c[..nt],
            e: &p.e[..nt],
            mass: &p.mass[..nt],
            coef: self.coef,
            dedt: &mut w.dde[self.slots.de_range(nt)],
        }
        .run(b);
    }
    fn terms(&self) -> Terms {
        Terms { acc: None, de: Some(3) }
    }
    fn assign(&mut self, slots: Slots) {
        self.slots = slots;
    }
}

/// The conductive term of the energy-rate sum.
pub struct ConductivityStage {
    alpha: f64,
    signal: i32,
    slots: Slots,
    /// Axisymmetric: the planar masses and the ring weights.
    rz: bool,
}

impl Stage for ConductivityStage {
    fn module(&self) -> Module {
        Module::Conductivity
    }
    fn name(&self) -> &'static str {
        "conductivity.price"
    }
    fn reads(&self) -> &[Field] {
        use Field::*;
        if self.rz {
            &[PairI, PairJ, Dwdx, X, V, Rho, P, E, Pmass, Rinv]
        } else {
            &[PairI, PairJ, Dwdx, X, V, Rho, P, E, Mass]
        }
    }
    fn writes(&self) -> &[Field] {
        &[Field::Dde]
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        self.slots.size(w, p.dim, p.ntotal);
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, nt) = (p.dim, p.ntotal);
        Price {
            dim,
            pairs: &w.pairs,
            dwdx: &w.dwdx,
            x: &p.x[..dim * nt],
            v: &p.v[..dim * nt],
            rho: &p.rho[..nt],
            p: &p.p[..nt],
            e: &p.e[..nt],
            mass: if self.rz { &w.pmass[..nt] } else { &p.mass[..nt] },
            alpha: self.alpha,
            signal: self.signal,
            rinv: if self.rz { &w.rinv[..nt] } else { &[] },
            dedt: &mut w.dde[self.slots.de_range(nt)],
        }
        .run(b);
    }
    fn terms(&self) -> Terms {
        Terms { acc: None, de: Some(3) }
    }
    fn assign(&mut self, slots: Slots) {
        self.slots = slots;
    }
}

/// Runs where `conductivity.alpha` > 0 (Price), or with `kind = "noh"` where g1 or g2 > 0.
pub fn plan(ctx: &PlanCtx) -> Contribution {
    let c = &ctx.case.conductivity;
    if c.kind == ConductivityKind::Noh {
        let (g1, g2) = (c.g1(), c.g2());
        let why = format!("artificial heat (Noh), g1 = {g1}, g2 = {g2}");
        if !c.on() {
            return Contribution::skip(format!("{why} (off)"));
        }
        let st = HeatStage { coef: HeatCoef { g1, g2, phi2: HeatCoef::PHI2 }, slots: Slots::default() };
        return Contribution::run(why, vec![(Phase::Rates, Box::new(st))]);
    }
    let signal = match c.signal {
        ConductivitySignal::Pressure => 0,
        ConductivitySignal::Velocity => 1,
    };
    let why = format!("alpha_u = {}, {:?} signal speed", c.alpha, c.signal).to_lowercase();
    if c.on() {
        let st = ConductivityStage { alpha: c.alpha, signal, slots: Slots::default(), rz: ctx.case.axisymmetric() };
        Contribution::run(why, vec![(Phase::Rates, Box::new(st))])
    } else {
        Contribution::skip("alpha_u = 0 (off)")
    }
}
