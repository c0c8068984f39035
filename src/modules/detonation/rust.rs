//! The Rust twin of the detonation: same operations in the same order, elementwise.

use super::{Burn, Light};
use crate::modules::{fmax, fmin, par_rows};
use crate::modules::param::{NPAR, SPH_EOS_JWL};

use super::ETA_CJ;

/// Row of D (m/s) in a JWL column of mpar (0-based).
const DET: usize = 6;

pub(super) fn light(a: &mut Light) {
    let Light { dim, x, mat, mt, xdet, nrm, sf, tlight } = a;
    let (dim, sf, nrm) = (*dim, *sf, *nrm);
    par_rows(&mut tlight[..mat.len()], 1, |i, t| {
        let m = mat[i] as usize;
        let t = &mut t[0];
        *t = 0.0;
        if mt.mtype[m] == SPH_EOS_JWL as i32 {
            if let Some(nrm) = nrm {
                let mut s = 0.0;
                for d in 0..dim {
                    s += (x[d + dim * i] - xdet[d]) * nrm[d];
                }
                *t = s.abs() / (sf * mt.mpar[DET + NPAR * m]);
            } else {
                let mut r2 = 0.0;
                for d in 0..dim {
                    r2 += (x[d + dim * i] - xdet[d]) * (x[d + dim * i] - xdet[d]);
                }
                *t = r2.sqrt() / (sf * mt.mpar[DET + NPAR * m]);
            }
        }
    });
}

pub(super) fn burn(a: &mut Burn) {
    let Burn { t, mat, mt, tlight, h, rho, width, burn } = a;
    let (t, width) = (*t, *width);
    par_rows(&mut burn[..mat.len()], 1, |i, l| {
        let col = &mt.mpar[NPAR * mat[i] as usize..NPAR * (mat[i] as usize + 1)];
        let lp = if width <= 0.0 {
            if t >= tlight[i] { 1.0 } else { 0.0 }
        } else {
            let r = (t - tlight[i]) * col[DET] / (width * h[i]);
            fmin(1.0, fmax(0.0, r))
        };
        l[0] = if col[ETA_CJ] > 1.0 {
            // Fortran's max(burn, lam, min(1, fb)): the largest, left to right
            let fb = (1.0 - col[0] / rho[i]) / (1.0 - 1.0 / col[ETA_CJ]);
            fmax(fmax(l[0], lp), fmin(1.0, fb))
        } else {
            lp
        };
    });
}
