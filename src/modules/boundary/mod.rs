//! Boundaries (thesis 4-6-1, after Liu's virt_part and ext_force). Fortran twin: `sph_boundary.f90`.
//!
//! Walls are segments `seg(3·dim, nseg)`: start a, end b, inward unit normal n (a point in 1D);
//! in 3D plane walls `seg(12, nseg)`: a corner a, edge vectors u and v, the inward unit normal
//! (parallelograms; the type I nodes a + k1 Δs1 û + k2 Δs2 v̂, the mirrors in a band κh in front
//! of the plane within its extent, images of images in up to three walls for the corners).
//! Type I: wall particles at a + k·ds·t (k = 0..nk, the end node only where `endnode`), and the
//! force per unit mass D[(r0/r)^{n1} − (r0/r)^{n2}] x_ij/r² (m/s²) on a real particle within r0.
//! Type II: mirror images of the real particles within κh of a wall (and images of those in a
//! second wall, for corners), rebuilt every step after the real particles: ρ, p, c, e, h, m, mat
//! copied; x, v (free slip or no slip) and τ (M τ M, M = I − 2 n nᵀ) reflected.

mod ffi;
#[cfg(test)]
mod parity;
mod repulsion;
mod rust;
pub mod walls;

pub use repulsion::{Repulsion, RepulsionCoef, RepulsionStage};

pub(crate) use rust::frame;
pub use rust::WallFrame;

use super::param::Segments;
use super::{Backend, Contribution, Module, Phase, PlanCtx, Slots, Stage, Terms, Twin};
use crate::case::WallKind;
use crate::state::{Clock, Field, Particles, Work};

/// The constants of the type I wall force: wall-particle spacing and range r0 (m), D (m²/s²),
/// exponents n1 > n2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallCoef {
    pub spacing: f64,
    pub r0: f64,
    pub d: f64,
    pub n1: i32,
    pub n2: i32,
}

/// `sph_boundary_wall_force`: the type I force on the `dvdt.len() / dim` real particles.
pub struct WallForce<'a> {
    pub dim: usize,
    pub x: &'a [f64],
    pub segs: &'a Segments,
    pub coef: WallCoef,
    /// Acceleration (m/s²), dim × n.
    pub dvdt: &'a mut [f64],
}

/// `sph_boundary_mirror_make`: the mirrors of the `h.len()` real particles: source particle and
/// wall(s) (−1 when none) of each (resized).
pub struct MirrorMake<'a> {
    pub dim: usize,
    pub x: &'a [f64],
    pub h: &'a [f64],
    /// Kernel support in units of h.
    pub kappa: f64,
    pub segs: &'a Segments,
    pub gsrc: &'a mut Vec<i32>,
    pub gseg: &'a mut Vec<i32>,
}

/// `sph_boundary_mirror_fill`: the mirror slots `n..n+ng` of the particle arrays.
pub struct MirrorFill<'a> {
    pub dim: usize,
    pub n: usize,
    pub gsrc: &'a [i32],
    pub gseg: &'a [i32],
    pub segs: &'a Segments,
    pub noslip: bool,
    pub x: &'a mut [f64],
    pub v: &'a mut [f64],
    pub rho: &'a mut [f64],
    pub p: &'a mut [f64],
    pub c: &'a mut [f64],
    pub e: &'a mut [f64],
    pub h: &'a mut [f64],
    pub mass: &'a mut [f64],
    pub mat: &'a mut [i32],
    /// Empty without strength.
    pub tau: &'a mut [f64],
}

/// `sph_boundary_mirror_copy`: `f[n + g] = f[source of g]`.
pub struct MirrorCopy<'a> {
    pub n: usize,
    pub gsrc: &'a [i32],
    pub f: &'a mut [f64],
}

impl Twin for WallForce<'_> {
    fn rust(&mut self) {
        rust::wall_force(self)
    }
    fn fortran(&mut self) {
        ffi::wall_force(self)
    }
}

impl Twin for MirrorMake<'_> {
    fn rust(&mut self) {
        rust::mirror_make(self)
    }
    fn fortran(&mut self) {
        ffi::mirror_make(self)
    }
}

impl Twin for MirrorFill<'_> {
    fn rust(&mut self) {
        rust::mirror_fill(self)
    }
    fn fortran(&mut self) {
        ffi::mirror_fill(self)
    }
}

impl Twin for MirrorCopy<'_> {
    fn rust(&mut self) {
        for (g, &s) in self.gsrc.iter().enumerate() {
            self.f[self.n + g] = self.f[s as usize];
        }
    }
    fn fortran(&mut self) {
        ffi::mirror_copy(self)
    }
}

/// The mirror list.
pub struct MakeStage {
    segs: Segments,
    kappa: f64,
}

impl Stage for MakeStage {
    fn module(&self) -> Module {
        Module::Boundary
    }
    fn name(&self) -> &'static str {
        "boundary.mirror_make"
    }
    fn reads(&self) -> &[Field] {
        &[Field::X, Field::H]
    }
    fn writes(&self) -> &[Field] {
        &[Field::Gsrc, Field::Gseg]
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, n) = (p.dim, p.nreal);
        let (x, h) = (&p.x[..dim * n], &p.h[..n]);
        MirrorMake { dim, x, h, kappa: self.kappa, segs: &self.segs, gsrc: &mut w.gsrc, gseg: &mut w.gseg }.run(b);
    }
}

/// The mirror particles, after the list (the particle arrays take the mirrors first).
pub struct FillStage {
    segs: Segments,
    noslip: bool,
}

