//! Every value of a case checked, one place per key: finite, in its physical range, with the
//! references between tables resolved. Errors are one line naming the key (`docs/reference/cases.md` gives
//! each key's range).
//!
//! A new key gets one line here: `v.num(&at, "key", value, Range::…)` (or `vec`, `int`, `name`).
//! Each check records the key's path (`material.eos.rho0_kgm3`), and a test walks every case in
//! `cases/` and every example of `docs/reference/cases.md`: a numeric key without a check fails it.
//!
//! The ranges are wide — they refuse what no explosion in soil or water can mean (a density of
//! 1e300, a spacing below a nanometre, a NaN floor) and what would make the run meaningless or
//! endless (a smoothing length a thousand spacings wide, a fixed step that needs more than
//! `max_steps` steps), never a value a careful user might choose.

use super::ConductivityKind;
use super::material::*;
use super::types::*;
use crate::error::{Result, input};
use std::collections::BTreeSet;

/// Coordinates (m): |x| at most this (a thousand kilometres).
pub const X_MAX: f64 = 1e6;
/// Densities (kg/m³).
pub const RHO_MIN: f64 = 1e-9;
pub const RHO_MAX: f64 = 1e6;
/// Speeds (m/s): sound, detonation, initial velocities.
pub const C_MAX: f64 = 1e6;
/// Pressures and moduli (Pa).
pub const P_MAX: f64 = 1e15;
/// Specific energies (J/kg).
pub const E_MAX: f64 = 1e10;
/// Times (s).
pub const T_MAX: f64 = 1e6;
/// Accelerations (m/s²).
pub const G_MAX: f64 = 1e8;
/// Exponents of the penalty and wall forces.
pub const N_MAX: i32 = 32;
/// Outputs to particles.h5 a run may write.
pub const MAX_OUTPUTS: f64 = 1e6;
/// Gauges a case may have (each is read every step).
pub const MAX_GAUGES: usize = 1000;
/// Vertices of one polygon.
pub const MAX_VERTICES: usize = 4096;
/// h / Δx of `sph.h_over_dx`, and the lower bound of a region's h / Δx.
pub const H_OVER_DX: (f64, f64) = (0.1, 10.0);
/// The largest h / Δx of a region in `d` dimensions. A particle has at most about (4 h/Δx)^d
/// neighbours within 2h: 400 in 1D at 100, 6 400 in 2D at 20, 64 000 in 3D at 10 (the 3D bound
/// is `sph.h_over_dx`'s). The bounds refuse a lattice whose pair list alone would dwarf the
/// particles, while a refined lattice under a fixed h (the book's shock tube at twice its
/// resolution: 16 spacings in 1D) stays allowed.
pub fn h_over_dx_max(d: usize) -> f64 {
    match d {
        1 => 100.0,
        2 => 20.0,
        _ => H_OVER_DX.1,
    }
}
/// The spacing relative to the largest coordinate of its region: below this, neighbouring
/// lattice points are not distinct in double precision.
pub const SPACING_REL: f64 = 1e-9;
/// Names (materials, regions, gauges, the case) at most this many characters.
pub const NAME_MAX: usize = 100;

/// A closed or half-open interval a number must lie in.
#[derive(Debug, Clone, Copy)]
pub struct Range {
    pub lo: f64,
    /// True: lo < v; false: lo ≤ v.
    pub lo_open: bool,
    pub hi: f64,
}

impl Range {
    /// lo < v ≤ hi.
    pub const fn above(lo: f64, hi: f64) -> Range {
        Range { lo, lo_open: true, hi }
    }
    /// lo ≤ v ≤ hi.
    pub const fn within(lo: f64, hi: f64) -> Range {
        Range { lo, lo_open: false, hi }
    }
    /// |v| ≤ max.
    pub const fn abs(max: f64) -> Range {
        Range { lo: -max, lo_open: false, hi: max }
    }
    /// Any finite number.
    pub const FINITE: Range = Range { lo: f64::MIN, lo_open: false, hi: f64::MAX };

    fn holds(&self, v: f64) -> bool {
        v.is_finite() && (if self.lo_open { v > self.lo } else { v >= self.lo }) && v <= self.hi
    }

