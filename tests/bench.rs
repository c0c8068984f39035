//! `blastsph bench` (docs/performance.md): the refinement of a case by k, the bench on the shock
//! tube at two resolutions with both backends (bench.csv's columns and rows, errors that fall with
//! resolution, Rust and Fortran rows with identical errors), the dry run, and bad flags.

mod common;

use blastsph::bench::{self, CSV_COLUMNS};
use blastsph::case::Case;
use std::collections::BTreeMap;
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

fn case_text(name: &str) -> String {
    std::fs::read_to_string(common::case_path(name)).expect("case file")
}

fn refined(name: &str, k: f64) -> (Case, Vec<String>) {
    bench::refine(&case_text(name), name, Some(name.trim_end_matches(".toml")), &[], k).expect("refine")
}

fn count(c: &Case) -> (usize, Vec<usize>) {
    let init = blastsph::setup::particles(c).expect("particles");
    (init.counts.iter().sum(), init.counts)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * b.abs().max(1e-300)
}

#[test]
fn refinement_of_the_shock_tube_keeps_the_book_layout() {
    let (base, _) = refined("shock_tube.toml", 1.0);
    for k in [0.5, 2.0, 4.0] {
        let (c, sets) = refined("shock_tube.toml", k);
        assert!(!sets.is_empty());
        let (l, r) = (&c.regions[0], &c.regions[1]);
        let (l0, r0) = (&base.regions[0], &base.regions[1]);
        assert!(close(l.spacing_m, l0.spacing_m / k) && close(r.spacing_m, r0.spacing_m / k));
        assert_eq!(l.count.as_ref().unwrap()[0] as f64, 320.0 * k);
        assert_eq!(r.count.as_ref().unwrap()[0] as f64, 80.0 * k);
        // a Riemann case: each lattice keeps its outer end, its first point one spacing from
        // the diaphragm (validation.md's resolution study)
        assert!(close(l.origin_m.as_ref().unwrap()[0], -0.6));
        assert!(close(r.origin_m.as_ref().unwrap()[0], r.spacing_m));
        assert!(close(l.mass_kg.unwrap(), 0.001875 / k) && close(r.mass_kg.unwrap(), 0.001875 / k));
        assert!(close(l.h_m.unwrap(), 0.015 / k) && close(r.h_m.unwrap(), 0.015 / k));
        assert!(close(c.time.dt_s.unwrap(), 0.005 / k));
        assert_eq!(c.time.end_s, base.time.end_s);
        assert_eq!(c.analysis.window_m, base.analysis.window_m);
        assert_eq!(count(&c).0 as f64, 400.0 * k, "particles scale as k^dim (dim = 1)");
    }
    // a count that does not come out whole is refused, naming the region
    let e = bench::refine(&case_text("shock_tube.toml"), "st", Some("shock_tube"), &[], 1.01).unwrap_err();
    assert!(e.to_string().contains("region[0] (left)"), "{e}");
}

#[test]
fn refinement_of_a_lattice_keeps_its_cells() {
    // outside a Riemann case a lattice point is the centre of its cell: origin' = o − s/2 + s'/2,
    // so the extent o − s/2 … o + (n − 1/2) s stays
    let body = "dim = 2\n[time]\nend_s = 1e-3\n[[material]]\nname = \"w\"\neos = { kind = \"ideal_gas\", gamma = 1.4, rho0_kgm3 = 1.0 }\n\
                [[region]]\nname = \"a\"\nmaterial = \"w\"\nshape = \"lattice\"\norigin_m = [0.05, 0.25]\ncount = [10, 4]\nspacing_m = 0.1\n";
    let (c, _) = bench::refine(body, "lattice", Some("lattice"), &[], 4.0).unwrap();
    let r = &c.regions[0];
    assert_eq!(r.count.as_deref(), Some(&[40usize, 16][..]));
    let o = r.origin_m.as_ref().unwrap();
    assert!(close(o[0], 0.0125) && close(o[1], 0.2125), "{o:?}");
    assert!(close(o[0] - 0.5 * r.spacing_m, 0.0) && close(o[1] - 0.5 * r.spacing_m, 0.2));
    assert_eq!(count(&c).0, 40 * 16);
}

