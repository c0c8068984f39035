//! The Rust twin of the axisymmetric geometry: elementwise, the Fortran's expressions in its
//! order (`if (rs < rmin) rs = rmin` as a comparison, not `f64::max`), 0 ULP.

use super::{Continuity, Hoop, Ring};
use crate::modules::param::NSTR;
use crate::modules::{par_rows, par_rows2};
use std::f64::consts::PI;

pub(super) fn ring(a: &mut Ring) {
    let Ring { dim, nreal, x, h, mass, rinv, pmass } = a;
    let (dim, nreal, x, h, mass) = (*dim, *nreal, *x, *h, *mass);
    let nt = mass.len();
    par_rows2(&mut rinv[..nt], 1, &mut pmass[..nt], 1, |i, ri, pm| {
        let mut rs = x[dim * i].abs();
        let rmin = 0.25 * h[i];
        if rs < rmin {
            rs = rmin;
        }
        // a mirror across the axis (r < 0) carries the signed 1/r*
        ri[0] = if i >= nreal && x[dim * i] < 0.0 { -1.0 / rs } else { 1.0 / rs };
        pm[0] = mass[i] / (2.0 * PI * rs);
    });
}

pub(super) fn hoop(a: &mut Hoop) {
    let Hoop { dim, rho, rinv, tau, dvdt } = a;
    let (dim, rho, rinv, tau) = (*dim, *rho, *rinv, *tau);
    let n = dvdt.len() / dim;
    par_rows(&mut dvdt[..dim * n], dim, |i, acc| {
        let t = &tau[NSTR * i..NSTR * i + NSTR];
        acc[0] = (t[0] - t[2]) / rho[i] * rinv[i];
        acc[1] = t[3] / rho[i] * rinv[i];
    });
}

pub(super) fn continuity(a: &mut Continuity) {
    let Continuity { dim, v, rho, rinv, drho } = a;
    let (dim, v, rho, rinv) = (*dim, *v, *rho, *rinv);
    let n = drho.len();
    par_rows(&mut drho[..n], 1, |i, d| d[0] -= rho[i] * (v[dim * i] * rinv[i]));
}
