//! Air beside dense materials: number density with the interface pressure form (the defaults
//! where a gas meets another material). Air at rest beside water at 900 times its density stays
//! at rest, and a TNT sphere in free air gives Kinney & Graham's (1985) blast within the
//! tolerances docs/validation.md ("Air blast") measures. The full-length blast:
//! `cargo test --release --test air -- --ignored`.

use blastsph::analysis::airblast;
use blastsph::runner::{self, RunOptions};
use blastsph::sim::Overrides;
use serde_json::Value;
use std::path::Path;

/// Runs the case text (Rust backend) with `sets`; its summary and sim.
fn run_text(text: &str, sets: &[&str]) -> (Value, blastsph::sim::Sim) {
    let d = tempfile::tempdir().unwrap();
    let cf = d.path().join("case.toml");
    std::fs::write(&cf, text).unwrap();
    let opts = RunOptions {
        out: Some(d.path().join("run")),
        quiet: true,
        sets: sets.iter().map(|s| s.to_string()).collect(),
        ov: Overrides { backend: Some(blastsph::modules::Backend::Rust), ..Default::default() },
        ..Default::default()
    };
    let r = runner::run(&cf, &opts).unwrap_or_else(|e| panic!("{e}"));
    (r.summary, r.sim)
}

/// A 0.3 x 0.3 m box, air over water, 2D plane at 1 cm, closed by mirror walls, for 2 ms. The
/// water is Tait's (p = B ((ρ/ρ0)^7 − 1), B = 101.3 kPa) at ρ = ρ0 2^(1/7) = 1104 kg/m³, where its
/// pressure is the air's 101.325 kPa (to the lattice's 0.1 % in B): no force but the method's.
const AIR_OVER_WATER: &str = r#"name = "air_over_water"
dim = 2
[time]
end_s = 2.0e-3
output_interval_s = 1.0e-3
[[material]]
name = "water"
eos = { kind = "tait", b_pa = 101325.0 }
[[material]]
name = "air"
preset = "air"
[[region]]
name = "water"
material = "water"
shape = "box"
lo_m = [0.0, 0.0]
hi_m = [0.3, 0.15]
spacing_m = 0.01
rho_kgm3 = 1104.0895136738122
[[region]]
name = "air"
material = "air"
shape = "box"
lo_m = [0.0, 0.15]
hi_m = [0.3, 0.3]
spacing_m = 0.01
[[wall]]
from_m = [0.0, 0.0]
to_m = [0.3, 0.0]
kind = "mirror"
[[wall]]
from_m = [0.3, 0.0]
to_m = [0.3, 0.3]
kind = "mirror"
[[wall]]
from_m = [0.0, 0.3]
to_m = [0.3, 0.3]
kind = "mirror"
[[wall]]
from_m = [0.0, 0.0]
to_m = [0.0, 0.3]
kind = "mirror"
"#;

fn max_speed(sim: &blastsph::sim::Sim) -> f64 {
    let (dim, n) = (sim.p.dim, sim.p.nreal);
    (0..n).map(|i| (0..dim).map(|d| sim.p.v[d + dim * i].powi(2)).sum::<f64>().sqrt()).fold(0.0, f64::max)
}

#[test]
fn air_at_rest_beside_water_stays_at_rest() {
    let (s, sim) = run_text(AIR_OVER_WATER, &[]);
    assert_eq!(s["status"], "ok", "{}", s["diagnostic"]);
    assert_eq!(sim.case.sph.density, blastsph::case::DensityKind::Number);
    assert_eq!(sim.case.sph.pressure_form, blastsph::case::PressureForm::Interface);
    // the air keeps its density: every air particle within 1 % of 1.225 kg/m³
    let air = sim.case.material_index("air").unwrap() as i32;
    let n = sim.p.nreal;
    let worst = (0..n).filter(|&i| sim.p.mat[i] == air).map(|i| (sim.p.rho[i] / 1.225 - 1.0).abs()).fold(0.0, f64::max);
    assert!(worst < 0.01, "an air particle's density is {worst:.3} off 1.225 kg/m³");
    // and stays at rest: under 1 % of the air's sound speed (343 m/s)
    let v = max_speed(&sim);
    assert!(v < 3.4, "fastest particle at {v} m/s");
    // mass summation, the standard pressure form: the air reads the water's masses and is thrown
    let (s, sim) =
        run_text(AIR_OVER_WATER, &["sph.density=summation", "sph.pressure_form=standard", "time.end_s=2e-4"]);
    let thrown = s["status"] != "ok" || max_speed(&sim) > 30.0;
    assert!(thrown, "summation kept the air at rest ({} m/s): the test above would not tell", max_speed(&sim));
}

