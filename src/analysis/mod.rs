//! Measurements of finished runs: craters, ejecta, blast-wave radii, and the exact solutions of
//! the verification problems (Riemann, Sedov–Taylor, Noh and wall reflection, the CJ detonation
//! and its Taylor wave).

pub use crate::modules::detonation::cj;
pub mod crater;
pub mod noh;
pub mod riemann;
pub mod sedov;
#[cfg(feature = "io")]
pub mod verify;
