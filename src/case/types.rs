//! The case's tables as Rust types: one struct per TOML table, `deny_unknown_fields` everywhere
//! (`docs/reference/cases.md` lists every key with its unit and default). What serde cannot check is
//! checked in [`super::validate`]: one place per key.

use super::PressureForm;
use super::conductivity::ConductivityCfg;
use super::material::MaterialCfg;
use serde::Deserialize;

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Case {
    /// Name of the case (default: the file stem).
    pub name: Option<String>,
    /// `"thesis"`: every key the case does not give takes the thesis's (and Liu's book code's)
    /// setting instead of the safe default (docs/reference/cases.md, "Defaults and the parity preset").
    pub parity: Option<String>,
    /// Free text.
    #[serde(default)]
    pub description: String,
    /// Space dimension: 1, 2 (plane strain) or 3.
    pub dim: usize,
    /// "plane" (default) or "axisymmetric" (dim = 2: x is the radius r ≥ 0, y the axis).
    #[serde(default)]
    pub geometry: Geometry,
    pub time: TimeCfg,
    #[serde(default)]
    pub sph: SphCfg,
    #[serde(default)]
    pub viscosity: ViscCfg,
    #[serde(default)]
    pub conductivity: ConductivityCfg,
    pub penalty: Option<PenaltyCfg>,
    #[serde(default)]
    pub boundary: BoundaryCfg,
    #[serde(default)]
    pub physics: PhysicsCfg,
    /// The state at t = 0 beyond what the regions give (the geostatic stress).
    #[serde(default)]
    pub initial: InitialCfg,
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
    /// Compatibility items: a profile and items by name, read by the layer a run attaches
    /// ([`crate::sim::Bridge`]); the core only carries them.
    #[serde(default)]
    pub compat: CompatCfg,
}

/// The case's `[compat]` table: a profile and items switched on or off over it, by name. The
/// core carries it unread; the bridge a run attaches gives it a meaning or refuses it.
#[derive(Debug, Clone, Default, Deserialize, serde::Serialize, PartialEq)]
pub struct CompatCfg {
    /// A profile, by name.
    #[serde(default)]
    pub profile: Option<String>,
    /// Items switched on (true) or off (false) over the profile, by name.
    #[serde(flatten)]
    pub items: std::collections::BTreeMap<String, bool>,
}

impl CompatCfg {
    /// True when the table names nothing.
    pub fn is_empty(&self) -> bool {
        self.profile.is_none() && self.items.is_empty()
    }
}

/// The geometry of a 2D case (docs/theory.md, axisymmetric SPH).
#[derive(Debug, Clone, Copy, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Geometry {
    /// Cartesian: plane strain in 2D (masses per metre of depth).
    #[default]
    Plane,
    /// Axisymmetric (RZ), dim = 2: x = r ≥ 0, y = z along the axis; a particle is a ring (kg).
    Axisymmetric,
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
    /// Smallest step (s) under the CFL rule: a run whose step falls below it stops as unstable
    /// with a diagnostic (default: [`DT_MIN_FRACTION`] × the first step).
    pub dt_min_s: Option<f64>,
    /// Stop after this many steps (a safety limit).
    #[serde(default = "default_max_steps")]
    pub max_steps: u64,
    /// Add the signal speed of the viscosity's β term, 1.2 β max_j |μ_ij|, to c + |v| in the CFL
    /// rule (Monaghan 1992). Without it a β = 10 viscosity is unstable at C_cfl = 0.25 in cold
    /// converging flow (docs/validation.md, "Verification problems").
    #[serde(default = "yes")]
    pub viscous_step: bool,
}

fn yes() -> bool {
    true
}

/// The default floor of the CFL step, as a fraction of the run's first step: a step that falls
/// this far has collapsed (healthy runs stay within a factor of a few of their first step).
pub const DT_MIN_FRACTION: f64 = 1e-3;

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
    /// Number-density summation (Hu & Adams 2006): ρ_i = m_i (W_ii + Σ_j W_ij), each particle's
    /// density from its own mass, so a light phase beside a heavy one keeps its own density.
    Number,
}

