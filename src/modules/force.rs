//! Internal force (thesis (4-33)…(4-38), sign as decided in THESIS.md §2; Liu's int_force), with
//! σ = −p δ + τ:
//! Dv_i^α/Dt = Σ_j m_j (σ_i^{αβ}/ρ_i² + σ_j^{αβ}/ρ_j²) ∂W_ij/∂x_i^β (m/s²),
//! De_i/Dt = ½ Σ_j m_j (p_i/ρ_i² + p_j/ρ_j²) v_ij·∇_i W_ij (J/kg/s).
//! The deviatoric work τ:ε̇/ρ comes from the strength module. Rust twin: gather, 0 ULP.

use super::{Backend, nnps::PairList, par_rows};
use crate::legacy::{self, NSTR};

const IV: [[usize; 3]; 3] = [[0, 3, 4], [3, 1, 5], [4, 5, 2]];

/// Fills `dvdt` (dim × ntotal) and `dedt` (ntotal). `tau` is empty for fluids.
#[allow(clippy::too_many_arguments)]
pub fn internal(
    b: Backend,
    dim: usize,
    pl: &PairList,
    dwdx: &[f64],
    mass: &[f64],
    rho: &[f64],
    p: &[f64],
    v: &[f64],
    tau: &[f64],
    dvdt: &mut [f64],
    dedt: &mut [f64],
) {
    match b {
        Backend::Fortran => legacy::force_internal(dim, &pl.i, &pl.j, dwdx, mass, rho, p, v, tau, dvdt, dedt),
        Backend::Rust => {
            let nt = mass.len();
            let strength = !tau.is_empty();
            par_rows(&mut dedt[..nt], 1, |a, de_out| {
                let mut de = 0.0;
                for &k in pl.incident(a) {
                    let k = k as usize;
                    let (i, j) = (pl.i[k] as usize, pl.j[k] as usize);
                    let pr = p[i] / (rho[i] * rho[i]) + p[j] / (rho[j] * rho[j]);
                    let mut vd = 0.0;
                    for d in 0..dim {
                        vd += (v[d + dim * i] - v[d + dim * j]) * dwdx[d + dim * k];
                    }
                    let other = if a == i { j } else { i };
                    de += mass[other] * (0.5 * pr * vd);
                }
                de_out[0] = de;
            });
            par_rows(&mut dvdt[..dim * nt], dim, |a, acc| {
                acc.iter_mut().for_each(|x| *x = 0.0);
                for &k in pl.incident(a) {
                    let k = k as usize;
                    let (i, j) = (pl.i[k] as usize, pl.j[k] as usize);
                    let g = &dwdx[dim * k..dim * k + dim];
                    let ri2 = rho[i] * rho[i];
                    let rj2 = rho[j] * rho[j];
                    if !strength {
                        let pr = p[i] / ri2 + p[j] / rj2;
                        for d in 0..dim {
                            let f = pr * g[d];
                            if a == i {
                                acc[d] -= mass[j] * f;
                            } else {
                                acc[d] += mass[i] * f;
                            }
                        }
                    } else {
                        for al in 0..dim {
                            let mut f = 0.0;
                            for be in 0..dim {
                                let q = IV[al][be];
                                let s = if al == be {
                                    (tau[q + NSTR * i] - p[i]) / ri2 + (tau[q + NSTR * j] - p[j]) / rj2
                                } else {
                                    tau[q + NSTR * i] / ri2 + tau[q + NSTR * j] / rj2
                                };
                                f += s * g[be];
                            }
                            if a == i {
                                acc[al] += mass[j] * f;
                            } else {
                                acc[al] -= mass[i] * f;
                            }
                        }
                    }
                }
            });
        }
    }
}
