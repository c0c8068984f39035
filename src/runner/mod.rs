//! `blastsph run`: the time loop with outputs, progress, checkpoints and the summary
//! ([`restart`] writes and reads the checkpoints and resumes a run).

mod follow;
pub mod restart;

use crate::analysis;
use crate::case::{self, AnalysisKind, StepRule};
use crate::error::{IoAt, Result, SphError, input};
use crate::gauges::Gauges;
use crate::modules::ranks;
use crate::output::{H5Part, Peaks};
use crate::progress::{self, Progress};
use crate::rundir::{self, Found, sha256_hex};
use crate::sim::{Overrides, Sim};
use serde::Serialize;
use serde_json::json;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    pub out: Option<PathBuf>,
    pub sets: Vec<String>,
    pub ov: Overrides,
    pub quiet: bool,
    pub threads: Option<usize>,
    /// Replace a non-empty run directory: its blastsph files are removed first (`--force`).
    pub force: bool,
    /// When checkpoints are written (default: never).
    pub checkpoints: Checkpoints,
    /// Stop cleanly after this step, as a SIGTERM would (a checkpoint, exit status 5).
    pub stop_after_step: Option<u64>,
}

/// When a run writes its checkpoint (`checkpoint.bin` in the run directory, replaced each time).
/// A clean stop (SIGINT, SIGTERM) always writes one.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Checkpoints {
    /// Every this many steps (`--checkpoint-every`).
    pub every_steps: Option<u64>,
    /// Every this many seconds of wall time (`--checkpoint-wall`).
    pub every_wall_s: Option<f64>,
    /// At the end of the run, so that `blastsph resume DIR --end-time S` can extend it.
    pub at_end: bool,
}

