//! Hostile input: a corpus of bad case files, bad values, bad command lines, unusable
//! `--out` paths and damaged run directories, each given to the built binary. Every one must be
//! refused before it costs anything: exit status 2, exactly one line on stderr (starting with
//! `error:`), nothing that says a panic, within a time limit. And the run-directory rules: no write
//! outside the run directory, no silent overwrite, no symbolic link followed, a default folder
//! that a case's name cannot move out of `runs/`.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn case(name: &str) -> String {
    root().join("cases").join(name).display().to_string()
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// Runs the binary with `args` in `cwd`, killed after `limit`; None when it had to be killed.
fn blastsph_in(cwd: &Path, args: &[OsString], limit: Duration) -> Option<Output> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_blastsph"))
        .args(args)
        .current_dir(cwd)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("cannot start the blastsph binary");
    let t0 = Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            return Some(child.wait_with_output().unwrap());
        }
        if t0.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// A damage done to a copy of a run directory.
type Damage = Box<dyn Fn(&Path)>;

/// One bad input: what it is, the command line, and a word its error must name.
struct Bad {
    what: String,
    args: Vec<OsString>,
    needle: Option<String>,
}

fn bad(what: &str, args: &[&str]) -> Bad {
    Bad { what: what.to_string(), args: args.iter().map(OsString::from).collect(), needle: None }
}

/// `check CASE --set s`: the error must name the key's last part (`c0_ms` of
/// `material.water.eos.c0_ms=nan`), so the input is refused for the reason it was made for.
fn set(what: &str, case_name: &str, s: &str) -> Bad {
    let key = s.split_once('=').map_or(s, |(k, _)| k);
    let last = key.rsplit('.').next().unwrap_or(key);
    set_n(what, case_name, s, last)
}

/// `check CASE --set s`, whose error must name `needle`.
fn set_n(what: &str, case_name: &str, s: &str, needle: &str) -> Bad {
    let mut b = bad(what, &["check", &case(case_name), "--set", s]);
    b.needle = Some(needle.to_string());
    b
}

/// Why `o` is not a proper refusal (None: it is one).
fn not_refused(o: &Option<Output>) -> Option<String> {
    let Some(o) = o else { return Some("did not end within the time limit".into()) };
    let (so, se) = (text(&o.stdout), text(&o.stderr));
    let why = if o.status.code() != Some(2) {
        format!("exit status {:?}, not 2", o.status.code())
    } else if se.lines().count() != 1 || !se.ends_with('\n') {
        format!("{} lines on stderr, not one", se.lines().count())
    } else if !se.starts_with("error: ") {
        "stderr does not start with `error: `".into()
    } else if se.contains("panicked") || se.contains("internal error") || se.contains("RUST_BACKTRACE") {
        "a panic".into()
    } else {
        return None;
    };
    Some(format!("{why}; stdout: {:?}; stderr: {:?}", so.chars().take(400).collect::<String>(), se))
}

/// Runs every input of `corpus` (a few at a time) and lists those not refused properly.
fn check_all(cwd: &Path, corpus: Vec<Bad>) -> usize {
    let n = corpus.len();
    let queue = std::sync::Mutex::new(corpus.into_iter());
    let failures = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..3 {
            s.spawn(|| {
                loop {
                    let Some(b) = queue.lock().unwrap().next() else { break };
                    let o = blastsph_in(cwd, &b.args, Duration::from_secs(60));
                    let why = not_refused(&o).or_else(|| {
                        let err = text(&o.as_ref()?.stderr);
                        let n = b.needle.as_deref()?;
                        (!err.contains(n)).then(|| format!("the error does not name `{n}`: {err:?}"))
                    });
                    if let Some(why) = why {
                        failures.lock().unwrap().push(format!("{} ({:?}): {why}", b.what, b.args));
                    }
                }
            });
        }
    });
    let f = failures.into_inner().unwrap();
    assert!(
        f.is_empty(),
        "{} of {n} bad inputs not refused with one line and exit status 2:\n{}",
        f.len(),
        f.join("\n")
    );
    n
}

