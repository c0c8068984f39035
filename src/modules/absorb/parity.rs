//! Parity of the absorbing walls: σ0 with and without strength, and the dampers' acceleration
//! over particles in front of, inside and behind the layer of walls in 1D, 2D and 3D, soil with
//! strength and water without.

use super::{Dashpot, Init};
use crate::modules::param::{NSTR, SPH_EOS_SOIL, SPH_EOS_WATER, Segments};
use crate::modules::testkit::*;

#[test]
fn absorb_init_with_and_without_strength() {
    let mut g = Rng::new(4301);
    let n = 500;
    let p = g.vec(n, -1e5, 5e7);
    let tau = g.vec(NSTR * n, -2e6, 2e6);
    for t in [&tau[..], &[][..]] {
        let tag = format!("absorb::init strength {}", !t.is_empty());
        let [s] = parity(&tag, 0, ["sigma0"], [sentinel(NSTR * n)], |b, [s]| run(Init { p: &p, tau: t, sigma0: s }, b));
        nonzero(&tag, &s);
    }
}

/// Walls bounding the unit cloud's box on its low sides (and, in 2D and 3D, one slanted).
fn walls(dim: usize, hi: f64) -> Segments {
    let mut s = Segments::default();
    match dim {
        1 => {
            s.seg.extend_from_slice(&[0.0, 0.0, 1.0]);
            s.seg.extend_from_slice(&[hi, hi, -1.0]);
            s.endnode = vec![1, 1];
        }
        2 => {
            s.seg.extend_from_slice(&[0.0, 0.0, hi, 0.0, 0.0, 1.0]);
            s.seg.extend_from_slice(&[0.0, hi, 0.0, 0.0, 1.0, 0.0]);
            let r = std::f64::consts::FRAC_1_SQRT_2;
            s.seg.extend_from_slice(&[hi, 0.0, 0.0, hi, -r, -r]);
            s.endnode = vec![1, 1, 1];
        }
        _ => {
            s.seg.extend_from_slice(&[0.0, 0.0, 0.0, hi, 0.0, 0.0, 0.0, hi, 0.0, 0.0, 0.0, 1.0]);
            s.seg.extend_from_slice(&[0.0, 0.0, 0.0, 0.0, hi, 0.0, 0.0, 0.0, hi, 1.0, 0.0, 0.0]);
            s.endnode = vec![15, 15];
        }
    }
    s
}

#[test]
fn absorb_dashpot_in_front_of_inside_and_behind_the_layer() {
    let mt = table(
        vec![
            (SPH_EOS_SOIL, column(1450.0, &LOOSE_SAND, 0.0, Some((63.58e6, 0.25, 2.0e3)))),
            (SPH_EOS_WATER, column(1000.0, &WATER, NO_FLOOR, None)),
            (SPH_EOS_SOIL, column(2200.0, &DENSE_SAND, 0.0, Some((240e6, 0.25, 5.0e4)))),
            (SPH_EOS_WATER, column(1000.0, &WATER, NO_FLOOR, None)),
        ],
        None,
    );
    for (dim, seed) in clouds(43) {
        let cl = cloud(dim, side(dim), seed);
        let n = cl.nreal;
        let hi = cl.dx * side(dim) as f64;
        let segs = walls(dim, hi);
        let sigma0 = Rng::new(seed).vec(NSTR * n, -1e6, 1e5);
        for layer in [2.0 * cl.dx, 3.5 * cl.dx] {
            let tag = format!("absorb::dashpot {dim}D seed {seed} layer {layer}");
            let [a] = parity(&tag, 0, ["dvdt"], [sentinel(dim * n)], |b, [dvdt]| {
                let (x, v, rho, c, mat) = (&cl.x[..dim * n], &cl.v[..dim * n], &cl.rho[..n], &cl.c[..n], &cl.mat[..n]);
                run(Dashpot { dim, x, v, rho, c, mat, mt: &mt, sigma0: &sigma0, segs: &segs, layer, dvdt }, b)
            });
            nonzero(&tag, &a);
            // the particles beyond every layer feel nothing
            let far = (0..n).filter(|&i| a[dim * i..dim * i + dim].iter().all(|&x| x == 0.0)).count();
            assert!(far > 0, "{tag}: every particle in a layer");
        }
    }
}
