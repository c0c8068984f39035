//! Parity of the density: summation (mass and number density), and the continuity rate in both forms, 1D to 3D.

use super::{Rate, Summation};
use crate::case::KernelKind;
use crate::modules::kernel::SelfW;
use crate::modules::testkit::*;

#[test]
fn density_summation_and_rate() {
    for (dim, seed) in clouds(51) {
        let cl = cloud(dim, side(dim), seed);
        let pl = pairs(&cl, 2.0);
        let (w, dwdx) = kernel_values(&cl, &pl);
        let mut w0 = vec![0.0; cl.nt];
        run(SelfW { dim, kind: KernelKind::Cubic, h: &cl.h, w0: &mut w0 }, F);
        for number in [false, true] {
            let tag = format!("density::summation {dim}D seed {seed} number {number}");
            parity(&tag, 0, ["rho"], [sentinel(cl.nt)], |b, [rho]| {
                run(Summation { pairs: &pl, w: &w, w0: &w0, mass: &cl.mass, number, rho }, b)
            });
        }
        for volume in [false, true] {
            let tag = format!("density::rate {dim}D seed {seed} volume {volume}");
            let [drho] = parity(&tag, 0, ["drho"], [sentinel(cl.nt)], |b, [drho]| {
                let (mass, rho, v) = (&cl.mass, &cl.rho, &cl.v);
                run(Rate { dim, volume, pairs: &pl, dwdx: &dwdx, mass, rho, v, drho }, b)
            });
            nonzero(&tag, &drho);
        }
    }
}
