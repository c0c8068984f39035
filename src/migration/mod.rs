//! Bring your own legacy code (docs/howto/migrate.md): a user's unmodified Liu-style Fortran,
//! described by a manifest ([`manifest`], argument names from [`vocab`]), built with generated
//! shims into a shared library ([`builder`], [`shim`]: `blastsph legacy build`), and called from
//! Rust through one C signature behind a safe API ([`ffi`]: [`LegacyLib`], [`Routine`], [`Args`]).
//!
//! The book's semantics that blastsph's Rust twins differ from are in `docs/compat-liu-book.md`.

pub mod adds;
pub mod attach;
pub mod bind;
pub mod builder;
pub mod compare;
pub mod compat;
pub mod ffi;
pub mod host_ffi;
#[cfg(feature = "plot")]
pub mod ledger;
pub mod legacy;
pub mod manifest;
pub mod shim;
pub mod vocab;

pub use attach::{LegacyBridge, bridge};
pub use builder::{BuildInfo, build};
pub use ffi::{Args, LegacyLib, Routine, Slot};
pub use manifest::{Manifest, check_capacity};