#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum ContinuityForm {
    Mass,
    Volume,
}

fn default_cform() -> ContinuityForm {
    ContinuityForm::Volume
}

/// Form of the pressure work in the energy equation (theory.md §5).
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum EnergyForm {
    /// ½ Σ m_j (p_i/ρ_i² + p_j/ρ_j²) v_ij·∇W (thesis 4-35, Liu).
    Symmetric,
    /// Σ m_j (p_i/ρ_i²) v_ij·∇W: each particle its own p dV work.
    Asymmetric,
}

fn default_eform() -> EnergyForm {
    EnergyForm::Asymmetric
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
    /// Form of the pressure work in the energy equation: "symmetric" (thesis 4-35) or
    /// "asymmetric" (each particle its own p dV work; keeps e ≥ 0 where p ≥ 0).
    #[serde(default = "default_eform")]
    pub energy_form: EnergyForm,
    /// Form of the pressure term of the momentum equation: "standard" (thesis 4-33) or
    /// "interface" (Colagrossi & Landrini 2003; resolved before reading: the default with
    /// `density = "number"`).
    #[serde(default = "default_pform")]
    pub pressure_form: PressureForm,
    #[serde(default = "default_smoothing")]
    pub smoothing: SmoothingKind,
    /// θ of the h update (2-16).
    #[serde(default = "one")]
    pub theta: f64,
    /// Cap on h: h ≤ h_max_ratio × the largest initial h (absent = no cap).
    pub h_max_ratio: Option<f64>,
    /// Floor e ≥ 0 after each step, the energy it adds booked in the balance (summary.json
    /// energy.work_floor).
    #[serde(default = "yes")]
    pub e_floor: bool,
    /// Clamp ρ of the real particles to [lo, hi] (kg/m³) after each density update of the
    /// leapfrog, as Liu and Liu's dam-break `time_integration` does (absent = off).
    pub density_clamp: Option<Vec<f64>>,
    /// XSPH averaging coefficient ε (0 = off).
    #[serde(default)]
    pub xsph_eps: f64,
    /// Sort the particles by cell every this many steps, for memory locality (0 = never). It
    /// changes the order of the neighbour sums, so results differ at round-off from an unsorted
    /// run (they stay independent of the backend and of the thread count).
    #[serde(default)]
    pub reorder_every: u64,
    /// Displacement of every lattice point at the start, as a fraction of its region's spacing:
    /// each coordinate moves by a deterministic pseudo-random amount in [−jitter/2, jitter/2) Δx.
    /// It breaks the exact mirror symmetry of a lattice about a point blast's centre, along whose
    /// lines of particles the standard viscosity lets a row run ahead as a jet (docs/validation.md,
    /// "Jets along the lattice's symmetry lines"). Resolved before reading (5e-2 for gas dynamics
    /// in 2D plane and 3D: `case::GAS_JITTER`; else 0).
    #[serde(default)]
    pub jitter: f64,
    /// Divide every pair's ∇W by the kernel's first moment on the lattice at `h_over_dx`
    /// (`kernel::lattice_moment`: 1.0200 for the cubic spline in 3D at h = Δx, 1.0131 in 2D), so
    /// that gradients of linear fields, and an elastic wave's speed, are exact on the lattice.
    /// Off by default (the thesis's and Liu's kernel); docs/validation.md, "Elastic P wave".
    #[serde(default)]
    pub lattice_gradient: bool,
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
fn default_pform() -> PressureForm {
    PressureForm::Standard
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
            energy_form: default_eform(),
            pressure_form: default_pform(),
            smoothing: default_smoothing(),
            theta: 1.0,
            h_max_ratio: None,
            e_floor: true,
            density_clamp: None,
            xsph_eps: 0.0,
            reorder_every: 0,
            jitter: 0.0,
            lattice_gradient: false,
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
    /// Viscosity switch (theory.md §6): `none` (α, β constant) or `morris_monaghan` (α_i evolves
    /// between `alpha_min` and `alpha`, β_ij = β α_ij/α).
    #[serde(default)]
    pub switch: ViscSwitch,
    /// Floor of the switch's α_i (Morris & Monaghan 1997: 0.1).
    #[serde(default = "default_alpha_min")]
    pub alpha_min: f64,
    /// ℓ of the switch's decay time τ_i = h_i/(ℓ c_i) (Morris & Monaghan: 0.2).
    #[serde(default = "default_switch_decay")]
    pub switch_decay: f64,
}

/// The artificial-viscosity switch.
#[derive(Debug, Clone, Copy, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ViscSwitch {
    /// Constant coefficients (the thesis's).
    #[default]
    None,
    /// Morris & Monaghan (1997): dα_i/dt = −(α_i − α_min)/τ_i + max(−∇·v_i, 0)(α_max − α_i).
    MorrisMonaghan,
}

