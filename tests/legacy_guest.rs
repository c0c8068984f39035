//! blastsph as the host of a legacy build: what `check`, `run --quiet` and the ledger say of
//! it, and where the user's code may write.

mod legacy_kit;
use legacy_kit::*;

/// The fixture with a set-up routine that writes a file where it runs, as set-up routines of
/// legacy codes do (the book's `input` writes `ini_xv.dat` and friends).
fn writing_setup() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        variant_built("setup_writes", "input.f", |t| {
            t.replacen(
                "      write(*,*) ' particles:', ntotal\n",
                "      write(*,*) ' particles:', ntotal\n      open(11, file='ini_count.dat')\n      write(11,*) ntotal\n      close(11)\n",
                1,
            )
        })
    })
}

#[test]
fn check_runs_the_users_setup_in_a_scratch_folder_and_says_so() {
    let d = writing_setup();
    let build = d.join("build");
    let o = blastsph(&["check", "shock_tube", "--legacy", build.to_str().unwrap()]);
    let (so, se) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert_eq!(o.status.code(), Some(0), "{so}{se}");
    // the routine's banner is not in check's text, and is said once
    assert!(!so.lines().any(|l| l.trim_start().starts_with("particles:")), "{so}");
    assert_eq!(se.matches("note: legacy input printed 1 line on standard output").count(), 1, "{se}");
    assert!(so.contains("they run in a scratch folder"), "{so}");
    assert!(so.contains("nothing is written in"), "{so}");
    assert!(!build.join("work").join("ini_count.dat").exists(), "check wrote the routine's file in the build");
    assert!(!build.join("work").exists(), "check made the build's work folder");
    // the scratch folder named is gone
    let line = so.lines().find(|l| l.contains("a scratch folder, ")).unwrap();
    let tmp = line.split("a scratch folder, ").nth(1).unwrap().split(", removed").next().unwrap();
    assert!(!Path::new(tmp).exists(), "{tmp} is left behind");
    // a run does write there: the routine's file is where the docs say the code runs
    let out = d.join("run");
    blastsph_ok(
        &["run", "shock_tube", "--legacy", build.to_str().unwrap(), "--compat", "liu-book", "--quiet", "--out"]
            .iter()
            .map(|s| s.to_string())
            .chain([out.to_str().unwrap().to_string()])
            .collect::<Vec<_>>(),
        0,
    );
    assert!(build.join("work").join("ini_count.dat").exists());
}

/// The fixture without sum_density: its con_density alone does not run in the shock tube's
/// summation density (`check` says "not run").
fn con_density_alone() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let v = variant("guest_con_density_alone", |m| {
            let (head, tail) = m.split_once("[[routine]]\nname = \"sum_density\"").expect("sum_density's entry");
            let rest = tail.split_once("[[routine]]").map_or(String::new(), |(_, r)| format!("[[routine]]{r}"));
            format!("{head}{rest}")
        });
        build(&v.join("legacy.toml"), &v.join("build")).expect("the variant builds");
        v.join("build")
    })
}