/// Case files and values: every one refused by `check` (and so by `run`) before anything is
/// generated or allocated.
#[test]
fn bad_case_files_and_values_are_refused_with_one_line() {
    let d = tempfile::tempdir().unwrap();
    let t = d.path();
    let s1 = "surface_loose_tnt6.toml";
    let tube = "shock_tube.toml";
    let water = "underwater_box.toml";
    let mut c = vec![
        // sizes: nothing allocated before the estimate
        set("capacity overflow (a region 1e200 m long)", s1, "region.soil.lo_m=[0.0,-1e200]"),
        set_n("a lattice of 1e14 particles", s1, "region.soil.hi_m=[1e5,1e5]", "particles"),
        set("a spacing of 1e-300", s1, "region.soil.spacing_m=1e-300"),
        set("a subnormal spacing", s1, "region.soil.spacing_m=5e-324"),
        // subnormal numbers anywhere (a JWL R1 of 1e-320 passed "above 0": the twins then
        // disagreed, NaN against −1.8e308)
        set_n("a subnormal JWL R1", s1, "material.tnt.eos.r1=1e-320", "material.tnt.eos.r1 = 1e-320: a subnormal"),
        set_n("a subnormal CFL", s1, "time.cfl=1e-320", "subnormal"),
        set_n("a subnormal detonation speed", s1, "material.tnt.eos.d_ms=-1e-320", "subnormal"),
        set("a spacing of 0", s1, "region.soil.spacing_m=0"),
        set_n("a 1D wall that is not a point", "verify/reflection_1d.toml", "wall.0.to_m=[0.1]", "to_m"),
        set("a negative spacing", s1, "region.soil.spacing_m=-0.01"),
        set("a spacing of NaN", s1, "region.soil.spacing_m=nan"),
        set("a count that wraps", tube, "region.left.count=[9223372036854775807]"),
        set("a count of 1e12", tube, "region.left.count=[1000000000000]"),
        set("a negative count", tube, "region.left.count=[-5]"),
        // smoothing lengths whose kernel reaches no neighbour (the run was silent garbage: no
        // particle moved, status ok)
        set_n("a region's h of 0.1 spacings", s1, "region.soil.h_m=0.001", "neighbour"),
        set_n("h_over_dx of 0.4 with the cubic kernel", tube, "sph.h_over_dx=0.4", "neighbour"),
        // a table for every entry of an array of tables (a table for one entry sets its keys)
        set_n("a table for all the regions", s1, "region={rho_kgm3=1500.0}", "every [[region]] entry"),
        set_n("an RZ Sedov centre off the axis", "verify/sedov_rz.toml", "analysis.center_m=[-1.0,0.0]", "on the axis"),
        set("a count that is not a whole number", tube, "region.left.count=[1e12]"),
        set("h a million spacings", s1, "sph.h_over_dx=1e6"),
        set_n("an h cap below the initial h", s1, "sph.h_max_ratio=0.5", "h_max_ratio"),
        set_n("a density clamp with lo above hi", s1, "sph.density_clamp=[1015.0,990.0]", "below the upper"),
        set_n("a density clamp with lo equal to hi", s1, "sph.density_clamp=[990.0,990.0]", "below the upper"),
        set_n("a density clamp of one bound", s1, "sph.density_clamp=[990.0]", "needs 2 components"),
        set_n("a density clamp from 0", s1, "sph.density_clamp=[0.0,1015.0]", "density_clamp[0] = 0"),
        set_n("a NaN density clamp", s1, "sph.density_clamp=[990.0,nan]", "density_clamp[1]"),
        set_n("a box with a radius", s1, "region.soil.radius_m=0.1", "not a key of shape"),
        // values: every float finite and in its range
        set("NaN pmin", s1, "material.loose_sand.pmin_pa=nan"),
        set("a positive pmin", s1, "material.loose_sand.pmin_pa=1e5"),
        set("inf sound speed", s1, "material.loose_sand.eos.c_ms=inf"),
        set("NaN density", s1, "material.loose_sand.eos.rho0_kgm3=nan"),
        set("a negative density", s1, "material.loose_sand.eos.rho0_kgm3=-1450"),
        // the value is shown short: 1e300, not its 301 digits
        set_n("a density of 1e300", s1, "material.loose_sand.eos.rho0_kgm3=1e300", "rho0_kgm3 = 1e300: "),
        set("NaN JWL omega", s1, "material.tnt.eos.omega=nan"),
        set("inf JWL A", s1, "material.tnt.eos.a_pa=inf"),
        set("a negative detonation speed", s1, "material.tnt.eos.d_ms=-6930"),
        set("NaN shear modulus", s1, "material.loose_sand.strength.shear_modulus_pa=nan"),
        set("inf cohesion", s1, "material.loose_sand.strength.cohesion_pa=inf"),
        set("NaN friction", s1, "material.loose_sand.strength.alpha_phi=nan"),
        set("NaN initial energy", s1, "material.loose_sand.e0_jkg=nan"),
        set("NaN water constant", water, "material.water.eos.c0_ms=nan"),
        set("inf water constant", water, "material.water.eos.a1_pa=inf"),
        set("NaN water constant b0", water, "material.water.eos.b0=nan"),
        set("inf end time", s1, "time.end_s=inf"),
        set("a negative end time", s1, "time.end_s=-1e-3"),
        set("an end time of 0", s1, "time.end_s=0"),
        set("an output interval of 1e-300", s1, "time.output_interval_s=1e-300"),
        set("NaN output interval", s1, "time.output_interval_s=nan"),
        set("NaN CFL", s1, "time.cfl=nan"),
        set("CFL of 100", s1, "time.cfl=100"),
        set("a CFL of 0", s1, "time.cfl=0"),
        set("NaN viscosity", s1, "viscosity.alpha=nan"),
        set("a negative viscosity", s1, "viscosity.beta=-1"),
        set("inf penalty", s1, "penalty.pbar=inf"),
        set("a penalty exponent of 1000", s1, "penalty.n1=1000"),
        set("NaN wall constant", s1, "boundary.d_m2s2=nan"),
        set("NaN dt floor", s1, "time.dt_min_s=nan"),
        set("a negative dt floor", s1, "time.dt_min_s=-1"),
        set("fixed steps over max_steps", tube, "time.dt_s=1e-12"),
        set("a fixed step of 0", tube, "time.dt_s=0"),
        set("a fixed step of NaN", tube, "time.dt_s=nan"),
        set("max_steps of 0", s1, "time.max_steps=0"),
        set("a negative max_steps", s1, "time.max_steps=-1"),
        // geometry
        set("a domain with lo > hi", s1, "domain.lo_m=[3.0,0.0]"),
        set("a domain of zero width", s1, "domain.hi_m=[-1.0,4.0]"),
        set("a domain with NaN", s1, "domain.lo_m=[nan,0.0]"),
        set("a region with lo > hi", s1, "region.soil.lo_m=[1.0,1.0]"),
        set_n("a region across a wall", s1, "region.soil.hi_m=[1.5,1.0]", "behind wall"),
        set("a region outside the domain", s1, "region.charge.lo_m=[5.0,5.0]"),
        set("a detonation point outside any charge", s1, "detonation.point_m=[0.1,0.1]"),
        set("a detonation point of NaN", s1, "detonation.point_m=[nan,0.97]"),
        set("a detonation point with 3 components in 2D", s1, "detonation.point_m=[0.5,0.97,0.0]"),
        set("a gauge outside the domain", s1, "gauge.A.point_m=[10.0,0.1]"),
        set("a gauge at infinity", s1, "gauge.A.point_m=[inf,0.1]"),
        set("a wall of zero length", s1, "wall.0.to_m=[0.0,1.0]"),
        set("a wall with NaN", s1, "wall.0.to_m=[nan,0.0]"),
        set("dim 4", s1, "dim=4"),
        set("dim 0", s1, "dim=0"),
        set("dim 3 with 2D coordinates", s1, "dim=3"),
        // references and names
        set("a region of an unknown material", s1, "region.soil.material=\"granite\""),
        set("subtracting an unknown region", s1, "region.soil.subtract=[\"nosuch\"]"),
        set("an unknown soil material in the analysis", s1, "analysis.soil_materials=[\"nosuch\"]"),
        set("an unknown EOS kind", s1, "material.0.eos={kind=\"nosuch\"}"),
        set("an unknown shape", s1, "region.soil.shape=\"blob\""),
        set("an unknown kernel", s1, "sph.kernel=\"nosuch\""),
        set("an unknown step rule", s1, "time.step=\"magic\""),
        set("an unknown detonation mode", s1, "detonation.mode=\"fire\""),
        set("a string for a number", s1, "time.end_s=\"abc\""),
        set("a number for a string", s1, "name=5"),
        set("a table for a number", s1, "time.end_s={a=1}"),
        set("an unknown key", s1, "foo.bar=1"),
        set("an unknown entry", s1, "region.nosuch.spacing_m=1"),
        set("an index out of range", s1, "region.7.spacing_m=1"),
        set("an override without =", s1, "nokey"),
        set("an empty key", s1, "=1"),
        set("a key with an empty part", s1, "time..end_s=1"),
        set("a name of 10000 characters", s1, &format!("name=\"{}\"", "x".repeat(10000))),
        set("a name with a newline", s1, "name=\"a\\nb\""),
        set("a material name used twice", s1, "material.1.name=\"tnt\""),
    ];
    // files
    let write = |name: &str, body: &[u8]| -> String {
        let p = t.join(name);
        std::fs::write(&p, body).unwrap();
        p.display().to_string()
    };
    let s1_text = std::fs::read_to_string(case(s1)).unwrap();
    let files: Vec<(&str, Vec<u8>)> = vec![
        ("nesting 20000 arrays deep", format!("a = {}{}", "[".repeat(20000), "]".repeat(20000)).into_bytes()),
        ("nesting 5000 tables deep", format!("a = {}1{}", "{b=".repeat(5000), "}".repeat(5000)).into_bytes()),
        ("bytes that are not UTF-8", b"\xff\xfe\x00garbage".to_vec()),
        ("an empty file", Vec::new()),
        ("a file of NUL bytes", vec![0u8; 4096]),
        ("not TOML", b"this is not a case file\n".to_vec()),
        ("a duplicate key", format!("{s1_text}\ndim = 2\n").into_bytes()),
        ("no regions", s1_text.split("[[region]]").next().unwrap().as_bytes().to_vec()),
        ("cut in the middle", s1_text.as_bytes()[..s1_text.len() / 2].to_vec()),
        ("5 MB of comments", format!("{s1_text}\n{}", "# padding\n".repeat(500_000)).into_bytes()),
        ("a region with 5000 polygon vertices", {
            let pts: Vec<String> = (0..5000)
                .map(|k| {
                    let a = k as f64 * std::f64::consts::TAU / 5000.0;
                    format!("[{:.6}, {:.6}]", 0.5 + 0.1 * a.cos(), 0.5 + 0.1 * a.sin())
                })
                .collect();
            let poly = format!(
                "[[region]]\nname = \"poly\"\nmaterial = \"loose_sand\"\nshape = \"polygon\"\nvertices_m = [{}]\nspacing_m = 0.01\n\n",
                pts.join(", ")
            );
            let k = s1_text.find("[[wall]]").unwrap();
            format!("{}{poly}{}", &s1_text[..k], &s1_text[k..]).into_bytes()
        }),
        ("1001 gauges", {
            let mut s = s1_text.replace("[analysis]", "[analysis_]");
            s = s.split("[analysis_]").next().unwrap().to_string();
            for k in 0..1001 {
                s += &format!("[[gauge]]\nname = \"g{k}\"\npoint_m = [0.5, 0.5]\n");
            }
            s.into_bytes()
        }),
    ];
    for (k, (what, body)) in files.into_iter().enumerate() {
        let p = write(&format!("bad{k}.toml"), &body);
        c.push(bad(what, &["check", &p]));
    }
    c.push(bad("a folder as the case", &["check", &t.display().to_string()]));
    c.push(bad("a missing case", &["check", &t.join("nosuch.toml").display().to_string()]));
    c.push(bad("a device as the case", &["check", "/dev/zero"]));
    let deep = format!("{}=1", vec!["a"; 40_000].join("."));
    c.push(bad("a --set key 40 000 levels deep (it overflowed the stack)", &["check", &case(tube), "--set", &deep]));
    c.push(bad("a fixed-step run too long for max_steps", &["run", &case(tube), "--set", "time.max_steps=3"]));
    let n = check_all(t, c);
    assert!(n > 90, "{n} inputs");
}

