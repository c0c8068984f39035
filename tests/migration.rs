//! Bring your own legacy code (docs/howto/migrate.md): the fixture `tests/legacy/` (a Liu-style F77
//! code written for these tests) built by `blastsph legacy build`, its routines called through the
//! run-time loader on small arrays and checked against the formulas of its source (with the same
//! single-precision constants), its own program run to the end of the shock tube, and every bad
//! manifest or build refused with one line and exit status 2.

mod legacy_kit;
use blastsph::migration::{Args, check_capacity};
use legacy_kit::*;

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
    let e = check_capacity(1000, 20000, 1001, None, "param.inc").unwrap_err();
    assert_eq!(e.exit_code(), 2);
    assert!(e.to_string().contains("maxn = 1000"), "{e}");
    assert!(check_capacity(1000, 20000, 1000, Some(20000), "param.inc").is_ok());
    assert!(
        check_capacity(1000, 20000, 10, Some(20001), "param.inc")
            .unwrap_err()
            .to_string()
            .contains("max_interaction = 20000")
    );
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
    println!("fixture program: L1(rho) over [-0.4, 0.4] = {l1:.6} (the book code's own program: 0.01553)");
    assert!(l1 < 0.02, "L1(rho) = {l1}");
    // the shocked gas moves at about u* = 0.673 m/s
    let mid: Vec<f64> = (0..n).filter(|&i| x[i] > 0.0 && x[i] < 0.2).map(|i| v[i]).collect();
    assert!(mid.iter().all(|u| (u - ex.u_star).abs() < 0.05), "{mid:?}");
}

// ---------------------------------------------------------------------------------------------
// bad manifests and bad builds: one line, exit status 2

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
fn an_init_routine_mapped_with_another_module_is_refused() {
    let d = variant("init_with_eos", |t| t.replacen("module = \"eos\"", "module = \"init,eos\"", 1));
    refused(&d, &["init,eos", "an init routine stands alone"]);
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
    refused(&d, &["p_gas", "argument 2 (\"itype\" in the manifest)", "dummy `u`", "double"]);
}

/// A scalar bound to an array dummy, or an array to a scalar dummy, compiles and links (names
/// are positional and FORTRAN 77 has no interfaces) and then reads past a one-value buffer or
/// sees one value of an array: the build reads each dummy's declaration (its includes too) and
/// refuses the mismatch. Before, `dt` for sum_density's `hsml(maxn)` built and `check` blamed
/// "another formulation"; p_gas's scalars mapped as whole arrays ran with p frozen for all but
/// the first particle.
#[test]
fn a_scalar_bound_to_an_array_dummy_or_the_reverse_is_refused() {
    let d = variant("dt_for_hsml", |t| {
        t.replace("[\"ntotal\", \"hsml\", \"mass\", \"niac\"", "[\"ntotal\", \"dt\", \"mass\", \"niac\"")
    });
    refused(
        &d,
        &["sum_density", "argument 2 (\"dt\" in the manifest, one value)", "is an array in density.f", "`hsml(maxn)`"],
    );
    // p_gas's four scalars (`double precision rho, u, p, c`) without `call = "each_particle"`
    let d = variant("p_gas_whole", |t| t.replacen("call = \"each_particle\"\nargs = [\"rho\"", "args = [\"rho\"", 1));
    refused(
        &d,
        &[
            "p_gas",
            "argument 1 (\"rho\" in the manifest, an array)",
            "is a scalar in eos.f (dummy `rho`)",
            "call = \"each_particle\"",
        ],
    );
    // two integers swapped: ntotal (one value) where sum_density declares itype(maxn), and the reverse
    let d = variant("ntotal_itype", |t| {
        t.replace(
            "[\"ntotal\", \"hsml\", \"mass\", \"niac\", \"pair_i\", \"pair_j\", \"w\", \"itype\", \"rho\"]",
            "[\"itype\", \"hsml\", \"mass\", \"niac\", \"pair_i\", \"pair_j\", \"w\", \"ntotal\", \"rho\"]",
        )
    });
    refused(
        &d,
        &["sum_density", "argument 1 (\"itype\" in the manifest, an array)", "dummy `ntotal`", "argument 8: swapped?"],
    );
}

