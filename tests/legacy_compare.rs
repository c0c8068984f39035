//! `blastsph legacy compare`: a run's particles.h5 against the files the fixture's own program
//! writes (its `output`, mapped as `module = "output"`), column by column.

mod legacy_kit;
use legacy_kit::*;

/// The manifest's entry of the fixture's output routine.
const OUTPUT: &str = "
[[routine]]
name = \"output\"
module = \"output\"
args = [\"x\", \"vx\", \"mass\", \"rho\", \"p\", \"u\", \"c\", \"itype\", \"hsml\", \"ntotal\"]
";

/// The fixture with its output routine mapped, built; its program run for 40 steps (its
/// final_state.dat in `prog`); `run --legacy --compat liu-book` of the shock tube to 40 steps.
struct Setup {
    build: PathBuf,
    prog: PathBuf,
    run: PathBuf,
}

fn setup() -> &'static Setup {
    static S: OnceLock<Setup> = OnceLock::new();
    S.get_or_init(|| {
        let d = variant("compare_fixture", |m| format!("{m}{OUTPUT}"));
        let build = d.join("build");
        blastsph::migration::build(&d.join("legacy.toml"), &build).expect("the fixture builds");
        let rows = program_rows_of(&build, "compare_program", 40);
        assert_eq!(rows.len(), 400);
        let prog = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("migration/compare_program");
        let run = d.join("run");
        let b = build.to_str().unwrap();
        let args = ["run", "shock_tube", "--legacy", b, "--compat", "liu-book", "--set", "time.end_s=0.2"];
        blastsph_ok(&[&args[..], &["--out", run.to_str().unwrap(), "--quiet"]].concat(), 0);
        Setup { build, prog, run }
    })
}

/// `blastsph legacy compare RUN --legacy BUILD --program-out PROG --out OUT`: (status, stdout,
/// stderr).
fn compare(run: &Path, build: &Path, prog: &Path, out: &Path) -> (Option<i32>, String, String) {
    let o = blastsph(&[
        "legacy",
        "compare",
        run.to_str().unwrap(),
        "--legacy",
        build.to_str().unwrap(),
        "--program-out",
        prog.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    (o.status.code(), String::from_utf8_lossy(&o.stdout).into_owned(), String::from_utf8_lossy(&o.stderr).into_owned())
}

fn columns(out: &Path) -> (serde_json::Value, Vec<serde_json::Value>) {
    let r: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("compare.json")).unwrap()).unwrap();
    let cols = r["files"][0]["columns"].as_array().unwrap().clone();
    (r, cols)
}

fn col<'a>(cols: &'a [serde_json::Value], field: &str) -> &'a serde_json::Value {
    cols.iter().find(|c| c["field"] == field).unwrap_or_else(|| panic!("no column named {field}: {cols:?}"))
}

#[test]
fn run_legacy_and_the_programs_own_output_agree_in_every_column() {
    let s = setup();
    let out = scratch("compare_equal");
    let (code, so, se) = compare(&s.run, &s.build, &s.prog, &out);
    assert_eq!(code, Some(0), "{so}{se}");
    assert!(so.contains("(Step#10, t = "), "the frame compared is named: {so}");
    assert!(so.contains("equal at the 17 digits written: bit for bit"), "{so}");
    let (r, cols) = columns(&out);
    assert_eq!(r["files"][0]["file"], "final_state.dat");
    assert_eq!(r["equal"], true);
    assert_eq!(r["digits"], 17);
    // the probes name the columns as output.f writes them: number, type, x, vx, mass, rho, p, u, hsml
    let named: Vec<&str> = cols.iter().map(|c| c["field"].as_str().unwrap()).collect();
    assert_eq!(named, ["", "itype", "x", "vx", "mass", "rho", "p", "u", "hsml"]);
    for c in &cols {
        assert_eq!(c["status"], "compared", "{c}");
        assert!(c["compared"].as_u64().unwrap() >= 400, "{c}");
        assert_eq!(c["differing"], 0, "{c}");
    }
}

