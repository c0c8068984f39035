//! The modules (docs/design.md, the module interface).
//!
//! A *module* is one physics or numerics routine family: a folder `src/modules/<module>/` with its
//! parameters and argument types (`mod.rs`), its Rust twin (`rust.rs`), the safe wrapper of its
//! Fortran twin `fortran/src/sph_<module>.f90` (`ffi.rs`, the only `unsafe`), and its parity test
//! (`parity.rs`). It is registered by one line of `registry!` below.
//!
//! Two values make a module:
//! - each routine's **argument list**, a struct written once, that implements [`Twin`]: the same
//!   value runs either implementation (`args.run(backend)`);
//! - its **stages** ([`Stage`]): a routine bound to the state, with the fields it reads and writes
//!   and the phase of the step it runs in. The module's `plan` function says which stages a case
//!   needs and why; the solver's step is the ordered list of those stages (`blastsph check` prints
//!   it). The dual run and the parity harness work on any stage through its declared outputs.
//!
//! Rust twins gather: every particle sums over the pairs that touch it, in ascending pair order
//! (the incidence lists of [`nnps::PairList`]). That is the order in which the Fortran pair loops
//! scatter into the same particle, and each pair term is computed with the same operations in the
//! same order, so the sums agree bit for bit and results do not depend on the thread count.

mod par;
/// The legacy interface's constants and the material table, from the core's leaf [`crate::param`].
pub use crate::param;
pub mod ranks;
mod stage;
#[cfg(test)]
pub(crate) mod testkit;
pub mod ulp;

pub(crate) mod ffi_util;
pub(crate) use par::{
    CHUNK, Sums, by_dim, fmax, fmin, gather_signed, gather_signed_max, gather_signed_own, grow, ipow, par_rows,
    par_rows2, serial,
};
pub use stage::{Backend, Contribution, Counterpart, InputWrite, Phase, PlanCtx, Slots, Stage, Terms, Tolerance, Twin};

/// The module registry: one line per module, `folder: Variant => "what it computes"`. The order is
/// the order in which a phase of the step runs the modules' stages. Each folder provides
/// `pub fn plan(ctx: &PlanCtx) -> Contribution`.
macro_rules! registry {
    ($($m:ident : $v:ident => $what:literal,)*) => {
        $(pub mod $m;)*

        /// A module of the registry.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
        #[serde(rename_all = "lowercase")]
        pub enum Module {
            $($v,)*
        }

        impl Module {
            /// Every module, in registry order.
            pub const ALL: &'static [Module] = &[$(Module::$v,)*];

            /// The module's name (its folder).
            pub fn name(self) -> &'static str {
                match self {
                    $(Module::$v => stringify!($m),)*
                }
            }

            /// What the module computes, for `blastsph check`.
            pub fn what(self) -> &'static str {
                match self {
                    $(Module::$v => $what,)*
                }
            }

            /// The stages a case needs from this module, and why.
            pub fn plan(self, ctx: &PlanCtx) -> Contribution {
                match self {
                    $(Module::$v => $m::plan(ctx),)*
                }
            }
        }
    };
}

registry! {
    boundary: Boundary => "virtual particles: type I wall force, type II mirrors",
    nnps: Nnps => "neighbour pairs within the kernel support",
    kernel: Kernel => "W_ij and grad W_ij per pair (5-1)",
    density: Density => "summation density or continuity rate (Table 4-1)",
    detonation: Detonation => "programmed burn: lighting times and burn fraction",
    eos: Eos => "p and c per material (4-39..4-46)",
    strength: Strength => "strain/rotation rates, Jaumann rate, Drucker-Prager (4-29..4-32)",
    force: Force => "momentum and energy rates from the stress (4-33..4-38)",
    viscosity: Viscosity => "Monaghan artificial viscosity (4-47, 4-48)",
    conductivity: Conductivity => "Price artificial conductivity or Noh artificial heat: energy exchange across jumps of e (off by default)",
    penalty: Penalty => "penalty force between materials (4-53, 4-54)",
    absorb: Absorb => "absorbing walls: Lysmer-Kuhlemeyer dashpots and the static reaction on a layer",
    xsph: Xsph => "averaged velocity (XSPH)",
    smoothing: Smoothing => "smoothing-length evolution (2-15, 2-16)",
    geometry: Geometry => "axisymmetric (RZ): ring masses m/(2 pi r), hoop terms",
    integrator: Integrator => "leapfrog, rate sums, CFL step (2-17..2-27)",
}

impl Module {
    pub fn parse(s: &str) -> Option<Module> {
        Module::ALL.iter().copied().find(|m| m.name() == s)
    }

    /// The names of every module, comma-separated.
    pub fn names() -> String {
        Module::ALL.iter().map(|m| m.name()).collect::<Vec<_>>().join(", ")
    }
}
