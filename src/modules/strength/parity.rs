//! Parity of the strength module: rates over mixed materials (with and without strength), the
//! yield return through every branch (yield, tension cut-off, elastic, no strength).

use super::{Rates, Yield};
use crate::modules::param::{MatTable, NSTR, SPH_EOS_SOIL, SPH_EOS_WATER, SPH_MP_ALPHA_PHI, SPH_MP_COHESION};
use crate::modules::testkit::*;

/// Soil with strength (0, 2), water without (1, G = 0), a soil without cohesion (3).
fn strength_table() -> MatTable {
    table(
        vec![
            (SPH_EOS_SOIL, column(1450.0, &LOOSE_SAND, 0.0, Some((63.58e6, 0.25, 2.0e3)))),
            (SPH_EOS_WATER, column(1000.0, &WATER, NO_FLOOR, None)),
            (SPH_EOS_SOIL, column(2200.0, &DENSE_SAND, 0.0, Some((240e6, 0.25, 5.0e4)))),
            (SPH_EOS_SOIL, column(1840.0, &[320.0, 4.92, 0.11], 0.0, Some((20e6, 0.25, 0.0)))),
        ],
        None,
    )
}

#[test]
fn strength_rates_mixed_materials() {
    let mt = strength_table();
    for (dim, seed) in clouds(91) {
        let cl = cloud(dim, side(dim), seed);
        let pl = pairs(&cl, 2.0);
        let (_, dwdx) = kernel_values(&cl, &pl);
        let (nt, n) = (cl.nt, cl.nreal);
        assert!(cl.mat[..n].contains(&1), "no G = 0 particle");
        // plane, and in 2D also axisymmetric (1/r of every particle: the hoop strain rate)
        let rz: Vec<f64> = (0..nt).map(|i| 1.0 / cl.x[dim * i].abs().max(0.25 * cl.h[i])).collect();
        for rinv in if dim == 2 { vec![&[][..], &rz[..]] } else { vec![&[][..]] } {
            let tag = format!("strength::rates {dim}D seed {seed} rz {}", !rinv.is_empty());
            let outs = [sentinel(NSTR * nt), sentinel(3 * nt), sentinel(NSTR * n), sentinel(n)];
            let [eps, _, dtau, _] = parity(&tag, 0, ["eps", "rot", "dtau", "dedt"], outs, |b, [eps, rot, dtau, dedt]| {
                let (mass, rho, v, mat, tau) = (&cl.mass, &cl.rho, &cl.v, &cl.mat, &cl.tau);
                let pairs = &pl;
                run(Rates { dim, nreal: n, pairs, dwdx: &dwdx, mass, rho, v, mat, mt: &mt, tau, rinv, eps, rot, dtau, dedt }, b)
            });
            nonzero(&tag, &dtau);
            // G = 0: no stress rate
            for i in 0..n {
                if cl.mat[i] == 1 {
                    assert!(dtau[NSTR * i..NSTR * i + NSTR].iter().all(|v| *v == 0.0));
                }
            }
            // the hoop strain rate is v_r/r in RZ, zero in plane strain
            for i in 0..nt {
                let want = if rinv.is_empty() { 0.0 } else { cl.v[dim * i] * rinv[i] };
                assert_eq!(eps[2 + NSTR * i], if dim == 3 { eps[2 + NSTR * i] } else { want }, "{tag}: eps_zz of {i}");
            }
        }
    }
}

#[test]
fn strength_yield_return_yield_cutoff_and_no_strength() {
    let mt = strength_table();
    let mut g = Rng::new(101);
    let n = 4000;
    let mat: Vec<i32> = (0..n).map(|_| g.below(4) as i32).collect();
    let mut p = Vec::with_capacity(n);
    let mut tau = Vec::with_capacity(NSTR * n);
    for &m in &mat {
        let k = mt.par(m as usize, SPH_MP_COHESION);
        let a = mt.par(m as usize, SPH_MP_ALPHA_PHI);
        // a quarter in tension beyond the cut-off, the rest in compression
        let pi = if g.chance(0.25) { g.range(-1e6, -k / (3.0 * a.max(0.25))) } else { g.range(0.0, 2e6) };
        let y = (3.0 * a * pi + k).max(1e3);
        // deviators from well inside to well outside the yield surface
        let s = y * g.range(0.0, 2.0);
        for _ in 0..NSTR {
            tau.push(s * g.range(-0.8, 0.8));
        }
        p.push(pi);
    }
    let [tf] = parity("strength::yield", 0, ["tau"], [tau.clone()], |b, [t]| {
        run(Yield { mat: &mat, mt: &mt, p: &p, tau: t }, b)
    });
    let row = |a: &[f64], i: usize| a[NSTR * i..NSTR * i + NSTR].to_vec();
    let (mut yielded, mut cut, mut kept, mut no_g) = (0, 0, 0, 0);
    for (i, &m) in mat.iter().enumerate() {
        let (before, after) = (row(&tau, i), row(&tf, i));
        if m == 1 {
            assert_eq!(before, after, "G = 0 material changed");
            no_g += 1;
        } else if after.iter().all(|v| *v == 0.0) {
            cut += 1;
        } else if after != before {
            yielded += 1;
        } else {
            kept += 1;
        }
    }
    assert!(
        yielded > 100 && cut > 100 && kept > 100 && no_g > 100,
        "yielded {yielded}, cut off {cut}, elastic {kept}, no strength {no_g}"
    );
}
