//! Absorbing walls: viscous dampers of the Lysmer–Kuhlemeyer kind (Lysmer & Kuhlemeyer 1969,
//! J. Eng. Mech. Div. ASCE 95(EM4) 859–877; docs/theory.md, "Absorbing walls"). A wall of kind
//! `absorbing` makes no virtual particles. The real particles in the layer of thickness L in front
//! of it (distance d along its inward normal n, 0 ≤ d < L, within its extent) feel, per unit mass
//! (m/s²),
//!
//! a = w(d) [−c_p v_n n − c_s (v − v_n n) + (σ0·(−n))/ρ],  w(d) = 2 (1 − d/L)/L (1/m),
//!
//! so that one column of the layer takes the tractions ρ c_p v_n and ρ c_s v_t of the dampers
//! (the midpoint sum of w over rows Δx apart is 1/Δx), and the traction of its stress at t = 0,
//! σ0 = −p I + τ, which the cut-away domain carried (the static reaction: a soil at rest stays
//! at rest). c_p² = c² + 4G/(3ρ), c_s² = G/ρ (m/s), c the EOS's bulk sound speed, G the shear
//! modulus (0 for a fluid). Fortran twin: `sph_absorb.f90`.

mod ffi;
#[cfg(test)]
mod parity;
mod rust;

use super::param::{MatTable, NSTR, Segments};
use super::{Backend, Contribution, Module, Phase, PlanCtx, Slots, Stage, Terms, Twin};
use crate::case::WallKind;
use crate::state::{Clock, Field, Particles, Work};

/// `sph_absorb_init`: σ0 = −p I + τ of the `p.len()` real particles.
pub struct Init<'a> {
    pub p: &'a [f64],
    /// Deviatoric stress (Pa), NSTR × n; empty without strength.
    pub tau: &'a [f64],
    /// σ0 (Pa, tension positive), NSTR × n.
    pub sigma0: &'a mut [f64],
}

/// `sph_absorb_dashpot`: the dashpot and static-reaction acceleration of the `rho.len()` real
/// particles.
pub struct Dashpot<'a> {
    pub dim: usize,
    pub x: &'a [f64],
    pub v: &'a [f64],
    pub rho: &'a [f64],
    pub c: &'a [f64],
    pub mat: &'a [i32],
    pub mt: &'a MatTable,
    pub sigma0: &'a [f64],
    /// The absorbing walls (inward normals).
    pub segs: &'a Segments,
    /// Layer thickness L (m).
    pub layer: f64,
    /// Acceleration (m/s²), dim × n.
    pub dvdt: &'a mut [f64],
}

impl Twin for Init<'_> {
    fn rust(&mut self) {
        rust::init(self)
    }
    fn fortran(&mut self) {
        ffi::init(self)
    }
}

impl Twin for Dashpot<'_> {
    fn rust(&mut self) {
        rust::dashpot(self)
    }
    fn fortran(&mut self) {
        ffi::dashpot(self)
    }
}

/// σ0 of every real particle, once, after the first p.
pub struct InitStage;

impl Stage for InitStage {
    fn module(&self) -> Module {
        Module::Absorb
    }
    fn name(&self) -> &'static str {
        "absorb.init"
    }
    fn reads(&self) -> &[Field] {
        &[Field::P, Field::Tau]
    }
    fn writes(&self) -> &[Field] {
        &[Field::Sigma0]
    }
    fn register(&self, p: &mut Particles) {
        p.sigma0 = vec![0.0; NSTR * p.nreal];
    }
    fn real_rows(&self) -> &[Field] {
        &[Field::Sigma0]
    }
    fn run(&self, b: Backend, p: &mut Particles, _w: &mut Work, _k: &Clock) {
        let n = p.nreal;
        let tau: &[f64] = if p.tau.is_empty() { &[] } else { &p.tau[..NSTR * n] };
        Init { p: &p.p[..n], tau, sigma0: &mut p.sigma0[..NSTR * n] }.run(b);
    }
}

/// The dampers' acceleration, a term of the acceleration.
pub struct DashpotStage {
    mt: MatTable,
    segs: Segments,
    layer: f64,
    slots: Slots,
}

impl Stage for DashpotStage {
    fn module(&self) -> Module {
        Module::Absorb
    }
    fn name(&self) -> &'static str {
        "absorb.dashpot"
    }
    fn reads(&self) -> &[Field] {
        &[Field::X, Field::V, Field::Rho, Field::C, Field::Mat, Field::Sigma0]
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
        Dashpot {
            dim,
            x: &p.x[..dim * n],
            v: &p.v[..dim * n],
            rho: &p.rho[..n],
            c: &p.c[..n],
            mat: &p.mat[..n],
            mt: &self.mt,
            sigma0: &p.sigma0[..NSTR * n],
            segs: &self.segs,
            layer: self.layer,
            dvdt: &mut w.acc[r.start..r.start + dim * n],
        }
        .run(b);
    }
    fn terms(&self) -> Terms {
        Terms { acc: Some(5), de: None }
    }
    fn assign(&mut self, slots: Slots) {
        self.slots = slots;
    }
}

/// The layer thickness L (m): `boundary.absorb_layer_m`, else the largest region spacing, so
/// that the whole traction lands on the row next to the wall, where the SPH free surface's own
/// force sits (at h = Δx the cubic spline's row beyond it lies at 2h, out of reach). Finer rows
/// share it when the spacings are whole fractions of it.
pub fn layer(ctx: &PlanCtx) -> f64 {
    let dx_max = ctx.case.regions.iter().map(|r| r.spacing_m).fold(ctx.dx_min, f64::max);
    ctx.case.boundary.absorb_layer_m.unwrap_or(dx_max)
}

/// Runs when the case has an `absorbing` wall.
pub fn plan(ctx: &PlanCtx) -> Contribution {
    let segs = super::boundary::walls::segments(ctx.case, ctx.x0, |k| k == WallKind::Absorbing);
    if segs.is_empty() {
        return Contribution::skip("no absorbing walls");
    }
    let l = layer(ctx);
    let why = format!("{} absorbing wall(s), layer {l:.4e} m", segs.len());
    let dash = DashpotStage { mt: ctx.mt.clone(), segs, layer: l, slots: Slots::default() };
    Contribution::run(why, vec![(Phase::Init, Box::new(InitStage)), (Phase::Rates, Box::new(dash))])
}
