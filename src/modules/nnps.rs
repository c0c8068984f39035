//! Neighbour search (Liu's direct_find and link_list; DESIGN.md "nnps").
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

use super::{Backend, CHUNK, serial};
use crate::legacy;
use rayon::prelude::*;
use std::sync::{Mutex, MutexGuard};

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
        if g.len() < len {
            g.resize(len, 0.0);
        }
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
    fn get_mut(&mut self) -> &mut Bufs {
        self.inner.get_mut().unwrap_or_else(|e| e.into_inner())
    }
}

/// The pair list shared by both backends, and (for the Rust gathers) the incidence lists: for each
/// particle, the pairs that touch it in ascending pair order.
#[derive(Debug, Clone, Default)]
pub struct PairList {
    pub i: Vec<i32>,
    pub j: Vec<i32>,
    inc_start: Vec<u32>,
    inc: Vec<Inc>,
    inc_fill: Vec<u32>,
    pub(crate) scratch: Scratch,
}

impl PairList {
    pub fn len(&self) -> usize {
        self.i.len()
    }
    pub fn is_empty(&self) -> bool {
        self.i.is_empty()
    }

    /// Builds the incidence lists for `ntotal` particles (a counting sort, deterministic). For
    /// every pair k, its entry in the list of `i` comes before its entry in the list of `j`.
    /// With more than one thread the particles are split into a few ranges, each counting and
    /// placing the entries of its own particles (every range reads the whole pair list, in
    /// order, so each list is still in ascending pair order).
    pub fn build_incidence(&mut self, ntotal: usize) {
        let np = self.i.len();
        assert_eq!(np, self.j.len(), "pair list: i and j differ in length");
        let nr = if serial() || np < 4096 { 1 } else { rayon::current_num_threads().min(4) };
        let rsize = ntotal.div_ceil(nr).max(1);
        let (pi, pj) = (&self.i[..np], &self.j[..np]);
        let start = &mut self.inc_start;
        start.clear();
        start.resize(ntotal + 1, 0);
        // counts of range r's particles, in start[a + 1]
        let count = |(r, cnt): (usize, &mut [u32])| {
            let a0 = r * rsize;
            for (&a, &b) in pi.iter().zip(pj) {
                for p in [a as usize, b as usize] {
                    if let Some(c) = p.checked_sub(a0).and_then(|l| cnt.get_mut(l)) {
                        *c += 1;
                    }
                }
            }
        };
        if nr == 1 {
            count((0, &mut start[1..]));
        } else {
            start[1..].par_chunks_mut(rsize).enumerate().for_each(count);
        }
        for a in 0..ntotal {
            start[a + 1] += start[a];
        }
        self.inc.resize(2 * np, Inc::default());
        let fill = &mut self.inc_fill;
        fill.clear();
        fill.extend_from_slice(&start[..ntotal]);
        // range r writes the slots of its particles, start[a0] .. start[a1]
        let mut parts: Vec<(usize, &mut [u32], &mut [Inc])> = Vec::with_capacity(nr);
        let mut rest = &mut self.inc[..];
        let mut base = 0usize;
        for (r, f) in fill.chunks_mut(rsize).enumerate() {
            let a1 = ((r + 1) * rsize).min(ntotal);
            let (mine, tail) = std::mem::take(&mut rest).split_at_mut(start[a1] as usize - base);
            base = start[a1] as usize;
            parts.push((r, f, mine));
            rest = tail;
        }
        let place = |(r, f, mine): (usize, &mut [u32], &mut [Inc])| {
            let a0 = r * rsize;
            let off = f.first().copied().unwrap_or(0) as usize;
            for (k, (&a, &b)) in pi.iter().zip(pj).enumerate() {
                for (p, q, side) in [(a as usize, b as u32, SIDE_I), (b as usize, a as u32, 0)] {
                    if let Some(fp) = p.checked_sub(a0).and_then(|l| f.get_mut(l)) {
                        mine[*fp as usize - off] = Inc { k: k as u32, o: q | side };
                        *fp += 1;
                    }
                }
            }
        };
        if nr == 1 {
            parts.into_iter().for_each(place);
        } else {
            parts.into_par_iter().for_each(place);
        }
    }

    /// Forgets the candidate lists the Rust cell search keeps between calls: to be called when
    /// the particles change places in memory (the lists hold particle indices).
    pub fn invalidate(&mut self) {
        self.scratch.get_mut().verlet.valid = false;
    }

    /// The pairs touching particle `a`, ascending.
    #[inline]
    pub fn incident(&self, a: usize) -> &[Inc] {
        &self.inc[self.inc_start[a] as usize..self.inc_start[a + 1] as usize]
    }
}

/// Finds the pairs. `x`, `h` hold `ntotal = h.len()` particles, the first `nreal` real.
pub fn search(b: Backend, cell: bool, dim: usize, nreal: usize, x: &[f64], h: &[f64], kappa: f64, pl: &mut PairList) {
    match b {
        Backend::Fortran => {
            let mut cap = pl.i.capacity().max(16 * h.len()).max(16);
            loop {
                pl.i.resize(cap, 0);
                pl.j.resize(cap, 0);
                let np = legacy::nnps(cell, dim, nreal, x, h, kappa, &mut pl.i, &mut pl.j);
                if np <= cap {
                    pl.i.truncate(np);
                    pl.j.truncate(np);
                    break;
                }
                cap = np + np / 4;
            }
        }
        Backend::Rust => {
            assert!(x.len() >= dim * h.len(), "nnps: x has {} values, need {}", x.len(), dim * h.len());
            let nreal = nreal.min(h.len());
            if cell { verlet(dim, nreal, x, h, kappa, pl) } else { rust_direct(dim, nreal, x, h, kappa, pl) }
        }
    }
}