    fn text(&self) -> String {
        if self.lo == f64::MIN && self.hi == f64::MAX {
            return "must be a finite number".into();
        }
        if self.lo == -self.hi && !self.lo_open {
            return format!("must be finite, at most {} in magnitude", num_text(self.hi));
        }
        let lo = if self.lo == f64::MIN {
            "finite".to_string()
        } else if self.lo_open {
            format!("above {}", num_text(self.lo))
        } else {
            format!("at least {}", num_text(self.lo))
        };
        if self.hi == f64::MAX {
            format!("must be {lo} (and finite)")
        } else {
            format!("must be {lo} and at most {}", num_text(self.hi))
        }
    }
}

/// Where in the case a check is: the table's path without indices (`material`), for the record
/// of keys checked, and its label in messages (`material[0] (loose_sand)`).
#[derive(Debug, Clone)]
pub struct At {
    path: String,
    label: String,
}

impl At {
    pub fn top(table: &str) -> At {
        At { path: table.to_string(), label: table.to_string() }
    }
    /// Entry `k` of an array of tables, labelled with its name.
    pub fn entry(table: &str, k: usize, name: &str) -> At {
        At { path: table.to_string(), label: format!("{table}[{k}] ({})", shown(name)) }
    }
    /// Entry `k` of an array of tables `key` inside this table (a region's `keep_below[k]`).
    pub(super) fn nested(&self, key: &str, k: usize) -> At {
        At { path: self.path(key), label: format!("{}[{k}]", self.key(key)) }
    }
    /// The label in messages (`region[0] (soil).keep_below[1]`).
    pub(super) fn label(&self) -> &str {
        &self.label
    }
    fn key(&self, key: &str) -> String {
        if self.label.is_empty() { key.to_string() } else { format!("{}.{key}", self.label) }
    }
    fn path(&self, key: &str) -> String {
        if self.path.is_empty() { key.to_string() } else { format!("{}.{key}", self.path) }
    }
}

/// A number as messages write it (a bound, or the value refused): 0.25, 1000, 1e15 — never the
/// 301 digits of 1e300.
pub(super) fn num_text(x: f64) -> String {
    if x != 0.0 && (x.abs() >= 1e5 || x.abs() < 1e-3) { format!("{x:e}") } else { format!("{x}") }
}

/// A direction mark or override (U+200E, U+200F, U+061C, U+202A–U+202E, U+2066–U+2069): it
/// reorders the text a terminal shows around it, so names refuse it and messages do not print it.
pub(crate) fn is_bidi(c: char) -> bool {
    matches!(c, '\u{200E}' | '\u{200F}' | '\u{061C}' | '\u{202A}'..='\u{202E}' | '\u{2066}'..='\u{2069}')
}

/// A name on one line, cut to a length that keeps a message readable.
fn shown(s: &str) -> String {
    let one: String = s.chars().map(|c| if c.is_control() || is_bidi(c) { '?' } else { c }).collect();
    if one.chars().count() > 60 { format!("{}…", one.chars().take(60).collect::<String>()) } else { one }
}

/// The checks, and the record of the keys they looked at.
#[derive(Debug, Default)]
pub struct Checker {
    /// Paths of the keys checked (`time.end_s`, `material.eos.rho0_kgm3`).
    pub seen: BTreeSet<String>,
}

impl Checker {
    /// A number in a range.
    pub fn num(&mut self, at: &At, key: &str, v: f64, r: Range) -> Result<()> {
        self.seen.insert(at.path(key));
        if r.holds(v) { Ok(()) } else { Err(input(format!("{} = {}: {}", at.key(key), num_text(v), r.text()))) }
    }

    /// An optional number in a range.
    pub fn opt(&mut self, at: &At, key: &str, v: Option<f64>, r: Range) -> Result<()> {
        self.seen.insert(at.path(key));
        match v {
            Some(v) => self.num(at, key, v, r),
            None => Ok(()),
        }
    }

    /// A vector of `n` components, each in a range.
    pub fn vec(&mut self, at: &At, key: &str, v: &[f64], n: usize, r: Range) -> Result<()> {
        self.seen.insert(at.path(key));
        if v.len() != n {
            return Err(input(format!("{}: needs {n} components, got {}", at.key(key), v.len())));
        }
        for (a, x) in v.iter().enumerate() {
            if !r.holds(*x) {
                return Err(input(format!("{}[{a}] = {}: {}", at.key(key), num_text(*x), r.text())));
            }
        }
        Ok(())
    }

