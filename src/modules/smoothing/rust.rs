//! The Rust twin of the smoothing module: same operations in the same order, elementwise.

use super::{Advance, FromDensity, Rate};
use crate::modules::{fmin, par_rows};

pub(super) fn from_density(a: &mut FromDensity) {
    let FromDensity { dim, rho, h0, rho0, rinv, hmax, h } = a;
    let (dim, hmax) = (*dim, *hmax);
    par_rows(h, 1, |i, hi| {
        let v = if let Some(ri) = rinv.get(i) {
            // axisymmetric: η0 = ρ0 r0 in rho0, h follows the spacing in the r-z plane
            h0[i] * (rho0[i] * ri / rho[i]).sqrt()
        } else {
            match dim {
                1 => h0[i] * (rho0[i] / rho[i]),
                2 => h0[i] * (rho0[i] / rho[i]).sqrt(),
                _ => h0[i] * (rho0[i] / rho[i]).powf(1.0 / 3.0),
            }
        };
        hi[0] = fmin(v, hmax);
    });
}

pub(super) fn rate(a: &mut Rate) {
    let Rate { dim, rho, h, drho, dhdt } = a;
    let d = *dim as f64;
    par_rows(dhdt, 1, |i, o| o[0] = -(h[i] / (rho[i] * d)) * drho[i]);
}

pub(super) fn advance(a: &mut Advance) {
    let Advance { dt, theta, hmax, dhdt, h } = a;
    let (dt, theta, hmax) = (*dt, *theta, *hmax);
    let n = dhdt.len();
    par_rows(&mut h[..n], 1, |i, hi| hi[0] = fmin(hi[0] + theta * dt * dhdt[i], hmax));
}
