//! Penalty force between materials (thesis (4-53), (4-54); THESIS.md §6): for a pair in different
//! penalty groups, pe = (h_i + h_j)/(2 r_ij); while pe > 1,
//! PB_ij = P̄ (pe^{n1} − pe^{n2}) x_ij / r_ij², a_i += PB_ij/m_i, a_j −= PB_ij/m_j (m/s²).
//! Integer powers as products.
//!
//! Rust twin: few pairs are active (different groups, pe > 1), so a parallel pass over the pairs
//! lists them (in ascending order, whatever the thread count) and the forces are then scattered
//! pair by pair in that order, exactly as the Fortran loop does. 0 ULP.

use super::{Backend, CHUNK, nnps::PairList, serial};
use crate::legacy::{self, MatTable};
use rayon::prelude::*;

#[inline]
fn ipow(x: f64, n: i32) -> f64 {
    let mut y = 1.0;
    for _ in 0..n {
        y *= x;
    }
    y
}

#[allow(clippy::too_many_arguments)]
pub fn force(
    b: Backend,
    dim: usize,
    pl: &PairList,
    x: &[f64],
    h: &[f64],
    mass: &[f64],
    mat: &[i32],
    mt: &MatTable,
    pbar: f64,
    n1: i32,
    n2: i32,
    dvdt: &mut [f64],
) {
    match b {
        Backend::Fortran => legacy::penalty_force(dim, &pl.i, &pl.j, x, h, mass, mat, mt, pbar, n1, n2, dvdt),
        Backend::Rust => {
            let nt = mass.len();
            let np = pl.len();
            let (pi, pj) = (&pl.i, &pl.j);
            let pair = |k: usize| -> Option<([f64; 3], f64, f64)> {
                let (i, j) = (pi[k] as usize, pj[k] as usize);
                if mt.group[mat[i] as usize] == mt.group[mat[j] as usize] {
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
            let buf = &mut *guard;
            let ntask = np.div_ceil(CHUNK);
            if buf.idx_tasks.len() < ntask {
                buf.idx_tasks.resize_with(ntask, Vec::new);
            }
            let find = |(t, b): (usize, &mut Vec<u32>)| {
                b.clear();
                b.extend((CHUNK * t..(CHUNK * t + CHUNK).min(np)).filter(|&k| pair(k).is_some()).map(|k| k as u32));
            };
            if serial() {
                buf.idx_tasks[..ntask].iter_mut().enumerate().for_each(find);
            } else {
                buf.idx_tasks[..ntask].par_iter_mut().enumerate().for_each(find);
            }
            let out = &mut dvdt[..dim * nt];
            out.fill(0.0);
            for b in &buf.idx_tasks[..ntask] {
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
    }
}
