//! Axisymmetric (RZ) and 3D geometry: the dual run of the compact-charge cases at 0 ULP
//! in every module it compares (the geometry module's hoop terms in RZ, the 3D walls as planes),
//! and the ring masses of an RZ case. The Sedov–Taylor blasts in RZ and 3D are in tests/verify.rs.

use blastsph::case;
use blastsph::cli;
use blastsph::modules::Module;
use blastsph::sim::Overrides;
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

/// Bad RZ and 3D input: one-line errors naming the key, no panic.
#[test]
fn rz_and_3d_bad_input_is_refused_with_one_line() {
    let gas = "[time]\nend_s = 1e-3\n[[material]]\nname = \"gas\"\neos = { kind = \"ideal_gas\", gamma = 1.4, rho0_kgm3 = 1.0 }\n";
    let cases = [
        // axisymmetric needs dim = 2
        (
            "dim = 3\ngeometry = \"axisymmetric\"\n[[region]]\nname = \"a\"\nmaterial = \"gas\"\nshape = \"box\"\nlo_m = [0, 0, 0]\nhi_m = [1, 1, 1]\nspacing_m = 0.1\n",
            "needs dim = 2",
        ),
        // x is the radius: r >= 0
        (
            "dim = 2\ngeometry = \"axisymmetric\"\n[[region]]\nname = \"a\"\nmaterial = \"gas\"\nshape = \"box\"\nlo_m = [-0.5, 0]\nhi_m = [1, 1]\nspacing_m = 0.1\n",
            "lo_m[0] = -0.5",
        ),
        // a sphere centred at r < 0 (a sign slip: a lens of a fifth of the mass, silently)
        (
            "dim = 2\ngeometry = \"axisymmetric\"\n[[region]]\nname = \"a\"\nmaterial = \"gas\"\nshape = \"sphere\"\ncenter_m = [-0.02, 0.7]\nradius_m = 0.05\nspacing_m = 0.01\n",
            "center_m[0] = -0.02",
        ),
        // a ring's mass is not given
        (
            "dim = 2\ngeometry = \"axisymmetric\"\n[[region]]\nname = \"a\"\nmaterial = \"gas\"\nshape = \"box\"\nlo_m = [0, 0]\nhi_m = [1, 1]\nspacing_m = 0.1\nmass_kg = 0.01\n",
            "mass_kg",
        ),
        // a lattice with a column on the axis: rings of zero mass
        (
            "dim = 2\ngeometry = \"axisymmetric\"\n[[region]]\nname = \"a\"\nmaterial = \"gas\"\nshape = \"lattice\"\norigin_m = [0, 0]\ncount = [5, 5]\nspacing_m = 0.1\n",
            "on the axis r = 0",
        ),
        // a wall on the axis
        (
            "dim = 2\ngeometry = \"axisymmetric\"\n[[region]]\nname = \"a\"\nmaterial = \"gas\"\nshape = \"box\"\nlo_m = [0, 0]\nhi_m = [1, 1]\nspacing_m = 0.1\n[[wall]]\nfrom_m = [0, 0]\nto_m = [0, 1]\n",
            "axis",
        ),
        // a cylinder needs 3D
        (
            "dim = 2\n[[region]]\nname = \"a\"\nmaterial = \"gas\"\nshape = \"cylinder\"\ncenter_m = [0, 0]\nradius_m = 1\nheight_m = 1\nspacing_m = 0.1\n",
            "needs dim = 3",
        ),
        // a sphere without its radius
        (
            "dim = 3\n[[region]]\nname = \"a\"\nmaterial = \"gas\"\nshape = \"sphere\"\ncenter_m = [0, 0, 0]\nspacing_m = 0.1\n",
            "radius_m: required",
        ),
        // a 3D wall that is not an axis-aligned rectangle, without edge_m
        (
            "dim = 3\n[[region]]\nname = \"a\"\nmaterial = \"gas\"\nshape = \"box\"\nlo_m = [0, 0, 0]\nhi_m = [1, 1, 1]\nspacing_m = 0.1\n[[wall]]\nfrom_m = [0, 0, 0]\nto_m = [1, 1, 1]\n",
            "axis-aligned rectangle",
        ),
        // edge_m parallel to the other edge
        (
            "dim = 3\n[[region]]\nname = \"a\"\nmaterial = \"gas\"\nshape = \"box\"\nlo_m = [0, 0, 0]\nhi_m = [1, 1, 1]\nspacing_m = 0.1\n[[wall]]\nfrom_m = [0, 0, 0]\nedge_m = [1, 0, 0]\nto_m = [2, 0, 0]\n",
            "parallelogram",
        ),
        // edge_m in 2D
        (
            "dim = 2\n[[region]]\nname = \"a\"\nmaterial = \"gas\"\nshape = \"box\"\nlo_m = [0, 0]\nhi_m = [1, 1]\nspacing_m = 0.1\n[[wall]]\nfrom_m = [0, 0]\nto_m = [1, 0]\nedge_m = [1, 0]\n",
            "only 3D walls",
        ),
    ];
    for (body, want) in cases {
        let text = format!("{body}{gas}");
        let err = case::parse(&text, "t.toml", &[], Some("t")).expect_err(want).to_string();
        assert!(err.contains(want), "want `{want}` in: {err}");
        assert!(!err.contains('\n'), "one line: {err}");
    }
}

