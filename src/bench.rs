//! `blastsph bench`: speed against error.
//!
//! Runs a matrix of cases × resolutions × backends × neighbour searches × kernels, and for every
//! run records its cost (wall time, particle-steps per second, per thread) beside its error:
//!
//! - a Riemann case (the shock tube): the L1 errors of ρ, v, p, e against the exact solution over
//!   the case's window ([`crate::report::l1_errors`] on the last output);
//! - a blast case: crater diameter and depth and the peak pressure at each gauge, as relative
//!   errors against the finest run of the same configuration (case, backend, search, kernel), and
//!   as relative differences from the thesis's numbers in the case (`[analysis]`).
//!
//! It writes `bench.csv` (one row per run), `bench.json` (the rows, the reference of every
//! configuration and how converged it is, the observed orders of convergence), `bench.md` (the
//! tables it prints) and log–log plots of error against wall time (`error_vs_time*.png`), one
//! curve per configuration across the resolutions, so that the Pareto front shows.
//!
//! Resolutions are refinement factors k: every spacing Δx becomes Δx/k ([`refine`]).

use crate::case::{self, AnalysisKind, Case, KernelKind, NnpsKind, Shape, StepRule};
use crate::error::{Result, SphError, input};
use crate::modules::Backend;
use crate::output::read_frames;
use crate::plot;
use crate::report::{L1, l1_errors, riemann_of};
use crate::runner::{self, RunOptions};
use crate::sim::Overrides;
use serde::Serialize;
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The flags of `blastsph bench`, as typed (checked by [`BenchOptions::from_args`], so that a
/// bad value gets one line and exit status 2).
#[derive(clap::Args, Debug, Clone)]
pub struct BenchArgs {
    /// Cases: names in the case folder, or paths to .toml files (comma-separated)
    #[arg(long, value_delimiter = ',', default_value = "shock_tube", value_name = "NAME,..")]
    pub cases: Vec<String>,
    /// Folder of the case files (default: cases/ of the repository around the current directory, else of the source tree)
    #[arg(long = "case-dir", value_name = "DIR")]
    pub case_dir: Option<PathBuf>,
    /// Refinement factors k: every spacing Δx becomes Δx/k (0.5 = twice as coarse)
    #[arg(long, value_delimiter = ',', default_value = "1,2,4", value_name = "K,..", allow_hyphen_values = true)]
    pub resolutions: Vec<String>,
    /// Backends: every module in Rust, or every module in Fortran
    #[arg(long, value_delimiter = ',', default_value = "rust,fortran", value_name = "rust|fortran,..")]
    pub backends: Vec<String>,
    /// Neighbour searches
    #[arg(long, value_delimiter = ',', default_value = "cell", value_name = "cell|direct,..")]
    pub nnps: Vec<String>,
    /// Kernels
    #[arg(long, value_delimiter = ',', default_value = "cubic", value_name = "cubic|gauss|quintic|wendland,..")]
    pub kernels: Vec<String>,
    /// Worker threads of the Rust modules (the Fortran core is serial)
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub threads: Option<String>,
    /// Stop every run at this time (s) instead of the case's end time
    #[arg(long = "end-time", value_name = "SECONDS", allow_hyphen_values = true)]
    pub end_time: Option<String>,
    /// Where the runs, bench.csv, bench.json and the plots go
    #[arg(long, default_value = "runs/bench", value_name = "DIR")]
    pub out: PathBuf,
    /// Skip direct-search runs with more particles than this (reported as skipped)
    #[arg(long = "max-direct-particles", default_value = "20000", value_name = "N", allow_hyphen_values = true)]
    pub max_direct_particles: String,
    /// Runs of each configuration; the row reports the fastest (the physics of the repeats is
    /// bitwise the same) and lists every wall time. For timings on a machine shared with other work.
    #[arg(long, default_value = "1", value_name = "N", allow_hyphen_values = true)]
    pub repeat: String,
    /// List the matrix (with particle counts) and run nothing
    #[arg(long = "dry-run")]
    pub dry_run: bool,
    /// Override a key of every case before it is refined: --set 'analysis.window_m=[-0.35, 0.35]'
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
}

/// The bench's matrix and settings, checked.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    /// Case files, in the order given.
    pub cases: Vec<PathBuf>,
    /// Refinement factors, ascending.
    pub resolutions: Vec<f64>,
    pub backends: Vec<Backend>,
    pub nnps: Vec<NnpsKind>,
    pub kernels: Vec<KernelKind>,
    pub threads: Option<usize>,
    pub end_time: Option<f64>,
    pub out: PathBuf,
    pub max_direct_particles: usize,
    /// Runs of each configuration (the fastest is reported).
    pub repeat: usize,
    pub dry_run: bool,
    pub sets: Vec<String>,
}

fn nnps_name(n: NnpsKind) -> &'static str {
    match n {
        NnpsKind::Cell => "cell",
        NnpsKind::Direct => "direct",
    }
}

/// Parses a comma-separated flag: every item through `f`, none empty, none twice.
fn list<T: PartialEq>(flag: &str, items: &[String], f: impl Fn(&str) -> Option<T>, what: &str) -> Result<Vec<T>> {
    let mut out = Vec::new();
    for s in items {
        let s = s.trim();
        let v = f(s).ok_or_else(|| input(format!("--{flag} {s}: {what}")))?;
        if out.contains(&v) {
            return Err(input(format!("--{flag}: `{s}` is given twice")));
        }
        out.push(v);
    }
    if out.is_empty() {
        return Err(input(format!("--{flag}: give at least one value")));
    }
    Ok(out)
}

impl BenchOptions {
    /// Checks the flags; every error is one line naming the flag.
    pub fn from_args(a: &BenchArgs) -> Result<BenchOptions> {
        let resolutions = {
            let mut r = list(
                "resolutions",
                &a.resolutions,
                |s| s.parse::<f64>().ok().filter(|k| k.is_finite() && *k > 0.0),
                "a refinement factor must be a positive number (1 = the case as written, 2 = half the spacing)",
            )?;
            r.sort_by(|x, y| x.total_cmp(y));
            r
        };
        let backends = list("backends", &a.backends, Backend::parse, "must be rust or fortran")?;
        let nnps = list(
            "nnps",
            &a.nnps,
            |s| match s {
                "cell" => Some(NnpsKind::Cell),
                "direct" => Some(NnpsKind::Direct),
                _ => None,
            },
            "must be cell or direct",
        )?;
        let kernels = list(
            "kernels",
            &a.kernels,
            |s| match s {
                "cubic" => Some(KernelKind::Cubic),
                "gauss" => Some(KernelKind::Gauss),
                "quintic" => Some(KernelKind::Quintic),
                "wendland" => Some(KernelKind::Wendland),
                _ => None,
            },
            "must be cubic, gauss, quintic or wendland",
        )?;
        let threads = match &a.threads {
            None => None,
            Some(s) => Some(
                s.trim()
                    .parse::<usize>()
                    .ok()
                    .filter(|n| *n > 0)
                    .ok_or_else(|| input(format!("--threads {s}: need a whole number of threads, at least 1")))?,
            ),
        };
        let end_time = match &a.end_time {
            None => None,
            Some(s) => Some(
                s.trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|t| t.is_finite() && *t > 0.0)
                    .ok_or_else(|| input(format!("--end-time {s}: must be a positive time in seconds")))?,
            ),
        };
        let max_direct_particles = a.max_direct_particles.trim().parse::<usize>().map_err(|_| {
            input(format!("--max-direct-particles {}: need a whole number of particles", a.max_direct_particles))
        })?;
        let repeat = a
            .repeat
            .trim()
            .parse::<usize>()
            .ok()
            .filter(|&r| (1..=100).contains(&r))
            .ok_or_else(|| input(format!("--repeat {}: need a whole number of runs from 1 to 100", a.repeat)))?;
        let mut cases = Vec::new();
        for c in &a.cases {
            let c = c.trim();
            if c.is_empty() {
                return Err(input("--cases: an empty case name"));
            }
            let path = if c.ends_with(".toml") || c.contains('/') {
                PathBuf::from(c)
            } else {
                crate::casedir::folder(a.case_dir.as_deref())?.join(format!("{c}.toml"))
            };
            if !path.is_file() {
                return Err(input(format!("--cases {c}: no case file {}", path.display())));
            }
            if cases.contains(&path) {
                return Err(input(format!("--cases: `{c}` is given twice")));
            }
            cases.push(path);
        }
        if cases.is_empty() {
            return Err(input("--cases: give at least one case"));
        }
        Ok(BenchOptions {
            cases,
            resolutions,
            backends,
            nnps,
            kernels,
            threads,
            end_time,
            out: a.out.clone(),
            max_direct_particles,
            repeat,
            dry_run: a.dry_run,
            sets: a.sets.clone(),
        })
    }
}

