//! Neighbour search (Liu's direct_find and link_list; docs/theory.md §3).
//!
//! Output: the canonical pair list — every (i, j) with i < j, i real (i < nreal), j any particle,
//! |x_i − x_j| < κ h_ij, h_ij = (h_i + h_j)/2 — sorted by i then j. Every search (direct or cell,
//! Fortran or Rust) returns the same list, so later sums do not depend on the search.
//! Indices are 0-based (`i32`, as at the C boundary).
//!
//! The Rust cell search sizes its cells from the mean h (edge κ h̄/2), not from the largest h as
//! the Fortran does, so that a few expanded particles (detonation products, h up to 5× the rest)
//! do not multiply everyone's candidates. Each pair is found once, by its *owner*: the particle
//! with the clearly larger h (h_a > h_b (1 + 1/16)), or, between similar h, the one that comes
//! first in cell order; the owner's box of half-width κ h_owner (1 + 1/16) ≥ κ h_ij holds every
//! partner. Between similar h a particle thus looks only forward in cell order (half the box), and
//! backward only through rows that hold a clearly smaller h. The test itself is the Fortran's,
//! evaluated with i < j:
//! `s = κ (0.5 (h_i + h_j)); r² < s²`. The pairs are then sorted into the canonical order
//! (counting sort by i, each row sorted by j), so the list is the Fortran's, whatever the order
//! in which they were found and however many threads found them.

mod ffi;
#[cfg(test)]
mod parity;
mod rust;
mod verlet;

use super::{Backend, CHUNK, Contribution, Module, Phase, PlanCtx, Stage, Twin, serial};
use crate::case::NnpsKind;
use crate::state::{Clock, Field, Particles, Work};
use rayon::prelude::*;
pub(crate) use crate::state::pair_list::{Bufs, IncPart, PerThread, SIDE_I, Verlet};
pub use crate::state::pair_list::{Inc, Incident, PairList, Scratch};

impl PerThread {
    /// Runs `f` on the calling thread's array, `len` values long (contents unspecified).
    pub(crate) fn with<R>(&self, len: usize, f: impl FnOnce(&mut [f64]) -> R) -> R {
        let k = rayon::current_thread_index().unwrap_or(0) % self.0.len().max(1);
        let mut g = match self.0.get(k) {
            Some(m) => m.lock().unwrap_or_else(|e| e.into_inner()),
            None => return f(&mut vec![0.0; len]),
        };
        crate::modules::grow(&mut g, len);
        f(&mut g[..len])
    }
}

