//! The repulsion of boundary particles (`[boundary] repulsion`, Liu & Liu 2003's `ext_force`): a
//! water particle thrown at a floor of held particles turns back before reaching its top row,
//! where without the repulsion it goes through; the dual run of a case with it is at 0 ULP; bad
//! values are refused in one line with exit status 2.

use blastsph::case;
use blastsph::sim::{Overrides, Sim};
use serde_json::Value;
use std::process::Command;

/// One water particle at (0, 0.03) m moving down at `speed` m/s, no gravity, over a floor of
/// held particles three rows deep (top row at y = −0.005 m); `repulsion` is the table's value.
fn drop_case(speed: f64, repulsion: Option<&str>) -> String {
    drop_case_ordered(speed, repulsion, false)
}

/// [`drop_case`], with the floor's region first when `floor_first` (its particles then get the
/// lower indices).
fn drop_case_ordered(speed: f64, repulsion: Option<&str>, floor_first: bool) -> String {
    let header = r#"
name = "drop"
dim = 2

[time]
end_s = 0.05
step = "cfl"
cfl = 0.25

[sph]
kernel = "cubic"
nnps = "cell"
density = "continuity"
smoothing = "constant"
h_over_dx = 1.2

[viscosity]
alpha = 0.1
beta = 0.0

[[material]]
name = "water"
eos = { kind = "tait", rho0_kgm3 = 1000.0, b_pa = 128571.43, gamma = 7.0, c_ms = 30.0 }

"#;
    let drop = format!(
        r#"[[region]]
name = "drop"
material = "water"
shape = "box"
lo_m = [-0.005, 0.025]
hi_m = [0.005, 0.035]
spacing_m = 0.01
velocity_ms = [0.0, {v}]

"#,
        v = -speed
    );
    let floor = r#"[[region]]
name = "floor"
material = "water"
shape = "box"
lo_m = [-0.05, -0.03]
hi_m = [0.05, 0.0]
spacing_m = 0.01
boundary_particles = "held"
"#;
    let mut s = if floor_first { format!("{header}{floor}\n{drop}") } else { format!("{header}{drop}\n{floor}") };
    if let Some(r) = repulsion {
        s += &format!("\n[boundary]\nrepulsion = {r}\n");
    }
    s
}

/// Runs the drop for `t` seconds: (lowest y of the water particle (m), its final v_y (m/s)).
fn lowest(text: &str, t: f64) -> (f64, f64) {
    let c = case::parse(text, "drop.toml", &[], None).expect("the drop case parses");
    let mut sim = Sim::new(c, &Overrides::default()).expect("the drop case sets up");
    let i = (0..sim.p.nreal).find(|&i| sim.p.bnd[i] == 0).expect("one water particle");
    assert_eq!(sim.p.bnd.iter().filter(|&&k| k == 0).count(), 1);
    let mut ymin = f64::INFINITY;
    while sim.t < t {
        sim.step().expect("a step");
        let k = (0..sim.p.nreal).find(|&k| sim.p.id[k] as usize == i).unwrap();
        ymin = ymin.min(sim.p.x[2 * k + 1]);
    }
    let k = (0..sim.p.nreal).find(|&k| sim.p.id[k] as usize == i).unwrap();
    (ymin, sim.p.v[2 * k + 1])
}

