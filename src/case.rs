//! Case files: TOML, SI units, every key with its unit in its name or its docs
//! (`docs/cases.md` lists them all). Unknown keys are refused (`deny_unknown_fields`).
//!
//! Loading is two stages: [`load`] parses and applies `--set` overrides, [`Case::validate`]
//! checks everything that serde cannot (positive densities, known material names, regions
//! that hold particles and do not overlap, …) and returns one-line errors naming the key.

use crate::error::{Result, input};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Case {
    /// Name of the case (default: the file stem).
    pub name: Option<String>,
    /// Free text.
    #[serde(default)]
    pub description: String,
    /// Space dimension: 1, 2 (plane strain) or 3.
    pub dim: usize,
    pub time: TimeCfg,
    #[serde(default)]
    pub sph: SphCfg,
    #[serde(default)]
    pub viscosity: ViscCfg,
    pub penalty: Option<PenaltyCfg>,
    #[serde(default)]
    pub boundary: BoundaryCfg,
    #[serde(default)]
    pub physics: PhysicsCfg,
    #[serde(rename = "material", default)]
    pub materials: Vec<MaterialCfg>,
    #[serde(rename = "region", default)]
    pub regions: Vec<RegionCfg>,
    #[serde(rename = "wall", default)]
    pub walls: Vec<WallCfg>,
    pub detonation: Option<DetonationCfg>,
    #[serde(rename = "gauge", default)]
    pub gauges: Vec<GaugeCfg>,
    #[serde(default)]
    pub analysis: AnalysisCfg,
    #[serde(default)]
    pub backend: BackendCfg,
    pub domain: Option<DomainCfg>,
    /// Compatibility items of the Rust twins (`--compat`; docs/migration.md A.6).
    #[serde(default)]
    pub compat: crate::migration::compat::CompatCfg,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeCfg {
    /// End time (s).
    pub end_s: f64,
    /// Interval between outputs to particles.h5 (s); 0 = first and last step only.
    #[serde(default)]
    pub output_interval_s: f64,
    /// Step rule: "cfl" (default) or "fixed".
    #[serde(default = "default_step")]
    pub step: StepRule,
    /// Fixed step (s), for `step = "fixed"`.
    pub dt_s: Option<f64>,
    /// Courant number C_cfl for `step = "cfl"`.
    #[serde(default = "default_cfl")]
    pub cfl: f64,
    /// Largest step (s) under the CFL rule.
    pub dt_max_s: Option<f64>,
    /// Stop after this many steps (a safety limit).
    #[serde(default = "default_max_steps")]
    pub max_steps: u64,
}

#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum StepRule {
    Cfl,
    Fixed,
}

fn default_step() -> StepRule {
    StepRule::Cfl
}
fn default_cfl() -> f64 {
    0.25
}
fn default_max_steps() -> u64 {
    10_000_000
}

#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum KernelKind {
    Cubic,
    Gauss,
    Quintic,
    Wendland,
}

impl KernelKind {
    /// The Fortran code (skf) of the kernel.
    pub fn skf(self) -> i32 {
        match self {
            KernelKind::Cubic => 1,
            KernelKind::Gauss => 2,
            KernelKind::Quintic => 3,
            KernelKind::Wendland => 4,
        }
    }
    /// Support radius in units of h.
    pub fn support(self) -> f64 {
        match self {
            KernelKind::Cubic | KernelKind::Wendland => 2.0,
            KernelKind::Gauss | KernelKind::Quintic => 3.0,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            KernelKind::Cubic => "cubic",
            KernelKind::Gauss => "gauss",
            KernelKind::Quintic => "quintic",
            KernelKind::Wendland => "wendland",
        }
    }
}

#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum NnpsKind {
    Direct,
    Cell,
}

#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum DensityKind {
    Summation,
    Continuity,
}

#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum ContinuityForm {
    Mass,
    Volume,
}

fn default_cform() -> ContinuityForm {
    ContinuityForm::Mass
}

