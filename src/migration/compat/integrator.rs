//! Liu & Liu's time integration and rate sums (`--compat`; docs/compat-liu-book.md §10, §11):
//! - `energy_floor`: after each update of u, `if (u < 0) u = 0`;
//! - `xsph_velocity`: the XSPH correction added to the velocity itself, without Δt,
//!   `v = (v + Δt/2 dv) + av` (first step), `v = (v_min + Δt dv) + av` (later), then `x += Δt v`;
//!   blastsph keeps v and moves x by Δt (v + av);
//! - `rate_sum`: `dv = (force + external) + viscosity`, `du = (force + viscosity) + 0` (the book's
//!   zeroed external and artificial-heat arrays added) for the real particles only (a boundary
//!   particle keeps dv = 0 and the force's du), and the source terms of `nsym = 0` in 1D,
//!   `du + (−(((0 p) v)/x)/ρ)` (±0, or NaN for a particle at x = 0, as in the book).
//!
//! The leapfrog is otherwise blastsph's, which is the book's for a fixed step (Δt/2 = ½ Δt,
//! ½ (Δt + Δt) = Δt exactly). No Fortran twin in blastsph's core.

use super::{Flags, Item};
use crate::modules::integrator::{IntegratorStage, Which, size_leapfrog};
use crate::modules::param::NSTR;
use crate::modules::{Backend, Contribution, Counterpart, Module, Phase, PlanCtx, Slots, Stage};
use crate::state::{Clock, Field, Particles, Work};

/// Which stage of the book's integration.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Part {
    Predict,
    Sum,
    Advance,
}

/// A stage of the book's time integration.
pub struct IntegratorCompat {
    part: Part,
    normal: IntegratorStage,
    f: Flags,
    /// The acceleration slot of the viscosity, if the case has one (the book adds it last).
    visc_slot: Option<usize>,
    why: &'static str,
}

/// Boundary particles ([`crate::case::BoundaryKind`]): a held one keeps ρ, e, v, τ and x; an
/// integrated one advances all but x; neither takes gravity (as the normal leapfrog).
fn held(p: &Particles, i: usize) -> bool {
    p.bnd.get(i) == Some(&(crate::case::BoundaryKind::Held as i32))
}

/// See [`held`]: a boundary particle of either kind.
fn fixed(p: &Particles, i: usize) -> bool {
    p.bnd.get(i).is_some_and(|&k| k != 0)
}

/// The 1D source term of nsym = 0: `-nsym*p(i)*vx(1,i)/x(1,i)/rho(i)` (and without p for ρ).
fn src(on: bool, dim: usize, p: f64, v: f64, x: f64, rho: f64) -> Option<f64> {
    (on && dim == 1).then(|| -((((0.0 * p) * v) / x) / rho))
}

impl IntegratorCompat {
    fn predict(&self, p: &mut Particles, w: &mut Work, k: &Clock) {
        let (dim, n, f) = (p.dim, p.nreal, self.f);
        let half = 0.5 * k.dt_prev;
        let (floor, rs) = (f.has(Item::EnergyFloor), f.has(Item::RateSum));
        for i in 0..n {
            w.e_min[i] = p.e[i];
            if self.normal.cont {
                w.rho_min[i] = p.rho[i];
            }
            for d in 0..dim {
                w.v_min[d + dim * i] = p.v[d + dim * i];
            }
            if held(p, i) {
                continue;
            }
            let t = src(rs, dim, p.p[i], p.v[dim * i], p.x[dim * i], p.rho[i]);
            let mut u = p.e[i] + half * t.map_or(w.de[i], |t| w.de[i] + t);
            if floor && u < 0.0 {
                u = 0.0;
            }
            p.e[i] = u;
            if self.normal.cont {
                let t = src(rs, dim, p.rho[i], p.v[dim * i], p.x[dim * i], 1.0);
                p.rho[i] += half * t.map_or(w.drho[i], |t| w.drho[i] + t);
            }
            for d in 0..dim {
                let l = d + dim * i;
                p.v[l] += half * w.dv[l];
            }
        }
        if !p.tau.is_empty() {
            for l in 0..NSTR * n {
                w.tau_min[l] = p.tau[l];
                if !held(p, l / NSTR) {
                    p.tau[l] += half * w.dtau[l];
                }
            }
        }
    }

    fn sum(&self, p: &Particles, w: &mut Work) {
        let (dim, n, nt) = (p.dim, p.nreal, p.ntotal);
        let Slots { nacc, nde, .. } = self.normal.slots;
        let (lda, g, vs) = (dim * nt, &self.normal.grav, self.visc_slot);
        for i in 0..n {
            if fixed(p, i) {
                // the book sums the rates of the real particles only: a virtual particle's dvx
                // is never written (a static local array, 0 as gfortran lays it out), and its
                // du is int_force's alone
                w.dv[dim * i..dim * (i + 1)].fill(0.0);
                w.de[i] = if nde > 0 { w.dde[i] } else { 0.0 };
                continue;
            }
            for d in 0..dim {
                let l = d + dim * i;
                // exdvxdt: gravity set first, then the other external terms added
                let mut ext = g[d];
                for t in (1..nacc).filter(|&t| Some(t) != vs) {
                    ext += w.acc[l + lda * t];
                }
                let force = if nacc > 0 { w.acc[l] } else { 0.0 };
                let visc = vs.map_or(0.0, |t| w.acc[l + lda * t]);
                w.dv[l] = (force + ext) + visc;
            }
            // du = du + avdudt + ahdudt: the artificial heat's slot (conductivity.noh) comes last
            let mut s = if nde > 0 { w.dde[i] } else { 0.0 };
            for t in 1..nde {
                s += w.dde[i + nt * t];
            }
            w.de[i] = s + 0.0;
        }
    }

