//! What `check` prints and what `dual` runs: the plan as text, the step-by-step dual run and
//! the free run of both backends.

use crate::case;
use crate::case::ConductivityKind;
use crate::dual::Comparator;
use crate::error::Result;
use crate::modules::Backend;
use crate::sim::{Overrides, Sim};
use std::path::Path;

/// The text of `blastsph check`: the case, the time rule, and the plan (modules and the
/// ordered stages of a step).
pub(crate) fn check_text(sim: &Sim) -> String {
    let c = &sim.case;
    let mut s = format!("case {}: dim {}, {} particles", c.name(), c.dim, sim.p.nreal);
    let mut by_mat = vec![(0usize, 0.0f64); c.materials.len()];
    for (&m, &mass) in sim.p.mat[..sim.p.nreal].iter().zip(&sim.p.mass) {
        by_mat[m as usize].0 += 1;
        by_mat[m as usize].1 += mass;
    }
    // the mass each material has in the model (a ring's whole mass in RZ; per metre of depth in
    // 2D plane, per m² in 1D; the modelled part only, with symmetry planes)
    let unit = crate::report::extensive_units(c).0;
    let parts: Vec<String> =
        c.materials.iter().zip(&by_mat).map(|(m, (k, mass))| format!("{} {k}: {mass:.4} {unit}", m.name)).collect();
    s += &format!(" ({}, in the model)\n", parts.join(", "));
    for m in &c.materials {
        if let Some(src) = m.preset.as_deref().and_then(crate::presets::source) {
            s += &format!("material {}: preset {} ({src})\n", m.name, m.preset.as_deref().unwrap_or_default());
        }
    }
    s += &format!(
        "time: end {:e} s, {:?} step{}, output every {:e} s\n",
        c.time.end_s,
        c.time.step,
        match c.time.step {
            case::StepRule::Fixed => format!(" dt = {:e} s", c.time.dt_s.unwrap_or(0.0)),
            case::StepRule::Cfl => format!(" C = {}", c.time.cfl),
        },
        c.time.output_interval_s
    );
    let det = c
        .detonation
        .as_ref()
        .filter(|d| d.mode == case::BurnMode::Programmed)
        .map(|d| {
            format!(
                ", burn: ramp {} h, beta burn {}, lighting at {} D",
                d.width_h,
                if d.beta_burn { "on" } else { "off" },
                d.lighting_speed_factor
            )
        })
        .unwrap_or_default();
    s += &format!(
        "numerics: {} density{}, energy {}, h {}{}, e floor {}, viscous step {}{}{}{}\n",
        format!("{:?}", c.sph.density).to_lowercase(),
        if c.sph.density == case::DensityKind::Continuity {
            format!(" ({:?} form)", c.sph.continuity_form).to_lowercase()
        } else {
            String::new()
        },
        {
            // a compatibility item that replaces the case's energy form says so here
            use crate::migration::compat::Item;
            let form = format!("{:?}", c.sph.energy_form).to_lowercase();
            if crate::migration::compat::flags(&c.compat).is_ok_and(|f| f.has(Item::ForceEnergy)) {
                format!("the book's symmetric form (compat force_energy, in place of the case's {form})")
            } else {
                form
            }
        },
        format!("{:?}", c.sph.smoothing).to_lowercase(),
        c.sph.h_max_ratio.map(|r| format!(" (h <= {r} h0 max)")).unwrap_or_default(),
        if c.sph.e_floor { "on" } else { "off" },
        if c.time.viscous_step { "on" } else { "off" },
        match (c.conductivity.on(), c.conductivity.kind) {
            (false, _) => String::new(),
            (true, ConductivityKind::Noh) => {
                format!(", artificial heat g1 = {}, g2 = {}", c.conductivity.g1(), c.conductivity.g2())
            }
            (true, ConductivityKind::Price) => {
                format!(", conductivity alpha_u = {} ({:?})", c.conductivity.alpha, c.conductivity.signal)
                    .to_lowercase()
            }
        },
        if c.sph.jitter > 0.0 { format!(", lattice jittered by {:e} dx", c.sph.jitter) } else { String::new() },
        det
    );
    if c.gravity_on() {
        s += if c.geostatic() {
            "start: geostatic (at rest under gravity, initial.geostatic)\n"
        } else {
            "start: uniform density under gravity (initial.geostatic = false)\n"
        };
    }
    if let Some(l) = crate::analysis::sedov_edge::sedov_check_line(c) {
        s += &format!("{l}\n");
    }
    for w in crate::advice::all(c, &sim.p, &sim.region).into_iter().chain(sim.plan.legacy_warnings()) {
        s += &format!("warning: {w}\n");
    }
    s + &sim.plan.text()
}

