//! The dual run end to end (docs/design.md, the dual run): `blastsph dual` over the shock tube and over a
//! small synthetic case in which every module is active, the structure of `dual_report.json`,
//! how a divergence is reported (module, field, step, particle), the free-running mode, and
//! thread-count independence of the Rust twins (bitwise-identical `particles.h5`).
//!
//! Observed on the development machine: every row of every dual run here is at 0 ULP (also eos
//! and smoothing, whose tier allows 4), and the free runs are bitwise identical at every step.

mod common;
use blastsph::case;
use blastsph::cli;
use blastsph::dual::Comparator;
use blastsph::modules::{Backend, Module, Stage};
use blastsph::sim::Overrides;
use blastsph::state::{Clock, Field, Particles, Work};
use common::h5_bits;
use serde_json::Value;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn shock_tube() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/shock_tube.toml")
}

fn blastsph(args: &[&str]) -> Output {
    let out = Command::new(env!("CARGO_BIN_EXE_blastsph")).args(args).output().expect("the blastsph binary runs");
    assert!(
        out.status.success(),
        "blastsph {args:?} failed ({}):\n{}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn read_json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A 2D case in which every module is active: TNT lit by a programmed burn in water over sand
/// with strength (three penalty groups), continuity density, h by rate, XSPH, gravity, CFL step,
/// cell search, walls with both type I force and type II mirrors (corners, so second-generation
/// mirrors appear), an absorbing wall over the water. Synthetic and small (256 particles): not a thesis scene.
const ALL_MODULES: &str = r#"
name = "dual_all_modules"
description = "synthetic: every module active (not a thesis scene)"
dim = 2

[time]
end_s = 1.0e-3
step = "cfl"
cfl = 0.25

[sph]
kernel = "cubic"
nnps = "cell"
density = "continuity"
smoothing = "rate"
xsph_eps = 0.3

[viscosity]
alpha = 1.0
beta = 10.0

[conductivity]
alpha = 1.0
signal = "velocity"

[penalty]
pbar = 1.0e5

[physics]
gravity_ms2 = [0.0, -9.81]

[[material]]
name = "tnt"
eos = { kind = "jwl", rho0_kgm3 = 1630.0, a_pa = 3.712e11, b_pa = 3.21e9, r1 = 4.15, r2 = 0.95, omega = 0.30, d_ms = 6930.0 }
e0_jkg = 4.29e6

[[material]]
name = "water"
eos = { kind = "water", rho0_kgm3 = 1000.0, a1_pa = 2.19e9, a2_pa = 9.224e9, a3_pa = 8.767e9, b0 = 0.4934, b1 = 1.3937, c0_ms = 1480.0 }
e0_jkg = 357.1
pmin_pa = -1.0e5
dynamic_viscosity_pa_s = 1.0e-3

[[material]]
name = "sand"
eos = { kind = "soil", rho0_kgm3 = 1450.0, c_ms = 1440.0, s = 1.6, gamma = 0.11 }
strength = { shear_modulus_pa = 63.58e6, alpha_phi = 0.25, cohesion_pa = 2.0e3 }
pmin_pa = 0.0

[[region]]
name = "sand"
material = "sand"
shape = "box"
lo_m = [0.0, 0.0]
hi_m = [0.16, 0.08]
spacing_m = 0.01

[[region]]
name = "water"
material = "water"
shape = "box"
lo_m = [0.0, 0.08]
hi_m = [0.16, 0.16]
spacing_m = 0.01
subtract = ["charge"]

[[region]]
name = "charge"
material = "tnt"
shape = "box"
lo_m = [0.06, 0.08]
hi_m = [0.10, 0.12]
spacing_m = 0.01

[detonation]
mode = "programmed"
point_m = [0.08, 0.10]
width_h = 1.0

[[wall]]
from_m = [0.0, 0.0]
to_m = [0.16, 0.0]
kind = "both"

[[wall]]
from_m = [0.16, 0.0]
to_m = [0.16, 0.16]
kind = "mirror"

[[wall]]
from_m = [0.0, 0.16]
to_m = [0.0, 0.0]
kind = "both"

[[wall]]
from_m = [0.16, 0.16]
to_m = [0.0, 0.16]
kind = "absorbing"
"#;

fn write_all_modules(dir: &Path) -> PathBuf {
    let path = dir.join("dual_all_modules.toml");
    std::fs::write(&path, ALL_MODULES).expect("write the synthetic case");
    path
}

/// Checks the structure of a `dual_report.json` and that every row is within tolerance;
/// returns the set of modules that were compared.
fn check_report(path: &Path, steps: u64) -> BTreeSet<String> {
    let rep = read_json(path);
    assert_eq!(rep["steps"].as_u64(), Some(steps), "steps");
    assert!(rep["case"].is_string() && rep["time"].as_f64().unwrap() > 0.0);
    assert_eq!(rep["within_tolerance"], Value::Bool(true));
    assert!(rep["diagnostic"].is_null(), "{}", rep["diagnostic"]);
    let rows = rep["rows"].as_array().expect("rows");
    assert!(!rows.is_empty());
    let mut seen = BTreeSet::new();
    let mut modules = BTreeSet::new();
    for row in rows {
        for key in [
            "module",
            "stage",
            "field",
            "tolerance_ulp",
            "tolerance_why",
            "compared",
            "max_abs",
            "max_rel",
            "max_ulp",
            "out_of_tolerance",
            "first_divergence",
            "first_difference",
        ] {
            assert!(row.get(key).is_some(), "row without `{key}`: {row}");
        }
        let name = row["module"].as_str().expect("module name");
        let stage = row["stage"].as_str().expect("stage name");
        let field = row["field"].as_str().expect("field name");
        assert!(Module::parse(name).is_some(), "unknown module {name}");
        assert!(stage.starts_with(&format!("{name}.")), "stage {stage} of module {name}");
        assert!(seen.insert((stage, field)), "row {stage}/{field} twice");
        // every stage declares 0 ULP (exp and pow come from the same C library on both sides)
        let tol = row["tolerance_ulp"].as_u64().unwrap();
        assert_eq!(tol, 0, "{stage}: tolerance");
        let ulp = row["max_ulp"].as_u64().unwrap();
        assert!(ulp <= tol, "{name}/{field}: {ulp} ULP > {tol}");
        assert_eq!(row["out_of_tolerance"].as_u64(), Some(0), "{name}/{field}");
        assert!(row["first_divergence"].is_null(), "{name}/{field}");
        if row["compared"].as_u64().unwrap() > 0 {
            modules.insert(name.to_string());
        }
        eprintln!("dual {stage}/{field}: max {ulp} ULP (tolerance {tol})");
    }
    modules
}

fn names(list: &[Module]) -> BTreeSet<String> {
    list.iter().map(|m| m.name().to_string()).collect()
}

// ---------------------------------------------------------------------------------------------
// The dual run over the cases.

#[test]
fn dual_shock_tube_every_module_within_tolerance() {
    let dir = tempfile::tempdir().unwrap();
    let c = case::load(&shock_tube(), &[]).expect("shock tube loads");
    let code = cli::dual_run(c, &Overrides::default(), 12, dir.path()).expect("dual run");
    assert_eq!(code, 0, "exit status of a dual run within tolerance");
    let modules = check_report(&dir.path().join("dual_report.json"), 12);
    let expected = names(&[
        Module::Nnps,
        Module::Kernel,
        Module::Density,
        Module::Eos,
        Module::Force,
        Module::Viscosity,
        Module::Integrator,
    ]);
    assert!(modules.is_superset(&expected), "shock tube compared {modules:?}");
}

/// The shock tube with Price's artificial conductivity, both signal speeds, and with the artificial
/// heat (Noh): its stage is compared too (off by default, so no other dual run has it).
#[test]
fn dual_shock_tube_with_conductivity() {
    let price = |signal: &str| vec!["conductivity.alpha=1.0".to_string(), format!("conductivity.signal=\"{signal}\"")];
    for (what, sets) in [
        ("pressure", price("pressure")),
        ("velocity", price("velocity")),
        ("noh", vec!["conductivity.kind=\"noh\"".to_string()]),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let c = case::load(&shock_tube(), &sets).expect("shock tube loads");
        let code = cli::dual_run(c, &Overrides::default(), 12, dir.path()).expect("dual run");
        assert_eq!(code, 0, "{what}: exit status of a dual run within tolerance");
        let modules = check_report(&dir.path().join("dual_report.json"), 12);
        assert!(modules.contains("conductivity"), "{what}: compared {modules:?}");
        let report = std::fs::read_to_string(dir.path().join("dual_report.json")).unwrap();
        let stage = if what == "noh" { "conductivity.noh" } else { "conductivity.price" };
        assert!(report.contains(stage), "{what}: no {stage} row");
    }
}

/// The binary over the whole shock tube (40 steps to t = 0.2 s), with the cell search.
#[test]
fn dual_binary_shock_tube_cell_search() {
    let dir = tempfile::tempdir().unwrap();
    let out = blastsph(&[
        "dual",
        shock_tube().to_str().unwrap(),
        "--steps",
        "100",
        "--nnps",
        "cell",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("module") && stdout.contains("maxULP") && stdout.contains("first divergence"),
        "no table:\n{stdout}"
    );
    assert!(stdout.contains("every module within tolerance"), "{stdout}");
    // the case ends at step 40 (t = 0.2 s, dt = 0.005 s), before the 100 asked for
    check_report(&dir.path().join("dual_report.json"), 40);
}

#[test]
fn dual_every_module_on_a_synthetic_case() {
    let dir = tempfile::tempdir().unwrap();
    let case_path = write_all_modules(dir.path());
    for nnps in ["cell", "direct"] {
        let out = dir.path().join(nnps);
        blastsph(&[
            "dual",
            case_path.to_str().unwrap(),
            "--steps",
            "15",
            "--nnps",
            nnps,
            "--out",
            out.to_str().unwrap(),
        ]);
        let modules = check_report(&out.join("dual_report.json"), 15);
        // every module but the axisymmetric geometry's hoop terms (a plane case; tests/rz3d.rs)
        let plane: Vec<Module> = Module::ALL.iter().copied().filter(|m| *m != Module::Geometry).collect();
        assert_eq!(modules, names(&plane), "modules compared ({nnps})");
    }
}

/// The physical viscosity (`force.newtonian`): the 1D shock tube with a viscous gas (0.1 mPa s;
/// at 50 mPa s its fixed 5 ms step exceeds the viscous limit ρh²/(8η) and the run blows up), and the 2D
/// synthetic case (its water at 1 mPa s, every other module on); the stage is compared at 0 ULP.
#[test]
fn dual_newtonian_viscosity_at_zero_ulp() {
    let dir = tempfile::tempdir().unwrap();
    let synthetic = write_all_modules(dir.path());
    for (what, path, sets) in [
        ("1D", shock_tube(), vec!["material.gas.dynamic_viscosity_pa_s=1.0e-4".to_string()]),
        ("2D", synthetic, vec![]),
    ] {
        let out = dir.path().join(what);
        std::fs::create_dir_all(&out).unwrap();
        let c = case::load(&path, &sets).expect("the case loads");
        let code = cli::dual_run(c, &Overrides::default(), 12, &out).expect("dual run");
        assert_eq!(code, 0, "{what}: exit status of a dual run within tolerance");
        check_report(&out.join("dual_report.json"), 12);
        let report = std::fs::read_to_string(out.join("dual_report.json")).unwrap();
        assert!(report.contains("force.newtonian"), "{what}: no force.newtonian row");
    }
}

/// The synthetic case with its water as Tait water (`kind = "tait"`, the defaults: Liu & Liu's
/// artificial water): the EOS stage, and every stage after it, at 0 ULP.
#[test]
fn dual_tait_water_at_zero_ulp() {
    let dir = tempfile::tempdir().unwrap();
    let polynomial = r#"eos = { kind = "water", rho0_kgm3 = 1000.0, a1_pa = 2.19e9, a2_pa = 9.224e9, a3_pa = 8.767e9, b0 = 0.4934, b1 = 1.3937, c0_ms = 1480.0 }"#;
    assert!(ALL_MODULES.contains(polynomial));
    let path = dir.path().join("dual_tait.toml");
    std::fs::write(&path, ALL_MODULES.replace(polynomial, r#"eos = { kind = "tait" }"#)).unwrap();
    let c = case::load(&path, &[]).expect("the Tait case loads");
    let water = c.materials.iter().find(|m| m.name == "water").unwrap();
    assert_eq!(water.eos.kind(), "tait");
    let code = cli::dual_run(c, &Overrides::default(), 15, dir.path()).expect("dual run");
    assert_eq!(code, 0, "exit status of a dual run within tolerance");
    let modules = check_report(&dir.path().join("dual_report.json"), 15);
    assert!(modules.contains("eos"), "compared {modules:?}");
}

/// The synthetic case with its sand as the compaction EOS (`preset = "dry_sand_loose"`, Laine &
/// Sandvik's dry sand): the EOS stage with its compaction history, and every stage after it, at
/// 0 ULP, the history `rho_max` among the fields compared.
#[test]
fn dual_compaction_sand_at_zero_ulp() {
    let dir = tempfile::tempdir().unwrap();
    let soil = r#"eos = { kind = "soil", rho0_kgm3 = 1450.0, c_ms = 1440.0, s = 1.6, gamma = 0.11 }
strength = { shear_modulus_pa = 63.58e6, alpha_phi = 0.25, cohesion_pa = 2.0e3 }"#;
    assert!(ALL_MODULES.contains(soil));
    let path = dir.path().join("dual_compaction.toml");
    std::fs::write(&path, ALL_MODULES.replace(soil, r#"preset = "dry_sand_loose""#)).unwrap();
    let c = case::load(&path, &[]).expect("the compaction case loads");
    let sand = c.materials.iter().find(|m| m.name == "sand").unwrap();
    assert_eq!(sand.eos.kind(), "compaction");
    let code = cli::dual_run(c, &Overrides::default(), 15, dir.path()).expect("dual run");
    assert_eq!(code, 0, "exit status of a dual run within tolerance");
    let modules = check_report(&dir.path().join("dual_report.json"), 15);
    assert!(modules.contains("eos") && modules.contains("strength"), "compared {modules:?}");
    let rep = read_json(&dir.path().join("dual_report.json"));
    let rows = rep["rows"].as_array().expect("rows");
    assert!(rows.iter().any(|r| r["field"] == "rho_max" && r["compared"].as_u64().unwrap_or(0) > 0), "no rho_max row");
}

/// The synthetic case with the density clamp on (`sph.density_clamp`): the charge starts at
/// 1630 kg/m³, above the upper bound, so the clamp changes ρ from the first step. Both clamp stages,
/// after the predict and after the advance, compare at 0 ULP.
#[test]
fn dual_density_clamp_at_zero_ulp() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("dual_clamp.toml");
    let line = "xsph_eps = 0.3\n";
    assert!(ALL_MODULES.contains(line));
    let clamped = ALL_MODULES.replace(line, "xsph_eps = 0.3\ndensity_clamp = [999.0, 1500.0]\n");
    std::fs::write(&path, clamped).unwrap();
    let c = case::load(&path, &[]).expect("the clamped case loads");
    assert_eq!(c.sph.density_clamp, Some(vec![999.0, 1500.0]));
    let code = cli::dual_run(c, &Overrides::default(), 15, dir.path()).expect("dual run");
    assert_eq!(code, 0, "exit status of a dual run within tolerance");
    check_report(&dir.path().join("dual_report.json"), 15);
    let rep = read_json(&dir.path().join("dual_report.json"));
    let rows = rep["rows"].as_array().expect("rows");
    for stage in ["integrator.clamp_predict", "integrator.clamp"] {
        let row = rows.iter().find(|r| r["stage"] == stage && r["field"] == "rho");
        let row = row.unwrap_or_else(|| panic!("no row of {stage}"));
        assert!(row["compared"].as_u64().unwrap() > 0, "{row}");
        assert_eq!(row["max_ulp"].as_u64(), Some(0), "{row}");
    }
}

/// The thesis's blast scenes: V1 (JWL charge in water, mirrors on all four walls) and S1 (TNT on
/// loose sand: strength, penalty, programmed burn), a few steps each, every module compared.
#[test]
fn dual_blast_scenes_every_module_within_tolerance() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
    for (name, extra) in [("underwater_box", vec![]), ("surface_loose_tnt6", vec![Module::Strength])] {
        let dir = tempfile::tempdir().unwrap();
        let c = case::load(&root.join(format!("{name}.toml")), &[]).expect("case loads");
        let code = cli::dual_run(c, &Overrides::default(), 3, dir.path()).expect("dual run");
        assert_eq!(code, 0, "{name}: exit status of a dual run within tolerance");
        let modules = check_report(&dir.path().join("dual_report.json"), 3);
        let mut want = vec![
            Module::Boundary,
            Module::Nnps,
            Module::Kernel,
            Module::Density,
            Module::Detonation,
            Module::Eos,
            Module::Force,
            Module::Viscosity,
            Module::Penalty,
            Module::Smoothing,
            Module::Integrator,
        ];
        want.extend(extra);
        assert!(modules.is_superset(&names(&want)), "{name} compared {modules:?}");
    }
}

/// The surface blast, free running: the all-Fortran and all-Rust runs stay bitwise equal.
#[test]
fn free_running_surface_blast_bitwise_equal() {
    let dir = tempfile::tempdir().unwrap();
    let c = case::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/surface_loose_tnt6.toml"), &[]).unwrap();
    let text = cli::free_run(c, &Overrides::default(), 10, dir.path()).expect("free run");
    assert!(text.contains("bitwise identical at every step"), "{text}");
    check_free(&dir.path().join("dual_free.json"), 10);
}

// ---------------------------------------------------------------------------------------------
// How a divergence is reported.

/// A state of four real particles (ids 100..103) and two mirrors, with a three-pair list.
fn small_state() -> (Particles, Work) {
    let p = Particles {
        dim: 2,
        nreal: 4,
        ntotal: 6,
        x: (0..12).map(|k| 0.01 * k as f64).collect(),
        p: vec![1.0e5, 2.5e6, -3.0e4, 7.0e7, 1.0e5, 2.5e6],
        id: vec![100, 101, 102, 103],
        ..Default::default()
    };
    let mut w = Work::default();
    w.pairs.i = vec![0, 1, 3];
    w.pairs.j = vec![1, 4, 5];
    w.w = vec![10.0, 20.0, 30.0];
    (p, w)
}

fn up(x: f64, ulps: u64) -> f64 {
    f64::from_bits(x.to_bits() + ulps)
}

/// A stage whose Rust twin edits one output (its Fortran twin leaves the state as it is): the
/// dual run's comparison must find the difference and name where it is.
struct Perturb {
    module: Module,
    name: &'static str,
    field: [Field; 1],
    edit: fn(&mut Particles, &mut Work),
}

impl Stage for Perturb {
    fn module(&self) -> Module {
        self.module
    }
    fn name(&self) -> &'static str {
        self.name
    }
    fn reads(&self) -> &[Field] {
        &[]
    }
    fn writes(&self) -> &[Field] {
        &self.field
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        if b == Backend::Rust {
            (self.edit)(p, w)
        }
    }
}

#[test]
fn divergence_names_stage_field_step_and_particle() {
    let (mut p, mut w) = small_state();
    let k = Clock::default();
    let mut cmp = Comparator::new(2);
    // step 3: the Rust result equals the Fortran one
    let same = Perturb { module: Module::Eos, name: "eos.eval", field: [Field::P], edit: |_, _| {} };
    cmp.run(&same, &mut p, &mut w, &k, 3);
    assert!(cmp.ok());
    // step 7: 10 ULP at particle 102
    let off =
        Perturb { module: Module::Eos, name: "eos.eval", field: [Field::P], edit: |p, _| p.p[2] = up(p.p[2], 10) };
    cmp.run(&off, &mut p, &mut w, &k, 7);
    assert!(!cmp.ok());
    assert_eq!(p.p[2], -3.0e4, "the run continues with the Fortran result");

    let st = &cmp.stats[&("eos.eval".to_string(), Field::P)];
    assert_eq!((st.module.as_str(), st.stage.as_str(), st.field.as_str()), ("eos", "eos.eval", "p"));
    assert_eq!(st.tolerance_ulp, 0);
    assert_eq!(st.compared, 12);
    assert_eq!(st.max_ulp, 10);
    assert_eq!(st.out_of_tolerance, 1);
    let diff = st.first_difference.as_ref().expect("a first difference");
    assert_eq!((diff.step, diff.index, diff.at.as_str()), (7, 2, "particle 102"));
    let d = st.first_divergence.as_ref().expect("a first divergence");
    assert_eq!((d.step, d.index, d.at.as_str()), (7, 2, "particle 102"));
    assert_eq!(d.fortran, -3.0e4);
    assert_eq!(d.rust, up(-3.0e4, 10));

    // the printed table and the report rows carry the same
    let table = cmp.table();
    let line = table.lines().find(|l| l.starts_with("eos.eval")).expect("an eos row");
    assert!(line.contains("step 7, particle 102: fortran -3e4"), "table row: {line}");
    let rows = serde_json::to_value(cmp.rows()).unwrap();
    let row = &rows[0];
    assert_eq!(row["module"], "eos");
    assert_eq!(row["stage"], "eos.eval");
    assert_eq!(row["field"], "p");
    assert_eq!(row["max_ulp"], 10);
    assert_eq!(row["out_of_tolerance"], 1);
    assert_eq!(row["first_divergence"]["step"], 7);
    assert_eq!(row["first_divergence"]["at"], "particle 102");
    assert_eq!(row["first_divergence"]["fortran"], -3.0e4);
}

/// One ULP is a divergence in a 0-ULP stage; a mirror, a pair and a length mismatch are named
/// as such.
#[test]
fn divergence_locations_mirror_pair_length() {
    let (mut p, mut w) = small_state();
    let k = Clock::default();
    let mut cmp = Comparator::new(2);
    let stat = |cmp: &Comparator, name: &str, f: Field| {
        cmp.stats[&(name.to_string(), f)].first_divergence.clone().expect("a divergence")
    };

    // x of mirror 1 (slot 5), component y, one ULP off, in boundary (tier 0)
    let s = Perturb {
        module: Module::Boundary,
        name: "boundary.x",
        field: [Field::X],
        edit: |p, _| p.x[11] = up(p.x[11], 1),
    };
    cmp.run(&s, &mut p, &mut w, &k, 2);
    let d = stat(&cmp, "boundary.x", Field::X);
    assert_eq!((d.step, d.index, d.at.as_str()), (2, 11, "mirror 1, y component"));

    // W of pair 2 (particles 3 and 5), in kernel
    let s = Perturb { module: Module::Kernel, name: "kernel.w", field: [Field::W], edit: |_, w| w.w[2] = 30.5 };
    cmp.run(&s, &mut p, &mut w, &k, 5);
    let d = stat(&cmp, "kernel.w", Field::W);
    assert_eq!(d.at, "pair 2 (3, 5)");
    assert_eq!((d.fortran, d.rust), (30.0, 30.5));

    // an integer field (the pair list) of another length, in nnps
    let s = Perturb { module: Module::Nnps, name: "nnps.j", field: [Field::PairJ], edit: |_, w| w.pairs.j.push(5) };
    cmp.run(&s, &mut p, &mut w, &k, 9);
    let d = stat(&cmp, "nnps.j", Field::PairJ);
    assert_eq!((d.step, d.at.as_str()), (9, "length"));
    assert_eq!((d.fortran, d.rust), (3.0, 4.0));
    assert!(!cmp.ok());
}

// ---------------------------------------------------------------------------------------------
// Free-running mode.

fn check_free(path: &Path, steps: u64) {
    let rep = read_json(path);
    assert_eq!(rep["steps"].as_u64(), Some(steps));
    assert!(rep["first_difference_step"].is_null(), "first difference at step {}", rep["first_difference_step"]);
    let rows = rep["rows"].as_array().expect("rows");
    assert_eq!(rows.len() as u64, steps);
    for (k, r) in rows.iter().enumerate() {
        assert_eq!(r["step"].as_u64(), Some(k as u64 + 1));
        assert_eq!(r["bitwise_equal"], Value::Bool(true), "step {}", k + 1);
        assert_eq!(r["t_fortran"], r["t_rust"]);
        for key in ["max_dx_m", "max_drho_rel", "max_dv_ms"] {
            assert_eq!(r[key].as_f64(), Some(0.0), "step {}: {key}", k + 1);
        }
    }
}

#[test]
fn free_running_shock_tube_bitwise_equal() {
    let dir = tempfile::tempdir().unwrap();
    let out = blastsph(&[
        "dual",
        shock_tube().to_str().unwrap(),
        "--free",
        "--steps",
        "40",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("bitwise identical at every step"), "{stdout}");
    check_free(&dir.path().join("dual_free.json"), 40);
}

#[test]
fn free_running_every_module_bitwise_equal() {
    let dir = tempfile::tempdir().unwrap();
    let case_path = write_all_modules(dir.path());
    let c = case::load(&case_path, &[]).unwrap();
    let text = cli::free_run(c, &Overrides::default(), 30, dir.path()).expect("free run");
    assert!(text.contains("bitwise identical at every step"), "{text}");
    check_free(&dir.path().join("dual_free.json"), 30);
}

// ---------------------------------------------------------------------------------------------
// Thread-count independence of the Rust twins.

fn assert_same_h5(a: &Path, b: &Path, what: &str) {
    let (fa, fb) = (h5_bits(a), h5_bits(b));
    let frames = fa.iter().filter(|x| x.1 == "TimeValue").count();
    assert!(frames >= 2, "{}: {frames} frames", a.display());
    let list = |f: &[(String, String, Vec<u64>)]| -> Vec<(String, String)> {
        f.iter().map(|x| (x.0.clone(), x.1.clone())).collect()
    };
    assert_eq!(list(&fa), list(&fb), "{what}: different groups or datasets");
    for (x, y) in fa.iter().zip(&fb) {
        if let Some(k) = x.2.iter().zip(&y.2).position(|(u, v)| u != v) {
            panic!(
                "{what}: {}/{} differs at particle {k}: {:e} vs {:e}",
                x.0,
                x.1,
                f64::from_bits(x.2[k]),
                f64::from_bits(y.2[k])
            );
        }
        assert_eq!(x.2.len(), y.2.len(), "{what}: {}/{}", x.0, x.1);
    }
}

fn run_case(case_path: &Path, out: &Path, extra: &[&str]) {
    let mut args = vec!["run", case_path.to_str().unwrap(), "--quiet", "--out", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    blastsph(&args);
}

/// `--backend rust --threads 1` and `--threads 2` write bitwise-identical particles.h5 (the
/// gathers do not depend on the split of the work), and so does `--backend fortran`.
#[test]
fn threads_shock_tube_bitwise_identical() {
    let dir = tempfile::tempdir().unwrap();
    let st = shock_tube();
    let one = dir.path().join("rust1");
    let two = dir.path().join("rust2");
    let fortran = dir.path().join("fortran");
    run_case(&st, &one, &["--backend", "rust", "--threads", "1"]);
    run_case(&st, &two, &["--backend", "rust", "--threads", "2"]);
    run_case(&st, &fortran, &["--backend", "fortran"]);
    for (d, th) in [(&one, 1), (&two, 2)] {
        let s = read_json(&d.join("summary.json"));
        assert_eq!(s["threads"].as_u64(), Some(th), "summary.json threads");
        assert_eq!(s["steps"].as_u64(), Some(40));
        assert_eq!(s["modules"]["force"], "rust");
    }
    let h5 = |d: &Path| d.join("particles.h5");
    assert_same_h5(&h5(&one), &h5(&two), "rust, 1 vs 2 threads");
    assert_same_h5(&h5(&one), &h5(&fortran), "rust vs fortran");
}

/// The same on the synthetic case, where the gathers run over 2D neighbourhoods, mirrors, stress
/// and penalty pairs.
#[test]
fn threads_every_module_bitwise_identical() {
    let dir = tempfile::tempdir().unwrap();
    let case_path = write_all_modules(dir.path());
    let end = ["--end-time", "2e-5"];
    let one = dir.path().join("rust1");
    let two = dir.path().join("rust2");
    run_case(&case_path, &one, &[&["--backend", "rust", "--threads", "1"][..], &end[..]].concat());
    run_case(&case_path, &two, &[&["--backend", "rust", "--threads", "2"][..], &end[..]].concat());
    assert_same_h5(&one.join("particles.h5"), &two.join("particles.h5"), "synthetic case, rust, 1 vs 2 threads");
}

/// Sorting particles by cell mid-run (sph.reorder_every) keeps both backends bitwise equal and
/// the gauges on their particles (they follow ids, not memory slots).
#[test]
fn reordering_keeps_parity_and_gauges() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/surface_loose_tnt4.toml");
    let dir = tempfile::tempdir().unwrap();
    let c = case::load(&root, &["sph.reorder_every=4".to_string()]).unwrap();
    assert_eq!(cli::dual_run(c, &Overrides::default(), 10, dir.path()).expect("dual"), 0);
    let run = |every: u64, out: &Path| -> Value {
        let opts = blastsph::runner::RunOptions {
            out: Some(out.to_path_buf()),
            quiet: true,
            sets: vec![format!("sph.reorder_every={every}")],
            ov: Overrides { end_time: Some(6.0e-5), ..Default::default() },
            ..Default::default()
        };
        blastsph::runner::run(&root, &opts).expect("run").summary
    };
    let (a, b) = (run(0, &dir.path().join("a")), run(7, &dir.path().join("b")));
    for (ga, gb) in a["gauges"].as_array().unwrap().iter().zip(b["gauges"].as_array().unwrap()) {
        assert_eq!(ga["particle"], gb["particle"], "the gauge follows its particle id");
        let (pa, pb) = (ga["peak_pa"].as_f64().unwrap(), gb["peak_pa"].as_f64().unwrap());
        assert!((pa - pb).abs() <= 1e-9 * pa.abs(), "peak {pa} vs {pb}: only round-off may differ");
    }
    // the particles' masses are untouched; their total is summed in another order
    let (ma, mb) = (a["mass"]["final"].as_f64().unwrap(), b["mass"]["final"].as_f64().unwrap());
    assert!((ma - mb).abs() <= 1e-13 * ma, "{ma} vs {mb}");
}