/// Command lines: parse errors as one line with the usage hint, numbers out of range, unusable
/// `--out` paths, `dual --steps 0`, damaged run directories given to `report` and `resume`.
#[test]
fn bad_command_lines_and_run_directories_are_refused_with_one_line() {
    let d = tempfile::tempdir().unwrap();
    let t = d.path();
    let s1 = case("surface_loose_tnt6.toml");
    let tube = case("shock_tube.toml");
    let p = |name: &str| t.join(name).display().to_string();
    let mut c = vec![
        bad("no command", &[]),
        bad("an unknown command", &["bogus"]),
        {
            // the missing argument named on the line (clap lists it on the next line)
            let mut b = bad("run without a case", &["run"]);
            b.needle = Some("provided: <CASE>".into());
            b
        },
        bad("an unknown flag", &["check", &s1, "--bogus"]),
        bad("a flag without its value", &["run", &s1, "--out"]),
        bad("a flag given twice", &["run", &tube, "--end-time", "1", "--end-time", "2"]),
        bad("threads not a number", &["run", &s1, "--threads", "abc"]),
        bad("a module in Rust and in Fortran", &["check", &s1, "--rust", "eos", "--fortran", "eos,force"]),
        bad("0 threads", &["run", &s1, "--threads", "0"]),
        {
            // a newline in the output folder's name (a shell's $(...) gone wrong)
            let mut b = bad("a newline in --out", &["run", &tube, "--out", &p("a\nb")]);
            b.needle = Some("control character".into());
            b
        },
        bad("a million threads", &["run", &s1, "--threads", "1000000"]),
        bad("threads beyond u64", &["run", &s1, "--threads", "99999999999999999999999"]),
        bad("--end-time inf", &["run", &tube, "--end-time", "inf"]),
        bad("--end-time NaN", &["run", &tube, "--end-time", "NaN"]),
        bad("--end-time 0", &["run", &tube, "--end-time", "0"]),
        bad("--end-time negative", &["run", &tube, "--end-time=-1"]),
        {
            // a negative number after a space is the flag's value, refused by its own check
            // (it was "unexpected argument '-1'")
            let mut b = bad("--end-time -1 (after a space)", &["run", &tube, "--end-time", "-1"]);
            b.needle = Some("--end-time -1: must be a positive time".into());
            b
        },
        {
            let mut b = bad("--threads -1 (after a space)", &["run", &tube, "--threads", "-1"]);
            b.needle = Some("'--threads <N>'".into());
            b
        },
        bad("--end-time 1e300", &["check", &tube, "--end-time", "1e300"]),
        bad("--progress-every NaN", &["run", &tube, "--progress-every", "nan"]),
        bad("--progress-every negative", &["run", &tube, "--progress-every=-5"]),
        bad("--checkpoint-every 0", &["run", &tube, "--checkpoint-every", "0"]),
        bad("--checkpoint-wall NaN", &["run", &tube, "--checkpoint-wall", "nan"]),
        bad("--checkpoint-wall 0", &["run", &tube, "--checkpoint-wall", "0"]),
        bad("--max-particles 0", &["check", &s1, "--max-particles", "0"]),
        bad("--max-particles below the case", &["run", &s1, "--max-particles", "100"]),
        bad("an unknown backend", &["run", &tube, "--backend", "cobol"]),
        bad("an unknown search", &["run", &tube, "--nnps", "fast"]),
        bad("an unknown module", &["run", &tube, "--rust", "nosuch"]),
        bad("dual --steps 0", &["dual", &tube, "--steps", "0"]),
        bad("dual --steps negative", &["dual", &tube, "--steps=-1"]),
        bad("report --times NaN", &["report", &p("x"), "--times", "nan"]),
        bad("report --times negative", &["report", &p("x"), "--times=-1"]),
        bad("validate an unknown scene", &["validate", "--only", "nosuch", "--out", &p("v")]),
        bad("bench --resolutions 1e6", &["bench", "--dry-run", "--resolutions", "1e6"]),
        bad("bench --resolutions 0", &["bench", "--dry-run", "--resolutions", "0"]),
        bad("bench --resolutions NaN", &["bench", "--dry-run", "--resolutions", "nan"]),
        bad("legacy build of a missing manifest", &["legacy", "build", &p("nosuch/legacy.toml")]),
        bad("a case name outside the case folder", &["check", "../../etc/passwd"]),
    ];
    // a case that is not a regular file: a device, a folder (the error says so)
    for (what, path) in [("a case that is a device", "/dev/zero".to_string()), ("a case that is a folder", p(""))] {
        let mut b = bad(what, &["check", &path]);
        b.needle = Some("not a regular file".into());
        c.push(b);
    }
    // a name with a direction override (it would reorder the terminal's line around it)
    c.push(set_n(
        "a name with U+202E",
        "verify/sedov_2d_g14.toml",
        "region.hot.name=\"ab\u{202E}cd\"",
        "direction marks",
    ));
    // --out: existing file, a path under a file, a link, a folder of someone else's files, a
    // folder with a planted link, /proc
    std::fs::write(t.join("afile"), b"x").unwrap();
    c.push(bad("--out an existing file", &["run", &tube, "--out", &p("afile")]));
    c.push(bad("--out under a file", &["run", &tube, "--out", &p("afile/sub")]));
    c.push(bad("--out unwritable", &["run", &tube, "--out", "/proc/blastsph_out"]));
    std::os::unix::fs::symlink(t, t.join("alink")).unwrap();
    c.push(bad("--out a symbolic link", &["run", &tube, "--out", &p("alink")]));
    std::fs::create_dir(t.join("theirs")).unwrap();
    std::fs::write(t.join("theirs/thesis.tex"), b"x").unwrap();
    c.push(bad("--out a folder of other files", &["run", &tube, "--out", &p("theirs")]));
    c.push(bad("--force on a folder of other files", &["run", &tube, "--force", "--out", &p("theirs")]));
    std::fs::create_dir(t.join("planted")).unwrap();
    std::os::unix::fs::symlink(t.join("afile"), t.join("planted/particles.h5")).unwrap();
    c.push(bad("--out with a planted link", &["run", &tube, "--out", &p("planted")]));
    c.push(bad("dual --out a file", &["dual", &tube, "--steps", "1", "--out", &p("afile")]));
    std::fs::create_dir(t.join("arun")).unwrap();
    std::fs::write(t.join("arun/summary.json"), "{}").unwrap();
    c.push(bad("dual --out a run's folder", &["dual", &tube, "--steps", "1", "--out", &p("arun")]));
    c.push(bad("bench --out a file", &["bench", "--cases", "shock_tube", "--resolutions", "1", "--out", &p("afile")]));
    c.push(bad(
        "bench --out a run's folder",
        &["bench", "--cases", "shock_tube", "--resolutions", "1", "--out", &p("arun")],
    ));
    c.push(bad(
        "bench --out a folder of other files",
        &["bench", "--cases", "shock_tube", "--resolutions", "1", "--out", &p("theirs")],
    ));
    c.push(bad("validate --out a folder of other files", &["validate", "--only", "buried_c4", "--out", &p("theirs")]));
    c.push(bad("validate --out a file", &["validate", "--only", "buried_c4", "--out", &p("afile")]));
    std::fs::create_dir(t.join("nocases")).unwrap();
    c.push(bad("validate --cases an empty folder", &["validate", "--cases", &p("nocases"), "--out", &p("vempty")]));
    c.push(bad(
        "legacy build --out a file",
        &["legacy", "build", &root().join("tests/legacy/legacy.toml").display().to_string(), "--out", &p("afile")],
    ));

    // damaged run directories: a finished run of the shock tube, then each damage on a copy
    let good = t.join("good");
    let o = blastsph_in(
        t,
        &["run", &tube, "--quiet", "--out", &good.display().to_string()].map(OsString::from),
        Duration::from_secs(120),
    )
    .expect("the shock tube run ended");
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let damaged = |name: &str, damage: &dyn Fn(&Path)| -> String {
        let dir = t.join(name);
        std::fs::create_dir(&dir).unwrap();
        for e in std::fs::read_dir(&good).unwrap() {
            let e = e.unwrap();
            std::fs::copy(e.path(), dir.join(e.file_name())).unwrap();
        }
        damage(&dir);
        dir.display().to_string()
    };
    let cut = |f: &'static str, keep: f64| {
        move |d: &Path| {
            let b = std::fs::read(d.join(f)).unwrap();
            std::fs::write(d.join(f), &b[..(b.len() as f64 * keep) as usize]).unwrap();
        }
    };
    let put = |f: &'static str, body: &'static [u8]| move |d: &Path| std::fs::write(d.join(f), body).unwrap();
    let rm = |f: &'static str| move |d: &Path| std::fs::remove_file(d.join(f)).unwrap();
    let dirs: Vec<(&str, Damage)> = vec![
        ("a truncated particles.h5", Box::new(cut("particles.h5", 0.1))),
        ("particles.h5 cut to 3/4", Box::new(cut("particles.h5", 0.75))),
        ("particles.h5 not HDF5", Box::new(put("particles.h5", b"hello"))),
        ("an empty particles.h5", Box::new(put("particles.h5", b""))),
        ("no particles.h5", Box::new(rm("particles.h5"))),
        ("summary.json not JSON", Box::new(put("summary.json", b"{ not json"))),
        ("summary.json a list", Box::new(put("summary.json", b"[]"))),
        ("summary.json an empty object", Box::new(put("summary.json", b"{}"))),
        ("case.toml not TOML", Box::new(put("case.toml", b"garbage = ["))),
        ("no case.toml", Box::new(rm("case.toml"))),
        (
            "case.toml of another case",
            Box::new(|d: &Path| {
                std::fs::copy(root().join("cases/surface_loose_tnt6_rz.toml"), d.join("case.toml")).unwrap();
            }),
        ),
        ("a planted link", Box::new(|d: &Path| std::os::unix::fs::symlink("/etc/passwd", d.join("x.png")).unwrap())),
        (
            // as when another run's particles.h5 is copied in (it was reported as this case's)
            "particles.h5 of another particle count",
            Box::new(|d: &Path| {
                let s = std::fs::read_to_string(d.join("summary.json")).unwrap();
                assert!(s.contains("\"particles\": 400"), "{s}");
                std::fs::write(d.join("summary.json"), s.replace("\"particles\": 400", "\"particles\": 401")).unwrap();
            }),
        ),
    ];
    for (k, (what, f)) in dirs.iter().enumerate() {
        let dir = damaged(&format!("damaged{k}"), f.as_ref());
        c.push(bad(&format!("report: {what}"), &["report", &dir]));
        if what.starts_with("case.toml of") {
            c.push(bad(&format!("revolve: {what}"), &["revolve", &dir]));
        }
    }
    let rdirs: Vec<(&str, Damage)> = vec![
        ("no checkpoint.bin", Box::new(rm("checkpoint.bin"))),
        ("a truncated checkpoint.bin", Box::new(cut("checkpoint.bin", 0.5))),
        ("checkpoint.bin not a checkpoint", Box::new(put("checkpoint.bin", b"BLASTSPH-CHECKPOINT\nxx"))),
        ("a truncated particles.h5", Box::new(cut("particles.h5", 0.1))),
        ("no particles.h5", Box::new(rm("particles.h5"))),
        ("no case.toml", Box::new(rm("case.toml"))),
        ("case.toml not TOML", Box::new(put("case.toml", b"garbage = ["))),
        ("a planted link", Box::new(|d: &Path| std::os::unix::fs::symlink("/etc/passwd", d.join("x.png")).unwrap())),
    ];
    for (k, (what, f)) in rdirs.iter().enumerate() {
        let dir = damaged(&format!("rdamaged{k}"), f.as_ref());
        c.push(bad(&format!("resume: {what}"), &["resume", &dir, "--allow-changed", "--end-time", "0.3"]));
    }
    let g = good.display().to_string();
    c.push(bad("resume a finished run without a later end", &["resume", &g]));
    c.push(bad("resume to an end before the checkpoint", &["resume", &g, "--end-time", "0.1"]));
    c.push(bad("resume to inf", &["resume", &g, "--end-time", "inf"]));
    c.push(bad("resume a missing folder", &["resume", &p("nosuch")]));
    c.push(bad("resume a file", &["resume", &p("afile")]));
    c.push(bad("report a missing folder", &["report", &p("nosuch")]));
    c.push(bad(
        "report an empty folder",
        &["report", &{
            std::fs::create_dir(t.join("empty")).unwrap();
            p("empty")
        }],
    ));
    c.push(bad("run into a finished run of another case", &["run", &tube, "--set", "time.end_s=0.1", "--out", &g]));
    // arguments that are not UTF-8
    {
        use std::os::unix::ffi::OsStringExt;
        let raw = OsString::from_vec(vec![b'x', 0xff, b'=', b'1']);
        c.push(Bad {
            what: "an override that is not UTF-8".into(),
            args: vec!["check".into(), tube.clone().into(), "--set".into(), raw],
            needle: None,
        });
    }
    let n = check_all(t, c);
    assert!(n > 60, "{n} inputs");
    // nothing written into the run directory by the refusals
    assert!(!t.join("theirs/particles.h5").exists() && !t.join("planted/case.toml").exists());
    assert_eq!(std::fs::read(t.join("afile")).unwrap(), b"x");
}

