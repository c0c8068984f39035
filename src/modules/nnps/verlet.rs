//! Verlet candidate lists kept between calls of the Rust cell search.

use super::{PairList, Verlet};
use super::rust::{Out, grid_dims, offsets, rust_cell, rust_cell_d, tasks, trim_box};
use crate::modules::{CHUNK, serial};
use rayon::prelude::*;


/// A pair as a sort key, and the key's row (its i).
#[inline]
fn key(i: usize, j: usize) -> u64 {
    ((i as u64) << 32) | j as u64
}

#[inline]
fn row(k: u64) -> usize {
    (k >> 32) as usize
}

/// The skin in units of the mean h: 0.5 in 1D and 2D; 0.2 in 3D, where the candidates grow as
/// (1 + s/(κh))³ (at 0.5 there were 2.5 candidates per pair). Measured on
/// surface_loose_tnt1kg_3d (110 592 particles, 316 steps, 1 thread): the search took 19.4–19.6 s
/// at 0.5 (6 rebuilds), 17.4–17.6 s at 0.3 (9), 14.0–14.7 s at 0.2 (13), 14.6 s at 0.15 (18),
/// 14.8 s at 0.1 (26). The skin changes the speed only: the list is canonical.
const fn skin_factor(dim: usize) -> f64 {
    if dim == 3 { 0.2 } else { 0.5 }
}

/// Fast threshold, as a fraction of the skin (below 1/2, so two slow drifts stay under the skin
/// with a margin far above rounding).
const FAST: f64 = 0.45;

pub(super) fn verlet(dim: usize, nreal: usize, x: &[f64], h: &[f64], kappa: f64, pl: &mut PairList) {
    match dim {
        1 => verlet_d::<1>(nreal, x, h, kappa, pl),
        2 => verlet_d::<2>(nreal, x, h, kappa, pl),
        _ => verlet_d::<3>(nreal, x, h, kappa, pl),
    }
}