/// Two reals swapped in the manifest compile and link (names are positional), but the build says
/// so: the dummy at the manifest's `u` is the routine's `rho`, and the reverse.
#[test]
fn swapped_arguments_build_with_a_warning_naming_both() {
    let d = variant("swapped", |t| t.replace("\"rho\", \"u\", \"p\", \"c\"]", "\"u\", \"rho\", \"p\", \"c\"]"));
    let out = d.join("build");
    let o = blastsph(&["legacy", "build", d.join("legacy.toml").to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let se = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(0), "{se}");
    let w: Vec<&str> = se.lines().filter(|l| l.starts_with("warning:")).collect();
    assert_eq!(w.len(), 1, "one warning for the swapped pair: {se}");
    assert!(w[0].contains("p_gas") && w[0].contains("argument 1 is `u`") && w[0].contains("swapped?"), "{se}");
    let info = std::fs::read_to_string(out.join("build.json")).unwrap();
    assert!(info.contains("swapped?"), "build.json keeps the warning");
}

#[test]
fn a_flag_that_changes_the_arithmetic_is_refused() {
    let d = variant("fast_math", |t| t.replace("[\"-finit-local-zero\"]", "[\"-finit-local-zero\", \"-ffast-math\"]"));
    refused(&d, &["-ffast-math", "fflags"]);
    for (flag, why) in [
        ("-ffinite-math-only", "arithmetic"),
        ("-O0", "fixed at -O2"),
        ("-Os", "fixed at -O2"),
        ("-fsanitize=address", "instrumented"),
        ("-pg", "instrumented"),
        ("-o", "compiles and links"),
        ("-mfpmath=387", "arithmetic"),
    ] {
        let d =
            variant("flag", |t| t.replace("[\"-finit-local-zero\"]", &format!("[\"-finit-local-zero\", \"{flag}\"]")));
        refused(&d, &[flag, why]);
    }
    // the level blastsph uses itself, copied from a Makefile, is fine
    let d = variant("flag_o2", |t| t.replace("[\"-finit-local-zero\"]", "[\"-finit-local-zero\", \"-O2\"]"));
    let o = blastsph(&[
        "legacy",
        "build",
        d.join("legacy.toml").to_str().unwrap(),
        "--out",
        d.join("build").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
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
    // a per-pair name in a whole-array call says which call it belongs to
    let d = variant("pair_in_whole", |t| t.replacen("call = \"each_pair\"", "call = \"whole\"", 1));
    refused(&d, &["\"r\"", "each_pair call only", "call = \"each_pair\""]);
}

// ---------------------------------------------------------------------------------------------
// the documentation a user follows

#[test]
fn the_docs_table_lists_every_vocabulary_name() {
    use blastsph::migration::vocab::{PAIR_TERMS, TERMS};
    let doc = std::fs::read_to_string(root().join("docs/reference/legacy.md")).unwrap();
    for t in TERMS.iter().chain(PAIR_TERMS) {
        assert!(doc.contains(&format!("| `{}` |", t.name)), "docs/reference/legacy.md has no row for `{}`", t.name);
    }
}

/// The manifest for the book code that docs/howto/migrate.md gives is accepted as it is, and builds
/// against the fixture (which has the book's routines and argument lists, less two); with it, as a
/// user who copies it whole would, the dual run is at 0 ULP and `run --legacy` ends as the program.
#[test]
fn the_books_manifest_in_the_docs_builds_against_the_fixture() {
    let doc = std::fs::read_to_string(root().join("docs/howto/migrate.md")).unwrap();
    let from = doc.find("## The book's routines, ready to copy").expect("the book's routines");
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
    blastsph_ok(&dual_book_args(&lg, None, &out), 0);
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

/// Fortran 90 declarations in a legacy source: `intent(in)` (gfortran's prototype says `const
/// double *`) builds; an assumed-shape dummy (`dens(:)`, which the shims' plain address cannot
/// describe: it crashed at the first call) is refused at build, naming the dummy; an internal
/// procedure (after CONTAINS of a subroutine) is refused as such (it read "not found").
#[test]
fn fortran_90_declarations_are_taken_or_refused_by_name() {
    let eos = |decl: &str| {
        format!(
            "subroutine eos90(dens, ene, pr, cs)\n  implicit none\n{decl}\n  pr = 0.4d0*dens*ene\n  cs = sqrt(0.4d0*ene)\nend subroutine eos90\n"
        )
    };
    let map = |t: &str| {
        t.replace("sources = [\"*.f\"]", "sources = [\"*.f\", \"eos90.f90\"]").replace(
            "[[routine]]\nname = \"p_gas\"",
            "[[routine]]\nname = \"eos90\"\nmodule = \"eos\"\ncall = \"each_particle\"\nargs = [\"rho\", \"u\", \"p\", \"c\"]\n\n[[routine]]\nname = \"p_gas\"",
        )
    };
    let d = variant("f90_intent", map);
    let src = eos("  double precision, intent(in) :: dens, ene\n  double precision, intent(out) :: pr, cs");
    std::fs::write(d.join("eos90.f90"), src).unwrap();
    let out = d.join("build");
    let o = blastsph(&["legacy", "build", d.join("legacy.toml").to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "intent(in) builds: {}", String::from_utf8_lossy(&o.stderr));
    let d = variant("f90_assumed_shape", |t| {
        map(t).replace(
            "call = \"each_particle\"\nargs = [\"rho\", \"u\", \"p\", \"c\"]\n\n[[routine]]\nname = \"p_gas\"",
            "args = [\"rho\", \"u\", \"p\", \"c\"]\n\n[[routine]]\nname = \"p_gas\"",
        )
    });
    std::fs::write(
        d.join("eos90.f90"),
        eos("  double precision :: dens(:), ene(:)\n  double precision, dimension(:) :: pr, cs"),
    )
    .unwrap();
    refused(&d, &["eos90", "argument 1 (dummy `dens`", "assumed-shape", "dens(*)"]);
    let d = variant("f90_internal", map);
    let m = format!(
        "subroutine eoshost()\ncontains\n{}end subroutine eoshost\n",
        eos("  double precision :: dens, ene, pr, cs")
    );
    std::fs::write(d.join("eos90.f90"), m).unwrap();
    refused(&d, &["eos90", "neither an external subroutine nor a module procedure"]);
}
