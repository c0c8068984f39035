//! The verification problems of `cases/verify/` against their exact solutions
//! (`src/analysis/{sedov,noh,cj}.rs`), at the default settings, as docs/validation.md
//! ("Verification problems") reports them. The short versions run in the normal test run; the
//! full ones are ignored and run by name:
//!
//! ```sh
//! cargo test --release --test verify -- --ignored --nocapture
//! ```
//!
//! Every bound below is the measured value of docs/validation.md with a stated margin, or the
//! acceptance bound the project set where that is tighter (called "required" below).

use blastsph::runner::{RunOptions, run};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn case(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/verify").join(format!("{name}.toml"))
}

/// Runs a verification case with `sets`; returns its summary.json (status ok asserted).
fn run_case(name: &str, sets: &[String]) -> Value {
    let dir = tempfile::tempdir().unwrap();
    let opts = RunOptions { out: Some(dir.path().join("run")), sets: sets.to_vec(), quiet: true, ..Default::default() };
    let r = run(&case(name), &opts).unwrap_or_else(|e| panic!("{name} {sets:?}: {e}"));
    assert_eq!(r.summary["status"], "ok", "{name}");
    r.summary
}

fn sets(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

fn num(v: &Value, k: &str) -> f64 {
    v["verification"][k].as_f64().unwrap_or_else(|| panic!("no {k} in {}", v["verification"]))
}

/// Sets for `cases/verify/sedov_2d_g*.toml` at `n` × `n` particles on its box (dx = 1/n m): the
/// hot region the particles within `half` spacings of the centre along each axis (1: the four
/// about the corner of an even lattice; 0.5: the one at the centre of an odd one), at `e` J/kg.
fn sedov_2d_sets(n: u32, half: f64, e: f64) -> Vec<String> {
    let dx = 1.0 / n as f64;
    vec![
        format!("region.ambient.spacing_m={dx}"),
        format!("region.hot.spacing_m={dx}"),
        format!("region.hot.lo_m=[{}, {}]", -half * dx, -half * dx),
        format!("region.hot.hi_m=[{}, {}]", half * dx, half * dx),
        format!("region.hot.e_jkg={e}"),
    ]
}

/// The detonation's front pressure over p_CJ at the report's outputs (every tenth of the run),
/// and the report, for the slab at spacing `dx` run over `travel` spacings.
fn slab(dx: f64, h_over_dx: f64, travel: f64, extra: &[&str]) -> (Vec<f64>, Value) {
    slab_of(&case("tnt_slab_1d"), dx, h_over_dx, travel, extra)
}

fn slab_of(path: &Path, dx: f64, h_over_dx: f64, travel: f64, extra: &[&str]) -> (Vec<f64>, Value) {
    let t = travel * dx / 6930.0;
    let mut s = sets(&[
        &format!("region.slab.spacing_m={dx}"),
        &format!("region.slab.hi_m=[{}]", dx * (travel + 100.0)),
        &format!("time.end_s={t}"),
        &format!("time.output_interval_s={}", t / 10.0),
        &format!("sph.h_over_dx={h_over_dx}"),
    ]);
    s.extend(sets(extra));
    let dir = tempfile::tempdir().unwrap();
    let opts = RunOptions { out: Some(dir.path().join("run")), sets: s.clone(), quiet: true, ..Default::default() };
    let r = run(path, &opts).unwrap_or_else(|e| panic!("slab {s:?}: {e}"));
    let rep = blastsph::report::report(&r.dir).expect("report");
    let hist: Vec<f64> =
        rep["history"].as_array().unwrap().iter().map(|h| h["peak_p_ratio"].as_f64().unwrap()).collect();
    // summary.json's history is the report's: every output, not the end state alone
    let sum: Vec<f64> = r.summary["verification"]["history"]
        .as_array()
        .unwrap()
        .iter()
        .map(|h| h["peak_p_ratio"].as_f64().unwrap())
        .collect();
    assert_eq!(sum, hist, "summary.json's history against the report's");
    assert!(hist.len() >= 5, "{} outputs in the history", hist.len());
    (hist, rep)
}

#[test]
fn noh_1d_post_shock_state_and_shock_position() {
    let s = run_case("noh_1d", &[]);
    let (rho, r) = (num(&s, "post_shock_density_ratio"), num(&s, "shock_radius_half_ratio"));
    eprintln!("noh 1D: rho2 ratio {rho:.4}, shock {r:.4}, wall heating {:.3}", num(&s, "wall_heating_e_excess"));
    assert!((rho - 1.0).abs() < 0.03, "post-shock density {rho} of the exact 4");
    assert!((r - 1.0).abs() < 0.03, "shock radius {r} of the exact 0.2 m");
    assert_eq!(num(&s, "negative_e_count"), 0.0);
}

#[test]
fn wall_reflection_1d_reflected_state() {
    let s = run_case("reflection_1d", &[]);
    let (rho, r) = (num(&s, "plateau_density_ratio"), num(&s, "shock_distance_ratio"));
    eprintln!("reflection: plateau rho {rho:.4}, shock {r:.4}, wall heating {:.3}", num(&s, "wall_heating_e_excess"));
    assert!((rho - 1.0).abs() < 0.03, "reflected density {rho} of the exact");
    assert!((r - 1.0).abs() < 0.03, "reflected shock {r} of the exact distance");
}

#[test]
fn sedov_2d_coarse_point_deposit() {
    // PySPH's set-up at 3/4 of its resolution (78²): the energy in the four central particles, at
    // the default lattice jitter of gas dynamics. Measured (docs/validation.md): R_peak 1.009,
    // R_half 1.058 (γ = 1.4). Asserted: the peak within the required 2 %, no particle running ahead
    // of the front, no e < 0, no clumping; and the front sharp: the half-jump threshold within
    // two spacings of the peak (at 25 spacings from the centre a spacing is 4 % of the radius, so
    // the threshold is no measure of the radius to 3 % here; it was 1.036 on the exact lattice,
    // whose diagonal jets thinned the ring's front)
    for (case_name, g) in [("sedov_2d_g14", 1.4), ("sedov_2d_g53", 5.0 / 3.0)] {
        let dx = 1.0 / 78.0;
        let s = run_case(case_name, &sedov_2d_sets(78, 1.0, 78.0 * 78.0 / 4.0));
        let (rp, rh, cl) =
            (num(&s, "shock_radius_peak_ratio"), num(&s, "shock_radius_half_ratio"), num(&s, "clumping"));
        let spacings = (rh - rp) * num(&s, "shock_radius_exact_m") / dx;
        eprintln!(
            "sedov 2D 78², gamma {g}: R_peak {rp:.4}, R_half {rh:.4} ({spacings:.2} spacings apart), clumping {cl:.3}, ahead {}",
            num(&s, "ahead_count")
        );
        assert!((rp - 1.0).abs() < 0.02, "gamma {g}: peak-density shock radius {rp} of the exact");
        assert!((0.0..2.0).contains(&spacings), "gamma {g}: threshold {spacings} spacings beyond the peak");
        assert_eq!(num(&s, "ahead_count"), 0.0, "gamma {g}: particles running ahead of the front");
        assert_eq!(num(&s, "negative_e_count"), 0.0, "gamma {g}: particles with e < 0");
        assert!(cl < 2.0, "gamma {g}: a particle at {cl} times the exact peak density");
    }
}

/// The required "0.85 of the jump at 10⁴ particles in 2D with the best documented option": PySPH's
/// set-up at γ = 5/3 (104², t = 0.1 s, `cases/verify/sedov_2d_g53.toml`) with β = 2 and the
/// Morris–Monaghan switch, at the default lattice jitter. Measured (docs/validation.md): binned
/// peak 0.856 of the jump, 1.00 of the exact Δx window, densest particle 1.46 × the exact peak,
/// R_peak 0.987, no particle ahead. Asserted: ≥ 0.85 of the jump, the required 2 % on the peak
/// radius, no jets, no clump at twice the exact peak, no e < 0.
#[test]
fn sedov_2d_best_option_reaches_the_jump() {
    let s = run_case("sedov_2d_g53", &sets(&["viscosity.beta=2.0", "viscosity.switch=\"morris_monaghan\""]));
    let (f, rp, cl) =
        (num(&s, "peak_density_fraction_of_jump"), num(&s, "shock_radius_peak_ratio"), num(&s, "clumping"));
    eprintln!("sedov 2D 104², gamma 5/3, beta 2 + switch: peak {f:.3} of the jump, R_peak {rp:.4}, clumping {cl:.3}");
    assert!(f >= 0.85, "peak density {f} of the jump");
    assert!((rp - 1.0).abs() < 0.02, "peak-density shock radius {rp}");
    assert_eq!(num(&s, "ahead_count"), 0.0, "particles running ahead of the front");
    assert!(cl < 2.0, "a particle at {cl} times the exact peak density");
    assert_eq!(num(&s, "negative_e_count"), 0.0);
}

/// A point blast from the one particle at the centre of an odd lattice (61², E = 1 J/m, γ = 1.4):
/// on the exact lattice (`sph.jitter = 0`) the rows along the axes through the deposit run ahead
/// of the front as jets (measured: 208 particles beyond 1.2 R, the farthest at 1.62 R, the peak
/// 4.6 % behind); the default jitter of gas dynamics breaks the lattice's mirror symmetry and
/// removes them (none beyond 1.2 R, the peak 1.1 % ahead). docs/validation.md, "Jets along the
/// lattice's symmetry lines".
#[test]
fn point_blast_on_a_particle_jets_on_an_exact_lattice_and_not_on_the_default_jittered_one() {
    let base = sedov_2d_sets(61, 0.5, 61.0 * 61.0);
    let exact = run_case("sedov_2d_g14", &[&base[..], &["sph.jitter=0".to_string()]].concat());
    let jit = run_case("sedov_2d_g14", &base);
    for (what, s) in [("exact lattice", &exact), ("default jitter", &jit)] {
        eprintln!(
            "centre deposit 61², {what}: ahead {} (farthest {:.3} R), R_peak {:.4}, R_half {:.4}, clumping {:.3}",
            num(s, "ahead_count"),
            num(s, "ahead_max_radius_ratio"),
            num(s, "shock_radius_peak_ratio"),
            num(s, "shock_radius_half_ratio"),
            num(s, "clumping")
        );
    }
    assert!(
        num(&exact, "ahead_count") > 50.0 && num(&exact, "ahead_max_radius_ratio") > 1.4,
        "no jets on the exact lattice"
    );
    assert_eq!(num(&jit, "ahead_count"), 0.0, "jets with the default jitter");
    assert!((num(&jit, "shock_radius_peak_ratio") - 1.0).abs() < 0.03, "peak-density shock radius");
    assert!(num(&jit, "clumping") < 2.0);
    assert_eq!(num(&jit, "negative_e_count"), 0.0);
}

/// The report of a 2D point blast draws the density map (the exact shock radius over the
/// particles), names it in report.json, and lists it among the report's plots (so that a later
/// report or a resume removes it).
#[test]
fn a_point_blast_report_draws_its_density_map() {
    let dir = tempfile::tempdir().unwrap();
    let mut sets = sedov_2d_sets(40, 1.0, 400.0);
    sets.push("time.end_s=0.05".to_string());
    let opts = RunOptions { out: Some(dir.path().join("run")), sets, quiet: true, ..Default::default() };
    let r = run(&case("sedov_2d_g14"), &opts).expect("run");
    let rep = blastsph::report::report(&r.dir).expect("report");
    let map = r.dir.join("density_map.png");
    let png = std::fs::read(&map).expect("density_map.png");
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    assert!(png.len() > 10_000, "density_map.png is {} bytes", png.len());
    assert_eq!(rep["map"], "density_map.png", "{rep}");
    assert!(blastsph::rundir::is_report_plot("density_map.png"));
}

/// Sets for `cases/verify/sedov_1d_g*.toml` at `n` × its resolution (dx = 5 mm / n on [−1, 1] m,
/// the whole deposit in the one central particle).
fn sedov_1d_sets(n: u32) -> Vec<String> {
    let dx = 0.005 / n as f64;
    sets(&[
        &format!("region.ambient.count=[{}]", 400 * n + 1),
        &format!("region.ambient.spacing_m={dx}"),
        &format!("region.hot.spacing_m={dx}"),
        &format!("region.hot.e_jkg={}", 200.0 * n as f64),
    ])
}

/// Sedov–Taylor planar from a point deposit, both γ, at 401 and 801 particles, as the case files
/// set it up (the artificial conductivity on, hence no h cap). Measured (docs/validation.md,
/// "Sedov–Taylor in 1D"): R_peak 0.994 / 0.998 and R_half 1.007 / 1.006 (γ = 1.4), L1(ρ)/ρ₂ 2.6 % →
/// 2.2 %; asserted: both radii within the required 2 %, the L1 error falling with resolution, no
/// e < 0, no clumping, energy within 0.2 %. Without the conductivity the default h cap strands the
/// deposit: the shock lags, and more so at the finer resolution (printed, and asserted below 0.9).
#[test]
fn sedov_1d_point_deposit() {
    for (name, g) in [("sedov_1d_g14", 1.4), ("sedov_1d_g53", 5.0 / 3.0)] {
        let l1: Vec<f64> = [1, 2]
            .iter()
            .map(|&n| {
                let s = run_case(name, &sedov_1d_sets(n));
                sedov_checks(&s, &format!("sedov 1D gamma {g:.3}, {} particles", 400 * n + 1), 0.02, 0.02);
                num(&s, "l1_rho_relative")
            })
            .collect();
        assert!(l1[1] < l1[0], "gamma {g}: L1(rho) {l1:?} does not fall with resolution");
    }
    // the same blast without the conductivity: the h cap keeps the deposit particle from expanding
    let off: Vec<f64> = [1, 2]
        .iter()
        .map(|&n| {
            let mut v = sedov_1d_sets(n);
            v.push("conductivity.alpha=0.0".into());
            num(&run_case("sedov_1d_g14", &v), "shock_radius_peak_ratio")
        })
        .collect();
    eprintln!("sedov 1D gamma 1.4 without the conductivity (h cap 4): R_peak {off:?}");
    assert!(off.iter().all(|&r| r < 0.9) && off[1] < off[0], "without the conductivity: R_peak {off:?}");
}

/// Sets for `cases/verify/sedov_rz.toml` at spacing `dx`: the energy 0.5 J (the half space above
/// the z = 0 mirror; 1 J the whole blast) in the ring nearest the centre, mass 2π (dx/2) dx² ρ.
fn sedov_rz_sets(dx: f64) -> Vec<String> {
    let m_ring = 2.0 * std::f64::consts::PI * (0.5 * dx) * dx * dx;
    sets(&[
        &format!("region.hot.hi_m=[{dx}, {dx}]"),
        &format!("region.hot.spacing_m={dx}"),
        &format!("region.hot.e_jkg={}", 0.5 / m_ring),
        &format!("region.ambient.spacing_m={dx}"),
    ])
}

/// The checks every Sedov run of this file makes: the two shock-radius measures within `tol_peak`
/// and `tol_half` of the exact, no e < 0, no clumping (the required bound: no particle above twice
/// the exact peak density), and the energy balance (the total less the floor's work) within 0.2 %.
/// In RZ the floor e ≥ 0 adds energy where rings next to the axis expand and cool (the axis
/// remedy gives them the work of their images' forces): 2.5e-3 of E at 50² and 3.3e-3 at 100²,
/// bounded at 4e-3; elsewhere the total itself is held within 0.2 %.
fn sedov_checks(s: &Value, what: &str, tol_peak: f64, tol_half: f64) {
    let (rp, rh, cl) = (num(s, "shock_radius_peak_ratio"), num(s, "shock_radius_half_ratio"), num(s, "clumping"));
    let (e0, e1) = (s["energy"]["initial"]["total"].as_f64().unwrap(), s["energy"]["final"]["total"].as_f64().unwrap());
    eprintln!(
        "{what}: R_peak {rp:.4}, R_half {rh:.4}, peak {:.3} of the jump, L1/rho2 {:.4}, clumping {cl:.3}, energy {e0:.6} -> {e1:.6}",
        num(s, "peak_density_fraction_of_jump"),
        num(s, "l1_rho_relative")
    );
    assert!((rp - 1.0).abs() < tol_peak, "{what}: peak-density shock radius {rp} of the exact");
    assert!((rh - 1.0).abs() < tol_half, "{what}: threshold shock radius {rh} of the exact");
    assert_eq!(num(s, "negative_e_count"), 0.0, "{what}: particles with e < 0");
    assert!(cl < 2.0, "{what}: a particle at {cl} times the exact peak density");
    let floor = s["energy"]["work_floor"].as_f64().unwrap();
    assert!(((e1 - floor) / e0 - 1.0).abs() < 2e-3, "{what}: total energy {e0} -> {e1}, the floor's work {floor}");
    if what.contains("RZ") {
        assert!(floor / e0 < 4e-3, "{what}: the floor e >= 0 added {floor} J to {e0} J");
    } else {
        assert!((e1 / e0 - 1.0).abs() < 2e-3, "{what}: total energy {e0} -> {e1}");
    }
}

/// Sedov–Taylor spherical in RZ, 50 × 50 rings (half the case's resolution), t = 0.1 s. Measured
/// (docs/validation.md): R_peak 1.009, R_half 1.043, energy 0.5 → 0.50125 J (the floor's work
/// included); asserted: peak within 3 % (the required bound), threshold within 5 % (measured
/// + 1 %), the energy balance within 0.2 %.
#[test]
fn sedov_rz_coarse_point_deposit() {
    let s = run_case("sedov_rz", &sedov_rz_sets(0.01));
    assert_eq!(num(&s, "geometry_j"), 3.0, "RZ is the spherical blast");
    assert!((num(&s, "energy") - 1.0).abs() < 1e-6, "the mirror doubles the half space's 0.5 J");
    sedov_checks(&s, "sedov RZ 50²", 0.03, 0.05);
}

/// A point blast whose shock reaches the edge of its gas (the RZ case at 50² run to 0.3 s: the
/// exact radius 0.64 m against a 0.5 m quarter disc) is said so, not passed as a Sedov blast:
/// `check` warns before the run (naming the side, and the last time the blast stays clear of it),
/// and the verification carries the warning (`report` prints it as a WARNING line). Run to
/// 0.1 s it carries none; fewer than 20 spacings to the shock (12 at 0.005 s) is warned of too.
#[test]
fn a_point_blast_that_leaves_its_gas_is_warned_of() {
    let bin = env!("CARGO_BIN_EXE_blastsph");
    let check = |extra: &[String]| {
        let mut c = std::process::Command::new(bin);
        c.arg("check").arg(case("sedov_rz"));
        for s in extra {
            c.args(["--set", s]);
        }
        let o = c.output().unwrap();
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned() + &String::from_utf8_lossy(&o.stderr)
    };
    let mut late = sedov_rz_sets(0.01);
    late.push("time.end_s=0.3".into());
    let text = check(&late);
    let w = text.lines().find(|l| l.contains("reaches within the kernel's reach")).unwrap_or_else(|| panic!("{text}"));
    // R(0.3 s) = 1.0328 (0.09)^(1/5) = 0.6381 m; the ambient's last ring at r = 0.495 m; clear
    // of it (R + 2h0 = 0.495 m) up to t = 0.3 (0.475/0.6381)^(5/2) = 0.1435 s
    assert!(w.starts_with("warning: ") && w.contains("side +x") && w.contains("R = 6.380"), "{w}");
    assert!(w.contains("end by 1.435e-1 s"), "{w}");
    assert!(!check(&sedov_rz_sets(0.01)).contains("warning:"), "the case as it is warns");
    let mut early = sedov_rz_sets(0.01);
    early.push("time.end_s=0.005".into());
    let text = check(&early);
    assert!(
        text.contains("warning: a point blast 1") && text.contains("spacings from its centre at the end"),
        "{text}"
    );

    let dir = tempfile::tempdir().unwrap();
    let opts = RunOptions { out: Some(dir.path().join("run")), sets: late, quiet: true, ..Default::default() };
    let r = run(&case("sedov_rz"), &opts).expect("run");
    let s = &r.summary;
    let w = s["verification"]["warning"].as_str().unwrap_or_else(|| panic!("{}", s["verification"]));
    assert!(w.contains("side +x"), "{w}");
    assert!((num(s, "edge_m") - 0.495).abs() < 1e-9, "{}", s["verification"]);
    // report: the warning as a WARNING line, and the balance said to be the half space's
    let o = std::process::Command::new(bin).arg("report").arg(&r.dir).output().unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{text}");
    assert!(text.lines().any(|l| l.starts_with("WARNING: the point blast's exact shock radius")), "{text}");
    assert!(text.contains("the modelled part, 1/2 of the blast"), "{text}");
    let s = run_case("sedov_rz", &sedov_rz_sets(0.01));
    assert!(s["verification"]["warning"].is_null(), "{}", s["verification"]);
}

/// The RZ point blast at the default viscosity (β = 10, in place of the case file's β = 2), 100²
/// rings, t = 0.1 s, 12 s. The hot ring sits beside the mirror at z = 0 with its h grown to 4 h0 and
/// reaches particles whose own h is h0; with the mirror band at κ h_i their images were missing,
/// the hot particle was pushed through the mirror and the axis clumped (measured before the band
/// was widened to κ (h_i + h_max)/2: a particle at 256 × the exact peak density, R_peak 1.027,
/// R_half 1.034). Now: R_peak 0.998, R_half 1.021, clumping 1.41; asserted: both within 3 %.
///
/// With the axis remedy (docs/axis_results.md) the densest ring is 1.18 × the exact peak
/// (R_peak 0.9996, R_half 1.0189, energy 0.5 → 0.500468 J); without it a ring near the axis
/// reached 2.03 ×, over the bound of 2.
#[test]
fn sedov_rz_default_viscosity_mirror_band() {
    let mut s = sedov_rz_sets(0.005);
    s.push("viscosity.beta=10".into());
    let s = run_case("sedov_rz", &s);
    sedov_checks(&s, "sedov RZ 100² beta 10", 0.03, 0.03);
}

/// Sedov–Taylor spherical in 3D, the octant with three symmetry planes at 16³ (dx = 1/32 m; the
/// shock at 13 spacings from the centre), t = 0.1 s, 5 s. Measured: R_peak 0.990, R_half 1.092
/// (the front is smeared over 3–4 spacings at this resolution: the mid-rise lies ahead; 1.040 at
/// 30³, docs/validation.md), energy 0.125 → 0.124958 J; asserted: peak within 3 % (the required
/// bound), threshold within 10 %, energy within 0.2 %.
#[test]
fn sedov_3d_coarse_octant() {
    let dx = 1.0 / 32.0;
    let s = run_case(
        "sedov_3d",
        &sets(&[
            &format!("region.hot.hi_m=[{dx}, {dx}, {dx}]"),
            &format!("region.hot.spacing_m={dx}"),
            &format!("region.hot.e_jkg={}", 0.125 / (dx * dx * dx)),
            &format!("region.ambient.spacing_m={dx}"),
        ]),
    );
    assert_eq!(num(&s, "geometry_j"), 3.0);
    assert!((num(&s, "energy") - 1.0).abs() < 1e-6, "three mirrors: 8 × the octant's 1/8 J");
    sedov_checks(&s, "sedov 3D octant 16³", 0.03, 0.10);
}

/// The arrival time of a gauge's front: where its `field` column of gauges.csv first passes half of
/// its extreme value (linear interpolation between steps).
/// A gauge's record from gauges.csv: (t, the column `field`) per step.
fn gauge_series(dir: &Path, field: &str) -> Vec<(f64, f64)> {
    let text = std::fs::read_to_string(dir.join("gauges.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = head.iter().position(|h| *h == field).unwrap_or_else(|| panic!("no column {field}"));
    lines
        .map(|l| {
            let v: Vec<&str> = l.split(',').collect();
            (v[0].parse().unwrap(), v[col].parse().unwrap())
        })
        .collect()
}

fn arrival(dir: &Path, field: &str) -> f64 {
    let rows = gauge_series(dir, field);
    let low = rows.iter().map(|r| r.1).fold(0.0, f64::min);
    let level = 0.5 * low;
    let k = rows.iter().position(|r| r.1 < level).expect("the front arrives");
    let ((t0, a0), (t1, a1)) = (rows[k - 1], rows[k]);
    t0 + (t1 - t0) * (a0 - level) / (a0 - a1)
}

/// A P wave in 3D elastic sand under uniaxial strain (cases/verify/elastic_wave_3d.toml) runs at
/// √((K + 4G/3)/ρ) = 1730.1 m/s, not at the bulk speed 1440 m/s. Measured (docs/validation.md):
/// 1787.7 m/s from σ_zz, 1785.9 from v_z (+3.3 %; 1771.7, +2.4 %, at Δx = 2.5 mm); asserted within
/// 5 % of c_p (the measured plus 1.7 %), and more than 15 % above c0.
#[test]
fn elastic_p_wave_in_3d_sand() {
    let dir = tempfile::tempdir().unwrap();
    let opts = RunOptions { out: Some(dir.path().join("run")), quiet: true, ..Default::default() };
    let r = run(&case("elastic_wave_3d"), &opts).expect("run");
    assert_eq!(r.summary["status"], "ok");
    let cp = ((1450.0 * 1440.0f64.powi(2) + 4.0 / 3.0 * 1.0e9) / 1450.0).sqrt();
    for field in ["szz_pa", "vz_ms"] {
        let (t1, t2) = (arrival(&r.dir, &format!("z80_{field}")), arrival(&r.dir, &format!("z40_{field}")));
        let c = 0.4 / (t2 - t1);
        eprintln!("P wave from {field}: {c:.1} m/s against c_p = {cp:.1} m/s ({:+.2} %)", 100.0 * (c / cp - 1.0));
        assert!((c / cp - 1.0).abs() < 0.05, "{field}: {c} m/s against {cp}");
        assert!(c > 1.15 * 1440.0, "{field}: {c} m/s: the shear modulus is not in the wave");
    }
    // the report's caveat that a blast's gauge peaks rise with refinement is not said of an
    // elastic wave (its peak is a plateau)
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_blastsph")).arg("report").arg(&r.dir).output().unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{text}");
    assert!(text.contains("gauge ") && !text.contains("peaks rise as the spacing shrinks"), "{text}");
}

/// The arrival of a compressive front at a gauge's `field` (a stress: compression negative): the
/// crossing of half its plateau, the plateau the median reading 20–60 µs after the reading first
/// passes half its largest compression (so the measure does not ride the front's overshoot).
fn arrival_at_half_plateau(dir: &Path, field: &str) -> f64 {
    let rows = gauge_series(dir, field);
    let y0 = rows[0].1;
    let y: Vec<(f64, f64)> = rows.iter().map(|&(t, v)| (t, y0 - v)).collect();
    let cross = |level: f64| {
        let k = y.iter().position(|r| r.1 >= level).expect("the front arrives");
        let ((t0, a0), (t1, a1)) = (y[k - 1], y[k]);
        t0 + (t1 - t0) * (level - a0) / (a1 - a0)
    };
    let top = y.iter().map(|r| r.1).fold(0.0, f64::max);
    let t50 = cross(0.5 * top);
    let mut p: Vec<f64> = y.iter().filter(|r| r.0 > t50 + 20e-6 && r.0 < t50 + 60e-6).map(|r| r.1).collect();
    assert!(p.len() > 5, "{field}: the run ends before the plateau");
    p.sort_by(f64::total_cmp);
    cross(0.5 * p[p.len() / 2])
}

/// The lattice's kernel moment S (`kernel::lattice_moment`: 1.0200 for the cubic spline in 3D at
/// h = Δx) makes the elastic wave of cases/verify/elastic_wave_3d.toml run S times
/// √((K + 4G/3)/ρ) at the defaults, and `sph.lattice_gradient = true`, which divides ∇W by S,
/// at √((K + 4G/3)/ρ) itself. Measured (docs/validation.md, "Elastic P wave in 3D sand"), the
/// arrival at half each gauge's plateau, 0.4 m apart: +2.0 % and +0.1 %; asserted: the default
/// within 0.5 % of S c_p, the normalised run within 0.5 % of c_p.
#[test]
fn the_lattice_gradient_puts_the_elastic_wave_at_its_speed() {
    let cp = ((1450.0 * 1440.0f64.powi(2) + 4.0 / 3.0 * 1.0e9) / 1450.0).sqrt();
    let s3 = blastsph::modules::kernel::lattice_moment(3, blastsph::case::KernelKind::Cubic, 1.0);
    for (on, want) in [(false, s3 * cp), (true, cp)] {
        let sets = vec!["time.end_s=4e-4".to_string(), format!("sph.lattice_gradient={on}")];
        let dir = tempfile::tempdir().unwrap();
        let opts = RunOptions { out: Some(dir.path().join("run")), sets, quiet: true, ..Default::default() };
        let r = run(&case("elastic_wave_3d"), &opts).expect("run");
        assert_eq!(r.summary["status"], "ok");
        let (t1, t2) = (arrival_at_half_plateau(&r.dir, "z80_szz_pa"), arrival_at_half_plateau(&r.dir, "z40_szz_pa"));
        let v = 0.4 / (t2 - t1);
        eprintln!(
            "lattice_gradient {on}: {v:.1} m/s, c_p {cp:.1} ({:+.2} %), S c_p {:.1}",
            100.0 * (v / cp - 1.0),
            s3 * cp
        );
        assert!((v / want - 1.0).abs() < 0.005, "lattice_gradient {on}: {v} m/s against {want}");
    }
}

/// The full-resolution RZ and 3D Sedov cases (100² rings; 30³ octant), as docs/validation.md.
#[test]
#[ignore]
fn sedov_rz_and_3d_full() {
    let s = run_case("sedov_rz", &[]);
    sedov_checks(&s, "sedov RZ 100²", 0.02, 0.02);
    let s = run_case("sedov_3d", &[]);
    sedov_checks(&s, "sedov 3D octant 30³", 0.02, 0.05);
}

/// The run that would produce e < 0 without the asymmetric energy form: the same point blast with
/// the thesis's symmetric form drains the neighbours of the hot particles below zero.
#[test]
fn point_blast_symmetric_energy_form_goes_negative_and_the_default_does_not() {
    let mut base = sedov_2d_sets(52, 1.0, 52.0 * 52.0 / 4.0);
    base.push("time.end_s=0.01".to_string());
    // without the floor e >= 0, so that the forms themselves are compared
    let mut sym = base.to_vec();
    sym.push("sph.energy_form=symmetric".into());
    sym.push("sph.e_floor=false".into());
    let s = run_case("sedov_2d_g53", &sym);
    let neg = num(&s, "negative_e_count");
    assert!(neg > 0.0, "the symmetric form left no particle with e < 0 (min e {})", num(&s, "min_e"));
    let mut asym = base.to_vec();
    asym.push("sph.e_floor=false".into());
    let s = run_case("sedov_2d_g53", &asym);
    assert_eq!(num(&s, "negative_e_count"), 0.0, "the asymmetric form (default) left e < 0");
    assert!(num(&s, "min_e") > 0.0);
    // at the defaults the floor has nothing to do
    let s = run_case("sedov_2d_g53", &base);
    assert_eq!(s["energy"]["work_floor"].as_f64(), Some(0.0));
}

#[test]
fn tnt_slab_front_holds_p_cj_short() {
    // 600 spacings at dx = 1 mm, h/dx = 1.0 and 1.5 (the problem is scale-free: other dx give the
    // same ratios at the same travel in spacings; the full study is the ignored test below)
    for h in [1.0, 1.5] {
        let (hist, rep) = slab(0.001, h, 600.0, &[]);
        eprintln!("slab h/dx {h}: front p/p_CJ {hist:?}");
        let last = *hist.last().unwrap();
        assert!((last - 1.0).abs() < 0.03, "h/dx {h}: front pressure {last} p_CJ after 600 spacings");
        assert!(hist.iter().all(|r| *r < 1.03), "h/dx {h}: the front pressure overshot: {hist:?}");
        let plateau = rep["plateau_ratio"].as_f64().unwrap();
        assert!((plateau - 1.0).abs() < 0.02, "h/dx {h}: plateau {plateau} of the Taylor wave's");
    }
}

#[test]
fn tnt_slab_thesis_parity_burn_crushes_the_unlit_explosive() {
    // the evidence for the burn defaults: the thesis's burn (no ramp, no beta burn, unlit = void)
    // crushes the explosive ahead of the front within 700 spacings
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(case("tnt_slab_1d")).unwrap();
    let void = text.replace(", unreacted_c_ms = 2390.0, unreacted_s = 2.05, unreacted_gamma = 1.0", "");
    assert_ne!(void, text, "the slab's TNT has an unreacted EOS to take out");
    let path = dir.path().join("tnt_slab_void.toml");
    std::fs::write(&path, void).unwrap();
    let (hist, rep) = slab_of(&path, 0.001, 1.0, 700.0, &["parity=\"thesis\""]);
    eprintln!("thesis-parity burn: {hist:?}, densest ahead {}", rep["max_density_ahead_of_front"]);
    assert!(hist.last().unwrap() > &1.2, "no runaway: {hist:?}");
}

/// docs/validation.md, "Detonation": dx = 1, 0.5, 0.25, 0.1 mm, h/dx = 1.0, 1.2, 1.5, 2000
/// spacings of travel, at the default settings.
#[test]
#[ignore]
fn tnt_slab_converges_to_cj_at_every_resolution() {
    for dx in [0.001, 0.0005, 0.00025, 0.0001] {
        for h in [1.0, 1.2, 1.5] {
            let (hist, rep) = slab(dx, h, 2000.0, &[]);
            let last = *hist.last().unwrap();
            let max = hist.iter().cloned().fold(0.0, f64::max);
            eprintln!(
                "dx {dx} h/dx {h}: front p/p_CJ at 200..2000 spacings {hist:.4?}, plateau {:.4}, L1(p) {:.4}",
                rep["plateau_ratio"].as_f64().unwrap(),
                rep["l1_p_taylor_relative"].as_f64().unwrap()
            );
            assert!((last - 1.0).abs() < 0.03, "dx {dx} h/dx {h}: {last}");
            assert!(max < 1.03, "dx {dx} h/dx {h}: runaway {max}");
        }
    }
}

/// docs/validation.md, "Sedov–Taylor": PySPH's set-up (104², t = 0.1), both γ, defaults (the
/// lattice jitter of gas dynamics). Measured: R_peak 0.994 / 0.988, R_half 1.033 / 1.028, no
/// particle ahead. Asserted: the peak within the required 2 %, the threshold within two spacings
/// of the peak (the front's width: 1.2 spacings, 3.6 % of the radius here), no jets, no e < 0,
/// no clump at twice the exact peak.
#[test]
#[ignore]
fn sedov_2d_pysph_setup() {
    for name in ["sedov_2d_g14", "sedov_2d_g53"] {
        let s = run_case(name, &[]);
        let v = &s["verification"];
        eprintln!("{name}: {v}");
        let (rp, rh) = (num(&s, "shock_radius_peak_ratio"), num(&s, "shock_radius_half_ratio"));
        assert!((rp - 1.0).abs() < 0.02, "{name}: peak measure {rp}");
        let spacings = (rh - rp) * num(&s, "shock_radius_exact_m") / num(&s, "dx_m");
        assert!((0.0..2.0).contains(&spacings), "{name}: threshold {spacings} spacings beyond the peak");
        assert_eq!(num(&s, "ahead_count"), 0.0, "{name}");
        assert_eq!(num(&s, "negative_e_count"), 0.0, "{name}");
        assert!(num(&s, "clumping") < 2.0, "{name}");
    }
}

/// The before/after table of docs/validation.md ("Verification problems"): every case of
/// cases/verify/ at today's defaults and with the settings of the code before (`parity =
/// "thesis"`, and the TNT without its unreacted EOS — bitwise the earlier code's defaults), with
/// the cost per particle-step. Prints markdown.
#[test]
#[ignore]
fn verification_table() {
    let names = [
        "sedov_1d_g14",
        "sedov_1d_g53",
        "sedov_2d_g14",
        "sedov_2d_g53",
        "noh_1d",
        "noh_2d",
        "reflection_1d",
        "tnt_slab_1d",
        "tnt_strip_2d",
    ];
    println!(
        "| case | settings | status | steps | shock radius (peak / threshold) / exact | peak density / exact peak | clumping | L1(ρ) / exact peak | e < 0 | front p / p_CJ | plateau / exact | wall heating (e excess) | µs per particle-step |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for name in names {
        for before in [true, false] {
            let dir = tempfile::tempdir().unwrap();
            let text = std::fs::read_to_string(case(name)).unwrap();
            let text = if before {
                text.replace(", unreacted_c_ms = 2390.0, unreacted_s = 2.05, unreacted_gamma = 1.0", "")
            } else {
                text
            };
            let path = dir.path().join(format!("{name}.toml"));
            std::fs::write(&path, text).unwrap();
            let sets = if before { sets(&["parity=\"thesis\""]) } else { vec![] };
            let opts = RunOptions { out: Some(dir.path().join("run")), sets, quiet: true, ..Default::default() };
            let (summary, status) = match run(&path, &opts) {
                Ok(r) => (r.summary, "ok".to_string()),
                Err(e) => {
                    let s = std::fs::read_to_string(dir.path().join("run/summary.json")).unwrap_or_default();
                    (
                        serde_json::from_str(&s).unwrap_or(Value::Null),
                        format!("unstable: {}", e.to_string().chars().take(60).collect::<String>()),
                    )
                }
            };
            let v = &summary["verification"];
            let f = |k: &str| v[k].as_f64().map_or("-".to_string(), |x| format!("{x:.3}"));
            let radius = if v["shock_radius_half_ratio"].is_null() && v["shock_distance_ratio"].is_null() {
                "-".to_string()
            } else if !v["shock_distance_ratio"].is_null() {
                f("shock_distance_ratio")
            } else {
                format!("{} / {}", f("shock_radius_peak_ratio"), f("shock_radius_half_ratio"))
            };
            let peak = if !v["peak_density_ratio"].is_null() {
                f("peak_density_ratio")
            } else if !v["post_shock_density_ratio"].is_null() {
                f("post_shock_density_ratio")
            } else if !v["plateau_density_ratio"].is_null() {
                f("plateau_density_ratio")
            } else {
                "-".into()
            };
            let wall = summary["wall_seconds"].as_f64().unwrap_or(f64::NAN);
            let ps = summary["particles"].as_f64().unwrap_or(f64::NAN) * summary["steps"].as_f64().unwrap_or(f64::NAN);
            println!(
                "| {name} | {} | {status} | {} | {radius} | {peak} | {} | {} | {} | {} | {} | {} | {:.2} |",
                if before { "before" } else { "defaults" },
                summary["steps"],
                f("clumping"),
                f("l1_rho_relative"),
                v["negative_e_count"].as_f64().map_or("-".into(), |x| format!("{x}")),
                f("front_p_ratio"),
                f("plateau_ratio"),
                f("wall_heating_e_excess"),
                1e6 * wall / ps
            );
        }
    }
}

/// Spherical Noh in RZ (cases/verify/noh_rz.toml, at 2 cm: the shock 10 rings from the centre,
/// 3 s): the case's β = 2 holds the post-shock density within 20 % of the exact 64 (0.84
/// measured; 0.96 at the case's 1 cm), the half-jump shock radius within 10 % (1.075; 1.041 at
/// 1 cm), no ring clumped above 1.5 × the exact peak and no e < 0; the default β = 10 reads the
/// post-shock density 0.1 lower or more (0.64 measured), which is why the case sets β = 2.
#[test]
fn noh_rz_post_shock_state_and_shock_position() {
    let coarse = sets(&["region.gas.spacing_m=0.02", "time.output_interval_s=0.3"]);
    let s = run_case("noh_rz", &coarse);
    let (rho, r, clump) =
        (num(&s, "post_shock_density_ratio"), num(&s, "shock_radius_half_ratio"), num(&s, "clumping"));
    eprintln!("noh RZ at 2 cm, beta = 2: rho2 ratio {rho:.4}, shock {r:.4}, clumping {clump:.3}");
    assert!((rho - 1.0).abs() < 0.2, "post-shock density {rho} of the exact 64");
    assert!((r - 1.0).abs() < 0.1, "shock radius {r} of the exact 0.2 m");
    assert!(clump < 1.5, "densest ring {clump} x the exact peak");
    assert_eq!(num(&s, "negative_e_count"), 0.0);
    let mut b10 = coarse.clone();
    b10.push("viscosity.beta=10".into());
    let d = run_case("noh_rz", &b10);
    let rho10 = num(&d, "post_shock_density_ratio");
    eprintln!("noh RZ at 2 cm, beta = 10: rho2 ratio {rho10:.4}");
    assert!(rho - rho10 > 0.1, "beta = 2 ({rho}) against the default beta = 10 ({rho10})");
}

/// A strip lit along its whole end (`detonation.plane_normal`): every explosive particle lights
/// at its distance from the plane over s D, whatever its height; lit from the point, those off
/// the centre line light later. A zero normal is refused.
#[test]
fn a_plane_lights_the_strip_by_distance_from_the_plane() {
    let tlight = |extra: &[&str]| {
        let dir = tempfile::tempdir().unwrap();
        let s = sets(&[&["time.end_s=2e-7", "time.output_interval_s=1e-7"], extra].concat());
        let opts = RunOptions { out: Some(dir.path().join("run")), sets: s, quiet: true, ..Default::default() };
        let r = run(&case("tnt_strip_2d"), &opts).unwrap();
        // the positions at t = 0, which the lighting times are of
        let x0 = blastsph::setup::particles(&r.sim.case).unwrap().x;
        (0..r.sim.p.nreal).map(|i| (x0[2 * i], x0[2 * i + 1], r.sim.p.tlight[i])).collect::<Vec<_>>()
    };
    let speed = 0.95 * 6930.0;
    let plane = tlight(&["detonation.plane_normal=[2.0, 0.0]"]);
    assert_eq!(plane.len(), 2100);
    for &(x, _, t) in &plane {
        assert!((t - x / speed).abs() <= 1e-12 * x / speed, "x {x}: t {t}");
    }
    let point = tlight(&[]);
    let later = point.iter().zip(&plane).filter(|(a, b)| a.2 > b.2 * (1.0 + 1e-9)).count();
    assert!(point.iter().zip(&plane).all(|(a, b)| a.2 >= b.2 && a.0 == b.0 && a.1 == b.1));
    assert!(later > 1500, "{later} of 2100 light later from the point");
    let bad = blastsph::case::load(&case("tnt_strip_2d"), &sets(&["detonation.plane_normal=[0.0, 0.0]"]));
    let e = bad.err().map(|e| e.to_string()).unwrap_or_default();
    assert!(e.contains("plane_normal") && e.contains("zero vector"), "{e}");
}
