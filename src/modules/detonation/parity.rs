//! Parity of the detonation: lighting times of two explosives (and water, which never lights),
//! burn fractions with and without a ramp at times from before lighting to long after, a lighting
//! front slower than D, a lighting plane, and the beta burn (burning by compression, never un-burning).

use super::{Burn, Light};
use super::ETA_CJ;
use crate::modules::param::{NPAR, SPH_EOS_JWL, SPH_EOS_WATER};
use crate::modules::testkit::*;

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
        let tag = format!("detonation::light {dim}D seed {seed}");
        let [lf] = parity(&tag, 0, ["tlight"], [sentinel(n)], |b, [tlight]| {
            run(Light { dim, x, mat: &mat, mt: &mt, xdet: &xdet, nrm: None, sf: 1.0, tlight }, b)
        });
        nonzero(&tag, &lf);
        // a lighting front at 0.95 D
        let tag = format!("detonation::light 0.95 {dim}D seed {seed}");
        let [sf] = parity(&tag, 0, ["tlight"], [sentinel(n)], |b, [tlight]| {
            run(Light { dim, x, mat: &mat, mt: &mt, xdet: &xdet, nrm: None, sf: 0.95, tlight }, b)
        });
        for i in 0..n {
            assert!(sf[i] >= lf[i], "a slower front lights no particle earlier");
        }
        // lit along a plane through the point (a unit normal not along an axis): no particle
        // lights later than from the point, and those on either side light
        let len = (0..dim).map(|d| (1.0 + d as f64).powi(2)).sum::<f64>().sqrt();
        let nrm: Vec<f64> = (0..dim).map(|d| (1.0 + d as f64) / len).collect();
        let tag = format!("detonation::light plane {dim}D seed {seed}");
        let [pl] = parity(&tag, 0, ["tlight"], [sentinel(n)], |b, [tlight]| {
            run(Light { dim, x, mat: &mat, mt: &mt, xdet: &xdet, nrm: Some(&nrm), sf: 0.95, tlight }, b)
        });
        nonzero(&tag, &pl);
        for i in 0..n {
            assert!(pl[i] <= sf[i] * (1.0 + 1e-12), "a plane lights no particle later than its point");
        }
        let tmax = lf.iter().cloned().fold(0.0, f64::max);
        let h = &cl.h[..n];
        // unlit (0), burning (0 < λ < 1, width > 0 only) and burnt (1) particles all appear
        let mut seen = [false; 3];
        // with the beta burn (η_CJ = 1.3666 for both explosives): densities from 0.9 to 1.5 times
        // ρ0 of the TNT, so that some particles burn by compression before they are lit; the
        // previous fractions random, so that some are kept
        let mut mtb = mt.clone();
        for m in [0, 2] {
            mtb.mpar[ETA_CJ + NPAR * m] = 1.3666;
        }
        let mut g = Rng::new(seed + 7);
        let rho: Vec<f64> = (0..n).map(|_| 1630.0 * g.range(0.9, 1.5)).collect();
        let prev: Vec<f64> = (0..n).map(|_| g.range(0.0, 1.0)).collect();
        let mut by_compression = 0;
        for (width, table, beta) in [(0.0, &mt, false), (1.5, &mt, false), (4.0, &mt, false), (1.5, &mtb, true)] {
            for frac in [0.0, 0.3, 0.6, 3.0] {
                let t = frac * tmax;
                let tag = format!("detonation::burn {dim}D seed {seed} width {width} beta {beta} t {t:.3e}");
                let start = if beta { prev.clone() } else { sentinel(n) };
                let [bf] = parity(&tag, 0, ["burn"], [start], |b, [burn]| {
                    run(Burn { t, mat: &mat, mt: table, tlight: &lf, h, rho: &rho, width, burn }, b)
                });
                if beta {
                    for i in (0..n).filter(|&i| mat[i] != 1) {
                        assert!(bf[i] >= prev[i], "the beta burn lowered a burn fraction");
                        if t < lf[i] && bf[i] > prev[i] {
                            by_compression += 1;
                        }
                    }
                }
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
            }
        }
        assert!(by_compression > 0, "{dim}D seed {seed}: the beta burn burnt no unlit particle");
        assert_eq!(seen, [true; 3], "{dim}D seed {seed}: unlit, burning, burnt");
    }
}