fn default_beta() -> f64 {
    10.0
}
fn default_phi() -> f64 {
    0.1
}
fn default_alpha_min() -> f64 {
    0.1
}
fn default_switch_decay() -> f64 {
    0.2
}

impl Default for ViscCfg {
    fn default() -> Self {
        ViscCfg {
            alpha: 1.0,
            beta: 10.0,
            phi_over_h: 0.1,
            switch: ViscSwitch::None,
            alpha_min: default_alpha_min(),
            switch_decay: default_switch_decay(),
        }
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
    /// Thickness (m) of the layer of particles an `absorbing` wall acts on; default: the largest
    /// region spacing.
    pub absorb_layer_m: Option<f64>,
    /// The repulsion of boundary particles ([`super::RepulsionCfg`]); none by default.
    pub repulsion: Option<super::RepulsionCfg>,
}

fn default_dwall() -> f64 {
    1e4
}
fn default_wall_n2() -> i32 {
    4
}

impl Default for BoundaryCfg {
    fn default() -> Self {
        BoundaryCfg {
            wall_spacing_m: None,
            r0_m: None,
            d_m2s2: 1e4,
            n1: 12,
            n2: 4,
            noslip: false,
            absorb_layer_m: None,
            repulsion: None,
        }
    }
}

#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PhysicsCfg {
    /// Gravity (m/s²), one component per dimension; absent = none.
    pub gravity_ms2: Option<Vec<f64>>,
    /// A force stage adds `gravity_ms2` itself (a legacy routine's): the rate sum does not.
    #[serde(default)]
    pub gravity_in_forces: bool,
}

