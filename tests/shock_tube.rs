//! The shock tube (Liu & Liu's book run, docs/validation.md): the exact Riemann solver against the
//! published numbers, and the SPH run (all modules in Fortran) against the exact solution.
//!
//! `cargo test --release -- --ignored shock_tube_convergence` runs the resolution study of
//! docs/validation.md and prints its table.

// Particle arrays are parallel (x, rho, v, ... indexed by particle), as in the crate itself.
#![allow(clippy::needless_range_loop)]

mod common;

use blastsph::analysis::riemann::{Riemann, Side};
use blastsph::modules::{Backend, Module};
use common::{TubeRun, refine_sets, run_tube};

fn book_problem() -> Riemann {
    Riemann::solve(Side { rho: 1.0, u: 0.0, p: 1.0 }, Side { rho: 0.25, u: 0.0, p: 0.1795 }, 1.4)
        .expect("the book's Riemann problem has a solution")
}

fn close(what: &str, got: f64, want: f64, tol: f64) {
    assert!((got - want).abs() <= tol, "{what} = {got:.7}, the exact solution gives {want} (tolerance {tol:e})");
}

#[test]
fn exact_solver_reproduces_the_book_problem() {
    let rs = book_problem();
    let (rl, rr) = rs.rho_star();
    close("p*", rs.p_star, 0.429346, 1e-5);
    close("u*", rs.u_star, 0.673103, 1e-5);
    close("rho*L", rl, 0.546663, 1e-5);
    close("rho*R", rr, 0.457328, 1e-5);
    close("shock speed", rs.right_shock_speed(), 1.48474, 1e-5);

    // the wave positions at t = 0.2 s (the exact solution, 4 decimals): shock 0.2970, contact 0.1346,
    // rarefaction from −0.2366 to −0.0751
    let t = 0.2;
    let cl = (1.4_f64 * 1.0 / 1.0).sqrt();
    let c_star_l = cl * (rs.p_star / 1.0).powf(0.4 / 2.8);
    close("shock position", rs.right_shock_speed() * t, 0.2970, 1e-4);
    close("contact position", rs.u_star * t, 0.1346, 1e-4);
    close("rarefaction head", -cl * t, -0.2366, 1e-4);
    close("rarefaction tail", (rs.u_star - c_star_l) * t, -0.0751, 1e-4);

    // the sampled solution has those waves where they should be
    let at = |x: f64| rs.sample(x / t);
    let (d, eps) = (1e-4, 1e-12);
    let s = at(0.2970 + 2.0 * d);
    assert!((s.rho - 0.25).abs() < eps && s.u.abs() < eps && (s.p - 0.1795).abs() < eps);
    let s = at(0.2969 - d);
    assert!((s.rho - rr).abs() < eps && (s.u - rs.u_star).abs() < eps);
    let s = at(0.1346 + d);
    assert!((s.rho - rr).abs() < eps && (s.p - rs.p_star).abs() < eps);
    let s = at(0.1346 - d);
    assert!((s.rho - rl).abs() < eps && (s.p - rs.p_star).abs() < eps);
    let s = at(-0.0751 + d);
    assert!((s.rho - rl).abs() < eps && (s.u - rs.u_star).abs() < eps);
    let s = at(-0.2366 - d);
    assert!((s.rho - 1.0).abs() < eps && s.u.abs() < eps && (s.p - 1.0).abs() < eps);
    // inside the fan: isentropic, p/ρ^γ of the left state, and u − 2c/(γ−1) constant
    for x in [-0.2, -0.15, -0.1] {
        let s = at(x);
        assert!(s.rho < 1.0 && s.rho > rl, "fan at x = {x}: rho = {}", s.rho);
        let entropy = s.p / s.rho.powf(1.4);
        assert!((entropy - 1.0).abs() < 1e-12, "fan at x = {x}: p/rho^gamma = {entropy}");
        let c = (1.4 * s.p / s.rho).sqrt();
        assert!((s.u + 2.0 * c / 0.4 - 2.0 * cl / 0.4).abs() < 1e-12, "Riemann invariant");
        assert!((s.e - s.p / (0.4 * s.rho)).abs() < 1e-14);
    }
}

