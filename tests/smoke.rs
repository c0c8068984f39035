//! Every case in cases/ (and cases/hard/, cases/verify/) runs a few steps with the Fortran backend and stays
//! finite with its mass exact, and the Rust backend gives the same bits. (The dual runs over the blast scenes are in tests/dual.rs.)

use blastsph::case;
use blastsph::sim::{Overrides, Sim};
use std::path::{Path, PathBuf};

fn case_files() -> Vec<PathBuf> {
    let mut v = Vec::new();
    for dir in ["cases", "cases/hard", "cases/verify"] {
        let d = Path::new(env!("CARGO_MANIFEST_DIR")).join(dir);
        if let Ok(rd) = std::fs::read_dir(&d) {
            for e in rd.flatten() {
                let p = e.path();
                if p.extension().and_then(|s| s.to_str()) == Some("toml") {
                    v.push(p);
                }
            }
        }
    }
    v.sort();
    v
}

#[test]
fn every_case_runs_a_few_steps() {
    let files = case_files();
    assert!(files.len() >= 14, "expected the thesis scenes in cases/, found {}", files.len());
    for f in files {
        let c = case::load(&f, &[]).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        let fortran = Overrides { backend: Some(blastsph::modules::Backend::Fortran), ..Default::default() };
        let mut sim = Sim::new(c, &fortran).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        let m0 = sim.total_mass();
        let x0 = sim.p.x.clone();
        for _ in 0..3 {
            sim.step().unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        }
        let n = sim.p.nreal;
        assert_eq!(sim.total_mass(), m0, "{}: mass changed", f.display());
        assert!(sim.t > 0.0, "{}: time did not advance", f.display());
        assert!(sim.p.x[..sim.cfg.dim * n].iter().all(|v| v.is_finite()), "{}", f.display());
        assert!(sim.p.x[..sim.cfg.dim * n] != x0[..sim.cfg.dim * n], "{}: nothing moved", f.display());
        // the Rust backend from the same start gives the same bits
        let c = case::load(&f, &[]).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        let rust = Overrides { backend: Some(blastsph::modules::Backend::Rust), ..Default::default() };
        let mut r = Sim::new(c, &rust).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        for _ in 0..3 {
            r.step().unwrap_or_else(|e| panic!("{} (rust): {e}", f.display()));
        }
        let (a, b) = (&sim.p, &r.p);
        assert_eq!(r.t.to_bits(), sim.t.to_bits(), "{}: time differs between backends", f.display());
        let dn = sim.cfg.dim * n;
        assert_eq!(r.p.nreal, n, "{}: particle counts differ between backends", f.display());
        for (name, u, w, len) in [
            ("x", &a.x, &b.x, dn),
            ("v", &a.v, &b.v, dn),
            ("rho", &a.rho, &b.rho, n),
            ("e", &a.e, &b.e, n),
            ("h", &a.h, &b.h, n),
        ] {
            assert!(u.len() >= len && w.len() >= len, "{}: {name} is shorter than the particles", f.display());
            assert!(
                u[..len].iter().zip(&w[..len]).all(|(p, q)| p.to_bits() == q.to_bits()),
                "{}: {name} differs between the Fortran and Rust backends after 3 steps",
                f.display()
            );
        }
    }
}
