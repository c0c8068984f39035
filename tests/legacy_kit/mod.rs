//! Helpers of the legacy-code tests (tests/migration.rs: the build and the loader;
//! tests/legacy_run.rs: run, dual and ledger): the fixture, one shared build, the binary.
#![allow(dead_code)]

pub use blastsph::migration::{LegacyLib, build};
pub use std::path::{Path, PathBuf};
pub use std::process::{Command, Output, Stdio};
pub use std::sync::OnceLock;

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub fn fixture() -> PathBuf {
    root().join("tests/legacy")
}

pub fn scratch(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("migration").join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("scratch folder");
    d
}

/// One build of the fixture for the tests of this file that call routines.
pub fn shared() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let d = scratch("shared");
        build(&fixture().join("legacy.toml"), &d).expect("the fixture builds");
        d
    })
}

pub fn lib() -> LegacyLib {
    LegacyLib::open(shared()).expect("the fixture's library loads")
}

pub fn blastsph<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_blastsph")).args(args).current_dir(root()).output().expect("blastsph runs")
}

/// `blastsph ARGS` in the repository root with the fixture program's input on stdin: `40` steps,
/// then `0` (no more), as host mode runs the program.
pub fn blastsph_40_steps<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_blastsph"))
        .args(args)
        .current_dir(root())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("blastsph starts");
    {
        use std::io::Write;
        child.stdin.take().unwrap().write_all(b"40\n0\n").unwrap();
    }
    child.wait_with_output().unwrap()
}

