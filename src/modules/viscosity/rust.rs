//! The Rust twin of the viscosity: one parallel pass over the pairs computes −Π_ij ∇_i W_ij and
//! ½ Π_ij v_ij·∇_i W_ij (the Fortran's expressions, i and j in pair order; zeros for receding
//! pairs) into a reused buffer, in blocks of pairs whose arithmetic runs on vectors; one parallel
//! pass over the particles adds, over each particle's pairs in ascending pair order (the Fortran's
//! scatter order), ± m_other × those terms into both outputs. A receding pair adds ±0, which leaves
//! the sum unchanged: an accumulator that starts at +0 is never −0 under round-to-nearest, and
//! x ± 0 = x for every other x. The same pair pass keeps −μ_ij of every approaching pair (+0 where
//! it recedes); mumax_i is their largest over particle i's pairs (a maximum: independent of the
//! order). 0 ULP, independent of the thread count.

use super::{Coef, Monaghan, Switch};
use crate::modules::{CHUNK, Twin, by_dim, gather_signed_max, par_rows, serial};
use rayon::prelude::*;

/// The read-only inputs of the pair pass.
struct In<'a> {
    pi: &'a [i32],
    pj: &'a [i32],
    dwdx: &'a [f64],
    x: &'a [f64],
    v: &'a [f64],
    h: &'a [f64],
    rho: &'a [f64],
    c: &'a [f64],
    rinv: &'a [f64],
    alpv: &'a [f64],
    amax: f64,
    coef: Coef,
}

pub(super) fn monaghan(a: &mut Monaghan) {
    // RZ: two energy columns (the i end's and the j end's terms differ)
    if a.rinv.is_empty() { by_dim!(a.dim, 1, run(a)) } else { by_dim!(a.dim, 2, run(a)) }
}

/// Values per pair in the block's work arrays: v·x, r², v·∇W, h̄, c̄, ρ̄, the j end's v·∇W (RZ),
/// and the pair's α and β (the switch's α_ij, β α_ij/α_max; else the constants).
const NV: usize = 9;

