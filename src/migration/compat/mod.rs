//! Compatibility profiles of the Rust twins (`--compat liu-book`, the case's `[compat]` table):
//! each **item** is one place where a legacy code computes differently from blastsph's twins
//! (`docs/compat-liu-book.md` §14), reproduced bit for bit by a variant of the module's Rust twin
//! in `src/migration/compat/<module>.rs`. A profile switches a set of items on; each item can be
//! switched on or off on its own over it:
//!
//! ```toml
//! [compat]
//! profile = "liu-book"     # every item of the book but global_h (that is link_list's)
//! sound_speed = false      # ... but blastsph's adiabatic sound speed
//! ```
//!
//! or `--compat liu-book,-sound_speed` on the command line (turned into the `--set` overrides
//! `compat.profile="liu-book"`, `compat.sound_speed=false`, so case.toml of the run records them).
//! Without a `[compat]` table nothing changes: the twins and their Fortran parity are untouched.
//! The variants have no Fortran twin in blastsph's core: the dual run says so for their stages and
//! compares them with the user's legacy routines (`dual --legacy`).

use crate::case::{Case, CompatCfg, EosCfg};
use crate::error::{Result, input};
use crate::modules::{Contribution, Module, PlanCtx};
use serde::Serialize;

/// The `Stage` methods of a compatibility stage (`compat/<module>.rs`) that stands where its field
/// `normal`, blastsph's own stage, would: its module, name, the fields it reads and writes, the
/// state it registers and sizes, and its rate-term slots are the normal stage's; the stage itself
/// writes only `run` and `counterpart`.
macro_rules! as_its_normal_stage {
    () => {
        fn module(&self) -> $crate::modules::Module {
            $crate::modules::Stage::module(&self.normal)
        }
        fn name(&self) -> &'static str {
            $crate::modules::Stage::name(&self.normal)
        }
        fn reads(&self) -> &[$crate::state::Field] {
            $crate::modules::Stage::reads(&self.normal)
        }
        fn writes(&self) -> &[$crate::state::Field] {
            $crate::modules::Stage::writes(&self.normal)
        }
        fn real_rows(&self) -> &[$crate::state::Field] {
            $crate::modules::Stage::real_rows(&self.normal)
        }
        fn register(&self, p: &mut $crate::state::Particles) {
            $crate::modules::Stage::register(&self.normal, p)
        }
        fn prepare(&self, p: &mut $crate::state::Particles, w: &mut $crate::state::Work) {
            $crate::modules::Stage::prepare(&self.normal, p, w)
        }
        fn terms(&self) -> $crate::modules::Terms {
            $crate::modules::Stage::terms(&self.normal)
        }
        fn assign(&mut self, slots: $crate::modules::Slots) {
            $crate::modules::Stage::assign(&mut self.normal, slots)
        }
    };
}
pub(crate) use as_its_normal_stage;

pub mod conductivity;
pub mod density;
pub mod eos;
pub mod force;
pub mod integrator;
pub mod kernel;
pub mod nnps;
pub mod smoothing;
pub mod viscosity;
pub mod xsph;

/// One compatibility item.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Item {
    Literals,
    InputLiterals,
    DtLiteral,
    KernelLiterals,
    SoundSpeed,
    Kernel,
    QuinticGradient,
    PairTest,
    VirtualPairs,
    GlobalH,
    ForceEnergy,
    PaSph1,
    NorDensity,
    HUpgrade,
    ViscMu,
    ViscEnergy,
    XsphExpr,
    XsphVelocity,
    EnergyFloor,
    RateSum,
    RealPower,
}