/// A region clipped by `keep_below` keeps its plane under refinement (a place, not a count of
/// spacings): the 2D box [0, 1]² under the line x + y = 0.57 keeps the cells with
/// i + j ≤ M, M = ⌊0.57/Δx⌋ − 1 (no node on the line at these spacings), (M + 1)(M + 2)/2 of
/// them at every k: 15, 66, 253 at Δx = 0.1, 0.05, 0.025 — not 15 k².
#[test]
fn refinement_keeps_a_regions_clip_planes() {
    let body = "dim = 2\n[time]\nend_s = 1e-3\n[[material]]\nname = \"w\"\neos = { kind = \"ideal_gas\", gamma = 1.4, rho0_kgm3 = 1.0 }\n\
                [[region]]\nname = \"a\"\nmaterial = \"w\"\nshape = \"box\"\nlo_m = [0.0, 0.0]\nhi_m = [1.0, 1.0]\nspacing_m = 0.1\n\
                keep_below = [{ point_m = [0.57, 0.0], normal = [1.0, 1.0] }]\n";
    for (k, want) in [(1.0, 15usize), (2.0, 66), (4.0, 253)] {
        let (c, sets) = bench::refine(body, "clip", Some("clip"), &[], k).unwrap();
        assert!(sets.iter().all(|s| !s.contains("keep_below")), "{sets:?}");
        let r = &c.regions[0];
        assert_eq!(r.keep_below.len(), 1);
        assert_eq!((&r.keep_below[0].point_m[..], &r.keep_below[0].normal[..]), (&[0.57, 0.0][..], &[1.0, 1.0][..]));
        let m = (0.57 / r.spacing_m).floor() as usize - 1;
        assert_eq!((m + 1) * (m + 2) / 2, want, "k = {k}");
        assert_eq!(count(&c).0, want, "k = {k}");
    }
}

#[test]
fn refinement_of_a_blast_scales_the_particles_and_keeps_the_scene() {
    let (base, _) = refined("surface_loose_tnt6.toml", 1.0);
    let (n1, per1) = count(&base);
    assert_eq!(n1, 10_000);
    for k in [2.0, 3.0] {
        let (c, _) = refined("surface_loose_tnt6.toml", k);
        let (n, per) = count(&c);
        assert_eq!(n as f64, n1 as f64 * k * k, "k = {k}");
        for (a, b) in per.iter().zip(&per1) {
            assert_eq!(*a as f64, *b as f64 * k * k, "every region scales (k = {k})");
        }
        for (r, r0) in c.regions.iter().zip(&base.regions) {
            assert!(close(r.spacing_m, r0.spacing_m / k));
            assert_eq!((&r.lo_m, &r.hi_m), (&r0.lo_m, &r0.hi_m), "the charge and the soil keep their boxes");
        }
        let g: Vec<_> = c.gauges.iter().map(|g| g.point_m.clone()).collect();
        let g0: Vec<_> = base.gauges.iter().map(|g| g.point_m.clone()).collect();
        assert_eq!(g, g0, "gauges stay");
        assert_eq!(c.walls.len(), base.walls.len());
        for (w, w0) in c.walls.iter().zip(&base.walls) {
            assert_eq!((&w.from_m, &w.to_m), (&w0.from_m, &w0.to_m), "walls stay");
        }
        assert_eq!(c.detonation.as_ref().unwrap().point_m, base.detonation.as_ref().unwrap().point_m);
        assert_eq!(c.time.end_s, base.time.end_s);
        assert_eq!(c.time.max_steps as f64, base.time.max_steps as f64 * k);
    }
}

#[test]
fn observed_orders() {
    assert!((bench::self_order([4.0, 2.0, 1.0], 2.0).unwrap() - 1.0).abs() < 1e-12);
    assert!((bench::self_order([1.0, 1.25, 1.3125], 2.0).unwrap() - 2.0).abs() < 1e-12);
    assert!((bench::exact_order([0.4, 0.1], 2.0).unwrap() - 2.0).abs() < 1e-12);
    assert!((bench::exact_order([0.9, 0.1], 3.0).unwrap() - 2.0).abs() < 1e-12);
    assert_eq!(bench::self_order([1.0, 1.0, 2.0], 2.0), None, "no order from a zero difference");
    assert_eq!(bench::exact_order([0.0, 0.1], 2.0), None);
}

