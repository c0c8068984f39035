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

use analysis::analyse;
use matrix::family_label;
use matrix::k_tag;
use matrix::plan;
use matrix::read_cases;
use options::nnps_name;
use output::csv;
use output::e3;
use output::plots;
use output::tables;
use output::wall;
use run::analysis_name;
use run::primary_name;
use run::run_one;

mod analysis;
mod matrix;
mod options;
mod output;

mod ranks;
mod run;

pub use crate::case::refine::{refine, refinement_sets};
pub use analysis::{Family, Order, exact_order, self_order};
pub use matrix::Planned;
pub use options::{BenchArgs, BenchOptions};
pub use output::CSV_COLUMNS;
pub use ranks::{RANK_COLUMNS, RankRow};
pub use run::{GaugePeak, Row};

use crate::error::{IoAt, Result};
use serde_json::json;
use std::fmt::Write as _;
use std::path::PathBuf;

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

/// Date and time now, in UTC ("YYYY-MM-DD hh:mm:ss UTC"), and the Unix time.
pub(super) fn utc_now() -> (String, u64) {
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

/// bench.json's `bench`: when, which commit and which machine, then the keys of `more` (an
/// object) that say what was run.
pub(super) fn meta(date: &str, unix: u64, commit: &Option<String>, more: serde_json::Value) -> serde_json::Value {
    let mut m = json!({
        "date_utc": date,
        "unix_time": unix,
        "commit": commit,
        "version": env!("CARGO_PKG_VERSION"),
        "cores": std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1),
    });
    if let (Some(m), serde_json::Value::Object(more)) = (m.as_object_mut(), more) {
        m.extend(more);
    }
    m
}

/// The commit of the working tree, if git can tell (with "-dirty" when it has changes).
pub(super) fn commit() -> Option<String> {
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

pub(super) fn dry_run_text(cells: &[Planned], warnings: &[String]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "blastsph bench --dry-run: {} runs\n", cells.len());
    let _ = writeln!(
        s,
        "| # | case | k | dx (m) | particles | k^dim × unrefined | backend | nnps | kernel | threads | run |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|");
    for (i, c) in cells.iter().enumerate() {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.4e} | {} | {}{} | {} | {} | {} | {} | {} |",
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
            // the run's own pool, the Fortran core's one, or the bench's pool
            match (c.threads, c.backend) {
                (Some(t), _) => t.to_string(),
                (None, crate::modules::Backend::Fortran) => "1".into(),
                (None, _) => "pool".into(),
            },
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
    if !o.ranks.is_empty() {
        return ranks::bench_ranks(o, &cases, &cells, warnings);
    }
    std::fs::create_dir_all(&o.out).io_at(o.out.display())?;
    // the folder is a bench's from now on (a bench stopped half-way can be run again into it):
    // bench.json says so until the results replace it
    std::fs::write(o.out.join("bench.json"), "{\"status\": \"running\"}\n").io_at(o.out.display())?;
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
            family_label(c.backend.name(), nnps_name(c.nnps), c.kernel.name(), c.threads)
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
    let meta = meta(
        &date,
        unix,
        &commit,
        json!({
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
        }),
    );
    let text = tables(&rows, &families, &warnings, &meta);
    let mut files = Vec::new();
    let write = |name: &str, body: &str, files: &mut Vec<PathBuf>| -> Result<()> {
        let p = o.out.join(name);
        std::fs::write(&p, body).io_at(p.display())?;
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
