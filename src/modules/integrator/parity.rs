//! Parity of the leapfrog: the rate sums (0 to 5 terms), predict and advance (first and later
//! steps, with and without τ, XSPH and continuity density; with boundary particles of both kinds),
//! the CFL step, the energy floor and the density clamp.

use super::{Advance, Cfl, Clamp, Efloor, Leapfrog, Predict, Rates, SumRates};
use crate::modules::param::NSTR;
use crate::modules::testkit::*;

#[test]
fn integrator_sum_rates() {
    let mut g = Rng::new(161);
    for dim in 1..=3 {
        let n = 400;
        let lda = dim * (n + 37); // the stacked arrays hold the mirrors too
        for nterm in [0, 1, 2, 5] {
            let acc = g.vec(lda * nterm, -1e6, 1e6);
            let grav: Vec<f64> = (0..dim).map(|d| if d + 1 == dim { -9.81 } else { 0.0 }).collect();
            let tag = format!("integrator::sum_rates {dim}D {nterm} terms");
            parity(&tag, 0, ["out"], [sentinel(dim * n)], |b, [out]| {
                run(SumRates { dim, n, lda, nterm, acc: &acc, grav: &grav, out, bnd: &[] }, b)
            });
            // boundary particles of both kinds take no gravity
            let bnd: Vec<i32> = (0..n as i32).map(|i| i % 3).collect();
            let tag = format!("integrator::sum_rates bnd {dim}D {nterm} terms");
            let [with] = parity(&tag, 0, ["out"], [sentinel(dim * n)], |b, [out]| {
                run(SumRates { dim, n, lda, nterm, acc: &acc, grav: &grav, out, bnd: &bnd }, b)
            });
            let [without] = parity(&tag, 0, ["out"], [sentinel(dim * n)], |b, [out]| {
                let zero = vec![0.0; dim];
                run(SumRates { dim, n, lda, nterm, acc: &acc, grav: &zero, out, bnd: &[] }, b)
            });
            for i in 0..n {
                let row = |a: &[f64]| a[dim * i..dim * (i + 1)].to_vec();
                assert_eq!(row(&with) == row(&without), bnd[i] != 0, "{tag}: particle {i}");
            }
        }
    }
}

const LF: [&str; 9] = ["rho", "e", "v", "tau", "rho_min", "e_min", "v_min", "tau_min", "x"];

/// The leapfrog state (the order of [`LF`]) of `n` particles.
fn state(g: &mut Rng, dim: usize, n: usize, with_tau: bool) -> [Vec<f64>; 9] {
    let nt = if with_tau { NSTR * n } else { 0 };
    [
        g.vec(n, 900.0, 2100.0),
        g.vec(n, 0.0, 1e6),
        g.vec(dim * n, -300.0, 300.0),
        g.vec(nt, -1e6, 1e6),
        g.vec(n, 900.0, 2100.0),
        g.vec(n, 0.0, 1e6),
        g.vec(dim * n, -300.0, 300.0),
        g.vec(nt, -1e6, 1e6),
        g.vec(dim * n, -0.5, 0.5),
    ]
}

/// The rates drho, de, dv, dtau.
fn rates(g: &mut Rng, dim: usize, n: usize, with_tau: bool) -> [Vec<f64>; 4] {
    [
        g.vec(n, -1e7, 1e7),
        g.vec(n, -1e10, 1e10),
        g.vec(dim * n, -1e7, 1e7),
        g.vec(if with_tau { NSTR * n } else { 0 }, -1e12, 1e12),
    ]
}

/// Splits the state into the leapfrog's variables and x.
fn split(s: &mut [Vec<f64>; 9]) -> (Leapfrog<'_>, &mut [f64]) {
    let [rho, e, v, tau, rho_min, e_min, v_min, tau_min, x] = s;
    (Leapfrog { rho, e, v, tau, rho_min, e_min, v_min, tau_min }, x)
}

