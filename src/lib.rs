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
//! | core | `error`, `files`, `presets`, `os_ffi`, `param`, `modules`, `state`, `case`, `setup`, `sim`, `pairs`, `dual` |
//! | bridge | `migration` |
//! | run | `casedir`, `rundir`, `progress`, `stress_invariants`, `output`, `analysis`, `advice`, `gauges`, `runner`, `mpirun` |
//! | post | `plot`, `report`, `blast_report`, `revolve`, `validate`, `bench`, `converge` |
//! | cli | `cli` |
//!
//! The core (the modules and their twins, the particle state, the case, the set-up, the solver
//! and the dual run) builds alone: `cargo build --no-default-features --lib`. Analysis computes
//! and never draws; the plots are the post layer's.
//!
//! ## The public API
//!
//! The binary calls [`cli::main`]; the rest of the public API is what a program (the tests, a
//! script's own driver) needs to run and check a case without the command line. Everything
//! else is crate-private.
//!
//! | entry point | what it does |
//! |---|---|
//! | [`case::load`] | reads a case file (with `--set` overrides) and checks it: a [`case::Case`] |
//! | [`setup::particles`], [`setup::material_table`] | the case's initial particles and its material table |
//! | [`sim::Sim`] with [`sim::Overrides`] | the solver: [`sim::Sim::new`], then step it |
//! | [`runner::run`] with [`runner::RunOptions`] | a whole run into a run directory (particles.h5, summary.json, gauges.csv); [`runner::run_sim`] runs a [`sim::Sim`] built by the caller |
//! | [`cli::dual_run`], [`dual::Comparator`] | the dual run: every stage in both twins, compared field by field |
//! | [`modules`] | each module's argument lists ([`modules::Twin`]), stages ([`modules::Stage`]) and [`modules::Module`] registry |
//! | [`state`] | the particle state ([`state::Particles`], [`state::Work`]) the stages read and write |
//! | [`param`] | the legacy interface's constants and the material table |
//! | [`output::read_frames`], [`report::report`], [`revolve::revolve`] | reading a run's frames back, its report, an RZ run revolved to 3D |
//! | [`analysis`] | exact solutions and measures (Riemann, Sedov, crater) |
//! | [`migration`] | the legacy bridge: build and run a user's own Liu-style Fortran |
//! | [`mod@bench`] | the benchmark matrix |
#![deny(unsafe_code)]
// The core-only build (no `io`) leaves out the run layer, whose helpers in the core's modules
// (files, run folders, crate-private measures) then have no caller.
#![cfg_attr(not(feature = "io"), allow(dead_code, unused_imports))]
// The Rust twins index arrays in loops written as the Fortran writes them (same order of
// operations, for bit-for-bit parity); iterator rewrites would obscure that correspondence.
#![allow(clippy::needless_range_loop)]

#[cfg(feature = "io")]
pub(crate) mod advice;
pub mod analysis;
#[cfg(feature = "plot")]
pub mod bench;
#[cfg(feature = "plot")]
pub(crate) mod blast_report;
pub mod case;
#[cfg(feature = "io")]
pub(crate) mod casedir;
#[cfg(feature = "cli")]
pub mod cli;
#[cfg(feature = "plot")]
pub(crate) mod converge;
pub mod dual;
pub mod error;
pub(crate) mod files;
#[cfg(feature = "io")]
pub(crate) mod gauges;
#[cfg(feature = "legacy")]
pub mod migration;
pub mod modules;
#[cfg(feature = "mpi")]
pub mod mpirun;
#[cfg(feature = "cli")]
pub(crate) mod os_ffi;
#[cfg(feature = "io")]
pub mod output;
pub(crate) mod pairs;
pub mod param;
#[cfg(feature = "plot")]
pub(crate) mod plot;
pub(crate) mod presets;
#[cfg(feature = "io")]
pub(crate) mod progress;
#[cfg(feature = "plot")]
pub mod report;
#[cfg(feature = "plot")]
pub mod revolve;
pub mod rundir;
#[cfg(feature = "io")]
pub mod runner;
pub mod setup;
pub mod sim;
pub mod state;
#[cfg(feature = "io")]
pub(crate) mod stress_invariants;
#[cfg(feature = "plot")]
pub(crate) mod validate;
