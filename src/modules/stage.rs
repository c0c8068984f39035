//! The shape every module shares: the implementations ([`Backend`]), a routine's argument list as
//! a value that runs either twin ([`Twin`]), a routine bound to the state ([`Stage`]), where in the
//! step it runs ([`Phase`]), and what a module contributes to a case's plan ([`Contribution`]).

use super::Module;
use super::param::MatTable;
use crate::case::Case;
use crate::state::{Clock, Field, Particles, Work};
use serde::Serialize;

/// Which implementation runs a module.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Backend {
    Fortran,
    Rust,
}

impl Backend {
    pub fn name(self) -> &'static str {
        match self {
            Backend::Fortran => "fortran",
            Backend::Rust => "rust",
        }
    }
    pub fn parse(s: &str) -> Option<Backend> {
        match s {
            "fortran" => Some(Backend::Fortran),
            "rust" => Some(Backend::Rust),
            _ => None,
        }
    }
}

/// A routine's argument list, written once: the struct holds the inputs and the outputs, and the
/// same value runs the Rust twin or the Fortran twin. [`Twin::run`] is the dispatch.
pub trait Twin {
    /// The Rust twin (`rust.rs`).
    fn rust(&mut self);
    /// The Fortran twin through its safe wrapper (`ffi.rs`).
    fn fortran(&mut self);
    /// Runs the implementation `b`.
    fn run(&mut self, b: Backend) {
        match b {
            Backend::Rust => self.rust(),
            Backend::Fortran => self.fortran(),
        }
    }
}

/// Where in the time step a stage runs. The step runs the phases in this order and, within a
/// phase, the stages of the modules in registry order (a module's own stages in the order its
/// `plan` lists them). `Init` runs once, before the first step; `Predict` every step but the first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Phase {
    /// Before the first step: lighting times, the burn at t = 0, the first p and c.
    Init,
    /// The staggered variables predicted at t (Liu's leapfrog).
    Predict,
    /// Type II mirror particles.
    Mirrors,
    /// Neighbour pairs.
    Search,
    /// W_ij and ∇W_ij.
    Kernel,
    /// Summation density.
    Density,
    /// ρ copied to the mirrors (summation density).
    DensityShare,
    /// Continuity rate Dρ/Dt.
    DensityRate,
    /// h from the density.
    Smooth,
    /// Burn fraction at t.
    Burn,
    /// Pressure and sound speed.
    Eos,
    /// p and c copied to the mirrors.
    EosShare,
    /// The viscosity switch's α_i advanced over the step.
    Switch,
    /// α copied to the mirrors.
    SwitchShare,
    /// The terms of the acceleration and energy rate (and dh/dt, XSPH).
    Rates,
    /// The total acceleration and energy rate.
    Sum,
    /// The step size (CFL).
    StepSize,
    /// The leapfrog to t + Δt.
    Advance,
    /// Corrections after the advance: return to the yield surface, h update.
    Correct,
}

impl Phase {
    /// The phases of one step, in order (`Init` excluded).
    pub const STEP: [Phase; 18] = [
        Phase::Predict,
        Phase::Mirrors,
        Phase::Search,
        Phase::Kernel,
        Phase::Density,
        Phase::DensityShare,
        Phase::DensityRate,
        Phase::Smooth,
        Phase::Burn,
        Phase::Eos,
        Phase::EosShare,
        Phase::Switch,
        Phase::SwitchShare,
        Phase::Rates,
        Phase::Sum,
        Phase::StepSize,
        Phase::Advance,
        Phase::Correct,
    ];
}

/// The rate terms a stage writes, by their rank in the sums: the acceleration is
/// Σ_terms acc_t + g and the energy rate Σ_terms de_t, added in rank order (the order fixes the
/// bits of the sums). Ranks in use: acceleration force 0, viscosity 1, penalty 2, wall 3; energy
/// force 0, viscosity 1, strength 2, conductivity 3.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Terms {
    pub acc: Option<u8>,
    pub de: Option<u8>,
}

/// The slots the plan gives a rate stage in the stacked term arrays (`Work::acc`, `Work::dde`),
/// and how many there are.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Slots {
    pub acc: usize,
    pub de: usize,
    pub nacc: usize,
    pub nde: usize,
}

impl Slots {
    /// The range of the acceleration term in `Work::acc` (`lda` = dim × ntotal values a term).
    pub fn acc_range(&self, lda: usize) -> std::ops::Range<usize> {
        self.acc * lda..(self.acc + 1) * lda
    }
    /// The range of the energy-rate term in `Work::dde` (`nt` values a term).
    pub fn de_range(&self, nt: usize) -> std::ops::Range<usize> {
        self.de * nt..(self.de + 1) * nt
    }
    /// Sizes the stacked term arrays for `dim` × `nt` (a no-op once sized).
    pub fn size(&self, w: &mut Work, dim: usize, nt: usize) {
        w.acc.resize(self.nacc * dim * nt, 0.0);
        w.dde.resize(self.nde * nt, 0.0);
    }
}

/// How far a stage's two implementations may differ, in units in the last place, and why.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Tolerance {
    pub ulp: u64,
    pub why: &'static str,
}

impl Default for Tolerance {
    fn default() -> Tolerance {
        Tolerance { ulp: 0, why: "same IEEE operations in the same order" }
    }
}

