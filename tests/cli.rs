//! The command line as users and tools meet it (docs/design.md): the built binary, bad
//! input refused with one line and exit status 2, `check`'s plan, the run directory's files
//! (H5Part layout, summary.json keys) and `report`.

// Particle arrays are parallel (x, rho, v, ... indexed by particle), as in the crate itself.
#![allow(clippy::needless_range_loop)]

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn blastsph(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_blastsph"))
        .args(args)
        .current_dir(common::root())
        .output()
        .expect("cannot start the blastsph binary")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn shock_tube_text() -> String {
    std::fs::read_to_string(common::case_path("shock_tube.toml")).expect("cases/shock_tube.toml")
}

fn write_case(dir: &Path, name: &str, body: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, body).expect("write case");
    p
}

/// `blastsph check CASE` must refuse the case: status 2, nothing on stdout, one line on stderr
/// that names the problem (every word of `needles`), and no panic.
fn refused(case: &Path, needles: &[&str]) {
    let out = blastsph(&["check", case.to_str().unwrap()]);
    let (so, se) = (text(&out.stdout), text(&out.stderr));
    let shown = format!("stdout:\n{so}\nstderr:\n{se}");
    assert_eq!(out.status.code(), Some(2), "exit status; {shown}");
    assert!(so.is_empty(), "nothing on stdout; {shown}");
    assert_eq!(se.lines().count(), 1, "exactly one line on stderr; {shown}");
    assert!(!se.contains("panicked") && !se.contains("RUST_BACKTRACE"), "no panic; {shown}");
    for n in needles {
        assert!(se.contains(n), "the error must name `{n}`; {shown}");
    }
}

/// Inserts `extra` after the first line that starts with `after`.
fn insert_after(base: &str, after: &str, extra: &str) -> String {
    let mut out = String::new();
    let mut done = false;
    for line in base.lines() {
        out.push_str(line);
        out.push('\n');
        if !done && line.starts_with(after) {
            out.push_str(extra);
            out.push('\n');
            done = true;
        }
    }
    assert!(done, "no line starting with `{after}`");
    out
}

/// Inserts a `[[region]]` table before `[analysis]` (after it, TOML would put the region's keys
/// inside the analysis table).
fn before_analysis(base: &str, region: &str) -> String {
    let k = base.find("[analysis]").expect("[analysis] in shock_tube.toml");
    format!("{}{region}\n{}", &base[..k], &base[k..])
}

#[test]
fn check_refuses_an_unknown_key() {
    let d = tempfile::tempdir().unwrap();
    let base = shock_tube_text();
    let top = insert_after(&base, "dim = 1", "colour = \"red\"");
    refused(&write_case(d.path(), "top.toml", &top), &["colour"]);
    let nested = insert_after(&base, "kernel = \"cubic\"", "kernal_radius = 2.0");
    refused(&write_case(d.path(), "nested.toml", &nested), &["kernal_radius"]);
}

#[test]
fn check_refuses_a_negative_density() {
    let d = tempfile::tempdir().unwrap();
    let bad = shock_tube_text().replace("rho_kgm3 = 0.25", "rho_kgm3 = -0.25");
    assert_ne!(bad, shock_tube_text());
    refused(&write_case(d.path(), "neg.toml", &bad), &["rho_kgm3", "right"]);
}

#[test]
fn check_refuses_a_missing_file() {
    let d = tempfile::tempdir().unwrap();
    let missing = d.path().join("no_such_case.toml");
    refused(&missing, &["no_such_case.toml"]);
}

#[test]
fn check_refuses_a_region_without_particles() {
    let d = tempfile::tempdir().unwrap();
    // a 1 mm box with a 1 cm spacing holds no lattice point
    let region = r#"
[[region]]
name = "sliver"
material = "gas"
shape = "box"
lo_m = [0.7]
hi_m = [0.701]
spacing_m = 0.01
rho_kgm3 = 0.25
"#;
    let bad = before_analysis(&shock_tube_text(), region);
    refused(&write_case(d.path(), "empty.toml", &bad), &["sliver", "no particles"]);
}

#[test]
fn check_refuses_a_material_without_an_eos() {
    let d = tempfile::tempdir().unwrap();
    // a region naming a material that is not defined (so has no equation of state)
    let bad = shock_tube_text().replacen("material = \"gas\"", "material = \"air\"", 1);
    refused(&write_case(d.path(), "undef.toml", &bad), &["air", "material", "eos"]);
    // a [[material]] that has no eos table
    let bad = insert_after(&shock_tube_text(), "eos = { kind = \"ideal_gas\"", "\n[[material]]\nname = \"dust\"");
    refused(&write_case(d.path(), "noeos.toml", &bad), &["eos"]);
}