/// What each item is: its name, the modules whose twins it changes, and what it does (the book
/// against blastsph; `docs/compat-liu-book.md` has the details, section in brackets).
pub const ITEMS: &[(Item, &str, &str, &str)] = &[
    (
        Item::Literals,
        "literals",
        "force,conductivity,eos,viscosity,xsph,integrator,boundary",
        "the routines' single-precision literals but the kernel's: the 2./3. of the viscous strain rate, 0.01 in the artificial heat; the case's gamma, a morris EOS's c_ms, dynamic_viscosity_pa_s, gravity_ms2, the boundary repulsion's r0_m and d_m2s2, phi_over_h, alpha, beta, g1, g2 and xsph_eps rounded to single precision as the book's literals are (§0, §13)",
    ),
    (
        Item::InputLiterals,
        "input_literals",
        "setup",
        "the input routine's single-precision literals: each region's rho, e, mass, h and velocity rounded to single precision (§0)",
    ),
    (
        Item::DtLiteral,
        "dt_literal",
        "integrator",
        "the time step's single-precision literal: the case's dt_s rounded to single precision (§0)",
    ),
    (
        Item::KernelLiterals,
        "kernel_literals",
        "kernel",
        "the kernel's single-precision literals: 2./3. and pi (param.inc's pi) in the kernel's expressions (§0, §3)",
    ),
    (
        Item::SoundSpeed,
        "sound_speed",
        "eos",
        "ideal-gas sound speed sqrt((gamma-1) e), not sqrt(gamma (gamma-1) e) (§5)",
    ),
    (
        Item::Kernel,
        "kernel",
        "kernel",
        "the book's kernel expressions, their association and the q <= 1, q <= 2 (q <= 3) branches (§3)",
    ),
    (
        Item::QuinticGradient,
        "quintic_gradient",
        "kernel",
        "the book's quintic gradient below q = 1, (-120 + 120 q - 50 q^2) (§3; a known defect of the book code)",
    ),
    (
        Item::PairTest,
        "pair_test",
        "nnps",
        "the search's test sqrt(r^2) < kappa h_ij with an integer kappa, not r^2 < (kappa h_ij)^2 (§2)",
    ),
    (
        Item::VirtualPairs,
        "virtual_pairs",
        "nnps",
        "pairs among virtual (mirror) particles too: i over all particles (§2)",
    ),
    (
        Item::GlobalH,
        "global_h",
        "nnps,kernel",
        "link_list's global h: the first particle's h in the test and in the kernel; pairs in canonical order (link_list's own order is compared as a set) (§2); not in the liu-book profile, which is direct_find's",
    ),
    (
        Item::ForceEnergy,
        "force_energy",
        "force",
        "the force's energy rate: sum_d (v_j - v_i)_d h_d per pair, scattered, then 0 + 0.5 x (§6)",
    ),
    (
        Item::PaSph1,
        "pa_sph1",
        "force",
        "param.inc's pa_sph = 1: h = -(p_i + p_j) dW/dx_d / (rho_i rho_j) and its energy rate (v_j - v_i)_d h_d, both scaled by 1/(rho_i rho_j) after the sum over d (§6); not in the liu-book profile (the book ships pa_sph = 2)",
    ),
    (
        Item::NorDensity,
        "nor_density",
        "density",
        "param.inc's nor_density = .true.: the summed density divided by the kernel's integral sum_j (m_j/rho_j) W_ij over the densities before the summation (§4); not in the liu-book profile (the book ships .false.)",
    ),
    (
        Item::HUpgrade,
        "h_upgrade",
        "smoothing",
        "param.inc's sle = 2: h_upgrade moves h by a whole step in the step, h += dt (h/dim) sum_j (m_j/rho_j)(v_j - v_i).gradW, h <= 0 undone, in place of blastsph's rate and theta update (§9); not in the liu-book profile (the book ships sle = 0)",
    ),
    (Item::ViscMu, "visc_mu", "viscosity", "the viscosity's mu denominator r^2 + ((h h) eta) eta (§7)"),
    (
        Item::ViscEnergy,
        "visc_energy",
        "viscosity",
        "the viscosity's energy: - (m dv_d) h_d per component into both particles, halved at the end (§7)",
    ),
    (Item::XsphExpr, "xsph_expr", "xsph", "XSPH's term ((2 m_j) dv/(rho_i + rho_j)) W_ij (§8)"),
    (
        Item::XsphVelocity,
        "xsph_velocity",
        "integrator",
        "XSPH added to the velocity itself, without dt: v = (v + dt/2 dv) + av, x += dt v (§8, §10)",
    ),
    (Item::EnergyFloor, "energy_floor", "integrator", "u < 0 set to 0 after each energy update (§10)"),
    (
        Item::RateSum,
        "rate_sum",
        "integrator",
        "the book's time integration order: dv = (force + external) + viscosity, du = (force + viscosity) + 0, the nsym = 0 source terms (§10, §11)",
    ),
    (
        Item::RealPower,
        "real_power",
        "kernel",
        "the cubic kernel's q^3 as the real power q**3.0 (libm's pow), as a code that writes q**3._rk computes it, with the item kernel; not in the liu-book profile (the book writes q**3, which gfortran multiplies out)",
    ),
];

