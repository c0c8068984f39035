//! Monaghan artificial viscosity (thesis (4-47), (4-48); Liu's art_visc), for approaching pairs:
//! μ_ij = h_ij v_ij·x_ij/(|x_ij|² + φ²), φ = etq h_ij; Π_ij = (β μ_ij − α c̄_ij) μ_ij / ρ̄_ij;
//! Dv_i/Dt −= Σ_j m_j Π_ij ∇_i W_ij (m/s²); De_i/Dt += ½ Σ_j m_j Π_ij v_ij·∇_i W_ij (J/kg/s).
//!
//! Rust twin: one parallel pass over the pairs computes −Π_ij ∇_i W_ij and ½ Π_ij v_ij·∇_i W_ij
//! (the Fortran's expressions, i and j in pair order; zeros for receding pairs) into a reused
//! buffer; one parallel pass over the particles adds, over each particle's pairs in ascending pair
//! order (the Fortran's scatter order), ± m_other × those terms into both outputs. A receding
//! pair adds ±0, which leaves the sum unchanged: an accumulator that starts at +0 is never −0
//! under round-to-nearest, and x ± 0 = x for every other x. 0 ULP, independent of the thread
//! count.

use super::{Backend, by_dim, gather_signed, nnps::PairList, par_rows};
use crate::legacy;

/// Π_ij of pair k (0 for receding pairs) and v_ij·∇W.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn pair_pi(
    dim: usize,
    i: usize,
    j: usize,
    g: &[f64],
    x: &[f64],
    v: &[f64],
    h: &[f64],
    rho: &[f64],
    c: &[f64],
    coef: (f64, f64, f64),
) -> Option<(f64, f64)> {
    let (alpha, beta, etq) = coef;
    let mut vr = 0.0;
    let mut r2 = 0.0;
    let mut dv = [0.0; 3];
    for d in 0..dim {
        dv[d] = v[d + dim * i] - v[d + dim * j];
        let dx = x[d + dim * i] - x[d + dim * j];
        vr += dv[d] * dx;
        r2 += dx * dx;
    }
    if vr < 0.0 {
        let hij = 0.5 * (h[i] + h[j]);
        let muv = hij * vr / (r2 + (etq * hij) * (etq * hij));
        let mc = 0.5 * (c[i] + c[j]);
        let mrho = 0.5 * (rho[i] + rho[j]);
        let piv = (beta * muv - alpha * mc) * muv / mrho;
        let mut vd = 0.0;
        for d in 0..dim {
            vd += dv[d] * g[d];
        }
        Some((piv, vd))
    } else {
        None
    }
}

#[allow(clippy::too_many_arguments)]
pub fn monaghan(
    b: Backend,
    dim: usize,
    pl: &PairList,
    dwdx: &[f64],
    x: &[f64],
    v: &[f64],
    h: &[f64],
    rho: &[f64],
    c: &[f64],
    mass: &[f64],
    coef: (f64, f64, f64),
    dvdt: &mut [f64],
    dedt: &mut [f64],
) {
    match b {
        Backend::Fortran => {
            legacy::viscosity_monaghan(dim, &pl.i, &pl.j, dwdx, x, v, h, rho, c, mass, coef, dvdt, dedt)
        }
        Backend::Rust => {
            by_dim!(dim, 1, rust(pl, dwdx, x, v, h, rho, c, mass, coef, dvdt, dedt))
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn rust<const D: usize, const W: usize>(
    pl: &PairList,
    dwdx: &[f64],
    x: &[f64],
    v: &[f64],
    h: &[f64],
    rho: &[f64],
    c: &[f64],
    mass: &[f64],
    coef: (f64, f64, f64),
    dvdt: &mut [f64],
    dedt: &mut [f64],
) {
    let np = pl.len();
    let mut buf = pl.scratch.lock();
    buf.pair.resize(W * np, 0.0);
    let (pi, pj) = (&pl.i, &pl.j);
    // pair terms: −Π ∇W (the i end gets + m_j t, the j end − m_i t), then ½ Π v·∇W
    par_rows(&mut buf.pair[..W * np], W, |k, t| {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        let g = &dwdx[D * k..D * k + D];
        match pair_pi(D, i, j, g, x, v, h, rho, c, coef) {
            Some((piv, vd)) => {
                for d in 0..D {
                    t[d] = -(piv * g[d]);
                }
                t[D] = 0.5 * piv * vd;
            }
            None => {
                // (a store of known length: `fill` would call memset for three values)
                if let Ok(t) = <&mut [f64; W]>::try_from(t) {
                    *t = [0.0; W];
                }
            }
        }
    });
    gather_signed::<D, W>(pl, &buf.pair, mass, None, dvdt, dedt);
}
