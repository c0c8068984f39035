//! The argument vocabulary of a legacy manifest: the names Liu & Liu's book code (2003) and the
//! codes grown out of it give their routines' dummy arguments, each with its blastsph meaning.
//!
//! A manifest lists a routine's arguments **by position**: the k-th name says what the routine's
//! k-th dummy argument is, whatever the routine calls it. So a code that names the density `dens`
//! still writes `rho` in that place. `docs/reference/legacy.md` has the same table for users; a test keeps
//! the two in step.
//!
//! Shapes are those of the legacy declarations (`x(dim,maxn)`, `w(max_interaction)`); blastsph
//! passes its own arrays (0-based, length `ntotal` or `npair`) and the generated shim copies them
//! into `maxn`- or `max_interaction`-sized buffers. Pair lists are 1-based in the legacy code and
//! 0-based in blastsph: the shim adds 1 on the way in and subtracts 1 on the way out.

use serde::{Deserialize, Serialize};

/// Fortran type of an argument: `double precision` or default `integer`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    Real,
    Int,
}

impl Kind {
    /// How messages name it: `double precision`, `a default integer`.
    pub fn described(self) -> &'static str {
        match self {
            Kind::Real => "double precision",
            Kind::Int => "a default integer",
        }
    }

    /// The C type gfortran's `-fc-prototypes-external` prints for it.
    pub fn c_type(self) -> &'static str {
        match self {
            Kind::Real => "double",
            Kind::Int => "int",
        }
    }
}

/// Shape of an argument in a whole-array call.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Shape {
    /// One value.
    Scalar,
    /// `a(maxn)`: one value per particle.
    Particle,
    /// `a(dim,maxn)`: a vector per particle.
    ParticleVec,
    /// `a(max_interaction)`: one value per pair.
    Pair,
    /// `a(dim,max_interaction)`: a vector per pair.
    PairVec,
}

impl Shape {
    /// Values per particle or pair (`dim` for vectors).
    pub fn stride(self, dim: usize) -> usize {
        match self {
            Shape::ParticleVec | Shape::PairVec => dim,
            _ => 1,
        }
    }
    pub fn per_pair(self) -> bool {
        matches!(self, Shape::Pair | Shape::PairVec)
    }
    pub fn per_particle(self) -> bool {
        matches!(self, Shape::Particle | Shape::ParticleVec)
    }
    /// How the docs write it.
    pub fn legacy(self) -> &'static str {
        match self {
            Shape::Scalar => "scalar",
            Shape::Particle => "maxn",
            Shape::ParticleVec => "dim×maxn",
            Shape::Pair => "max_interaction",
            Shape::PairVec => "dim×max_interaction",
        }
    }
}

/// Index base: `One` marks 1-based particle numbers that the shim translates (+1 in, −1 out).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Base {
    /// Not an index.
    None,
    /// A 1-based particle index in the legacy code, 0-based in blastsph.
    One,
}

/// What a routine usually does with it: `adds` takes `out` names only ([`super::adds`]); the
/// shim copies every array both ways.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    In,
    Out,
    InOut,
}

impl Role {
    pub fn name(self) -> &'static str {
        match self {
            Role::In => "in",
            Role::Out => "out",
            Role::InOut => "in/out",
        }
    }
}

/// One name of the vocabulary.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Term {
    /// The canonical name (lower case).
    pub name: &'static str,
    /// Other names of the same thing in Liu-derived codes.
    pub aliases: &'static [&'static str],
    pub kind: Kind,
    pub shape: Shape,
    pub base: Base,
    /// SI unit (`-` for counts and codes).
    pub unit: &'static str,
    /// The blastsph field it is, or what blastsph supplies.
    pub field: &'static str,
    pub role: Role,
    /// Which book routines take it, and any note.
    pub note: &'static str,
}

/// A [`Term`] from its fields, in the order of the struct.
macro_rules! t {
    ($name:expr, $aliases:expr, $kind:expr, $shape:expr, $base:expr, $unit:expr, $field:expr, $role:expr, $note:expr $(,)?) => {
        Term {
            name: $name,
            aliases: $aliases,
            kind: $kind,
            shape: $shape,
            base: $base,
            unit: $unit,
            field: $field,
            role: $role,
            note: $note,
        }
    };
}

use Base::{None as NB, One};
use Kind::{Int, Real};
use Role::{In, InOut, Out};
use Shape::{Pair, PairVec, Particle, ParticleVec, Scalar};

