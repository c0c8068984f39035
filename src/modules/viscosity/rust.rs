//! The Rust twin of the viscosity: one parallel pass over the pairs computes −Π_ij ∇_i W_ij and
//! ½ Π_ij v_ij·∇_i W_ij (the Fortran's expressions, i and j in pair order; zeros for receding
//! pairs) into a reused buffer, pair by pair from a per-particle record of x, v, h, c, ρ (in 3D
//! this measured faster than blocks of pairs staged for vector arithmetic); one parallel
//! pass over the particles adds, over each particle's pairs in ascending pair order (the Fortran's
//! scatter order), ± m_other × those terms into both outputs. A receding pair adds ±0, which leaves
//! the sum unchanged: an accumulator that starts at +0 is never −0 under round-to-nearest, and
//! x ± 0 = x for every other x. The same pair pass keeps −μ_ij of every approaching pair (+0 where
//! it recedes); mumax_i is their largest over particle i's pairs (a maximum: independent of the
//! order). 0 ULP, independent of the thread count.

use crate::modules::grow;
use super::{Coef, Monaghan, Switch};
use crate::modules::{CHUNK, Sums, Twin, by_dim, gather_signed_max, par_rows, serial};
use rayon::prelude::*;

/// The read-only inputs of the pair pass. `rec` holds each particle's x, v, h, c and ρ in one
/// record of [`rec_len`] values (copies: the same values), so that a pair reads two records.
struct In<'a> {
    pi: &'a [i32],
    pj: &'a [i32],
    dwdx: &'a [f64],
    rec: &'a [f64],
    rinv: &'a [f64],
    alpv: &'a [f64],
    amax: f64,
    coef: Coef,
}

pub(super) fn monaghan(a: &mut Monaghan) {
    // RZ: two energy columns (the i end's and the j end's terms differ)
    if a.rinv.is_empty() { by_dim!(a.dim, 1, run(a)) } else { by_dim!(a.dim, 2, run(a)) }
}

/// Values in a particle's record: x (D), v (D), h, c, ρ.
const fn rec_len(d: usize) -> usize {
    2 * d + 3
}

/// The pair terms of the pairs from `k0` (as many as `t` holds, W + 1 values each: the terms,
/// then −μ): the same operations per pair as the Fortran's loop body, with the approaching test
/// as an exact bit-mask select (a receding pair gets +0 in every value).
fn pairs<const D: usize, const W: usize>(a: &In, k0: usize, t: &mut [f64]) {
    let Coef { alpha, beta, etq } = a.coef;
    let nr = rec_len(D);
    let rz = W == D + 2;
    let sw = !a.alpv.is_empty();
    for (l, tp) in t.chunks_exact_mut(W + 1).enumerate() {
        let k = k0 + l;
        let (i, j) = (a.pi[k] as usize, a.pj[k] as usize);
        let g = &a.dwdx[D * k..D * k + D];
        let ri = &a.rec[nr * i..nr * i + nr];
        let rj = &a.rec[nr * j..nr * j + nr];
        let (xi, vi) = (&ri[..D], &ri[D..2 * D]);
        let (xj, vj) = (&rj[..D], &rj[D..2 * D]);
        let (mut vr, mut r2, mut vd, mut vdj) = (0.0, 0.0, 0.0, 0.0);
        let (mut vwi, mut vwj) = (0.0, 0.0);
        if rz {
            // the axisymmetric energy terms: v_i − (r_j/r_i) v_j and (r_i/r_j) v_i − v_j, and
            // v_i·∇W, v_j·∇W for a pair across the axis
            let (sji, sij) = (a.rinv[i] / a.rinv[j], a.rinv[j] / a.rinv[i]);
            for d in 0..D {
                let dv = vi[d] - vj[d];
                let dx = xi[d] - xj[d];
                vr += dv * dx;
                r2 += dx * dx;
                vd += (vi[d] - sji * vj[d]) * g[d];
                vdj += (sij * vi[d] - vj[d]) * g[d];
                vwi += vi[d] * g[d];
                vwj += vj[d] * g[d];
            }
        } else {
            for d in 0..D {
                let dv = vi[d] - vj[d];
                let dx = xi[d] - xj[d];
                vr += dv * dx;
                r2 += dx * dx;
                vd += dv * g[d];
            }
        }
        let (aij, bij) = if sw {
            let av = 0.5 * (a.alpv[i] + a.alpv[j]);
            (av, beta * (av / a.amax))
        } else {
            (alpha, beta)
        };
        let hv = 0.5 * (ri[2 * D] + rj[2 * D]);
        let mc = 0.5 * (ri[2 * D + 1] + rj[2 * D + 1]);
        let mrho = 0.5 * (ri[2 * D + 2] + rj[2 * D + 2]);
        // Π, masked to +0 where the pair recedes
        let muv = hv * vr / (r2 + (etq * hv) * (etq * hv));
        let piv = (bij * muv - aij * mc) * muv / mrho;
        let on = 0u64.wrapping_sub((vr < 0.0) as u64);
        let mask = |x: f64| f64::from_bits(x.to_bits() & on);
        let pm = mask(piv);
        for d in 0..D {
            tp[d] = mask(-(pm * g[d]));
        }
        if rz {
            // a pair across the axis (the other end an image, 1/r* < 0): the real ring's
            // internal energy takes the work of the image's viscous force on it, Π v·∇W per μ
            let di = if a.rinv[j] < 0.0 { piv * vwi } else { 0.5 * piv * vd };
            let dj = if a.rinv[i] < 0.0 { -(piv * vwj) } else { 0.5 * piv * vdj };
            tp[D] = mask(di);
            tp[D + 1] = mask(dj);
        } else {
            tp[D] = mask(0.5 * piv * vd);
        }
        tp[W] = mask(-muv);
    }
}

