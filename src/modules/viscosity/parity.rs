//! Parity of the Monaghan viscosity over jittered clouds with virtual particles, 1D to 3D, three
//! sets of coefficients.

use super::{Coef, Monaghan, Switch};
use crate::modules::testkit::*;

#[test]
fn viscosity_monaghan() {
    for (dim, seed) in clouds(81) {
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
        // the switch's α_i: any values in (0, α_max]
        let al: Vec<f64> = (0..cl.nt).map(|i| 0.1 + 0.9 * ((i * 37 % 101) as f64 / 100.0)).collect();
        let geoms: &[bool] = if dim == 2 { &[false, true] } else { &[false] };
        for (((alpha, beta, etq), axi), sw) in [(1.0, 10.0, 0.1), (1.0, 1.0, 0.1), (0.5, 0.0, 0.05)]
            .into_iter()
            .flat_map(|c| geoms.iter().map(move |&g| (c, g)))
            .flat_map(|cg| [false, true].into_iter().map(move |s| (cg, s)))
        {
            let coef = Coef { alpha, beta, etq };
            let rinv: &[f64] = if axi { &rz } else { &[] };
            let alpv: &[f64] = if sw { &al } else { &[] };
            let tag = format!(
                "viscosity::monaghan {dim}D seed {seed} {coef:?}{}{}",
                if axi { " axisymmetric" } else { "" },
                if sw { " switch" } else { "" }
            );
            let outs = [sentinel(dim * cl.nt), sentinel(cl.nt), sentinel(cl.nt)];
            let [acc, _, mu] = parity(&tag, 0, ["dvdt", "dedt", "mumax"], outs, |b, [dvdt, dedt, mumax]| {
                let (x, v, h, rho, c, mass) = (&cl.x, &cl.v, &cl.h, &cl.rho, &cl.c, &cl.mass);
                run(
                    Monaghan { dim, pairs: &pl, dwdx: &dwdx, x, v, h, rho, c, mass, coef, alpv, amax: 1.0, rinv, dvdt, dedt, mumax },
                    b,
                )
            });
            nonzero(&tag, &acc);
            nonzero(&tag, &mu);
            assert!(mu.iter().all(|&m| m >= 0.0), "{tag}: mumax is a magnitude");
        }
    }
}

#[test]
fn viscosity_switch() {
    for (dim, seed) in clouds(83) {
        let cl = cloud(dim, side(dim), seed);
        let pl = pairs(&cl, 2.0);
        let (_, dwdx) = kernel_values(&cl, &pl);
        let al0: Vec<f64> = (0..cl.nt).map(|i| 0.1 + 0.9 * ((i * 53 % 97) as f64 / 96.0)).collect();
        for dt in [0.0, 1e-4, 1e3] {
            let tag = format!("viscosity::switch {dim}D seed {seed} dt {dt}");
            let [al, _] = parity(&tag, 0, ["alpv", "dv"], [al0.clone(), sentinel(cl.nt)], |b, [alpv, dv]| {
                let (mass, rho, v, h, c) = (&cl.mass, &cl.rho, &cl.v, &cl.h, &cl.c);
                let n = cl.nreal;
                let (amin, amax, ell) = (0.1, 1.0, 0.2);
                run(Switch { dim, n, pairs: &pl, dwdx: &dwdx, mass, rho, v, h, c, amin, amax, ell, dt, alpv, dv }, b)
            });
            // α stays within [α_min, α_max]; the mirrors' values are not touched; dt = 0 changes nothing
            let out = al.iter().find(|&&a| !(0.1 - 1e-12..=1.0 + 1e-12).contains(&a));
            assert!(out.is_none(), "{tag}: alpha {out:?} out of [0.1, 1] (beyond round-off)");
            assert_eq!(al[cl.nreal..], al0[cl.nreal..], "{tag}: the mirrors' alpha changed");
            if dt == 0.0 {
                assert_eq!(al, al0, "{tag}");
            } else {
                assert!(al[..cl.nreal] != al0[..cl.nreal], "{tag}: nothing changed");
            }
        }
    }
}