#[inline]
fn within(dim: usize, x: &[f64], h: &[f64], kappa: f64, i: usize, j: usize) -> bool {
    let mut r2 = 0.0;
    for d in 0..dim {
        let dxd = x[d + dim * i] - x[d + dim * j];
        r2 += dxd * dxd;
    }
    let s = kappa * (0.5 * (h[i] + h[j]));
    r2 < s * s
}

/// Runs `f(task, buffer)` for `ntask` tasks, each with its own cleared buffer.
fn tasks<T: Send, F>(bufs: &mut Vec<Vec<T>>, ntask: usize, f: F)
where
    F: Fn(usize, &mut Vec<T>) + Sync + Send,
{
    if bufs.len() < ntask {
        bufs.resize_with(ntask, Vec::new);
    }
    let run = |(t, b): (usize, &mut Vec<T>)| {
        b.clear();
        f(t, b)
    };
    if serial() {
        bufs[..ntask].iter_mut().enumerate().for_each(run);
    } else {
        bufs[..ntask].par_iter_mut().enumerate().for_each(run);
    }
}

fn rust_direct(dim: usize, nreal: usize, x: &[f64], h: &[f64], kappa: f64, pl: &mut PairList) {
    let nt = h.len();
    let PairList { i: pi, j: pj, scratch, .. } = pl;
    let s = scratch.get_mut();
    let ntask = nreal.div_ceil(64);
    tasks(&mut s.pair_tasks, ntask, |t, buf| {
        for i in 64 * t..(64 * t + 64).min(nreal) {
            for j in i + 1..nt {
                if within(dim, x, h, kappa, i, j) {
                    buf.push([i as u32, j as u32]);
                }
            }
        }
    });
    pi.clear();
    pj.clear();
    for buf in &s.pair_tasks[..ntask] {
        for &[i, j] in buf {
            pi.push(i as i32);
            pj.push(j as i32);
        }
    }
}

/// Two h are "similar" unless one exceeds the other times ONEP (an exact binary fraction).
const ONEP: f64 = 1.0 + 1.0 / 16.0;

/// A cell grid over the particles sorted by cell.
struct Grid<'a> {
    lo: [f64; 3],
    /// 1 / cell edge.
    inv: f64,
    nc: [usize; 3],
    start: &'a [u32],
    order: &'a [u32],
    xs: &'a [f64],
    hs: &'a [f64],
    kappa: f64,
    nreal: usize,
}

impl Grid<'_> {
    /// The pairs owned by the particles in `slots` (cell order), as [i, j] into `bufs[i / rows]`.
    fn find<const D: usize>(&self, slots: std::ops::Range<usize>, rows: usize, bufs: &mut [Vec<[u32; 2]>]) {
        let Grid { lo, inv, nc, start, order, xs, hs, kappa, nreal } = *self;
        for slot in slots {
            let a = order[slot] as usize;
            let ha = hs[slot];
            let xa: [f64; D] = xs[D * slot..D * slot + D].try_into().unwrap_or([0.0; D]);
            // the box holds every partner a owns: r < κ (h_a + h_b)/2 ≤ κ h_a ONEP
            let rad = kappa * (ha * ONEP);
            let rad = rad + rad * 1e-9;
            let mut clo = [0usize; 3];
            let mut chi = [0usize; 3];
            for d in 0..D {
                let k0 = ((xa[d] - rad - lo[d]) * inv) as isize;
                let k1 = ((xa[d] + rad - lo[d]) * inv) as isize;
                clo[d] = k0.clamp(0, nc[d] as isize - 1) as usize;
                chi[d] = k1.clamp(0, nc[d] as isize - 1) as usize;
            }
            let mut test = |sb: usize| {
                let b = order[sb] as usize;
                let i = a.min(b);
                if i >= nreal {
                    return;
                }
                let hb = hs[sb];
                let xb = &xs[D * sb..D * sb + D];
                // (x_i − x_j)² = (x_a − x_b)² and h_i + h_j = h_a + h_b, exactly
                let mut r2 = 0.0;
                for d in 0..D {
                    let dxd = xa[d] - xb[d];
                    r2 += dxd * dxd;
                }
                let sr = kappa * (0.5 * (ha + hb));
                if r2 < sr * sr {
                    bufs[i / rows].push([i as u32, a.max(b) as u32]);
                }
            };
            for z in clo[2]..=chi[2] {
                for y in clo[1]..=chi[1] {
                    let row = nc[0] * (y + nc[1] * z);
                    let (s0, s1) = (start[row + clo[0]] as usize, start[row + chi[0] + 1] as usize);
                    // later slots: a owns b unless b is clearly larger
                    for sb in s0.max(slot + 1)..s1 {
                        let b_larger = hs[sb] > ha * ONEP;
                        if b_larger {
                            continue;
                        }
                        test(sb);
                    }
                    // earlier slots: a owns b only if a is clearly larger (rarely any)
                    let back = s0..s1.min(slot).max(s0);
                    if hs[back.clone()].iter().any(|&hb| ha > hb * ONEP) {
                        for sb in back {
                            if ha > hs[sb] * ONEP {
                                test(sb);
                            }
                        }
                    }
                }
            }
        }
    }
}

