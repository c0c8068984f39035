//! The smoothing length as Liu & Liu's book code evolves it with `sle = 2` (`--compat
//! liu-book,h_upgrade`; docs/compat-liu-book.md §9), item `h_upgrade`: inside the step, after the
//! forces, `h_upgrade` takes the velocity divergence over the pairs and moves h by a whole step at
//! once (no separate rate and update, no θ, no cap):
//!
//! ```text
//! vcc(i) += mass(j)*hvcc/rho(j), vcc(j) += mass(i)*hvcc/rho(i)   (pair order)
//!   with hvcc = sum_d (vx(d,j) - vx(d,i))*dwdx(d,k)
//! hsml(i) = hsml(i) + dt*((hsml(i)/dim)*vcc(i))
//! if (hsml(i) <= 0) hsml(i) = hsml(i) - dt*dhsml(i)
//! ```
//!
//! i.e. h_i ← h_i + Δt (h_i/d) Σ_j (m_j/ρ_j)(v_j − v_i)·∇_i W_ij (m), real particles only. Planar
//! cases only. No Fortran twin in blastsph's core.

use super::{Flags, Item};
use crate::modules::{Backend, Contribution, Counterpart, Module, Phase, PlanCtx, Stage, by_dim};
use crate::state::{Clock, Field, Particles, Work};

/// `h_upgrade` with `sle = 2`: h moved by a whole step from the velocity divergence.
pub struct HUpgrade {
    /// The case's fixed step (s): the book's `dt`, known before the rates (the clock's step is
    /// set after them when the step is a CFL one).
    dt: Option<f64>,
    why: &'static str,
}

fn run_d<const D: usize, const W: usize>(p: &mut Particles, w: &Work, dt: f64) {
    let (nt, n) = (p.ntotal, p.nreal);
    let (pl, dwdx) = (&w.pairs, &w.dwdx);
    let (mass, rho, v) = (&p.mass[..nt], &p.rho[..nt], &p.v[..D * nt]);
    let mut vcc = vec![0.0; nt];
    for k in 0..pl.len() {
        let (i, j) = (pl.i[k] as usize, pl.j[k] as usize);
        let g = &dwdx[D * k..D * k + D];
        // hvcc = dvx(1)*dwdx(1,k), then + dvx(d)*dwdx(d,k), dvx = vx(:,j) - vx(:,i)
        let mut hvcc = (v[D * j] - v[D * i]) * g[0];
        for d in 1..D {
            hvcc += (v[d + D * j] - v[d + D * i]) * g[d];
        }
        vcc[i] += mass[j] * hvcc / rho[j];
        vcc[j] += mass[i] * hvcc / rho[i];
    }
    let h = &mut p.h[..n];
    for i in 0..n {
        let dh = (h[i] / D as f64) * vcc[i];
        h[i] += dt * dh;
        if h[i] <= 0.0 {
            h[i] -= dt * dh;
        }
    }
}

impl Stage for HUpgrade {
    fn module(&self) -> Module {
        Module::Smoothing
    }
    fn name(&self) -> &'static str {
        "smoothing.h_upgrade"
    }
    fn reads(&self) -> &[Field] {
        &[Field::PairI, Field::PairJ, Field::Dwdx, Field::Mass, Field::Rho, Field::V, Field::H]
    }
    fn writes(&self) -> &[Field] {
        &[Field::H]
    }
    fn run(&self, _b: Backend, p: &mut Particles, w: &mut Work, k: &Clock) {
        by_dim!(p.dim, 0, run_d(p, w, self.dt.unwrap_or(k.dt)))
    }
    fn counterpart(&self) -> Counterpart {
        Counterpart::None(self.why)
    }
}

/// The book's h_upgrade in place of the rate and the update, when `h_upgrade` is on and the case
/// evolves h by its rate (`smoothing = "rate"`).
pub fn plan(ctx: &PlanCtx, f: Flags) -> Option<Contribution> {
    let sph = &ctx.case.sph;
    if !f.has(Item::HUpgrade) || sph.smoothing != crate::case::SmoothingKind::Rate || ctx.case.axisymmetric() {
        return None;
    }
    let why: &'static str = Box::leak(format!("smoothing: {}", f.label()).into_boxed_str());
    let t = &ctx.case.time;
    let dt = (t.step == crate::case::StepRule::Fixed).then_some(t.dt_s).flatten();
    Some(Contribution::run(
        format!("h_upgrade, sle = 2 [compat {}]", f.label()),
        vec![(Phase::Rates, Box::new(HUpgrade { dt, why }) as Box<dyn Stage>)],
    ))
}
