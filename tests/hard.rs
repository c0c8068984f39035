//! The hard cases of cases/hard/: each runs (shortened where it would take long) and its
//! invariants are checked. Full-length runs: `cargo test --release --test hard -- --ignored`.

use blastsph::runner::{self, RunOptions};
use blastsph::sim::Overrides;
use serde_json::Value;
use std::path::{Path, PathBuf};

fn case(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/hard").join(format!("{name}.toml"))
}

/// Runs a hard case (with the Rust backend, optionally shortened) and returns its summary and sim.
fn run(name: &str, end: Option<f64>) -> (Value, blastsph::sim::Sim, tempfile::TempDir) {
    let dir = tempfile::tempdir().expect("tempdir");
    let opts = RunOptions {
        out: Some(dir.path().to_path_buf()),
        quiet: true,
        ov: Overrides { backend: Some(blastsph::modules::Backend::Rust), end_time: end, ..Default::default() },
        ..Default::default()
    };
    let r = runner::run(&case(name), &opts).unwrap_or_else(|e| panic!("{name}: {e}"));
    (r.summary, r.sim, dir)
}

/// The invariants every hard case must keep.
fn common(name: &str, s: &Value, energy_bound: f64) {
    assert_eq!(s["stability"]["left_domain"], 0, "{name}: particles lost");
    common_but_domain(name, s, energy_bound);
}

/// The invariants but the count of particles outside `[domain]` (for runs whose ejecta may fly
/// beyond it: the caller checks where they went).
fn common_but_domain(name: &str, s: &Value, energy_bound: f64) {
    assert_eq!(s["status"], "ok", "{name}: {}", s["diagnostic"]);
    assert_eq!(s["mass"]["initial"], s["mass"]["final"], "{name}: mass must be exact");
    let st = &s["stability"];
    assert_eq!(st["nan"], false, "{name}");
    let res = s["energy"]["balance_residual_relative"].as_f64().expect("energy residual");
    assert!(res.abs() < energy_bound, "{name}: energy balance residual {res:e} (bound {energy_bound})");
}

fn dx_of(sim: &blastsph::sim::Sim) -> f64 {
    sim.cfg.dx_min
}

/// Smallest distance between two real particles, in units of dx.
fn min_pair_distance(sim: &blastsph::sim::Sim) -> f64 {
    let (dim, n) = (sim.cfg.dim, sim.p.nreal);
    let mut m = f64::INFINITY;
    for k in 0..sim.w.pairs.len() {
        let (i, j) = (sim.w.pairs.i[k] as usize, sim.w.pairs.j[k] as usize);
        if j < n {
            let r2: f64 = (0..dim).map(|d| (sim.p.x[d + dim * i] - sim.p.x[d + dim * j]).powi(2)).sum();
            m = m.min(r2.sqrt());
        }
    }
    m / dx_of(sim)
}

#[test]
fn tnt_against_water_and_soil() {
    let (s, sim, _d) = run("tnt_water_soil", None);
    common("tnt_water_soil", &s, 0.02);
    let st = &s["stability"];
    let gap = st["min_interface_gap_dx"].as_f64().expect("interface gap");
    assert!(gap > 0.3, "materials came within {gap} dx of each other");
    assert!(st["max_wall_penetration_m"].as_f64().unwrap() < 0.1 * dx_of(&sim));
    // the charge really was at 8.4 GPa against rest, and the shock went into both media
    let peak_water = (0..sim.p.nreal).filter(|&i| sim.p.mat[i] == 1).map(|i| sim.p.v[2 * i + 1]).fold(0.0, f64::max);
    let peak_soil = (0..sim.p.nreal).filter(|&i| sim.p.mat[i] == 2).map(|i| -sim.p.v[2 * i + 1]).fold(0.0, f64::max);
    assert!(peak_water > 10.0 && peak_soil > 10.0, "water up {peak_water} m/s, soil down {peak_soil} m/s");
}

