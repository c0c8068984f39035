//! The repulsion of boundary particles (Liu & Liu 2003's `ext_force`, after Monaghan 1994's
//! boundary force; docs/theory.md "Boundary particles"): over the pair list, the ordinary member
//! o of each pair with one ordinary and one boundary particle b gets, while r = |x_o − x_b| < r0,
//! the acceleration D (x_o − x_b) [(r0/r)^p1 − (r0/r)^p2]/r² (m/s²). Under
//! `physics.gravity_in_forces` the term starts at the gravity, on every particle, as the book's
//! routine does. Fortran twin: `sph_boundary_repulsion` in `sph_boundary.f90`.

use super::super::nnps::PairList;
use super::super::{Backend, Phase, PlanCtx, Slots, Stage, Terms, Twin};
use crate::modules::Module;
use crate::state::{Clock, Field, Particles, Work};

/// The constants of the repulsion: range r0 (m), D (m²/s²), exponents p1 > p2 (real powers).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RepulsionCoef {
    pub r0: f64,
    pub d: f64,
    pub p1: f64,
    pub p2: f64,
}

/// `sph_boundary_repulsion`: the term of the `dvdt.len() / dim` particles given (ntotal).
pub struct Repulsion<'a> {
    pub dim: usize,
    pub pairs: &'a PairList,
    /// Positions (m), dim × ntotal.
    pub x: &'a [f64],
    /// Boundary kind of the first `bnd.len()` (real) particles: 0 ordinary, else a boundary
    /// particle; the particles after them (mirrors) are neither.
    pub bnd: &'a [i32],
    pub coef: RepulsionCoef,
    /// The gravity the term starts at (m/s², `dim` values), or empty for none.
    pub grav: &'a [f64],
    /// Acceleration (m/s²), dim × ntotal.
    pub dvdt: &'a mut [f64],
}

impl Twin for Repulsion<'_> {
    fn rust(&mut self) {
        repulsion(self)
    }
    fn fortran(&mut self) {
        super::ffi::repulsion(self)
    }
}

/// The Rust twin: the pairs in reach are listed in parallel (in ascending order, whatever the
/// thread count), then added pair by pair in that order, as the Fortran loop adds them. 0 ULP.
fn repulsion(a: &mut Repulsion) {
    let Repulsion { dim, pairs: pl, x, bnd, coef, grav, dvdt } = a;
    let (dim, RepulsionCoef { r0, d: dd, p1, p2 }) = (*dim, *coef);
    let (n, np) = (bnd.len(), pl.len());
    let (pi, pj) = (&pl.i, &pl.j);
    // the ordinary and the boundary member of pair k, with their separation and distance
    let pair = |k: usize| -> Option<(usize, [f64; 3], f64)> {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        if i >= n || j >= n {
            return None;
        }
        let (o, b) = match (bnd[i], bnd[j]) {
            (0, kj) if kj != 0 => (i, j),
            (ki, 0) if ki != 0 => (j, i),
            _ => return None,
        };
        let mut dx = [0.0; 3];
        let mut rr = 0.0;
        for d in 0..dim {
            dx[d] = x[d + dim * o] - x[d + dim * b];
            rr += dx[d] * dx[d];
        }
        let rr = rr.sqrt();
        (rr < r0).then_some((o, dx, rr))
    };
    let mut guard = pl.scratch.lock();
    let tasks = crate::modules::par::select_pairs(&mut guard, np, |k| pair(k).is_some());
    if grav.len() == dim {
        for row in dvdt.chunks_exact_mut(dim) {
            row.copy_from_slice(grav);
        }
    } else {
        dvdt.fill(0.0);
    }
    for b in tasks {
        for &k in b {
            if let Some((o, dx, rr)) = pair(k as usize) {
                let q = r0 / rr;
                let f = (q.powf(p1) - q.powf(p2)) / (rr * rr);
                for d in 0..dim {
                    dvdt[d + dim * o] += dd * dx[d] * f;
                }
            }
        }
    }
}

/// The repulsion term of the acceleration (with the gravity under `physics.gravity_in_forces`).
pub struct RepulsionStage {
    pub(super) coef: RepulsionCoef,
    /// The gravity the term starts at (m/s²), or empty.
    pub(super) grav: Vec<f64>,
    pub(super) slots: Slots,
}

impl Stage for RepulsionStage {
    fn module(&self) -> Module {
        Module::Boundary
    }
    fn name(&self) -> &'static str {
        "boundary.repulsion"
    }
    fn reads(&self) -> &[Field] {
        &[Field::PairI, Field::PairJ, Field::X, Field::Bnd]
    }
    fn writes(&self) -> &[Field] {
        &[Field::Acc]
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        self.slots.size(w, p.dim, p.ntotal);
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, nt) = (p.dim, p.ntotal);
        let bnd = &p.bnd[..p.bnd.len().min(p.nreal)];
        let dvdt = &mut w.acc[self.slots.acc_range(dim * nt)];
        let (x, grav) = (&p.x[..dim * nt], &self.grav[..]);
        Repulsion { dim, pairs: &w.pairs, x, bnd, coef: self.coef, grav, dvdt }.run(b);
    }
    fn terms(&self) -> Terms {
        Terms { acc: Some(3), de: None }
    }
    fn assign(&mut self, slots: Slots) {
        self.slots = slots;
    }
}

/// The stage where the case has `[boundary] repulsion`: its gravity is `physics.gravity_ms2`
/// under `physics.gravity_in_forces`, none otherwise.
pub(super) fn stage(ctx: &PlanCtx) -> Option<(Phase, Box<dyn Stage>)> {
    let r = ctx.case.boundary.repulsion?;
    let coef = RepulsionCoef { r0: r.r0_m, d: r.d_m2s2, p1: r.p1, p2: r.p2 };
    let ph = &ctx.case.physics;
    let grav = match &ph.gravity_ms2 {
        Some(g) if ph.gravity_in_forces => g.clone(),
        _ => Vec::new(),
    };
    Some((Phase::Rates, Box::new(RepulsionStage { coef, grav, slots: Slots::default() })))
}
