//! The Rust twin of the kernel: every expression in the Fortran's order, 0 ULP. The pair loop is
//! monomorphised over the dimension and the kernel; the cubic spline runs in blocks of pairs over
//! contiguous arrays, its branches as exact bit-mask selects, so that the square roots and
//! divisions run on vectors (same operations per pair, same bits).

use super::{Pairs, SelfW};
use crate::case::KernelKind;
use crate::modules::nnps::PairList;
use crate::modules::{CHUNK, par_rows, par_rows2, serial};
use std::f64::consts::PI;

#[inline(always)]
fn alpha(dim: usize, kind: KernelKind, h: f64) -> f64 {
    match kind {
        KernelKind::Cubic => match dim {
            1 => 1.0 / h,
            2 => 15.0 / (7.0 * PI * h * h),
            _ => 3.0 / (2.0 * PI * h * h * h),
        },
        KernelKind::Gauss => match dim {
            1 => 1.0 / (PI.sqrt() * h),
            2 => 1.0 / (PI * h * h),
            _ => 1.0 / (PI * PI.sqrt() * h * h * h),
        },
        KernelKind::Quintic => match dim {
            1 => 1.0 / (120.0 * h),
            2 => 7.0 / (478.0 * PI * h * h),
            _ => 1.0 / (120.0 * PI * h * h * h),
        },
        KernelKind::Wendland => match dim {
            1 => 5.0 / (8.0 * h),
            2 => 7.0 / (4.0 * PI * h * h),
            _ => 21.0 / (16.0 * PI * h * h * h),
        },
    }
}

/// W and ∇W for the separation `dx` (length `dim`) at distance `r`; writes ∇W into `dwdx`.
#[inline(always)]
pub fn w_dw(dim: usize, kind: KernelKind, r: f64, dx: &[f64], h: f64, dwdx: &mut [f64]) -> f64 {
    let q = r / h;
    let al = alpha(dim, kind, h);
    let mut w = 0.0;
    let mut g = 0.0;
    match kind {
        KernelKind::Cubic => {
            if q < 1.0 {
                w = al * (2.0 / 3.0 - q * q + 0.5 * q * q * q);
                g = al * (-2.0 + 1.5 * q);
            } else if q < 2.0 {
                let a = 2.0 - q;
                w = al * (a * a * a / 6.0);
                g = -al * 0.5 * a * a / q;
            }
        }
        KernelKind::Gauss => {
            if q < 3.0 {
                let a = (-q * q).exp();
                w = al * a;
                g = -2.0 * al * a;
            }
        }
        KernelKind::Quintic => {
            if q < 3.0 {
                let a = 3.0 - q;
                let a2 = a * a;
                w = a2 * a2 * a;
                g = -5.0 * a2 * a2;
                if q < 2.0 {
                    let b = 2.0 - q;
                    let b2 = b * b;
                    w -= 6.0 * b2 * b2 * b;
                    g += 30.0 * b2 * b2;
                    if q < 1.0 {
                        let c = 1.0 - q;
                        let c2 = c * c;
                        w += 15.0 * c2 * c2 * c;
                        g = -120.0 + 120.0 * q * q - 50.0 * q * q * q;
                    } else {
                        g /= q;
                    }
                } else {
                    g /= q;
                }
                w *= al;
                g *= al;
            }
        }
        KernelKind::Wendland => {
            if q < 2.0 {
                let a = 1.0 - 0.5 * q;
                if dim == 1 {
                    w = al * a * a * a * (1.5 * q + 1.0);
                    g = -3.0 * al * a * a;
                } else {
                    w = al * a * a * a * a * (2.0 * q + 1.0);
                    g = -5.0 * al * a * a * a;
                }
            }
        }
    }
    for d in 0..dim {
        dwdx[d] = g * dx[d] / (h * h);
    }
    w
}

/// W_ij and ∇_i W_ij of every pair. The lattice normalisation (`gscale` ≠ 1) multiplies each
/// component of ∇W in the same loops, as the Fortran does in its pair loop.
pub(super) fn pairs(a: &mut Pairs) {
    match a.dim {
        1 => pairs_d::<1>(a),
        2 => pairs_d::<2>(a),
        _ => pairs_d::<3>(a),
    }
}

const KINDS: [KernelKind; 4] = [KernelKind::Cubic, KernelKind::Gauss, KernelKind::Quintic, KernelKind::Wendland];

fn pairs_d<const D: usize>(a: &mut Pairs) {
    match a.kind {
        KernelKind::Cubic => pairs_dk::<D, 0>(a),
        KernelKind::Gauss => pairs_dk::<D, 1>(a),
        KernelKind::Quintic => pairs_dk::<D, 2>(a),
        KernelKind::Wendland => pairs_dk::<D, 3>(a),
    }
}

