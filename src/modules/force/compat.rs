//! The internal force as Liu & Liu's book code computes it (`--compat`;
//! docs/compat-liu-book.md §6), item `force_energy`: the acceleration has blastsph's bits
//! (`h = −(p_i/ρ_i² + p_j/ρ_j²) ∂W/∂x_d`, `+ m_j h` at i, `− m_i h` at j), the energy rate is the
//! book's: per pair `he = Σ_d (v_j − v_i)_d h_d` (from 0), `dedt_i += m_j he`, `dedt_j += m_i he`
//! in pair order, then `dedt = tdsdt + 0.5 dedt` with the book's tdsdt = 0 for an inviscid gas.
//! Fluids only (the book has no stress): with strength the module keeps blastsph's twin. No
//! Fortran twin in blastsph's core.

use super::ForceStage;
use crate::migration::compat::{Flags, Item};
use crate::modules::{
    Backend, Contribution, Counterpart, Module, Phase, PlanCtx, Slots, Stage, Terms, by_dim, gather_signed, par_rows,
};
use crate::state::{Clock, Field, Particles, Work};

/// The book's int_force (pa_sph = 2, inviscid), after its EOS.
pub struct ForceCompat {
    normal: ForceStage,
    why: &'static str,
}

fn run_d<const D: usize, const W: usize>(p: &Particles, w: &mut Work, slots: Slots) {
    let nt = p.ntotal;
    let (mass, rho, pr, v) = (&p.mass[..nt], &p.rho[..nt], &p.p[..nt], &p.v[..D * nt]);
    let Work { pairs: pl, dwdx, acc, dde, .. } = w;
    let np = pl.len();
    let mut guard = pl.scratch.lock();
    let buf = &mut *guard;
    buf.part.resize(nt, 0.0);
    // p(i)/rho(i)**2 per particle: the same operations as per pair
    par_rows(&mut buf.part[..nt], 1, |i, s| s[0] = pr[i] / (rho[i] * rho[i]));
    buf.pair.resize(W * np, 0.0);
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
    fn module(&self) -> Module {
        Module::Force
    }
    fn name(&self) -> &'static str {
        "force.internal"
    }
    fn reads(&self) -> &[Field] {
        self.normal.reads()
    }
    fn writes(&self) -> &[Field] {
        self.normal.writes()
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        self.normal.prepare(p, w)
    }
    fn run(&self, _b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let slots = self.normal.slots;
        by_dim!(p.dim, 1, run_d(p, w, slots))
    }
    fn terms(&self) -> Terms {
        self.normal.terms()
    }
    fn assign(&mut self, slots: Slots) {
        self.normal.assign(slots)
    }
    fn counterpart(&self) -> Counterpart {
        Counterpart::None(self.why)
    }
}

/// The book's energy rate, when `force_energy` is on and the case has no strength.
pub fn plan(ctx: &PlanCtx, f: Flags) -> Option<Contribution> {
    // the book is planar: an axisymmetric case keeps blastsph's twin
    if !f.has(Item::ForceEnergy) || crate::setup::has_strength(ctx.case) || ctx.case.axisymmetric() {
        return None;
    }
    let why: &'static str = Box::leak(format!("force: {}", f.label()).into_boxed_str());
    let stage = ForceCompat { normal: ForceStage { slots: Slots::default(), rz: false, asym: false }, why };
    Some(Contribution::run(
        format!("pressure only [compat {}]", f.label()),
        vec![(Phase::Rates, Box::new(stage) as Box<dyn Stage>)],
    ))
}