fn verlet_d<const D: usize>(nreal: usize, x: &[f64], h: &[f64], kappa: f64, pl: &mut PairList) {
    let nt = h.len();
    let hreal = &h[..nreal];
    // anything outside the plain case (no particles, odd h or κ, non-finite values) goes to the
    // cell search, which has its own fallbacks
    // (per fixed chunk, combined in order: the same values whatever the thread count)
    let part = |c: usize| -> (f64, bool) {
        let (a0, a1) = (CHUNK * c, (CHUNK * c + CHUNK).min(nt));
        let ok = x[D * a0..D * a1].iter().all(|v| v.is_finite()) && h[a0..a1].iter().all(|v| v.is_finite() && *v > 0.0);
        (h[a0..a1.min(nreal).max(a0)].iter().sum(), ok)
    };
    let nchunk_t = nt.div_ceil(CHUNK);
    let parts: Vec<(f64, bool)> =
        if serial() { (0..nchunk_t).map(part).collect() } else { (0..nchunk_t).into_par_iter().map(part).collect() };
    let hsum: f64 = parts.iter().map(|p| p.0).sum();
    let plain = nreal > 0 && kappa > 0.0 && kappa.is_finite() && parts.iter().all(|p| p.1);
    if !plain {
        pl.invalidate();
        return rust_cell(D, nreal, x, h, kappa, pl);
    }
    let mut v = std::mem::take(&mut pl.scratch.get_mut().verlet);
    // drift since the last rebuild, and the fast particles
    let mut rebuild = !(v.valid && v.nreal == nreal && v.dim == D && v.kappa == kappa);
    if !rebuild {
        let lim = FAST * v.skin;
        v.fast.resize(nreal, 0);
        let (xb, hb) = (&v.xb, &v.hb);
        let mark = |(c, f): (usize, &mut [u8])| {
            for (l, fl) in f.iter_mut().enumerate() {
                let a = CHUNK * c + l;
                let mut d2 = 0.0;
                for d in 0..D {
                    let dd = x[d + D * a] - xb[d + D * a];
                    d2 += dd * dd;
                }
                let drift = d2.sqrt() + 0.5 * kappa * (h[a] - hb[a]).max(0.0);
                // a NaN drift counts as fast
                *fl = u8::from(drift.is_nan() || drift > lim);
            }
        };
        if serial() {
            v.fast.chunks_mut(CHUNK).enumerate().for_each(mark);
        } else {
            v.fast.par_chunks_mut(CHUNK).enumerate().for_each(mark);
        }
        v.fast_list.clear();
        v.fast_list.extend((0..nreal as u32).filter(|&a| v.fast[a as usize] != 0));
        rebuild = v.fast_list.len() > nreal / 32;
    }
    if rebuild {
        v.skin = skin_factor(D) * (hsum / nreal as f64);
        v.hraise.clear();
        v.hraise.extend(hreal.iter().map(|&a| a + v.skin / kappa));
        let s = pl.scratch.get_mut();
        rust_cell_d::<D>(nreal, &x[..D * nreal], &v.hraise, kappa, s, Out::Rows(&mut v.cstart, &mut v.cand));
        // the per-task buffers held every candidate: given back until the next rebuild
        s.pair_tasks = Vec::new();
        v.xb.clear();
        v.xb.extend_from_slice(&x[..D * nreal]);
        v.hb.clear();
        v.hb.extend_from_slice(hreal);
        v.fast.clear();
        v.fast.resize(nreal, 0);
        v.fast_list.clear();
        v.nreal = nreal;
        v.dim = D;
        v.kappa = kappa;
        v.valid = true;
        v.builds += 1;
    }
    let test = |i: usize, j: usize| within::<D>(x, h, kappa, i, j);
    // 1. the candidates between slow particles, filtered by the exact test
    v.keep.resize(v.cand.len(), 0);
    {
        let (cstart, cand, fast) = (&v.cstart, &v.cand, &v.fast);
        let rows = |(c, keep): (usize, &mut [u8])| {
            let k0 = CHUNK * c;
            // the row of the first candidate of this chunk, then walk forward
            let mut i = cstart.partition_point(|&s| (s as usize) <= k0) - 1;
            for (l, kp) in keep.iter_mut().enumerate() {
                let k = k0 + l;
                while cstart[i + 1] as usize <= k {
                    i += 1;
                }
                let j = cand[k] as usize;
                *kp = u8::from(fast[i] == 0 && fast[j] == 0 && test(i, j));
            }
        };
        if serial() {
            v.keep.chunks_mut(CHUNK).enumerate().for_each(rows);
        } else {
            v.keep.par_chunks_mut(CHUNK).enumerate().for_each(rows);
        }
    }
    // 2. pairs with a fast particle or a mirror, searched in a grid over the real particles
    extra_pairs::<D>(&mut v, x, h, kappa, (nreal, hsum));
    // 3. the canonical list: per row, the kept candidates and the extra pairs, merged by j; the
    //    rows in chunks, each writing its own slice of the list
    canonical(&mut v, nreal, pl);
    pl.scratch.get_mut().verlet = v;
}

/// The exact test of a pair: r_ij < κ (h_i + h_j)/2.
#[inline]
fn within<const D: usize>(x: &[f64], h: &[f64], kappa: f64, i: usize, j: usize) -> bool {
    let mut r2 = 0.0;
    for d in 0..D {
        let dxd = x[d + D * i] - x[d + D * j];
        r2 += dxd * dxd;
    }
    let s = kappa * (0.5 * (h[i] + h[j]));
    r2 < s * s
}

