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

/// A whole array of vectors whose leading extent is not `dim` (`vx(maxdim,maxn)`, maxdim = 3, in
/// the 1D fixture): blastsph passes dim values per particle, so the routine would read another
/// particle's values. The build refuses it in one line naming the routine, the array and why.
#[test]
fn a_leading_extent_other_than_dim_is_refused_in_one_line() {
    let d = variant("maxdim", |m| m.to_string());
    let f = d.join("av_vel.f");
    let text = std::fs::read_to_string(&f).unwrap();
    let new = text
        .replacen(
            "      include 'param.inc'\n",
            "      include 'param.inc'\n      integer maxdim\n      parameter (maxdim = 3)\n",
            1,
        )
        .replacen("vx(dim,maxn)", "vx(maxdim,maxn)", 1);
    assert_ne!(new, text);
    std::fs::write(&f, new).unwrap();
    refused(&d, &["routine av_vel", "`vx`", "(maxdim,maxn)", "leading extent `maxdim` is not provably dim (= 1)"]);
    // the same extent as the number dim is provably right: it builds
    let d = variant("maxdim_literal", |m| m.to_string());
    let f = d.join("av_vel.f");
    let text = std::fs::read_to_string(&f).unwrap();
    std::fs::write(&f, text.replacen("vx(dim,maxn)", "vx(1,maxn)", 1)).unwrap();
    build(&d.join("legacy.toml"), &d.join("build")).expect("x(1,maxn) in a 1D build is x(dim,maxn)");
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
