//! Averaged velocity (XSPH; Liu's av_vel): av_i = ε Σ_j (m_j/ρ̄_ij)(v_j − v_i) W_ij (m/s).
//! The integrator moves particles with v + av.
//!
//! Rust twin: the pair term f = (v_i − v_j)/ρ̄_ij W_ij is computed once per pair (a parallel pass,
//! stored as −f); each particle then adds ± m_other × it over its pairs in ascending pair order
//! (the Fortran's scatter order) and scales by ε. 0 ULP, independent of the thread count.

use super::{Backend, by_dim, gather_signed, nnps::PairList, par_rows};
use crate::legacy;

#[allow(clippy::too_many_arguments)]
pub fn average(
    b: Backend,
    dim: usize,
    pl: &PairList,
    w: &[f64],
    mass: &[f64],
    rho: &[f64],
    v: &[f64],
    eps: f64,
    av: &mut [f64],
) {
    match b {
        Backend::Fortran => legacy::xsph_average(dim, &pl.i, &pl.j, w, mass, rho, v, eps, av),
        Backend::Rust => by_dim!(dim, 0, rust(pl, w, mass, rho, v, eps, av)),
    }
}

fn rust<const D: usize, const W: usize>(
    pl: &PairList,
    w: &[f64],
    mass: &[f64],
    rho: &[f64],
    v: &[f64],
    eps: f64,
    av: &mut [f64],
) {
    let np = pl.len();
    let mut buf = pl.scratch.lock();
    buf.pair.resize(W * np, 0.0);
    let (pi, pj) = (&pl.i, &pl.j);
    par_rows(&mut buf.pair[..W * np], W, |k, t| {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        let mrho = 0.5 * (rho[i] + rho[j]);
        for d in 0..D {
            t[d] = -((v[d + D * i] - v[d + D * j]) / mrho * w[k]);
        }
    });
    gather_signed::<D, W>(pl, &buf.pair, mass, Some(eps), av, &mut []);
}
