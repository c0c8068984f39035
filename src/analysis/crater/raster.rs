//! The raster of soil occupancy a crater's voids are read on, and the ground surface of the
//! columns walked upward through it.

/// Soil occupancy on a raster of square (2D) or cubic (3D) cells of side `ds`, the last axis
/// vertical: a cell is solid where a soil particle lies within one cell size of its centre;
/// `open` marks the empty cells connected to the raster's border (the sky) through empty cells
/// sharing a face (a flood fill), the other empty cells are enclosed voids.
pub(super) struct Raster {
    /// Number of axes (2 or 3).
    pub(super) d: usize,
    /// Lower corner (m) and cells along each axis (1 along the axes beyond `d`).
    pub(super) lo: [f64; 3],
    pub(super) n: [usize; 3],
    pub(super) ds: f64,
    pub(super) solid: Vec<bool>,
    pub(super) open: Vec<bool>,
}

impl Raster {
    /// The raster of the points whose coordinates along each axis are `pts[axis]` (2 or 3 axes,
    /// the last vertical), covering `lims[axis]` (m) and two cells more on every side. The
    /// margin below the limits, and the margins beside them below the height `ground` (m), are
    /// solid: beyond the measured soil the ground is taken to go on (a wall of the box, or soil
    /// the scene does not model), so a crack in the soil that reaches its side or bottom is not
    /// open to the sky there.
    pub(super) fn new(pts: &[&[f64]], ds: f64, lims: &[(f64, f64)], ground: f64) -> Raster {
        let d = pts.len().min(3);
        let (mut lo, mut n) = ([0.0; 3], [1usize; 3]);
        for a in 0..d {
            lo[a] = lims[a].0 - 2.0 * ds;
            // (cells to the limits' span, an exact multiple of ds within rounding not rounded up
            // to one more: that column, outside the soil and inside the margin, was a void)
            let m = (lims[a].1 - lims[a].0) / ds;
            let cells = if (m - m.round()).abs() <= 1e-9 * m.abs().max(1.0) { m.round() } else { m.ceil() };
            n[a] = (cells as usize + 4).max(1);
        }
        let stride = [1, n[0], n[0] * n[1]];
        let total = n[0] * n[1] * n[2];
        let mut solid = vec![false; total];
        'points: for i in 0..pts[0].len() {
            let mut iu = [0i64; 3];
            for a in 0..d {
                let u = (pts[a][i] - lo[a]) / ds;
                if u < -1.0 || u > n[a] as f64 + 1.0 {
                    continue 'points;
                }
                iu[a] = u.floor() as i64;
            }
            'cells: for o in 0..3usize.pow(d as u32) {
                let (mut k, mut r2, mut rest) = (0, 0.0, o);
                for a in 0..d {
                    let c = iu[a] + (rest % 3) as i64 - 1;
                    rest /= 3;
                    if c < 0 || c >= n[a] as i64 {
                        continue 'cells;
                    }
                    r2 += (lo[a] + (c as f64 + 0.5) * ds - pts[a][i]).powi(2);
                    k += c as usize * stride[a];
                }
                if r2 <= ds * ds {
                    solid[k] = true;
                }
            }
        }
        // the margins taken as ground
        let v = d - 1;
        for (k, cell) in solid.iter_mut().enumerate() {
            let idx = |a: usize| k / stride[a] % n[a];
            let z = lo[v] + (idx(v) as f64 + 0.5) * ds;
            let beside = (0..v).any(|a| idx(a) < 2 || idx(a) + 2 >= n[a]);
            if idx(v) < 2 || (beside && z < ground) {
                *cell = true;
            }
        }
        // flood the empty cells from the border, through faces
        let mut open = vec![false; total];
        let on_border = |k: usize| (0..d).any(|a| [0, n[a] - 1].contains(&(k / stride[a] % n[a])));
        flood(&n[..d], (0..total).filter(|&k| on_border(k)).collect(), |k| !solid[k], &mut open);
        Raster { d, lo, n, ds, solid, open }
    }

    /// The cell holding the point `p` (its first `d` coordinates), if the raster covers it.
    pub(super) fn cell(&self, p: &[f64]) -> Option<usize> {
        let (mut k, mut stride) = (0, 1);
        for a in 0..self.d {
            let u = (p[a] - self.lo[a]) / self.ds;
            if u < 0.0 || u >= self.n[a] as f64 {
                return None;
            }
            k += u as usize * stride;
            stride *= self.n[a];
        }
        Some(k)
    }

    /// What the vertical gap from height `za` to `zb` over the horizontal point `h` is in the
    /// raster: open to the sky (an open cell along it, or a point beyond the raster, which ends
    /// above the ground), an enclosed void (empty cells, none open), or solid all along (too
    /// thin to hold a cell farther than Δs from every particle).
    pub(super) fn gap(&self, h: &[f64], za: f64, zb: f64) -> Gap {
        let mut p = [0.0; 3];
        p[..self.d - 1].copy_from_slice(&h[..self.d - 1]);
        let mut any_void = false;
        let mut z = za + self.ds;
        while z < zb - 0.5 * self.ds {
            p[self.d - 1] = z;
            match self.cell(&p) {
                None => return Gap::Open,
                Some(k) if self.open[k] => return Gap::Open,
                Some(k) if !self.solid[k] => any_void = true,
                _ => {}
            }
            z += 0.5 * self.ds;
        }
        if any_void { Gap::Enclosed } else { Gap::Solid }
    }

    /// The cell holding the point `p` (m, one coordinate per axis), if the raster covers it.
    pub(super) fn cell_of(&self, p: &[f64]) -> Option<usize> {
        let stride = [1, self.n[0], self.n[0] * self.n[1]];
        let mut k = 0;
        for a in 0..self.d {
            let u = ((p[a] - self.lo[a]) / self.ds).floor();
            if !(u >= 0.0 && u < self.n[a] as f64) {
                return None;
            }
            k += u as usize * stride[a];
        }
        Some(k)
    }

    /// The largest enclosed void (a face-connected component of empty, not open cells) that
    /// holds one of the cells `holding` (any void when it is empty): its number of cells and its
    /// bounding box (m, lower and upper bound along each axis).
    pub(super) fn largest_void(&self, holding: &[usize]) -> Option<(usize, [(f64, f64); 3])> {
        let stride = [1, self.n[0], self.n[0] * self.n[1]];
        let total = self.solid.len();
        let void = |k: usize| !self.solid[k] && !self.open[k];
        let mut seen = vec![false; total];
        let mut mark = vec![holding.is_empty(); total];
        for &k in holding {
            mark[k] = true;
        }
        let mut best: Option<(usize, [(f64, f64); 3])> = None;
        for k0 in 0..total {
            if seen[k0] || !void(k0) {
                continue;
            }
            let cells = flood(&self.n[..self.d], vec![k0], void, &mut seen);
            if !cells.iter().any(|&k| mark[k]) {
                continue;
            }
            let count = cells.len();
            let (mut ilo, mut ihi) = ([usize::MAX; 3], [0usize; 3]);
            for k in cells {
                for a in 0..self.d {
                    let i = k / stride[a] % self.n[a];
                    ilo[a] = ilo[a].min(i);
                    ihi[a] = ihi[a].max(i);
                }
            }
            let mut bb = [(0.0, 0.0); 3];
            for a in 0..self.d {
                bb[a] = (self.lo[a] + ilo[a] as f64 * self.ds, self.lo[a] + (ihi[a] + 1) as f64 * self.ds);
            }
            if best.as_ref().is_none_or(|b| count > b.0) {
                best = Some((count, bb));
            }
        }
        best
    }
}

