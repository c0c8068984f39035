//! The defect ledger (`blastsph legacy ledger CASE --legacy DIR [--compat PROFILE]`): what each
//! compatibility item does to the result. It runs the case
//!
//! 1. with the user's routines (`run --legacy`: the legacy code, with the profile's Rust twins
//!    for what the manifest does not map, such as the time integration),
//! 2. with the profile's Rust twins only (the user's set-up routine, if mapped, gives the
//!    initial particles: both runs start from the same state),
//! 3. with the profile less one item, for each item the profile switches on,
//! 4. with no item (blastsph's own twins),
//!
//! and tabulates, for each run, the largest difference of ρ, v, p and e at the end from run 2,
//! particle by particle (by particle id), and the case's own error where it has one (the
//! volume-weighted L1 of ρ, v, p, e against the exact solution of a Riemann case). Row 1 against
//! row 2 is the claim "the Rust code reproduces the old code": 0 everywhere when every mapped
//! routine is matched. Each row 3 is one deliberate change and its effect. Results go to
//! `OUT/ledger.json`.

use super::compat::{Flags, Item};
use crate::case::{AnalysisKind, Case, StepRule};
use crate::error::{Result, SphError};
use crate::sim::Sim;
use crate::sim::plan::Overrides;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The state at the end of one run, real particles in id order.
struct End {
    steps: u64,
    t: f64,
    x: Vec<f64>,
    v: Vec<f64>,
    rho: Vec<f64>,
    p: Vec<f64>,
    e: Vec<f64>,
    mass: Vec<f64>,
    id: Vec<i64>,
    dim: usize,
}

/// One row of the ledger.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    /// "legacy", "profile", "-ITEM" (the profile less ITEM) or "none".
    pub run: String,
    /// The items on in this run, comma-separated.
    pub items: String,
    /// What the row is.
    pub what: String,
    pub steps: u64,
    pub time: f64,
    /// Largest |Δ| at the end against the profile run: ρ (kg/m³), v (m/s), p (Pa), e (J/kg).
    pub max_abs_rho: f64,
    pub max_abs_v: f64,
    pub max_abs_p: f64,
    pub max_abs_e: f64,
    /// Particles whose ρ, v, p or e differ at all from the profile run.
    pub particles_differing: usize,
    /// The case's own error (Riemann cases): volume-weighted L1 of ρ, v, p, e against the
    /// exact solution over the case's window; absent for other cases.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub l1: Option<[f64; 4]>,
    /// Why the run did not reach the end (a case that goes unstable without an item): the
    /// differences are then not measured (zeros).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failed: Option<String>,
}

/// Runs the case to its end (a fixed step: the number of steps `run` takes, round(end/dt)).
fn run_to_end(case: Case, ov: &Overrides) -> Result<End> {
    let mut sim = Sim::new(case, ov)?;
    let fixed = (sim.cfg.step == StepRule::Fixed).then(|| (sim.cfg.end / sim.cfg.dt_fixed).round().max(1.0) as u64);
    loop {
        let done = match fixed {
            Some(n) => sim.nstep >= n,
            None => sim.t >= sim.cfg.end * (1.0 - 1e-12),
        };
        if done {
            break;
        }
        sim.step()?;
    }
    let (n, dim) = (sim.p.nreal, sim.p.dim);
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&i| sim.p.id.get(i).copied().unwrap_or(i as i64));
    let pick = |a: &[f64], w: usize| -> Vec<f64> { order.iter().flat_map(|&i| a[w * i..w * i + w].to_vec()).collect() };
    Ok(End {
        steps: sim.nstep,
        t: sim.t,
        x: pick(&sim.p.x, dim),
        v: pick(&sim.p.v, dim),
        rho: pick(&sim.p.rho, 1),
        p: pick(&sim.p.p, 1),
        e: pick(&sim.p.e, 1),
        mass: pick(&sim.p.mass, 1),
        id: order.iter().map(|&i| sim.p.id.get(i).copied().unwrap_or(i as i64)).collect(),
        dim,
    })
}

