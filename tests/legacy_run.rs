//! Bring your own legacy code, part 2 (docs/howto/migrate.md): the fixture run by blastsph
//! (`run --legacy`), dual-checked routine by routine against the Rust twins (`dual --legacy`,
//! with and without `--compat liu-book`), and the ledger.

mod legacy_kit;
use legacy_kit::*;

#[test]
fn dual_legacy_with_the_liu_book_profile_is_at_zero_ulp_for_every_mapped_routine() {
    let out = scratch("dual_book");
    let so = blastsph_ok(
        &[
            "dual",
            "shock_tube",
            "--legacy",
            shared().to_str().unwrap(),
            "--compat",
            "liu-book",
            "--out",
            out.to_str().unwrap(),
        ],
        0,
    );
    assert!(so.contains("40 steps compared; every compared stage within tolerance"), "{so}");
    let (r, rows) = report_rows(&out.join("dual_report.json"));
    assert_eq!(r["steps"], 40);
    for (stage, fields) in MAPPED {
        for f in *fields {
            let x = row(&rows, stage, f);
            assert_eq!(x["counterpart"], "legacy", "{x}");
            assert!(x["compared"].as_u64().unwrap() >= 400 * 40, "{stage} {f}: {x}");
            assert_eq!(x["max_ulp"], 0, "{stage} {f}: {x}");
            assert_eq!(x["out_of_tolerance"], 0, "{stage} {f}: {x}");
        }
    }
    // a routine standing for stages of two modules: each row names the module of its field
    assert_eq!(row(&rows, "legacy.int_force", "p")["module"], "eos");
    assert_eq!(row(&rows, "legacy.int_force", "acc")["module"], "force");
    // what each routine was compared with (the chain of Rust twins) and what was not run
    let lg = &r["legacy"]["routines"];
    assert_eq!(lg["direct_find"]["stands_for"], serde_json::json!(["nnps.search", "kernel.pairs"]));
    assert_eq!(lg["int_force"]["stands_for"], serde_json::json!(["eos.eval", "force.internal"]));
    assert_eq!(lg["sum_density"]["stands_for"], serde_json::json!(["kernel.self", "density.summation"]));
    assert_eq!(lg["input"]["status"], "setup");
    assert_eq!(lg["av_vel"]["status"], "not run");
}

#[test]
fn dual_legacy_without_the_profile_names_each_difference() {
    let out = scratch("dual_plain");
    let so =
        blastsph_ok(&["dual", "shock_tube", "--legacy", shared().to_str().unwrap(), "--out", out.to_str().unwrap()], 4);
    assert!(so.contains("MODULES OUT OF TOLERANCE"), "{so}");
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    // the same pairs in the same order (the fixture's direct_find and blastsph's direct search)
    assert_eq!(row(&rows, "legacy.direct_find", "pair_i")["out_of_tolerance"], 0);
    assert_eq!(row(&rows, "legacy.direct_find", "pair_j")["out_of_tolerance"], 0);
    // the book's sound speed sqrt((gamma-1) e) against sqrt(gamma (gamma-1) e): c differs from
    // the first evaluation, by the factor sqrt(gamma) less the single-precision gamma
    let c = row(&rows, "legacy.p_gas", "c");
    assert!(c["out_of_tolerance"].as_u64().unwrap() > 0, "{c}");
    let (lf, rs) =
        (c["first_divergence"]["fortran"].as_f64().unwrap(), c["first_divergence"]["rust"].as_f64().unwrap());
    assert!((rs / lf - 1.4f64.sqrt()).abs() < 1e-6, "c: legacy {lf}, rust {rs}");
    assert!(c["tolerance_why"].as_str().unwrap().contains("sound_speed"), "{c}");
    // the kernel's single-precision 2/3 and the viscosity's order: named, item by item
    for (stage, field, item) in [
        ("legacy.kernel", "w", "kernel"),
        ("legacy.sum_density", "rho", "kernel_literals"),
        ("legacy.art_visc", "dde", "visc_energy"),
        ("legacy.int_force", "dde", "force_energy"),
    ] {
        let x = row(&rows, stage, field);
        assert!(x["out_of_tolerance"].as_u64().unwrap() > 0, "{stage} {field}: {x}");
        assert!(x["tolerance_why"].as_str().unwrap().contains(item), "{stage} {field} must name {item}: {x}");
    }
}

