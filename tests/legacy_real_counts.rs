//! Codes that declare their counts, indices and pair lists double precision (`real(8) ntotal,
//! niac, pair_i(...)`), as some rewrites of the book's code do: the shims hold such an argument
//! as a double and convert it both ways, exactly (a whole number below 2^53). A count declared
//! single precision is still refused.

mod legacy_kit;
use legacy_kit::*;

/// The fixture with direct_find's and sum_density's counts, pair lists, neighbour counts and
/// types declared double precision (the rest of the program is not run).
fn real_counts(name: &str) -> PathBuf {
    let d = variant(name, |m| m.to_string());
    for (file, old, new) in [
        (
            "direct_find.f",
            "      integer itimestep, ntotal, niac, pair_i(max_interaction),\n     &        pair_j(max_interaction), countiac(maxn)\n",
            "      integer itimestep\n      double precision ntotal, niac, pair_i(max_interaction),\n     &        pair_j(max_interaction), countiac(maxn)\n",
        ),
        (
            "density.f",
            "      integer ntotal, niac, pair_i(max_interaction),\n     &        pair_j(max_interaction), itype(maxn)\n      double precision hsml(maxn), mass(maxn), w(max_interaction),\n     &        rho(maxn)\n      integer i, j, k, d\n      double precision w0, zero(dim), r, wsum(maxn)\n",
            "      double precision ntotal, niac, pair_i(max_interaction),\n     &        pair_j(max_interaction), itype(maxn)\n      double precision hsml(maxn), mass(maxn), w(max_interaction),\n     &        rho(maxn)\n      integer i, j, k, d\n      double precision w0, zero(dim), r, wsum(maxn)\n",
        ),
    ] {
        let p = d.join(file);
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(text.contains(old), "{file}: {old}");
        std::fs::write(&p, text.replacen(old, new, 1)).unwrap();
    }
    d
}