    /// A whole number in lo..=hi.
    pub fn int(&mut self, at: &At, key: &str, v: i64, lo: i64, hi: i64) -> Result<()> {
        self.seen.insert(at.path(key));
        if (lo..=hi).contains(&v) {
            Ok(())
        } else {
            Err(input(format!("{} = {v}: must be a whole number from {lo} to {hi}", at.key(key))))
        }
    }

    /// A name: not empty, at most [`NAME_MAX`] characters, no control characters, no
    /// direction marks or overrides (U+200E, U+200F, U+061C, U+202A–U+202E, U+2066–U+2069: they
    /// reorder the text a terminal shows around them), commas or quotes (names become columns of
    /// gauges.csv and words of one-line messages).
    pub fn name(&mut self, at: &At, key: &str, v: &str) -> Result<()> {
        self.seen.insert(at.path(key));
        let bad = v.chars().find(|&c| c.is_control() || is_bidi(c) || matches!(c, ',' | '"'));
        if v.trim().is_empty() {
            Err(input(format!("{}: an empty name", at.key(key))))
        } else if v.chars().count() > NAME_MAX {
            Err(input(format!("{}: a name of at most {NAME_MAX} characters", at.key(key))))
        } else if let Some(c) = bad {
            Err(input(format!(
                "{}: the name holds {c:?} (no control characters, direction marks, commas or quotes)",
                at.key(key)
            )))
        } else {
            Ok(())
        }
    }

    /// Records a key that needs no range (a count of steps, a flag), so the coverage test knows
    /// it was considered.
    pub fn any(&mut self, at: &At, key: &str) {
        self.seen.insert(at.path(key));
    }
}

mod regions;

impl Case {
    /// The keys of the conductivity's kind: g1 and g2 belong to the artificial heat, α_u and the
    /// signal speed to Price's; the artificial heat has no axisymmetric form.
    fn conductivity_kind(&self, v: &mut Checker, at: &At) -> Result<()> {
        let c = &self.conductivity;
        v.opt(at, "g1", c.g1, Range::within(0.0, 100.0))?;
        v.opt(at, "g2", c.g2, Range::within(0.0, 100.0))?;
        v.any(at, "kind");
        match c.kind {
            ConductivityKind::Price if c.g1.is_some() || c.g2.is_some() => Err(input(
                "conductivity.g1, g2 are the artificial heat's: set conductivity.kind = \"noh\" (or drop them)",
            )),
            ConductivityKind::Noh if c.alpha > 0.0 => {
                Err(input("conductivity.alpha is Price's: kind = \"noh\" takes g1 and g2 (drop alpha or the kind)"))
            }
            ConductivityKind::Noh if self.axisymmetric() => Err(input(
                "conductivity.kind = \"noh\": the artificial heat has no axisymmetric form (use kind = \"price\")",
            )),
            _ => Ok(()),
        }
    }
}

impl Case {
    /// Checks what serde cannot; errors are one line naming the key.
    pub fn validate(&self) -> Result<()> {
        self.validate_with(&mut Checker::default())
    }

    /// [`Case::validate`], recording the keys checked in `v`.
    pub fn validate_with(&self, v: &mut Checker) -> Result<()> {
        let top = At::top("");
        v.int(&top, "dim", i64::try_from(self.dim).unwrap_or(i64::MAX), 1, 3)?;
        let d = self.dim;
        if let Some(n) = &self.name {
            v.name(&top, "name", if n.is_empty() { "case" } else { n })?;
        }
        v.any(&top, "description");
        v.any(&top, "parity");
        self.validate_time(v)?;
        self.validate_numerics(v)?;
        if let Some(g) = &self.physics.gravity_ms2 {
            v.vec(&At::top("physics"), "gravity_ms2", g, d, Range::abs(G_MAX))?;
        }
        v.any(&At::top("initial"), "geostatic");
        if self.initial.geostatic == Some(true) && !self.gravity_on() {
            return Err(input(
                "initial.geostatic = true: the geostatic stress is the weight of the soil, and the case has no gravity (physics.gravity_ms2)",
            ));
        }
        self.validate_materials(v)?;
        self.validate_regions(v)?;
        self.validate_walls(v)?;
        self.validate_detonation(v)?;
        self.validate_gauges(v)?;
        self.validate_analysis(v)?;
        self.validate_backend(v)?;
        if let Some(dm) = &self.domain {
            let at = At::top("domain");
            v.vec(&at, "lo_m", &dm.lo_m, d, Range::abs(X_MAX))?;
            v.vec(&at, "hi_m", &dm.hi_m, d, Range::abs(X_MAX))?;
            v.any(&at, "stop_on_exit");
            for a in 0..d {
                if dm.hi_m[a] <= dm.lo_m[a] {
                    return Err(input(format!(
                        "domain: hi_m[{a}] = {} must exceed lo_m[{a}] = {}",
                        dm.hi_m[a], dm.lo_m[a]
                    )));
                }
            }
        }
        super::dims::geometry(self, v)
    }

