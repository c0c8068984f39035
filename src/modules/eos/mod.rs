//! Equations of state: p (Pa) and c (m/s) from ρ (kg/m³) and e (J/kg), per material.
//! Ideal gas p = (γ−1)ρe, c = √(γ(γ−1)e); JWL (4-39) times the burn fraction λ, plus (1 − λ) times
//! the unreacted explosive's Mie–Grüneisen pressure (linear Us–Up, energy above e_chem) when it has
//! one, c² blended the same way (theory.md §8, §9); water polynomial (4-40, 4-41); soil Mie–Grüneisen with a linear Us–Up Hugoniot (4-42…4-46);
//! porous compaction (Laine & Sandvik 2001): ρ_max ← max(ρ_max, ρ), p = p_c(ρ_max) + c_u(ρ_max)² (ρ − ρ_max)
//! (Pa), c = c_u(ρ_max) (m/s), p_c the plastic compaction curve and c_u the bulk sound speed of the
//! elastic unloading line, both piecewise linear tables in ρ (kg/m³). The sound speed is
//! the isentropic c² = ∂p/∂ρ|_e + (p/ρ²) ∂p/∂e|_ρ, floored at 1 % of the reference speed; p is
//! floored at the material's pmin. Fortran twin: `fortran/src/sph_eos.f90`.
//!
//! Tier: 0 ULP where only + − × ÷ √ are involved (ideal gas, water, soil); JWL calls `exp`, which
//! both sides take from the same C library, so it is 0 ULP too (see docs/howto/add-module.md).

mod ffi;
#[cfg(test)]
mod parity;
mod rust;

pub use rust::{point, point_hist};

use super::param::{EosKind, MatTable};
use super::{Backend, Contribution, Module, Phase, PlanCtx, Stage, Tolerance, Twin};
use crate::state::{Clock, Field, Particles, Work};

/// `sph_eos_eval`: p and c of the first `mat.len()` particles.
pub struct Eval<'a> {
    pub mt: &'a MatTable,
    /// Material of each particle (0-based).
    pub mat: &'a [i32],
    /// Burn fraction of each particle (programmed burn), or empty.
    pub burn: &'a [f64],
    /// Compaction history: the largest density each particle has reached (kg/m³), updated; or
    /// empty (every compaction material on its loading curve).
    pub rho_max: &'a mut [f64],
    pub rho: &'a [f64],
    pub e: &'a [f64],
    pub p: &'a mut [f64],
    pub c: &'a mut [f64],
}

impl Twin for Eval<'_> {
    fn rust(&mut self) {
        rust::eval(self)
    }
    fn fortran(&mut self) {
        ffi::eval(self)
    }
}

/// p and c of the real particles, and their compaction history where a material compacts.
pub struct EosStage {
    pub(crate) mt: MatTable,
}

impl EosStage {
    /// True when some material of the table is a compaction EOS (it carries `rho_max`).
    fn compacts(&self) -> bool {
        self.mt.mtype.contains(&(EosKind::Compaction as i32))
    }
}

impl Stage for EosStage {
    fn module(&self) -> Module {
        Module::Eos
    }
    fn name(&self) -> &'static str {
        "eos.eval"
    }
    /// e is read unless every material's EOS is one of ρ alone (Tait, Morris, or none).
    fn reads(&self) -> &[Field] {
        let of_rho_alone =
            self.mt.mtype.iter().all(|&k| [EosKind::Tait, EosKind::Morris, EosKind::None].iter().any(|&t| k == t as i32));
        if self.compacts() {
            &[Field::Rho, Field::E, Field::Mat, Field::Burn, Field::RhoMax]
        } else if of_rho_alone {
            &[Field::Rho, Field::Mat, Field::Burn]
        } else {
            &[Field::Rho, Field::E, Field::Mat, Field::Burn]
        }
    }
    fn writes(&self) -> &[Field] {
        if self.compacts() { &[Field::P, Field::C, Field::RhoMax] } else { &[Field::P, Field::C] }
    }
    /// The history starts at the particle's density (the set-up's, geostatic or uniform).
    fn register(&self, p: &mut Particles) {
        if self.compacts() {
            p.rho_max = p.rho[..p.nreal].to_vec();
        }
    }
    fn run(&self, b: Backend, p: &mut Particles, _w: &mut Work, _k: &Clock) {
        let n = p.nreal;
        let burn: &[f64] = if p.burn.is_empty() { &[] } else { &p.burn[..n] };
        let rho_max: &mut [f64] = if p.rho_max.is_empty() { &mut [] } else { &mut p.rho_max[..n] };
        Eval {
            mt: &self.mt,
            mat: &p.mat[..n],
            burn,
            rho_max,
            rho: &p.rho[..n],
            e: &p.e[..n],
            p: &mut p.p[..n],
            c: &mut p.c[..n],
        }
        .run(b);
    }
    fn real_rows(&self) -> &[Field] {
        if self.compacts() { &[Field::P, Field::C, Field::RhoMax] } else { &[Field::P, Field::C] }
    }
    fn tolerance(&self) -> Tolerance {
        if self.mt.has_jwl() {
            Tolerance { ulp: 0, why: "JWL calls exp: both sides take it from the same C library" }
        } else {
            Tolerance::default()
        }
    }
}

/// Every case evaluates its EOS: once before the first step and at every step.
pub fn plan(ctx: &PlanCtx) -> Contribution {
    let kinds: Vec<&str> = ctx.case.materials.iter().map(|m| m.eos.kind()).collect();
    let stage = || Box::new(EosStage { mt: ctx.mt.clone() }) as Box<dyn Stage>;
    Contribution::run(kinds.join(", "), vec![(Phase::Init, stage()), (Phase::Eos, stage())])
}
