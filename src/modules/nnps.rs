//! Neighbour search (Liu's direct_find and link_list; DESIGN.md "nnps").
//!
//! Output: the canonical pair list — every (i, j) with i < j, i real (i < nreal), j any particle,
//! |x_i − x_j| < κ h_ij, h_ij = (h_i + h_j)/2 — sorted by i then j. Every search (direct or cell,
//! Fortran or Rust) returns the same list, so later sums do not depend on the search.
//! Indices are 0-based (`i32`, as at the C boundary).

use super::Backend;
use crate::legacy;
use rayon::prelude::*;

/// The pair list shared by both backends, and (for the Rust gathers) the incidence lists: for each
/// particle, the pairs that touch it in ascending pair order.
#[derive(Debug, Clone, Default)]
pub struct PairList {
    pub i: Vec<i32>,
    pub j: Vec<i32>,
    pub inc_start: Vec<u32>,
    pub inc: Vec<u32>,
    inc_fill: Vec<u32>,
}

impl PairList {
    pub fn len(&self) -> usize {
        self.i.len()
    }
    pub fn is_empty(&self) -> bool {
        self.i.is_empty()
    }

    /// Builds the incidence lists for `ntotal` particles (a counting sort, deterministic).
    pub fn build_incidence(&mut self, ntotal: usize) {
        let np = self.i.len();
        self.inc_start.clear();
        self.inc_start.resize(ntotal + 1, 0);
        for k in 0..np {
            self.inc_start[self.i[k] as usize + 1] += 1;
            self.inc_start[self.j[k] as usize + 1] += 1;
        }
        for a in 0..ntotal {
            self.inc_start[a + 1] += self.inc_start[a];
        }
        self.inc.resize(2 * np, 0);
        self.inc_fill.clear();
        self.inc_fill.extend_from_slice(&self.inc_start[..ntotal]);
        for k in 0..np {
            let a = self.i[k] as usize;
            self.inc[self.inc_fill[a] as usize] = k as u32;
            self.inc_fill[a] += 1;
            let b = self.j[k] as usize;
            self.inc[self.inc_fill[b] as usize] = k as u32;
            self.inc_fill[b] += 1;
        }
    }

    /// The pairs touching particle `a`, ascending.
    #[inline]
    pub fn incident(&self, a: usize) -> &[u32] {
        &self.inc[self.inc_start[a] as usize..self.inc_start[a + 1] as usize]
    }
}

/// Finds the pairs. `x`, `h` hold `ntotal = h.len()` particles, the first `nreal` real.
pub fn search(b: Backend, cell: bool, dim: usize, nreal: usize, x: &[f64], h: &[f64], kappa: f64, pl: &mut PairList) {
    match b {
        Backend::Fortran => {
            let mut cap = pl.i.capacity().max(16 * h.len()).max(16);
            loop {
                pl.i.resize(cap, 0);
                pl.j.resize(cap, 0);
                let np = legacy::nnps(cell, dim, nreal, x, h, kappa, &mut pl.i, &mut pl.j);
                if np <= cap {
                    pl.i.truncate(np);
                    pl.j.truncate(np);
                    break;
                }
                cap = np + np / 4;
            }
        }
        Backend::Rust => {
            if cell {
                rust_cell(dim, nreal, x, h, kappa, pl)
            } else {
                rust_direct(dim, nreal, x, h, kappa, pl)
            }
        }
    }
}

#[inline]
fn within(dim: usize, x: &[f64], h: &[f64], kappa: f64, i: usize, j: usize) -> bool {
    let mut r2 = 0.0;
    for d in 0..dim {
        let dxd = x[d + dim * i] - x[d + dim * j];
        r2 += dxd * dxd;
    }
    let s = kappa * (0.5 * (h[i] + h[j]));
    r2 < s * s
}

fn rust_direct(dim: usize, nreal: usize, x: &[f64], h: &[f64], kappa: f64, pl: &mut PairList) {
    let nt = h.len();
    let rows: Vec<Vec<i32>> = (0..nreal)
        .into_par_iter()
        .map(|i| ((i + 1)..nt).filter(|&j| within(dim, x, h, kappa, i, j)).map(|j| j as i32).collect())
        .collect();
    fill(pl, &rows);
}

fn fill(pl: &mut PairList, rows: &[Vec<i32>]) {
    pl.i.clear();
    pl.j.clear();
    for (i, r) in rows.iter().enumerate() {
        for &j in r {
            pl.i.push(i as i32);
            pl.j.push(j);
        }
    }
}

