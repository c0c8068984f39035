//! Boundary particles (`[[region]] boundary_particles`, Liu & Liu 2003's virtual particles):
//! a water column on a floor of held particles stays put while without the floor it falls; the
//! integrator never moves either kind and holds the held kind's ρ, e, v; the dual run over the
//! shipped dam break is at 0 ULP; the kinds survive a checkpoint and reach particles.h5; bad
//! values are refused in one line with exit status 2; the energy the held walls absorb closes the
//! balance.

use blastsph::case;
use blastsph::output::read_frames;
use blastsph::sim::{Blob, Overrides, Sim};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Spacing of the column and of its tank (m).
const DX: f64 = 0.01;

fn dam_break() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/dam_break_held.toml")
}

/// A water column 0.1 m wide and 0.2 m tall (Tait water, c = 30 m/s) under gravity, in a tank of
/// boundary particles of `kind` (three layers: a floor and two walls touching the column), or
/// with no tank when `kind` is None.
fn column(kind: Option<&str>) -> String {
    let mut s = String::from(
        r#"
name = "column"
dim = 2

[time]
end_s = 0.1
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

[physics]
gravity_ms2 = [0.0, -9.81]

[[material]]
name = "water"
eos = { kind = "tait", rho0_kgm3 = 1000.0, b_pa = 128571.43, gamma = 7.0, c_ms = 30.0 }

[[region]]
name = "water"
material = "water"
shape = "box"
lo_m = [0.0, 0.0]
hi_m = [0.1, 0.2]
spacing_m = 0.01
"#,
    );
    if let Some(k) = kind {
        for (name, lo, hi) in [
            ("floor", [-0.03, -0.03], [0.13, 0.0]),
            ("left", [-0.03, 0.0], [0.0, 0.25]),
            ("right", [0.1, 0.0], [0.13, 0.25]),
        ] {
            s += &format!(
                "\n[[region]]\nname = \"{name}\"\nmaterial = \"water\"\nshape = \"box\"\nlo_m = {lo:?}\nhi_m = {hi:?}\nspacing_m = 0.01\nboundary_particles = \"{k}\"\n"
            );
        }
    }
    s
}

fn sim_of(text: &str, backend: Option<&str>) -> Sim {
    let c = case::parse(text, "column.toml", &[], None).expect("the column case parses");
    let backend = backend
        .map(|b| if b == "rust" { blastsph::modules::Backend::Rust } else { blastsph::modules::Backend::Fortran });
    Sim::new(c, &Overrides { backend, ..Default::default() }).expect("the column case sets up")
}

fn run_to(sim: &mut Sim, t: f64) {
    while sim.t < t {
        sim.step().expect("a step");
    }
}

/// (lowest y of the water (m), largest |v| of the water (m/s), mean v_y of the water (m/s)).
fn water_stats(sim: &Sim) -> (f64, f64, f64) {
    let p = &sim.p;
    let (mut ymin, mut vmax, mut vy, mut n) = (f64::INFINITY, 0.0f64, 0.0, 0.0);
    for i in 0..p.nreal {
        if p.bnd.get(i).copied().unwrap_or(0) != 0 {
            continue;
        }
        ymin = ymin.min(p.x[2 * i + 1]);
        vmax = vmax.max(p.v[2 * i].hypot(p.v[2 * i + 1]));
        vy += p.v[2 * i + 1];
        n += 1.0;
    }
    (ymin, vmax, vy / n)
}

