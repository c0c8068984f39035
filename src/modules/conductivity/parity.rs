//! Parity of Price's artificial conductivity over jittered clouds with virtual particles, 1D to
//! 3D, both signal speeds, two coefficients; the pair terms cancel in Σ m_i De_i/Dt, and a pair
//! of coincident particles exchanges nothing.

use super::Price;
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
