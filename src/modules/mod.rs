//! The module interface (DESIGN.md "The module interface").
//!
//! A *module* is one physics or numerics routine family with one interface and two
//! implementations: the legacy Fortran routine (through [`crate::legacy`]) and its Rust twin.
//! Each file here holds the dispatch functions of one module — they take a [`Backend`] and whole
//! arrays, so one foreign call is made per module per step — and the Rust twin.
//!
//! Rust twins gather: every particle sums over the pairs that touch it, in ascending pair order
//! (the incidence lists of [`nnps::PairList`]). That is the order in which the Fortran pair loops
//! scatter into the same particle, and each pair term is computed with the same operations in the
//! same order, so the sums agree bit for bit and results do not depend on the thread count. A pair
//! term is computed once (a parallel pass over the pairs, into a buffer the pair list keeps from
//! step to step) and the gather adds it to both ends. Loops run in tasks of `CHUNK` rows, inline
//! when the pool has one thread; the CLI runs the whole simulation on a pool worker, so a parallel
//! call starts there instead of being handed over from an outside thread.

pub mod boundary;
pub mod density;
pub mod detonation;
pub mod eos;
pub mod force;
pub mod integrator;
pub mod kernel;
pub mod nnps;
pub mod penalty;
pub mod smoothing;
pub mod strength;
pub mod viscosity;
pub mod xsph;

use serde::Serialize;

/// Which implementation runs a module.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Backend {
    Fortran,
    Rust,
}

impl Backend {
    pub fn name(self) -> &'static str {
        match self {
            Backend::Fortran => "fortran",
            Backend::Rust => "rust",
        }
    }
    pub fn parse(s: &str) -> Option<Backend> {
        match s {
            "fortran" => Some(Backend::Fortran),
            "rust" => Some(Backend::Rust),
            _ => None,
        }
    }
}

/// The modules of DESIGN.md's table (plus detonation and XSPH).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Module {
    Boundary,
    Nnps,
    Kernel,
    Density,
    Detonation,
    Eos,
    Strength,
    Force,
    Viscosity,
    Penalty,
    Xsph,
    Smoothing,
    Integrator,
}

impl Module {
    /// In the order a step calls them.
    pub const ALL: [Module; 13] = [
        Module::Boundary,
        Module::Nnps,
        Module::Kernel,
        Module::Density,
        Module::Detonation,
        Module::Eos,
        Module::Strength,
        Module::Force,
        Module::Viscosity,
        Module::Penalty,
        Module::Xsph,
        Module::Smoothing,
        Module::Integrator,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Module::Boundary => "boundary",
            Module::Nnps => "nnps",
            Module::Kernel => "kernel",
            Module::Density => "density",
            Module::Detonation => "detonation",
            Module::Eos => "eos",
            Module::Strength => "strength",
            Module::Force => "force",
            Module::Viscosity => "viscosity",
            Module::Penalty => "penalty",
            Module::Xsph => "xsph",
            Module::Smoothing => "smoothing",
            Module::Integrator => "integrator",
        }
    }

    pub fn parse(s: &str) -> Option<Module> {
        Module::ALL.iter().copied().find(|m| m.name() == s)
    }

    pub fn names() -> String {
        Module::ALL.iter().map(|m| m.name()).collect::<Vec<_>>().join(", ")
    }

    /// What the module computes, for `blastsph check`.
    pub fn what(self) -> &'static str {
        match self {
            Module::Boundary => "virtual particles: type I wall force, type II mirrors",
            Module::Nnps => "neighbour pairs within the kernel support",
            Module::Kernel => "W_ij and grad W_ij per pair (5-1)",
            Module::Density => "summation density or continuity rate (Table 4-1)",
            Module::Detonation => "programmed burn: lighting times and burn fraction",
            Module::Eos => "p and c per material (4-39..4-46)",
            Module::Strength => "strain/rotation rates, Jaumann rate, Drucker-Prager (4-29..4-32)",
            Module::Force => "momentum and energy rates from the stress (4-33..4-38)",
            Module::Viscosity => "Monaghan artificial viscosity (4-47, 4-48)",
            Module::Penalty => "penalty force between materials (4-53, 4-54)",
            Module::Xsph => "averaged velocity (XSPH)",
            Module::Smoothing => "smoothing-length evolution (2-15, 2-16)",
            Module::Integrator => "leapfrog, rate sums, CFL step (2-17..2-27)",
        }
    }
}

/// One choice of implementation per module.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Choice {
    pub backend: [Backend; 13],
}

impl Choice {
    pub fn all(b: Backend) -> Choice {
        Choice { backend: [b; 13] }
    }
    pub fn get(&self, m: Module) -> Backend {
        self.backend[Module::ALL.iter().position(|x| *x == m).unwrap_or(0)]
    }
    pub fn set(&mut self, m: Module, b: Backend) {
        if let Some(k) = Module::ALL.iter().position(|x| *x == m) {
            self.backend[k] = b;
        }
    }
}

/// Rows (particles) or pairs per rayon task. At 10^4 particles a finer split costs more in task
/// hand-offs than it gains; results never depend on it (every row is computed whole by one task).
pub(crate) const CHUNK: usize = 512;

