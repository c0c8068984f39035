//! Density (thesis Table 4-1; Liu's sum_density and con_density):
//! summation ρ_i = m_i W_ii + Σ_j m_j W_ij (kg/m³), or the continuity rate
//! Dρ_i/Dt = Σ_j m_j (v_i − v_j)·∇_i W_ij (kg/m³/s, the thesis's mass form), or the volume form
//! Dρ_i/Dt = ρ_i Σ_j (m_j/ρ_j)(v_i − v_j)·∇_i W_ij, which stays consistent across large density
//! ratios (detonation products against soil). Rust twin: the pair term v_ij·∇_i W_ij is computed
//! once per pair (a parallel pass over the pairs, into a reused buffer), then each particle adds
//! m_other × term (volume form: (m/ρ)_other × term, then × ρ_i) over its pairs in ascending pair
//! order — the order of the Fortran scatter — so 0 ULP and independent of the thread count.

use super::{Backend, by_dim, nnps::PairList, par_rows};
use crate::legacy;

pub fn summation(b: Backend, pl: &PairList, w: &[f64], w0: &[f64], mass: &[f64], rho: &mut [f64]) {
    match b {
        Backend::Fortran => legacy::density_sum(&pl.i, &pl.j, w, w0, mass, rho),
        Backend::Rust => {
            let nt = mass.len();
            par_rows(&mut rho[..nt], 1, |a, r| {
                let mut s = mass[a] * w0[a];
                for e in pl.incident(a) {
                    s += mass[e.other()] * w[e.pair()];
                }
                r[0] = s;
            });
        }
    }
}

/// v_ij·∇_i W_ij of every pair into `out`, in the Fortran's order.
fn vdotw(dim: usize, pl: &PairList, dwdx: &[f64], v: &[f64], out: &mut Vec<f64>) {
    out.resize(pl.len(), 0.0);
    by_dim!(dim, 0, vdotw_d(pl, dwdx, v, out));
}

fn vdotw_d<const D: usize, const W: usize>(pl: &PairList, dwdx: &[f64], v: &[f64], out: &mut [f64]) {
    let np = pl.len();
    let (pi, pj) = (&pl.i, &pl.j);
    par_rows(&mut out[..np], 1, |k, o| {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        let mut vcc = 0.0;
        for d in 0..D {
            vcc += (v[d + D * i] - v[d + D * j]) * dwdx[d + D * k];
        }
        o[0] = vcc;
    });
}

pub fn rate(b: Backend, dim: usize, pl: &PairList, dwdx: &[f64], mass: &[f64], v: &[f64], drho: &mut [f64]) {
    match b {
        Backend::Fortran => legacy::density_rate(dim, &pl.i, &pl.j, dwdx, mass, v, drho),
        Backend::Rust => {
            let nt = mass.len();
            let mut buf = pl.scratch.lock();
            vdotw(dim, pl, dwdx, v, &mut buf.pair);
            let vcc: &[f64] = &buf.pair;
            par_rows(&mut drho[..nt], 1, |a, r| {
                let mut s = 0.0;
                for e in pl.incident(a) {
                    s += mass[e.other()] * vcc[e.pair()];
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
            let mut guard = pl.scratch.lock();
            let buf = &mut *guard;
            vdotw(dim, pl, dwdx, v, &mut buf.pair);
            buf.part.resize(nt, 0.0);
            par_rows(&mut buf.part[..nt], 1, |a, r| r[0] = mass[a] / rho[a]);
            let (vcc, vol): (&[f64], &[f64]) = (&buf.pair, &buf.part);
            par_rows(&mut drho[..nt], 1, |a, r| {
                let mut s = 0.0;
                for e in pl.incident(a) {
                    s += vol[e.other()] * vcc[e.pair()];
                }
                r[0] = rho[a] * s;
            });
        }
    }
}