#[test]
fn a_run_of_blastsphs_own_twins_parts_from_the_program_and_is_named() {
    let s = setup();
    let plain = scratch("compare_plain_run");
    blastsph_ok(&["run", "shock_tube", "--set", "time.end_s=0.2", "--out", plain.to_str().unwrap(), "--quiet"], 0);
    let out = scratch("compare_plain");
    let (code, so, se) = compare(&plain, &s.build, &s.prog, &out);
    assert_eq!(code, Some(0), "{so}{se}");
    assert!(so.contains("they part: first at final_state.dat col "), "{so}");
    let (r, cols) = columns(&out);
    assert_eq!(r["equal"], false);
    // the sound speed alone moves rho by 1e-3 and more (tests/legacy_run.rs)
    let rho = col(&cols, "rho");
    assert!(rho["max_abs"].as_f64().unwrap() > 1e-3, "{rho}");
    assert!(rho["first_differing"]["particle"].as_u64().is_some(), "{rho}");
}

#[test]
fn one_changed_value_in_the_programs_file_is_found_at_its_particle() {
    let s = setup();
    let prog = scratch("compare_perturbed_program");
    let text = std::fs::read_to_string(s.prog.join("final_state.dat")).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    // line 8 holds particle 7; its sixth value is rho
    let mut t: Vec<String> = lines[7].split_whitespace().map(String::from).collect();
    assert_eq!(t[0], "7");
    let rho: f64 = t[5].parse().unwrap();
    t[5] = format!("{:.16e}", rho * (1.0 + 1e-12));
    lines[7] = t.join(" ");
    std::fs::write(prog.join("final_state.dat"), lines.join("\n") + "\n").unwrap();
    let out = scratch("compare_perturbed");
    let (code, so, se) = compare(&s.run, &s.build, &prog, &out);
    assert_eq!(code, Some(0), "{so}{se}");
    assert!(so.contains("they part: first at final_state.dat col 6 (rho), particle 7"), "{so}");
    let (_, cols) = columns(&out);
    let c = col(&cols, "rho");
    assert_eq!((c["differing"].as_u64(), c["first_differing"]["particle"].as_u64()), (Some(1), Some(7)), "{c}");
    assert!((c["max_rel"].as_f64().unwrap() - 1e-12).abs() < 1e-13, "{c}");
    for other in ["x", "vx", "p", "u"] {
        assert_eq!(col(&cols, other)["differing"], 0, "{other}");
    }
}

/// `legacy compare` that must end with exit status 2 and one line holding each of `needles`.
fn refused(run: &Path, build: &Path, prog: &Path, name: &str, needles: &[&str]) {
    let (code, so, se) = compare(run, build, prog, &scratch(name));
    assert_eq!(code, Some(2), "{so}{se}");
    assert_eq!(se.lines().count(), 1, "one line: {se}");
    assert!(!se.contains("panicked"), "{se}");
    for n in needles {
        assert!(se.contains(n), "the error must name `{n}`: {se}");
    }
}

#[test]
fn bad_input_is_one_line_and_exit_status_2() {
    let s = setup();
    // a build without an output routine: says to map one
    refused(&s.run, shared(), &s.prog, "compare_no_output", &["no output routine", "module = \"output\""]);
    // no such program folder, no run folder
    refused(&s.run, &s.build, &s.run.join("nosuch"), "compare_no_prog", &["--program-out", "nosuch"]);
    refused(&s.prog, &s.build, &s.prog, "compare_no_run", &["case.toml"]);
    // the program's file with a particle less
    let text = std::fs::read_to_string(s.prog.join("final_state.dat")).unwrap();
    let short = scratch("compare_short_program");
    let lines: Vec<&str> = text.lines().collect();
    std::fs::write(short.join("final_state.dat"), lines[..lines.len() - 1].join("\n")).unwrap();
    refused(&s.run, &s.build, &short, "compare_short", &["final_state.dat", "400 lines", "401"]);
    // a token that is no number: the file, line and token
    let bad = scratch("compare_bad_token");
    std::fs::write(bad.join("final_state.dat"), text.replacen("\n      3 ", "\n      3x ", 1)).unwrap();
    refused(&s.run, &s.build, &bad, "compare_bad", &["final_state.dat", "line 4", "`3x`"]);
    // a frame the run does not have
    let o = blastsph(&[
        "legacy",
        "compare",
        s.run.to_str().unwrap(),
        "--legacy",
        s.build.to_str().unwrap(),
        "--program-out",
        s.prog.to_str().unwrap(),
        "--step",
        "99",
        "--out",
        scratch("compare_step").to_str().unwrap(),
    ]);
    let se = String::from_utf8_lossy(&o.stderr);
    assert_eq!((o.status.code(), se.lines().count()), (Some(2), 1), "{se}");
    assert!(se.contains("--step 99") && se.contains("Step#0 to Step#10"), "{se}");
    // a missing program file
    refused(&s.run, &s.build, &scratch("compare_empty_program"), "compare_missing", &["no final_state.dat"]);
}

