//! Detonation (THESIS.md §5 decision). Programmed burn: particle i lights at t_i = |x_i − x_det|/D
//! (s); its burn fraction λ_i = 1 once t ≥ t_i (width 0) or min(1, max(0, (t − t_i) D/(w h_i))).
//! The instantaneous burn needs no routine. Rust twin: same order, 0 ULP.

use super::{Backend, par_rows};
use crate::legacy::{self, MatTable, NPAR, SPH_EOS_JWL};

const DET: usize = 6; // row of D (m/s) in a JWL column of mpar (0-based)

pub fn light(b: Backend, dim: usize, x: &[f64], mat: &[i32], mt: &MatTable, xdet: &[f64], tlight: &mut [f64]) {
    match b {
        Backend::Fortran => legacy::detonation_light(dim, x, mat, mt, xdet, tlight),
        Backend::Rust => par_rows(&mut tlight[..mat.len()], 1, |i, t| {
            let m = mat[i] as usize;
            let t = &mut t[0];
            *t = 0.0;
            if mt.mtype[m] == SPH_EOS_JWL as i32 {
                let mut r2 = 0.0;
                for d in 0..dim {
                    r2 += (x[d + dim * i] - xdet[d]) * (x[d + dim * i] - xdet[d]);
                }
                *t = r2.sqrt() / mt.mpar[DET + NPAR * m];
            }
        }),
    }
}

#[allow(clippy::too_many_arguments)]
pub fn burn(b: Backend, t: f64, mat: &[i32], mt: &MatTable, tlight: &[f64], h: &[f64], width: f64, lam: &mut [f64]) {
    match b {
        Backend::Fortran => legacy::detonation_burn(t, mat, mt, tlight, h, width, lam),
        Backend::Rust => par_rows(&mut lam[..mat.len()], 1, |i, l| {
            l[0] = if width <= 0.0 {
                if t >= tlight[i] { 1.0 } else { 0.0 }
            } else {
                let d = mt.mpar[DET + NPAR * mat[i] as usize];
                let r = (t - tlight[i]) * d / (width * h[i]);
                let r = if r > 0.0 { r } else { 0.0 };
                if r < 1.0 { r } else { 1.0 }
            };
        }),
    }
}