/// The cell search: a uniform grid of edge ≈ κ h̄/2 (h̄ the mean h), particles sorted by cell
/// (counting sort, ascending index within a cell); each particle looks through the cells that
/// meet the box of half-width κ h_a around it and keeps the pairs it owns.
fn rust_cell(dim: usize, nreal: usize, x: &[f64], h: &[f64], kappa: f64, pl: &mut PairList) {
    match dim {
        1 => rust_cell_d::<1>(nreal, x, h, kappa, pl),
        2 => rust_cell_d::<2>(nreal, x, h, kappa, pl),
        _ => rust_cell_d::<3>(nreal, x, h, kappa, pl),
    }
}

/// CSR offsets of `n` bins from the bin of each item (a counting sort's first half):
/// `out[b]..out[b + 1]` is the range of bin b.
fn offsets(out: &mut Vec<u32>, n: usize, bins: impl Iterator<Item = usize>) {
    out.clear();
    out.resize(n + 1, 0);
    for b in bins {
        out[b + 1] += 1;
    }
    for b in 0..n {
        out[b + 1] += out[b];
    }
}

/// The grid over the box lo…hi with cells of side `cs` (m), doubled until there are no more than
/// a few cells per particle (sparse clouds): 1/side and the cells per axis.
fn grid_dims<const D: usize>(lo: &[f64; 3], hi: &[f64; 3], cs: f64, n: usize) -> (f64, [usize; 3]) {
    let mut cs = cs;
    loop {
        let mut prod: u64 = 1;
        for d in 0..D {
            prod = prod.saturating_mul((((hi[d] - lo[d]) / cs) as u64).saturating_add(1));
        }
        if prod <= (4 * n as u64).max(64) {
            break;
        }
        cs *= 2.0;
    }
    let inv = 1.0 / cs;
    let mut nc = [1usize; 3];
    for d in 0..D {
        nc[d] = (((hi[d] - lo[d]) * inv) as usize).saturating_add(1);
    }
    (inv, nc)
}

