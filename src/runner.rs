//! `blastsph run`: the time loop with outputs, progress and the summary.

use crate::analysis;
use crate::case::{self, AnalysisKind, StepRule};
use crate::error::{Result, SphError};
use crate::output::{Gauges, H5Part};
use crate::sim::{Overrides, Sim};
use serde::Serialize;
use serde_json::json;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    pub out: Option<PathBuf>,
    pub sets: Vec<String>,
    pub ov: Overrides,
    pub quiet: bool,
    pub threads: Option<usize>,
}

#[derive(Debug, Clone, Copy, Serialize)]
pub struct Energy {
    pub kinetic: f64,
    pub internal: f64,
    /// Elastic strain energy Σ m τ:τ/(4Gρ) — part of the internal energy, shown apart.
    pub elastic: f64,
    /// kinetic + internal.
    pub total: f64,
}

fn energy(sim: &Sim) -> Energy {
    let (k, i, e) = sim.energies();
    Energy { kinetic: k, internal: i, elastic: e, total: k + i }
}

/// What a finished (or stopped) run returns.
pub struct RunResult {
    pub dir: PathBuf,
    pub summary: serde_json::Value,
    pub sim: Sim,
}

pub fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::{Digest, Sha256};
    let d = Sha256::digest(bytes);
    d.iter().map(|b| format!("{b:02x}")).collect()
}

pub fn run(case_path: &Path, opts: &RunOptions) -> Result<RunResult> {
    let text = std::fs::read_to_string(case_path)
        .map_err(|e| crate::error::input(format!("{}: cannot read the case file: {e}", case_path.display())))?;
    let case = case::parse(
        &text,
        &case_path.display().to_string(),
        &opts.sets,
        case_path.file_stem().and_then(|s| s.to_str()),
    )?;
    let sim = Sim::new(case, &opts.ov)?;
    let dir = opts.out.clone().unwrap_or_else(|| PathBuf::from("runs").join(sim.case.name()));
    run_sim(sim, &dir, &text, opts)
}