/// The pair loop for one dimension and one kernel (`KINDS[K]`), so both are constants in it.
fn pairs_dk<const D: usize, const K: usize>(a: &mut Pairs) {
    let Pairs { pairs: pl, x, h, w, dwdx, gscale, .. } = a;
    let (pl, x, h, gs): (&PairList, &[f64], &[f64], f64) = (pl, x, h, *gscale);
    let np = pl.len();
    let (pi, pj) = (&pl.i, &pl.j);
    if K == 0 {
        // the cubic spline in blocks, with a per-thread buffer of D + 2 values per pair
        let inp = In { pi, pj, x, h, gs };
        let mut guard = pl.scratch.lock();
        guard.per_thread.ensure();
        let tls = &guard.per_thread;
        let body = |c: usize, (wb, gb): (&mut [f64], &mut [f64])| {
            tls.with((D + 2) * wb.len(), |tb| cubic_block::<D>(&inp, CHUNK * c, wb, gb, tb))
        };
        let (wc, gc) = (w[..np].chunks_mut(CHUNK), dwdx[..D * np].chunks_mut(D * CHUNK));
        if serial() {
            wc.zip(gc).enumerate().for_each(|(c, b)| body(c, b));
        } else {
            use rayon::prelude::*;
            let (wc, gc) = (w[..np].par_chunks_mut(CHUNK), dwdx[..D * np].par_chunks_mut(D * CHUNK));
            wc.zip(gc).enumerate().for_each(|(c, b)| body(c, b));
        }
        return;
    }
    par_rows2(&mut w[..np], 1, &mut dwdx[..D * np], D, |k, wk, g| {
        let i = pi[k] as usize;
        let j = pj[k] as usize;
        let mut dx = [0.0; D];
        let mut r2 = 0.0;
        for d in 0..D {
            dx[d] = x[d + D * i] - x[d + D * j];
            r2 += dx[d] * dx[d];
        }
        let hij = 0.5 * (h[i] + h[j]);
        wk[0] = w_dw(D, KINDS[K], r2.sqrt(), &dx, hij, g);
        if gs != 1.0 {
            g.iter_mut().for_each(|v| *v *= gs);
        }
    });
}

/// The read-only inputs of a block of pairs.
#[derive(Clone, Copy)]
struct In<'a> {
    pi: &'a [i32],
    pj: &'a [i32],
    x: &'a [f64],
    h: &'a [f64],
    /// The lattice normalisation of ∇W (1: none).
    gs: f64,
}

/// The cubic spline over a block of pairs, in loops over contiguous arrays (in `tmp`: D + 2 values
/// per pair) so that the square roots and divisions, the branches written as selects, run on
/// vectors: the same operations per pair, so the same bits.
fn cubic_block<const D: usize>(inp: &In, k0: usize, w: &mut [f64], g: &mut [f64], tmp: &mut [f64]) {
    let In { pi, pj, x, h, gs } = *inp;
    let len = w.len();
    let (dx, rest) = tmp.split_at_mut(D * len);
    let (r2s, hs) = rest.split_at_mut(len);
    for l in 0..len {
        let (i, j) = (pi[k0 + l] as usize, pj[k0 + l] as usize);
        let mut r2 = 0.0;
        for d in 0..D {
            let e = x[d + D * i] - x[d + D * j];
            dx[d * len + l] = e;
            r2 += e * e;
        }
        r2s[l] = r2;
        hs[l] = 0.5 * (h[i] + h[j]);
    }
    // r2s becomes the gradient factor g(q)
    for l in 0..len {
        let hv = hs[l];
        let q = r2s[l].sqrt() / hv;
        let al = alpha(D, KernelKind::Cubic, hv);
        let w1 = al * (2.0 / 3.0 - q * q + 0.5 * q * q * q);
        let g1 = al * (-2.0 + 1.5 * q);
        let a = 2.0 - q;
        let w2 = al * (a * a * a / 6.0);
        let g2 = -al * 0.5 * a * a / q;
        // the branches as bit masks: exact selects, and they vectorise
        let near = 0u64.wrapping_sub((q < 1.0) as u64);
        let mid = 0u64.wrapping_sub((q < 2.0) as u64) & !near;
        let pick = |a: f64, b: f64| f64::from_bits((a.to_bits() & near) | (b.to_bits() & mid));
        w[l] = pick(w1, w2);
        r2s[l] = pick(g1, g2);
    }
    for dxd in dx.chunks_exact_mut(len) {
        for l in 0..len {
            dxd[l] = r2s[l] * dxd[l] / (hs[l] * hs[l]);
        }
    }
    for l in 0..len {
        for d in 0..D {
            g[D * l + d] = dx[d * len + l];
        }
    }
    if gs != 1.0 {
        g.iter_mut().for_each(|v| *v *= gs);
    }
}

/// The self-contribution W(0, h_i) of each particle.
pub(super) fn self_w(a: &mut SelfW) {
    let SelfW { dim, kind, h, w0 } = a;
    let (dim, kind, h) = (*dim, *kind, *h);
    let dx = [0.0; 3];
    par_rows(&mut w0[..h.len()], 1, |i, w| {
        let mut g = [0.0; 3];
        w[0] = w_dw(dim, kind, 0.0, &dx[..dim], h[i], &mut g[..dim]);
    });
}