#[test]
fn run_legacy_ends_in_the_state_of_the_codes_own_program_bit_for_bit() {
    let f = assert_run_ends_as_the_program(shared(), "run_book");
    // without the profile blastsph's own integrator and twins run around the user's routines:
    // a different end state (the sound speed alone moves rho by 1e-3 and more)
    let out2 = scratch("run_plain");
    blastsph_ok(
        &["run", "shock_tube", "--legacy", shared().to_str().unwrap(), "--out", out2.to_str().unwrap(), "--quiet"],
        0,
    );
    let g = blastsph::output::read_frames(&out2.join("particles.h5")).unwrap().pop().unwrap();
    assert_ne!(g.rho, f.rho);
}

#[test]
fn the_ledger_attributes_each_difference_to_its_item() {
    let out = scratch("ledger");
    let ledger =
        ["legacy", "ledger", "shock_tube", "--legacy", shared().to_str().unwrap(), "--out", out.to_str().unwrap()];
    let so = blastsph_ok(&[&ledger[..], &["--threads", "1"]].concat(), 0);
    assert!(so.contains("end in the same state, bit for bit"), "{so}");
    let (r, rows) = report_rows(&out.join("ledger.json"));
    assert_eq!(r["profile"], "liu-book");
    let get = |run: &str| rows.iter().find(|x| x["run"] == run).unwrap_or_else(|| panic!("no row {run}: {so}"));
    let num = |run: &str, k: &str| get(run)[k].as_f64().unwrap();
    // the user's routines and the profile's Rust twins: the same end state
    assert_eq!(get("legacy")["particles_differing"], 0);
    assert_eq!(get("profile")["particles_differing"], 0);
    assert_eq!(get("legacy")["steps"], 40);
    // the items this case exercises move the end state; the largest is the sound speed
    let moving = ["-literals", "-dt_literal", "-kernel_literals", "-sound_speed", "-kernel"];
    for item in moving.iter().chain(&["-force_energy", "-visc_energy"]) {
        assert!(num(item, "max_abs_rho") > 0.0 || num(item, "max_abs_e") > 0.0, "{item}: {so}");
    }
    assert!(num("-sound_speed", "max_abs_rho") > 1e-3, "{so}");
    for item in ["-literals", "-dt_literal", "-kernel_literals", "-kernel", "-force_energy", "-visc_energy"] {
        assert!(num(item, "max_abs_rho") < 1e-6, "{item}: {so}");
    }
    // items of what the case does not run (virtual particles, XSPH, the quintic kernel): no effect
    // and the regions' values, which the user's set-up routine gives in every run
    for item in ["-virtual_pairs", "-xsph_velocity", "-quintic_gradient", "-input_literals"] {
        assert_eq!(get(item)["particles_differing"], 0, "{item}: {so}");
    }
    // the case's own error: the book code's sound speed lowers its L1(rho) (0.01553, measured with the book code's own program)
    let l1 = |run: &str| get(run)["l1"][0].as_f64().unwrap();
    assert!((l1("profile") - 0.01553).abs() < 2e-4, "{so}");
    assert!(l1("-sound_speed") > l1("profile"), "{so}");
    // a second ledger into the same folder replaces the first (its ledger.json is blastsph's)
    let again = blastsph(&ledger);
    assert_eq!(again.status.code(), Some(0), "{}", String::from_utf8_lossy(&again.stderr));
    // --compat none: the routines against blastsph's own twins, no item rows (it ran the
    // liu-book profile in its place)
    let none = scratch("ledger_none");
    let so = blastsph_ok(
        &[
            "legacy",
            "ledger",
            "shock_tube",
            "--legacy",
            shared().to_str().unwrap(),
            "--compat",
            "none",
            "--out",
            none.to_str().unwrap(),
        ],
        0,
    );
    let (r, rows) = report_rows(&none.join("ledger.json"));
    assert_eq!(r["profile"], "none", "{so}");
    let runs: Vec<&str> = rows.iter().map(|x| x["run"].as_str().unwrap()).collect();
    assert_eq!(runs, ["legacy", "profile"], "{so}");
    // the book's routines under blastsph's own semantics: its sound speed moves the end state
    assert!(rows[0]["max_abs_rho"].as_f64().unwrap() > 1e-3, "{so}");
}