/// bench.csv as (header, rows of column → value).
fn read_csv(path: &std::path::Path) -> (Vec<String>, Vec<BTreeMap<String, String>>) {
    let t = std::fs::read_to_string(path).expect("bench.csv");
    let mut lines = t.lines();
    let head: Vec<String> = lines.next().expect("header").split(',').map(String::from).collect();
    let rows = lines
        .map(|l| {
            let v: Vec<&str> = l.split(',').collect();
            assert_eq!(v.len(), head.len(), "every row has every column: {l}");
            head.iter().cloned().zip(v.iter().map(|s| s.to_string())).collect()
        })
        .collect();
    (head, rows)
}

#[test]
fn bench_of_the_shock_tube_with_both_backends() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bench");
    let o = out.to_str().unwrap();
    let res = blastsph(&[
        "bench",
        "--cases",
        "shock_tube",
        "--resolutions",
        "1,2",
        "--backends",
        "rust,fortran",
        "--nnps",
        "cell",
        "--out",
        o,
    ]);
    let shown = format!("stdout:\n{}\nstderr:\n{}", text(&res.stdout), text(&res.stderr));
    assert_eq!(res.status.code(), Some(0), "{shown}");
    assert!(text(&res.stdout).contains("| k | dx (m) | particles |"), "prints the table; {shown}");

    let (head, rows) = read_csv(&out.join("bench.csv"));
    assert_eq!(head, CSV_COLUMNS.iter().map(|s| s.to_string()).collect::<Vec<_>>(), "the columns of bench.csv");
    assert_eq!(rows.len(), 4, "1 case × 2 resolutions × 2 backends × 1 search × 1 kernel");
    let get = |backend: &str, k: &str| {
        rows.iter().find(|r| r["backend"] == backend && r["k"] == k).unwrap_or_else(|| panic!("row {backend} k={k}"))
    };
    let num = |r: &BTreeMap<String, String>, c: &str| -> f64 {
        r[c].parse().unwrap_or_else(|_| panic!("column {c} = `{}` is not a number", r[c]))
    };
    for r in &rows {
        assert_eq!(r["case"], "shock_tube");
        assert_eq!(r["status"], "ok");
        assert_eq!(r["nnps"], "cell");
        assert_eq!(r["kernel"], "cubic");
        assert_eq!(r["count_exact"], "true");
        assert!(num(r, "wall_s") > 0.0 && num(r, "particle_steps_per_s") > 0.0);
        let per = num(r, "particle_steps_per_s") / num(r, "threads");
        assert!((num(r, "particle_steps_per_s_per_thread") - per).abs() <= 1e-9 * per);
    }
    assert_eq!(get("fortran", "1")["threads"], "1", "the Fortran core is serial");
    for b in ["rust", "fortran"] {
        let (a, c) = (get(b, "1"), get(b, "2"));
        assert_eq!((num(a, "particles"), num(c, "particles")), (400.0, 800.0));
        assert_eq!((num(a, "steps"), num(c, "steps")), (40.0, 80.0));
        assert!(close(num(c, "dx_m"), 0.0009375));
        for q in ["l1_rho", "l1_v", "l1_p", "l1_e"] {
            assert!(num(c, q) < num(a, q), "{b}: {q} falls with resolution: {} -> {}", a[q], c[q]);
        }
        // the book's run and validation.md's resolution study
        assert!((num(a, "l1_rho") / 1.6161e-2 - 1.0).abs() < 1e-4, "{}", a["l1_rho"]);
        assert!((num(c, "l1_rho") / 9.6646e-3 - 1.0).abs() < 1e-4, "{}", c["l1_rho"]);
    }
    for k in ["1", "2"] {
        for q in ["l1_rho", "l1_v", "l1_p", "l1_e"] {
            assert_eq!(get("rust", k)[q], get("fortran", k)[q], "k = {k}: the backends are bitwise equal ({q})");
        }
    }
    let js: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("bench.json")).unwrap()).expect("bench.json");
    assert_eq!(js["runs"].as_array().map(|a| a.len()), Some(4));
    let confs = js["configurations"].as_array().expect("configurations");
    assert_eq!(confs.len(), 2);
    for c in confs {
        let p = c["exact_orders"]["l1_rho"][0]["p"].as_f64().expect("an order from the exact errors");
        assert!(p > 0.5, "observed order {p}");
    }
    for f in ["bench.md", "error_vs_time.png", "error_vs_time_shock_tube.png"] {
        assert!(out.join(f).is_file(), "{f} written");
    }
    assert!(out.join("shock_tube/k2_fortran_cell_cubic/summary.json").is_file(), "the runs stay for inspection");
}