// ---------------------------------------------------------------------------------------------
// Refinement
// ---------------------------------------------------------------------------------------------

/// A float as TOML text that reads back to the same f64 (Debug prints the shortest round-trip
/// form, always with a `.` or an exponent, so TOML reads a float, never an integer).
fn num(x: f64) -> String {
    format!("{x:?}")
}

/// The `--set` overrides that refine `case` by the factor `k` (Δx → Δx/k):
///
/// - every region: `spacing_m` / k; `mass_kg` / k^dim and `h_m` / k where the region gives them
///   (otherwise their defaults ρΔx^d and h_over_dx·Δx follow the spacing by themselves);
/// - lattice regions: `count` × k per axis (it must come out whole) and the origin moved so that
///   the lattice covers the same cells. Lattice points are cell centres (the extent that
///   docs/cases.md gives a lattice), so origin' = origin − Δx/2 + Δx'/2 — except in a 1D Riemann
///   case (`analysis.kind = "riemann"`), where each point is taken at the end of its cell away
///   from the diaphragm x0: origin' = origin left of x0, origin − Δx + Δx' right of it. That
///   is the book's shock tube (its first particles one spacing from the diaphragm on either
///   side) at every resolution; read as cell centres, its two lattices leave a gap of fixed width
///   (−Δx_L/2 … Δx_R/2 = 4.7 mm) between the gases, which h/k soon fails to bridge (at k = 2 the
///   run blows up);
/// - box and polygon regions are cell-centred lattices of their shape: the shape stays, and a box
///   whose sides are whole multiples of Δx/k is filled exactly;
/// - `time.dt_s` / k for fixed steps, `time.dt_max_s` / k where given, and `time.max_steps` × k
///   (a safety limit, not a physical time) for k > 1;
/// - `boundary.wall_spacing_m` and `boundary.r0_m` / k where given (their defaults follow the
///   finest spacing by themselves);
/// - everything else stays: gauges, walls, charges, the detonation point, the analysis.
///
/// k = 1 gives no overrides. Regions are named by index, so any region name works.
pub fn refinement_sets(case: &Case, k: f64) -> Result<Vec<String>> {
    if !(k.is_finite() && k > 0.0) {
        return Err(input(format!("refinement factor {k}: must be a positive number")));
    }
    if k == 1.0 {
        return Ok(Vec::new());
    }
    let d = case.dim as i32;
    let mut s = Vec::new();
    for (i, r) in case.regions.iter().enumerate() {
        let sp = r.spacing_m / k;
        s.push(format!("region.{i}.spacing_m={}", num(sp)));
        if r.shape == Shape::Lattice {
            let mut counts = Vec::new();
            for &n in r.count.as_deref().unwrap_or(&[]) {
                let nk = n as f64 * k;
                if (nk - nk.round()).abs() > 1e-9 * nk.max(1.0) || nk.round() < 1.0 {
                    return Err(input(format!(
                        "region[{i}] ({}): count {n} × k = {k} is not a whole number of particles: choose another refinement",
                        r.name
                    )));
                }
                counts.push(format!("{}", nk.round() as u64));
            }
            let diaphragm = match (case.analysis.kind, case.analysis.diaphragm_m) {
                (AnalysisKind::Riemann, Some(x0)) if case.dim == 1 => Some(x0),
                _ => None,
            };
            let origin: Vec<String> = r
                .origin_m
                .as_deref()
                .unwrap_or(&[])
                .iter()
                .map(|&o| {
                    num(match diaphragm {
                        // the point at the end of its cell away from the diaphragm
                        Some(x0) if o < x0 => o,
                        Some(_) => o - r.spacing_m + sp,
                        // the point at the centre of its cell
                        None => o - 0.5 * r.spacing_m + 0.5 * sp,
                    })
                })
                .collect();
            s.push(format!("region.{i}.count=[{}]", counts.join(", ")));
            s.push(format!("region.{i}.origin_m=[{}]", origin.join(", ")));
        }
        if let Some(m) = r.mass_kg {
            s.push(format!("region.{i}.mass_kg={}", num(m / k.powi(d))));
        }
        if let Some(h) = r.h_m {
            s.push(format!("region.{i}.h_m={}", num(h / k)));
        }
    }
    let t = &case.time;
    if t.step == StepRule::Fixed
        && let Some(dt) = t.dt_s
    {
        s.push(format!("time.dt_s={}", num(dt / k)));
    }
    if let Some(m) = t.dt_max_s {
        s.push(format!("time.dt_max_s={}", num(m / k)));
    }
    if k > 1.0 {
        let ms = (t.max_steps as f64 * k).ceil().min(i64::MAX as f64) as i64;
        s.push(format!("time.max_steps={ms}"));
    }
    if let Some(w) = case.boundary.wall_spacing_m {
        s.push(format!("boundary.wall_spacing_m={}", num(w / k)));
    }
    if let Some(r0) = case.boundary.r0_m {
        s.push(format!("boundary.r0_m={}", num(r0 / k)));
    }
    Ok(s)
}

/// The case in `text` (after the `sets` overrides) refined by `k`, with every override that made
/// it (`sets` first, then those of [`refinement_sets`]): handing these to `blastsph run --set`
/// (or [`RunOptions::sets`]) gives the same case, and summary.json records them.
pub fn refine(text: &str, origin: &str, stem: Option<&str>, sets: &[String], k: f64) -> Result<(Case, Vec<String>)> {
    let base = case::parse(text, origin, sets, stem)?;
    let mut all = sets.to_vec();
    all.extend(refinement_sets(&base, k)?);
    let refined = case::parse(text, origin, &all, stem)?;
    Ok((refined, all))
}

// ---------------------------------------------------------------------------------------------
// The matrix
// ---------------------------------------------------------------------------------------------

/// One case of the bench, read once.
struct CaseFile {
    name: String,
    path: PathBuf,
    text: String,
    base: Case,
    /// Particles per region of the unrefined case.
    base_counts: Vec<usize>,
}

/// One cell of the matrix.
#[derive(Debug, Clone)]
pub struct Planned {
    pub case: String,
    ci: usize,
    pub k: f64,
    pub backend: Backend,
    pub nnps: NnpsKind,
    pub kernel: KernelKind,
    /// The refined case (with the kernel and the bench's settings applied).
    pub refined: Case,
    /// Finest initial spacing of the refined case (m).
    pub dx_m: f64,
    pub particles: usize,
    /// Particles of the unrefined case × k^dim.
    pub particles_expected: f64,
    /// Every region holds exactly its unrefined count × k^dim.
    pub count_exact: bool,
    pub sets: Vec<String>,
    pub dir: PathBuf,
    /// Why the run is skipped.
    pub skip: Option<String>,
}

fn k_tag(k: f64) -> String {
    format!("{k}")
}

fn family_label(backend: &str, nnps: &str, kernel: &str) -> String {
    format!("{backend}/{nnps}/{kernel}")
}