/// The floor holds the column for 0.1 s: no water particle sinks below the floor's top row, the
/// mean velocity stays under 5 % of free fall's g t and the largest speed under 20 % (the column
/// starts at uniform density, not hydrostatic: it rings at about g H / c = 0.065 m/s). The
/// boundary particles keep their positions bit for bit, the held ones their ρ, e, v. Without the
/// tank the column falls: its mean velocity is within 10 % of g t, its lowest particle as far.
#[test]
fn a_floor_of_held_particles_holds_a_water_column_that_falls_without_it() {
    let t = 0.1;
    let free = 9.81 * t;
    let mut held = sim_of(&column(Some("held")), None);
    let start = held.p.clone();
    let nb = start.bnd.iter().filter(|&&k| k == 2).count();
    assert_eq!(nb, 16 * 3 + 2 * 25 * 3, "held particles");
    run_to(&mut held, t);
    let (ymin, vmax, vy) = water_stats(&held);
    eprintln!(
        "held floor, t = {:.4} s: lowest water y {ymin:.5} m, largest |v| {vmax:.4} m/s, mean vy {vy:.5} m/s",
        held.t
    );
    assert!(ymin > -0.5 * DX, "a water particle went through the floor: y = {ymin}");
    assert!(vy.abs() < 0.05 * free, "mean vertical velocity {vy} m/s against free fall's {free}");
    assert!(vmax < 0.2 * free, "largest speed {vmax} m/s against free fall's {free}");
    let p = &held.p;
    for i in 0..p.nreal {
        let id = p.id[i] as usize;
        if start.bnd[id] == 0 {
            continue;
        }
        assert_eq!(p.bnd[i], start.bnd[id]);
        assert_eq!(&p.x[2 * i..2 * i + 2], &start.x[2 * id..2 * id + 2], "boundary particle {id} moved");
        assert_eq!(&p.v[2 * i..2 * i + 2], &start.v[2 * id..2 * id + 2], "held particle {id}: v");
        assert_eq!((p.rho[i], p.e[i]), (start.rho[id], start.e[id]), "held particle {id}: rho, e");
    }

    let mut bare = sim_of(&column(None), None);
    assert!(bare.p.bnd.is_empty());
    run_to(&mut bare, t);
    let (ymin, _, vy) = water_stats(&bare);
    let fall = -vy / (9.81 * bare.t);
    eprintln!("no floor, t = {:.4} s: lowest water y {ymin:.5} m, mean vy {vy:.5} m/s ({fall:.4} g t)", bare.t);
    assert!((0.9..=1.1).contains(&fall), "mean velocity {vy} m/s: {fall} g t");
    // the lowest row starts at y = Δx/2
    assert!(ymin < 0.5 * DX - 0.9 * 0.5 * 9.81 * bare.t * bare.t, "lowest water y {ymin} m");
}

/// Integrated boundary particles: x never moves and gravity does not act on them, while the water
/// falling on them changes their ρ (continuity) and v, and stays above them.
#[test]
fn integrated_boundary_particles_stay_in_place_and_evolve() {
    let mut sim = sim_of(&column(Some("integrated")), Some("fortran"));
    let start = sim.p.clone();
    assert!(start.bnd.iter().all(|&k| k == 0 || k == 1));
    for _ in 0..40 {
        sim.step().expect("a step");
    }
    let p = &sim.p;
    let (mut drho, mut dv) = (0, 0);
    for i in 0..p.nreal {
        let id = p.id[i] as usize;
        if start.bnd[id] != 1 {
            continue;
        }
        assert_eq!(&p.x[2 * i..2 * i + 2], &start.x[2 * id..2 * id + 2], "boundary particle {id} moved");
        drho += usize::from(p.rho[i] != start.rho[id]);
        dv += usize::from(p.v[2 * i + 1] != start.v[2 * id + 1]);
    }
    let nb = start.bnd.iter().filter(|&&k| k == 1).count();
    assert!(nb > 0 && dv > 0, "no integrated particle's v changed");
    assert!(drho > 0, "no integrated particle's density changed");
    let (ymin, _, _) = water_stats(&sim);
    assert!(ymin > 0.0, "lowest water y {ymin} m");

    // the column itself made of integrated particles too: at rest at uniform density, under
    // gravity, nothing moves (gravity does not act on boundary particles; it would give -g t)
    let all = column(Some("integrated")).replacen(
        "spacing_m = 0.01\n",
        "spacing_m = 0.01\nboundary_particles = \"integrated\"\n",
        1,
    );
    let mut sim = sim_of(&all, Some("rust"));
    assert!(sim.p.bnd.iter().all(|&k| k == 1));
    for _ in 0..40 {
        sim.step().expect("a step");
    }
    assert!(sim.t > 0.0);
    assert!(sim.p.v.iter().all(|&v| v == 0.0), "a boundary particle moves");
}

