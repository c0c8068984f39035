//! The Rust twin of the neighbour search: the direct search, and the owner-based cell search
//! (see the module's documentation) that the Verlet lists of `verlet.rs` call to rebuild.

use super::{PairList, Search, verlet};
use crate::modules::{CHUNK, serial};
use rayon::prelude::*;

/// Finds the pairs: the cell search keeps Verlet candidate lists between calls (`verlet.rs`).
pub(super) fn search(a: &mut Search) {
    let Search { cell, dim, nreal, x, h, kappa, pairs } = a;
    let (dim, kappa) = (*dim, *kappa);
    assert!(x.len() >= dim * h.len(), "nnps: x has {} values, need {}", x.len(), dim * h.len());
    let nreal = (*nreal).min(h.len());
    if *cell { verlet::verlet(dim, nreal, x, h, kappa, pairs) } else { rust_direct(dim, nreal, x, h, kappa, pairs) }
}

#[inline]
pub(super) fn within(dim: usize, x: &[f64], h: &[f64], kappa: f64, i: usize, j: usize) -> bool {
    let mut r2 = 0.0;
    for d in 0..dim {
        let dxd = x[d + dim * i] - x[d + dim * j];
        r2 += dxd * dxd;
    }
    let s = kappa * (0.5 * (h[i] + h[j]));
    r2 < s * s
}

/// Runs `f(task, buffer)` for `ntask` tasks, each with its own cleared buffer.
pub(super) fn tasks<T: Send, F>(bufs: &mut Vec<Vec<T>>, ntask: usize, f: F)
where
    F: Fn(usize, &mut Vec<T>) + Sync + Send,
{
    if bufs.len() < ntask {
        bufs.resize_with(ntask, Vec::new);
    }
    let run = |(t, b): (usize, &mut Vec<T>)| {
        b.clear();
        f(t, b)
    };
    if serial() {
        bufs[..ntask].iter_mut().enumerate().for_each(run);
    } else {
        bufs[..ntask].par_iter_mut().enumerate().for_each(run);
    }
}

pub(super) fn rust_direct(dim: usize, nreal: usize, x: &[f64], h: &[f64], kappa: f64, pl: &mut PairList) {
    let PairList { i: pi, j: pj, scratch, .. } = pl;
    direct_into(dim, nreal, x, h, kappa, scratch.get_mut(), (pi, pj));
}

fn direct_into(
    dim: usize,
    nreal: usize,
    x: &[f64],
    h: &[f64],
    kappa: f64,
    s: &mut super::Bufs,
    (pi, pj): (&mut Vec<i32>, &mut Vec<i32>),
) {
    let nt = h.len();
    let ntask = nreal.div_ceil(64);
    tasks(&mut s.pair_tasks, ntask, |t, buf| {
        for i in 64 * t..(64 * t + 64).min(nreal) {
            for j in i + 1..nt {
                if within(dim, x, h, kappa, i, j) {
                    buf.push([i as u32, j as u32]);
                }
            }
        }
    });
    pi.clear();
    pj.clear();
    for buf in &s.pair_tasks[..ntask] {
        for &[i, j] in buf {
            pi.push(i as i32);
            pj.push(j as i32);
        }
    }
}

/// Where the cell search puts the canonical pairs: a pair list, or (for the Verlet candidates)
/// rows: `start[a]..start[a + 1]` (`nreal + 1` offsets) of `cand`, the j of row a ascending.
pub(super) enum Out<'a> {
    List(&'a mut Vec<i32>, &'a mut Vec<i32>),
    Rows(&'a mut Vec<u32>, &'a mut Vec<i32>),
}

/// Two h are "similar" unless one exceeds the other times ONEP (an exact binary fraction).
const ONEP: f64 = 1.0 + 1.0 / 16.0;

/// A cell grid over the particles sorted by cell.
struct Grid<'a> {
    lo: [f64; 3],
    /// 1 / cell edge.
    inv: f64,
    nc: [usize; 3],
    start: &'a [u32],
    order: &'a [u32],
    xs: &'a [f64],
    hs: &'a [f64],
    kappa: f64,
    nreal: usize,
}