/// The vocabulary of whole-array calls (the default `call`).
#[rustfmt::skip]
pub const TERMS: &[Term] = &[
    // counts, step and time
    t!("itimestep", &[], Int, Scalar, NB, "-", "step number, 1 on the first step (blastsph's step count + 1)", In,
      "direct_find, link_list, tree_search, int_force, virt_part, single_step"),
    t!("maxtimestep", &[], Int, Scalar, NB, "-", "number of steps to run", In, "time_integration (a driver)"),
    t!("ntotal", &["nt", "n"], Int, Scalar, NB, "-", "number of particles the routine works on: real + virtual (Particles::ntotal)", InOut,
      "every routine; the book passes ntotal+nvirt; input returns it"),
    t!("nvirt", &[], Int, Scalar, NB, "-", "number of virtual (boundary) particles (ntotal − nreal)", InOut, "virt_part (out)"),
    t!("niac", &["npair"], Int, Scalar, NB, "-", "number of pairs (PairList length)", InOut,
      "out of the searches, in to every pair routine"),
    t!("dt", &[], Real, Scalar, NB, "s", "time step", In, "int_force, h_upgrade, single_step, time_integration"),
    t!("time", &[], Real, Scalar, NB, "s", "time", In, "thesis codes"),
    // particle state
    t!("x", &[], Real, ParticleVec, NB, "m", "position, Particles::x (x[d + dim*i])", InOut, "nearly every routine"),
    t!("vx", &["v"], Real, ParticleVec, NB, "m/s", "velocity, Particles::v", InOut, "nearly every routine"),
    t!("mass", &[], Real, Particle, NB, "kg (per m² in 1D, per m in 2D)", "mass, Particles::mass", In, ""),
    t!("hsml", &["h"], Real, Particle, NB, "m", "smoothing length, Particles::h", InOut,
      "h_upgrade writes it; link_list declares it a scalar and reads hsml(1), the book's global h"),
    t!("rho", &[], Real, Particle, NB, "kg/m³", "density, Particles::rho", InOut, "sum_density writes it"),
    t!("p", &[], Real, Particle, NB, "Pa", "pressure, Particles::p", InOut, "written by int_force (it calls the EOS)"),
    t!("c", &[], Real, Particle, NB, "m/s", "sound speed, Particles::c", InOut, "written by int_force, read by art_visc"),
    t!("u", &[], Real, Particle, NB, "J/kg", "specific internal energy, Particles::e", InOut, ""),
    t!("itype", &[], Int, Particle, NB, "-", "the book's type code: 1 ideal gas, 2 water (artificial EOS), < 0 a virtual particle", In,
      "int_force, viscosity, ext_force, sum_density; blastsph maps its materials to codes"),
    t!("mat", &[], Int, Particle, One, "-", "material number, 1-based (Particles::mat + 1)", In, "thesis codes"),
    t!("e", &[], Real, Particle, NB, "J/kg", "total specific energy (the book never sets it): a work array", Out, "time_integration"),
    t!("s", &[], Real, Particle, NB, "J/(kg K)", "entropy (not used by the book): a work array", InOut, "single_step, time_integration"),
    t!("t", &["temp"], Real, Particle, NB, "K", "temperature (not used by the book): a work array", InOut, "int_force, single_step"),
    t!("eta", &[], Real, Particle, NB, "Pa s", "dynamic viscosity, a work array (blastsph: the materials' dynamic_viscosity_pa_s, read by force.newtonian; not compared)", InOut, "viscosity (out), int_force (in)"),
    t!("burn", &["bf", "lambda"], Real, Particle, NB, "-", "burn fraction of a programmed burn, 0..1 (Particles::burn)", InOut, "thesis codes"),
    // deviatoric stress and its rates (thesis codes), each component its own array
    t!("sxx", &[], Real, Particle, NB, "Pa", "deviatoric stress xx, Particles::tau[0 + 6*i]", InOut, "thesis codes"),
    t!("syy", &[], Real, Particle, NB, "Pa", "deviatoric stress yy, Particles::tau[1 + 6*i]", InOut, "thesis codes"),
    t!("szz", &[], Real, Particle, NB, "Pa", "deviatoric stress zz, Particles::tau[2 + 6*i]", InOut, "thesis codes"),
    t!("sxy", &[], Real, Particle, NB, "Pa", "deviatoric stress xy, Particles::tau[3 + 6*i]", InOut, "thesis codes"),
    t!("sxz", &[], Real, Particle, NB, "Pa", "deviatoric stress xz, Particles::tau[4 + 6*i]", InOut, "thesis codes"),
    t!("syz", &[], Real, Particle, NB, "Pa", "deviatoric stress yz, Particles::tau[5 + 6*i]", InOut, "thesis codes"),
    t!("dsxx", &[], Real, Particle, NB, "Pa/s", "stress rate xx, Work::dtau[0 + 6*i]", Out, "thesis codes"),
    t!("dsyy", &[], Real, Particle, NB, "Pa/s", "stress rate yy, Work::dtau[1 + 6*i]", Out, "thesis codes"),
    t!("dszz", &[], Real, Particle, NB, "Pa/s", "stress rate zz, Work::dtau[2 + 6*i]", Out, "thesis codes"),
    t!("dsxy", &[], Real, Particle, NB, "Pa/s", "stress rate xy, Work::dtau[3 + 6*i]", Out, "thesis codes"),
    t!("dsxz", &[], Real, Particle, NB, "Pa/s", "stress rate xz, Work::dtau[4 + 6*i]", Out, "thesis codes"),
    t!("dsyz", &[], Real, Particle, NB, "Pa/s", "stress rate yz, Work::dtau[5 + 6*i]", Out, "thesis codes"),
    t!("epsxx", &["exx"], Real, Particle, NB, "1/s", "strain rate xx, Work::eps[0 + 6*i]", Out, "thesis codes"),
    t!("epsyy", &["eyy"], Real, Particle, NB, "1/s", "strain rate yy, Work::eps[1 + 6*i]", Out, "thesis codes"),
    t!("epszz", &["ezz"], Real, Particle, NB, "1/s", "strain rate zz, Work::eps[2 + 6*i]", Out, "thesis codes"),
    t!("epsxy", &["exy"], Real, Particle, NB, "1/s", "strain rate xy, Work::eps[3 + 6*i]", Out, "thesis codes"),
    t!("epsxz", &["exz"], Real, Particle, NB, "1/s", "strain rate xz, Work::eps[4 + 6*i]", Out, "thesis codes"),
    t!("epsyz", &["eyz"], Real, Particle, NB, "1/s", "strain rate yz, Work::eps[5 + 6*i]", Out, "thesis codes"),
    t!("rxy", &[], Real, Particle, NB, "1/s", "rotation rate xy, Work::rot[0 + 3*i]", Out, "thesis codes"),
    t!("rxz", &[], Real, Particle, NB, "1/s", "rotation rate xz, Work::rot[1 + 3*i]", Out, "thesis codes"),
    t!("ryz", &[], Real, Particle, NB, "1/s", "rotation rate yz, Work::rot[2 + 3*i]", Out, "thesis codes"),
    // rates
    t!("drhodt", &["drho"], Real, Particle, NB, "kg/(m³ s)", "density rate, Work::drho", Out, "con_density (out), time_integration"),
    t!("dvxdt", &[], Real, ParticleVec, NB, "m/s²", "the routine's own acceleration: its term of Work::acc", Out,
      "int_force, art_visc, ext_force"),
    t!("indvxdt", &[], Real, ParticleVec, NB, "m/s²", "acceleration of the internal force (the force term of Work::acc)", Out, "single_step"),
    t!("ardvxdt", &[], Real, ParticleVec, NB, "m/s²", "acceleration of the artificial viscosity (its term of Work::acc)", Out, "single_step"),
    t!("exdvxdt", &[], Real, ParticleVec, NB, "m/s²", "external acceleration (gravity, walls: their terms of Work::acc)", Out, "single_step"),
    t!("dvx", &[], Real, ParticleVec, NB, "m/s²", "total acceleration, Work::dv", Out, "single_step, time_integration"),
    t!("dedt", &[], Real, Particle, NB, "J/(kg s)", "the routine's own energy rate: its term of Work::dde", Out,
      "int_force, art_visc, art_heat"),
    t!("du", &[], Real, Particle, NB, "J/(kg s)", "total energy rate, Work::de (single_step passes it to int_force as dedt)", Out,
      "single_step, time_integration"),
    t!("avdudt", &[], Real, Particle, NB, "J/(kg s)", "energy rate of the artificial viscosity (its term of Work::dde)", Out, "single_step"),
    t!("ahdudt", &[], Real, Particle, NB, "J/(kg s)", "energy rate of the artificial heat (the conductivity's term of Work::dde, conductivity.noh)", Out, "single_step"),
    t!("tdsdt", &[], Real, Particle, NB, "J/(kg s)", "viscous heating T ds/dt = η/(2ρ) ε:ε, added by int_force to dedt (blastsph: the energy term of force.newtonian; not compared on its own)", Out, "int_force"),
    t!("ds", &[], Real, Particle, NB, "J/(kg K s)", "entropy rate (not used by the book): a work array", Out, "single_step"),
    t!("av", &[], Real, ParticleVec, NB, "m/s", "averaged-velocity (XSPH) correction, Work::av", Out, "av_vel, single_step"),
    t!("dx", &[], Real, ParticleVec, NB, "m/s", "dx/dt (never set by the book): a work array; in each_pair calls the pair's separation", Out,
      "single_step, time_integration"),
    t!("v_min", &[], Real, ParticleVec, NB, "m/s", "velocity at the last half step, Work::v_min", InOut, "time_integration"),
    t!("u_min", &["e_min"], Real, Particle, NB, "J/kg", "energy at the last half step, Work::e_min", InOut, "time_integration"),
    t!("rho_min", &[], Real, Particle, NB, "kg/m³", "density at the last half step, Work::rho_min", InOut, "time_integration"),
    t!("countiac", &["ns"], Int, Particle, NB, "-", "number of neighbours of each particle", Out, "direct_find, link_list, tree_search"),
    // pairs
    t!("pair_i", &[], Int, Pair, One, "-", "first particle of each pair, PairList::i (0-based there)", InOut,
      "out of the searches, in to every pair routine"),
    t!("pair_j", &[], Int, Pair, One, "-", "second particle of each pair, PairList::j (0-based there)", InOut,
      "out of the searches, in to every pair routine"),
    t!("w", &[], Real, Pair, NB, "1/m^dim", "kernel W_ij of each pair, Work::w", InOut, "out of the searches, in to sum_density, av_vel"),
    t!("dwdx", &[], Real, PairVec, NB, "1/m^(dim+1)", "kernel gradient ∇_i W_ij of each pair, Work::dwdx", InOut,
      "out of the searches, in to every force routine"),
    // one component of a vector, for codes that keep one array per component (xp, yp, zp)
    t!("x_1", &[], Real, Particle, NB, "m", "position's first component, Particles::x[0 + dim*i]", InOut, "split-array codes"),
    t!("x_2", &[], Real, Particle, NB, "m", "position's second component, Particles::x[1 + dim*i] (dim ≥ 2)", InOut, "split-array codes"),
    t!("x_3", &[], Real, Particle, NB, "m", "position's third component, Particles::x[2 + dim*i] (dim 3)", InOut, "split-array codes"),
    t!("vx_1", &[], Real, Particle, NB, "m/s", "velocity's first component, Particles::v[0 + dim*i]", InOut, "split-array codes"),
    t!("vx_2", &[], Real, Particle, NB, "m/s", "velocity's second component (dim ≥ 2)", InOut, "split-array codes"),
    t!("vx_3", &[], Real, Particle, NB, "m/s", "velocity's third component (dim 3)", InOut, "split-array codes"),
    t!("dvxdt_1", &[], Real, Particle, NB, "m/s²", "first component of the routine's own acceleration (its term of Work::acc)", Out, "split-array codes"),
    t!("dvxdt_2", &[], Real, Particle, NB, "m/s²", "second component of the routine's own acceleration (dim ≥ 2)", Out, "split-array codes"),
    t!("dvxdt_3", &[], Real, Particle, NB, "m/s²", "third component of the routine's own acceleration (dim 3)", Out, "split-array codes"),
    t!("dwdx_1", &[], Real, Pair, NB, "1/m^(dim+1)", "first component of each pair's kernel gradient, Work::dwdx[0 + dim*k]", InOut, "split-array codes"),
    t!("dwdx_2", &[], Real, Pair, NB, "1/m^(dim+1)", "second component of each pair's kernel gradient (dim ≥ 2)", InOut, "split-array codes"),
    t!("dwdx_3", &[], Real, Pair, NB, "1/m^(dim+1)", "third component of each pair's kernel gradient (dim 3)", InOut, "split-array codes"),
];

