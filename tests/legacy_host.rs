//! Host mode (`blastsph legacy host`, docs/howto/migrate.md): the fixture's own program runs
//! as written, its mapped routines compared against their Rust twins at every call.

mod legacy_kit;
use legacy_kit::*;

/// `blastsph legacy host shock_tube --legacy BUILD --compat liu-book --out OUT` (with
/// `--rust-outputs` when `rust`), the program's input `40` then `0` on stdin: (status, stdout,
/// stderr).
fn host(build: &Path, out: &Path, rust: bool) -> (Option<i32>, String, String) {
    let _ = std::fs::remove_dir_all(out);
    let mut args = vec![
        "legacy",
        "host",
        "shock_tube",
        "--legacy",
        build.to_str().unwrap(),
        "--compat",
        "liu-book",
        "--out",
        out.to_str().unwrap(),
    ];
    if rust {
        args.push("--rust-outputs");
    }
    let o = blastsph_40_steps(&args);
    (o.status.code(), String::from_utf8_lossy(&o.stdout).into_owned(), String::from_utf8_lossy(&o.stderr).into_owned())
}

/// The final state a host run's program wrote (17 digits), as numbers.
fn host_state(out: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(out.join("work/final_state.dat")).expect("the program wrote final_state.dat");
    text.lines().skip(1).map(|l| l.split_whitespace().map(|v| v.parse::<f64>().unwrap()).collect()).collect()
}

fn bits(rows: &[Vec<f64>]) -> Vec<Vec<u64>> {
    rows.iter().map(|r| r.iter().map(|v| v.to_bits()).collect()).collect()
}

fn report(out: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("host_report.json")).expect("host_report.json")).unwrap()
}