/// A uniform grid of cells of edge ≥ κ max(h), particles sorted by cell (counting sort).
pub struct CellGrid {
    pub dim: usize,
    pub nc: [usize; 3],
    pub lo: [f64; 3],
    pub cs: f64,
    /// First slot of each cell in `order` (ncell + 1).
    pub start: Vec<u32>,
    /// Particle indices sorted by cell, ascending within a cell.
    pub order: Vec<u32>,
    pub cell_of: Vec<u32>,
}

impl CellGrid {
    pub fn build(dim: usize, x: &[f64], h: &[f64], kappa: f64) -> CellGrid {
        let nt = h.len();
        let hmax = h.iter().cloned().fold(0.0_f64, f64::max);
        let mut lo = [0.0; 3];
        let mut hi = [0.0; 3];
        for d in 0..dim {
            lo[d] = f64::INFINITY;
            hi[d] = f64::NEG_INFINITY;
            for i in 0..nt {
                lo[d] = lo[d].min(x[d + dim * i]);
                hi[d] = hi[d].max(x[d + dim * i]);
            }
        }
        let mut cs = kappa * hmax;
        loop {
            let mut prod: u64 = 1;
            for d in 0..dim {
                prod = prod.saturating_mul(((hi[d] - lo[d]) / cs) as u64 + 1);
            }
            if prod <= (8 * nt as u64).max(64) {
                break;
            }
            cs *= 2.0;
        }
        let mut nc = [1usize; 3];
        for d in 0..dim {
            nc[d] = ((hi[d] - lo[d]) / cs) as usize + 1;
        }
        let ncell = nc[0] * nc[1] * nc[2];
        let mut cell_of = vec![0u32; nt];
        let mut count = vec![0u32; ncell + 1];
        for i in 0..nt {
            let mut c = [0usize; 3];
            for d in 0..dim {
                let k = ((x[d + dim * i] - lo[d]) / cs) as isize;
                c[d] = k.clamp(0, nc[d] as isize - 1) as usize;
            }
            let ic = c[0] + nc[0] * (c[1] + nc[1] * c[2]);
            cell_of[i] = ic as u32;
            count[ic + 1] += 1;
        }
        for c in 0..ncell {
            count[c + 1] += count[c];
        }
        let start = count.clone();
        let mut fillp = count;
        let mut order = vec![0u32; nt];
        for i in 0..nt {
            let c = cell_of[i] as usize;
            order[fillp[c] as usize] = i as u32;
            fillp[c] += 1;
        }
        CellGrid { dim, nc, lo, cs, start, order, cell_of }
    }

    /// Calls `f(j)` for every particle in the 3^dim cells around particle `i`'s cell.
    #[inline]
    pub fn around<F: FnMut(usize)>(&self, i: usize, mut f: F) {
        let ic = self.cell_of[i] as usize;
        let c2 = ic / (self.nc[0] * self.nc[1]);
        let c1 = (ic - c2 * self.nc[0] * self.nc[1]) / self.nc[0];
        let c0 = ic - self.nc[0] * (c1 + self.nc[1] * c2);
        let c = [c0, c1, c2];
        let mut lo = [0usize; 3];
        let mut hi = [0usize; 3];
        for d in 0..self.dim {
            lo[d] = c[d].saturating_sub(1);
            hi[d] = (c[d] + 1).min(self.nc[d] - 1);
        }
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                let row = self.nc[0] * (y + self.nc[1] * z);
                let s = self.start[row + lo[0]] as usize;
                let e = self.start[row + hi[0] + 1] as usize;
                for &j in &self.order[s..e] {
                    f(j as usize);
                }
            }
        }
    }
}

fn rust_cell(dim: usize, nreal: usize, x: &[f64], h: &[f64], kappa: f64, pl: &mut PairList) {
    let nt = h.len();
    if nt == 0 {
        pl.i.clear();
        pl.j.clear();
        return;
    }
    let grid = CellGrid::build(dim, x, h, kappa);
    let rows: Vec<Vec<i32>> = (0..nreal)
        .into_par_iter()
        .map(|i| {
            let mut r = Vec::new();
            grid.around(i, |j| {
                if j > i && within(dim, x, h, kappa, i, j) {
                    r.push(j as i32);
                }
            });
            r.sort_unstable();
            r
        })
        .collect();
    fill(pl, &rows);
}