/// A value of 100 000 characters given to --set is refused on one line that quotes only its
/// start (the message does not carry the whole value).
#[test]
fn a_huge_value_is_refused_with_a_short_line() {
    let d = tempfile::tempdir().unwrap();
    let big = format!("time.end_s={}", "9".repeat(100_000));
    let args: Vec<OsString> = ["check", &case("shock_tube.toml"), "--set", &big].iter().map(OsString::from).collect();
    let o = blastsph_in(d.path(), &args, Duration::from_secs(60));
    assert_eq!(not_refused(&o), None);
    let err = text(&o.unwrap().stderr);
    assert!(err.len() < 1000, "{} characters on the error line", err.len());
    assert!(err.contains("characters)"), "{err}");
}

/// A case's name never moves the default run directory out of `runs/` of the working folder.
#[test]
fn a_case_name_cannot_move_the_run_directory() {
    let d = tempfile::tempdir().unwrap();
    let work = d.path().join("a/b");
    std::fs::create_dir_all(&work).unwrap();
    let tube = std::fs::read_to_string(case("shock_tube.toml")).unwrap();
    for (k, name) in ["../../x", "/tmp/blastsph_x", "", "..//..//y"].iter().enumerate() {
        let body = tube.replacen("name = \"shock_tube\"", &format!("name = {name:?}"), 1);
        assert_ne!(body, tube, "the name line of shock_tube.toml");
        let p = d.path().join(format!("named{k}.toml"));
        std::fs::write(&p, body).unwrap();
        let o = blastsph_in(
            &work,
            &["run", &p.display().to_string(), "--quiet", "--end-time", "0.01"].map(OsString::from),
            Duration::from_secs(120),
        )
        .expect("ended");
        assert_eq!(o.status.code(), Some(0), "name {name:?}: {}", text(&o.stderr));
    }
    // everything under a/b/runs, one folder per run
    let top: Vec<String> =
        std::fs::read_dir(d.path()).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert!(top.iter().all(|n| n == "a" || n.starts_with("named")), "written outside: {top:?}");
    assert!(!Path::new("/tmp/blastsph_x").exists(), "a name wrote to /tmp");
    let inside: Vec<String> =
        std::fs::read_dir(&work).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert_eq!(inside, ["runs"]);
    let runs: Vec<PathBuf> = std::fs::read_dir(work.join("runs")).unwrap().map(|e| e.unwrap().path()).collect();
    assert_eq!(runs.len(), 4, "{runs:?}");
    for r in runs {
        assert!(r.join("summary.json").is_file(), "{}", r.display());
    }
}

