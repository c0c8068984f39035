//! Case files: TOML, SI units, every key with its unit in its name or its docs
//! (`docs/reference/cases.md` lists them all). Unknown keys are refused (`deny_unknown_fields`).
//!
//! What is where:
//! - `types`: the tables as Rust types (serde);
//! - `sets`: `--set KEY=VALUE` overrides, applied to the text;
//! - [`validate`]: every value checked, one place per key (finite, in its physical range, the
//!   references between tables), with one-line errors naming the key;
//! - [`size`]: the particle count and the memory a case needs, estimated before anything is
//!   generated, and the limit it must stay under;
//! - `dims`: what depends on the dimension and the geometry: round shapes (cylinder, sphere),
//!   3D walls (planes), the axisymmetric geometry (RZ);
//! - the checks that need the generated particles (regions behind a wall or outside the domain, a
//!   detonation point outside every charge, a gauge outside the material) are the set-up's
//!   (`setup/geometry.rs`), run once the particles are made.
//!
//! Loading is [`load`] (the file, read with a size limit) then [`parse`] (overrides, serde,
//! validation).

mod conductivity;
mod dims;
mod forms;
mod material;
pub mod refine;
mod repulsion;
mod sets;
pub mod size;
pub mod slips;
mod types;
pub mod validate;

pub use conductivity::*;
pub use forms::*;
pub use material::*;
pub use repulsion::RepulsionCfg;
pub use sets::{apply_sets, apply_sets_by};
pub use types::*;

use crate::error::{Result, SphError, input};
use std::io::Read;
use std::path::Path;

/// The largest case file read (bytes): a case is a few kilobytes; anything near this is not one.
pub const MAX_CASE_BYTES: u64 = 4 << 20;

/// Reads a case file: a regular file (not a folder, a device or a pipe) of at most
/// [`MAX_CASE_BYTES`], in UTF-8. Errors are one line naming the file.
pub fn read_text(path: &Path) -> Result<String> {
    let shown = path.display();
    let meta = std::fs::metadata(path).map_err(|e| input(format!("{shown}: cannot read the case file: {e}")))?;
    if !meta.is_file() {
        return Err(input(format!("{shown}: not a case file (a folder, a device or a pipe)")));
    }
    if meta.len() > MAX_CASE_BYTES {
        return Err(input(format!(
            "{shown}: {} bytes is too large for a case file (at most {MAX_CASE_BYTES})",
            meta.len()
        )));
    }
    let f = std::fs::File::open(path).map_err(|e| input(format!("{shown}: cannot read the case file: {e}")))?;
    let mut bytes = Vec::new();
    f.take(MAX_CASE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| input(format!("{shown}: cannot read the case file: {e}")))?;
    if bytes.len() as u64 > MAX_CASE_BYTES {
        return Err(input(format!("{shown}: too large for a case file (at most {MAX_CASE_BYTES} bytes)")));
    }
    String::from_utf8(bytes).map_err(|e| input(format!("{shown}: not UTF-8 text: {e}")))
}

/// Reads a case file, applies `key=value` overrides, and parses it.
pub fn load(path: &Path, sets: &[String]) -> Result<Case> {
    let text = read_text(path)?;
    parse(&text, &path.display().to_string(), sets, path.file_stem().and_then(|s| s.to_str()))
}

