//! Bring your own legacy code (docs/migration.md): the fixture `tests/legacy/` (a Liu-style F77
//! code written for these tests) built by `blastsph legacy build`, its routines called through the
//! run-time loader on small arrays and checked against the formulas of its source (with the same
//! single-precision constants), its own program run to the end of the shock tube, and every bad
//! manifest or build refused with one line and exit status 2.

use blastsph::migration::{Args, LegacyLib, build, check_capacity};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::OnceLock;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn fixture() -> PathBuf {
    root().join("tests/legacy")
}

fn scratch(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("migration").join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("scratch folder");
    d
}

/// One build of the fixture for the tests of this file that call routines.
fn shared() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let d = scratch("shared");
        build(&fixture().join("legacy.toml"), &d).expect("the fixture builds");
        d
    })
}

fn lib() -> LegacyLib {
    LegacyLib::open(shared()).expect("the fixture's library loads")
}

fn blastsph(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_blastsph")).args(args).current_dir(root()).output().expect("blastsph runs")
}

/// A deterministic generator of inputs (xorshift64*), values in [0, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The fixture's cubic spline in 1D (kernel.f, skf = 1) with gfortran's reading of it: the literal
/// `2./3.` is a default-real (f32) constant; `q**3` is (q*q)*q; the operations in source order.
fn cubic(r: f64, dx: f64, h: f64) -> (f64, f64) {
    let q = r / h;
    let fac = 1.0 / h;
    if (0.0..=1.0).contains(&q) {
        let w = fac * ((2.0f32 / 3.0f32) as f64 - q * q + q * q * q / 2.0);
        let g = fac * (-2.0 + 1.5 * q) / (h * h) * dx;
        (w, g)
    } else if q > 1.0 && q <= 2.0 {
        let a = 2.0 - q;
        let w = fac / 6.0 * (a * a * a);
        let g = -(fac / 6.0 * 3.0 * (a * a) / h * (dx / r));
        (w, g)
    } else {
        (0.0, 0.0)
    }
}

/// Particles on a line with jitter and per-particle h (1D, as the fixture's dim).
fn cloud(n: usize, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut g = Rng(seed);
    let x: Vec<f64> = (0..n).map(|i| 0.01 * i as f64 + 0.004 * (g.next() - 0.5)).collect();
    let h: Vec<f64> = (0..n).map(|_| 0.012 + 0.006 * g.next()).collect();
    (x, h)
}

/// The pairs the fixture's direct_find forms (i < j, sqrt(r²) < 2 h_ij), 0-based, in its order.
fn pairs_of(x: &[f64], h: &[f64]) -> (Vec<i32>, Vec<i32>) {
    let (mut pi, mut pj) = (Vec::new(), Vec::new());
    for i in 0..x.len() {
        for j in i + 1..x.len() {
            let d = x[i] - x[j];
            let hij = (h[i] + h[j]) / 2.0;
            if (d * d).sqrt() < 2.0 * hij {
                pi.push(i as i32);
                pj.push(j as i32);
            }
        }
    }
    (pi, pj)
}

fn same_bits(what: &str, got: &[f64], want: &[f64]) {
    assert_eq!(got.len(), want.len(), "{what}: lengths");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert_eq!(g.to_bits(), w.to_bits(), "{what}[{k}]: legacy {g:e}, formula {w:e}");
    }
}

#[test]
fn the_fixture_builds_with_the_cli() {
    let out = scratch("cli_build");
    let t = std::time::Instant::now();
    let o = blastsph(&["legacy", "build", "tests/legacy/legacy.toml", "--out", out.to_str().unwrap()]);
    let secs = t.elapsed().as_secs_f64();
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.join("liblegacy.so").is_file() && out.join("program").is_file() && out.join("build.log").is_file());
    let info: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("build.json")).unwrap()).expect("build.json");
    // param.inc's values, the last one an expression (20*maxn) that only the compiler evaluates
    assert_eq!(
        (info["dim"].as_u64(), info["maxn"].as_u64(), info["max_interaction"].as_u64()),
        (Some(1), Some(1000), Some(20000))
    );
    assert_eq!(info["routines"].as_array().map(|r| r.len()), Some(10));
    let kernel = info["routines"].as_array().unwrap().iter().find(|r| r["name"] == "kernel").unwrap();
    let b: Vec<&str> = kernel["bindings"].as_array().unwrap().iter().map(|b| b["name"].as_str().unwrap()).collect();
    assert_eq!(b, ["niac", "pair_i", "pair_j", "x", "hsml", "w", "dwdx"]);
    let dummies: Vec<&str> = kernel["args"].as_array().unwrap().iter().map(|a| a["dummy"].as_str().unwrap()).collect();
    assert_eq!(dummies, ["r", "dx", "hsml", "w", "dwdx"], "the dummy names read from the source");
    let sph =
        info["sources"].as_array().unwrap().iter().find(|s| s["path"].as_str().unwrap().ends_with("sph.f")).unwrap();
    assert_eq!(sph["program_unit"], true, "the main program is kept out of the library");
    assert!(info["flags"]["fixed_form"].as_array().unwrap().iter().any(|f| f == "-std=legacy"));
    assert!(info["flags"]["fixed_form"].as_array().unwrap().iter().any(|f| f == "-ffp-contract=off"));
    // the sources are unmodified: nothing is written beside them
    let names: Vec<String> =
        std::fs::read_dir(fixture()).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into()).collect();
    assert!(names.iter().all(|n| n.ends_with(".f") || n.ends_with(".inc") || n.ends_with(".toml")), "{names:?}");
    println!("legacy build of the fixture: {secs:.1} s");
}

#[test]
fn p_gas_per_particle_is_the_books_ideal_gas() {
    let lib = lib();
    let mut g = Rng(7);
    let n = 37;
    let mut rho: Vec<f64> = (0..n).map(|_| 0.1 + 2.0 * g.next()).collect();
    let mut u: Vec<f64> = (0..n).map(|_| 0.5 + 3.0 * g.next()).collect();
    let (mut p, mut c) = (vec![f64::NAN; n], vec![f64::NAN; n]);
    let mut nt = [n as i32];
    let (rho0, u0) = (rho.clone(), u.clone());
    let mut args =
        Args::new().int("ntotal", &mut nt).real("rho", &mut rho).real("u", &mut u).real("p", &mut p).real("c", &mut c);
    lib.routine("p_gas").unwrap().call(&mut args).unwrap();
    // gam = 1.4 is a default-real literal: 1.39999997615814...
    let gam = 1.4f32 as f64;
    let want_p: Vec<f64> = (0..n).map(|i| (gam - 1.0) * rho0[i] * u0[i]).collect();
    let want_c: Vec<f64> = (0..n).map(|i| ((gam - 1.0) * u0[i]).sqrt()).collect();
    same_bits("p", &p, &want_p);
    same_bits("c", &c, &want_c);
    same_bits("rho unchanged", &rho, &rho0);
    // and not the adiabatic sound speed
    assert!(c.iter().zip(&u0).all(|(c, u)| *c < (1.4 * 0.4 * u).sqrt() * 0.9));
}

