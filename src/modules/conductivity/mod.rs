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
//! Fortran twin: `fortran/src/sph_conductivity.f90`. Tier: 0 ULP (+ − × ÷ √ only).

mod ffi;
#[cfg(test)]
mod parity;
mod rust;

use super::nnps::PairList;
use super::{Backend, Contribution, Module, Phase, PlanCtx, Slots, Stage, Terms, Twin};
use crate::case::ConductivitySignal;
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

/// Runs where `conductivity.alpha` > 0.
pub fn plan(ctx: &PlanCtx) -> Contribution {
    let c = &ctx.case.conductivity;
    let signal = match c.signal {
        ConductivitySignal::Pressure => 0,
        ConductivitySignal::Velocity => 1,
    };
    let why = format!("alpha_u = {}, {:?} signal speed", c.alpha, c.signal).to_lowercase();
    if c.alpha > 0.0 {
        let st = ConductivityStage { alpha: c.alpha, signal, slots: Slots::default(), rz: ctx.case.axisymmetric() };
        Contribution::run(why, vec![(Phase::Rates, Box::new(st))])
    } else {
        Contribution::skip("alpha_u = 0 (off)")
    }
}
