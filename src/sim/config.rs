//! What the solver itself needs from the case, resolved once: the time-step rule, the output
//! interval, the end, the walls for the penetration checks, gravity for the energy book-keeping.
//! (What a module needs lives in its stages.)

use crate::case::{Case, KernelKind, NnpsKind, StepRule};
use crate::modules::boundary;
use crate::modules::param::{MatTable, Segments};

/// A wall's frame: unit tangent(s), length(s) (m), unit normal.
pub type Frame = boundary::WallFrame;

#[derive(Debug, Clone)]
pub struct Config {
    pub dim: usize,
    /// The kernel (for interpolation outside the modules: point gauges).
    pub kernel: KernelKind,
    /// Kernel support in units of h.
    pub kappa: f64,
    /// The cell search (for reports).
    pub cell: bool,
    pub mt: MatTable,
    /// Every wall segment and its frame (for the penetration checks).
    pub all_segs: Segments,
    pub all_frames: Vec<Frame>,
    /// Gravity (m/s²), one component per dimension.
    pub grav: Vec<f64>,
    pub step: StepRule,
    pub dt_fixed: f64,
    pub dt_max: f64,
    /// End time (s).
    pub end: f64,
    /// Interval between outputs (s).
    pub out_interval: f64,
    /// Finest initial spacing (m).
    pub dx_min: f64,
    pub max_steps: u64,
}

impl Config {
    pub fn new(case: &Case, mt: MatTable, x0: &[f64], dx_min: f64) -> Config {
        let dim = case.dim;
        let all_segs = crate::setup::segments(case, x0, |_| true);
        Config {
            dim,
            kernel: case.sph.kernel,
            kappa: case.sph.kernel.support(),
            cell: case.sph.nnps == NnpsKind::Cell,
            mt,
            all_frames: (0..all_segs.len()).map(|s| boundary::frame(dim, all_segs.get(dim, s))).collect(),
            all_segs,
            grav: case.physics.gravity_ms2.clone().unwrap_or_else(|| vec![0.0; dim]),
            step: case.time.step,
            dt_fixed: case.time.dt_s.unwrap_or(0.0),
            dt_max: case.time.dt_max_s.unwrap_or(f64::INFINITY),
            end: case.time.end_s,
            out_interval: case.time.output_interval_s,
            dx_min,
            max_steps: case.time.max_steps,
        }
    }
}
