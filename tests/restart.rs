//! Restart bit for bit (docs/reference/output.md "Checkpoints and resume"), through the built
//! binary as a user meets it: a surface blast stopped past 40 % of its end time — by SIGTERM
//! (a clean stop: its own checkpoint, exit status 5) and by SIGKILL (after a periodic
//! checkpoint; the run may have written more outputs after it) — and continued with `blastsph
//! resume` is bitwise the uninterrupted run: every dataset of every step of particles.h5, every
//! byte of gauges.csv and particles.xmf, and every physical number of summary.json. For both
//! backends, with 1 and 2 threads, and resumed with another thread count than the run had.
//! Also: a changed case is refused unless `--allow-changed`, naming what changed; `report` on a
//! killed run works and says PARTIAL; `run` into its own stopped run continues it.

mod common;
use common::h5_bits;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// End time of the small blast (s): about 150 steps.
const END: f64 = 1e-4;
/// Where the run is stopped: past this fraction of END.
const STOP_AT: f64 = 0.4;

fn case() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/cases/surface_loose_tnt6.toml").to_string()
}

/// [`common::SMALL_S1`] as owned strings.
fn small() -> Vec<String> {
    common::SMALL_S1.iter().map(|s| s.to_string()).collect()
}

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_blastsph"));
    c.current_dir(env!("CARGO_MANIFEST_DIR"));
    c
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn shown(o: &Output) -> String {
    format!("status {:?}\nstdout:\n{}\nstderr:\n{}", o.status.code(), text(&o.stdout), text(&o.stderr))
}

/// `blastsph run` of the small blast into `dir`.
fn run_cmd(dir: &Path, backend: &str, threads: usize, extra: &[&str]) -> Command {
    run_to(dir, backend, threads, END, extra)
}

/// `blastsph run` of the small blast into `dir`, to `end` (s). The Fortran-backend runs have the
/// Morris–Monaghan viscosity switch (its α_i is state the checkpoint must carry); the Rust ones
/// the constant coefficients.
fn run_to(dir: &Path, backend: &str, threads: usize, end: f64, extra: &[&str]) -> Command {
    let mut c = bin();
    c.args(["run", &case(), "--quiet", "--out"]).arg(dir);
    c.args(["--backend", backend, "--threads", &threads.to_string(), "--end-time", &format!("{end:?}")]);
    for s in small() {
        c.args(["--set", &s]);
    }
    if backend == "fortran" {
        c.args(["--set", "viscosity.switch=\"morris_monaghan\""]);
    }
    c.args(extra);
    c
}

fn resume(dir: &Path, threads: usize, extra: &[&str]) -> Output {
    let mut c = bin();
    c.args(["resume", "--quiet", "--threads", &threads.to_string()]).arg(dir).args(extra);
    c.output().expect("start blastsph resume")
}

fn summary(dir: &Path) -> Option<Value> {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).ok()?).ok()
}