/// A vector's component name (`x_2`): the vector's name and the 0-based component.
pub fn vector_component(name: &str) -> Option<(&'static str, usize)> {
    let (base, k) = name.rsplit_once('_')?;
    let k: usize = match k {
        "1" => 0,
        "2" => 1,
        "3" => 2,
        _ => return None,
    };
    ["x", "vx", "dvxdt", "dwdx"].into_iter().find(|b| *b == base).map(|b| (b, k))
}

/// The names of an `each_pair` call: what the book's `direct_find` hands to `kernel` for pair k.
#[rustfmt::skip]
pub const PAIR_TERMS: &[Term] = &[
    t!("r", &[], Real, Scalar, NB, "m", "distance ‖x_i − x_j‖ = sqrt(Σ_d dx_d²), summed from d = 1 as direct_find does", In, "kernel"),
    t!("dx", &[], Real, ParticleVec, NB, "m", "separation x_i − x_j (dim values)", In, "kernel"),
    t!("hsml", &["h"], Real, Scalar, NB, "m", "the pair's smoothing length (h_i + h_j)/2, as direct_find computes it", In, "kernel"),
    t!("w", &[], Real, Scalar, NB, "1/m^dim", "W_ij, stored into Work::w[k]", Out, "kernel"),
    t!("dwdx", &[], Real, ParticleVec, NB, "1/m^(dim+1)", "∇_i W_ij (dim values), stored into Work::dwdx", Out, "kernel"),
];

