//! Detonation (docs/theory.md §9). Programmed burn: particle i lights at
//! t_i = |x_i − x_det|/(s D) (s), or t_i = |(x_i − x_det)·n̂|/(s D) when lit along a plane of unit
//! normal n̂, s the lighting-speed factor (1: the thesis's reading); its burn
//! fraction is λ_p = 1 once t ≥ t_i (width 0) or min(1, max(0, (t − t_i) D/(w h_i))). With the beta
//! burn (row η_CJ = ρ_CJ/ρ0 > 1), an explosive compressed towards its CJ density burns too and never
//! un-burns: λ_i ← max(λ_i, λ_p, min(1, (1 − ρ0/ρ_i)/(1 − 1/η_CJ))). The instantaneous burn needs no
//! routine. Fortran twin: `sph_detonation.f90`. Tier: 0 ULP (a maximum is exact).

pub mod cj;
mod ffi;
#[cfg(test)]
mod parity;
mod rust;

use super::param::MatTable;
use super::{Backend, Contribution, Module, Phase, PlanCtx, Stage, Twin};
use crate::state::{Clock, Field, Particles, Work};

/// Row of η_CJ = ρ_CJ/ρ0 of the beta burn in a column of mpar (0-based; 0 = off).
pub(crate) const ETA_CJ: usize = super::param::SPH_MP_ETA_CJ as usize - 1;

/// `sph_detonation_light`: the lighting time (s) of the first `mat.len()` particles (0 for
/// materials that are not explosives).
pub struct Light<'a> {
    pub dim: usize,
    pub x: &'a [f64],
    pub mat: &'a [i32],
    pub mt: &'a MatTable,
    /// The lighting point (m).
    pub xdet: &'a [f64],
    /// The unit normal of a lighting plane through `xdet`; `None`: lit from the point.
    pub nrm: Option<&'a [f64]>,
    /// The lighting speed over D (1: the thesis's reading).
    pub sf: f64,
    pub tlight: &'a mut [f64],
}

/// `sph_detonation_burn`: the burn fraction at time `t` (s) of the first `mat.len()` particles;
/// `burn` holds the previous fractions (0 at the start), which the beta burn never lowers.
pub struct Burn<'a> {
    pub t: f64,
    pub mat: &'a [i32],
    pub mt: &'a MatTable,
    pub tlight: &'a [f64],
    pub h: &'a [f64],
    /// Density (kg/m³), for the beta burn.
    pub rho: &'a [f64],
    /// Width of the burn ramp in units of h (0: a particle burns at once when lit).
    pub width: f64,
    pub burn: &'a mut [f64],
}

impl Twin for Light<'_> {
    fn rust(&mut self) {
        rust::light(self)
    }
    fn fortran(&mut self) {
        ffi::light(self)
    }
}

impl Twin for Burn<'_> {
    fn rust(&mut self) {
        rust::burn(self)
    }
    fn fortran(&mut self) {
        ffi::burn(self)
    }
}

/// Lighting times, once.
pub struct LightStage {
    mt: MatTable,
    xdet: Vec<f64>,
    nrm: Option<Vec<f64>>,
    sf: f64,
}

impl Stage for LightStage {
    fn module(&self) -> Module {
        Module::Detonation
    }
    fn name(&self) -> &'static str {
        "detonation.light"
    }
    fn reads(&self) -> &[Field] {
        &[Field::X, Field::Mat]
    }
    fn writes(&self) -> &[Field] {
        &[Field::Tlight]
    }
    fn register(&self, p: &mut Particles) {
        p.tlight = vec![0.0; p.nreal];
    }
    fn run(&self, b: Backend, p: &mut Particles, _w: &mut Work, _k: &Clock) {
        let (dim, n) = (p.dim, p.nreal);
        let (x, mat) = (&p.x[..dim * n], &p.mat[..n]);
        let (xdet, nrm, sf) = (&self.xdet, self.nrm.as_deref(), self.sf);
        Light { dim, x, mat, mt: &self.mt, xdet, nrm, sf, tlight: &mut p.tlight }.run(b);
    }
}

/// The burn fraction at the stage's time.
pub struct BurnStage {
    mt: MatTable,
    width: f64,
    /// The burn at t = 0: from zero (a dual run repeats the set-up on a state that has burnt).
    init: bool,
}

impl Stage for BurnStage {
    fn module(&self) -> Module {
        Module::Detonation
    }
    fn name(&self) -> &'static str {
        "detonation.burn"
    }
    fn reads(&self) -> &[Field] {
        &[Field::Mat, Field::Tlight, Field::H, Field::Rho, Field::Burn]
    }
    fn writes(&self) -> &[Field] {
        &[Field::Burn]
    }
    fn register(&self, p: &mut Particles) {
        p.burn = vec![0.0; p.nreal];
    }
    fn run(&self, b: Backend, p: &mut Particles, _w: &mut Work, k: &Clock) {
        let n = p.nreal;
        if self.init {
            p.burn[..n].fill(0.0);
        }
        let (mat, tlight, h, rho) = (&p.mat[..n], &p.tlight, &p.h[..n], &p.rho[..n]);
        Burn { t: k.t, mat, mt: &self.mt, tlight, h, rho, width: self.width, burn: &mut p.burn }.run(b);
    }
}

/// Runs for a programmed burn: the lighting times and the burn at t = 0 before the first step,
/// the burn fraction at every step.
pub fn plan(ctx: &PlanCtx) -> Contribution {
    let case = ctx.case;
    if !crate::case::programmed(case) {
        return Contribution::skip(if case.detonation.is_some() {
            "instantaneous burn: nothing to run"
        } else {
            "no charge lit"
        });
    }
    let det = case.detonation.as_ref();
    let xdet = det.and_then(|d| d.point_m.clone()).unwrap_or_default();
    let width = det.map(|d| d.width_h).unwrap_or(0.0);
    let sf = det.map(|d| d.lighting_speed_factor).unwrap_or(1.0);
    // the plane's normal made a unit vector here, once, outside the twins
    let nrm = det.and_then(|d| d.plane_normal.as_ref()).map(|n| {
        let len = n.iter().map(|v| v * v).sum::<f64>().sqrt();
        n.iter().map(|v| v / len).collect::<Vec<f64>>()
    });
    let burn = |init| Box::new(BurnStage { mt: ctx.mt.clone(), width, init }) as Box<dyn Stage>;
    let beta = ctx.mt.mpar.chunks(super::param::NPAR).any(|c| c[ETA_CJ] > 1.0);
    let why = match (beta, nrm.is_some()) {
        (true, false) => "programmed burn with the beta burn",
        (false, false) => "programmed burn",
        (true, true) => "programmed burn lit along a plane, with the beta burn",
        (false, true) => "programmed burn lit along a plane",
    };
    Contribution::run(
        why,
        vec![
            (Phase::Init, Box::new(LightStage { mt: ctx.mt.clone(), xdet, nrm, sf })),
            (Phase::Init, burn(true)),
            (Phase::Burn, burn(false)),
        ],
    )
}