impl Grid<'_> {
    /// The pairs owned by the particles in `slots` (cell order), as [i, j] into `bufs[i / rows]`.
    fn find<const D: usize>(&self, slots: std::ops::Range<usize>, rows: usize, bufs: &mut [Vec<[u32; 2]>]) {
        let Grid { lo, inv, nc, start, order, xs, hs, kappa, nreal } = *self;
        for slot in slots {
            let a = order[slot] as usize;
            let ha = hs[slot];
            let xa: [f64; D] = xs[D * slot..D * slot + D].try_into().unwrap_or([0.0; D]);
            // the box holds every partner a owns: r < κ (h_a + h_b)/2 ≤ κ h_a ONEP
            let rad = kappa * (ha * ONEP);
            let rad = rad + rad * 1e-9;
            let mut clo = [0usize; 3];
            let mut chi = [0usize; 3];
            for d in 0..D {
                let k0 = ((xa[d] - rad - lo[d]) * inv) as isize;
                let k1 = ((xa[d] + rad - lo[d]) * inv) as isize;
                clo[d] = k0.clamp(0, nc[d] as isize - 1) as usize;
                chi[d] = k1.clamp(0, nc[d] as isize - 1) as usize;
            }
            let mut test = |sb: usize| {
                let b = order[sb] as usize;
                let i = a.min(b);
                if i >= nreal {
                    return;
                }
                let hb = hs[sb];
                let xb = &xs[D * sb..D * sb + D];
                // (x_i − x_j)² = (x_a − x_b)² and h_i + h_j = h_a + h_b, exactly
                let mut r2 = 0.0;
                for d in 0..D {
                    let dxd = xa[d] - xb[d];
                    r2 += dxd * dxd;
                }
                let sr = kappa * (0.5 * (ha + hb));
                if r2 < sr * sr {
                    bufs[i / rows].push([i as u32, a.max(b) as u32]);
                }
            };
            for z in clo[2]..=chi[2] {
                for y in clo[1]..=chi[1] {
                    let row = nc[0] * (y + nc[1] * z);
                    let (s0, s1) = (start[row + clo[0]] as usize, start[row + chi[0] + 1] as usize);
                    // later slots: a owns b unless b is clearly larger
                    for sb in s0.max(slot + 1)..s1 {
                        let b_larger = hs[sb] > ha * ONEP;
                        if b_larger {
                            continue;
                        }
                        test(sb);
                    }
                    // earlier slots: a owns b only if a is clearly larger (rarely any)
                    let back = s0..s1.min(slot).max(s0);
                    if hs[back.clone()].iter().any(|&hb| ha > hb * ONEP) {
                        for sb in back {
                            if ha > hs[sb] * ONEP {
                                test(sb);
                            }
                        }
                    }
                }
            }
        }
    }
}

/// The cell search: a uniform grid of edge ≈ κ h̄/2 (h̄ the mean h), particles sorted by cell
/// (counting sort, ascending index within a cell); each particle looks through the cells that
/// meet the box of half-width κ h_a around it and keeps the pairs it owns.
pub(super) fn rust_cell(dim: usize, nreal: usize, x: &[f64], h: &[f64], kappa: f64, pl: &mut PairList) {
    let PairList { i, j, scratch, .. } = pl;
    let (s, out) = (scratch.get_mut(), Out::List(i, j));
    match dim {
        1 => rust_cell_d::<1>(nreal, x, h, kappa, s, out),
        2 => rust_cell_d::<2>(nreal, x, h, kappa, s, out),
        _ => rust_cell_d::<3>(nreal, x, h, kappa, s, out),
    }
}

/// CSR offsets of `n` bins from the bin of each item (a counting sort's first half):
/// `out[b]..out[b + 1]` is the range of bin b.
pub(super) fn offsets(out: &mut Vec<u32>, n: usize, bins: impl Iterator<Item = usize>) {
    out.clear();
    out.resize(n + 1, 0);
    for b in bins {
        out[b + 1] += 1;
    }
    for b in 0..n {
        out[b + 1] += out[b];
    }
}