/// The arguments of `blastsph dual shock_tube --legacy LG --compat liu-book [--steps N] --out OUT`
/// (the dual run of the fixture's builds with the book's profile).
pub fn dual_book_args(lg: &Path, steps: Option<usize>, out: &Path) -> Vec<String> {
    let mut a: Vec<String> = ["dual", "shock_tube", "--legacy", lg.to_str().unwrap(), "--compat", "liu-book"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    if let Some(n) = steps {
        a.extend(["--steps".to_string(), n.to_string()]);
    }
    a.extend(["--out".to_string(), out.to_str().unwrap().to_string()]);
    a
}

/// `blastsph dual shock_tube --legacy LG --steps N --out OUT --threads 1` (no compat profile).
pub fn dual_plain(lg: &Path, steps: usize, out: &Path) -> Output {
    let n = steps.to_string();
    blastsph(&[
        "dual",
        "shock_tube",
        "--legacy",
        lg.to_str().unwrap(),
        "--steps",
        &n,
        "--out",
        out.to_str().unwrap(),
        "--threads",
        "1",
    ])
}

/// [`dual_book_args`] run.
pub fn dual_book(lg: &Path, steps: Option<usize>, out: &Path) -> Output {
    blastsph(&dual_book_args(lg, steps, out))
}

/// A deterministic generator of inputs (xorshift64*), values in [0, 1).
pub struct Rng(pub u64);
impl Rng {
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The fixture's cubic spline in 1D (kernel.f, skf = 1) with gfortran's reading of it: the literal
/// `2./3.` is a default-real (f32) constant; `q**3` is (q*q)*q; the operations in source order.
pub fn cubic(r: f64, dx: f64, h: f64) -> (f64, f64) {
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
pub fn cloud(n: usize, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut g = Rng(seed);
    let x: Vec<f64> = (0..n).map(|i| 0.01 * i as f64 + 0.004 * (g.next() - 0.5)).collect();
    let h: Vec<f64> = (0..n).map(|_| 0.012 + 0.006 * g.next()).collect();
    (x, h)
}

/// The pairs the fixture's direct_find forms (i < j, sqrt(r²) < 2 h_ij), 0-based, in its order.
pub fn pairs_of(x: &[f64], h: &[f64]) -> (Vec<i32>, Vec<i32>) {
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

pub fn same_bits(what: &str, got: &[f64], want: &[f64]) {
    assert_eq!(got.len(), want.len(), "{what}: lengths");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert_eq!(g.to_bits(), w.to_bits(), "{what}[{k}]: legacy {g:e}, formula {w:e}");
    }
}

/// A copy of the fixture in a scratch folder, with `edit` applied to its manifest text.
pub fn variant(name: &str, edit: impl Fn(&str) -> String) -> PathBuf {
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

/// A copy of the fixture in a scratch folder with `edit` applied to file `file` (param.inc's
/// switches, say), built into `DIR/build`; returns DIR.
pub fn variant_built(name: &str, file: &str, edit: impl Fn(&str) -> String) -> PathBuf {
    let d = variant(name, |m| m.to_string());
    let f = d.join(file);
    let text = std::fs::read_to_string(&f).unwrap();
    let new = edit(&text);
    assert_ne!(new, text, "the edit of {file} changes it");
    std::fs::write(&f, new).unwrap();
    build(&d.join("legacy.toml"), &d.join("build")).expect("the variant builds");
    d
}

/// The shock tube with the book's averaged velocity (param.inc's `average_velocity = .true.`,
/// av_vel's ε = 0.3): cases/shock_tube.toml with `xsph_eps = 0.3`, written into `dir`.
pub fn xsph_case(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(root().join("cases/shock_tube.toml")).unwrap();
    let new = text.replace("smoothing = \"constant\"", "smoothing = \"constant\"\nxsph_eps = 0.3");
    assert_ne!(new, text);
    let p = dir.join("shock_tube_xsph.toml");
    std::fs::write(&p, new).unwrap();
    p
}

/// `legacy build` refuses: status 2, one line on stderr naming every needle, no panic.
pub fn refused(dir: &Path, needles: &[&str]) -> String {
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

/// `blastsph ARGS`, which must exit with `code`; returns stdout.
pub fn blastsph_ok<S: AsRef<std::ffi::OsStr> + std::fmt::Debug>(args: &[S], code: i32) -> String {
    let o = blastsph(args);
    let (so, se) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert_eq!(o.status.code(), Some(code), "blastsph {args:?}\nstdout: {so}\nstderr: {se}");
    so.into_owned()
}

pub fn report_rows(path: &Path) -> (serde_json::Value, Vec<serde_json::Value>) {
    let r: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).expect("report")).expect("json");
    let rows = r["rows"].as_array().expect("rows").clone();
    (r, rows)
}

/// The routines of the fixture that the shock tube runs, each with the fields it writes.
pub const MAPPED: &[(&str, &[&str])] = &[
    ("legacy.direct_find", &["pair_i", "pair_j", "w", "dwdx"]),
    ("legacy.kernel", &["w", "dwdx"]),
    ("legacy.sum_density", &["rho"]),
    ("legacy.p_gas", &["p", "c"]),
    ("legacy.int_force", &["p", "c", "acc", "dde"]),
    ("legacy.art_visc", &["acc", "dde"]),
];

pub fn row<'a>(rows: &'a [serde_json::Value], stage: &str, field: &str) -> &'a serde_json::Value {
    rows.iter()
        .find(|r| r["stage"] == stage && r["field"] == field)
        .unwrap_or_else(|| panic!("no row {stage} {field} in the report"))
}

/// The fixture's own program to the end of the shock tube: its final state (17 digits), once.
pub fn program_final_state() -> &'static [Vec<f64>] {
    static ROWS: OnceLock<Vec<Vec<f64>>> = OnceLock::new();
    ROWS.get_or_init(program_rows)
}

pub fn program_rows() -> Vec<Vec<f64>> {
    program_rows_of(shared(), "program_run_2", 40)
}

/// The program of the build in `build` run for `steps` steps (input `steps` then `0`): its final
/// state at 17 digits (columns: number, type, x, vx, mass, rho, p, u, hsml).
pub fn program_rows_of(build: &Path, name: &str, steps: u32) -> Vec<Vec<f64>> {
    let work = scratch(name);
    let mut child = Command::new(build.join("program"))
        .current_dir(&work)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the fixture's program starts");
    {
        use std::io::Write;
        child.stdin.take().unwrap().write_all(format!("{steps}\n0\n").as_bytes()).unwrap();
    }
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(work.join("final_state.dat")).expect("final_state.dat");
    text.lines().skip(1).map(|l| l.split_whitespace().map(|v| v.parse::<f64>().unwrap()).collect()).collect()
}

/// `run CASE --legacy BUILD --compat liu-book` ends in the state of the fixture's own program, bit
/// for bit; returns the last frame.
pub fn assert_run_ends_as_the_program(build: &Path, name: &str) -> blastsph::output::Frame {
    assert_run_ends_as(build, "shock_tube", "liu-book", program_final_state(), name)
}