#[test]
fn bad_legacy_runs_are_refused_with_one_line() {
    let one_line = |args: &[&str], needles: &[&str]| {
        let o = blastsph(args);
        let se = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {se}");
        assert_eq!(se.lines().count(), 1, "{se}");
        for n in needles {
            assert!(se.contains(n), "must name {n}: {se}");
        }
    };
    let lg = shared().to_str().unwrap();
    // a folder that is no build
    let empty = scratch("no_build");
    one_line(&["check", "shock_tube", "--legacy", empty.to_str().unwrap()], &[empty.to_str().unwrap()]);
    // a case of another dimension than the build's param.inc
    one_line(&["check", "underwater_box", "--legacy", lg], &["dim = 1", "dim = 2"]);
    // an unknown compat item or profile
    one_line(&["check", "shock_tube", "--legacy", lg, "--compat", "liu-book,-sound_sped"], &["sound_sped"]);
    // more particles than maxn
    one_line(
        &["check", "shock_tube", "--legacy", lg, "--set", "region.right.count=[700]"],
        &["maxn = 1000", "1020 particles"],
    );
}

/// A source that needs another compiler's module (the book's `time_print.f90` and
/// `time_elapsed.f90` use `dfport`): refused as a compile error, built once the manifest excludes
/// it, also when that leaves a `sources` pattern with no file (the book's `*.f90`: only the two
/// timers). `run_dirs` makes the folders the code opens its files in (the book's `./TEST/data`).
#[test]
fn a_file_that_does_not_compile_with_gfortran_can_be_excluded() {
    let dfport = "subroutine time_print\n  use dfport\n  implicit none\nend subroutine time_print\n";
    let d = variant("dfport", |t| t.replace("sources = [\"*.f\"]", "sources = [\"*.f\", \"*.f90\"]"));
    std::fs::write(d.join("time_print.f90"), dfport).unwrap();
    refused(&d, &["time_print.f90", "build.log"]);
    let d = variant("dfport_excluded", |t| {
        t.replace(
            "sources = [\"*.f\"]",
            "sources = [\"*.f\", \"*.f90\"]\nexclude = [\"time_print.f90\"]\nrun_dirs = [\"TEST/data\"]",
        )
    });
    std::fs::write(d.join("time_print.f90"), dfport).unwrap();
    let b = d.join("build");
    let o = blastsph(&["legacy", "build", d.join("legacy.toml").to_str().unwrap(), "--out", b.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    blastsph_ok(&["check", "shock_tube", "--legacy", b.to_str().unwrap()], 0);
    assert!(!b.join("work").exists(), "check writes nothing in DIR (its routines run in a scratch folder)");
    blastsph_ok(&dual_book_args(&b, Some(1), &d.join("dual")), 0);
    assert!(b.join("work/TEST/data").is_dir(), "run_dirs made in DIR/work");
    let d = variant("exclude_nothing", |t| {
        t.replace("sources = [\"*.f\"]", "sources = [\"*.f\"]\nexclude = [\"nosuch.f\"]")
    });
    refused(&d, &["exclude", "nosuch.f", "matches no file"]);
    let d = variant("run_dirs_outside", |t| {
        t.replace("sources = [\"*.f\"]", "sources = [\"*.f\"]\nrun_dirs = [\"../../x\"]")
    });
    refused(&d, &["run_dirs", "../../x"]);
}

/// A search that returns the same pairs in another order and the other way round
/// (`tests/legacy_extra/rev_find.f`, mapped in place of direct_find): the dual run compares the
/// pair lists as sets, lines the Rust side's w and ∇W up with the legacy order (∇W negated for a
/// reversed pair), reports the order difference, and everything stays at 0 ULP.
#[test]
fn a_pair_list_in_another_order_is_compared_as_a_set() {
    let d = variant("rev_find", |t| t.replace("name = \"direct_find\"", "name = \"rev_find\""));
    std::fs::copy(root().join("tests/legacy_extra/rev_find.f"), d.join("rev_find.f")).unwrap();
    let lg = d.join("build");
    build(&d.join("legacy.toml"), &lg).expect("the variant builds");
    let out = d.join("dual");
    let so = blastsph_ok(&dual_book_args(&lg, None, &out), 0);
    assert!(so.contains("pairs as sets: 40 steps in another order"), "{so}");
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    for f in ["pair_i", "pair_j", "w", "dwdx"] {
        let x = row(&rows, "legacy.rev_find", f);
        assert_eq!((x["max_ulp"].as_u64(), x["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{f}: {x}");
    }
    let o = &row(&rows, "legacy.rev_find", "pair_i")["pair_order"];
    let compared = row(&rows, "legacy.rev_find", "pair_i")["compared"].as_u64().unwrap();
    assert_eq!(o["reversed"].as_u64(), Some(compared), "every pair reversed: {o}");
    assert!(o["moved"].as_u64().unwrap() > compared / 2, "{o}");
    assert_eq!((o["only_counterpart"].as_u64(), o["only_rust"].as_u64()), (Some(0), Some(0)), "{o}");
    for (stage, field) in [("legacy.sum_density", "rho"), ("legacy.int_force", "acc"), ("legacy.art_visc", "dde")] {
        assert_eq!(row(&rows, stage, field)["max_ulp"], 0, "{stage} {field}");
    }
}

/// A search that declares `hsml` a scalar, as the book's link_list does (`double precision
/// hsml`: it reads the first particle's h, the compat item global_h): it builds, and in the
/// shock tube (one h for all) its pairs agree with the twins'.
#[test]
fn a_search_with_a_scalar_hsml_builds_as_the_books_link_list() {
    let d = variant_built("scalar_hsml", "direct_find.f", |t| {
        t.replacen("hsml(maxn), x(dim,maxn)", "hsml, x(dim,maxn)", 1).replacen(
            "hij = (hsml(i) + hsml(j))/2.",
            "hij = hsml",
            1,
        )
    });
    let lg = d.join("build");
    let mut args = dual_book_args(&lg, Some(2), &d.join("dual"));
    args[5] = "liu-book,global_h".to_string();
    blastsph_ok(&args, 0);
    let (_, rows) = report_rows(&d.join("dual/dual_report.json"));
    for f in ["pair_i", "pair_j", "w", "dwdx"] {
        let x = row(&rows, "legacy.direct_find", f);
        assert_eq!((x["max_ulp"].as_u64(), x["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{f}: {x}");
    }
}

/// A legacy routine that adds rate terms but cannot stand for its module's Rust stage (here the
/// CFL step reads max|μ|, which the book's art_visc does not give) is not run beside that stage:
/// running both would count the viscosity twice.
#[test]
fn a_routine_that_cannot_stand_for_its_stage_is_not_added_to_it() {
    let d = shared().to_str().unwrap();
    let base = ["check", "shock_tube", "--legacy", d, "--compat", "liu-book"];
    let so = blastsph_ok(&base, 0);
    assert!(so.contains("legacy.art_visc"), "{so}");
    let cfl = [&base[..], &["--set", "time.step=cfl", "--set", "time.viscous_step=true"]].concat();
    let so = blastsph_ok(&cfl, 0);
    let line = so.lines().find(|l| l.trim_start().starts_with("art_visc")).unwrap_or_default();
    assert!(line.contains("not run") && line.contains("twice"), "{so}");
    assert!(!so.contains("legacy.art_visc"), "{so}");
    assert!(so.contains("energy rate = legacy.int_force + viscosity.monaghan\n"), "{so}");
    // what it lacks, and the setting that asks for it
    assert!(line.contains("also writes mumax") && line.contains("time.viscous_step=false"), "{so}");
    // the dual run says so in a warning and on its verdict line (it was read as agreement)
    let out = scratch("unrun_dual");
    let mut args = dual_book_args(shared(), Some(2), &out.join("d"));
    args.extend(["--set", "time.step=cfl", "--set", "time.viscous_step=true"].map(String::from));
    let o = blastsph(&args);
    let (so, se) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(se.contains("warning: legacy art_visc is not run:") && se.contains("mumax"), "{se}");
    assert!(so.contains("1 mapped legacy routine(s) NOT RUN"), "{so}");
}

/// The switches of param.inc that the book ships off, each met by its compat item (found on the
/// genuine book code, docs/howto/migrate.md): with `pa_sph = 1` int_force differs from the profile
/// until `pa_sph1` is on, with `nor_density` sum_density until `nor_density` is on; with the item
/// every mapped routine is at 0 ULP and `run --legacy` ends where the variant's own program ends.
#[test]
fn param_inc_switches_are_matched_by_their_compat_items_at_zero_ulp() {
    let cases: [(&str, &str, &str, &str, &str, &str); 2] = [
        ("pa1", "parameter (pa_sph = 2)", "parameter (pa_sph = 1)", "pa_sph1", "legacy.int_force", "acc"),
        (
            "nor",
            "parameter (nor_density       = .false.)",
            "parameter (nor_density       = .true.)",
            "nor_density",
            "legacy.sum_density",
            "rho",
        ),
    ];
    for (name, from, to, item, stage, field) in cases {
        let d = variant_built(&format!("switch_{name}"), "param.inc", |t| t.replace(from, to));
        let b = d.join("build");
        let (bs, off, on) = (b.to_str().unwrap(), d.join("dual_off"), d.join("dual_on"));
        // the profile alone: the routine differs, and its row names the item that is off
        blastsph_ok(&["dual", "shock_tube", "--legacy", bs, "--compat", "liu-book", "--out", off.to_str().unwrap()], 4);
        let (_, rows) = report_rows(&off.join("dual_report.json"));
        let x = row(&rows, stage, field);
        assert!(x["out_of_tolerance"].as_u64().unwrap() > 0, "{name}: {x}");
        assert!(x["tolerance_why"].as_str().unwrap().contains(item), "{name}: {x}");
        // with the item: every mapped routine at 0 ULP
        let spec = format!("liu-book,{item}");
        let so =
            blastsph_ok(&["dual", "shock_tube", "--legacy", bs, "--compat", &spec, "--out", on.to_str().unwrap()], 0);
        assert!(so.contains("40 steps compared; every compared stage within tolerance"), "{name}: {so}");
        let (_, rows) = report_rows(&on.join("dual_report.json"));
        for (stage, fields) in MAPPED {
            for f in *fields {
                let x = row(&rows, stage, f);
                assert_eq!((x["max_ulp"].as_u64(), x["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{name}: {x}");
            }
        }
        // run --legacy ends in the state of the variant's own program, bit for bit
        let prog = program_rows_of(&b, &format!("switch_{name}_program"), 40);
        assert_run_ends_as(&b, "shock_tube", &spec, &prog, &format!("switch_{name}_run"));
    }
}

/// The book ships `average_velocity = .true.` (av_vel, ε = 0.3): av_vel at 0 ULP, run --legacy
/// equal to the program, and in the ledger the case without the book's sound speed goes unstable:
/// a row that says so, not the end of the ledger.
#[test]
fn the_books_averaged_velocity_is_matched_and_an_unstable_ledger_row_is_reported() {
    let d = variant_built("switch_xsph", "param.inc", |t| {
        t.replace("parameter (average_velocity  = .false.)", "parameter (average_velocity  = .true.)")
    });
    let (b, case) = (d.join("build"), xsph_case(&d));
    let (bs, cs, out) = (b.to_str().unwrap(), case.to_str().unwrap(), d.join("dual"));
    blastsph_ok(&["dual", cs, "--legacy", bs, "--compat", "liu-book", "--out", out.to_str().unwrap()], 0);
    let (r, rows) = report_rows(&out.join("dual_report.json"));
    assert_eq!(r["legacy"]["routines"]["av_vel"]["stands_for"], serde_json::json!(["xsph.average"]));
    let x = row(&rows, "legacy.av_vel", "av");
    assert_eq!((x["compared"].as_u64(), x["max_ulp"].as_u64()), (Some(400 * 40), Some(0)), "{x}");
    let prog = program_rows_of(&b, "switch_xsph_program", 40);
    assert_run_ends_as(&b, cs, "liu-book", &prog, "switch_xsph_run");
    // the ledger: every row but -sound_speed reaches the end
    let led = d.join("ledger");
    let so = blastsph_ok(&["legacy", "ledger", cs, "--legacy", bs, "--out", led.to_str().unwrap()], 0);
    let l: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(led.join("ledger.json")).unwrap()).unwrap();
    for r in l["rows"].as_array().unwrap() {
        let failed = r.get("failed").and_then(|f| f.as_str());
        if r["run"] == "-sound_speed" {
            assert!(failed.is_some_and(|f| f.contains("unstable")), "{r}");
        } else {
            assert_eq!((failed, r["steps"].as_u64()), (None, Some(40)), "{r}");
        }
    }
    assert!(so.contains("-sound_speed         did not finish: unstable"), "{so}");
    assert!(so.contains("bit for bit"), "{so}");
}

/// param.inc's `sle = 2` (h_upgrade, case `smoothing = "rate"`) with the item `h_upgrade`: h moved
/// inside the step as the book does, at 0 ULP; the shock tube with it goes unstable (the genuine
/// book code at step 13, A.7; this fixture later): blastsph stops there, says so, and equals the
/// program before.
#[test]
fn the_books_h_upgrade_is_matched_until_the_run_blows_up() {
    let d = variant_built("switch_sle2", "param.inc", |t| t.replace("parameter (sle = 0)", "parameter (sle = 2)"));
    let b = d.join("build");
    let text = std::fs::read_to_string(root().join("cases/shock_tube.toml")).unwrap();
    let case = d.join("shock_tube_sle2.toml");
    std::fs::write(&case, text.replace("smoothing = \"constant\"", "smoothing = \"rate\"")).unwrap();
    let (bs, cs, out) = (b.to_str().unwrap(), case.to_str().unwrap(), d.join("dual"));
    let so =
        blastsph_ok(&["dual", cs, "--legacy", bs, "--compat", "liu-book,h_upgrade", "--out", out.to_str().unwrap()], 3);
    assert!(so.contains("up to where it stopped); STOPPED before the end: unstable"), "{so}");
    let (r, rows) = report_rows(&out.join("dual_report.json"));
    assert_eq!(r["legacy"]["routines"]["h_upgrade"]["stands_for"], serde_json::json!(["smoothing.h_upgrade"]));
    // every step and the evaluation at t = 0 for the output
    let n = r["steps"].as_u64().unwrap();
    assert!(n >= 10, "{r}");
    let x = row(&rows, "legacy.h_upgrade", "h");
    assert_eq!((x["compared"].as_u64(), x["max_ulp"].as_u64()), (Some(400 * (n + 1)), Some(0)), "{x}");
    for (stage, fields) in MAPPED {
        for f in *fields {
            assert_eq!(row(&rows, stage, f)["max_ulp"], 0, "{stage} {f}");
        }
    }
    let prog = program_rows_of(&b, "switch_sle2_program", 10);
    assert_run_ends_as_after(&b, cs, "liu-book,h_upgrade", &prog, "switch_sle2_run", 10);
}

/// A routine that changes an argument its stage only reads (here the viscosity nudging the
/// velocity it is given): blastsph's twins leave it alone, so `dual --legacy` reports the change
/// as a divergence of its own (exit 4, the routine, the argument, the step and the particle), and
/// `run --legacy` warns once and keeps the change in the state, as the legacy program's arrays do.
#[test]
fn a_routine_that_changes_an_input_is_reported_by_the_dual_run() {
    let d = variant_built("input_write", "art_visc.f", |t| {
        t.replacen("      end\n", "      vx(1,3) = vx(1,3)*1.001d0\n      end\n", 1)
    });
    let lg = d.join("build");
    let out = d.join("dual");
    let o = dual_book(&lg, Some(3), &out);
    let se = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(4), "{se}");
    // (the third particle is at rest at step 1: its first change is at step 2)
    assert!(se.contains("legacy routine art_visc changed its input `vx` at step 2"), "{se}");
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    let r = row(&rows, "legacy.art_visc", "v (input `vx` changed)");
    assert_eq!(r["out_of_tolerance"], 2, "one value a step, steps 2 and 3: {r}");
    let fd = &r["first_divergence"];
    assert_eq!(fd["step"], 1, "{r}");
    assert!(fd["at"].as_str().unwrap().starts_with("particle 2"), "{r}");
    assert_eq!(fd["fortran"].as_f64().unwrap(), fd["rust"].as_f64().unwrap() * 1.001, "{r}");
    // the outputs themselves still agree
    assert_eq!(row(&rows, "legacy.art_visc", "acc")["max_ulp"], 0);
    let run = d.join("run");
    let o = blastsph(&[
        "run",
        "shock_tube",
        "--legacy",
        lg.to_str().unwrap(),
        "--compat",
        "liu-book",
        "--set",
        "time.end_s=2e-2",
        "--out",
        run.to_str().unwrap(),
        "--quiet",
    ]);
    let se = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{se}");
    assert_eq!(se.matches("changed its input `vx`").count(), 1, "warned once: {se}");
    assert!(se.contains("the state keeps it"), "{se}");
    // a routine called per particle (p_gas, `call = "each_particle"`) that writes its u
    let d = variant_built("input_write_each", "eos.f", |t| {
        t.replacen("      c = sqrt((gam - 1)*u)\n", "      c = sqrt((gam - 1)*u)\n      u = 1.5d0*u\n", 1)
    });
    let out = d.join("dual");
    let o = dual_book(&d.join("build"), Some(2), &out);
    assert_eq!(o.status.code(), Some(4), "{}", String::from_utf8_lossy(&o.stderr));
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    let r = row(&rows, "legacy.p_gas", "e (input `u` changed)");
    assert!(r["out_of_tolerance"].as_u64().unwrap() >= 400, "every particle's u: {r}");
    assert!(r["first_divergence"]["at"].as_str().unwrap().starts_with("particle 0"), "{r}");
}

/// A `STOP` in the legacy code (libgfortran exits with status 0 for `STOP 'text'`) ends blastsph
/// with one line naming the routine and the step, and exit status 3, in `run` and in `dual`.
#[test]
fn a_stop_in_the_legacy_code_ends_blastsph_with_status_3() {
    let d = variant_built("stop", "eos.f", |t| {
        t.replacen(
            "      p = (gam - 1)*rho*u\n",
            "      if (rho .gt. 0.5d0) stop 'p_gas: bad state'\n      p = (gam - 1)*rho*u\n",
            1,
        )
    });
    let lg = d.join("build");
    // an earlier dual run's report in the folder: it goes (the STOP leaves none of this run's)
    std::fs::create_dir_all(d.join("dual")).unwrap();
    std::fs::write(d.join("dual").join("dual_report.json"), "{\"steps\": 20}").unwrap();
    for (cmd, out) in [("run", d.join("run")), ("dual", d.join("dual"))] {
        let o = blastsph(&[cmd, "shock_tube", "--legacy", lg.to_str().unwrap(), "--out", out.to_str().unwrap()]);
        let se = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(3), "{cmd}: {se}");
        let line = se.lines().find(|l| l.starts_with("error:")).unwrap_or_else(|| panic!("{cmd}: {se}"));
        assert!(
            line.contains("legacy routine p_gas ended the process at step 1") && line.contains("(a STOP, a CALL EXIT"),
            "{cmd}: {se}"
        );
    }
    assert!(!d.join("dual").join("dual_report.json").exists(), "the earlier report is gone");
    // the run's particles.h5 was closed, not cut off by the exit: a valid file (the STOP came
    // before the first frame, so it holds no step)
    let o = blastsph(&["report", d.join("run").to_str().unwrap()]);
    let se = String::from_utf8_lossy(&o.stderr);
    assert!(se.contains("holds no step") && !se.contains("damaged"), "{se}");
    // and a summary.json says how it ended (there was none: the STOP came before the first)
    let sj: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("run").join("summary.json")).unwrap()).unwrap();
    assert_eq!(
        (&sj["status"], &sj["partial"], &sj["steps"], &sj["dim"]),
        (&"unstable".into(), &true.into(), &0.into(), &1.into()),
        "{sj}"
    );
    assert!(sj["diagnostic"].as_str().is_some_and(|d| d.contains("p_gas ended the process at step 1")), "{sj}");
}

/// A `STOP` later in a run leaves its summary.json saying how the run ended (it said "running",
/// from the run's start or its last checkpoint), and `report` reads the frames written before it.
/// The run folder is given relative to the current folder (`--out run`): the legacy call runs in
/// `DIR/work`, where that relative path named nothing, and the summary kept saying "running".
#[test]
fn a_stop_later_in_a_run_is_told_in_its_summary() {
    let d = variant_built("stop_later", "eos.f", |t| {
        t.replacen(
            "      p = (gam - 1)*rho*u\n",
            "      if (u .gt. 2.0d0 .and. u .lt. 2.45d0) stop 'p_gas: bad state'\n      p = (gam - 1)*rho*u\n",
            1,
        )
    });
    let (lg, run) = (d.join("build"), d.join("run"));
    let case = root().join("cases").join("shock_tube.toml");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_blastsph"))
        .args(["run", case.to_str().unwrap(), "--legacy", "build", "--out", "run"])
        .args(["--set", "time.output_interval_s=0.005"])
        .current_dir(&d)
        .output()
        .expect("blastsph runs");
    assert!(lg.join("build.json").is_file());
    let se = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{se}");
    let line = se.lines().find(|l| l.starts_with("error:")).unwrap_or_else(|| panic!("{se}"));
    let at = line.split("ended the process at step ").nth(1).unwrap_or_else(|| panic!("{line}"));
    let step: u64 = at.split_whitespace().next().unwrap().parse().unwrap();
    assert!(step > 1, "{line}");
    let sj: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("summary.json")).unwrap()).unwrap();
    assert_eq!(sj["status"], "unstable", "{sj}");
    assert_eq!(sj["partial"], true, "{sj}");
    let diag = sj["diagnostic"].as_str().unwrap();
    assert!(diag.contains(&format!("legacy routine p_gas ended the process at step {step} ")), "{diag}");
    // the steps completed before it (the legacy code counts from 1: its step k is blastsph's
    // k − 1 completed steps), not the start's 0
    assert_eq!(sj["steps"].as_u64(), Some(step - 1), "{sj}");
    assert!(sj["time"].as_f64().is_some_and(|t| t > 0.0), "{sj}");
    // the frames before the STOP are read
    let o = blastsph(&["report", run.to_str().unwrap()]);
    let (so, se) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success(), "{so}{se}");
}

