//! ParaView opens a run: `pvpython tests/paraview_check.py` (Debian's python3-paraview) on the
//! particles.xmf of a short surface blast, through `OpenDataFile` (the reader ParaView picks for
//! .xmf) and the older XDMF reader: every output step, every particle, a 3-component velocity
//! and the stress tensor. Needs pvpython, so it is `#[ignore]`d; run it with
//! `cargo test --release --test paraview -- --ignored` (README).

mod common;

use std::process::Command;

#[test]
#[ignore = "needs pvpython (Debian package python3-paraview)"]
fn paraview_opens_particles_xmf_of_the_surface_blast() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path().join("blast");
    let out = Command::new(env!("CARGO_BIN_EXE_blastsph"))
        .args(["run", "cases/surface_loose_tnt6.toml", "--quiet", "--end-time", "1e-4", "--out"])
        .arg(&dir)
        .current_dir(common::root())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let (steps, n) = (s["outputs"].as_u64().unwrap(), s["particles"].as_u64().unwrap());
    let pv = Command::new("pvpython")
        .arg(common::root().join("tests/paraview_check.py"))
        .arg(&dir)
        .arg(steps.to_string())
        .arg(n.to_string())
        .arg("1")
        .current_dir(d.path())
        .output()
        .expect("pvpython not found: apt-get install python3-paraview");
    let so = String::from_utf8_lossy(&pv.stdout);
    println!("{so}");
    assert_eq!(pv.status.code(), Some(0), "{so}\n{}", String::from_utf8_lossy(&pv.stderr));
    assert!(so.contains("paraview: all checks passed"), "{so}");
}
