//! The Rust twin of the penalty force: few pairs are active (different groups, pe > 1), so a
//! parallel pass over the pairs lists them (in ascending order, whatever the thread count) and the
//! forces are then scattered pair by pair in that order, exactly as the Fortran loop does. 0 ULP.

use super::{Coef, Force};
use crate::modules::ipow;

pub(super) fn force(a: &mut Force) {
    let Force { dim, pairs: pl, x, h, mass, mat, mt, coef, dvdt } = a;
    let (dim, Coef { pbar, n1, n2 }) = (*dim, *coef);
    let nt = mass.len();
    let np = pl.len();
    let (pi, pj) = (&pl.i, &pl.j);
    let pair = |k: usize| -> Option<([f64; 3], f64, f64)> {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        let (gi, gj) = (mt.group[mat[i] as usize], mt.group[mat[j] as usize]);
        if gi == gj || gi < 0 || gj < 0 {
            return None;
        }
        let mut dx = [0.0; 3];
        let mut r2 = 0.0;
        for d in 0..dim {
            dx[d] = x[d + dim * i] - x[d + dim * j];
            r2 += dx[d] * dx[d];
        }
        let pe = 0.5 * (h[i] + h[j]) / r2.sqrt();
        if pe > 1.0 { Some((dx, r2, pe)) } else { None }
    };
    let mut guard = pl.scratch.lock();
    let tasks = crate::modules::par::select_pairs(&mut guard, np, |k| pair(k).is_some());
    let out = &mut dvdt[..dim * nt];
    out.fill(0.0);
    for b in tasks {
        for &k in b {
            let k = k as usize;
            let (i, j) = (pi[k] as usize, pj[k] as usize);
            if let Some((dx, r2, pe)) = pair(k) {
                let f = pbar * (ipow(pe, n1) - ipow(pe, n2)) / r2;
                for d in 0..dim {
                    out[d + dim * i] += f * dx[d] / mass[i];
                    out[d + dim * j] -= f * dx[d] / mass[j];
                }
            }
        }
    }
}
