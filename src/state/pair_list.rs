//! The pair list the state carries ([`super::Work::pairs`]): the canonical pairs (i, j), the
//! incidence lists the Rust twins gather over, and the scratch buffers they reuse. The neighbour
//! search (`modules::nnps`) fills it and builds its incidence lists; the types live here so that
//! the state names them without importing the modules.

use std::sync::{Mutex, MutexGuard};

/// One entry of a particle's incidence list: a pair touching it and the pair's other particle.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Inc {
    pub(crate) k: u32,
    pub(crate) o: u32,
}

pub(crate) const SIDE_I: u32 = 1 << 31;

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
    /// Candidate lists kept from step to step (see [`Verlet`], searched by `modules::nnps`).
    pub verlet: Verlet,
    /// Small per-thread work arrays (a block's intermediate values stay in cache).
    pub per_thread: PerThread,
}

/// One work array per pool thread, each behind its own (never contended) lock.
#[derive(Default)]
pub(crate) struct PerThread(pub(crate) Vec<Mutex<Vec<f64>>>);

impl PerThread {
    /// One array for each thread of the current pool.
    pub(crate) fn ensure(&mut self) {
        let n = rayon::current_num_threads();
        if self.0.len() < n {
            self.0.resize_with(n, Default::default);
        }
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
    pub(crate) fn get_mut(&mut self) -> &mut Bufs {
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
    pub(crate) inc: IncPart,
    /// With more than one thread: the parts built in parallel, then merged into `inc`.
    pub(crate) parts: Vec<IncPart>,
    pub(crate) row_start: Vec<u32>,
    pub(crate) scratch: Scratch,
}

/// The listed ends of one range of pairs, by particle: particle a's are `inc[start[a]..start[a + 1]]`.
#[derive(Debug, Clone, Default)]
pub(crate) struct IncPart {
    pub(crate) start: Vec<u32>,
    pub(crate) inc: Vec<Inc>,
}

impl IncPart {
    /// Lists the ends of the pairs `pi`, `pj` (the pairs `k0..` of the list) by particle, for
    /// `ntotal` particles: the `j` ends, and the `i` ends too unless `canonical` (a counting sort;
    /// an end outside `0..ntotal` is not listed).
    pub(crate) fn build(&mut self, pi: &[i32], pj: &[i32], k0: usize, canonical: bool, ntotal: usize) {
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
    pub(crate) fn of(&self, a: usize) -> &[Inc] {
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

    /// The pairs touching particle `a`, ascending.
    #[inline]
    pub fn incident(&self, a: usize) -> Incident<'_> {
        Incident { list: self.inc.of(a), rows: self.row_start[a] as usize..self.row_start[a + 1] as usize, pj: &self.j }
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
    pub(crate) nreal: usize,
    pub(crate) dim: usize,
    pub(crate) kappa: f64,
    pub(crate) skin: f64,
    pub(crate) xb: Vec<f64>,
    pub(crate) hb: Vec<f64>,
    /// Candidate rows (CSR over the real particles) and their keep flags.
    pub(crate) cstart: Vec<u32>,
    pub(crate) cand: Vec<i32>,
    pub(crate) keep: Vec<u8>,
    /// Fast flags and the fast particles.
    pub(crate) fast: Vec<u8>,
    pub(crate) fast_list: Vec<u32>,
    /// Raised h of a rebuild.
    pub(crate) hraise: Vec<f64>,
    /// Scratch of the second grid's box (percentiles, with far ejecta).
    pub(crate) trim: Vec<f64>,
    /// Pairs with a fast particle or a mirror, per task, then merged, as keys i·2³² + j (which
    /// sort as the pairs do).
    pub(crate) extra_tasks: Vec<Vec<u64>>,
    pub(crate) extra: Vec<u64>,
    /// A grid over the real particles: first slot of each cell, particles by cell.
    pub(crate) gstart: Vec<u32>,
    pub(crate) gorder: Vec<u32>,
    pub(crate) gcell: Vec<u32>,
    pub(crate) gfill: Vec<u32>,
    /// Per-row counts and offsets of the result.
    pub(crate) off: Vec<u32>,
    /// Number of rebuilds (for tests and diagnostics).
    pub(crate) builds: u64,
}
