//! Internal force (thesis (4-33)…(4-38), sign as decided in THESIS.md §2; Liu's int_force), with
//! σ = −p δ + τ:
//! Dv_i^α/Dt = Σ_j m_j (σ_i^{αβ}/ρ_i² + σ_j^{αβ}/ρ_j²) ∂W_ij/∂x_i^β (m/s²),
//! De_i/Dt = ½ Σ_j m_j (p_i/ρ_i² + p_j/ρ_j²) v_ij·∇_i W_ij (J/kg/s).
//! The deviatoric work τ:ε̇/ρ comes from the strength module.
//!
//! Rust twin: the per-particle quotients of the Fortran's pair expression (p_i/ρ_i², and
//! (τ_i − p_i δ)/ρ_i² with strength; the same operations, so the same values) are computed once per
//! particle; one parallel pass over the pairs then forms each pair's force term f (their sums in
//! the Fortran's order, i and j in pair order) and energy term ½ p̄ v_ij·∇W into a reused buffer; one
//! parallel pass over the particles then adds, over each particle's pairs in ascending pair order
//! (the Fortran's scatter order), ∓ m_other f and m_other × the energy term, writing both outputs.
//! Where the Fortran subtracts m f, the buffer holds −f and the gather adds (x − m f and
//! x + m (−f) are the same IEEE operation). 0 ULP, independent of the thread count.

use super::{Backend, by_dim, gather_signed, nnps::PairList, par_rows};
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
        Backend::Rust => by_dim!(dim, 1, rust(pl, dwdx, mass, rho, p, v, tau, dvdt, dedt)),
    }
}

#[allow(clippy::too_many_arguments)]
fn rust<const D: usize, const W: usize>(
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
    let np = pl.len();
    let nt = mass.len();
    let strength = !tau.is_empty();
    let mut guard = pl.scratch.lock();
    let buf = &mut *guard;
    // per particle, the values the Fortran computes per pair: p/ρ², then (τ − p δ)/ρ² (D × D)
    let wp = if strength { 1 + D * D } else { 1 };
    buf.part.resize(wp * nt, 0.0);
    par_rows(&mut buf.part[..wp * nt], wp, |i, sg| {
        let ri2 = rho[i] * rho[i];
        sg[0] = p[i] / ri2;
        if strength {
            for al in 0..D {
                for be in 0..D {
                    let q = IV[al][be];
                    sg[1 + D * al + be] =
                        if al == be { (tau[q + NSTR * i] - p[i]) / ri2 } else { tau[q + NSTR * i] / ri2 };
                }
            }
        }
    });
    buf.pair.resize(W * np, 0.0);
    let sig: &[f64] = &buf.part;
    let (pi, pj) = (&pl.i, &pl.j);
    // pair terms: t (D values; the i end gets + m_j t, the j end − m_i t), then de
    par_rows(&mut buf.pair[..W * np], W, |k, t| {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        let g = &dwdx[D * k..D * k + D];
        let (si, sj) = (&sig[wp * i..wp * i + wp], &sig[wp * j..wp * j + wp]);
        let pr = si[0] + sj[0];
        let mut vd = 0.0;
        for d in 0..D {
            vd += (v[d + D * i] - v[d + D * j]) * g[d];
        }
        if !strength {
            for d in 0..D {
                t[d] = -(pr * g[d]);
            }
        } else {
            for al in 0..D {
                let mut f = 0.0;
                for be in 0..D {
                    let s = si[1 + D * al + be] + sj[1 + D * al + be];
                    f += s * g[be];
                }
                t[al] = f;
            }
        }
        t[D] = 0.5 * pr * vd;
    });
    gather_signed::<D, W>(pl, &buf.pair, mass, None, dvdt, dedt);
}
