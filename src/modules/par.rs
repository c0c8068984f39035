//! Parallel loops of the Rust twins. Rows (particles) or pairs are split into fixed tasks of
//! [`CHUNK`] rows; every row is computed whole by one task and writes only its own slot, so results
//! never depend on the thread count. With one thread in the pool the loops run inline.

use super::{nnps, ranks};

/// Rows (particles) or pairs per rayon task. At 10^4 particles a finer split costs more in task
/// hand-offs than it gains; results never depend on it (every row is computed whole by one task).
pub(crate) const CHUNK: usize = 512;

/// True when the current pool has one thread: the loops below then run inline, without rayon.
#[inline]
pub(crate) fn serial() -> bool {
    rayon::current_num_threads() == 1
}

/// Runs `f(a, row)` over the rows of `out` (row `a` = particle `a`, `width` values), in parallel
/// over tasks of [`CHUNK`] rows: each call writes only its own row. Across processes
/// ([`super::ranks`]) each rank computes a block of the rows and the blocks are gathered.
pub(crate) fn par_rows<F>(out: &mut [f64], width: usize, f: F)
where
    F: Fn(usize, &mut [f64]) + Sync + Send,
{
    if width == 0 {
        return;
    }
    if out.len().is_multiple_of(width)
        && let Some((r, b, counts)) = ranks::block(out.len() / width)
    {
        ranks::whole(|| rows_from(&mut out[width * b.start..width * b.end], width, b.start, &f));
        ranks::gather(r, out, width, &counts);
        return;
    }
    ranks::whole(|| rows_from(out, width, 0, &f));
}

/// [`par_rows`] on this process over the rows of `out`, the first of which is row `first`.
fn rows_from<F>(out: &mut [f64], width: usize, first: usize, f: &F)
where
    F: Fn(usize, &mut [f64]) + Sync + Send,
{
    use rayon::prelude::*;
    let body = |c: usize, blk: &mut [f64]| {
        for (r, row) in blk.chunks_mut(width).enumerate() {
            f(first + c * CHUNK + r, row);
        }
    };
    if serial() {
        out.chunks_mut(width * CHUNK).enumerate().for_each(|(c, blk)| body(c, blk));
    } else {
        out.par_chunks_mut(width * CHUNK).enumerate().for_each(|(c, blk)| body(c, blk));
    }
}

/// Makes a reused scratch buffer hold at least `n` values. It never shrinks: the stages that share
/// the pair list's scratch ask for different sizes in turn (the density 1 value per pair, the
/// force 4, the viscosity 5 in 3D), and `Vec::resize` would zero the growth at every turn; each
/// user writes every value of its own `[..n]` before it reads it.
pub(crate) fn grow(v: &mut Vec<f64>, n: usize) {
    if v.len() < n {
        v.resize(n, 0.0);
    }
}

/// As [`par_rows`] over two arrays with the same rows: `f(a, row1, row2)`, rows of `w1` and `w2`
/// values (`w2` may be 0: `row2` is then empty).
pub(crate) fn par_rows2<F>(out1: &mut [f64], w1: usize, out2: &mut [f64], w2: usize, f: F)
where
    F: Fn(usize, &mut [f64], &mut [f64]) + Sync + Send,
{
    if w1 == 0 {
        return;
    }
    if w2 == 0 {
        par_rows(out1, w1, |a, r1| f(a, r1, &mut []));
        return;
    }
    let rows = out1.len() / w1;
    let out2 = &mut out2[..w2 * rows];
    if out1.len().is_multiple_of(w1)
        && let Some((r, b, counts)) = ranks::block(rows)
    {
        let (b1, b2) = (&mut out1[w1 * b.start..w1 * b.end], &mut out2[w2 * b.start..w2 * b.end]);
        ranks::whole(|| rows2_from(b1, w1, b2, w2, b.start, &f));
        ranks::gather(r, out1, w1, &counts);
        ranks::gather(r, out2, w2, &counts);
        return;
    }
    ranks::whole(|| rows2_from(out1, w1, out2, w2, 0, &f));
}

