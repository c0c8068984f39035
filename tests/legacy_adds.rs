//! Legacy routines that add into their outputs without zeroing them first
//! (`dvxdt(d,i) = dvxdt(d,i) + ...`): the manifest key `adds` makes the shim zero those arrays
//! before each call (docs/reference/legacy.md, the manifest table).

mod legacy_kit;
use legacy_kit::*;

/// The fixture's art_visc without its zeroing loop: it adds into dvxdt and dedt.
fn adding(text: &str) -> String {
    let zeroing = "      do 10 i = 1, ntotal\n        do 5 d = 1, dim\n          dvxdt(d,i) = 0.e0\n    5   continue\n        dedt(i) = 0.e0\n   10 continue\n";
    assert!(text.contains(zeroing), "art_visc's zeroing loop");
    text.replace(zeroing, "")
}

/// The wrapper a user wrote before the key: it zeroes rows 1..ntotal and calls art_visc.
const WRAPPER: &str = "      subroutine art_visc_term(ntotal, hsml, mass, x, vx, niac, rho,
     &                         c, pair_i, pair_j, w, dwdx, dvxdt, dedt)
      implicit none
      include 'param.inc'
      integer ntotal, niac, pair_i(max_interaction),
     &        pair_j(max_interaction), i, d
      double precision hsml(maxn), mass(maxn), x(dim,maxn),
     &        vx(dim,maxn), rho(maxn), c(maxn), w(max_interaction),
     &        dwdx(dim,max_interaction), dvxdt(dim,maxn), dedt(maxn)
      do 10 i = 1, ntotal
        dedt(i) = 0.d0
        do 5 d = 1, dim
          dvxdt(d,i) = 0.d0
    5   continue
   10 continue
      call art_visc(ntotal, hsml, mass, x, vx, niac, rho, c, pair_i,
     &              pair_j, w, dwdx, dvxdt, dedt)
      end
";

/// art_visc's arguments as the fixture's manifest writes them.
const AV_ARGS: &str = "\"w\", \"dwdx\",\n        \"dvxdt\", \"dedt\"]";

/// The fixture with the adding art_visc, its manifest edited by `edit`, built into `DIR/build`.
fn adding_variant(name: &str, edit: impl Fn(&str) -> String) -> PathBuf {
    let d = variant(name, |m| {
        assert!(m.contains(AV_ARGS), "art_visc's entry");
        edit(m)
    });
    let f = d.join("art_visc.f");
    std::fs::write(&f, adding(&std::fs::read_to_string(&f).unwrap())).unwrap();
    d
}

/// The manifest with `line` after art_visc's arguments.
fn with_key(m: &str, line: &str) -> String {
    m.replacen(AV_ARGS, &format!("{AV_ARGS}\n{line}"), 1)
}

/// The dual run of build `lg` over 3 steps with the book's profile: its exit status and the rows
/// of art_visc (or of the routine `stage`).
fn art_visc_rows(lg: &Path, out: &Path, stage: &str) -> (Option<i32>, Vec<serde_json::Value>) {
    let o = dual_book(lg, Some(3), out);
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    let av: Vec<serde_json::Value> = rows.into_iter().filter(|r| r["stage"] == stage).collect();
    assert!(!av.is_empty(), "{stage} was compared: {}", String::from_utf8_lossy(&o.stdout));
    (o.status.code(), av)
}

