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

/// A TNT charge (preset `tnt`) in a block of dense sand (preset `dense_sand`), in RZ: the charge a
/// box from the axis to r = `charge_r`, from z = `charge_z.0` to `charge_z.1`; the sand r ≤
/// `block.0`, z ≤ `block.1`, the charge cut out of it; walls along the bottom and at r = `block.0`
/// up to z = `wall_top`; a programmed burn lit on the axis at z = `det_z`; a crater analysis. All
/// lengths in metres, one `spacing` for both regions.
pub struct RzCharge {
    pub name: &'static str,
    pub end_s: f64,
    pub output_s: f64,
    pub charge_r: f64,
    pub charge_z: (f64, f64),
    pub block: (f64, f64),
    pub wall_top: f64,
    pub spacing: f64,
    pub det_z: f64,
    /// A point gauge on the axis at this z, named `A`.
    pub gauge_z: Option<f64>,
}

/// The case file of an [`RzCharge`].
pub fn rz_charge_case(c: &RzCharge) -> String {
    let gauge = c
        .gauge_z
        .map_or(String::new(), |z| format!("[[gauge]]\nname = \"A\"\npoint_m = [0.0, {z}]\nkind = \"point\"\n"));
    format!(
        r#"name = "{}"
dim = 2
geometry = "axisymmetric"
[time]
end_s = {:e}
output_interval_s = {:e}
[[material]]
name = "tnt"
preset = "tnt"
[[material]]
name = "sand"
preset = "dense_sand"
[[region]]
name = "charge"
material = "tnt"
shape = "box"
lo_m = [0.0, {}]
hi_m = [{}, {}]
spacing_m = {}
[[region]]
name = "soil"
material = "sand"
shape = "box"
lo_m = [0.0, 0.0]
hi_m = [{}, {}]
spacing_m = {}
subtract = ["charge"]
[[wall]]
from_m = [0.0, 0.0]
to_m = [{}, 0.0]
[[wall]]
from_m = [{}, 0.0]
to_m = [{}, {}]
[detonation]
mode = "programmed"
point_m = [0.0, {}]
{gauge}[analysis]
kind = "crater"
"#,
        c.name,
        c.end_s,
        c.output_s,
        c.charge_z.0,
        c.charge_r,
        c.charge_z.1,
        c.spacing,
        c.block.0,
        c.block.1,
        c.spacing,
        c.block.0,
        c.block.0,
        c.block.0,
        c.wall_top,
        c.det_z,
    )
}

/// Every `Step#N` group of a particles.h5: (group, dataset) → the bits of its values, the
/// group's `TimeValue` first.
pub fn h5_bits(path: &Path) -> Vec<(String, String, Vec<u64>)> {
    let f = hdf5::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut groups = f.member_names().unwrap();
    groups.retain(|g| g.starts_with("Step#"));
    let mut out = Vec::new();
    for gname in groups {
        let g = f.group(&gname).unwrap();
        let t: f64 = g.attr("TimeValue").unwrap().read_scalar().unwrap();
        out.push((gname.clone(), "TimeValue".into(), vec![t.to_bits()]));
        for dname in g.member_names().unwrap() {
            let d = g.dataset(&dname).unwrap();
            let bits: Vec<u64> = match dname.as_str() {
                "mat" => d.read_raw::<i32>().unwrap().iter().map(|v| *v as u64).collect(),
                "id" => d.read_raw::<i64>().unwrap().iter().map(|v| *v as u64).collect(),
                _ => d.read_raw::<f64>().unwrap().iter().map(|v| v.to_bits()).collect(),
            };
            out.push((gname.clone(), dname, bits));
        }
    }
    out
}

/// `--set` lines that make S1 (`cases/surface_loose_tnt6.toml`, TNT 6 × 6 cm on loose sand)
/// small and fast: the soil a 40 × 30 cm box around the charge at the case's own 1 cm spacing
/// (1200 particles), the walls moved to its sides and bottom, gauges D and E inside it, an output
/// every 10 µs.
pub const SMALL_S1: [&str; 11] = [
    "region.soil.lo_m=[0.3,0.7]",
    "region.soil.hi_m=[0.7,1.0]",
    "wall.0.from_m=[0.3,1.0]",
    "wall.0.to_m=[0.3,0.7]",
    "wall.1.from_m=[0.3,0.7]",
    "wall.1.to_m=[0.7,0.7]",
    "wall.2.from_m=[0.7,0.7]",
    "wall.2.to_m=[0.7,1.0]",
    "gauge.D.point_m=[0.5,0.75]",
    "gauge.E.point_m=[0.5,0.73]",
    "time.output_interval_s=1e-5",
];
