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
use std::sync::{Mutex, MutexGuard};
use verlet::Verlet;

/// One entry of a particle's incidence list: a pair touching it and the pair's other particle.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Inc {
    k: u32,
    o: u32,
}

const SIDE_I: u32 = 1 << 31;

impl Inc {
    /// The pair's index in the list.
    #[inline]
    pub fn pair(self) -> usize {
        self.k as usize
    }
    /// The pair's other particle.
    #[inline]
    pub fn other(self) -> usize {
        (self.o & !SIDE_I) as usize
    }
    /// True when this particle is the pair's `i` (then the other is its `j`).
    #[inline]
    pub fn is_i(self) -> bool {
        self.o & SIDE_I != 0
    }
}

/// Work buffers that the Rust twins reuse from step to step (never part of a result): the pair
/// terms of the pair-sum modules, a per-particle array, per-task lists, and the cell search's
/// grid. Behind a mutex so that modules handed `&PairList` can use them; the solver calls one
/// module at a time, so the lock is never contended. Cloning gives empty buffers.
#[derive(Default)]
pub struct Scratch {
    inner: Mutex<Bufs>,
}

#[derive(Default)]
pub(crate) struct Bufs {
    /// Pair terms, `width` values per pair.
    pub pair: Vec<f64>,
    /// One value per particle.
    pub part: Vec<f64>,
    /// Per-task buffers of pair indices or pairs.
    pub idx_tasks: Vec<Vec<u32>>,
    pub pair_tasks: Vec<Vec<[u32; 2]>>,
    /// Cell grid: cell of each particle, first slot of each cell, particles in cell order, their
    /// positions and h in that order.
    pub cell_of: Vec<u32>,
    pub start: Vec<u32>,
    pub order: Vec<u32>,
    pub xs: Vec<f64>,
    pub hs: Vec<f64>,
    pub fill: Vec<u32>,
    /// Candidate lists kept from step to step (see [`Verlet`]).
    pub verlet: Verlet,
    /// Small per-thread work arrays (a block's intermediate values stay in cache).
    pub per_thread: PerThread,
}

/// One work array per pool thread, each behind its own (never contended) lock.
#[derive(Default)]
pub(crate) struct PerThread(Vec<Mutex<Vec<f64>>>);

impl PerThread {
    /// One array for each thread of the current pool.
    pub(crate) fn ensure(&mut self) {
        let n = rayon::current_num_threads();
        if self.0.len() < n {
            self.0.resize_with(n, Default::default);
        }
    }

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

impl Clone for Scratch {
    fn clone(&self) -> Scratch {
        Scratch::default()
    }
}

impl std::fmt::Debug for Scratch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Scratch")
    }
}

impl Scratch {
    pub(crate) fn lock(&self) -> MutexGuard<'_, Bufs> {
        self.inner.lock().unwrap_or_else(|e| e.into_inner())
    }
    pub(super) fn get_mut(&mut self) -> &mut Bufs {
        self.inner.get_mut().unwrap_or_else(|e| e.into_inner())
    }
}

/// The pair list shared by both backends, and (for the Rust gathers) the incidence lists: for each
/// particle, the pairs that touch it in ascending pair order.
///
/// The canonical list (sorted by i, every i < j: what every search returns) needs no list for
/// the pairs where a particle is the `i`: they are one contiguous row of the list, and they come
/// after every pair where it is the `j` (those have a smaller i, so an earlier row). Only the `j`
/// ends are listed then, one [`Inc`] (8 bytes) per pair. Any other order (a legacy search) lists
/// both ends of every pair, as [`Inc`]s in ascending pair order, with empty rows.
///
/// With more than one thread the listed ends are first built in parts, part p from a contiguous
/// range of pairs (the ranges in ascending order) by its own thread, then merged: a particle's
/// ends from part 0, then part 1, …, so in ascending pair order whatever the number of parts.
#[derive(Debug, Clone, Default)]
pub struct PairList {
    pub i: Vec<i32>,
    pub j: Vec<i32>,
    /// The listed ends, particle a's at `inc.inc[inc.start[a]..inc.start[a + 1]]`.
    inc: IncPart,
    /// With more than one thread: the parts built in parallel, then merged into `inc`.
    parts: Vec<IncPart>,
    row_start: Vec<u32>,
    pub(crate) scratch: Scratch,
}

