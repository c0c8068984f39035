//! Parity of the EOS: every material kind, every branch (floors, tension and compression of water,
//! soil and Tait water, μ = 0), with and without a burn array; the compaction kind with and
//! without its history, on its loading curve and its unloading line; and the compaction path.

use super::Eval;
use crate::modules::param::row::{CMP_C, CMP_CRHO, CMP_N, CMP_P, CMP_RHO, CMP_RMAX0};
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
        // the book's artificial water of Morris's form, c = 0.01 m/s (single precision), with
        // a floor
        (EosKind::Morris as u32, column(1000.0, &[0.009999999776482582], 5.0e-2, None)),
        // the dry sand of Laine & Sandvik (2001), no tension
        (EosKind::Compaction as u32, sand_column()),
    ];
    table(mats, None)
}

/// Laine & Sandvik's dry sand (the `dry_sand_loose` preset) as a material-table column.
fn sand_column() -> Vec<f64> {
    let mut c = column(1674.0, &[], 0.0, Some((76.9e6, 0.24, 0.0)));
    let rho = [1674.0, 1739.0, 1874.0, 1997.0, 2144.0, 2250.0, 2380.0, 2485.0, 2585.0, 2671.0];
    let p = [0.0, 4.577e6, 1.498e7, 2.954e7, 5.94e7, 9.886e7, 1.794e8, 2.867e8, 4.155e8, 6.505e8];
    let crho = [1674.0, 1746.0, 2086.0, 2147.0, 2300.0, 2572.0, 2598.0, 2635.0, 2641.0, 2800.0];
    let cu = [265.2, 852.1, 1721.7, 1875.5, 2264.8, 2956.1, 3112.2, 4600.0, 4634.0, 4634.0];
    c[CMP_N] = 10.0;
    c[CMP_RHO..CMP_RHO + 10].copy_from_slice(&rho);
    c[CMP_P..CMP_P + 10].copy_from_slice(&p);
    c[CMP_CRHO..CMP_CRHO + 10].copy_from_slice(&crho);
    c[CMP_C..CMP_C + 10].copy_from_slice(&cu);
    c[CMP_RMAX0] = 1674.0;
    c
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
        // Morris water: either side of its floor (p = 0.05 Pa at 500 kg/m³)
        9 => (1000.0 * g.range(0.3, 1.3), g.range(0.0, 5e4)),
        // compaction sand: below its start, along and past its tables
        10 => (g.range(1600.0, 2900.0), g.range(0.0, 2e3)),
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
            run(Eval { mt: &mt, mat: &mat, burn: b, rho_max: &mut [], rho: &rho, e: &e, p, c }, bk)
        });
        // every branch is reached: floors, tension and compression of water and soil
        let count = |m: usize, f: &dyn Fn(usize) -> bool| (0..n).filter(|&i| mat[i] as usize == m && f(i)).count();
        let mu = |i: usize| rho[i] / mt.mpar[NPAR * mat[i] as usize] - 1.0;
        assert!(count(4, &|i| pf[i] == -2.0e6) > 0, "water floor never active");
        assert!(count(5, &|i| pf[i] == 0.0) > 0, "soil floor never active");
        assert!(count(6, &|i| pf[i] < 0.0) > 0, "dense sand never in tension");
        assert!(count(8, &|i| pf[i] == -5.0e4) > 0, "Tait floor never active");
        assert!(count(9, &|i| pf[i] == 5.0e-2) > 0 && count(9, &|i| pf[i] > 5.0e-2) > 0, "Morris floor");
        for m in [3, 5, 6, 7, 8] {
            assert!(count(m, &|i| mu(i) > 0.0) > 0 && count(m, &|i| mu(i) <= 0.0) > 0);
        }
        assert!(pf.iter().chain(&cf).all(|v| v.is_finite()));
    }
}

