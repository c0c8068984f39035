//! The parity harness shared by every module's `parity.rs`: both implementations of a routine run
//! on the same seeded random inputs of realistic ranges, and every output is compared value by
//! value in units in the last place at the stage's tolerance (0 ULP everywhere: JWL's `exp`, the
//! Gauss kernel's `exp` and h from density in 3D (`pow`) come from the same C library on both
//! sides). [`parity`] is generic over [`Twin`]: a test builds the routine's argument list around
//! the outputs it is handed and the harness runs it once per implementation, outputs pre-filled
//! with a sentinel so that a twin that forgets to write a slot the other writes is caught.
//! Run `cargo test --release --lib parity -- --nocapture` to see the max ULP of every check.
//!
//! The generator is a xorshift64* written here, with a fixed seed per test.

use super::nnps::{self, PairList};
use super::param::{MatTable, NPAR, NSTR, SPH_MP_ALPHA_PHI, SPH_MP_COHESION, SPH_MP_PMIN, SPH_MP_SHEAR};
use super::{Backend, Twin, kernel};
use crate::case::KernelKind;
use crate::modules::ulp::ulp_diff;

pub const F: Backend = Backend::Fortran;
pub const R: Backend = Backend::Rust;
/// Written into every output array before a call: a slot left unwritten keeps it.
pub const SENTINEL: f64 = 1.234_567_890_123e300;
pub const KERNELS: [KernelKind; 4] = [KernelKind::Cubic, KernelKind::Gauss, KernelKind::Quintic, KernelKind::Wendland];

/// xorshift64* (Vigna), seeded.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    pub fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }
    pub fn vec(&mut self, n: usize, lo: f64, hi: f64) -> Vec<f64> {
        (0..n).map(|_| self.range(lo, hi)).collect()
    }
}

/// Asserts that the Fortran and Rust outputs agree within `tol` ULP (NaN on either side fails);
/// prints and returns the largest difference.
pub fn check(what: &str, tol: u64, fortran: &[f64], rust: &[f64]) -> u64 {
    assert_eq!(fortran.len(), rust.len(), "{what}: lengths differ (fortran {}, rust {})", fortran.len(), rust.len());
    let mut worst = 0;
    for (k, (&a, &b)) in fortran.iter().zip(rust).enumerate() {
        let u = ulp_diff(a, b);
        assert!(
            u <= tol,
            "{what}: value {k}: fortran {a:e} ({:#018x}), rust {b:e} ({:#018x}): {u} ULP > {tol}",
            a.to_bits(),
            b.to_bits()
        );
        worst = worst.max(u);
    }
    eprintln!("parity {what}: {} values, max {worst} ULP (tier {tol})", fortran.len());
    worst
}

/// Asserts equal integer outputs.
pub fn check_i(what: &str, fortran: &[i32], rust: &[i32]) {
    assert_eq!(fortran.len(), rust.len(), "{what}: lengths differ");
    if let Some(k) = fortran.iter().zip(rust).position(|(a, b)| a != b) {
        panic!("{what}: entry {k}: fortran {}, rust {}", fortran[k], rust[k]);
    }
    eprintln!("parity {what}: {} integers, identical", fortran.len());
}

/// Fails when every value is zero or the sentinel: the test would exercise nothing.
pub fn nonzero(what: &str, v: &[f64]) {
    assert!(v.iter().any(|x| *x != 0.0 && *x != SENTINEL), "{what}: every value is zero: the test exercises nothing");
}

/// The generic harness: `call(b, outs)` builds the routine's argument list around `outs` and
/// runs implementation `b` (`Twin::run`). `outs` start as `init` (a sentinel-filled array for a
/// pure output, the current values for an in-place update); each output is compared at `tol` ULP
/// and the Fortran outputs are returned. `names` label the outputs in messages.
pub fn parity<const K: usize>(
    tag: &str,
    tol: u64,
    names: [&str; K],
    init: [Vec<f64>; K],
    call: impl Fn(Backend, &mut [Vec<f64>; K]),
) -> [Vec<f64>; K] {
    let mut f = init.clone();
    let mut r = init;
    call(F, &mut f);
    call(R, &mut r);
    for k in 0..K {
        check(&format!("{tag} {}", names[k]), tol, &f[k], &r[k]);
    }
    f
}