/// The fixture with `tests/legacy_extra/FILE` in place of its output.f, built into `NAME/build`;
/// its program run for 40 steps in `NAME/prog/work` (with `NAME/prog/data` beside it); `run
/// --legacy --compat liu-book` of the shock tube to 0.2 s in `NAME/run`: (build, prog, run).
fn output_variant(name: &str, file: &str) -> (PathBuf, PathBuf, PathBuf) {
    let d = variant(name, |m| format!("{m}{OUTPUT}"));
    std::fs::remove_file(d.join("output.f")).unwrap();
    std::fs::copy(root().join("tests/legacy_extra").join(file), d.join(file)).unwrap();
    let build = d.join("build");
    blastsph::migration::build(&d.join("legacy.toml"), &build).expect("the output variant builds");
    let prog = d.join("prog");
    std::fs::create_dir_all(prog.join("work")).unwrap();
    std::fs::create_dir_all(prog.join("data")).unwrap();
    let mut child = Command::new(build.join("program"))
        .current_dir(prog.join("work"))
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .spawn()
        .expect("the program starts");
    {
        use std::io::Write;
        child.stdin.take().unwrap().write_all(b"40\n0\n").unwrap();
    }
    assert!(child.wait().unwrap().success());
    let run = d.join("run");
    let b = build.to_str().unwrap();
    let args = ["run", "shock_tube", "--legacy", b, "--compat", "liu-book", "--set", "time.end_s=0.2"];
    blastsph_ok(&[&args[..], &["--out", run.to_str().unwrap(), "--quiet"]].concat(), 0);
    (build, prog, run)
}

#[test]
fn the_books_three_files_at_eight_digits_are_equal_at_the_digits_written() {
    // output_book.f: f_xv.dat, f_state.dat and f_other.dat in ../data, written with e14.8
    let (build, prog, run) = output_variant("compare_book_fixture", "output_book.f");
    let out = scratch("compare_book");
    let (code, so, se) = compare(&run, &build, &prog.join("data"), &out);
    assert_eq!(code, Some(0), "{so}{se}");
    assert!(so.contains("equal at the 8 digits written"), "{so}");
    let r: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("compare.json")).unwrap()).unwrap();
    assert_eq!(r["digits"], 8);
    let files = r["files"].as_array().unwrap();
    let fields = |name: &str| -> Vec<(String, String)> {
        let f = files.iter().find(|f| f["file"] == format!("../data/{name}")).unwrap_or_else(|| panic!("{name}: {r}"));
        f["columns"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| (c["field"].as_str().unwrap().to_string(), c["status"].as_str().unwrap().to_string()))
            .collect()
    };
    let named = |name: &str| fields(name).into_iter().map(|(f, _)| f).collect::<Vec<_>>();
    assert_eq!(named("f_xv.dat"), ["", "x", "vx"]);
    assert_eq!(named("f_state.dat"), ["", "mass", "rho", "p", "u", "c"]);
    assert_eq!(named("f_other.dat"), ["", "itype", "hsml"]);
    // the sound speed is not in particles.h5: its column is named and left out
    assert_eq!(fields("f_state.dat")[5].1, "not in particles.h5");
    assert!(so.contains("not in particles.h5"), "{so}");
}