fn read_cases(o: &BenchOptions) -> Result<Vec<CaseFile>> {
    let mut out: Vec<CaseFile> = Vec::new();
    for path in &o.cases {
        let text = std::fs::read_to_string(path)
            .map_err(|e| input(format!("{}: cannot read the case file: {e}", path.display())))?;
        let origin = path.display().to_string();
        let stem = path.file_stem().and_then(|s| s.to_str());
        let base = case::parse(&text, &origin, &o.sets, stem)?;
        let name = base.name().to_string();
        if out.iter().any(|c| c.name == name) {
            return Err(input(format!("--cases: two cases are named `{name}`")));
        }
        let base_counts = crate::setup::particles(&base)?.counts;
        out.push(CaseFile { name, path: path.clone(), text, base, base_counts });
    }
    Ok(out)
}

/// The matrix in run order: case, kernel, search, backend, then the resolutions from coarse to
/// fine. Every refined case is parsed, validated and its particles generated (so a refinement
/// that does not work stops the bench before anything runs).
fn plan(o: &BenchOptions, cases: &[CaseFile]) -> Result<(Vec<Planned>, Vec<String>)> {
    let mut cells = Vec::new();
    let mut warnings = Vec::new();
    for (ci, cf) in cases.iter().enumerate() {
        let origin = cf.path.display().to_string();
        let stem = cf.path.file_stem().and_then(|s| s.to_str());
        let nbase: usize = cf.base_counts.iter().sum();
        let dim = cf.base.dim as i32;
        for &kernel in &o.kernels {
            let mut head = o.sets.clone();
            head.push(format!("sph.kernel={}", kernel.name()));
            // only the first and the last step go to particles.h5: a bench times the solver
            head.push("time.output_interval_s=0.0".to_string());
            let mut per_k = Vec::new();
            for &k in &o.resolutions {
                let (refined, sets) = refine(&cf.text, &origin, stem, &head, k)
                    .map_err(|e| input(format!("{} refined by k = {k}: {e}", cf.name)))?;
                let init = crate::setup::particles(&refined)
                    .map_err(|e| input(format!("{} refined by k = {k}: {e}", cf.name)))?;
                let kd = k.powi(dim);
                let exact =
                    init.counts.iter().zip(&cf.base_counts).all(|(n, b)| (*n as f64 - *b as f64 * kd).abs() < 1e-6);
                let particles: usize = init.counts.iter().sum();
                if !exact && kernel == o.kernels[0] {
                    let detail: Vec<String> = refined
                        .regions
                        .iter()
                        .zip(init.counts.iter().zip(&cf.base_counts))
                        .filter(|(_, (n, b))| (**n as f64 - **b as f64 * kd).abs() >= 1e-6)
                        .map(|(r, (n, b))| {
                            format!(
                                "{} {n} (expected {}{})",
                                r.name,
                                *b as f64 * kd,
                                match r.shape {
                                    Shape::Polygon => ", a polygon: its edge cuts the refined lattice elsewhere",
                                    _ => "",
                                }
                            )
                        })
                        .collect();
                    warnings.push(format!(
                        "{} k = {k}: {particles} particles, not {} × k^{dim} = {}: {}",
                        cf.name,
                        nbase,
                        nbase as f64 * kd,
                        detail.join("; ")
                    ));
                }
                per_k.push((k, refined, sets, init.dx_min, particles, nbase as f64 * kd, exact));
            }
            for &nnps in &o.nnps {
                for &backend in &o.backends {
                    for (k, refined, sets, dx, particles, expected, exact) in &per_k {
                        let skip = (nnps == NnpsKind::Direct && *particles > o.max_direct_particles).then(|| {
                            format!(
                                "direct search with {particles} particles (more than --max-direct-particles {})",
                                o.max_direct_particles
                            )
                        });
                        let dir = o.out.join(&cf.name).join(format!(
                            "k{}_{}_{}_{}",
                            k_tag(*k),
                            backend.name(),
                            nnps_name(nnps),
                            kernel.name()
                        ));
                        cells.push(Planned {
                            case: cf.name.clone(),
                            ci,
                            k: *k,
                            backend,
                            nnps,
                            kernel,
                            refined: refined.clone(),
                            dx_m: *dx,
                            particles: *particles,
                            particles_expected: *expected,
                            count_exact: *exact,
                            sets: sets.clone(),
                            dir,
                            skip,
                        });
                    }
                }
            }
        }
    }
    Ok((cells, warnings))
}

// ---------------------------------------------------------------------------------------------
// Runs and their measurements
// ---------------------------------------------------------------------------------------------

/// A gauge's peak as a run measured it.
#[derive(Debug, Clone, Serialize)]
pub struct GaugePeak {
    pub name: String,
    pub peak_pa: f64,
    pub peak_time_s: f64,
}

/// One run of the matrix: what it cost and what it measured.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    pub case: String,
    /// "riemann", "crater" or "none" (the case's `analysis.kind`).
    pub analysis: String,
    pub k: f64,
    pub dx_m: f64,
    pub particles: usize,
    pub particles_expected: f64,
    pub count_exact: bool,
    pub backend: String,
    pub nnps: String,
    pub kernel: String,
    /// Threads the run computes on: the Rust worker pool, 1 for the (serial) Fortran core.
    pub threads: usize,
    /// The Rust worker pool of the process.
    pub pool_threads: usize,
    pub end_time_s: f64,
    pub steps: Option<u64>,
    pub wall_s: Option<f64>,
    /// The wall time of every run of this configuration (`--repeat`), in the order run;
    /// `wall_s` and the rates are those of the fastest.
    pub wall_s_runs: Vec<f64>,
    pub particle_steps_per_s: Option<f64>,
    pub particle_steps_per_s_per_thread: Option<f64>,
    /// CPU seconds (user + system, every thread) the process spent on the run, set-up and
    /// output included (Linux: /proc/self/stat); less sensitive than wall time to other work
    /// on the machine.
    pub cpu_s: Option<f64>,
    /// The machine's 1-minute load average when the run started (Linux: /proc/loadavg): above
    /// the number of threads the run uses, something else was competing for the cores.
    pub load_avg: Option<f64>,
    /// "ok", "unstable" or "skipped".
    pub status: String,
    /// The diagnostic of an unstable run, or why a run was skipped.
    pub note: Option<String>,
    /// Energy balance residual over the run, relative to the initial total (summary.json): a
    /// run that finished but blew up shows here.
    pub energy_residual_rel: Option<f64>,
    pub dir: String,
    /// Riemann: the window of the L1 errors (m) and the errors against the exact solution.
    pub window_m: Option<[f64; 2]>,
    pub l1: Option<L1>,
    /// Blast: the crater at the end of the run (m) and the gauge peaks.
    pub crater_diameter_m: Option<f64>,
    pub crater_depth_m: Option<f64>,
    pub gauges: Vec<GaugePeak>,
    /// Wall seconds per module (summary.json `module_seconds`).
    pub module_seconds: Value,
    /// The k of this configuration's reference run (its finest run that finished).
    pub reference_k: Option<f64>,
    /// |q − q_ref| / |q_ref| per blast quantity (absent for the reference run itself).
    pub err_ref: BTreeMap<String, f64>,
    /// (q − q_thesis) / q_thesis per quantity the case gives a thesis value for.
    pub vs_thesis: BTreeMap<String, f64>,
    /// On the case's Pareto front of (wall time, primary error).
    pub pareto: Option<bool>,
}