#[test]
fn kernel_per_pair_matches_its_formula_and_pairs_stay_zero_based() {
    let lib = lib();
    let (mut x, mut h) = cloud(40, 11);
    let (mut pi, mut pj) = pairs_of(&x, &h);
    // add pairs beyond the support (W = 0) and one of a particle with itself (r = 0)
    pi.extend([0, 3, 5]);
    pj.extend([30, 39, 5]);
    let np = pi.len();
    let (pi0, pj0) = (pi.clone(), pj.clone());
    let (mut w, mut dw) = (vec![f64::NAN; np], vec![f64::NAN; np]);
    let mut niac = [np as i32];
    let mut args = Args::new()
        .int("niac", &mut niac)
        .int("pair_i", &mut pi)
        .int("pair_j", &mut pj)
        .real("x", &mut x)
        .real("hsml", &mut h)
        .real("w", &mut w)
        .real("dwdx", &mut dw);
    lib.routine("kernel").unwrap().call(&mut args).unwrap();
    let mut want_w = Vec::new();
    let mut want_g = Vec::new();
    for k in 0..np {
        let (i, j) = (pi0[k] as usize, pj0[k] as usize);
        let d = x[i] - x[j];
        let (a, b) = cubic((d * d).sqrt(), d, (h[i] + h[j]) / 2.0);
        want_w.push(a);
        want_g.push(b);
    }
    same_bits("w", &w, &want_w);
    same_bits("dwdx", &dw, &want_g);
    assert_eq!((pi, pj), (pi0, pj0), "pair lists come back 0-based");
    assert!(want_w.iter().filter(|v| **v > 0.0).count() > 20 && want_w.contains(&0.0));
    // both branches of the spline were reached
    let q: Vec<f64> = (0..np - 3).map(|k| want_g[k]).collect();
    assert!(q.iter().any(|g| g.abs() > 0.0));
}

#[test]
fn direct_find_returns_zero_based_pairs_with_the_kernel_and_refuses_too_small_arrays() {
    let lib = lib();
    let n = 60;
    let (mut x, mut h) = cloud(n, 23);
    let (want_i, want_j) = pairs_of(&x, &h);
    let cap = 2000;
    let (mut pi, mut pj) = (vec![-7; cap], vec![-7; cap]);
    let (mut w, mut dw) = (vec![0.0; cap], vec![0.0; cap]);
    let mut cnt = vec![-1; n];
    let (mut step, mut nt, mut niac) = ([1], [n as i32], [0]);
    let mut args = Args::new()
        .int("itimestep", &mut step)
        .int("ntotal", &mut nt)
        .real("hsml", &mut h)
        .real("x", &mut x)
        .int("niac", &mut niac)
        .int("pair_i", &mut pi)
        .int("pair_j", &mut pj)
        .real("w", &mut w)
        .real("dwdx", &mut dw)
        .int("countiac", &mut cnt);
    lib.routine("direct_find").unwrap().call(&mut args).unwrap();
    drop(args);
    let np = niac[0] as usize;
    assert_eq!(np, want_i.len());
    assert_eq!(&pi[..np], &want_i[..], "pair_i, 0-based, in the search's order");
    assert_eq!(&pj[..np], &want_j[..]);
    assert!(pi[np..].iter().all(|v| *v == -7), "nothing written past niac");
    let mut want_w = Vec::new();
    for k in 0..np {
        let (i, j) = (want_i[k] as usize, want_j[k] as usize);
        let d = x[i] - x[j];
        want_w.push(cubic((d * d).sqrt(), d, (h[i] + h[j]) / 2.0));
    }
    same_bits("w", &w[..np], &want_w.iter().map(|v| v.0).collect::<Vec<_>>());
    same_bits("dwdx", &dw[..np], &want_w.iter().map(|v| v.1).collect::<Vec<_>>());
    for (i, got) in cnt.iter().enumerate() {
        let c = want_i.iter().chain(&want_j).filter(|v| **v as usize == i).count();
        assert_eq!(*got as usize, c, "countiac of particle {i}");
    }

    // the same through the per-pair kernel: the shim forms r, dx and h as direct_find does
    let (mut pi2, mut pj2) = (want_i.clone(), want_j.clone());
    let (mut w2, mut dw2) = (vec![0.0; np], vec![0.0; np]);
    let mut niac2 = [np as i32];
    let mut args = Args::new()
        .int("niac", &mut niac2)
        .int("pair_i", &mut pi2)
        .int("pair_j", &mut pj2)
        .real("x", &mut x)
        .real("hsml", &mut h)
        .real("w", &mut w2)
        .real("dwdx", &mut dw2);
    lib.routine("kernel").unwrap().call(&mut args).unwrap();
    same_bits("kernel each_pair = direct_find's kernel", &w2, &w[..np]);
    same_bits("kernel each_pair = direct_find's gradient", &dw2, &dw[..np]);

    // pair arrays too small for what the search finds: an error, the first pairs kept
    let small = np / 2;
    let (mut pi, mut pj, mut w, mut dw) = (vec![0; small], vec![0; small], vec![0.0; small], vec![0.0; small]);
    let mut niac = [0];
    let mut args = Args::new()
        .int("itimestep", &mut step)
        .int("ntotal", &mut nt)
        .real("hsml", &mut h)
        .real("x", &mut x)
        .int("niac", &mut niac)
        .int("pair_i", &mut pi)
        .int("pair_j", &mut pj)
        .real("w", &mut w)
        .real("dwdx", &mut dw)
        .int("countiac", &mut cnt);
    let e = lib.routine("direct_find").unwrap().call(&mut args).unwrap_err().to_string();
    drop(args);
    assert!(e.contains("more than the pair arrays hold"), "{e}");
    assert_eq!(niac[0] as usize, np);
    assert_eq!(&pi[..], &want_i[..small]);
}

