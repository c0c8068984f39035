//! Measurements of finished runs: craters, ejecta, the exact Riemann solution, blast-wave radii.

#[cfg(feature = "io")]
pub mod blastwave;
pub mod crater;
pub mod riemann;