/// `blastsph revolve` of an axisymmetric run: every ring becomes N points at its radius and
/// height, over the angle asked; the points' masses add up to that share of the rings' masses;
/// a plane run and a bad sector count are refused with exit 2.
#[test]
fn revolve_writes_the_rings_as_3d_points() {
    let d = tempfile::tempdir().unwrap();
    let run = d.path().join("run");
    let opts = blastsph::runner::RunOptions {
        out: Some(run.clone()),
        sets: [
            "region.hot.hi_m=[0.05, 0.05]",
            "region.hot.spacing_m=0.05",
            "region.ambient.spacing_m=0.05",
            "time.end_s=0.002",
            "time.output_interval_s=0.001",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect(),
        quiet: true,
        ..Default::default()
    };
    blastsph::runner::run(&case_path("verify/sedov_rz.toml"), &opts).expect("run");
    let frames = blastsph::output::read_frames(&run.join("particles.h5")).unwrap();
    let (sectors, angle) = (12usize, 270.0f64);
    let xmf = blastsph::revolve::revolve(&run, sectors, angle).expect("revolve");
    assert!(xmf.ends_with("revolved.xmf") && xmf.is_file());
    let f = hdf5::File::open(run.join("revolved.h5")).unwrap();
    for (k, fr) in frames.iter().enumerate() {
        let g = f.group(&format!("Step#{k}")).unwrap();
        let xyz: Vec<f64> = g.dataset("xyz").unwrap().read_raw().unwrap();
        let mass: Vec<f64> = g.dataset("mass").unwrap().read_raw().unwrap();
        let n = fr.x.len();
        assert_eq!(xyz.len(), 3 * n * sectors, "step {k}: points");
        for i in 0..n {
            for s in 0..sectors {
                let q = &xyz[3 * (i * sectors + s)..3 * (i * sectors + s) + 3];
                let (r, z) = (q[0].hypot(q[1]), q[2]);
                assert!((r - fr.x[i]).abs() <= 1e-12 * (1.0 + fr.x[i]) && z == fr.y[i], "step {k} ring {i}");
                let th = q[1].atan2(q[0]).rem_euclid(std::f64::consts::TAU);
                assert!(th < angle.to_radians() + 1e-12, "step {k}: angle {th} beyond {angle} degrees");
            }
        }
        let (m_pts, m_rings) = (mass.iter().sum::<f64>(), fr.mass.iter().sum::<f64>());
        assert!((m_pts / m_rings - angle / 360.0).abs() < 1e-12, "mass share {}", m_pts / m_rings);
    }
    // again into the same folder: refused (the files exist)
    assert!(blastsph::revolve::revolve(&run, sectors, angle).is_err());
    // `run --force` into the revolved run: a file blastsph did not write refuses it, and nothing
    // is removed (it removed the run's files before it found the stranger); without the
    // stranger the revolved files are blastsph's and go with the rest
    let bin = env!("CARGO_BIN_EXE_blastsph");
    let names = |d: &std::path::Path| {
        let mut v: Vec<String> =
            std::fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        v.sort();
        v
    };
    std::fs::write(run.join("notes.txt"), "mine").unwrap();
    let before = names(&run);
    let force = |extra: &[&str]| {
        let mut c = std::process::Command::new(bin);
        c.arg("run").arg(case_path("verify/sedov_rz.toml")).args(["--force", "--quiet", "--out"]).arg(&run);
        c.args(["--set", "region.hot.hi_m=[0.05, 0.05]", "--set", "region.hot.spacing_m=0.05"]);
        c.args(["--set", "region.ambient.spacing_m=0.05", "--set", "time.end_s=0.001"]).args(extra);
        c.output().unwrap()
    };
    let o = force(&[]);
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("notes.txt"));
    assert_eq!(names(&run), before, "a refused --force removed files");
    std::fs::remove_file(run.join("notes.txt")).unwrap();
    let o = force(&[]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!run.join("revolved.h5").exists() && !run.join("revolved.xmf").exists());
    blastsph::revolve::revolve(&run, sectors, angle).expect("revolve of the new run");
    // a resume makes later frames: the revolved ones of the run as it was go, as its report does
    let o = std::process::Command::new(bin)
        .arg("resume")
        .arg(&run)
        .args(["--end-time", "0.002", "--quiet"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!run.join("revolved.h5").exists() && !run.join("revolved.xmf").exists());
    blastsph::revolve::revolve(&run, sectors, angle).expect("revolve of the resumed run");
    // the CLI: a plane run and a bad sector count, one line and exit 2
    let o = std::process::Command::new(bin).args(["revolve", "--sectors", "0"]).arg(&run).output().unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    let plane = d.path().join("plane");
    let opts = blastsph::runner::RunOptions {
        out: Some(plane.clone()),
        sets: vec!["time.end_s=1e-6".into()],
        quiet: true,
        ..Default::default()
    };
    blastsph::runner::run(&case_path("verify/noh_1d.toml"), &opts).expect("plane run");
    let o = std::process::Command::new(bin).arg("revolve").arg(&plane).output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("not an axisymmetric run"), "{err}");
}