#[test]
fn sum_density_is_the_self_term_then_the_pairs_in_order() {
    let lib = lib();
    let n = 50;
    let (mut x, mut h) = cloud(n, 5);
    let (mut pi, mut pj) = pairs_of(&x, &h);
    let np = pi.len();
    let mut g = Rng(99);
    let mut mass: Vec<f64> = (0..n).map(|_| 0.001 + 0.002 * g.next()).collect();
    let mut w = vec![0.0; np];
    let mut dw = vec![0.0; np];
    let mut niac = [np as i32];
    let mut args = Args::new()
        .int("niac", &mut niac)
        .int("pair_i", &mut pi)
        .int("pair_j", &mut pj)
        .real("x", &mut x)
        .real("hsml", &mut h)
        .real("w", &mut w)
        .real("dwdx", &mut dw);
    lib.routine("kernel").unwrap().call(&mut args).unwrap();
    drop(args);
    let mut rho = vec![1.0; n];
    let mut itype = vec![1; n];
    let mut nt = [n as i32];
    let mut args = Args::new()
        .int("ntotal", &mut nt)
        .real("hsml", &mut h)
        .real("mass", &mut mass)
        .int("niac", &mut niac)
        .int("pair_i", &mut pi)
        .int("pair_j", &mut pj)
        .real("w", &mut w)
        .int("itype", &mut itype)
        .real("rho", &mut rho);
    lib.routine("sum_density").unwrap().call(&mut args).unwrap();
    drop(args);
    let mut want: Vec<f64> = (0..n).map(|i| cubic(0.0, 0.0, h[i]).0 * mass[i]).collect();
    for k in 0..np {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        want[i] += mass[j] * w[k];
        want[j] += mass[i] * w[k];
    }
    same_bits("rho", &rho, &want);
}

#[test]
fn the_safe_api_checks_kinds_lengths_and_indices() {
    let lib = lib();
    let r = lib.routine("p_gas").unwrap();
    let (mut rho, mut u, mut p, mut c) = (vec![1.0; 3], vec![1.0; 3], vec![0.0; 3], vec![0.0; 3]);
    let mut nt = [3];
    // a missing argument
    let mut a = Args::new().int("ntotal", &mut nt).real("rho", &mut rho).real("u", &mut u).real("p", &mut p);
    assert!(r.call(&mut a).unwrap_err().to_string().contains("\"c\" missing"));
    drop(a);
    // more particles than ntotal says the arrays hold
    let mut nt4 = [4];
    let mut a =
        Args::new().int("ntotal", &mut nt4).real("rho", &mut rho).real("u", &mut u).real("p", &mut p).real("c", &mut c);
    assert!(r.call(&mut a).unwrap_err().to_string().contains("ntotal is 4"));
    drop(a);
    // more than maxn
    let mut big = vec![1.0; 1001];
    let mut a =
        Args::new().int("ntotal", &mut nt).real("rho", &mut big).real("u", &mut u).real("p", &mut p).real("c", &mut c);
    assert!(r.call(&mut a).unwrap_err().to_string().contains("more than the build's 1000"));
    drop(a);
    // a pair index outside the particles
    let k = lib.routine("kernel").unwrap();
    let (mut x, mut h) = (vec![0.0, 0.01], vec![0.01, 0.01]);
    let (mut pi, mut pj, mut w, mut dw, mut ni) = (vec![0], vec![2], vec![0.0], vec![0.0], [1]);
    let mut a = Args::new()
        .int("niac", &mut ni)
        .int("pair_i", &mut pi)
        .int("pair_j", &mut pj)
        .real("x", &mut x)
        .real("hsml", &mut h)
        .real("w", &mut w)
        .real("dwdx", &mut dw);
    assert!(k.call(&mut a).unwrap_err().to_string().contains("pair_j[0] = 2"));
    drop(a);
    // an unknown routine
    assert!(lib.routine("tree_search").unwrap_err().to_string().contains("no routine tree_search"));
    // the case-size check the solver calls
    let e = check_capacity(1000, 20000, 1001, None).unwrap_err();
    assert_eq!(e.exit_code(), 2);
    assert!(e.to_string().contains("maxn = 1000"), "{e}");
    assert!(check_capacity(1000, 20000, 1000, Some(20000)).is_ok());
    assert!(check_capacity(1000, 20000, 10, Some(20001)).unwrap_err().to_string().contains("max_interaction = 20000"));
    assert!(lib.info().check_capacity(400, Some(5000)).is_ok());
}

/// The fixture's own program: the shock tube for 40 steps, its final state written to a file.
#[test]
fn the_fixtures_own_program_runs_the_shock_tube() {
    let work = scratch("program_run");
    let exe = shared().join("program");
    let mut child = Command::new(&exe)
        .current_dir(&work)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the fixture's program starts");
    {
        use std::io::Write;
        child.stdin.take().unwrap().write_all(b"40\n0\n").unwrap();
    }
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(work.join("final_state.dat")).expect("final_state.dat");
    let mut lines = text.lines();
    let n: usize = lines.next().unwrap().trim().parse().unwrap();
    assert_eq!(n, 400);
    let rows: Vec<Vec<f64>> =
        lines.map(|l| l.split_whitespace().map(|v| v.parse::<f64>().unwrap()).collect::<Vec<f64>>()).collect();
    assert_eq!(rows.len(), n);
    // columns: number, type, x, vx, mass, rho, p, u, hsml
    let x: Vec<f64> = rows.iter().map(|r| r[2]).collect();
    let v: Vec<f64> = rows.iter().map(|r| r[3]).collect();
    let m: Vec<f64> = rows.iter().map(|r| r[4]).collect();
    let rho: Vec<f64> = rows.iter().map(|r| r[5]).collect();
    assert!(m.iter().all(|v| *v == (0.75f32 / 400f32) as f64), "the single-precision mass");
    assert!(x.windows(2).all(|p| p[0] < p[1]), "no particle overtakes another in 1D");
    // against the exact solution at t = 40 dt (the volume-weighted L1 of docs/validation.md)
    use blastsph::analysis::riemann::{Riemann, Side};
    let ex = Riemann::solve(Side { rho: 1.0, u: 0.0, p: 1.0 }, Side { rho: 0.25, u: 0.0, p: 0.1795 }, 1.4).unwrap();
    let t = 40.0 * (0.005f32 as f64);
    let (mut num, mut den) = (0.0, 0.0);
    for i in 0..n {
        if (-0.4..=0.4).contains(&x[i]) {
            let vol = m[i] / rho[i];
            num += vol * (rho[i] - ex.sample(x[i] / t).rho).abs();
            den += vol;
        }
    }
    let l1 = num / den;
    println!("fixture program: L1(rho) over [-0.4, 0.4] = {l1:.6} (REFERENCES.md: the book code 0.01553)");
    assert!(l1 < 0.02, "L1(rho) = {l1}");
    // the shocked gas moves at about u* = 0.673 m/s
    let mid: Vec<f64> = (0..n).filter(|&i| x[i] > 0.0 && x[i] < 0.2).map(|i| v[i]).collect();
    assert!(mid.iter().all(|u| (u - ex.u_star).abs() < 0.05), "{mid:?}");
}