#[test]
fn soil_spalls_with_the_tension_cut_off() {
    let (s, sim, _d) = run("soil_spall", None);
    common("soil_spall", &s, 0.02);
    let n = sim.p.nreal;
    // the cut-off: no tension anywhere, and no clumping of particles (tensile instability)
    assert!(sim.p.p[..n].iter().all(|p| *p >= 0.0), "negative pressure with pmin = 0");
    let dmin = min_pair_distance(&sim);
    assert!(dmin > 0.5, "particles clumped: closest pair {dmin} dx");
    // spall: the top 3 cm flies off, the column below the top 10 cm stays nearly at rest
    let band = |lo: f64, hi: f64| -> f64 {
        let ids: Vec<usize> = (0..n).filter(|&i| sim.x_init[2 * i + 1] >= lo && sim.x_init[2 * i + 1] < hi).collect();
        ids.iter().map(|&i| sim.p.v[2 * i + 1]).sum::<f64>() / ids.len() as f64
    };
    let top = band(0.30, 0.33);
    let low = band(0.03, 0.20);
    assert!(top > 10.0, "top layer at {top} m/s: no spall");
    assert!(low.abs() < 1.0, "column below at {low} m/s");
}

#[test]
fn high_speed_wall_impact_does_not_penetrate() {
    let (s, sim, _d) = run("wall_impact", None);
    common("wall_impact", &s, 0.02);
    let pen = s["stability"]["max_wall_penetration_m"].as_f64().unwrap();
    assert!(pen < 0.1 * dx_of(&sim), "penetration {pen} m");
    // the block reached the wall and the wall took up most of its normal momentum (water at
    // 300 m/s does not bounce back: it spreads along the wall)
    let n = sim.p.nreal;
    let mean_vx = sim.p.v[..2 * n].iter().step_by(2).sum::<f64>() / n as f64;
    assert!(mean_vx > -150.0, "mean vx = {mean_vx} m/s: the wall did not stop the block");
    let xmin = sim.p.x[..2 * n].iter().step_by(2).cloned().fold(f64::INFINITY, f64::min);
    assert!(xmin < 0.01, "the block never reached the wall (closest {xmin} m)");
    assert!(xmin > 0.25 * dx_of(&sim), "a particle within {xmin} m of the wall line (r0 = dx/2)");
}

#[test]
fn free_expansion_keeps_h_and_neighbours_sane() {
    let (s, _sim, _d) = run("free_expansion", None);
    common("free_expansion", &s, 0.01);
    let st = &s["stability"];
    let hmax = st["h_ratio_max"].as_f64().unwrap();
    assert!(hmax > 2.0 && hmax < 20.0, "h/h0 grew to {hmax}");
    let nmax = st["max_neighbours"].as_u64().unwrap();
    let nmean = st["mean_neighbours"].as_f64().unwrap();
    assert!(nmax <= 40 && nmean >= 2.0, "neighbours: max {nmax}, mean {nmean}");
}

/// A TNT sphere alone in vacuum, in 3D, at the defaults: products alone take summation density
/// (by continuity the rarefied centre ran below zero density at 18.5 µs and the run stopped).
#[test]
fn a_free_tnt_sphere_expands_at_the_defaults() {
    let (s, sim, _d) = run("free_sphere_3d", None);
    common("free_sphere_3d", &s, 0.01);
    assert_eq!(sim.case.sph.density, blastsph::case::DensityKind::Summation);
    let n = sim.p.nreal;
    assert!(sim.p.rho[..n].iter().all(|&r| r > 0.0));
    // the products spread: the farthest particle from 2 cm to beyond 6 cm in 60 µs
    let rmax = (0..n).map(|i| (0..3).map(|d| sim.p.x[d + 3 * i].powi(2)).sum::<f64>().sqrt()).fold(0.0, f64::max);
    assert!(rmax > 0.06, "farthest particle at {rmax} m");
    // and their volume Σ m/ρ (the report's equivalent radius) tracks that extent: with the gas
    // dynamics' cap h ≤ 4 h0 their density stuck at m W(0, 4 h0) and the radius at 0.42 of it
    let vol: f64 = (0..n).map(|i| sim.p.mass[i] / sim.p.rho[i]).sum();
    let req = (3.0 * vol / (4.0 * std::f64::consts::PI)).cbrt();
    assert!(req > 0.8 * rmax && req < 1.25 * rmax, "equivalent radius {req} m, farthest particle {rmax} m");
}

