//! The Rust twin of the boundaries: same order, 0 ULP. The wall frames are computed once per
//! call (the Fortran recomputes them per particle; same values). The wall force skips a wall
//! whose line (plane, in 3D) lies farther than 1.01 r0 from the particle: no wall particle on it
//! can be within r0, so the Fortran adds nothing for it either.

use super::{MirrorFill, MirrorMake, WallCoef, WallForce};
use crate::modules::param::{NSTR, Segments, seg_len};
use crate::modules::{CHUNK, ipow, par_rows, par_rows2, serial};
use rayon::prelude::*;

const IV: [[usize; 3]; 3] = [[0, 3, 4], [3, 1, 5], [4, 5, 2]];

/// A wall's frame: unit edge direction(s) `t` (1D and 2D: `t[0]`, the segment's tangent, zeros
/// for a point; 3D: `t[0]`, `t[1]` along the two edge vectors), their lengths `el` (m), and the
/// unit normal `nrm`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WallFrame {
    pub t: [[f64; 3]; 2],
    pub el: [f64; 2],
    pub nrm: [f64; 3],
}

/// The frame of wall `sg` ([`seg_len`] values: 1D, 2D from, to, normal; 3D corner, the two edge
/// vectors, normal), as the Fortran's `seg_frame` and `plane_frame` compute it.
pub(crate) fn frame(dim: usize, sg: &[f64]) -> WallFrame {
    let mut f = WallFrame::default();
    if dim == 3 {
        let (mut el1, mut el2) = (0.0, 0.0);
        for d in 0..3 {
            f.t[0][d] = sg[3 + d];
            f.t[1][d] = sg[6 + d];
            el1 += f.t[0][d] * f.t[0][d];
            el2 += f.t[1][d] * f.t[1][d];
            f.nrm[d] = sg[9 + d];
        }
        f.el = [f64::sqrt(el1), f64::sqrt(el2)];
        for d in 0..3 {
            f.t[0][d] /= f.el[0];
            f.t[1][d] /= f.el[1];
        }
        return f;
    }
    let mut el = 0.0;
    for d in 0..dim {
        f.t[0][d] = sg[dim + d] - sg[d];
        el += f.t[0][d] * f.t[0][d];
        f.nrm[d] = sg[2 * dim + d];
    }
    let el = f64::sqrt(el);
    if el > 0.0 {
        for v in f.t[0].iter_mut().take(dim) {
            *v /= el;
        }
    }
    f.el[0] = el;
    f
}

/// The node range `lo..=hi` of one edge direction for a particle at `tp` along it: nodes within
/// r0, the far edge (`nk`) only where the wall owns it, the near one (0) likewise.
#[inline]
fn node_range(tp: f64, r0: f64, ds: f64, nk: i64, far: bool, near: bool) -> (i64, i64) {
    let lo = (((tp - r0) / ds).ceil() as i64).max(0);
    let hi = (((tp + r0) / ds).floor() as i64).min(nk);
    let hi = if far { hi } else { hi.min(nk - 1) };
    let lo = if near { lo } else { lo.max(1) };
    (lo, hi)
}