    fn advance(&self, p: &mut Particles, w: &mut Work, k: &Clock) {
        let (dim, n, f, dt) = (p.dim, p.nreal, self.f, k.dt);
        let sc = if k.first { 0.5 * dt } else { 0.5 * (k.dt_prev + dt) };
        let (floor, rs, xv) = (f.has(Item::EnergyFloor), f.has(Item::RateSum), f.has(Item::XsphVelocity));
        let av = &w.av;
        for i in 0..n {
            if held(p, i) {
                continue;
            }
            let t = src(rs, dim, p.p[i], p.v[dim * i], p.x[dim * i], p.rho[i]);
            let du = t.map_or(w.de[i], |t| w.de[i] + t);
            let mut u = if k.first { p.e[i] + sc * du } else { w.e_min[i] + sc * du };
            if floor && u < 0.0 {
                u = 0.0;
            }
            p.e[i] = u;
            if self.normal.cont {
                let t = src(rs, dim, p.rho[i], p.v[dim * i], p.x[dim * i], 1.0);
                let dr = t.map_or(w.drho[i], |t| w.drho[i] + t);
                p.rho[i] = if k.first { p.rho[i] + sc * dr } else { w.rho_min[i] + sc * dr };
            }
            for d in 0..dim {
                let l = d + dim * i;
                let mut v = if k.first { p.v[l] + sc * w.dv[l] } else { w.v_min[l] + sc * w.dv[l] };
                if xv {
                    v += if av.is_empty() { 0.0 } else { av[l] };
                }
                p.v[l] = v;
                if !fixed(p, i) {
                    p.x[l] += if xv || av.is_empty() { dt * v } else { dt * (v + av[l]) };
                }
            }
        }
        if !p.tau.is_empty() {
            for l in 0..NSTR * n {
                if held(p, l / NSTR) {
                    continue;
                }
                p.tau[l] = if k.first { p.tau[l] + sc * w.dtau[l] } else { w.tau_min[l] + sc * w.dtau[l] };
            }
        }
    }
}

impl Stage for IntegratorCompat {
    fn module(&self) -> Module {
        Module::Integrator
    }
    fn name(&self) -> &'static str {
        self.normal.name()
    }
    fn reads(&self) -> &[Field] {
        match self.part {
            Part::Predict | Part::Advance => &[
                Field::Drho,
                Field::De,
                Field::Dv,
                Field::Dtau,
                Field::Av,
                Field::RhoMin,
                Field::P,
                Field::X,
                Field::Bnd,
            ],
            Part::Sum => self.normal.reads(),
        }
    }
    fn writes(&self) -> &[Field] {
        self.normal.writes()
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        self.normal.prepare(p, w);
        if self.part != Part::Sum {
            size_leapfrog(p, w);
        }
    }
    fn run(&self, _b: Backend, p: &mut Particles, w: &mut Work, k: &Clock) {
        match self.part {
            Part::Predict => self.predict(p, w, k),
            Part::Sum => self.sum(p, w),
            Part::Advance => self.advance(p, w, k),
        }
    }
    fn assign(&mut self, slots: Slots) {
        self.normal.assign(slots)
    }
    fn counterpart(&self) -> Counterpart {
        Counterpart::None(self.why)
    }
}

/// The book's integration, when one of its items is on.
pub fn plan(ctx: &PlanCtx, f: Flags) -> Option<Contribution> {
    if ![Item::EnergyFloor, Item::XsphVelocity, Item::RateSum].iter().any(|&i| f.has(i)) {
        return None;
    }
    let normal = crate::modules::integrator::plan(ctx);
    let v = &ctx.case.viscosity;
    let visc_slot = (v.alpha > 0.0 || v.beta > 0.0).then_some(1);
    let why: &'static str = Box::leak(format!("integrator: {}", f.label()).into_boxed_str());
    let stages = normal
        .stages
        .into_iter()
        .map(|(ph, s)| -> (Phase, Box<dyn Stage>) {
            let part = match s.name() {
                "integrator.predict" => Part::Predict,
                "integrator.sum_rates" if f.has(Item::RateSum) => Part::Sum,
                "integrator.advance" => Part::Advance,
                _ => return (ph, s),
            };
            let cont = ctx.case.sph.density == crate::case::DensityKind::Continuity;
            let grav = crate::modules::integrator::rate_sum_gravity(ctx);
            let which = match part {
                Part::Predict => Which::Predict,
                Part::Sum => Which::Sum,
                Part::Advance => Which::Advance,
            };
            let normal = IntegratorStage { which, cont, grav, slots: Slots::default() };
            (ph, Box::new(IntegratorCompat { part, normal, f, visc_slot, why }))
        })
        .collect();
    Some(Contribution::run(format!("{} [compat {}]", normal.why, f.label()), stages))
}
