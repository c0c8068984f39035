//! `blastsph run`: the time loop with outputs, progress and the summary.

use crate::analysis;
use crate::case::{self, AnalysisKind, StepRule};
use crate::error::{Result, SphError};
use crate::gauges::Gauges;
use crate::output::{H5Part, Peaks};
use crate::progress::{self, Progress};
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
    let as_run = case_as_run(&text, &case_path.display().to_string(), opts)?;
    run_sim_as(sim, &dir, &text, &as_run, opts)
}

/// The text of the run directory's `case.toml`: the case file with every `--set` applied (and
/// `--end-time`, `--nnps` as the keys they replace), each changed value marked, and a header
/// that lists the overrides and the flags that do not change the results (backends).
pub fn case_as_run(text: &str, origin: &str, opts: &RunOptions) -> Result<String> {
    let mut sets = opts.sets.clone();
    if let Some(t) = opts.ov.end_time {
        sets.push(format!("time.end_s={t:?}"));
    }
    if let Some(n) = &opts.ov.nnps {
        sets.push(format!("sph.nnps=\"{n}\""));
    }
    let body = case::apply_sets(text, &sets)?;
    let mut head = format!(
        "# The case as run by blastsph {} from {origin}.\n# Rerun it as it is: blastsph run case.toml\n",
        env!("CARGO_PKG_VERSION")
    );
    if sets.is_empty() {
        head += "# No command-line override: the text below is the case file's.\n";
    } else {
        head += "# The case file with these command-line overrides applied (each value marked `# set by --set`):\n";
        for s in &opts.sets {
            head += &format!("#   --set {s}\n");
        }
        if let Some(t) = opts.ov.end_time {
            head += &format!("#   --end-time {t:?}  (as time.end_s)\n");
        }
        if let Some(n) = &opts.ov.nnps {
            head += &format!("#   --nnps {n}  (as sph.nnps)\n");
        }
    }
    let mut flags = Vec::new();
    if let Some(b) = opts.ov.backend {
        flags.push(format!("--backend {}", b.name()));
    }
    if !opts.ov.rust.is_empty() {
        flags.push(format!("--rust {}", opts.ov.rust.join(",")));
    }
    if !opts.ov.fortran.is_empty() {
        flags.push(format!("--fortran {}", opts.ov.fortran.join(",")));
    }
    if !flags.is_empty() {
        head += &format!(
            "# Run with {} (the implementations are bitwise equal; pass the same flags to rerun it the same way).\n",
            flags.join(" ")
        );
    }
    Ok(format!("{head}\n{body}"))
}

/// Runs a prepared simulation into `dir`; `case_text` is the case file as given (its SHA-256
/// goes into summary.json) and case.toml holds the case file's text unchanged.
pub fn run_sim(sim: Sim, dir: &Path, case_text: &str, opts: &RunOptions) -> Result<RunResult> {
    run_sim_as(sim, dir, case_text, case_text, opts)
}

/// Runs a prepared simulation into `dir`, writing `as_run` as case.toml.
pub fn run_sim_as(mut sim: Sim, dir: &Path, case_text: &str, as_run: &str, opts: &RunOptions) -> Result<RunResult> {
    std::fs::create_dir_all(dir).map_err(|e| SphError::Io(format!("{}: {e}", dir.display())))?;
    std::fs::write(dir.join("case.toml"), as_run).map_err(|e| SphError::Io(format!("case.toml: {e}")))?;
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
    let mut peaks = Peaks::new(&sim);
    h5.write(&sim, Some(&peaks))?;
    gauges.sample(&sim)?;

    let mut pb = Progress::new(
        progress::Mode::choose(opts.quiet, progress::every()),
        sim.cfg.end,
        n,
        &format!("{}: ", sim.case.name()),
    );
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
                peaks.update(&sim);
                if sim.t >= next_out * (1.0 - 1e-9) {
                    sim.interface_stats();
                    h5.write(&sim, Some(&peaks))?;
                    gauges.flush();
                    last_written = sim.nstep;
                    while next_out <= sim.t * (1.0 + 1e-9) {
                        next_out += interval;
                    }
                }
                pb.update(sim.nstep, sim.t, dt);
            }
            Err(e) => {
                diag = Some(e);
                break;
            }
        }
    }
    pb.finish();
    if last_written != sim.nstep {
        sim.interface_stats();
        h5.write(&sim, Some(&peaks))?;
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
        "case_toml": "the case as run: every --set (and --end-time, --nnps) already applied",
        "status": if diag.is_some() { "unstable" } else { "ok" },
        "diagnostic": diag.as_ref().map(|d| d.to_string()),
    });
    if !gauges.names.is_empty() {
        summary["gauges"] = json!(gauges.summary());
    }
    if sim.case.analysis.kind == AnalysisKind::Crater {
        match analysis::crater::measure(&sim) {
            Ok(c) => {
                summary["crater"] = serde_json::to_value(&c).unwrap_or(serde_json::Value::Null);
                summary["crater"]["measured"] = json!(true);
                summary["ejecta_height_m"] = json!(c.ejecta_height_m);
            }
            Err(why) => summary["crater"] = json!({ "measured": false, "reason": why }),
        }
    }
    let text = serde_json::to_string_pretty(&summary).unwrap_or_default();
    std::fs::write(dir.join("summary.json"), text).map_err(|e| SphError::Io(format!("summary.json: {e}")))?;
    if let Some(d) = diag {
        return Err(d);
    }
    Ok(RunResult { dir: dir.to_path_buf(), summary, sim })
}