/// Without the key, an art_visc that adds into its term adds to the term of the step before:
/// the dual run finds it at the second step. With `adds = ["dvxdt", "dedt"]` the shim zeroes
/// the term before each call and the dual run is at 0 ULP; `run --legacy` then ends bit for bit
/// where the same code ends with the wrapper that zeroes the term and calls art_visc.
#[test]
fn a_routine_that_adds_into_its_term_is_zeroed_before_each_call_by_the_key_adds() {
    // without the key: the term of step 1 stays in the sum of step 2
    let bare = adding_variant("adds_bare", |m| m.to_string());
    build(&bare.join("legacy.toml"), &bare.join("build")).expect("the adding variant builds");
    let (code, rows) = art_visc_rows(&bare.join("build"), &bare.join("dual"), "legacy.art_visc");
    assert_eq!(code, Some(4), "{rows:?}");
    let acc = rows.iter().find(|r| r["field"] == "acc").expect("acc row");
    assert!(acc["out_of_tolerance"].as_u64().unwrap() > 0, "{acc}");
    assert_eq!(acc["first_divergence"]["step"], 2, "{acc}");

    // with the key: 0 ULP in the acceleration and the heating
    let keyed = adding_variant("adds_keyed", |m| with_key(m, "adds = [\"dvxdt\", \"dedt\"]"));
    let info = build(&keyed.join("legacy.toml"), &keyed.join("build")).expect("the keyed variant builds");
    let av = info.routines.iter().find(|r| r.name == "art_visc").unwrap();
    assert_eq!(av.adds, ["dvxdt", "dedt"], "build.json names the arrays");
    let (code, rows) = art_visc_rows(&keyed.join("build"), &keyed.join("dual"), "legacy.art_visc");
    assert_eq!(code, Some(0), "{rows:?}");
    for f in ["acc", "dde"] {
        let r = rows.iter().find(|r| r["field"] == f).unwrap_or_else(|| panic!("no {f} row: {rows:?}"));
        assert!(r["compared"].as_u64().unwrap() > 0, "{r}");
        assert_eq!((r["max_ulp"].as_u64(), r["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{f}: {r}");
    }

    // host mode: the program's single_step zeroes the array it passes (ardvxdt, avdudt), so
    // what the routine added, after less before, is its sum from 0: 0 ULP at every call
    let host = keyed.join("host");
    let kb = keyed.join("build");
    let o = host_run(&kb, &host, &[]);
    let so = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{so}{}", String::from_utf8_lossy(&o.stderr));
    assert!(so.contains("adds into dvxdt, dedt: compared as the array after the call less before it"), "{so}");
    let r: serde_json::Value = serde_json::from_slice(&std::fs::read(host.join("host_report.json")).unwrap()).unwrap();
    let m = &r["routines"]["art_visc"];
    let calls = m["calls"].as_u64().unwrap();
    assert!(calls > 0 && m["compared_calls"].as_u64() == Some(calls), "{m}");
    for f in ["acc", "dde"] {
        let row = m["rows"].as_array().unwrap().iter().find(|x| x["field"] == f).unwrap_or_else(|| panic!("{f}: {m}"));
        assert_eq!((row["max_ulp"].as_u64(), row["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{row}");
    }

    // on the twins' outputs: the program's array (0) plus the twin's term, its own end
    let host_rust = keyed.join("host_rust");
    let o = host_run(&kb, &host_rust, &["--rust-outputs"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(bits(&state_of(&host_rust.join("work"))), bits(program_final_state()));
    // the fixture's program zeroes in art_visc what this one zeroes in the shim: the same end
    assert_run_ends_as_the_program(&kb, "adds_keyed_run");

    // the wrapper of a user who zeroes the term in a routine of their own
    let wrapped = adding_variant("adds_wrapper", |m| m.replacen("name = \"art_visc\"", "name = \"art_visc_term\"", 1));
    std::fs::write(wrapped.join("art_visc_term.f"), WRAPPER).unwrap();
    build(&wrapped.join("legacy.toml"), &wrapped.join("build")).expect("the wrapper variant builds");
    let names = ["x", "vx", "rho", "p", "e", "h"];
    let frames: Vec<Vec<Vec<f64>>> = [&keyed, &wrapped]
        .iter()
        .map(|d| {
            let out = d.join("run");
            let lg = d.join("build");
            blastsph_ok(
                &[
                    "run",
                    "shock_tube",
                    "--legacy",
                    lg.to_str().unwrap(),
                    "--compat",
                    "liu-book",
                    "--set",
                    "time.end_s=0.2",
                    "--out",
                    out.to_str().unwrap(),
                    "--quiet",
                ],
                0,
            );
            last_frame(&out, &names)
        })
        .collect();
    for (k, n) in names.iter().enumerate() {
        assert_eq!(frames[0][k].len(), 400, "{n}");
        let same = frames[0][k].iter().zip(&frames[1][k]).all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same, "{n}: run --legacy with adds differs from the wrapper's run");
    }
}

/// The key names arrays the routine writes: a name it does not take, a scalar, an input, a
/// total, and the key on a set-up routine are each refused in one line (exit status 2).
#[test]
fn adds_names_only_arrays_the_routine_writes() {
    for (name, line, needles) in [
        ("adds_not_arg", "adds = [\"drhodt\"]", &["art_visc", "adds", "\"drhodt\" is not among"][..]),
        ("adds_scalar", "adds = [\"ntotal\"]", &["adds", "\"ntotal\" is one value"][..]),
        ("adds_input", "adds = [\"rho\"]", &["adds", "reads \"rho\""][..]),
        ("adds_unknown", "adds = [\"dvdt\"]", &["adds", "unknown name \"dvdt\""][..]),
        ("adds_twice", "adds = [\"dedt\", \"DEDT\"]", &["adds", "given twice"][..]),
    ] {
        let d = adding_variant(name, |m| with_key(m, line));
        refused(&d, needles);
    }
    // the total acceleration: blastsph sums the terms itself
    let total = "\"w\", \"dwdx\",\n        \"dvx\", \"dedt\"]\nadds = [\"dvx\"]";
    let d = adding_variant("adds_total", |m| m.replacen(AV_ARGS, total, 1));
    refused(&d, &["adds", "\"dvx\" is the total", "\"dvxdt\""]);
    // a set-up routine is not called at each step
    let d = variant("adds_setup", |m| {
        let old = "\"itype\", \"hsml\", \"ntotal\"]";
        assert!(m.contains(old), "input's entry");
        m.replacen(old, &format!("{old}\nadds = [\"x\"]"), 1)
    });
    refused(&d, &["routine[9] (input).adds", "module \"setup\""]);
}

fn bits(rows: &[Vec<f64>]) -> Vec<Vec<u64>> {
    rows.iter().map(|r| r.iter().map(|v| v.to_bits()).collect()).collect()
}

/// The final state a program wrote into `work` (17 digits), as numbers.
fn state_of(work: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(work.join("final_state.dat")).expect("final_state.dat");
    text.lines().skip(1).map(|l| l.split_whitespace().map(|v| v.parse::<f64>().unwrap()).collect()).collect()
}

/// The adding art_visc with every vector declared `(mxd, ...)`, mxd = 3 in the 1D param.inc:
/// the shim zeroes each particle's 3 declared values, and the dual run stays at 0 ULP; `run
/// --legacy` ends in the fixture program's state bit for bit.
#[test]
fn adds_zeroes_whole_rows_of_an_array_declared_with_a_leading_extent_above_dim() {
    let d = adding_variant("adds_mxd", |m| with_key(m, "adds = [\"dvxdt\", \"dedt\"]"));
    assert!(with_mxd_layout(&d) >= 8);
    let lg = d.join("build");
    let info = build(&d.join("legacy.toml"), &lg).expect("the layout builds");
    let av = info.routines.iter().find(|r| r.name == "art_visc").unwrap();
    let dv = av.args.iter().find(|a| a.name == "dvxdt").unwrap();
    assert_eq!(dv.lead, Some(3), "{dv:?}");
    let shims = std::fs::read_to_string(lg.join("obj/blastsph_shims.f90")).unwrap();
    assert!(shims.contains("v13(1:(ncopy/bs_dim)*3) = 0.0d0"), "the rows zeroed whole");
    let (code, rows) = art_visc_rows(&lg, &d.join("dual"), "legacy.art_visc");
    assert_eq!(code, Some(0), "{rows:?}");
    for f in ["acc", "dde"] {
        let r = rows.iter().find(|r| r["field"] == f).unwrap_or_else(|| panic!("no {f} row: {rows:?}"));
        assert_eq!((r["max_ulp"].as_u64(), r["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{f}: {r}");
    }
    assert_run_ends_as_the_program(&lg, "adds_mxd_run");
}

/// A program that has art_visc add into the acceleration int_force filled (its `indvxdt`):
/// host mode compares what the routine added, after less before, with the twin's term from 0.
/// That is not bit for bit (the program's sum rounds otherwise): the table says so, its last
/// line marks the routine, and the values compared are the viscosity's, not the total's.
#[test]
fn host_mode_compares_what_a_routine_added_onto_values_the_array_held() {
    let d = adding_variant("adds_onto", |m| with_key(m, "adds = [\"dvxdt\", \"dedt\"]"));
    let f = d.join("single_step.f");
    let text = std::fs::read_to_string(&f).unwrap();
    let new = text.replacen("     &               ardvxdt, avdudt)", "     &               indvxdt, avdudt)", 1);
    assert_ne!(new, text, "single_step's call of art_visc");
    std::fs::write(&f, new).unwrap();
    let lg = d.join("build");
    build(&d.join("legacy.toml"), &lg).expect("the variant builds");
    let host = d.join("host");
    let o = host_run(&lg, &host, &[]);
    let so = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(4), "{so}{}", String::from_utf8_lossy(&o.stderr));
    assert!(so.contains("DIVERGING: art_visc (adds: after less before)"), "{so}");
    assert!(so.contains("adds into dvxdt, dedt: compared as the array after the call less before it"), "{so}");
    let r: serde_json::Value = serde_json::from_slice(&std::fs::read(host.join("host_report.json")).unwrap()).unwrap();
    let rows = r["routines"]["art_visc"]["rows"].as_array().unwrap().clone();
    let dde = rows.iter().find(|x| x["field"] == "dde").unwrap();
    assert_eq!(dde["max_ulp"].as_u64(), Some(0), "avdudt is zeroed by the program: {dde}");
    let acc = rows.iter().find(|x| x["field"] == "acc").unwrap();
    assert!(acc["out_of_tolerance"].as_u64().unwrap() > 0, "{acc}");
    // the first value that differs is the viscosity's own (not int_force's term plus it), in its
    // last bits
    let (l, rs) =
        (acc["first_divergence"]["fortran"].as_f64().unwrap(), acc["first_divergence"]["rust"].as_f64().unwrap());
    assert!(l != rs && (l - rs).abs() < 1e-12 * rs.abs(), "{acc}");
}

/// `blastsph legacy host shock_tube --legacy BUILD --compat liu-book [EXTRA] --out OUT`, the
/// program's input `40` then `0`.
fn host_run(build: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["legacy", "host", "shock_tube", "--legacy", build.to_str().unwrap(), "--compat", "liu-book"];
    args.extend_from_slice(extra);
    args.extend(["--out", out.to_str().unwrap()]);
    blastsph_40_steps(&args)
}
