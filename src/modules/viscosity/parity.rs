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
        // axisymmetric: 1/r* of every particle (any positive values: r* = max(|x|, h/4))
        let rz: Vec<f64> = (0..cl.nt).map(|i| 1.0 / cl.x[dim * i].abs().max(0.25 * cl.h[i])).collect();
        let geoms: &[bool] = if dim == 2 { &[false, true] } else { &[false] };
        for ((alpha, beta, etq), axi) in [(1.0, 10.0, 0.1), (1.0, 1.0, 0.1), (0.5, 0.0, 0.05)]
            .into_iter()
            .flat_map(|c| geoms.iter().map(move |&g| (c, g)))
        {
            let coef = Coef { alpha, beta, etq };
            let rinv: &[f64] = if axi { &rz } else { &[] };
            let tag = format!("viscosity::monaghan {dim}D seed {seed} {coef:?}{}", if axi { " axisymmetric" } else { "" });
            let outs = [sentinel(dim * cl.nt), sentinel(cl.nt), sentinel(cl.nt)];
            let [acc, _, mu] = parity(&tag, 0, ["dvdt", "dedt", "mumax"], outs, |b, [dvdt, dedt, mumax]| {
                let (x, v, h, rho, c, mass) = (&cl.x, &cl.v, &cl.h, &cl.rho, &cl.c, &cl.mass);
                run(Monaghan { dim, pairs: &pl, dwdx: &dwdx, x, v, h, rho, c, mass, coef, rinv, dvdt, dedt, mumax }, b)
            });
            nonzero(&tag, &acc);
            nonzero(&tag, &mu);
            assert!(mu.iter().all(|&m| m >= 0.0), "{tag}: mumax is a magnitude");
        }
    }
}