impl Stage for FillStage {
    fn module(&self) -> Module {
        Module::Boundary
    }
    fn name(&self) -> &'static str {
        "boundary.mirror_fill"
    }
    fn reads(&self) -> &[Field] {
        &[Field::Gsrc, Field::Gseg]
    }
    fn writes(&self) -> &[Field] {
        &[Field::X, Field::V, Field::Rho, Field::P, Field::C, Field::E, Field::H, Field::Mass, Field::Mat, Field::Tau]
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        p.set_ntotal(p.nreal + w.gsrc.len());
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let Particles { dim, nreal, x, v, rho, p, c, e, h, mass, mat, tau, .. } = p;
        let (dim, n, gsrc, gseg) = (*dim, *nreal, &w.gsrc, &w.gseg);
        let segs = &self.segs;
        MirrorFill { dim, n, gsrc, gseg, segs, noslip: self.noslip, x, v, rho, p, c, e, h, mass, mat, tau }.run(b);
    }
}

/// Copies of fields to the mirrors after they change (ρ of summation density; p and c; the
/// viscosity switch's α).
pub struct CopyStage {
    fields: Vec<Field>,
}

impl Stage for CopyStage {
    fn module(&self) -> Module {
        Module::Boundary
    }
    fn name(&self) -> &'static str {
        "boundary.mirror_copy"
    }
    fn reads(&self) -> &[Field] {
        &[Field::Gsrc]
    }
    fn writes(&self) -> &[Field] {
        &self.fields
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        for &f in &self.fields {
            let f = match f {
                Field::Rho => &mut p.rho,
                Field::P => &mut p.p,
                Field::Alpha => &mut p.alpha,
                _ => &mut p.c,
            };
            MirrorCopy { n: p.nreal, gsrc: &w.gsrc, f }.run(b);
        }
    }
}

/// The type I wall force, a term of the acceleration.
pub struct WallStage {
    segs: Segments,
    coef: WallCoef,
    slots: Slots,
}

impl Stage for WallStage {
    fn module(&self) -> Module {
        Module::Boundary
    }
    fn name(&self) -> &'static str {
        "boundary.wall_force"
    }
    fn reads(&self) -> &[Field] {
        &[Field::X]
    }
    fn writes(&self) -> &[Field] {
        &[Field::Acc]
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        self.slots.size(w, p.dim, p.ntotal);
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, n) = (p.dim, p.nreal);
        let r = self.slots.acc_range(dim * p.ntotal);
        let dvdt = &mut w.acc[r.start..r.start + dim * n];
        WallForce { dim, x: &p.x[..dim * n], segs: &self.segs, coef: self.coef, dvdt }.run(b);
    }
    fn terms(&self) -> Terms {
        Terms { acc: Some(3), de: None }
    }
    fn assign(&mut self, slots: Slots) {
        self.slots = slots;
    }
}

/// Runs when the case has walls (mirrors for type II, the force for type I) or `[boundary]
/// repulsion`.
pub fn plan(ctx: &PlanCtx) -> Contribution {
    let case = ctx.case;
    let mirror_segs = walls::segments(case, ctx.x0, WallKind::mirrors);
    let wall_segs = walls::segments(case, ctx.x0, WallKind::repels);
    let mut stages: Vec<(Phase, Box<dyn Stage>)> = Vec::new();
    if !mirror_segs.is_empty() {
        stages.push((Phase::Mirrors, Box::new(MakeStage { segs: mirror_segs.clone(), kappa: ctx.kappa })));
        stages.push((Phase::Mirrors, Box::new(FillStage { segs: mirror_segs, noslip: case.boundary.noslip })));
        if case.sph.density.summed() {
            stages.push((Phase::DensityShare, Box::new(CopyStage { fields: vec![Field::Rho] })));
        }
        stages.push((Phase::EosShare, Box::new(CopyStage { fields: vec![Field::P, Field::C] })));
        if case.viscosity.switch != crate::case::ViscSwitch::None && case.viscosity.alpha > 0.0 {
            stages.push((Phase::SwitchShare, Box::new(CopyStage { fields: vec![Field::Alpha] })));
        }
    }
    if !wall_segs.is_empty() {
        let b = &case.boundary;
        let coef = WallCoef {
            spacing: b.wall_spacing_m.unwrap_or(0.25 * ctx.dx_min),
            r0: b.r0_m.unwrap_or(0.5 * ctx.dx_min),
            d: b.d_m2s2,
            n1: b.n1,
            n2: b.n2,
        };
        stages.push((Phase::Rates, Box::new(WallStage { segs: wall_segs, coef, slots: Slots::default() })));
    }
    let mirrors = case.walls.iter().any(|w| w.kind.mirrors());
    let rep_walls = case.walls.iter().any(|w| w.kind.repels());
    let mut why = match (mirrors, rep_walls) {
        (true, true) => "walls: type I force and type II mirrors",
        (true, false) => "walls: type II mirrors",
        (false, true) => "walls: type I force",
        _ => "no walls",
    }
    .to_string();
    if let Some(s) = repulsion::stage(ctx) {
        let rep = if case.physics.gravity_in_forces && case.gravity_on() {
            "repulsion of boundary particles (with the gravity)"
        } else {
            "repulsion of boundary particles"
        };
        why = if mirrors || rep_walls { format!("{why}; {rep}") } else { rep.to_string() };
        stages.push(s);
    }
    Contribution::run(why, stages)
}
