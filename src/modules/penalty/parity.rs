//! Parity of the penalty force: five materials in three groups (two share one) and one exempt,
//! 1D to 3D.

use super::{Coef, Force};
use crate::modules::param::{SPH_EOS_JWL, SPH_EOS_SOIL, SPH_EOS_WATER};
use crate::modules::testkit::*;

#[test]
fn penalty_force_multiple_groups() {
    // five materials in three groups: 1 and 2 share one (no force between them); 4 is exempt
    let mt = table(
        vec![
            (SPH_EOS_JWL, column(1630.0, &TNT, NO_FLOOR, None)),
            (SPH_EOS_WATER, column(1000.0, &WATER, NO_FLOOR, None)),
            (SPH_EOS_WATER, column(1000.0, &WATER, -1e5, None)),
            (SPH_EOS_SOIL, column(1450.0, &LOOSE_SAND, 0.0, Some((63.58e6, 0.25, 2e3)))),
            (SPH_EOS_WATER, column(1000.0, &WATER, NO_FLOOR, None)),
        ],
        Some(vec![0, 1, 1, 2, -1]),
    );
    for (dim, seed) in clouds(111) {
        let mut cl = cloud(dim, side(dim), seed);
        // every fifth particle of the exempt material
        cl.mat.iter_mut().step_by(5).for_each(|m| *m = 4);
        let pl = pairs(&cl, 2.0);
        // an exempt particle close enough to another material's to be pushed (pe > 1) if it were not
        let close = (0..pl.len()).any(|k| {
            let (i, j) = (pl.i[k] as usize, pl.j[k] as usize);
            let r2: f64 = (0..dim).map(|d| (cl.x[d + dim * i] - cl.x[d + dim * j]).powi(2)).sum();
            cl.mat[i] != cl.mat[j] && (cl.mat[i] == 4 || cl.mat[j] == 4) && 0.5 * (cl.h[i] + cl.h[j]) > r2.sqrt()
        });
        assert!(close, "no exempt pair within reach");
        let same = (0..pl.len())
            .filter(|&k| {
                let (a, b) = (cl.mat[pl.i[k] as usize], cl.mat[pl.j[k] as usize]);
                a != b && mt.group[a as usize] == mt.group[b as usize]
            })
            .count();
        assert!(same > 0, "no pair of different materials in one group");
        for (pbar, n1, n2) in [(1e5, 12, 6), (3e4, 4, 2)] {
            let coef = Coef { pbar, n1, n2 };
            let tag = format!("penalty::force {dim}D seed {seed} n1 {n1} n2 {n2}");
            let [acc] = parity(&tag, 0, ["dvdt"], [sentinel(dim * cl.nt)], |b, [dvdt]| {
                let (x, h, mass, mat) = (&cl.x, &cl.h, &cl.mass, &cl.mat);
                run(Force { dim, pairs: &pl, x, h, mass, mat, mt: &mt, coef, dvdt }, b)
            });
            nonzero(&tag, &acc);
        }
    }
}