/// The `[initial]` table: what the set-up adds to the regions' state at t = 0.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialCfg {
    /// Start at rest under gravity: σ_v = g ∫ρ dz over the column above each particle,
    /// σ_h = K0 σ_v (Jaky: K0 = 1 − sin φ for a material with strength, 1 for a fluid), the density
    /// from the EOS at that mean stress, τ the deviator (docs/theory.md, "Geostatic start").
    /// Absent: on where gravity is on and some material has strength ([`Case::geostatic`]).
    pub geostatic: Option<bool>,
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
    /// A cylinder (3D) with its axis along z: `center_m` the centre of its base, `radius_m`,
    /// `height_m`; cell-centred lattice (from `lo_m` when given, which with `hi_m` also clips it).
    Cylinder,
    /// A sphere (a disc in 2D): `center_m`, `radius_m`; lattice and clipping as for a cylinder.
    Sphere,
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
    /// Cylinder: centre of the base (m); sphere: the centre.
    pub center_m: Option<Vec<f64>>,
    /// Cylinder, sphere: radius (m).
    pub radius_m: Option<f64>,
    /// Cylinder: height (m), along z.
    pub height_m: Option<f64>,
    /// Initial particle spacing Δx (m).
    pub spacing_m: f64,
    /// Initial density (kg/m³); default: the material's ρ0.
    pub rho_kgm3: Option<f64>,
    /// Initial specific internal energy (J/kg); default: the material's e0_jkg, else 0.
    pub e_jkg: Option<f64>,
    /// Initial velocity (m/s).
    pub velocity_ms: Option<Vec<f64>>,
    /// Initial radial velocity (m/s, negative = towards `radial_center_m`), added to
    /// `velocity_ms`: v = radial_velocity_ms (x − c)/|x − c| (zero at the centre). The Noh problem.
    pub radial_velocity_ms: Option<f64>,
    /// Centre of `radial_velocity_ms` (m); default the origin.
    pub radial_center_m: Option<Vec<f64>>,
    /// Particle mass (kg, per metre of depth in 2D); default ρ Δx^d.
    pub mass_kg: Option<f64>,
    /// Initial smoothing length (m); default h_over_dx × Δx.
    pub h_m: Option<f64>,
    /// Regions whose shape is cut out of this one.
    #[serde(default)]
    pub subtract: Vec<String>,
    /// Half-spaces that clip the region's shape (any shape, any dimension): a point x belongs
    /// to the region only where (x − point_m)·n̂ ≤ 0 for every plane, n̂ = normal/|normal|
    /// (the normal points out of the kept side). See [`ClipPlane`].
    #[serde(default)]
    pub keep_below: Vec<ClipPlane>,
    /// Makes the region's particles boundary particles of this kind; absent: ordinary ones.
    pub boundary_particles: Option<BoundaryKind>,
}

/// A region's boundary particles (Liu & Liu 2003's virtual particles): in every pair sum, never
/// moved. The value is the one the state stores per particle ([`crate::state::Particles::bnd`]).
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum BoundaryKind {
    /// ρ, e, v (and τ) integrated like any particle's; x fixed.
    Integrated = 1,
    /// ρ, e, v, τ and x held at their initial values by the leapfrog.
    Held = 2,
}

/// One plane of a region's `keep_below`: the region keeps the closed half-space
/// (x − point_m)·n̂ ≤ 0 (m), n̂ = normal/|normal|, so the normal points out of the kept side
/// (up, out of the ground, for a soil surface). A point on the plane is kept. In 1D the plane is
/// a point; in 2D a line; in axisymmetric geometry a line of the r–z half plane, so the surface
/// it cuts is a cone about the axis (a plane z = const when the normal is along z, a cylinder
/// r = const when it is along r).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClipPlane {
    /// A point of the plane (m), `dim` components.
    pub point_m: Vec<f64>,
    /// The plane's normal, pointing out of the kept side (`dim` components, any length but
    /// zero: it is normalised).
    pub normal: Vec<f64>,
}

impl ClipPlane {
    /// The signed distance (m) of `p` from the plane along the unit normal,
    /// s = (p − point_m)·n̂ with n̂ = normal/|normal|: s ≤ 0 on the kept side. The sum runs over
    /// the plane's own components (`dim` of them after validation).
    pub fn signed_distance(&self, p: &[f64]) -> f64 {
        let len = self.normal.iter().map(|c| c * c).sum::<f64>().sqrt();
        self.point_m.iter().zip(&self.normal).zip(p).map(|((q, n), x)| (x - q) * (n / len)).sum()
    }

    /// Is `p` on the kept side, s ≤ 0 ([`ClipPlane::signed_distance`])?
    pub fn keeps(&self, p: &[f64]) -> bool {
        self.signed_distance(p) <= 0.0
    }
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
    /// A viscous boundary of the Lysmer–Kuhlemeyer kind: no virtual particles; the particles
    /// within `boundary.absorb_layer_m` of it feel dashpot tractions ρ c_p v_n and ρ c_s v_t
    /// against their motion, and the traction of their initial stress (docs/theory.md,
    /// "Absorbing walls").
    Absorbing,
}

