//! `blastsph bench --ranks N,M`: every run of the matrix under `mpirun -np N` for each N, with
//! this same binary, timed from the summary.json of rank 0.

use crate::error::{IoAt, Result, SphError, input};

use super::BenchOutput;
use super::matrix::{CaseFile, Planned, k_tag};
use super::options::{BenchOptions, nnps_name};
use super::output::{e3, g2, g3, wall};
use serde::Serialize;
use serde_json::{Value, json};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// One run under mpirun: its rank count and what it cost.
#[derive(Debug, Clone, Serialize)]
pub struct RankRow {
    pub case: String,
    pub k: f64,
    pub particles: usize,
    pub backend: String,
    pub nnps: String,
    pub kernel: String,
    /// `mpirun -np` of the run.
    pub ranks: usize,
    pub steps: Option<u64>,
    /// Rank 0's wall time of the solver (summary.json `wall_seconds`), the fastest of `--repeat`.
    pub wall_s: Option<f64>,
    pub wall_s_runs: Vec<f64>,
    pub particle_steps_per_s: Option<f64>,
    /// particle-steps/s over that of the same configuration on one rank.
    pub speedup_vs_1: Option<f64>,
    /// Rank 0's seconds in the gathers of split row loops over its wall time (absent on one rank).
    pub comm_share: Option<f64>,
    pub dir: String,
}

/// The `mpirun` on the PATH, or a one-line refusal.
pub(super) fn find_mpirun() -> Result<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path).map(|d| d.join("mpirun")).find(|p| p.is_file()).ok_or_else(|| {
        input("--ranks: no `mpirun` on the PATH; install an MPI (scripts/setup installs Open MPI) or drop --ranks")
    })
}

/// One run of `p` on `np` ranks into its folder; rank 0's summary.json.
fn run_np(
    mpirun: &Path,
    exe: &Path,
    p: &Planned,
    cf: &CaseFile,
    o: &BenchOptions,
    np: usize,
    dir: &Path,
) -> Result<Value> {
    let mut c = Command::new(mpirun);
    c.args(["-np", &np.to_string()]).arg(exe).arg("run").arg(&cf.path);
    c.args(["--out"]).arg(dir).args(["--force", "--quiet", "--backend", p.backend.name(), "--nnps", nnps_name(p.nnps)]);
    for s in &p.sets {
        c.args(["--set", s]);
    }
    if let Some(t) = o.end_time {
        c.args(["--end-time", &t.to_string()]);
    }
    if let Some(t) = o.threads {
        c.args(["--threads", &t.to_string()]);
    }
    let out = c.output().io_at(format!("cannot start {}", mpirun.display()))?;
    let s = std::fs::read_to_string(dir.join("summary.json")).unwrap_or_default();
    let summary: Value = serde_json::from_str(&s).unwrap_or(Value::Null);
    if !out.status.success() && summary["status"].as_str() != Some("unstable") {
        let err = String::from_utf8_lossy(&out.stderr);
        let last = err.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("no message");
        return Err(SphError::Io(format!("{} on {np} ranks: mpirun ended with {} ({last})", p.case, out.status)));
    }
    Ok(summary)
}