#[test]
fn exact_solver_reproduces_sod() {
    let rs = Riemann::solve(Side { rho: 1.0, u: 0.0, p: 1.0 }, Side { rho: 0.125, u: 0.0, p: 0.1 }, 1.4)
        .expect("Sod's problem has a solution");
    close("Sod p*", rs.p_star, 0.303130, 1e-5);
    close("Sod u*", rs.u_star, 0.927453, 1e-5);
    // pressure and velocity are continuous across the contact: the star state satisfies both
    // wave curves (shock on the right, Rankine–Hugoniot; rarefaction on the left, isentropic)
    let (rl, rr) = rs.rho_star();
    let g: f64 = 1.4;
    let k = (g - 1.0) / (g + 1.0);
    let pr = rs.p_star / 0.1;
    assert!((rr - 0.125 * (pr + k) / (k * pr + 1.0)).abs() < 1e-12);
    assert!((rl - rs.p_star.powf(1.0 / g)).abs() < 1e-12);
}

#[test]
fn exact_solver_refuses_vacuum() {
    // two gases flying apart faster than 2(c_L + c_R)/(γ−1) = 10c: no star state
    let side = |u| Side { rho: 1.0, u, p: 1.0 };
    let c = 1.4_f64.sqrt();
    assert!(Riemann::solve(side(-5.5 * c), side(5.5 * c), 1.4).is_none());
    // and a symmetric collision gives u* = 0
    let rs = Riemann::solve(side(1.0), side(-1.0), 1.4).expect("collision");
    assert!(rs.u_star.abs() < 1e-14 && rs.p_star > 1.0);
}

/// L1 density error over [−0.4, 0.4] of the book run measured with this code: 1.616e−2 (see
/// docs/validation.md for the full table and how it was produced).
///
/// The bound, 0.02, is that value plus 25 %: room for the last digits of a different libm or
/// compiler, not for a change of method — dropping the artificial viscosity, using a wrong h_ij
/// or a wrong sign in the energy equation each moves the error by far more than that. It is also
/// comparable to what the book's own figures show (the contact and the shock smeared over
/// 3–4 h = 0.05 m with jumps of 0.1–0.2 in ρ give ≈ 0.015).
const L1_RHO_BOUND: f64 = 0.02;

