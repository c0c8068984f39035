//! A fuzzer of the built binary: proptest mutates case files (values replaced by
//! hostile ones, numbers scaled by powers of ten, keys renamed, lines deleted, copied or cut)
//! and command lines (flags with good and bad values, junk words), runs `blastsph check` or a
//! short `blastsph run` under a time and memory limit, and asserts what every input must get:
//! exit status 0, 2 or 3; with status 2 exactly one line on stderr; never a panic, an abort, a
//! signal, or a run that does not end.
//!
//! Size: `BLASTSPH_FUZZ_CASES` inputs (default 200, about fifteen seconds on two cores);
//! `BLASTSPH_FUZZ_CASES=2000 cargo test --release --test fuzz` for a longer search, with
//! `BLASTSPH_FUZZ_LOG=FILE` to tally the statuses (one line per input). A failing
//! input is shrunk and printed; proptest keeps it in `proptest-regressions/fuzz.txt`, run first
//! the next time.

use proptest::prelude::*;
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Base cases: 1D fixed step, 2D blasts in soil and water, layered soil, a slope, a cylinder.
const BASES: &[&str] = &[
    "shock_tube.toml",
    "surface_loose_tnt6.toml",
    "underwater_box.toml",
    "buried_c4.toml",
    "two_layer_10.toml",
    "slope_45.toml",
    "hard/free_expansion.toml",
];

/// Values that have broken parsers and solvers before.
const HOSTILE: &[&str] = &[
    "0",
    "-1",
    "1",
    "2",
    "0.5",
    "-0.0",
    "1e-12",
    "1e-300",
    "5e-324",
    "1e300",
    "-1e300",
    "1e18",
    "nan",
    "inf",
    "-inf",
    "9223372036854775807",
    "-9223372036854775808",
    "4294967296",
    "\"\"",
    "\"x\"",
    "\"../../x\"",
    "\"/tmp/x\"",
    "true",
    "[]",
    "[0.0]",
    "[0.0, 0.0]",
    "[0.0, 0.0, 0.0]",
    "[1e300, -1e300]",
    "[nan, 0.0]",
    "[inf, inf, inf]",
    "[-1.0, 2.0]",
    "[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]",
    "[2147483648]",
    "[100000, 100000]",
    "{}",
    "{ kind = \"soil\" }",
    "\"cell\"",
    "\"direct\"",
    "\"fixed\"",
    "\"cfl\"",
    "1979-05-27",
];

/// Keys a mutation may introduce (real ones in the wrong place, and unknown ones).
const KEYS: &[&str] = &[
    "dt_s",
    "dt_min_s",
    "max_steps",
    "spacing_m",
    "count",
    "lo_m",
    "hi_m",
    "point_m",
    "pmin_pa",
    "h_over_dx",
    "name",
    "material",
    "subtract",
    "shape",
    "bogus",
    "end_s",
    "radius_m",
    "centre_m",
];

