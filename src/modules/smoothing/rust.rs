//! The Rust twin of the smoothing module: same operations in the same order, elementwise.

use super::{Advance, FromDensity, Rate};
use crate::modules::par_rows;

pub(super) fn from_density(a: &mut FromDensity) {
    let FromDensity { dim, rho, h0, rho0, rinv, h } = a;
    let dim = *dim;
    par_rows(h, 1, |i, hi| {
        if let Some(ri) = rinv.get(i) {
            // axisymmetric: η0 = ρ0 r0 in rho0, h follows the spacing in the r-z plane
            hi[0] = h0[i] * (rho0[i] * ri / rho[i]).sqrt();
            return;
        }
        hi[0] = match dim {
            1 => h0[i] * (rho0[i] / rho[i]),
            2 => h0[i] * (rho0[i] / rho[i]).sqrt(),
            _ => h0[i] * (rho0[i] / rho[i]).powf(1.0 / 3.0),
        }
    });
}

pub(super) fn rate(a: &mut Rate) {
    let Rate { dim, rho, h, drho, dhdt } = a;
    let d = *dim as f64;
    par_rows(dhdt, 1, |i, o| o[0] = -(h[i] / (rho[i] * d)) * drho[i]);
}

pub(super) fn advance(a: &mut Advance) {
    let Advance { dt, theta, dhdt, h } = a;
    let (dt, theta) = (*dt, *theta);
    let n = dhdt.len();
    par_rows(&mut h[..n], 1, |i, hi| hi[0] += theta * dt * dhdt[i]);
}