fn rust_cell_d<const D: usize>(nreal: usize, x: &[f64], h: &[f64], kappa: f64, pl: &mut PairList) {
    let nt = h.len();
    let PairList { i: pi, j: pj, scratch, .. } = pl;
    pi.clear();
    pj.clear();
    if nt == 0 || nreal == 0 {
        return;
    }
    let s = scratch.get_mut();
    // the grid: bounding box, smallest and mean h, in tasks of CHUNK particles (the partial sums
    // added in task order, so h̄ does not depend on the thread count)
    let stats = |c: usize| -> ([f64; 3], [f64; 3], f64, f64) {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let (mut hsum, mut hmin) = (0.0, f64::INFINITY);
        for i in CHUNK * c..(CHUNK * c + CHUNK).min(nt) {
            for d in 0..D {
                lo[d] = lo[d].min(x[d + D * i]);
                hi[d] = hi[d].max(x[d + D * i]);
            }
            hsum += h[i];
            hmin = hmin.min(h[i]);
        }
        (lo, hi, hsum, hmin)
    };
    let nchunk = nt.div_ceil(CHUNK);
    let parts: Vec<_> =
        if serial() { (0..nchunk).map(stats).collect() } else { (0..nchunk).into_par_iter().map(stats).collect() };
    let mut lo = [0.0f64; 3];
    let mut hi = [0.0f64; 3];
    lo[..D].fill(f64::INFINITY);
    hi[..D].fill(f64::NEG_INFINITY);
    let (mut hsum, mut hmin) = (0.0, f64::INFINITY);
    for (plo, phi, ps, pm) in parts {
        for d in 0..D {
            lo[d] = lo[d].min(plo[d]);
            hi[d] = hi[d].max(phi[d]);
        }
        hsum += ps;
        hmin = hmin.min(pm);
    }
    if hmin < 0.0 || kappa.is_nan() || kappa < 0.0 {
        // the owner's box assumes h ≥ 0 and κ ≥ 0; anything else gets the direct search
        return rust_direct(D, nreal, x, h, kappa, pl);
    }
    let hmean = hsum / nt as f64;
    let mut cs = 0.5 * kappa * hmean;
    if !(cs > 0.0 && cs.is_finite()) {
        cs = (0..D).map(|d| hi[d] - lo[d]).fold(1.0, f64::max);
    }
    let (inv, nc) = grid_dims::<D>(&lo, &hi, cs, nt);
    let ncell = nc[0] * nc[1] * nc[2];
    // a particle's cell; the box search below uses the same map, which is monotone in x
    let cell = |p: &[f64]| -> usize {
        let mut c = [0usize; 3];
        for d in 0..D {
            let k = ((p[d] - lo[d]) * inv) as isize;
            c[d] = k.clamp(0, nc[d] as isize - 1) as usize;
        }
        c[0] + nc[0] * (c[1] + nc[1] * c[2])
    };
    s.cell_of.resize(nt, 0);
    let cells = |(c, out): (usize, &mut [u32])| {
        for (l, o) in out.iter_mut().enumerate() {
            let i = CHUNK * c + l;
            *o = cell(&x[D * i..D * i + D]) as u32;
        }
    };
    if serial() {
        s.cell_of.chunks_mut(CHUNK).enumerate().for_each(cells);
    } else {
        s.cell_of.par_chunks_mut(CHUNK).enumerate().for_each(cells);
    }
    offsets(&mut s.start, ncell, s.cell_of.iter().map(|&c| c as usize));
    let start = &s.start;
    let fill = &mut s.fill;
    fill.clear();
    fill.extend_from_slice(&start[..ncell]);
    s.order.resize(nt, 0);
    s.xs.resize(D * nt, 0.0);
    s.hs.resize(nt, 0.0);
    let (order, xs, hs) = (&mut s.order[..], &mut s.xs[..], &mut s.hs[..]);
    for (i, (p, &c)) in x[..D * nt].chunks_exact(D).zip(&s.cell_of).enumerate() {
        let f = &mut fill[c as usize];
        let slot = *f as usize;
        *f += 1;
        order[slot] = i as u32;
        xs[D * slot..D * slot + D].copy_from_slice(p);
        hs[slot] = h[i];
    }
    // each particle (in cell order) finds the pairs it owns, into per-task buffers, one per
    // bucket of rows (the pair's i). The list is canonical whatever the split, so the split may
    // follow the thread count: a few tasks and buckets per thread keep the buffers O(threads²).
    let g = Grid { lo, inv, nc, start: &s.start, order: &s.order, xs: &s.xs, hs: &s.hs, kappa, nreal };
    let per = 4 * rayon::current_num_threads();
    let ntask = nt.div_ceil(CHUNK).min(per);
    let slots = nt.div_ceil(ntask);
    let nb = nreal.div_ceil(CHUNK).min(per);
    let rows = nreal.div_ceil(nb);
    if s.pair_tasks.len() < ntask * nb {
        s.pair_tasks.resize_with(ntask * nb, Vec::new);
    }
    let find = |(t, bufs): (usize, &mut [Vec<[u32; 2]>])| {
        bufs.iter_mut().for_each(Vec::clear);
        g.find::<D>(slots * t..(slots * t + slots).min(nt), rows, bufs);
    };
    let found = &mut s.pair_tasks[..ntask * nb];
    if serial() {
        found.chunks_mut(nb).enumerate().for_each(find);
    } else {
        found.par_chunks_mut(nb).enumerate().for_each(find);
    }
    // canonical order, bucket by bucket: a counting sort by i, then each row by j
    let found = &s.pair_tasks[..ntask * nb];
    let size = |b: usize| -> usize { (0..ntask).map(|t| found[t * nb + b].len()).sum() };
    let np: usize = (0..nb).map(size).sum();
    pi.resize(np, 0);
    pj.resize(np, 0);
    let mut parts: Vec<(usize, &mut [i32], &mut [i32])> = Vec::with_capacity(nb);
    let (mut ri, mut rj) = (&mut pi[..], &mut pj[..]);
    for b in 0..nb {
        let len = size(b);
        let (head_i, tail_i) = std::mem::take(&mut ri).split_at_mut(len);
        let (head_j, tail_j) = std::mem::take(&mut rj).split_at_mut(len);
        parts.push((b, head_i, head_j));
        ri = tail_i;
        rj = tail_j;
    }
    let place = |(b, ri, rj): (usize, &mut [i32], &mut [i32])| {
        let a0 = rows * b;
        let nr = rows.min(nreal - a0);
        let mut cnt = vec![0u32; nr + 1];
        for t in 0..ntask {
            for &[i, _] in &found[t * nb + b] {
                cnt[i as usize - a0 + 1] += 1;
            }
        }
        for r in 0..nr {
            cnt[r + 1] += cnt[r];
        }
        let mut fill = cnt[..nr].to_vec();
        for t in 0..ntask {
            for &[i, j] in &found[t * nb + b] {
                let f = &mut fill[i as usize - a0];
                rj[*f as usize] = j as i32;
                *f += 1;
            }
        }
        for r in 0..nr {
            let (r0, r1) = (cnt[r] as usize, cnt[r + 1] as usize);
            ri[r0..r1].fill((a0 + r) as i32);
            rj[r0..r1].sort_unstable();
        }
    };
    if serial() {
        parts.into_iter().for_each(place);
    } else {
        parts.into_par_iter().for_each(place);
    }
}

