//! Smoothing kernel W(r, h) and ∇W (thesis (5-1); Liu & Liu ch. 3). Units: W in m^-d, ∇W in
//! m^-(d+1). Cubic spline (support 2h), Gauss (3h), quintic spline (Morris 1996, 3h; the book's
//! gradient for q ≤ 1 is wrong and not reproduced), Wendland C2 (2h). ∇_i W_ij is written
//! α g(q) (x_i − x_j)/h², so r = 0 is harmless. Pairs use h_ij = (h_i + h_j)/2.
//! Fortran twin: `sph_kernel.f90`.

mod ffi;
#[cfg(test)]
mod parity;
mod rust;

pub use rust::w_dw;

use super::nnps::PairList;
use super::{Backend, Contribution, Module, Phase, PlanCtx, Stage, Twin};
use crate::case::KernelKind;
use crate::state::{Clock, Field, Particles, Work};

/// `sph_kernel_pairs`: W_ij and ∇_i W_ij of every pair.
pub struct Pairs<'a> {
    pub dim: usize,
    pub kind: KernelKind,
    pub pairs: &'a PairList,
    pub x: &'a [f64],
    pub h: &'a [f64],
    /// W_ij (m^-d), npair.
    pub w: &'a mut [f64],
    /// ∇_i W_ij (m^-(d+1)), dim × npair.
    pub dwdx: &'a mut [f64],
    /// Factor of ∇W (1: none): 1/S, the lattice normalisation of `sph.lattice_gradient`
    /// ([`lattice_moment`]).
    pub gscale: f64,
}

impl Twin for Pairs<'_> {
    fn rust(&mut self) {
        rust::pairs(self)
    }
    fn fortran(&mut self) {
        ffi::pairs(self)
    }
}

/// `sph_kernel_self`: the self-contribution W(0, h_i) of each particle.
pub struct SelfW<'a> {
    pub dim: usize,
    pub kind: KernelKind,
    pub h: &'a [f64],
    pub w0: &'a mut [f64],
}

impl Twin for SelfW<'_> {
    fn rust(&mut self) {
        rust::self_w(self)
    }
    fn fortran(&mut self) {
        ffi::self_w(self)
    }
}

/// `sph_kernel_point`: W and ∇W at one separation `dx` (length `dim`).
pub struct Point<'a> {
    pub dim: usize,
    pub kind: KernelKind,
    pub dx: &'a [f64],
    pub h: f64,
    pub w: &'a mut f64,
    pub dwdx: &'a mut [f64],
}

impl Twin for Point<'_> {
    fn rust(&mut self) {
        let r2: f64 = self.dx.iter().fold(0.0, |s, d| s + d * d);
        *self.w = w_dw(self.dim, self.kind, r2.sqrt(), self.dx, self.h, self.dwdx);
    }
    fn fortran(&mut self) {
        ffi::point(self)
    }
}

/// The kernel's first moment summed over a lattice of unit spacing, S = Σ_{j≠0} x_j,1 ∂W/∂x_1 —
/// the SPH gradient Σ_j V_j (f_j − f_i) ∇_i W_ij of f = x_1 (the particle at the origin, W at
/// h = `h_over_dx`, every node of volume 1), for `dim` = 1, 2 or 3. An SPH gradient of a linear field on that lattice comes out S times the exact one: the
/// velocity gradient (continuity, strain rate) and the stress divergence each carry S, so an
/// elastic wave runs S times its speed (the cubic spline at h = Δx: S = 1.0200 in 3D, 1.0131 in
/// 2D; at h = 1.2 Δx 0.9817 in 3D). `sph.lattice_gradient` divides ∇W by it. Dimensionless.
pub fn lattice_moment(dim: usize, kind: KernelKind, h_over_dx: f64) -> f64 {
    let reach = (kind.support() * h_over_dx).ceil() as i64 + 1;
    let mut s = 0.0;
    let mut g = [0.0; 3];
    let span = -reach..=reach;
    let (ny, nz) = (if dim >= 2 { reach } else { 0 }, if dim >= 3 { reach } else { 0 });
    for k in -nz..=nz {
        for j in -ny..=ny {
            for i in span.clone() {
                if i == 0 && j == 0 && k == 0 {
                    continue;
                }
                // ∇_0 W(0 − x_j): the separation from the node to the origin
                let dx = [-(i as f64), -(j as f64), -(k as f64)];
                let r = dx[..dim].iter().map(|d| d * d).sum::<f64>().sqrt();
                w_dw(dim, kind, r, &dx[..dim], h_over_dx, &mut g[..dim]);
                s += (i as f64) * g[0];
            }
        }
    }
    s
}

/// W and ∇W of every pair.
pub struct PairsStage {
    pub(crate) kind: KernelKind,
    pub(crate) gscale: f64,
}

impl Stage for PairsStage {
    fn module(&self) -> Module {
        Module::Kernel
    }
    fn name(&self) -> &'static str {
        "kernel.pairs"
    }
    fn reads(&self) -> &[Field] {
        &[Field::PairI, Field::PairJ, Field::X, Field::H]
    }
    fn writes(&self) -> &[Field] {
        &[Field::W, Field::Dwdx]
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        let np = w.pairs.len();
        w.w.resize(np, 0.0);
        w.dwdx.resize(p.dim * np, 0.0);
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, nt) = (p.dim, p.ntotal);
        let (x, h) = (&p.x[..dim * nt], &p.h[..nt]);
        Pairs { dim, kind: self.kind, pairs: &w.pairs, x, h, w: &mut w.w, dwdx: &mut w.dwdx, gscale: self.gscale }
            .run(b);
    }
}

/// The self-contribution of summation density.
pub struct SelfStage {
    kind: KernelKind,
}

impl Stage for SelfStage {
    fn module(&self) -> Module {
        Module::Kernel
    }
    fn name(&self) -> &'static str {
        "kernel.self"
    }
    fn reads(&self) -> &[Field] {
        &[Field::H]
    }
    fn writes(&self) -> &[Field] {
        &[Field::W0]
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        w.w0.resize(p.ntotal, 0.0);
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        SelfW { dim: p.dim, kind: self.kind, h: &p.h[..p.ntotal], w0: &mut w.w0 }.run(b);
    }
}

/// Every case evaluates the kernel over its pairs; summation density also needs W(0, h).
pub fn plan(ctx: &PlanCtx) -> Contribution {
    let kind = ctx.case.sph.kernel;
    let (gscale, norm) = if ctx.case.sph.lattice_gradient {
        let s = lattice_moment(ctx.case.dim, kind, ctx.case.sph.h_over_dx);
        (1.0 / s, format!(", grad W / {s:.5} (the lattice's first moment at h = {} dx)", ctx.case.sph.h_over_dx))
    } else {
        (1.0, String::new())
    };
    let mut stages: Vec<(Phase, Box<dyn Stage>)> = vec![(Phase::Kernel, Box::new(PairsStage { kind, gscale }))];
    if ctx.case.sph.density.summed() {
        stages.push((Phase::Density, Box::new(SelfStage { kind })));
    }
    Contribution::run(format!("{} kernel, support {}h{norm}", kind.name(), kind.support()), stages)
}