impl Checkpoints {
    /// `blastsph run`'s default: every 15 minutes of wall time, and at the end.
    pub const CLI: Checkpoints = Checkpoints { every_steps: None, every_wall_s: Some(900.0), at_end: true };
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

pub(crate) fn energy(sim: &Sim) -> Energy {
    let (k, i, e) = sim.energies();
    Energy { kinetic: k, internal: i, elastic: e, total: k + i }
}

/// What a finished (or stopped) run returns.
pub struct RunResult {
    pub dir: PathBuf,
    pub summary: serde_json::Value,
    pub sim: Sim,
}

/// The flag a SIGINT or SIGTERM sets (the command line installs the handlers): the run finishes
/// its step, writes a checkpoint and stops with exit status 5.
pub(crate) fn stop_flag() -> Arc<AtomicBool> {
    static FLAG: std::sync::OnceLock<Arc<AtomicBool>> = std::sync::OnceLock::new();
    FLAG.get_or_init(|| Arc::new(AtomicBool::new(false))).clone()
}

pub fn run(case_path: &Path, opts: &RunOptions) -> Result<RunResult> {
    if !ranks::is_root() {
        return follow::run(case_path, opts);
    }
    // under mpirun the other ranks wait while rank 0 checks the case and prepares the run
    // directory alone: a refusal here ends them too (before the time loop no row loop is split)
    let ready = (|| {
        let (text, case, dir, as_run, lock, clear) = match start(case_path, opts)? {
            Start::Fresh { text, case, dir, as_run, lock, clear } => (text, case, dir, as_run, lock, clear),
            Start::Resume(dir, ro) => return Ok(Err((dir, ro))),
        };
        let sim = Sim::new(*case, &opts.ov)?;
        crate::case::slips::check(&sim.case, &sim.p, sim.cfg.dx_min)?;
        rundir::prepare(&dir, clear)?;
        let lock = match lock {
            Some(l) => l,
            None => rundir::lock_run(&dir, "--out")?,
        };
        if !opts.quiet {
            // the settings known to fail, as `blastsph check` lists them (once the run directory
            // is ready: a refused run stays one line)
            for w in crate::advice::all(&sim.case, &sim.p, &sim.region) {
                eprintln!("warning: {w}");
            }
        }
        // a mapped routine that does not run is said even with --quiet: the run would otherwise
        // read as the user's code
        for w in sim.plan.legacy_warnings() {
            eprintln!("warning: {w}");
        }
        Ok(Ok((Loop::fresh(sim, &dir, &text, &as_run, opts)?, lock)))
    })();
    match follow::settle_run(ready)? {
        Ok((lp, _lock)) => lp.go(opts),
        Err((dir, ro)) => restart::resume(&dir, &ro),
    }
}

/// How `run` starts: a new run into its folder, or the continuation of the same run.
enum Start {
    Fresh {
        text: String,
        case: Box<case::Case>,
        dir: PathBuf,
        as_run: String,
        lock: Option<rundir::DirLock>,
        clear: bool,
    },
    Resume(PathBuf, restart::ResumeOptions),
}

/// The checks of `run` before the solver is built: the case, and what its run directory holds.
fn start(case_path: &Path, opts: &RunOptions) -> Result<Start> {
    let text = case::read_text(case_path)?;
    let origin = case_path.display().to_string();
    let case = case::parse(&text, &origin, &opts.sets, case_path.file_stem().and_then(|s| s.to_str()))?;
    let dir = opts.out.clone().unwrap_or_else(|| rundir::default_dir(case.name()));
    let as_run = case_as_run(&text, &origin, opts)?;
    let found = rundir::inspect(&dir, "--out")?;
    // a run's folder is locked before it is looked into further or cleared (a run into a folder
    // another run is writing deleted that run's files); a new or empty one once it is made (a
    // refused run writes nothing into it), and one of other files is refused below untouched
    let lock = match found {
        Found::Run { .. } => Some(rundir::lock_run(&dir, "--out")?),
        _ => None,
    };
    let shown = dir.display();
    let clear = match found {
        Found::Missing | Found::Empty => false,
        Found::Run { case_toml: Some(t), checkpoint: true, .. } if t == as_run && !opts.force => {
            // its own restart: the same case, stopped or killed after a checkpoint
            let status = std::fs::read(dir.join("summary.json"))
                .ok()
                .and_then(|b| serde_json::from_slice::<serde_json::Value>(&b).ok())
                .and_then(|v| v["status"].as_str().map(String::from));
            if matches!(status.as_deref(), Some("ok" | "unstable")) {
                return Err(input(format!(
                    "--out {shown}: holds this run, finished (status {}): --force runs it again, `blastsph resume {shown} --end-time S` extends it",
                    status.unwrap_or_default()
                )));
            }
            if !opts.quiet {
                eprintln!("{shown} holds this run, stopped at its checkpoint: continuing it (--force starts it anew)");
            }
            let ro = restart::ResumeOptions::of_run(opts);
            // (resume takes the lock itself)
            drop(lock);
            return Ok(Start::Resume(dir, ro));
        }
        _ if opts.force => true,
        Found::Run { .. } => {
            return Err(input(format!(
                "--out {shown}: holds another run (its case.toml differs, or it has no checkpoint): `blastsph resume {shown}` continues it, --force replaces it"
            )));
        }
        Found::Other(name) => {
            return Err(input(format!(
                "--out {shown}: not empty (it holds `{name}`, not written by blastsph): give an empty or new folder"
            )));
        }
    };
    Ok(Start::Fresh { text, case: Box::new(case), dir, as_run, lock, clear })
}

/// The text of the run directory's `case.toml`: the case file with every `--set` applied (and
/// `--end-time`, `--nnps` as the keys they replace), each changed value marked, and a header
/// that lists the overrides and the flags that do not change the results (backends).
pub(crate) fn case_as_run(text: &str, origin: &str, opts: &RunOptions) -> Result<String> {
    let mut sets = opts.sets.clone();
    let mut body = case::apply_sets(text, &opts.sets)?;
    // the flags that stand for a key, each marked with its own name
    if let Some(t) = opts.ov.end_time {
        let s = format!("time.end_s={t:?}");
        body = case::apply_sets_by(&body, std::slice::from_ref(&s), "--end-time")?;
        sets.push(s);
    }
    if let Some(n) = &opts.ov.nnps {
        let s = format!("sph.nnps=\"{n}\"");
        body = case::apply_sets_by(&body, std::slice::from_ref(&s), "--nnps")?;
        sets.push(s);
    }
    let mut head = format!(
        "# The case as run by blastsph {} from {origin}.\n# Rerun it as it is: blastsph run case.toml\n",
        env!("CARGO_PKG_VERSION")
    );
    if sets.is_empty() {
        head += "# No command-line override: the text below is the case file's.\n";
    } else {
        head += "# The case file with these command-line overrides applied (each value marked `# set by` its flag):\n";
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

/// Runs a prepared simulation into `dir` (new or empty; with `opts.force`, a run directory
/// cleared first), writing `as_run` as case.toml.
pub fn run_sim_as(sim: Sim, dir: &Path, case_text: &str, as_run: &str, opts: &RunOptions) -> Result<RunResult> {
    let clear = match rundir::inspect(dir, "--out")? {
        Found::Missing | Found::Empty => false,
        _ if opts.force => true,
        _ => return Err(input(format!("--out {}: not empty (--force replaces a run directory)", dir.display()))),
    };
    rundir::prepare(dir, clear)?;
    Loop::fresh(sim, dir, case_text, as_run, opts)?.go(opts)
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Status {
    /// In progress (a summary written at a checkpoint: a run killed later keeps it).
    Running,
    /// Stopped cleanly (a signal): a checkpoint was written, `blastsph resume` continues it.
    Stopped,
    Ok,
    Unstable,
}

impl Status {
    fn name(self) -> &'static str {
        match self {
            Status::Running => "running",
            Status::Stopped => "stopped",
            Status::Ok => "ok",
            Status::Unstable => "unstable",
        }
    }
}

/// The run loop's state beside the solver's: what a checkpoint keeps of it
/// ([`restart`]).
pub(crate) struct Loop {
    pub sim: Sim,
    pub dir: PathBuf,
    pub h5: H5Part,
    pub gauges: Gauges,
    pub peaks: Peaks,
    /// Energy and mass at t = 0.
    pub e0: Energy,
    pub m0: f64,
    /// Time of the next output (s).
    pub next_out: f64,
    /// The step last written to particles.h5.
    pub last_written: u64,
    /// Wall seconds of the run before this process (a resumed run).
    pub wall_before: f64,
    /// SHA-256 of the case file as given, and of case.toml (the case as run).
    pub case_sha: String,
    pub case_toml_sha: String,
    /// The `--set` overrides of the run.
    pub sets: Vec<String>,
    /// (step, time) of each resume.
    pub resumes: Vec<(u64, f64)>,
    /// What each resume continued with changed (`resume --allow-changed`; empty: nothing).
    pub resume_changes: Vec<String>,
    pub start: Instant,
    /// A detonation's outputs so far (time, x, p, material: [`analysis::verify::slim`]), for
    /// the history in summary.json; empty for the other analyses.
    pub det_frames: Vec<crate::output::Frame>,
}

impl Loop {
    /// A new run in the prepared folder `dir`: case.toml, particles.h5 with Step#0, gauges.csv.
    fn fresh(mut sim: Sim, dir: &Path, case_text: &str, as_run: &str, opts: &RunOptions) -> Result<Loop> {
        use std::io::Write;
        let mut f = rundir::create_new(&dir.join("case.toml"))?;
        f.write_all(as_run.as_bytes()).io_at("case.toml")?;
        let mut h5 = H5Part::create(&dir.join("particles.h5"))?;
        let mut gauges = Gauges::new(&sim, Some(&dir.join("gauges.csv")))?;
        let e0 = energy(&sim);
        let m0 = sim.total_mass();
        // a legacy STOP in the rates at t = 0 ends the process before the summary below: the
        // exit handler then writes this much of one
        #[cfg(feature = "legacy")]
        if !sim.plan.legacy.is_null() {
            crate::migration::ffi::report_exit_with(
                dir.join("summary.json"),
                serde_json::json!({
                    "case": sim.case.name(), "backend": sim.plan.label(), "legacy": sim.plan.legacy_modules(),
                    "dim": sim.cfg.dim, "particles": sim.p.nreal, "end_time": sim.cfg.end,
                    "case_toml_sha256": sha256_hex(as_run.as_bytes()),
                }),
            );
        }
        sim.rates();
        sim.interface_stats();
        let peaks = Peaks::new(&sim);
        h5.write(&sim, Some(&peaks))?;
        gauges.sample(&sim)?;
        let interval = sim.cfg.out_interval;
        let lp = Loop {
            sim,
            dir: dir.to_path_buf(),
            h5,
            gauges,
            peaks,
            e0,
            m0,
            next_out: if interval > 0.0 { interval } else { f64::INFINITY },
            last_written: 0,
            wall_before: 0.0,
            case_sha: sha256_hex(case_text.as_bytes()),
            case_toml_sha: sha256_hex(as_run.as_bytes()),
            sets: opts.sets.clone(),
            resumes: Vec::new(),
            resume_changes: Vec::new(),
            start: Instant::now(),
            det_frames: Vec::new(),
        };
        // a summary from the start: a run killed before its first checkpoint is still reported
        lp.write_summary(Status::Running, None)?;
        Ok(lp)
    }

    /// Wall seconds of the whole run so far.
    pub fn wall(&self) -> f64 {
        self.wall_before + self.start.elapsed().as_secs_f64()
    }

    /// Steps to the end until done; writes the outputs, the checkpoints and the summary.
    pub fn go(mut self, opts: &RunOptions) -> Result<RunResult> {
        let n = self.sim.p.nreal;
        let fixed_steps = match self.sim.cfg.step {
            StepRule::Fixed => Some((self.sim.cfg.end / self.sim.cfg.dt_fixed).round().max(1.0) as u64),
            StepRule::Cfl => None,
        };
        let interval = self.sim.cfg.out_interval;
        let mut pb = Progress::new(
            progress::Mode::choose(opts.quiet, progress::every()),
            self.sim.cfg.end,
            n,
            &format!("{}: ", self.sim.case.name()),
        )
        .starting_at(self.sim.t, self.sim.nstep);
        let stop = stop_flag();
        // every rank is at its time loop: the row loops split from here on
        ranks::arm();
        // a legacy STOP ends the process inside a step: its exit handler marks this summary
        let _watch = legacy_watch::Watch::start(&self.sim, &self.dir);
        let cp = opts.checkpoints;
        let (mut cp_step, mut cp_wall) = (self.sim.nstep, Instant::now());
        let mut diag: Option<SphError> = None;
        let mut stopped = false;
        loop {
            let done = match fixed_steps {
                Some(ns) => self.sim.nstep >= ns,
                None => self.sim.t >= self.sim.cfg.end * (1.0 - 1e-12),
            };
            if done {
                break;
            }
            match self.sim.step() {
                Ok(dt) => {
                    if let Some(w) = &_watch {
                        w.progress(&self.sim);
                    }
                    self.gauges.sample(&self.sim)?;
                    self.peaks.update(&self.sim);
                    if self.sim.t >= self.next_out * (1.0 - 1e-9) {
                        self.sim.interface_stats();
                        self.h5.write(&self.sim, Some(&self.peaks))?;
                        if self.sim.case.analysis.kind == AnalysisKind::Detonation {
                            self.det_frames.push(analysis::verify::slim(analysis::verify::frame_of(&self.sim)));
                        }
                        self.gauges.flush();
                        self.last_written = self.sim.nstep;
                        while self.next_out <= self.sim.t * (1.0 + 1e-9) {
                            self.next_out += interval;
                        }
                    }
                    pb.update(self.sim.nstep, self.sim.t, dt);
                }
                Err(SphError::Unstable(msg)) => {
                    // the diagnostic names the likely fix (src/advice/)
                    let mut hint = crate::advice::hint(&self.sim.case, &msg);
                    if !self.sim.plan.legacy.is_null() {
                        hint = format!(
                            "with --legacy, a mapped routine may have made it: `blastsph dual --legacy` names the first one whose output differs from blastsph's; else {hint}"
                        );
                    }
                    diag = Some(SphError::Unstable(format!("{msg}; {hint}")));
                    break;
                }
                Err(e) => {
                    diag = Some(e);
                    break;
                }
            }
            // a clean stop, after the step and its outputs
            // (under mpirun every rank stops after the same step: a signal reaches each rank
            // at its own moment)
            if ranks::any(stop.load(Ordering::Relaxed) || opts.stop_after_step.is_some_and(|s| self.sim.nstep >= s)) {
                stopped = true;
                break;
            }
            let due = cp.every_steps.is_some_and(|k| self.sim.nstep - cp_step >= k)
                || cp.every_wall_s.is_some_and(|s| cp_wall.elapsed().as_secs_f64() >= s);
            if due {
                restart::write(&mut self)?;
                self.write_summary(Status::Running, None)?;
                (cp_step, cp_wall) = (self.sim.nstep, Instant::now());
            }
        }
        pb.finish();
        if stopped {
            restart::write(&mut self)?;
            let line = SphError::Stopped(format!(
                "at step {} (t = {:.6e} s of {:e} s): checkpoint written; `blastsph resume {}` continues the run",
                self.sim.nstep,
                self.sim.t,
                self.sim.cfg.end,
                self.dir.display()
            ));
            // (the summary's diagnostic is the line the run ended with)
            self.write_summary(Status::Stopped, Some(&line))?;
            return Err(line);
        }
        if self.last_written != self.sim.nstep {
            self.sim.interface_stats();
            self.h5.write(&self.sim, Some(&self.peaks))?;
            self.last_written = self.sim.nstep;
        }
        self.h5.sync_xdmf()?;
        self.gauges.flush();
        if diag.is_none() && cp.at_end {
            restart::write(&mut self)?;
        }
        let status = if diag.is_some() { Status::Unstable } else { Status::Ok };
        let summary = self.write_summary(status, diag.as_ref())?;
        if let Some(d) = diag {
            return Err(d);
        }
        Ok(RunResult { dir: self.dir, summary, sim: self.sim })
    }

    /// summary.json for the run as it stands, written (through a temporary file) and returned.
    pub(crate) fn write_summary(&self, status: Status, diag: Option<&SphError>) -> Result<serde_json::Value> {
        let sim = &self.sim;
        let n = sim.p.nreal;
        let wall = self.wall();
        let (e0, e1, m1) = (self.e0, energy(sim), sim.total_mass());
        let modules: serde_json::Map<String, serde_json::Value> = sim
            .plan
            .modules
            .iter()
            .filter(|(_, p)| p.active)
            .map(|(m, _)| (m.name().to_string(), json!(sim.plan.implementation(*m))))
            .collect();
        let skipped: serde_json::Map<String, serde_json::Value> = sim
            .plan
            .modules
            .iter()
            .filter(|(_, p)| !p.active)
            .map(|(m, p)| (m.name().to_string(), json!(p.why)))
            .collect();
        let bk = &sim.book;
        let residual = e1.total - e0.total - bk.work();
        let mut summary = json!({
            "case": sim.case.name(),
            "backend": sim.plan.label(),
            "modules": modules,
            "legacy": sim.plan.legacy_modules(),
            "skipped": skipped,
            "dim": sim.cfg.dim,
            "particles": n,
            "steps": sim.nstep,
            "time": sim.t,
            "end_time": sim.cfg.end,
            "wall_seconds": wall,
            "particle_steps_per_second": (n as f64 * sim.nstep as f64) / wall.max(1e-9),
            "threads": rayon::current_num_threads(),
            "nnps": if sim.cfg.cell { "cell" } else { "direct" },
            "mass": { "initial": self.m0, "final": m1 },
            "energy": {
                "initial": e0, "final": e1,
                "work_wall": sim.book.work_wall,
                "work_penalty": sim.book.work_penalty,
                "work_gravity": sim.book.work_gravity,
                "work_floor": sim.book.work_floor,
                "work_boundary": sim.book.work_boundary,
                "balance_residual": residual,
                // over the energy the run has had to work with: the initial energy and the
                // external forces' work, each in magnitude (a body at rest at e = 0 under
                // gravity starts from 0 J)
                "balance_residual_relative": residual / bk.scale(e0.total).max(1e-300),
            },
            "stability": sim.stab,
            "module_seconds": sim.seconds(),
            "outputs": self.h5.steps,
            "version": env!("CARGO_PKG_VERSION"),
            "case_sha256": self.case_sha,
            "case_toml_sha256": self.case_toml_sha,
            "sets": self.sets,
            "case_toml": "the case as run: every --set (and --end-time, --nnps) already applied",
            "status": status.name(),
            "partial": matches!(status, Status::Running | Status::Stopped),
            "diagnostic": diag.map(|d| d.to_string()),
            "resumed": self.resumes.iter().enumerate().map(|(k, (s, t))| {
                let changed = self.resume_changes.get(k).filter(|c| !c.is_empty());
                json!({ "step": s, "time": t, "changed": changed })
            }).collect::<Vec<_>>(),
        });
        // particles with negative specific internal energy, per material
        {
            let mut by = serde_json::Map::new();
            let (mut count, mut emin) = (0usize, f64::INFINITY);
            for (m, mc) in sim.case.materials.iter().enumerate() {
                let es: Vec<f64> = (0..n).filter(|&i| sim.p.mat[i] as usize == m).map(|i| sim.p.e[i]).collect();
                let neg = es.iter().filter(|&&e| e < 0.0).count();
                let lo = es.iter().cloned().fold(f64::INFINITY, f64::min);
                count += neg;
                emin = emin.min(lo);
                let lo = if lo.is_finite() { json!(lo) } else { json!(null) };
                by.insert(mc.name.clone(), json!({ "count": neg, "min_e_jkg": lo }));
            }
            let emin = if emin.is_finite() { json!(emin) } else { json!(null) };
            summary["negative_e"] = json!({ "count": count, "min_e_jkg": emin, "by_material": by });
        }
        // the analyses measure what the run made: nothing before its first step (and the summary
        // written at the start stays out of the run's time)
        let made = sim.nstep > 0;
        if made
            && matches!(
                sim.case.analysis.kind,
                AnalysisKind::Sedov | AnalysisKind::Noh | AnalysisKind::Reflection | AnalysisKind::Detonation
            )
        {
            // the measures of the current state; a detonation's history over the outputs (and
            // the current state, when it is not the last output)
            let f = analysis::verify::frame_of(sim);
            let mut frames: Vec<&crate::output::Frame> =
                self.det_frames.iter().filter(|g| g.time < f.time * (1.0 - 1e-12)).collect();
            frames.push(&f);
            let frames: Vec<crate::output::Frame> = frames.into_iter().cloned().collect();
            if let Ok((v, _)) = analysis::verify::measure(&sim.case, &frames, &sim.x_init) {
                summary["verification"] = v;
            }
        }
        if !self.gauges.names.is_empty() {
            summary["gauges"] = json!(self.gauges.summary());
        }
        if ranks::size() > 1 {
            // rank 0's share of the work split across the ranks of an mpirun
            summary["ranks"] = json!({ "count": ranks::size(), "rank0": ranks::traffic() });
        }
        if made && sim.case.analysis.kind == AnalysisKind::Crater {
            match analysis::crater::measure(sim) {
                Ok(c) => {
                    summary["crater"] = serde_json::to_value(&c).unwrap_or(serde_json::Value::Null);
                    summary["crater"]["measured"] = json!(true);
                    summary["ejecta_height_m"] = json!(c.ejecta_height_m);
                }
                Err(why) => summary["crater"] = json!({ "measured": false, "reason": why }),
            }
        }
        let text = serde_json::to_string_pretty(&summary).unwrap_or_default();
        rundir::write_atomic(&self.dir.join("summary.json"), text.as_bytes())?;
        Ok(summary)
    }
}

/// A legacy STOP ends the process inside a step: the bridge's exit handler then marks the run's
/// summary with the step reached. Nothing without the bridge.
mod legacy_watch {
    use crate::sim::Sim;
    use std::path::Path;

    pub struct Watch;

    impl Watch {
        #[cfg(feature = "legacy")]
        pub fn start(sim: &Sim, dir: &Path) -> Option<Watch> {
            (!sim.plan.legacy.is_null()).then(|| {
                crate::migration::ffi::report_exit_to(Some(dir.join("summary.json")));
                crate::migration::ffi::report_progress(sim.nstep, sim.t);
                Watch
            })
        }
        #[cfg(not(feature = "legacy"))]
        pub fn start(_sim: &Sim, _dir: &Path) -> Option<Watch> {
            None
        }
        pub fn progress(&self, _sim: &Sim) {
            #[cfg(feature = "legacy")]
            crate::migration::ffi::report_progress(_sim.nstep, _sim.t);
        }
    }

    #[cfg(feature = "legacy")]
    impl Drop for Watch {
        fn drop(&mut self) {
            crate::migration::ffi::report_exit_to(None);
        }
    }
}
