//! Parity of the detonation: lighting times of two explosives (and water, which never lights),
//! burn fractions with and without a ramp at times from before lighting to long after.

use super::{Burn, Light};
use crate::modules::param::{SPH_EOS_JWL, SPH_EOS_WATER};
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
            run(Light { dim, x, mat: &mat, mt: &mt, xdet: &xdet, tlight }, b)
        });
        nonzero(&tag, &lf);
        let tmax = lf.iter().cloned().fold(0.0, f64::max);
        let h = &cl.h[..n];
        // unlit (0), burning (0 < λ < 1, width > 0 only) and burnt (1) particles all appear
        let mut seen = [false; 3];
        for width in [0.0, 1.5, 4.0] {
            for frac in [0.0, 0.3, 0.6, 3.0] {
                let t = frac * tmax;
                let tag = format!("detonation::burn {dim}D seed {seed} width {width} t {t:.3e}");
                let [bf] = parity(&tag, 0, ["burn"], [sentinel(n)], |b, [burn]| {
                    run(Burn { t, mat: &mat, mt: &mt, tlight: &lf, h, width, burn }, b)
                });
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
        assert_eq!(seen, [true; 3], "{dim}D seed {seed}: unlit, burning, burnt");
    }
}
