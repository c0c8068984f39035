//! Helpers shared by the integration tests: paths, a seeded generator, and the shock-tube run.
#![allow(dead_code)]

use blastsph::analysis::riemann::Riemann;
use blastsph::case::Case;
use blastsph::output::{Frame, read_frames};
use blastsph::report::{L1, l1_errors, riemann_of};
use blastsph::runner::{self, RunOptions};
use std::path::{Path, PathBuf};

/// The package root (where `cases/` lives).
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A case file of `cases/`.
pub fn case_path(name: &str) -> PathBuf {
    root().join("cases").join(name)
}

/// SplitMix64: a small deterministic generator, so every test draws the same numbers.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
}

/// What one shock-tube run gives back.
pub struct TubeRun {
    pub case: Case,
    pub summary: serde_json::Value,
    pub frames: Vec<Frame>,
    pub exact: Riemann,
    pub x0: f64,
}

impl TubeRun {
    /// The last output (t = end time).
    pub fn last(&self) -> &Frame {
        self.frames.last().expect("particles.h5 holds no step")
    }
    /// L1 errors of the last output over `[lo, hi]` (m).
    pub fn l1(&self, lo: f64, hi: f64) -> L1 {
        l1_errors(self.last(), &self.exact, self.x0, (lo, hi))
    }
}

/// Runs `cases/shock_tube.toml` with `--set` overrides `sets` into `dir` through the library
/// (the same path as `blastsph run`), and reads the run back.
pub fn run_tube(sets: &[String], dir: &Path) -> TubeRun {
    // the legacy Fortran modules (the Rust twins give the same bits: tests/dual.rs)
    let ov = blastsph::sim::Overrides { backend: Some(blastsph::modules::Backend::Fortran), ..Default::default() };
    let opts = RunOptions { out: Some(dir.to_path_buf()), sets: sets.to_vec(), quiet: true, ov, ..Default::default() };
    let r = runner::run(&case_path("shock_tube.toml"), &opts).expect("shock tube run failed");
    let frames = read_frames(&dir.join("particles.h5")).expect("cannot read particles.h5");
    let (exact, x0) = riemann_of(&r.sim.case).expect("no exact solution for the shock tube");
    TubeRun { case: r.sim.case.clone(), summary: r.summary, frames, exact, x0 }
}

/// The `--set` overrides that refine the book's shock tube by `k` (1, 2, 4, ...): particle
/// counts times k; spacings, masses, h and (for the fixed step) dt divided by k. The right
/// region starts one right spacing after the diaphragm, as in the book.
pub fn refine_sets(k: u32, fixed_step: bool) -> Vec<String> {
    let f = f64::from(k);
    let dxl = 0.001875 / f;
    let dxr = 0.0075 / f;
    let mut s = vec![
        format!("region.left.count=[{}]", 320 * k),
        format!("region.left.spacing_m={dxl}"),
        format!("region.left.mass_kg={dxl}"),
        format!("region.left.h_m={}", 0.015 / f),
        format!("region.right.count=[{}]", 80 * k),
        format!("region.right.origin_m=[{dxr}]"),
        format!("region.right.spacing_m={dxr}"),
        format!("region.right.mass_kg={dxl}"),
        format!("region.right.h_m={}", 0.015 / f),
    ];
    if fixed_step {
        s.push(format!("time.dt_s={}", 0.005 / f));
    }
    s
}
