//! The size of a case, estimated from its keys before a particle is generated: the particle count
//! (an upper bound: cut-outs and polygon edges only remove particles), the neighbour pairs, and
//! the memory a run takes. A case over the limit is refused with one line giving the estimate.
//!
//! All arithmetic on counts is in floating point (a count of 1e300 is a number here, not a
//! wrapped integer); only a case within the limit reaches the integer code that generates it.
//!
//! The memory model was fitted to measured peak resident sizes of the 2D surface blast (with
//! strength, mirrors and gauges): 160 000 particles 214 MiB, 640 000 particles 811 MiB, i.e.
//! about 1.3 kB a particle with h = Δx; it charges 700 B a particle (1.5× where walls make
//! mirror particles), and 40 + 24·dim B per neighbour pair, a pair per particle being half the
//! lattice points within the kernel's support.

use super::types::{Case, Shape};
use crate::error::{Result, input};

/// Bytes per particle (real or mirror) of the state, the work arrays and the run loop.
const BYTES_PER_PARTICLE: f64 = 700.0;
/// The fraction of the machine's memory a run may plan to take.
const MEMORY_FRACTION: f64 = 0.8;
/// Particle and pair indices cross the Fortran boundary as 32-bit integers.
const INDEX_MAX: f64 = i32::MAX as f64;

/// What a case needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// Real particles (an upper bound).
    pub particles: f64,
    /// Real and mirror particles.
    pub total: f64,
    /// Neighbour pairs.
    pub pairs: f64,
    /// Memory (bytes).
    pub bytes: f64,
    /// Point tests of the generation (polygons test every lattice point of their bounding box
    /// against every edge).
    pub tests: f64,
}

/// Lattice points of region `r` before cut-outs (per axis and in all).
fn lattice_count(case: &Case, r: usize) -> (f64, f64) {
    let rc = &case.regions[r];
    let d = case.dim;
    let dx = rc.spacing_m;
    let axis = |lo: f64, hi: f64| cells(hi - lo, dx) as f64;
    let (mut n, mut tests) = (1.0f64, 0.0);
    match rc.shape {
        Shape::Box => {
            if let (Some(lo), Some(hi)) = (&rc.lo_m, &rc.hi_m) {
                for a in 0..d.min(lo.len()).min(hi.len()) {
                    n *= axis(lo[a], hi[a]);
                }
            }
        }
        Shape::Polygon => {
            let v = rc.vertices_m.as_deref().unwrap_or(&[]);
            for a in 0..2 {
                let lo = v.iter().filter_map(|p| p.get(a)).fold(f64::INFINITY, |m, x| m.min(*x));
                let hi = v.iter().filter_map(|p| p.get(a)).fold(f64::NEG_INFINITY, |m, x| m.max(*x));
                n *= if hi > lo { axis(lo, hi) } else { 0.0 };
            }
            tests = n * v.len() as f64;
        }
        Shape::Lattice => {
            for &c in rc.count.as_deref().unwrap_or(&[]) {
                n *= c as f64;
            }
        }
        Shape::Cylinder | Shape::Sphere => {
            // the (clipped) bounding box: an upper bound of the points kept
            if let (Some(c), Some(rad)) = (&rc.center_m, rc.radius_m) {
                for a in 0..d.min(c.len()) {
                    let (mut lo, mut hi) = (c[a] - rad, c[a] + rad);
                    if rc.shape == Shape::Cylinder && a == 2 {
                        (lo, hi) = (c[2], c[2] + rc.height_m.unwrap_or(0.0));
                    }
                    if let (Some(l), Some(h)) = (&rc.lo_m, &rc.hi_m)
                        && a < l.len().min(h.len())
                    {
                        (lo, hi) = (lo.max(l[a]), hi.min(h[a]));
                    }
                    n *= if hi > lo { axis(lo, hi) } else { 0.0 };
                }
            }
        }
    }
    (n, tests)
}

/// The case's size, from its keys (a validated case).
pub fn estimate(case: &Case) -> Estimate {
    let d = case.dim;
    let kappa = case.sph.kernel.support();
    // lattice points within the support of a particle: the ball of radius κ h/Δx
    let ball = |q: f64| -> f64 {
        let r = kappa * q;
        match d {
            1 => 2.0 * r,
            2 => std::f64::consts::PI * r * r,
            _ => 4.0 / 3.0 * std::f64::consts::PI * r * r * r,
        }
    };
    let mut e = Estimate { particles: 0.0, total: 0.0, pairs: 0.0, bytes: 0.0, tests: 0.0 };
    let mut per_region = Vec::with_capacity(case.regions.len());
    for (r, rc) in case.regions.iter().enumerate() {
        let (n, tests) = lattice_count(case, r);
        let q = rc.h_m.map_or(case.sph.h_over_dx, |h| h / rc.spacing_m);
        e.particles += n;
        e.tests += tests;
        per_region.push((n, 0.5 * ball(q)));
    }
    for (n, half) in per_region {
        e.pairs += n * half.min(e.particles);
    }
    let mirrors = case.walls.iter().any(|w| w.kind.mirrors());
    e.total = e.particles * if mirrors { 1.5 } else { 1.0 };
    e.bytes = e.total * BYTES_PER_PARTICLE + e.pairs * (40.0 + 24.0 * d as f64);
    e
}

