//! The book's third search, `tree_search` (param.inc's `nnps = 3`), run through blastsph: a tree
//! search of our own (`tests/legacy_extra/tree_search.f`, a binary tree by bisection in 1D) in a
//! copy of the fixture whose single_step calls it. Its pairs are direct_find's, in the tree's
//! order: the dual run and host mode compare them as sets, and `run --legacy` sums in that order.
//! The search is written for any `dim`: built in 2D and 3D it is compared on blastsph's own cases.

mod legacy_kit;
use legacy_kit::*;

/// The fixture with `nnps = 3` in its param.inc, a single_step that calls the search nnps names,
/// tree_search.f beside it and mapped in direct_find's place; built into `DIR/build` once.
fn tree_fixture() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let d = variant("tree_search", |m| m.replace("name = \"direct_find\"", "name = \"tree_search\""));
        std::fs::copy(root().join("tests/legacy_extra/tree_search.f"), d.join("tree_search.f")).unwrap();
        let edit = |file: &str, old: &str, new: &str| {
            let text = std::fs::read_to_string(d.join(file)).unwrap();
            assert!(text.contains(old), "{file}: {old}");
            std::fs::write(d.join(file), text.replacen(old, new, 1)).unwrap();
        };
        edit(
            "param.inc",
            "c     pa_sph :",
            "c     nnps   : neighbour search, 1 = direct_find, 3 = tree_search\n      integer nnps\n      parameter (nnps = 3)\n\nc     pa_sph :",
        );
        edit(
            "single_step.f",
            "      call direct_find(itimestep, ntotal + nvirt, hsml, x, niac,\n     &                 pair_i, pair_j, w, dwdx, ns)\n",
            "      if (nnps .eq. 1) then
        call direct_find(itimestep, ntotal + nvirt, hsml, x, niac,
     &                   pair_i, pair_j, w, dwdx, ns)
      else if (nnps .eq. 3) then
        call tree_search(itimestep, ntotal + nvirt, hsml, x, niac,
     &                   pair_i, pair_j, w, dwdx, ns)
      endif
",
        );
        build(&d.join("legacy.toml"), &d.join("build")).expect("the tree_search variant builds");
        d
    })
}