/// `run CASE --legacy BUILD --compat COMPAT` ends in the state `rows` (a program's final state,
/// [`program_rows_of`]), bit for bit; returns the last frame.
pub fn assert_run_ends_as(
    build: &Path,
    case: &str,
    compat: &str,
    rows: &[Vec<f64>],
    name: &str,
) -> blastsph::output::Frame {
    assert_run_ends_as_after(build, case, compat, rows, name, 40)
}

/// [`assert_run_ends_as`] after `steps` steps of dt = 0.005 s (the case's end set to steps·dt).
pub fn assert_run_ends_as_after(
    build: &Path,
    case: &str,
    compat: &str,
    rows: &[Vec<f64>],
    name: &str,
    steps: u32,
) -> blastsph::output::Frame {
    let out = scratch(name);
    let end = format!("time.end_s={}", steps as f64 * 0.005);
    let so = blastsph_ok(
        &[
            "run",
            case,
            "--legacy",
            build.to_str().unwrap(),
            "--compat",
            compat,
            "--set",
            &end,
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ],
        0,
    );
    assert!(so.contains(&format!("400 particles, {steps} steps")), "{so}");
    // the run says that legacy routines ran, and which modules they are in (summary.json too)
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).expect("summary.json")).unwrap();
    let legacy = summary["legacy"].as_array().cloned().unwrap_or_default();
    assert!(!legacy.is_empty(), "summary.json legacy: {summary}");
    assert!(so.contains("legacy routines in "), "{so}");
    let frames = blastsph::output::read_frames(&out.join("particles.h5")).expect("particles.h5");
    let f = frames.last().unwrap();
    assert!((f.time - steps as f64 * 0.005).abs() < 1e-6, "t = {}", f.time);
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

/// The datasets `names` of the last frame of `dir`/particles.h5.
pub fn last_frame(dir: &Path, names: &[&str]) -> Vec<Vec<f64>> {
    let f = hdf5::File::open(dir.join("particles.h5")).unwrap();
    let last = f
        .member_names()
        .unwrap()
        .into_iter()
        .filter(|s| s.starts_with("Step#"))
        .max_by_key(|s| s[5..].parse::<u64>().unwrap())
        .unwrap();
    let g = f.group(&last).unwrap();
    names.iter().map(|n| g.dataset(n).unwrap_or_else(|e| panic!("{n}: {e}")).read_raw::<f64>().unwrap()).collect()
}

/// The fixture's art_visc with its arrays in COMMON blocks instead of arguments (a routine with
/// no arguments, as many old codes write them): the include file that declares the blocks.
pub const AVSTATE_INC: &str = "      include 'param.inc'
      integer ntotal, niac, pair_i(max_interaction),
     &        pair_j(max_interaction)
      double precision hsml(maxn), mass(maxn), x(dim,maxn),
     &        vx(dim,maxn), rho(maxn), c(maxn), w(max_interaction),
     &        dwdx(dim,max_interaction), dvxdt(dim,maxn), dedt(maxn)
      common /avst/ hsml, mass, x, vx, rho, c, w, dwdx, dvxdt, dedt
      common /avcnt/ ntotal, niac, pair_i, pair_j
";

/// The globals of the COMMON and module variants: every legacy name is the vocabulary's.
pub const AV_GLOBALS: &str = "globals = { ntotal = \"ntotal\", hsml = \"hsml\", mass = \"mass\", x = \"x\", vx = \"vx\", niac = \"niac\", rho = \"rho\", c = \"c\", pair_i = \"pair_i\", pair_j = \"pair_j\", w = \"w\", dwdx = \"dwdx\", dvxdt = \"dvxdt\", dedt = \"dedt\" }";

/// The fixture with art_visc's arguments moved into globals: its source edited by `src`, the
/// manifest's entry by `entry` (the text after `module = "viscosity"`), and `head` added to
/// the manifest's top.
pub fn av_globals_variant(name: &str, head: &str, entry: &str, src: impl Fn(&str) -> String) -> PathBuf {
    let v = variant(name, |m| {
        let old = "module = \"viscosity\"\nargs = [\"ntotal\", \"hsml\", \"mass\", \"x\", \"vx\", \"niac\", \"rho\", \"c\", \"pair_i\", \"pair_j\", \"w\", \"dwdx\",\n        \"dvxdt\", \"dedt\"]";
        assert!(m.contains(old), "art_visc's entry");
        let m = m.replace(old, &format!("module = \"viscosity\"\n{entry}"));
        m.replacen("[[routine]]", &format!("{head}\n\n[[routine]]"), 1)
    });
    let f = v.join("art_visc.f");
    let text = std::fs::read_to_string(&f).unwrap();
    let new = src(&text);
    assert_ne!(new, text);
    std::fs::write(&f, new).unwrap();
    v
}