/// Runs cases/verify/airblast_rz.toml to `end` s; per gauge (name, Z, peak/KG, impulse/KG).
fn airblast(end: f64) -> Vec<(String, f64, f64, f64)> {
    let d = tempfile::tempdir().unwrap();
    let cf = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/verify/airblast_rz.toml");
    let opts = RunOptions {
        out: Some(d.path().join("run")),
        quiet: true,
        ov: Overrides { backend: Some(blastsph::modules::Backend::Rust), end_time: Some(end), ..Default::default() },
        ..Default::default()
    };
    let r = runner::run(&cf, &opts).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(r.summary["status"], "ok", "{}", r.summary["diagnostic"]);
    let sim = &r.sim;
    let tnt = sim.case.material_index("tnt").unwrap() as i32;
    // the whole charge: the modelled half (ring masses) and its image across the plane z = 0
    let w = 2.0 * (0..sim.p.nreal).filter(|&i| sim.p.mat[i] == tnt).map(|i| sim.p.mass[i]).sum::<f64>();
    // gauges.csv: time_s, then each gauge's <name>_p_pa
    let text = std::fs::read_to_string(d.path().join("run/gauges.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let rows: Vec<Vec<Option<f64>>> = lines.map(|l| l.split(',').map(|f| f.parse().ok()).collect()).collect();
    let t: Vec<f64> = rows.iter().map(|r| r[0].unwrap()).collect();
    sim.case
        .gauges
        .iter()
        .map(|gc| {
            let c = head.iter().position(|h| *h == format!("{}_p_pa", gc.name)).unwrap();
            let p: Vec<Option<f64>> = rows.iter().map(|r| r[c]).collect();
            let z = gc.point_m[0].hypot(gc.point_m[1]) / w.cbrt();
            let (peak, imp) = airblast::measure(&t, &p, p[0].unwrap()).unwrap_or((0.0, 0.0));
            (gc.name.clone(), z, peak / airblast::overpressure(z), imp / airblast::impulse(z, w))
        })
        .collect()
}

/// The short version: to 1.25 ms, the gauges at Z = 1.5 and 2 m/kg^⅓ in the plane z = 0. At
/// 10 mm (3 rings of charge), at the defaults (β = 2 with the switch where a gas meets another
/// material), the peaks came within 16 % of Kinney & Graham: held to 20 %. The positive impulse
/// measured 0.75–0.81 of theirs on average over four directions at every viscosity tried (β = 10,
/// β = 2, β = 2 with the switch; docs/validation.md, "Air blast"), 0.79 here: held to 25 %.
#[test]
fn tnt_in_free_air_against_kinney_graham() {
    let rows = airblast(1.25e-3);
    for (name, z, rp, ri) in rows.iter().filter(|r| r.0 == "Z1.5" || r.0 == "Z2") {
        eprintln!("{name}: Z = {z:.2}, peak {rp:.2}, impulse {ri:.2} of Kinney & Graham");
        assert!((rp - 1.0).abs() < 0.2, "{name}: peak {rp:.2} of Kinney & Graham");
        assert!((ri - 1.0).abs() < 0.25, "{name}: impulse {ri:.2} of Kinney & Graham");
    }
    assert_eq!(rows.iter().filter(|r| r.0 == "Z1.5" || r.0 == "Z2").count(), 2);
}

/// The full case to 3 ms (about a minute): docs/validation.md's "Air blast" table, the gauges in
/// the plane z = 0. Peaks within 20 % at Z = 1.5–3, impulses within 25 % there.
#[test]
#[ignore]
fn tnt_in_free_air_full() {
    let rows = airblast(3.0e-3);
    for (name, z, rp, ri) in &rows {
        eprintln!("{name}: Z = {z:.2}, peak {rp:.2}, impulse {ri:.2} of Kinney & Graham");
        if *z > 1.2 {
            assert!((rp - 1.0).abs() < 0.2, "{name}: peak {rp:.2}");
            assert!((ri - 1.0).abs() < 0.25, "{name}: impulse {ri:.2}");
        }
    }
}

/// The penalty force leaves the air alone by default: on a particle 10³ times lighter than the
/// soil, its P̄ (an energy) gives a 10³ times larger push. The charge on sand under air to
/// 0.2 ms: residual 0.74 % with the air exempt, 1.5 % with the air in a penalty group of its own
/// (+0.9 % against +6.9 % at 1 ms; docs/validation.md, "Air blast"). Under the parity preset the
/// thesis's groups stay.
#[test]
fn the_penalty_force_leaves_the_air_alone() {
    let cf = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/surface_tnt_air_rz.toml");
    let group = |sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let c = blastsph::case::load(&cf, &sets).unwrap();
        let m = c.material_index("air").unwrap();
        c.materials[m].penalty_group.clone()
    };
    assert_eq!(group(&[]).as_deref(), Some("none"));
    assert_eq!(group(&["parity=\"thesis\""]), None);
    let text = std::fs::read_to_string(&cf).unwrap();
    let residual = |sets: &[&str]| {
        let mut all = vec!["time.end_s=2e-4"];
        all.extend_from_slice(sets);
        let (s, _) = run_text(&text, &all);
        assert_eq!(s["status"], "ok");
        s["energy"]["balance_residual_relative"].as_f64().unwrap()
    };
    let (exempt, pushed) = (residual(&[]), residual(&["material.air.penalty_group=\"air\""]));
    assert!(exempt.abs() < 0.01, "residual {exempt:.3e} with the air exempt");
    assert!(pushed > 0.012, "residual {pushed:.3e} with the penalty on the air: the test above would not tell");
}