/// Built, the two routines are at 0 ULP in the dual run with the book's profile, and `run
/// --legacy` ends in the fixture's own program's state bit for bit.
#[test]
fn counts_declared_double_are_converted_exactly() {
    let d = real_counts("real_counts");
    let b = d.join("build");
    build(&d.join("legacy.toml"), &b).expect("the variant builds");
    let info = std::fs::read_to_string(b.join("build.json")).unwrap();
    let info: serde_json::Value = serde_json::from_str(&info).unwrap();
    let routine = |n: &str| {
        info["routines"].as_array().unwrap().iter().find(|r| r["name"] == n).cloned().unwrap_or_else(|| panic!("{n}"))
    };
    let real: Vec<String> = routine("direct_find")["args"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|a| a["real"] == true)
        .map(|a| a["name"].as_str().unwrap().to_string())
        .collect();
    assert_eq!(real, ["ntotal", "niac", "pair_i", "pair_j", "countiac"]);
    let out = d.join("dual");
    let so = blastsph_ok(&dual_book_args(&b, None, &out), 0);
    assert!(so.contains("40 steps compared; every compared stage within tolerance"), "{so}");
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    for (stage, f) in [
        ("legacy.direct_find", "pair_i"),
        ("legacy.direct_find", "pair_j"),
        ("legacy.direct_find", "w"),
        ("legacy.sum_density", "rho"),
    ] {
        let x = row(&rows, stage, f);
        assert_eq!(x["counterpart"], "legacy", "{x}");
        assert!(x["compared"].as_u64().unwrap() >= 400 * 40, "{stage} {f}: {x}");
        assert_eq!((x["max_ulp"].as_u64(), x["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{stage} {f}: {x}");
    }
    assert_run_ends_as_the_program(&b, "real_counts_run");
}

/// A count declared `real` (4 bytes) would round a count past 2^24: refused, one line naming the
/// routine, the dummy and the type.
#[test]
fn a_count_declared_single_precision_is_refused() {
    let d = real_counts("real_counts_single");
    let p = d.join("density.f");
    let text = std::fs::read_to_string(&p).unwrap();
    std::fs::write(&p, text.replacen("      double precision ntotal, niac,", "      real ntotal, niac,", 1)).unwrap();
    refused(&d, &["sum_density", "ntotal", "float"]);
}

/// An integer of the vocabulary bound to a double dummy of another name (`itype` where p_gas
/// declares `u`) is a misplaced argument, not a count declared double: refused, with the reason.
#[test]
fn an_integer_bound_to_a_double_of_another_name_is_refused() {
    let d = variant("real_counts_misplaced", |t| {
        t.replace("\"rho\", \"u\", \"p\", \"c\"]", "\"rho\", \"itype\", \"p\", \"c\"]")
    });
    refused(&d, &["p_gas", "dummy `u`", "under the vocabulary's name only"]);
}

/// A search that counts on from the `niac` its caller zeroed (no `niac = 0` of its own, as the
/// real(8) rewrite above writes its direct_find): blastsph hands every search niac = 0, so the
/// pairs are the step's own. Before, it counted on from the last step's pairs and ran out of
/// max_interaction within a few steps. The dual run is at 0 ULP, and `run --legacy` ends in the
/// variant's own program's state bit for bit.
#[test]
fn a_search_that_counts_on_from_its_callers_zero_gets_zero() {
    let d = variant("search_from_callers_zero", |m| m.to_string());
    for (file, old, new) in [
        ("direct_find.f", "      niac = 0\n", ""),
        (
            "single_step.f",
            "      call direct_find(itimestep, ntotal + nvirt, hsml, x, niac,\n",
            "      niac = 0\n      call direct_find(itimestep, ntotal + nvirt, hsml, x, niac,\n",
        ),
    ] {
        let p = d.join(file);
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(text.contains(old), "{file}: {old}");
        std::fs::write(&p, text.replacen(old, new, 1)).unwrap();
    }
    let b = d.join("build");
    build(&d.join("legacy.toml"), &b).expect("the variant builds");
    let out = d.join("dual");
    let so = blastsph_ok(&dual_book_args(&b, None, &out), 0);
    assert!(so.contains("40 steps compared; every compared stage within tolerance"), "{so}");
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    let x = row(&rows, "legacy.direct_find", "pair_i");
    assert_eq!((x["max_ulp"].as_u64(), x["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{x}");
    assert_eq!(x["pair_order"]["only_counterpart"].as_u64().unwrap_or(0), 0, "{x}");
    let prog = program_rows_of(&b, "search_from_callers_zero_program", 40);
    assert_run_ends_as(&b, "shock_tube", "liu-book", &prog, "search_from_callers_zero_run");
}

/// Host mode on a program whose direct_find (alone) declares its counts double precision and whose
/// single_step calls it on doubles, then copies them back into its integers: the search is
/// read and written as doubles at each of its 40 calls, at 0 ULP, and the program ends in the
/// fixture's own state bit for bit, with the program's and with the twins' outputs.
#[test]
fn host_mode_reads_and_writes_counts_declared_double() {
    let d = real_counts("real_counts_host");
    // sum_density as the fixture has it: the program calls it on its integers
    std::fs::copy(fixture().join("density.f"), d.join("density.f")).unwrap();
    let p = d.join("single_step.f");
    let text = std::fs::read_to_string(&p).unwrap();
    let (decl, call) = (
        "     &        avdudt(maxn), ahdudt(maxn), c(maxn), eta(maxn)\n",
        "      call direct_find(itimestep, ntotal + nvirt, hsml, x, niac,\n     &                 pair_i, pair_j, w, dwdx, ns)\n",
    );
    assert!(text.contains(decl) && text.contains(call));
    let text = text.replacen(
        decl,
        &format!("{decl}      double precision rnt, rniac, rpi(max_interaction),\n     &        rpj(max_interaction), rns(maxn)\n      integer k\n"),
        1,
    );
    let text = text.replacen(
        call,
        "      rnt = ntotal + nvirt
      call direct_find(itimestep, rnt, hsml, x, rniac,
     &                 rpi, rpj, w, dwdx, rns)
      niac = nint(rniac)
      do 12 k = 1, niac
        pair_i(k) = nint(rpi(k))
        pair_j(k) = nint(rpj(k))
   12 continue
      do 13 i = 1, ntotal + nvirt
        ns(i) = nint(rns(i))
   13 continue
",
        1,
    );
    std::fs::write(&p, text).unwrap();
    let b = d.join("build");
    build(&d.join("legacy.toml"), &b).expect("the variant builds");
    assert_eq!(bits(&program_rows_of(&b, "real_counts_host_program", 40)), bits(program_final_state()));
    for rust in [false, true] {
        let out = d.join(if rust { "host_rust" } else { "host" });
        let mut args = vec!["legacy", "host", "shock_tube", "--legacy", b.to_str().unwrap(), "--compat", "liu-book"];
        if rust {
            args.push("--rust-outputs");
        }
        args.extend(["--out", out.to_str().unwrap()]);
        let o = blastsph_40_steps(&args);
        let so = String::from_utf8_lossy(&o.stdout);
        assert_eq!(o.status.code(), Some(0), "{so}{}", String::from_utf8_lossy(&o.stderr));
        let r: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("host_report.json")).unwrap()).unwrap();
        let m = &r["routines"]["direct_find"];
        assert_eq!(m["compared_calls"].as_u64(), Some(40), "{m}");
        for row in m["rows"].as_array().unwrap() {
            assert_eq!((row["max_ulp"].as_u64(), row["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{row}");
        }
        let text = std::fs::read_to_string(out.join("work/final_state.dat")).unwrap();
        let rows: Vec<Vec<f64>> =
            text.lines().skip(1).map(|l| l.split_whitespace().map(|v| v.parse::<f64>().unwrap()).collect()).collect();
        assert_eq!(bits(&rows), bits(program_final_state()), "rust outputs: {rust}");
    }
}

fn bits(rows: &[Vec<f64>]) -> Vec<Vec<u64>> {
    rows.iter().map(|r| r.iter().map(|v| v.to_bits()).collect()).collect()
}