// ---------------------------------------------------------------------------------------------
// bad manifests and bad builds: one line, exit status 2

/// A copy of the fixture in a scratch folder, with `edit` applied to its manifest text.
fn variant(name: &str, edit: impl Fn(&str) -> String) -> PathBuf {
    let d = scratch(name);
    for e in std::fs::read_dir(fixture()).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, d.join(p.file_name().unwrap())).unwrap();
    }
    let m = d.join("legacy.toml");
    let text = std::fs::read_to_string(&m).unwrap();
    std::fs::write(&m, edit(&text)).unwrap();
    d
}

/// `legacy build` refuses: status 2, one line on stderr naming every needle, no panic.
fn refused(dir: &Path, needles: &[&str]) -> String {
    let out = dir.join("build");
    let o = blastsph(&["legacy", "build", dir.join("legacy.toml").to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let se = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(2), "exit status; stderr: {se}");
    assert_eq!(se.lines().count(), 1, "one line: {se}");
    assert!(!se.contains("panicked"), "{se}");
    for n in needles {
        assert!(se.contains(n), "the error must name `{n}`: {se}");
    }
    se
}

#[test]
fn an_unknown_argument_name_is_refused() {
    let d = variant("bad_name", |t| t.replace("\"rho\", \"u\", \"p\", \"c\"]", "\"rho\", \"energy\", \"p\", \"c\"]"));
    refused(&d, &["unknown argument name \"energy\"", "p_gas"]);
}

#[test]
fn a_routine_missing_from_the_sources_is_refused() {
    let d = variant("missing_routine", |t| {
        format!("{t}\n[[routine]]\nname = \"tree_search\"\nmodule = \"nnps\"\nargs = [\"x\"]\n")
    });
    refused(&d, &["tree_search", "not found in the sources"]);
}

#[test]
fn a_dim_that_disagrees_with_param_inc_is_refused() {
    let d = variant("bad_dim", |t| t.replace("dim = 1", "dim = 2"));
    refused(&d, &["dim = 2", "param.inc", "dim = 1"]);
}

#[test]
fn a_missing_source_is_refused() {
    let d = variant("missing_source", |t| t.replace("sources = [\"*.f\"]", "sources = [\"*.f\", \"extra/tree.f\"]"));
    refused(&d, &["extra/tree.f", "matches no file"]);
}

#[test]
fn a_compile_error_in_the_users_code_is_refused_with_the_log() {
    let d = variant("compile_error", |t| t.to_string());
    std::fs::write(
        d.join("broken.f"),
        "      subroutine broken(a)\n      double precision a\n      a = (1.0 +\n      end\n",
    )
    .unwrap();
    let se = refused(&d, &["broken.f", "compile error", "Error", "build.log"]);
    let log = std::fs::read_to_string(d.join("build/build.log")).expect("the log is written");
    assert!(log.contains("broken.f") && log.contains("Error"), "the compiler's message is in the log");
    assert!(se.contains(&d.join("build/build.log").display().to_string()), "the line gives the log's path: {se}");
}

#[test]
fn a_wrong_number_or_type_of_arguments_is_refused() {
    let d = variant("arg_count", |t| t.replace("\"rho\", \"u\", \"p\", \"c\"]", "\"rho\", \"u\", \"p\"]"));
    refused(&d, &["p_gas", "names 3 arguments", "declares 4", "rho, u, p, c"]);
    let d = variant("arg_type", |t| t.replace("\"rho\", \"u\", \"p\", \"c\"]", "\"rho\", \"itype\", \"p\", \"c\"]"));
    refused(&d, &["p_gas", "argument u", "double", "itype"]);
}

#[test]
fn a_flag_that_changes_the_arithmetic_is_refused() {
    let d = variant("fast_math", |t| t.replace("[\"-finit-local-zero\"]", "[\"-finit-local-zero\", \"-ffast-math\"]"));
    refused(&d, &["-ffast-math", "fflags"]);
}

#[test]
fn a_bad_call_mode_or_module_is_refused() {
    let d = variant("bad_call", |t| t.replace("call = \"each_particle\"", "call = \"per_particle\""));
    refused(&d, &["call", "per_particle"]);
    let d = variant("bad_module", |t| t.replace("module = \"xsph\"", "module = \"xsph,smoothnig\""));
    refused(&d, &["smoothnig", "not a blastsph module"]);
    let d =
        variant("pair_in_particle", |t| t.replace("\"rho\", \"u\", \"p\", \"c\"]", "\"rho\", \"u\", \"p\", \"w\"]"));
    refused(&d, &["\"w\"", "each_particle"]);
}

// ---------------------------------------------------------------------------------------------
// the documentation a user follows

#[test]
fn the_docs_table_lists_every_vocabulary_name() {
    use blastsph::migration::vocab::{PAIR_TERMS, TERMS};
    let doc = std::fs::read_to_string(root().join("docs/migration.md")).unwrap();
    for t in TERMS.iter().chain(PAIR_TERMS) {
        assert!(doc.contains(&format!("| `{}` |", t.name)), "docs/migration.md has no row for `{}`", t.name);
    }
}

/// The manifest for the book code that docs/migration.md gives is accepted as it is, and builds
/// against the fixture (which has the book's routines and argument lists, less two); with it, as a
/// user who copies it whole would, the dual run is at 0 ULP and `run --legacy` ends as the program.
#[test]
fn the_books_manifest_in_the_docs_builds_against_the_fixture() {
    let doc = std::fs::read_to_string(root().join("docs/migration.md")).unwrap();
    let from = doc.find("### A.3").expect("section A.3");
    let start = from + doc[from..].find("```toml\n").expect("a toml block") + 8;
    let end = start + doc[start..].find("```").unwrap();
    let mut table: toml::Table = doc[start..end].parse().expect("the docs' manifest is TOML");
    table.insert("sources".into(), toml::Value::Array(vec!["*.f".into()]));
    table.insert("include_dirs".into(), toml::Value::Array(vec![".".into()]));
    let d = variant("docs_manifest", |t| t.to_string());
    std::fs::write(d.join("legacy.toml"), toml::to_string(&table).unwrap()).unwrap();
    let m = blastsph::migration::manifest::load(&d.join("legacy.toml")).expect("every name is in the vocabulary");
    assert_eq!(m.routines.len(), 17);
    // the fixture has no ext_force, virt_part (link_list, tree_search, art_heat are commented out)
    let absent = ["ext_force", "virt_part"];
    if let Some(toml::Value::Array(rs)) = table.get_mut("routine") {
        rs.retain(|r| !absent.contains(&r.get("name").and_then(|n| n.as_str()).unwrap_or("")));
    }
    std::fs::write(d.join("legacy.toml"), toml::to_string(&table).unwrap()).unwrap();
    let info = build(&d.join("legacy.toml"), &d.join("build")).expect("the docs' manifest builds");
    assert_eq!(info.routines.len(), 15);
    let lg = d.join("build");
    let out = d.join("dual");
    blastsph_ok(
        &[
            "dual",
            "shock_tube",
            "--legacy",
            lg.to_str().unwrap(),
            "--compat",
            "liu-book",
            "--out",
            out.to_str().unwrap(),
        ],
        0,
    );
    let (r, rows) = report_rows(&out.join("dual_report.json"));
    for (stage, fields) in MAPPED {
        for f in *fields {
            assert_eq!(row(&rows, stage, f)["max_ulp"], 0, "{stage} {f}");
        }
    }
    let st = &r["legacy"]["routines"];
    for (name, status) in [("viscosity", "alone"), ("single_step", "not run"), ("time_integration", "not run")] {
        assert_eq!(st[name]["status"], status, "{name}: {}", st[name]);
    }
    assert_run_ends_as_the_program(&lg, "docs_run");
}

#[test]
fn an_include_file_without_the_sizes_is_refused() {
    let d = variant("no_sizes", |t| {
        t.replace(
            "fflags = [\"-finit-local-zero\"]",
            "fflags = [\"-finit-local-zero\"]\n[param_names]\nmax_interaction = \"maxpairs\"",
        )
    });
    refused(&d, &["param.inc", "maxpairs", "probe", "build.log"]);
}

/// Pairs of a cloud with random velocities, for the force routines.
struct Flow {
    n: usize,
    x: Vec<f64>,
    h: Vec<f64>,
    v: Vec<f64>,
    rho: Vec<f64>,
    mass: Vec<f64>,
    u: Vec<f64>,
    pi: Vec<i32>,
    pj: Vec<i32>,
    dw: Vec<f64>,
}

fn flow(n: usize, seed: u64) -> Flow {
    let (x, h) = cloud(n, seed);
    let (pi, pj) = pairs_of(&x, &h);
    let mut g = Rng(seed ^ 0x9e37);
    let v = (0..n).map(|_| g.next() - 0.5).collect();
    let rho = (0..n).map(|_| 0.3 + g.next()).collect();
    let mass = (0..n).map(|_| 0.001 + 0.001 * g.next()).collect();
    let u = (0..n).map(|_| 1.0 + 2.0 * g.next()).collect();
    let dw = (0..pi.len())
        .map(|k| {
            let (i, j) = (pi[k] as usize, pj[k] as usize);
            let d = x[i] - x[j];
            cubic((d * d).sqrt(), d, (h[i] + h[j]) / 2.0).1
        })
        .collect();
    Flow { n, x, h, v, rho, mass, u, pi, pj, dw }
}

/// art_visc as docs/compat-liu-book.md §7 describes it: etq = 0.1e0, the μ denominator
/// ((h̄h̄)η)η, the energy per component into i and j inside the pair loop, halved at the end.
#[test]
fn art_visc_is_the_books_viscosity_with_its_energy_order() {
    let lib = lib();
    let mut f = flow(70, 31);
    let n = f.n;
    let np = f.pi.len();
    let mut g = Rng(3);
    let mut c: Vec<f64> = (0..n).map(|_| 0.5 + g.next()).collect();
    let (mut a, mut e) = (vec![f64::NAN; n], vec![f64::NAN; n]);
    let mut w = vec![0.0; np];
    let (mut nt, mut niac) = ([n as i32], [np as i32]);
    let mut args = Args::new()
        .int("ntotal", &mut nt)
        .real("hsml", &mut f.h)
        .real("mass", &mut f.mass)
        .real("x", &mut f.x)
        .real("vx", &mut f.v)
        .int("niac", &mut niac)
        .real("rho", &mut f.rho)
        .real("c", &mut c)
        .int("pair_i", &mut f.pi)
        .int("pair_j", &mut f.pj)
        .real("w", &mut w)
        .real("dwdx", &mut f.dw)
        .real("dvxdt", &mut a)
        .real("dedt", &mut e);
    lib.routine("art_visc").unwrap().call(&mut args).unwrap();
    drop(args);
    let etq = 0.1f32 as f64;
    let (mut wa, mut we) = (vec![0.0; n], vec![0.0; n]);
    let mut approaching = 0;
    for k in 0..np {
        let (i, j) = (f.pi[k] as usize, f.pj[k] as usize);
        let hij = (f.h[i] + f.h[j]) / 2.0;
        let dv = f.v[i] - f.v[j];
        let dx = f.x[i] - f.x[j];
        let (vr, rr) = (0.0 + dv * dx, 0.0 + dx * dx);
        if vr < 0.0 {
            approaching += 1;
            let muv = hij * vr / (rr + hij * hij * etq * etq);
            let mc = 0.5 * (c[i] + c[j]);
            let mrho = 0.5 * (f.rho[i] + f.rho[j]);
            let piv = (muv - mc) * muv / mrho;
            let hh = -piv * f.dw[k];
            wa[i] += f.mass[j] * hh;
            wa[j] -= f.mass[i] * hh;
            we[i] -= f.mass[j] * dv * hh;
            we[j] -= f.mass[i] * dv * hh;
        }
    }
    let we: Vec<f64> = we.iter().map(|v| 0.5 * v).collect();
    assert!(approaching > 10 && approaching < np, "both approaching and receding pairs");
    same_bits("dvxdt", &a, &wa);
    same_bits("dedt", &e, &we);
    // blastsph's current form, 0.5·Π·(v·∇W) per pair with η in double, differs
    let mut other = vec![0.0; n];
    for k in 0..np {
        let (i, j) = (f.pi[k] as usize, f.pj[k] as usize);
        let hij = 0.5 * (f.h[i] + f.h[j]);
        let dv = f.v[i] - f.v[j];
        let dx = f.x[i] - f.x[j];
        let vr = dv * dx;
        if vr < 0.0 {
            let muv = hij * vr / (dx * dx + (0.1 * hij) * (0.1 * hij));
            let piv = (muv - 0.5 * (c[i] + c[j])) * muv / (0.5 * (f.rho[i] + f.rho[j]));
            let de = 0.5 * piv * (dv * f.dw[k]);
            other[i] += f.mass[j] * de;
            other[j] += f.mass[i] * de;
        }
    }
    assert!(other.iter().zip(&e).any(|(a, b)| a.to_bits() != b.to_bits()), "the test tells the two forms apart");
}

/// int_force as docs/compat-liu-book.md §6 describes it (pa_sph = 2, no physical viscosity): the
/// EOS of every particle by its type, the force, the energy rate summed per component and halved.
#[test]
fn int_force_calls_the_eos_by_type_and_sums_the_books_way() {
    let lib = lib();
    let mut f = flow(64, 47);
    let n = f.n;
    let np = f.pi.len();
    let mut itype: Vec<i32> = (0..n).map(|i| if i % 5 == 0 { 2 } else { 1 }).collect();
    let (mut p, mut c, mut a, mut e, mut tds) =
        (vec![f64::NAN; n], vec![f64::NAN; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let (mut eta, mut t) = (vec![0.0; n], vec![0.0; n]);
    let (mut step, mut nt, mut niac, mut dt) = ([1], [n as i32], [np as i32], [0.005]);
    let itype0 = itype.clone();
    let mut args = Args::new()
        .int("itimestep", &mut step)
        .real("dt", &mut dt)
        .int("ntotal", &mut nt)
        .real("hsml", &mut f.h)
        .real("mass", &mut f.mass)
        .real("vx", &mut f.v)
        .int("niac", &mut niac)
        .real("rho", &mut f.rho)
        .real("eta", &mut eta)
        .int("pair_i", &mut f.pi)
        .int("pair_j", &mut f.pj)
        .real("dwdx", &mut f.dw)
        .real("u", &mut f.u)
        .int("itype", &mut itype)
        .real("x", &mut f.x)
        .real("t", &mut t)
        .real("c", &mut c)
        .real("p", &mut p)
        .real("dvxdt", &mut a)
        .real("tdsdt", &mut tds)
        .real("dedt", &mut e);
    lib.routine("int_force").unwrap().call(&mut args).unwrap();
    drop(args);
    let gam = 1.4f32 as f64;
    let cw = 0.01f32 as f64;
    let wp: Vec<f64> =
        (0..n).map(|i| if itype0[i] == 1 { (gam - 1.0) * f.rho[i] * f.u[i] } else { cw * cw * f.rho[i] }).collect();
    let wc: Vec<f64> = (0..n).map(|i| if itype0[i] == 1 { ((gam - 1.0) * f.u[i]).sqrt() } else { cw }).collect();
    same_bits("p", &p, &wp);
    same_bits("c", &c, &wc);
    let (mut wa, mut we) = (vec![0.0; n], vec![0.0; n]);
    for k in 0..np {
        let (i, j) = (f.pi[k] as usize, f.pj[k] as usize);
        let h = -(wp[i] / (f.rho[i] * f.rho[i]) + wp[j] / (f.rho[j] * f.rho[j])) * f.dw[k];
        let he = 0.0 + (f.v[j] - f.v[i]) * h;
        wa[i] += f.mass[j] * h;
        wa[j] -= f.mass[i] * h;
        we[i] += f.mass[j] * he;
        we[j] += f.mass[i] * he;
    }
    let we: Vec<f64> = we.iter().map(|v| 0.0 + 0.5 * v).collect();
    same_bits("dvxdt", &a, &wa);
    same_bits("dedt", &e, &we);
    assert!(tds.iter().all(|v| *v == 0.0), "no viscous entropy without visc");
}

#[test]
fn the_build_folder_cannot_be_the_source_folder() {
    let o = blastsph(&["legacy", "build", "tests/legacy/legacy.toml", "--out", "tests/legacy"]);
    let se = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{se}");
    assert_eq!(se.lines().count(), 1, "{se}");
    assert!(se.contains("folder of the sources"), "{se}");
    assert!(
        !fixture().join("build.log").exists() && !fixture().join("obj").exists(),
        "nothing written beside the sources"
    );
}

#[test]
fn an_argument_given_twice_is_refused_by_the_safe_api() {
    let lib = lib();
    let (mut rho, mut u, mut p, mut c, mut rho2) = (vec![1.0], vec![1.0], vec![0.0], vec![0.0], vec![2.0]);
    let mut nt = [1];
    let mut a = Args::new()
        .int("ntotal", &mut nt)
        .real("rho", &mut rho)
        .real("u", &mut u)
        .real("p", &mut p)
        .real("c", &mut c)
        .real("RHO", &mut rho2);
    let e = lib.routine("p_gas").unwrap().call(&mut a).unwrap_err().to_string();
    assert!(e.contains("\"rho\" given twice"), "{e}");
}

// ---------------------------------------------------------------------------------------------
// part 2: the fixture run by blastsph (`run --legacy`), dual-checked routine by routine against
// the Rust twins (`dual --legacy`, with and without `--compat liu-book`), and the ledger

/// `blastsph ARGS`, which must exit with `code`; returns stdout.
fn blastsph_ok(args: &[&str], code: i32) -> String {
    let o = blastsph(args);
    let (so, se) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert_eq!(o.status.code(), Some(code), "blastsph {args:?}\nstdout: {so}\nstderr: {se}");
    so.into_owned()
}

fn report_rows(path: &Path) -> (serde_json::Value, Vec<serde_json::Value>) {
    let r: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).expect("report")).expect("json");
    let rows = r["rows"].as_array().expect("rows").clone();
    (r, rows)
}

/// The routines of the fixture that the shock tube runs, each with the fields it writes.
const MAPPED: &[(&str, &[&str])] = &[
    ("legacy.direct_find", &["pair_i", "pair_j", "w", "dwdx"]),
    ("legacy.kernel", &["w", "dwdx"]),
    ("legacy.sum_density", &["rho"]),
    ("legacy.p_gas", &["p", "c"]),
    ("legacy.int_force", &["p", "c", "acc", "dde"]),
    ("legacy.art_visc", &["acc", "dde"]),
];

fn row<'a>(rows: &'a [serde_json::Value], stage: &str, field: &str) -> &'a serde_json::Value {
    rows.iter()
        .find(|r| r["stage"] == stage && r["field"] == field)
        .unwrap_or_else(|| panic!("no row {stage} {field} in the report"))
}