/// The type I force of 3D walls (plane walls whose nodes are a + k1 ds1 t1 + k2 ds2 t2): the
/// Fortran's `wall_force_3d`, a wall skipped when the particle lies farther than 1.01 r0 from its
/// plane (no node of it can then be within r0).
fn wall_force_3d(x: &[f64], segs: &Segments, coef: WallCoef, dvdt: &mut [f64]) {
    let WallCoef { spacing, r0, d: dcoef, n1, n2 } = coef;
    struct Wall {
        f: WallFrame,
        nk: [i64; 2],
        ds: [f64; 2],
    }
    let walls: Vec<Wall> = (0..segs.len())
        .map(|s| {
            let f = frame(3, segs.get(3, s));
            let nk = [((f.el[0] / spacing).round() as i64).max(1), ((f.el[1] / spacing).round() as i64).max(1)];
            Wall { f, nk, ds: [f.el[0] / nk[0] as f64, f.el[1] / nk[1] as f64] }
        })
        .collect();
    let n = x.len() / 3;
    let reach = 1.01 * r0;
    par_rows(&mut dvdt[..3 * n], 3, |i, acc| {
        let mut sum = [0.0f64; 3];
        let xi = &x[3 * i..3 * i + 3];
        for (s, w) in walls.iter().enumerate() {
            let sg = segs.get(3, s);
            let (t1, t2) = (&w.f.t[0], &w.f.t[1]);
            let (mut tp1, mut tp2, mut dn) = (0.0, 0.0, 0.0);
            for d in 0..3 {
                let e = xi[d] - sg[d];
                tp1 += e * t1[d];
                tp2 += e * t2[d];
                dn += e * w.f.nrm[d];
            }
            if dn.abs() > reach {
                continue;
            }
            let own = segs.endnode[s];
            let (lo1, hi1) = node_range(tp1, r0, w.ds[0], w.nk[0], own & 1 != 0, own & 4 != 0);
            let (lo2, hi2) = node_range(tp2, r0, w.ds[1], w.nk[1], own & 2 != 0, own & 8 != 0);
            for k2 in lo2..=hi2 {
                for k1 in lo1..=hi1 {
                    let mut dx = [0.0; 3];
                    let mut r2 = 0.0;
                    for d in 0..3 {
                        dx[d] = xi[d] - (sg[d] + k1 as f64 * w.ds[0] * t1[d] + k2 as f64 * w.ds[1] * t2[d]);
                        r2 += dx[d] * dx[d];
                    }
                    if r2 < r0 * r0 {
                        let q = r0 / r2.sqrt();
                        let f = dcoef * (ipow(q, n1) - ipow(q, n2)) / r2;
                        for d in 0..3 {
                            sum[d] += f * dx[d];
                        }
                    }
                }
            }
        }
        acc.copy_from_slice(&sum);
    });
}

