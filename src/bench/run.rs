//! One run of the matrix and what it measures.

use crate::error::Result;
use crate::error::input;
use serde::Serialize;

use super::matrix::CaseFile;
use super::matrix::Planned;
use super::matrix::family_label;
use super::options::BenchOptions;
use super::options::nnps_name;
use crate::case::AnalysisKind;
use crate::error::SphError;
use crate::modules::Backend;
use crate::output::read_frames;
use crate::report::L1;
use crate::report::l1_errors;
use crate::report::riemann_of;
use crate::runner;
use crate::runner::RunOptions;
use crate::sim::Overrides;
use serde_json::Value;
use std::collections::BTreeMap;

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
    /// The thread count of this row when `--threads` was a list (an axis of the matrix: the
    /// row's configuration includes it), else absent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub thread_axis: Option<usize>,
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

/// A configuration: case, backend, search, kernel, and the thread count when it is an axis.
pub(super) type Key = (String, String, String, String, Option<usize>);

impl Row {
    pub(super) fn family(&self) -> Key {
        (self.case.clone(), self.backend.clone(), self.nnps.clone(), self.kernel.clone(), self.thread_axis)
    }
    pub(super) fn label(&self) -> String {
        family_label(&self.backend, &self.nnps, &self.kernel, self.thread_axis)
    }
    pub(super) fn ok(&self) -> bool {
        self.status == "ok"
    }
    /// The measured quantities q of the run, by name.
    pub(super) fn quantities(&self) -> Vec<(String, f64)> {
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
    pub(super) fn quantity(&self, name: &str) -> Option<f64> {
        self.quantities().into_iter().find(|(n, _)| n == name).map(|(_, v)| v)
    }
    /// The error the Pareto front and the summary plot use: L1 of ρ against the exact solution
    /// (Riemann), the crater depth against the reference (blast).
    pub(super) fn primary(&self) -> Option<f64> {
        match self.analysis.as_str() {
            "riemann" => self.l1.map(|l| l.rho),
            "crater" => self.err_ref.get("crater_depth").copied(),
            _ => None,
        }
    }
}

pub(super) fn primary_name(analysis: &str) -> &'static str {
    match analysis {
        "riemann" => "L1 error of rho against the exact solution",
        "crater" => "crater depth: relative error against the finest run",
        _ => "(no error measure)",
    }
}

pub(super) fn analysis_name(k: AnalysisKind) -> &'static str {
    k.name()
}

/// CPU time of this process so far (s): utime + stime of /proc/self/stat, in clock ticks of
/// USER_HZ = 100 per second (fixed for /proc on Linux). None where there is no /proc.
pub(super) fn cpu_seconds() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/stat").ok()?;
    // the command name (field 2) is in parentheses and may hold spaces: count from after it
    let rest = &s[s.rfind(')')? + 1..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    // fields 14 and 15 of the line are the 12th and 13th after the name
    let (u, k): (f64, f64) = (f.get(11)?.parse().ok()?, f.get(12)?.parse().ok()?);
    Some((u + k) / 100.0)
}

/// The 1-minute load average (Linux: /proc/loadavg).
pub(super) fn load_avg() -> Option<f64> {
    std::fs::read_to_string("/proc/loadavg").ok()?.split_whitespace().next()?.parse().ok()
}

/// Stack of a row's own pool's threads (the run executes on one of them, as on the CLI's pool).
const STACK_BYTES: usize = 16 << 20;

pub(super) fn run_one(p: &Planned, cf: &CaseFile, o: &BenchOptions) -> Result<Row> {
    // a row of a `--threads` list runs on its own pool of that many threads
    let own = match p.threads {
        Some(t) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .stack_size(STACK_BYTES)
                .build()
                .map_err(|e| input(format!("--threads {t}: {e}")))?,
        ),
        None => None,
    };
    let pool = own.as_ref().map_or_else(rayon::current_num_threads, |p| p.current_num_threads());
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
        thread_axis: p.threads,
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
        threads: p.threads.or(o.threads),
        // the bench's folders are its own: each run replaces its last
        force: true,
        ..Default::default()
    };
    row.load_avg = load_avg();
    let cpu0 = cpu_seconds();
    let result = match &own {
        Some(pool) => pool.install(|| runner::run(&cf.path, &opts)),
        None => runner::run(&cf.path, &opts),
    };
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
        _ => {}
    }
    Ok(row)
}