/// A sentinel-filled output of `n` values.
pub fn sentinel(n: usize) -> Vec<f64> {
    vec![SENTINEL; n]
}

/// Runs `t` with implementation `b` (the [`Twin`] dispatch), for tests that build the argument
/// list in place.
pub fn run<T: Twin>(mut t: T, b: Backend) {
    t.run(b)
}

/// A particle cloud in the Fortran layout: a jittered lattice of `side^dim` real particles of
/// spacing `dx` (0.01 m), then a layer of virtual particles: the images of the first two lattice
/// layers across the plane x0 = −dx/2 (as mirrors would be). Per-particle h in [1.0, 1.5] dx.
pub struct Cloud {
    pub dim: usize,
    pub nreal: usize,
    pub nt: usize,
    pub dx: f64,
    pub x: Vec<f64>,
    pub v: Vec<f64>,
    pub h: Vec<f64>,
    pub rho: Vec<f64>,
    pub mass: Vec<f64>,
    pub p: Vec<f64>,
    pub c: Vec<f64>,
    pub e: Vec<f64>,
    pub mat: Vec<i32>,
    pub tau: Vec<f64>,
}

pub fn cloud(dim: usize, side: usize, seed: u64) -> Cloud {
    let mut g = Rng::new(seed);
    let dx = 0.01;
    let nreal = side.pow(dim as u32);
    let mut x = Vec::with_capacity(dim * nreal * 2);
    for l in 0..nreal {
        let mut k = l;
        for _ in 0..dim {
            let idx = (k % side) as f64;
            k /= side;
            x.push((idx + g.range(-0.2, 0.2)) * dx);
        }
    }
    let mut ghosts = Vec::new();
    for i in 0..nreal {
        if x[dim * i] < 1.5 * dx {
            ghosts.push(-dx - x[dim * i]);
            ghosts.extend_from_slice(&x[dim * i + 1..dim * i + dim]);
        }
    }
    x.extend_from_slice(&ghosts);
    let nt = x.len() / dim;
    assert!(nt > nreal);
    let h = (0..nt).map(|_| dx * g.range(1.0, 1.5)).collect();
    let rho: Vec<f64> = g.vec(nt, 900.0, 2100.0);
    let mass = rho.iter().map(|r| r * dx.powi(dim as i32) * g.range(0.95, 1.05)).collect();
    let mut tau = g.vec(NSTR * nt, -2e6, 2e6);
    if dim == 2 {
        // plane strain: no out-of-plane shear
        for i in 0..nt {
            tau[4 + NSTR * i] = 0.0;
            tau[5 + NSTR * i] = 0.0;
        }
    }
    Cloud {
        dim,
        nreal,
        nt,
        dx,
        v: g.vec(dim * nt, -80.0, 80.0),
        h,
        rho,
        mass,
        p: g.vec(nt, -1e5, 5e7),
        c: g.vec(nt, 300.0, 2000.0),
        e: g.vec(nt, 0.0, 5e5),
        mat: (0..nt).map(|_| g.below(4) as i32).collect(),
        tau,
        x,
    }
}

/// Seeds per dimension for the cloud-based tests.
const SEEDS: u64 = 6;

/// (dim, seed) for dims 1, 2, 3 and [`SEEDS`] seeds each.
pub fn clouds(base: u64) -> Vec<(usize, u64)> {
    (1..=3).flat_map(|d| (0..SEEDS).map(move |s| (d, base * 1000 + 10 * s + d as u64))).collect()
}

/// The side of the lattice for a cloud of a few hundred particles.
pub fn side(dim: usize) -> usize {
    match dim {
        1 => 150,
        2 => 18,
        _ => 7,
    }
}

/// The neighbour search of implementation `b` over the cloud.
pub fn search(b: Backend, cell: bool, cl: &Cloud, kappa: f64) -> PairList {
    let mut pl = PairList::default();
    nnps::Search { cell, dim: cl.dim, nreal: cl.nreal, x: &cl.x, h: &cl.h, kappa, pairs: &mut pl }.run(b);
    pl
}