/// The grid over the box lo…hi with cells of side `cs` (m), doubled until there are no more than
/// a few cells per particle (sparse clouds): 1/side and the cells per axis.
pub(super) fn grid_dims<const D: usize>(lo: &[f64; 3], hi: &[f64; 3], cs: f64, n: usize) -> (f64, [usize; 3]) {
    let mut cs = cs;
    loop {
        let mut prod: u64 = 1;
        for d in 0..D {
            prod = prod.saturating_mul((((hi[d] - lo[d]) / cs) as u64).saturating_add(1));
        }
        if prod <= (4 * n as u64).max(64) {
            break;
        }
        cs *= 2.0;
    }
    let inv = 1.0 / cs;
    let mut nc = [1usize; 3];
    for d in 0..D {
        nc[d] = (((hi[d] - lo[d]) * inv) as usize).saturating_add(1);
    }
    (inv, nc)
}

/// When the bounding box lo…hi would need more than a few cells of edge `cs` per particle (a few
/// particles far from the rest: ejecta thrown metres above a crater a few decimetres wide), the
/// grid's box shrinks to the 1st … 99th percentile of the particles along each axis (2 cells of
/// margin): the others fall into its border cells. Every pair is still found (the cell map
/// clamps to the border, so it stays monotone in x and a box query still covers every partner),
/// while the cells keep their edge instead of doubling until the sparse box fits (ejecta
/// hundreds of metres up made a crater run's search 9 times slower: docs/performance.md, "Far
/// ejecta and the search grid").
/// `v` is scratch (kept by the caller: this runs every step of a run with far ejecta).
pub(super) fn trim_box<const D: usize>(
    x: &[f64],
    nt: usize,
    cs: f64,
    lo: &mut [f64; 3],
    hi: &mut [f64; 3],
    v: &mut Vec<f64>,
) {
    let cells = |lo: &[f64; 3], hi: &[f64; 3]| -> u64 {
        (0..D).fold(1u64, |p, d| p.saturating_mul((((hi[d] - lo[d]) / cs) as u64).saturating_add(1)))
    };
    let k = nt / 100;
    if k == 0 || cells(lo, hi) <= (4 * nt as u64).max(64) {
        return;
    }
    v.resize(nt, 0.0);
    for d in 0..D {
        for (i, c) in v.iter_mut().enumerate() {
            *c = x[d + D * i];
        }
        let a = *v.select_nth_unstable_by(k, f64::total_cmp).1;
        let b = *v.select_nth_unstable_by(nt - 1 - k, f64::total_cmp).1;
        if a.is_finite() && b.is_finite() {
            lo[d] = lo[d].max(a - 2.0 * cs);
            hi[d] = hi[d].min(b + 2.0 * cs);
        }
    }
}