/// The memory a run may plan to take (bytes), and where the number comes from: 80 % of the
/// machine's memory, or of the control group's limit where that is lower.
pub fn memory_limit() -> (f64, String) {
    static LIMIT: std::sync::OnceLock<(f64, String)> = std::sync::OnceLock::new();
    LIMIT
        .get_or_init(|| {
            let total = std::fs::read_to_string("/proc/meminfo").ok().and_then(|s| {
                s.lines()
                    .find(|l| l.starts_with("MemTotal:"))
                    .and_then(|l| l.split_whitespace().nth(1))
                    .and_then(|k| k.parse::<f64>().ok())
                    .map(|k| k * 1024.0)
            });
            let cgroup =
                std::fs::read_to_string("/sys/fs/cgroup/memory.max").ok().and_then(|s| s.trim().parse::<f64>().ok());
            let (bytes, from) = match (total, cgroup) {
                (Some(t), Some(c)) if c < t => (c, "this control group's memory limit"),
                (Some(t), _) => (t, "this machine's memory"),
                (None, Some(c)) => (c, "this control group's memory limit"),
                (None, None) => (8.0 * 1024.0 * 1024.0 * 1024.0, "an assumed 8 GiB (the machine's memory is unknown)"),
            };
            (MEMORY_FRACTION * bytes, format!("80 % of {from}, {}", bytes_text(bytes)))
        })
        .clone()
}

/// A byte count as people read it.
pub fn bytes_text(b: f64) -> String {
    const UNITS: [&str; 6] = ["B", "kB", "MB", "GB", "TB", "PB"];
    let mut x = b;
    let mut u = 0;
    while x >= 1000.0 && u + 1 < UNITS.len() {
        x /= 1000.0;
        u += 1;
    }
    if u + 1 == UNITS.len() && x >= 1000.0 { format!("{b:.2e} B") } else { format!("{x:.1} {}", UNITS[u]) }
}

/// Refuses a case that exceeds the limit: `max_particles` when given (`--max-particles`), else
/// the particles that fit in [`memory_limit`]; and, whatever the limit, counts beyond the 32-bit
/// indices of the Fortran boundary or generations that would take hours. Returns the estimate.
pub fn check(case: &Case, max_particles: Option<u64>) -> Result<Estimate> {
    let e = estimate(case);
    let what = format!(
        "the case needs about {:.3e} particles ({:.3e} neighbour pairs, {} of memory)",
        e.particles,
        e.pairs,
        bytes_text(e.bytes)
    );
    if !(e.particles.is_finite() && e.bytes.is_finite()) || e.total > INDEX_MAX || e.pairs > INDEX_MAX {
        return Err(input(format!("{what}: beyond the 2^31 particles and pairs the solver can index")));
    }
    if e.tests > 1e10 {
        return Err(input(format!(
            "{what}: filling its polygons takes {:.3e} point tests (at most 1e10: fewer vertices or a coarser spacing)",
            e.tests
        )));
    }
    match max_particles {
        Some(m) if e.particles > m as f64 => Err(input(format!("{what}: more than --max-particles {m}"))),
        Some(_) => Ok(e),
        None => {
            let (limit, from) = memory_limit();
            if e.bytes > limit {
                let per = e.bytes / e.particles.max(1.0);
                Err(input(format!(
                    "{what}: more than the limit of {:.3e} particles ({} of memory, {from}; --max-particles N to change it)",
                    (limit / per).floor(),
                    bytes_text(limit)
                )))
            } else {
                Ok(e)
            }
        }
    }
}

/// The whole spacings `dx` in an extent: ⌊extent/dx⌋, with a tolerance of 10⁻⁴ of the count (and
/// 10⁻⁹) for an extent written to a few significant digits (0.073096 for four spacings of
/// 0.01827416 is 3.99996 of them: four, not three).
pub(crate) fn cells(extent: f64, dx: f64) -> usize {
    let r = extent / dx;
    (r + 1e-9 + 1e-4 * r.abs()).floor().max(0.0) as usize
}
