//! Runs under `mpirun` (Open MPI, which `scripts/setup` installs): 2 ranks of 2 threads and 3
//! ranks of one give the one-thread serial run's particles.h5 bit for bit, with its gauges.csv
//! and summary.json, on short 2D plane, RZ and 3D cases; a checkpoint written by 3 ranks
//! resumes on 2; a bad case ends every rank with one line and exit status 2; a rank killed by
//! SIGKILL ends the job, and its last checkpoint resumes to the serial run bitwise; `check` prints
//! once; `run --legacy` on 2 ranks is the serial run bitwise.
#![cfg(feature = "mpi")]

mod common;
use common::h5_bits;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn case_path(name: &str) -> String {
    format!("{}/cases/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// `blastsph run` under `mpirun -np N` (Open MPI refuses root without its two variables, and
/// more ranks than cores without --oversubscribe: both are set for this child only).
fn mpirun(np: usize) -> Command {
    let mut c = Command::new("mpirun");
    c.current_dir(env!("CARGO_MANIFEST_DIR"));
    c.args(["--oversubscribe", "-np", &np.to_string(), env!("CARGO_BIN_EXE_blastsph")]);
    c.env("OMPI_ALLOW_RUN_AS_ROOT", "1").env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
    c
}

fn serial() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_blastsph"));
    c.current_dir(env!("CARGO_MANIFEST_DIR"));
    c
}

/// Runs `c` to its end, killed (and the test failed) after `limit_s` seconds: never a hang.
fn finish(mut c: Command, limit_s: u64, what: &str) -> Output {
    let mut child = c
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("{what}: cannot start ({e}); scripts/setup installs Open MPI"));
    let t0 = Instant::now();
    loop {
        if child.try_wait().expect("wait").is_some() {
            return child.wait_with_output().expect("output");
        }
        if t0.elapsed() > Duration::from_secs(limit_s) {
            let _ = child.kill();
            let o = child.wait_with_output().expect("output");
            panic!("{what}: still running after {limit_s} s (a hang); stderr: {}", String::from_utf8_lossy(&o.stderr));
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// `blastsph run CASE` with `sets` into `out`, in one process (`np` = 0) or under mpirun; on 2
/// ranks with 2 threads each (rayon inside each rank), else with one.
fn run(np: usize, case: &str, sets: &[&str], out: &Path) -> Output {
    let mut c = if np == 0 { serial() } else { mpirun(np) };
    let threads = if np == 2 { "2" } else { "1" };
    c.arg("run").arg(case_path(case)).args(["--threads", threads, "--quiet", "--out"]).arg(out);
    for s in sets {
        c.args(["--set", s]);
    }
    let o = finish(c, 300, &format!("{case} on {np} ranks"));
    assert!(o.status.success(), "{case} on {np} ranks: {:?}; stderr: {}", o.status, String::from_utf8_lossy(&o.stderr));
    o
}

fn summary(dir: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(dir.join("summary.json")).expect("summary.json")).expect("json")
}

/// A summary's physics: all but the wall times, the thread count and the ranks' traffic.
fn physics(mut s: Value) -> Value {
    let o = s.as_object_mut().expect("summary.json is an object");
    for k in ["wall_seconds", "particle_steps_per_second", "module_seconds", "threads", "ranks"] {
        o.remove(k);
    }
    s
}

/// How the run in `b` differs from the serial run in `a` (None: bitwise the same).
fn difference(a: &Path, b: &Path) -> Option<String> {
    let (ha, hb) = (h5_bits(&a.join("particles.h5")), h5_bits(&b.join("particles.h5")));
    if ha.len() != hb.len() {
        return Some(format!("particles.h5: {} vs {} datasets", ha.len(), hb.len()));
    }
    for (x, y) in ha.iter().zip(&hb) {
        if (&x.0, &x.1) != (&y.0, &y.1) || x.2.len() != y.2.len() {
            return Some(format!(
                "particles.h5: {}/{} ({} values) vs {}/{} ({})",
                x.0,
                x.1,
                x.2.len(),
                y.0,
                y.1,
                y.2.len()
            ));
        }
        if let Some(k) = x.2.iter().zip(&y.2).position(|(u, v)| u != v) {
            return Some(format!(
                "particles.h5 {}/{} differs at entry {k}: bits {:#x} vs {:#x}",
                x.0, x.1, x.2[k], y.2[k]
            ));
        }
    }
    for f in ["gauges.csv", "particles.xmf"] {
        if std::fs::read(a.join(f)).ok() != std::fs::read(b.join(f)).ok() {
            return Some(format!("{f} differs"));
        }
    }
    let (sa, sb) = (physics(summary(a)), physics(summary(b)));
    if sa != sb {
        let keys: Vec<&String> = sa.as_object().unwrap().keys().filter(|k| sa[k.as_str()] != sb[k.as_str()]).collect();
        return Some(format!("summary.json differs in {keys:?}"));
    }
    None
}

/// The serial run of `case`, then the same under mpirun with each of `nps` ranks: each is
/// bitwise the serial run, and each split its row loops (rank 0 received values from others).
fn same_as_serial(case: &str, sets: &[&str], nps: &[usize]) {
    let root = tempfile::tempdir().unwrap();
    let one = root.path().join("serial");
    run(0, case, sets, &one);
    let outputs = h5_bits(&one.join("particles.h5")).iter().filter(|x| x.1 == "TimeValue").count();
    assert!(outputs >= 3, "{case}: {outputs} outputs; the test wants several");
    for &np in nps {
        let dir: PathBuf = root.path().join(format!("np{np}"));
        run(np, case, sets, &dir);
        if let Some(d) = difference(&one, &dir) {
            panic!("{case} on {np} ranks is not the serial run: {d}");
        }
        let s = summary(&dir);
        if np > 1 {
            assert_eq!(s["ranks"]["count"], np, "{case}: summary.json ranks");
            let got = s["ranks"]["rank0"]["values_received"].as_u64().unwrap_or(0);
            assert!(got > 0, "{case} on {np} ranks: rank 0 received nothing (no loop was split)");
        } else {
            assert!(s.get("ranks").is_none(), "{case}: one rank is a plain run");
        }
    }
}

/// [`common::SMALL_S1`] to 50 µs, reordered in memory every 10 steps.
fn plane() -> Vec<&'static str> {
    plane_to("time.end_s=5e-5")
}

/// [`plane`] with the end time `end` (a `time.end_s=..` override).
fn plane_to(end: &'static str) -> Vec<&'static str> {
    common::SMALL_S1.iter().copied().chain([end, "sph.reorder_every=10"]).collect()
}

#[test]
fn plane_2d_on_1_2_and_3_ranks_is_the_serial_run_bitwise() {
    same_as_serial("surface_loose_tnt6.toml", &plane(), &[1, 2, 3]);
}

#[test]
fn rz_on_2_and_3_ranks_is_the_serial_run_bitwise() {
    let sets = [
        "region.charge.spacing_m=0.023",
        "region.soil.spacing_m=0.023",
        "time.end_s=6e-5",
        "time.output_interval_s=2e-5",
    ];
    same_as_serial("surface_loose_tnt1kg_rz.toml", &sets, &[2, 3]);
}

#[test]
fn three_d_on_2_and_3_ranks_is_the_serial_run_bitwise() {
    let sets = [
        "region.charge.spacing_m=0.046",
        "region.soil.spacing_m=0.046",
        "time.end_s=3e-5",
        "time.output_interval_s=1e-5",
    ];
    same_as_serial("surface_loose_tnt1kg_3d.toml", &sets, &[2, 3]);
}

#[test]
fn a_bad_case_under_mpirun_ends_every_rank_with_one_line_and_status_2() {
    let root = tempfile::tempdir().unwrap();
    let bad = root.path().join("bad.toml");
    std::fs::write(&bad, "[time]\nend_s = \"soon\"\n").unwrap();
    let mut c = mpirun(3);
    c.arg("run").arg(&bad).arg("--out").arg(root.path().join("out"));
    let o = finish(c, 30, "a bad case on 3 ranks");
    assert_eq!(o.status.code(), Some(2), "stderr: {}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    let ours: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(ours.len(), 1, "one line from rank 0, not one per rank: {err}");
    assert!(ours[0].contains("bad.toml"), "the line names the file: {}", ours[0]);
    assert!(!root.path().join("out").exists(), "a refused run writes nothing");
}

#[test]
fn check_on_2_ranks_prints_once_and_exits_0() {
    let case = case_path("surface_loose_tnt6.toml");
    let one = finish(
        {
            let mut c = serial();
            c.arg("check").arg(&case);
            c
        },
        30,
        "check in one process",
    );
    assert_eq!(one.status.code(), Some(0), "stderr: {}", String::from_utf8_lossy(&one.stderr));
    let mut c = mpirun(2);
    c.arg("check").arg(&case);
    let o = finish(c, 60, "check on 2 ranks");
    assert_eq!(o.status.code(), Some(0), "stderr: {}", String::from_utf8_lossy(&o.stderr));
    // rank 0's text is the single process's, once (the size line names the memory, the same
    // on both)
    assert_eq!(String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&one.stdout));
    assert!(!o.stdout.is_empty());
}

#[test]
fn dual_is_refused_on_several_ranks_with_one_line() {
    let mut c = mpirun(2);
    c.args(["dual", "shock_tube", "--steps", "2"]);
    let o = finish(c, 30, "dual on 2 ranks");
    assert_eq!(o.status.code(), Some(2), "stderr: {}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.lines().filter(|l| l.starts_with("error:")).count(), 1, "{err}");
}

/// The legacy fixture (tests/legacy: the book's shock tube code, at most 1000 particles) built
/// and run by `run --legacy` on 2 ranks: bitwise the single process's run, and the routines' own
/// prints appear once.
#[cfg(feature = "legacy")]
#[test]
fn run_legacy_on_2_ranks_is_the_serial_run_bitwise() {
    let root = tempfile::tempdir().unwrap();
    let lg = root.path().join("lg");
    let mut b = serial();
    b.args(["legacy", "build", "tests/legacy/legacy.toml", "--out"]).arg(&lg);
    let o = finish(b, 300, "legacy build of the fixture");
    assert!(o.status.success(), "the fixture builds: {}", String::from_utf8_lossy(&o.stderr));
    let (one, two) = (root.path().join("serial"), root.path().join("np2"));
    // the fixture's set-up routine prints " particles:" once
    let mut prints = Vec::new();
    for (mut c, dir) in [(serial(), &one), (mpirun(2), &two)] {
        c.args(["run", "shock_tube", "--legacy"]).arg(&lg).args(["--threads", "1", "--quiet", "--out"]).arg(dir);
        let o = finish(c, 300, "run --legacy");
        assert!(o.status.success(), "run --legacy: {:?}; stderr: {}", o.status, String::from_utf8_lossy(&o.stderr));
        prints.push(String::from_utf8_lossy(&o.stdout).lines().filter(|l| l.contains(" particles:")).count());
    }
    assert!(prints[0] > 0, "the serial run printed the routine's own lines");
    assert_eq!(prints[1], prints[0], "the routine's own prints once, not once per rank");
    assert_eq!(summary(&two)["ranks"]["count"], 2, "the run went on 2 ranks");
    assert!(summary(&two)["legacy"].as_array().is_some_and(|a| !a.is_empty()), "legacy routines ran");
    if let Some(d) = difference(&one, &two) {
        panic!("run --legacy on 2 ranks is not the serial run: {d}");
    }
}

/// `resume DIR --end-time T` on `np` ranks (0: one process).
fn resume(np: usize, dir: &Path, end: &str) -> Output {
    let mut c = if np == 0 { serial() } else { mpirun(np) };
    c.arg("resume").arg(dir).args(["--end-time", end, "--threads", "1", "--quiet"]);
    let o = finish(c, 300, &format!("resume on {np} ranks"));
    assert!(o.status.success(), "resume on {np} ranks: {:?}; stderr: {}", o.status, String::from_utf8_lossy(&o.stderr));
    o
}

#[test]
fn a_checkpoint_written_by_3_ranks_resumes_on_2_as_the_serial_run_resumed() {
    let root = tempfile::tempdir().unwrap();
    let (one, many) = (root.path().join("serial"), root.path().join("np3"));
    let sets = plane_to("time.end_s=3e-5");
    run(0, "surface_loose_tnt6.toml", &sets, &one);
    run(3, "surface_loose_tnt6.toml", &sets, &many);
    resume(0, &one, "6e-5");
    resume(2, &many, "6e-5");
    let s = summary(&many);
    let t = s["time"].as_f64().unwrap_or(0.0);
    assert!((t - 6e-5).abs() < 1e-12, "the resumed run reached its new end: t = {t}");
    assert_eq!(s["ranks"]["count"], 2, "the resume ran on 2 ranks");
    if let Some(d) = difference(&one, &many) {
        panic!("3 ranks then 2 differ from one process then one: {d}");
    }
}

/// The processes whose parent is `pid` (Linux: /proc/PID/task/*/children).
fn children(pid: u32) -> Vec<u32> {
    let mut out = Vec::new();
    for t in std::fs::read_dir(format!("/proc/{pid}/task")).into_iter().flatten().flatten() {
        let s = std::fs::read_to_string(t.path().join("children")).unwrap_or_default();
        out.extend(s.split_whitespace().filter_map(|p| p.parse::<u32>().ok()));
    }
    out
}

#[test]
fn a_rank_killed_by_sigkill_ends_the_job_and_the_last_checkpoint_resumes_bitwise() {
    let root = tempfile::tempdir().unwrap();
    let (one, killed) = (root.path().join("serial"), root.path().join("killed"));
    let sets = plane_to("time.end_s=3e-4");
    run(0, "surface_loose_tnt6.toml", &sets, &one);
    let mut c = mpirun(2);
    c.arg("run").arg(case_path("surface_loose_tnt6.toml")).args([
        "--threads",
        "1",
        "--quiet",
        "--checkpoint-every",
        "10",
    ]);
    c.arg("--out").arg(&killed);
    for s in &sets {
        c.args(["--set", s]);
    }
    let mut job =
        c.stdout(Stdio::null()).stderr(Stdio::piped()).spawn().expect("mpirun; scripts/setup installs Open MPI");
    let t0 = Instant::now();
    while !killed.join("checkpoint.bin").is_file() {
        assert!(job.try_wait().unwrap().is_none(), "the job ended before its first checkpoint");
        assert!(t0.elapsed() < Duration::from_secs(120), "no checkpoint after 120 s");
        std::thread::sleep(Duration::from_millis(20));
    }
    let ranks = children(job.id());
    assert_eq!(ranks.len(), 2, "mpirun -np 2 started 2 processes: {ranks:?}");
    let st = Command::new("kill").args(["-KILL", &ranks[1].to_string()]).status().expect("kill");
    assert!(st.success(), "kill -KILL {}", ranks[1]);
    let t1 = Instant::now();
    let status = loop {
        if let Some(s) = job.try_wait().unwrap() {
            break s;
        }
        if t1.elapsed() > Duration::from_secs(60) {
            let _ = job.kill();
            panic!("mpirun still running 60 s after a rank was killed (a hang)");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    assert!(!status.success(), "the job ends with a failure when a rank dies: {status:?}");
    let s = summary(&killed);
    assert_ne!(s["status"], "ok", "the job was killed before its end");
    resume(0, &killed, "3e-4");
    assert_eq!(h5_bits(&one.join("particles.h5")), h5_bits(&killed.join("particles.h5")), "particles.h5");
    for f in ["gauges.csv", "particles.xmf"] {
        assert_eq!(std::fs::read(one.join(f)).ok(), std::fs::read(killed.join(f)).ok(), "{f}");
    }
}