/// Runs every cell of the matrix on each rank count of `--ranks`, and writes ranks.csv,
/// bench.json and bench.md into `o.out`.
pub(super) fn bench_ranks(
    o: &BenchOptions,
    cases: &[CaseFile],
    cells: &[Planned],
    warnings: Vec<String>,
) -> Result<BenchOutput> {
    let mpirun = find_mpirun()?;
    let exe = std::env::current_exe().io_at("cannot find the blastsph binary")?;
    std::fs::create_dir_all(&o.out).io_at(o.out.display())?;
    std::fs::write(o.out.join("bench.json"), "{\"status\": \"running\"}\n").io_at(o.out.display())?;
    let (date, unix) = super::utc_now();
    let commit = super::commit();
    let mut rows: Vec<RankRow> = Vec::new();
    for p in cells.iter().filter(|p| p.skip.is_none()) {
        let mut one: Option<f64> = None;
        for &np in &o.ranks {
            let dir = PathBuf::from(format!("{}_np{np}", p.dir.display()));
            let mut best: Option<Value> = None;
            let mut runs = Vec::new();
            for _ in 0..o.repeat {
                let s = run_np(&mpirun, &exe, p, &cases[p.ci], o, np, &dir)?;
                let w = s["wall_seconds"].as_f64();
                runs.extend(w);
                if best.as_ref().is_none_or(|b| w.zip(b["wall_seconds"].as_f64()).is_some_and(|(a, b)| a < b)) {
                    best = Some(s);
                }
            }
            let s = best.unwrap_or(Value::Null);
            let wall_s = s["wall_seconds"].as_f64();
            let rate = s["particle_steps_per_second"].as_f64();
            if np == 1 {
                one = rate;
            }
            let comm = s["ranks"]["rank0"]["gather_seconds"].as_f64().zip(wall_s).map(|(g, w)| g / w);
            let row = RankRow {
                case: p.case.clone(),
                k: p.k,
                particles: p.particles,
                backend: p.backend.name().into(),
                nnps: nnps_name(p.nnps).into(),
                kernel: p.kernel.name().into(),
                ranks: np,
                steps: s["steps"].as_u64(),
                wall_s,
                wall_s_runs: runs,
                particle_steps_per_s: rate,
                speedup_vs_1: rate.zip(one).map(|(r, b)| r / b),
                comm_share: comm,
                dir: dir.display().to_string(),
            };
            eprintln!(
                "{} k = {} {}/{}/{} on {np} ranks: {} s, {} particle-steps/s",
                row.case,
                k_tag(row.k),
                row.backend,
                row.nnps,
                row.kernel,
                wall(row.wall_s),
                e3(row.particle_steps_per_s)
            );
            rows.push(row);
        }
    }
    let text = table(&rows, &warnings);
    let meta = super::meta(
        &date,
        unix,
        &commit,
        json!({
            "ranks": o.ranks,
            "threads_per_rank": o.threads,
            "end_time_s": o.end_time,
            "repeat": o.repeat,
            "sets": o.sets,
        }),
    );
    let mut files = Vec::new();
    let mut write = |name: &str, body: &str| -> Result<()> {
        let p = o.out.join(name);
        std::fs::write(&p, body).io_at(p.display())?;
        files.push(p);
        Ok(())
    };
    write("ranks.csv", &csv(&rows))?;
    let js = json!({ "bench": meta, "rank_runs": rows, "warnings": warnings });
    write("bench.json", &serde_json::to_string_pretty(&js).unwrap_or_default())?;
    write("bench.md", &text)?;
    Ok(BenchOutput { rows: Vec::new(), families: Vec::new(), warnings, text, files })
}

/// The columns of ranks.csv.
pub const RANK_COLUMNS: [&str; 12] = [
    "case",
    "k",
    "particles",
    "backend",
    "nnps",
    "kernel",
    "ranks",
    "steps",
    "wall_s",
    "particle_steps_per_s",
    "speedup_vs_1",
    "comm_share",
];

fn csv(rows: &[RankRow]) -> String {
    let f = super::output::f;
    let mut s = RANK_COLUMNS.join(",") + "\n";
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{}",
            r.case,
            r.k,
            r.particles,
            r.backend,
            r.nnps,
            r.kernel,
            r.ranks,
            r.steps.map_or(String::new(), |n| n.to_string()),
            f(r.wall_s),
            f(r.particle_steps_per_s),
            f(r.speedup_vs_1),
            f(r.comm_share)
        );
    }
    s
}

fn table(rows: &[RankRow], warnings: &[String]) -> String {
    let mut s = String::from("## Ranks (mpirun -np N)\n\n");
    s += "| case | k | particles | backend/nnps/kernel | ranks | steps | wall (s) | particle-steps/s | vs 1 rank | gathers / wall |\n";
    s += "|---|---|---|---|---|---|---|---|---|---|\n";
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {}/{}/{} | {} | {} | {} | {} | {} | {} |",
            r.case,
            k_tag(r.k),
            r.particles,
            r.backend,
            r.nnps,
            r.kernel,
            r.ranks,
            r.steps.map_or("-".into(), |n| n.to_string()),
            wall(r.wall_s),
            e3(r.particle_steps_per_s),
            g2(r.speedup_vs_1),
            g3(r.comm_share)
        );
    }
    for w in warnings {
        let _ = writeln!(s, "\nwarning: {w}");
    }
    s
}
