//! Parity of the neighbour search: Fortran and Rust, direct and cell, over jittered clouds with
//! virtual particles and a sparse cloud with widely varying h (every search returns the same
//! canonical list); the Rust cell search against the direct one on ties, large h, duplicates,
//! outliers and non-finite values; the Verlet candidate lists over many moving calls.

use super::{PairList, Search};
use crate::modules::Backend;
use crate::modules::testkit::{self, Cloud, F, R, check_i, cloud, clouds, run, side};

#[test]
fn nnps_direct_and_cell_fortran_vs_rust() {
    for (dim, seed) in clouds(31) {
        for kappa in [2.0, 3.0] {
            let cl = cloud(dim, side(dim), seed);
            let reference = testkit::search(F, false, &cl, kappa);
            assert!(reference.j.iter().any(|&j| j as usize >= cl.nreal));
            for cell in [false, true] {
                let f = testkit::search(F, cell, &cl, kappa);
                let r = testkit::search(R, cell, &cl, kappa);
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
    let mut g = testkit::Rng::new(41);
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
        let reference = testkit::search(F, false, &cl, 2.0);
        assert!(!reference.is_empty());
        for cell in [false, true] {
            let f = testkit::search(F, cell, &cl, 2.0);
            let r = testkit::search(R, cell, &cl, 2.0);
            let tag = format!("nnps::search sparse {} {dim}D", if cell { "cell" } else { "direct" });
            check_i(&format!("{tag} i"), &f.i, &r.i);
            check_i(&format!("{tag} j"), &f.j, &r.j);
            check_i(&format!("{tag} i (vs direct)"), &reference.i, &f.i);
            check_i(&format!("{tag} j (vs direct)"), &reference.j, &f.j);
        }
    }
}

/// xorshift64*, seeded (this file's own stream, kept so the clouds stay those the tests were
/// written for).
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
    run(Search { cell, dim, nreal, x, h, kappa, pairs: &mut pl }, b);
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
/// Ejecta: a lattice with about 4 % of its particles thrown far above it (up to 60 m over a box
/// 0.3 m wide), some of them in small groups within each other's reach: the cell grid keeps
/// its cells and lets the far ones fall into its border cells; the list is still the Fortran's
/// direct one.
#[test]
fn cell_search_with_far_ejecta_equals_direct() {
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    for dim in 2..=3 {
        let side: usize = [0, 0, 30, 10][dim];
        let n = side.pow(dim as u32);
        let mut x = Vec::new();
        for i in 0..n {
            let mut r = i;
            for _ in 0..dim {
                x.push(0.01 * (r % side) as f64);
                r /= side;
            }
        }
        let mut h = vec![0.01; n];
        let far = n / 25;
        for g in 0..far {
            // a group leader far up, and every third one with a partner 0.5 h away
            let base: Vec<f64> = (0..dim)
                .map(|d| if d == dim - 1 { 1.0 + 59.0 * rng.f() } else { 0.3 * rng.f() - 0.1 + 5.0 * (rng.f() - 0.5) })
                .collect();
            x.extend(&base);
            h.push(0.01 * (1.0 + rng.f()));
            if g % 3 == 0 {
                x.extend(base.iter().enumerate().map(|(d, &b)| if d == 0 { b + 0.005 } else { b }));
                h.push(0.01);
            }
        }
        let nt = h.len();
        let nreal = nt - 3;
        for kappa in [2.0, 3.0] {
            let want = lists(Backend::Fortran, false, dim, nreal, &x, &h, kappa);
            let far_pairs = want.iter().filter(|&&(i, _)| i as usize >= n).count();
            assert!(far_pairs >= far / 3 - 1, "{dim}D: {far_pairs} pairs among the ejecta");
            assert_eq!(lists(Backend::Rust, true, dim, nreal, &x, &h, kappa), want, "{dim}D kappa {kappa}");
        }
        // the Verlet lists (their second grid, for fast particles and the 3 virtual ones), over
        // calls in which the ejecta fly on (fast) and the lattice barely moves
        let mut pl = PairList::default();
        for call in 0..6 {
            for a in 0..nreal {
                let step = if a >= n { 0.02 } else { 0.0001 };
                x[dim * a + dim - 1] += step * rng.f();
            }
            verlet_call_matches_direct(&mut pl, dim, nreal, &x, &h, call);
        }
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
        if verlet_call_matches_direct(&mut pl, 2, nreal, &xt, &ht, call) {
            rebuilds += 1;
        } else {
            incremental += 1;
        }
    }
    assert!(incremental > 10 && rebuilds > 1, "both paths taken: {incremental} incremental, {rebuilds} rebuilds");
}


/// One call of the Rust cell search (with its Verlet candidates kept in `pl` between calls) on
/// `x`, `h`: its pairs equal the direct search's; returns whether the call rebuilt the candidates.
fn verlet_call_matches_direct(pl: &mut PairList, dim: usize, nreal: usize, x: &[f64], h: &[f64], call: usize) -> bool {
    let before = pl.scratch.get_mut().verlet.builds;
    run(Search { cell: true, dim, nreal, x, h, kappa: 2.0, pairs: pl }, R);
    let got: Vec<(i32, i32)> = pl.i.iter().copied().zip(pl.j.iter().copied()).collect();
    let want = lists(Backend::Fortran, false, dim, nreal, x, h, 2.0);
    assert_eq!(got, want, "{dim}D call {call}: kept candidates differ from the direct search");
    pl.scratch.get_mut().verlet.builds != before
}

/// The Fortran search's capacity protocol: with room for a third of the pairs it stores the
/// prefix of the canonical list and returns the full count (the wrapper then grows the lists).
#[test]
fn fortran_search_reports_overflow_count_and_keeps_the_prefix() {
    let cl = testkit::cloud(2, 18, 11);
    let want = testkit::search(F, false, &cl, 2.0);
    let cap = want.len() / 3;
    for cell in [false, true] {
        let (mut pi, mut pj) = (vec![-1i32; cap], vec![-1i32; cap]);
        let mut dummy = PairList::default();
        let a = Search { cell, dim: 2, nreal: cl.nreal, x: &cl.x, h: &cl.h, kappa: 2.0, pairs: &mut dummy };
        let np = super::ffi::search_into(&a, &mut pi, &mut pj);
        assert_eq!(np, want.len(), "cell = {cell}: the count must be the full count");
        assert_eq!(pi, want.i[..cap], "cell = {cell}: stored prefix (i)");
        assert_eq!(pj, want.j[..cap], "cell = {cell}: stored prefix (j)");
    }
}

/// As [`kept_candidates_equal_direct_over_many_calls`], in 3D (where the skin is smaller): a
/// drifting lattice with a few fast particles, growing h, and mirrors below z = 0.
#[test]
fn kept_candidates_equal_direct_over_many_calls_3d() {
    let mut rng = Rng(0x7654_3210_FEDC_BA98);
    let (side, dx) = (9usize, 0.01);
    let nreal = side * side * side;
    let mut x = Vec::new();
    let mut h = Vec::new();
    for k in 0..side {
        for j in 0..side {
            for i in 0..side {
                x.extend([(i as f64 + 0.5) * dx, (j as f64 + 0.5) * dx, (k as f64 + 0.5) * dx]);
                h.push(dx * (1.0 + 0.2 * rng.f()));
            }
        }
    }
    let mut pl = PairList::default();
    let (mut rebuilds, mut incremental) = (0, 0);
    for call in 0..60 {
        let shift = if call % 20 == 19 { dx } else { 0.0 };
        for a in 0..nreal {
            x[3 * a] += shift;
            let step = if rng.f() < 0.03 { 0.004 } else { 0.0001 };
            for d in 0..3 {
                x[3 * a + d] += step * (rng.f() - 0.5);
            }
            if rng.f() < 0.05 {
                h[a] *= 1.0 + 0.01 * rng.f();
            }
        }
        let (mut xt, mut ht) = (x.clone(), h.clone());
        for a in 0..nreal {
            if x[3 * a + 2] < 2.0 * h[a] && x[3 * a + 2] >= 0.0 {
                xt.extend([x[3 * a], x[3 * a + 1], -x[3 * a + 2]]);
                ht.push(h[a]);
            }
        }
        if verlet_call_matches_direct(&mut pl, 3, nreal, &xt, &ht, call) {
            rebuilds += 1;
        } else {
            incremental += 1;
        }
    }
    assert!(incremental > 10 && rebuilds > 1, "both paths taken: {incremental} incremental, {rebuilds} rebuilds");
}

/// The pairs touching each particle, as the gathers read them.
fn incidence_of(pl: &PairList, n: usize) -> Vec<Vec<(usize, usize, bool)>> {
    (0..n).map(|a| pl.incident(a).map(|e| (e.pair(), e.other(), e.is_i())).collect()).collect()
}

#[test]
fn incidence_lists_do_not_depend_on_the_number_of_threads() {
    // a canonical list (i ascending, i < j) and a legacy one (any order, both ends listed, with
    // ends beyond n that must not be listed; the legacy bridge refuses negative indices), each built on 1, 2 and 3 threads
    let n = 1500;
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut canon = Vec::new();
    for i in 0..n {
        for _ in 0..(rng.f() * 12.0) as usize {
            let j = i + 1 + (rng.f() * 40.0) as usize;
            if j < n {
                canon.push((i as i32, j as i32));
            }
        }
    }
    canon.sort();
    canon.dedup();
    let mut legacy: Vec<(i32, i32)> = canon.iter().map(|&(i, j)| if rng.f() < 0.5 { (j, i) } else { (i, j) }).collect();
    for k in (0..legacy.len()).rev().step_by(97) {
        legacy.swap(k, (rng.f() * k as f64) as usize);
    }
    legacy.push((n as i32 + 3, 7));
    legacy.push((5, n as i32));
    assert!(canon.len() > 4096 && legacy.len() > 4096, "too few pairs to split: {}", canon.len());
    for pairs in [&canon, &legacy] {
        let build = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let mut pl = PairList::new(pairs.iter().map(|p| p.0).collect(), pairs.iter().map(|p| p.1).collect());
                pl.build_incidence(n);
                incidence_of(&pl, n)
            })
        };
        let one = build(1);
        // every pair in range at both ends, once at each, in ascending pair order
        let listed: usize = one.iter().map(Vec::len).sum();
        let ok = |a: i32| a >= 0 && (a as usize) < n;
        assert_eq!(listed, pairs.iter().map(|p| ok(p.0) as usize + ok(p.1) as usize).sum::<usize>());
        for (a, l) in one.iter().enumerate() {
            assert!(l.windows(2).all(|w| w[0].0 < w[1].0), "particle {a}: not in pair order");
            for &(k, o, is_i) in l {
                let (i, j) = pairs[k];
                let (me, other) = if is_i { (i, j) } else { (j, i) };
                assert_eq!(me as usize, a);
                assert!(!ok(other) || other as usize == o);
            }
        }
        assert_eq!(build(2), one);
        assert_eq!(build(3), one);
    }
}