/// A checkpoint carries the kinds: a run restored from it after 20 steps goes on bit for bit as
/// the run it was taken from.
#[test]
fn a_restored_run_continues_bit_for_bit() {
    let text = column(Some("held"));
    let mut a = sim_of(&text, None);
    for _ in 0..20 {
        a.step().unwrap();
    }
    let bytes = {
        let mut b = Blob::default();
        a.save_state(&mut b);
        b.encode()
    };
    let mut b = sim_of(&text, None);
    b.p.bnd.iter_mut().for_each(|k| *k = 0);
    b.restore_state(&Blob::decode(&bytes).unwrap()).expect("restore");
    assert_eq!(b.p.bnd, a.p.bnd);
    for _ in 0..20 {
        a.step().unwrap();
        b.step().unwrap();
    }
    assert_eq!(a.p.x, b.p.x);
    assert_eq!(a.p.v, b.p.v);
    assert_eq!(a.p.rho, b.p.rho);
}

fn blastsph(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_blastsph")).args(args).output().expect("the blastsph binary runs")
}

/// `blastsph dual` over the shipped dam break: every row at 0 ULP, the integrator's stages
/// among them; `run` writes the kinds to particles.h5 and names them in particles.xmf.
#[test]
fn dam_break_dual_at_zero_ulp_and_kinds_in_the_output() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_str().unwrap();
    let out = blastsph(&["dual", dam_break().to_str().unwrap(), "--steps", "30", "--out", d]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let rep: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("dual_report.json")).unwrap()).unwrap();
    assert_eq!(rep["within_tolerance"], Value::Bool(true));
    let rows = rep["rows"].as_array().unwrap();
    let mut stages = Vec::new();
    for r in rows {
        assert_eq!(r["max_ulp"].as_u64(), Some(0), "{r}");
        if r["compared"].as_u64().unwrap_or(0) > 0 {
            stages.push(r["stage"].as_str().unwrap().to_string());
        }
    }
    for s in ["integrator.predict", "integrator.advance", "force.internal"] {
        assert!(stages.iter().any(|x| x == s), "{s} not compared: {stages:?}");
    }

    let run = dir.path().join("run");
    let c = case::load(&dam_break(), &[]).unwrap();
    let out = blastsph(&[
        "run",
        dam_break().to_str().unwrap(),
        "--quiet",
        "--end-time",
        "0.02",
        "--out",
        run.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let frames = read_frames(&run.join("particles.h5")).unwrap();
    let last = frames.last().unwrap();
    let water = c.regions.iter().position(|r| r.name == "water").unwrap();
    let counts: Vec<usize> = (0..3).map(|k| last.bnd.iter().filter(|&&b| b == k).count()).collect();
    assert_eq!(counts[1], 0);
    assert_eq!(counts[0], 10 * 20, "water particles (region {water})");
    assert_eq!(counts[0] + counts[2], last.x.len());
    let xmf = std::fs::read_to_string(run.join("particles.xmf")).unwrap();
    assert!(xmf.contains("Name=\"bnd\""), "particles.xmf names no bnd attribute");
}

/// An unknown kind, and held particles with h by rate, are refused in one line, exit status 2.
#[test]
fn bad_kinds_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    for (what, text, want) in [
        ("unknown kind", column(Some("fixed")), "unknown variant `fixed`"),
        ("held with smoothing = rate", column(Some("held")).replace("\"constant\"", "\"rate\""), "smoothing"),
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

/// The shipped dam break's energy balance closes once the held particles' share is booked: the
/// residual is below 0.1 % of gravity's work, while the booked share is several per cent of it
/// (without it the residual would be that share).
#[test]
fn the_held_walls_share_closes_the_energy_balance() {
    let dir = tempfile::tempdir().unwrap();
    let out = blastsph(&["run", dam_break().to_str().unwrap(), "--quiet", "--out", dir.path().to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let s: Value = serde_json::from_str(&std::fs::read_to_string(dir.path().join("summary.json")).unwrap()).unwrap();
    let en = &s["energy"];
    let f = |k: &str| en[k].as_f64().unwrap_or_else(|| panic!("energy.{k} missing: {en}"));
    let (gravity, boundary, residual) = (f("work_gravity"), f("work_boundary"), f("balance_residual"));
    assert!(gravity > 5.0, "gravity's work {gravity} J/m");
    assert!(boundary < -0.02 * gravity, "held walls' share {boundary} J/m against gravity's {gravity}");
    assert!(residual.abs() < 1e-3 * gravity, "residual {residual} J/m against gravity's work {gravity}");
    assert!(!String::from_utf8_lossy(&out.stderr).contains("WARNING"), "{}", String::from_utf8_lossy(&out.stderr));
}
