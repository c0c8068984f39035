//! Checkpoints and `blastsph resume` (docs/reference/output.md "Checkpoints and resume").
//!
//! A checkpoint (`checkpoint.bin`, replaced atomically each time) holds the solver's state
//! ([`Sim::save_state`]), the run loop's (`Loop`: output schedule, peaks, gauge records,
//! energies at t = 0), what particles.h5 and gauges.csv held when it was written, and a header
//! (JSON) naming the binary and the case that wrote it. Resuming rebuilds the simulation from the
//! run directory's case.toml exactly as the run built it, puts the state back, cuts particles.h5
//! and gauges.csv back to the checkpoint (a run killed later may have written more), and goes on:
//! every output after the checkpoint is bitwise the uninterrupted run's.

use crate::error::{IoAt, Result, SphError, input};
use crate::gauges::Gauges;
use crate::modules::Backend;
use crate::output::{H5Part, Peaks};
use crate::rundir::sha256_hex;
use crate::runner::{Checkpoints, Energy, Loop, RunOptions, RunResult};
use crate::sim::checkpoint::{Blob, Item};
use crate::sim::{Overrides, Sim};
use serde_json::{Value, json};
use std::path::Path;
use std::time::Instant;

/// The checkpoint's file name in a run directory.
pub const FILE: &str = "checkpoint.bin";

/// SHA-256 of this program's executable (what "the binary changed" compares), or "unknown".
pub(crate) fn binary_sha256() -> String {
    static SUM: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    SUM.get_or_init(|| {
        use sha2::{Digest, Sha256};
        use std::io::Read;
        let Ok(exe) = std::env::current_exe() else { return "unknown".into() };
        let Ok(mut f) = std::fs::File::open(exe) else { return "unknown".into() };
        let mut h = Sha256::new();
        let mut buf = vec![0u8; 1 << 20];
        loop {
            match f.read(&mut buf) {
                Ok(0) => break,
                Ok(k) => h.update(&buf[..k]),
                Err(_) => return "unknown".into(),
            }
        }
        h.finalize().iter().map(|b| format!("{b:02x}")).collect()
    })
    .clone()
}

/// Writes the checkpoint of `lp` (after syncing gauges.csv, whose length it records).
pub(crate) fn write(lp: &mut Loop) -> Result<()> {
    // the executable's checksum first (hashed once, 40 ms for the release binary): the wall time
    // stamped below then includes it, so that a resumed run's total is not short of it
    let _ = binary_sha256();
    lp.gauges.sync()?;
    lp.h5.sync_xdmf()?;
    let gpath = lp.dir.join("gauges.csv");
    let gauges_bytes = std::fs::symlink_metadata(&gpath).map(|m| m.len()).unwrap_or(0);
    let mut b = Blob::default();
    lp.sim.save_state(&mut b);
    lp.h5.save(&mut b);
    lp.gauges.save(&mut b);
    b.put_f64("run.peaks.ppv", &lp.peaks.ppv);
    b.put_f64("run.peaks.p_peak", &lp.peaks.p_peak);
    let e = lp.e0;
    b.put_f64("run.e0", &[e.kinetic, e.internal, e.elastic, e.total]);
    b.put_f64("run.scalars", &[lp.next_out, lp.m0, lp.wall()]);
    b.put("run.last_written", Item::U64(vec![lp.last_written]));
    b.put_f64("run.resumes.t", &lp.resumes.iter().map(|r| r.1).collect::<Vec<_>>());
    b.put("run.resumes.step", Item::U64(lp.resumes.iter().map(|r| r.0).collect()));
    b.put_text("run.resumes.changed", &json!(lp.resume_changes).to_string());
    let plan = &lp.sim.plan;
    let backends: serde_json::Map<String, Value> =
        plan.modules.iter().map(|(m, p)| (m.name().to_string(), json!(p.backend.name()))).collect();
    let meta = json!({
        "format": "blastsph checkpoint",
        "version": env!("CARGO_PKG_VERSION"),
        "binary_sha256": binary_sha256(),
        "case": lp.sim.case.name(),
        "case_toml_sha256": lp.case_toml_sha,
        "case_sha256": lp.case_sha,
        "sets": lp.sets,
        "backends": backends,
        "step": lp.sim.nstep,
        "time": lp.sim.t,
        "gauges_csv_bytes": gauges_bytes,
        "gauges": gauge_defs(&lp.sim.case),
    });
    b.put_text("run.meta", &meta.to_string());
    crate::rundir::write_atomic_with(&lp.dir.join(FILE), |w| b.encode_to(w))
}