/// A vertical gap between two particles of a column, as the raster sees it ([`Raster::gap`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Gap {
    Open,
    Enclosed,
    Solid,
}

/// A flood fill on a grid of `n[axis]` cells along each axis (cell (i0, i1, i2) is entry
/// i0 + n0 (i1 + n1 i2)): marks in `reached` the cells that `member` admits and that connect to
/// `seeds` through the faces of such cells, not already reached; returns them.
pub(super) fn flood(
    n: &[usize],
    mut stack: Vec<usize>,
    member: impl Fn(usize) -> bool,
    reached: &mut [bool],
) -> Vec<usize> {
    let mut out = Vec::new();
    while let Some(k) = stack.pop() {
        if reached[k] || !member(k) {
            continue;
        }
        reached[k] = true;
        out.push(k);
        let mut stride = 1;
        for &na in n {
            let i = k / stride % na;
            if i > 0 {
                stack.push(k - stride);
            }
            if i + 1 < na {
                stack.push(k + stride);
            }
            stride *= na;
        }
    }
    out
}

/// Ground surface per column from the positions of the soil particles, `pts[axis]` (2D: x, y;
/// 3D: x, y, z; the last axis vertical). The columns lie on a horizontal grid of `nc` columns
/// along each horizontal axis (2D: one axis), `ds` apart from the corner `lo` (m): column k is
/// centred at lo + (k + 1/2) ds along each axis and gathers the particles within ±ds of its
/// centre along each (two spacings wide, so a smooth lateral shift of the lattice cannot empty
/// it); the particles are walked upward from the lowest up to the first vertical gap larger
/// than 2 ds that is not an enclosed void of `raster`; the surface is the highest particle within
/// ±3ds/4 of the centre along each horizontal axis that lies at most 2 ds above the walk's top
/// (the band's top when there is none), NaN for an empty column. Column (k0, k1) is entry
/// k0 + nc[0] k1 of the result.
pub(super) fn surface(pts: &[&[f64]], lo: &[f64], ds: f64, nc: &[usize], raster: &Raster) -> Vec<f64> {
    let dh = pts.len() - 1;
    let z = pts[dh];
    // each particle in the bin of the column nearest to it (bins -1..=nc along each axis): a
    // column's particles lie in its own bin and the bins beside it
    let nb: Vec<usize> = nc[..dh].iter().map(|n| n + 2).collect();
    let mut bins: Vec<Vec<u32>> = vec![Vec::new(); nb.iter().product()];
    let u = |i: usize, a: usize| (pts[a][i] - lo[a]) / ds - 0.5;
    'points: for i in 0..z.len() {
        let (mut b, mut stride) = (0, 1);
        for a in 0..dh {
            let v = (u(i, a) + 0.5).floor() + 1.0;
            if !(v >= 0.0 && v < nb[a] as f64) {
                continue 'points;
            }
            b += v as usize * stride;
            stride *= nb[a];
        }
        bins[b].push(i as u32);
    }
    let ncol: usize = nc[..dh].iter().product();
    let mut c: Vec<(f64, bool)> = Vec::new();
    (0..ncol)
        .map(|kc| {
            let mut k = [0usize; 2];
            let mut rest = kc;
            for a in 0..dh {
                k[a] = rest % nc[a];
                rest /= nc[a];
            }
            let centre: Vec<f64> = (0..dh).map(|a| lo[a] + (k[a] as f64 + 0.5) * ds).collect();
            // gather the band: the particles within ±ds of the centre along each axis
            c.clear();
            for o in 0..3usize.pow(dh as u32) {
                let (mut b, mut stride, mut rest) = (0, 1, o);
                for a in 0..dh {
                    b += (k[a] + rest % 3) * stride;
                    rest /= 3;
                    stride *= nb[a];
                }
                for &i in &bins[b] {
                    let i = i as usize;
                    let inside = (0..dh).all(|a| {
                        let v = u(i, a);
                        (v - 1.0).ceil() <= k[a] as f64 && k[a] as f64 <= (v + 1.0).floor()
                    });
                    if inside {
                        c.push((z[i], (0..dh).all(|a| (pts[a][i] - centre[a]).abs() <= 0.75 * ds)));
                    }
                }
            }
            if c.is_empty() {
                return f64::NAN;
            }
            c.sort_by(|a, b| a.0.total_cmp(&b.0));
            // walk the band up to the first gap open to the sky; a gap the raster sees as
            // solid ends it too where the band's particles lie mostly below it (a few lifted
            // particles over the ground), not where most lie above (a crack low in the soil, a
            // row pulled off the floor of the box)
            let mut top = 0;
            for q in 1..c.len() {
                if c[q].0 - c[top].0 > 2.0 * ds {
                    let ends = match raster.gap(&centre, c[top].0, c[q].0) {
                        Gap::Open => true,
                        Gap::Enclosed => false,
                        Gap::Solid => q >= c.len() - q,
                    };
                    if ends {
                        break;
                    }
                }
                top = q;
            }
            // the height is read from the particles within ±3ds/4 of the column's centre (the
            // band's ±ds would lift a crater's edge to the rim beside it; ±ds/2 finds no
            // particle near the top of a column whose own particles moved sideways, and then
            // reads a hole one or two spacings deep), up to 2 ds above the band's top (the gap
            // rule), else from the band
            let lim = c[top].0 + 2.0 * ds;
            c.iter()
                .filter(|(y, near)| *y <= lim && *near)
                .map(|p| p.0)
                .fold(None, |a: Option<f64>, y| Some(a.map_or(y, |a| a.max(y))))
                .unwrap_or(c[top].0)
        })
        .collect()
}