impl WallKind {
    /// Does the wall make type II mirror particles?
    pub fn mirrors(self) -> bool {
        matches!(self, WallKind::Mirror | WallKind::Both)
    }
    /// Does the wall push with the type I force?
    pub fn repels(self) -> bool {
        matches!(self, WallKind::Repulsive | WallKind::Both)
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallCfg {
    /// Start point (m).
    pub from_m: Vec<f64>,
    /// End point (m); equal to from_m in 1D; in 3D the corner opposite `from_m`.
    pub to_m: Vec<f64>,
    /// 3D: the corner next to `from_m` along the wall's first edge (a parallelogram from_m,
    /// edge_m, to_m, from_m + to_m − edge_m); absent = an axis-aligned rectangle.
    pub edge_m: Option<Vec<f64>>,
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
    #[serde(default = "default_width_h")]
    pub width_h: f64,
    /// Beta burn (Wilkins): an explosive compressed towards its CJ density burns too, and never
    /// un-burns: λ = max(λ_previous, λ_programmed, (1 − ρ0/ρ)/(1 − ρ0/ρ_CJ)), ρ_CJ from the CJ
    /// state of its JWL (theory.md §9).
    #[serde(default = "yes")]
    pub beta_burn: bool,
    /// The lighting front runs at this fraction of D: t_i = |x_i − x_det|/(s D) (theory.md §9).
    #[serde(default = "default_lighting")]
    pub lighting_speed_factor: f64,
    /// Lit along the plane through `point_m` with this normal: t_i = |(x_i − x_det)·n̂|/(s D).
    pub plane_normal: Option<Vec<f64>>,
}

fn default_width_h() -> f64 {
    2.0
}
fn default_lighting() -> f64 {
    0.95
}

/// What a gauge follows (docs/reference/cases.md `[[gauge]]`).
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
    /// Sedov–Taylor point blast: shock radius, peak density, profiles against the similarity
    /// solution (`src/analysis/sedov.rs`).
    Sedov,
    /// Noh implosion: shock radius, post-shock state, wall heating at the centre.
    Noh,
    /// A 1D shock reflected from a rigid wall: the reflected state and the wall heating.
    Reflection,
    /// A programmed-burn detonation: front pressure against p_CJ, plateau, Taylor wave.
    Detonation,
}

impl AnalysisKind {
    /// The name as written in a case file.
    pub fn name(self) -> &'static str {
        match self {
            AnalysisKind::None => "none",
            AnalysisKind::Riemann => "riemann",
            AnalysisKind::Crater => "crater",
            AnalysisKind::Sedov => "sedov",
            AnalysisKind::Noh => "noh",
            AnalysisKind::Reflection => "reflection",
            AnalysisKind::Detonation => "detonation",
        }
    }
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
    /// Crater: the window of the report's particle maps, [x_lo, x_hi, y_lo, y_hi] (m; r and z in
    /// RZ, x and z of the vertical section in 3D); default the scene at t = 0 with room above.
    pub view_m: Option<Vec<f64>>,
    /// Crater: the materials that count as soil (default: every material with strength).
    pub soil_materials: Option<Vec<String>>,
    /// Thesis values to report beside ours: final crater diameter and depth (m).
    pub thesis_crater_m: Option<Vec<f64>>,
    /// Thesis crater growth: [time (s), diameter (m), depth (m)] rows.
    pub thesis_crater_history: Option<Vec<Vec<f64>>>,
    /// Thesis gauge readings to report beside ours.
    #[serde(default)]
    pub thesis_gauge: Vec<ThesisGauge>,
    /// Sedov, Noh: the centre of the blast or the implosion (m); default the origin.
    pub center_m: Option<Vec<f64>>,
    /// Sedov: the energy released (J in 3D, J/m in 2D, J/m² in 1D); default the initial internal
    /// energy of every particle above that of the ambient gas (the region with most particles).
    pub energy_j: Option<f64>,
}

/// One gauge reading reported by the thesis (docs/validation.md, "Thesis scenes").
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThesisGauge {
    /// Gauge name (as in `[[gauge]]`).
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