/// The gauges as a checkpoint records them (name, kind, point): a resume that would carry a
/// gauge's record over to another point or name is refused.
fn gauge_defs(case: &crate::case::Case) -> Value {
    json!(
        case.gauges
            .iter()
            .map(|g| json!({"name": g.name, "kind": format!("{:?}", g.kind).to_lowercase(), "point_m": g.point_m}))
            .collect::<Vec<_>>()
    )
}

/// What `blastsph resume` is given.
#[derive(Debug, Clone, Default)]
pub struct ResumeOptions {
    /// A new end time (s), beyond the checkpoint's time: case.toml's `time.end_s` is changed.
    pub end_time: Option<f64>,
    /// Continue although the case or the binary changed since the checkpoint.
    pub allow_changed: bool,
    pub quiet: bool,
    pub checkpoints: Checkpoints,
    pub max_particles: Option<u64>,
    /// Stop cleanly after this step (as a signal would).
    pub stop_after_step: Option<u64>,
}

impl ResumeOptions {
    /// A `run` that finds its own restart in its folder continues it with its own options.
    pub(crate) fn of_run(o: &RunOptions) -> ResumeOptions {
        ResumeOptions {
            end_time: None,
            allow_changed: false,
            quiet: o.quiet,
            checkpoints: o.checkpoints,
            max_particles: o.ov.max_particles,
            stop_after_step: o.stop_after_step,
        }
    }
}

/// Reads and checks the checkpoint of run directory `dir`: its bytes, its header.
pub fn read(dir: &Path) -> Result<(Blob<'static>, Value)> {
    let path = dir.join(FILE);
    let shown = dir.display();
    let bytes = match std::fs::read(&path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(input(format!(
                "resume {shown}: no {FILE} (the run wrote no checkpoint: it was killed before its first, or ran without them)"
            )));
        }
        Err(e) => return Err(input(format!("resume {shown}: {FILE}: {e}"))),
    };
    let blob = Blob::decode(&bytes).map_err(|e| input(format!("resume {shown}: {e}")))?;
    let meta: Value = serde_json::from_str(&blob.text("run.meta")?)
        .map_err(|e| input(format!("resume {shown}: {FILE}: a header that is not JSON ({e})")))?;
    Ok((blob, meta))
}

/// Continues the run in `dir` from its checkpoint (`blastsph resume DIR`).
pub fn resume(dir: &Path, o: &ResumeOptions) -> Result<RunResult> {
    let ro = RunOptions {
        quiet: o.quiet,
        checkpoints: o.checkpoints,
        stop_after_step: o.stop_after_step,
        ..Default::default()
    };
    if !crate::modules::ranks::is_root() {
        return super::follow::resume(&ro);
    }
    // under mpirun the other ranks build their solvers from the case as rank 0 resumes it
    let ready = prepare(dir, o);
    let text = ready.as_ref().map(|r| r.1.clone()).unwrap_or_default();
    let (lp, _, _lock) = super::follow::settle_resume(ready, dir, &text, o.max_particles)?;
    lp.go(&ro)
}

/// The solver of a resumed run, as a rank other than 0 builds it: the case as rank 0 resumes
/// it (`text`), the checkpoint of `dir`.
pub(super) fn solver_of(dir: &Path, text: &str, max_particles: Option<u64>) -> Result<Sim> {
    let (blob, meta) = read(dir)?;
    let name = meta["case"].as_str().unwrap_or("case");
    let case = crate::case::parse(text, &dir.join("case.toml").display().to_string(), &[], Some(name))?;
    let mut sim = Sim::new(case, &overrides_of(&meta, max_particles))?;
    sim.restore_state(&blob)?;
    Ok(sim)
}

