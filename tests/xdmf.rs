//! particles.xmf against particles.h5 (docs/reference/output.md): every dataset the XDMF names exists with
//! the shape it states, one grid per H5Part step with the step's TimeValue, the interleaved views
//! equal the H5Part columns, the datasets are compressed and the zero components store nothing.
//! Runs the 1D shock tube and a short 2D surface blast (with stress).

mod common;

use std::collections::HashMap;
use std::path::Path;
use std::process::Command;

fn run(args: &[&str]) {
    let out = Command::new(env!("CARGO_BIN_EXE_blastsph")).args(args).current_dir(common::root()).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
}

/// Reads a dataset as f64 whatever its stored type (f64, i32, i64).
fn values(f: &hdf5::File, path: &str) -> Vec<f64> {
    let ds = f.dataset(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let dt = ds.dtype().unwrap();
    if dt.is::<f64>() {
        ds.read_raw::<f64>().unwrap()
    } else if dt.is::<i32>() {
        ds.read_raw::<i32>().unwrap().into_iter().map(f64::from).collect()
    } else {
        ds.read_raw::<i64>().unwrap().into_iter().map(|v| v as f64).collect()
    }
}

/// Checks the XDMF of run directory `dir`; returns the number of grids.
fn check(dir: &Path, stress: bool) -> usize {
    let text = std::fs::read_to_string(dir.join("particles.xmf")).expect("particles.xmf beside particles.h5");
    let opt = roxmltree::ParsingOptions { allow_dtd: true, ..Default::default() };
    let doc = roxmltree::Document::parse_with_options(&text, opt).expect("particles.xmf is XML");
    let f = hdf5::File::open(dir.join("particles.h5")).unwrap();
    let steps = f.member_names().unwrap().iter().filter(|n| n.starts_with("Step#")).count();
    let coll = doc
        .descendants()
        .find(|n| n.has_tag_name("Grid") && n.attribute("CollectionType") == Some("Temporal"))
        .expect("a temporal collection");
    let grids: Vec<_> = coll.children().filter(|n| n.has_tag_name("Grid")).collect();
    assert_eq!(grids.len(), steps, "one grid per H5Part step");
    for (k, g) in grids.iter().enumerate() {
        let t: f64 = g
            .children()
            .find(|n| n.has_tag_name("Time"))
            .and_then(|n| n.attribute("Value"))
            .and_then(|v| v.parse().ok())
            .expect("<Time Value>");
        let tv: f64 = f.group(&format!("Step#{k}")).unwrap().attr("TimeValue").unwrap().read_scalar().unwrap();
        assert_eq!(t.to_bits(), tv.to_bits(), "grid {k}: time {t} against TimeValue {tv}");
        let n = values(&f, &format!("Step#{k}/x")).len();
        let mut seen: HashMap<String, Vec<f64>> = HashMap::new();
        for item in g.descendants().filter(|n| n.has_tag_name("DataItem") && n.attribute("Format") == Some("HDF")) {
            let body = item.text().unwrap().trim();
            let (file, path) = body.split_once(':').expect("file:/path");
            assert_eq!(file, "particles.h5");
            let ds = f.dataset(path).unwrap_or_else(|e| panic!("{path} named by the XDMF: {e}"));
            let dims: Vec<usize> =
                item.attribute("Dimensions").unwrap().split_whitespace().map(|d| d.parse().unwrap()).collect();
            assert_eq!(ds.shape(), dims, "{path}: shape");
            assert_eq!(dims[0], n, "{path}: one row per particle");
            let prec = item.attribute("Precision").unwrap();
            assert_eq!(ds.dtype().unwrap().size().to_string(), prec, "{path}: precision");
            seen.insert(path.to_string(), values(&f, path));
        }
        let att = |name: &str| g.children().any(|c| c.has_tag_name("Attribute") && c.attribute("Name") == Some(name));
        for a in ["velocity", "rho", "p", "e", "h", "mass", "mat", "id"] {
            assert!(att(a), "grid {k}: attribute {a}");
        }
        assert_eq!(att("stress"), stress, "grid {k}: stress tensor");
        // the interleaved views hold the H5Part columns (zero where a component does not exist)
        let col = |name: &str| values(&f, &format!("Step#{k}/{name}"));
        let xyz = &seen[&format!("/xdmf/Step#{k}/xyz")];
        let vxyz = &seen[&format!("/xdmf/Step#{k}/vxyz")];
        for (c, (a, b)) in [("x", "vx"), ("y", "vy"), ("z", "vz")].iter().enumerate() {
            let (pa, pb) = (col(a), col(b));
            for i in 0..n {
                assert_eq!(xyz[3 * i + c].to_bits(), pa[i].to_bits(), "xyz[{i},{c}]");
                assert_eq!(vxyz[3 * i + c].to_bits(), pb[i].to_bits(), "vxyz[{i},{c}]");
            }
        }
        if stress {
            let s = &seen[&format!("/xdmf/Step#{k}/stress")];
            let names = ["sxx", "sxy", "sxz", "sxy", "syy", "syz", "sxz", "syz", "szz"];
            for (c, nm) in names.iter().enumerate() {
                let v = col(nm);
                for i in 0..n {
                    assert_eq!(s[9 * i + c].to_bits(), v[i].to_bits(), "stress[{i},{c}] = {nm}");
                }
            }
        }
        // topology: every particle a vertex cell (the ids are a permutation of 0..n)
        let mut ids: Vec<i64> = col("id").iter().map(|v| *v as i64).collect();
        ids.sort_unstable();
        assert_eq!(ids, (0..n as i64).collect::<Vec<_>>());
    }
    grids.len()
}

fn compressed_and_zeros_free(dir: &Path, zero: &[&str], live: &[&str]) {
    let f = hdf5::File::open(dir.join("particles.h5")).unwrap();
    let g = f.group("Step#1").unwrap();
    for name in live {
        let ds = g.dataset(name).unwrap();
        let filters = ds.filters();
        assert!(filters.iter().any(|x| matches!(x, hdf5::filters::Filter::Deflate(_))), "{name}: deflate");
        assert!(filters.iter().any(|x| matches!(x, hdf5::filters::Filter::Shuffle)), "{name}: shuffle");
        assert!(ds.chunk().is_some(), "{name}: chunked");
    }
    for name in zero {
        let ds = g.dataset(name).unwrap();
        assert_eq!(ds.storage_size(), 0, "{name} is zero by construction and stores nothing");
        assert!(ds.read_raw::<f64>().unwrap().iter().all(|v| *v == 0.0), "{name} reads as zeros");
    }
}

#[test]
fn xdmf_names_exactly_what_the_h5part_file_holds_1d() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path().join("st");
    run(&["run", "cases/shock_tube.toml", "--out", dir.to_str().unwrap(), "--quiet"]);
    assert!(check(&dir, false) >= 2);
    compressed_and_zeros_free(&dir, &["y", "z", "vy", "vz"], &["x", "vx", "rho", "p", "e", "h", "mass"]);
}

#[test]
fn xdmf_names_exactly_what_the_h5part_file_holds_2d_with_stress() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path().join("blast");
    run(&[
        "run",
        "cases/surface_loose_tnt6.toml",
        "--out",
        dir.to_str().unwrap(),
        "--quiet",
        "--end-time",
        "3e-5",
        "--set",
        "time.output_interval_s=1e-5",
    ]);
    assert!(check(&dir, true) >= 4);
    compressed_and_zeros_free(
        &dir,
        &["z", "vz", "sxz", "syz"],
        &["x", "y", "vx", "vy", "rho", "p", "sxx", "syy", "szz", "sxy", "ppv", "p_peak"],
    );
}