/// `blastsph dual`: returns exit 0 when every module is within tolerance, 4 otherwise.
pub fn dual_run(c: case::Case, ov: &Overrides, steps: u64, dir: &Path) -> Result<i32> {
    let mut sim = Sim::new(c, ov)?;
    let unrun = sim.plan.legacy_warnings();
    for w in &unrun {
        eprintln!("warning: {w}");
    }
    sim.enable_dual(Comparator::new(sim.cfg.dim));
    // an earlier dual run's report goes now: a run that a legacy STOP ends writes none, and the
    // folder must not keep one that reads as this run's
    let path = dir.join("dual_report.json");
    if let Err(e) = std::fs::remove_file(&path)
        && e.kind() != std::io::ErrorKind::NotFound
    {
        return Err(crate::error::SphError::Io(format!("{}: cannot replace it: {e}", path.display())));
    }
    let mut done = 0;
    let mut diag = None;
    let mut signalled = false;
    // a fixed step: the number of steps `run` takes, round(end/dt)
    let fixed =
        (sim.cfg.step == case::StepRule::Fixed).then(|| (sim.cfg.end / sim.cfg.dt_fixed).round().max(1.0) as u64);
    while done < steps
        && match fixed {
            Some(n) => sim.nstep < n,
            None => sim.t < sim.cfg.end * (1.0 - 1e-12),
        }
    {
        if let Err(e) = sim.step() {
            diag = Some(e.to_string());
            break;
        }
        done += 1;
        // SIGINT or SIGTERM: the steps so far are reported, and the status is 5
        if crate::runner::stop_flag().load(std::sync::atomic::Ordering::Relaxed) {
            signalled = true;
            break;
        }
    }
    let cmp = sim.cmp.take().unwrap_or_default();
    print!("{}", cmp.table());
    let ok = cmp.ok();
    let uncompared = cmp.uncompared();
    let rep = serde_json::json!({
        "case": sim.case.name(),
        "steps": done,
        "time": sim.t,
        "within_tolerance": ok,
        "stopped_by_signal": signalled,
        "diagnostic": diag,
        "not_compared": uncompared,
        "legacy": sim.plan.legacy,
        "rows": cmp.rows(),
    });
    crate::rundir::write_atomic(&path, serde_json::to_string_pretty(&rep).unwrap_or_default().as_bytes())?;
    let not = if uncompared.is_empty() {
        String::new()
    } else {
        format!(
            "; {} stages not compared ({}: compat variants without a Fortran twin, compared through --legacy; legacy routines without a Rust twin)",
            uncompared.len(),
            uncompared.join(", ")
        )
    };
    // a run that stopped before the end says so on the summary line (the case went unstable:
    // the steps before it were compared)
    // (the step that failed was compared up to where it stopped: its rows hold step `done`)
    let not = if unrun.is_empty() {
        not
    } else {
        format!(
            "{not}; {} mapped legacy routine(s) NOT RUN, blastsph's own stages ran in their place (the warning above says why)",
            unrun.len()
        )
    };
    let not = if signalled { format!("{not}; STOPPED by a signal before --steps") } else { not };
    let stopped = diag.as_ref().map_or(String::new(), |d| {
        format!(" (and step {done} of the report's rows, counted from 0, up to where it stopped); STOPPED before the end: {d}")
    });
    println!(
        "{} steps compared{stopped}; {}{}; report {}",
        done,
        match (ok, not.is_empty()) {
            (true, true) => "every module within tolerance",
            (true, false) => "every compared stage within tolerance",
            _ => "MODULES OUT OF TOLERANCE",
        },
        not,
        path.display()
    );
    // out of tolerance first; else a case that went unstable is status 3, as for `run`
    Ok(if !ok {
        4
    } else if diag.is_some() {
        3
    } else if signalled {
        5
    } else {
        0
    })
}