#[test]
fn dual_legacy_with_the_liu_book_profile_is_at_zero_ulp_for_every_mapped_routine() {
    let out = scratch("dual_book");
    let so = blastsph_ok(
        &[
            "dual",
            "shock_tube",
            "--legacy",
            shared().to_str().unwrap(),
            "--compat",
            "liu-book",
            "--out",
            out.to_str().unwrap(),
        ],
        0,
    );
    assert!(so.contains("40 steps compared; every compared stage within tolerance"), "{so}");
    let (r, rows) = report_rows(&out.join("dual_report.json"));
    assert_eq!(r["steps"], 40);
    for (stage, fields) in MAPPED {
        for f in *fields {
            let x = row(&rows, stage, f);
            assert_eq!(x["counterpart"], "legacy", "{x}");
            assert!(x["compared"].as_u64().unwrap() >= 400 * 40, "{stage} {f}: {x}");
            assert_eq!(x["max_ulp"], 0, "{stage} {f}: {x}");
            assert_eq!(x["out_of_tolerance"], 0, "{stage} {f}: {x}");
        }
    }
    // what each routine was compared with (the chain of Rust twins) and what was not run
    let lg = &r["legacy"]["routines"];
    assert_eq!(lg["direct_find"]["stands_for"], serde_json::json!(["nnps.search", "kernel.pairs"]));
    assert_eq!(lg["int_force"]["stands_for"], serde_json::json!(["eos.eval", "force.internal"]));
    assert_eq!(lg["sum_density"]["stands_for"], serde_json::json!(["kernel.self", "density.summation"]));
    assert_eq!(lg["input"]["status"], "setup");
    assert_eq!(lg["av_vel"]["status"], "not run");
}