/// At 80 m/s (above the sound speed, 30 m/s) the pressure of the held floor does not stop the
/// particle: without the repulsion it passes the floor's top row (y = −0.005 m). With r0 = 0.01 m
/// and D = v² it turns back above the floor's surface (y = 0), whether the floor's particles come
/// before the water's or after (the ordinary member first in a pair, or second). At 5 m/s with
/// r0 = 0.02 m the pressure turns it back, and the repulsion keeps it farther from the floor.
#[test]
fn a_particle_thrown_at_a_held_floor_turns_back_before_its_top_row() {
    let rep = "{ r0_m = 0.01, d_m2s2 = 6400.0 }";
    let without = lowest(&drop_case(80.0, None), 0.05);
    let with = lowest(&drop_case(80.0, Some(rep)), 0.05);
    // the floor's region first: its particles get the lower indices
    let floor_first = lowest(&drop_case_ordered(80.0, Some(rep), true), 0.05);
    eprintln!(
        "80 m/s: lowest y without {:.5} m; with {:.5} m (v_y {:.3} m/s); floor first {:.5} m",
        without.0, with.0, with.1, floor_first.0
    );
    assert!(without.0 < -0.005, "without the repulsion the particle stops at y = {} m", without.0);
    for (what, (y, vy)) in [("water first", with), ("floor first", floor_first)] {
        assert!(y > 0.0 && vy > 0.0, "{what}: lowest y {y} m, final v_y {vy} m/s");
    }
    let slow = lowest(&drop_case(5.0, Some("{ r0_m = 0.02, d_m2s2 = 25.0 }")), 0.05);
    let slow_without = lowest(&drop_case(5.0, None), 0.05);
    eprintln!("5 m/s: lowest y without {:.5} m; with r0 = 0.02 m {:.5} m", slow_without.0, slow.0);
    assert!(slow.0 > slow_without.0 + 0.002, "with {} m, without {} m", slow.0, slow_without.0);
}

fn blastsph(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_blastsph")).args(args).output().expect("the blastsph binary runs")
}

/// `blastsph dual` over the drop at 80 m/s: every row at 0 ULP, `boundary.repulsion` among them.
#[test]
fn dual_of_the_repulsion_at_zero_ulp() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("drop.toml");
    std::fs::write(&path, drop_case(80.0, Some("{ r0_m = 0.01, d_m2s2 = 6400.0, p1 = 12.0, p2 = 4.0 }"))).unwrap();
    let out_dir = dir.path().join("dual");
    let out = blastsph(&["dual", path.to_str().unwrap(), "--steps", "200", "--out", out_dir.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let rep: Value = serde_json::from_str(&std::fs::read_to_string(out_dir.join("dual_report.json")).unwrap()).unwrap();
    let rows = rep["rows"].as_array().unwrap();
    for r in rows {
        assert_eq!(r["max_ulp"].as_u64(), Some(0), "{r}");
    }
    let pushed = rows.iter().any(|r| r["stage"] == "boundary.repulsion" && r["compared"].as_u64().unwrap_or(0) > 0);
    assert!(pushed, "boundary.repulsion not compared");
}

/// Zero, negative and non-finite numbers, p1 ≤ p2, an unknown key, and a case with no boundary
/// particles are refused in one line, exit status 2.
#[test]
fn bad_repulsion_values_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let no_floor = {
        let t = drop_case(2.0, Some("{ r0_m = 0.01, d_m2s2 = 4.0 }"));
        t.replace("boundary_particles = \"held\"\n", "")
    };
    for (what, text, want) in [
        ("r0 zero", drop_case(2.0, Some("{ r0_m = 0.0, d_m2s2 = 4.0 }")), "boundary.repulsion.r0_m = 0"),
        ("D negative", drop_case(2.0, Some("{ r0_m = 0.01, d_m2s2 = -4.0 }")), "boundary.repulsion.d_m2s2 = -4"),
        ("D infinite", drop_case(2.0, Some("{ r0_m = 0.01, d_m2s2 = inf }")), "boundary.repulsion.d_m2s2"),
        ("p2 zero", drop_case(2.0, Some("{ r0_m = 0.01, d_m2s2 = 4.0, p2 = 0.0 }")), "boundary.repulsion.p2 = 0"),
        ("p1 = p2", drop_case(2.0, Some("{ r0_m = 0.01, d_m2s2 = 4.0, p1 = 4.0 }")), "need p1 > p2"),
        ("unknown key", drop_case(2.0, Some("{ r0_m = 0.01, d_m2s2 = 4.0, n1 = 12 }")), "unknown field `n1`"),
        ("missing D", drop_case(2.0, Some("{ r0_m = 0.01 }")), "d_m2s2"),
        ("no boundary particles", no_floor, "no boundary particles"),
    ] {
        let path = dir.path().join("bad.toml");
        std::fs::write(&path, text).unwrap();
        let out = blastsph(&["check", path.to_str().unwrap()]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{what}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{what}: {err}");
        assert!(err.contains(want), "{what}: {err}");
    }
}