#[test]
fn coarse_25x25_runs_and_craters() {
    let (s, sim, _d) = run("coarse_25", None);
    common("coarse_25", &s, 0.02);
    assert!(s["stability"]["max_wall_penetration_m"].as_f64().unwrap() < 0.1 * dx_of(&sim));
    let depth = s["crater"]["depth_m"].as_f64().unwrap();
    assert!(depth > dx_of(&sim), "no crater at dx = 4 cm: depth {depth} m");
}

#[test]
fn long_surface_blast_first_tenth_of_a_millisecond() {
    let (s, sim, _d) = run("long_surface", Some(1.0e-4));
    common("long_surface", &s, 0.02);
    assert!(s["stability"]["max_wall_penetration_m"].as_f64().unwrap() < 0.1 * dx_of(&sim));
}

/// The whole 5 ms (6859 steps, about 20 s with the Rust backend on 2 cores). Over 5 ms the
/// detonation products and the fastest ejecta (hundreds of m/s to km/s) fly beyond the case's
/// `[domain]` (3 × 4.1 m), which is a bookkeeping box, not a wall: what must hold is that every particle
/// outside it left through the free surface — above the original ground (y = 1 m), moving up —
/// and none through the walls.
#[test]
#[ignore = "long: run with --ignored"]
fn long_surface_full() {
    let (s, sim, _d) = run("long_surface", None);
    common_but_domain("long_surface", &s, 0.02);
    let p = &sim.p;
    let dom = sim.case.domain.as_ref().expect("long_surface has a [domain]");
    let mut out: usize = 0;
    for a in 0..p.nreal {
        let (x, y) = (p.x[2 * a], p.x[2 * a + 1]);
        if (dom.lo_m[0]..=dom.hi_m[0]).contains(&x) && (dom.lo_m[1]..=dom.hi_m[1]).contains(&y) {
            continue;
        }
        out += 1;
        assert!(y > 1.0 && p.v[2 * a + 1] > 0.0, "particle {a} left the domain at ({x}, {y}) m, not as ejecta");
    }
    assert_eq!(s["stability"]["left_domain"].as_u64(), Some(out as u64), "summary.json counts the particles outside");
    assert!(out < p.nreal / 50, "{out} particles left: more than 2 % of the scene");
    assert!(s["stability"]["max_wall_penetration_m"].as_f64().unwrap() < 0.1 * dx_of(&sim));
    let gap = s["stability"]["min_interface_gap_dx"].as_f64().expect("gap");
    assert!(gap > 0.3, "materials came within {gap} dx");
}

/// A body at rest at e = 0 under gravity starts from 0 J: the energy check took any kinetic
/// energy as energy created ("exceeds the initial 0 J … by more than the initial energy") and
/// stopped it at step 1. It falls, and where the block's particles end is x0 − ½ g t² (every
/// particle feels gravity alone: the gas at e = 0 carries no pressure).
#[test]
fn a_body_at_rest_at_zero_energy_falls_under_gravity() {
    let d = tempfile::tempdir().unwrap();
    let cf = d.path().join("fall.toml");
    std::fs::write(
        &cf,
        "name = \"fall\"\ndim = 2\n[time]\nend_s = 0.1\noutput_interval_s = 0.05\n[physics]\ngravity_ms2 = [0.0, -9.81]\n\
         [[material]]\nname = \"dust\"\neos = { kind = \"ideal_gas\", gamma = 1.4 }\n\
         [[region]]\nname = \"blob\"\nmaterial = \"dust\"\nshape = \"box\"\nlo_m = [0.0, 0.0]\nhi_m = [0.1, 0.1]\n\
         spacing_m = 0.01\nrho_kgm3 = 1.0\ne_jkg = 0.0\n",
    )
    .unwrap();
    let opts = RunOptions { out: Some(d.path().join("run")), quiet: true, ..Default::default() };
    let r = runner::run(&cf, &opts).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(r.summary["status"], "ok");
    let sim = &r.sim;
    let t = sim.t;
    for i in 0..sim.p.nreal {
        let drop = sim.x_init[2 * i + 1] - sim.p.x[2 * i + 1];
        assert!((drop - 0.5 * 9.81 * t * t).abs() < 1e-9, "particle {i} fell {drop} m in {t} s");
    }
    let rel = r.summary["energy"]["balance_residual_relative"].as_f64().unwrap();
    assert!(rel.abs() < 0.05, "residual over the initial energy and gravity's work: {rel}");
}