#[test]
fn integrator_predict() {
    let mut g = Rng::new(171);
    for dim in 1..=3 {
        let n = 500;
        for with_tau in [false, true] {
            for cont in [false, true] {
                let start = state(&mut g, dim, n, with_tau);
                let rt = rates(&mut g, dim, n, with_tau);
                let dt_prev = g.range(1e-8, 1e-6);
                let tag = format!("integrator::predict {dim}D tau {with_tau} cont {cont}");
                let f = parity(&tag, 0, LF, start.clone(), |b, s| {
                    let (lf, _) = split(s);
                    let rates = Rates { drho: &rt[0], de: &rt[1], dv: &rt[2], dtau: &rt[3] };
                    run(Predict { dim, n, dt_prev, cont, lf, rates, bnd: &[] }, b)
                });
                assert_ne!(f[2], start[2]);
                assert_eq!(f[0] != start[0], cont);
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
                        let start = state(&mut g, dim, n, with_tau);
                        let rt = rates(&mut g, dim, n, with_tau);
                        let av = if with_av { g.vec(dim * n, -5.0, 5.0) } else { vec![] };
                        let dt_prev = g.range(1e-8, 1e-6);
                        let dt = dt_prev * g.range(0.8, 1.2);
                        let tag =
                            format!("integrator::advance {dim}D first {first} tau {with_tau} av {with_av} cont {cont}");
                        let f = parity(&tag, 0, LF, start.clone(), |b, s| {
                            let (lf, x) = split(s);
                            let rates = Rates { drho: &rt[0], de: &rt[1], dv: &rt[2], dtau: &rt[3] };
                            run(Advance { dim, n, first, dt_prev, dt, cont, lf, rates, av: &av, x, bnd: &[] }, b)
                        });
                        assert_ne!(f[8], start[8]);
                    }
                }
            }
        }
    }
}