#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum SmoothingKind {
    /// h fixed at its initial value.
    Constant,
    /// h = h0 (rho0/rho)^(1/d).
    Density,
    /// dh/dt of the thesis (2-15, 2-16).
    Rate,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphCfg {
    #[serde(default = "default_kernel")]
    pub kernel: KernelKind,
    /// h0 = h_over_dx × the region's spacing (thesis: 1.0–1.2).
    #[serde(default = "one")]
    pub h_over_dx: f64,
    #[serde(default = "default_nnps")]
    pub nnps: NnpsKind,
    #[serde(default = "default_density")]
    pub density: DensityKind,
    /// Form of the continuity equation: "mass" (Σ m_j v_ij·∇W, thesis Table 4-1) or "volume"
    /// (ρ_i Σ (m_j/ρ_j) v_ij·∇W, for large density ratios).
    #[serde(default = "default_cform")]
    pub continuity_form: ContinuityForm,
    #[serde(default = "default_smoothing")]
    pub smoothing: SmoothingKind,
    /// θ of the h update (2-16).
    #[serde(default = "one")]
    pub theta: f64,
    /// XSPH averaging coefficient ε (0 = off).
    #[serde(default)]
    pub xsph_eps: f64,
    /// Sort the particles by cell every this many steps, for memory locality (0 = never). It
    /// changes the order of the neighbour sums, so results differ at round-off from an unsorted
    /// run (they stay independent of the backend and of the thread count).
    #[serde(default)]
    pub reorder_every: u64,
}

fn one() -> f64 {
    1.0
}
fn default_kernel() -> KernelKind {
    KernelKind::Cubic
}
fn default_nnps() -> NnpsKind {
    NnpsKind::Cell
}
fn default_density() -> DensityKind {
    DensityKind::Continuity
}
fn default_smoothing() -> SmoothingKind {
    SmoothingKind::Rate
}