/// A strong shock tube (1000 : 1 in pressure) with the artificial viscosity off and a fixed step:
/// particles pass through each other at the shock, and the run used to end "ok" (h/h0 down to
/// 0.0016, ρ 154 against the exact 6). It stops as unstable on the smoothing length's collapse,
/// and the hint says to turn the viscosity back on.
#[test]
fn an_inviscid_strong_shock_that_interpenetrates_stops() {
    let d = tempfile::tempdir().unwrap();
    let cf = d.path().join("tube.toml");
    let region = |name: &str, lo: f64, hi: f64, e: f64| {
        format!(
            "[[region]]\nname = \"{name}\"\nmaterial = \"gas\"\nshape = \"box\"\nlo_m = [{lo:?}]\nhi_m = [{hi:?}]\nspacing_m = 0.00125\nrho_kgm3 = 1.0\ne_jkg = {e:?}\n"
        )
    };
    std::fs::write(
        &cf,
        format!(
            "name = \"strong_tube\"\ndim = 1\n[time]\nend_s = 0.012\nstep = \"fixed\"\ndt_s = 2e-5\n[viscosity]\nalpha = 0.0\nbeta = 0.0\n\
             [[material]]\nname = \"gas\"\neos = {{ kind = \"ideal_gas\", gamma = 1.4 }}\n{}{}",
            region("left", -1.0, 0.0, 2500.0),
            region("right", 0.0, 0.6, 0.025)
        ),
    )
    .unwrap();
    let opts = RunOptions { out: Some(d.path().join("run")), quiet: true, ..Default::default() };
    let e = runner::run(&cf, &opts).err().expect("the run stops").to_string();
    assert!(
        e.contains("h/h0 (smoothing length collapsed)") && e.contains("turn the artificial viscosity back on"),
        "{e}"
    );
}

/// A viscous gas (η = 50 mPa s) in the shock tube under the CFL step: the diffusion limit
/// ρh²/(8η) holds the step, so the run ends stable, in more steps than the inviscid run's. A step
/// near the inviscid one (9.5e-4 s, fixed) blows up at step 10 with this η.
#[test]
fn a_viscous_gas_keeps_the_diffusion_step_limit() {
    let tube = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/shock_tube.toml");
    let steps = |eta: f64| {
        let dir = tempfile::tempdir().expect("tempdir");
        let opts = RunOptions {
            out: Some(dir.path().to_path_buf()),
            quiet: true,
            sets: vec!["time.step=\"cfl\"".into(), format!("material.gas.dynamic_viscosity_pa_s={eta}")],
            ..Default::default()
        };
        let r = runner::run(&tube, &opts).expect("the run");
        assert_eq!(r.summary["status"], "ok", "eta {eta}: {}", r.summary["diagnostic"]);
        r.summary["steps"].as_u64().expect("steps")
    };
    let (inviscid, viscous) = (steps(0.0), steps(0.05));
    // ρh²/(8η) with ρ ≤ 1 kg/m³, h = 0.015 m: at most 5.6e-4 s, against 9.5e-4 s inviscid
    assert!(viscous > 5 * inviscid, "steps {viscous} (viscous) against {inviscid} (inviscid)");
}