/// Step 2 of [`verlet_d`]: the pairs of a fast particle or a mirror with the real particles,
/// searched in a grid of cells κ h̄/2 wide (`hsum` the real particles' sum of h), sorted into
/// `v.extra`.
fn extra_pairs<const D: usize>(v: &mut Verlet, x: &[f64], h: &[f64], kappa: f64, (nreal, hsum): (usize, f64)) {
    let nt = h.len();
    let test = |i: usize, j: usize| within::<D>(x, h, kappa, i, j);
    v.extra.clear();
    let nsearch = v.fast_list.len() + (nt - nreal);
    if nsearch > 0 {
        let bbox = |c: usize| -> ([f64; 3], [f64; 3], f64) {
            let (mut lo, mut hi, mut hm) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3], 0.0f64);
            for a in CHUNK * c..(CHUNK * c + CHUNK).min(nreal) {
                for d in 0..D {
                    lo[d] = lo[d].min(x[d + D * a]);
                    hi[d] = hi[d].max(x[d + D * a]);
                }
                hm = hm.max(h[a]);
            }
            (lo, hi, hm)
        };
        let nchunk = nreal.div_ceil(CHUNK);
        let parts: Vec<_> =
            if serial() { (0..nchunk).map(bbox).collect() } else { (0..nchunk).into_par_iter().map(bbox).collect() };
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let mut hmax: f64 = 0.0;
        for (plo, phi, pm) in parts {
            for d in 0..D {
                lo[d] = lo[d].min(plo[d]);
                hi[d] = hi[d].max(phi[d]);
            }
            hmax = hmax.max(pm);
        }
        let cs = 0.5 * kappa * (hsum / nreal as f64);
        trim_box::<D>(x, nreal, cs, &mut lo, &mut hi, &mut v.trim);
        let (inv, nc) = grid_dims::<D>(&lo, &hi, cs, nreal);
        let ncell = nc[0] * nc[1] * nc[2];
        let cell_at = |p: &[f64]| -> [usize; 3] {
            let mut c = [0usize; 3];
            for d in 0..D {
                let k = ((p[d] - lo[d]) * inv) as isize;
                c[d] = k.clamp(0, nc[d] as isize - 1) as usize;
            }
            c
        };
        v.gcell.resize(nreal, 0);
        let cells = |(c, out): (usize, &mut [u32])| {
            for (l, o) in out.iter_mut().enumerate() {
                let a = CHUNK * c + l;
                let q = cell_at(&x[D * a..D * a + D]);
                *o = (q[0] + nc[0] * (q[1] + nc[1] * q[2])) as u32;
            }
        };
        if serial() {
            v.gcell.chunks_mut(CHUNK).enumerate().for_each(cells);
        } else {
            v.gcell.par_chunks_mut(CHUNK).enumerate().for_each(cells);
        }
        offsets(&mut v.gstart, ncell, v.gcell.iter().map(|&c| c as usize));
        v.gorder.resize(nreal, 0);
        v.gfill.clear();
        v.gfill.extend_from_slice(&v.gstart[..ncell]);
        for (a, &c) in v.gcell.iter().enumerate() {
            v.gorder[v.gfill[c as usize] as usize] = a as u32;
            v.gfill[c as usize] += 1;
        }
        let (gstart, gorder, fast, fast_list) = (&v.gstart, &v.gorder, &v.fast, &v.fast_list);
        // searcher a (a fast real particle, or a mirror): every real partner b in its box
        let around = |a: usize, buf: &mut Vec<u64>| {
            let rad = kappa * (0.5 * (h[a] + hmax));
            let rad = rad + rad * 1e-9;
            let mut clo = [0usize; 3];
            let mut chi = [0usize; 3];
            for d in 0..D {
                let k0 = ((x[d + D * a] - rad - lo[d]) * inv) as isize;
                let k1 = ((x[d + D * a] + rad - lo[d]) * inv) as isize;
                clo[d] = k0.clamp(0, nc[d] as isize - 1) as usize;
                chi[d] = k1.clamp(0, nc[d] as isize - 1) as usize;
            }
            for z in clo[2]..=chi[2] {
                for y in clo[1]..=chi[1] {
                    let row = nc[0] * (y + nc[1] * z);
                    for &b in &gorder[gstart[row + clo[0]] as usize..gstart[row + chi[0] + 1] as usize] {
                        let b = b as usize;
                        // a fast-fast pair is kept by its first particle only
                        if b == a || (a < nreal && fast[b] != 0 && b < a) {
                            continue;
                        }
                        let (i, j) = (a.min(b), a.max(b));
                        if test(i, j) {
                            buf.push(key(i, j));
                        }
                    }
                }
            }
        };
        let per = 64;
        let ntask = nsearch.div_ceil(per);
        let searcher = |t: usize| -> usize {
            if t < fast_list.len() { fast_list[t] as usize } else { nreal + (t - fast_list.len()) }
        };
        tasks(&mut v.extra_tasks, ntask, |t, buf| {
            for q in per * t..(per * t + per).min(nsearch) {
                around(searcher(q), buf);
            }
        });
        for b in &v.extra_tasks[..ntask] {
            v.extra.extend_from_slice(b);
        }
        if serial() {
            v.extra.sort_unstable();
        } else {
            v.extra.par_sort_unstable();
        }
    }
}