/// The compaction kind with a history: ρ_max drawn at or above ρ (unloading) and below it
/// (loading); p, c and the updated ρ_max of both twins at 0 ULP.
#[test]
fn eos_eval_compaction_history() {
    let mt = eos_table();
    let sand = (mt.nmat() - 1) as i32;
    let mut g = Rng::new(67);
    let n = 20_000;
    let mat: Vec<i32> = (0..n).map(|k| if k % 5 == 0 { 5 } else { sand }).collect();
    let rho: Vec<f64> = (0..n).map(|k| if k % 5 == 0 { 1450.0 * g.range(0.9, 1.3) } else { g.range(1600.0, 2900.0) }).collect();
    let hist: Vec<f64> = rho.iter().map(|&r| r + g.range(-50.0, 300.0)).collect();
    let [pf, cf, hf] = parity("eos::eval compaction history", 0, ["p", "c", "rho_max"], [sentinel(n), sentinel(n), hist.clone()], |bk, o| {
        let [p, c, h] = o;
        run(Eval { mt: &mt, mat: &mat, burn: &[], rho_max: h, rho: &rho, e: &vec![0.0; n], p, c }, bk)
    });
    let sandi = |i: usize| mat[i] == sand;
    assert!((0..n).any(|i| sandi(i) && hf[i] == rho[i] && rho[i] > hist[i]), "never loading");
    assert!((0..n).any(|i| sandi(i) && hf[i] > rho[i] && pf[i] > 0.0), "never on an unloading line");
    assert!((0..n).any(|i| sandi(i) && pf[i] == 0.0), "tension cut-off never active");
    // the history of another material is left alone
    assert!((0..n).filter(|&i| !sandi(i)).all(|i| hf[i] == hist[i]));
    assert!(pf.iter().chain(&cf).all(|v| v.is_finite()));
}

/// The compaction path of Laine & Sandvik's sand, both twins: loading along the curve to
/// 1874 kg/m³ gives its tabulated 14.98 MPa; unloading by 5 kg/m³ follows the line of slope
/// c_u(1874)², c_u interpolated between 852.1 m/s at 1746 and 1721.7 m/s at 2086; reloading
/// back returns to the curve; the history keeps the largest density; far below it p = 0.
#[test]
fn compaction_loading_unloading_reloading() {
    let mut col = sand_column();
    col[crate::modules::param::row::PMIN] = -f64::MAX;
    let mt = table(vec![(EosKind::Compaction as u32, col)], None);
    let path = [1674.0, 1700.0, 1874.0, 1869.0, 1874.0, 1900.0, 1700.0];
    for bk in [crate::modules::Backend::Fortran, crate::modules::Backend::Rust] {
        let mut h = vec![1674.0];
        let mut out = vec![];
        for &r in &path {
            let (mut p, mut c) = (vec![0.0], vec![0.0]);
            run(Eval { mt: &mt, mat: &[0], burn: &[], rho_max: &mut h, rho: &[r], e: &[0.0], p: &mut p, c: &mut c }, bk);
            out.push((p[0], c[0], h[0]));
        }
        let cu = 852.1 + (1874.0 - 1746.0) / (2086.0 - 1746.0) * (1721.7 - 852.1);
        assert_eq!(out[0], (0.0, 265.2, 1674.0), "{bk:?} at rest");
        let load = 0.0 + (1700.0 - 1674.0) / (1739.0 - 1674.0) * 4.577e6;
        assert!((out[1].0 - load).abs() < 1e-6 * load, "{bk:?} loading: {:?}", out[1]);
        assert!((out[2].0 - 1.498e7).abs() < 1e-3, "{bk:?} on the curve at 1874: {:?}", out[2]);
        assert!((out[2].1 - cu).abs() < 1e-9, "{bk:?} c_u at 1874: {:?}", out[2]);
        let unload = 1.498e7 - cu * cu * 5.0;
        assert!((out[3].0 - unload).abs() < 1e-6 * 1.498e7, "{bk:?} unloading: {:?} want {unload}", out[3]);
        assert_eq!(out[3].2, 1874.0, "{bk:?} history kept on unloading");
        assert_eq!(out[4].0, out[2].0, "{bk:?} reloading returns to the curve");
        assert!(out[5].0 > out[4].0 && out[5].2 == 1900.0, "{bk:?} loading further: {:?}", out[5]);
        // far below the history the line gives tension; with no floor it is negative
        assert!(out[6].0 < 0.0 && out[6].2 == 1900.0, "{bk:?} {:?}", out[6]);
    }
}
