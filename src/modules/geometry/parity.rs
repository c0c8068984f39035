//! Parity of the axisymmetric geometry: the ring quantities (both branches of r* = max(|r|, h/4),
//! mirrors at r < 0), the hoop acceleration of a deviatoric stress, the continuity term.

use super::{Continuity, Hoop, Ring};
use crate::modules::testkit::*;

#[test]
fn geometry_ring_hoop_continuity() {
    for seed in 0..6u64 {
        let cl = cloud(2, side(2), 131_000 + seed);
        let nt = cl.nt;
        let tag = format!("geometry 2D seed {seed}");
        let [rinv, pmass] = parity(&format!("{tag} ring"), 0, ["rinv", "pmass"], [sentinel(nt), sentinel(nt)], |b, [rinv, pmass]| {
            run(Ring { dim: 2, nreal: cl.nreal, x: &cl.x, h: &cl.h, mass: &cl.mass, rinv, pmass }, b)
        });
        nonzero(&tag, &pmass);
        // both branches of r*: particles nearer the axis than h/4, and farther
        let floored = (0..nt).filter(|&i| cl.x[2 * i].abs() < 0.25 * cl.h[i]).count();
        assert!(floored > 0 && floored < nt, "{tag}: r* = h/4 for {floored} of {nt} particles");
        // 1/r* > 0 on the particles, < 0 on the mirrors across the axis (r < 0)
        let image = |i: usize| i >= cl.nreal && cl.x[2 * i] < 0.0;
        let signed = (0..nt).all(|i| rinv[i].is_finite() && (rinv[i] < 0.0) == image(i));
        assert!(signed && rinv.iter().any(|r| *r < 0.0), "{tag}: 1/r* and its sign");
        let n = cl.nreal;
        let [acc] = parity(&format!("{tag} hoop"), 0, ["dvdt"], [sentinel(2 * n)], |b, [dvdt]| {
            run(Hoop { dim: 2, rho: &cl.rho, rinv: &rinv, tau: &cl.tau, dvdt }, b)
        });
        nonzero(&tag, &acc);
        let drho0: Vec<f64> = cl.e[..n].to_vec();
        let [drho] = parity(&format!("{tag} continuity"), 0, ["drho"], [drho0.clone()], |b, [drho]| {
            run(Continuity { dim: 2, v: &cl.v, rho: &cl.rho, rinv: &rinv, drho }, b)
        });
        assert!(drho != drho0, "{tag}: the continuity term changed nothing");
    }
}