#[test]
fn check_refuses_overlapping_regions() {
    let d = tempfile::tempdir().unwrap();
    let region = r#"
[[region]]
name = "intruder"
material = "gas"
shape = "lattice"
origin_m = [-0.3]
count = [10]
spacing_m = 0.001875
rho_kgm3 = 1.0
e_jkg = 2.5
"#;
    let bad = before_analysis(&shock_tube_text(), region);
    refused(&write_case(d.path(), "overlap.toml", &bad), &["overlaps", "left", "intruder"]);
}

#[test]
fn run_refuses_a_bad_case_without_writing_a_run_directory() {
    let d = tempfile::tempdir().unwrap();
    let bad = shock_tube_text().replace("rho_kgm3 = 0.25", "rho_kgm3 = -0.25");
    let case = write_case(d.path(), "neg.toml", &bad);
    let out_dir = d.path().join("run");
    let out = blastsph(&["run", case.to_str().unwrap(), "--out", out_dir.to_str().unwrap(), "--quiet"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert_eq!(text(&out.stderr).lines().count(), 1);
    assert!(!out_dir.exists(), "no partial output for a refused case");
}

#[test]
fn check_prints_the_module_plan_of_the_shock_tube() {
    let out = blastsph(&["check", "cases/shock_tube.toml"]);
    let so = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(text(&out.stderr).is_empty(), "{}", text(&out.stderr));
    assert!(so.contains("shock_tube"), "{so}");
    assert!(so.contains("400 particles"), "{so}");
    assert!(so.contains("module plan:"), "{so}");
    let line = |m: &str| {
        so.lines()
            .find(|l| l.split_whitespace().next() == Some(m))
            .unwrap_or_else(|| panic!("no plan line for `{m}` in:\n{so}"))
            .to_string()
    };
    for m in ["nnps", "kernel", "density", "eos", "force", "viscosity", "integrator"] {
        assert!(line(m).contains("rust"), "{m} runs in Rust by default: {}", line(m));
    }
    for m in ["boundary", "strength", "penalty", "detonation", "smoothing", "xsph"] {
        assert!(line(m).contains("skipped"), "{m} is not needed: {}", line(m));
    }
    assert!(line("nnps").contains("direct"));
    assert!(line("density").contains("summation"));
    // flags change the plan
    let out = blastsph(&["check", "cases/shock_tube.toml", "--backend", "fortran", "--rust", "eos", "--nnps", "cell"]);
    let so = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0));
    let eos = so.lines().find(|l| l.trim_start().starts_with("eos")).unwrap();
    assert!(eos.contains("rust"), "{eos}");
    let force = so.lines().find(|l| l.trim_start().starts_with("force")).unwrap();
    assert!(force.contains("fortran"), "{force}");
    let nnps = so.lines().find(|l| l.trim_start().starts_with("nnps")).unwrap();
    assert!(nnps.contains("cell"), "{nnps}");
}