/// Candidate lists kept between calls of the Rust cell search (a Verlet list with a skin s).
///
/// At a rebuild, the candidates of each real particle i are the real j > i with
/// r_ij < κ h_ij + s (the owner-based cell search run with every h raised by s/κ). A particle's
/// drift since then is δ_a = |x_a − x_a^b| + κ max(0, h_a − h_a^b)/2. A pair of real particles that
/// is not a candidate had r ≥ κ h_ij + s at the rebuild, so now r ≥ κ h_ij + s − δ_i − δ_j: it
/// cannot be a pair while δ_i + δ_j < s. Particles with δ > 0.45 s ("fast") have their pairs
/// searched afresh every call, and so have the mirror particles (rebuilt every step); every
/// other pair comes from filtering the candidates with the exact test. The result is merged into
/// the canonical list, identical to the Fortran's. When more than 1/32 of the particles are
/// fast, or the particle set changed, the lists are rebuilt.
#[derive(Default)]
pub(crate) struct Verlet {
    pub(crate) valid: bool,
    nreal: usize,
    dim: usize,
    kappa: f64,
    skin: f64,
    xb: Vec<f64>,
    hb: Vec<f64>,
    /// Candidate rows (CSR over the real particles) and their keep flags.
    cstart: Vec<u32>,
    cand: Vec<u32>,
    keep: Vec<u8>,
    /// Fast flags and the fast particles.
    fast: Vec<u8>,
    fast_list: Vec<u32>,
    /// Raised h of a rebuild.
    hraise: Vec<f64>,
    /// Pairs with a fast particle or a mirror, per task, then merged, as keys i·2³² + j (which
    /// sort as the pairs do).
    extra_tasks: Vec<Vec<u64>>,
    extra: Vec<u64>,
    /// A grid over the real particles: first slot of each cell, particles by cell.
    gstart: Vec<u32>,
    gorder: Vec<u32>,
    gcell: Vec<u32>,
    gfill: Vec<u32>,
    /// Per-row counts and offsets of the result.
    off: Vec<u32>,
    /// Number of rebuilds (for tests and diagnostics).
    pub(crate) builds: u64,
}

/// A pair as a sort key, and the key's row (its i).
#[inline]
fn key(i: usize, j: usize) -> u64 {
    ((i as u64) << 32) | j as u64
}

#[inline]
fn row(k: u64) -> usize {
    (k >> 32) as usize
}

/// Fast threshold, as a fraction of the skin (below 1/2, so two slow drifts stay under the skin
/// with a margin far above rounding).
const FAST: f64 = 0.45;

fn verlet(dim: usize, nreal: usize, x: &[f64], h: &[f64], kappa: f64, pl: &mut PairList) {
    match dim {
        1 => verlet_d::<1>(nreal, x, h, kappa, pl),
        2 => verlet_d::<2>(nreal, x, h, kappa, pl),
        _ => verlet_d::<3>(nreal, x, h, kappa, pl),
    }
}