#[test]
fn dual_legacy_without_the_profile_names_each_difference() {
    let out = scratch("dual_plain");
    let so =
        blastsph_ok(&["dual", "shock_tube", "--legacy", shared().to_str().unwrap(), "--out", out.to_str().unwrap()], 4);
    assert!(so.contains("MODULES OUT OF TOLERANCE"), "{so}");
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    // the same pairs in the same order (the fixture's direct_find and blastsph's direct search)
    assert_eq!(row(&rows, "legacy.direct_find", "pair_i")["out_of_tolerance"], 0);
    assert_eq!(row(&rows, "legacy.direct_find", "pair_j")["out_of_tolerance"], 0);
    // the book's sound speed sqrt((gamma-1) e) against sqrt(gamma (gamma-1) e): c differs from
    // the first evaluation, by the factor sqrt(gamma) less the single-precision gamma
    let c = row(&rows, "legacy.p_gas", "c");
    assert!(c["out_of_tolerance"].as_u64().unwrap() > 0, "{c}");
    let (lf, rs) =
        (c["first_divergence"]["fortran"].as_f64().unwrap(), c["first_divergence"]["rust"].as_f64().unwrap());
    assert!((rs / lf - 1.4f64.sqrt()).abs() < 1e-6, "c: legacy {lf}, rust {rs}");
    assert!(c["tolerance_why"].as_str().unwrap().contains("sound_speed"), "{c}");
    // the kernel's single-precision 2/3 and the viscosity's order: named, item by item
    for (stage, field, item) in [
        ("legacy.kernel", "w", "kernel"),
        ("legacy.sum_density", "rho", "literals"),
        ("legacy.art_visc", "dde", "visc_energy"),
        ("legacy.int_force", "dde", "force_energy"),
    ] {
        let x = row(&rows, stage, field);
        assert!(x["out_of_tolerance"].as_u64().unwrap() > 0, "{stage} {field}: {x}");
        assert!(x["tolerance_why"].as_str().unwrap().contains(item), "{stage} {field} must name {item}: {x}");
    }
}