pub(super) fn rust_cell_d<const D: usize>(nreal: usize, x: &[f64], h: &[f64], kappa: f64, s: &mut super::Bufs, out: Out) {
    let nt = h.len();
    let (mut pi, mut rstart, pj) = match out {
        Out::List(pi, pj) => (Some(pi), None, pj),
        Out::Rows(start, cand) => (None, Some(start), cand),
    };
    if let Some(pi) = pi.as_deref_mut() {
        pi.clear();
    }
    pj.clear();
    if let Some(st) = rstart.as_deref_mut() {
        st.clear();
        st.resize(nreal + 1, 0);
    }
    if nt == 0 || nreal == 0 {
        return;
    }
    // the grid: bounding box, smallest and mean h
    let (mut lo, mut hi, hsum, hmin) = grid_stats::<D>(x, h);
    if hmin < 0.0 || kappa.is_nan() || kappa < 0.0 {
        // the owner's box assumes h ≥ 0 and κ ≥ 0; anything else gets the direct search
        let mut tmp = Vec::new();
        direct_into(D, nreal, x, h, kappa, s, (pi.unwrap_or(&mut tmp), pj));
        if let Some(st) = rstart {
            offsets(st, nreal, tmp.iter().map(|&i| i as usize));
        }
        return;
    }
    let hmean = hsum / nt as f64;
    let mut cs = 0.5 * kappa * hmean;
    if !(cs > 0.0 && cs.is_finite()) {
        cs = (0..D).map(|d| hi[d] - lo[d]).fold(1.0, f64::max);
    }
    // (hs is filled below, after the grid is laid out: free until then)
    trim_box::<D>(x, nt, cs, &mut lo, &mut hi, &mut s.hs);
    let (inv, nc) = grid_dims::<D>(&lo, &hi, cs, nt);
    sort_into_cells::<D>(s, x, h, (&lo, inv, nc));
    // each particle (in cell order) finds the pairs it owns, into per-task buffers, one per
    // bucket of rows (the pair's i). The list is canonical whatever the split, so the split may
    // follow the thread count: a few tasks and buckets per thread keep the buffers O(threads²).
    let g = Grid { lo, inv, nc, start: &s.start, order: &s.order, xs: &s.xs, hs: &s.hs, kappa, nreal };
    let per = 4 * rayon::current_num_threads();
    let ntask = nt.div_ceil(CHUNK).min(per);
    let slots = nt.div_ceil(ntask);
    let nb = nreal.div_ceil(CHUNK).min(per);
    let rows = nreal.div_ceil(nb);
    if s.pair_tasks.len() < ntask * nb {
        s.pair_tasks.resize_with(ntask * nb, Vec::new);
    }
    let find = |(t, bufs): (usize, &mut [Vec<[u32; 2]>])| {
        bufs.iter_mut().for_each(Vec::clear);
        g.find::<D>(slots * t..(slots * t + slots).min(nt), rows, bufs);
    };
    let found = &mut s.pair_tasks[..ntask * nb];
    if serial() {
        found.chunks_mut(nb).enumerate().for_each(find);
    } else {
        found.par_chunks_mut(nb).enumerate().for_each(find);
    }
    // canonical order, bucket by bucket: a counting sort by i, then each row by j
    let found = &s.pair_tasks[..ntask * nb];
    let size = |b: usize| -> usize { (0..ntask).map(|t| found[t * nb + b].len()).sum() };
    let np: usize = (0..nb).map(size).sum();
    pj.resize(np, 0);
    // the rows of each bucket: their i in a list, or their lengths in `start[1..]`
    enum Ri<'a> {
        I(&'a mut [i32]),
        Len(&'a mut [u32]),
    }
    let mut parts: Vec<(usize, Ri, &mut [i32])> = Vec::with_capacity(nb);
    let mut rj = &mut pj[..];
    let mut ri = pi.map(|pi| {
        pi.resize(np, 0);
        &mut pi[..]
    });
    let mut rl = rstart.as_deref_mut().map(|st| &mut st[1..]);
    for b in 0..nb {
        let len = size(b);
        let (head_j, tail_j) = std::mem::take(&mut rj).split_at_mut(len);
        rj = tail_j;
        let r = match (ri.take(), rl.take()) {
            (Some(all), _) => {
                let (head, tail) = all.split_at_mut(len);
                ri = Some(tail);
                Ri::I(head)
            }
            (None, Some(all)) => {
                let (head, tail) = all.split_at_mut(rows.min(all.len()));
                rl = Some(tail);
                Ri::Len(head)
            }
            (None, None) => unreachable!("the cell search has an output"),
        };
        parts.push((b, r, head_j));
    }
    let place = |(b, ri, rj): (usize, Ri, &mut [i32])| {
        let a0 = rows * b;
        let nr = rows.min(nreal - a0);
        let mut cnt = vec![0u32; nr + 1];
        for t in 0..ntask {
            for &[i, _] in &found[t * nb + b] {
                cnt[i as usize - a0 + 1] += 1;
            }
        }
        for r in 0..nr {
            cnt[r + 1] += cnt[r];
        }
        let mut fill = cnt[..nr].to_vec();
        for t in 0..ntask {
            for &[i, j] in &found[t * nb + b] {
                let f = &mut fill[i as usize - a0];
                rj[*f as usize] = j as i32;
                *f += 1;
            }
        }
        let mut ri = ri;
        for r in 0..nr {
            let (r0, r1) = (cnt[r] as usize, cnt[r + 1] as usize);
            match &mut ri {
                Ri::I(ri) => ri[r0..r1].fill((a0 + r) as i32),
                Ri::Len(l) => l[r] = (r1 - r0) as u32,
            }
            rj[r0..r1].sort_unstable();
        }
    };
    if serial() {
        parts.into_iter().for_each(place);
    } else {
        parts.into_par_iter().for_each(place);
    }
    if let Some(st) = rstart {
        for a in 0..nreal {
            st[a + 1] += st[a];
        }
    }
}

/// The bounding box, the sum and the smallest of h over all particles, in tasks of CHUNK
/// particles (the partial sums added in task order, so h̄ does not depend on the thread count).
fn grid_stats<const D: usize>(x: &[f64], h: &[f64]) -> ([f64; 3], [f64; 3], f64, f64) {
    let nt = h.len();
    let stats = |c: usize| -> ([f64; 3], [f64; 3], f64, f64) {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let (mut hsum, mut hmin) = (0.0, f64::INFINITY);
        for i in CHUNK * c..(CHUNK * c + CHUNK).min(nt) {
            for d in 0..D {
                lo[d] = lo[d].min(x[d + D * i]);
                hi[d] = hi[d].max(x[d + D * i]);
            }
            hsum += h[i];
            hmin = hmin.min(h[i]);
        }
        (lo, hi, hsum, hmin)
    };
    let nchunk = nt.div_ceil(CHUNK);
    let parts: Vec<_> =
        if serial() { (0..nchunk).map(stats).collect() } else { (0..nchunk).into_par_iter().map(stats).collect() };
    let mut lo = [0.0f64; 3];
    let mut hi = [0.0f64; 3];
    lo[..D].fill(f64::INFINITY);
    hi[..D].fill(f64::NEG_INFINITY);
    let (mut hsum, mut hmin) = (0.0, f64::INFINITY);
    for (plo, phi, ps, pm) in parts {
        for d in 0..D {
            lo[d] = lo[d].min(plo[d]);
            hi[d] = hi[d].max(phi[d]);
        }
        hsum += ps;
        hmin = hmin.min(pm);
    }
    (lo, hi, hsum, hmin)
}

/// Every particle's cell of the grid (`lo`, 1/cell size `inv`, `nc` cells per axis), and the
/// particles sorted by cell: `s.start` (cell offsets), `s.order`, and their positions and h
/// copied in that order (`s.xs`, `s.hs`).
fn sort_into_cells<const D: usize>(s: &mut super::Bufs, x: &[f64], h: &[f64], (lo, inv, nc): (&[f64; 3], f64, [usize; 3])) {
    let nt = h.len();
    let ncell = nc[0] * nc[1] * nc[2];
    // a particle's cell; the box search below uses the same map, which is monotone in x
    let cell = |p: &[f64]| -> usize {
        let mut c = [0usize; 3];
        for d in 0..D {
            let k = ((p[d] - lo[d]) * inv) as isize;
            c[d] = k.clamp(0, nc[d] as isize - 1) as usize;
        }
        c[0] + nc[0] * (c[1] + nc[1] * c[2])
    };
    s.cell_of.resize(nt, 0);
    let cells = |(c, out): (usize, &mut [u32])| {
        for (l, o) in out.iter_mut().enumerate() {
            let i = CHUNK * c + l;
            *o = cell(&x[D * i..D * i + D]) as u32;
        }
    };
    if serial() {
        s.cell_of.chunks_mut(CHUNK).enumerate().for_each(cells);
    } else {
        s.cell_of.par_chunks_mut(CHUNK).enumerate().for_each(cells);
    }
    offsets(&mut s.start, ncell, s.cell_of.iter().map(|&c| c as usize));
    let start = &s.start;
    let fill = &mut s.fill;
    fill.clear();
    fill.extend_from_slice(&start[..ncell]);
    s.order.resize(nt, 0);
    s.xs.resize(D * nt, 0.0);
    s.hs.resize(nt, 0.0);
    let (order, xs, hs) = (&mut s.order[..], &mut s.xs[..], &mut s.hs[..]);
    for (i, (p, &c)) in x[..D * nt].chunks_exact(D).zip(&s.cell_of).enumerate() {
        let f = &mut fill[c as usize];
        let slot = *f as usize;
        *f += 1;
        order[slot] = i as u32;
        xs[D * slot..D * slot + D].copy_from_slice(p);
        hs[slot] = h[i];
    }
}
