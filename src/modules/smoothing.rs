//! Smoothing-length evolution (thesis (2-15), (2-16); Liu's h_upgrade):
//! from density h_i = h0_i (ρ0_i/ρ_i)^{1/d}; rate dh_i/dt = −(h_i/(ρ_i d)) Dρ_i/Dt (m/s), with
//! Dρ_i/Dt the continuity sum; h_i ← h_i + θ Δt dh_i/dt. Rust twin: same order; 0 ULP in 1D and
//! 2D (division, √), and in 3D (`powf(1/3)`, the same C library `pow` on both sides).

use super::{Backend, par_rows};
use crate::legacy;

pub fn from_density(b: Backend, dim: usize, rho: &[f64], h0: &[f64], rho0: &[f64], h: &mut [f64]) {
    match b {
        Backend::Fortran => legacy::smoothing_density(dim, rho, h0, rho0, h),
        Backend::Rust => par_rows(h, 1, |i, hi| {
            hi[0] = match dim {
                1 => h0[i] * (rho0[i] / rho[i]),
                2 => h0[i] * (rho0[i] / rho[i]).sqrt(),
                _ => h0[i] * (rho0[i] / rho[i]).powf(1.0 / 3.0),
            }
        }),
    }
}

pub fn rate(b: Backend, dim: usize, rho: &[f64], h: &[f64], drho: &[f64], dhdt: &mut [f64]) {
    match b {
        Backend::Fortran => legacy::smoothing_rate(dim, rho, h, drho, dhdt),
        Backend::Rust => par_rows(dhdt, 1, |i, d| {
            d[0] = -(h[i] / (rho[i] * dim as f64)) * drho[i];
        }),
    }
}

pub fn advance(b: Backend, dt: f64, theta: f64, dhdt: &[f64], h: &mut [f64]) {
    match b {
        Backend::Fortran => legacy::smoothing_advance(dt, theta, dhdt, h),
        Backend::Rust => {
            let n = dhdt.len();
            par_rows(&mut h[..n], 1, |i, hi| hi[0] += theta * dt * dhdt[i]);
        }
    }
}