/// How a routine is called.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CallMode {
    /// Once, on whole arrays (the default).
    Whole,
    /// Once per particle i = 1..ntotal, with element i of each per-particle argument.
    EachParticle,
    /// Once per pair k = 1..niac, with the pair's r, dx, h and slots k of w and dwdx.
    EachPair,
}

impl CallMode {
    pub fn parse(s: &str) -> Option<CallMode> {
        match s {
            "whole" => Some(CallMode::Whole),
            "each_particle" => Some(CallMode::EachParticle),
            "each_pair" => Some(CallMode::EachPair),
            _ => None,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            CallMode::Whole => "whole",
            CallMode::EachParticle => "each_particle",
            CallMode::EachPair => "each_pair",
        }
    }
}

/// The term a name stands for in a whole-array call (canonical names and aliases, any case).
pub fn lookup(name: &str) -> Option<&'static Term> {
    let n = name.trim().to_ascii_lowercase();
    TERMS.iter().find(|t| t.name == n || t.aliases.contains(&n.as_str()))
}

/// The term a name stands for in an `each_pair` call.
pub fn lookup_pair(name: &str) -> Option<&'static Term> {
    let n = name.trim().to_ascii_lowercase();
    PAIR_TERMS.iter().find(|t| t.name == n || t.aliases.contains(&n.as_str()))
}