/// The fixture's own program to the end of the shock tube: its final state (17 digits), once.
fn program_final_state() -> &'static [Vec<f64>] {
    static ROWS: OnceLock<Vec<Vec<f64>>> = OnceLock::new();
    ROWS.get_or_init(program_rows)
}

fn program_rows() -> Vec<Vec<f64>> {
    let work = scratch("program_run_2");
    let mut child = Command::new(shared().join("program"))
        .current_dir(&work)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the fixture's program starts");
    {
        use std::io::Write;
        child.stdin.take().unwrap().write_all(b"40\n0\n").unwrap();
    }
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(work.join("final_state.dat")).expect("final_state.dat");
    text.lines().skip(1).map(|l| l.split_whitespace().map(|v| v.parse::<f64>().unwrap()).collect()).collect()
}

/// `run CASE --legacy BUILD --compat liu-book` ends in the state of the fixture's own program, bit
/// for bit; returns the last frame.
fn assert_run_ends_as_the_program(build: &Path, name: &str) -> blastsph::output::Frame {
    let rows = program_final_state();
    let out = scratch(name);
    let so = blastsph_ok(
        &[
            "run",
            "shock_tube",
            "--legacy",
            build.to_str().unwrap(),
            "--compat",
            "liu-book",
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ],
        0,
    );
    assert!(so.contains("400 particles, 40 steps"), "{so}");
    let frames = blastsph::output::read_frames(&out.join("particles.h5")).expect("particles.h5");
    let f = frames.last().unwrap();
    assert!((f.time - 0.2).abs() < 1e-6, "t = {}", f.time);
    assert_eq!(f.x.len(), rows.len());
    // columns: number, type, x, vx, mass, rho, p, u, hsml
    for i in 0..rows.len() {
        let k = f.id[i] as usize;
        let r = &rows[k];
        let got = [f.x[i], f.vx[i], f.mass[i], f.rho[i], f.p[i], f.e[i], f.h[i]];
        let want = [r[2], r[3], r[4], r[5], r[6], r[7], r[8]];
        assert_eq!(got, want, "particle {} (x, vx, mass, rho, p, u, hsml)", k + 1);
    }
    f.clone()
}

#[test]
fn run_legacy_ends_in_the_state_of_the_codes_own_program_bit_for_bit() {
    let f = assert_run_ends_as_the_program(shared(), "run_book");
    // without the profile blastsph's own integrator and twins run around the user's routines:
    // a different end state (the sound speed alone moves rho by 1e-3 and more)
    let out2 = scratch("run_plain");
    blastsph_ok(
        &["run", "shock_tube", "--legacy", shared().to_str().unwrap(), "--out", out2.to_str().unwrap(), "--quiet"],
        0,
    );
    let g = blastsph::output::read_frames(&out2.join("particles.h5")).unwrap().pop().unwrap();
    assert_ne!(g.rho, f.rho);
}