/// The type I force: each real particle sums over the wall particles of every segment within r0.
pub(super) fn wall_force(a: &mut WallForce) {
    let WallForce { dim, x, segs, coef, dvdt } = a;
    if *dim == 3 {
        return wall_force_3d(x, segs, *coef, dvdt);
    }
    let (dim, WallCoef { spacing, r0, d: dcoef, n1, n2 }) = (*dim, *coef);
    struct Wall {
        t: [f64; 3],
        el: f64,
        nk: i64,
        ds: f64,
    }
    let walls: Vec<Wall> = (0..segs.len())
        .map(|s| {
            let f = frame(dim, segs.get(dim, s));
            let el = f.el[0];
            let nk = ((el / spacing).round() as i64).max(1);
            Wall { t: f.t[0], el, nk, ds: el / nk as f64 }
        })
        .collect();
    let n = x.len() / dim.max(1);
    let reach2 = (1.01 * r0) * (1.01 * r0);
    par_rows(&mut dvdt[..dim * n], dim, |i, acc| {
        let mut sum = [0.0f64; 3];
        let xi = &x[dim * i..dim * i + dim];
        for (s, w) in walls.iter().enumerate() {
            let sg = segs.get(dim, s);
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
fn in_band(dim: usize, sg: &[f64], fr: &WallFrame, y: &[f64], band: f64) -> bool {
    if dim == 3 {
        let (mut dn, mut tp, mut tp2) = (0.0, 0.0, 0.0);
        for d in 0..3 {
            dn += (y[d] - sg[d]) * fr.nrm[d];
            tp += (y[d] - sg[d]) * fr.t[0][d];
            tp2 += (y[d] - sg[d]) * fr.t[1][d];
        }
        return dn >= 0.0
            && dn < band
            && tp >= -band
            && tp <= fr.el[0] + band
            && tp2 >= -band
            && tp2 <= fr.el[1] + band;
    }
    let (t, el, nrm) = (&fr.t[0], fr.el[0], &fr.nrm);
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
/// `reach` is (κ, h_max): the band of particle i is κ (h_i + h_max)/2.
fn first_images<const D: usize>(
    rows: std::ops::Range<usize>,
    x: &[f64],
    h: &[f64],
    reach: (f64, f64),
    segs: &Segments,
    frames: &[WallFrame],
    out: &mut Vec<[i32; 2]>,
) {
    let (kappa, hmax) = reach;
    for i in rows {
        let band = kappa * (0.5 * (h[i] + hmax));
        let y = &x[D * i..D * i + D];
        for (s, fr) in frames.iter().enumerate() {
            if in_band(D, segs.get(D, s), fr, y, band) {
                out.push([i as i32, s as i32]);
            }
        }
    }
}

/// Reflects `y` in the plane (line, point) of wall `sg`, whose normal is its last `dim` values.
fn reflect(dim: usize, sg: &[f64], y: &mut [f64]) {
    let no = seg_len(dim) - dim;
    let mut dn = 0.0;
    for d in 0..dim {
        dn += (y[d] - sg[d]) * sg[no + d];
    }
    for d in 0..dim {
        y[d] -= 2.0 * dn * sg[no + d];
    }
}

/// Lists the mirrors of the `h.len()` real particles into `gsrc`, `gseg` (resized; `gseg` holds
/// 2 walls per mirror, 3 in 3D, −1 = none). A particle i is mirrored when it lies within
/// κ (h_i + h_max)/2 of a wall (m), h_max the largest h: the farthest any real particle j reaches (a
/// pair interacts within κ (h_i + h_j)/2), so that a particle with a large h near a wall sees the
/// images of every particle it sees on its own side.
pub(super) fn mirror_make(a: &mut MirrorMake) {
    let MirrorMake { dim, x, h, kappa, segs, gsrc, gseg } = a;
    let (dim, kappa) = (*dim, *kappa);
    let ngen = 2 + dim / 3;
    let n = h.len();
    let ns = segs.len();
    let hmax = h.iter().fold(0.0f64, |a, &b| a.max(b));
    let sg = |s: usize| segs.get(dim, s);
    let frames: Vec<WallFrame> = (0..ns).map(|s| frame(dim, sg(s))).collect();
    // the first images, by particle then wall, in tasks of CHUNK particles
    let task = |c: usize| -> Vec<[i32; 2]> {
        let mut out = Vec::new();
        let rows = CHUNK * c..(CHUNK * c + CHUNK).min(n);
        match dim {
            1 => first_images::<1>(rows, x, h, (kappa, hmax), segs, &frames, &mut out),
            2 => first_images::<2>(rows, x, h, (kappa, hmax), segs, &frames, &mut out),
            _ => first_images::<3>(rows, x, h, (kappa, hmax), segs, &frames, &mut out),
        }
        out
    };
    let nc = n.div_ceil(CHUNK);
    let found: Vec<Vec<[i32; 2]>> =
        if serial() { (0..nc).map(task).collect() } else { (0..nc).into_par_iter().map(task).collect() };
    gsrc.clear();
    gseg.clear();
    let none = [-1i32; 2];
    for &[i, s] in found.iter().flatten() {
        gsrc.push(i);
        gseg.push(s);
        gseg.extend_from_slice(&none[..ngen - 1]);
    }
    let ng1 = gsrc.len();
    // the images of the first images in a later wall (corners), in tasks of CHUNK first images,
    // joined in order: the same list as one loop over them
    let second = |c: usize| -> Vec<[i32; 3]> {
        let mut out = Vec::new();
        for g in CHUNK * c..(CHUNK * c + CHUNK).min(ng1) {
            let i = gsrc[g] as usize;
            let s = gseg[ngen * g] as usize;
            let mut y = [0.0; 3];
            y[..dim].copy_from_slice(&x[dim * i..dim * i + dim]);
            reflect(dim, sg(s), &mut y[..dim]);
            for t in s + 1..ns {
                if in_band(dim, sg(t), &frames[t], &y[..dim], kappa * (0.5 * (h[i] + hmax))) {
                    out.push([i as i32, s as i32, t as i32]);
                }
            }
        }
        out
    };
    let nc1 = ng1.div_ceil(CHUNK);
    let found2: Vec<Vec<[i32; 3]>> =
        if serial() { (0..nc1).map(second).collect() } else { (0..nc1).into_par_iter().map(second).collect() };
    for &[i, s, t] in found2.iter().flatten() {
        gsrc.push(i);
        gseg.extend_from_slice(&[s, t]);
        gseg.extend_from_slice(&none[..ngen - 2]);
    }
    if dim != 3 {
        return;
    }
    // 3D: images of the corner images in a third wall
    let ng2 = gsrc.len();
    for g in ng1..ng2 {
        let i = gsrc[g] as usize;
        let (s, t) = (gseg[3 * g] as usize, gseg[3 * g + 1] as usize);
        let mut y = [0.0; 3];
        y.copy_from_slice(&x[3 * i..3 * i + 3]);
        reflect(3, sg(s), &mut y);
        reflect(3, sg(t), &mut y);
        for u in t + 1..ns {
            if in_band(3, sg(u), &frames[u], &y, kappa * (0.5 * (h[i] + hmax))) {
                gsrc.push(i as i32);
                gseg.extend_from_slice(&[s as i32, t as i32, u as i32]);
            }
        }
    }
}

/// The 3 × 3 product a b, each entry summed over q = 0, 1, 2 from +0 (the Fortran's order).
fn mul3(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut c = [[0.0f64; 3]; 3];
    for al in 0..3 {
        for be in 0..3 {
            let mut sm = 0.0;
            for q in 0..3 {
                sm += a[al][q] * b[q][be];
            }
            c[al][be] = sm;
        }
    }
    c
}

/// Fills the mirror slots `n..n+ng` of the arrays: each mirror a copy of its source, reflected
/// in its walls in turn (position and, free-slip, the normal velocity; no-slip, the velocity
/// reversed; the stress rotated as R τ R, R = I − 2 n nᵀ). One parallel pass per field (the
/// slots are disjoint, the sources are real particles).
pub(super) fn mirror_fill(a: &mut MirrorFill) {
    let (dim, n, gsrc, gseg, segs, noslip) = (a.dim, a.n, a.gsrc, a.gseg, a.segs, a.noslip);
    let ng = gsrc.len();
    let (ngen, no) = (2 + dim / 3, seg_len(dim) - dim);
    // the walls of mirror g, in order
    let walls = move |g: usize| {
        gseg[ngen * g..ngen * g + ngen].iter().filter(|&&s| s >= 0).map(move |&s| segs.get(dim, s as usize))
    };
    let src = |g: usize| gsrc[g] as usize;
    {
        let (xr, xg) = a.x.split_at_mut(dim * n);
        let (vr, vg) = a.v.split_at_mut(dim * n);
        par_rows2(&mut xg[..dim * ng], dim, &mut vg[..dim * ng], dim, |g, xm, vm| {
            let i = src(g);
            xm.copy_from_slice(&xr[dim * i..dim * i + dim]);
            vm.copy_from_slice(&vr[dim * i..dim * i + dim]);
            for sg in walls(g) {
                reflect(dim, sg, xm);
                if !noslip {
                    let nrm = &sg[no..no + dim];
                    let mut vn = 0.0;
                    for d in 0..dim {
                        vn += vm[d] * nrm[d];
                    }
                    for d in 0..dim {
                        vm[d] -= 2.0 * vn * nrm[d];
                    }
                }
            }
            if noslip {
                for d in 0..dim {
                    vm[d] = -vr[d + dim * i];
                }
            }
        });
    }
    for f in [&mut *a.rho, &mut *a.p, &mut *a.c, &mut *a.e, &mut *a.h, &mut *a.mass] {
        let (fr, fg) = f.split_at_mut(n);
        par_rows(&mut fg[..ng], 1, |g, o| o[0] = fr[src(g)]);
    }
    for g in 0..ng {
        a.mat[n + g] = a.mat[src(g)];
    }
    if a.tau.is_empty() {
        return;
    }
    let (tr, tg) = a.tau.split_at_mut(NSTR * n);
    par_rows(&mut tg[..NSTR * ng], NSTR, |g, out| {
        let i = src(g);
        let mut t3 = [[0.0f64; 3]; 3];
        for al in 0..3 {
            for be in 0..3 {
                t3[al][be] = tr[IV[al][be] + NSTR * i];
            }
        }
        for sg in walls(g) {
            let mut nrm = [0.0; 3];
            nrm[..dim].copy_from_slice(&sg[no..no + dim]);
            let mut rm = [[0.0f64; 3]; 3];
            for al in 0..3 {
                for be in 0..3 {
                    rm[al][be] = -2.0 * nrm[al] * nrm[be];
                    if al == be {
                        rm[al][be] += 1.0;
                    }
                }
            }
            t3 = mul3(&rm, &mul3(&t3, &rm));
        }
        for al in 0..3 {
            for be in al..3 {
                out[IV[al][be]] = t3[al][be];
            }
        }
    });
}