/// Waits until the running `child` has written a checkpoint past STOP_AT of the end time (its
/// summary.json, written right after each checkpoint, says how far it is).
fn wait_for_checkpoint(child: &mut Child, dir: &Path) {
    let t0 = Instant::now();
    loop {
        if let Some(st) = child.try_wait().unwrap() {
            panic!("the run ended ({st}) before a checkpoint past {STOP_AT} of its end time: nothing to interrupt");
        }
        if let Some(s) = summary(dir)
            && s["status"] == "running"
            && s["time"].as_f64().unwrap_or(0.0) >= STOP_AT * END
        {
            assert!(dir.join("checkpoint.bin").is_file(), "summary.json at t > 0 without a checkpoint");
            return;
        }
        assert!(t0.elapsed() < Duration::from_secs(600), "no checkpoint after 10 minutes");
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// The physics of a summary.json: everything but the wall times, the thread count and the
/// record of resumes.
fn physics(mut s: Value) -> Value {
    let o = s.as_object_mut().expect("summary.json is an object");
    for k in ["wall_seconds", "particle_steps_per_second", "module_seconds", "threads", "resumed"] {
        assert!(k == "resumed" || o.contains_key(k), "summary.json has no `{k}`");
        o.remove(k);
    }
    s
}

/// How the run in `b` differs from the run in `a` (None: bitwise the same): particles.h5 (every
/// dataset of every step), gauges.csv and particles.xmf byte for byte, summary.json's physics.
fn difference(a: &Path, b: &Path) -> Option<String> {
    let (ha, hb) = (h5_bits(&a.join("particles.h5")), h5_bits(&b.join("particles.h5")));
    let list = |f: &[(String, String, Vec<u64>)]| -> Vec<(String, String)> {
        f.iter().map(|x| (x.0.clone(), x.1.clone())).collect()
    };
    if list(&ha) != list(&hb) {
        return Some(format!("particles.h5 has other groups or datasets: {:?} vs {:?}", list(&ha), list(&hb)));
    }
    for (x, y) in ha.iter().zip(&hb) {
        if x.2.len() != y.2.len() {
            return Some(format!("{}/{}: {} vs {} values", x.0, x.1, x.2.len(), y.2.len()));
        }
        if let Some(k) = x.2.iter().zip(&y.2).position(|(u, v)| u != v) {
            return Some(format!(
                "particles.h5 {}/{} differs at entry {k}: {:e} vs {:e} (bits {:#x} vs {:#x})",
                x.0,
                x.1,
                f64::from_bits(x.2[k]),
                f64::from_bits(y.2[k]),
                x.2[k],
                y.2[k]
            ));
        }
    }
    for f in ["gauges.csv", "particles.xmf"] {
        let (u, v) = (std::fs::read(a.join(f)).unwrap(), std::fs::read(b.join(f)).unwrap());
        if u != v {
            let (lu, lv) = (text(&u), text(&v));
            let k = lu.lines().zip(lv.lines()).position(|(p, q)| p != q);
            return Some(format!(
                "{f} differs ({} vs {} bytes), first at line {k:?}: {:?} vs {:?}",
                u.len(),
                v.len(),
                k.and_then(|k| lu.lines().nth(k)),
                k.and_then(|k| lv.lines().nth(k))
            ));
        }
    }
    let (sa, sb) = (physics(summary(a).expect("summary.json of a")), physics(summary(b).expect("summary.json of b")));
    if sa != sb {
        let o = sa.as_object().unwrap();
        let keys: Vec<&String> = o.keys().filter(|k| sa[k.as_str()] != sb[k.as_str()]).collect();
        return Some(format!("summary.json differs in {keys:?}"));
    }
    None
}

/// The run in `b` is bitwise the run in `a`, which is the uninterrupted run; `b` was resumed.
fn assert_same_run(a: &Path, b: &Path, what: &str) {
    let steps = h5_bits(&a.join("particles.h5")).iter().filter(|x| x.1 == "TimeValue").count();
    assert!(steps >= 10, "{what}: {steps} outputs (expected one every 10 µs to 100 µs)");
    assert!(!std::fs::read(a.join("gauges.csv")).unwrap().is_empty(), "{what}: gauges.csv empty");
    let (sa, sb) = (summary(a).expect("summary.json of a"), summary(b).expect("summary.json of b"));
    assert_eq!(sa["status"], "ok", "{what}: the uninterrupted run");
    assert_eq!(sb["status"], "ok", "{what}: the resumed run");
    assert!(!sb["resumed"].as_array().unwrap().is_empty(), "{what}: summary.json records the resume");
    if let Some(d) = difference(a, b) {
        panic!("{what}: not the uninterrupted run: {d}");
    }
}

/// The run that is not interrupted, with `threads` threads.
fn reference(root: &Path, backend: &str, threads: usize) -> PathBuf {
    let dir = root.join(format!("ref_{backend}_{threads}"));
    let o = run_cmd(&dir, backend, threads, &[]).output().unwrap();
    assert_eq!(o.status.code(), Some(0), "the uninterrupted run: {}", shown(&o));
    let s = summary(&dir).unwrap();
    assert!(s["steps"].as_u64().unwrap() >= 50, "a run of some length: {s}");
    dir
}

/// Stopped by SIGTERM past STOP_AT: it finishes its step, writes a checkpoint, exits with 5 and
/// one line; `resume` with the same thread count gives the uninterrupted run. The TERM is sent
/// twice at once, as `timeout` or a batch system sends it to the process and then to its group:
/// one request, not the second signal that ends the program.
fn sigterm_then_resume(root: &Path, reference: &Path, backend: &str, threads: usize) {
    let dir = root.join(format!("term_{backend}_{threads}"));
    let mut child = run_cmd(&dir, backend, threads, &["--checkpoint-every", "5"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_for_checkpoint(&mut child, &dir);
    for _ in 0..2 {
        let k = Command::new("kill").args(["-TERM", &child.id().to_string()]).status().unwrap();
        assert!(k.success(), "kill -TERM");
    }
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(5), "a clean stop: {}", shown(&o));
    let err = text(&o.stderr);
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(err.starts_with("stopped at step") && err.contains("blastsph resume"), "{err}");
    let s = summary(&dir).unwrap();
    assert_eq!(s["status"], "stopped");
    assert_eq!(s["partial"], true);
    // the diagnostic is the line the run ended with (it was null)
    assert_eq!(s["diagnostic"].as_str().map(|d| err.contains(d)), Some(true), "{}", s["diagnostic"]);
    let t = s["time"].as_f64().unwrap();
    assert!((STOP_AT * END..END).contains(&t), "stopped at t = {t:e} s, past {STOP_AT} of {END:e} s");

    // with one thread, the file is also left as a kill in the middle of a later step can leave
    // it (seen once in the SIGKILL test): resume rebuilds it from the steps the checkpoint needs
    let damaged = threads == 1;
    if damaged {
        leave_a_half_written_step(&dir.join("particles.h5"));
    }
    let r = resume(&dir, threads, &[]);
    assert_eq!(r.status.code(), Some(0), "resume: {}", shown(&r));
    if damaged {
        let err = text(&r.stderr);
        assert!(err.contains("could not be cut back in place") && err.contains("rebuilt from its first"), "{err}");
    }
    assert_same_run(
        reference,
        &dir,
        &format!(
            "SIGTERM at t = {t:e} s, {backend}, {threads} thread(s){}",
            if damaged { ", a half-written later step" } else { "" }
        ),
    );
}

/// What a kill while a step is written can leave in particles.h5: the root group links a step
/// past the checkpoint whose object header was never written, and HDF5 then refuses to unlink
/// it ("bad object header version number"). Made here by adding the step and zeroing the
/// start of its group's object header (its address: the location token, an address in the
/// HDF5 1.10 this project builds on).
fn leave_a_half_written_step(h5: &Path) {
    use std::io::{Seek, SeekFrom, Write};
    let token = {
        let f = hdf5::File::open_rw(h5).unwrap();
        let n = f.member_names().unwrap().iter().filter(|m| m.starts_with("Step#")).count();
        let g = f.create_group(&format!("Step#{n}")).unwrap();
        g.new_dataset_builder().with_data(&[1.0f64; 8]).create("x").unwrap();
        format!("{:?}", g.loc_info().unwrap().token)
    };
    let addr: u64 = token
        .strip_prefix("LocationToken(")
        .and_then(|t| t.strip_suffix(')'))
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("the group's location token is not an address: {token} (an HDF5 other than 1.10?)"));
    let mut f = std::fs::OpenOptions::new().write(true).open(h5).unwrap();
    f.seek(SeekFrom::Start(addr)).unwrap();
    f.write_all(&[0u8; 16]).unwrap();
}

/// Killed by SIGKILL after a checkpoint past STOP_AT (with whatever it wrote after it); `report`
/// works on the killed run and says PARTIAL; `resume` with the other thread count gives the
/// uninterrupted run.
fn sigkill_then_resume(root: &Path, reference: &Path, backend: &str, threads: usize) {
    let dir = root.join(format!("kill_{backend}_{threads}"));
    let mut child = run_cmd(&dir, backend, threads, &["--checkpoint-every", "20"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    wait_for_checkpoint(&mut child, &dir);
    child.kill().unwrap();
    let st = child.wait().unwrap();
    assert_eq!(st.code(), None, "killed by a signal, not finished");
    let s = summary(&dir).unwrap();
    assert_eq!(s["status"], "running", "a killed run's summary: {s}");

    // report on the killed run (a copy: report writes its files into the folder)
    let copy = root.join(format!("kill_{backend}_{threads}_report"));
    std::fs::create_dir(&copy).unwrap();
    for e in std::fs::read_dir(&dir).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), copy.join(e.file_name())).unwrap();
    }
    let rep = bin().arg("report").arg(&copy).output().unwrap();
    assert_eq!(rep.status.code(), Some(0), "report on a killed run: {}", shown(&rep));
    assert!(text(&rep.stdout).starts_with("PARTIAL: the run did not finish"), "{}", shown(&rep));
    let rj: Value = serde_json::from_str(&std::fs::read_to_string(copy.join("report.json")).unwrap()).unwrap();
    assert_eq!(rj["partial"], true, "report.json says partial");

    let other = 3 - threads;
    let r = resume(&dir, other, &[]);
    assert_eq!(r.status.code(), Some(0), "resume: {}", shown(&r));
    let t = s["time"].as_f64().unwrap();
    assert_same_run(
        reference,
        &dir,
        &format!(
            "SIGKILL after the checkpoint at t = {t:e} s, {backend}, run with {threads} thread(s), resumed with {other}"
        ),
    );
}

fn both_stops(backend: &str, threads: usize) {
    let d = tempfile::tempdir().unwrap();
    let r = reference(d.path(), backend, threads);
    sigterm_then_resume(d.path(), &r, backend, threads);
    sigkill_then_resume(d.path(), &r, backend, threads);
}

#[test]
fn fortran_1_thread_resumes_bitwise_after_sigterm_and_sigkill() {
    both_stops("fortran", 1);
}

#[test]
fn fortran_2_threads_resumes_bitwise_after_sigterm_and_sigkill() {
    both_stops("fortran", 2);
}

#[test]
fn rust_1_thread_resumes_bitwise_after_sigterm_and_sigkill() {
    both_stops("rust", 1);
}

#[test]
fn rust_2_threads_resumes_bitwise_after_sigterm_and_sigkill() {
    both_stops("rust", 2);
}

/// A stopped run whose case.toml was edited is refused (exit 2, one line naming the case)
/// unless `--allow-changed`; `run` with the same case into its stopped run continues it, and a
/// finished run is not resumed without a later `--end-time`, which extends it.
#[test]
fn a_changed_case_is_refused_unless_allowed_and_run_continues_its_own_restart() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path().join("run");
    let o = run_to(&dir, "rust", 1, 3e-5, &[]).output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", shown(&o));
    // a finished run: nothing to resume without a later end
    let r = resume(&dir, 1, &[]);
    assert_eq!(r.status.code(), Some(2), "{}", shown(&r));
    assert_eq!(text(&r.stderr).lines().count(), 1, "{}", shown(&r));
    assert!(text(&r.stderr).contains("--end-time"), "{}", shown(&r));
    let r = resume(&dir, 1, &["--end-time", "2e-5"]);
    assert_eq!(r.status.code(), Some(2), "an end before the checkpoint: {}", shown(&r));

    // edit the case: refused, naming it, nothing written
    let cp = dir.join("case.toml");
    let was = std::fs::read_to_string(&cp).unwrap();
    std::fs::write(&cp, was.replace("cfl = 0.25", "cfl = 0.2")).unwrap();
    let before = std::fs::read(dir.join("particles.h5")).unwrap();
    let r = resume(&dir, 1, &["--end-time", "5e-5"]);
    assert_eq!(r.status.code(), Some(2), "{}", shown(&r));
    let err = text(&r.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("the case") && err.contains("--allow-changed"), "{err}");
    assert_eq!(std::fs::read(dir.join("particles.h5")).unwrap(), before, "a refused resume writes nothing");
    // a gauge moved: refused even when changes are allowed (its record so far would be carried
    // on under the new point), and nothing written
    let edited = std::fs::read_to_string(&cp).unwrap();
    let moved = edited.replacen("point_m = [0.5,0.75]", "point_m = [0.45,0.75]", 1);
    assert_ne!(moved, edited, "gauge D's point in case.toml");
    std::fs::write(&cp, &moved).unwrap();
    let r = resume(&dir, 1, &["--end-time", "5e-5", "--allow-changed"]);
    assert_eq!(r.status.code(), Some(2), "{}", shown(&r));
    let err = text(&r.stderr);
    assert!(err.contains("gauge `D`") && err.contains("another name, kind or point"), "{err}");
    assert_eq!(std::fs::read(dir.join("particles.h5")).unwrap(), before, "a refused resume writes nothing");
    std::fs::write(&cp, &edited).unwrap();
    // allowed: it continues with the edited case, and the summary says what changed
    let r = resume(&dir, 1, &["--end-time", "5e-5", "--allow-changed"]);
    assert_eq!(r.status.code(), Some(0), "{}", shown(&r));
    let s = summary(&dir).unwrap();
    assert!(s["resumed"][0]["changed"].as_str().is_some_and(|c| c.starts_with("the case")), "{}", s["resumed"]);
    assert_eq!(s["status"], "ok");
    assert_eq!(s["end_time"].as_f64(), Some(5e-5));
    assert!(s["time"].as_f64().unwrap() >= 5e-5 * (1.0 - 1e-9));
    // case.toml says the new end came from the resume (the run's own --end-time kept its mark)
    let ct = std::fs::read_to_string(&cp).unwrap();
    assert!(ct.starts_with("# Resumed with --end-time 5e-5 from the checkpoint"), "{ct}");
    assert!(ct.contains("end_s = 5e-5  # set by resume --end-time (was 3e-5)"), "{ct}");
    assert!(ct.contains("#   --end-time 3e-5  (as time.end_s)"), "{ct}");

    // run into its own stopped run: continues it, and is then the uninterrupted run
    let refd = d.path().join("ref");
    let o = run_cmd(&refd, "rust", 1, &[]).output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", shown(&o));
    let own = d.path().join("own");
    let mut child = run_cmd(&own, "rust", 1, &["--checkpoint-every", "5"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    wait_for_checkpoint(&mut child, &own);
    Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert_eq!(child.wait().unwrap().code(), Some(5), "SIGINT: a clean stop");
    let o = run_cmd(&own, "rust", 2, &[]).output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", shown(&o));
    assert_same_run(&refd, &own, "SIGINT, then `run` again into its folder");
    // another case into it: refused without --force
    let o = run_cmd(&own, "rust", 1, &["--set", "time.cfl=0.2"]).output().unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", shown(&o));
    assert_eq!(text(&o.stderr).lines().count(), 1, "{}", shown(&o));
}

/// A damaged checkpoint is refused with one line (exit 2), and so is a folder without one.
#[test]
fn a_damaged_checkpoint_is_refused_with_one_line() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path().join("run");
    let mut child = run_cmd(&dir, "fortran", 1, &["--checkpoint-every", "5"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    wait_for_checkpoint(&mut child, &dir);
    child.kill().unwrap();
    child.wait().unwrap();
    let cp = dir.join("checkpoint.bin");
    let good = std::fs::read(&cp).unwrap();
    let refuse = |what: &str| {
        let r = resume(&dir, 1, &[]);
        assert_eq!(r.status.code(), Some(2), "{what}: {}", shown(&r));
        assert_eq!(text(&r.stderr).lines().count(), 1, "{what}: {}", shown(&r));
        assert!(text(&r.stdout).is_empty(), "{what}: {}", shown(&r));
    };
    std::fs::write(&cp, &good[..good.len() / 2]).unwrap();
    refuse("a truncated checkpoint");
    let mut flipped = good.clone();
    let k = flipped.len() / 3;
    flipped[k] ^= 0x10;
    std::fs::write(&cp, &flipped).unwrap();
    refuse("one bit flipped");
    std::fs::write(&cp, b"").unwrap();
    refuse("an empty checkpoint");
    std::fs::remove_file(&cp).unwrap();
    refuse("no checkpoint");
    // particles.h5 damaged: refused, not a panic
    std::fs::write(&cp, &good).unwrap();
    let h5 = dir.join("particles.h5");
    let bytes = std::fs::read(&h5).unwrap();
    std::fs::write(&h5, &bytes[..bytes.len() / 4]).unwrap();
    refuse("a truncated particles.h5");
}

/// The comparison can fail: a checkpoint whose velocities are each one ULP off (the file
/// rewritten with a valid checksum) resumes into a run that differs from the uninterrupted one.
#[test]
fn a_checkpoint_one_ulp_off_gives_another_run() {
    use blastsph::sim::checkpoint::{Blob, Item};
    let d = tempfile::tempdir().unwrap();
    let r = reference(d.path(), "rust", 1);
    let dir = d.path().join("off");
    let mut child = run_cmd(&dir, "rust", 1, &["--checkpoint-every", "5"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    wait_for_checkpoint(&mut child, &dir);
    Command::new("kill").args(["-TERM", &child.id().to_string()]).status().unwrap();
    assert_eq!(child.wait().unwrap().code(), Some(5));
    let cp = dir.join("checkpoint.bin");
    let mut b = Blob::decode(&std::fs::read(&cp).unwrap()).unwrap();
    let v = b.f64("p.v").unwrap();
    let moved = v.iter().filter(|x| **x != 0.0).count();
    assert!(moved > 0, "particles in motion at the checkpoint");
    let off: Vec<f64> = v.iter().map(|x| if *x == 0.0 { *x } else { f64::from_bits(x.to_bits() + 1) }).collect();
    b.put("p.v", Item::F64(off));
    std::fs::write(&cp, b.encode()).unwrap();
    let o = resume(&dir, 1, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", shown(&o));
    let diff = difference(&r, &dir);
    assert!(diff.is_some(), "{moved} velocities one ULP off, and the run is bitwise the same");
}

/// A run directory a run is writing is locked (run.lock): `run --force` into it, `resume` and
/// `report` are refused with one line while the run goes on (`--force` deleted the running run's
/// files, which then died at its next output); after the run the folder reports as usual.
#[test]
fn a_folder_a_run_is_writing_is_refused_to_other_commands() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path().join("live");
    let mut child = run_to(&dir, "rust", 1, 1.0, &["--checkpoint-every", "20"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    while summary(&dir).is_none_or(|s| s["status"] != "running") {
        assert!(child.try_wait().unwrap().is_none(), "the run ended before it could be disturbed");
        assert!(t0.elapsed() < Duration::from_secs(120), "no summary.json after 2 minutes");
        std::thread::sleep(Duration::from_millis(5));
    }
    let force = run_to(&dir, "rust", 1, END, &["--force"]).output().unwrap();
    let rep = bin().arg("report").arg(&dir).output().unwrap();
    let res = resume(&dir, 1, &[]);
    let alive = child.try_wait().unwrap().is_none();
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(alive, "the run was still going while the others were refused");
    for (what, o) in [("run --force", &force), ("report", &rep), ("resume", &res)] {
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{what}: {}", shown(o));
        assert_eq!(err.lines().count(), 1, "{what}: one line: {err}");
        assert!(err.contains("a run is writing it now"), "{what}: {err}");
    }
    assert!(dir.join("particles.h5").is_file() && dir.join("case.toml").is_file(), "the run's files are there");
    // the run was killed: its folder is free again
    let r = resume(&dir, 1, &["--end-time", "2e-5"]);
    assert!(!text(&r.stderr).contains("a run is writing it now"), "{}", shown(&r));
}