/// [`par_rows2`] on this process, the first row being row `first`.
fn rows2_from<F>(out1: &mut [f64], w1: usize, out2: &mut [f64], w2: usize, first: usize, f: &F)
where
    F: Fn(usize, &mut [f64], &mut [f64]) + Sync + Send,
{
    use rayon::prelude::*;
    let body = |c: usize, b1: &mut [f64], b2: &mut [f64]| {
        let n = b1.len() / w1;
        for r in 0..n {
            f(first + c * CHUNK + r, &mut b1[w1 * r..w1 * r + w1], &mut b2[w2 * r..w2 * r + w2]);
        }
    };
    if serial() {
        out1.chunks_mut(w1 * CHUNK)
            .zip(out2.chunks_mut(w2 * CHUNK))
            .enumerate()
            .for_each(|(c, (b1, b2))| body(c, b1, b2));
    } else {
        out1.par_chunks_mut(w1 * CHUNK)
            .zip(out2.par_chunks_mut(w2 * CHUNK))
            .enumerate()
            .for_each(|(c, (b1, b2))| body(c, b1, b2));
    }
}

/// Calls `$f::<D, W>($args)` with D = `$dim` (1, 2 or 3) and W = D + `$extra` (0, 1 or 2): the pair
/// loops are monomorphised over the dimension, so their short inner loops are unrolled.
macro_rules! by_dim {
    ($dim:expr, 0, $f:ident($($args:expr),* $(,)?)) => {
        match $dim {
            1 => $f::<1, 1>($($args),*),
            2 => $f::<2, 2>($($args),*),
            _ => $f::<3, 3>($($args),*),
        }
    };
    ($dim:expr, 1, $f:ident($($args:expr),* $(,)?)) => {
        match $dim {
            1 => $f::<1, 2>($($args),*),
            2 => $f::<2, 3>($($args),*),
            _ => $f::<3, 4>($($args),*),
        }
    };
    ($dim:expr, 2, $f:ident($($args:expr),* $(,)?)) => {
        match $dim {
            1 => $f::<1, 3>($($args),*),
            2 => $f::<2, 4>($($args),*),
            _ => $f::<3, 5>($($args),*),
        }
    };
}
pub(crate) use by_dim;

/// The gather of a pair sum whose pair k holds W terms `t` (a reused buffer): for every particle
/// `a`, over its pairs in ascending pair order, `acc += m_j t[0..D]` where `a` is the pair's i and
/// `acc −= m_i t[0..D]` where it is the j (written as `+= (−m_i) t`, the same IEEE operation), and,
/// when W = D + 1, `e += m_other t[D]`; when W = D + 2, `e += m_other t[D]` at the i end and
/// `e += m_other t[D + 1]` at the j end. Rows are `acc` (D values) and `e` (one value, or none
/// when W = D); `scale` multiplies `acc` at the end.
pub(crate) fn gather_signed<const D: usize, const W: usize>(
    pl: &nnps::PairList,
    terms: &[f64],
    mass: &[f64],
    scale: Option<f64>,
    acc: &mut [f64],
    e: &mut [f64],
) {
    gather_signed_max::<D, W, false>(pl, terms, W, mass, scale, Sums { acc, e, mx: &mut [] }, (&[], 0));
}

/// [`gather_signed`] with W = D + 1 whose energy term is completed by a per-particle factor of
/// the receiving end: `e += m_other (f_a t[D])` at either end a, f_a = `own[stride a]` (the
/// product formed first, as a pair term f_a t[D] would have been: the same IEEE operations).
pub(crate) fn gather_signed_own<const D: usize, const W: usize>(
    pl: &nnps::PairList,
    terms: &[f64],
    mass: &[f64],
    own: &[f64],
    stride: usize,
    acc: &mut [f64],
    e: &mut [f64],
) {
    assert!(W == D + 1, "a per-particle energy factor needs one energy column");
    gather_signed_max::<D, W, true>(pl, terms, W, mass, None, Sums { acc, e, mx: &mut [] }, (own, stride));
}

