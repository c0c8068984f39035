//! The equation of state as Liu & Liu's book code computes it (`--compat`;
//! docs/compat-liu-book.md §5): item `sound_speed`, the book's ideal-gas sound speed
//! c = √((γ−1)e) (`p_gas`) where blastsph has the adiabatic √(γ(γ−1)e). The pressure
//! p = ((γ−1)ρ)e is the same operations in the same order as blastsph's. The γ of the book's
//! `p_gas` is the single-precision literal 1.4: with `literals` the case's γ is rounded so
//! (`migration::compat::apply_case`). Other materials keep blastsph's EOS. No Fortran twin in
//! blastsph's core.

use super::{Flags, Item};
use crate::modules::eos::{EosStage, point};
use crate::modules::param::{NPAR, SPH_EOS_IDEAL_GAS, SPH_MP_E1, SPH_MP_PMIN};
use crate::modules::{Backend, Contribution, Counterpart, Module, Phase, PlanCtx, Stage, par_rows2};
use crate::state::{Clock, Field, Particles, Work};

/// p and c of the real particles, the ideal gas as `p_gas`.
pub struct EosCompat {
    normal: EosStage,
    why: &'static str,
}

impl Stage for EosCompat {
    fn module(&self) -> Module {
        Module::Eos
    }
    fn name(&self) -> &'static str {
        "eos.eval"
    }
    fn reads(&self) -> &[Field] {
        self.normal.reads()
    }
    fn writes(&self) -> &[Field] {
        self.normal.writes()
    }
    fn real_rows(&self) -> &[Field] {
        self.normal.real_rows()
    }
    fn run(&self, _b: Backend, p: &mut Particles, _w: &mut Work, _k: &Clock) {
        let n = p.nreal;
        let mt = &self.normal.mt;
        let (mat, burn, rho, e) = (&p.mat[..n], &p.burn, &p.rho[..n], &p.e[..n]);
        par_rows2(&mut p.p[..n], 1, &mut p.c[..n], 1, |i, pi, ci| {
            let m = mat[i] as usize;
            let col = &mt.mpar[NPAR * m..NPAR * (m + 1)];
            if mt.mtype[m] == SPH_EOS_IDEAL_GAS as i32 {
                let g = col[SPH_MP_E1 as usize - 1];
                // p = (gamma-1) * rho * u;  c = sqrt((gamma-1) * u)
                let pp = (g - 1.0) * rho[i] * e[i];
                let pmin = col[SPH_MP_PMIN as usize - 1];
                pi[0] = if pmin > pp { pmin } else { pp };
                ci[0] = ((g - 1.0) * e[i]).sqrt();
            } else {
                let lam = if burn.is_empty() { 1.0 } else { burn[i] };
                let (pp, cc) = point(mt.mtype[m], col, rho[i], e[i], lam);
                pi[0] = pp;
                ci[0] = cc;
            }
        });
    }
    fn tolerance(&self) -> crate::modules::Tolerance {
        self.normal.tolerance()
    }
    fn counterpart(&self) -> Counterpart {
        Counterpart::None(self.why)
    }
}

/// The EOS with the book's ideal gas, when `sound_speed` is on.
pub fn plan(ctx: &PlanCtx, f: Flags) -> Option<Contribution> {
    if !f.has(Item::SoundSpeed) {
        return None;
    }
    let normal = crate::modules::eos::plan(ctx);
    let why: &'static str = Box::leak(format!("eos: {}", f.label()).into_boxed_str());
    let stage = || Box::new(EosCompat { normal: EosStage { mt: ctx.mt.clone() }, why }) as Box<dyn Stage>;
    Some(Contribution::run(
        format!("{} [compat {}]", normal.why, f.label()),
        vec![(Phase::Init, stage()), (Phase::Eos, stage())],
    ))
}