impl Default for SphCfg {
    fn default() -> Self {
        SphCfg {
            kernel: default_kernel(),
            h_over_dx: 1.0,
            nnps: default_nnps(),
            density: default_density(),
            continuity_form: default_cform(),
            smoothing: default_smoothing(),
            theta: 1.0,
            xsph_eps: 0.0,
            reorder_every: 0,
        }
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ViscCfg {
    /// Monaghan α (thesis: 1).
    #[serde(default = "one")]
    pub alpha: f64,
    /// Monaghan β (thesis: 10).
    #[serde(default = "default_beta")]
    pub beta: f64,
    /// φ = phi_over_h × h_ij (4-48; 0.1).
    #[serde(default = "default_phi")]
    pub phi_over_h: f64,
}

fn default_beta() -> f64 {
    10.0
}
fn default_phi() -> f64 {
    0.1
}

impl Default for ViscCfg {
    fn default() -> Self {
        ViscCfg { alpha: 1.0, beta: 10.0, phi_over_h: 0.1 }
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PenaltyCfg {
    /// P̄ (N·m in 2D plane, per metre of depth): the penalty constant (4-53; 1e5).
    #[serde(default = "default_pbar")]
    pub pbar: f64,
    #[serde(default = "default_n1")]
    pub n1: i32,
    #[serde(default = "default_n2")]
    pub n2: i32,
}

fn default_pbar() -> f64 {
    1e5
}
fn default_n1() -> i32 {
    12
}
fn default_n2() -> i32 {
    6
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundaryCfg {
    /// Spacing of type I wall particles along a wall (m); default: a quarter of the finest
    /// region spacing.
    pub wall_spacing_m: Option<f64>,
    /// Range r0 of the wall force (m); default: half the finest region spacing.
    pub r0_m: Option<f64>,
    /// D of the wall force (m²/s²).
    #[serde(default = "default_dwall")]
    pub d_m2s2: f64,
    #[serde(default = "default_n1")]
    pub n1: i32,
    #[serde(default = "default_wall_n2")]
    pub n2: i32,
    /// Mirror velocities: false = free slip (normal component reversed), true = no slip.
    #[serde(default)]
    pub noslip: bool,
}

fn default_dwall() -> f64 {
    1e4
}
fn default_wall_n2() -> i32 {
    4
}

impl Default for BoundaryCfg {
    fn default() -> Self {
        BoundaryCfg { wall_spacing_m: None, r0_m: None, d_m2s2: 1e4, n1: 12, n2: 4, noslip: false }
    }
}

#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PhysicsCfg {
    /// Gravity (m/s²), one component per dimension; absent = none.
    pub gravity_ms2: Option<Vec<f64>>,
}

/// One material: its equation of state and, for soils, its strength. A `preset` fills in the keys
/// the table does not give ([`crate::presets`]).
#[derive(Debug, Clone, Deserialize)]
#[serde(try_from = "toml::Table")]
pub struct MaterialCfg {
    pub name: String,
    /// The preset the material was built from, if any.
    pub preset: Option<String>,
    pub eos: EosCfg,
    pub strength: Option<StrengthCfg>,
    /// Pressure floor (Pa): tension cut-off of soils, cavitation of water. Absent = none.
    pub pmin_pa: Option<f64>,
    /// Specific internal energy at the start (J/kg) for regions of this material that give none.
    pub e0_jkg: Option<f64>,
    /// Materials with the same penalty group feel no penalty force between them
    /// (default: each material its own group).
    pub penalty_group: Option<String>,
}

/// The keys of a `[[material]]` table once its preset is merged in.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialFields {
    name: String,
    preset: Option<String>,
    eos: EosCfg,
    strength: Option<StrengthCfg>,
    pmin_pa: Option<f64>,
    e0_jkg: Option<f64>,
    penalty_group: Option<String>,
}

impl TryFrom<toml::Table> for MaterialCfg {
    type Error = String;
    fn try_from(mut t: toml::Table) -> std::result::Result<MaterialCfg, String> {
        let name = t.get("name").and_then(|n| n.as_str()).unwrap_or("?").to_string();
        let preset = match t.get("preset") {
            None => None,
            Some(toml::Value::String(p)) => Some(p.clone()),
            Some(v) => {
                return Err(format!(
                    "material `{name}`: preset = {v}: must be a preset name ({})",
                    crate::presets::names()
                ));
            }
        };
        if let Some(p) = &preset {
            let mut base = crate::presets::get(p).ok_or_else(|| {
                format!("material `{name}`: preset = \"{p}\": no such preset (presets: {})", crate::presets::names())
            })?;
            t.remove("preset");
            crate::presets::merge(&mut base, t);
            t = base;
            t.insert("preset".into(), toml::Value::String(p.clone()));
        }
        let f = MaterialFields::deserialize(toml::Value::Table(t))
            .map_err(|e| format!("material `{name}`: {}", e.message().replace('\n', " ")))?;
        Ok(MaterialCfg {
            name: f.name,
            preset: f.preset,
            eos: f.eos,
            strength: f.strength,
            pmin_pa: f.pmin_pa,
            e0_jkg: f.e0_jkg,
            penalty_group: f.penalty_group,
        })
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum EosCfg {
    /// Ideal gas p = (γ−1)ρe.
    IdealGas { gamma: f64, rho0_kgm3: Option<f64> },
    /// JWL (4-39).
    Jwl { rho0_kgm3: f64, a_pa: f64, b_pa: f64, r1: f64, r2: f64, omega: f64, d_ms: f64 },
    /// Water polynomial (4-40, 4-41).
    Water { rho0_kgm3: f64, a1_pa: f64, a2_pa: f64, a3_pa: f64, b0: f64, b1: f64, c0_ms: f64 },
    /// Soil Mie–Grüneisen with a linear Us–Up Hugoniot (4-42…4-46).
    Soil { rho0_kgm3: f64, c_ms: f64, s: f64, gamma: f64 },
}

impl EosCfg {
    pub fn rho0(&self) -> Option<f64> {
        match self {
            EosCfg::IdealGas { rho0_kgm3, .. } => *rho0_kgm3,
            EosCfg::Jwl { rho0_kgm3, .. } | EosCfg::Water { rho0_kgm3, .. } | EosCfg::Soil { rho0_kgm3, .. } => {
                Some(*rho0_kgm3)
            }
        }
    }
    pub fn kind(&self) -> &'static str {
        match self {
            EosCfg::IdealGas { .. } => "ideal_gas",
            EosCfg::Jwl { .. } => "jwl",
            EosCfg::Water { .. } => "water",
            EosCfg::Soil { .. } => "soil",
        }
    }
}

/// Drucker–Prager strength (4-29…4-32).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StrengthCfg {
    /// Shear modulus G (Pa).
    pub shear_modulus_pa: f64,
    /// α_φ of the yield surface √J2 = 3 α_φ p + k.
    pub alpha_phi: f64,
    /// k of the yield surface (Pa).
    pub cohesion_pa: f64,
}

#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Shape {
    /// An axis-aligned box `lo_m`..`hi_m`, particles at the centres of its lattice cells.
    Box,
    /// A polygon (2D) `vertices_m`, cell-centred lattice from its lower-left corner.
    Polygon,
    /// `count` particles per axis at `origin_m + k × spacing_m` (Liu's shock tube).
    Lattice,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionCfg {
    pub name: String,
    pub material: String,
    pub shape: Shape,
    pub lo_m: Option<Vec<f64>>,
    pub hi_m: Option<Vec<f64>>,
    pub vertices_m: Option<Vec<Vec<f64>>>,
    pub origin_m: Option<Vec<f64>>,
    pub count: Option<Vec<usize>>,
    /// Initial particle spacing Δx (m).
    pub spacing_m: f64,
    /// Initial density (kg/m³); default: the material's ρ0.
    pub rho_kgm3: Option<f64>,
    /// Initial specific internal energy (J/kg); default: the material's e0_jkg, else 0.
    pub e_jkg: Option<f64>,
    /// Initial velocity (m/s).
    pub velocity_ms: Option<Vec<f64>>,
    /// Particle mass (kg, per metre of depth in 2D); default ρ Δx^d.
    pub mass_kg: Option<f64>,
    /// Initial smoothing length (m); default h_over_dx × Δx.
    pub h_m: Option<f64>,
    /// Regions whose shape is cut out of this one.
    #[serde(default)]
    pub subtract: Vec<String>,
}

#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum WallKind {
    /// Type I: wall particles with a repulsive force.
    Repulsive,
    /// Type II: mirror particles.
    Mirror,
    /// Both kinds (the thesis's blast runs).
    Both,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallCfg {
    /// Start point (m).
    pub from_m: Vec<f64>,
    /// End point (m); equal to from_m in 1D.
    pub to_m: Vec<f64>,
    #[serde(default = "default_wall_kind")]
    pub kind: WallKind,
}

fn default_wall_kind() -> WallKind {
    WallKind::Both
}

#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum BurnMode {
    /// Constant-volume burn: all products at ρ0, e0 at t = 0.
    Instant,
    /// Programmed burn from `point_m` at the detonation speed D.
    Programmed,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DetonationCfg {
    pub mode: BurnMode,
    /// Lighting point (m), for the programmed burn.
    pub point_m: Option<Vec<f64>>,
    /// Width of the burn ramp in units of h (0 = a particle burns at once when lit).
    #[serde(default)]
    pub width_h: f64,
}

/// What a gauge follows (docs/cases.md `[[gauge]]`).
#[derive(Debug, Clone, Copy, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum GaugeKind {
    /// Lagrangian: the real particle nearest `point_m` at t = 0 (ties within 1e-6 of the finest
    /// spacing go to the particle generated first, i.e. the lowest id), followed as it moves.
    #[default]
    Particle,
    /// Eulerian: the fixed point `point_m`, values by the Shepard-normalised SPH interpolation
    /// Σ_j (m_j/ρ_j) f_j W(|x − x_j|, h_j) / Σ_j (m_j/ρ_j) W(|x − x_j|, h_j) over the real particles.
    Point,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GaugeCfg {
    pub name: String,
    /// Where the gauge is (m).
    pub point_m: Vec<f64>,
    /// "particle" (default: the particle nearest the point at t = 0) or "point" (the fixed point).
    #[serde(default)]
    pub kind: GaugeKind,
}

#[derive(Debug, Clone, Copy, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum AnalysisKind {
    #[default]
    None,
    /// A 1D Riemann problem: L1 errors against the exact solution.
    Riemann,
    /// A blast in soil: crater, ejecta, gauges.
    Crater,
}

#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnalysisCfg {
    #[serde(default)]
    pub kind: AnalysisKind,
    /// Riemann: position of the diaphragm (m).
    pub diaphragm_m: Option<f64>,
    /// Riemann: the interval over which L1 errors are taken (m).
    pub window_m: Option<Vec<f64>>,
    /// Crater: the materials that count as soil (default: every material with strength).
    pub soil_materials: Option<Vec<String>>,
    /// Thesis values to report beside ours: final crater diameter and depth (m).
    pub thesis_crater_m: Option<Vec<f64>>,
    /// Thesis crater growth: [time (s), diameter (m), depth (m)] rows.
    pub thesis_crater_history: Option<Vec<Vec<f64>>>,
    /// Thesis gauge readings to report beside ours.
    #[serde(default)]
    pub thesis_gauge: Vec<ThesisGauge>,
}

/// One gauge reading reported by the thesis (THESIS.md §9).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThesisGauge {
    /// Gauge name (as in [[gauge]]).
    pub gauge: String,
    /// Time of the peak (s).
    pub peak_time_s: Option<f64>,
    /// Peak pressure (Pa).
    pub peak_pa: Option<f64>,
}

