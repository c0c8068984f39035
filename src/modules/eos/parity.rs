//! Parity of the EOS: every material kind, every branch (floors, tension and compression of water,
//! soil and Tait water, μ = 0), with and without a burn array.

use super::Eval;
use crate::modules::param::{EosKind, MatTable, NPAR, SPH_EOS_IDEAL_GAS, SPH_EOS_JWL, SPH_EOS_SOIL, SPH_EOS_WATER};
use crate::modules::testkit::*;

/// The table of the EOS tests: (mtype, column) per material.
fn eos_table() -> MatTable {
    let mats: Vec<(u32, Vec<f64>)> = vec![
        (SPH_EOS_IDEAL_GAS, column(1.0, &[1.4], NO_FLOOR, None)),
        (SPH_EOS_JWL, column(1630.0, &TNT, NO_FLOOR, None)),
        (SPH_EOS_JWL, column(1601.0, &C4, 0.0, None)),
        (SPH_EOS_WATER, column(1000.0, &WATER, NO_FLOOR, None)),
        // water with a cavitation floor
        (SPH_EOS_WATER, column(1000.0, &WATER, -2.0e6, None)),
        // loose sand with a tension cut-off at p = 0
        (SPH_EOS_SOIL, column(1450.0, &LOOSE_SAND, 0.0, Some((63.58e6, 0.25, 2.0e3)))),
        // dense sand without a floor (negative pressures come out)
        (SPH_EOS_SOIL, column(2200.0, &DENSE_SAND, NO_FLOOR, Some((240e6, 0.25, 2.0e3)))),
        // TNT with its unreacted explosive (Mie–Grüneisen, C = 2390 m/s, S = 2.05, Γ = 1,
        // e_chem = 4.29 MJ/kg): the mixture of the burn fraction
        (SPH_EOS_JWL, {
            let mut c = column(1630.0, &TNT, NO_FLOOR, None);
            c[11..15].copy_from_slice(&[2390.0, 2.05, 1.0, 4.29e6]);
            c
        }),
        // Tait water (Liu & Liu's artificial water: B = 1.013e5 Pa, γ = 7, c = 1480 m/s), with
        // a cavitation floor
        (EosKind::Tait as u32, column(1000.0, &[1.013e5, 7.0, 1480.0], -5.0e4, None)),
    ];
    table(mats, None)
}

/// Per material of [`eos_table`]: ρ and e drawn in the physical range of its EOS.
fn eos_state(g: &mut Rng, m: usize) -> (f64, f64) {
    match m {
        // ideal gas: the shock tube's range and beyond
        0 => (g.range(0.05, 5.0), g.range(0.1, 1e3)),
        // JWL products: from the charge (η = 1.3) to far expansion (η = 0.01)
        1 => (1630.0 * g.range(0.01, 1.3), g.range(1e4, 6e6)),
        2 => (1601.0 * g.range(0.01, 1.3), g.range(1e4, 6e6)),
        // water: tension (μ down to −8 %) and compression (μ up to +25 %)
        3 | 4 => (1000.0 * g.range(0.92, 1.25), g.range(0.0, 5e4)),
        // soils: tension and compression
        5 => (1450.0 * g.range(0.9, 1.35), g.range(0.0, 2e3)),
        // unreacted TNT: tension and compression, e below and above e_chem
        7 => (1630.0 * g.range(0.9, 1.4), g.range(4.0e6, 6e6)),
        // Tait water: tension below the floor and compression
        8 => (1000.0 * g.range(0.85, 1.1), g.range(0.0, 5e4)),
        _ => (2200.0 * g.range(0.9, 1.3), g.range(0.0, 2e3)),
    }
}

#[test]
fn eos_eval_every_material_with_and_without_burn() {
    let mt = eos_table();
    let mut g = Rng::new(61);
    let n = 35_000;
    let mut mat = Vec::with_capacity(n);
    let mut rho = Vec::with_capacity(n);
    let mut e = Vec::with_capacity(n);
    for k in 0..n {
        let m = k % mt.nmat();
        let (r, en) = if k < 7 * mt.nmat() && k % 2 == 0 {
            // a few exactly at the reference density (μ = 0: the tension branch)
            (mt.mpar[NPAR * m], eos_state(&mut g, m).1)
        } else {
            eos_state(&mut g, m)
        };
        mat.push(m as i32);
        rho.push(r);
        e.push(en);
    }
    let burn: Vec<f64> = (0..n)
        .map(|_| match g.below(4) {
            0 => 0.0,
            1 => 1.0,
            _ => g.unit(),
        })
        .collect();
    for (label, b) in [("no burn array", &[][..]), ("burn array", &burn[..])] {
        let [pf, cf] = parity(&format!("eos::eval {label}"), 0, ["p", "c"], [sentinel(n), sentinel(n)], |bk, o| {
            let [p, c] = o;
            run(Eval { mt: &mt, mat: &mat, burn: b, rho: &rho, e: &e, p, c }, bk)
        });
        // every branch is reached: floors, tension and compression of water and soil
        let count = |m: usize, f: &dyn Fn(usize) -> bool| (0..n).filter(|&i| mat[i] as usize == m && f(i)).count();
        let mu = |i: usize| rho[i] / mt.mpar[NPAR * mat[i] as usize] - 1.0;
        assert!(count(4, &|i| pf[i] == -2.0e6) > 0, "water floor never active");
        assert!(count(5, &|i| pf[i] == 0.0) > 0, "soil floor never active");
        assert!(count(6, &|i| pf[i] < 0.0) > 0, "dense sand never in tension");
        assert!(count(8, &|i| pf[i] == -5.0e4) > 0, "Tait floor never active");
        for m in [3, 5, 6, 7, 8] {
            assert!(count(m, &|i| mu(i) > 0.0) > 0 && count(m, &|i| mu(i) <= 0.0) > 0);
        }
        assert!(pf.iter().chain(&cf).all(|v| v.is_finite()));
    }
}