/// Every field of the search and of the routines after it at 0 ULP in the dual run with the
/// book's profile; the search's pairs are direct_find's as a set, most of them at other places.
#[test]
fn the_tree_search_is_compared_as_a_set_and_every_routine_is_at_zero_ulp() {
    let d = tree_fixture();
    let out = d.join("dual");
    let so = blastsph_ok(&dual_book_args(&d.join("build"), None, &out), 0);
    assert!(so.contains("40 steps compared; every compared stage within tolerance"), "{so}");
    assert!(so.contains("pairs as sets: 40 steps in another order"), "{so}");
    let (r, rows) = report_rows(&out.join("dual_report.json"));
    assert_eq!(
        r["legacy"]["routines"]["tree_search"]["stands_for"],
        serde_json::json!(["nnps.search", "kernel.pairs"])
    );
    let tree = MAPPED.iter().map(|(s, f)| (s.replace("direct_find", "tree_search"), *f));
    for (stage, fields) in tree {
        for f in fields {
            let x = row(&rows, &stage, f);
            assert_eq!(x["counterpart"], "legacy", "{x}");
            assert!(x["compared"].as_u64().unwrap() >= 400 * 40, "{stage} {f}: {x}");
            assert_eq!((x["max_ulp"].as_u64(), x["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{stage} {f}: {x}");
        }
    }
    let pi = row(&rows, "legacy.tree_search", "pair_i");
    let o = &pi["pair_order"];
    let compared = pi["compared"].as_u64().unwrap();
    assert_eq!((o["only_counterpart"].as_u64(), o["only_rust"].as_u64()), (Some(0), Some(0)), "{o}");
    assert_eq!(o["reversed"].as_u64(), Some(0), "every pair (i, j) with i < j: {o}");
    assert!(o["moved"].as_u64().unwrap() > compared / 4, "the tree's order is not direct_find's: {o}");
}

/// `run --legacy` with the tree search ends in the state of the variant's own program, bit for
/// bit: the legacy search's pairs, in the tree's order, are the ones every later stage sums over.
/// The program's end differs from the fixture's (direct_find's order), so the order is seen.
#[test]
fn run_legacy_with_the_tree_search_ends_in_the_state_of_its_program() {
    let d = tree_fixture();
    let b = d.join("build");
    let prog = program_rows_of(&b, "tree_search_program", 40);
    assert_run_ends_as(&b, "shock_tube", "liu-book", &prog, "tree_search_run");
    let bits =
        |rows: &[Vec<f64>]| -> Vec<Vec<u64>> { rows.iter().map(|r| r.iter().map(|v| v.to_bits()).collect()).collect() };
    assert_ne!(bits(&prog), bits(program_final_state()), "another summation order, another rounding");
    // the ledger's profile run sums over blastsph's own search, in direct_find's order: its
    // `legacy` row is the rounding of the two orders, not 0
    let led = d.join("ledger");
    let so = blastsph_ok(
        &["legacy", "ledger", "shock_tube", "--legacy", b.to_str().unwrap(), "--out", led.to_str().unwrap()],
        0,
    );
    let (_, rows) = report_rows(&led.join("ledger.json"));
    let legacy = rows.iter().find(|x| x["run"] == "legacy").unwrap_or_else(|| panic!("{so}"));
    assert!(legacy["particles_differing"].as_u64().unwrap() > 0, "{so}");
    assert!(legacy["max_abs_rho"].as_f64().unwrap() < 1e-12, "{so}");
}

/// `blastsph legacy host shock_tube --legacy BUILD --compat liu-book --out OUT` (with
/// `--rust-outputs` when `rust`), input `40` then `0`: (status, stdout, stderr, the final state
/// the program wrote).
fn host(build: &Path, out: &Path, rust: bool) -> (Option<i32>, String, String, Vec<Vec<f64>>) {
    let mut args = vec!["legacy", "host", "shock_tube", "--legacy", build.to_str().unwrap(), "--compat", "liu-book"];
    if rust {
        args.push("--rust-outputs");
    }
    let o = blastsph_40_steps(&[&args[..], &["--out", out.to_str().unwrap()]].concat());
    let text = std::fs::read_to_string(out.join("work/final_state.dat")).unwrap_or_default();
    let rows =
        text.lines().skip(1).map(|l| l.split_whitespace().map(|v| v.parse::<f64>().unwrap()).collect()).collect();
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
        rows,
    )
}

/// Host mode on the variant's program: the tree search's call compared as a set at each of its
/// 40 calls, every field of every routine at 0 ULP, and the program's own end. On the twins'
/// outputs the program gets blastsph's pairs, in direct_find's order: it ends in the state of the
/// fixture's program (direct_find), not of its own.
#[test]
fn host_mode_compares_the_tree_searchs_pairs_as_a_set() {
    let d = tree_fixture();
    let b = d.join("build");
    let out = scratch("tree_search_host");
    let (code, so, se, end) = host(&b, &out, false);
    assert_eq!(code, Some(0), "{so}{se}");
    assert!(so.contains("6 routines at 0 ULP at every compared call"), "{so}");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("host_report.json")).expect("host_report.json"))
            .unwrap();
    let t = &r["routines"]["tree_search"];
    assert_eq!((t["calls"].as_u64(), t["compared_calls"].as_u64()), (Some(40), Some(40)), "{t}");
    for row in t["rows"].as_array().unwrap() {
        assert_eq!((row["max_ulp"].as_u64(), row["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{row}");
    }
    let pi = t["rows"].as_array().unwrap().iter().find(|x| x["field"] == "pair_i").expect("a pair_i row");
    assert!(pi["pair_order"]["moved"].as_u64().unwrap() > 0, "{pi}");
    // the program ran as written
    let own = program_rows_of(&b, "tree_search_host_program", 40);
    assert_eq!(end, own);
    let out = scratch("tree_search_host_rust");
    let (code, so, se, end) = host(&b, &out, true);
    assert_eq!(code, Some(0), "{so}{se}");
    assert_ne!(end, own);
    assert_eq!(end, program_final_state());
}

/// The tree search alone, built with `dim` = 2 (a quadtree) and 3 (an octree) and larger arrays,
/// in the dual run of a coarse Noh problem in 2D and of the Sedov octant in 3D (three mirror
/// planes, whose particles it searches too). Its pairs are the twin's as a set, with w and dW/dx
/// at 0 ULP, over 5 steps; most pairs come at other places than the twin's.
#[test]
fn the_tree_search_finds_the_twins_pairs_in_2d_and_3d() {
    let cases: [(usize, &str, &[&str]); 2] = [
        (2, "cases/verify/noh_2d.toml", &["region.gas.spacing_m=0.04"]),
        (
            3,
            "cases/verify/sedov_3d.toml",
            &["region.ambient.spacing_m=0.05", "region.hot.spacing_m=0.05", "region.hot.hi_m=[0.05, 0.05, 0.05]"],
        ),
    ];
    for (dim, case, sets) in cases {
        let d = variant(&format!("tree_search_{dim}d"), |m| {
            let i = m.find("[[routine]]").unwrap();
            let head = m[..i].replace("dim = 1", &format!("dim = {dim}"));
            format!(
                "{head}[[routine]]\nname = \"tree_search\"\nmodule = \"nnps,kernel\"\nargs = [\"itimestep\", \"ntotal\", \"hsml\", \"x\", \"niac\", \"pair_i\", \"pair_j\", \"w\", \"dwdx\", \"countiac\"]\n"
            )
        });
        std::fs::copy(root().join("tests/legacy_extra/tree_search.f"), d.join("tree_search.f")).unwrap();
        let inc = std::fs::read_to_string(d.join("param.inc")).unwrap();
        let new = inc
            .replace("parameter (dim = 1)", &format!("parameter (dim = {dim})"))
            .replace("maxn = 1000, max_interaction = 20*maxn", "maxn = 4000, max_interaction = 40*maxn");
        assert_ne!(new, inc);
        std::fs::write(d.join("param.inc"), new).unwrap();
        build(&d.join("legacy.toml"), &d.join("build")).expect("the tree_search variant builds");
        let out = d.join("dual");
        let mut args = vec!["dual".to_string(), root().join(case).to_str().unwrap().to_string()];
        for s in sets {
            args.extend(["--set".to_string(), s.to_string()]);
        }
        for a in ["--legacy", d.join("build").to_str().unwrap(), "--compat", "liu-book", "--steps", "5", "--out"] {
            args.push(a.to_string());
        }
        args.push(out.to_str().unwrap().to_string());
        let so = blastsph_ok(&args, 0);
        assert!(so.contains("5 steps compared; every compared stage within tolerance"), "{dim}D: {so}");
        let (_, rows) = report_rows(&out.join("dual_report.json"));
        for f in ["pair_i", "pair_j", "w", "dwdx"] {
            let x = row(&rows, "legacy.tree_search", f);
            assert_eq!(x["counterpart"], "legacy", "{dim}D {f}: {x}");
            assert_eq!((x["max_ulp"].as_u64(), x["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{dim}D {f}: {x}");
        }
        let pi = row(&rows, "legacy.tree_search", "pair_i");
        let o = &pi["pair_order"];
        let compared = pi["compared"].as_u64().unwrap();
        assert!(compared > 50_000, "{dim}D: {pi}");
        assert_eq!((o["only_counterpart"].as_u64(), o["only_rust"].as_u64()), (Some(0), Some(0)), "{dim}D: {o}");
        assert!(o["moved"].as_u64().unwrap() > compared / 4, "{dim}D: the tree's order is not the twin's: {o}");
    }
}