/// What a gather writes per particle: the D-vector sums `acc`, the energy sums `e` (one per
/// particle when W > D) and the maxima `mx` (one per particle, or empty).
pub(crate) struct Sums<'a> {
    pub acc: &'a mut [f64],
    pub e: &'a mut [f64],
    pub mx: &'a mut [f64],
}

/// [`gather_signed`] over pair rows of `s` ≥ W values (the terms first); when s > W and `mx` is
/// not empty, also `mx[a]` = the largest `t[W]` over particle a's pairs, from +0 (`t[W] > m`
/// replaces m: a maximum, whatever the order). OWN: the energy term times the receiving end's
/// `own.0[own.1 a]` ([`gather_signed_own`]); a const, so that the other gathers' loops carry no
/// test for it.
pub(crate) fn gather_signed_max<const D: usize, const W: usize, const OWN: bool>(
    pl: &nnps::PairList,
    terms: &[f64],
    s: usize,
    mass: &[f64],
    scale: Option<f64>,
    out: Sums,
    own: (&[f64], usize),
) {
    let Sums { acc, e, mx } = out;
    assert!(s >= W, "pair rows of {s} values, fewer than the {W} terms");
    let with_max = s > W && !mx.is_empty();
    let body = |a: usize, acc: &mut [f64], e: &mut [f64], mx: &mut [f64]| {
        let mut sa = [0.0f64; D];
        let mut se = 0.0;
        let mut sm = 0.0f64;
        let fa = if OWN { own.0[own.1 * a] } else { 0.0 };
        let inc = pl.incident(a);
        // the listed ends (the j ends of a canonical list), then the row of pairs with a as i
        for r in inc.list {
            let k = r.pair();
            let t = &terms[s * k..s * k + s];
            let m = mass[r.other()];
            let ms = if r.is_i() { m } else { -m };
            for d in 0..D {
                sa[d] += ms * t[d];
            }
            if W > D {
                let te = t[if W > D + 1 && !r.is_i() { D + 1 } else { D }];
                se += m * if OWN { fa * te } else { te };
            }
            if with_max && t[W] > sm {
                sm = t[W];
            }
        }
        for k in inc.rows {
            let t = &terms[s * k..s * k + s];
            let m = mass[inc.pj[k] as usize];
            for d in 0..D {
                sa[d] += m * t[d];
            }
            if W > D {
                se += m * if OWN { fa * t[D] } else { t[D] };
            }
            if with_max && t[W] > sm {
                sm = t[W];
            }
        }
        match scale {
            Some(s) => {
                for d in 0..D {
                    acc[d] = s * sa[d];
                }
            }
            None => acc.copy_from_slice(&sa),
        }
        if W > D {
            e[0] = se;
        }
        if with_max {
            mx[0] = sm;
        }
    };
    let n = mass.len();
    let we = if W > D { 1 } else { 0 };
    let wm = if with_max { 1 } else { 0 };
    par_rows3(&mut acc[..D * n], D, &mut e[..we * n], we, &mut mx[..wm * n], wm, body);
}

/// As [`par_rows`] over three arrays with the same rows: `f(a, row1, row2, row3)`, rows of `w1`,
/// `w2` and `w3` values (`w2` and `w3` may be 0: those rows are then empty).
pub(crate) fn par_rows3<F>(out1: &mut [f64], w1: usize, out2: &mut [f64], w2: usize, out3: &mut [f64], w3: usize, f: F)
where
    F: Fn(usize, &mut [f64], &mut [f64], &mut [f64]) + Sync + Send,
{
    if w1 == 0 {
        return;
    }
    let rows = out1.len() / w1;
    let (out2, out3) = (&mut out2[..w2 * rows], &mut out3[..w3 * rows]);
    if out1.len().is_multiple_of(w1)
        && let Some((r, b, counts)) = ranks::block(rows)
    {
        let (s, e) = (b.start, b.end);
        let outs = [(&mut out1[w1 * s..w1 * e], w1), (&mut out2[w2 * s..w2 * e], w2), (&mut out3[w3 * s..w3 * e], w3)];
        ranks::whole(|| rows3_from(outs, s, &f));
        ranks::gather(r, out1, w1, &counts);
        ranks::gather(r, out2, w2, &counts);
        ranks::gather(r, out3, w3, &counts);
        return;
    }
    ranks::whole(|| rows3_from([(out1, w1), (out2, w2), (out3, w3)], 0, &f));
}