#[test]
fn the_ledger_attributes_each_difference_to_its_item() {
    let out = scratch("ledger");
    let so = blastsph_ok(
        &["legacy", "ledger", "shock_tube", "--legacy", shared().to_str().unwrap(), "--out", out.to_str().unwrap()],
        0,
    );
    assert!(so.contains("end in the same state, bit for bit"), "{so}");
    let (r, rows) = report_rows(&out.join("ledger.json"));
    assert_eq!(r["profile"], "liu-book");
    let get = |run: &str| rows.iter().find(|x| x["run"] == run).unwrap_or_else(|| panic!("no row {run}: {so}"));
    let num = |run: &str, k: &str| get(run)[k].as_f64().unwrap();
    // the user's routines and the profile's Rust twins: the same end state
    assert_eq!(get("legacy")["particles_differing"], 0);
    assert_eq!(get("profile")["particles_differing"], 0);
    assert_eq!(get("legacy")["steps"], 40);
    // the items this case exercises move the end state; the largest is the sound speed
    for item in ["-literals", "-sound_speed", "-kernel", "-force_energy", "-visc_energy"] {
        assert!(num(item, "max_abs_rho") > 0.0 || num(item, "max_abs_e") > 0.0, "{item}: {so}");
    }
    assert!(num("-sound_speed", "max_abs_rho") > 1e-3, "{so}");
    for item in ["-literals", "-kernel", "-force_energy", "-visc_energy"] {
        assert!(num(item, "max_abs_rho") < 1e-6, "{item}: {so}");
    }
    // items of what the case does not run (virtual particles, XSPH, the quintic kernel): no effect
    for item in ["-virtual_pairs", "-xsph_velocity", "-quintic_gradient"] {
        assert_eq!(get(item)["particles_differing"], 0, "{item}: {so}");
    }
    // the case's own error: the book code's sound speed lowers its L1(rho) (REFERENCES.md 0.01553)
    let l1 = |run: &str| get(run)["l1"][0].as_f64().unwrap();
    assert!((l1("profile") - 0.01553).abs() < 2e-4, "{so}");
    assert!(l1("-sound_speed") > l1("profile"), "{so}");
}

#[test]
fn bad_legacy_runs_are_refused_with_one_line() {
    let one_line = |args: &[&str], needles: &[&str]| {
        let o = blastsph(args);
        let se = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {se}");
        assert_eq!(se.lines().count(), 1, "{se}");
        for n in needles {
            assert!(se.contains(n), "must name {n}: {se}");
        }
    };
    let lg = shared().to_str().unwrap();
    // a folder that is no build
    let empty = scratch("no_build");
    one_line(&["check", "shock_tube", "--legacy", empty.to_str().unwrap()], &[empty.to_str().unwrap()]);
    // a case of another dimension than the build's param.inc
    one_line(&["check", "underwater_box", "--legacy", lg], &["dim = 1", "dim = 2"]);
    // an unknown compat item or profile
    one_line(&["check", "shock_tube", "--legacy", lg, "--compat", "liu-book,-sound_sped"], &["sound_sped"]);
    // more particles than maxn
    one_line(
        &["check", "shock_tube", "--legacy", lg, "--set", "region.right.count=[700]"],
        &["maxn = 1000", "1020 particles"],
    );
}

/// A source that needs another compiler's module (the book's `time_print.f` uses `dfport`):
/// refused as a compile error, built once the manifest excludes it.
#[test]
fn a_file_that_does_not_compile_with_gfortran_can_be_excluded() {
    let d = variant("dfport", |t| t.to_string());
    std::fs::write(
        d.join("time_print.f"),
        "      subroutine time_print\n      use dfport\n      implicit none\n      end\n",
    )
    .unwrap();
    refused(&d, &["time_print.f", "build.log"]);
    let d = variant("dfport_excluded", |t| {
        t.replace("sources = [\"*.f\"]", "sources = [\"*.f\"]\nexclude = [\"time_print.f\"]")
    });
    std::fs::write(
        d.join("time_print.f"),
        "      subroutine time_print\n      use dfport\n      implicit none\n      end\n",
    )
    .unwrap();
    let o = blastsph(&[
        "legacy",
        "build",
        d.join("legacy.toml").to_str().unwrap(),
        "--out",
        d.join("build").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let d = variant("exclude_nothing", |t| {
        t.replace("sources = [\"*.f\"]", "sources = [\"*.f\"]\nexclude = [\"nosuch.f\"]")
    });
    refused(&d, &["exclude", "nosuch.f", "matches no file"]);
}

/// A search that returns the same pairs in another order and the other way round
/// (`tests/legacy_extra/rev_find.f`, mapped in place of direct_find): the dual run compares the
/// pair lists as sets, lines the Rust side's w and ∇W up with the legacy order (∇W negated for a
/// reversed pair), reports the order difference, and everything stays at 0 ULP.
#[test]
fn a_pair_list_in_another_order_is_compared_as_a_set() {
    let d = variant("rev_find", |t| t.replace("name = \"direct_find\"", "name = \"rev_find\""));
    std::fs::copy(root().join("tests/legacy_extra/rev_find.f"), d.join("rev_find.f")).unwrap();
    let lg = d.join("build");
    build(&d.join("legacy.toml"), &lg).expect("the variant builds");
    let out = d.join("dual");
    let so = blastsph_ok(
        &[
            "dual",
            "shock_tube",
            "--legacy",
            lg.to_str().unwrap(),
            "--compat",
            "liu-book",
            "--out",
            out.to_str().unwrap(),
        ],
        0,
    );
    assert!(so.contains("pairs as sets: 40 steps in another order"), "{so}");
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    for f in ["pair_i", "pair_j", "w", "dwdx"] {
        let x = row(&rows, "legacy.rev_find", f);
        assert_eq!((x["max_ulp"].as_u64(), x["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{f}: {x}");
    }
    let o = &row(&rows, "legacy.rev_find", "pair_i")["pair_order"];
    let compared = row(&rows, "legacy.rev_find", "pair_i")["compared"].as_u64().unwrap();
    assert_eq!(o["reversed"].as_u64(), Some(compared), "every pair reversed: {o}");
    assert!(o["moved"].as_u64().unwrap() > compared / 2, "{o}");
    assert_eq!((o["only_counterpart"].as_u64(), o["only_rust"].as_u64()), (Some(0), Some(0)), "{o}");
    for (stage, field) in [("legacy.sum_density", "rho"), ("legacy.int_force", "acc"), ("legacy.art_visc", "dde")] {
        assert_eq!(row(&rows, stage, field)["max_ulp"], 0, "{stage} {field}");
    }
}

/// A legacy routine that adds rate terms but cannot stand for its module's Rust stage (here the
/// CFL step reads max|μ|, which the book's art_visc does not give) is not run beside that stage:
/// running both would count the viscosity twice.
#[test]
fn a_routine_that_cannot_stand_for_its_stage_is_not_added_to_it() {
    let d = shared().to_str().unwrap();
    let base = ["check", "shock_tube", "--legacy", d, "--compat", "liu-book"];
    let so = blastsph_ok(&base, 0);
    assert!(so.contains("legacy.art_visc"), "{so}");
    let cfl = [&base[..], &["--set", "time.step=cfl", "--set", "time.viscous_step=true"]].concat();
    let so = blastsph_ok(&cfl, 0);
    let line = so.lines().find(|l| l.trim_start().starts_with("art_visc")).unwrap_or_default();
    assert!(line.contains("not run") && line.contains("twice"), "{so}");
    assert!(!so.contains("legacy.art_visc"), "{so}");
    assert!(so.contains("energy rate = legacy.int_force + viscosity.monaghan\n"), "{so}");
}