/// No silent overwrite: a run into a finished run is refused (one line, exit 2, nothing
/// changed); `--force` replaces it, and leaves nothing of the old run (the report's pictures).
#[test]
fn a_run_never_silently_overwrites_another() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path().join("run");
    let s = dir.display().to_string();
    let tube = case("shock_tube.toml");
    let go = |args: &[&str]| {
        blastsph_in(d.path(), &args.iter().map(OsString::from).collect::<Vec<_>>(), Duration::from_secs(120))
            .expect("ended")
    };
    let o = go(&["run", &tube, "--quiet", "--out", &s]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let o = go(&["report", &s]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let pngs = |dir: &Path| {
        std::fs::read_dir(dir)
            .unwrap()
            .filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().ends_with(".png"))
            .count()
    };
    assert!(pngs(&dir) > 0, "the report drew pictures");
    let before = std::fs::read(dir.join("summary.json")).unwrap();
    // the same case again, another case: both refused
    for extra in [&[][..], &["--set", "time.end_s=0.1"][..]] {
        let mut a = vec!["run", &tube, "--quiet", "--out", &s];
        a.extend_from_slice(extra);
        let o = Some(go(&a));
        if let Some(why) = not_refused(&o) {
            panic!("run into a finished run with {extra:?}: {why}");
        }
        assert_eq!(std::fs::read(dir.join("summary.json")).unwrap(), before, "nothing changed");
    }
    let o = go(&["run", &tube, "--quiet", "--force", "--set", "time.end_s=0.1", "--out", &s]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert_eq!(pngs(&dir), 0, "--force left the old report's pictures");
    assert!(!dir.join("report.json").exists(), "--force left the old report.json");
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(v["end_time"].as_f64(), Some(0.1));
}
