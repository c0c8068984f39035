//! The Rust twin of XSPH: the pair term f = (v_i − v_j)/ρ̄_ij W_ij is computed once per pair (a
//! parallel pass, stored as −f); each particle then adds ± m_other × it over its pairs in
//! ascending pair order (the Fortran's scatter order) and scales by ε. 0 ULP, independent of the
//! thread count.

use crate::modules::grow;
use super::Average;
use crate::modules::{by_dim, gather_signed, par_rows};

pub(super) fn average(a: &mut Average) {
    by_dim!(a.dim, 0, run(a))
}

fn run<const D: usize, const W: usize>(a: &mut Average) {
    let pl = a.pairs;
    let (w, rho, v) = (a.w, a.rho, a.v);
    let np = pl.len();
    let mut buf = pl.scratch.lock();
    grow(&mut buf.pair, W * np);
    let (pi, pj) = (&pl.i, &pl.j);
    par_rows(&mut buf.pair[..W * np], W, |k, t| {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        let mrho = 0.5 * (rho[i] + rho[j]);
        for d in 0..D {
            t[d] = -((v[d + D * i] - v[d + D * j]) / mrho * w[k]);
        }
    });
    gather_signed::<D, W>(pl, &buf.pair, a.mass, Some(a.eps), a.av, &mut []);
}
