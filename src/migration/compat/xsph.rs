//! XSPH as Liu & Liu's book code computes it (`--compat`; docs/compat-liu-book.md §8), item
//! `xsph_expr`: `av_i −= ((2 m_j) dv / (ρ_i + ρ_j)) W_ij`, `av_j += ((2 m_i) dv / (ρ_i + ρ_j)) W_ij`
//! per component in pair order (dv = v_i − v_j), then `av = ε av` (the book's ε = 0.3 is a
//! single-precision literal: with `literals` the case's `xsph_eps` is rounded so). Where the book
//! adds av (to v, without Δt) is the integrator's item `xsph_velocity`. No Fortran twin in
//! blastsph's core.

use super::{Flags, Item};
use crate::modules::xsph::XsphStage;
use crate::modules::{Backend, Contribution, Counterpart, Phase, PlanCtx, Stage, par_rows};
use crate::state::{Clock, Particles, Work};

/// The book's av_vel.
pub struct XsphCompat {
    normal: XsphStage,
    why: &'static str,
}

impl Stage for XsphCompat {
    super::as_its_normal_stage!();

    fn run(&self, _b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, nt, eps) = (p.dim, p.ntotal, self.normal.eps);
        let (mass, rho, v) = (&p.mass[..nt], &p.rho[..nt], &p.v[..dim * nt]);
        let pl = &w.pairs;
        let (pi, pj, wk) = (&pl.i, &pl.j, &w.w);
        par_rows(&mut w.av[..dim * nt], dim, |a, av| {
            for d in 0..dim {
                let mut s = 0.0;
                for inc in pl.incident(a) {
                    let k = inc.pair();
                    let (i, j) = (pi[k] as usize, pj[k] as usize);
                    let dv = v[d + dim * i] - v[d + dim * j];
                    let t = 2.0 * mass[inc.other()] * dv / (rho[i] + rho[j]) * wk[k];
                    if inc.is_i() {
                        s -= t;
                    } else {
                        s += t;
                    }
                }
                av[d] = eps * s;
            }
        });
    }
    fn counterpart(&self) -> Counterpart {
        Counterpart::None(self.why)
    }
}

/// The book's XSPH term, when `xsph_expr` is on (and the case has XSPH).
pub fn plan(ctx: &PlanCtx, f: Flags) -> Option<Contribution> {
    let eps = ctx.case.sph.xsph_eps;
    // the book is planar: an axisymmetric case keeps blastsph's twin
    if !f.has(Item::XsphExpr) || eps <= 0.0 || ctx.case.axisymmetric() {
        return None;
    }
    let why: &'static str = Box::leak(format!("xsph: {}", f.label()).into_boxed_str());
    let st = XsphCompat { normal: XsphStage { eps, rz: false }, why };
    Some(Contribution::run(
        format!("eps = {eps} [compat {}]", f.label()),
        vec![(Phase::Rates, Box::new(st) as Box<dyn Stage>)],
    ))
}
