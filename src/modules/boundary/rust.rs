//! The Rust twin of the boundaries: same order, 0 ULP. The segment frames are computed once per
//! call (the Fortran recomputes them per particle; same values). The wall force skips a segment
//! whose line lies farther than 1.01 r0 from the particle: no wall particle on it can be within
//! r0, so the Fortran adds nothing for it either.

use super::{MirrorFill, MirrorMake, WallCoef, WallForce};
use crate::modules::param::{NSTR, Segments};
use crate::modules::{CHUNK, ipow, par_rows, serial};
use rayon::prelude::*;

const IV: [[usize; 3]; 3] = [[0, 3, 4], [3, 1, 5], [4, 5, 2]];

/// Unit tangent (zeros for a degenerate segment), length (m) and unit normal of the segment
/// `sg` (from, to, normal; `dim` values each).
pub(crate) fn frame(dim: usize, sg: &[f64]) -> ([f64; 3], f64, [f64; 3]) {
    let mut t = [0.0; 3];
    let mut nrm = [0.0; 3];
    let mut el = 0.0;
    for d in 0..dim {
        t[d] = sg[dim + d] - sg[d];
        el += t[d] * t[d];
        nrm[d] = sg[2 * dim + d];
    }
    let el = f64::sqrt(el);
    if el > 0.0 {
        for v in t.iter_mut().take(dim) {
            *v /= el;
        }
    }
    (t, el, nrm)
}

/// The type I force: each real particle sums over the wall particles of every segment within r0.
pub(super) fn wall_force(a: &mut WallForce) {
    let WallForce { dim, x, segs, coef, dvdt } = a;
    let (dim, WallCoef { spacing, r0, d: dcoef, n1, n2 }) = (*dim, *coef);
    struct Wall {
        t: [f64; 3],
        el: f64,
        nk: i64,
        ds: f64,
    }
    let walls: Vec<Wall> = (0..segs.len())
        .map(|s| {
            let (t, el, _) = frame(dim, &segs.seg[3 * dim * s..3 * dim * (s + 1)]);
            let nk = ((el / spacing).round() as i64).max(1);
            Wall { t, el, nk, ds: el / nk as f64 }
        })
        .collect();
    let n = x.len() / dim.max(1);
    let reach2 = (1.01 * r0) * (1.01 * r0);
    par_rows(&mut dvdt[..dim * n], dim, |i, acc| {
        let mut sum = [0.0f64; 3];
        let xi = &x[dim * i..dim * i + dim];
        for (s, w) in walls.iter().enumerate() {
            let sg = &segs.seg[3 * dim * s..3 * dim * (s + 1)];
            let (t, el, nk, ds) = (&w.t, w.el, w.nk, w.ds);
            let mut tp = 0.0;
            let mut ee = 0.0;
            for d in 0..dim {
                let e = xi[d] - sg[d];
                tp += e * t[d];
                ee += e * e;
            }
            let (klo, khi) = if el > 0.0 {
                // distance² to the wall's line, with room for rounding
                if dim > 1 && ee - tp * tp > reach2 + 1e-12 * ee {
                    continue;
                }
                let klo = (((tp - r0) / ds).ceil() as i64).max(0);
                let khi = ((tp + r0) / ds).floor() as i64;
                let khi = if segs.endnode[s] != 0 { khi.min(nk) } else { khi.min(nk - 1) };
                (klo, khi)
            } else {
                (0, 0)
            };
            for k in klo..=khi {
                let mut dx = [0.0; 3];
                let mut r2 = 0.0;
                for d in 0..dim {
                    dx[d] = xi[d] - (sg[d] + k as f64 * ds * t[d]);
                    r2 += dx[d] * dx[d];
                }
                if r2 < r0 * r0 {
                    let q = r0 / r2.sqrt();
                    let f = dcoef * (ipow(q, n1) - ipow(q, n2)) / r2;
                    for d in 0..dim {
                        sum[d] += f * dx[d];
                    }
                }
            }
        }
        acc.copy_from_slice(&sum[..dim]);
    });
}

#[inline(always)]
fn in_band(dim: usize, sg: &[f64], fr: &([f64; 3], f64, [f64; 3]), y: &[f64], band: f64) -> bool {
    let (t, el, nrm) = fr;
    let el = *el;
    let mut dn = 0.0;
    let mut tp = 0.0;
    for d in 0..dim {
        dn += (y[d] - sg[d]) * nrm[d];
        tp += (y[d] - sg[d]) * t[d];
    }
    dn >= 0.0 && dn < band && tp >= -band && tp <= el + band
}

/// The (particle, wall) pairs of the particles `rows` that lie in a wall's band, by particle then
/// wall: [`in_band`] with the dimension a constant, so its loops unroll (the same operations).
fn first_images<const D: usize>(
    rows: std::ops::Range<usize>,
    x: &[f64],
    h: &[f64],
    kappa: f64,
    segs: &Segments,
    frames: &[([f64; 3], f64, [f64; 3])],
    out: &mut Vec<[i32; 2]>,
) {
    for i in rows {
        let band = kappa * h[i];
        let y = &x[D * i..D * i + D];
        for (s, fr) in frames.iter().enumerate() {
            if in_band(D, &segs.seg[3 * D * s..3 * D * (s + 1)], fr, y, band) {
                out.push([i as i32, s as i32]);
            }
        }
    }
}