/// The profiles and the items each switches on.
pub const PROFILES: &[(&str, &str)] = &[
    (
        "liu-book",
        "every item but global_h, pa_sph1, nor_density, h_upgrade, real_power: Liu & Liu's book code as shipped (direct_find, pa_sph = 2, nor_density off)",
    ),
    ("none", "no item (blastsph's own twins)"),
];

impl Item {
    pub fn name(self) -> &'static str {
        ITEMS.iter().find(|t| t.0 == self).map_or("?", |t| t.1)
    }
    pub fn modules(self) -> &'static str {
        ITEMS.iter().find(|t| t.0 == self).map_or("", |t| t.2)
    }
    pub fn parse(s: &str) -> Option<Item> {
        ITEMS.iter().find(|t| t.1 == s).map(|t| t.0)
    }
    fn bit(self) -> u32 {
        1 << (self as u32)
    }
    /// Every item, in order.
    pub fn all() -> impl Iterator<Item = Item> {
        ITEMS.iter().map(|t| t.0)
    }
}

/// The items switched on: a small copyable set, carried by the compat stages.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct Flags(u32);

impl Flags {
    pub fn has(self, i: Item) -> bool {
        self.0 & i.bit() != 0
    }
    pub fn with(self, i: Item, on: bool) -> Flags {
        if on { Flags(self.0 | i.bit()) } else { Flags(self.0 & !i.bit()) }
    }
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }
    /// Any of the items of `module` on.
    pub fn touches(self, module: &str) -> bool {
        Item::all().any(|i| self.has(i) && i.modules().split(',').any(|m| m == module))
    }
    /// The names of the items on, comma-separated.
    pub fn names(self) -> String {
        Item::all().filter(|&i| self.has(i)).map(Item::name).collect::<Vec<_>>().join(",")
    }
    /// The items of a profile.
    pub fn profile(name: &str) -> Option<Flags> {
        match name {
            "liu-book" => Some(
                Item::all()
                    .filter(|&i| {
                        !matches!(i, Item::GlobalH | Item::PaSph1 | Item::NorDensity | Item::HUpgrade | Item::RealPower)
                    })
                    .fold(Flags(0), |f, i| f.with(i, true)),
            ),
            "none" => Some(Flags(0)),
            _ => None,
        }
    }
    /// A short label for plan lines and reports ("liu-book", "liu-book,-sound_speed", ...).
    pub fn label(self) -> String {
        if self.is_empty() {
            return "none".into();
        }
        let book = Flags::profile("liu-book").unwrap_or_default();
        if self == book {
            return "liu-book".into();
        }
        let off: Vec<&str> = Item::all().filter(|&i| book.has(i) && !self.has(i)).map(Item::name).collect();
        let on: Vec<&str> = Item::all().filter(|&i| !book.has(i) && self.has(i)).map(Item::name).collect();
        if off.len() <= on.len() + 3 && off.len() < 7 {
            let mut parts = vec!["liu-book".to_string()];
            parts.extend(off.iter().map(|n| format!("-{n}")));
            parts.extend(on.iter().map(|n| n.to_string()));
            parts.join(",")
        } else {
            self.names()
        }
    }
}

/// The items the case's `[compat]` table switches on; an unknown profile or item is an input
/// error.
pub fn flags(cfg: &CompatCfg) -> Result<Flags> {
    let mut f = match &cfg.profile {
        None => Flags(0),
        Some(p) => Flags::profile(p).ok_or_else(|| {
            input(format!("compat.profile = \"{p}\": no such profile (profiles: {})", profile_names()))
        })?,
    };
    for (k, &on) in &cfg.items {
        let i = Item::parse(k)
            .ok_or_else(|| input(format!("compat.{k}: no such compatibility item (items: {})", item_names())))?;
        f = f.with(i, on);
    }
    Ok(f)
}

