//! blastsph: a hydrocode for explosions in soil and water by smoothed particle hydrodynamics,
//! built as a Fortran-interoperable hybrid. The legacy Liu-style Fortran core (`fortran/`) and
//! its Rust twin implement every module ([`modules`]); the solver ([`sim`]) runs either, or any
//! mix; the dual run ([`dual`]) checks each Rust routine against its Fortran twin, step by step.
//!
//! Physics and equation numbers: `docs/theory.md` (thesis numbering). Case format: `docs/reference/cases.md`.
//!
//! ## Layers
//!
//! The layers are listed from the bottom up. A module imports only from its own layer and the
//! layers listed before it, and no two modules import each other, directly or through others
//! (`tests/layers.rs` reads this table).
//!
//! | layer | modules |
//! |---|---|
//! | core | `error`, `files`, `presets`, `os_ffi`, `modules`, `state`, `case`, `setup`, `sim`, `pairs`, `dual` |
//! | bridge | `migration` |
//! | run | `casedir`, `rundir`, `progress`, `stress_invariants`, `output`, `analysis`, `advice`, `gauges`, `runner`, `mpirun` |
//! | post | `plot`, `report`, `blast_report`, `revolve`, `validate`, `bench`, `converge` |
//! | cli | `cli` |
//!
//! The core (the modules and their twins, the particle state, the case, the set-up, the solver
//! and the dual run) builds alone: `cargo build --no-default-features --lib`. Analysis computes
//! and never draws; the plots are the post layer's.
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
pub mod files;
pub mod gauges;
#[cfg(feature = "legacy")]
pub mod migration;
pub mod modules;
#[cfg(feature = "mpi")]
pub mod mpirun;
pub mod os_ffi;
#[cfg(feature = "io")]
pub mod output;
pub mod pairs;
#[cfg(feature = "plot")]
pub mod plot;
pub mod presets;
#[cfg(feature = "io")]
pub mod progress;
#[cfg(feature = "plot")]
pub mod report;
#[cfg(feature = "plot")]
pub mod revolve;
pub mod rundir;
#[cfg(feature = "io")]
pub mod runner;
#[cfg(feature = "io")]
pub use runner::restart;
pub mod setup;
pub mod sim;
pub mod state;
pub mod stress_invariants;
#[cfg(feature = "plot")]
pub mod validate;