/// art_visc.f with its argument list and declarations replaced by `decl` (fixed form).
pub fn av_without_arguments(text: &str, decl: &str) -> String {
    let (head, rest) =
        text.split_once("      implicit none\n      include 'param.inc'\n").expect("art_visc's declarations");
    let body = rest.split_once("dedt(maxn)\n").expect("the last declaration line").1;
    let head = head.replace(
        "      subroutine art_visc(ntotal, hsml, mass, x, vx, niac, rho, c,\n     &                    pair_i, pair_j, w, dwdx, dvxdt, dedt)",
        "      subroutine art_visc",
    );
    assert!(head.starts_with("      subroutine art_visc\n"), "{head}");
    format!("{head}{decl}{body}")
}

/// The book's `ext_force` in the fixture's dialect: gravity on the last component when `gravity`
/// (its `-9.8d0`), then the repulsion D (x_i − x_j) [(r0/r)^12 − (r0/r)^4]/r² of each ordinary
/// particle i by a boundary particle j (negative itype) within r0, r0 and D written as the
/// literals `rr0` and `dd`.
pub fn ext_force_f(gravity: bool, rr0: &str, dd: &str) -> String {
    let g = if gravity { "        dvxdt(dim,i) = -9.8d0\n" } else { "" };
    format!(
        "      subroutine ext_force(ntotal, mass, x, niac, pair_i, pair_j,
     &                     itype, hsml, dvxdt)
c-----------------------------------------------------------------------
c     External forces: gravity and the boundary repulsion.
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer ntotal, niac, pair_i(max_interaction),
     &        pair_j(max_interaction), itype(maxn)
      double precision mass(maxn), x(dim,maxn), hsml(maxn),
     &        dvxdt(dim,maxn)
      integer i, j, k, d
      double precision dx(dim), rr, f, rr0, dd, p1, p2

      do 10 i = 1, ntotal
        do 5 d = 1, dim
          dvxdt(d,i) = 0.
    5   continue
{g}   10 continue

      rr0 = {rr0}
      dd = {dd}
      p1 = 12
      p2 = 4
      do 40 k = 1, niac
        i = pair_i(k)
        j = pair_j(k)
        if (itype(i) .gt. 0 .and. itype(j) .lt. 0) then
          rr = 0.
          do 30 d = 1, dim
            dx(d) = x(d,i) - x(d,j)
            rr = rr + dx(d)*dx(d)
   30     continue
          rr = sqrt(rr)
          if (rr .lt. rr0) then
            f = ((rr0/rr)**p1 - (rr0/rr)**p2)/rr**2
            do 35 d = 1, dim
              dvxdt(d,i) = dvxdt(d,i) + dd*dx(d)*f
   35       continue
          endif
        endif
   40 continue

      end
"
    )
}

/// Declares every vector of the fixture copy in `dir` with a leading extent `mxd` = 3 in place
/// of `dim` (`x(mxd,maxn)`, as 2D codes write `x(maxdim,maxn)`): param.inc gains `mxd`, each
/// source's `(dim,` becomes `(mxd,`. Returns the number of files changed.
pub fn with_mxd_layout(dir: &Path) -> usize {
    let mut changed = 0;
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        let text = std::fs::read_to_string(&p).unwrap();
        let new = if p.file_name().is_some_and(|f| f == "param.inc") {
            text.replacen(
                "      parameter (dim = 1)\n",
                "      parameter (dim = 1)\n      integer mxd\n      parameter (mxd = 3)\n",
                1,
            )
        } else if p.extension().is_some_and(|x| x == "f") {
            text.replace("(dim,", "(mxd,")
        } else {
            continue;
        };
        changed += (new != text) as usize;
        std::fs::write(&p, new).unwrap();
    }
    changed
}