/// A NaN sound speed from a legacy EOS shows first in its neighbours' viscosity rates; the
/// diagnostic names the non-finite value and the legacy stages that write it (it named only the
/// viscosity), and the hint points at `dual --legacy`.
#[test]
fn a_nan_from_a_legacy_routine_is_traced_to_the_routine_that_writes_it() {
    let d = variant_built("nan_c", "eos.f", |t| {
        t.replacen(
            "      c = sqrt((gam - 1)*u)\n",
            "      c = sqrt((gam - 1)*u)\n      if (rho .gt. 0.3d0 .and. rho .lt. 0.99d0) c = sqrt(-u)\n",
            1,
        )
    });
    let lg = d.join("build");
    let o =
        blastsph(&["run", "shock_tube", "--legacy", lg.to_str().unwrap(), "--out", d.join("run").to_str().unwrap()]);
    let se = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{se}");
    let line = se.lines().find(|l| l.starts_with("error:")).unwrap_or_else(|| panic!("{se}"));
    assert!(line.contains("non-finite rate") && line.contains("c is NaN already (written by legacy."), "{line}");
    assert!(line.contains("`blastsph dual --legacy` names the first one"), "{line}");
}

/// A set-up routine whose particles are not the ones the case describes is said once (the run
/// takes the routine's; only maxn was checked): another count, or the same count in another
/// state (mass, volume, energy, momentum or centre of a material).
#[test]
fn a_setup_routine_of_another_particle_count_is_warned_of() {
    let d = scratch("setup_count");
    let lg = shared().to_str().unwrap();
    let run = |out: &str, extra: &[&str]| {
        let mut a = vec!["run", "shock_tube", "--legacy", lg, "--compat", "liu-book", "--quiet", "--out", out];
        a.extend_from_slice(extra);
        blastsph(&a)
    };
    let same = run(d.join("same").to_str().unwrap(), &[]);
    assert_eq!(same.status.code(), Some(0), "{}", String::from_utf8_lossy(&same.stderr));
    assert!(!String::from_utf8_lossy(&same.stderr).contains("particles, the case describes"));
    let other = run(
        d.join("other").to_str().unwrap(),
        &["--set", "region.left.count=[300]", "--set", "region.left.spacing_m=0.002"],
    );
    let se = String::from_utf8_lossy(&other.stderr);
    assert_eq!(other.status.code(), Some(0), "{se}");
    assert!(se.contains("warning: legacy input made 400 particles, the case describes 380"), "{se}");
    // the same count in another state: the case's right state is Sod's ρ = 0.125 (the routine
    // keeps 0.25), or its e is 2.0 (the routine's 1.795): the integrals name what differs
    assert!(!String::from_utf8_lossy(&same.stderr).contains("not the state the case describes"));
    for (set, what) in
        [("region.right.rho_kgm3=0.125", "gas: volume Σm/ρ"), ("region.right.e_jkg=2.0", "gas: internal energy Σme")]
    {
        let o = run(d.join(set).to_str().unwrap(), &["--set", set]);
        let se = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(0), "{se}");
        let line =
            se.lines().find(|l| l.contains("not the state the case describes")).unwrap_or_else(|| panic!("{se}"));
        assert!(line.starts_with("warning: legacy input's particles") && line.contains(what), "{line}");
        assert!(!line.contains("particles against the case's"), "{line}");
    }
}