fn check_book_run(run: &TubeRun) {
    let s = &run.summary;
    assert_eq!(s["backend"], "fortran");
    for m in Module::ALL {
        if let Some(b) = s["modules"].get(m.name()) {
            assert_eq!(b, Backend::Fortran.name(), "module {}", m.name());
        }
    }
    assert_eq!(s["particles"], 400);
    assert_eq!(s["steps"], 40, "fixed dt = 0.005 s to t = 0.2 s is 40 steps");
    let t = s["time"].as_f64().unwrap();
    assert!((t - 0.2).abs() < 1e-12, "end time {t}");
    assert!((run.last().time - t).abs() < 1e-15, "the last output is at the end time");

    // mass: Σ m_i is conserved to round-off, in summary.json and in the last output
    let m0 = s["mass"]["initial"].as_f64().unwrap();
    let m1 = s["mass"]["final"].as_f64().unwrap();
    assert!((m0 - 0.75).abs() < 1e-12, "400 × 0.001875 kg = 0.75 kg, got {m0}");
    assert!((m1 - m0).abs() <= 1e-14 * m0, "mass {m0} -> {m1}");
    let m_frame: f64 = run.last().mass.iter().sum();
    assert!((m_frame - m0).abs() <= 1e-14 * m0, "mass in the last output {m_frame}");

    // the exact problem the report builds from the case is the book's
    let rs = &run.exact;
    assert!((rs.p_star - 0.429346).abs() < 1e-5 && (rs.u_star - 0.673103).abs() < 1e-5);
    assert_eq!(run.x0, 0.0);

    let l1 = run.l1(-0.4, 0.4);
    println!(
        "book run, [-0.4, 0.4]: {} particles, L1 rho {:.4e} v {:.4e} p {:.4e} e {:.4e}",
        l1.n, l1.rho, l1.v, l1.p, l1.e
    );
    assert!(l1.n > 250, "particles in the window: {}", l1.n);
    assert!(l1.rho < L1_RHO_BOUND, "L1 density error {:.4e} over [-0.4, 0.4] exceeds {L1_RHO_BOUND}", l1.rho);
    // the other fields, with the same 25 % margin over what was measured (docs/validation.md:
    // v 2.677e−2, p 1.799e−2, e 3.260e−2)
    assert!(l1.v < 0.0335, "L1 velocity error {:.4e}", l1.v);
    assert!(l1.p < 0.0225, "L1 pressure error {:.4e}", l1.p);
    assert!(l1.e < 0.041, "L1 energy error {:.4e}", l1.e);

    // plateaus: the SPH star state near the middle of each plateau is within a few % of exact
    let f = run.last();
    let mean = |lo: f64, hi: f64, q: &dyn Fn(usize) -> f64| {
        let idx: Vec<usize> = (0..f.x.len()).filter(|&i| f.x[i] > lo && f.x[i] < hi).collect();
        assert!(idx.len() >= 3, "no particles in [{lo}, {hi}]");
        idx.iter().map(|&i| q(i)).sum::<f64>() / idx.len() as f64
    };
    let (rl, rr) = rs.rho_star();
    let p_mid = mean(-0.04, 0.10, &|i| f.p[i]);
    let u_mid = mean(-0.04, 0.25, &|i| f.vx[i]);
    let rl_sph = mean(-0.04, 0.10, &|i| f.rho[i]);
    let rr_sph = mean(0.17, 0.26, &|i| f.rho[i]);
    for (what, got, want) in
        [("p*", p_mid, rs.p_star), ("u*", u_mid, rs.u_star), ("rho*L", rl_sph, rl), ("rho*R", rr_sph, rr)]
    {
        assert!(((got - want) / want).abs() < 0.03, "SPH {what} = {got:.5}, exact {want:.5}");
    }
    // the shock: where the SPH velocity falls through u*/2 (interpolated between particles)
    // must be the exact shock position 0.2970 m within h/2 = 0.0075 m
    let mut order: Vec<usize> = (0..f.x.len()).collect();
    order.sort_by(|&a, &b| f.x[a].total_cmp(&f.x[b]));
    let half = 0.5 * rs.u_star;
    let k = order
        .windows(2)
        .position(|w| f.x[w[0]] > 0.2 && f.vx[w[0]] >= half && f.vx[w[1]] < half)
        .expect("no shock found right of x = 0.2");
    let (a, b) = (order[k], order[k + 1]);
    let xs = f.x[a] + (f.x[b] - f.x[a]) * (f.vx[a] - half) / (f.vx[a] - f.vx[b]);
    let exact = rs.right_shock_speed() * f.time;
    assert!((xs - exact).abs() < 0.0075, "SPH shock at x = {xs:.4} m, exact {exact:.4} m");
}

#[test]
fn shock_tube_book_run_against_exact_solution() {
    let dir = tempfile::tempdir().expect("tempdir");
    let run = run_tube(&[], dir.path());
    check_book_run(&run);
}

/// The option that beats the book code's own L1(ρ) = 0.0155 at its resolution (docs/validation.md, shock tube):
/// the Morris–Monaghan viscosity switch at its authors' parameters (α_min = 0.1, ℓ = 0.2), on the
/// book's run (the case's parity preset; the default stays without the switch). Measured
/// (docs/validation.md): 0.01469 against 0.01616 without it; asserted below 0.0155, and below
/// the run without the switch.
#[test]
fn viscosity_switch_beats_the_book_code_on_its_shock_tube() {
    let d0 = tempfile::tempdir().expect("tempdir");
    let d1 = tempfile::tempdir().expect("tempdir");
    let without = run_tube(&[], d0.path()).l1(-0.4, 0.4).rho;
    let run = run_tube(&["viscosity.switch=\"morris_monaghan\"".to_string()], d1.path());
    assert_eq!(run.case.viscosity.switch, blastsph::case::ViscSwitch::MorrisMonaghan);
    let l1 = run.l1(-0.4, 0.4).rho;
    eprintln!("L1(rho) {without:.5} without the switch, {l1:.5} with it");
    assert!(l1 < 0.0155, "L1(rho) {l1} with the switch, the book code's 0.0155");
    assert!(l1 < without, "the switch ({l1}) against none ({without})");
}