#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BackendCfg {
    /// "fortran" or "rust" for every module not named below.
    pub default: Option<String>,
    #[serde(default)]
    pub rust: Vec<String>,
    #[serde(default)]
    pub fortran: Vec<String>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DomainCfg {
    /// A particle outside lo_m..hi_m is counted as having left the domain.
    pub lo_m: Vec<f64>,
    pub hi_m: Vec<f64>,
    /// Stop the run when a particle leaves (default: count it and go on).
    #[serde(default)]
    pub stop_on_exit: bool,
}

/// Reads a case file, applies `key=value` overrides, and parses it.
pub fn load(path: &Path, sets: &[String]) -> Result<Case> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| input(format!("{}: cannot read the case file: {e}", path.display())))?;
    parse(&text, &path.display().to_string(), sets, path.file_stem().and_then(|s| s.to_str()))
}

/// Parses case text; `origin` names it in error messages. The `--set` overrides are applied to
/// the text ([`apply_sets`]); an error they cause names the override, not a line of the edited
/// text.
pub fn parse(text: &str, origin: &str, sets: &[String], stem: Option<&str>) -> Result<Case> {
    text.parse::<toml::Table>().map_err(|e| toml_error(origin, text, &e))?;
    let attempt = |k: usize| -> Result<Case> {
        let edited = apply_sets(text, &sets[..k])?;
        let mut case: Case = toml::from_str(&edited).map_err(|e| toml_error(origin, &edited, &e))?;
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

/// The error of a case with overrides, attributed: to the file when the file alone gives the same
/// error, else to the first override after which it appears.
fn blame(
    e: &crate::error::SphError,
    sets: &[String],
    attempt: &dyn Fn(usize) -> Result<Case>,
) -> crate::error::SphError {
    let msg = |e: &crate::error::SphError| -> String {
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
            return input(format!("--set {}: {want}", sets[k - 1]));
        }
    }
    input(format!("--set {}: {want}", sets.join(" --set ")))
}

fn toml_error(origin: &str, text: &str, e: &toml::de::Error) -> crate::error::SphError {
    let line = e.span().map(|s| text[..s.start.min(text.len())].matches('\n').count() + 1);
    let msg = e.message().replace('\n', " ");
    match line {
        Some(l) => input(format!("{origin}:{l}: {msg}")),
        None => input(format!("{origin}: {msg}")),
    }
}

/// The case text with `--set a.b.c=value` overrides applied (value parsed as TOML, else taken as
/// a string), keeping the file's layout and comments; a changed value is marked with a comment
/// `# set by --set (was …)`. Arrays of tables are indexed by number or by their `name`:
/// `material.loose_sand.pmin_pa=0`.
pub fn apply_sets(text: &str, sets: &[String]) -> Result<String> {
    if sets.is_empty() {
        return Ok(text.to_string());
    }
    let mut doc: toml_edit::DocumentMut = text.parse().map_err(|e| input(format!("{e}")))?;
    for s in sets {
        apply_set(&mut doc, s)?;
    }
    Ok(doc.to_string())
}

fn apply_set(doc: &mut toml_edit::DocumentMut, s: &str) -> Result<()> {
    use toml_edit::Item;
    let (key, val) = s.split_once('=').ok_or_else(|| input(format!("--set {s}: expected key=value")))?;
    let key = key.trim();
    let mut parsed: toml_edit::Value = match format!("v = {val}").parse::<toml_edit::DocumentMut>() {
        Ok(d) => match d.get("v").and_then(|v| v.as_value()) {
            Some(v) => v.clone(),
            None => toml_edit::Value::from(val),
        },
        Err(_) => toml_edit::Value::from(val),
    };
    if key.is_empty() || key.split('.').any(|p| p.is_empty()) {
        return Err(input(format!("--set {s}: an empty key")));
    }
    let parts: Vec<&str> = key.split('.').collect();
    let mut cur: &mut Item = doc.as_item_mut();
    for part in parts {
        let array_len = match &*cur {
            Item::ArrayOfTables(a) => Some(a.len()),
            Item::Value(toml_edit::Value::Array(a)) => Some(a.len()),
            _ => None,
        };
        cur = if let Some(len) = array_len {
            let idx = match part.parse::<usize>() {
                Ok(i) => i,
                Err(_) => {
                    let named = |t: Option<&str>| t == Some(part);
                    let pos = match &*cur {
                        Item::ArrayOfTables(a) => a.iter().position(|t| named(t.get("name").and_then(|n| n.as_str()))),
                        Item::Value(toml_edit::Value::Array(a)) => a.iter().position(|v| {
                            named(v.as_inline_table().and_then(|t| t.get("name")).and_then(|n| n.as_str()))
                        }),
                        _ => None,
                    };
                    pos.ok_or_else(|| input(format!("--set {key}: no entry named `{part}`")))?
                }
            };
            if idx >= len {
                return Err(input(format!("--set {key}: index {idx} out of range ({len} entries)")));
            }
            cur.get_mut(idx).ok_or_else(|| input(format!("--set {key}: index {idx} out of range")))?
        } else if cur.is_table_like() || cur.is_none() {
            cur.get_mut(part).ok_or_else(|| input(format!("--set {key}: `{part}` is not inside a table")))?
        } else {
            return Err(input(format!("--set {key}: `{part}` is not inside a table")));
        };
    }
    if let Some(old) = cur.as_value() {
        let mut was = old.clone();
        was.decor_mut().clear();
        let prefix = old.decor().prefix().and_then(|p| p.as_str()).unwrap_or(" ").to_string();
        parsed.decor_mut().set_prefix(prefix);
        parsed.decor_mut().set_suffix(format!("  # set by --set (was {})", was.to_string().trim()));
    } else if !cur.is_none() && !matches!(parsed, toml_edit::Value::InlineTable(_)) {
        return Err(input(format!("--set {key}: replaces a table with a value")));
    }
    *cur = Item::Value(parsed);
    Ok(())
}

impl Case {
    pub fn name(&self) -> &str {
        self.name.as_deref().unwrap_or("case")
    }

    pub fn material_index(&self, name: &str) -> Option<usize> {
        self.materials.iter().position(|m| m.name == name)
    }

    /// Checks what serde cannot; errors are one line naming the key.
    pub fn validate(&self) -> Result<()> {
        self.compat.flags()?;
        let d = self.dim;
        if !(1..=3).contains(&d) {
            return Err(input(format!("dim = {d}: must be 1, 2 or 3")));
        }
        let t = &self.time;
        pos("time.end_s", t.end_s)?;
        if t.output_interval_s < 0.0 || !t.output_interval_s.is_finite() {
            return Err(input("time.output_interval_s: must be zero or positive"));
        }
        match t.step {
            StepRule::Fixed => {
                pos("time.dt_s", t.dt_s.ok_or_else(|| input("time.dt_s: required when time.step = \"fixed\""))?)?
            }
            StepRule::Cfl => {
                pos("time.cfl", t.cfl)?;
                if t.cfl > 1.0 {
                    return Err(input(format!("time.cfl = {}: must not exceed 1", t.cfl)));
                }
            }
        }
        if let Some(m) = t.dt_max_s {
            pos("time.dt_max_s", m)?;
        }
        pos("sph.h_over_dx", self.sph.h_over_dx)?;
        pos("sph.theta", self.sph.theta)?;
        if self.sph.xsph_eps < 0.0 {
            return Err(input("sph.xsph_eps: must not be negative"));
        }
        nonneg("viscosity.alpha", self.viscosity.alpha)?;
        nonneg("viscosity.beta", self.viscosity.beta)?;
        pos("viscosity.phi_over_h", self.viscosity.phi_over_h)?;
        if let Some(p) = &self.penalty {
            pos("penalty.pbar", p.pbar)?;
            if p.n1 <= p.n2 || p.n2 < 1 {
                return Err(input(format!("penalty: need n1 > n2 >= 1 (got n1 = {}, n2 = {})", p.n1, p.n2)));
            }
        }
        let b = &self.boundary;
        if let Some(s) = b.wall_spacing_m {
            pos("boundary.wall_spacing_m", s)?;
        }
        if let Some(s) = b.r0_m {
            pos("boundary.r0_m", s)?;
        }
        nonneg("boundary.d_m2s2", b.d_m2s2)?;
        if b.n1 <= b.n2 || b.n2 < 1 {
            return Err(input(format!("boundary: need n1 > n2 >= 1 (got n1 = {}, n2 = {})", b.n1, b.n2)));
        }
        if let Some(g) = &self.physics.gravity_ms2 {
            vecd("physics.gravity_ms2", g, d)?;
        }

        if self.materials.is_empty() {
            return Err(input("no [[material]]: a case needs at least one material with an eos"));
        }
        let mut names = std::collections::BTreeSet::new();
        for (k, m) in self.materials.iter().enumerate() {
            let key = format!("material[{k}] ({})", m.name);
            if !names.insert(m.name.as_str()) {
                return Err(input(format!("{key}: the name is used twice")));
            }
            match &m.eos {
                EosCfg::IdealGas { gamma, rho0_kgm3 } => {
                    if *gamma <= 1.0 || !gamma.is_finite() {
                        return Err(input(format!("{key}.eos.gamma = {gamma}: must exceed 1")));
                    }
                    if let Some(r) = rho0_kgm3 {
                        pos(&format!("{key}.eos.rho0_kgm3"), *r)?;
                    }
                }
                EosCfg::Jwl { rho0_kgm3, a_pa, b_pa, r1, r2, omega, d_ms } => {
                    pos(&format!("{key}.eos.rho0_kgm3"), *rho0_kgm3)?;
                    nonneg(&format!("{key}.eos.a_pa"), *a_pa)?;
                    nonneg(&format!("{key}.eos.b_pa"), *b_pa)?;
                    pos(&format!("{key}.eos.r1"), *r1)?;
                    pos(&format!("{key}.eos.r2"), *r2)?;
                    pos(&format!("{key}.eos.omega"), *omega)?;
                    pos(&format!("{key}.eos.d_ms"), *d_ms)?;
                }
                EosCfg::Water { rho0_kgm3, a1_pa, c0_ms, .. } => {
                    pos(&format!("{key}.eos.rho0_kgm3"), *rho0_kgm3)?;
                    pos(&format!("{key}.eos.a1_pa"), *a1_pa)?;
                    pos(&format!("{key}.eos.c0_ms"), *c0_ms)?;
                }
                EosCfg::Soil { rho0_kgm3, c_ms, s, gamma } => {
                    pos(&format!("{key}.eos.rho0_kgm3"), *rho0_kgm3)?;
                    pos(&format!("{key}.eos.c_ms"), *c_ms)?;
                    pos(&format!("{key}.eos.s"), *s)?;
                    nonneg(&format!("{key}.eos.gamma"), *gamma)?;
                }
            }
            if let Some(s) = &m.strength {
                pos(&format!("{key}.strength.shear_modulus_pa"), s.shear_modulus_pa)?;
                nonneg(&format!("{key}.strength.alpha_phi"), s.alpha_phi)?;
                nonneg(&format!("{key}.strength.cohesion_pa"), s.cohesion_pa)?;
            }
            if let Some(e) = m.e0_jkg {
                finite(&format!("{key}.e0_jkg"), e)?;
            }
        }

        if self.regions.is_empty() {
            return Err(input("no [[region]]: a case needs at least one region of particles"));
        }
        let mut rnames = std::collections::BTreeSet::new();
        for (k, r) in self.regions.iter().enumerate() {
            let key = format!("region[{k}] ({})", r.name);
            if !rnames.insert(r.name.as_str()) {
                return Err(input(format!("{key}: the name is used twice")));
            }
            let mi = self.material_index(&r.material).ok_or_else(|| {
                input(format!(
                    "{key}.material = \"{}\": no [[material]] of that name (a material needs an eos)",
                    r.material
                ))
            })?;
            pos(&format!("{key}.spacing_m"), r.spacing_m)?;
            match r.shape {
                Shape::Box => {
                    let lo =
                        r.lo_m.as_ref().ok_or_else(|| input(format!("{key}.lo_m: required for shape = \"box\"")))?;
                    let hi =
                        r.hi_m.as_ref().ok_or_else(|| input(format!("{key}.hi_m: required for shape = \"box\"")))?;
                    vecd(&format!("{key}.lo_m"), lo, d)?;
                    vecd(&format!("{key}.hi_m"), hi, d)?;
                    for a in 0..d {
                        if hi[a] <= lo[a] {
                            return Err(input(format!(
                                "{key}: hi_m[{a}] = {} must exceed lo_m[{a}] = {}",
                                hi[a], lo[a]
                            )));
                        }
                    }
                }
                Shape::Polygon => {
                    if d != 2 {
                        return Err(input(format!("{key}: shape = \"polygon\" needs dim = 2")));
                    }
                    let v = r
                        .vertices_m
                        .as_ref()
                        .ok_or_else(|| input(format!("{key}.vertices_m: required for shape = \"polygon\"")))?;
                    if v.len() < 3 {
                        return Err(input(format!("{key}.vertices_m: a polygon needs at least 3 vertices")));
                    }
                    for (q, p) in v.iter().enumerate() {
                        vecd(&format!("{key}.vertices_m[{q}]"), p, 2)?;
                    }
                }
                Shape::Lattice => {
                    let o = r
                        .origin_m
                        .as_ref()
                        .ok_or_else(|| input(format!("{key}.origin_m: required for shape = \"lattice\"")))?;
                    vecd(&format!("{key}.origin_m"), o, d)?;
                    let c = r
                        .count
                        .as_ref()
                        .ok_or_else(|| input(format!("{key}.count: required for shape = \"lattice\"")))?;
                    if c.len() != d || c.contains(&0) {
                        return Err(input(format!("{key}.count: need {d} positive counts")));
                    }
                }
            }
            if let Some(rho) = r.rho_kgm3 {
                pos(&format!("{key}.rho_kgm3"), rho)?;
            } else if self.materials[mi].eos.rho0().is_none() {
                return Err(input(format!("{key}.rho_kgm3: required (material `{}` has no rho0_kgm3)", r.material)));
            }
            if let Some(e) = r.e_jkg {
                finite(&format!("{key}.e_jkg"), e)?;
            }
            if let Some(v) = &r.velocity_ms {
                vecd(&format!("{key}.velocity_ms"), v, d)?;
            }
            if let Some(m) = r.mass_kg {
                pos(&format!("{key}.mass_kg"), m)?;
            }
            if let Some(h) = r.h_m {
                pos(&format!("{key}.h_m"), h)?;
            }
            for s in &r.subtract {
                if !self.regions.iter().any(|q| &q.name == s) || s == &r.name {
                    return Err(input(format!("{key}.subtract: no other region named `{s}`")));
                }
            }
        }

        for (k, w) in self.walls.iter().enumerate() {
            vecd(&format!("wall[{k}].from_m"), &w.from_m, d)?;
            vecd(&format!("wall[{k}].to_m"), &w.to_m, d)?;
            if d == 3 {
                return Err(input(format!("wall[{k}]: walls are segments (1D, 2D); 3D walls are not supported yet")));
            }
            if d == 2 && w.from_m == w.to_m {
                return Err(input(format!("wall[{k}]: from_m and to_m coincide")));
            }
        }
        if let Some(det) = &self.detonation {
            if det.mode == BurnMode::Programmed {
                let p = det
                    .point_m
                    .as_ref()
                    .ok_or_else(|| input("detonation.point_m: required for mode = \"programmed\""))?;
                vecd("detonation.point_m", p, d)?;
            }
            nonneg("detonation.width_h", det.width_h)?;
            if !self.materials.iter().any(|m| matches!(m.eos, EosCfg::Jwl { .. })) {
                return Err(input("detonation: no material has eos kind = \"jwl\""));
            }
        }
        let mut gnames = std::collections::BTreeSet::new();
        for (k, g) in self.gauges.iter().enumerate() {
            vecd(&format!("gauge[{k}].point_m"), &g.point_m, d)?;
            if !gnames.insert(g.name.as_str()) {
                return Err(input(format!("gauge[{k}] ({}): the name is used twice", g.name)));
            }
        }
        if self.analysis.kind == AnalysisKind::Riemann {
            if d != 1 {
                return Err(input("analysis.kind = \"riemann\" needs dim = 1"));
            }
            if self.analysis.diaphragm_m.is_none() {
                return Err(input("analysis.diaphragm_m: required for kind = \"riemann\""));
            }
            if let Some(w) = &self.analysis.window_m
                && (w.len() != 2 || w[1] <= w[0])
            {
                return Err(input("analysis.window_m: need [lo, hi] with hi > lo"));
            }
        }
        for (k, t) in self.analysis.thesis_gauge.iter().enumerate() {
            if !self.gauges.iter().any(|g| g.name == t.gauge) {
                return Err(input(format!(
                    "analysis.thesis_gauge[{k}].gauge = \"{}\": no [[gauge]] of that name",
                    t.gauge
                )));
            }
        }
        if let Some(h) = &self.analysis.thesis_crater_history
            && h.iter().any(|r| r.len() != 3)
        {
            return Err(input("analysis.thesis_crater_history: rows must be [time_s, diameter_m, depth_m]"));
        }
        if let Some(sm) = &self.analysis.soil_materials {
            for s in sm {
                if self.material_index(s).is_none() {
                    return Err(input(format!("analysis.soil_materials: no material named `{s}`")));
                }
            }
        }
        if let Some(dm) = &self.domain {
            vecd("domain.lo_m", &dm.lo_m, d)?;
            vecd("domain.hi_m", &dm.hi_m, d)?;
        }
        let mods: BTreeMap<&str, ()> = crate::modules::Module::ALL.iter().map(|m| (m.name(), ())).collect();
        for (key, list) in [("backend.rust", &self.backend.rust), ("backend.fortran", &self.backend.fortran)] {
            for m in list {
                if !mods.contains_key(m.as_str()) {
                    return Err(input(format!(
                        "{key}: unknown module `{m}` (modules: {})",
                        crate::modules::Module::names()
                    )));
                }
            }
        }
        if let Some(dft) = &self.backend.default
            && dft != "fortran"
            && dft != "rust"
        {
            return Err(input(format!("backend.default = \"{dft}\": must be \"fortran\" or \"rust\"")));
        }
        Ok(())
    }
}

fn finite(key: &str, v: f64) -> Result<()> {
    if v.is_finite() { Ok(()) } else { Err(input(format!("{key} = {v}: must be a finite number"))) }
}

fn pos(key: &str, v: f64) -> Result<()> {
    if v > 0.0 && v.is_finite() { Ok(()) } else { Err(input(format!("{key} = {v}: must be positive"))) }
}

fn nonneg(key: &str, v: f64) -> Result<()> {
    if v >= 0.0 && v.is_finite() { Ok(()) } else { Err(input(format!("{key} = {v}: must not be negative"))) }
}

fn vecd(key: &str, v: &[f64], d: usize) -> Result<()> {
    if v.len() != d {
        return Err(input(format!("{key}: needs {d} components (dim = {d}), got {}", v.len())));
    }
    for x in v {
        finite(key, *x)?;
    }
    Ok(())
}
