//! Penalty force between materials (thesis (4-53), (4-54); THESIS.md §6): for a pair in different
//! penalty groups, pe = (h_i + h_j)/(2 r_ij); while pe > 1,
//! PB_ij = P̄ (pe^{n1} − pe^{n2}) x_ij / r_ij², a_i += PB_ij/m_i, a_j −= PB_ij/m_j (m/s²).
//! Integer powers as products. Rust twin: gather, 0 ULP.

use super::{Backend, nnps::PairList, par_rows};
use crate::legacy::{self, MatTable};

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
            par_rows(&mut dvdt[..dim * nt], dim, |a, acc| {
                acc.iter_mut().for_each(|x| *x = 0.0);
                for &k in pl.incident(a) {
                    let k = k as usize;
                    let (i, j) = (pl.i[k] as usize, pl.j[k] as usize);
                    if mt.group[mat[i] as usize] == mt.group[mat[j] as usize] {
                        continue;
                    }
                    let mut dx = [0.0; 3];
                    let mut r2 = 0.0;
                    for d in 0..dim {
                        dx[d] = x[d + dim * i] - x[d + dim * j];
                        r2 += dx[d] * dx[d];
                    }
                    let pe = 0.5 * (h[i] + h[j]) / r2.sqrt();
                    if pe > 1.0 {
                        let f = pbar * (ipow(pe, n1) - ipow(pe, n2)) / r2;
                        for d in 0..dim {
                            if a == i {
                                acc[d] += f * dx[d] / mass[i];
                            } else {
                                acc[d] -= f * dx[d] / mass[j];
                            }
                        }
                    }
                }
            });
        }
    }
}
