//! Runs across processes: the one place where the core meets a message-passing layer. The core
//! defines the [`Ranks`] trait and splits the parallel row loops of the Rust twins by it; it knows
//! nothing of what implements it. The run layer's `mpirun` module implements it with MPI.
//!
//! The scheme is replicated data with partitioned compute. Every rank holds the whole state and
//! runs the same plan. A row loop (one row per particle or per pair, each row computed whole by
//! one task) computes a contiguous block of its rows on each rank; the blocks are then gathered
//! into every rank's copy. Each row is the same IEEE operations on the same inputs in any
//! process, so the state stays bitwise equal to a single process's. Everything outside the
//! split row loops (the pair search, sums, the health check) runs whole on every rank.
//!
//! A loop is split only on the thread that [`split`] marks, inside the solver's stages, and only
//! once every rank has reached its time loop ([`arm`]): every rank reaches the same loops in the
//! same order there, which the gathers (collective calls) need. Elsewhere, and in a rayon
//! worker, a row loop computes every row itself.

use std::cell::Cell;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// The processes of a run, as the message-passing layer gives them.
pub trait Ranks: Send + Sync {
    /// This process's rank, 0 ≤ rank < size.
    fn rank(&self) -> usize;
    /// The number of processes.
    fn size(&self) -> usize;
    /// Gathers into every rank's `out` the blocks of values each rank computed: rank r holds
    /// `counts[r]` values at the offset `Σ_{q<r} counts[q]`. Collective: every rank calls it with
    /// the same counts.
    fn allgather(&self, out: &mut [f64], counts: &[usize]);
    /// True on every rank when `flag` is true on any (collective).
    fn any(&self, flag: bool) -> bool;
    /// Rank 0's `bytes` into every rank's (collective).
    fn broadcast(&self, bytes: &mut Vec<u8>);
}

static RANKS: OnceLock<Box<dyn Ranks>> = OnceLock::new();

/// Set once every rank has built its solver and the run loop begins ([`arm`]).
static ARMED: AtomicBool = AtomicBool::new(false);

/// The gathers so far: how many, the values gathered into this rank (8 bytes each), and the
/// wall time spent in them (ns).
static GATHERS: [AtomicU64; 3] = [AtomicU64::new(0), AtomicU64::new(0), AtomicU64::new(0)];

/// What the gathers of this process have cost so far.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct Traffic {
    /// Split row loops' gathers (one per output array of a loop).
    pub gathers: u64,
    /// Values received from the other ranks (f64, 8 bytes each).
    pub values_received: u64,
    /// Wall time inside the gathers, waiting included (s).
    pub gather_seconds: f64,
}

/// The gathers' cost in this process so far.
pub fn traffic() -> Traffic {
    let g = |k: usize| GATHERS[k].load(Ordering::Relaxed);
    Traffic { gathers: g(0), values_received: g(1), gather_seconds: g(2) as f64 * 1e-9 }
}

thread_local! {
    static SPLIT: Cell<bool> = const { Cell::new(false) };
}

/// Installs the processes of this run (once, at start-up). Returns false when some were already
/// installed (they stay).
pub fn install(r: Box<dyn Ranks>) -> bool {
    RANKS.set(r).is_ok()
}

/// The installed processes, if more than one.
pub fn get() -> Option<&'static dyn Ranks> {
    RANKS.get().map(|r| r.as_ref()).filter(|r| r.size() > 1)
}

/// This process's rank (0 without processes installed).
pub fn rank() -> usize {
    get().map_or(0, |r| r.rank())
}

/// True on the rank that writes the outputs and prints (rank 0, or the only process).
pub fn is_root() -> bool {
    rank() == 0
}

/// The number of processes (1 without processes installed).
pub fn size() -> usize {
    get().map_or(1, |r| r.size())
}

/// True on every rank when `flag` is true on any (a single process: `flag`).
pub fn any(flag: bool) -> bool {
    get().map_or(flag, |r| r.any(flag))
}

/// Rank 0's `bytes` on every rank (a single process: unchanged).
pub fn broadcast(bytes: &mut Vec<u8>) {
    if let Some(r) = get() {
        r.broadcast(bytes);
    }
}

/// Starts splitting: called by every rank as its time loop begins. Before it, while the ranks
/// build their solvers and rank 0 checks and prepares the run directory alone, every row loop
/// runs whole in each process, so a rank that stops there leaves no other waiting.
pub fn arm() {
    ARMED.store(true, Ordering::Relaxed);
}

/// Runs `f` with the row loops of this thread split across the ranks (see the module's text).
pub fn split<R>(f: impl FnOnce() -> R) -> R {
    let before = SPLIT.with(|s| s.replace(true));
    let out = f();
    SPLIT.with(|s| s.set(before));
    out
}

/// Runs `f` with the row loops of this thread computed whole: the block a rank computes, whose
/// tasks may run loops of their own (a rayon thread waiting on its tasks runs others' tasks).
pub(crate) fn whole<R>(f: impl FnOnce() -> R) -> R {
    let before = SPLIT.with(|s| s.replace(false));
    let out = f();
    SPLIT.with(|s| s.set(before));
    out
}

/// Fewer rows than this are computed whole on every rank: their gather would cost more.
const MIN_ROWS: usize = 1024;

/// The block of `rows` rows this rank computes, and the rows of every rank, when the loop is
/// split; `None` when this rank computes every row.
pub(crate) fn block(rows: usize) -> Option<(&'static dyn Ranks, std::ops::Range<usize>, Vec<usize>)> {
    if rows < MIN_ROWS || !SPLIT.with(|s| s.get()) || !ARMED.load(Ordering::Relaxed) {
        return None;
    }
    let r = get()?;
    let n = r.size();
    let edge = |k: usize| rows * k / n;
    let counts: Vec<usize> = (0..n).map(|k| edge(k + 1) - edge(k)).collect();
    let me = r.rank();
    Some((r, edge(me)..edge(me + 1), counts))
}

/// Gathers the rows each rank computed of `out` (`width` values a row) into every rank's copy.
pub(crate) fn gather(r: &dyn Ranks, out: &mut [f64], width: usize, counts: &[usize]) {
    if width == 0 {
        return;
    }
    let c: Vec<usize> = counts.iter().map(|k| k * width).collect();
    let t0 = std::time::Instant::now();
    r.allgather(out, &c);
    let received = c.iter().sum::<usize>() - c[r.rank()];
    GATHERS[0].fetch_add(1, Ordering::Relaxed);
    GATHERS[1].fetch_add(received as u64, Ordering::Relaxed);
    GATHERS[2].fetch_add(t0.elapsed().as_nanos() as u64, Ordering::Relaxed);
}