impl Row {
    fn family(&self) -> (String, String, String, String) {
        (self.case.clone(), self.backend.clone(), self.nnps.clone(), self.kernel.clone())
    }
    fn label(&self) -> String {
        family_label(&self.backend, &self.nnps, &self.kernel)
    }
    fn ok(&self) -> bool {
        self.status == "ok"
    }
    /// The measured quantities q of the run, by name.
    fn quantities(&self) -> Vec<(String, f64)> {
        let mut q = Vec::new();
        if let Some(l) = &self.l1 {
            q.extend([("l1_rho", l.rho), ("l1_v", l.v), ("l1_p", l.p), ("l1_e", l.e)].map(|(n, v)| (n.to_string(), v)));
        }
        if let Some(d) = self.crater_diameter_m {
            q.push(("crater_diameter".into(), d));
        }
        if let Some(z) = self.crater_depth_m {
            q.push(("crater_depth".into(), z));
        }
        for g in &self.gauges {
            q.push((format!("peak_{}", g.name), g.peak_pa));
        }
        q
    }
    fn quantity(&self, name: &str) -> Option<f64> {
        self.quantities().into_iter().find(|(n, _)| n == name).map(|(_, v)| v)
    }
    /// The error the Pareto front and the summary plot use: L1 of ρ against the exact solution
    /// (Riemann), the crater depth against the reference (blast).
    fn primary(&self) -> Option<f64> {
        match self.analysis.as_str() {
            "riemann" => self.l1.map(|l| l.rho),
            "crater" => self.err_ref.get("crater_depth").copied(),
            _ => None,
        }
    }
}

fn primary_name(analysis: &str) -> &'static str {
    match analysis {
        "riemann" => "L1 error of rho against the exact solution",
        "crater" => "crater depth: relative error against the finest run",
        _ => "(no error measure)",
    }
}

fn analysis_name(k: AnalysisKind) -> &'static str {
    match k {
        AnalysisKind::Riemann => "riemann",
        AnalysisKind::Crater => "crater",
        AnalysisKind::None => "none",
    }
}

/// CPU time of this process so far (s): utime + stime of /proc/self/stat, in clock ticks of
/// USER_HZ = 100 per second (fixed for /proc on Linux). None where there is no /proc.
fn cpu_seconds() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/stat").ok()?;
    // the command name (field 2) is in parentheses and may hold spaces: count from after it
    let rest = &s[s.rfind(')')? + 1..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    // fields 14 and 15 of the line are the 12th and 13th after the name
    let (u, k): (f64, f64) = (f.get(11)?.parse().ok()?, f.get(12)?.parse().ok()?);
    Some((u + k) / 100.0)
}

/// The 1-minute load average (Linux: /proc/loadavg).
fn load_avg() -> Option<f64> {
    std::fs::read_to_string("/proc/loadavg").ok()?.split_whitespace().next()?.parse().ok()
}

fn run_one(p: &Planned, cf: &CaseFile, o: &BenchOptions) -> Result<Row> {
    let pool = rayon::current_num_threads();
    let mut row = Row {
        case: p.case.clone(),
        analysis: analysis_name(p.refined.analysis.kind).into(),
        k: p.k,
        dx_m: p.dx_m,
        particles: p.particles,
        particles_expected: p.particles_expected,
        count_exact: p.count_exact,
        backend: p.backend.name().into(),
        nnps: nnps_name(p.nnps).into(),
        kernel: p.kernel.name().into(),
        threads: if p.backend == Backend::Fortran { 1 } else { pool },
        pool_threads: pool,
        end_time_s: o.end_time.unwrap_or(p.refined.time.end_s),
        steps: None,
        wall_s: None,
        wall_s_runs: Vec::new(),
        particle_steps_per_s: None,
        particle_steps_per_s_per_thread: None,
        cpu_s: None,
        load_avg: None,
        status: "skipped".into(),
        note: p.skip.clone(),
        energy_residual_rel: None,
        dir: p.dir.display().to_string(),
        window_m: None,
        l1: None,
        crater_diameter_m: None,
        crater_depth_m: None,
        gauges: Vec::new(),
        module_seconds: Value::Null,
        reference_k: None,
        err_ref: BTreeMap::new(),
        vs_thesis: BTreeMap::new(),
        pareto: None,
    };
    if p.skip.is_some() {
        return Ok(row);
    }
    let opts = RunOptions {
        out: Some(p.dir.clone()),
        sets: p.sets.clone(),
        ov: Overrides {
            backend: Some(p.backend),
            nnps: Some(nnps_name(p.nnps).to_string()),
            end_time: o.end_time,
            ..Default::default()
        },
        quiet: true,
        threads: o.threads,
    };
    row.load_avg = load_avg();
    let cpu0 = cpu_seconds();
    let result = runner::run(&cf.path, &opts);
    row.cpu_s = cpu_seconds().zip(cpu0).map(|(b, a)| b - a);
    let summary = match result {
        Ok(r) => r.summary,
        Err(SphError::Unstable(msg)) => {
            row.note = Some(msg);
            let s = std::fs::read_to_string(p.dir.join("summary.json")).unwrap_or_default();
            serde_json::from_str(&s).unwrap_or(Value::Null)
        }
        Err(e) => return Err(e),
    };
    row.status = summary["status"].as_str().unwrap_or("unstable").to_string();
    row.steps = summary["steps"].as_u64();
    row.wall_s = summary["wall_seconds"].as_f64();
    row.particle_steps_per_s = summary["particle_steps_per_second"].as_f64();
    row.particle_steps_per_s_per_thread = row.particle_steps_per_s.map(|r| r / row.threads as f64);
    row.module_seconds = summary["module_seconds"].clone();
    row.energy_residual_rel = summary["energy"]["balance_residual_relative"].as_f64();
    if !row.ok() {
        return Ok(row);
    }
    match p.refined.analysis.kind {
        AnalysisKind::Riemann => {
            let frames = read_frames(&p.dir.join("particles.h5"))?;
            let last = frames.last().ok_or_else(|| SphError::Io(format!("{}: no step written", row.dir)))?;
            let (rs, x0) = riemann_of(&p.refined)?;
            let w = p.refined.analysis.window_m.clone().unwrap_or(vec![f64::NEG_INFINITY, f64::INFINITY]);
            row.window_m = Some([w[0], w[1]]);
            row.l1 = Some(l1_errors(last, &rs, x0, (w[0], w[1])));
        }
        AnalysisKind::Crater => {
            row.crater_diameter_m = summary["crater"]["diameter_m"].as_f64();
            row.crater_depth_m = summary["crater"]["depth_m"].as_f64();
            for g in summary["gauges"].as_array().cloned().unwrap_or_default() {
                row.gauges.push(GaugePeak {
                    name: g["name"].as_str().unwrap_or("?").to_string(),
                    peak_pa: g["peak_pa"].as_f64().unwrap_or(f64::NAN),
                    peak_time_s: g["peak_time_s"].as_f64().unwrap_or(f64::NAN),
                });
            }
            let an = &cf.base.analysis;
            if let Some(t) = an.thesis_crater_m.as_ref().filter(|t| t.len() == 2) {
                for (q, ours, th) in
                    [("crater_diameter", row.crater_diameter_m, t[0]), ("crater_depth", row.crater_depth_m, t[1])]
                {
                    if let Some(v) = ours {
                        row.vs_thesis.insert(q.into(), (v - th) / th);
                    }
                }
            }
            for tg in &an.thesis_gauge {
                if let Some(g) = row.gauges.iter().find(|g| g.name == tg.gauge) {
                    if let Some(pk) = tg.peak_pa {
                        row.vs_thesis.insert(format!("peak_{}", g.name), (g.peak_pa - pk) / pk);
                    }
                    if let Some(tt) = tg.peak_time_s {
                        row.vs_thesis.insert(format!("peak_time_{}", g.name), (g.peak_time_s - tt) / tt);
                    }
                }
            }
        }
        AnalysisKind::None => {}
    }
    Ok(row)
}

// ---------------------------------------------------------------------------------------------
// Convergence
// ---------------------------------------------------------------------------------------------

/// An observed order of convergence from the runs at `ks`.
#[derive(Debug, Clone, Serialize)]
pub struct Order {
    pub ks: Vec<f64>,
    /// None where it is undefined (a difference or an error of zero, or not finite).
    pub p: Option<f64>,
}