#[test]
fn quiet_keeps_the_not_run_warning_and_the_summary_names_the_legacy_modules() {
    let lg = con_density_alone().to_str().unwrap();
    let so = blastsph_ok(&["check", "shock_tube", "--legacy", lg, "--compat", "liu-book"], 0);
    let unrun: Vec<&str> =
        so.lines().filter(|l| l.starts_with("warning: legacy") && l.contains("is not run")).collect();
    assert!(unrun.iter().any(|l| l.contains("con_density")), "{so}");
    let out = scratch("quiet_unrun");
    let o = blastsph(&[
        "run",
        "shock_tube",
        "--legacy",
        lg,
        "--compat",
        "liu-book",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    let se = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{se}");
    for w in &unrun {
        assert!(se.contains(w), "--quiet dropped `{w}`: {se}");
    }
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    // direct_find stands for the search, p_gas for the EOS: the modules say so
    assert_eq!(s["modules"]["nnps"], "legacy", "{}", s["modules"]);
    assert_eq!(s["modules"]["eos"], "legacy", "{}", s["modules"]);
    // no routine of this build stands for the density: its implementation's name (compat, or
    // blastsph's backend)
    assert_ne!(s["modules"]["density"], "legacy", "{}", s["modules"]);
    assert_eq!(s["modules"]["integrator"], "compat", "{}", s["modules"]);
}

#[test]
fn the_ledger_says_a_setup_warning_once() {
    let out = scratch("ledger_once");
    let o = blastsph(&[
        "legacy",
        "ledger",
        "shock_tube",
        "--legacy",
        shared().to_str().unwrap(),
        "--set",
        "region.left.count=[300]",
        "--set",
        "region.left.spacing_m=0.002",
        "--out",
        out.to_str().unwrap(),
    ]);
    let se = String::from_utf8_lossy(&o.stderr);
    let n = se.matches("made 400 particles, the case describes 380").count();
    assert_eq!(n, 1, "status {:?}: {se}", o.status.code());
}

/// A whole array of vectors whose leading extent is not provably a number (`vx(ndim,maxn)` with
/// ndim = dim + 2, an expression the build does not evaluate), or below dim: blastsph could not
/// lay each particle's values out as the routine reads them. The build refuses it in one line
/// naming the routine, the array and why. A number or a `parameter` of a number builds
/// (tests/legacy_host.rs runs a whole program laid out so).
#[test]
fn a_leading_extent_that_cannot_be_proved_is_refused_in_one_line() {
    let with = |name: &str, decl: &str, extent: &str| {
        let d = variant(name, |m| m.to_string());
        let f = d.join("av_vel.f");
        let text = std::fs::read_to_string(&f).unwrap();
        let new = text
            .replacen("      include 'param.inc'\n", &format!("      include 'param.inc'\n{decl}"), 1)
            .replacen("vx(dim,maxn)", &format!("vx({extent},maxn)"), 1);
        assert_ne!(new, text);
        std::fs::write(&f, new).unwrap();
        d
    };
    let d = with("ndim_expr", "      integer ndim\n      parameter (ndim = dim + 2)\n", "ndim");
    refused(&d, &["routine av_vel", "`vx`", "(ndim,maxn)", "leading extent `ndim` is not a number or a `parameter`"]);
    let d = with("ndim_zero", "      integer ndim\n      parameter (ndim = 0)\n", "ndim");
    refused(&d, &["routine av_vel", "`vx`", "`ndim` = 0 is below dim (= 1)"]);
    // the same extent as the number dim, or a parameter of a number: it builds
    let d = with("maxdim_literal", "", "1");
    build(&d.join("legacy.toml"), &d.join("build")).expect("x(1,maxn) in a 1D build is x(dim,maxn)");
    let d = with("maxdim_parameter", "      integer maxdim\n      parameter (maxdim = 3)\n", "maxdim");
    let info = build(&d.join("legacy.toml"), &d.join("build")).expect("x(maxdim,maxn) with maxdim = 3");
    let av = info.routine("av_vel").unwrap();
    assert_eq!(av.args.iter().find(|a| a.name == "vx").unwrap().lead, Some(3));
}

/// The peak resident memory of `blastsph ARGS` (kB), read from /proc while it runs (VmHWM, the
/// high-water mark, only grows), and its exit status.
fn peak_kb(args: &[&str]) -> (u64, Option<i32>) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_blastsph"))
        .args(args)
        .current_dir(root())
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    let status = format!("/proc/{}/status", child.id());
    let mut peak = 0;
    loop {
        if let Ok(text) = std::fs::read_to_string(&status)
            && let Some(l) = text.lines().find(|l| l.starts_with("VmHWM:"))
        {
            peak = peak.max(l.split_whitespace().nth(1).and_then(|v| v.parse().ok()).unwrap_or(0));
        }
        if let Some(s) = child.try_wait().unwrap() {
            return (peak, s.code());
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
}

/// A search's shim copies the pairs in use, not its max_interaction-long buffers: with
/// max_interaction = 2e7 (480 MB of pair arrays), a run of the 400-particle fixture stays small.
#[test]
fn a_search_shims_cost_follows_the_pairs_in_use_not_max_interaction() {
    let d = variant_built("big_max_interaction", "param.inc", |t| {
        t.replace("max_interaction = 20*maxn", "max_interaction = 20000000")
    });
    let (lg, out) = (d.join("build"), d.join("run"));
    let (peak, code) = peak_kb(&[
        "run",
        "shock_tube",
        "--legacy",
        lg.to_str().unwrap(),
        "--compat",
        "liu-book",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0));
    assert!(peak > 0, "no reading of the run's memory");
    assert!(peak < 150_000, "peak resident memory {peak} kB: the shim touched its max_interaction buffers");
    // and the run is the fixture's program's, bit for bit
    assert_run_ends_as_the_program(&lg, "big_max_interaction_run");
}

/// The fixture with `eos_sw` (`tests/legacy_extra/eos_switch.f`: p_gas with an integer switch, a
/// logical and a default-real γ as dummies) mapped in place of p_gas, its manifest's entry with
/// the given `values`.
fn eos_switch(name: &str, values: &str) -> PathBuf {
    let d = variant(name, |t| {
        t.replace(
            "name = \"p_gas\"\nmodule = \"eos\"\ncall = \"each_particle\"\nargs = [\"rho\", \"u\", \"p\", \"c\"]\n",
            &format!(
                "name = \"eos_sw\"\nmodule = \"eos\"\ncall = \"each_particle\"\nargs = [\"ieos\", \"rho\", \"u\", \"p\", \"c\", \"sound\", \"gam\"]\nvalues = {values}\n"
            ),
        )
    });
    assert!(std::fs::read_to_string(d.join("legacy.toml")).unwrap().contains("eos_sw"));
    std::fs::copy(root().join("tests/legacy_extra/eos_switch.f"), d.join("eos_switch.f")).unwrap();
    d
}

/// Dummies blastsph has no name for (a switch, a logical, a default-real constant) are bound to
/// the manifest's `values`: the routine runs with them, at 0 ULP against the EOS twin. With the
/// logical false the routine leaves c as it was, and the dual run says so; a value of another
/// type than its dummy's, a vocabulary name or a name not in `args` is refused in one line.
#[test]
fn dummies_bound_to_values_in_the_manifest_reach_the_routine() {
    let d = eos_switch("values_on", "{ ieos = 1, sound = true, gam = 1.4 }");
    let lg = d.join("build");
    let info = build(&d.join("legacy.toml"), &lg).expect("values bind the switches");
    let r = info.routine("eos_sw").unwrap();
    let ty = |n: &str| r.args.iter().find(|a| a.name == n).unwrap().value.clone().unwrap();
    assert_eq!(ty("ieos"), ("integer".to_string(), "1".to_string()));
    assert_eq!(ty("sound").0, "logical");
    assert_eq!(ty("gam").0, "real");
    let out = d.join("dual");
    blastsph_ok(&dual_book_args(&lg, Some(5), &out), 0);
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    for f in ["p", "c"] {
        let x = row(&rows, "legacy.eos_sw", f);
        assert!(x["compared"].as_u64().unwrap() > 0, "{x}");
        assert_eq!((x["max_ulp"].as_u64(), x["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{f}: {x}");
    }
    // the logical switched off: c is not the routine's output any more, the twin's is
    let d = eos_switch("values_off", "{ ieos = 1, sound = false, gam = 1.4 }");
    let lg = d.join("build");
    build(&d.join("legacy.toml"), &lg).expect("builds");
    let out = d.join("dual");
    blastsph_ok(&dual_book_args(&lg, Some(5), &out), 4);
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    assert_eq!(row(&rows, "legacy.eos_sw", "p")["max_ulp"], 0);
    assert!(row(&rows, "legacy.eos_sw", "c")["out_of_tolerance"].as_u64().unwrap() > 0);
    // refused, one line each
    refused(
        &eos_switch("values_type", "{ ieos = 1, sound = 1, gam = 1.4 }"),
        &["routine eos_sw", "argument 6 (\"sound\" in values)", "int_least32_t", "the manifest gives an integer"],
    );
    refused(
        &eos_switch("values_vocab", "{ ieos = 1, sound = true, gam = 1.4, rho = 1.0 }"),
        &["values.rho", "name of the argument vocabulary"],
    );
    refused(
        &eos_switch("values_absent", "{ ieos = 1, sound = true, gam = 1.4, skf = 1 }"),
        &["values.skf", "not in args"],
    );
    refused(&eos_switch("values_missing", "{ ieos = 1, sound = true }"), &["unknown argument name \"gam\""]);
}

/// A default-real (4-byte) code: a dummy declared `real` where the vocabulary has a double
/// precision value is refused in one line naming the routine, the argument and both types.
#[test]
fn a_default_real_dummy_is_refused_in_one_line() {
    let d = variant("real4", |m| m.to_string());
    let f = d.join("eos.f");
    let text = std::fs::read_to_string(&f).unwrap();
    let new = text.replacen("      double precision rho, u, p, c\n", "      real rho, u, p, c\n", 1);
    assert_ne!(new, text);
    std::fs::write(&f, new).unwrap();
    refused(&d, &["routine p_gas", "argument 1 (\"rho\" in the manifest)", "declared float", "double precision"]);
}

/// The fixture with an EOS that gives p only (`tests/legacy_extra/eos_p_only.f`: the ideal gas's
/// p, no c) in place of p_gas, both where it is mapped and where int_force calls it. Its program's
/// c is an array that no routine writes, so its artificial viscosity reads c = 0.
fn p_only() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let d = variant("p_only", |t| {
            t.replace(
                "name = \"p_gas\"\nmodule = \"eos\"\ncall = \"each_particle\"\nargs = [\"rho\", \"u\", \"p\", \"c\"]\n",
                "name = \"p_gas_p\"\nmodule = \"eos\"\ncall = \"each_particle\"\nargs = [\"rho\", \"u\", \"p\"]\n",
            )
        });
        assert!(std::fs::read_to_string(d.join("legacy.toml")).unwrap().contains("p_gas_p"));
        std::fs::copy(root().join("tests/legacy_extra/eos_p_only.f"), d.join("eos_p_only.f")).unwrap();
        let f = d.join("int_force.f");
        let text = std::fs::read_to_string(&f).unwrap();
        let new = text.replace("call p_gas(rho(i), u(i), p(i), c(i))", "call p_gas_p(rho(i), u(i), p(i))");
        assert_ne!(new, text);
        std::fs::write(&f, new).unwrap();
        build(&d.join("legacy.toml"), &d.join("build")).expect("the variant builds");
        d.join("build")
    })
}

/// An EOS routine that gives p only stands for the EOS stage for p: `check` says so on its line,
/// the dual run compares p at 0 ULP and says on its row which c each side used, and `run
/// --legacy` runs on c = 0 as the program does, bit for bit to the end of the shock tube.
#[test]
fn an_eos_that_gives_p_only_stands_for_p_and_leaves_c_at_zero() {
    let lg = p_only();
    let so = blastsph_ok(&["check", "shock_tube", "--legacy", lg.to_str().unwrap(), "--compat", "liu-book"], 0);
    let line = so.lines().find(|l| l.trim_start().starts_with("p_gas_p ")).unwrap_or_else(|| panic!("{so}"));
    assert!(line.contains(" run ") && line.contains("stands for eos.eval for p only"), "{line}");
    assert!(line.contains("leaves c at 0") && line.contains("the Rust twin uses its own c"), "{line}");
    assert!(!so.contains("warning: legacy p_gas_p"), "{so}");
    // the dual run: p compared at 0 ULP, c not compared, the row saying which c each side used
    let out = scratch("p_only_dual");
    let o = blastsph(&dual_book_args(lg, Some(5), &out));
    let so = String::from_utf8_lossy(&o.stdout);
    assert!(!so.contains("NOT RUN"), "{so}");
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    let x = row(&rows, "legacy.p_gas_p", "p");
    assert!(x["compared"].as_u64().unwrap() > 0, "{x}");
    assert_eq!((x["max_ulp"].as_u64(), x["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{x}");
    let why = x["tolerance_why"].as_str().unwrap();
    assert!(why.contains("leaves c at 0") && why.contains("the Rust twin uses its own c"), "{why}");
    assert!(!rows.iter().any(|r| r["stage"] == "legacy.p_gas_p" && r["field"] == "c"), "c is not compared");
    // int_force, which no longer writes c, hands on the 0 it was given: its twin's c differs
    assert!(row(&rows, "legacy.int_force", "c")["out_of_tolerance"].as_u64().unwrap() > 0);
    assert_eq!(o.status.code(), Some(4), "{so}");
    // the program on c = 0 ends elsewhere than the fixture's (its viscosity's alpha term sees
    // c = 0), and `run --legacy` ends where it does
    let rows = program_rows_of(lg, "p_only_program", 40);
    assert_ne!(rows, program_final_state(), "c = 0 changes the program's run");
    assert_run_ends_as(lg, "shock_tube", "liu-book", &rows, "p_only_run");
}

/// The fixture with a set-up routine that reads a file its folder does not hold (a code run away
/// from its `../data`): gfortran's runtime error ends the routine inside an OPEN statement.
fn missing_file_setup() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        variant_built("setup_missing_file", "input.f", |t| {
            t.replacen(
                "      write(*,*) ' particles:', ntotal\n",
                "      write(*,*) ' particles:', ntotal\n      open(11, file='../data/ini_xv.dat', status='old')\n      read(11,*) ntotal\n      close(11)\n",
                1,
            )
        })
    })
}

/// `blastsph ARGS` with `stdin` on its standard input, killed after `secs` seconds: (status, stderr),
/// status None when it had to be killed.
fn within(args: &[&str], stdin: &[u8], secs: u64) -> (Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_blastsph"))
        .args(args)
        .current_dir(root())
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("blastsph starts");
    {
        use std::io::Write;
        let _ = child.stdin.take().unwrap().write_all(stdin);
    }
    let start = std::time::Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s.code();
        }
        if start.elapsed().as_secs() >= secs {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    let mut se = String::new();
    use std::io::Read;
    let _ = child.stderr.take().unwrap().read_to_string(&mut se);
    (status, se)
}

#[test]
fn a_runtime_error_in_an_open_statement_ends_every_command_with_status_3() {
    let d = missing_file_setup();
    let build = d.join("build");
    let b = build.to_str().unwrap();
    let dual = d.join("dual");
    let run = d.join("run");
    let host = d.join("host");
    let commands: [Vec<&str>; 4] = [
        vec!["check", "shock_tube", "--legacy", b],
        vec!["run", "shock_tube", "--legacy", b, "--compat", "liu-book", "--quiet", "--out", run.to_str().unwrap()],
        vec![
            "dual",
            "shock_tube",
            "--legacy",
            b,
            "--compat",
            "liu-book",
            "--steps",
            "1",
            "--out",
            dual.to_str().unwrap(),
        ],
        vec!["legacy", "host", "shock_tube", "--legacy", b, "--compat", "liu-book", "--out", host.to_str().unwrap()],
    ];
    for args in &commands {
        let (status, se) = within(args, b"1\n0\n", 60);
        assert!(status.is_some(), "blastsph {args:?} did not end in 60 s; stderr: {se}");
        assert!(se.contains("Cannot open file '../data/ini_xv.dat'"), "blastsph {args:?}: libgfortran's line: {se}");
        assert!(!se.contains("panicked"), "{se}");
        if args[0] != "legacy" {
            assert_eq!(status, Some(3), "blastsph {args:?}: {se}");
            let ours: Vec<&str> = se.lines().filter(|l| l.starts_with("error:")).collect();
            assert_eq!(ours.len(), 1, "one line of blastsph's: {se}");
            assert!(ours[0].contains("legacy routine input ended the process"), "{se}");
        } else {
            assert_ne!(status, Some(0), "blastsph {args:?}: {se}");
        }
    }
}

/// The fixture with a set-up routine that writes into the build's `data` folder beside where it
/// runs (the book's `../data`) and into a `run_dirs` folder one level up.
#[test]
fn check_gives_the_setup_the_builds_layout_and_run_dirs_may_climb_once() {
    let d = variant("setup_writes_up", |m| {
        m.replace("sources = [\"*.f\"]", "sources = [\"*.f\"]\nrun_dirs = [\"../out/frames\"]")
    });
    let f = d.join("input.f");
    let text = std::fs::read_to_string(&f).unwrap();
    let new = text.replacen(
        "      write(*,*) ' particles:', ntotal\n",
        "      open(11, file='../data/ini_count.dat')\n      write(11,*) ntotal\n      close(11)\n      open(12, file='../out/frames/f.dat')\n      write(12,*) ntotal\n      close(12)\n",
        1,
    );
    assert_ne!(new, text);
    std::fs::write(&f, new).unwrap();
    let build = d.join("build");
    blastsph::migration::build(&d.join("legacy.toml"), &build).expect("the variant builds");
    let (status, se) = within(&["check", "shock_tube", "--legacy", build.to_str().unwrap()], b"", 60);
    assert_eq!(status, Some(0), "{se}");
    assert!(!build.join("data").exists() && !build.join("out").exists(), "check wrote in the build");
}

/// An include file with a comment that is not UTF-8 (GBK's 0xB0 0xA1, as in codes commented in
/// Chinese): gfortran compiles it, and the build reads its parameters (direct_find's `x` declared
/// `(maxdim,maxn)`, `maxdim` a parameter of that include).
#[test]
fn an_include_with_a_comment_that_is_not_utf8_builds() {
    let d = variant("param_gbk", |m| m.to_string());
    let src = d.join("direct_find.f");
    let text = std::fs::read_to_string(&src).unwrap();
    std::fs::write(&src, text.replacen("x(dim,maxn)", "x(maxdim,maxn)", 1)).unwrap();
    let f = d.join("param.inc");
    let mut bytes = b"c     \xb0\xa1 sizes\n".to_vec();
    bytes.extend(std::fs::read(&f).unwrap());
    bytes.extend(b"      integer maxdim\n      parameter (maxdim = 1)\n");
    assert!(String::from_utf8(bytes.clone()).is_err());
    std::fs::write(&f, bytes).unwrap();
    let out = d.join("build");
    let o = blastsph(&["legacy", "build", d.join("legacy.toml").to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let se = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{se}");
    let info: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("build.json")).unwrap()).unwrap();
    assert_eq!((info["dim"].as_u64(), info["maxn"].as_u64()), (Some(1), Some(1000)), "{info}");
}
