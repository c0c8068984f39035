//! blastsph: a hydrocode for explosions in soil and water by smoothed particle hydrodynamics,
//! built as a Fortran-interoperable hybrid. The legacy Liu-style Fortran core (`fortran/`) and
//! its Rust twin implement every module ([`modules`]); the solver ([`sim`]) runs either, or any
//! mix; the dual run ([`dual`]) checks each Rust routine against its Fortran twin, step by step.
//!
//! Physics and equation numbers: `docs/theory.md` (thesis numbering). Case format: `docs/cases.md`.
#![deny(unsafe_code)]
// The Rust twins index arrays in loops written as the Fortran writes them (same order of
// operations, for bit-for-bit parity); iterator rewrites would obscure that correspondence.
#![allow(clippy::needless_range_loop)]

pub mod advice;
pub mod analysis;
#[cfg(feature = "plot")]
pub mod bench;
#[cfg(feature = "plot")]
pub mod blast_report;
pub mod case;
pub mod casedir;
#[cfg(feature = "cli")]
pub mod cli;
#[cfg(feature = "plot")]
pub mod converge;
pub mod dual;
pub mod error;
pub mod gauges;
pub mod migration;
pub mod modules;
pub mod os_ffi;
#[cfg(feature = "io")]
pub mod output;
#[cfg(feature = "plot")]
pub mod plot;
pub mod presets;
#[cfg(feature = "io")]
pub mod progress;
#[cfg(feature = "plot")]
pub mod report;
#[cfg(feature = "io")]
pub mod restart;
#[cfg(feature = "plot")]
pub mod revolve;
pub mod rundir;
#[cfg(feature = "io")]
pub mod runner;
pub mod setup;
pub mod sim;
pub mod state;
pub mod stress_invariants;
#[cfg(feature = "plot")]
pub mod validate;