/// One configuration (case, backend, search, kernel) across its resolutions.
#[derive(Debug, Clone, Serialize)]
pub struct Family {
    pub case: String,
    /// The case's analysis: "riemann" (errors against the exact solution), "crater" (against
    /// the reference run), "none".
    pub analysis: String,
    pub backend: String,
    pub nnps: String,
    pub kernel: String,
    /// Resolutions that finished.
    pub ks: Vec<f64>,
    /// Blast: the reference, the finest run that finished (a Riemann case's reference is the
    /// exact solution).
    pub reference_k: Option<f64>,
    /// The second finest run that finished.
    pub second_k: Option<f64>,
    /// How converged the reference is: |q_finest − q_second| / |q_finest| per quantity.
    pub reference_change: BTreeMap<String, f64>,
    /// Observed order from three resolutions k, rk, r²k without a reference:
    /// p = ln(|q_k − q_rk| / |q_rk − q_r²k|) / ln r (r = 2: log2).
    pub self_orders: BTreeMap<String, Vec<Order>>,
    /// Riemann: observed order from the exact errors of two resolutions, p = ln(E_k / E_rk) / ln r.
    pub exact_orders: BTreeMap<String, Vec<Order>>,
}

fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// Observed order from three values at resolutions in a constant ratio r.
pub fn self_order(q: [f64; 3], r: f64) -> Option<f64> {
    let (a, b) = ((q[0] - q[1]).abs(), (q[1] - q[2]).abs());
    if a > 0.0 && b > 0.0 && r > 1.0 { finite((a / b).ln() / r.ln()) } else { None }
}

/// Observed order from the errors at two resolutions in the ratio r.
pub fn exact_order(e: [f64; 2], r: f64) -> Option<f64> {
    if e[0] > 0.0 && e[1] > 0.0 && r > 1.0 { finite((e[0] / e[1]).ln() / r.ln()) } else { None }
}

/// Groups the rows into configurations, fills each row's reference errors, and returns the
/// configurations with their references and orders.
fn analyse(rows: &mut [Row]) -> Vec<Family> {
    let mut keys: Vec<(String, String, String, String)> = Vec::new();
    for r in rows.iter() {
        if !keys.contains(&r.family()) {
            keys.push(r.family());
        }
    }
    let mut fams = Vec::new();
    for key in keys {
        let idx: Vec<usize> = (0..rows.len()).filter(|&i| rows[i].family() == key && rows[i].ok()).collect();
        let mut idx = idx;
        idx.sort_by(|&a, &b| rows[a].k.total_cmp(&rows[b].k));
        let ks: Vec<f64> = idx.iter().map(|&i| rows[i].k).collect();
        let crater = idx.first().is_some_and(|&i| rows[i].analysis == "crater");
        let mut fam = Family {
            case: key.0.clone(),
            analysis: idx.first().map_or(String::new(), |&i| rows[i].analysis.clone()),
            backend: key.1.clone(),
            nnps: key.2.clone(),
            kernel: key.3.clone(),
            ks: ks.clone(),
            reference_k: if crater { ks.last().copied() } else { None },
            second_k: if crater && ks.len() >= 2 { Some(ks[ks.len() - 2]) } else { None },
            reference_change: BTreeMap::new(),
            self_orders: BTreeMap::new(),
            exact_orders: BTreeMap::new(),
        };
        let names: Vec<String> =
            idx.last().map(|&i| rows[i].quantities().into_iter().map(|q| q.0).collect()).unwrap_or_default();
        if let Some(&iref) = idx.last().filter(|_| crater) {
            let refrow = rows[iref].clone();
            for &i in &idx {
                rows[i].reference_k = Some(refrow.k);
                if i == iref {
                    continue;
                }
                for (q, v) in rows[i].quantities() {
                    if let Some(r) = refrow.quantity(&q)
                        && r != 0.0
                        && let Some(e) = finite((v - r).abs() / r.abs())
                    {
                        rows[i].err_ref.insert(q, e);
                    }
                }
            }
            if idx.len() >= 2 {
                let sec = &rows[idx[idx.len() - 2]];
                for q in &names {
                    if let (Some(a), Some(b)) = (refrow.quantity(q), sec.quantity(q))
                        && a != 0.0
                        && let Some(c) = finite((a - b).abs() / a.abs())
                    {
                        fam.reference_change.insert(q.clone(), c);
                    }
                }
            }
        }
        for q in &names {
            let vals: Vec<Option<f64>> = idx.iter().map(|&i| rows[i].quantity(q)).collect();
            let mut so = Vec::new();
            for w in 0..idx.len().saturating_sub(2) {
                let (k0, k1, k2) = (ks[w], ks[w + 1], ks[w + 2]);
                let r = k1 / k0;
                if ((k2 / k1) / r - 1.0).abs() > 1e-9 {
                    continue;
                }
                if let (Some(a), Some(b), Some(c)) = (vals[w], vals[w + 1], vals[w + 2]) {
                    so.push(Order { ks: vec![k0, k1, k2], p: self_order([a, b, c], r) });
                }
            }
            if !so.is_empty() {
                fam.self_orders.insert(q.clone(), so);
            }
            if q.starts_with("l1_") {
                let mut eo = Vec::new();
                for w in 0..idx.len().saturating_sub(1) {
                    if let (Some(a), Some(b)) = (vals[w], vals[w + 1]) {
                        eo.push(Order { ks: vec![ks[w], ks[w + 1]], p: exact_order([a, b], ks[w + 1] / ks[w]) });
                    }
                }
                if !eo.is_empty() {
                    fam.exact_orders.insert(q.clone(), eo);
                }
            }
        }
        fams.push(fam);
    }
    // the Pareto front of each case: no other run is at least as fast and at least as accurate
    let cases: Vec<String> = rows.iter().map(|r| r.case.clone()).fold(Vec::new(), |mut v, c| {
        if !v.contains(&c) {
            v.push(c);
        }
        v
    });
    for c in cases {
        let pts: Vec<(usize, f64, f64)> = rows
            .iter()
            .enumerate()
            .filter(|(_, r)| r.case == c && r.ok())
            .filter_map(|(i, r)| Some((i, r.wall_s?, r.primary().filter(|e| *e > 0.0)?)))
            .collect();
        for &(i, t, e) in &pts {
            let dominated = pts.iter().any(|&(j, t2, e2)| j != i && t2 <= t && e2 <= e && (t2 < t || e2 < e));
            rows[i].pareto = Some(!dominated);
        }
    }
    fams
}

// ---------------------------------------------------------------------------------------------
// Output
// ---------------------------------------------------------------------------------------------

/// What a bench returns: its rows, its configurations and the text it printed.
pub struct BenchOutput {
    pub rows: Vec<Row>,
    pub families: Vec<Family>,
    pub warnings: Vec<String>,
    /// The tables (Markdown), as printed and written to bench.md.
    pub text: String,
    /// Files written (bench.csv, bench.json, bench.md, plots).
    pub files: Vec<PathBuf>,
}

fn f(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x}"),
        _ => String::new(),
    }
}

fn e4(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x:.4e}"),
        _ => "-".into(),
    }
}

fn g2(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x:.2}"),
        _ => "-".into(),
    }
}

fn g3(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x:.3}"),
        _ => "-".into(),
    }
}

/// The fixed columns of bench.csv; gauge columns follow (`peak_<g>_pa`, `peak_<g>_err_ref`,
/// `peak_time_<g>_s`, and `peak_<g>_vs_thesis`, `peak_time_<g>_vs_thesis` where the thesis gives them).
pub const CSV_COLUMNS: [&str; 33] = [
    "case",
    "analysis",
    "k",
    "dx_m",
    "particles",
    "particles_expected",
    "count_exact",
    "backend",
    "nnps",
    "kernel",
    "threads",
    "end_time_s",
    "steps",
    "wall_s",
    "particle_steps_per_s",
    "particle_steps_per_s_per_thread",
    "cpu_s",
    "load_avg",
    "status",
    "energy_residual_rel",
    "reference_k",
    "pareto",
    "l1_rho",
    "l1_v",
    "l1_p",
    "l1_e",
    "crater_diameter_m",
    "crater_depth_m",
    "crater_diameter_err_ref",
    "crater_depth_err_ref",
    "crater_diameter_vs_thesis",
    "crater_depth_vs_thesis",
    "wall_s_runs",
];