/// One change to a case file's text (line indices are taken modulo its line count).
#[derive(Debug, Clone)]
enum Edit {
    /// The value of line k replaced.
    Value(usize, &'static str),
    /// The numbers of line k scaled by 10^e.
    Scale(usize, i32),
    /// Line k deleted.
    Delete(usize),
    /// Line k copied after line j.
    Copy(usize, usize),
    /// The key of line k renamed.
    Key(usize, &'static str),
    /// `key = value` inserted after line k.
    Insert(usize, &'static str, &'static str),
    /// The text cut at this fraction of its length (on a character boundary).
    Cut(f64),
}

fn edit() -> impl Strategy<Value = Edit> {
    let k = 0usize..10_000;
    prop_oneof![
        4 => (k.clone(), prop::sample::select(HOSTILE)).prop_map(|(k, v)| Edit::Value(k, v)),
        3 => (k.clone(), -12i32..=12).prop_map(|(k, e)| Edit::Scale(k, e)),
        2 => k.clone().prop_map(Edit::Delete),
        1 => (k.clone(), k.clone()).prop_map(|(a, b)| Edit::Copy(a, b)),
        1 => (k.clone(), prop::sample::select(KEYS)).prop_map(|(k, s)| Edit::Key(k, s)),
        1 => (k, prop::sample::select(KEYS), prop::sample::select(HOSTILE)).prop_map(|(k, s, v)| Edit::Insert(k, s, v)),
        1 => (0.0f64..1.0).prop_map(Edit::Cut),
    ]
}

/// Scales every number in `v` by 10^e (a number: what parses as f64 among the words).
fn scale(v: &str, e: i32) -> String {
    let mut out = String::new();
    let mut word = String::new();
    let flush = |w: &mut String, out: &mut String| {
        match w.parse::<f64>() {
            Ok(x) if !w.is_empty() && w.chars().any(|c| c.is_ascii_digit()) => {
                out.push_str(&format!("{:?}", x * 10f64.powi(e)))
            }
            _ => out.push_str(w),
        }
        w.clear();
    };
    for ch in v.chars() {
        if ch.is_ascii_digit() || matches!(ch, '.' | 'e' | 'E' | '-' | '+') {
            word.push(ch);
        } else {
            flush(&mut word, &mut out);
            out.push(ch);
        }
    }
    flush(&mut word, &mut out);
    out
}

fn apply(text: &str, edits: &[Edit]) -> String {
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    for e in edits {
        if lines.is_empty() {
            break;
        }
        let n = lines.len();
        // a key line: `key = value` (not a comment, not a table header)
        let kv = |l: &str| !l.trim_start().starts_with(['#', '[']) && l.contains('=');
        let pick =
            |k: usize, lines: &[String]| -> Option<usize> { (0..n).map(|i| (k + i) % n).find(|&i| kv(&lines[i])) };
        match *e {
            Edit::Value(k, v) => {
                if let Some(i) = pick(k, &lines) {
                    let key = lines[i].split_once('=').map(|(a, _)| a.to_string()).unwrap_or_default();
                    lines[i] = format!("{key}= {v}");
                }
            }
            Edit::Scale(k, s) => {
                if let Some(i) = pick(k, &lines) {
                    let (key, val) = lines[i].split_once('=').map(|(a, b)| (a.to_string(), b.to_string())).unwrap();
                    let val = val.split('#').next().unwrap_or("").to_string();
                    lines[i] = format!("{key}={}", scale(&val, s));
                }
            }
            Edit::Delete(k) => {
                lines.remove(k % n);
            }
            Edit::Copy(a, b) => {
                let l = lines[a % n].clone();
                lines.insert(b % n + 1, l);
            }
            Edit::Key(k, s) => {
                if let Some(i) = pick(k, &lines) {
                    let val = lines[i].split_once('=').map(|(_, b)| b.to_string()).unwrap_or_default();
                    lines[i] = format!("{s} ={val}");
                }
            }
            Edit::Insert(k, s, v) => lines.insert(k % n + 1, format!("{s} = {v}")),
            Edit::Cut(f) => {
                let all = lines.join("\n");
                let mut at = (all.len() as f64 * f) as usize;
                while !all.is_char_boundary(at) {
                    at -= 1;
                }
                lines = all[..at].lines().map(String::from).collect();
            }
        }
    }
    lines.join("\n") + "\n"
}

/// A flag of `check` and `run`, with a good or a bad value; or a junk word.
fn flag() -> impl Strategy<Value = Vec<String>> {
    let v = |xs: &'static [&'static str]| prop::sample::select(xs).prop_map(String::from);
    prop_oneof![
        v(&["1", "2", "0", "-1", "abc", "1025", "99999999999999999999"]).prop_map(|x| vec!["--threads".into(), x]),
        v(&["cell", "direct", "fast", ""]).prop_map(|x| vec!["--nnps".into(), x]),
        v(&["rust", "fortran", "cobol"]).prop_map(|x| vec!["--backend".into(), x]),
        v(&["eos", "force,nnps", "nosuch", ",", ""]).prop_map(|x| vec!["--rust".into(), x]),
        v(&["eos", "kernel,density", "nosuch"]).prop_map(|x| vec!["--fortran".into(), x]),
        v(&["1e-6", "0", "-1", "nan", "inf", "1e300", "5e-324", "x"]).prop_map(|x| vec![format!("--end-time={x}")]),
        v(&["time.cfl=0.1", "sph.nnps=direct", "region.0.spacing_m=nan", "x=1", "=", "time.end_s=", "dim=2"])
            .prop_map(|x| vec!["--set".into(), x]),
        v(&["--bogus", "-x", "--", "extra", "--help=no", "--quiet"]).prop_map(|x| vec![x]),
    ]
}

#[derive(Debug, Clone)]
struct Input {
    base: &'static str,
    edits: Vec<Edit>,
    flags: Vec<Vec<String>>,
    /// A short run instead of `check`.
    run: bool,
}

fn input() -> impl Strategy<Value = Input> {
    (
        prop::sample::select(BASES),
        prop::collection::vec(edit(), 0..4),
        // mostly none: a refused flag hides what the case would do
        prop::collection::vec(flag(), 0..3).prop_map(|mut f| {
            f.truncate(f.len().saturating_sub(1));
            f
        }),
        prop::bool::weighted(0.35),
    )
        .prop_map(|(base, edits, flags, run)| Input { base, edits, flags, run })
}

/// Steps of a fuzzed run (`time.max_steps`): a CFL run stops there (exit 3), a fixed-step run
/// that needs more is refused (exit 2): every run is short. (The shock tube's end is set to what
/// its fixed step reaches in these steps.)
const RUN_STEPS: u32 = 8;
/// Particles any input may make (`--max-particles`): what it cannot allocate is refused first.
const MAX_PARTICLES: &str = "60000";
/// Time limit of one input.
const LIMIT: Duration = Duration::from_secs(60);
/// Address-space limit of one input (KiB).
const MEMORY_KIB: u64 = 6 << 20;

/// Runs one input; Err says what went wrong.
fn exercise(inp: &Input, dir: &Path) -> Result<(), String> {
    let base = std::fs::read_to_string(root().join("cases").join(inp.base)).unwrap();
    let text = apply(&base, &inp.edits);
    let case = dir.join("fuzzed.toml");
    std::fs::write(&case, &text).unwrap();
    let out = dir.join("run");
    let _ = std::fs::remove_dir_all(&out);
    let mut args: Vec<OsString> = vec![if inp.run { "run" } else { "check" }.into(), case.clone().into()];
    for f in &inp.flags {
        args.extend(f.iter().map(OsString::from));
    }
    args.extend(["--max-particles".into(), MAX_PARTICLES.into()]);
    if inp.run {
        args.extend(["--quiet".into(), "--out".into(), out.into()]);
        args.extend(["--set".into(), format!("time.max_steps={RUN_STEPS}").into()]);
        if inp.base == "shock_tube.toml" {
            // its fixed step: an end that RUN_STEPS steps of the unchanged case reach
            args.extend(["--set".into(), "time.end_s=0.04".into()]);
        }
    }
    // the memory limit through the shell (no unsafe pre_exec here)
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v {MEMORY_KIB}; exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_blastsph"))
        .args(&args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if t0.elapsed() > LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("did not end within {LIMIT:?}; case:\n{text}"));
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    let mut err = String::new();
    use std::io::Read;
    child.stderr.take().unwrap().read_to_string(&mut err).unwrap();
    let shown = || format!("args {args:?}; status {status}; stderr {err:?}; case:\n{text}");
    if let Ok(log) = std::env::var("BLASTSPH_FUZZ_LOG") {
        // a tally for whoever tunes the fuzzer: status, command, base, the first line of stderr
        use std::io::Write;
        let line = format!(
            "{:?}\t{}\t{}\t{:.2}\t{}\n",
            status.code(),
            if inp.run { "run" } else { "check" },
            inp.base,
            t0.elapsed().as_secs_f64(),
            err.lines().next().unwrap_or("")
        );
        let mut f = std::fs::OpenOptions::new().create(true).append(true).open(log).unwrap();
        f.write_all(line.as_bytes()).unwrap();
    }
    if err.contains("panicked") || err.contains("internal error") || err.contains("RUST_BACKTRACE") {
        return Err(format!("a panic: {}", shown()));
    }
    match status.code() {
        Some(0 | 3) => Ok(()),
        Some(2) if err.lines().count() == 1 && err.starts_with("error: ") => Ok(()),
        Some(2) => Err(format!("exit 2 without exactly one `error:` line: {}", shown())),
        _ => Err(format!("exit status not 0, 2 or 3 (an abort or a signal?): {}", shown())),
    }
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn cases() -> u32 {
    std::env::var("BLASTSPH_FUZZ_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(200)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), max_shrink_iters: 200, ..ProptestConfig::default() })]

    #[test]
    fn fuzzed_cases_and_command_lines_are_run_or_refused_cleanly(inp in input()) {
        let d = tempfile::tempdir().unwrap();
        if let Err(why) = exercise(&inp, d.path()) {
            prop_assert!(false, "{:?}: {}", inp, why);
        }
    }
}

/// The mutations do what they say (a check of the fuzzer itself).
#[test]
fn the_mutations_change_what_they_say() {
    let t = "a = 1.5\n# c = 2\n[t]\nb = [1.0, -2e3]\n";
    assert_eq!(apply(t, &[Edit::Value(0, "nan")]), "a = nan\n# c = 2\n[t]\nb = [1.0, -2e3]\n");
    assert_eq!(apply(t, &[Edit::Value(1, "x")]), "a = 1.5\n# c = 2\n[t]\nb = x\n");
    assert_eq!(apply(t, &[Edit::Scale(3, 2)]), "a = 1.5\n# c = 2\n[t]\nb = [100.0, -200000.0]\n");
    assert_eq!(apply(t, &[Edit::Delete(0)]), "# c = 2\n[t]\nb = [1.0, -2e3]\n");
    assert_eq!(apply(t, &[Edit::Key(0, "bogus")]), "bogus = 1.5\n# c = 2\n[t]\nb = [1.0, -2e3]\n");
    assert_eq!(apply(t, &[Edit::Cut(0.0)]), "\n");
}
