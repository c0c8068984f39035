//! `blastsph report DIR`: measurements and plots of a finished run.

use crate::analysis::riemann::{Riemann, Side};
use crate::case::{self, AnalysisKind, Case, EosCfg};
use crate::error::{Result, input};
use crate::output::Frame;
use crate::plot;
use serde_json::{Value, json};
use std::path::Path;

mod verify;

/// L1 errors of a 1D Riemann run against the exact solution.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct L1 {
    pub rho: f64,
    pub v: f64,
    pub p: f64,
    pub e: f64,
    /// Particles in the window.
    pub n: usize,
}

/// The units of a mass and an energy of the model (kg, J): per m² of the plane in 1D, per metre
/// of depth in 2D plane; whole in RZ and 3D (of the modelled part, with symmetry planes).
pub(crate) fn extensive_units(case: &Case) -> (&'static str, &'static str) {
    match (case.dim, case.axisymmetric()) {
        (1, _) => ("kg/m²", "J/m²"),
        (2, false) => ("kg/m", "J/m"),
        _ => ("kg", "J"),
    }
}

/// Loads the case of a run directory (case.toml with the run's --set overrides) and its
/// summary. A run killed before it wrote summary.json gets a summary that says so
/// (`"status": "killed"`, `"partial": true`).
pub(crate) fn load_case(dir: &Path) -> Result<(Case, Value)> {
    let sp = dir.join("summary.json");
    let summary: Value = match std::fs::read(&sp) {
        Ok(bytes) => {
            let v: Value = serde_json::from_slice(&bytes)
                .map_err(|e| input(format!("{}: damaged, not JSON ({e}): not a run directory?", sp.display())))?;
            if v.is_object() && (v["steps"].as_u64().is_none() || v["dim"].as_u64().is_none()) {
                return Err(input(format!("{}: not a run's summary (no `steps` or `dim`)", sp.display())));
            }
            v
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound && dir.join("case.toml").is_file() => {
            json!({ "status": "killed", "partial": true, "case_toml": "the case as run" })
        }
        Err(e) => return Err(input(format!("{}: {e} (is this a run directory?)", sp.display()))),
    };
    if !summary.is_object() {
        return Err(input(format!("{}: not a run's summary (a JSON object)", sp.display())));
    }
    // since case.toml holds the case as run, the overrides are in it; older run directories
    // kept the case file as given and the overrides in summary.json `sets`
    let sets: Vec<String> = if summary.get("case_toml").is_some() {
        Vec::new()
    } else {
        summary["sets"]
            .as_array()
            .map(|a| a.iter().filter_map(|v| v.as_str().map(String::from)).collect())
            .unwrap_or_default()
    };
    let cp = dir.join("case.toml");
    let text = crate::case::read_text(&cp)?;
    // case.toml must be the case this run ran (runs since summary.json carried its hash)
    if let Some(want) = summary["case_toml_sha256"].as_str()
        && crate::rundir::sha256_hex(text.as_bytes()) != want
    {
        return Err(input(format!(
            "{}: not the case this run ran (its SHA-256 differs from summary.json's case_toml_sha256): restore it, or run the case again",
            cp.display()
        )));
    }
    let name = summary["case"]
        .as_str()
        .map(String::from)
        .or_else(|| dir.file_name().map(|n| n.to_string_lossy().into_owned()));
    let case = case::parse(&text, &cp.display().to_string(), &sets, name.as_deref())?;
    if let Some(d) = summary["dim"].as_u64()
        && d as usize != case.dim
    {
        return Err(input(format!("{}: dim = {} but summary.json says the run had dim = {d}", cp.display(), case.dim)));
    }
    Ok((case, summary))
}

/// The exact problem of a Riemann case: left and right states from its regions.
pub fn riemann_of(case: &Case) -> Result<(Riemann, f64)> {
    let x0 = case.analysis.diaphragm_m.ok_or_else(|| input("analysis.diaphragm_m missing"))?;
    let mut left = None;
    let mut right = None;
    let mut gamma = None;
    for r in &case.regions {
        let m = &case.materials[case.material_index(&r.material).unwrap_or(0)];
        let g = match m.eos {
            EosCfg::IdealGas { gamma, .. } => gamma,
            _ => return Err(input("analysis.kind = \"riemann\" needs ideal-gas regions")),
        };
        gamma = Some(g);
        let rho = r.rho_kgm3.or(m.eos.rho0()).unwrap_or(1.0);
        let e = r.e_jkg.or(m.e0_jkg).unwrap_or(0.0);
        let u = r.velocity_ms.as_ref().map(|v| v[0]).unwrap_or(0.0);
        let side = Side { rho, u, p: (g - 1.0) * rho * e };
        let xs = r.origin_m.as_ref().or(r.lo_m.as_ref()).map(|v| v[0]).unwrap_or(0.0);
        if xs < x0 { left = Some(side) } else { right = Some(side) }
    }
    let (l, r, g) = (
        left.ok_or_else(|| input("riemann: no region left of the diaphragm"))?,
        right.ok_or_else(|| input("riemann: no region right of the diaphragm"))?,
        gamma.unwrap_or(1.4),
    );
    let rs = Riemann::solve(l, r, g).ok_or_else(|| input("riemann: the exact solver found no solution (vacuum?)"))?;
    Ok((rs, x0))
}

/// Volume-weighted L1 errors over `window`: Σ V_i |q_i − q(x_i)| / Σ V_i, V_i = m_i/ρ_i.
pub fn l1_errors(f: &Frame, rs: &Riemann, x0: f64, window: (f64, f64)) -> L1 {
    let (mut er, mut ev, mut ep, mut ee, mut vol) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let mut n = 0;
    for i in 0..f.x.len() {
        let x = f.x[i];
        if x < window.0 || x > window.1 {
            continue;
        }
        let s = rs.sample((x - x0) / f.time);
        let vi = f.mass[i] / f.rho[i];
        er += vi * (f.rho[i] - s.rho).abs();
        ev += vi * (f.vx[i] - s.u).abs();
        ep += vi * (f.p[i] - s.p).abs();
        ee += vi * (f.e[i] - s.e).abs();
        vol += vi;
        n += 1;
    }
    let v = vol.max(1e-300);
    L1 { rho: er / v, v: ev / v, p: ep / v, e: ee / v, n }
}

fn riemann_report(dir: &Path, case: &Case, frames: &[Frame]) -> Result<Value> {
    let (rs, x0) = riemann_of(case)?;
    let last = frames.last().ok_or_else(|| input("particles.h5 holds no step"))?;
    let w = case.analysis.window_m.clone().unwrap_or(vec![f64::NEG_INFINITY, f64::INFINITY]);
    let l1 = l1_errors(last, &rs, x0, (w[0], w[1]));
    let (xa, xb) = (
        last.x.iter().cloned().fold(f64::INFINITY, f64::min),
        last.x.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
    );
    let exact: Vec<(f64, crate::analysis::riemann::State)> = (0..=2000)
        .map(|k| {
            let x = xa + (xb - xa) * k as f64 / 2000.0;
            (x, rs.sample((x - x0) / last.time))
        })
        .collect();
    let mk = |title: &str,
              unit: &str,
              q: &dyn Fn(usize) -> f64,
              qe: &dyn Fn(&crate::analysis::riemann::State) -> f64| plot::Panel {
        title: title.into(),
        xlabel: "x (m)".into(),
        ylabel: unit.into(),
        points: (0..last.x.len()).map(|i| (last.x[i], q(i))).collect(),
        curve: exact.iter().map(|(x, s)| (*x, qe(s))).collect(),
        curve_label: "exact".into(),
        points_label: "SPH".into(),
    };
    let panels = [
        mk("density", "rho (kg/m3)", &|i| last.rho[i], &|s| s.rho),
        mk("velocity", "v (m/s)", &|i| last.vx[i], &|s| s.u),
        mk("pressure", "p (Pa)", &|i| last.p[i], &|s| s.p),
        mk("internal energy", "e (J/kg)", &|i| last.e[i], &|s| s.e),
    ];
    let png = dir.join("profiles.png");
    plot::panels(&png, &panels, 2, (1200, 900))?;
    let (rl, rr) = rs.rho_star();
    println!(
        "exact: p* = {:.6}, u* = {:.6}, rho*L = {:.6}, rho*R = {:.6}; {} (m/s)",
        rs.p_star,
        rs.u_star,
        rl,
        rr,
        rs.waves()
    );
    println!(
        "L1 errors at t = {:.4} s over [{}, {}] m ({} particles): rho {:.4e}  v {:.4e}  p {:.4e}  e {:.4e}",
        last.time, w[0], w[1], l1.n, l1.rho, l1.v, l1.p, l1.e
    );
    println!("plot: {}", png.display());
    Ok(json!({
        "exact": { "p_star": rs.p_star, "u_star": rs.u_star, "rho_star_left": rl, "rho_star_right": rr, "shock_speed": (rs.p_star > rs.right.p).then(|| rs.right_shock_speed()), "waves": rs.waves() },
        "time": last.time,
        "window_m": w,
        "l1": l1,
        "plot": "profiles.png",
    }))
}

pub fn report(dir: &Path) -> Result<Value> {
    report_at(dir, &[])
}

/// The report, with particle snapshots at `times` (s; empty: the start, the quarters, the end).
pub(crate) fn report_at(dir: &Path, times: &[f64]) -> Result<Value> {
    report_with(dir, times, false)
}

/// The report, with snapshots at `times` and, when `animate`, animation.gif.
pub(crate) fn report_with(dir: &Path, times: &[f64], animate: bool) -> Result<Value> {
    report_in(dir, times, animate, None)
}

/// [`report_with`], the particle maps in `window` ([x_lo, x_hi, y_lo, y_hi], m) when given, in
/// place of the case's `analysis.view_m` (`report --window`).
pub(crate) fn report_in(dir: &Path, times: &[f64], animate: bool, window: Option<[f64; 4]>) -> Result<Value> {
    let _lock = crate::rundir::lock_read(dir, "report")?;
    let (mut case, mut summary) = load_case(dir)?;
    if let Some(w) = window {
        case.analysis.view_m = Some(w.to_vec());
    }
    let (frames, skipped) = crate::output::read_complete_frames(&dir.join("particles.h5"))?;
    let last = frames.last().ok_or_else(|| input(format!("{}: particles.h5 holds no step", dir.display())))?;
    // the file is this run's: its first step holds the run's particles, of the case's materials
    // (another run's particles.h5 copied in was reported as this case's)
    if let Some(n) = summary["particles"].as_u64()
        && frames[0].x.len() as u64 != n
    {
        return Err(input(format!(
            "{}: particles.h5 holds {} particles at its first step, summary.json says the run has {n}: not this run's file",
            dir.display(),
            frames[0].x.len()
        )));
    }
    if let Some(&m) = frames.iter().flat_map(|f| f.mat.iter()).find(|&&m| m < 0 || m as usize >= case.materials.len()) {
        return Err(input(format!(
            "{}: particles.h5 holds material {m}, the case has {} materials: not this run's file",
            dir.display(),
            case.materials.len()
        )));
    }
    crate::rundir::remove_report(dir)?;
    // a run that did not finish: reported up to its last complete output
    let partial = summary["partial"].as_bool().unwrap_or(false)
        || !matches!(summary["status"].as_str(), Some("ok" | "unstable"))
        || skipped.is_some();
    if partial {
        println!(
            "PARTIAL: the run did not finish (status {}): reported up to its last complete output, Step#{} at t = {:.6e} s{}",
            summary["status"].as_str().unwrap_or("?"),
            frames.len() - 1,
            last.time,
            skipped.as_deref().map(|s| format!(" ({s})")).unwrap_or_default()
        );
        if summary.get("particles").is_none() {
            summary["case"] = json!(case.name());
            summary["particles"] = json!(last.x.len());
            summary["time"] = json!(last.time);
        }
    }
    println!(
        "{}: {} particles, {} steps to t = {:.4e} s in {:.2} s ({}, status {})",
        summary["case"].as_str().unwrap_or("?"),
        summary["particles"],
        summary["steps"],
        summary["time"].as_f64().unwrap_or(0.0),
        summary["wall_seconds"].as_f64().unwrap_or(0.0),
        summary["backend"].as_str().unwrap_or("?"),
        summary["status"].as_str().unwrap_or("?")
    );
    // the error bars of a `converge` ladder this run is a level of
    for l in crate::converge::report_lines(dir) {
        println!("{l}");
    }
    let m0 = summary["mass"]["initial"].as_f64().unwrap_or(0.0);
    let m1 = summary["mass"]["final"].as_f64().unwrap_or(0.0);
    let (mu, eu) = extensive_units(&case);
    println!(
        "mass ({mu}): initial {m0:.12e}, final {m1:.12e}, relative change {:.3e}",
        (m1 - m0) / m0.abs().max(1e-300)
    );
    let en = &summary["energy"];
    println!(
        "energy ({eu}): initial {:.6e}, final {:.6e} (kinetic {:.4e}, internal {:.4e}, elastic {:.4e}); work: wall {:.3e}, penalty {:.3e}, gravity {:.3e}, floor e >= 0 {:.3e}; balance residual {:.3e} ({:.3e} relative)",
        en["initial"]["total"].as_f64().unwrap_or(0.0),
        en["final"]["total"].as_f64().unwrap_or(0.0),
        en["final"]["kinetic"].as_f64().unwrap_or(0.0),
        en["final"]["internal"].as_f64().unwrap_or(0.0),
        en["final"]["elastic"].as_f64().unwrap_or(0.0),
        en["work_wall"].as_f64().unwrap_or(0.0),
        en["work_penalty"].as_f64().unwrap_or(0.0),
        en["work_gravity"].as_f64().unwrap_or(0.0),
        en["work_floor"].as_f64().unwrap_or(0.0),
        en["balance_residual"].as_f64().unwrap_or(0.0),
        en["balance_residual_relative"].as_f64().unwrap_or(0.0)
    );

    if let Some(w) = energy_warning(&summary) {
        println!("WARNING: {w}");
    }

    let out = match case.analysis.kind {
        AnalysisKind::Riemann => riemann_report(dir, &case, &frames)?,
        AnalysisKind::Crater => crate::blast_report::report(dir, &case, &summary, &frames, times, animate)?,
        AnalysisKind::Sedov | AnalysisKind::Noh | AnalysisKind::Reflection | AnalysisKind::Detonation => {
            verify::report(dir, &case, &frames)?
        }
        AnalysisKind::None if case.dim >= 2 => {
            crate::blast_report::report(dir, &case, &summary, &frames, times, animate)?
        }
        AnalysisKind::None => json!({}),
    };
    // a crater asked of a case it cannot be measured in (1D): the reason the run recorded
    if case.analysis.kind == AnalysisKind::Crater
        && case.dim < 2
        && let Some(why) = summary["crater"]["reason"].as_str()
    {
        println!("crater: cannot be measured: {why}");
    }
    let mut out = out;
    // a charge in air: the gauges against Kinney & Graham
    if let Some(v) = crate::blast_report::air_blast(dir, &case, &frames)?
        && out.is_object()
    {
        out["air_blast"] = v;
    }
    // the gauges of a case that is not a blast (a blast's report has them already)
    let blast = matches!(case.analysis.kind, AnalysisKind::Crater)
        || (case.analysis.kind == AnalysisKind::None && case.dim >= 2);
    if !blast {
        let files = crate::blast_report::gauges_only(dir, &case, &summary, last.time)?;
        if !files.is_empty() {
            println!("plots in {}: {}", dir.display(), files.join(", "));
            if out.is_object() {
                out["gauge_plots"] = json!(files);
            }
        }
    }
    if partial && out.is_object() {
        out["partial"] = json!(true);
        out["partial_note"] = json!(format!(
            "the run did not finish (status {}): reported up to its last complete output, t = {:e} s",
            summary["status"].as_str().unwrap_or("?"),
            last.time
        ));
    }
    let text = serde_json::to_string_pretty(&out).unwrap_or_default();
    crate::rundir::write_atomic(&dir.join("report.json"), text.as_bytes())?;
    Ok(out)
}

/// Above this share of the initial energy, a run's energy balance residual is warned of (the
/// blasts and verification problems of docs/validation.md stay below 0.2 %; a run at
/// `time.cfl = 1` gained 28 % and finished "ok"; the run stops as unstable only at 100 %).
pub(crate) const ENERGY_WARN: f64 = 0.05;

/// The warning for a summary.json whose energy balance residual is above [`ENERGY_WARN`] of
/// the initial energy.
pub(crate) fn energy_warning(summary: &serde_json::Value) -> Option<String> {
    let r = summary["energy"]["balance_residual_relative"].as_f64()?;
    (r.abs() > ENERGY_WARN).then(|| {
        format!(
            "the energy balance residual is {:+.1} % of the initial energy and the external forces' work (summary.json energy.balance_residual_relative): a run this far from conserving energy is not to be trusted; lower time.cfl (or time.dt_s for a fixed step)",
            100.0 * r
        )
    })
}

#[cfg(test)]
mod energy_tests {
    use super::*;

    #[test]
    fn an_energy_balance_off_by_more_than_five_per_cent_is_warned_of() {
        let s = |r: f64| serde_json::json!({ "energy": { "balance_residual_relative": r } });
        assert!(energy_warning(&s(2e-3)).is_none());
        assert!(energy_warning(&s(-0.049)).is_none());
        let w = energy_warning(&s(0.283)).unwrap();
        assert!(w.contains("+28.3 %") && w.contains("time.cfl"), "{w}");
        assert!(energy_warning(&s(-0.06)).unwrap().contains("-6.0 %"));
        assert!(energy_warning(&serde_json::json!({})).is_none());
    }
}