/// Everything `resume` checks and prepares before its time loop: the run, the case as resumed,
/// and the lock held until the run ends.
fn prepare(dir: &Path, o: &ResumeOptions) -> Result<(Loop, String, crate::rundir::DirLock)> {
    let shown = dir.display().to_string();
    crate::rundir::check_existing(dir, "resume")?;
    // held until the resumed run ends (two resumes of one folder both ran; the later one failed
    // at its end)
    let lock = crate::rundir::lock_run(dir, "resume")?;
    let (blob, meta) = read(dir)?;
    let case_path = dir.join("case.toml");
    let text = crate::case::read_text(&case_path).map_err(|e| input(format!("resume {shown}: {e}")))?;

    // what changed since the checkpoint
    let changed = changes(&meta, &text);
    if !changed.is_empty() && !o.allow_changed {
        return Err(input(format!(
            "resume {shown}: {} changed since the checkpoint: --allow-changed continues with it (the result is then not the uninterrupted run's)",
            changed.join(" and ")
        )));
    }
    let t_cp = blob.scalar("sim.t")?;
    let summary_status = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|s| serde_json::from_str::<Value>(&s).ok())
        .and_then(|v| v["status"].as_str().map(String::from));
    let text = with_end_time(o, text, (t_cp, &case_path), summary_status.as_deref(), &shown)?;
    let name = meta["case"].as_str().unwrap_or("case");
    let case = crate::case::parse(&text, &case_path.display().to_string(), &[], Some(name))?;
    let ov = overrides_of(&meta, o.max_particles);
    same_gauges(&meta, &case, &shown)?;
    let mut sim = Sim::new(case, &ov).map_err(|e| match e {
        SphError::Input(m) => input(format!("resume {shown}: {m}")),
        e => e,
    })?;
    sim.restore_state(&blob).map_err(|e| input(format!("resume {shown}: {e}")))?;

    // everything checked before anything is written: a refused resume leaves the folder as it was
    let gpath = dir.join("gauges.csv");
    let gbytes = meta["gauges_csv_bytes"].as_u64().unwrap_or(0);
    let gfile = if sim.case.gauges.is_empty() {
        None
    } else {
        let f = crate::rundir::open_rw(&gpath)?;
        let len = f.metadata().map(|m| m.len()).unwrap_or(0);
        if len < gbytes {
            return Err(input(format!(
                "resume {shown}: gauges.csv holds {len} bytes, fewer than the {gbytes} of the checkpoint (damaged)"
            )));
        }
        Some(f)
    };
    let n = sim.p.nreal;
    let peaks = Peaks { ppv: blob.f64("run.peaks.ppv")?, p_peak: blob.f64("run.peaks.p_peak")? };
    if peaks.ppv.len() != n || peaks.p_peak.len() != n {
        return Err(input(format!("resume {shown}: {FILE}: the peaks are not the particles'")));
    }
    let e = blob.f64("run.e0")?;
    let s = blob.f64("run.scalars")?;
    let (&[kinetic, internal, elastic, total], &[next_out, m0, wall_before]) = (e.as_slice(), s.as_slice()) else {
        return Err(input(format!("resume {shown}: {FILE}: the run's numbers are incomplete")));
    };
    let mut resumes: Vec<(u64, f64)> =
        blob.u64("run.resumes.step")?.into_iter().zip(blob.f64("run.resumes.t")?).collect();
    // (a checkpoint from before this record: nothing recorded as changed)
    let mut resume_changes: Vec<String> = blob
        .text("run.resumes.changed")
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .unwrap_or_else(|| vec![String::new(); resumes.len()]);
    resume_changes.resize(resumes.len(), String::new());
    resumes.push((sim.nstep, sim.t));
    resume_changes.push(changed.join(" and "));
    let last_written = blob.count("run.last_written")?;
    let gauges = Gauges::resume(&sim, Some(&gpath), &blob)?;
    // a detonation's history: its outputs up to the checkpoint (read before the file is cut)
    let det_frames = if sim.case.analysis.kind == crate::case::AnalysisKind::Detonation {
        // (a last step a kill left half-written is not read: it is past the checkpoint)
        crate::output::read_complete_frames(&dir.join("particles.h5"))?
            .0
            .into_iter()
            .filter(|f| f.time <= sim.t * (1.0 + 1e-12))
            .map(crate::analysis::verify::slim)
            .collect()
    } else {
        Vec::new()
    };
    // the files, cut back to the checkpoint (a run killed later may have written more):
    // particles.h5 first, since it is checked as it is opened
    let h5 = H5Part::resume(&dir.join("particles.h5"), &blob)?;
    if let Some(f) = gfile {
        f.set_len(gbytes).io_at("gauges.csv")?;
    }
    // a report of the run as it was (report.json, its plots), and its revolved points, no longer
    // describe it
    crate::rundir::remove_report(dir)?;
    crate::rundir::remove_revolved(dir)?;
    let case_toml_sha = sha256_hex(text.as_bytes());
    if o.end_time.is_some() {
        crate::rundir::write_atomic(&case_path, text.as_bytes())?;
    }
    let sets = meta["sets"]
        .as_array()
        .map(|a| a.iter().filter_map(|v| v.as_str().map(String::from)).collect())
        .unwrap_or_default();
    if !o.quiet {
        eprintln!("resume {shown}: from step {} (t = {:.6e} s) to t = {:e} s", sim.nstep, sim.t, sim.cfg.end);
    }
    let lp = Loop {
        sim,
        dir: dir.to_path_buf(),
        h5,
        gauges,
        peaks,
        e0: Energy { kinetic, internal, elastic, total },
        m0,
        next_out,
        last_written,
        wall_before,
        case_sha: meta["case_sha256"].as_str().unwrap_or("").to_string(),
        case_toml_sha,
        sets,
        resumes,
        resume_changes,
        start: Instant::now(),
        det_frames,
    };
    // summary.json at once, as a fresh run writes it: a run killed before its first checkpoint
    // must not keep the summary (and case.toml hash) of the run before the resume
    lp.write_summary(crate::runner::Status::Running, None)?;
    Ok((lp, text, lock))
}

