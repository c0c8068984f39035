//! `[boundary] repulsion`: the force that pushes ordinary particles off boundary particles
//! (Liu & Liu 2003's `ext_force`; docs/theory.md "Boundary particles", docs/reference/cases.md).

use super::validate::{At, C_MAX, Checker, N_MAX, Range, X_MAX};
use crate::error::{Result, input};
use serde::Deserialize;

/// The repulsion D (x_o − x_b) [(r0/r)^p1 − (r0/r)^p2]/r² (m/s²) on an ordinary particle o
/// within r0 of a boundary particle b.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RepulsionCfg {
    /// Range r0 (m).
    pub r0_m: f64,
    /// D (m²/s²): the square of the largest speed expected (a dam-break code of the book's line: 9.8 m²/s²).
    pub d_m2s2: f64,
    /// Exponent p1 (the book's 12).
    #[serde(default = "default_p1")]
    pub p1: f64,
    /// Exponent p2 < p1 (the book's 4).
    #[serde(default = "default_p2")]
    pub p2: f64,
}

fn default_p1() -> f64 {
    12.0
}
fn default_p2() -> f64 {
    4.0
}

impl RepulsionCfg {
    /// Positive finite numbers, p1 > p2. That the case has boundary particles to push off is
    /// checked once they are made (`Sim::new`: a region's, or a legacy `virt_part`'s).
    pub(super) fn check(&self, v: &mut Checker) -> Result<()> {
        let at = At::top("boundary.repulsion");
        v.num(&at, "r0_m", self.r0_m, Range::above(0.0, X_MAX))?;
        v.num(&at, "d_m2s2", self.d_m2s2, Range::above(0.0, C_MAX * C_MAX))?;
        let pmax = f64::from(N_MAX);
        v.num(&at, "p1", self.p1, Range::above(0.0, pmax))?;
        v.num(&at, "p2", self.p2, Range::above(0.0, pmax))?;
        if self.p1 <= self.p2 {
            return Err(input(format!("boundary.repulsion: need p1 > p2 (got p1 = {}, p2 = {})", self.p1, self.p2)));
        }
        Ok(())
    }
}
