//! The Rust twin of the density: the pair term v_ij·∇_i W_ij is computed once per pair (a parallel
//! pass over the pairs, into a reused buffer), then each particle adds m_other × term (volume
//! form: (m/ρ)_other × term, then × ρ_i) over its pairs in ascending pair order — the order of the
//! Fortran scatter — so 0 ULP and independent of the thread count.

use crate::modules::grow;
use super::{Rate, Summation};
use crate::modules::nnps::PairList;
use crate::modules::{by_dim, par_rows};

pub(super) fn summation(a: &mut Summation) {
    let Summation { pairs: pl, w, w0, mass, number, rho } = a;
    let nt = mass.len();
    if *number {
        par_rows(&mut rho[..nt], 1, |i, r| {
            let mut s = w0[i];
            for e in pl.incident(i) {
                s += w[e.pair()];
            }
            r[0] = mass[i] * s;
        });
        return;
    }
    par_rows(&mut rho[..nt], 1, |i, r| {
        let mut s = mass[i] * w0[i];
        for e in pl.incident(i) {
            s += mass[e.other()] * w[e.pair()];
        }
        r[0] = s;
    });
}

/// v_ij·∇_i W_ij of every pair into `out`, in the Fortran's order.
fn vdotw(dim: usize, pl: &PairList, dwdx: &[f64], v: &[f64], out: &mut Vec<f64>) {
    grow(out, pl.len());
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

pub(super) fn rate(a: &mut Rate) {
    let Rate { dim, volume, pairs: pl, dwdx, mass, rho, v, drho } = a;
    let nt = mass.len();
    let mut guard = pl.scratch.lock();
    let buf = &mut *guard;
    vdotw(*dim, pl, dwdx, v, &mut buf.pair);
    let vcc: &[f64] = &buf.pair;
    if !*volume {
        par_rows(&mut drho[..nt], 1, |i, r| {
            let mut s = 0.0;
            for e in pl.incident(i) {
                s += mass[e.other()] * vcc[e.pair()];
            }
            r[0] = s;
        });
        return;
    }
    grow(&mut buf.part, nt);
    par_rows(&mut buf.part[..nt], 1, |i, r| r[0] = mass[i] / rho[i]);
    let vol: &[f64] = &buf.part;
    par_rows(&mut drho[..nt], 1, |i, r| {
        let mut s = 0.0;
        for e in pl.incident(i) {
            s += vol[e.other()] * vcc[e.pair()];
        }
        r[0] = rho[i] * s;
    });
}