/// Parses case text; `origin` names it in error messages. The `--set` overrides are applied to
/// the text ([`apply_sets`]); an error they cause names the override, not a line of the edited
/// text.
pub fn parse(text: &str, origin: &str, sets: &[String], stem: Option<&str>) -> Result<Case> {
    // a key deeper than any case's (an element of a vector in a region's table has 5 levels:
    // region.soil.subtract.0.lo_m) is refused before the TOML parser's recursion meets it (40 000 levels overflowed
    // the stack)
    for s in sets {
        let key = s.split_once('=').map_or(s.as_str(), |(k, _)| k);
        let depth = key.split('.').count();
        if depth > 16 {
            return Err(input(format!(
                "--set {}: a key of {depth} levels, more than 16 (a case's keys have a few: material.NAME.eos.KEY)",
                sets::shown(key)
            )));
        }
    }
    text.parse::<toml::Table>().map_err(|e| toml_error(origin, text, &e))?;
    let attempt = |k: usize| -> Result<Case> {
        let edited = apply_sets(text, &sets[..k])?;
        // errors name the line of the file as written (or as changed by --set), before the keys
        // whose defaults depend on the rest of the case are filled in
        let mut case: Case = toml::from_str(&edited).map_err(|e| toml_error(origin, &edited, &e))?;
        let mut value: toml::Table = edited.parse().map_err(|e| toml_error(origin, &edited, &e))?;
        if let Some((key, v)) = subnormal(&value, "") {
            return Err(input(format!(
                "{origin}: {key} = {v:e}: a subnormal number (below the smallest normal double, {:e}): no quantity of a case is meaningful there, and the twins need not agree on it",
                f64::MIN_POSITIVE
            )));
        }
        if resolve_defaults(&mut value)? {
            let full = toml::to_string(&value).map_err(|e| input(e.to_string()))?;
            case =
                toml::from_str(&full).map_err(|e| toml_error(&format!("{origin} (with its defaults)"), &full, &e))?;
        }
        if case.name.is_none() {
            case.name = Some(stem.unwrap_or("case").to_string());
        }
        case.validate()?;
        Ok(case)
    };
    match attempt(sets.len()) {
        Ok(c) => Ok(c),
        Err(e) if sets.is_empty() => Err(e),
        Err(e) => Err(blame(&e, sets, &attempt)),
    }
}

