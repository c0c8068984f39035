//! What a blast engineer meets: help on every argument, progress in a log file while
//! a run goes, material presets equal to the constants typed out, a run directory that reruns
//! the same run, `--set` errors that name the override, cases found by name, gauges of both
//! kinds, and a crater that is measured from the soil or refused with a reason.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn blastsph_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_blastsph")).args(args).current_dir(dir).output().expect("blastsph")
}

fn blastsph(args: &[&str]) -> Output {
    blastsph_in(&common::root(), args)
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn ok(o: &Output) {
    assert_eq!(o.status.code(), Some(0), "stdout:\n{}\nstderr:\n{}", text(&o.stdout), text(&o.stderr));
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// Every argument and option of every subcommand has a help line in `--help`.
#[test]
fn every_argument_of_every_subcommand_has_a_help_line() {
    let top = text(&blastsph(&["--help"]).stdout);
    let subs: Vec<String> = top
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next().map(String::from))
        .filter(|s| s != "help")
        .collect();
    assert!(subs.len() >= 6, "subcommands: {subs:?}\n{top}");
    // a subcommand with subcommands of its own is checked through them
    let mut paths: Vec<Vec<String>> = Vec::new();
    for sub in &subs {
        let h = text(&blastsph(&[sub, "--help"]).stdout);
        let nested: Vec<String> = h
            .lines()
            .skip_while(|l| !l.starts_with("Commands:"))
            .skip(1)
            .take_while(|l| l.starts_with("  "))
            .filter_map(|l| l.split_whitespace().next().map(String::from))
            .filter(|s| s != "help")
            .collect();
        if nested.is_empty() {
            paths.push(vec![sub.clone()]);
        } else {
            paths.extend(nested.into_iter().map(|n| vec![sub.clone(), n]));
        }
    }
    for path in &paths {
        let sub = path.join(" ");
        let mut args: Vec<&str> = path.iter().map(String::as_str).collect();
        args.push("--help");
        let h = text(&blastsph(&args).stdout);
        let mut entries = 0;
        let lines: Vec<&str> = h.lines().collect();
        let mut in_list = false;
        for (k, l) in lines.iter().enumerate() {
            if l.starts_with("Arguments:") || l.starts_with("Options:") {
                in_list = true;
                continue;
            }
            if !l.starts_with(' ') {
                in_list = false;
            }
            let t = l.trim_start();
            let indent = l.len() - t.len();
            let entry = (t.starts_with('-') && (2..=6).contains(&indent))
                || ((t.starts_with('<') || t.starts_with('[')) && indent == 2);
            if !in_list || !entry {
                continue;
            }
            entries += 1;
            // the help text follows on the line (after two spaces) or on the next, deeper line
            let inline = t.split_once("  ").is_some_and(|(_, rest)| !rest.trim().is_empty());
            let next = lines.get(k + 1).is_some_and(|n| {
                let nt = n.trim_start();
                n.len() - nt.len() > 6 && !nt.is_empty() && !nt.starts_with('-')
            });
            assert!(inline || next, "`blastsph {sub} --help`: `{}` has no help line\n{h}", t);
        }
        assert!(entries >= 2, "`blastsph {sub} --help` lists its arguments\n{h}");
    }
}

/// With stderr redirected to a file (a batch job), a run logs progress lines while it runs.
#[test]
fn a_run_with_stderr_in_a_file_logs_progress_while_it_runs() {
    let d = tempfile::tempdir().unwrap();
    let log = d.path().join("run.log");
    let out = d.path().join("run");
    let mut child = Command::new(env!("CARGO_BIN_EXE_blastsph"))
        .args(["run", "cases/surface_loose_tnt6.toml", "--end-time", "2e-3", "--progress-every", "0.2", "--out"])
        .arg(&out)
        .current_dir(common::root())
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&log).unwrap())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let mut seen = String::new();
    while start.elapsed() < Duration::from_secs(120) {
        seen = std::fs::read_to_string(&log).unwrap_or_default();
        if seen.lines().filter(|l| l.starts_with("progress: ")).count() >= 2 {
            break;
        }
        assert!(child.try_wait().unwrap().is_none(), "the run ended before two progress lines:\n{seen}");
        std::thread::sleep(Duration::from_millis(50));
    }
    let running = child.try_wait().unwrap().is_none();
    let _ = child.kill();
    let _ = child.wait();
    assert!(running, "the progress lines must come while the run goes");
    let line =
        seen.lines().find(|l| l.starts_with("progress: ")).unwrap_or_else(|| panic!("no progress line:\n{seen}"));
    for w in ["step ", "t = ", "dt = ", "particle-steps/s", "ETA "] {
        assert!(line.contains(w), "`{w}` in `{line}`");
    }
    // --quiet: nothing on stderr
    let q = d.path().join("quiet");
    let o =
        blastsph(&["run", "cases/shock_tube.toml", "--quiet", "--progress-every", "0", "--out", q.to_str().unwrap()]);
    ok(&o);
    assert!(text(&o.stderr).is_empty(), "--quiet: {}", text(&o.stderr));
}