/// Pairs within κ h_ij from the (Fortran, direct) search, with the incidence lists.
pub fn pairs(cl: &Cloud, kappa: f64) -> PairList {
    let mut pl = search(F, false, cl, kappa);
    pl.build_incidence(cl.nt);
    assert!(pl.len() > cl.nreal, "too few pairs: {}", pl.len());
    assert!(pl.j.iter().any(|&j| j as usize >= cl.nreal), "no pair reaches a virtual particle");
    pl
}

/// W and ∇W of every pair (cubic spline), the input of the pair-sum modules.
pub fn kernel_values(cl: &Cloud, pl: &PairList) -> (Vec<f64>, Vec<f64>) {
    let mut w = vec![0.0; pl.len()];
    let mut dwdx = vec![0.0; cl.dim * pl.len()];
    kernel::Pairs {
        dim: cl.dim,
        kind: KernelKind::Cubic,
        pairs: pl,
        x: &cl.x,
        h: &cl.h,
        w: &mut w,
        dwdx: &mut dwdx,
        gscale: 1.0,
    }
    .run(F);
    (w, dwdx)
}

/// One material column of `mpar`.
pub fn column(rho0: f64, e: &[f64], pmin: f64, strength: Option<(f64, f64, f64)>) -> Vec<f64> {
    let mut col = vec![0.0; NPAR];
    col[0] = rho0;
    col[1..1 + e.len()].copy_from_slice(e);
    col[SPH_MP_PMIN as usize - 1] = pmin;
    if let Some((g, aphi, k)) = strength {
        col[SPH_MP_SHEAR as usize - 1] = g;
        col[SPH_MP_ALPHA_PHI as usize - 1] = aphi;
        col[SPH_MP_COHESION as usize - 1] = k;
    }
    col
}

pub const NO_FLOOR: f64 = -f64::MAX;
pub const TNT: [f64; 6] = [3.712e11, 3.21e9, 4.15, 0.95, 0.30, 6930.0];
pub const C4: [f64; 6] = [6.0997e11, 1.295e10, 4.5, 1.4, 0.25, 8193.0];
pub const WATER: [f64; 6] = [2.19e9, 9.224e9, 8.767e9, 0.4934, 1.3937, 1480.0];
pub const LOOSE_SAND: [f64; 3] = [1440.0, 1.6, 0.11];
pub const DENSE_SAND: [f64; 3] = [1614.0, 1.5, 0.11];

/// A material table from (mtype, column) per material and optional penalty groups.
pub fn table(mats: Vec<(u32, Vec<f64>)>, group: Option<Vec<i32>>) -> MatTable {
    let n = mats.len();
    MatTable {
        mtype: mats.iter().map(|m| m.0 as i32).collect(),
        mpar: mats.into_iter().flat_map(|m| m.1).collect(),
        group: group.unwrap_or_else(|| (0..n as i32).collect()),
    }
}

#[test]
#[should_panic(expected = "1 ULP > 0")]
fn harness_detects_one_ulp() {
    let a = [1.0f64, 2.5, -3.75];
    let mut b = a;
    b[1] = f64::from_bits(b[1].to_bits() + 1);
    check("harness", 0, &a, &b);
}

#[test]
#[should_panic(expected = "ULP > 4")]
fn harness_detects_nan() {
    check("harness", 4, &[1.0], &[f64::NAN]);
}

#[test]
fn harness_ulp_distance() {
    assert_eq!(ulp_diff(0.0, -0.0), 0);
    assert_eq!(ulp_diff(1.0, f64::from_bits(1.0f64.to_bits() + 3)), 3);
    // across zero: the smallest subnormals on either side are 2 ULP apart
    assert_eq!(ulp_diff(f64::from_bits(1), -f64::from_bits(1)), 2);
}

/// The harness must fail when one implementation differs: a routine whose "Rust twin" adds one
/// ULP to a value is caught.
#[test]
#[should_panic(expected = "ULP > 0")]
fn harness_catches_a_twin_that_differs() {
    struct Off<'a>(&'a mut [f64]);
    impl Twin for Off<'_> {
        fn rust(&mut self) {
            self.0[0] = f64::from_bits(2.0f64.to_bits() + 1);
        }
        fn fortran(&mut self) {
            self.0[0] = 2.0;
        }
    }
    parity("harness twin", 0, ["out"], [sentinel(1)], |b, o| run(Off(&mut o[0]), b));
}