/// What changed since the checkpoint: the case file (its SHA-256) and the binary.
fn changes(meta: &Value, text: &str) -> Vec<String> {
    let mut changed = Vec::new();
    let was = meta["case_toml_sha256"].as_str().unwrap_or("?");
    let now = sha256_hex(text.as_bytes());
    if was != now {
        changed.push(format!("the case (case.toml's SHA-256 is {}…, the checkpoint's {}…)", &now[..12], cut(was)));
    }
    let (bw, bn) = (meta["binary_sha256"].as_str().unwrap_or("?"), binary_sha256());
    if bw != bn {
        changed.push(format!(
            "the binary (blastsph {} {}… wrote the checkpoint; this is blastsph {} {}…)",
            meta["version"].as_str().unwrap_or("?"),
            cut(bw),
            env!("CARGO_PKG_VERSION"),
            cut(&bn)
        ));
    }
    changed
}

/// The case's text to resume with: with `--end-time`, the checkpoint's case with its new end
/// (marked); without, the case as it was, refused when the run finished.
fn with_end_time(
    o: &ResumeOptions,
    text: String,
    (t_cp, case_path): (f64, &Path),
    summary_status: Option<&str>,
    shown: &str,
) -> Result<String> {
    Ok(match o.end_time {
        Some(t) => {
            let max = crate::case::validate::T_MAX;
            if !(t.is_finite() && t <= max) {
                return Err(input(format!("--end-time {t}: must be a finite time in seconds, at most {max:e}")));
            }
            if t <= t_cp {
                return Err(input(format!(
                    "--end-time {t}: the checkpoint is at t = {t_cp:e} s already; give a later end"
                )));
            }
            // the text must parse first: its error names the file and line, as `check`'s does
            crate::case::parse(&text, &case_path.display().to_string(), &[], None)?;
            let body = crate::case::apply_sets_by(&text, &[format!("time.end_s={t:?}")], "resume --end-time")?;
            format!(
                "# Resumed with --end-time {t:?} from the checkpoint at t = {t_cp:e} s (time.end_s, marked below).\n{body}"
            )
        }
        None => {
            if summary_status == Some("ok") {
                return Err(input(format!(
                    "resume {shown}: the run finished (t = {t_cp:e} s); --end-time S extends it"
                )));
            }
            text
        }
    })
}

/// The backends the checkpointed run used, module by module.
fn overrides_of(meta: &Value, max_particles: Option<u64>) -> Overrides {
    let mut ov = Overrides { max_particles, ..Default::default() };
    // the case's [compat] table, as the run had it
    #[cfg(feature = "legacy")]
    {
        ov.bridge = Some(crate::migration::bridge(None, false));
    }
    if let Some(b) = meta["backends"].as_object() {
        for (m, v) in b {
            match v.as_str().and_then(Backend::parse) {
                Some(Backend::Rust) => ov.rust.push(m.clone()),
                Some(Backend::Fortran) => ov.fortran.push(m.clone()),
                None => {}
            }
        }
    }
    ov
}

/// Refused when a gauge changed its name, kind or point since the checkpoint.
fn same_gauges(meta: &Value, case: &crate::case::Case, shown: &str) -> Result<()> {
    // a gauge's record belongs to its point and name: --allow-changed does not move or rename it
    // (its record so far would be carried on under the new definition)
    if let Some(was) = meta["gauges"].as_array() {
        let now = gauge_defs(case);
        let now = now.as_array().map_or(&[][..], |v| v.as_slice());
        if was.len() == now.len()
            && let Some((a, b)) = was.iter().zip(now).find(|(a, b)| a != b)
        {
            return Err(input(format!(
                "resume {shown}: gauge `{}` ({} at {}) is now `{}` ({} at {}): a gauge's record so far would be carried on under another name, kind or point; resume with the gauges as they were (a new gauge needs a new run)",
                a["name"].as_str().unwrap_or("?"),
                a["kind"].as_str().unwrap_or("?"),
                a["point_m"],
                b["name"].as_str().unwrap_or("?"),
                b["kind"].as_str().unwrap_or("?"),
                b["point_m"]
            )));
        }
    }
    Ok(())
}

/// The first 12 characters of a checksum.
fn cut(s: &str) -> &str {
    s.get(..12).unwrap_or(s)
}
