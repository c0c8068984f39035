//! Measurements of finished runs: craters, ejecta, the exact Riemann solution.

pub mod crater;
pub mod riemann;