fn csv(rows: &[Row]) -> String {
    let mut gauges: Vec<String> = Vec::new();
    for r in rows {
        for g in &r.gauges {
            if !gauges.contains(&g.name) {
                gauges.push(g.name.clone());
            }
        }
    }
    let thesis_peak = |g: &str| rows.iter().any(|r| r.vs_thesis.contains_key(&format!("peak_{g}")));
    let thesis_time = |g: &str| rows.iter().any(|r| r.vs_thesis.contains_key(&format!("peak_time_{g}")));
    let mut head: Vec<String> = CSV_COLUMNS.iter().map(|s| s.to_string()).collect();
    for g in &gauges {
        head.push(format!("peak_{g}_pa"));
        head.push(format!("peak_{g}_err_ref"));
        head.push(format!("peak_time_{g}_s"));
        if thesis_peak(g) {
            head.push(format!("peak_{g}_vs_thesis"));
        }
        if thesis_time(g) {
            head.push(format!("peak_time_{g}_vs_thesis"));
        }
    }
    let mut s = head.join(",") + "\n";
    for r in rows {
        let l1 = |g: fn(&L1) -> f64| f(r.l1.as_ref().map(g));
        let mut v: Vec<String> = vec![
            r.case.clone(),
            r.analysis.clone(),
            format!("{}", r.k),
            f(Some(r.dx_m)),
            r.particles.to_string(),
            f(Some(r.particles_expected)),
            r.count_exact.to_string(),
            r.backend.clone(),
            r.nnps.clone(),
            r.kernel.clone(),
            r.threads.to_string(),
            f(Some(r.end_time_s)),
            r.steps.map(|s| s.to_string()).unwrap_or_default(),
            f(r.wall_s),
            f(r.particle_steps_per_s),
            f(r.particle_steps_per_s_per_thread),
            f(r.cpu_s),
            f(r.load_avg),
            r.status.clone(),
            f(r.energy_residual_rel),
            f(r.reference_k),
            r.pareto.map(|p| p.to_string()).unwrap_or_default(),
            l1(|l| l.rho),
            l1(|l| l.v),
            l1(|l| l.p),
            l1(|l| l.e),
            f(r.crater_diameter_m),
            f(r.crater_depth_m),
            f(r.err_ref.get("crater_diameter").copied()),
            f(r.err_ref.get("crater_depth").copied()),
            f(r.vs_thesis.get("crater_diameter").copied()),
            f(r.vs_thesis.get("crater_depth").copied()),
            r.wall_s_runs.iter().map(|w| f(Some(*w))).collect::<Vec<_>>().join(" "),
        ];
        for g in &gauges {
            let gp = r.gauges.iter().find(|x| &x.name == g);
            v.push(f(gp.map(|x| x.peak_pa)));
            v.push(f(r.err_ref.get(&format!("peak_{g}")).copied()));
            v.push(f(gp.map(|x| x.peak_time_s)));
            if thesis_peak(g) {
                v.push(f(r.vs_thesis.get(&format!("peak_{g}")).copied()));
            }
            if thesis_time(g) {
                v.push(f(r.vs_thesis.get(&format!("peak_time_{g}")).copied()));
            }
        }
        s += &(v.join(",") + "\n");
    }
    s
}

fn ord(v: Option<&Vec<Order>>) -> String {
    match v {
        None => "-".into(),
        Some(list) => list
            .iter()
            .map(|o| {
                let ks: Vec<String> = o.ks.iter().map(|k| k_tag(*k)).collect();
                format!("{} ({})", o.p.map_or("undefined".into(), |p| format!("{p:.2}")), ks.join(","))
            })
            .collect::<Vec<_>>()
            .join("; "),
    }
}

fn quantity_title(q: &str) -> String {
    match q {
        "l1_rho" => "L1 rho (kg/m3)".into(),
        "l1_v" => "L1 v (m/s)".into(),
        "l1_p" => "L1 p (Pa)".into(),
        "l1_e" => "L1 e (J/kg)".into(),
        "crater_diameter" => "crater diameter".into(),
        "crater_depth" => "crater depth".into(),
        _ => match q.strip_prefix("peak_time_") {
            Some(g) => format!("peak time at gauge {g}"),
            None => match q.strip_prefix("peak_") {
                Some(g) => format!("peak pressure at gauge {g}"),
                None => q.into(),
            },
        },
    }
}

