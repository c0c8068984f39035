//! Soil at rest and boundaries that let waves out: the geostatic start (a column of sand left
//! alone under gravity stays put) and the absorbing wall (a plane wave in sand leaves through
//! it). Full measurements: `cargo test --release --test sand -- --ignored --nocapture`
//! (docs/validation.md, "Geostatic start" and "Absorbing walls").

use blastsph::case;
use blastsph::modules::Backend;
use blastsph::sim::{Overrides, Sim};
use std::path::Path;

fn rust() -> Overrides {
    Overrides { backend: Some(Backend::Rust), ..Default::default() }
}

fn load(rel: &str, sets: &[&str]) -> case::Case {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(rel);
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    case::load(&path, &sets).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// Runs the case to its end; returns the largest speed (m/s) any real particle had at the end of
/// any step, and the sim.
fn max_speed(c: case::Case) -> (f64, Sim) {
    let mut sim = Sim::new(c, &rust()).expect("sim");
    let end = sim.cfg.end;
    let dim = sim.cfg.dim;
    let mut vmax = 0.0f64;
    while sim.t < end * (1.0 - 1e-12) {
        sim.step().expect("step");
        for i in 0..sim.p.nreal {
            let v2: f64 = (0..dim).map(|d| sim.p.v[d + dim * i].powi(2)).sum();
            vmax = vmax.max(v2.sqrt());
        }
    }
    (vmax, sim)
}

/// A column of loose sand 1 m deep, 0.2 m wide (Δx = 2 cm), under gravity for `end` s: the
/// geostatic start holds it (speeds under 1 mm/s); from a uniform density it settles at about
/// g H / c.
fn column(end: &str, extra: &[&str]) -> (f64, f64) {
    let t = format!("time.end_s={end}");
    let mut on = vec![t.as_str()];
    on.extend_from_slice(extra);
    let (v_geo, sim) = max_speed(load("cases/verify/geostatic_column.toml", &on));
    // the stress is there: the bottom row carries the column's weight, σ_v = ρ g (H − Δx/2)
    let dim = 2;
    let bottom = (0..sim.p.nreal).find(|&i| sim.x_init[dim * i + 1] < 0.011).expect("a bottom particle");
    let tyy = sim.p.tau[6 * bottom + 1];
    let sv = sim.p.p[bottom] - tyy;
    let want = 1450.0 * 9.81 * 0.99;
    assert!((sv / want - 1.0).abs() < 0.05, "bottom σ_v = {sv} Pa against ρ g z = {want} Pa");
    let mut off = on.clone();
    off.push("initial.geostatic=false");
    let (v_flat, _) = max_speed(load("cases/verify/geostatic_column.toml", &off));
    eprintln!("column to {end} s: max speed {v_geo:.3e} m/s geostatic, {v_flat:.3e} m/s from a uniform density");
    (v_geo, v_flat)
}

#[test]
fn a_sand_column_at_rest_stays_put_short() {
    let (geo, flat) = column("0.002", &[]);
    assert!(geo < 1e-3, "geostatic column moved at {geo} m/s");
    // the test can tell: without the geostatic stress the column settles visibly faster
    assert!(flat > 3.0 * geo, "uniform start {flat} m/s against geostatic {geo} m/s");
}

#[test]
#[ignore]
fn a_sand_column_at_rest_stays_put_10_ms() {
    let (geo, _) = column("0.01", &[]);
    assert!(geo < 1e-3, "geostatic column moved at {geo} m/s");
}