/// Step 3 of [`verlet_d`]: the canonical list into `pl`, per row the kept candidates and the
/// extra pairs merged by j; the rows in chunks, each writing its own slice of the list.
fn canonical(v: &mut Verlet, nreal: usize, pl: &mut PairList) {
    let nchunk = nreal.div_ceil(CHUNK);
    v.off.clear();
    v.off.resize(nreal + 1, 0);
    {
        let (keep, cstart, extra) = (&v.keep, &v.cstart, &v.extra);
        let count = |(c, out): (usize, &mut [u32])| {
            let a0 = CHUNK * c;
            let mut e = extra.partition_point(|&p| row(p) < a0);
            for (l, o) in out.iter_mut().enumerate() {
                let a = a0 + l;
                let mut n = keep[cstart[a] as usize..cstart[a + 1] as usize].iter().filter(|&&k| k != 0).count();
                while e < extra.len() && row(extra[e]) == a {
                    n += 1;
                    e += 1;
                }
                *o = n as u32;
            }
        };
        let counts = &mut v.off[1..];
        if serial() {
            counts.chunks_mut(CHUNK).enumerate().for_each(count);
        } else {
            counts.par_chunks_mut(CHUNK).enumerate().for_each(count);
        }
    }
    for a in 0..nreal {
        v.off[a + 1] += v.off[a];
    }
    let np = v.off[nreal] as usize;
    let PairList { i: pi, j: pj, .. } = pl;
    // (every slot is written below: no clearing, only the length set)
    pi.resize(np, 0);
    pj.resize(np, 0);
    let mut slices: Vec<(usize, &mut [i32], &mut [i32])> = Vec::with_capacity(nchunk);
    let (mut ri, mut rj) = (&mut pi[..], &mut pj[..]);
    for c in 0..nchunk {
        let len = (v.off[(CHUNK * c + CHUNK).min(nreal)] - v.off[CHUNK * c]) as usize;
        let (hi_, ti) = std::mem::take(&mut ri).split_at_mut(len);
        let (hj, tj) = std::mem::take(&mut rj).split_at_mut(len);
        slices.push((c, hi_, hj));
        ri = ti;
        rj = tj;
    }
    let (keep, cstart, cand, extra, off) = (&v.keep, &v.cstart, &v.cand, &v.extra, &v.off);
    let fill = |(c, si, sj): (usize, &mut [i32], &mut [i32])| {
        let a0 = CHUNK * c;
        let base = off[a0] as usize;
        let mut e = extra.partition_point(|&p| row(p) < a0);
        let mut w = 0usize;
        for a in a0..(a0 + CHUNK).min(nreal) {
            let (k0, k1) = (cstart[a] as usize, cstart[a + 1] as usize);
            let mut k = k0;
            while e < extra.len() && row(extra[e]) == a {
                let je = extra[e] as u32 as i32;
                while k < k1 && cand[k] < je {
                    if keep[k] != 0 {
                        si[w] = a as i32;
                        sj[w] = cand[k];
                        w += 1;
                    }
                    k += 1;
                }
                si[w] = a as i32;
                sj[w] = je;
                w += 1;
                e += 1;
            }
            while k < k1 {
                if keep[k] != 0 {
                    si[w] = a as i32;
                    sj[w] = cand[k];
                    w += 1;
                }
                k += 1;
            }
            debug_assert_eq!(base + w, off[a + 1] as usize);
        }
    };
    if serial() {
        slices.into_iter().for_each(fill);
    } else {
        slices.into_par_iter().for_each(fill);
    }
}