/// The tables: runs per case, gauges, references and orders, the Pareto front.
fn tables(rows: &[Row], fams: &[Family], warnings: &[String], meta: &Value) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "blastsph bench: {} runs, {} (commit {}), {} cores\n",
        rows.len(),
        meta["date_utc"].as_str().unwrap_or("?"),
        meta["commit"].as_str().unwrap_or("unknown"),
        meta["cores"]
    );
    let mut cases: Vec<&str> = Vec::new();
    for r in rows {
        if !cases.contains(&r.case.as_str()) {
            cases.push(&r.case);
        }
    }
    for c in &cases {
        let rs: Vec<&Row> = rows.iter().filter(|r| r.case == *c).collect();
        let an = rs[0].analysis.as_str();
        let _ = writeln!(s, "### {c}\n");
        match an {
            "riemann" => {
                let w = rs.iter().find_map(|r| r.window_m);
                let _ = writeln!(
                    s,
                    "L1 errors against the exact solution at the end time, over x in {}:\n",
                    w.map_or("-".into(), |w| format!("[{}, {}] m", w[0], w[1]))
                );
                let _ = writeln!(
                    s,
                    "| k | dx (m) | particles | backend | nnps | kernel | threads | steps | wall (s) | particle-steps/s | per thread | cpu (s) | load | L1 rho | L1 v | L1 p | L1 e | status |"
                );
                let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
                for r in &rs {
                    let l = r.l1;
                    let _ = writeln!(
                        s,
                        "| {} | {:.4e} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                        k_tag(r.k),
                        r.dx_m,
                        r.particles,
                        r.backend,
                        r.nnps,
                        r.kernel,
                        r.threads,
                        r.steps.map_or("-".into(), |x| x.to_string()),
                        wall(r.wall_s),
                        e3(r.particle_steps_per_s),
                        e3(r.particle_steps_per_s_per_thread),
                        wall(r.cpu_s),
                        g2(r.load_avg),
                        e4(l.map(|l| l.rho)),
                        e4(l.map(|l| l.v)),
                        e4(l.map(|l| l.p)),
                        e4(l.map(|l| l.e)),
                        status(r)
                    );
                }
            }
            _ => {
                let _ = writeln!(
                    s,
                    "Crater at the end time (cm); err = |q − q_ref| / |q_ref| against the finest run of the same configuration; thesis = (q − q_thesis) / q_thesis:\n"
                );
                let _ = writeln!(
                    s,
                    "| k | dx (m) | particles | backend | nnps | kernel | threads | end (s) | steps | wall (s) | particle-steps/s | per thread | cpu (s) | load | D | depth | D err | depth err | D thesis | depth thesis | status |"
                );
                let _ = writeln!(
                    s,
                    "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
                );
                for r in &rs {
                    let _ = writeln!(
                        s,
                        "| {} | {:.4e} | {} | {} | {} | {} | {} | {:e} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                        k_tag(r.k),
                        r.dx_m,
                        r.particles,
                        r.backend,
                        r.nnps,
                        r.kernel,
                        r.threads,
                        r.end_time_s,
                        r.steps.map_or("-".into(), |x| x.to_string()),
                        wall(r.wall_s),
                        e3(r.particle_steps_per_s),
                        e3(r.particle_steps_per_s_per_thread),
                        wall(r.cpu_s),
                        g2(r.load_avg),
                        cm(r.crater_diameter_m),
                        cm(r.crater_depth_m),
                        e3(r.err_ref.get("crater_diameter").copied()),
                        e3(r.err_ref.get("crater_depth").copied()),
                        g3(r.vs_thesis.get("crater_diameter").copied()),
                        g3(r.vs_thesis.get("crater_depth").copied()),
                        status(r)
                    );
                }
                let gnames: Vec<String> =
                    rs.iter().flat_map(|r| r.gauges.iter().map(|g| g.name.clone())).fold(Vec::new(), |mut v, g| {
                        if !v.contains(&g) {
                            v.push(g);
                        }
                        v
                    });
                if !gnames.is_empty() {
                    let _ = writeln!(
                        s,
                        "\nGauge peaks: MPa at µs (err against the reference; thesis = relative difference of the peak, or of its time where the thesis gives only the time):\n"
                    );
                    let _ = writeln!(s, "| k | configuration | {} |", gnames.join(" | "));
                    let _ = writeln!(s, "|---|---|{}", "---|".repeat(gnames.len()));
                    for r in rs.iter().filter(|r| r.ok()) {
                        let cells: Vec<String> = gnames
                            .iter()
                            .map(|g| match r.gauges.iter().find(|x| &x.name == g) {
                                None => "-".into(),
                                Some(x) => {
                                    let mut c = format!("{:.1} at {:.0}", x.peak_pa / 1e6, x.peak_time_s * 1e6);
                                    if let Some(e) = r.err_ref.get(&format!("peak_{g}")) {
                                        c += &format!(", err {e:.2e}");
                                    }
                                    if let Some(t) = r.vs_thesis.get(&format!("peak_{g}")) {
                                        c += &format!(", thesis {t:.2}");
                                    }
                                    if let Some(t) = r.vs_thesis.get(&format!("peak_time_{g}")) {
                                        c += &format!(", thesis time {t:.2}");
                                    }
                                    c
                                }
                            })
                            .collect();
                        let _ = writeln!(s, "| {} | {} | {} |", k_tag(r.k), r.label(), cells.join(" | "));
                    }
                }
            }
        }
        let _ = writeln!(s);
    }
    let _ = writeln!(
        s,
        "### References and observed orders\n\nReference of a blast = the finest run of each configuration that finished; change = |q_finest − q_second| / |q_finest| (how converged the reference is). The shock tube's reference is the exact solution. Self-convergence order p = ln(|q_k − q_rk| / |q_rk − q_r²k|) / ln r over three resolutions (r = 2: log2); for the shock tube also p = ln(E_k / E_rk) / ln r from the exact errors E. The resolutions used are in brackets.\n"
    );
    let _ = writeln!(
        s,
        "| case | configuration | reference k | second k | quantity | change | self-convergence p | p from exact errors |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    for fm in fams {
        let names: Vec<String> = {
            let mut n: Vec<String> = fm.reference_change.keys().cloned().collect();
            for k in fm.self_orders.keys().chain(fm.exact_orders.keys()) {
                if !n.contains(k) {
                    n.push(k.clone());
                }
            }
            n.sort_by_key(|q| quantity_rank(q));
            n
        };
        if names.is_empty() {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | - | - | - | - |",
                fm.case,
                family_label(&fm.backend, &fm.nnps, &fm.kernel),
                reference(fm),
                fm.second_k.map_or("-".into(), k_tag)
            );
        }
        for q in names {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} | {} |",
                fm.case,
                family_label(&fm.backend, &fm.nnps, &fm.kernel),
                reference(fm),
                fm.second_k.map_or("-".into(), k_tag),
                q,
                e3(fm.reference_change.get(&q).copied()),
                ord(fm.self_orders.get(&q)),
                ord(fm.exact_orders.get(&q))
            );
        }
    }
    let _ = writeln!(s, "\n### Pareto front (wall time against the primary error)\n");
    for c in &cases {
        let front: Vec<String> = rows
            .iter()
            .filter(|r| r.case == *c && r.pareto == Some(true))
            .map(|r| format!("k = {} {} ({} s, {})", k_tag(r.k), r.label(), wall(r.wall_s), e3(r.primary())))
            .collect();
        let an = rows.iter().find(|r| r.case == *c).map_or("", |r| r.analysis.as_str());
        let _ = writeln!(
            s,
            "- {c} ({}): {}",
            primary_name(an),
            if front.is_empty() { "-".into() } else { front.join("; ") }
        );
    }
    if !warnings.is_empty() {
        let _ = writeln!(s, "\n### Warnings\n");
        for w in warnings {
            let _ = writeln!(s, "- {w}");
        }
    }
    s
}

/// Order of quantities in the tables: L1 errors, crater, then the gauges by name.
fn quantity_rank(q: &str) -> (u8, String) {
    let r = match q {
        "l1_rho" => 0,
        "l1_v" => 1,
        "l1_p" => 2,
        "l1_e" => 3,
        "crater_diameter" => 4,
        "crater_depth" => 5,
        _ => 6,
    };
    (r, q.to_string())
}

fn reference(fm: &Family) -> String {
    match (fm.analysis.as_str(), fm.reference_k) {
        ("riemann", _) => "exact solution".into(),
        (_, Some(k)) => k_tag(k),
        (_, None) => "-".into(),
    }
}

fn wall(v: Option<f64>) -> String {
    match v {
        Some(x) if x >= 100.0 => format!("{x:.0}"),
        Some(x) if x >= 1.0 => format!("{x:.2}"),
        Some(x) => format!("{x:.3}"),
        None => "-".into(),
    }
}

fn e3(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{x:.3e}"),
        _ => "-".into(),
    }
}

fn cm(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{:.1}", 100.0 * x),
        _ => "-".into(),
    }
}

fn status(r: &Row) -> String {
    match (&r.note, r.status.as_str()) {
        (Some(n), "skipped") => format!("skipped: {n}"),
        (Some(_), st) => st.to_string(),
        (None, st) => st.to_string(),
    }
}

/// An error measure of a run, for a plot.
type ErrOf = Box<dyn Fn(&Row) -> Option<f64>>;

/// Error-against-time plots: `error_vs_time.png` (one panel per case, its primary error) and
/// `error_vs_time_<case>.png` (one panel per quantity of the case).
fn plots(out: &Path, rows: &[Row]) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let mut cases: Vec<&str> = Vec::new();
    for r in rows {
        if !cases.contains(&r.case.as_str()) {
            cases.push(&r.case);
        }
    }
    let series = |case: &str, err: &dyn Fn(&Row) -> Option<f64>| -> Vec<plot::LogSeries> {
        let mut fams: Vec<plot::LogSeries> = Vec::new();
        for r in rows.iter().filter(|r| r.case == case && r.ok()) {
            let (Some(t), Some(e)) = (r.wall_s, err(r)) else { continue };
            let pt = (t, e, format!("k={}", k_tag(r.k)));
            match fams.iter_mut().find(|f| f.0 == r.label()) {
                Some(f) => f.1.push(pt),
                None => fams.push((r.label(), vec![pt])),
            }
        }
        for f in &mut fams {
            f.1.sort_by(|a, b| a.0.total_cmp(&b.0));
        }
        fams
    };
    let mut summary = Vec::new();
    for c in &cases {
        let an = rows.iter().find(|r| r.case == *c).map_or("", |r| r.analysis.as_str());
        if an == "none" {
            continue;
        }
        summary.push(plot::LogPanel {
            title: format!("{c}: {}", primary_name(an)),
            xlabel: "wall time (s)".into(),
            ylabel: "error".into(),
            series: series(c, &|r: &Row| r.primary()),
        });
        let mut qs: Vec<(String, String)> = Vec::new();
        let mut panels = Vec::new();
        for r in rows.iter().filter(|r| r.case == *c) {
            for (q, _) in r.quantities() {
                let key = (q.clone(), "ref".to_string());
                if an == "crater" && !qs.contains(&key) {
                    qs.push(key);
                }
                if an == "riemann" && !qs.contains(&(q.clone(), "exact".into())) {
                    qs.push((q, "exact".into()));
                }
            }
            for q in r.vs_thesis.keys() {
                let key = (q.clone(), "thesis".to_string());
                if !qs.contains(&key) {
                    qs.push(key);
                }
            }
        }
        qs.sort_by_key(|(q, how)| (how == "thesis", quantity_rank(q)));
        for (q, how) in &qs {
            let (title, err): (String, ErrOf) = match how.as_str() {
                "exact" => (format!("{} against the exact solution", quantity_title(q)), {
                    let q = q.clone();
                    Box::new(move |r: &Row| r.quantity(&q))
                }),
                "ref" => (format!("{}: relative error against the finest run", quantity_title(q)), {
                    let q = q.clone();
                    Box::new(move |r: &Row| r.err_ref.get(&q).copied())
                }),
                _ => (format!("{}: |relative difference| from the thesis", quantity_title(q)), {
                    let q = q.clone();
                    Box::new(move |r: &Row| r.vs_thesis.get(&q).map(|v| v.abs()))
                }),
            };
            panels.push(plot::LogPanel {
                title,
                xlabel: "wall time (s)".into(),
                ylabel: "error".into(),
                series: series(c, &*err),
            });
        }
        if !panels.is_empty() {
            let cols = panels.len().min(3);
            let nrows = panels.len().div_ceil(cols);
            let path = out.join(format!("error_vs_time_{c}.png"));
            plot::loglog_panels(&path, &panels, cols, (560 * cols as u32, 420 * nrows as u32))?;
            files.push(path);
        }
    }
    if !summary.is_empty() {
        let cols = summary.len().min(2);
        let nrows = summary.len().div_ceil(cols);
        let path = out.join("error_vs_time.png");
        plot::loglog_panels(&path, &summary, cols, (720 * cols as u32, 520 * nrows as u32))?;
        files.insert(0, path);
    }
    Ok(files)
}