impl PairList {
    /// Builds the incidence lists for `ntotal` particles (counting sorts, deterministic). For
    /// every pair k, its `i` end comes before its `j` end in the lists. With more than one
    /// thread the pairs are split into a few contiguous ranges, one part each (see
    /// [`PairList`]): the lists do not depend on the number of parts.
    pub fn build_incidence(&mut self, ntotal: usize) {
        let np = self.i.len();
        assert_eq!(np, self.j.len(), "pair list: i and j differ in length");
        assert!(np < SIDE_I as usize, "pair list: {np} pairs, more than 2^31");
        let nr = if serial() || np < 4096 { 1 } else { rayon::current_num_threads().min(4) };
        let (pi, pj) = (&self.i[..np], &self.j[..np]);
        // the canonical order: i ascending, every i < j, every index in range
        let canon_part = |(c, pc): (usize, &[i32])| -> bool {
            let mut prev = if c == 0 { 0 } else { pi[CHUNK * c - 1] };
            pc.iter().zip(&pj[CHUNK * c..]).all(|(&a, &b)| {
                let ok = a >= prev && a < b && (b as usize) < ntotal;
                prev = a;
                ok
            })
        };
        let canonical = if nr == 1 {
            pi.chunks(CHUNK).enumerate().all(canon_part)
        } else {
            pi.par_chunks(CHUNK).enumerate().all(canon_part)
        };
        let rows = &mut self.row_start;
        rows.clear();
        rows.resize(ntotal + 1, 0);
        if canonical {
            // row a: the pairs with i = a, from the first pair with i ≥ a
            let first = |(c, rc): (usize, &mut [u32])| {
                let a0 = c * CHUNK;
                let mut k = pi.partition_point(|&x| (x as usize) < a0);
                for (a, r) in (a0..).zip(rc) {
                    while k < np && (pi[k] as usize) < a {
                        k += 1;
                    }
                    *r = k as u32;
                }
            };
            if nr == 1 {
                rows.chunks_mut(CHUNK).enumerate().for_each(first);
            } else {
                rows.par_chunks_mut(CHUNK).enumerate().for_each(first);
            }
        }
        if nr == 1 {
            self.parts = Vec::new();
            self.inc.build(pi, pj, 0, canonical, ntotal);
            return;
        }
        self.parts.resize_with(nr, IncPart::default);
        self.parts.par_iter_mut().enumerate().for_each(|(r, part)| {
            let (k0, k1) = (np * r / nr, np * (r + 1) / nr);
            part.build(&pi[k0..k1], &pj[k0..k1], k0, canonical, ntotal);
        });
        // the merge: particle a's first slot is the sum of its first slots in the parts; ranges
        // of particles, each copying its particles' ends part by part into its own slice
        let parts = &self.parts;
        let start = &mut self.inc.start;
        start.resize(ntotal + 1, 0);
        start.par_chunks_mut(CHUNK).enumerate().for_each(|(c, sc)| {
            for (a, s) in (CHUNK * c..).zip(sc) {
                *s = parts.iter().map(|p| p.start[a]).sum();
            }
        });
        let n = start[ntotal] as usize;
        let inc = &mut self.inc.inc;
        if inc.capacity() > n + n / 4 {
            *inc = Vec::new();
        }
        inc.resize(n, Inc::default());
        let start = &self.inc.start;
        let mut pieces: Vec<(usize, &mut [Inc])> = Vec::with_capacity(ntotal.div_ceil(CHUNK));
        let mut rest = &mut inc[..];
        for c in 0..ntotal.div_ceil(CHUNK) {
            let (a0, a1) = (CHUNK * c, (CHUNK * c + CHUNK).min(ntotal));
            let (mine, tail) = std::mem::take(&mut rest).split_at_mut((start[a1] - start[a0]) as usize);
            pieces.push((a0, mine));
            rest = tail;
        }
        pieces.into_par_iter().for_each(|(a0, mine)| {
            let mut w = 0;
            for a in a0..(a0 + CHUNK).min(ntotal) {
                for p in parts {
                    let src = p.of(a);
                    mine[w..w + src.len()].copy_from_slice(src);
                    w += src.len();
                }
            }
        });
    }

    /// Forgets the candidate lists the Rust cell search keeps between calls: to be called when
    /// the particles change places in memory (the lists hold particle indices).
    pub fn invalidate(&mut self) {
        self.scratch.get_mut().verlet.valid = false;
    }

}

/// `sph_nnps_direct` / `sph_nnps_cell`: the canonical pair list of `ntotal = h.len()` particles,
/// the first `nreal` real.
pub struct Search<'a> {
    /// The cell search (else the direct all-pairs search).
    pub cell: bool,
    pub dim: usize,
    pub nreal: usize,
    pub x: &'a [f64],
    pub h: &'a [f64],
    /// Kernel support in units of h.
    pub kappa: f64,
    pub pairs: &'a mut PairList,
}

impl Twin for Search<'_> {
    fn rust(&mut self) {
        rust::search(self)
    }
    fn fortran(&mut self) {
        ffi::search(self)
    }
}

/// The neighbour pairs of every real particle (mirrors included as partners).
pub struct SearchStage {
    cell: bool,
    kappa: f64,
}

impl Stage for SearchStage {
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
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, nt) = (p.dim, p.ntotal);
        let (x, h) = (&p.x[..dim * nt], &p.h[..nt]);
        Search { cell: self.cell, dim, nreal: p.nreal, x, h, kappa: self.kappa, pairs: &mut w.pairs }.run(b);
    }
}

/// Every case searches its neighbours.
pub fn plan(ctx: &PlanCtx) -> Contribution {
    let cell = ctx.case.sph.nnps == NnpsKind::Cell;
    Contribution::run(
        if cell { "cell search" } else { "direct search" },
        vec![(Phase::Search, Box::new(SearchStage { cell, kappa: ctx.kappa }))],
    )
}