/// The case with `flags` as its `[compat]` table.
fn with_flags(case: &Case, flags: Flags) -> Case {
    let mut c = case.clone();
    c.compat.profile = Some("none".into());
    c.compat.items = Item::all().filter(|&i| flags.has(i)).map(|i| (i.name().to_string(), true)).collect();
    c
}

/// One run's end state as the L1 errors read it, real particles in id order: time (s),
/// positions (m), velocities (m/s), densities (kg/m³), pressures (Pa), specific internal energies
/// (J/kg) and masses (kg).
pub struct EndState<'a> {
    pub t: f64,
    pub x: &'a [f64],
    pub v: &'a [f64],
    pub rho: &'a [f64],
    pub p: &'a [f64],
    pub e: &'a [f64],
    pub mass: &'a [f64],
}

/// The L1 errors (ρ, v, p, e) of a 1D Riemann case's end state against its exact solution: the
/// caller's, as the exact solution belongs to a layer above the bridge.
pub type L1 = fn(&Case, &EndState<'_>) -> Result<[f64; 4]>;

/// The L1 errors of a Riemann case against its exact solution (`None` for other cases).
fn l1(case: &Case, e: &End, l1_errors: L1) -> Result<Option<[f64; 4]>> {
    if case.analysis.kind != AnalysisKind::Riemann || e.dim != 1 {
        return Ok(None);
    }
    let s = EndState { t: e.t, x: &e.x, v: &e.v, rho: &e.rho, p: &e.p, e: &e.e, mass: &e.mass };
    Ok(Some(l1_errors(case, &s)?))
}

fn row(run: &str, what: String, flags: Flags, e: &End, base: &End, l1: Option<[f64; 4]>) -> Result<Row> {
    if e.id != base.id {
        return Err(SphError::Input(format!(
            "ledger: run `{run}` ends with other particles than the profile run ({} against {})",
            e.id.len(),
            base.id.len()
        )));
    }
    let d = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    let dim = e.dim;
    let differing = (0..e.id.len())
        .filter(|&i| {
            e.rho[i] != base.rho[i]
                || e.p[i] != base.p[i]
                || e.e[i] != base.e[i]
                || (0..dim).any(|k| e.v[dim * i + k] != base.v[dim * i + k])
        })
        .count();
    Ok(Row {
        run: run.to_string(),
        items: if flags.is_empty() { "-".into() } else { flags.names() },
        what,
        steps: e.steps,
        time: e.t,
        max_abs_rho: d(&e.rho, &base.rho),
        max_abs_v: d(&e.v, &base.v),
        max_abs_p: d(&e.p, &base.p),
        max_abs_e: d(&e.e, &base.e),
        particles_differing: differing,
        l1,
        failed: None,
    })
}

/// A row of a run that stopped before the end: `err` says why.
fn failed_row(run: &str, what: String, flags: Flags, err: &SphError) -> Row {
    Row {
        run: run.to_string(),
        items: if flags.is_empty() { "-".into() } else { flags.names() },
        what,
        steps: 0,
        time: 0.0,
        max_abs_rho: 0.0,
        max_abs_v: 0.0,
        max_abs_p: 0.0,
        max_abs_e: 0.0,
        particles_differing: 0,
        l1: None,
        failed: Some(err.to_string()),
    }
}

/// The row of a comparison run, or the row saying why it stopped (an item the case cannot do
/// without: the run goes unstable).
fn row_or_failed(
    run: &str,
    what: String,
    flags: Flags,
    end: Result<End>,
    base: &End,
    (case, l1_errors): (&Case, L1),
) -> Result<Row> {
    match end {
        Ok(e) => row(run, what, flags, &e, base, l1(case, &e, l1_errors)?),
        Err(err) => Ok(failed_row(run, what, flags, &err)),
    }
}

/// Runs the ledger of `case` against the legacy build `legacy`, with the case's compat profile
/// (`liu-book` when the case says nothing of compat: no `[compat]` key and no `--compat`; a case
/// that names the profile `none`, or turns every item off, gets the ledger against blastsph's own
/// twins); writes `out/ledger.json` and returns the table. `l1_errors` gives a Riemann case's L1
/// errors.
pub fn ledger(case: &Case, legacy: &Path, out: &Path, l1_errors: L1) -> Result<(Vec<Row>, String)> {
    let mut profile = super::compat::flags(&case.compat)?;
    if case.compat.profile.is_none() && case.compat.items.is_empty() {
        profile = Flags::profile("liu-book").unwrap_or_default();
    }
    // one bridge for every run of the ledger: a set-up warning is said once, not once per row
    let said = std::sync::Arc::new(std::sync::Mutex::new(std::collections::BTreeSet::new()));
    let ov = |setup_only: bool| -> Overrides {
        let b = super::LegacyBridge {
            dir: Some(legacy.to_path_buf()),
            setup_only,
            scratch: false,
            said: said.clone(),
            ..Default::default()
        };
        Overrides { bridge: Some(std::sync::Arc::new(b)), ..Default::default() }
    };
    // the legacy code first: its SAVEd locals and COMMON blocks start as in its own program
    let leg = run_to_end(with_flags(case, profile), &ov(false))?;
    let base = run_to_end(with_flags(case, profile), &ov(true))?;
    let mut rows = vec![
        row(
            "legacy",
            format!("your routines (run --legacy), compat {} for the rest", profile.label()),
            profile,
            &leg,
            &base,
            l1(case, &leg, l1_errors)?,
        )?,
        row(
            "profile",
            format!("the Rust twins, compat {}", profile.label()),
            profile,
            &base,
            &base,
            l1(case, &base, l1_errors)?,
        )?,
    ];
    for item in Item::all().filter(|&i| profile.has(i)) {
        let f = profile.with(item, false);
        let e = run_to_end(with_flags(case, f), &ov(true));
        let what = super::compat::ITEMS.iter().find(|t| t.0 == item).map_or("", |t| t.3);
        rows.push(row_or_failed(&format!("-{}", item.name()), what.to_string(), f, e, &base, (case, l1_errors))?);
    }
    // (against an empty profile, the row `profile` is blastsph's own twins already)
    if !profile.is_empty() {
        let none = run_to_end(with_flags(case, Flags::default()), &ov(true));
        let what = "blastsph's own twins (no compat item)".to_string();
        rows.push(row_or_failed("none", what, Flags::default(), none, &base, (case, l1_errors))?);
    }
    let text = table(&rows, case.analysis.kind == AnalysisKind::Riemann);
    let rep = serde_json::json!({
        "case": case.name(),
        "legacy": legacy.display().to_string(),
        "profile": profile.label(),
        "against": "the profile run (row `profile`), particle by particle at the end",
        "rows": rows,
    });
    let path: PathBuf = out.join("ledger.json");
    crate::files::write_atomic(&path, serde_json::to_string_pretty(&rep).unwrap_or_default().as_bytes())?;
    Ok((rows, text))
}

/// The ledger as a table.
pub fn table(rows: &[Row], riemann: bool) -> String {
    let mut s = format!(
        "{:<20} {:>6} {:>10} {:>10} {:>10} {:>10} {:>6}{}\n",
        "run",
        "steps",
        "max|drho|",
        "max|dv|",
        "max|dp|",
        "max|de|",
        "parts",
        if riemann { "   L1 rho     L1 v       L1 p       L1 e" } else { "" }
    );
    for r in rows {
        if let Some(why) = &r.failed {
            s += &format!("{:<20} did not finish: {why}\n", r.run);
            continue;
        }
        s += &format!(
            "{:<20} {:>6} {:>10.3e} {:>10.3e} {:>10.3e} {:>10.3e} {:>6}",
            r.run, r.steps, r.max_abs_rho, r.max_abs_v, r.max_abs_p, r.max_abs_e, r.particles_differing
        );
        if let Some(l) = r.l1 {
            s += &format!("   {:.4e} {:.4e} {:.4e} {:.4e}", l[0], l[1], l[2], l[3]);
        }
        s += "\n";
    }
    s
}