/// A disc (2D) and a ball (3D) region clipped by a box whose corner lies below the shape: every
/// node of the box's cell-centred lattice inside the shape is generated, those in the top half
/// cell of the shape's extent included (they were lost: a disc of radius 1.6 Δx about a lattice
/// corner kept 8 of its 12 nodes, the four at +1.5 Δx missing, and the energy put in it was 2/3 of
/// the intended). Counted against a brute-force scan of the same lattice.
#[test]
fn clipped_disc_and_ball_keep_every_lattice_node() {
    for (dim, rad) in [(2usize, 1.6), (2, 2.1), (2, 1.0), (3, 1.6), (3, 2.3)] {
        let dx = 0.01;
        let lo = -0.1;
        let v = |x: f64| format!("[{}]", vec![format!("{x}"); dim].join(", "));
        let text = format!(
            "dim = {dim}\n[time]\nend_s = 1e-3\n[[material]]\nname = \"gas\"\neos = {{ kind = \"ideal_gas\", gamma = 1.4 }}\n\
             [[region]]\nname = \"hot\"\nmaterial = \"gas\"\nshape = \"sphere\"\ncenter_m = {}\nradius_m = {}\n\
             lo_m = {}\nhi_m = {}\nspacing_m = {dx}\nrho_kgm3 = 1.0\ne_jkg = 1.0\n",
            v(0.0),
            rad * dx,
            v(lo),
            v(-lo)
        );
        let c = case::parse(&text, "t.toml", &[], Some("t")).expect("case parses");
        let init = blastsph::setup::particles(&c).expect("particles");
        let n = 20i32;
        let mut want = 0;
        let ks: Vec<i32> = (0..n).collect();
        for &i in &ks {
            for &j in &ks {
                for &k in if dim == 3 { &ks[..] } else { &ks[..1] } {
                    let p = [
                        lo + (f64::from(i) + 0.5) * dx,
                        lo + (f64::from(j) + 0.5) * dx,
                        lo + (f64::from(k) + 0.5) * dx,
                    ];
                    let r2: f64 = p[..dim].iter().map(|a| a * a).sum();
                    if r2 < (rad * dx) * (rad * dx) {
                        want += 1;
                    }
                }
            }
        }
        assert_eq!(init.counts[0], want, "{dim}D, radius {rad} dx: nodes inside");
    }
}

