//! The Rust twin of the absorbing walls: the Fortran's operations in its order, 0 ULP. Each
//! particle sums over the walls in order; the wall frames are computed once per call (the
//! Fortran recomputes them per particle; same values).

use super::{Dashpot, Init};
use crate::modules::param::{NPAR, NSTR, SPH_MP_SHEAR, seg_len};
use crate::modules::par_rows;

const IV: [[usize; 3]; 3] = [[0, 3, 4], [3, 1, 5], [4, 5, 2]];

pub(super) fn init(a: &mut Init) {
    let n = a.p.len();
    let tau = a.tau;
    par_rows(&mut a.sigma0[..NSTR * n], NSTR, |i, s| {
        for k in 0..NSTR {
            s[k] = if tau.is_empty() { 0.0 } else { tau[k + NSTR * i] };
        }
        for k in 0..3 {
            s[k] -= a.p[i];
        }
    });
}

/// A wall's inward normal, unit edge directions and their lengths (the Fortran's `frame`).
struct Frame {
    nrm: [f64; 3],
    t1: [f64; 3],
    el1: f64,
    t2: [f64; 3],
    el2: f64,
}

fn frame(dim: usize, sg: &[f64]) -> Frame {
    let no = seg_len(dim) - dim;
    let mut f = Frame { nrm: [0.0; 3], t1: [0.0; 3], el1: 0.0, t2: [0.0; 3], el2: 0.0 };
    f.nrm[..dim].copy_from_slice(&sg[no..no + dim]);
    if dim == 2 {
        for d in 0..2 {
            f.t1[d] = sg[2 + d] - sg[d];
            f.el1 += f.t1[d] * f.t1[d];
        }
    } else if dim == 3 {
        f.t1.copy_from_slice(&sg[3..6]);
        f.t2.copy_from_slice(&sg[6..9]);
        for d in 0..3 {
            f.el1 += f.t1[d] * f.t1[d];
            f.el2 += f.t2[d] * f.t2[d];
        }
    }
    f.el1 = f.el1.sqrt();
    f.el2 = f.el2.sqrt();
    if f.el1 > 0.0 {
        f.t1.iter_mut().for_each(|t| *t /= f.el1);
    }
    if f.el2 > 0.0 {
        f.t2.iter_mut().for_each(|t| *t /= f.el2);
    }
    f
}

pub(super) fn dashpot(a: &mut Dashpot) {
    let Dashpot { dim, x, v, rho, c, mat, mt, sigma0, segs, layer, dvdt } = a;
    let (dim, layer) = (*dim, *layer);
    let n = rho.len();
    let frames: Vec<Frame> = (0..segs.len()).map(|s| frame(dim, segs.get(dim, s))).collect();
    let shear = SPH_MP_SHEAR as usize - 1;
    par_rows(&mut dvdt[..dim * n], dim, |i, acc| {
        acc.fill(0.0);
        let mut g = mt.mpar[shear + NPAR * mat[i] as usize];
        if g < 0.0 {
            g = 0.0;
        }
        let cp = (c[i] * c[i] + 4.0 * g / (3.0 * rho[i])).sqrt();
        let cs = (g / rho[i]).sqrt();
        for (s, f) in frames.iter().enumerate() {
            let sg = segs.get(dim, s);
            let (mut dn, mut tp1, mut tp2) = (0.0, 0.0, 0.0);
            for d in 0..dim {
                let r = x[d + dim * i] - sg[d];
                dn += r * f.nrm[d];
                tp1 += r * f.t1[d];
                tp2 += r * f.t2[d];
            }
            let mut inside = dn < layer;
            if dim >= 2 {
                inside = inside && tp1 >= 0.0 && tp1 <= f.el1;
            }
            if dim == 3 {
                inside = inside && tp2 >= 0.0 && tp2 <= f.el2;
            }
            if !inside {
                continue;
            }
            if dn < 0.0 {
                dn = 0.0;
            }
            let w = 2.0 * (1.0 - dn / layer) / layer;
            let mut vn = 0.0;
            for d in 0..dim {
                vn += v[d + dim * i] * f.nrm[d];
            }
            for d in 0..dim {
                let mut t0 = 0.0;
                for b in 0..dim {
                    t0 -= sigma0[IV[d][b] + NSTR * i] * f.nrm[b];
                }
                acc[d] += w * ((-cp * vn * f.nrm[d] - cs * (v[d + dim * i] - vn * f.nrm[d])) + t0 / rho[i]);
            }
        }
    });
}