fn profile_names() -> String {
    PROFILES.iter().map(|p| p.0).collect::<Vec<_>>().join(", ")
}

/// The names of every item, comma-separated.
pub fn item_names() -> String {
    Item::all().map(Item::name).collect::<Vec<_>>().join(", ")
}

/// `--compat SPEC` as `--set` overrides of the case's `[compat]` table. SPEC is comma-separated:
/// a profile (`liu-book`, `none`), an item to switch on (`sound_speed`), or one to switch off
/// (`-sound_speed`, `no-sound_speed`).
pub fn sets_of(spec: &str) -> Result<Vec<String>> {
    let mut out = Vec::new();
    for part in spec.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        if Flags::profile(part).is_some() {
            out.push(format!("compat.profile=\"{part}\""));
            continue;
        }
        let (name, on) = match part.strip_prefix('-').or_else(|| part.strip_prefix("no-")) {
            Some(n) => (n, false),
            None => (part, true),
        };
        if Item::parse(name).is_none() {
            return Err(input(format!(
                "--compat {spec}: \"{part}\" is neither a profile ({}) nor an item ({})",
                profile_names(),
                item_names()
            )));
        }
        out.push(format!("compat.{name}={on}"));
    }
    if out.is_empty() {
        return Err(input(format!("--compat {spec}: name a profile ({}) or items", profile_names())));
    }
    Ok(out)
}

/// Rounds a double through single precision: what gfortran does with a default-real literal.
pub fn single(x: f64) -> f64 {
    x as f32 as f64
}

/// Applies the items that change the case's own numbers (`literals`, `input_literals`,
/// `dt_literal`): the values a legacy code writes as default-real literals are rounded to single
/// precision. Nothing without the items.
/// Refuses an unknown item and a case whose other keys contradict an item.
pub fn apply_case(case: &mut Case) -> Result<()> {
    let f = flags(&case.compat)?;
    if case.sph.lattice_gradient && [Item::Kernel, Item::QuinticGradient, Item::GlobalH].iter().any(|&i| f.has(i)) {
        return Err(input(format!(
            "sph.lattice_gradient = true with the book's kernel (compat {}): the book's kernel has no lattice normalisation; drop one of them",
            f.label()
        )));
    }
    if f.has(Item::DtLiteral)
        && let Some(dt) = case.time.dt_s.as_mut()
    {
        *dt = single(*dt);
    }
    if f.has(Item::InputLiterals) {
        for r in &mut case.regions {
            for x in [&mut r.rho_kgm3, &mut r.e_jkg, &mut r.mass_kg, &mut r.h_m].into_iter().flatten() {
                *x = single(*x);
            }
            if let Some(vel) = r.velocity_ms.as_mut() {
                vel.iter_mut().for_each(|x| *x = single(*x));
            }
        }
    }
    if !f.has(Item::Literals) {
        return Ok(());
    }
    for m in &mut case.materials {
        match &mut m.eos {
            EosCfg::IdealGas { gamma, .. } => *gamma = single(*gamma),
            // p_art_water's c = 0.01 of the form p = c² ρ
            EosCfg::Morris { c_ms, .. } => *c_ms = single(*c_ms),
            _ => {}
        }
        if let Some(eta) = m.dynamic_viscosity_pa_s.as_mut() {
            *eta = single(*eta);
        }
    }
    let v = &mut case.viscosity;
    (v.alpha, v.beta, v.phi_over_h) = (single(v.alpha), single(v.beta), single(v.phi_over_h));
    case.sph.xsph_eps = single(case.sph.xsph_eps);
    // the book's ext_force writes its gravity as the literal -9.8, its repulsion's r0 and D as
    // literals too
    if let Some(g) = case.physics.gravity_ms2.as_mut() {
        g.iter_mut().for_each(|x| *x = single(*x));
    }
    if let Some(r) = case.boundary.repulsion.as_mut() {
        (r.r0_m, r.d_m2s2) = (single(r.r0_m), single(r.d_m2s2));
    }
    let c = &mut case.conductivity;
    if c.kind == crate::case::ConductivityKind::Noh {
        (c.g1, c.g2) = (Some(single(c.g1())), Some(single(c.g2())));
    }
    Ok(())
}

