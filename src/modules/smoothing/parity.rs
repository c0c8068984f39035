//! Parity of the smoothing module: h from density and dh/dt in 1D to 3D, the update.

use super::{Advance, FromDensity, Rate};
use crate::modules::testkit::*;

#[test]
fn smoothing_from_density_rate_advance() {
    let mut g = Rng::new(131);
    let n = 3000;
    let rho0 = g.vec(n, 1000.0, 2200.0);
    let rho: Vec<f64> = rho0.iter().map(|r| r * g.range(0.3, 1.6)).collect();
    let h0 = g.vec(n, 0.005, 0.02);
    let h = g.vec(n, 0.005, 0.03);
    let drho = g.vec(n, -5e6, 5e6);
    let dhdt = g.vec(n, -20.0, 20.0);
    let rinv = g.vec(n, 1.0, 500.0);
    for dim in 1..=3 {
        parity(&format!("smoothing::from_density {dim}D"), 0, ["h"], [sentinel(n)], |b, [hh]| {
            run(FromDensity { dim, rho: &rho, h0: &h0, rho0: &rho0, rinv: &[], h: hh }, b)
        });
        if dim == 2 {
            // axisymmetric: rho0 holds ρ0 r0
            let eta0: Vec<f64> = rho0.iter().zip(&rinv).map(|(r, ri)| r / ri).collect();
            let [hr] = parity("smoothing::from_density RZ", 0, ["h"], [sentinel(n)], |b, [hh]| {
                run(FromDensity { dim, rho: &rho, h0: &h0, rho0: &eta0, rinv: &rinv, h: hh }, b)
            });
            nonzero("smoothing::from_density RZ", &hr);
        }
        parity(&format!("smoothing::rate {dim}D"), 0, ["dhdt"], [sentinel(n)], |b, [o]| {
            run(Rate { dim, rho: &rho, h: &h, drho: &drho, dhdt: o }, b)
        });
    }
    for (dt, theta) in [(1e-7, 1.0), (3.3e-6, 0.7)] {
        let [f] = parity(&format!("smoothing::advance dt {dt}"), 0, ["h"], [h.clone()], |b, [hh]| {
            run(Advance { dt, theta, dhdt: &dhdt, h: hh }, b)
        });
        assert_ne!(f, h);
    }
}
