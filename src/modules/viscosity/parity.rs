//! Parity of the Monaghan viscosity over jittered clouds with virtual particles, 1D to 3D, three
//! sets of coefficients.

use super::{Coef, Monaghan};
use crate::modules::testkit::*;

#[test]
fn viscosity_monaghan() {
    for (dim, seed) in clouds(81) {
        let cl = cloud(dim, side(dim), seed);
        let pl = pairs(&cl, 2.0);
        let (_, dwdx) = kernel_values(&cl, &pl);
        for (alpha, beta, etq) in [(1.0, 10.0, 0.1), (1.0, 1.0, 0.1), (0.5, 0.0, 0.05)] {
            let coef = Coef { alpha, beta, etq };
            let tag = format!("viscosity::monaghan {dim}D seed {seed} {coef:?}");
            let outs = [sentinel(dim * cl.nt), sentinel(cl.nt), sentinel(cl.nt)];
            let [acc, _, mu] = parity(&tag, 0, ["dvdt", "dedt", "mumax"], outs, |b, [dvdt, dedt, mumax]| {
                let (x, v, h, rho, c, mass) = (&cl.x, &cl.v, &cl.h, &cl.rho, &cl.c, &cl.mass);
                run(Monaghan { dim, pairs: &pl, dwdx: &dwdx, x, v, h, rho, c, mass, coef, dvdt, dedt, mumax }, b)
            });
            nonzero(&tag, &acc);
            nonzero(&tag, &mu);
            assert!(mu.iter().all(|&m| m >= 0.0), "{tag}: mumax is a magnitude");
        }
    }
}