/// The first float of `t` (its key's dotted path, after `prefix`) that is subnormal: not zero and
/// below the smallest normal double in magnitude.
fn subnormal(t: &toml::Table, prefix: &str) -> Option<(String, f64)> {
    fn walk(v: &toml::Value, key: &str) -> Option<(String, f64)> {
        match v {
            toml::Value::Float(x) if *x != 0.0 && x.is_finite() && x.abs() < f64::MIN_POSITIVE => {
                Some((key.to_string(), *x))
            }
            toml::Value::Table(t) => subnormal(t, key),
            // an element of an array of tables by its name (material.tnt), else its index
            toml::Value::Array(a) => a.iter().enumerate().find_map(|(k, e)| {
                let at = e.get("name").and_then(|n| n.as_str()).map_or(k.to_string(), |n| n.to_string());
                walk(e, &format!("{key}.{at}"))
            }),
            _ => None,
        }
    }
    t.iter().find_map(|(k, v)| walk(v, &if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") }))
}

/// The error of a case with overrides, attributed: to the file when the file alone gives the same
/// error, else to the first override after which it appears.
fn blame(e: &SphError, sets: &[String], attempt: &dyn Fn(usize) -> Result<Case>) -> SphError {
    let msg = |e: &SphError| -> String {
        // the message without a leading `origin:line: `
        let s = e.to_string();
        match s.split_once(": ") {
            Some((head, rest)) if head.rsplit(':').next().is_some_and(|l| l.parse::<usize>().is_ok()) => {
                rest.to_string()
            }
            _ => s,
        }
    };
    let want = msg(e);
    if let Err(e0) = attempt(0)
        && msg(&e0) == want
    {
        return e0;
    }
    for k in 1..=sets.len() {
        if let Err(ek) = attempt(k)
            && msg(&ek) == want
        {
            if want.starts_with("--set ") {
                return input(want);
            }
            return input(format!("--set {}: {want}", sets::shown(&sets[k - 1])));
        }
    }
    let all: Vec<String> = sets.iter().map(|s| sets::shown(s)).collect();
    input(format!("--set {}: {want}", all.join(" --set ")))
}

/// The default `sph.jitter` of gas dynamics in 2D plane and 3D (a fraction of the spacing): the
/// smallest of those measured (1e-4 to 5e-2) with no particle running ahead of a point blast's
/// front from a deposit on a particle, in 2D (61² to 105²) and in 3D (41³); 1e-2 left jets in 3D
/// (docs/validation.md, "Jets along the lattice's symmetry lines").
pub const GAS_JITTER: f64 = 5e-2;

/// The keys of the parity preset `parity = "thesis"`: the thesis's and Liu's settings, for every
/// key a case leaves out (table, key, value).
pub const THESIS_PARITY: [(&str, &str, &str); 12] = [
    ("sph", "density", "\"continuity\""),
    ("sph", "jitter", "0.0"),
    ("sph", "lattice_gradient", "false"),
    ("sph", "continuity_form", "\"mass\""),
    ("sph", "smoothing", "\"rate\""),
    ("sph", "energy_form", "\"symmetric\""),
    ("sph", "e_floor", "false"),
    ("time", "viscous_step", "false"),
    ("detonation", "width_h", "0.0"),
    ("detonation", "beta_burn", "false"),
    ("detonation", "lighting_speed_factor", "1.0"),
    ("initial", "geostatic", "false"),
];

/// Fills the keys whose default depends on the rest of the case, before it is read: the parity
/// preset, then, without it, `viscosity.beta` and `viscosity.switch` (2 and the Morris & Monaghan
/// switch where an ideal gas meets another material) and `conductivity.alpha` (1 for gas dynamics
/// in axisymmetric geometry), then `sph.density` (number density where an ideal gas meets another material, with
/// `sph.pressure_form = "interface"`; summation when every material is an ideal gas — gas
/// dynamics — or detonation products; continuity otherwise), `sph.jitter` ([`GAS_JITTER`] for gas dynamics in 2D plane and 3D, else
/// 0) and `sph.smoothing` (h from the density with summation, capped at 4 h0 but for a JWL's products alone, by the rate
/// otherwise). Returns whether anything was added.
fn resolve_defaults(root: &mut toml::Table) -> Result<bool> {
    let mut changed = false;
    let get = |root: &toml::Table, t: &str, k: &str| root.get(t).and_then(|v| v.get(k)).cloned();
    let put = |root: &mut toml::Table, t: &str, k: &str, v: toml::Value| -> Result<()> {
        let tab = root.entry(t.to_string()).or_insert_with(|| toml::Value::Table(toml::Table::new()));
        match tab {
            toml::Value::Table(tt) => {
                tt.insert(k.to_string(), v);
                Ok(())
            }
            _ => Err(input(format!("`{t}` must be a table"))),
        }
    };
    match root.get("parity") {
        None => {}
        Some(toml::Value::String(p)) if p == "thesis" => {
            for (t, k, v) in THESIS_PARITY {
                // the detonation keys only where the case has a [detonation]
                if (t == "detonation" && !root.contains_key("detonation")) || get(root, t, k).is_some() {
                    continue;
                }
                let val = format!("v = {v}").parse::<toml::Table>().ok().and_then(|mut x| x.remove("v"));
                if let Some(val) = val {
                    put(root, t, k, val)?;
                    changed = true;
                }
            }
        }
        Some(other) => return Err(input(format!("parity = {other}: the only preset is \"thesis\""))),
    }
    // each material's EOS kind, a preset's included (its eos table may change constants only)
    let kind = |m: &toml::Value| -> Option<String> {
        let own = m.get("eos").and_then(|e| e.get("kind")).and_then(|k| k.as_str()).map(String::from);
        own.or_else(|| {
            let pre = crate::presets::get(m.get("preset")?.as_str()?)?;
            pre.get("eos")?.get("kind")?.as_str().map(String::from)
        })
    };
    let every = |ok: &dyn Fn(&str) -> bool| {
        root.get("material")
            .and_then(|m| m.as_array())
            .is_some_and(|a| !a.is_empty() && a.iter().all(|m| kind(m).as_deref().is_some_and(ok)))
    };
    let gas = every(&|k| k == "ideal_gas");
    // detonation products alone (every material an ideal gas or JWL: a charge in a void) take
    // summation density too: by continuity, the rarefied products at the centre of an unconfined
    // 3D charge ran below zero density within 20 µs whatever the step (docs/validation.md, "A
    // charge alone in a void"). A programmed burn starts from the condensed explosive: its front
    // holds p_CJ by continuity and overshoots by 7 % with summation, so only products from the
    // start (an instant burn or none)
    let programmed = root.get("detonation").and_then(|d| d.get("mode")).and_then(|m| m.as_str()) == Some("programmed");
    let products = !programmed && every(&|k| k == "ideal_gas" || k == "jwl");
    // a gas beside a condensed material (air around a charge or above the ground, 10³–10⁴ times
    // lighter): number density, each particle's density from its own mass (Hu & Adams 2006); by
    // summation the heavy neighbours' masses entered the air's density and its h shrank 20-fold
    let some = |ok: &dyn Fn(&str) -> bool| {
        root.get("material")
            .and_then(|m| m.as_array())
            .is_some_and(|a| a.iter().any(|m| kind(m).as_deref().is_some_and(ok)))
    };
    let mixed = some(&|k| k == "ideal_gas") && some(&|k| k != "ideal_gas");
    let parity = root.contains_key("parity");
    if mixed && !parity {
        // a blast wave in air: Monaghan's β = 2 with the Morris & Monaghan switch. The thesis's
        // β = 10 spread the front and cut the peak overpressure (docs/validation.md, "Air blast")
        for (k, v) in [("beta", toml::Value::Float(2.0)), ("switch", toml::Value::String("morris_monaghan".into()))] {
            if get(root, "viscosity", k).is_none() {
                put(root, "viscosity", k, v)?;
                changed = true;
            }
        }
    }
    if mixed && !parity && root.contains_key("penalty") {
        changed |= exempt_gases(root, &kind);
    }
    if get(root, "sph", "density").is_none() {
        let d = if mixed {
            "number"
        } else if products {
            "summation"
        } else {
            "continuity"
        };
        put(root, "sph", "density", toml::Value::String(d.into()))?;
        changed = true;
    }
    let density = get(root, "sph", "density").and_then(|v| v.as_str().map(String::from));
    if density.as_deref() == Some("number") && get(root, "sph", "pressure_form").is_none() {
        // its pressure term in the interface form (Colagrossi & Landrini 2003)
        put(root, "sph", "pressure_form", toml::Value::String("interface".into()))?;
        changed = true;
    }
    let rz = root.get("geometry").and_then(|v| v.as_str()) == Some("axisymmetric");
    if get(root, "sph", "jitter").is_none() {
        // gas dynamics in 2D plane and 3D: break the lattice's mirror symmetry about a point blast, or
        // its rows of particles along the symmetry lines run ahead of the front as jets
        // (docs/validation.md, "Jets along the lattice's symmetry lines"). The soil scenes keep
        // their exact lattice (their results as validated), and so does axisymmetric geometry (its
        // blasts sit on the axis, a mirror by construction; no jets measured from the exact lattice)
        let dim = root.get("dim").and_then(|v| v.as_integer()).unwrap_or(0);
        put(root, "sph", "jitter", toml::Value::Float(if gas && dim >= 2 && !rz { GAS_JITTER } else { 0.0 }))?;
        changed = true;
    }
    // gas dynamics in RZ: Price's conductivity. Without it the front near the axis lagged 4 %
    // and a converging shock heated the axis 1.9-fold (docs/axis_results.md, "The conductivity
    // in RZ"). Under the parity preset, or with another kind, as the case says
    let conductivity_given =
        get(root, "conductivity", "alpha").is_some() || get(root, "conductivity", "kind").is_some();
    if gas && rz && !conductivity_given && !parity {
        put(root, "conductivity", "alpha", toml::Value::Float(1.0))?;
        changed = true;
    }
    let sum = matches!(density.as_deref(), Some("summation" | "number"));
    if get(root, "sph", "smoothing").is_none() {
        put(root, "sph", "smoothing", toml::Value::String(if sum { "density" } else { "rate" }.into()))?;
        // with h from the summation density, the few rarefied particles at a blast's centre would
        // grow h without bound and act across the blast (docs/validation.md, "Sedov–Taylor");
        // with the artificial conductivity on, their heat flows to their neighbours and h stays
        // bounded by itself, and the cap would only strand the deposit (the 1D point blast lags
        // 2.5 % with it, 0.6 % without): no cap then
        let conducting = get(root, "conductivity", "alpha")
            .and_then(|v| v.as_float().or(v.as_integer().map(|i| i as f64)))
            .is_some_and(|a| a > 0.0);
        // products alone with a JWL (a charge in a void) expand as a whole: h grows everywhere
        // alike and the neighbours stay ~26 in 3D without a cap, while with it their density
        // stuck at m W(0, 4 h0) once they were 8 spacings apart (docs/validation.md, "A charge
        // alone in a void"): no cap then either
        let jwl_products = products && !gas;
        if sum && !conducting && !jwl_products && get(root, "sph", "h_max_ratio").is_none() {
            put(root, "sph", "h_max_ratio", toml::Value::Float(4.0))?;
        }
        changed = true;
    }
    Ok(changed)
}

/// Every ideal-gas material without a `penalty_group` takes `"none"` (the penalty force leaves it
/// alone); true if one did. The penalty's P̄ is an energy, the same for any particle, so on an air
/// particle 10³ times lighter than the soil its acceleration is 10³ times larger. In the charge on
/// sand under air that force broke the energy balance by +6.9 % at 1 ms (+0.9 % without it), and
/// the interface pressure form already keeps the air off the other materials (docs/validation.md,
/// "Air blast").
fn exempt_gases(root: &mut toml::Table, kind: &dyn Fn(&toml::Value) -> Option<String>) -> bool {
    let Some(mats) = root.get_mut("material").and_then(|m| m.as_array_mut()) else { return false };
    let mut changed = false;
    for m in mats.iter_mut() {
        let gas = kind(m).as_deref() == Some("ideal_gas");
        if let Some(t) = m.as_table_mut().filter(|t| gas && !t.contains_key("penalty_group")) {
            t.insert("penalty_group".into(), toml::Value::String(PENALTY_EXEMPT.into()));
            changed = true;
        }
    }
    changed
}

fn toml_error(origin: &str, text: &str, e: &toml::de::Error) -> SphError {
    // the line of the span's start (counted in bytes: a span need not fall on a char boundary)
    let line = e.span().map(|s| text.as_bytes()[..s.start.min(text.len())].iter().filter(|&&b| b == b'\n').count() + 1);
    let msg = e.message().replace(['\n', '\r'], " ");
    match line {
        Some(l) => input(format!("{origin}:{l}: {msg}")),
        None => input(format!("{origin}: {msg}")),
    }
}

impl Case {
    pub fn name(&self) -> &str {
        self.name.as_deref().unwrap_or("case")
    }

    pub fn material_index(&self, name: &str) -> Option<usize> {
        self.materials.iter().position(|m| m.name == name)
    }

    /// Is gravity on (some component of `physics.gravity_ms2` non-zero)?
    pub fn gravity_on(&self) -> bool {
        self.physics.gravity_ms2.as_ref().is_some_and(|g| g.iter().any(|&x| x != 0.0))
    }

    /// Does the run start from the geostatic stress (`initial.geostatic`; absent: where gravity
    /// is on and some material has strength, a soil at rest)?
    pub fn geostatic(&self) -> bool {
        self.initial.geostatic.unwrap_or_else(|| self.gravity_on() && has_strength(self))
    }

    /// True for `geometry = "axisymmetric"`.
    pub fn axisymmetric(&self) -> bool {
        self.geometry == Geometry::Axisymmetric
    }

    /// The `mirror` walls that are axis-aligned planes (lines x = c or y = c in 2D; a 3D wall
    /// without `edge_m` whose corners share a coordinate), as (axis: 0 for x, 1 for y, 2 for z;
    /// c in m): the symmetry planes a half, quarter or octant model is completed across.
    pub fn axis_mirrors(&self) -> Vec<(usize, f64)> {
        self.walls
            .iter()
            .filter(|w| w.kind == WallKind::Mirror && w.edge_m.is_none())
            .filter_map(|w| {
                (0..self.dim)
                    .find(|&k| w.from_m.get(k).is_some_and(|a| Some(a) == w.to_m.get(k)))
                    .map(|k| (k, w.from_m[k]))
            })
            .collect()
    }
}

/// Is the charge lit by a programmed burn?
pub fn programmed(case: &Case) -> bool {
    matches!(&case.detonation, Some(d) if d.mode == BurnMode::Programmed)
}

/// Does any material carry strength?
pub fn has_strength(case: &Case) -> bool {
    case.materials.iter().any(|m| m.strength.is_some())
}
