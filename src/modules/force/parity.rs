//! Parity of the internal force, fluid and with a deviatoric stress, 1D to 3D.

use super::{Internal, Newtonian};
use crate::modules::testkit::*;

#[test]
fn force_internal_fluid_and_with_tau() {
    for (dim, seed) in clouds(71) {
        let cl = cloud(dim, side(dim), seed);
        let pl = pairs(&cl, 2.0);
        let (_, dwdx) = kernel_values(&cl, &pl);
        // axisymmetric: 1/r* of every particle, r* = max(|x|, h/4), < 0 for a mirror at x < 0
        let rz: Vec<f64> = (0..cl.nt)
            .map(|i| {
                let ri = 1.0 / cl.x[dim * i].abs().max(0.25 * cl.h[i]);
                if cl.x[dim * i] < 0.0 { -ri } else { ri }
            })
            .collect();
        let geoms: &[bool] = if dim == 2 { &[false, true] } else { &[false] };
        for (with_tau, asym, axi) in [(false, false), (true, false), (false, true), (true, true)]
            .into_iter()
            .flat_map(|(t, a)| geoms.iter().map(move |&g| (t, a, g)))
        {
            let tau: &[f64] = if with_tau { &cl.tau } else { &[] };
            let rinv: &[f64] = if axi { &rz } else { &[] };
            for iface in [false, true] {
                let tag = format!(
                    "force::internal {dim}D seed {seed} {} {}{}{}",
                    if with_tau { "with tau" } else { "fluid" },
                    if asym { "asymmetric" } else { "symmetric" },
                    if axi { " axisymmetric" } else { "" },
                    if iface { " interface" } else { "" }
                );
                let sz = [sentinel(dim * cl.nt), sentinel(cl.nt)];
                let [acc, _] = parity(&tag, 0, ["dvdt", "dedt"], sz, |b, [dvdt, dedt]| {
                    let (mass, rho, p, v) = (&cl.mass, &cl.rho, &cl.p, &cl.v);
                    let pairs = &pl;
                    run(Internal { dim, pairs, dwdx: &dwdx, mass, rho, p, v, tau, asym, iface, rinv, dvdt, dedt }, b)
                });
                nonzero(&tag, &acc);
            }
        }
    }
}

#[test]
fn force_newtonian_viscosity() {
    for (dim, seed) in clouds(83) {
        let cl = cloud(dim, side(dim), seed);
        let pl = pairs(&cl, 2.0);
        let (_, dwdx) = kernel_values(&cl, &pl);
        // a water-like η on two of three particles, 0 (a gas) on the rest
        let eta: Vec<f64> = cl.mat.iter().map(|&m| if m % 3 == 0 { 0.0 } else { 1.0e-3 * f64::from(1 + m % 3) }).collect();
        let tag = format!("force::newtonian {dim}D seed {seed}");
        let sz = [sentinel(dim * cl.nt), sentinel(cl.nt)];
        let [acc, de] = parity(&tag, 0, ["dvdt", "dedt"], sz, |b, [dvdt, dedt]| {
            let (mass, rho, v) = (&cl.mass, &cl.rho, &cl.v);
            run(Newtonian { dim, pairs: &pl, dwdx: &dwdx, mass, rho, v, eta: &eta, dvdt, dedt }, b)
        });
        nonzero(&tag, &acc);
        nonzero(&tag, &de);
    }
}
