//! Smoothing kernel W(r, h) and ∇W (thesis (5-1); Liu & Liu ch. 3). Units: W in m^-d, ∇W in
//! m^-(d+1). Cubic spline (support 2h), Gauss (3h), quintic spline (Morris 1996, 3h; the book's
//! gradient for q ≤ 1 is wrong and not reproduced), Wendland C2 (2h). ∇_i W_ij is written
//! α g(q) (x_i − x_j)/h², so r = 0 is harmless. Pairs use h_ij = (h_i + h_j)/2.
//! Fortran twin: `sph_kernel.f90`.

mod ffi;
#[cfg(test)]
mod parity;
pub(crate) mod compat;
mod rust;

pub use rust::w_dw;

use super::nnps::PairList;
use super::{Backend, Contribution, Module, Phase, PlanCtx, Stage, Twin};
use crate::case::{DensityKind, KernelKind};
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

/// W and ∇W of every pair.
pub struct PairsStage {
    kind: KernelKind,
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
        Pairs { dim, kind: self.kind, pairs: &w.pairs, x, h, w: &mut w.w, dwdx: &mut w.dwdx }.run(b);
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
    let mut stages: Vec<(Phase, Box<dyn Stage>)> = vec![(Phase::Kernel, Box::new(PairsStage { kind }))];
    if ctx.case.sph.density == DensityKind::Summation {
        stages.push((Phase::Density, Box::new(SelfStage { kind })));
    }
    Contribution::run(format!("{} kernel, support {}h", kind.name(), kind.support()), stages)
}
