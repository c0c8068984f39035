//! Density (thesis Table 4-1; Liu's sum_density and con_density):
//! summation ρ_i = m_i W_ii + Σ_j m_j W_ij (kg/m³), or the continuity rate
//! Dρ_i/Dt = Σ_j m_j (v_i − v_j)·∇_i W_ij (kg/m³/s, the thesis's mass form), or the volume form
//! Dρ_i/Dt = ρ_i Σ_j (m_j/ρ_j)(v_i − v_j)·∇_i W_ij, which stays consistent across large density
//! ratios (detonation products against soil). Rust twin: gather in pair order, 0 ULP.

use super::{Backend, nnps::PairList, par_rows};
use crate::legacy;

pub fn summation(b: Backend, pl: &PairList, w: &[f64], w0: &[f64], mass: &[f64], rho: &mut [f64]) {
    match b {
        Backend::Fortran => legacy::density_sum(&pl.i, &pl.j, w, w0, mass, rho),
        Backend::Rust => {
            let nt = mass.len();
            par_rows(&mut rho[..nt], 1, |a, r| {
                let mut s = mass[a] * w0[a];
                for &k in pl.incident(a) {
                    let k = k as usize;
                    let (i, j) = (pl.i[k] as usize, pl.j[k] as usize);
                    let other = if a == i { j } else { i };
                    s += mass[other] * w[k];
                }
                r[0] = s;
            });
        }
    }
}

pub fn rate(b: Backend, dim: usize, pl: &PairList, dwdx: &[f64], mass: &[f64], v: &[f64], drho: &mut [f64]) {
    match b {
        Backend::Fortran => legacy::density_rate(dim, &pl.i, &pl.j, dwdx, mass, v, drho),
        Backend::Rust => {
            let nt = mass.len();
            par_rows(&mut drho[..nt], 1, |a, r| {
                let mut s = 0.0;
                for &k in pl.incident(a) {
                    let k = k as usize;
                    let (i, j) = (pl.i[k] as usize, pl.j[k] as usize);
                    let mut vcc = 0.0;
                    for d in 0..dim {
                        vcc += (v[d + dim * i] - v[d + dim * j]) * dwdx[d + dim * k];
                    }
                    let other = if a == i { j } else { i };
                    s += mass[other] * vcc;
                }
                r[0] = s;
            });
        }
    }
}

/// The volume form ρ_i Σ_j (m_j/ρ_j) v_ij·∇_i W_ij (kg/m³/s).
#[allow(clippy::too_many_arguments)]
pub fn rate_vol(
    b: Backend,
    dim: usize,
    pl: &PairList,
    dwdx: &[f64],
    mass: &[f64],
    rho: &[f64],
    v: &[f64],
    drho: &mut [f64],
) {
    match b {
        Backend::Fortran => legacy::density_rate_vol(dim, &pl.i, &pl.j, dwdx, mass, rho, v, drho),
        Backend::Rust => {
            let nt = mass.len();
            par_rows(&mut drho[..nt], 1, |a, r| {
                let mut s = 0.0;
                for &k in pl.incident(a) {
                    let k = k as usize;
                    let (i, j) = (pl.i[k] as usize, pl.j[k] as usize);
                    let mut vcc = 0.0;
                    for d in 0..dim {
                        vcc += (v[d + dim * i] - v[d + dim * j]) * dwdx[d + dim * k];
                    }
                    let other = if a == i { j } else { i };
                    s += mass[other] / rho[other] * vcc;
                }
                r[0] = rho[a] * s;
            });
        }
    }
}