    fn validate_time(&self, v: &mut Checker) -> Result<()> {
        let t = &self.time;
        let at = At::top("time");
        v.num(&at, "end_s", t.end_s, Range::above(0.0, T_MAX))?;
        v.num(&at, "output_interval_s", t.output_interval_s, Range::within(0.0, T_MAX))?;
        if t.output_interval_s > 0.0 && t.end_s / t.output_interval_s > MAX_OUTPUTS {
            return Err(input(format!(
                "time.output_interval_s = {:e}: the run would write {:.3e} outputs (end_s / output_interval_s; at most {MAX_OUTPUTS:e}): is time.end_s = {:e} s meant (seconds, not ms or µs)?",
                t.output_interval_s,
                t.end_s / t.output_interval_s,
                t.end_s
            )));
        }
        v.int(&at, "max_steps", i64::try_from(t.max_steps).unwrap_or(i64::MAX), 1, i64::MAX)?;
        v.any(&at, "step");
        v.any(&at, "viscous_step");
        v.num(&at, "cfl", t.cfl, Range::above(0.0, 1.0))?;
        v.opt(&at, "dt_max_s", t.dt_max_s, Range::above(0.0, T_MAX))?;
        v.opt(&at, "dt_min_s", t.dt_min_s, Range::above(0.0, T_MAX))?;
        if let (Some(lo), Some(hi)) = (t.dt_min_s, t.dt_max_s)
            && lo >= hi
        {
            return Err(input(format!("time.dt_min_s = {lo:e} must be below time.dt_max_s = {hi:e}")));
        }
        v.opt(&at, "dt_s", t.dt_s, Range::above(0.0, T_MAX))?;
        if t.step == StepRule::Fixed {
            let dt = t.dt_s.ok_or_else(|| input("time.dt_s: required when time.step = \"fixed\""))?;
            if dt > t.end_s {
                return Err(input(format!("time.dt_s = {dt:e}: longer than the run (time.end_s = {:e})", t.end_s)));
            }
            let steps = (t.end_s / dt).round();
            if steps > t.max_steps as f64 {
                return Err(input(format!(
                    "time.dt_s = {dt:e}: the run needs {steps:.0} fixed steps to reach time.end_s = {:e} s, more than time.max_steps = {}",
                    t.end_s, t.max_steps
                )));
            }
        }
        Ok(())
    }