#[test]
fn a_list_of_thread_counts_runs_each_rust_configuration_on_each() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bench");
    let o = out.to_str().unwrap();
    let res = blastsph(&[
        "bench",
        "--cases",
        "shock_tube",
        "--resolutions",
        "1",
        "--backends",
        "rust,fortran",
        "--threads",
        "1,2",
        "--out",
        o,
    ]);
    let shown = format!("stdout:\n{}\nstderr:\n{}", text(&res.stdout), text(&res.stderr));
    assert_eq!(res.status.code(), Some(0), "{shown}");
    let (_, rows) = read_csv(&out.join("bench.csv"));
    // the Rust configuration once per thread count, the (serial) Fortran core once
    let th: Vec<(&str, &str)> = rows.iter().map(|r| (r["backend"].as_str(), r["threads"].as_str())).collect();
    assert_eq!(th, [("rust", "1"), ("rust", "2"), ("fortran", "1")], "{shown}");
    for r in &rows {
        assert_eq!(r["status"], "ok");
        assert_eq!(r["steps"], rows[0]["steps"]);
        for q in ["l1_rho", "l1_v", "l1_p", "l1_e"] {
            assert_eq!(r[q], rows[0][q], "bitwise the same on 1 and 2 threads and in Fortran ({q})");
        }
    }
    let md = std::fs::read_to_string(out.join("bench.md")).unwrap();
    assert!(md.contains("rust/cell/cubic ×1") && md.contains("rust/cell/cubic ×2"), "{md}");
    let js: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("bench.json")).unwrap()).expect("bench.json");
    assert_eq!(js["configurations"].as_array().map(|a| a.len()), Some(3), "one configuration per thread count");
    assert!(
        out.join("shock_tube/k1_rust_cell_cubic_t1").is_dir() && out.join("shock_tube/k1_rust_cell_cubic_t2").is_dir()
    );
}

#[test]
fn dry_run_lists_the_matrix_and_the_skipped_runs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never");
    let res = blastsph(&[
        "bench",
        "--dry-run",
        "--cases",
        "shock_tube,surface_loose_tnt6",
        "--resolutions",
        "1,2",
        "--nnps",
        "cell,direct",
        "--backends",
        "fortran",
        "--max-direct-particles",
        "1000",
        "--out",
        out.to_str().unwrap(),
    ]);
    let so = text(&res.stdout);
    assert_eq!(res.status.code(), Some(0), "{so}{}", text(&res.stderr));
    assert!(so.contains("8 runs"), "{so}");
    assert!(so.contains("| surface_loose_tnt6 | 2 | 5.0000e-3 | 40000 | 40000 |"), "{so}");
    assert_eq!(so.matches("skipped: direct search").count(), 2, "the blast's direct runs; {so}");
    assert!(!out.exists(), "a dry run writes nothing");
}