/// Date and time now, in UTC ("YYYY-MM-DD hh:mm:ss UTC"), and the Unix time.
fn utc_now() -> (String, u64) {
    let secs = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map(|d| d.as_secs()).unwrap_or(0);
    // days since 1970-01-01 to a civil date (H. Hinnant's algorithm)
    let z = (secs / 86_400) as i64 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    let rem = secs % 86_400;
    (format!("{year:04}-{month:02}-{day:02} {:02}:{:02}:{:02} UTC", rem / 3600, rem % 3600 / 60, rem % 60), secs)
}

/// The commit of the working tree, if git can tell (with "-dirty" when it has changes).
fn commit() -> Option<String> {
    let out = std::process::Command::new("git").args(["rev-parse", "--short=10", "HEAD"]).output().ok()?;
    if !out.status.success() {
        return None;
    }
    let mut c = String::from_utf8_lossy(&out.stdout).trim().to_string();
    let dirty = std::process::Command::new("git")
        .args(["status", "--porcelain", "--untracked-files=no"])
        .output()
        .ok()
        .is_some_and(|o| o.status.success() && !o.stdout.is_empty());
    if dirty {
        c += "-dirty";
    }
    Some(c)
}

fn dry_run_text(cells: &[Planned], warnings: &[String]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "blastsph bench --dry-run: {} runs\n", cells.len());
    let _ = writeln!(s, "| # | case | k | dx (m) | particles | k^dim × unrefined | backend | nnps | kernel | run |");
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|");
    for (i, c) in cells.iter().enumerate() {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.4e} | {} | {}{} | {} | {} | {} | {} |",
            i + 1,
            c.case,
            k_tag(c.k),
            c.dx_m,
            c.particles,
            c.particles_expected,
            if c.count_exact { "" } else { " (differs)" },
            c.backend.name(),
            nnps_name(c.nnps),
            c.kernel.name(),
            match &c.skip {
                Some(w) => format!("skipped: {w}"),
                None => c.dir.display().to_string(),
            }
        );
    }
    for w in warnings {
        let _ = writeln!(s, "\nwarning: {w}");
    }
    s
}

/// Runs the bench (or, with `dry_run`, lists its matrix) and writes its files into `o.out`.
pub fn bench(o: &BenchOptions) -> Result<BenchOutput> {
    let cases = read_cases(o)?;
    let (cells, warnings) = plan(o, &cases)?;
    if o.dry_run {
        let text = dry_run_text(&cells, &warnings);
        return Ok(BenchOutput { rows: Vec::new(), families: Vec::new(), warnings, text, files: Vec::new() });
    }
    for w in &warnings {
        eprintln!("bench: warning: {w}");
    }
    std::fs::create_dir_all(&o.out).map_err(|e| SphError::Io(format!("{}: {e}", o.out.display())))?;
    // the date and the commit of the start: what was measured, not what the tree became meanwhile
    let (date, unix) = utc_now();
    let commit = commit();
    let mut rows = Vec::new();
    let n = cells.len();
    for (i, c) in cells.iter().enumerate() {
        let what = format!(
            "bench [{}/{n}] {} k = {} ({} particles) {}",
            i + 1,
            c.case,
            k_tag(c.k),
            c.particles,
            family_label(c.backend.name(), nnps_name(c.nnps), c.kernel.name())
        );
        let mut row = run_one(c, &cases[c.ci], o)?;
        let mut runs: Vec<f64> = row.wall_s.into_iter().collect();
        for _ in 1..o.repeat {
            if !row.ok() {
                break;
            }
            let again = run_one(c, &cases[c.ci], o)?;
            runs.extend(again.wall_s);
            if again.wall_s.zip(row.wall_s).is_some_and(|(a, b)| a < b) {
                row = again;
            }
        }
        row.wall_s_runs = runs;
        match row.status.as_str() {
            "skipped" => eprintln!("{what}: skipped"),
            st => eprintln!(
                "{what}: {} steps, {} s, {} particle-steps/s{}",
                row.steps.unwrap_or(0),
                wall(row.wall_s),
                e3(row.particle_steps_per_s),
                if st == "ok" { String::new() } else { format!(" ({st})") }
            ),
        }
        rows.push(row);
    }
    let families = analyse(&mut rows);
    let meta = json!({
        "date_utc": date,
        "unix_time": unix,
        "commit": commit,
        "version": env!("CARGO_PKG_VERSION"),
        "cores": std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1),
        "pool_threads": rayon::current_num_threads(),
        "cases": cases.iter().map(|c| c.path.display().to_string()).collect::<Vec<_>>(),
        "resolutions": o.resolutions,
        "backends": o.backends.iter().map(|b| b.name()).collect::<Vec<_>>(),
        "nnps": o.nnps.iter().map(|n| nnps_name(*n)).collect::<Vec<_>>(),
        "kernels": o.kernels.iter().map(|k| k.name()).collect::<Vec<_>>(),
        "end_time_s": o.end_time,
        "max_direct_particles": o.max_direct_particles,
        "repeat": o.repeat,
        "sets": o.sets,
    });
    let text = tables(&rows, &families, &warnings, &meta);
    let mut files = Vec::new();
    let write = |name: &str, body: &str, files: &mut Vec<PathBuf>| -> Result<()> {
        let p = o.out.join(name);
        std::fs::write(&p, body).map_err(|e| SphError::Io(format!("{}: {e}", p.display())))?;
        files.push(p);
        Ok(())
    };
    write("bench.csv", &csv(&rows), &mut files)?;
    let js = json!({
        "bench": meta,
        "primary_error": cases.iter().map(|c| (c.name.clone(), json!(primary_name(analysis_name(c.base.analysis.kind))))).collect::<serde_json::Map<_, _>>(),
        "runs": rows,
        "configurations": families,
        "warnings": warnings,
    });
    write("bench.json", &serde_json::to_string_pretty(&js).unwrap_or_default(), &mut files)?;
    write("bench.md", &text, &mut files)?;
    files.extend(plots(&o.out, &rows)?);
    Ok(BenchOutput { rows, families, warnings, text, files })
}
