//! Internal force (thesis (4-33)…(4-38), sign as decided in THESIS.md §2; Liu's int_force), with
//! σ = −p δ + τ:
//! Dv_i^α/Dt = Σ_j m_j (σ_i^{αβ}/ρ_i² + σ_j^{αβ}/ρ_j²) ∂W_ij/∂x_i^β (m/s²),
//! De_i/Dt = ½ Σ_j m_j (p_i/ρ_i² + p_j/ρ_j²) v_ij·∇_i W_ij (J/kg/s).
//! The deviatoric work τ:ε̇/ρ comes from the strength module.
//!
//! Rust twin: one parallel pass over the pairs computes each pair's force term f (the Fortran's
//! expression, i and j in pair order) and energy term ½ p̄ v_ij·∇W into a reused buffer; one
//! parallel pass over the particles then adds, over each particle's pairs in ascending pair order
//! (the Fortran's scatter order), ∓ m_other f and m_other × the energy term, writing both outputs.
//! Where the Fortran subtracts m f, the buffer holds −f and the gather adds (x − m f and
//! x + m (−f) are the same IEEE operation). 0 ULP, independent of the thread count.

use super::{Backend, nnps::PairList, par_rows, par_rows2};
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
            let np = pl.len();
            let strength = !tau.is_empty();
            let wd = dim + 1;
            let mut buf = pl.scratch.lock();
            buf.pair.resize(wd * np, 0.0);
            let (pi, pj) = (&pl.i, &pl.j);
            // pair terms: t (dim values; the i end gets + m_j t, the j end − m_i t), then de
            par_rows(&mut buf.pair[..wd * np], wd, |k, t| {
                let (i, j) = (pi[k] as usize, pj[k] as usize);
                let g = &dwdx[dim * k..dim * k + dim];
                let ri2 = rho[i] * rho[i];
                let rj2 = rho[j] * rho[j];
                let pr = p[i] / ri2 + p[j] / rj2;
                let mut vd = 0.0;
                for d in 0..dim {
                    vd += (v[d + dim * i] - v[d + dim * j]) * g[d];
                }
                if !strength {
                    for d in 0..dim {
                        t[d] = -(pr * g[d]);
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
                        t[al] = f;
                    }
                }
                t[dim] = 0.5 * pr * vd;
            });
            let terms: &[f64] = &buf.pair;
            par_rows2(&mut dvdt[..dim * nt], dim, &mut dedt[..nt], 1, |a, acc, de| {
                let mut sa = [0.0f64; 3];
                let mut se = 0.0;
                for e in pl.incident(a) {
                    let t = &terms[wd * e.pair()..wd * e.pair() + wd];
                    let m = mass[e.other()];
                    let ms = if e.is_i() { m } else { -m };
                    for d in 0..dim {
                        sa[d] += ms * t[d];
                    }
                    se += m * t[dim];
                }
                acc.copy_from_slice(&sa[..dim]);
                de[0] = se;
            });
        }
    }
}