/// Every name and alias of the vocabulary (for error messages).
pub fn all_names() -> Vec<&'static str> {
    TERMS.iter().map(|t| t.name).collect()
}

/// The blastsph module names a manifest may give (`module = "eos,force"`): the solver's modules
/// (the registry, `crate::modules::Module::ALL`), plus `setup` (a routine that makes the initial
/// particles, like the book's `input`), `output`, and `init` (a routine that fills the code's
/// COMMON blocks, called once before everything else).
pub fn modules() -> Vec<&'static str> {
    crate::modules::Module::ALL.iter().map(|m| m.name()).chain(["setup", "output", "init"]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_aliases_are_unique() {
        let mut seen = std::collections::HashSet::new();
        for t in TERMS {
            assert!(seen.insert(t.name), "{} twice", t.name);
            for a in t.aliases {
                assert!(seen.insert(a), "alias {a} twice");
            }
        }
    }

    #[test]
    fn lookup_finds_aliases_in_any_case() {
        assert_eq!(lookup("NS").map(|t| t.name), Some("countiac"));
        assert_eq!(lookup("Drho").map(|t| t.name), Some("drhodt"));
        assert!(lookup("nonsense").is_none());
        assert_eq!(lookup_pair("r").map(|t| t.name), Some("r"));
        assert!(lookup_pair("rho").is_none());
    }

    #[test]
    fn the_module_list_holds_every_solver_module_and_setup() {
        let m = modules();
        assert!(m.contains(&"eos") && m.contains(&"geometry") && m.contains(&"setup"), "{m:?}");
    }
}