/// What the dual run compares a stage's Rust implementation with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Counterpart {
    /// blastsph's own Fortran twin (every module's stages).
    Fortran,
    /// Nothing in blastsph: a compatibility variant of the Rust twin (`src/migration/compat/<module>.rs`,
    /// `--compat`) reproduces a legacy code's semantics and has no Fortran twin in blastsph's
    /// core; it is compared with the user's legacy routine (`dual --legacy`). The string says
    /// which items it reproduces.
    None(&'static str),
    /// The user's legacy routine (`--legacy`): `run(Fortran)` calls it, `run(Rust)` runs the
    /// chain of Rust twins it stands for.
    Legacy,
    /// A legacy routine with no Rust twin in the case: it runs alone, not compared; the string
    /// says why.
    LegacyAlone(&'static str),
}

/// A routine bound to the state: what it reads and writes, and how it runs.
pub trait Stage: Send + Sync {
    /// The module it belongs to.
    fn module(&self) -> Module;
    /// `module.routine`, e.g. `viscosity.monaghan`.
    fn name(&self) -> &'static str;
    /// The fields it reads.
    fn reads(&self) -> &[Field];
    /// The fields it writes: what the dual run and the parity harness compare.
    fn writes(&self) -> &[Field];
    /// The outputs it writes for the real particles only, leaving the mirrors' rows to a later
    /// stage (the EOS's p and c, which `boundary.mirror_copy` copies to the mirrors): the dual
    /// run compares those rows only (a legacy routine that also fills the mirrors is not wrong).
    fn real_rows(&self) -> &[Field] {
        &[]
    }
    /// Allocates the state it keeps (once, when the simulation is set up: Spheral's
    /// `registerState`), e.g. the stress of a material with strength.
    fn register(&self, _p: &mut Particles) {}
    /// Sizes its outputs (before the call, outside the timing and the comparison).
    fn prepare(&self, _p: &mut Particles, _w: &mut Work) {}
    /// Runs implementation `b` on the state.
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, k: &Clock);
    /// The dual run's tolerance for this stage.
    fn tolerance(&self) -> Tolerance {
        Tolerance::default()
    }
    /// The rate terms it writes.
    fn terms(&self) -> Terms {
        Terms::default()
    }
    /// Takes the slots the plan assigned to its rate terms.
    fn assign(&mut self, _slots: Slots) {}
    /// What the dual run compares its Rust implementation with (default: the Fortran twin).
    fn counterpart(&self) -> Counterpart {
        Counterpart::Fortran
    }
    /// The module an output field belongs to (a legacy routine that stands for stages of several
    /// modules: the module of the stage that writes it); its own module by default.
    fn module_of(&self, _f: Field) -> Module {
        self.module()
    }
    /// The inputs its last run changed (a legacy routine writing an argument that its stages
    /// only read), taken: the dual run reports each as a divergence. Empty for blastsph's own
    /// stages, which write only their outputs.
    fn take_input_writes(&self) -> Vec<InputWrite> {
        Vec::new()
    }
}

/// A routine's change to an input of its stage (an argument the stage only reads): the first
/// changed value and the extent of the change, over the valid values (`ntotal` particles or
/// `niac` pairs).
#[derive(Debug, Clone, PartialEq)]
pub struct InputWrite {
    pub field: Field,
    /// The argument's name in the manifest's vocabulary (`u`, `vx`, `sxy`).
    pub arg: String,
    /// Per particle (false: per pair).
    pub per_particle: bool,
    /// Values per particle or pair in the argument (dim for `x`, `vx`; else 1).
    pub width: usize,
    /// The first changed value's index in the argument, its value before and after.
    pub index: usize,
    pub before: f64,
    pub after: f64,
    /// How many values were looked at and how many changed, the largest absolute and relative
    /// change, and the largest distance in units in the last place.
    pub checked: u64,
    pub count: u64,
    pub max_abs: f64,
    pub max_rel: f64,
    pub max_ulp: u64,
    /// Whether the state took the change (per-particle state, as the legacy program keeps it)
    /// or it was dropped (the pair list, kernel values and rate arrays are not the routine's).
    pub kept: bool,
}

/// What the plan knows when it asks the modules for their stages.
pub struct PlanCtx<'a> {
    pub case: &'a Case,
    pub dim: usize,
    pub mt: &'a MatTable,
    /// Kernel support in units of h.
    pub kappa: f64,
    /// Finest initial particle spacing (m).
    pub dx_min: f64,
    /// Initial positions of the real particles (m), dim × n.
    pub x0: &'a [f64],
    /// Initial smoothing lengths of the real particles (m).
    pub h0: &'a [f64],
}

/// What a module contributes to a case's plan: its stages with their phases, and why they run
/// (or, with no stages, why the module is skipped).
pub struct Contribution {
    pub why: String,
    pub stages: Vec<(Phase, Box<dyn Stage>)>,
}

impl Contribution {
    /// The module runs these stages.
    pub fn run(why: impl Into<String>, stages: Vec<(Phase, Box<dyn Stage>)>) -> Contribution {
        Contribution { why: why.into(), stages }
    }
    /// The module is not needed.
    pub fn skip(why: impl Into<String>) -> Contribution {
        Contribution { why: why.into(), stages: Vec::new() }
    }
}