fn run<const D: usize, const W: usize>(a: &mut Monaghan) {
    let pl = a.pairs;
    let np = pl.len();
    let mut guard = pl.scratch.lock();
    let buf = &mut *guard;
    // each particle's record: x, v, h, c, ρ
    let (nt, nr) = (a.h.len(), rec_len(D));
    grow(&mut buf.part, nr * nt);
    let (x, v, h, c, rho) = (a.x, a.v, a.h, a.c, a.rho);
    par_rows(&mut buf.part[..nr * nt], nr, |i, r| {
        r[..D].copy_from_slice(&x[D * i..D * i + D]);
        r[D..2 * D].copy_from_slice(&v[D * i..D * i + D]);
        r[2 * D] = h[i];
        r[2 * D + 1] = c[i];
        r[2 * D + 2] = rho[i];
    });
    let inp = In {
        pi: &pl.i,
        pj: &pl.j,
        dwdx: a.dwdx,
        rec: &buf.part,
        rinv: a.rinv,
        alpv: a.alpv,
        amax: a.amax,
        coef: a.coef,
    };
    // per pair: the W terms, then −μ (+0 where it recedes), for the viscous signal speed
    grow(&mut buf.pair, (W + 1) * np);
    // pair terms: −Π ∇W (the i end gets + m_j t, the j end − m_i t), then ½ Π v·∇W, then −μ
    let body = |b: usize, t: &mut [f64]| pairs::<D, W>(&inp, CHUNK * b, t);
    let tc = &mut buf.pair[..(W + 1) * np];
    if serial() {
        tc.chunks_mut((W + 1) * CHUNK).enumerate().for_each(|(b, t)| body(b, t));
    } else {
        tc.par_chunks_mut((W + 1) * CHUNK).enumerate().for_each(|(b, t)| body(b, t));
    }
    // the sums, and the largest −μ over each particle's pairs (a maximum: independent of the
    // order)
    let nt = a.mass.len();
    gather_signed_max::<D, W, false>(
        pl,
        &buf.pair,
        W + 1,
        a.mass,
        None,
        Sums { acc: a.dvdt, e: a.dedt, mx: &mut a.mumax[..nt] },
        (&[], 0),
    );
}

/// The switch: −∇·v_i ρ_i = Σ_j m_j v_ij·∇_i W_ij is the density module's continuity sum (its
/// Rust twin, as the Fortran calls `sph_density_rate`), then the Fortran's backward-Euler step
/// per real particle. 0 ULP, independent of the thread count.
pub(super) fn switch(a: &mut Switch) {
    let Switch { dim, n, pairs, dwdx, mass, rho, v, h, c, amin, amax, ell, dt, alpv, dv } = a;
    let (n, rho, h, c) = (*n, *rho, *h, *c);
    let (amin, amax, ell, dt) = (*amin, *amax, *ell, *dt);
    crate::modules::density::Rate { dim: *dim, volume: false, pairs, dwdx, mass, rho, v, drho: dv }.rust();
    let dv: &[f64] = dv;
    par_rows(&mut alpv[..n], 1, |i, al| {
        let mut s = dv[i] / rho[i];
        if s < 0.0 {
            s = 0.0;
        }
        let r = ell * c[i] / h[i];
        al[0] = (al[0] + dt * (amin * r + s * amax)) / (1.0 + dt * (r + s));
    });
}