/// Every routine of [`MAPPED`] compared at every call it was called, every field at 0 ULP;
/// its number of calls.
fn assert_all_zero(r: &serde_json::Value, except: &str) -> std::collections::BTreeMap<String, u64> {
    let mut calls = std::collections::BTreeMap::new();
    for (stage, fields) in MAPPED {
        let name = stage.strip_prefix("legacy.").unwrap();
        let m = &r["routines"][name];
        let n = m["calls"].as_u64().unwrap();
        assert!(n > 0 && m["compared_calls"].as_u64() == Some(n), "{name}: {m}");
        let rows = m["rows"].as_array().unwrap();
        for f in *fields {
            let row = rows.iter().find(|x| x["field"] == *f).unwrap_or_else(|| panic!("{name} {f}: {m}"));
            assert!(row["compared"].as_u64().unwrap() >= n, "{name} {f}: {row}");
            if name != except {
                assert_eq!((row["max_ulp"].as_u64(), row["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{row}");
            }
        }
        calls.insert(name.to_string(), n);
    }
    calls
}

#[test]
fn host_mode_runs_the_fixtures_program_with_every_twinned_routine_at_zero_ulp_at_every_call() {
    let out = scratch("host_fixture");
    let (code, so, se) = host(shared(), &out, false);
    assert_eq!(code, Some(0), "{so}{se}");
    assert!(so.contains("6 routines at 0 ULP at every compared call"), "{so}");
    let r = report(&out);
    let calls = assert_all_zero(&r, "");
    // the program's own calls: one search and one force per step, the EOS per particle, the
    // kernel per pair (and per particle for the self term)
    assert_eq!((calls["direct_find"], calls["int_force"], calls["p_gas"]), (40, 40, 16000), "{calls:?}");
    assert!(calls["kernel"] > 178_213, "{calls:?}");
    // a routine the case gives no twin is called but not compared
    assert_eq!(r["routines"]["input"]["calls"], 1);
    assert_eq!(r["routines"]["input"]["compared_calls"], 0);
    assert_eq!(r["routines"]["con_density"]["calls"], 0);
    // the program ran as written: its final state is its own program's, bit for bit
    let own = program_rows_of(shared(), "host_fixture_program", 40);
    assert_eq!(bits(&host_state(&out)), bits(&own));

    // on the twins' outputs it runs to the end, in the same state (every twin is at 0 ULP)
    let out = scratch("host_fixture_rust");
    let (code, so, se) = host(shared(), &out, true);
    assert_eq!(code, Some(0), "{so}{se}");
    assert!(so.contains("the Rust twins' outputs"), "{so}");
    assert_eq!(report(&out)["outputs"], "rust");
    assert_eq!(bits(&host_state(&out)), bits(&own));
}

/// A copy of the fixture whose int_force changes one particle's energy rate at its 7th call is
/// reported there: call 7, particle 319 (counted from 0), every other routine at 0 ULP. On the
/// twins' outputs the program ends in the unchanged program's state.
#[test]
fn a_perturbed_routine_is_reported_at_the_call_where_it_diverges() {
    let v = variant_built("host_perturbed", "int_force.f", |t| {
        let end = "   80 continue\n";
        assert!(t.contains(end));
        t.replacen(end, &format!("{end}      if (itimestep .eq. 7) dedt(320) = dedt(320)*1.0000001d0\n"), 1)
    });
    let b = v.join("build");
    let out = scratch("host_perturbed_run");
    let (code, so, se) = host(&b, &out, false);
    assert_eq!(code, Some(4), "{so}{se}");
    assert!(so.contains("DIVERGING: int_force"), "{so}");
    let r = report(&out);
    assert_all_zero(&r, "int_force");
    let rows = r["routines"]["int_force"]["rows"].as_array().unwrap().clone();
    let dde = rows.iter().find(|x| x["field"] == "dde").unwrap();
    assert_eq!(dde["out_of_tolerance"], 1, "{dde}");
    let d = &dde["first_divergence"];
    assert_eq!(d["step"], 7, "{d}");
    assert!(d["at"].as_str().unwrap().ends_with("particle 319"), "{d}");
    for f in ["p", "c", "acc"] {
        let row = rows.iter().find(|x| x["field"] == f).unwrap();
        assert_eq!(row["max_ulp"], 0, "{row}");
    }
    // the program as written: the perturbed program's own end, not the fixture's
    let perturbed = program_rows_of(&b, "host_perturbed_program", 40);
    let own = program_rows_of(shared(), "host_unperturbed_program", 40);
    assert_ne!(bits(&perturbed), bits(&own));
    assert_eq!(bits(&host_state(&out)), bits(&perturbed));

    // on the twins' outputs: the divergence is still reported, and the program runs to the end
    // where the unperturbed program ends
    let out = scratch("host_perturbed_rust");
    let (code, so, se) = host(&b, &out, true);
    assert_eq!(code, Some(4), "{so}{se}");
    let r = report(&out);
    let rows = r["routines"]["int_force"]["rows"].as_array().unwrap();
    assert_eq!(rows.iter().find(|x| x["field"] == "dde").unwrap()["first_divergence"]["step"], 7);
    assert_eq!(bits(&host_state(&out)), bits(&own));
}

/// A routine called from the file that defines it is interposed too: the fixture with its
/// kernel moved into direct_find's file gives the same calls, all at 0 ULP.
#[test]
fn a_routine_called_inside_its_own_file_is_compared_at_every_call() {
    let v = variant("host_one_file", |m| m.to_string());
    let k = std::fs::read_to_string(v.join("kernel.f")).unwrap();
    let mut d = std::fs::read_to_string(v.join("direct_find.f")).unwrap();
    d.push('\n');
    d.push_str(&k);
    std::fs::write(v.join("direct_find.f"), d).unwrap();
    std::fs::remove_file(v.join("kernel.f")).unwrap();
    build(&v.join("legacy.toml"), &v.join("build")).expect("the one-file variant builds");
    let out = scratch("host_one_file_run");
    let (code, so, se) = host(&v.join("build"), &out, false);
    assert_eq!(code, Some(0), "{so}{se}");
    let calls = assert_all_zero(&report(&out), "");
    let whole = scratch("host_one_file_ref");
    let (code, so, se) = host(shared(), &whole, false);
    assert_eq!(code, Some(0), "{so}{se}");
    assert_eq!(calls, assert_all_zero(&report(&whole), ""));
}

/// A routine whose values host mode cannot read from its arguments (art_visc with its arrays in
/// COMMON blocks) is refused before the program starts: one line naming it and why.
#[test]
fn a_routine_host_mode_cannot_compare_is_refused_with_one_line() {
    let v = av_globals_variant("host_globals", "global_includes = [\"avstate.inc\"]", AV_GLOBALS, |t| {
        av_without_arguments(t, "      implicit none\n      include 'avstate.inc'\n")
    });
    std::fs::write(v.join("avstate.inc"), AVSTATE_INC).unwrap();
    build(&v.join("legacy.toml"), &v.join("build")).expect("the COMMON variant builds");
    let out = scratch("host_globals_run");
    let (code, so, se) = host(&v.join("build"), &out, false);
    assert_eq!(code, Some(2), "{so}{se}");
    assert_eq!(se.lines().count(), 1, "{se}");
    assert!(se.starts_with("error: legacy host: cannot compare routine art_visc:") && se.contains("globals"), "{se}");
    assert!(!so.contains("number of time steps"), "the program did not start: {so}");
}

/// The fixture with every array of vectors declared `(mxd, ...)`, mxd = 3 in its 1D param.inc
/// (a name as long as `dim`, so that every line stays within 72 columns), as codes that keep 3
/// components whatever `dim` do (`x(maxdim,maxn)`): the build lays each particle's
/// and pair's values out 3 apart, host mode compares every call at 0 ULP, and `run --legacy`
/// ends in the program's state bit for bit (the same state as the fixture's, whose arithmetic
/// it is).
#[test]
fn arrays_declared_with_a_leading_extent_above_dim_are_laid_out_as_declared() {
    let d = variant("maxdim_layout", |m| m.to_string());
    let changed = with_mxd_layout(&d);
    assert!(changed >= 8, "{changed} files changed");
    let build = d.join("build");
    blastsph::migration::build(&d.join("legacy.toml"), &build).expect("the layout builds");
    let info: serde_json::Value = serde_json::from_slice(&std::fs::read(build.join("build.json")).unwrap()).unwrap();
    let av = info["routines"].as_array().unwrap().iter().find(|r| r["name"] == "art_visc").unwrap();
    let x = av["args"].as_array().unwrap().iter().find(|a| a["name"] == "x").unwrap();
    assert_eq!(x["lead"], 3, "{x}");
    // its own program computes what the fixture's does
    let own = program_rows_of(&build, "maxdim_program", 40);
    assert_eq!(bits(&own), bits(program_final_state()));
    // host mode: every twinned routine at 0 ULP at every call, the program as written
    let out = scratch("maxdim_host");
    let (code, so, se) = host(&build, &out, false);
    assert_eq!(code, Some(0), "{so}{se}");
    assert_all_zero(&report(&out), "");
    assert_eq!(bits(&host_state(&out)), bits(&own));
    // on the twins' outputs, written back 3 apart: the same end
    let out = scratch("maxdim_host_rust");
    let (code, so, se) = host(&build, &out, true);
    assert_eq!(code, Some(0), "{so}{se}");
    assert_eq!(bits(&host_state(&out)), bits(&own));
    // blastsph as the host: the program's end, bit for bit
    assert_run_ends_as_the_program(&build, "maxdim_run");
}

/// An EOS whose sound speed is NaN (the square root of a negative number): the table prints the
/// ULP distance of a NaN as `NaN`, as the dual run's table does.
#[test]
fn a_nan_from_the_users_routine_is_printed_as_nan() {
    let d = variant_built("host_nan", "eos.f", |t| {
        t.replacen("      c = sqrt((gam - 1)*u)\n", "      c = sqrt((gam - 1)*u - 1.d10)\n", 1)
    });
    let out = scratch("host_nan_run");
    let (code, so, se) = host(&d.join("build"), &out, false);
    assert_eq!(code, Some(4), "{so}{se}");
    assert!(!so.contains(&u64::MAX.to_string()), "{so}");
    // a row: [routine calls compared] field values max-abs max-rel maxULP out first-divergence
    let nan_ulp = |l: &str| {
        let t: Vec<&str> = l.split_whitespace().collect();
        t.iter().position(|x| *x == "c").is_some_and(|k| t.get(k + 4) == Some(&"NaN"))
    };
    assert!(so.lines().any(nan_ulp), "no row of c with maxULP NaN: {so}");
}