/// Runs a prepared simulation into `dir`.
pub fn run_sim(mut sim: Sim, dir: &Path, case_text: &str, opts: &RunOptions) -> Result<RunResult> {
    std::fs::create_dir_all(dir).map_err(|e| SphError::Io(format!("{}: {e}", dir.display())))?;
    std::fs::write(dir.join("case.toml"), case_text).map_err(|e| SphError::Io(format!("case.toml: {e}")))?;
    let mut h5 = H5Part::create(&dir.join("particles.h5"))?;
    let gpath = dir.join("gauges.csv");
    let mut gauges = Gauges::new(&sim, Some(&gpath))?;
    let e0 = energy(&sim);
    let m0 = sim.total_mass();
    let n = sim.p.nreal;
    let start = Instant::now();

    let fixed_steps = match sim.cfg.step {
        StepRule::Fixed => Some((sim.cfg.end / sim.cfg.dt_fixed).round().max(1.0) as u64),
        StepRule::Cfl => None,
    };
    let interval = sim.cfg.out_interval;
    let mut next_out = if interval > 0.0 { interval } else { f64::INFINITY };
    sim.rates();
    sim.interface_stats();
    h5.write(&sim)?;
    gauges.sample(&sim)?;

    let pb = if opts.quiet {
        indicatif::ProgressBar::hidden()
    } else {
        let pb = indicatif::ProgressBar::new(1000);
        pb.set_style(
            indicatif::ProgressStyle::with_template("{bar:30} {percent:>3}% {msg} [{elapsed} < {eta}]")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        pb
    };
    let mut diag: Option<SphError> = None;
    let mut last_written = 0u64;
    loop {
        let done = match fixed_steps {
            Some(ns) => sim.nstep >= ns,
            None => sim.t >= sim.cfg.end * (1.0 - 1e-12),
        };
        if done {
            break;
        }
        match sim.step() {
            Ok(dt) => {
                gauges.sample(&sim)?;
                if sim.t >= next_out * (1.0 - 1e-9) {
                    sim.interface_stats();
                    h5.write(&sim)?;
                    gauges.flush();
                    last_written = sim.nstep;
                    while next_out <= sim.t * (1.0 + 1e-9) {
                        next_out += interval;
                    }
                }
                if sim.nstep % 10 == 0 {
                    let el = start.elapsed().as_secs_f64().max(1e-9);
                    pb.set_position(((sim.t / sim.cfg.end) * 1000.0).min(1000.0) as u64);
                    pb.set_message(format!(
                        "step {} t = {:.3e} s dt = {:.2e} s {:.2e} particle-steps/s",
                        sim.nstep,
                        sim.t,
                        dt,
                        (n as f64 * sim.nstep as f64) / el
                    ));
                }
            }
            Err(e) => {
                diag = Some(e);
                break;
            }
        }
    }
    pb.finish_and_clear();
    if last_written != sim.nstep {
        sim.interface_stats();
        h5.write(&sim)?;
    }
    gauges.flush();
    let wall = start.elapsed().as_secs_f64();
    let e1 = energy(&sim);
    let m1 = sim.total_mass();

    let modules: serde_json::Map<String, serde_json::Value> = sim
        .plan
        .modules
        .iter()
        .filter(|(_, p)| p.active)
        .map(|(m, p)| (m.name().to_string(), json!(p.backend.name())))
        .collect();
    let skipped: serde_json::Map<String, serde_json::Value> =
        sim.plan.modules.iter().filter(|(_, p)| !p.active).map(|(m, p)| (m.name().to_string(), json!(p.why))).collect();
    let work = sim.book.work_wall + sim.book.work_penalty + sim.book.work_gravity;
    let residual = e1.total - e0.total - work;
    let mut summary = json!({
        "case": sim.case.name(),
        "backend": sim.plan.label(),
        "modules": modules,
        "skipped": skipped,
        "dim": sim.cfg.dim,
        "particles": n,
        "steps": sim.nstep,
        "time": sim.t,
        "wall_seconds": wall,
        "particle_steps_per_second": (n as f64 * sim.nstep as f64) / wall.max(1e-9),
        "threads": rayon::current_num_threads(),
        "nnps": if sim.cfg.cell { "cell" } else { "direct" },
        "mass": { "initial": m0, "final": m1 },
        "energy": {
            "initial": e0, "final": e1,
            "work_wall": sim.book.work_wall,
            "work_penalty": sim.book.work_penalty,
            "work_gravity": sim.book.work_gravity,
            "balance_residual": residual,
            "balance_residual_relative": residual / e0.total.abs().max(1e-300),
        },
        "stability": sim.stab,
        "module_seconds": sim.seconds(),
        "outputs": h5.steps,
        "version": env!("CARGO_PKG_VERSION"),
        "case_sha256": sha256_hex(case_text.as_bytes()),
        "sets": opts.sets,
        "status": if diag.is_some() { "unstable" } else { "ok" },
        "diagnostic": diag.as_ref().map(|d| d.to_string()),
    });
    if !gauges.names.is_empty() {
        let g: Vec<_> = (0..gauges.names.len())
            .map(|k| {
                let i = sim.index_of_id[gauges.particle[k]] as usize;
                json!({
                    "name": gauges.names[k],
                    "point_m": gauges.points[k],
                    "particle": sim.p.id[i],
                    "peak_pa": gauges.peak[k].0,
                    "peak_time_s": gauges.peak[k].1,
                    "arrival_s": gauges.arrival(k),
                })
            })
            .collect();
        summary["gauges"] = json!(g);
    }
    if sim.case.analysis.kind == AnalysisKind::Crater {
        let c = analysis::crater::measure(&sim);
        summary["crater"] = serde_json::to_value(&c).unwrap_or(serde_json::Value::Null);
        summary["ejecta_height_m"] = json!(c.ejecta_height_m);
    }
    let text = serde_json::to_string_pretty(&summary).unwrap_or_default();
    std::fs::write(dir.join("summary.json"), text).map_err(|e| SphError::Io(format!("summary.json: {e}")))?;
    if let Some(d) = diag {
        return Err(d);
    }
    Ok(RunResult { dir: dir.to_path_buf(), summary, sim })
}
