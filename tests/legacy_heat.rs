//! A legacy code with the book's artificial heat (param.inc's `heat_artificial`, the routine
//! `art_heat`): mapped onto the conductivity module, it stands for `conductivity.noh`, the dual run
//! compares the two at 0 ULP with the book's profile, and `run --legacy` ends in the state of the
//! code's own program, bit for bit.

mod legacy_kit;
use legacy_kit::*;

/// The manifest's entry of `art_heat`.
const ENTRY: &str = "
[[routine]]
name = \"art_heat\"
module = \"conductivity\"
args = [\"ntotal\", \"hsml\", \"mass\", \"x\", \"vx\", \"niac\", \"rho\", \"u\", \"c\", \"pair_i\", \"pair_j\", \"w\", \"dwdx\",
        \"dedt\"]
";

/// The fixture with `heat_artificial = .true.` and `art_heat` mapped, built into DIR/build;
/// returns DIR.
fn heat_variant(name: &str) -> PathBuf {
    let d = variant(name, |m| format!("{m}{ENTRY}"));
    let f = d.join("param.inc");
    let text = std::fs::read_to_string(&f).unwrap();
    let (from, to) = ("parameter (heat_artificial   = .false.)", "parameter (heat_artificial   = .true.)");
    assert!(text.contains(from));
    std::fs::write(&f, text.replace(from, to)).unwrap();
    build(&d.join("legacy.toml"), &d.join("build")).expect("the artificial-heat variant builds");
    d
}

/// cases/shock_tube.toml with the artificial heat (`[conductivity] kind = "noh"`), written into
/// `dir`.
fn heat_case(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(root().join("cases/shock_tube.toml")).unwrap();
    let p = dir.join("shock_tube_heat.toml");
    std::fs::write(&p, format!("{text}\n[conductivity]\nkind = \"noh\"\n")).unwrap();
    p
}

#[test]
fn the_books_artificial_heat_is_compared_at_zero_ulp_and_run_as_its_program_runs() {
    let d = heat_variant("heat");
    let (b, case) = (d.join("build"), heat_case(&d));
    let (bs, cs) = (b.to_str().unwrap(), case.to_str().unwrap());
    // check: art_heat stands for the twin, with the book's single-precision constants
    let so = blastsph_ok(&["check", cs, "--legacy", bs, "--compat", "liu-book"], 0);
    assert!(so.contains("stands for conductivity.noh"), "{so}");
    assert!(so.contains(&format!("phi2 = {}", 0.01f32 as f64)), "{so}");
    // dual: every mapped routine, art_heat included, at 0 ULP over the 40 steps
    let out = d.join("dual");
    let so = blastsph_ok(&["dual", cs, "--legacy", bs, "--compat", "liu-book", "--out", out.to_str().unwrap()], 0);
    assert!(so.contains("40 steps compared; every compared stage within tolerance"), "{so}");
    let (r, rows) = report_rows(&out.join("dual_report.json"));
    assert_eq!(r["legacy"]["routines"]["art_heat"]["stands_for"], serde_json::json!(["conductivity.noh"]));
    let x = row(&rows, "legacy.art_heat", "dde");
    assert!(x["compared"].as_u64().unwrap() > 0, "{x}");
    assert_eq!((x["max_ulp"].as_u64(), x["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{x}");
    for (stage, fields) in MAPPED {
        for f in *fields {
            assert_eq!(row(&rows, stage, f)["max_ulp"], 0, "{stage} {f}");
        }
    }
    // the heat changes the program's end state, and run --legacy ends in it
    let prog = program_rows_of(&b, "heat_program", 40);
    let plain = program_final_state();
    let moved = (0..prog.len()).filter(|&i| prog[i][7] != plain[i][7]).count();
    assert!(moved > 0, "the artificial heat changes no particle's energy");
    assert_run_ends_as(&b, cs, "liu-book", &prog, "heat_run");
}

/// The artificial heat in axisymmetric geometry, g1 without its kind, and α_u with it: each
/// refused in one line, exit status 2.
#[test]
fn misplaced_artificial_heat_keys_are_refused_in_one_line() {
    for (case, set, needle) in [
        ("cases/underwater_tnt_rz.toml", "conductivity.kind=\"noh\"", "axisymmetric"),
        ("cases/shock_tube.toml", "conductivity.g1=0.2", "conductivity.g1"),
        ("cases/shock_tube.toml", "conductivity.kind=\"noh\"\nconductivity.alpha=1.0", "conductivity.alpha"),
    ] {
        let mut args = vec!["check", case];
        for s in set.split('\n') {
            args.extend(["--set", s]);
        }
        let o = blastsph(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{set}: {err}");
        assert!(err.contains(needle) && err.lines().count() == 1, "{set}: {err}");
    }
}