/// The listed ends of one range of pairs, by particle: particle a's are `inc[start[a]..start[a + 1]]`.
#[derive(Debug, Clone, Default)]
struct IncPart {
    start: Vec<u32>,
    inc: Vec<Inc>,
}

impl IncPart {
    /// Lists the ends of the pairs `pi`, `pj` (the pairs `k0..` of the list) by particle, for
    /// `ntotal` particles: the `j` ends, and the `i` ends too unless `canonical` (a counting sort;
    /// an end outside `0..ntotal` is not listed).
    fn build(&mut self, pi: &[i32], pj: &[i32], k0: usize, canonical: bool, ntotal: usize) {
        // counts of particle a in start[a + 2]; their sum up to a in start[a + 1] (the first slot
        // of a); placing moves start[a + 1] to the first slot of a + 1, so it ends as start[a]
        let slot = |a: i32| usize::try_from(a).ok().filter(|&a| a < ntotal);
        let start = &mut self.start;
        start.clear();
        start.resize(ntotal + 2, 0);
        for (&a, &b) in pi.iter().zip(pj) {
            if !canonical && let Some(a) = slot(a) {
                start[a + 2] += 1;
            }
            if let Some(b) = slot(b) {
                start[b + 2] += 1;
            }
        }
        for a in 1..ntotal + 2 {
            start[a] += start[a - 1];
        }
        let n = start[ntotal + 1] as usize;
        // (never more than it needs: a list sized for both ends is given back when the pair
        // list becomes canonical)
        if self.inc.capacity() > n + n / 4 {
            self.inc = Vec::new();
        }
        self.inc.resize(n, Inc::default());
        let inc = &mut self.inc;
        for (k, (&a, &b)) in pi.iter().zip(pj).enumerate() {
            let k = (k0 + k) as u32;
            if !canonical && let Some(ia) = slot(a) {
                inc[start[ia + 1] as usize] = Inc { k, o: b as u32 | SIDE_I };
                start[ia + 1] += 1;
            }
            if let Some(ib) = slot(b) {
                inc[start[ib + 1] as usize] = Inc { k, o: a as u32 };
                start[ib + 1] += 1;
            }
        }
        start.truncate(ntotal + 1);
    }

    #[inline]
    fn of(&self, a: usize) -> &[Inc] {
        &self.inc[self.start[a] as usize..self.start[a + 1] as usize]
    }
}

/// The pairs touching one particle, in ascending pair order: the listed ends, then the row of
/// pairs where it is the `i` (see [`PairList`]).
#[derive(Debug, Clone)]
pub struct Incident<'a> {
    /// The listed ends.
    pub list: &'a [Inc],
    /// The row: pairs `rows.start..rows.end`, each with this particle as its `i` and `pj[k]` as
    /// the other.
    pub rows: std::ops::Range<usize>,
    pub pj: &'a [i32],
}

impl Iterator for Incident<'_> {
    type Item = Inc;
    #[inline]
    fn next(&mut self) -> Option<Inc> {
        if let Some((&e, rest)) = self.list.split_first() {
            self.list = rest;
            return Some(e);
        }
        let k = self.rows.next()?;
        Some(Inc { k: k as u32, o: self.pj[k] as u32 | SIDE_I })
    }
    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = self.list.len() + self.rows.len();
        (n, Some(n))
    }
}

impl PairList {
    /// A list of the given pairs (i, j), 0-based.
    pub fn new(i: Vec<i32>, j: Vec<i32>) -> PairList {
        PairList { i, j, ..Default::default() }
    }

    pub fn len(&self) -> usize {
        self.i.len()
    }
    pub fn is_empty(&self) -> bool {
        self.i.is_empty()
    }

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

    /// The pairs touching particle `a`, ascending.
    #[inline]
    pub fn incident(&self, a: usize) -> Incident<'_> {
        Incident { list: self.inc.of(a), rows: self.row_start[a] as usize..self.row_start[a + 1] as usize, pj: &self.j }
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