#[test]
fn run_writes_h5part_and_summary_and_report_reads_them() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path().join("st");
    let out = blastsph(&["run", "cases/shock_tube.toml", "--out", dir.to_str().unwrap(), "--quiet"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(!text(&out.stderr).contains("panicked"));

    // particles.h5: groups Step#0..Step#K, equal-length 1D datasets, a float64 TimeValue; beside
    // them only `xdmf`, the (N, 3) views particles.xmf reads (docs/reference/output.md)
    let f = hdf5::File::open(dir.join("particles.h5")).expect("open particles.h5");
    let mut steps: Vec<usize> = f
        .member_names()
        .unwrap()
        .iter()
        .filter(|n| n.as_str() != "xdmf")
        .map(|n| {
            n.strip_prefix("Step#")
                .and_then(|k| k.parse().ok())
                .unwrap_or_else(|| panic!("unexpected top-level member `{n}`"))
        })
        .collect();
    steps.sort_unstable();
    assert!(steps.len() >= 2, "at least the first and the last step");
    assert_eq!(steps, (0..steps.len()).collect::<Vec<_>>(), "Step#0.. without gaps");
    let mut last_t = -1.0;
    for k in &steps {
        let g = f.group(&format!("Step#{k}")).unwrap();
        let a = g.attr("TimeValue").expect("TimeValue attribute");
        assert!(a.dtype().unwrap().is::<f64>(), "TimeValue is float64");
        let t: f64 = a.read_scalar().unwrap();
        assert!(t > last_t, "times increase: {t} after {last_t}");
        last_t = t;
        for name in ["x", "y", "z", "vx", "vy", "vz", "rho", "p", "e", "h", "mass"] {
            let ds = g.dataset(name).unwrap_or_else(|_| panic!("Step#{k}/{name}"));
            assert_eq!(ds.shape(), vec![400], "Step#{k}/{name} is 1D of 400");
            assert!(ds.dtype().unwrap().is::<f64>(), "{name} is float64");
        }
        let id = g.dataset("id").unwrap();
        assert!(id.dtype().unwrap().is::<i64>(), "id is int64");
        assert_eq!(id.read_raw::<i64>().unwrap(), (0..400).collect::<Vec<i64>>());
        let mat = g.dataset("mat").unwrap();
        assert_eq!(mat.shape(), vec![400]);
        let z = g.dataset("z").unwrap().read_raw::<f64>().unwrap();
        assert!(z.iter().all(|v| *v == 0.0), "z = 0 below 3D");
        let mass = g.dataset("mass").unwrap().read_raw::<f64>().unwrap();
        assert!(mass.iter().all(|m| *m == 0.001875));
    }
    let first = f.group("Step#0").unwrap();
    assert_eq!(first.attr("TimeValue").unwrap().read_scalar::<f64>().unwrap(), 0.0);
    assert!((last_t - 0.2).abs() < 1e-12, "last step at t = 0.2 s, got {last_t}");
    // Step#0 holds the summation density of the initial lattice: the book's states in the bulk
    let x0 = first.dataset("x").unwrap().read_raw::<f64>().unwrap();
    let rho0 = first.dataset("rho").unwrap().read_raw::<f64>().unwrap();
    for i in 0..400 {
        if x0[i].abs() > 0.05 && x0[i].abs() < 0.55 {
            let want = if x0[i] < 0.0 { 1.0 } else { 0.25 };
            assert!((rho0[i] - want).abs() < 1e-3 * want, "x = {}: rho = {}", x0[i], rho0[i]);
        }
    }
    drop(first);
    drop(f);

    // summary.json: the keys of docs/reference/output.md
    let s: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap())
        .expect("summary.json is JSON");
    assert_eq!(s["case"], "shock_tube");
    assert_eq!(s["backend"], "rust");
    assert_eq!(s["dim"], 1);
    assert_eq!(s["particles"], 400);
    assert_eq!(s["steps"], 40);
    assert!((s["time"].as_f64().unwrap() - 0.2).abs() < 1e-12);
    assert!(s["wall_seconds"].as_f64().unwrap() >= 0.0);
    let modules = s["modules"].as_object().expect("modules is an object");
    for m in ["nnps", "kernel", "density", "eos", "force", "viscosity", "integrator"] {
        assert_eq!(modules[m], "rust", "modules.{m}");
    }
    assert!(modules.values().all(|v| v == "fortran" || v == "rust"));
    for k in ["initial", "final"] {
        assert!(s["mass"][k].as_f64().unwrap() > 0.0, "mass.{k}");
        let e = &s["energy"][k];
        let (kin, int, tot) =
            (e["kinetic"].as_f64().unwrap(), e["internal"].as_f64().unwrap(), e["total"].as_f64().unwrap());
        assert!((kin + int - tot).abs() <= 1e-12 * tot, "energy.{k}: total = kinetic + internal");
    }
    assert_eq!(s["energy"]["initial"]["kinetic"], 0.0, "the gas starts at rest");
    assert_eq!(s["outputs"].as_u64().unwrap() as usize, steps.len());

    // report: L1 errors on stdout, profiles.png written
    let out = blastsph(&["report", dir.to_str().unwrap()]);
    let so = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(so.contains("L1 errors"), "{so}");
    assert!(so.contains("p* = 0.429346"), "{so}");
    let l1_line = so.lines().find(|l| l.contains("L1 errors")).unwrap();
    let rho: f64 = l1_line
        .split("rho ")
        .nth(1)
        .and_then(|r| r.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no rho value in `{l1_line}`"));
    assert!(rho > 0.0 && rho < 0.02, "L1 rho {rho} (tests/shock_tube.rs explains the bound)");
    let png = std::fs::read(dir.join("profiles.png")).expect("profiles.png");
    assert!(png.len() > 10_000, "profiles.png is {} bytes", png.len());
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n", "profiles.png is a PNG");
    assert!(dir.join("report.json").exists());
    // the report's plots are all of the names a later report or a resume removes
    for e in std::fs::read_dir(&dir).unwrap().filter_map(|e| e.ok()) {
        let n = e.file_name().to_string_lossy().into_owned();
        if n.ends_with(".png") {
            assert!(blastsph::rundir::is_report_plot(&n), "{n} is not in rundir::is_report_plot's list");
        }
    }
}

#[test]
fn report_refuses_a_directory_that_is_not_a_run() {
    let d = tempfile::tempdir().unwrap();
    let out = blastsph(&["report", d.path().to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert_eq!(text(&out.stderr).lines().count(), 1);
    assert!(text(&out.stderr).contains("summary.json"));
}

#[test]
fn set_overrides_parse_strings_numbers_and_arrays() {
    // `--set time.step=cfl` (not TOML, so taken as a string), a number, and an array by name
    let out = blastsph(&[
        "check",
        "cases/shock_tube.toml",
        "--set",
        "time.step=cfl",
        "--set",
        "time.cfl=0.3",
        "--set",
        "region.left.count=[640]",
        "--set",
        "region.left.spacing_m=0.0009375",
    ]);
    let so = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(so.contains("Cfl step C = 0.3"), "{so}");
    assert!(so.contains("720 particles"), "{so}");
    // a key that does not exist is refused like one in the file
    let out = blastsph(&["check", "cases/shock_tube.toml", "--set", "time.colour=1"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("colour"), "{}", text(&out.stderr));
    assert_eq!(text(&out.stderr).lines().count(), 1);
}

/// The error of a key at the start of a line must name that line (a span starting at column 0
/// was once counted one line short), and so must an indented key.
#[test]
fn error_names_the_line_of_an_unknown_key() {
    let d = tempfile::tempdir().unwrap();
    let body = "dim = 1\n[time]\nend_s = 1.0\ncolour = 3\n";
    let case = write_case(d.path(), "line.toml", body);
    let out = blastsph(&["check", case.to_str().unwrap()]);
    let se = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2));
    assert!(se.contains("line.toml:4:"), "the unknown key is on line 4: {se}");
}

/// `blastsph validate` on one scene (shortened): the run directory, the report and the table.
#[test]
fn validate_runs_a_scene_and_writes_the_table() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("val");
    let o = blastsph(&[
        "validate",
        "--only",
        "slope_45",
        "--end-time",
        "5e-5",
        "--backend",
        "rust",
        "--out",
        out.to_str().unwrap(),
        "--cases",
        concat!(env!("CARGO_MANIFEST_DIR"), "/cases"),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let md = std::fs::read_to_string(out.join("validation.md")).expect("validation.md");
    assert!(md.contains("| slope_45 | ok |"), "{md}");
    assert!(md.contains("bowl width at half depth"));
    assert!(out.join("slope_45/summary.json").exists() && out.join("slope_45/report.json").exists());
    let js: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("validation.json")).unwrap()).unwrap();
    assert_eq!(js["scenes"][0]["case"], "slope_45");
    // a scene that is not the thesis's is refused with one line and status 2
    let bad = blastsph(&["validate", "--only", "nonsense", "--out", out.to_str().unwrap()]);
    assert_eq!(bad.status.code(), Some(2));
    assert_eq!(String::from_utf8_lossy(&bad.stderr).lines().count(), 1);
}

/// A run that blows up (here: the book's shock tube refined with a gap at the diaphragm and a
/// fixed step, which creates energy) stops with one line naming the step, the particle and the
/// quantity, exit status 3, and keeps what it wrote: summary.json (status "unstable") and the
/// particles.h5 steps written so far.
#[test]
fn an_unstable_run_stops_with_a_diagnostic_and_keeps_its_output() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("blow");
    let sets = [
        "region.left.count=[640]",
        "region.left.spacing_m=0.0009375",
        "region.left.mass_kg=0.0009375",
        "region.left.h_m=0.0075",
        "region.left.origin_m=[-0.60046875]",
        "region.right.count=[160]",
        "region.right.spacing_m=0.00375",
        "region.right.mass_kg=0.0009375",
        "region.right.h_m=0.0075",
        "region.right.origin_m=[0.005625]",
        "time.dt_s=0.0025",
        "time.output_interval_s=0.01",
    ];
    let mut args = vec!["run", concat!(env!("CARGO_MANIFEST_DIR"), "/cases/shock_tube.toml"), "--quiet", "--out"];
    let o = out.to_str().unwrap().to_string();
    args.push(&o);
    for s in &sets {
        args.push("--set");
        args.push(s);
    }
    let r = blastsph(&args);
    assert_eq!(r.status.code(), Some(3), "exit status of an unstable run");
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(err.contains("unstable: step") && err.contains("particle") && err.contains("total energy"), "{err}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["status"], "unstable");
    assert!(s["diagnostic"].as_str().unwrap().contains("total energy"));
    let f = hdf5::File::open(out.join("particles.h5")).expect("particles.h5 kept");
    assert!(f.member_names().unwrap().len() >= 2, "the steps written before the failure are kept");
}

#[test]
fn check_states_a_sedov_blasts_energy_and_its_exact_radius_at_the_end() {
    let out = blastsph(&["check", "cases/verify/sedov_3d.toml"]);
    let so = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    // the octant's hot corner particle holds E/8; its three mirrors make the whole blast's 1 J:
    // R = 1.03278 (1 J × (0.1 s)² / 1 kg/m³)^(1/5) = 0.41116 m
    let line = so.lines().find(|l| l.starts_with("Sedov (spherical)")).unwrap_or_else(|| panic!("{so}"));
    assert!(line.contains("E = 1.000000e0 J") && line.contains("xi0 = 1.03278"), "{line}");
    assert!(line.contains("R = 4.11156e-1 m"), "{line}");
}

#[test]
fn the_lattice_gradient_is_refused_with_the_books_kernel() {
    let out =
        blastsph(&["check", "cases/shock_tube.toml", "--compat", "liu-book", "--set", "sph.lattice_gradient=true"]);
    let se = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{se}");
    assert_eq!(se.lines().count(), 1, "{se}");
    assert!(se.contains("sph.lattice_gradient") && se.contains("book's kernel"), "{se}");
    // on its own it is accepted, and `check` names the factor on the kernel's line
    let out = blastsph(&["check", "cases/shock_tube.toml", "--set", "sph.lattice_gradient=true"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("grad W / "), "{}", text(&out.stdout));
}

/// A 1 kg charge buried 0.207 m deep in RZ (dense sand, 23 mm) ends contained in a cavity by
/// 1 ms; a point gauge on the axis 5 cm under the surface ends inside it, one 0.6 m deep and 0.3 m
/// out does not: `report` says so of the first only.
#[test]
fn report_says_which_point_gauges_end_inside_a_contained_charges_cavity() {
    let d = tempfile::tempdir().unwrap();
    let body = "name = \"buried_rz\"\ndim = 2\ngeometry = \"axisymmetric\"\n[time]\nend_s = 1.0e-3\noutput_interval_s = 2.5e-4\n\
        [penalty]\npbar = 1e5\n[[material]]\nname = \"sand\"\npreset = \"dense_sand\"\n[[material]]\nname = \"tnt\"\npreset = \"tnt\"\n\
        [[region]]\nname = \"charge\"\nmaterial = \"tnt\"\nshape = \"box\"\nlo_m = [0.0, -0.299]\nhi_m = [0.046, -0.207]\nspacing_m = 0.023\n\
        [[region]]\nname = \"soil\"\nmaterial = \"sand\"\nshape = \"box\"\nlo_m = [0.0, -1.012]\nhi_m = [1.012, 0.0]\nspacing_m = 0.023\nsubtract = [\"charge\"]\n\
        [[wall]]\nfrom_m = [1.012, -1.012]\nto_m = [1.012, 0.3]\n[[wall]]\nfrom_m = [0.0, -1.012]\nto_m = [1.012, -1.012]\n\
        [detonation]\nmode = \"programmed\"\npoint_m = [0.0, -0.253]\n\
        [[gauge]]\nname = \"shallow\"\npoint_m = [0.0, -0.05]\nkind = \"point\"\n\
        [[gauge]]\nname = \"far\"\npoint_m = [0.3, -0.6]\nkind = \"point\"\n[analysis]\nkind = \"crater\"\n";
    let case = write_case(d.path(), "buried.toml", body);
    let run = d.path().join("run");
    let out = blastsph(&["run", case.to_str().unwrap(), "--out", run.to_str().unwrap(), "--quiet"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let out = blastsph(&["report", run.to_str().unwrap()]);
    let so = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(so.contains("contained in a cavity"), "{so}");
    assert!(so.contains("gauge shallow: its point lies inside the cavity"), "{so}");
    assert!(!so.contains("gauge far: its point lies inside"), "{so}");
}

/// Output into a pipe whose reader has gone ends the process by SIGPIPE, quietly (no
/// "internal error" line: the write used to panic): the reader's end is closed before the
/// process starts, so its first line meets it.
#[cfg(unix)]
#[test]
fn a_closed_output_pipe_ends_the_process_quietly() {
    use std::os::unix::process::ExitStatusExt;
    let (reader, writer) = std::io::pipe().expect("a pipe");
    drop(reader);
    let o = Command::new(env!("CARGO_BIN_EXE_blastsph"))
        .args(["check", "shock_tube"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(writer)
        .output()
        .expect("blastsph runs");
    let err = text(&o.stderr);
    assert!(!err.contains("internal error"), "{err}");
    assert_eq!(o.status.signal(), Some(13), "ended by SIGPIPE: {:?} {err}", o.status);
}

/// An analysis about the wrong point is warned of by `check`: a Sedov centre 0.1 m off the
/// deposit (a docs-only check read the shock radius 0.727 of exact, as if the code failed), a
/// Noh analysis of a case with no inflow; the shipped verification cases are not.
#[test]
fn an_analysis_about_the_wrong_point_is_warned_of() {
    let warned = |args: &[&str]| {
        let o = blastsph(args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let so = String::from_utf8_lossy(&o.stdout).into_owned();
        so.lines().any(|l| {
            l.starts_with("warning:") && (l.contains("analysis.center_m is") || l.contains("no region has a radial"))
        })
    };
    for c in ["sedov_2d_g14", "sedov_3d", "sedov_rz", "noh_2d", "noh_rz"] {
        assert!(!warned(&["check", &format!("cases/verify/{c}.toml")]), "{c}");
    }
    assert!(warned(&["check", "cases/verify/sedov_2d_g14.toml", "--set", "analysis.center_m=[0.1, 0.0]"]));
    assert!(warned(&["check", "cases/verify/sedov_rz.toml", "--set", "analysis.center_m=[0.0, 0.1]"]));
    assert!(warned(&["check", "cases/shock_tube.toml", "--set", "analysis.kind=noh"]));
}

/// `--compat -ITEM` (a leading minus, with a space after the flag) is the item switched off, not
/// an unknown flag; an unknown item is still one line and exit status 2.
#[test]
fn compat_takes_an_item_switched_off_after_a_space() {
    let o = blastsph(&["check", "shock_tube", "--compat", "-force_energy"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let o = blastsph(&["check", "shock_tube", "--compat", "-nonsense"]);
    let se = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{se}");
    assert!(se.contains("\"-nonsense\" is neither a profile") && se.trim().lines().count() == 1, "{se}");
}

/// A TNT sphere alone in vacuum with continuity density set (the old default) goes below zero
/// density; the diagnostic names that density behind the infinite pressure, and the advice is
/// the summation density products alone now take by default (it said "lower time.cfl", which
/// does not help: validation.md, "A charge alone in a void").
#[test]
fn products_alone_by_continuity_name_their_negative_density_and_the_fix() {
    let case = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/hard/free_sphere_3d.toml");
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("run");
    let o = blastsph(&[
        "run",
        case.to_str().unwrap(),
        "--threads",
        "1",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
        "--set",
        "sph.density=\"continuity\"",
    ]);
    let se = text(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{se}");
    assert!(se.contains("kg/m3 (not above zero)"), "{se}");
    assert!(se.contains("likely fix: detonation products alone in a void: set sph.density = \"summation\""), "{se}");
    assert!(!se.contains("lower time.cfl"), "{se}");
}

/// `check` takes `--threads` as `run` does (a run's command line checks as it is); a count out of
/// range is one line and exit status 2.
#[test]
fn check_takes_threads_as_run_does() {
    let o = blastsph(&["check", "shock_tube", "--threads", "1"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let o = blastsph(&["check", "shock_tube", "--threads", "0"]);
    let se = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{se}");
    assert_eq!(se.lines().count(), 1, "{se}");
    assert!(se.contains("--threads 0"), "{se}");
}