#[test]
fn integrator_boundary_particles() {
    let mut g = Rng::new(197);
    for dim in 1..=3 {
        // more than one block of the Rust twin; ordinary, integrated and held particles mixed
        let n = 2000 + dim;
        let bnd: Vec<i32> = (0..n).map(|i| [0, 1, 2, 0, 2][(i * 7 + i / 3) % 5]).collect();
        for first in [true, false] {
            for with_tau in [false, true] {
                for cont in [false, true] {
                    let start = state(&mut g, dim, n, with_tau);
                    let rt = rates(&mut g, dim, n, with_tau);
                    let av = g.vec(dim * n, -5.0, 5.0);
                    let dt_prev = g.range(1e-8, 1e-6);
                    let dt = dt_prev * g.range(0.8, 1.2);
                    let tag = format!("integrator::predict bnd {dim}D tau {with_tau} cont {cont}");
                    let pre = parity(&tag, 0, LF, start.clone(), |b, s| {
                        let (lf, _) = split(s);
                        let rates = Rates { drho: &rt[0], de: &rt[1], dv: &rt[2], dtau: &rt[3] };
                        run(Predict { dim, n, dt_prev, cont, lf, rates, bnd: &bnd }, b)
                    });
                    let tag = format!("integrator::advance bnd {dim}D first {first} tau {with_tau} cont {cont}");
                    let f = parity(&tag, 0, LF, pre.clone(), |b, s| {
                        let (lf, x) = split(s);
                        let rates = Rates { drho: &rt[0], de: &rt[1], dv: &rt[2], dtau: &rt[3] };
                        run(Advance { dim, n, first, dt_prev, dt, cont, lf, rates, av: &av, x, bnd: &bnd }, b)
                    });
                    // per particle: (field, values per particle) of the leapfrog variables present
                    let mut lfv = vec![(1, 1), (2, dim)];
                    if cont {
                        lfv.push((0, 1));
                    }
                    if with_tau {
                        lfv.push((3, NSTR));
                    }
                    for i in 0..n {
                        let xs = |a: &[f64]| a[dim * i..dim * (i + 1)].to_vec();
                        assert_eq!(xs(&f[8]) == xs(&start[8]), bnd[i] != 0, "{tag}: x of particle {i} ({})", bnd[i]);
                        for &(k, w) in &lfv {
                            let (a0, a1) = (&start[k][w * i..w * (i + 1)], &f[k][w * i..w * (i + 1)]);
                            assert_eq!(a0 == a1, bnd[i] == 2, "{tag}: {} of particle {i} ({})", LF[k], bnd[i]);
                        }
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
            // without and with the viscous signal speed (largest |μ| per particle, m/s)
            let mu = g.vec(n, 0.0, 3000.0);
            // three materials, the first inviscid; η large enough in some trials to set the step
            let eta = [0.0, 10f64.powf(g.range(-4.0, 2.0)), 10f64.powf(g.range(-4.0, 2.0))];
            let mat: Vec<i32> = (0..n).map(|i| (i % 3) as i32).collect();
            let rho = g.vec(n, 1.0, 3000.0);
            let mut steps = Vec::new();
            for (kv, mumax, eta) in [(0.0, &[][..], &[][..]), (12.0, &mu[..], &[][..]), (12.0, &mu[..], &eta[..])] {
                let tag = format!("integrator::cfl {dim}D trial {trial} kv {kv} eta {}", eta.len());
                let [f] = parity(&tag, 0, ["dt"], [sentinel(1)], |b, [dt]| {
                    let (mat, rho) = (&mat[..], &rho[..]);
                    run(Cfl { dim, cfl, h: &h, c: &c, v: &v, dv: &dv, kv, mumax, eta, mat, rho, dt: &mut dt[0] }, b)
                });
                assert!(f[0] > 0.0 && f[0].is_finite());
                steps.push(f[0]);
            }
            assert!(steps[1] <= steps[0], "the viscous signal speed cannot lengthen the step");
            // the diffusion limit: never longer, and exactly the smallest ρh²/(8η) where that binds
            let tv = (0..n)
                .filter(|&i| eta[mat[i] as usize] > 0.0)
                .map(|i| 0.125 * rho[i] * h[i] * h[i] / eta[mat[i] as usize])
                .fold(f64::MAX, f64::min);
            assert_eq!(steps[2], steps[1].min(tv), "{dim}D trial {trial}");
        }
    }
}

#[test]
fn integrator_efloor() {
    let mut g = Rng::new(211);
    for trial in 0..10 {
        let n = 500 + trial;
        let mass = g.vec(n, 0.1, 3.0);
        // a third of the energies negative
        let e: Vec<f64> = (0..n).map(|i| if i % 3 == 0 { -g.range(1e-3, 1e5) } else { g.range(0.0, 1e6) }).collect();
        let tag = format!("integrator::efloor trial {trial}");
        let [ef, af] = parity(&tag, 0, ["e", "added"], [e.clone(), sentinel(1)], |b, [ee, added]| {
            run(Efloor { mass: &mass, e: ee, added: &mut added[0] }, b)
        });
        let want: f64 = e.iter().zip(&mass).filter(|(x, _)| **x < 0.0).map(|(x, m)| -m * x).sum();
        assert!((af[0] - want).abs() <= 1e-12 * want, "energy added {} against {want}", af[0]);
        assert!(ef.iter().all(|x| *x >= 0.0));
        for i in 0..n {
            if e[i] >= 0.0 {
                assert_eq!(ef[i], e[i], "a non-negative energy is left as it was");
            }
        }
    }
}

#[test]
fn integrator_clamp() {
    let mut g = Rng::new(223);
    for (trial, (lo, hi)) in [(990.0, 1015.0), (1.5, 2.5), (1000.0, 1000.5)].into_iter().enumerate() {
        let n = 600 + trial;
        // densities from 2 % below lo to 2 % above hi, and the bounds themselves
        let mut rho = g.vec(n, 0.98 * lo, 1.02 * hi);
        rho[0] = lo;
        rho[1] = hi;
        let tag = format!("integrator::clamp [{lo}, {hi}]");
        let [rf] = parity(&tag, 0, ["rho"], [rho.clone()], |b, [r]| run(Clamp { lo, hi, rho: r }, b));
        let (mut below, mut above, mut inside) = (0, 0, 0);
        for (i, (&before, &after)) in rho.iter().zip(&rf).enumerate() {
            if before < lo {
                below += 1;
                assert_eq!(after, lo, "particle {i}: {before} below lo");
            } else if before > hi {
                above += 1;
                assert_eq!(after, hi, "particle {i}: {before} above hi");
            } else {
                inside += 1;
                assert_eq!(after, before, "particle {i}: {before} within the bounds");
            }
        }
        assert!(below > 0 && above > 0 && inside > 0, "{tag}: {below} below, {above} above, {inside} inside");
    }
}
