//! The matrix: cases × resolutions × backends × searches × kernels, read and planned.

use crate::error::Result;

use super::options::BenchOptions;
use super::options::nnps_name;
use crate::case;
use crate::case::Case;
use crate::case::KernelKind;
use crate::case::NnpsKind;
use crate::case::Shape;
use crate::case::refine::refine;
use crate::error::input;
use crate::modules::Backend;
use std::path::PathBuf;

/// One case of the bench, read once.
pub(super) struct CaseFile {
    pub(super) name: String,
    pub(super) path: PathBuf,
    pub(super) text: String,
    pub(super) base: Case,
    /// Particles per region of the unrefined case.
    pub(super) base_counts: Vec<usize>,
}

/// One cell of the matrix.
#[derive(Debug, Clone)]
pub struct Planned {
    pub case: String,
    pub(super) ci: usize,
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
    /// The run's own pool of this many threads (`--threads` as a list), else the bench's pool.
    pub threads: Option<usize>,
    pub dir: PathBuf,
    /// Why the run is skipped.
    pub skip: Option<String>,
}

pub(super) fn k_tag(k: f64) -> String {
    format!("{k}")
}

/// A configuration's label: `backend/search/kernel`, and ` ×N` threads when the thread count is
/// an axis of the matrix.
pub(super) fn family_label(backend: &str, nnps: &str, kernel: &str, threads: Option<usize>) -> String {
    match threads {
        Some(t) => format!("{backend}/{nnps}/{kernel} ×{t}"),
        None => format!("{backend}/{nnps}/{kernel}"),
    }
}

pub(super) fn read_cases(o: &BenchOptions) -> Result<Vec<CaseFile>> {
    let mut out: Vec<CaseFile> = Vec::new();
    for path in &o.cases {
        let text = case::read_text(path)?;
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
pub(super) fn plan(o: &BenchOptions, cases: &[CaseFile]) -> Result<(Vec<Planned>, Vec<String>)> {
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
                                    _ if !r.keep_below.is_empty() => {
                                        ", clipped by keep_below: a plane cuts the refined lattice elsewhere"
                                    }
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
                        // the Rust runs once per thread count of a `--threads` list
                        let per_thread: Vec<Option<usize>> = if backend == Backend::Rust && !o.thread_axis.is_empty() {
                            o.thread_axis.iter().map(|&t| Some(t)).collect()
                        } else {
                            vec![None]
                        };
                        for threads in per_thread {
                            let dir = o.out.join(&cf.name).join(format!(
                                "k{}_{}_{}_{}{}",
                                k_tag(*k),
                                backend.name(),
                                nnps_name(nnps),
                                kernel.name(),
                                threads.map_or(String::new(), |t| format!("_t{t}"))
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
                                threads,
                                dir,
                                skip: skip.clone(),
                            });
                        }
                    }
                }
            }
        }
    }
    Ok((cells, warnings))
}