fn reflect(dim: usize, sg: &[f64], y: &mut [f64]) {
    let mut dn = 0.0;
    for d in 0..dim {
        dn += (y[d] - sg[d]) * sg[2 * dim + d];
    }
    for d in 0..dim {
        y[d] -= 2.0 * dn * sg[2 * dim + d];
    }
}

/// Lists the mirrors of the `h.len()` real particles into `gsrc`, `gseg` (resized).
pub(super) fn mirror_make(a: &mut MirrorMake) {
    let MirrorMake { dim, x, h, kappa, segs, gsrc, gseg } = a;
    let (dim, kappa) = (*dim, *kappa);
    let n = h.len();
    let ns = segs.len();
    let sg = |s: usize| &segs.seg[3 * dim * s..3 * dim * (s + 1)];
    let frames: Vec<_> = (0..ns).map(|s| frame(dim, sg(s))).collect();
    // the first images, by particle then wall, in tasks of CHUNK particles
    let task = |c: usize| -> Vec<[i32; 2]> {
        let mut out = Vec::new();
        let rows = CHUNK * c..(CHUNK * c + CHUNK).min(n);
        match dim {
            1 => first_images::<1>(rows, x, h, kappa, segs, &frames, &mut out),
            2 => first_images::<2>(rows, x, h, kappa, segs, &frames, &mut out),
            _ => first_images::<3>(rows, x, h, kappa, segs, &frames, &mut out),
        }
        out
    };
    let nc = n.div_ceil(CHUNK);
    let found: Vec<Vec<[i32; 2]>> =
        if serial() { (0..nc).map(task).collect() } else { (0..nc).into_par_iter().map(task).collect() };
    gsrc.clear();
    gseg.clear();
    for &[i, s] in found.iter().flatten() {
        gsrc.push(i);
        gseg.extend_from_slice(&[s, -1]);
    }
    let ng1 = gsrc.len();
    for g in 0..ng1 {
        let i = gsrc[g] as usize;
        let s = gseg[2 * g] as usize;
        let mut y = [0.0; 3];
        y[..dim].copy_from_slice(&x[dim * i..dim * i + dim]);
        reflect(dim, sg(s), &mut y[..dim]);
        for t in s + 1..ns {
            if in_band(dim, sg(t), &frames[t], &y[..dim], kappa * h[i]) {
                gsrc.push(i as i32);
                gseg.extend_from_slice(&[s as i32, t as i32]);
            }
        }
    }
}

/// Fills the mirror slots `n..n+ng` of the arrays.
pub(super) fn mirror_fill(a: &mut MirrorFill) {
    let (dim, n, gsrc, gseg, segs, noslip) = (a.dim, a.n, a.gsrc, a.gseg, a.segs, a.noslip);
    let with_tau = !a.tau.is_empty();
    for (g, &src) in gsrc.iter().enumerate() {
        let i = src as usize;
        let m = n + g;
        for d in 0..dim {
            a.x[d + dim * m] = a.x[d + dim * i];
            a.v[d + dim * m] = a.v[d + dim * i];
        }
        a.rho[m] = a.rho[i];
        a.p[m] = a.p[i];
        a.c[m] = a.c[i];
        a.e[m] = a.e[i];
        a.h[m] = a.h[i];
        a.mass[m] = a.mass[i];
        a.mat[m] = a.mat[i];
        let mut t3 = [[0.0f64; 3]; 3];
        if with_tau {
            for al in 0..3 {
                for be in 0..3 {
                    t3[al][be] = a.tau[IV[al][be] + NSTR * i];
                }
            }
        }
        for l in 0..2 {
            let s = gseg[l + 2 * g];
            if s < 0 {
                continue;
            }
            let sg = &segs.seg[3 * dim * s as usize..3 * dim * (s as usize + 1)];
            reflect(dim, sg, &mut a.x[dim * m..dim * m + dim]);
            let mut nrm = [0.0; 3];
            nrm[..dim].copy_from_slice(&sg[2 * dim..3 * dim]);
            if !noslip {
                let mut vn = 0.0;
                for d in 0..dim {
                    vn += a.v[d + dim * m] * nrm[d];
                }
                for d in 0..dim {
                    a.v[d + dim * m] -= 2.0 * vn * nrm[d];
                }
            }
            if with_tau {
                let mut rm = [[0.0f64; 3]; 3];
                for al in 0..3 {
                    for be in 0..3 {
                        rm[al][be] = -2.0 * nrm[al] * nrm[be];
                        if al == be {
                            rm[al][be] += 1.0;
                        }
                    }
                }
                let mut u3 = [[0.0f64; 3]; 3];
                for al in 0..3 {
                    for be in 0..3 {
                        let mut sm = 0.0;
                        for q in 0..3 {
                            sm += t3[al][q] * rm[q][be];
                        }
                        u3[al][be] = sm;
                    }
                }
                for al in 0..3 {
                    for be in 0..3 {
                        let mut sm = 0.0;
                        for q in 0..3 {
                            sm += rm[al][q] * u3[q][be];
                        }
                        t3[al][be] = sm;
                    }
                }
            }
        }
        if noslip {
            for d in 0..dim {
                a.v[d + dim * m] = -a.v[d + dim * i];
            }
        }
        if with_tau {
            for al in 0..3 {
                for be in al..3 {
                    a.tau[IV[al][be] + NSTR * m] = t3[al][be];
                }
            }
        }
    }
}