    fn validate_numerics(&self, v: &mut Checker) -> Result<()> {
        let s = &self.sph;
        let at = At::top("sph");
        for k in [
            "kernel",
            "nnps",
            "density",
            "continuity_form",
            "energy_form",
            "smoothing",
            "reorder_every",
            "e_floor",
            "lattice_gradient",
        ] {
            v.any(&at, k);
        }
        v.opt(&at, "h_max_ratio", s.h_max_ratio, Range::within(1.0, 1000.0))?;
        if let Some(b) = &s.density_clamp {
            v.vec(&at, "density_clamp", b, 2, Range::above(0.0, RHO_MAX))?;
            if b[0] >= b[1] {
                return Err(input(format!(
                    "{} = [{}, {}]: the lower bound must be below the upper one",
                    at.key("density_clamp"),
                    num_text(b[0]),
                    num_text(b[1])
                )));
            }
        }
        v.num(&at, "h_over_dx", s.h_over_dx, Range::within(H_OVER_DX.0, H_OVER_DX.1))?;
        if s.kernel.support() * s.h_over_dx <= 1.0 {
            return Err(input(format!(
                "{} = {}: the kernel's support ({} h) would not reach the next particle one spacing away: no particle would have a neighbour (h_over_dx must be above {})",
                at.key("h_over_dx"),
                s.h_over_dx,
                s.kernel.support(),
                1.0 / s.kernel.support()
            )));
        }
        v.num(&at, "theta", s.theta, Range::above(0.0, 10.0))?;
        v.num(&at, "xsph_eps", s.xsph_eps, Range::within(0.0, 1.0))?;
        v.num(&at, "jitter", s.jitter, Range::within(0.0, 0.5))?;
        let at = At::top("viscosity");
        v.num(&at, "alpha", self.viscosity.alpha, Range::within(0.0, 100.0))?;
        v.num(&at, "beta", self.viscosity.beta, Range::within(0.0, 100.0))?;
        v.num(&at, "phi_over_h", self.viscosity.phi_over_h, Range::above(0.0, 1.0))?;
        if self.viscosity.switch == ViscSwitch::MorrisMonaghan {
            v.num(&at, "alpha", self.viscosity.alpha, Range::above(0.0, 100.0))?;
            v.num(&at, "alpha_min", self.viscosity.alpha_min, Range::within(0.0, self.viscosity.alpha))?;
            v.num(&at, "switch_decay", self.viscosity.switch_decay, Range::above(0.0, 10.0))?;
        }
        let at = At::top("conductivity");
        v.num(&at, "alpha", self.conductivity.alpha, Range::within(0.0, 100.0))?;
        v.any(&at, "signal");
        self.conductivity_kind(v, &at)?;
        if let Some(p) = &self.penalty {
            let at = At::top("penalty");
            v.num(&at, "pbar", p.pbar, Range::above(0.0, P_MAX))?;
            exponents(v, &at, p.n1, p.n2)?;
        }
        let b = &self.boundary;
        let at = At::top("boundary");
        v.opt(&at, "wall_spacing_m", b.wall_spacing_m, Range::above(0.0, X_MAX))?;
        v.opt(&at, "r0_m", b.r0_m, Range::above(0.0, X_MAX))?;
        v.num(&at, "d_m2s2", b.d_m2s2, Range::within(0.0, C_MAX * C_MAX))?;
        v.any(&at, "noslip");
        v.opt(&at, "absorb_layer_m", b.absorb_layer_m, Range::above(0.0, X_MAX))?;
        if let Some(r) = &b.repulsion {
            r.check(v)?;
        }
        exponents(v, &at, b.n1, b.n2)
    }

    fn validate_materials(&self, v: &mut Checker) -> Result<()> {
        if self.materials.is_empty() {
            return Err(input("no [[material]]: a case needs at least one material with an eos"));
        }
        let mut names = BTreeSet::new();
        for (k, m) in self.materials.iter().enumerate() {
            let at = At::entry("material", k, &m.name);
            v.name(&at, "name", &m.name)?;
            if !names.insert(m.name.as_str()) {
                return Err(input(format!("{}: the name is used twice", at.label)));
            }
            v.any(&at, "preset");
            let e = At { path: "material.eos".into(), label: at.key("eos") };
            v.any(&e, "kind");
            m.eos.check(v, &e)?;
            if let Some(s) = &m.strength {
                let st = At { path: "material.strength".into(), label: at.key("strength") };
                v.num(&st, "shear_modulus_pa", s.shear_modulus_pa, Range::above(0.0, P_MAX))?;
                v.num(&st, "alpha_phi", s.alpha_phi, Range::within(0.0, 10.0))?;
                v.num(&st, "cohesion_pa", s.cohesion_pa, Range::within(0.0, P_MAX))?;
                // φ = 90° would leave no horizontal stress at rest (K0 = 0): below it
                v.opt(&st, "friction_angle_deg", s.friction_angle_deg, Range { lo: 0.0, lo_open: false, hi: 89.0 })?;
            }
            // a floor: the tension cut-off of a soil (0), the cavitation of water (< 0); -1e30
            // is "no floor"
            v.opt(&at, "pmin_pa", m.pmin_pa, Range::within(f64::MIN, 0.0))?;
            v.opt(&at, "e0_jkg", m.e0_jkg, Range::within(0.0, E_MAX))?;
            if let Some(g) = &m.penalty_group {
                v.name(&at, "penalty_group", g)?;
            }
            v.opt(&at, "dynamic_viscosity_pa_s", m.dynamic_viscosity_pa_s, Range::within(0.0, 1.0e6))?;
            if m.dynamic_viscosity_pa_s.is_some_and(|e| e > 0.0) && self.axisymmetric() {
                return Err(input(format!(
                    "{}: the physical viscosity has no axisymmetric form (drop the key or use a plane case)",
                    at.key("dynamic_viscosity_pa_s")
                )));
            }
        }
        Ok(())
    }

