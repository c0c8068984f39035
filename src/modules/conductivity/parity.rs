//! Parity of Price's artificial conductivity over jittered clouds with virtual particles, 1D to
//! 3D, both signal speeds, two coefficients; the pair terms cancel in Σ m_i De_i/Dt, and a pair
//! of coincident particles exchanges nothing. The artificial heat (Noh) over the same clouds,
//! with compressing and expanding particles both present, and the book's constants in single
//! precision.

use super::{HeatCoef, Noh, Price};
use crate::modules::nnps::PairList;
use crate::modules::testkit::*;

#[test]
fn conductivity_price() {
    for (dim, seed) in clouds(241) {
        let cl = cloud(dim, side(dim), seed);
        let pl = pairs(&cl, 2.0);
        let (_, dwdx) = kernel_values(&cl, &pl);
        // axisymmetric: 1/r* of every particle (r* = max(|x|, h/4)) and the ring masses 2π r* μ
        let rz: Vec<f64> = (0..cl.nt).map(|i| 1.0 / cl.x[dim * i].abs().max(0.25 * cl.h[i])).collect();
        let geoms: &[bool] = if dim == 2 { &[false, true] } else { &[false] };
        for ((alpha, signal), axi) in
            [(1.0, 0), (1.0, 1), (0.3, 1)].into_iter().flat_map(|c| geoms.iter().map(move |&g| (c, g)))
        {
            let rinv: &[f64] = if axi { &rz } else { &[] };
            let tag = format!(
                "conductivity::price {dim}D seed {seed} alpha {alpha} signal {signal}{}",
                if axi { " axisymmetric" } else { "" }
            );
            let [de] = parity(&tag, 0, ["dedt"], [sentinel(cl.nt)], |b, [dedt]| {
                let (x, v, rho, p, e, mass) = (&cl.x, &cl.v, &cl.rho, &cl.p, &cl.e, &cl.mass);
                run(Price { dim, pairs: &pl, dwdx: &dwdx, x, v, rho, p, e, mass, alpha, signal, rinv, dedt }, b)
            });
            nonzero(&tag, &de);
            // energy is exchanged, not made: Σ M_i De_i/Dt = 0 up to rounding, M_i the masses the
            // energy is carried by (RZ: the rings 2π r* μ)
            let m_of = |i: usize| if axi { 2.0 * std::f64::consts::PI / rz[i] * cl.mass[i] } else { cl.mass[i] };
            let (sum, mag) = (0..cl.nt).fold((0.0, 0.0), |(s, a), i| (s + m_of(i) * de[i], a + (m_of(i) * de[i]).abs()));
            assert!(sum.abs() <= 1e-12 * mag, "{tag}: Σ m de = {sum:e} of {mag:e}");
        }
    }
    // two coincident particles and a third: the coincident pair adds nothing, the other pair
    // carries heat from the hotter particle (e = 2) to the colder (e = 1)
    let x = [0.0, 0.0, 0.01];
    let mut pl = PairList::new(vec![0, 0, 1], vec![1, 2, 2]);
    pl.build_incidence(3);
    // ∇_i W_ij along x_ij = −0.01 m, with dW/dr < 0
    let dwdx = [0.0, 50.0, 50.0];
    let (v, rho, p, e, mass) = ([0.0; 3], [1.0; 3], [1.0, 1.0, 2.0], [2.0, 2.0, 1.0], [1e-2; 3]);
    for signal in [0, 1] {
        let v = if signal == 1 { [0.0, 0.0, -10.0] } else { v };
        let [de] = parity("conductivity::price coincident", 0, ["dedt"], [sentinel(3)], |b, [dedt]| {
            let rinv: &[f64] = &[];
            run(Price { dim: 1, pairs: &pl, dwdx: &dwdx, x: &x, v: &v, rho: &rho, p: &p, e: &e, mass: &mass, alpha: 1.0, signal, rinv, dedt }, b)
        });
        assert!(de[0] < 0.0 && de[1] < 0.0 && de[2] > 0.0, "signal {signal}: heat flows to the colder particle: {de:?}");
        assert_eq!(de[0], de[1], "signal {signal}: the coincident pair exchanges nothing");
    }
}