/// Every dataset of every step, bitwise.
fn same_h5(a: &Path, b: &Path) {
    let (fa, fb) = (hdf5::File::open(a).unwrap(), hdf5::File::open(b).unwrap());
    let names = fa.member_names().unwrap();
    assert_eq!(names, fb.member_names().unwrap());
    let mut n = 0;
    for g in names.iter().filter(|n| n.starts_with("Step#")) {
        let (ga, gb) = (fa.group(g).unwrap(), fb.group(g).unwrap());
        let ta: f64 = ga.attr("TimeValue").unwrap().read_scalar().unwrap();
        let tb: f64 = gb.attr("TimeValue").unwrap().read_scalar().unwrap();
        assert_eq!(ta.to_bits(), tb.to_bits(), "{g} TimeValue");
        for ds in ga.member_names().unwrap() {
            let x = ga.dataset(&ds).unwrap();
            if x.dtype().unwrap().is::<f64>() {
                let (va, vb) = (x.read_raw::<f64>().unwrap(), gb.dataset(&ds).unwrap().read_raw::<f64>().unwrap());
                assert!(
                    va.iter().zip(&vb).all(|(p, q)| p.to_bits() == q.to_bits()) && va.len() == vb.len(),
                    "{g}/{ds}"
                );
                n += 1;
            }
        }
    }
    assert!(n > 20, "compared {n} datasets");
}

