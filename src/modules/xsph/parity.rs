//! Parity of XSPH over jittered clouds with virtual particles, 1D to 3D.

use super::Average;
use crate::modules::testkit::*;

#[test]
fn xsph_average() {
    for (dim, seed) in clouds(141) {
        let cl = cloud(dim, side(dim), seed);
        let pl = pairs(&cl, 2.0);
        let (w, _) = kernel_values(&cl, &pl);
        for eps in [0.5, 0.05] {
            let tag = format!("xsph::average {dim}D seed {seed} eps {eps}");
            let [av] = parity(&tag, 0, ["av"], [sentinel(dim * cl.nt)], |b, [av]| {
                let (mass, rho, v) = (&cl.mass, &cl.rho, &cl.v);
                run(Average { dim, pairs: &pl, w: &w, mass, rho, v, eps, av }, b)
            });
            nonzero(&tag, &av);
        }
    }
}