/// The compat variant of module `m`'s stages when the case switches one of its items on, else
/// `None` (the module's own plan).
pub fn plan(m: Module, ctx: &PlanCtx) -> Option<Contribution> {
    let f = flags(&ctx.case.compat).ok()?;
    if f.is_empty() {
        return None;
    }
    match m {
        Module::Smoothing => smoothing::plan(ctx, f),
        Module::Density => density::plan(ctx, f),
        Module::Nnps => nnps::plan(ctx, f),
        Module::Kernel => kernel::plan(ctx, f),
        Module::Eos => eos::plan(ctx, f),
        Module::Force => force::plan(ctx, f),
        Module::Viscosity => viscosity::plan(ctx, f),
        Module::Conductivity => conductivity::plan(ctx, f),
        Module::Xsph => xsph::plan(ctx, f),
        Module::Integrator => integrator::plan(ctx, f),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profiles_items_and_specs() {
        let book = Flags::profile("liu-book").unwrap();
        assert!(book.has(Item::SoundSpeed) && !book.has(Item::GlobalH));
        assert!(!book.has(Item::PaSph1) && !book.has(Item::NorDensity));
        assert_eq!(book.with(Item::PaSph1, true).label(), "liu-book,pa_sph1");
        assert_eq!(book.label(), "liu-book");
        assert_eq!(book.with(Item::SoundSpeed, false).label(), "liu-book,-sound_speed");
        let s = sets_of("liu-book,-sound_speed,global_h").unwrap();
        assert_eq!(s, ["compat.profile=\"liu-book\"", "compat.sound_speed=false", "compat.global_h=true"]);
        assert!(sets_of("bogus").unwrap_err().to_string().contains("neither a profile"));
        let cfg = CompatCfg { profile: Some("liu-book".into()), items: [("kernel".to_string(), false)].into() };
        assert!(!flags(&cfg).unwrap().has(Item::Kernel));
        let bad = CompatCfg { profile: None, items: [("kernal".to_string(), true)].into() };
        assert!(flags(&bad).unwrap_err().to_string().contains("compat.kernal"));
        assert_eq!(single(1.4), 1.399_999_976_158_142);
        assert!(book.touches("viscosity") && !Flags::default().touches("eos"));
    }

    /// Each literal item rounds its own numbers and nothing else: a code with a double-precision
    /// gamma and a single-precision dt takes `-literals` and keeps `dt_literal`.
    #[test]
    fn the_literal_items_round_their_own_numbers() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/cases/shock_tube.toml");
        let text = std::fs::read_to_string(path).unwrap();
        let with = |spec: &str| {
            let mut c = crate::case::parse(&text, "shock_tube", &sets_of(spec).unwrap(), Some("shock_tube")).unwrap();
            apply_case(&mut c).unwrap();
            let gamma = c.materials.iter().find_map(|m| match m.eos {
                EosCfg::IdealGas { gamma, .. } => Some(gamma),
                _ => None,
            });
            // the low-pressure side's 1.795 J/kg is not a single-precision number
            let e = c.regions.iter().filter_map(|r| r.e_jkg).next_back();
            (c.time.dt_s.unwrap(), gamma.unwrap(), c.viscosity.phi_over_h, e.unwrap())
        };
        let none = with("none");
        let book = with("liu-book");
        assert_ne!(none.0, single(none.0), "the shock tube's dt is not a single-precision number");
        assert_ne!(none.3, single(none.3));
        assert_eq!(book, (single(none.0), single(none.1), single(none.2), single(none.3)));
        let no_lit = with("liu-book,-literals");
        assert_eq!(no_lit, (single(none.0), none.1, none.2, single(none.3)));
        assert_eq!(with("liu-book,-dt_literal").0, none.0);
        assert_eq!(with("liu-book,-input_literals").3, none.3);
        assert_eq!(with("none,dt_literal"), (single(none.0), none.1, none.2, none.3));
    }
}