/// The velocity divergence Σ_j (m_j/ρ_j)(v_j − v_i)·∇_i W_ij of every particle, summed plainly
/// (only its sign is used).
fn divergence(cl: &Cloud, pl: &PairList, dwdx: &[f64]) -> Vec<f64> {
    let dim = cl.dim;
    let mut div = vec![0.0; cl.nt];
    for k in 0..pl.len() {
        let (i, j) = (pl.i[k] as usize, pl.j[k] as usize);
        let hv: f64 = (0..dim).map(|d| (cl.v[d + dim * j] - cl.v[d + dim * i]) * dwdx[d + dim * k]).sum();
        div[i] += cl.mass[j] * hv / cl.rho[j];
        div[j] += cl.mass[i] * hv / cl.rho[i];
    }
    div
}

#[test]
fn conductivity_noh() {
    let book = HeatCoef { g1: 0.1f32 as f64, g2: 1.0, phi2: 0.01f32 as f64 };
    for (dim, seed) in clouds(243) {
        let cl = cloud(dim, side(dim), seed);
        let pl = pairs(&cl, 2.0);
        let (_, dwdx) = kernel_values(&cl, &pl);
        let div = divergence(&cl, &pl, &dwdx);
        assert!(div.iter().any(|&d| d < 0.0) && div.iter().any(|&d| d > 0.0), "{dim}D seed {seed}: both signs of div v");
        for coef in [
            HeatCoef { g1: 0.1, g2: 1.0, phi2: HeatCoef::PHI2 },
            HeatCoef { g1: 0.0, g2: 1.0, phi2: HeatCoef::PHI2 },
            HeatCoef { g1: 0.5, g2: 0.0, phi2: HeatCoef::PHI2 },
            book,
        ] {
            let tag = format!("conductivity::noh {dim}D seed {seed} {coef:?}");
            let [de] = parity(&tag, 0, ["dedt"], [sentinel(cl.nt)], |b, [dedt]| {
                let (x, v, h, rho, c, e, mass) = (&cl.x, &cl.v, &cl.h, &cl.rho, &cl.c, &cl.e, &cl.mass);
                run(Noh { dim, pairs: &pl, dwdx: &dwdx, x, v, h, rho, c, e, mass, coef, dedt }, b)
            });
            nonzero(&tag, &de);
            let (sum, mag) =
                (0..cl.nt).fold((0.0, 0.0), |(s, a), i| (s + cl.mass[i] * de[i], a + (cl.mass[i] * de[i]).abs()));
            assert!(sum.abs() <= 1e-12 * mag, "{tag}: Σ m de = {sum:e} of {mag:e}");
        }
    }
    // two particles approaching each other: the hotter (e = 2) loses heat to the colder (e = 1),
    // through the quadratic term alone (g1 = 0) as through the linear one (g2 = 0); receding, the
    // quadratic term alone gives nothing
    let x = [0.0, 0.01];
    let mut pl = PairList::new(vec![0], vec![1]);
    pl.build_incidence(2);
    // ∇_i W_ij along x_ij = −0.01 m, with dW/dr < 0
    let dwdx = [50.0];
    let (h, rho, c, e, mass) = ([0.01; 2], [1.0; 2], [1.0; 2], [2.0, 1.0], [1e-2; 2]);
    for (g1, g2, u, flows) in [(0.0, 1.0, 10.0, true), (0.1, 0.0, 10.0, true), (0.0, 1.0, -10.0, false)] {
        let v = [u, 0.0];
        let coef = HeatCoef { g1, g2, phi2: HeatCoef::PHI2 };
        let [de] = parity("conductivity::noh pair", 0, ["dedt"], [sentinel(2)], |b, [dedt]| {
            run(Noh { dim: 1, pairs: &pl, dwdx: &dwdx, x: &x, v: &v, h: &h, rho: &rho, c: &c, e: &e, mass: &mass, coef, dedt }, b)
        });
        if flows {
            assert!(de[0] < 0.0 && de[1] > 0.0, "g1 {g1} g2 {g2} v {u}: heat flows to the colder particle: {de:?}");
        } else {
            assert!(de[0] == 0.0 && de[1] == 0.0, "g1 {g1} g2 {g2} v {u}: an expanding pair exchanges nothing: {de:?}");
        }
    }
}