/// True when the current pool has one thread: the loops below then run inline, without rayon.
#[inline]
pub(crate) fn serial() -> bool {
    rayon::current_num_threads() == 1
}

/// Runs `f(a, row)` over the rows of `out` (row `a` = particle `a`, `width` values), in parallel
/// over tasks of [`CHUNK`] rows: each call writes only its own row.
pub(crate) fn par_rows<F>(out: &mut [f64], width: usize, f: F)
where
    F: Fn(usize, &mut [f64]) + Sync + Send,
{
    use rayon::prelude::*;
    if width == 0 {
        return;
    }
    let body = |c: usize, blk: &mut [f64]| {
        for (r, row) in blk.chunks_mut(width).enumerate() {
            f(c * CHUNK + r, row);
        }
    };
    if serial() {
        out.chunks_mut(width * CHUNK).enumerate().for_each(|(c, blk)| body(c, blk));
    } else {
        out.par_chunks_mut(width * CHUNK).enumerate().for_each(|(c, blk)| body(c, blk));
    }
}

/// As [`par_rows`] over two arrays with the same rows: `f(a, row1, row2)`, rows of `w1` and `w2`
/// values (`w2` may be 0: `row2` is then empty).
pub(crate) fn par_rows2<F>(out1: &mut [f64], w1: usize, out2: &mut [f64], w2: usize, f: F)
where
    F: Fn(usize, &mut [f64], &mut [f64]) + Sync + Send,
{
    use rayon::prelude::*;
    if w1 == 0 {
        return;
    }
    let rows = out1.len() / w1;
    let out2 = &mut out2[..w2 * rows];
    let body = |c: usize, b1: &mut [f64], b2: &mut [f64]| {
        let n = b1.len() / w1;
        for r in 0..n {
            f(c * CHUNK + r, &mut b1[w1 * r..w1 * r + w1], &mut b2[w2 * r..w2 * r + w2]);
        }
    };
    if w2 == 0 {
        par_rows(out1, w1, |a, r1| f(a, r1, &mut []));
        return;
    }
    if serial() {
        out1.chunks_mut(w1 * CHUNK)
            .zip(out2.chunks_mut(w2 * CHUNK))
            .enumerate()
            .for_each(|(c, (b1, b2))| body(c, b1, b2));
    } else {
        out1.par_chunks_mut(w1 * CHUNK)
            .zip(out2.par_chunks_mut(w2 * CHUNK))
            .enumerate()
            .for_each(|(c, (b1, b2))| body(c, b1, b2));
    }
}

/// Calls `$f::<D, W>($args)` with D = `$dim` (1, 2 or 3) and W = D + `$extra` (0 or 1): the pair
/// loops are monomorphised over the dimension, so their short inner loops are unrolled.
macro_rules! by_dim {
    ($dim:expr, 0, $f:ident($($args:expr),* $(,)?)) => {
        match $dim {
            1 => $f::<1, 1>($($args),*),
            2 => $f::<2, 2>($($args),*),
            _ => $f::<3, 3>($($args),*),
        }
    };
    ($dim:expr, 1, $f:ident($($args:expr),* $(,)?)) => {
        match $dim {
            1 => $f::<1, 2>($($args),*),
            2 => $f::<2, 3>($($args),*),
            _ => $f::<3, 4>($($args),*),
        }
    };
}
pub(crate) use by_dim;

/// The gather of a pair sum whose pair k holds W terms `t` (a reused buffer): for every particle
/// `a`, over its pairs in ascending pair order, `acc += m_j t[0..D]` where `a` is the pair's i and
/// `acc −= m_i t[0..D]` where it is the j (written as `+= (−m_i) t`, the same IEEE operation), and,
/// when W = D + 1, `e += m_other t[D]`. Rows are `acc` (D values) and `e` (one value, or none
/// when W = D); `scale` multiplies `acc` at the end.
pub(crate) fn gather_signed<const D: usize, const W: usize>(
    pl: &nnps::PairList,
    terms: &[f64],
    mass: &[f64],
    scale: Option<f64>,
    acc: &mut [f64],
    e: &mut [f64],
) {
    let body = |a: usize, acc: &mut [f64], e: &mut [f64]| {
        let mut sa = [0.0f64; D];
        let mut se = 0.0;
        for inc in pl.incident(a) {
            let k = inc.pair();
            let t = &terms[W * k..W * k + W];
            let m = mass[inc.other()];
            let ms = if inc.is_i() { m } else { -m };
            for d in 0..D {
                sa[d] += ms * t[d];
            }
            if W > D {
                se += m * t[W - 1];
            }
        }
        match scale {
            Some(s) => {
                for d in 0..D {
                    acc[d] = s * sa[d];
                }
            }
            None => acc.copy_from_slice(&sa),
        }
        if W > D {
            e[0] = se;
        }
    };
    let n = mass.len();
    if W > D {
        par_rows2(&mut acc[..D * n], D, &mut e[..n], 1, body);
    } else {
        par_rows(&mut acc[..D * n], D, |a, r| body(a, r, &mut []));
    }
}