/// Doubling the resolution (800 particles, h, spacings, masses and dt halved) must roughly
/// halve the error where the diaphragm's exact solution holds. Over [−0.35, 0.35] — clear of
/// the rarefactions that start at the tube's open ends, which the exact solution does not
/// contain — the observed order log2(E_400/E_800) of the density error is 0.97 (fixed step);
/// first order is what a shock-capturing scheme with artificial viscosity can reach on a
/// solution with discontinuities. The bound 0.8 leaves room for platform noise and fails if
/// the refinement stops paying (e.g. an h that does not follow the spacing).
#[test]
fn shock_tube_error_falls_with_resolution() {
    let d1 = tempfile::tempdir().expect("tempdir");
    let d2 = tempfile::tempdir().expect("tempdir");
    let coarse = run_tube(&refine_sets(1, true), d1.path());
    let fine = run_tube(&refine_sets(2, true), d2.path());
    assert_eq!(fine.summary["particles"], 800);
    assert_eq!(fine.summary["steps"], 80);
    let (e1, e2) = (coarse.l1(-0.35, 0.35), fine.l1(-0.35, 0.35));
    let order = (e1.rho / e2.rho).log2();
    println!("L1 rho over [-0.35, 0.35]: {:.4e} (400), {:.4e} (800), order {order:.2}", e1.rho, e2.rho);
    assert!(order > 0.8, "observed order {order:.2} of the L1 density error");
}

/// The resolution study of docs/validation.md: 400, 800, 1600 and 3200 particles (h, spacings
/// and masses / k; fixed dt / k, or the CFL rule), L1 errors over [−0.4, 0.4] and
/// [−0.35, 0.35], and the observed order log2(E_N / E_2N). Prints Markdown tables; asserts
/// only that the error falls.
#[test]
#[ignore = "resolution study (about 15 s in release): cargo test --release -- --ignored shock_tube_convergence"]
fn shock_tube_convergence() {
    for (label, fixed) in [("fixed dt = 0.005 s / k", true), ("CFL, C = 0.25", false)] {
        let mut rows = Vec::new();
        for k in [1, 2, 4, 8] {
            let dir = tempfile::tempdir().expect("tempdir");
            let mut sets = refine_sets(k, fixed);
            if !fixed {
                sets.push("time.step=cfl".into());
                sets.push("time.cfl=0.25".into());
            }
            let run = run_tube(&sets, dir.path());
            let steps = run.summary["steps"].as_u64().unwrap_or(0);
            rows.push((400 * k, steps, run.l1(-0.4, 0.4), run.l1(-0.35, 0.35)));
        }
        println!("\n{label}");
        println!(
            "| N | steps | window | L1 rho | L1 v | L1 p | L1 e | order (rho) |\n|---|---|---|---|---|---|---|---|"
        );
        for (w, pick) in [("[-0.4, 0.4]", 0usize), ("[-0.35, 0.35]", 1)] {
            for r in 0..rows.len() {
                let (n, steps, a, b) = &rows[r];
                let l = if pick == 0 { a } else { b };
                let order = if r == 0 {
                    "".to_string()
                } else {
                    let prev = if pick == 0 { &rows[r - 1].2 } else { &rows[r - 1].3 };
                    format!("{:.2}", (prev.rho / l.rho).log2())
                };
                println!("| {n} | {steps} | {w} | {:.4e} | {:.4e} | {:.4e} | {:.4e} | {order} |", l.rho, l.v, l.p, l.e);
            }
        }
        for r in 1..rows.len() {
            assert!(rows[r].2.rho < rows[r - 1].2.rho, "{label}: the L1 density error must fall with resolution");
        }
    }
}
