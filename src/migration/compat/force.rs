//! The internal force as Liu & Liu's book code computes it (`--compat`;
//! docs/compat-liu-book.md §6), item `force_energy`: the acceleration has blastsph's bits
//! (`h = −(p_i/ρ_i² + p_j/ρ_j²) ∂W/∂x_d`, `+ m_j h` at i, `− m_i h` at j), the energy rate is the
//! book's: per pair `he = Σ_d (v_j − v_i)_d h_d` (from 0), `dedt_i += m_j he`, `dedt_j += m_i he`
//! in pair order, then `dedt = tdsdt + 0.5 dedt` with the book's tdsdt = 0 for an inviscid gas.
//! Item `pa_sph1` is the book's other form (param.inc's `pa_sph = 1`): per pair and component
//! `h = -(p_i + p_j) ∂W/∂x_d`, `he += (v_j − v_i)_d h`, then `h·(1/(ρ_iρ_j))` scattered as
//! above, and `he·(1/(ρ_iρ_j))` into both energies, halved at the end (m/s², J/kg/s).
//! Fluids only (the book has no stress): with strength the module keeps blastsph's twin. No
//! Fortran twin in blastsph's core.

use super::{Flags, Item};
use crate::modules::force::ForceStage;
use crate::modules::grow;
use crate::modules::{
    Backend, Contribution, Counterpart, Phase, PlanCtx, Slots, Stage, by_dim, gather_signed, par_rows,
};
use crate::state::{Clock, Particles, Work};

/// The book's int_force (pa_sph = 2, or 1 with `pa_sph1`; inviscid), after its EOS.
pub struct ForceCompat {
    normal: ForceStage,
    pa1: bool,
    why: &'static str,
}

/// `pa_sph = 1`: the pair terms -(p_i + p_j) ∂W/∂x_d and their energy, scaled by 1/(ρ_i ρ_j).
fn run_pa1_d<const D: usize, const W: usize>(p: &Particles, w: &mut Work, slots: Slots) {
    let nt = p.ntotal;
    let (mass, rho, pr, v) = (&p.mass[..nt], &p.rho[..nt], &p.p[..nt], &p.v[..D * nt]);
    let Work { pairs: pl, dwdx, acc, dde, .. } = w;
    let np = pl.len();
    let mut guard = pl.scratch.lock();
    let buf = &mut *guard;
    grow(&mut buf.pair, W * np);
    let (pi, pj) = (&pl.i, &pl.j);
    par_rows(&mut buf.pair[..W * np], W, |k, t| {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        let g = &dwdx[D * k..D * k + D];
        // rhoij = 1.e0/(rho(i)*rho(j))
        let rhoij = 1.0 / (rho[i] * rho[j]);
        let mut he = 0.0;
        for d in 0..D {
            // h = -(p(i) + p(j))*dwdx(d,k); he = he + (vx(d,j) - vx(d,i))*h; h = h*rhoij
            let h = -(pr[i] + pr[j]) * g[d];
            he += (v[d + D * j] - v[d + D * i]) * h;
            t[d] = h * rhoij;
        }
        t[D] = he * rhoij;
    });
    let (dvdt, dedt) = (&mut acc[slots.acc_range(D * nt)], &mut dde[slots.de_range(nt)]);
    gather_signed::<D, W>(pl, &buf.pair, mass, None, dvdt, dedt);
    // dedt(i) = tdsdt(i) + 0.5e0*dedt(i), tdsdt = 0
    par_rows(&mut dedt[..nt], 1, |_, e| e[0] = 0.0 + 0.5 * e[0]);
}

fn run_d<const D: usize, const W: usize>(p: &Particles, w: &mut Work, slots: Slots) {
    let nt = p.ntotal;
    let (mass, rho, pr, v) = (&p.mass[..nt], &p.rho[..nt], &p.p[..nt], &p.v[..D * nt]);
    let Work { pairs: pl, dwdx, acc, dde, .. } = w;
    let np = pl.len();
    let mut guard = pl.scratch.lock();
    let buf = &mut *guard;
    grow(&mut buf.part, nt);
    // p(i)/rho(i)**2 per particle: the same operations as per pair
    par_rows(&mut buf.part[..nt], 1, |i, s| s[0] = pr[i] / (rho[i] * rho[i]));
    grow(&mut buf.pair, W * np);
    let sig: &[f64] = &buf.part;
    let (pi, pj) = (&pl.i, &pl.j);
    par_rows(&mut buf.pair[..W * np], W, |k, t| {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        let g = &dwdx[D * k..D * k + D];
        let s = sig[i] + sig[j];
        let mut he = 0.0;
        for d in 0..D {
            let h = -(s * g[d]);
            he += (v[d + D * j] - v[d + D * i]) * h;
            t[d] = h;
        }
        t[D] = he;
    });
    let (dvdt, dedt) = (&mut acc[slots.acc_range(D * nt)], &mut dde[slots.de_range(nt)]);
    gather_signed::<D, W>(pl, &buf.pair, mass, None, dvdt, dedt);
    // dedt(i) = tdsdt(i) + 0.5e0*dedt(i), tdsdt = 0
    par_rows(&mut dedt[..nt], 1, |_, e| e[0] = 0.0 + 0.5 * e[0]);
}

impl Stage for ForceCompat {
    super::as_its_normal_stage!();

    fn run(&self, _b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let slots = self.normal.slots;
        if self.pa1 { by_dim!(p.dim, 1, run_pa1_d(p, w, slots)) } else { by_dim!(p.dim, 1, run_d(p, w, slots)) }
    }
    fn counterpart(&self) -> Counterpart {
        Counterpart::None(self.why)
    }
}

/// The book's energy rate, when `force_energy` is on, or its pa_sph = 1 form (`pa_sph1`), and the
/// case has no strength.
pub fn plan(ctx: &PlanCtx, f: Flags) -> Option<Contribution> {
    let pa1 = f.has(Item::PaSph1);
    // the book is planar: an axisymmetric case keeps blastsph's twin
    if !(f.has(Item::ForceEnergy) || pa1) || crate::setup::has_strength(ctx.case) || ctx.case.axisymmetric() {
        return None;
    }
    let why: &'static str = Box::leak(format!("force: {}", f.label()).into_boxed_str());
    let stage =
        ForceCompat { normal: ForceStage { slots: Slots::default(), rz: false, asym: false, iface: false }, pa1, why };
    Some(Contribution::run(
        format!("pressure only{} [compat {}]", if pa1 { ", pa_sph = 1" } else { "" }, f.label()),
        vec![(Phase::Rates, Box::new(stage) as Box<dyn Stage>)],
    ))
}