    fn validate_detonation(&self, v: &mut Checker) -> Result<()> {
        let Some(det) = &self.detonation else { return Ok(()) };
        let at = At::top("detonation");
        v.any(&at, "mode");
        v.num(&at, "width_h", det.width_h, Range::within(0.0, 100.0))?;
        v.any(&at, "beta_burn");
        // at most 1: a front faster than D is not a detonation of this explosive
        v.num(&at, "lighting_speed_factor", det.lighting_speed_factor, Range::above(0.0, 1.0))?;
        if let Some(p) = &det.point_m {
            v.vec(&at, "point_m", p, self.dim, Range::abs(X_MAX))?;
        } else if det.mode == BurnMode::Programmed {
            return Err(input("detonation.point_m: required for mode = \"programmed\""));
        }
        if let Some(n) = &det.plane_normal {
            v.vec(&at, "plane_normal", n, self.dim, Range::abs(X_MAX))?;
            if n.iter().map(|c| c * c).sum::<f64>() < f64::MIN_POSITIVE {
                return Err(input(
                    "detonation.plane_normal: a zero vector has no direction (give the lighting plane's normal)",
                ));
            }
            if det.mode != BurnMode::Programmed {
                return Err(input(
                    "detonation.plane_normal: only for mode = \"programmed\" (an instant burn lights nothing)",
                ));
            }
        }
        if !self.materials.iter().any(|m| matches!(m.eos, EosCfg::Jwl { .. })) {
            return Err(input("detonation: no material has eos kind = \"jwl\""));
        }
        Ok(())
    }

    fn validate_gauges(&self, v: &mut Checker) -> Result<()> {
        if self.gauges.len() > MAX_GAUGES {
            return Err(input(format!("{} gauges: at most {MAX_GAUGES}", self.gauges.len())));
        }
        let mut names = BTreeSet::new();
        for (k, g) in self.gauges.iter().enumerate() {
            let at = At::entry("gauge", k, &g.name);
            v.name(&at, "name", &g.name)?;
            v.vec(&at, "point_m", &g.point_m, self.dim, Range::abs(X_MAX))?;
            v.any(&at, "kind");
            if !names.insert(g.name.as_str()) {
                return Err(input(format!("{}: the name is used twice", at.label)));
            }
        }
        Ok(())
    }

