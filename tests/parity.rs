//! Parity tests: every module function that has both a Fortran and a Rust implementation, run on
//! the same seeded random inputs of realistic ranges, the two outputs compared value by value in
//! units in the last place (`blastsph::dual::ulp_diff`) at the module's tier
//! (`blastsph::dual::tolerance`: 0 ULP everywhere, eos and smoothing included, whose `exp` / `pow`
//! both sides take from the same C library).
//!
//! Pair-sum modules see realistic neighbourhoods: the pair lists come from the real neighbour
//! search over jittered lattices with a per-particle h and a layer of virtual particles
//! (nreal < ntotal), and the Rust twins get `PairList::build_incidence(ntotal)` first, as the
//! solver does. Output arrays start filled with a sentinel on both sides, so a twin that forgets
//! to write (or zero) a slot that the other writes is caught.
//!
//! Observed on the development machine (x86_64, gfortran 12 with `-O2 -ffp-contract=off`, glibc
//! libm, Rust 1.95): **0 ULP in every comparison of this file**, including the JWL EOS (`exp`),
//! the Gauss kernel (`exp`) and h from density in 3D (`pow`): both sides call the same C library
//! functions in the same order, so the 4-ULP allowance of eos and smoothing is not used here. It
//! exists for builds where the two sides take `exp`/`pow` from different libraries.
//! Run `cargo test --release --test parity -- --nocapture` to see the max ULP of every check.
//!
//! The generator is a xorshift64* written here, with a fixed seed per test, so every run sees the
//! same inputs.

use blastsph::case::KernelKind;
use blastsph::dual::{tolerance, ulp_diff};
use blastsph::legacy::{
    self, Leapfrog, MatTable, MirrorArrays, NPAR, NSTR, Rates, SPH_EOS_IDEAL_GAS, SPH_EOS_JWL, SPH_EOS_SOIL,
    SPH_EOS_WATER, SPH_MP_ALPHA_PHI, SPH_MP_COHESION, SPH_MP_PMIN, SPH_MP_SHEAR, Segments,
};
use blastsph::modules::nnps::{self, PairList};
use blastsph::modules::strength::StrengthOut;
use blastsph::modules::{
    Backend, Module, boundary, density, detonation, eos, force, integrator, kernel, penalty, smoothing, strength,
    viscosity, xsph,
};

const F: Backend = Backend::Fortran;
const R: Backend = Backend::Rust;
/// Written into every output array before a call: a slot left unwritten keeps it.
const SENTINEL: f64 = 1.234_567_890_123e300;
const KERNELS: [KernelKind; 4] = [KernelKind::Cubic, KernelKind::Gauss, KernelKind::Quintic, KernelKind::Wendland];

// ---------------------------------------------------------------------------------------------
// Helpers: generator, comparison, particle clouds, material tables.

/// xorshift64* (Vigna), seeded.
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Rng {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
    fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }
    fn vec(&mut self, n: usize, lo: f64, hi: f64) -> Vec<f64> {
        (0..n).map(|_| self.range(lo, hi)).collect()
    }
}

/// The widest tier of a module over the inputs these tests draw (3D and JWL included).
fn tier(m: Module) -> u64 {
    tolerance(m, 3, true).0
}