fn verlet_d<const D: usize>(nreal: usize, x: &[f64], h: &[f64], kappa: f64, pl: &mut PairList) {
    let nt = h.len();
    let hreal = &h[..nreal];
    // anything outside the plain case (no particles, odd h or κ, non-finite values) goes to the
    // cell search, which has its own fallbacks
    // (per fixed chunk, combined in order: the same values whatever the thread count)
    let part = |c: usize| -> (f64, bool) {
        let (a0, a1) = (CHUNK * c, (CHUNK * c + CHUNK).min(nt));
        let ok = x[D * a0..D * a1].iter().all(|v| v.is_finite()) && h[a0..a1].iter().all(|v| v.is_finite() && *v > 0.0);
        (h[a0..a1.min(nreal).max(a0)].iter().sum(), ok)
    };
    let nchunk_t = nt.div_ceil(CHUNK);
    let parts: Vec<(f64, bool)> =
        if serial() { (0..nchunk_t).map(part).collect() } else { (0..nchunk_t).into_par_iter().map(part).collect() };
    let hsum: f64 = parts.iter().map(|p| p.0).sum();
    let plain = nreal > 0 && kappa > 0.0 && kappa.is_finite() && parts.iter().all(|p| p.1);
    if !plain {
        pl.invalidate();
        return rust_cell(D, nreal, x, h, kappa, pl);
    }
    let mut v = std::mem::take(&mut pl.scratch.get_mut().verlet);
    // drift since the last rebuild, and the fast particles
    let mut rebuild = !(v.valid && v.nreal == nreal && v.dim == D && v.kappa == kappa);
    if !rebuild {
        let lim = FAST * v.skin;
        v.fast.resize(nreal, 0);
        let (xb, hb) = (&v.xb, &v.hb);
        let mark = |(c, f): (usize, &mut [u8])| {
            for (l, fl) in f.iter_mut().enumerate() {
                let a = CHUNK * c + l;
                let mut d2 = 0.0;
                for d in 0..D {
                    let dd = x[d + D * a] - xb[d + D * a];
                    d2 += dd * dd;
                }
                let drift = d2.sqrt() + 0.5 * kappa * (h[a] - hb[a]).max(0.0);
                // a NaN drift counts as fast
                *fl = u8::from(drift.is_nan() || drift > lim);
            }
        };
        if serial() {
            v.fast.chunks_mut(CHUNK).enumerate().for_each(mark);
        } else {
            v.fast.par_chunks_mut(CHUNK).enumerate().for_each(mark);
        }
        v.fast_list.clear();
        v.fast_list.extend((0..nreal as u32).filter(|&a| v.fast[a as usize] != 0));
        rebuild = v.fast_list.len() > nreal / 32;
    }
    if rebuild {
        v.skin = 0.5 * (hsum / nreal as f64);
        v.hraise.clear();
        v.hraise.extend(hreal.iter().map(|&a| a + v.skin / kappa));
        rust_cell_d::<D>(nreal, &x[..D * nreal], &v.hraise, kappa, pl);
        offsets(&mut v.cstart, nreal, pl.i.iter().map(|&i| i as usize));
        v.cand.clear();
        v.cand.extend(pl.j.iter().map(|&j| j as u32));
        v.xb.clear();
        v.xb.extend_from_slice(&x[..D * nreal]);
        v.hb.clear();
        v.hb.extend_from_slice(hreal);
        v.fast.clear();
        v.fast.resize(nreal, 0);
        v.fast_list.clear();
        v.nreal = nreal;
        v.dim = D;
        v.kappa = kappa;
        v.valid = true;
        v.builds += 1;
    }
    let test = |i: usize, j: usize| -> bool {
        let mut r2 = 0.0;
        for d in 0..D {
            let dxd = x[d + D * i] - x[d + D * j];
            r2 += dxd * dxd;
        }
        let s = kappa * (0.5 * (h[i] + h[j]));
        r2 < s * s
    };
    // 1. the candidates between slow particles, filtered by the exact test
    v.keep.resize(v.cand.len(), 0);
    {
        let (cstart, cand, fast) = (&v.cstart, &v.cand, &v.fast);
        let rows = |(c, keep): (usize, &mut [u8])| {
            let k0 = CHUNK * c;
            // the row of the first candidate of this chunk, then walk forward
            let mut i = cstart.partition_point(|&s| (s as usize) <= k0) - 1;
            for (l, kp) in keep.iter_mut().enumerate() {
                let k = k0 + l;
                while cstart[i + 1] as usize <= k {
                    i += 1;
                }
                let j = cand[k] as usize;
                *kp = u8::from(fast[i] == 0 && fast[j] == 0 && test(i, j));
            }
        };
        if serial() {
            v.keep.chunks_mut(CHUNK).enumerate().for_each(rows);
        } else {
            v.keep.par_chunks_mut(CHUNK).enumerate().for_each(rows);
        }
    }
    // 2. pairs with a fast particle or a mirror, searched in a grid over the real particles
    v.extra.clear();
    let nsearch = v.fast_list.len() + (nt - nreal);
    if nsearch > 0 {
        let bbox = |c: usize| -> ([f64; 3], [f64; 3], f64) {
            let (mut lo, mut hi, mut hm) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3], 0.0f64);
            for a in CHUNK * c..(CHUNK * c + CHUNK).min(nreal) {
                for d in 0..D {
                    lo[d] = lo[d].min(x[d + D * a]);
                    hi[d] = hi[d].max(x[d + D * a]);
                }
                hm = hm.max(h[a]);
            }
            (lo, hi, hm)
        };
        let nchunk = nreal.div_ceil(CHUNK);
        let parts: Vec<_> =
            if serial() { (0..nchunk).map(bbox).collect() } else { (0..nchunk).into_par_iter().map(bbox).collect() };
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let mut hmax: f64 = 0.0;
        for (plo, phi, pm) in parts {
            for d in 0..D {
                lo[d] = lo[d].min(plo[d]);
                hi[d] = hi[d].max(phi[d]);
            }
            hmax = hmax.max(pm);
        }
        let (inv, nc) = grid_dims::<D>(&lo, &hi, 0.5 * kappa * (hsum / nreal as f64), nreal);
        let ncell = nc[0] * nc[1] * nc[2];
        let cell_at = |p: &[f64]| -> [usize; 3] {
            let mut c = [0usize; 3];
            for d in 0..D {
                let k = ((p[d] - lo[d]) * inv) as isize;
                c[d] = k.clamp(0, nc[d] as isize - 1) as usize;
            }
            c
        };
        v.gcell.resize(nreal, 0);
        let cells = |(c, out): (usize, &mut [u32])| {
            for (l, o) in out.iter_mut().enumerate() {
                let a = CHUNK * c + l;
                let q = cell_at(&x[D * a..D * a + D]);
                *o = (q[0] + nc[0] * (q[1] + nc[1] * q[2])) as u32;
            }
        };
        if serial() {
            v.gcell.chunks_mut(CHUNK).enumerate().for_each(cells);
        } else {
            v.gcell.par_chunks_mut(CHUNK).enumerate().for_each(cells);
        }
        offsets(&mut v.gstart, ncell, v.gcell.iter().map(|&c| c as usize));
        v.gorder.resize(nreal, 0);
        v.gfill.clear();
        v.gfill.extend_from_slice(&v.gstart[..ncell]);
        for (a, &c) in v.gcell.iter().enumerate() {
            v.gorder[v.gfill[c as usize] as usize] = a as u32;
            v.gfill[c as usize] += 1;
        }
        let (gstart, gorder, fast, fast_list) = (&v.gstart, &v.gorder, &v.fast, &v.fast_list);
        // searcher a (a fast real particle, or a mirror): every real partner b in its box
        let around = |a: usize, buf: &mut Vec<u64>| {
            let rad = kappa * (0.5 * (h[a] + hmax));
            let rad = rad + rad * 1e-9;
            let mut clo = [0usize; 3];
            let mut chi = [0usize; 3];
            for d in 0..D {
                let k0 = ((x[d + D * a] - rad - lo[d]) * inv) as isize;
                let k1 = ((x[d + D * a] + rad - lo[d]) * inv) as isize;
                clo[d] = k0.clamp(0, nc[d] as isize - 1) as usize;
                chi[d] = k1.clamp(0, nc[d] as isize - 1) as usize;
            }
            for z in clo[2]..=chi[2] {
                for y in clo[1]..=chi[1] {
                    let row = nc[0] * (y + nc[1] * z);
                    for &b in &gorder[gstart[row + clo[0]] as usize..gstart[row + chi[0] + 1] as usize] {
                        let b = b as usize;
                        // a fast-fast pair is kept by its first particle only
                        if b == a || (a < nreal && fast[b] != 0 && b < a) {
                            continue;
                        }
                        let (i, j) = (a.min(b), a.max(b));
                        if test(i, j) {
                            buf.push(key(i, j));
                        }
                    }
                }
            }
        };
        let per = 64;
        let ntask = nsearch.div_ceil(per);
        let searcher = |t: usize| -> usize {
            if t < fast_list.len() { fast_list[t] as usize } else { nreal + (t - fast_list.len()) }
        };
        tasks(&mut v.extra_tasks, ntask, |t, buf| {
            for q in per * t..(per * t + per).min(nsearch) {
                around(searcher(q), buf);
            }
        });
        for b in &v.extra_tasks[..ntask] {
            v.extra.extend_from_slice(b);
        }
        if serial() {
            v.extra.sort_unstable();
        } else {
            v.extra.par_sort_unstable();
        }
    }
    // 3. the canonical list: per row, the kept candidates and the extra pairs, merged by j; the
    //    rows in chunks, each writing its own slice of the list
    let nchunk = nreal.div_ceil(CHUNK);
    v.off.clear();
    v.off.resize(nreal + 1, 0);
    {
        let (keep, cstart, extra) = (&v.keep, &v.cstart, &v.extra);
        let count = |(c, out): (usize, &mut [u32])| {
            let a0 = CHUNK * c;
            let mut e = extra.partition_point(|&p| row(p) < a0);
            for (l, o) in out.iter_mut().enumerate() {
                let a = a0 + l;
                let mut n = keep[cstart[a] as usize..cstart[a + 1] as usize].iter().filter(|&&k| k != 0).count();
                while e < extra.len() && row(extra[e]) == a {
                    n += 1;
                    e += 1;
                }
                *o = n as u32;
            }
        };
        let counts = &mut v.off[1..];
        if serial() {
            counts.chunks_mut(CHUNK).enumerate().for_each(count);
        } else {
            counts.par_chunks_mut(CHUNK).enumerate().for_each(count);
        }
    }
    for a in 0..nreal {
        v.off[a + 1] += v.off[a];
    }
    let np = v.off[nreal] as usize;
    let PairList { i: pi, j: pj, .. } = pl;
    pi.clear();
    pj.clear();
    pi.resize(np, 0);
    pj.resize(np, 0);
    let mut slices: Vec<(usize, &mut [i32], &mut [i32])> = Vec::with_capacity(nchunk);
    let (mut ri, mut rj) = (&mut pi[..], &mut pj[..]);
    for c in 0..nchunk {
        let len = (v.off[(CHUNK * c + CHUNK).min(nreal)] - v.off[CHUNK * c]) as usize;
        let (hi_, ti) = std::mem::take(&mut ri).split_at_mut(len);
        let (hj, tj) = std::mem::take(&mut rj).split_at_mut(len);
        slices.push((c, hi_, hj));
        ri = ti;
        rj = tj;
    }
    let (keep, cstart, cand, extra, off) = (&v.keep, &v.cstart, &v.cand, &v.extra, &v.off);
    let fill = |(c, si, sj): (usize, &mut [i32], &mut [i32])| {
        let a0 = CHUNK * c;
        let base = off[a0] as usize;
        let mut e = extra.partition_point(|&p| row(p) < a0);
        let mut w = 0usize;
        for a in a0..(a0 + CHUNK).min(nreal) {
            let (k0, k1) = (cstart[a] as usize, cstart[a + 1] as usize);
            let mut k = k0;
            while e < extra.len() && row(extra[e]) == a {
                let je = extra[e] as u32;
                while k < k1 && cand[k] < je {
                    if keep[k] != 0 {
                        si[w] = a as i32;
                        sj[w] = cand[k] as i32;
                        w += 1;
                    }
                    k += 1;
                }
                si[w] = a as i32;
                sj[w] = je as i32;
                w += 1;
                e += 1;
            }
            while k < k1 {
                if keep[k] != 0 {
                    si[w] = a as i32;
                    sj[w] = cand[k] as i32;
                    w += 1;
                }
                k += 1;
            }
            debug_assert_eq!(base + w, off[a + 1] as usize);
        }
    };
    if serial() {
        slices.into_iter().for_each(fill);
    } else {
        slices.into_par_iter().for_each(fill);
    }
    pl.scratch.get_mut().verlet = v;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// xorshift64*, seeded.
    struct Rng(u64);
    impl Rng {
        fn f(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    fn lists(b: Backend, cell: bool, dim: usize, nreal: usize, x: &[f64], h: &[f64], kappa: f64) -> Vec<(i32, i32)> {
        let mut pl = PairList::default();
        search(b, cell, dim, nreal, x, h, kappa, &mut pl);
        pl.i.iter().copied().zip(pl.j.iter().copied()).collect()
    }

    /// The owner-based cell search returns the Fortran's direct list: lattices with equal h (ties),
    /// a few particles with h up to 5×, duplicated positions, points exactly at the support
    /// radius, a far outlier, and the fallbacks (negative h, non-finite values).
    #[test]
    fn cell_search_equals_direct() {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        let mut checked = 0;
        for dim in 1..=3 {
            let side = [400, 24, 8][dim - 1];
            let n = [side, side * side, side * side * side][dim - 1];
            for case in 0..6 {
                let mut x = vec![0.0; dim * n];
                let mut h = vec![0.01; n];
                for i in 0..n {
                    let mut r = i;
                    for d in 0..dim {
                        let jitter = if case % 2 == 0 { 0.0 } else { 0.004 * (rng.f() - 0.5) };
                        x[d + dim * i] = 0.01 * (r % side) as f64 + jitter;
                        r /= side;
                    }
                    if case >= 2 && rng.f() < 0.03 {
                        h[i] = 0.01 * (1.0 + 4.0 * rng.f());
                    }
                    if case >= 4 && rng.f() < 0.3 {
                        h[i] = 0.01 * (0.9 + 0.2 * rng.f());
                    }
                }
                if case == 3 {
                    // a duplicate, and a far outlier with a huge h
                    x[dim] = x[0];
                    x[dim * (n - 1)] = 50.0;
                    h[n - 1] = 0.3;
                }
                if case == 5 {
                    h[7] = -0.01;
                }
                let nreal = n - n / 7;
                for kappa in [2.0, 3.0] {
                    let want = lists(Backend::Fortran, false, dim, nreal, &x, &h, kappa);
                    assert!(!want.is_empty());
                    assert_eq!(lists(Backend::Rust, true, dim, nreal, &x, &h, kappa), want, "{dim}D case {case}");
                    assert_eq!(lists(Backend::Rust, false, dim, nreal, &x, &h, kappa), want, "{dim}D case {case}");
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 36);
        // non-finite values
        let x = vec![0.0, 0.01, f64::NAN, 0.03, 0.04, f64::INFINITY, 0.06];
        for h in [vec![0.01; 7], vec![0.01, 0.01, 0.01, f64::INFINITY, 0.01, 0.01, f64::NAN]] {
            let want = lists(Backend::Fortran, false, 1, 6, &x, &h, 2.0);
            assert_eq!(lists(Backend::Rust, true, 1, 6, &x, &h, 2.0), want);
        }
    }
    /// The candidate lists kept between calls give the Fortran's list at every call: a 2D cloud
    /// whose particles mostly drift slowly, a few jump far (fast), some h grow, and a changing
    /// set of virtual particles is appended each call.
    #[test]
    fn kept_candidates_equal_direct_over_many_calls() {
        let mut rng = Rng(0x0123_4567_89AB_CDEF);
        let (side, dx) = (24usize, 0.01);
        let nreal = side * side;
        let mut x = Vec::new();
        let mut h = Vec::new();
        for j in 0..side {
            for i in 0..side {
                x.extend([(i as f64 + 0.5) * dx, (j as f64 + 0.5) * dx]);
                h.push(dx * (1.0 + 0.2 * rng.f()));
            }
        }
        let mut pl = PairList::default();
        let mut rebuilds = 0;
        let mut incremental = 0;
        for call in 0..80 {
            // every 25 calls the whole cloud moves by a spacing: the lists must be rebuilt
            let shift = if call % 25 == 24 { dx } else { 0.0 };
            for a in 0..nreal {
                x[2 * a] += shift;
                let fast = rng.f() < 0.03;
                let step = if fast { 0.004 } else { 0.0002 };
                x[2 * a] += step * (rng.f() - 0.5);
                x[2 * a + 1] += step * (rng.f() - 0.5);
                if rng.f() < 0.05 {
                    h[a] *= 1.0 + 0.01 * rng.f();
                }
            }
            // mirrors of the particles near x = 0, rebuilt every call
            let mut xt = x.clone();
            let mut ht = h.clone();
            for a in 0..nreal {
                if x[2 * a] < 2.0 * h[a] && x[2 * a] >= 0.0 {
                    xt.extend([-x[2 * a], x[2 * a + 1]]);
                    ht.push(h[a]);
                }
            }
            let before = pl.scratch.get_mut().verlet.builds;
            search(Backend::Rust, true, 2, nreal, &xt, &ht, 2.0, &mut pl);
            let got: Vec<(i32, i32)> = pl.i.iter().copied().zip(pl.j.iter().copied()).collect();
            let want = lists(Backend::Fortran, false, 2, nreal, &xt, &ht, 2.0);
            assert_eq!(got, want, "call {call}: kept candidates differ from the direct search");
            if pl.scratch.get_mut().verlet.builds == before {
                incremental += 1;
            } else {
                rebuilds += 1;
            }
        }
        assert!(incremental > 10 && rebuilds > 1, "both paths taken: {incremental} incremental, {rebuilds} rebuilds");
    }
}