#[test]
fn bad_flags_get_one_line_and_status_2() {
    for (args, needle) in [
        (vec!["--resolutions", "0"], "--resolutions 0"),
        (vec!["--resolutions", "1,fine"], "--resolutions fine"),
        (vec!["--resolutions", "1,1"], "twice"),
        (vec!["--backends", "cobol"], "--backends cobol"),
        (vec!["--nnps", "tree"], "--nnps tree"),
        (vec!["--kernels", "lucy"], "--kernels lucy"),
        (vec!["--cases", "no_such_case"], "no_such_case"),
        (vec!["--threads", "0"], "--threads 0"),
        (vec!["--threads", "1,x"], "--threads 1,x"),
        (vec!["--threads", "1,0"], "--threads 1,0"),
        (vec!["--threads", "1,2,1"], "1 threads twice"),
        (vec!["--end-time", "-1"], "--end-time -1"),
        (vec!["--resolutions", "-2"], "--resolutions -2"),
        (vec!["--max-direct-particles", "many"], "--max-direct-particles many"),
        (vec!["--set", "sph.no_such_key=1"], "no_such_key"),
        (vec!["--resolutions", "1.01"], "region[0] (left)"),
        (vec!["--ranks", "0"], "--ranks 0"),
        (vec!["--ranks", "1,1"], "twice"),
        (vec!["--ranks", "1,2", "--threads", "1,2"], "not a list"),
    ] {
        let mut a = vec!["bench", "--dry-run"];
        a.extend(args.iter());
        let res = blastsph(&a);
        let (so, se) = (text(&res.stdout), text(&res.stderr));
        let shown = format!("{a:?}: stdout:\n{so}\nstderr:\n{se}");
        assert_eq!(res.status.code(), Some(2), "{shown}");
        assert_eq!(se.lines().count(), 1, "one line; {shown}");
        assert!(se.contains(needle), "names `{needle}`; {shown}");
        assert!(!se.contains("panicked"), "{shown}");
    }
}

/// `bench --ranks 1,2` (Open MPI refuses root without its two variables: set for this child).
#[cfg(feature = "mpi")]
#[test]
fn ranks_run_each_configuration_under_mpirun_on_each_rank_count() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bench");
    let res = Command::new(env!("CARGO_BIN_EXE_blastsph"))
        .args(["bench", "--cases", "shock_tube", "--resolutions", "1", "--backends", "rust", "--threads", "1"])
        .args(["--ranks", "1,2", "--out"])
        .arg(&out)
        .current_dir(common::root())
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .output()
        .expect("cannot start the blastsph binary");
    let shown = format!("stdout:\n{}\nstderr:\n{}", text(&res.stdout), text(&res.stderr));
    assert_eq!(res.status.code(), Some(0), "{shown}");
    let (head, rows) = read_csv(&out.join("ranks.csv"));
    assert_eq!(head, bench::RANK_COLUMNS, "{shown}");
    let np: Vec<&str> = rows.iter().map(|r| r["ranks"].as_str()).collect();
    assert_eq!(np, ["1", "2"], "{shown}");
    assert_eq!(rows[0]["steps"], rows[1]["steps"], "{shown}");
    let num = |r: &BTreeMap<String, String>, k: &str| r[k].parse::<f64>().unwrap_or(f64::NAN);
    for r in &rows {
        assert!(num(r, "wall_s") > 0.0 && num(r, "particle_steps_per_s") > 0.0, "{shown}");
    }
    // the ratio is of the two measured rates, and only split loops have gathers
    let ratio = num(&rows[1], "particle_steps_per_s") / num(&rows[0], "particle_steps_per_s");
    assert!((num(&rows[1], "speedup_vs_1") - ratio).abs() <= 1e-12 * ratio, "{shown}");
    assert_eq!(rows[0]["comm_share"], "", "one rank gathers nothing; {shown}");
    let share = num(&rows[1], "comm_share");
    assert!(share > 0.0 && share < 1.0, "2 ranks: a share of the wall time in gathers; {shown}");
    // the runs are real: 2 ranks wrote the one-rank particles bit for bit
    let run = |n: usize| out.join(format!("shock_tube/k1_rust_cell_cubic_np{n}/particles.h5"));
    assert_eq!(common::h5_bits(&run(1)), common::h5_bits(&run(2)), "{shown}");
    let md = std::fs::read_to_string(out.join("bench.md")).unwrap();
    assert!(md.contains("| shock_tube | 1 | 400 | rust/cell/cubic | 2 |"), "{md}");
}

#[test]
fn ranks_without_mpirun_get_one_line_and_status_2() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bench");
    let res = Command::new(env!("CARGO_BIN_EXE_blastsph"))
        .args(["bench", "--cases", "shock_tube", "--resolutions", "1", "--backends", "rust", "--ranks", "1,2"])
        .arg("--out")
        .arg(&out)
        .current_dir(common::root())
        .env("PATH", dir.path())
        .output()
        .expect("cannot start the blastsph binary");
    let se = text(&res.stderr);
    assert_eq!(res.status.code(), Some(2), "{se}");
    assert_eq!(se.lines().count(), 1, "{se}");
    assert!(se.contains("mpirun"), "{se}");
}
