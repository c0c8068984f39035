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

pub mod analysis;
pub mod bench;
pub mod blast_report;
pub mod case;
pub mod casedir;
pub mod cli;
pub mod dual;
pub mod error;
pub mod gauges;
pub mod migration;
pub mod modules;
pub mod output;
pub mod plot;
pub mod presets;
pub mod progress;
pub mod report;
pub mod runner;
pub mod setup;
pub mod sim;
pub mod state;
pub mod validate;