/// Asserts that the Fortran and Rust outputs agree within `tol` ULP (NaN on either side fails);
/// prints and returns the largest difference.
fn check(what: &str, tol: u64, fortran: &[f64], rust: &[f64]) -> u64 {
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

fn check_i(what: &str, fortran: &[i32], rust: &[i32]) {
    assert_eq!(fortran.len(), rust.len(), "{what}: lengths differ");
    if let Some(k) = fortran.iter().zip(rust).position(|(a, b)| a != b) {
        panic!("{what}: entry {k}: fortran {}, rust {}", fortran[k], rust[k]);
    }
    eprintln!("parity {what}: {} integers, identical", fortran.len());
}

fn nonzero(what: &str, v: &[f64]) {
    assert!(v.iter().any(|x| *x != 0.0 && *x != SENTINEL), "{what}: every value is zero: the test exercises nothing");
}

fn sentinel(n: usize) -> Vec<f64> {
    vec![SENTINEL; n]
}

/// A particle cloud in the Fortran layout: a jittered lattice of `side^dim` real particles of
/// spacing `dx` (0.01 m), then a layer of virtual particles: the images of the first two lattice
/// layers across the plane x0 = −dx/2 (as mirrors would be). Per-particle h in [1.0, 1.5] dx.
struct Cloud {
    dim: usize,
    nreal: usize,
    nt: usize,
    dx: f64,
    x: Vec<f64>,
    v: Vec<f64>,
    h: Vec<f64>,
    rho: Vec<f64>,
    mass: Vec<f64>,
    p: Vec<f64>,
    c: Vec<f64>,
    e: Vec<f64>,
    mat: Vec<i32>,
    tau: Vec<f64>,
}

fn cloud(dim: usize, side: usize, seed: u64) -> Cloud {
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
fn clouds(base: u64) -> Vec<(usize, u64)> {
    (1..=3).flat_map(|d| (0..SEEDS).map(move |s| (d, base * 1000 + 10 * s + d as u64))).collect()
}

/// The side of the lattice for a cloud of a few hundred particles.
fn side(dim: usize) -> usize {
    match dim {
        1 => 150,
        2 => 18,
        _ => 7,
    }
}

/// Pairs within κ h_ij from the real (Fortran, direct) search, with the incidence lists.
fn pairs(cl: &Cloud, kappa: f64) -> PairList {
    let mut pl = PairList::default();
    nnps::search(F, false, cl.dim, cl.nreal, &cl.x, &cl.h, kappa, &mut pl);
    pl.build_incidence(cl.nt);
    assert!(pl.len() > cl.nreal, "too few pairs: {}", pl.len());
    assert!(pl.j.iter().any(|&j| j as usize >= cl.nreal), "no pair reaches a virtual particle");
    pl
}

/// W and ∇W of every pair (cubic spline), the input of the pair-sum modules.
fn kernel_values(cl: &Cloud, pl: &PairList) -> (Vec<f64>, Vec<f64>) {
    let mut w = vec![0.0; pl.len()];
    let mut dwdx = vec![0.0; cl.dim * pl.len()];
    kernel::pairs(F, cl.dim, KernelKind::Cubic, pl, &cl.x, &cl.h, &mut w, &mut dwdx);
    (w, dwdx)
}

/// One material column of `mpar`.
fn column(rho0: f64, e: &[f64], pmin: f64, strength: Option<(f64, f64, f64)>) -> Vec<f64> {
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

const NO_FLOOR: f64 = -f64::MAX;
const TNT: [f64; 6] = [3.712e11, 3.21e9, 4.15, 0.95, 0.30, 6930.0];
const C4: [f64; 6] = [6.0997e11, 1.295e10, 4.5, 1.4, 0.25, 8193.0];
const WATER: [f64; 6] = [2.19e9, 9.224e9, 8.767e9, 0.4934, 1.3937, 1480.0];
const LOOSE_SAND: [f64; 3] = [1440.0, 1.6, 0.11];
const DENSE_SAND: [f64; 3] = [1614.0, 1.5, 0.11];

/// The table of the EOS tests: (mtype, column) per material.
fn eos_table() -> MatTable {
    let mats: Vec<(u32, Vec<f64>)> = vec![
        (SPH_EOS_IDEAL_GAS, column(1.0, &[1.4], NO_FLOOR, None)),
        (SPH_EOS_JWL, column(1630.0, &TNT, NO_FLOOR, None)),
        (SPH_EOS_JWL, column(1601.0, &C4, 0.0, None)),
        (SPH_EOS_WATER, column(1000.0, &WATER, NO_FLOOR, None)),
        // water with a cavitation floor
        (SPH_EOS_WATER, column(1000.0, &WATER, -2.0e6, None)),
        // loose sand with a tension cut-off at p = 0
        (SPH_EOS_SOIL, column(1450.0, &LOOSE_SAND, 0.0, Some((63.58e6, 0.25, 2.0e3)))),
        // dense sand without a floor (negative pressures come out)
        (SPH_EOS_SOIL, column(2200.0, &DENSE_SAND, NO_FLOOR, Some((240e6, 0.25, 2.0e3)))),
    ];
    table(mats, None)
}

fn table(mats: Vec<(u32, Vec<f64>)>, group: Option<Vec<i32>>) -> MatTable {
    let n = mats.len();
    MatTable {
        mtype: mats.iter().map(|m| m.0 as i32).collect(),
        mpar: mats.into_iter().flat_map(|m| m.1).collect(),
        group: group.unwrap_or_else(|| (0..n as i32).collect()),
    }
}

// ---------------------------------------------------------------------------------------------
// The comparison itself must be able to fail.

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

// ---------------------------------------------------------------------------------------------
// kernel

#[test]
fn kernel_pairs_all_kernels_all_dims() {
    for (dim, seed) in clouds(11) {
        let cl = cloud(dim, side(dim), seed);
        for kind in KERNELS {
            let pl = pairs(&cl, kind.support());
            let np = pl.len();
            // the pairs reach every branch of the kernel: q < 1, 1 ≤ q < 2, (and 2 ≤ q < 3)
            let mut branch = [0usize; 3];
            for k in 0..np {
                let (i, j) = (pl.i[k] as usize, pl.j[k] as usize);
                let r = (0..dim).map(|d| (cl.x[d + dim * i] - cl.x[d + dim * j]).powi(2)).sum::<f64>().sqrt();
                let q = r / (0.5 * (cl.h[i] + cl.h[j]));
                branch[(q as usize).min(2)] += 1;
            }
            assert!(branch[0] > 0 && branch[1] > 0, "{branch:?}");
            if kind.support() > 2.0 {
                assert!(branch[2] > 0, "{branch:?}");
            }
            let (mut wf, mut gf) = (sentinel(np), sentinel(dim * np));
            let (mut wr, mut gr) = (sentinel(np), sentinel(dim * np));
            kernel::pairs(F, dim, kind, &pl, &cl.x, &cl.h, &mut wf, &mut gf);
            kernel::pairs(R, dim, kind, &pl, &cl.x, &cl.h, &mut wr, &mut gr);
            let tag = format!("kernel::pairs {} {dim}D seed {seed}", kind.name());
            nonzero(&tag, &gf);
            check(&format!("{tag} w"), tier(Module::Kernel), &wf, &wr);
            check(&format!("{tag} dwdx"), tier(Module::Kernel), &gf, &gr);
        }
    }
}

#[test]
fn kernel_self_all_kernels_all_dims() {
    let mut g = Rng::new(21);
    let h = g.vec(500, 0.002, 0.05);
    for dim in 1..=3 {
        for kind in KERNELS {
            let (mut f, mut r) = (sentinel(h.len()), sentinel(h.len()));
            kernel::self_w(F, dim, kind, &h, &mut f);
            kernel::self_w(R, dim, kind, &h, &mut r);
            let tag = format!("kernel::self_w {} {dim}D", kind.name());
            nonzero(&tag, &f);
            check(&tag, tier(Module::Kernel), &f, &r);
        }
    }
}

/// The Fortran point evaluation against the Rust `w_dw` at the branch edges q = 0, 1, 2, 3 (and
/// either side of them), along an axis and along a diagonal.
#[test]
fn kernel_point_at_branch_edges() {
    let h = 0.013;
    let mut qs = vec![0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5];
    for edge in [1.0f64, 2.0, 3.0] {
        qs.push(f64::from_bits(edge.to_bits() - 1));
        qs.push(f64::from_bits(edge.to_bits() + 1));
    }
    for dim in 1..=3 {
        for kind in KERNELS {
            let mut f = Vec::new();
            let mut r = Vec::new();
            for &q in &qs {
                for diagonal in [false, true] {
                    let mut dx = vec![0.0; dim];
                    if diagonal {
                        let s = q * h / (dim as f64).sqrt();
                        dx.iter_mut().enumerate().for_each(|(d, v)| {
                            *v = if d % 2 == 0 { s } else { -s };
                        });
                    } else {
                        dx[0] = q * h;
                    }
                    let (wf, gf) = legacy::kernel_point(dim, kind.skf(), &dx, h);
                    let rr = dx.iter().map(|v| v * v).sum::<f64>().sqrt();
                    let mut gr = vec![0.0; dim];
                    let wr = kernel::w_dw(dim, kind, rr, &dx, h, &mut gr);
                    f.push(wf);
                    f.extend_from_slice(&gf);
                    r.push(wr);
                    r.extend_from_slice(&gr);
                }
            }
            let tag = format!("kernel::w_dw edges {} {dim}D", kind.name());
            check(&tag, tier(Module::Kernel), &f, &r);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// nnps

fn search(b: Backend, cell: bool, cl: &Cloud, kappa: f64) -> PairList {
    let mut pl = PairList::default();
    nnps::search(b, cell, cl.dim, cl.nreal, &cl.x, &cl.h, kappa, &mut pl);
    pl
}

#[test]
fn nnps_direct_and_cell_fortran_vs_rust() {
    for (dim, seed) in clouds(31) {
        for kappa in [2.0, 3.0] {
            let cl = cloud(dim, side(dim), seed);
            let reference = search(F, false, &cl, kappa);
            assert!(reference.j.iter().any(|&j| j as usize >= cl.nreal));
            for cell in [false, true] {
                let f = search(F, cell, &cl, kappa);
                let r = search(R, cell, &cl, kappa);
                let tag =
                    format!("nnps::search {} {dim}D seed {seed} kappa {kappa}", if cell { "cell" } else { "direct" });
                check_i(&format!("{tag} i (fortran vs rust)"), &f.i, &r.i);
                check_i(&format!("{tag} j (fortran vs rust)"), &f.j, &r.j);
                // every search returns the same canonical list
                check_i(&format!("{tag} i (vs direct)"), &reference.i, &f.i);
                check_i(&format!("{tag} j (vs direct)"), &reference.j, &f.j);
            }
        }
    }
}

/// A sparse cloud (two clusters far apart, a lone far particle, widely varying h): the cell grid
/// has to coarsen its cells to stay small, and some particles have no neighbour at all.
#[test]
fn nnps_sparse_cloud_with_varying_h() {
    let mut g = Rng::new(41);
    for dim in 1..=3 {
        let nreal = 150;
        let nt = 190;
        let mut x = Vec::new();
        for i in 0..nt {
            let base = if i % 2 == 0 { 0.0 } else { 25.0 };
            for d in 0..dim {
                let far = if i == 7 && d == 0 { 400.0 } else { 0.0 };
                x.push(base + far + g.range(0.0, 0.3));
            }
        }
        let h: Vec<f64> = (0..nt).map(|_| g.range(0.005, 0.08)).collect();
        let cl = Cloud {
            dim,
            nreal,
            nt,
            dx: 0.0,
            x,
            v: vec![],
            h,
            rho: vec![],
            mass: vec![],
            p: vec![],
            c: vec![],
            e: vec![],
            mat: vec![],
            tau: vec![],
        };
        let reference = search(F, false, &cl, 2.0);
        assert!(!reference.is_empty());
        for cell in [false, true] {
            let f = search(F, cell, &cl, 2.0);
            let r = search(R, cell, &cl, 2.0);
            let tag = format!("nnps::search sparse {} {dim}D", if cell { "cell" } else { "direct" });
            check_i(&format!("{tag} i"), &f.i, &r.i);
            check_i(&format!("{tag} j"), &f.j, &r.j);
            check_i(&format!("{tag} i (vs direct)"), &reference.i, &f.i);
            check_i(&format!("{tag} j (vs direct)"), &reference.j, &f.j);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// density

#[test]
fn density_summation_and_rate() {
    for (dim, seed) in clouds(51) {
        let cl = cloud(dim, side(dim), seed);
        let pl = pairs(&cl, 2.0);
        let (w, dwdx) = kernel_values(&cl, &pl);
        let mut w0 = vec![0.0; cl.nt];
        kernel::self_w(F, dim, KernelKind::Cubic, &cl.h, &mut w0);

        let (mut f, mut r) = (sentinel(cl.nt), sentinel(cl.nt));
        density::summation(F, &pl, &w, &w0, &cl.mass, &mut f);
        density::summation(R, &pl, &w, &w0, &cl.mass, &mut r);
        check(&format!("density::summation {dim}D seed {seed}"), tier(Module::Density), &f, &r);

        let (mut f, mut r) = (sentinel(cl.nt), sentinel(cl.nt));
        density::rate(F, dim, &pl, &dwdx, &cl.mass, &cl.v, &mut f);
        density::rate(R, dim, &pl, &dwdx, &cl.mass, &cl.v, &mut r);
        nonzero("density::rate", &f);
        check(&format!("density::rate {dim}D seed {seed}"), tier(Module::Density), &f, &r);
    }
}

// ---------------------------------------------------------------------------------------------
// eos

/// Per material of [`eos_table`]: ρ and e drawn in the physical range of its EOS.
fn eos_state(g: &mut Rng, m: usize) -> (f64, f64) {
    match m {
        // ideal gas: the shock tube's range and beyond
        0 => (g.range(0.05, 5.0), g.range(0.1, 1e3)),
        // JWL products: from the charge (η = 1.3) to far expansion (η = 0.01)
        1 => (1630.0 * g.range(0.01, 1.3), g.range(1e4, 6e6)),
        2 => (1601.0 * g.range(0.01, 1.3), g.range(1e4, 6e6)),
        // water: tension (μ down to −8 %) and compression (μ up to +25 %)
        3 | 4 => (1000.0 * g.range(0.92, 1.25), g.range(0.0, 5e4)),
        // soils: tension and compression
        5 => (1450.0 * g.range(0.9, 1.35), g.range(0.0, 2e3)),
        _ => (2200.0 * g.range(0.9, 1.3), g.range(0.0, 2e3)),
    }
}

#[test]
fn eos_eval_every_material_with_and_without_burn() {
    let mt = eos_table();
    let mut g = Rng::new(61);
    let n = 35_000;
    let mut mat = Vec::with_capacity(n);
    let mut rho = Vec::with_capacity(n);
    let mut e = Vec::with_capacity(n);
    for k in 0..n {
        let m = k % mt.nmat();
        let (r, en) = if k < 7 * mt.nmat() && k % 2 == 0 {
            // a few exactly at the reference density (μ = 0: the tension branch)
            (mt.mpar[NPAR * m], eos_state(&mut g, m).1)
        } else {
            eos_state(&mut g, m)
        };
        mat.push(m as i32);
        rho.push(r);
        e.push(en);
    }
    let burn: Vec<f64> = (0..n)
        .map(|_| match g.below(4) {
            0 => 0.0,
            1 => 1.0,
            _ => g.unit(),
        })
        .collect();
    for (label, b) in [("no burn array", &[][..]), ("burn array", &burn[..])] {
        let (mut pf, mut cf) = (sentinel(n), sentinel(n));
        let (mut pr, mut cr) = (sentinel(n), sentinel(n));
        eos::eval(F, &mt, &mat, b, &rho, &e, &mut pf, &mut cf);
        eos::eval(R, &mt, &mat, b, &rho, &e, &mut pr, &mut cr);
        // every branch is reached: floors, tension and compression of water and soil
        let count = |m: usize, f: &dyn Fn(usize) -> bool| (0..n).filter(|&i| mat[i] as usize == m && f(i)).count();
        let mu = |i: usize| rho[i] / mt.mpar[NPAR * mat[i] as usize] - 1.0;
        assert!(count(4, &|i| pf[i] == -2.0e6) > 0, "water floor never active");
        assert!(count(5, &|i| pf[i] == 0.0) > 0, "soil floor never active");
        assert!(count(6, &|i| pf[i] < 0.0) > 0, "dense sand never in tension");
        for m in [3, 5, 6] {
            assert!(count(m, &|i| mu(i) > 0.0) > 0 && count(m, &|i| mu(i) <= 0.0) > 0);
        }
        assert!(pf.iter().chain(&cf).all(|v| v.is_finite()));
        // per material, so that the report says which EOS differs
        let names = [
            "ideal gas",
            "JWL TNT",
            "JWL C4 (floor 0)",
            "water",
            "water (floor)",
            "soil loose (floor 0)",
            "soil dense",
        ];
        for (m, name) in names.iter().enumerate() {
            let pick = |a: &[f64]| -> Vec<f64> { (0..n).filter(|&i| mat[i] as usize == m).map(|i| a[i]).collect() };
            let tag = format!("eos::eval {name}, {label}");
            check(&format!("{tag} p"), tier(Module::Eos), &pick(&pf), &pick(&pr));
            check(&format!("{tag} c"), tier(Module::Eos), &pick(&cf), &pick(&cr));
        }
    }
}

// ---------------------------------------------------------------------------------------------
// force

#[test]
fn force_internal_fluid_and_with_tau() {
    for (dim, seed) in clouds(71) {
        let cl = cloud(dim, side(dim), seed);
        let pl = pairs(&cl, 2.0);
        let (_, dwdx) = kernel_values(&cl, &pl);
        for with_tau in [false, true] {
            let tau: &[f64] = if with_tau { &cl.tau } else { &[] };
            let (mut af, mut ef) = (sentinel(dim * cl.nt), sentinel(cl.nt));
            let (mut ar, mut er) = (sentinel(dim * cl.nt), sentinel(cl.nt));
            for (b, a, e) in [(F, &mut af, &mut ef), (R, &mut ar, &mut er)] {
                force::internal(b, dim, &pl, &dwdx, &cl.mass, &cl.rho, &cl.p, &cl.v, tau, a, e);
            }
            let tag = format!("force::internal {dim}D seed {seed} {}", if with_tau { "with tau" } else { "fluid" });
            nonzero(&tag, &af);
            check(&format!("{tag} dvdt"), tier(Module::Force), &af, &ar);
            check(&format!("{tag} dedt"), tier(Module::Force), &ef, &er);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// viscosity

#[test]
fn viscosity_monaghan() {
    for (dim, seed) in clouds(81) {
        let cl = cloud(dim, side(dim), seed);
        let pl = pairs(&cl, 2.0);
        let (_, dwdx) = kernel_values(&cl, &pl);
        for coef in [(1.0, 10.0, 0.1), (1.0, 1.0, 0.1), (0.5, 0.0, 0.05)] {
            let (mut af, mut ef) = (sentinel(dim * cl.nt), sentinel(cl.nt));
            let (mut ar, mut er) = (sentinel(dim * cl.nt), sentinel(cl.nt));
            for (b, a, e) in [(F, &mut af, &mut ef), (R, &mut ar, &mut er)] {
                viscosity::monaghan(b, dim, &pl, &dwdx, &cl.x, &cl.v, &cl.h, &cl.rho, &cl.c, &cl.mass, coef, a, e);
            }
            let tag = format!("viscosity::monaghan {dim}D seed {seed} {coef:?}");
            nonzero(&tag, &af);
            check(&format!("{tag} dvdt"), tier(Module::Viscosity), &af, &ar);
            check(&format!("{tag} dedt"), tier(Module::Viscosity), &ef, &er);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// strength

/// Soil with strength (0, 2), water without (1, G = 0), a soil without cohesion (3).
fn strength_table() -> MatTable {
    table(
        vec![
            (SPH_EOS_SOIL, column(1450.0, &LOOSE_SAND, 0.0, Some((63.58e6, 0.25, 2.0e3)))),
            (SPH_EOS_WATER, column(1000.0, &WATER, NO_FLOOR, None)),
            (SPH_EOS_SOIL, column(2200.0, &DENSE_SAND, 0.0, Some((240e6, 0.25, 5.0e4)))),
            (SPH_EOS_SOIL, column(1840.0, &[320.0, 4.92, 0.11], 0.0, Some((20e6, 0.25, 0.0)))),
        ],
        None,
    )
}

#[test]
fn strength_rates_mixed_materials() {
    let mt = strength_table();
    for (dim, seed) in clouds(91) {
        let cl = cloud(dim, side(dim), seed);
        let pl = pairs(&cl, 2.0);
        let (_, dwdx) = kernel_values(&cl, &pl);
        let (nt, n) = (cl.nt, cl.nreal);
        assert!(cl.mat[..n].contains(&1), "no G = 0 particle");
        let mut outs = Vec::new();
        for b in [F, R] {
            let mut eps = sentinel(NSTR * nt);
            let mut rot = sentinel(3 * nt);
            let mut dtau = sentinel(NSTR * n);
            let mut dedt = sentinel(n);
            strength::rates(
                b,
                dim,
                n,
                &pl,
                &dwdx,
                &cl.mass,
                &cl.rho,
                &cl.v,
                &cl.mat,
                &mt,
                &cl.tau,
                StrengthOut { eps: &mut eps, rot: &mut rot, dtau: &mut dtau, dedt: &mut dedt },
            );
            outs.push((eps, rot, dtau, dedt));
        }
        let (f, r) = (&outs[0], &outs[1]);
        let t = tier(Module::Strength);
        let tag = format!("strength::rates {dim}D seed {seed}");
        nonzero(&tag, &f.2);
        check(&format!("{tag} eps"), t, &f.0, &r.0);
        check(&format!("{tag} rot"), t, &f.1, &r.1);
        check(&format!("{tag} dtau"), t, &f.2, &r.2);
        check(&format!("{tag} dedt"), t, &f.3, &r.3);
        // G = 0: no stress rate
        for i in 0..n {
            if cl.mat[i] == 1 {
                assert!(f.2[NSTR * i..NSTR * i + NSTR].iter().all(|v| *v == 0.0));
            }
        }
    }
}

#[test]
fn strength_yield_return_yield_cutoff_and_no_strength() {
    let mt = strength_table();
    let mut g = Rng::new(101);
    let n = 4000;
    let mat: Vec<i32> = (0..n).map(|_| g.below(4) as i32).collect();
    let mut p = Vec::with_capacity(n);
    let mut tau = Vec::with_capacity(NSTR * n);
    for &m in &mat {
        let k = mt.par(m as usize, SPH_MP_COHESION);
        let a = mt.par(m as usize, SPH_MP_ALPHA_PHI);
        // a quarter in tension beyond the cut-off, the rest in compression
        let pi = if g.chance(0.25) { g.range(-1e6, -k / (3.0 * a.max(0.25))) } else { g.range(0.0, 2e6) };
        let y = (3.0 * a * pi + k).max(1e3);
        // deviators from well inside to well outside the yield surface
        let s = y * g.range(0.0, 2.0);
        for _ in 0..NSTR {
            tau.push(s * g.range(-0.8, 0.8));
        }
        p.push(pi);
    }
    let (mut tf, mut tr) = (tau.clone(), tau.clone());
    strength::yield_return(F, &mat, &mt, &p, &mut tf);
    strength::yield_return(R, &mat, &mt, &p, &mut tr);
    let row = |a: &[f64], i: usize| a[NSTR * i..NSTR * i + NSTR].to_vec();
    let (mut yielded, mut cut, mut kept, mut no_g) = (0, 0, 0, 0);
    for (i, &m) in mat.iter().enumerate() {
        let (before, after) = (row(&tau, i), row(&tf, i));
        if m == 1 {
            assert_eq!(before, after, "G = 0 material changed");
            no_g += 1;
        } else if after.iter().all(|v| *v == 0.0) {
            cut += 1;
        } else if after != before {
            yielded += 1;
        } else {
            kept += 1;
        }
    }
    assert!(
        yielded > 100 && cut > 100 && kept > 100 && no_g > 100,
        "yielded {yielded}, cut off {cut}, elastic {kept}, no strength {no_g}"
    );
    check("strength::yield_return", tier(Module::Strength), &tf, &tr);
}

// ---------------------------------------------------------------------------------------------
// penalty

#[test]
fn penalty_force_multiple_groups() {
    // four materials in three groups: 1 and 2 share one (no force between them)
    let mt = table(
        vec![
            (SPH_EOS_JWL, column(1630.0, &TNT, NO_FLOOR, None)),
            (SPH_EOS_WATER, column(1000.0, &WATER, NO_FLOOR, None)),
            (SPH_EOS_WATER, column(1000.0, &WATER, -1e5, None)),
            (SPH_EOS_SOIL, column(1450.0, &LOOSE_SAND, 0.0, Some((63.58e6, 0.25, 2e3)))),
        ],
        Some(vec![0, 1, 1, 2]),
    );
    for (dim, seed) in clouds(111) {
        let cl = cloud(dim, side(dim), seed);
        let pl = pairs(&cl, 2.0);
        let same = (0..pl.len())
            .filter(|&k| {
                let (a, b) = (cl.mat[pl.i[k] as usize], cl.mat[pl.j[k] as usize]);
                a != b && mt.group[a as usize] == mt.group[b as usize]
            })
            .count();
        assert!(same > 0, "no pair of different materials in one group");
        for (pbar, n1, n2) in [(1e5, 12, 6), (3e4, 4, 2)] {
            let (mut af, mut ar) = (sentinel(dim * cl.nt), sentinel(dim * cl.nt));
            for (b, a) in [(F, &mut af), (R, &mut ar)] {
                penalty::force(b, dim, &pl, &cl.x, &cl.h, &cl.mass, &cl.mat, &mt, pbar, n1, n2, a);
            }
            let tag = format!("penalty::force {dim}D seed {seed} n1 {n1} n2 {n2}");
            nonzero(&tag, &af);
            check(&tag, tier(Module::Penalty), &af, &ar);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// boundary

/// A box of `side × side` particles (spacing dx, jittered) with four walls, turned by `angle`
/// so that no normal is along an axis. Returns the cloud (no virtual particles) and the walls.
fn walled_box(side: usize, angle: f64, seed: u64) -> (Cloud, Segments) {
    let mut g = Rng::new(seed);
    let dx = 0.01;
    let l = side as f64 * dx;
    let (cs, sn) = (angle.cos(), angle.sin());
    let rot = |p: [f64; 2]| [cs * p[0] - sn * p[1], sn * p[0] + cs * p[1]];
    let n = side * side;
    let mut x = Vec::with_capacity(2 * n);
    for k in 0..n {
        let (a, b) = ((k % side) as f64, (k / side) as f64);
        let p = rot([(a + 0.5 + g.range(-0.35, 0.35)) * dx, (b + 0.5 + g.range(-0.35, 0.35)) * dx]);
        x.extend_from_slice(&p);
    }
    // corners counter-clockwise; inward normals; the end node kept on two of the four walls
    let corners = [[0.0, 0.0], [l, 0.0], [l, l], [0.0, l]];
    let normals = [[0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [1.0, 0.0]];
    let mut segs = Segments::default();
    for s in 0..4 {
        segs.seg.extend_from_slice(&rot(corners[s]));
        segs.seg.extend_from_slice(&rot(corners[(s + 1) % 4]));
        segs.seg.extend_from_slice(&rot(normals[s]));
        segs.endnode.push(i32::from(s % 2 == 0));
    }
    let cl = Cloud {
        dim: 2,
        nreal: n,
        nt: n,
        dx,
        v: g.vec(2 * n, -60.0, 60.0),
        h: (0..n).map(|_| dx * g.range(1.0, 1.5)).collect(),
        rho: g.vec(n, 1000.0, 2000.0),
        mass: g.vec(n, 0.1, 0.2),
        p: g.vec(n, -1e5, 1e7),
        c: g.vec(n, 300.0, 1500.0),
        e: g.vec(n, 0.0, 1e4),
        mat: (0..n).map(|_| g.below(3) as i32).collect(),
        tau: g.vec(NSTR * n, -1e6, 1e6),
        x,
    };
    (cl, segs)
}

/// A 1D column between two point walls.
fn walled_column(n: usize, seed: u64) -> (Cloud, Segments) {
    let mut g = Rng::new(seed);
    let dx = 0.01;
    let l = n as f64 * dx;
    let x = (0..n).map(|k| (k as f64 + 0.5 + g.range(-0.35, 0.35)) * dx).collect();
    let segs = Segments { seg: vec![0.0, 0.0, 1.0, l, l, -1.0], endnode: vec![1, 1] };
    let cl = Cloud {
        dim: 1,
        nreal: n,
        nt: n,
        dx,
        v: g.vec(n, -60.0, 60.0),
        h: (0..n).map(|_| dx * g.range(1.0, 1.5)).collect(),
        rho: g.vec(n, 1000.0, 2000.0),
        mass: g.vec(n, 10.0, 20.0),
        p: g.vec(n, -1e5, 1e7),
        c: g.vec(n, 300.0, 1500.0),
        e: g.vec(n, 0.0, 1e4),
        mat: (0..n).map(|_| g.below(3) as i32).collect(),
        tau: g.vec(NSTR * n, -1e6, 1e6),
        x,
    };
    (cl, segs)
}

fn walled_cases() -> Vec<(String, Cloud, Segments)> {
    let mut v = Vec::new();
    let (c, s) = walled_column(60, 121);
    v.push(("1D column".to_string(), c, s));
    let (c, s) = walled_box(16, 0.0, 122);
    v.push(("2D box".to_string(), c, s));
    let (c, s) = walled_box(16, 0.37, 123);
    v.push(("2D turned box".to_string(), c, s));
    v
}

#[test]
fn boundary_wall_force() {
    for (name, cl, segs) in walled_cases() {
        let dim = cl.dim;
        for (spacing, r0, dcoef, n1, n2) in
            [(0.25 * cl.dx, 0.5 * cl.dx, 1e4, 12, 4), (cl.dx, cl.dx, 5.0 * 9.81 * 0.2, 4, 2)]
        {
            let (mut af, mut ar) = (sentinel(dim * cl.nreal), sentinel(dim * cl.nreal));
            for (b, a) in [(F, &mut af), (R, &mut ar)] {
                boundary::wall_force(b, dim, &cl.x, &segs, spacing, r0, dcoef, n1, n2, a);
            }
            let tag = format!("boundary::wall_force {name} r0 {r0}");
            nonzero(&tag, &af);
            check(&tag, tier(Module::Boundary), &af, &ar);
        }
    }
}

/// Mirrors of the walled cases: the lists, then the fill (free and no slip, with and without
/// τ), then the copy of one field.
#[test]
fn boundary_mirrors_make_fill_copy() {
    for (name, cl, segs) in walled_cases() {
        let dim = cl.dim;
        let n = cl.nreal;
        let kappa = 2.0;
        let (mut sf, mut gf) = (vec![7; 3], vec![7; 5]);
        let (mut sr, mut gr) = (vec![7; 3], vec![7; 5]);
        boundary::mirror_make(F, dim, &cl.x, &cl.h, kappa, &segs, &mut sf, &mut gf);
        boundary::mirror_make(R, dim, &cl.x, &cl.h, kappa, &segs, &mut sr, &mut gr);
        check_i(&format!("boundary::mirror_make {name} gsrc"), &sf, &sr);
        check_i(&format!("boundary::mirror_make {name} gseg"), &gf, &gr);
        let ng = sf.len();
        assert!(ng > 0);
        if dim == 2 {
            let second = (0..ng).filter(|&g| gf[2 * g + 1] >= 0).count();
            assert!(second > 0, "{name}: no second-generation (corner) mirror");
        }
        let nt = n + ng;
        for noslip in [false, true] {
            for with_tau in [false, true] {
                // real part copied from the cloud, mirror part a sentinel
                let grow = |a: &[f64], w: usize| {
                    let mut v = a[..w * n].to_vec();
                    v.resize(w * nt, SENTINEL);
                    v
                };
                let mut st = Vec::new();
                for b in [F, R] {
                    let mut x = grow(&cl.x, dim);
                    let mut v = grow(&cl.v, dim);
                    let mut rho = grow(&cl.rho, 1);
                    let mut p = grow(&cl.p, 1);
                    let mut c = grow(&cl.c, 1);
                    let mut e = grow(&cl.e, 1);
                    let mut h = grow(&cl.h, 1);
                    let mut mass = grow(&cl.mass, 1);
                    let mut mat = cl.mat[..n].to_vec();
                    mat.resize(nt, -9);
                    let mut tau = if with_tau { grow(&cl.tau, NSTR) } else { vec![] };
                    boundary::mirror_fill(
                        b,
                        dim,
                        n,
                        &sf,
                        &gf,
                        &segs,
                        noslip,
                        MirrorArrays {
                            x: &mut x,
                            v: &mut v,
                            rho: &mut rho,
                            p: &mut p,
                            c: &mut c,
                            e: &mut e,
                            h: &mut h,
                            mass: &mut mass,
                            mat: &mut mat,
                            tau: &mut tau,
                        },
                    );
                    st.push(([x, v, rho, p, c, e, h, mass, tau], mat));
                }
                let tag = format!(
                    "boundary::mirror_fill {name} {} {}",
                    if noslip { "no slip" } else { "free slip" },
                    if with_tau { "with tau" } else { "no tau" }
                );
                let fields = ["x", "v", "rho", "p", "c", "e", "h", "mass", "tau"];
                for (k, field) in fields.iter().enumerate() {
                    assert!(st[0].0[k].iter().all(|v| *v != SENTINEL), "{tag} {field}");
                    check(&format!("{tag} {field}"), tier(Module::Boundary), &st[0].0[k], &st[1].0[k]);
                }
                check_i(&format!("{tag} mat"), &st[0].1, &st[1].1);
            }
        }
        let mut f = cl.e[..n].to_vec();
        f.resize(nt, SENTINEL);
        let mut r = f.clone();
        boundary::mirror_copy(F, n, &sf, &mut f);
        boundary::mirror_copy(R, n, &sf, &mut r);
        check(&format!("boundary::mirror_copy {name}"), tier(Module::Boundary), &f, &r);
    }
}

// ---------------------------------------------------------------------------------------------
// smoothing

#[test]
fn smoothing_from_density_rate_advance() {
    let mut g = Rng::new(131);
    let n = 3000;
    let rho0 = g.vec(n, 1000.0, 2200.0);
    let rho: Vec<f64> = rho0.iter().map(|r| r * g.range(0.3, 1.6)).collect();
    let h0 = g.vec(n, 0.005, 0.02);
    let h = g.vec(n, 0.005, 0.03);
    let drho = g.vec(n, -5e6, 5e6);
    let dhdt = g.vec(n, -20.0, 20.0);
    let t = tier(Module::Smoothing);
    for dim in 1..=3 {
        let (mut f, mut r) = (sentinel(n), sentinel(n));
        smoothing::from_density(F, dim, &rho, &h0, &rho0, &mut f);
        smoothing::from_density(R, dim, &rho, &h0, &rho0, &mut r);
        check(&format!("smoothing::from_density {dim}D"), t, &f, &r);

        let (mut f, mut r) = (sentinel(n), sentinel(n));
        smoothing::rate(F, dim, &rho, &h, &drho, &mut f);
        smoothing::rate(R, dim, &rho, &h, &drho, &mut r);
        check(&format!("smoothing::rate {dim}D"), t, &f, &r);
    }
    for (dt, theta) in [(1e-7, 1.0), (3.3e-6, 0.7)] {
        let (mut f, mut r) = (h.clone(), h.clone());
        smoothing::advance(F, dt, theta, &dhdt, &mut f);
        smoothing::advance(R, dt, theta, &dhdt, &mut r);
        assert_ne!(f, h);
        check(&format!("smoothing::advance dt {dt}"), t, &f, &r);
    }
}

// ---------------------------------------------------------------------------------------------
// xsph

#[test]
fn xsph_average() {
    for (dim, seed) in clouds(141) {
        let cl = cloud(dim, side(dim), seed);
        let pl = pairs(&cl, 2.0);
        let (w, _) = kernel_values(&cl, &pl);
        for eps in [0.5, 0.05] {
            let (mut f, mut r) = (sentinel(dim * cl.nt), sentinel(dim * cl.nt));
            xsph::average(F, dim, &pl, &w, &cl.mass, &cl.rho, &cl.v, eps, &mut f);
            xsph::average(R, dim, &pl, &w, &cl.mass, &cl.rho, &cl.v, eps, &mut r);
            let tag = format!("xsph::average {dim}D seed {seed} eps {eps}");
            nonzero(&tag, &f);
            check(&tag, tier(Module::Xsph), &f, &r);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// detonation

#[test]
fn detonation_light_and_burn() {
    // two explosives (different D) and water, which never lights
    let mt = table(
        vec![
            (SPH_EOS_JWL, column(1630.0, &TNT, NO_FLOOR, None)),
            (SPH_EOS_WATER, column(1000.0, &WATER, NO_FLOOR, None)),
            (SPH_EOS_JWL, column(1601.0, &C4, NO_FLOOR, None)),
        ],
        None,
    );
    for (dim, seed) in clouds(151) {
        let cl = cloud(dim, side(dim), seed);
        let n = cl.nreal;
        let mat: Vec<i32> = cl.mat[..n].iter().map(|m| m % 3).collect();
        let x = &cl.x[..dim * n];
        let xdet: Vec<f64> = (0..dim).map(|d| 0.031 + 0.004 * d as f64).collect();
        let (mut lf, mut lr) = (sentinel(n), sentinel(n));
        detonation::light(F, dim, x, &mat, &mt, &xdet, &mut lf);
        detonation::light(R, dim, x, &mat, &mt, &xdet, &mut lr);
        nonzero("detonation::light", &lf);
        check(&format!("detonation::light {dim}D seed {seed}"), tier(Module::Detonation), &lf, &lr);
        let tmax = lf.iter().cloned().fold(0.0, f64::max);
        let h = &cl.h[..n];
        // unlit (0), burning (0 < λ < 1, width > 0 only) and burnt (1) particles all appear
        let mut seen = [false; 3];
        for width in [0.0, 1.5, 4.0] {
            for frac in [0.0, 0.3, 0.6, 3.0] {
                let t = frac * tmax;
                let (mut bf, mut br) = (sentinel(n), sentinel(n));
                detonation::burn(F, t, &mat, &mt, &lf, h, width, &mut bf);
                detonation::burn(R, t, &mat, &mt, &lf, h, width, &mut br);
                for l in &bf {
                    assert!((0.0..=1.0).contains(l), "burn fraction {l}");
                    seen[if *l == 0.0 {
                        0
                    } else if *l < 1.0 {
                        1
                    } else {
                        2
                    }] = true;
                }
                check(
                    &format!("detonation::burn {dim}D seed {seed} width {width} t {t:.3e}"),
                    tier(Module::Detonation),
                    &bf,
                    &br,
                );
            }
        }
        assert_eq!(seen, [true; 3], "{dim}D seed {seed}: unlit, burning, burnt");
    }
}

// ---------------------------------------------------------------------------------------------
// integrator

#[test]
fn integrator_sum_rates() {
    let mut g = Rng::new(161);
    for dim in 1..=3 {
        let n = 400;
        let lda = dim * (n + 37); // the stacked arrays hold the mirrors too
        for nterm in [0, 1, 2, 5] {
            let acc = g.vec(lda * nterm, -1e6, 1e6);
            let grav: Vec<f64> = (0..dim).map(|d| if d + 1 == dim { -9.81 } else { 0.0 }).collect();
            let (mut f, mut r) = (sentinel(dim * n), sentinel(dim * n));
            integrator::sum_rates(F, dim, n, lda, nterm, &acc, &grav, &mut f);
            integrator::sum_rates(R, dim, n, lda, nterm, &acc, &grav, &mut r);
            check(&format!("integrator::sum_rates {dim}D {nterm} terms"), tier(Module::Integrator), &f, &r);
        }
    }
}

/// The leapfrog state, owned.
#[derive(Clone)]
struct Lf {
    rho: Vec<f64>,
    e: Vec<f64>,
    v: Vec<f64>,
    tau: Vec<f64>,
    rho_min: Vec<f64>,
    e_min: Vec<f64>,
    v_min: Vec<f64>,
    tau_min: Vec<f64>,
    x: Vec<f64>,
}

impl Lf {
    fn new(g: &mut Rng, dim: usize, n: usize, with_tau: bool) -> Lf {
        let nt = if with_tau { NSTR * n } else { 0 };
        Lf {
            rho: g.vec(n, 900.0, 2100.0),
            e: g.vec(n, 0.0, 1e6),
            v: g.vec(dim * n, -300.0, 300.0),
            tau: g.vec(nt, -1e6, 1e6),
            rho_min: g.vec(n, 900.0, 2100.0),
            e_min: g.vec(n, 0.0, 1e6),
            v_min: g.vec(dim * n, -300.0, 300.0),
            tau_min: g.vec(nt, -1e6, 1e6),
            x: g.vec(dim * n, -0.5, 0.5),
        }
    }
    fn lf(&mut self) -> Leapfrog<'_> {
        Leapfrog {
            rho: &mut self.rho,
            e: &mut self.e,
            v: &mut self.v,
            tau: &mut self.tau,
            rho_min: &mut self.rho_min,
            e_min: &mut self.e_min,
            v_min: &mut self.v_min,
            tau_min: &mut self.tau_min,
        }
    }
    fn fields(&self) -> [(&'static str, &Vec<f64>); 9] {
        [
            ("rho", &self.rho),
            ("e", &self.e),
            ("v", &self.v),
            ("tau", &self.tau),
            ("rho_min", &self.rho_min),
            ("e_min", &self.e_min),
            ("v_min", &self.v_min),
            ("tau_min", &self.tau_min),
            ("x", &self.x),
        ]
    }
}

struct Rt {
    drho: Vec<f64>,
    de: Vec<f64>,
    dv: Vec<f64>,
    dtau: Vec<f64>,
}

impl Rt {
    fn new(g: &mut Rng, dim: usize, n: usize, with_tau: bool) -> Rt {
        Rt {
            drho: g.vec(n, -1e7, 1e7),
            de: g.vec(n, -1e10, 1e10),
            dv: g.vec(dim * n, -1e7, 1e7),
            dtau: g.vec(if with_tau { NSTR * n } else { 0 }, -1e12, 1e12),
        }
    }
    fn rates(&self) -> Rates<'_> {
        Rates { drho: &self.drho, de: &self.de, dv: &self.dv, dtau: &self.dtau }
    }
}

fn compare_lf(tag: &str, f: &Lf, r: &Lf) {
    for ((name, a), (_, b)) in f.fields().iter().zip(r.fields().iter()) {
        check(&format!("{tag} {name}"), tier(Module::Integrator), a, b);
    }
}

#[test]
fn integrator_predict() {
    let mut g = Rng::new(171);
    for dim in 1..=3 {
        let n = 500;
        for with_tau in [false, true] {
            for cont in [false, true] {
                let start = Lf::new(&mut g, dim, n, with_tau);
                let rt = Rt::new(&mut g, dim, n, with_tau);
                let dt_prev = g.range(1e-8, 1e-6);
                let (mut f, mut r) = (start.clone(), start.clone());
                integrator::predict(F, dim, n, dt_prev, cont, f.lf(), rt.rates());
                integrator::predict(R, dim, n, dt_prev, cont, r.lf(), rt.rates());
                assert_ne!(f.v, start.v);
                assert_eq!(f.rho != start.rho, cont);
                compare_lf(&format!("integrator::predict {dim}D tau {with_tau} cont {cont}"), &f, &r);
            }
        }
    }
}

#[test]
fn integrator_advance_first_and_later_steps() {
    let mut g = Rng::new(181);
    for dim in 1..=3 {
        let n = 500;
        for first in [true, false] {
            for with_tau in [false, true] {
                for with_av in [false, true] {
                    for cont in [false, true] {
                        let start = Lf::new(&mut g, dim, n, with_tau);
                        let rt = Rt::new(&mut g, dim, n, with_tau);
                        let av = if with_av { g.vec(dim * n, -5.0, 5.0) } else { vec![] };
                        let dt_prev = g.range(1e-8, 1e-6);
                        let dt = dt_prev * g.range(0.8, 1.2);
                        let (mut f, mut r) = (start.clone(), start.clone());
                        for (b, s) in [(F, &mut f), (R, &mut r)] {
                            let mut x = std::mem::take(&mut s.x);
                            integrator::advance(b, dim, n, first, dt_prev, dt, cont, s.lf(), rt.rates(), &av, &mut x);
                            s.x = x;
                        }
                        assert_ne!(f.x, start.x);
                        compare_lf(
                            &format!(
                                "integrator::advance {dim}D first {first} tau {with_tau} \
                                 av {with_av} cont {cont}"
                            ),
                            &f,
                            &r,
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn integrator_cfl() {
    let mut g = Rng::new(191);
    for dim in 1..=3 {
        for trial in 0..20 {
            let n = 300 + trial;
            let h = g.vec(n, 0.005, 0.02);
            let c = g.vec(n, 0.1, 7000.0);
            let v = g.vec(dim * n, -500.0, 500.0);
            // at rest for some particles (no force limit), huge accelerations for others
            let scale = 10f64.powf(g.range(2.0, 12.0));
            let dv: Vec<f64> =
                (0..dim * n).map(|l| if (l / dim) % 3 == 0 { 0.0 } else { g.range(-scale, scale) }).collect();
            let cfl = g.range(0.1, 0.4);
            let f = integrator::cfl(F, dim, cfl, &h, &c, &v, &dv);
            let r = integrator::cfl(R, dim, cfl, &h, &c, &v, &dv);
            assert!(f > 0.0 && f.is_finite());
            check(&format!("integrator::cfl {dim}D trial {trial}"), tier(Module::Integrator), &[f], &[r]);
        }
    }
}