/// A thesis case written with presets is bit for bit the same run as with the constants typed
/// out (S1 loose sand and V2 buried C4).
#[test]
fn presets_give_the_same_run_bit_for_bit() {
    let d = tempfile::tempdir().unwrap();
    for (typed, preset, end) in
        [("surface_loose_tnt6", "surface_loose_tnt6_presets", "5e-5"), ("buried_c4", "buried_c4_presets", "6e-5")]
    {
        let (a, b) = (d.path().join(typed), d.path().join(preset));
        for (case, dir) in [(typed, &a), (preset, &b)] {
            ok(&blastsph(&[
                "run",
                &format!("cases/{case}.toml"),
                "--quiet",
                "--end-time",
                end,
                "--set",
                "time.output_interval_s=1e-5",
                "--out",
                dir.to_str().unwrap(),
            ]));
        }
        same_h5(&a.join("particles.h5"), &b.join("particles.h5"));
        let (ga, gb) = (
            std::fs::read_to_string(a.join("gauges.csv")).unwrap(),
            std::fs::read_to_string(b.join("gauges.csv")).unwrap(),
        );
        assert_eq!(ga, gb, "{typed}: gauges.csv");
        let (sa, sb) = (summary(&a), summary(&b));
        assert_eq!(sa["energy"], sb["energy"], "{typed}: energies");
        assert_eq!(sa["steps"], sb["steps"]);
    }
    // a key beside the preset overrides the preset's
    let o = blastsph(&["check", "cases/surface_loose_tnt6_presets.toml", "--set", "material.tnt.preset=tnt_dobratz"]);
    ok(&o);
    let o = blastsph(&["check", "cases/surface_loose_tnt6_presets.toml", "--set", "material.tnt.preset=tnx"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("no such preset") && text(&o.stderr).contains("tnt_dobratz"),
        "{}",
        text(&o.stderr)
    );
}

/// The run directory's case.toml holds every override; rerun from it, the run is the same.
#[test]
fn case_toml_reruns_the_same_run_and_set_errors_name_the_override() {
    let d = tempfile::tempdir().unwrap();
    let (a, b) = (d.path().join("a"), d.path().join("b"));
    ok(&blastsph(&[
        "run",
        "cases/shock_tube.toml",
        "--quiet",
        "--set",
        "viscosity.alpha=1.2",
        "--set",
        "time.output_interval_s=0.05",
        "--end-time",
        "0.1",
        "--out",
        a.to_str().unwrap(),
    ]));
    let ct = std::fs::read_to_string(a.join("case.toml")).unwrap();
    assert!(ct.contains("--set viscosity.alpha=1.2") && ct.contains("alpha = 1.2  # set by --set (was 1.0)"), "{ct}");
    assert!(ct.contains("# Liu"), "the case file's comments are kept:\n{ct}");
    ok(&blastsph(&["run", a.join("case.toml").to_str().unwrap(), "--quiet", "--out", b.to_str().unwrap()]));
    same_h5(&a.join("particles.h5"), &b.join("particles.h5"));
    assert_eq!(summary(&a)["steps"], summary(&b)["steps"]);
    // an override that breaks the case is named, with no line of a generated file
    for (set, want) in
        [("time.colour=1", "--set time.colour=1"), ("region.right.rho_kgm3=-1", "--set region.right.rho_kgm3=-1")]
    {
        let o = blastsph(&["check", "cases/shock_tube.toml", "--set", "time.cfl=0.3", "--set", set]);
        let e = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{e}");
        assert_eq!(e.lines().count(), 1, "{e}");
        assert!(e.contains(want), "the error names the override: {e}");
        assert!(!e.contains("(with --set)"), "{e}");
    }
}

/// Cases by name from outside the repository (the source tree's cases/), or from --case-dir;
/// a name found nowhere is refused with one line.
#[test]
fn cases_are_found_by_name_from_anywhere() {
    let d = tempfile::tempdir().unwrap();
    let o = blastsph_in(d.path(), &["check", "shock_tube"]);
    ok(&o);
    assert!(text(&o.stdout).contains("400 particles"));
    let o = blastsph_in(
        d.path(),
        &["bench", "--dry-run", "--cases", "shock_tube", "--resolutions", "1", "--backends", "rust"],
    );
    ok(&o);
    let cases: PathBuf = common::root().join("cases");
    let o = blastsph_in(d.path(), &["check", "slope_45", "--case-dir", cases.to_str().unwrap()]);
    ok(&o);
    let o = blastsph_in(d.path(), &["check", "no_such_scene"]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(text(&o.stderr).lines().count(), 1);
    assert!(text(&o.stderr).contains("no_such_scene"), "{}", text(&o.stderr));
    let o = blastsph_in(d.path(), &["check", "shock_tube", "--case-dir", d.path().to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
}

/// Gauges: a particle gauge on a point between four particles picks one without a tie-break by
/// rounding (the lowest id, the same after the case is rescaled); a point gauge interpolates
/// and records pressure, velocity and stress; gauges.csv has a column per quantity.
#[test]
fn gauges_of_both_kinds_record_pressure_velocity_and_stress() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path().join("g");
    ok(&blastsph(&[
        "run",
        "cases/surface_loose_tnt6.toml",
        "--quiet",
        "--end-time",
        "1e-4",
        "--set",
        "gauge.B.kind=point",
        "--out",
        dir.to_str().unwrap(),
    ]));
    let s = summary(&dir);
    let g = s["gauges"].as_array().unwrap();
    let a = g.iter().find(|g| g["name"] == "A").unwrap();
    let b = g.iter().find(|g| g["name"] == "B").unwrap();
    assert_eq!(a["kind"], "particle");
    assert_eq!(a["tied_particles"], 4, "A at (0.5, 0.82) lies between four lattice sites");
    let st: Vec<f64> = a["particle_start_m"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert!((st[0] - 0.495).abs() < 1e-12 && (st[1] - 0.815).abs() < 1e-12, "the lowest of the tied: {st:?}");
    assert_eq!(b["kind"], "point");
    assert!(b["particle"].is_null());
    for k in ["peak_pa", "peak_time_s", "arrival_s", "impulse_pa_s", "ppv_ms"] {
        assert!(a[k].as_f64().is_some_and(|v| v.is_finite()), "A {k}: {}", a[k]);
        assert!(b[k].as_f64().is_some_and(|v| v.is_finite()), "B {k}: {}", b[k]);
    }
    assert!(b["peak_pa"].as_f64().unwrap() > 1e6, "the wave passed B by 100 µs");
    assert!(a["impulse_pa_s"].as_f64().unwrap() > 0.0 && a["ppv_ms"].as_f64().unwrap() > 1.0);
    let csv = std::fs::read_to_string(dir.join("gauges.csv")).unwrap();
    let head: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    for c in ["time_s", "A_p_pa", "B_p_pa", "A_vx_ms", "A_vy_ms", "B_sxx_pa", "B_syy_pa", "B_szz_pa", "B_sxy_pa"] {
        assert!(head.contains(&c), "gauges.csv column {c}: {head:?}");
    }
    // the pressure columns come first, as before gauges recorded more
    assert_eq!(&head[..6], &["time_s", "A_p_pa", "B_p_pa", "C_p_pa", "D_p_pa", "E_p_pa"]);
    let rows: Vec<Vec<f64>> =
        csv.lines().skip(1).map(|l| l.split(',').map(|v| v.parse().unwrap_or(f64::NAN)).collect()).collect();
    assert_eq!(rows.len() as u64, s["steps"].as_u64().unwrap() + 1, "a row per step and t = 0");
    // the point gauge's peak is the largest interpolated pressure of its column
    let kb = head.iter().position(|c| *c == "B_p_pa").unwrap();
    let peak = rows.iter().map(|r| r[kb]).fold(f64::NEG_INFINITY, f64::max);
    assert!((peak - b["peak_pa"].as_f64().unwrap()).abs() <= 1e-6 * peak, "{peak} vs {}", b["peak_pa"]);
    // the stress invariants of B's row at its peak pressure agree with its own stress columns:
    // σ_m the trace's third, von Mises √(3 J2), the principal stresses those of the 3×3 tensor
    // (xz = yz = 0 in 2D), given here in closed form for the in-plane pair
    let col = |n: &str| head.iter().position(|c| *c == format!("B_{n}_pa")).unwrap_or_else(|| panic!("B_{n}_pa"));
    let r = rows.iter().find(|r| r[kb] == peak).unwrap();
    let [xx, yy, zz, xy] = ["sxx", "syy", "szz", "sxy"].map(|n| r[col(n)]);
    let mean = (xx + yy + zz) / 3.0;
    let j2 = 0.5 * ((xx - mean).powi(2) + (yy - mean).powi(2) + (zz - mean).powi(2)) + xy * xy;
    let (c, rad) = (0.5 * (xx + yy), (0.25 * (xx - yy).powi(2) + xy * xy).sqrt());
    let mut principal = [c + rad, c - rad, zz];
    principal.sort_by(|a, b| b.total_cmp(a));
    let near = |a: f64, b: f64| (a - b).abs() <= 1e-5 * xx.abs().max(yy.abs()).max(zz.abs());
    assert!(near(r[col("sigma_mean")], mean), "σ_m {} vs {mean}", r[col("sigma_mean")]);
    assert!(near(r[col("von_mises")], (3.0 * j2).sqrt()), "σ_vm {} vs {}", r[col("von_mises")], (3.0 * j2).sqrt());
    for (k, want) in principal.iter().enumerate() {
        let got = r[col(&format!("sigma_{}", k + 1))];
        assert!(near(got, *want), "σ{} {got} vs {want}", k + 1);
    }
    assert!(mean < 0.0, "the wave compresses B at its peak: σ_m = {mean}");
    // summary.json: the record's highest von Mises and lowest mean stress bound every row's
    let vm_peak = b["peak_von_mises_pa"].as_f64().unwrap();
    let mean_min = b["min_mean_stress_pa"].as_f64().unwrap();
    assert!(
        rows.iter().map(|r| r[col("von_mises")]).all(|v| v.is_nan() || v <= vm_peak * (1.0 + 1e-6)),
        "peak von Mises {vm_peak}"
    );
    assert!(
        rows.iter().map(|r| r[col("sigma_mean")]).all(|v| v.is_nan() || v >= mean_min * (1.0 + 1e-6)),
        "min mean stress {mean_min}"
    );
    assert!(mean_min <= mean * (1.0 - 1e-6) + 1.0, "{mean_min} vs the row's {mean}");
}

/// The crater: with a charge lattice finer than the soil's the crater is the same (within a
/// column) as with equal lattices; a buried charge under an intact dome has a cavity and no
/// apparent crater yet; a report never prints NaN.
#[test]
fn crater_is_measured_from_the_soil_or_refused_with_a_reason() {
    let d = tempfile::tempdir().unwrap();
    let (a, b) = (d.path().join("coarse"), d.path().join("fine"));
    let common_args = ["--quiet", "--end-time", "6e-5", "--set", "time.output_interval_s=2e-5"];
    let mut args = vec!["run", "cases/surface_loose_tnt6.toml", "--out", a.to_str().unwrap()];
    args.extend(common_args);
    ok(&blastsph(&args));
    let mut args = vec![
        "run",
        "cases/surface_loose_tnt6.toml",
        "--out",
        b.to_str().unwrap(),
        "--set",
        "region.charge.spacing_m=0.005",
    ];
    args.extend(common_args);
    ok(&blastsph(&args));
    let (ca, cb) = (summary(&a)["crater"].clone(), summary(&b)["crater"].clone());
    assert_eq!(ca["measured"], true);
    assert_eq!(cb["measured"], true);
    assert_eq!(cb["column_m"], 0.01, "columns of the soil's spacing, not the charge's");
    let (da, db) = (ca["diameter_m"].as_f64().unwrap(), cb["diameter_m"].as_f64().unwrap());
    let (za, zb) = (ca["depth_m"].as_f64().unwrap(), cb["depth_m"].as_f64().unwrap());
    assert!(da > 0.05 && za > 0.03, "a crater by 60 µs: {ca}");
    assert!((da - db).abs() <= 0.041 && (za - zb).abs() <= 0.02, "coarse {ca} against fine {cb}");
    // buried C4 at 60 µs: the dome is up, the gas under it
    let c = d.path().join("c4");
    ok(&blastsph(&["run", "cases/buried_c4.toml", "--quiet", "--end-time", "6e-5", "--out", c.to_str().unwrap()]));
    let cc = summary(&c)["crater"].clone();
    assert_eq!(cc["measured"], true, "{cc}");
    assert_eq!(cc["diameter_m"], 0.0, "no apparent crater under an intact dome: {cc}");
    assert!(cc["note"].as_str().unwrap().contains("contained"), "{cc}");
    let cav = &cc["cavity"];
    assert!(cav["width_m"].as_f64().unwrap() >= 0.06 && cav["height_m"].as_f64().unwrap() >= 0.02, "{cc}");
    assert!(cc["mound_height_m"].as_f64().unwrap() > 0.0, "{cc}");
    let o = blastsph(&["report", c.to_str().unwrap()]);
    ok(&o);
    let so = text(&o.stdout);
    assert!(so.contains("no apparent crater") && so.contains("cavity:"), "{so}");
    assert!(!so.contains("NaN") && !so.contains("nan"), "{so}");
}

/// A 3D blast's report: the crater in its four sections through the charge's axis (summary.json
/// and the text), and the plots drawn on the vertical section through the axis (maps in x–z),
/// with the peaks scaled by the whole charge (the quarter's four images).
#[test]
fn a_3d_report_draws_its_section_and_measures_the_crater_in_sections() {
    let d = tempfile::tempdir().unwrap();
    let r = d.path().join("q");
    ok(&blastsph(&[
        "run",
        "cases/surface_loose_tnt1kg_3d.toml",
        "--quiet",
        "--end-time",
        "1.2e-4",
        "--out",
        r.to_str().unwrap(),
        "--set",
        "region.soil.spacing_m=0.023",
        "--set",
        "region.charge.spacing_m=0.023",
    ]));
    let secs = summary(&r)["crater"]["sections"].as_array().cloned().expect("crater.sections in 3D");
    let deg: Vec<f64> = secs.iter().map(|s| s["azimuth_deg"].as_f64().unwrap()).collect();
    assert_eq!(deg, [0.0, 45.0, 90.0, 135.0]);
    // the quarter's two symmetry planes: the sections along x and along y read the same crater
    assert_eq!(secs[0]["diameter_m"], secs[2]["diameter_m"], "{secs:?}");
    assert!(secs[0]["diameter_m"].as_f64().unwrap() > 0.1, "a crater by 120 µs: {secs:?}");
    // the crater as a surface: the whole scene (the quarter and its 3 images) in cells of 23 mm
    let map = summary(&r)["crater"]["surface"].clone();
    assert!(map.is_object(), "crater.surface in 3D: {map}");
    assert!(map["note"].is_null(), "{map}");
    let num = |k: &str| map[k].as_f64().filter(|v| v.is_finite()).unwrap_or_else(|| panic!("{k}: {map}"));
    assert_eq!(num("cell_m"), 0.023);
    assert_eq!(map["cells"], serde_json::json!([48, 48]), "{map}");
    for k in ["depth_m", "volume_m3", "plan_area_m2", "radius_min_m", "radius_max_m"] {
        assert!(num(k) > 0.0, "{k}: {map}");
    }
    assert!(num("radius_min_m") <= num("radius_max_m"), "{map}");
    let eq = num("equivalent_diameter_m");
    assert!((eq - 2.0 * (num("plan_area_m2") / std::f64::consts::PI).sqrt()).abs() < 1e-12, "{map}");
    // the same crater as the sections' within two cells
    let mean = secs.iter().map(|s| s["diameter_m"].as_f64().unwrap()).sum::<f64>() / 4.0;
    assert!((eq - mean).abs() <= 2.0 * 0.023, "equivalent diameter {eq}, sections {secs:?}");
    let o = blastsph(&["report", r.to_str().unwrap()]);
    ok(&o);
    let so = text(&o.stdout);
    assert!(so.contains("sections through the charge's axis"), "{so}");
    assert!(so.contains("crater as a surface") && so.contains("equivalent diameter"), "{so}");
    for f in ["peaks.png", "crater_profile.png", "crater_map.png", "gauges.png", "bubble_growth.png", "ppv_map.png"] {
        assert!(r.join(f).exists(), "{f} not drawn:\n{so}");
    }
    let snaps = std::fs::read_dir(&r).unwrap().filter_map(|e| e.ok()).filter(|e| {
        let n = e.file_name().to_string_lossy().into_owned();
        n.starts_with("snap_material_") && n.ends_with(".png")
    });
    assert!(snaps.count() >= 2, "{so}");
    let rep: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(r.join("report.json")).unwrap()).unwrap();
    let scaled = rep["peaks_scaled"].as_array().cloned().unwrap_or_default();
    assert!(!scaled.is_empty(), "{rep}");
    // gauge A 0.15 m from the detonation point; the whole charge is 4 x the quarter's lattice
    // cylinder at 23 mm: 4 x 12 particles x 1630 kg/m3 x 0.023^3 m3 = 0.952 kg (the report's title)
    let a = scaled.iter().find(|g| g["gauge"].as_str().unwrap_or("").starts_with("A ")).expect("gauge A");
    let z = a["scaled_distance"].as_f64().unwrap();
    assert!((z - 0.15 / 0.952f64.cbrt()).abs() < 2e-4, "scaled distance of A: {z}");
    // the crater scaled by the whole charge: R/W^(1/3), R half the surface map's equivalent
    // diameter (in report.json's crater, and printed)
    let c = &rep["crater"];
    let w = c["charge_mass_kg"].as_f64().unwrap_or_else(|| panic!("{c}"));
    assert!((w - 4.0 * 12.0 * 1630.0 * 0.023f64.powi(3)).abs() < 1e-9, "charge {w}");
    let dq = c["surface"]["equivalent_diameter_m"].as_f64().unwrap();
    let sc = c["scaled_radius_m_per_kg_cbrt"].as_f64().unwrap();
    assert!(dq > 0.0 && (sc - 0.5 * dq / w.cbrt()).abs() < 1e-12, "R/W^(1/3) {sc} from D {dq}, W {w}");
    assert!(so.contains(&format!("R/W^(1/3) = {sc:.3} m/kg^(1/3)")), "{so}");
    // every plot the report wrote is one a later report or a resume removes by name
    for e in std::fs::read_dir(&r).unwrap().filter_map(|e| e.ok()) {
        let n = e.file_name().to_string_lossy().into_owned();
        if n.ends_with(".png") || n.ends_with(".gif") {
            assert!(blastsph::rundir::is_report_plot(&n), "{n} is not in rundir::is_report_plot's list");
        }
    }
    // a second report at other times replaces the first's snapshots; a PNG of the user's stays
    std::fs::write(r.join("mine.png"), b"not blastsph's").unwrap();
    let o = blastsph(&["report", r.to_str().unwrap(), "--times", "0", "--animate"]);
    ok(&o);
    // the animation is written under a temporary name and renamed whole (an interrupted report
    // left a truncated one under the final name): a GIF with its trailer, no .tmp beside it
    let gif = std::fs::read(r.join("animation.gif")).unwrap();
    assert!(gif.starts_with(b"GIF8") && gif.last() == Some(&b';'), "a whole GIF");
    assert!(!r.join("animation.gif.tmp").exists());
    let mut snaps: Vec<String> = std::fs::read_dir(&r)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("snap_material_"))
        .collect();
    snaps.sort();
    assert_eq!(snaps.len(), 1, "{snaps:?}");
    assert!(r.join("mine.png").exists() && r.join("peaks.png").exists());
}

/// An underwater charge in RZ over a symmetry plane (a mirror wall on y = 0 through its centre,
/// the set-up docs/reference/cases.md gives for a point blast): the report scales by the whole charge, both
/// halves (it used to take the modelled half: distances 2^⅓ too far, the products' radius 2^⅓
/// too small), and a gauge the wave has not reached is not a peak (it used to read its noise
/// over the ambient pressure as a peak, arriving at t = 0).
#[test]
fn a_half_space_charge_is_scaled_whole_and_an_unreached_gauge_is_no_peak() {
    let d = tempfile::tempdir().unwrap();
    let dir = run_inline(
        d.path(),
        r#"name = "uw_half"
dim = 2
geometry = "axisymmetric"
[time]
end_s = 8.0e-6
output_interval_s = 4.0e-6
[[material]]
name = "tnt"
preset = "tnt"
[[material]]
name = "water"
preset = "water"
[[region]]
name = "charge"
material = "tnt"
shape = "sphere"
center_m = [0.0, 0.0]
radius_m = 0.012
lo_m = [0.0, 0.0]
hi_m = [0.012, 0.012]
spacing_m = 0.002
[[region]]
name = "water"
material = "water"
shape = "box"
lo_m = [0.0, 0.0]
hi_m = [0.12, 0.12]
spacing_m = 0.004
subtract = ["charge"]
[[wall]]
from_m = [0.0, 0.0]
to_m = [0.12, 0.0]
kind = "mirror"
[detonation]
mode = "programmed"
point_m = [0.0, 0.0]
[[gauge]]
name = "near"
point_m = [0.03, 0.002]
kind = "point"
[[gauge]]
name = "far"
point_m = [0.11, 0.002]
kind = "point"
"#,
    );
    let s = summary(&dir);
    let g = s["gauges"].as_array().unwrap();
    let (near, far) = (&g[0], &g[1]);
    assert_eq!(near["reached"], true, "{near}");
    assert!(near["arrival_s"].as_f64().is_some_and(|t| t > 0.0), "{near}");
    assert_eq!(far["reached"], false, "the wave travels < 5 cm in 8 µs: {far}");
    assert!(far["arrival_s"].is_null(), "{far}");
    let o = blastsph(&["report", dir.to_str().unwrap()]);
    ok(&o);
    assert!(text(&o.stdout).contains("gauge far (point): not reached by the wave"), "{}", text(&o.stdout));
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    // the whole sphere: 4/3 π R³ ρ, the products' radius R at t = 0 (the lattice's few per cent)
    let (r0, rho) = (0.012f64, 1630.0);
    let w = 4.0 / 3.0 * std::f64::consts::PI * r0.powi(3) * rho;
    let b0 = r["bubble"][0]["equivalent_radius_m"].as_f64().unwrap();
    assert!((b0 / r0 - 1.0).abs() < 0.08, "the products' radius at t = 0: {b0} m for a {r0} m charge");
    let peaks = r["peaks_scaled"].as_array().unwrap();
    assert_eq!(peaks.len(), 1, "only the reached gauge: {peaks:?}");
    let z = peaks[0]["scaled_distance"].as_f64().unwrap();
    let z_whole = 0.03f64.hypot(0.002) / w.cbrt();
    assert!((z / z_whole - 1.0).abs() < 0.05, "scaled distance {z} against {z_whole} for the whole {w:.4} kg");
}

/// A gauge placed in the explosive is named by `check` (a particle gauge would follow a products
/// particle, a point gauge read the products); the shipped gauges, in the ground, are not.
#[test]
fn a_gauge_inside_the_charge_is_named() {
    let case = "cases/surface_loose_tnt1kg_rz.toml";
    let o = blastsph(&["check", case]);
    ok(&o);
    assert!(!text(&o.stdout).contains("inside the explosive"), "{}", text(&o.stdout));
    let o = blastsph(&[
        "check",
        case,
        "--set",
        "gauge.A.point_m=[0.01,0.95]",
        "--set",
        "gauge.C.kind=\"point\"",
        "--set",
        "gauge.C.point_m=[0.02,0.93]",
    ]);
    ok(&o);
    // (check prints its warnings with the plan, on stdout)
    let err = text(&o.stdout);
    let lines: Vec<&str> = err.lines().filter(|l| l.contains("inside the explosive `tnt`")).collect();
    assert_eq!(lines.len(), 2, "{err}");
    assert!(
        lines[0].contains("gauge `A`") && lines[0].contains("follows a particle of the detonation products"),
        "{err}"
    );
    assert!(lines[1].contains("gauge `C`") && lines[1].contains("reads the detonation products"), "{err}");
}

/// A 3D half model without a detonation point: the charge's axis is the whole charge's, on the
/// symmetry plane (it was the modelled half's centroid, half a charge off it), so the gauges'
/// distances, the sections and the crater are measured about it.
#[test]
fn a_half_model_charge_is_centred_on_its_symmetry_plane() {
    let d = tempfile::tempdir().unwrap();
    let dir = run_inline(
        d.path(),
        r#"name = "half3d"
dim = 3
[time]
end_s = 1.0e-4
output_interval_s = 5.0e-5
[[material]]
name = "tnt"
preset = "tnt"
[[material]]
name = "sand"
preset = "dense_sand"
[[region]]
name = "charge"
material = "tnt"
shape = "box"
lo_m = [-0.05, 0.0, 0.2]
hi_m = [0.05, 0.05, 0.3]
spacing_m = 0.025
[[region]]
name = "soil"
material = "sand"
shape = "box"
lo_m = [-0.3, 0.0, 0.0]
hi_m = [0.3, 0.3, 0.3]
spacing_m = 0.025
subtract = ["charge"]
[[wall]]
from_m = [-0.3, 0.0, 0.0]
to_m = [0.3, 0.0, 0.6]
kind = "mirror"
[[wall]]
from_m = [-0.3, 0.0, 0.0]
to_m = [0.3, 0.3, 0.0]
[detonation]
mode = "instant"
[[gauge]]
name = "y_side"
point_m = [0.0, 0.175, 0.25]
[analysis]
kind = "crater"
"#,
    );
    let s = summary(&dir);
    let ax = &s["crater"]["surface"]["axis_m"];
    assert!(ax[1].as_f64().is_some_and(|y| y.abs() < 1e-12), "the axis on the plane y = 0: {ax}");
    let o = blastsph(&["report", dir.to_str().unwrap()]);
    ok(&o);
    let out = text(&o.stdout);
    assert!(out.contains("the modelled part, 1/2 of the scene"), "{out}");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    // the gauge's particle starts 17.5 cm from the axis (12.5 cm from the half's centroid)
    let g = &r["peaks_scaled"][0];
    assert!(g["gauge"].as_str().is_some_and(|l| l.starts_with("y_side (18 cm")), "{g}");
}

/// Writes the case `text` into `d` and runs it (quiet) into `d/run`, which it returns.
fn run_inline(d: &std::path::Path, text: &str) -> std::path::PathBuf {
    let case = d.join("case.toml");
    std::fs::write(&case, text).unwrap();
    let dir = d.join("run");
    ok(&blastsph(&["run", case.to_str().unwrap(), "--quiet", "--out", dir.to_str().unwrap()]));
    dir
}

/// `blastsph check` of the shipped 3D quarter compact charge with `--set` overrides.
fn check_quarter(sets: &[&str]) -> Output {
    let case = common::root().join("cases/surface_loose_tnt1kg_3d.toml");
    let mut a = vec!["check", case.to_str().unwrap()];
    for s in sets {
        a.extend(["--set", s]);
    }
    blastsph(&a)
}

/// Its output, the check passed (exit 0): stdout and stderr together.
fn checked_quarter(sets: &[&str]) -> String {
    let o = check_quarter(sets);
    ok(&o);
    text(&o.stdout) + &text(&o.stderr)
}

/// Slips of units that make a case run as another scene (a docs-only engineer's mistakes: each
/// passed `check` silently; three then ended the run at its first steps with advice to lower the
/// CFL, one made a square prism of the cylinder): `check` names each with its likely unit (a
/// density in g/cm³ it refuses), and the case as shipped names none of them.
#[test]
fn slips_of_units_are_named_by_check() {
    let plain = checked_quarter(&[]);
    for hint in ["g/cm³", "kJ/kg", "in mm", "mass_kg is each particle's mass, in kg"] {
        assert!(!plain.contains(hint), "{hint} in the shipped case: {plain}");
    }
    for (set, want) in [
        ("region.charge.e_jkg=4290", "warning: region charge (tnt): e_jkg = 4290 J/kg"),
        ("region.charge.radius_m=46", "warning: region charge: its radius_m = 46 m does not cut its lo_m/hi_m box"),
        ("region.charge.mass_kg=2.4", "warning: region charge (tnt): mass_kg = 2.4 kg per particle"),
    ] {
        let t = checked_quarter(&[set]);
        let line = t.lines().find(|l| l.starts_with(want)).unwrap_or_else(|| panic!("{set}: {t}"));
        assert!(line.contains('?') || line.contains("in kg"), "{line}");
    }
    // a density in g/cm³ is refused, not warned of (tests/slips.rs)
    let o = check_quarter(&["material.tnt.eos.rho0_kgm3=1.63"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(text(&o.stderr).starts_with("error: material tnt: rho0_kgm3 = 1.63 kg/m³"), "{}", text(&o.stderr));
}

/// A quarter model whose charge is off its symmetry planes' intersection (a docs-only engineer's
/// 0.5 kg charge centred 0.1 m off both planes ran as four charges, 2 kg, with no word): `check`
/// says the planes' images make more charges, and how many; the shipped quarter (the charge on
/// the planes) says nothing of it.
#[test]
fn a_charge_beside_its_symmetry_planes_is_said_to_be_several() {
    assert!(!checked_quarter(&[]).contains("does not abut the symmetry plane"));
    let t = checked_quarter(&[
        "region.charge.center_m=[0.1, 0.1, 0.46]",
        "region.charge.lo_m=[0.0, 0.0, 0.0]",
        "region.charge.hi_m=[0.552, 0.552, 0.552]",
        "detonation.point_m=[0.1, 0.1, 0.506]",
    ]);
    let line = t.lines().find(|l| l.contains("does not abut the symmetry plane")).unwrap_or_else(|| panic!("{t}"));
    // the whole cylinder (radius 4 spacings of 11.5 mm) 0.1 - 0.046 = 0.054 m off x = 0 and y = 0
    assert!(line.starts_with("warning: region charge (explosive)"), "{line}");
    assert!(line.contains("x = 0 m (0.054 m from it) and y = 0 m (0.054 m from it)"), "{line}");
    assert!(line.contains("the scene holds 4 charges"), "{line}");
}

/// Two refusals a docs-only engineer found unclear now say what is allowed: a point gauge
/// outside the particles names the range it may lie in (the extent and the kernel's reach
/// beyond it, added up), and an end time whose outputs run into the millions asks whether the
/// end time was meant in seconds.
#[test]
fn refusals_of_a_gauge_outside_and_of_an_end_in_milliseconds_say_what_is_meant() {
    let refused = |sets: &[&str]| {
        let o = check_quarter(sets);
        assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
        assert_eq!(text(&o.stderr).lines().count(), 1, "{}", text(&o.stderr));
        text(&o.stderr)
    };
    // the quarter's particles span 0.00575 .. 0.54625 m along y (spacing 11.5 mm), the reach 2h
    let e = refused(&["gauge.G2.kind=point", "gauge.G2.point_m=[0.2, -0.2, 0.4]"]);
    assert!(e.contains("on axis 1 (y): a point gauge may lie from -0.017250 to 0.569250 m"), "{e}");
    let e = refused(&["time.end_s=300"]);
    assert!(e.contains("is time.end_s = 3e2 s meant (seconds, not ms or µs)?"), "{e}");
}
