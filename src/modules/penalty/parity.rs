//! Parity of the penalty force: four materials in three groups (two share one), 1D to 3D.

use super::{Coef, Force};
use crate::modules::param::{SPH_EOS_JWL, SPH_EOS_SOIL, SPH_EOS_WATER};
use crate::modules::testkit::*;

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