/// [`par_rows3`] on this process over three (array, width) pairs, the first row being row `first`.
fn rows3_from<F>(outs: [(&mut [f64], usize); 3], first: usize, f: &F)
where
    F: Fn(usize, &mut [f64], &mut [f64], &mut [f64]) + Sync + Send,
{
    use rayon::prelude::*;
    let [(out1, w1), (out2, w2), (out3, w3)] = outs;
    let rows = out1.len() / w1;
    let body = |c: usize, b1: &mut [f64], b2: &mut [f64], b3: &mut [f64]| {
        let n = b1.len() / w1;
        for r in 0..n {
            let (r1, r2, r3) =
                (&mut b1[w1 * r..w1 * r + w1], &mut b2[w2 * r..w2 * r + w2], &mut b3[w3 * r..w3 * r + w3]);
            f(first + c * CHUNK + r, r1, r2, r3);
        }
    };
    // (an empty array gives one empty chunk per chunk of the first)
    let nchunk = rows.div_ceil(CHUNK);
    fn split(o: &mut [f64], w: usize, nchunk: usize) -> Vec<&mut [f64]> {
        if w == 0 { (0..nchunk).map(|_| <&mut [f64]>::default()).collect() } else { o.chunks_mut(w * CHUNK).collect() }
    }
    let (c2, c3) = (split(out2, w2, nchunk), split(out3, w3, nchunk));
    if serial() {
        out1.chunks_mut(w1 * CHUNK).zip(c2).zip(c3).enumerate().for_each(|(c, ((b1, b2), b3))| body(c, b1, b2, b3));
    } else {
        out1.par_chunks_mut(w1 * CHUNK)
            .zip(c2.into_par_iter())
            .zip(c3.into_par_iter())
            .enumerate()
            .for_each(|(c, ((b1, b2), b3))| body(c, b1, b2, b3));
    }
}

/// x^n as a product of n factors, left to right (the Fortran twins write integer powers the same
/// way, never as `x**n`).
#[inline]
pub(crate) fn ipow(x: f64, n: i32) -> f64 {
    let mut y = 1.0;
    for _ in 0..n {
        y *= x;
    }
    y
}

/// Fortran's `min(a, b)` as gfortran evaluates it for non-NaN arguments: `a` unless `b` is
/// smaller (the Rust twins use it wherever their Fortran twin writes `min`).
#[inline]
pub(crate) fn fmin(a: f64, b: f64) -> f64 {
    if b < a { b } else { a }
}

/// Fortran's `max(a, b)` for non-NaN arguments: `a` unless `b` is larger.
#[inline]
pub(crate) fn fmax(a: f64, b: f64) -> f64 {
    if b > a { b } else { a }
}

/// The pairs `0..np` that `keep` selects, found in parallel per fixed chunk of [`CHUNK`] pairs
/// into the scratch's per-task lists: the lists of the chunks in order, each in pair order (so
/// a loop over them visits the selected pairs in pair order, whatever the thread count).
pub(crate) fn select_pairs(
    buf: &mut crate::state::pair_list::Bufs,
    np: usize,
    keep: impl Fn(usize) -> bool + Sync,
) -> &[Vec<u32>] {
    use rayon::prelude::*;
    let ntask = np.div_ceil(CHUNK);
    if buf.idx_tasks.len() < ntask {
        buf.idx_tasks.resize_with(ntask, Vec::new);
    }
    let find = |(t, b): (usize, &mut Vec<u32>)| {
        b.clear();
        b.extend((CHUNK * t..(CHUNK * t + CHUNK).min(np)).filter(|&k| keep(k)).map(|k| k as u32));
    };
    if serial() {
        buf.idx_tasks[..ntask].iter_mut().enumerate().for_each(find);
    } else {
        buf.idx_tasks[..ntask].par_iter_mut().enumerate().for_each(find);
    }
    &buf.idx_tasks[..ntask]
}