    fn validate_analysis(&self, v: &mut Checker) -> Result<()> {
        let an = &self.analysis;
        let at = At::top("analysis");
        v.any(&at, "kind");
        v.opt(&at, "diaphragm_m", an.diaphragm_m, Range::abs(X_MAX))?;
        if let Some(w) = &an.window_m {
            v.vec(&at, "window_m", w, 2, Range::abs(X_MAX))?;
            if w[1] <= w[0] {
                return Err(input("analysis.window_m: need [lo, hi] with hi > lo"));
            }
        }
        if let Some(w) = &an.view_m {
            v.vec(&at, "view_m", w, 4, Range::abs(X_MAX))?;
            if w[1] <= w[0] || w[3] <= w[2] {
                return Err(input("analysis.view_m: need [x_lo, x_hi, y_lo, y_hi] with x_hi > x_lo and y_hi > y_lo"));
            }
        }
        let ideal = self.materials.iter().any(|m| matches!(m.eos, EosCfg::IdealGas { .. }));
        match an.kind {
            AnalysisKind::Sedov | AnalysisKind::Noh | AnalysisKind::Reflection if !ideal => {
                return Err(input(format!("analysis.kind = \"{}\" needs an ideal-gas material", an.kind.name())));
            }
            AnalysisKind::Reflection if self.dim != 1 || self.walls.is_empty() => {
                return Err(input("analysis.kind = \"reflection\" needs dim = 1 and a [[wall]]"));
            }
            AnalysisKind::Detonation if self.detonation.as_ref().is_none_or(|dt| dt.mode != BurnMode::Programmed) => {
                return Err(input("analysis.kind = \"detonation\" needs [detonation] mode = \"programmed\""));
            }
            _ => {}
        }
        if let Some(c) = &an.center_m {
            v.vec(&at, "center_m", c, self.dim, Range::abs(X_MAX))?;
            // in RZ a centre of symmetry (a Sedov or Noh point) is on the axis: off it, the
            // exact solution the report compares with is not the run's (a centre at r = -1 m read
            // a shock radius 11.7 times the exact one)
            if self.axisymmetric()
                && matches!(an.kind, AnalysisKind::Sedov | AnalysisKind::Noh)
                && c.first().is_some_and(|&r| r != 0.0)
            {
                return Err(input(format!(
                    "{}: r = {:e} m; in axisymmetric geometry the centre of a {} problem is on the axis (r = 0)",
                    at.key("center_m"),
                    c[0],
                    if an.kind == AnalysisKind::Sedov { "Sedov" } else { "Noh" }
                )));
            }
        }
        v.opt(&at, "energy_j", an.energy_j, Range::above(0.0, 1e30))?;
        if an.kind == AnalysisKind::Riemann {
            if self.dim != 1 {
                return Err(input("analysis.kind = \"riemann\" needs dim = 1"));
            }
            if an.diaphragm_m.is_none() {
                return Err(input("analysis.diaphragm_m: required for kind = \"riemann\""));
            }
        }
        if let Some(c) = &an.thesis_crater_m {
            v.vec(&at, "thesis_crater_m", c, 2, Range::within(0.0, X_MAX))?;
        }
        if let Some(h) = &an.thesis_crater_history {
            for row in h {
                if row.len() != 3 {
                    return Err(input("analysis.thesis_crater_history: rows must be [time_s, diameter_m, depth_m]"));
                }
                // nan: a value the thesis does not give
                let given: Vec<f64> =
                    row.iter().enumerate().map(|(k, x)| if k > 0 && x.is_nan() { 0.0 } else { *x }).collect();
                v.vec(&at, "thesis_crater_history", &given, 3, Range::within(0.0, X_MAX))?;
            }
        }
        for (k, t) in an.thesis_gauge.iter().enumerate() {
            let tg = At { path: "analysis.thesis_gauge".into(), label: format!("analysis.thesis_gauge[{k}]") };
            v.any(&tg, "gauge");
            v.opt(&tg, "peak_time_s", t.peak_time_s, Range::within(0.0, T_MAX))?;
            v.opt(&tg, "peak_pa", t.peak_pa, Range::abs(P_MAX))?;
            if !self.gauges.iter().any(|g| g.name == t.gauge) {
                return Err(input(format!(
                    "analysis.thesis_gauge[{k}].gauge = \"{}\": no [[gauge]] of that name",
                    shown(&t.gauge)
                )));
            }
        }
        if let Some(sm) = &an.soil_materials {
            v.any(&at, "soil_materials");
            for s in sm {
                if self.material_index(s).is_none() {
                    return Err(input(format!("analysis.soil_materials: no material named `{}`", shown(s))));
                }
            }
        }
        Ok(())
    }

    fn validate_backend(&self, v: &mut Checker) -> Result<()> {
        let at = At::top("backend");
        // the module names are checked where the plan is chosen (`sim::plan::choices`), before
        // any particle is made
        v.any(&at, "rust");
        v.any(&at, "fortran");
        v.any(&at, "default");
        if let Some(dft) = &self.backend.default
            && dft != "fortran"
            && dft != "rust"
        {
            return Err(input(format!("backend.default = \"{}\": must be \"fortran\" or \"rust\"", shown(dft))));
        }
        Ok(())
    }
}

/// The two exponents of a force: 1 ≤ n2 < n1 ≤ [`N_MAX`].
fn exponents(v: &mut Checker, at: &At, n1: i32, n2: i32) -> Result<()> {
    v.int(at, "n1", i64::from(n1), 2, i64::from(N_MAX))?;
    v.int(at, "n2", i64::from(n2), 1, i64::from(N_MAX) - 1)?;
    if n1 <= n2 {
        return Err(input(format!("{}: need n1 > n2 >= 1 (got n1 = {n1}, n2 = {n2})", at.label)));
    }
    Ok(())
}
