//! The neighbour search as Liu & Liu's book code decides a pair (`--compat`;
//! docs/compat-liu-book.md §2): items `pair_test` (`sqrt(r²) < κ h_ij` with the integer κ of the
//! kernel, where blastsph tests `r² < (κ h_ij)²`), `virtual_pairs` (i over all particles, so two
//! virtual particles pair too) and `global_h` (link_list's one h, the first particle's). The pairs
//! come in the book's direct_find order (i, then j ascending), which is blastsph's canonical order;
//! link_list's own order is compared as a set by the dual run. No Fortran twin in blastsph's core.
//!
//! The candidates come from blastsph's own Rust search with a support widened by 10⁻⁶ (a
//! superset of both tests); each is then decided by the book's test on the book's operands.

use super::{Flags, Item};
use crate::modules::Twin;
use crate::modules::nnps::Search;
use crate::modules::{Backend, Contribution, Counterpart, Module, PlanCtx, Stage};
use crate::state::{Clock, Field, Particles, Work};

/// The search with the book's pair test.
pub struct SearchCompat {
    cell: bool,
    kappa: f64,
    f: Flags,
    why: &'static str,
}

impl Stage for SearchCompat {
    fn module(&self) -> Module {
        Module::Nnps
    }
    fn name(&self) -> &'static str {
        "nnps.search"
    }
    fn reads(&self) -> &[Field] {
        &[Field::X, Field::H]
    }
    fn writes(&self) -> &[Field] {
        &[Field::PairI, Field::PairJ]
    }
    fn run(&self, _b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, nt, f) = (p.dim, p.ntotal, self.f);
        let x = &p.x[..dim * nt];
        let global: Vec<f64>;
        let h: &[f64] = if f.has(Item::GlobalH) && nt > 0 {
            global = vec![p.h[0]; nt];
            &global
        } else {
            &p.h[..nt]
        };
        let nreal = if f.has(Item::VirtualPairs) { nt } else { p.nreal };
        let wide = self.kappa * (1.0 + 1.0e-6);
        Search { cell: self.cell, dim, nreal, x, h, kappa: wide, pairs: &mut w.pairs }.run(Backend::Rust);
        let (kappa, book) = (self.kappa, f.has(Item::PairTest));
        let scale = kappa.round();
        let keep = |i: usize, j: usize| -> bool {
            let mut r2 = 0.0;
            for d in 0..dim {
                let e = x[d + dim * i] - x[d + dim * j];
                r2 += e * e;
            }
            if book {
                // mhsml = (hsml(i)+hsml(j))/2.; sqrt(driac) .lt. scale_k*mhsml
                r2.sqrt() < scale * ((h[i] + h[j]) / 2.0)
            } else {
                let s = kappa * (0.5 * (h[i] + h[j]));
                r2 < s * s
            }
        };
        let pl = &mut w.pairs;
        let mut n = 0;
        for k in 0..pl.len() {
            let (i, j) = (pl.i[k], pl.j[k]);
            if keep(i as usize, j as usize) {
                pl.i[n] = i;
                pl.j[n] = j;
                n += 1;
            }
        }
        pl.i.truncate(n);
        pl.j.truncate(n);
    }
    fn counterpart(&self) -> Counterpart {
        Counterpart::None(self.why)
    }
}

/// The search with the book's test, when an item of the search is on.
pub fn plan(ctx: &PlanCtx, f: Flags) -> Option<Contribution> {
    if ![Item::PairTest, Item::VirtualPairs, Item::GlobalH].iter().any(|&i| f.has(i)) {
        return None;
    }
    let cell = ctx.case.sph.nnps == crate::case::NnpsKind::Cell;
    let why: &'static str = Box::leak(format!("nnps: {}", f.label()).into_boxed_str());
    let stage = SearchCompat { cell, kappa: ctx.kappa, f, why };
    let what = if cell { "cell search" } else { "direct search" };
    Some(Contribution::run(
        format!("{what} [compat {}]", f.label()),
        vec![(crate::modules::Phase::Search, Box::new(stage) as Box<dyn Stage>)],
    ))
}