/// The first pulse of gauge `g` of a finished run: its peak over the gauge's initial pressure
/// (Pa), its arrival (s: where it first passes a tenth of that peak) and its impulse ∫ (p − p₀) dt
/// over the 100 µs from the arrival (Pa·s, trapezoids over the steps). The whole record's
/// impulse also holds the reflections from the far walls, which a square quarter and a cylinder
/// of the same size return differently; the first pulse is the same physics in both.
fn first_pulse(dir: &Path, g: &str) -> (f64, f64, f64) {
    let text = std::fs::read_to_string(dir.join("gauges.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = head.iter().position(|h| *h == format!("{g}_p_pa")).unwrap_or_else(|| panic!("no gauge {g}"));
    let rows: Vec<(f64, f64)> = lines
        .map(|l| {
            let v: Vec<&str> = l.split(',').collect();
            (v[0].parse().unwrap(), v[col].parse().unwrap())
        })
        .collect();
    let p0 = rows[0].1;
    let peak = rows.iter().map(|r| r.1 - p0).fold(f64::MIN, f64::max);
    let k = rows.iter().position(|r| r.1 - p0 > 0.1 * peak).expect("the pulse arrives");
    let t0 = rows[k].0;
    let mut imp = 0.0;
    for w in rows[k..].windows(2).take_while(|w| w[1].0 <= t0 + 1.0e-4) {
        imp += 0.5 * (w[0].1 + w[1].1 - 2.0 * p0) * (w[1].0 - w[0].0);
    }
    (peak, t0, imp)
}

/// The compact 1 kg charge in RZ and in 3D (the quarter), same soil box, charge and gauges, at
/// spacing `dx` to 500 µs, on the loose sand (`surface_loose_tnt1kg_rz_box.toml`,
/// `surface_loose_tnt1kg_3d.toml`) or the dense (`surface_dense_tnt1kg_rz.toml`,
/// `surface_dense_tnt1kg_3d.toml`): per gauge (A, C on the axis; G1, G2, S2 off it) the RZ/3D − 1
/// of the first pulse's peak, arrival and impulse, and of the crater's diameter and depth.
fn rz_against_3d(dx: f64, dense: bool) -> (Vec<(String, [f64; 3])>, [f64; 2]) {
    use blastsph::runner::{RunOptions, run};
    let dirs = tempfile::tempdir().unwrap();
    let mut out = Vec::new();
    let pair = if dense {
        [("surface_dense_tnt1kg_rz.toml", "rz"), ("surface_dense_tnt1kg_3d.toml", "3d")]
    } else {
        [("surface_loose_tnt1kg_rz_box.toml", "rz"), ("surface_loose_tnt1kg_3d.toml", "3d")]
    };
    let sand = if dense { "dense" } else { "loose" };
    for (name, tag) in pair {
        let sets: Vec<String> = vec![
            "time.end_s=5e-4".into(),
            format!("region.soil.spacing_m={dx}"),
            format!("region.charge.spacing_m={dx}"),
        ];
        let opts = RunOptions { out: Some(dirs.path().join(tag)), sets, quiet: true, ..Default::default() };
        let r = run(&case_path(name), &opts).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(r.summary["status"], "ok", "{name}");
        out.push(r);
    }
    let mut gauges = Vec::new();
    for g in ["A", "C", "G1", "G2", "S2"] {
        let (a, b) = (first_pulse(&out[0].dir, g), first_pulse(&out[1].dir, g));
        let d = [a.0 / b.0 - 1.0, a.1 / b.1 - 1.0, a.2 / b.2 - 1.0];
        eprintln!(
            "{sand} dx {dx}: gauge {g:2}: peak {:.1} / {:.1} MPa ({:+.1} %), arrival {:.1} / {:.1} µs ({:+.1} %), 100 µs impulse {:.2} / {:.2} kPa·s ({:+.1} %)",
            a.0 / 1e6,
            b.0 / 1e6,
            100.0 * d[0],
            a.1 * 1e6,
            b.1 * 1e6,
            100.0 * d[1],
            a.2 / 1e3,
            b.2 / 1e3,
            100.0 * d[2]
        );
        gauges.push((g.to_string(), d));
    }
    let num = |v: &serde_json::Value, what: &str| v.as_f64().unwrap_or_else(|| panic!("no crater {what}: {v}"));
    let (rz, d3) = (&out[0].summary["crater"], &out[1].summary["crater"]);
    // the 3D crater's diameter as the map's equivalent diameter (the mean of a crater that is
    // not round on the cubic lattice); the revolution measure reads its narrowest direction
    let (drz, d3d) = (num(&rz["diameter_m"], "diameter"), num(&d3["surface"]["equivalent_diameter_m"], "surface"));
    let d3rev = num(&d3["diameter_m"], "diameter");
    let (hrz, h3d) = (num(&rz["depth_m"], "depth"), num(&d3["depth_m"], "depth"));
    let c = [drz / d3d - 1.0, hrz / h3d - 1.0];
    eprintln!(
        "{sand} dx {dx}: crater diameter RZ {:.1} cm, 3D {:.1} cm (map's equivalent; revolution {:.1}) {:+.1} %, depth {:.1} / {:.1} cm {:+.1} %",
        100.0 * drz,
        100.0 * d3d,
        100.0 * d3rev,
        100.0 * c[0],
        100.0 * hrz,
        100.0 * h3d,
        100.0 * c[1]
    );
    (gauges, c)
}

/// Tolerances of an RZ–3D comparison: the first pulses' peak, arrival and impulse, the crater's
/// diameter and depth (each |RZ/3D − 1|).
struct Within {
    peak: f64,
    arrival: f64,
    impulse: f64,
    diameter: f64,
    depth: f64,
}

/// `rz_against_3d(dx, dense)` within the tolerances `w`.
fn assert_rz_3d_within(dx: f64, dense: bool, w: &Within) -> (Vec<(String, [f64; 3])>, [f64; 2]) {
    let (gauges, crater) = rz_against_3d(dx, dense);
    for (g, d) in &gauges {
        assert!(d[0].abs() < w.peak, "dx {dx}, gauge {g}: peak RZ/3D − 1 = {:.3}", d[0]);
        assert!(d[1].abs() < w.arrival, "dx {dx}, gauge {g}: arrival RZ/3D − 1 = {:.3}", d[1]);
        assert!(d[2].abs() < w.impulse, "dx {dx}, gauge {g}: impulse RZ/3D − 1 = {:.3}", d[2]);
    }
    assert!(crater[0].abs() < w.diameter && crater[1].abs() < w.depth, "dx {dx}: crater RZ/3D − 1: {crater:?}");
    (gauges, crater)
}

/// At 23 and 11.5 mm: the largest first-pulse impulse difference shrinks, the crater's diameter
/// difference grows by no more than 2 points (loose −0.7 → +1.5 %, dense +8.0 → +5.8 %), and the
/// 11.5 mm comparison is within `fine`.
fn assert_rz_3d_converge(dense: bool, fine: &Within) {
    let worst = |v: &[(String, [f64; 3])]| v.iter().map(|(_, d)| d[2].abs()).fold(0.0, f64::max);
    let (g0, c0) = rz_against_3d(0.023, dense);
    let (g1, c1) = assert_rz_3d_within(0.0115, dense, fine);
    assert!(worst(&g1) < worst(&g0), "impulse difference {} → {}", worst(&g0), worst(&g1));
    assert!(c1[0].abs() <= c0[0].abs() + 0.02, "crater diameter difference {} → {}", c0[0], c1[0]);
}

/// RZ against 3D at 23 mm (docs/validation.md, "RZ against 3D"): measured there, the first
/// pulses' peaks −4.7 % … +11.6 %, arrivals −5.0 … −9.0 %, impulses −14.9 % … +14.5 %, the crater
/// diameter −0.7 % (against the 3D map's equivalent diameter) and depth −3.8 % (−0.9 % before the
/// axis remedy gave the rings next to the axis their images' work: the RZ pit on the axis is
/// shallower); asserted with margins of 1–2 points.
#[test]
fn rz_and_3d_compact_charge_agree_at_23_mm() {
    let w = Within { peak: 0.13, arrival: 0.09, impulse: 0.16, diameter: 0.02, depth: 0.05 };
    assert_rz_3d_within(0.023, false, &w);
}

/// The same at 23 and 11.5 mm (the 3D run at 11.5 mm is 1.1 × 10⁵ particles, about 3 minutes):
/// the largest first-pulse impulse difference shrinks (measured 14.9 % → 5.7 %) and is within 7 %
/// at 11.5 mm; the arrivals within 5 %; the crater within 5 % (measured −0.7 → +1.5 % / +3.6 %;
/// the depth was +7.0 % before the 3D revolution measure's pit test took the column's ±Δs band).
/// The peaks do not converge to each other (−4.7 … +11.4 % → −13.5 … −3.2 %, the 3D higher on
/// the axis; neither is converged: docs/validation.md), asserted only within 15 %.
#[test]
#[ignore]
fn rz_and_3d_compact_charge_agreement_shrinks_with_resolution() {
    assert_rz_3d_converge(false, &Within { peak: 0.15, arrival: 0.05, impulse: 0.07, diameter: 0.05, depth: 0.05 });
}

/// RZ against 3D on the dense sand at 23 mm (`surface_dense_tnt1kg_rz.toml`,
/// `surface_dense_tnt1kg_3d.toml`; docs/validation.md "RZ against 3D"): measured there, the first
/// pulses' peaks −0.4 % … +12.6 %, arrivals −5.9 … −9.6 %, impulses −7.6 … +13.0 %, the crater
/// diameter +8.0 % (against the 3D map's equivalent diameter; 2 spacings per charge radius) and
/// depth −3.7 %; asserted with margins of 1–2 points.
#[test]
fn rz_and_3d_compact_charge_on_dense_sand_agree_at_23_mm() {
    let w = Within { peak: 0.14, arrival: 0.11, impulse: 0.14, diameter: 0.10, depth: 0.05 };
    assert_rz_3d_within(0.023, true, &w);
}

/// The dense sand at 23 and 11.5 mm: the largest impulse difference shrinks (measured 13.0 % →
/// 6.3 %) and is within 7 % at 11.5 mm, the arrivals within 5 % (4.0 %), the crater's diameter
/// difference shrinks (+8.0 % → +5.8 %) and is within 7 %, its depth within 5 % (+0.4 %); the peaks
/// do not converge to each other (−0.4 … +12.6 % → −12.0 … −2.0 %, the 3D higher on the axis, as
/// on the loose sand): asserted only within 14 %.
#[test]
#[ignore]
fn rz_and_3d_compact_charge_on_dense_sand_agreement_shrinks_with_resolution() {
    assert_rz_3d_converge(true, &Within { peak: 0.14, arrival: 0.05, impulse: 0.07, diameter: 0.07, depth: 0.05 });
}

/// A case of one gas with the regions `regions` (TOML text) in `dim` dimensions (`geometry`
/// "plane" or "axisymmetric").
fn gas_case(dim: usize, geometry: &str, regions: &str) -> String {
    format!(
        "dim = {dim}\ngeometry = \"{geometry}\"\n[time]\nend_s = 1e-3\n[[material]]\nname = \"gas\"\n\
         eos = {{ kind = \"ideal_gas\", gamma = 1.4, rho0_kgm3 = 1.0 }}\n{regions}"
    )
}

/// A box region `name` of the gas over [0, 1]^dim at Δx = 0.05 (20 cells an axis), with extra
/// keys `more` (a `keep_below`, a `subtract`).
fn unit_box(name: &str, dim: usize, more: &str) -> String {
    let v = |x: f64| format!("[{}]", vec![format!("{x}"); dim].join(", "));
    format!(
        "[[region]]\nname = \"{name}\"\nmaterial = \"gas\"\nshape = \"box\"\nlo_m = {}\nhi_m = {}\nspacing_m = 0.05\n{more}\n",
        v(0.0),
        v(1.0)
    )
}

/// The cells of the unit box's 20^3 lattice (centres (i + 1/2) Δx, Δx = 0.05) under the plane
/// n·(x − p) = 0 with n_z > 0, counted column by column: in column (i, j) the plane stands at
/// z_max = p_z − (n_x (x − p_x) + n_y (y − p_y))/n_z, and the column keeps the k = 0 … 19 with
/// (k + 1/2) Δx ≤ z_max, i.e. min(20, max(0, ⌊z_max/Δx − 1/2⌋ + 1)) of them.
fn cells_under(p: [f64; 3], n: [f64; 3]) -> usize {
    let dx = 0.05;
    let mut count = 0;
    for i in 0..20 {
        for j in 0..20 {
            let (x, y) = ((f64::from(i) + 0.5) * dx, (f64::from(j) + 0.5) * dx);
            let zmax = p[2] - (n[0] * (x - p[0]) + n[1] * (y - p[1])) / n[2];
            count += ((zmax / dx - 0.5).floor() + 1.0).clamp(0.0, 20.0) as usize;
        }
    }
    count
}

/// `keep_below` clips a region's lattice to the half-spaces (x − point_m)·n ≤ 0: counted
/// against the plane's own column formula (an inclined plane through no lattice node), against
/// counts exact by construction (a 45° plane x + y ≤ 10.5 Δx keeps the 55 columns with
/// i + j ≤ 9; a ridge of two planes keeps 110 columns' worth), in 3D, 2D, RZ (the plane a cone
/// there, its rings' mass summed by hand) and 1D, and a disc halved; every particle kept lies on
/// the kept side.
#[test]
fn keep_below_clips_any_region_to_its_half_spaces() {
    let count = |text: &str| -> Vec<usize> {
        let c = case::parse(text, "t.toml", &[], Some("t")).unwrap_or_else(|e| panic!("{e}\n{text}"));
        blastsph::setup::particles(&c).expect("particles").counts
    };
    // an inclined plane, normal (1, 2, 3) (not unit: it is normalised), through no node
    let (p, n) = ([0.5, 0.5, 0.5123], [1.0, 2.0, 3.0]);
    let want = cells_under(p, n);
    assert!(want > 1000 && want < 7000, "a real cut: {want} of 8000");
    let plane = format!("keep_below = [{{ point_m = {p:?}, normal = {n:?} }}]");
    let c = case::parse(&gas_case(3, "plane", &unit_box("a", 3, &plane)), "t.toml", &[], Some("t")).unwrap();
    let init = blastsph::setup::particles(&c).expect("particles");
    assert_eq!(init.counts, [want], "inclined plane: the column formula");
    for q in init.x.chunks(3) {
        let s: f64 = (0..3).map(|a| n[a] * (q[a] - p[a])).sum();
        assert!(s <= 0.0, "a particle at {q:?} above the plane ({s})");
    }
    // the mirror image of that plane through the box's centre keeps as many
    let (pm, nm) = ([0.5, 0.5, 1.0 - 0.5123], [-1.0, -2.0, -3.0]);
    let mirrored = format!("keep_below = [{{ point_m = {pm:?}, normal = {nm:?} }}]");
    assert_eq!(count(&gas_case(3, "plane", &unit_box("a", 3, &mirrored))), [want], "mirrored plane");
    // x + y <= 10.5 dx: columns with i + j <= 9, 55 of them, each 20 cells tall
    let diag = "keep_below = [{ point_m = [0.525, 0.0, 0.0], normal = [1.0, 1.0, 0.0] }]";
    assert_eq!(count(&gas_case(3, "plane", &unit_box("a", 3, diag))), [55 * 20], "45-degree plane");
    // a ridge: z <= 0.525 - |x - 0.5|, two planes; row i keeps floor(10 - |i - 9.5|) + 1 cells
    let ridge = "keep_below = [{ point_m = [0.5, 0.0, 0.525], normal = [1.0, 0.0, 1.0] },\n\
                 { point_m = [0.5, 0.0, 0.525], normal = [-1.0, 0.0, 1.0] }]";
    assert_eq!(count(&gas_case(3, "plane", &unit_box("a", 3, ridge))), [110 * 20], "a ridge of two planes");
    // 2D plane and RZ (there the line r + z = 10.5 dx revolves into a cone): 55 cells
    let diag2 = "keep_below = [{ point_m = [0.525, 0.0], normal = [1.0, 1.0] }]";
    assert_eq!(count(&gas_case(2, "plane", &unit_box("a", 2, diag2))), [55], "2D");
    let c = case::parse(&gas_case(2, "axisymmetric", &unit_box("a", 2, diag2)), "t.toml", &[], Some("t")).unwrap();
    let init = blastsph::setup::particles(&c).expect("particles");
    assert_eq!(init.counts, [55], "RZ");
    // the cone's rings: a ring at r_i holds 2 pi r_i rho dx^2, and column i keeps 10 - i rings
    let want_mass: f64 = (0..10)
        .map(|i| f64::from(10 - i) * 2.0 * std::f64::consts::PI * (f64::from(i) + 0.5) * 0.05 * 0.05 * 0.05)
        .sum();
    let mass: f64 = init.mass.iter().sum();
    assert!((mass / want_mass - 1.0).abs() < 1e-12, "RZ cone mass {mass} against {want_mass}");
    // 1D: a lattice of 20 points at (k + 1/2) 0.05 keeping x >= 0.3 (normal -1): k = 6 ... 19
    let lat = "[[region]]\nname = \"a\"\nmaterial = \"gas\"\nshape = \"lattice\"\norigin_m = [0.025]\ncount = [20]\n\
               spacing_m = 0.05\nkeep_below = [{ point_m = [0.3], normal = [-2.0] }]\n";
    assert_eq!(count(&gas_case(1, "plane", lat)), [14], "1D");
    // a sphere cut in half by a plane through its centre: the disc of radius 0.3 about (0.5, 0.5)
    // on the 2D lattice keeps the nodes with y < 0.5, half of them (no node on y = 0.5)
    let disc = |more: &str| {
        format!(
            "[[region]]\nname = \"a\"\nmaterial = \"gas\"\nshape = \"sphere\"\ncenter_m = [0.5, 0.5]\nradius_m = 0.3\n\
             lo_m = [0.0, 0.0]\nhi_m = [1.0, 1.0]\nspacing_m = 0.05\n{more}\n"
        )
    };
    let whole = count(&gas_case(2, "plane", &disc("")))[0];
    let half = count(&gas_case(2, "plane", &disc("keep_below = [{ point_m = [0.5, 0.5], normal = [0.0, 1.0] }]")))[0];
    assert!(whole > 100 && whole % 2 == 0 && half * 2 == whole, "half disc {half} of {whole}");
}

/// `cases/slope_3d.toml`: its ground is the box clipped by the 30° plane through the crest, so
/// its soil count is the plane's column formula less the half charge it makes room for (a half
/// disc of radius 4 Δx about a cell corner: 26 cells, 8 layers); a few steps run with status ok.
/// The charge's own mass warning goes once the charge is clipped by a plane (its shape's mass is
/// then not known).
#[test]
fn slope_3d_case_is_the_clipped_box_and_runs() {
    let c = case::load(&case_path("slope_3d.toml"), &[]).expect("case loads");
    let init = blastsph::setup::particles(&c).expect("particles");
    let dx = 0.0115;
    let (x_crest, top, tan) = (40.0 * dx, 36.0 * dx, 30f64.to_radians().tan());
    let mut columns = 0;
    for i in 0..76 {
        let zmax = top - ((f64::from(i) + 0.5) * dx - x_crest) * tan;
        columns += ((zmax / dx - 0.5).floor() + 1.0).clamp(0.0, 36.0) as usize;
    }
    let half_disc = (-4..4).flat_map(|i| (0..4).map(move |j| (i, j))).filter(|&(i, j)| {
        let (u, v) = (f64::from(i) + 0.5, f64::from(j) + 0.5);
        u * u + v * v < 16.0
    });
    let charge = 8 * half_disc.count();
    assert_eq!(charge, 208);
    assert_eq!(init.counts, [charge, 33 * columns - charge], "charge and soil particles");
    assert!(init.counts.iter().sum::<usize>() <= 80_000);

    let bin = env!("CARGO_BIN_EXE_blastsph");
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("run");
    let o = std::process::Command::new(bin)
        .arg("run")
        .arg(case_path("slope_3d.toml"))
        .args(["--end-time", "3e-6", "--threads", "1", "--quiet", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let s: Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["status"], "ok", "{s}");
    assert!(s["steps"].as_u64().unwrap() >= 3, "{}", s["steps"]);
    assert_eq!(s["particles"].as_u64(), Some(33 * columns as u64));
    // the report says the crater of revolution misreads ground that is not level: the map's
    // relief of the original ground within twice the crater's edge of the axis (at 3 µs the
    // charge's pit, its edge a few spacings out, reaches over the crest line onto the face: 3 Δx
    // of fall measured) is more than a cell
    let o = std::process::Command::new(bin).arg("report").arg(&out).output().unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{text}{}", String::from_utf8_lossy(&o.stderr));
    assert!(text.lines().any(|l| l.starts_with("note: the original ground is not level about the charge")), "{text}");
    let r: Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let relief = r["crater"]["surface"]["ground_relief_m"].as_f64().unwrap_or_else(|| panic!("{}", r["crater"]));
    assert!(relief > 1.5 * dx, "relief {relief}");

    // without its mass_kg the half charge holds 3.4 % more than its half cylinder: check warns;
    // clipped by a plane (one above it all, which keeps every particle) it does not
    let text = std::fs::read_to_string(case_path("slope_3d.toml")).unwrap();
    let bare: String = text.lines().filter(|l| !l.starts_with("mass_kg")).map(|l| format!("{l}\n")).collect();
    assert!(bare.len() < text.len());
    let check = |body: &str| {
        let f = d.path().join("slope.toml");
        std::fs::write(&f, body).unwrap();
        let o = std::process::Command::new(bin).arg("check").arg(&f).output().unwrap();
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned() + &String::from_utf8_lossy(&o.stderr)
    };
    let warned = check(&bare);
    assert!(warned.contains("region charge (tnt)") && warned.contains("+3.4 %"), "{warned}");
    let clipped = bare.replace(
        "spacing_m = 0.0115\n\n[[region]]\nname = \"soil\"",
        "spacing_m = 0.0115\nkeep_below = [{ point_m = [0.0, 0.0, 1.0], normal = [0.0, 0.0, 1.0] }]\n\n[[region]]\nname = \"soil\"",
    );
    assert_ne!(clipped, bare);
    let quiet = check(&clipped);
    assert!(quiet.contains("tnt 208") && !quiet.contains("region charge (tnt)"), "{quiet}");
}

/// Bad `keep_below` input: `blastsph check` refuses it with exit status 2 and one line naming
/// the region and the key (an unknown key inside a plane: the line of the file and the key, as
/// every unknown key), never a panic.
#[test]
fn keep_below_bad_input_is_refused_with_one_line() {
    let bin = env!("CARGO_BIN_EXE_blastsph");
    let d = tempfile::tempdir().unwrap();
    let cases = [
        (
            "{ point_m = [0.5, 0.5], normal = [0.0, 0.0, 1.0] }",
            "region[0] (a).keep_below[0].point_m: needs 3 components, got 2",
        ),
        (
            "{ point_m = [0.5, 0.5, 0.5], normal = [0.0, 1.0] }",
            "region[0] (a).keep_below[0].normal: needs 3 components, got 2",
        ),
        (
            "{ point_m = [0.5, 0.5, 0.5], normal = [0.0, 0.0, 0.0] }",
            "region[0] (a).keep_below[0].normal = [0, 0, 0]: a zero vector",
        ),
        ("{ point_m = [0.5, 0.5, 0.5], normal = [0.0, nan, 1.0] }", "region[0] (a).keep_below[0].normal[1] = NaN"),
        ("{ point_m = [0.5, 0.5, 0.5], normal = [0.0, 0.0, inf] }", "region[0] (a).keep_below[0].normal[2] = inf"),
        (
            "{ point_m = [0.5, 0.5, 0.5], normal = [1e200, 0.0, 1e200] }",
            "region[0] (a).keep_below[0].normal = [1e200, 0, 1e200]: too long",
        ),
        (
            "{ point_m = [0.5, 0.5, 0.5], normal = [0.0, 0.0, 1e-170] }",
            "region[0] (a).keep_below[0].normal = [0, 0, 1e-170]: too short",
        ),
        ("{ point_m = [0.5, 0.5, -inf], normal = [0.0, 0.0, 1.0] }", "region[0] (a).keep_below[0].point_m[2] = -inf"),
        ("{ point_m = [0.5, 0.5, 0.5] }", "missing field `normal`"),
        ("{ point_m = [0.5, 0.5, 0.5], normal = [0.0, 0.0, 1.0], colour = 1 }", "t.toml:16: unknown field `colour`"),
        // the plane keeps nothing of the box: its normal is the wrong way round
        (
            "{ point_m = [0.5, 0.5, 1.0], normal = [0.0, 0.0, -1.0] }",
            "region[0] (a).keep_below: the planes leave none of the shape's 8000 lattice points",
        ),
    ];
    for (plane, want) in cases {
        let f = d.path().join("t.toml");
        let body = gas_case(3, "plane", &unit_box("a", 3, &format!("keep_below = [\n  {plane}\n]")));
        std::fs::write(&f, &body).unwrap();
        let o = std::process::Command::new(bin).arg("check").arg(&f).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{plane}: {err}");
        assert_eq!(err.lines().count(), 1, "{plane}: one line: {err}");
        assert!(err.contains(want), "{plane}: want `{want}` in: {err}");
        assert!(!err.contains("panick"), "{err}");
    }
}

/// Regions that meet along a plane: a box kept below an inclined plane and the same box kept
/// above it (the normal reversed) are two regions with no `subtract` that together fill the
/// box, each point once; moving the upper one's plane down a spacing (by `--set` into the
/// plane) makes them overlap, refused; a box that subtracts the clipped box loses only the
/// points under the plane.
#[test]
fn keep_below_regions_meet_along_their_plane() {
    let (p, n) = ([0.5, 0.5, 0.5123], [1.0, 2.0, 3.0]);
    let below = cells_under(p, n);
    let neg = n.map(|c| -c);
    let two = format!(
        "{}{}",
        unit_box("low", 3, &format!("keep_below = [{{ point_m = {p:?}, normal = {n:?} }}]")),
        unit_box("high", 3, &format!("keep_below = [{{ point_m = {p:?}, normal = {neg:?} }}]"))
    );
    let text = gas_case(3, "plane", &two);
    let c = case::parse(&text, "t.toml", &[], Some("t")).expect("case parses");
    let init = blastsph::setup::particles(&c).expect("two regions along a plane are no overlap");
    assert_eq!(init.counts, [below, 8000 - below]);
    // the upper region's plane a spacing lower: the two share a band of points
    let lower = "region.high.keep_below.0.point_m=[0.5, 0.5, 0.4623]".to_string();
    let c = case::parse(&text, "t.toml", &[lower], Some("t")).expect("case parses");
    let err = blastsph::setup::particles(&c).expect_err("overlap").to_string();
    assert!(err.contains("region[0] (low) overlaps region[1] (high)") && !err.contains('\n'), "{err}");
    // the upper region raised a spacing instead: a gap between them, no overlap
    let raised = "region.high.keep_below.0.point_m=[0.5, 0.5, 0.5623]".to_string();
    let c = case::parse(&text, "t.toml", &[raised], Some("t")).expect("case parses");
    let init = blastsph::setup::particles(&c).expect("a gap is no overlap");
    assert_eq!(init.counts, [below, 8000 - cells_under([0.5, 0.5, 0.5623], n)]);
    // subtract: the whole box less the clipped box is the part above the plane
    let cut = format!(
        "{}{}",
        unit_box("host", 3, "subtract = [\"cut\"]"),
        unit_box("cut", 3, &format!("keep_below = [{{ point_m = {p:?}, normal = {n:?} }}]"))
    );
    let c = case::parse(&gas_case(3, "plane", &cut), "t.toml", &[], Some("t")).expect("case parses");
    let init = blastsph::setup::particles(&c).expect("particles");
    assert_eq!(init.counts, [8000 - below, below], "subtract removes only the clipped shape's points");
}