/// Free-running mode: separation of an all-Fortran and an all-Rust run over time.
pub fn free_run(c: case::Case, ov: &Overrides, steps: u64, dir: &Path) -> Result<String> {
    let mut ovf = ov.clone();
    ovf.backend = Some(Backend::Fortran);
    let mut ovr = ov.clone();
    ovr.backend = Some(Backend::Rust);
    let mut a = Sim::new(c.clone(), &ovf)?;
    let mut b = Sim::new(c, &ovr)?;
    let mut rows = Vec::new();
    let mut first_diff: Option<u64> = None;
    for _ in 0..steps {
        if a.t >= a.cfg.end * (1.0 - 1e-12) {
            break;
        }
        a.step()?;
        b.step()?;
        let n = a.p.nreal;
        let dim = a.cfg.dim;
        let dx = (0..dim * n).map(|l| (a.p.x[l] - b.p.x[l]).abs()).fold(0.0, f64::max);
        let drho = (0..n).map(|i| ((a.p.rho[i] - b.p.rho[i]) / a.p.rho[i]).abs()).fold(0.0, f64::max);
        let dv = (0..dim * n).map(|l| (a.p.v[l] - b.p.v[l]).abs()).fold(0.0, f64::max);
        let bitwise = a.p.x == b.p.x && a.p.v == b.p.v && a.p.rho == b.p.rho && a.p.e == b.p.e && a.t == b.t;
        if !bitwise && first_diff.is_none() {
            first_diff = Some(a.nstep);
        }
        rows.push(serde_json::json!({"step": a.nstep, "t_fortran": a.t, "t_rust": b.t, "max_dx_m": dx, "max_drho_rel": drho, "max_dv_ms": dv, "bitwise_equal": bitwise}));
    }
    let rep =
        serde_json::json!({"case": a.case.name(), "steps": a.nstep, "first_difference_step": first_diff, "rows": rows});
    let path = dir.join("dual_free.json");
    crate::rundir::write_atomic(&path, serde_json::to_string_pretty(&rep).unwrap_or_default().as_bytes())?;
    Ok(match first_diff {
        None => format!(
            "free run: {} steps, Fortran and Rust states bitwise identical at every step; {}",
            a.nstep,
            path.display()
        ),
        Some(s) => format!("free run: {} steps, first difference at step {s}; {}", a.nstep, path.display()),
    })
}

/// The L1 errors (ρ, v, p, e) of a ledger run's end state against the case's exact Riemann
/// solution, in the ledger's window.
pub(super) fn ledger_l1(
    case: &crate::case::Case,
    s: &crate::migration::ledger::EndState<'_>,
) -> crate::error::Result<[f64; 4]> {
    let (rs, x0) = crate::report::riemann_of(case)?;
    let f = crate::output::Frame {
        time: s.t,
        x: s.x.to_vec(),
        vx: s.v.to_vec(),
        rho: s.rho.to_vec(),
        p: s.p.to_vec(),
        e: s.e.to_vec(),
        mass: s.mass.to_vec(),
        ..Default::default()
    };
    let w = case.analysis.window_m.clone().unwrap_or(vec![f64::NEG_INFINITY, f64::INFINITY]);
    let l = crate::report::l1_errors(&f, &rs, x0, (w[0], w.get(1).copied().unwrap_or(f64::INFINITY)));
    Ok([l.rho, l.v, l.p, l.e])
}