/// The pair terms of the block of pairs from `k0` (as many as `t` holds): the same operations per
/// pair as the Fortran's loop body, with the approaching test as an exact bit-mask select (a
/// receding pair gets +0), so that the divisions run on vectors.
fn block<const D: usize, const W: usize>(a: &In, k0: usize, t: &mut [f64], tmp: &mut [f64]) {
    let Coef { alpha, beta, etq } = a.coef;
    let (x, v) = (a.x, a.v);
    // each pair's row: its W terms, then −μ
    let s = W + 1;
    let len = t.len() / s;
    let (vr, rest) = tmp.split_at_mut(len);
    let (r2, rest) = rest.split_at_mut(len);
    let (vd, rest) = rest.split_at_mut(len);
    let (hij, rest) = rest.split_at_mut(len);
    let (mc, rest) = rest.split_at_mut(len);
    let (mrho, rest) = rest.split_at_mut(len);
    let (vdj, rest) = rest.split_at_mut(len);
    let (aij, bij) = rest.split_at_mut(len);
    let rz = W == D + 2;
    let sw = !a.alpv.is_empty();
    for l in 0..len {
        let k = k0 + l;
        let (i, j) = (a.pi[k] as usize, a.pj[k] as usize);
        let g = &a.dwdx[D * k..D * k + D];
        let (mut s_vr, mut s_r2, mut s_vd, mut s_vdj) = (0.0, 0.0, 0.0, 0.0);
        if rz {
            // the axisymmetric energy terms: v_i − (r_j/r_i) v_j and (r_i/r_j) v_i − v_j
            let (sji, sij) = (a.rinv[i] / a.rinv[j], a.rinv[j] / a.rinv[i]);
            for d in 0..D {
                let dv = v[d + D * i] - v[d + D * j];
                let dx = x[d + D * i] - x[d + D * j];
                s_vr += dv * dx;
                s_r2 += dx * dx;
                s_vd += (v[d + D * i] - sji * v[d + D * j]) * g[d];
                s_vdj += (sij * v[d + D * i] - v[d + D * j]) * g[d];
            }
        } else {
            for d in 0..D {
                let dv = v[d + D * i] - v[d + D * j];
                let dx = x[d + D * i] - x[d + D * j];
                s_vr += dv * dx;
                s_r2 += dx * dx;
                s_vd += dv * g[d];
            }
        }
        vr[l] = s_vr;
        r2[l] = s_r2;
        vd[l] = s_vd;
        vdj[l] = s_vdj;
        if sw {
            let av = 0.5 * (a.alpv[i] + a.alpv[j]);
            aij[l] = av;
            bij[l] = beta * (av / a.amax);
        } else {
            aij[l] = alpha;
            bij[l] = beta;
        }
        hij[l] = 0.5 * (a.h[i] + a.h[j]);
        mc[l] = 0.5 * (a.c[i] + a.c[j]);
        mrho[l] = 0.5 * (a.rho[i] + a.rho[j]);
    }
    // Π of every pair, masked to +0 where the pair recedes; vd becomes ½ Π v·∇W
    for l in 0..len {
        let hv = hij[l];
        let muv = hv * vr[l] / (r2[l] + (etq * hv) * (etq * hv));
        let piv = (bij[l] * muv - aij[l] * mc[l]) * muv / mrho[l];
        let on = 0u64.wrapping_sub((vr[l] < 0.0) as u64);
        r2[l] = f64::from_bits((-muv).to_bits() & on);
        let de = 0.5 * piv * vd[l];
        let dej = 0.5 * piv * vdj[l];
        hij[l] = f64::from_bits(piv.to_bits() & on);
        vd[l] = f64::from_bits(de.to_bits() & on);
        vdj[l] = f64::from_bits(dej.to_bits() & on);
        vr[l] = f64::from_bits(on);
    }
    for l in 0..len {
        let g = &a.dwdx[D * (k0 + l)..D * (k0 + l) + D];
        let on = vr[l].to_bits();
        for d in 0..D {
            t[s * l + d] = f64::from_bits((-(hij[l] * g[d])).to_bits() & on);
        }
        t[s * l + D] = vd[l];
        if rz {
            t[s * l + D + 1] = vdj[l];
        }
        t[s * l + W] = r2[l];
    }
}

fn run<const D: usize, const W: usize>(a: &mut Monaghan) {
    let pl = a.pairs;
    let np = pl.len();
    let inp = In {
        pi: &pl.i,
        pj: &pl.j,
        dwdx: a.dwdx,
        x: a.x,
        v: a.v,
        h: a.h,
        rho: a.rho,
        c: a.c,
        rinv: a.rinv,
        alpv: a.alpv,
        amax: a.amax,
        coef: a.coef,
    };
    let mut guard = pl.scratch.lock();
    let buf = &mut *guard;
    // per pair: the W terms, then −μ (+0 where it recedes), for the viscous signal speed
    buf.pair.resize((W + 1) * np, 0.0);
    buf.per_thread.ensure();
    let tls = &buf.per_thread;
    // pair terms: −Π ∇W (the i end gets + m_j t, the j end − m_i t), then ½ Π v·∇W; in blocks of
    // pairs, the gathers first (into a per-thread array), then the arithmetic over it
    let body = |b: usize, t: &mut [f64]| {
        tls.with(NV * (t.len() / (W + 1)), |tmp| block::<D, W>(&inp, CHUNK * b, t, tmp))
    };
    let tc = &mut buf.pair[..(W + 1) * np];
    if serial() {
        tc.chunks_mut((W + 1) * CHUNK).enumerate().for_each(|(b, t)| body(b, t));
    } else {
        tc.par_chunks_mut((W + 1) * CHUNK).enumerate().for_each(|(b, t)| body(b, t));
    }
    // the sums, and the largest −μ over each particle's pairs (a maximum: independent of the
    // order)
    let nt = a.mass.len();
    gather_signed_max::<D, W>(pl, &buf.pair, W + 1, a.mass, None, a.dvdt, a.dedt, &mut a.mumax[..nt]);
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
