//! Measurements of finished runs: craters, ejecta, blast-wave radii, and the exact solutions of
//! the verification problems (Riemann, Sedov–Taylor, Noh and wall reflection, the CJ detonation
//! and its Taylor wave).

#[cfg(feature = "io")]
mod axis;
#[cfg(feature = "io")]
pub mod cj;
pub mod crater;
pub mod noh;
pub mod riemann;
pub mod sedov;
#[cfg(feature = "io")]
pub mod verify;
