//! Monaghan artificial viscosity (thesis (4-47), (4-48); Liu's art_visc), for approaching pairs:
//! μ_ij = h_ij v_ij·x_ij/(|x_ij|² + φ²), φ = etq h_ij; Π_ij = (β μ_ij − α c̄_ij) μ_ij / ρ̄_ij;
//! Dv_i/Dt −= Σ_j m_j Π_ij ∇_i W_ij (m/s²); De_i/Dt += ½ Σ_j m_j Π_ij v_ij·∇_i W_ij (J/kg/s).
//! Rust twin: gather, 0 ULP.

use super::{Backend, nnps::PairList, par_rows};
use crate::legacy;

/// Π_ij of pair k (0 for receding pairs) and v_ij·∇W.
#[inline]
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
            let nt = mass.len();
            par_rows(&mut dedt[..nt], 1, |a, out| {
                let mut de = 0.0;
                for &k in pl.incident(a) {
                    let k = k as usize;
                    let (i, j) = (pl.i[k] as usize, pl.j[k] as usize);
                    if let Some((piv, vd)) = pair_pi(dim, i, j, &dwdx[dim * k..dim * k + dim], x, v, h, rho, c, coef) {
                        let other = if a == i { j } else { i };
                        de += mass[other] * (0.5 * piv * vd);
                    }
                }
                out[0] = de;
            });
            par_rows(&mut dvdt[..dim * nt], dim, |a, acc| {
                acc.iter_mut().for_each(|x| *x = 0.0);
                for &k in pl.incident(a) {
                    let k = k as usize;
                    let (i, j) = (pl.i[k] as usize, pl.j[k] as usize);
                    let g = &dwdx[dim * k..dim * k + dim];
                    if let Some((piv, _)) = pair_pi(dim, i, j, g, x, v, h, rho, c, coef) {
                        for d in 0..dim {
                            let f = piv * g[d];
                            if a == i {
                                acc[d] -= mass[j] * f;
                            } else {
                                acc[d] += mass[i] * f;
                            }
                        }
                    }
                }
            });
        }
    }
}