#[test]
fn a_tecplot_header_before_the_numbers_is_left_out() {
    let s = setup();
    let prog = scratch("compare_tecplot_program");
    let text = std::fs::read_to_string(s.prog.join("final_state.dat")).unwrap();
    let head = "TITLE=\"shock tube\"\nVARIABLES=\"n\",\"type\",\"x\",\"vx\",\"mass\",\"rho\",\"p\",\"u\",\"hsml\"\nZONE I=400, F=POINT\n";
    std::fs::write(prog.join("final_state.dat"), format!("{head}{text}")).unwrap();
    let out = scratch("compare_tecplot");
    let (code, so, se) = compare(&s.run, &s.build, &prog, &out);
    assert_eq!(code, Some(0), "{so}{se}");
    assert!(so.contains("equal at the 17 digits written: bit for bit"), "{so}");
}

#[test]
fn a_failed_compare_leaves_nothing_that_refuses_the_next() {
    let s = setup();
    let text = std::fs::read_to_string(s.prog.join("final_state.dat")).unwrap();
    let bad = scratch("compare_retry_program");
    std::fs::write(bad.join("final_state.dat"), text.replacen("\n      3 ", "\n      3x ", 1)).unwrap();
    let out = scratch("compare_retry").join("out");
    for _ in 0..2 {
        let (code, so, se) = compare(&s.run, &s.build, &bad, &out);
        assert_eq!(code, Some(2), "{so}{se}");
        assert!(se.contains("`3x` is not a number"), "{se}");
        assert!(!out.exists(), "a failed compare left {}", out.display());
    }
    let (code, so, se) = compare(&s.run, &s.build, &s.prog, &out);
    assert_eq!(code, Some(0), "{so}{se}");
}

#[test]
fn files_written_beside_the_program_and_in_data_are_found_from_its_working_folder() {
    // output_two_dirs.f: xv.dat in ../data, state.dat beside the program
    let (build, prog, run) = output_variant("compare_two_dirs_fixture", "output_two_dirs.f");
    assert!(prog.join("data/xv.dat").is_file() && prog.join("work/state.dat").is_file());
    let out = scratch("compare_two_dirs");
    let (code, so, se) = compare(&run, &build, &prog.join("work"), &out);
    assert_eq!(code, Some(0), "{so}{se}");
    assert!(so.contains("equal at the 8 digits written"), "{so}");
    let r: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("compare.json")).unwrap()).unwrap();
    let files: Vec<&str> = r["files"].as_array().unwrap().iter().map(|f| f["file"].as_str().unwrap()).collect();
    assert_eq!(files, ["../data/xv.dat", "state.dat"]);
    // the folder of ../data alone lacks state.dat: one line, exit status 2
    let (code, so, se) = compare(&run, &build, &prog.join("data"), &scratch("compare_two_dirs_data"));
    assert_eq!(code, Some(2), "{so}{se}");
    assert!(se.contains("no state.dat") && se.lines().count() == 1, "{se}");
}

/// A binary dump beside a text file (output_dump.f): the dump has no text columns, so it is
/// listed as not compared, in the text and in compare.json, and the verdict is the text file's.
#[test]
fn an_unformatted_dump_is_named_as_not_compared() {
    let (build, prog, run) = output_variant("compare_dump_fixture", "output_dump.f");
    let out = scratch("compare_dump");
    let (code, so, se) = compare(&run, &build, &prog.join("work"), &out);
    assert_eq!(code, Some(0), "{so}{se}");
    assert!(so.contains("equal at the 8 digits written"), "{so}");
    let line = so.lines().find(|l| l.starts_with("dump.dat")).unwrap_or_else(|| panic!("no dump.dat line: {so}"));
    assert!(line.contains("not compared") && line.contains("no text columns"), "{line}");
    let r: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("compare.json")).unwrap()).unwrap();
    let dump = r["files"].as_array().unwrap().iter().find(|f| f["file"] == "dump.dat").expect("dump.dat listed");
    assert_eq!(dump["status"], "not compared: no text columns", "{dump}");
}
