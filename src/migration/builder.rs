//! `blastsph legacy build MANIFEST --out DIR`: compiles a user's legacy sources, unmodified, with
//! generated shims into one shared library, and records what it built in `DIR/build.json`.
//!
//! Steps: read the manifest; evaluate `dim`, `maxn`, `max_interaction` by compiling and running a
//! probe program that includes the user's `param.inc` or uses the module of the sizes (gfortran
//! evaluates it, whatever its expressions); compile every source to an object (`-std=legacy` for fixed form, `-fPIC -O2
//! -ffp-contract=off`, then the manifest's `fflags`), reading the C prototypes of its external
//! procedures from the same compile (`-fc-prototypes-external`) to check that each mapped routine
//! exists and takes the manifest's number and types of arguments; generate and compile the shims;
//! link `DIR/liblegacy.so` (`-Wl,--no-undefined`, `-Wl,-Bsymbolic`) from every object that is not a
//! main program; link the main program, if the sources have one, with the same objects into
//! `DIR/program` (the user's own executable, built with the same flags, for comparisons).
//! Every compiler command and its output go to `DIR/build.log`. A problem is one line naming it
//! and the log, an input error (exit status 2).

use super::manifest::{self, FIXED_FORM, Manifest};
use super::shim::{self, Sizes};
use super::vocab::{Base, CallMode, Kind, Shape};
use crate::error::{Result, SphError, input};
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

mod check;
mod host;
mod modproc;
mod probe;
mod text;

pub use host::{HOOK_SYMBOL, HOST_LIBRARY};

use text::*;

/// The flags every object gets, for parity with blastsph's own Fortran core (build.rs):
/// `-ffp-contract=off` keeps `a*b + c` two roundings on FMA hardware; no `-ffast-math` (no
/// reassociation), no `-march=native` (results must not depend on the build machine).
pub const BASE_FLAGS: &[&str] = &["-fPIC", "-O2", "-ffp-contract=off"];
/// Added for fixed-form sources: accepts the legacy dialect (argument mismatches between
/// routines, tabs, old extensions) as gfortran did before version 10.
pub const FIXED_FLAGS: &[&str] = &["-std=legacy"];
/// Link flags of the library: every symbol resolved at build time; the library's own routines
/// call each other, never a same-named symbol of the program that loads it.
pub const LINK_FLAGS: &[&str] = &["-shared", "-Wl,--no-undefined", "-Wl,-Bsymbolic"];
/// The library's file name in the build folder.
pub const LIBRARY: &str = "liblegacy.so";
/// The manifest of the build folder.
pub const BUILD_JSON: &str = "build.json";
pub const BUILD_LOG: &str = "build.log";

/// One argument of a mapped routine, as built.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ArgInfo {
    /// Vocabulary name.
    pub name: String,
    /// The name as the manifest wrote it (an alias, maybe).
    pub written: String,
    /// The dummy argument's name in the user's source.
    pub dummy: String,
    pub kind: Kind,
    /// Shape in the routine's own call: for per-particle and per-pair calls, `scalar` or a
    /// `dim`-vector (`particle_vec`) of one particle or pair.
    pub shape: Shape,
    pub unit: String,
    /// The declared leading extent of a whole array of vectors when it is not `dim`
    /// (`x(maxdim,maxn)`, maxdim = 3 in a 2D code): the shims and host mode lay each particle's
    /// or pair's `dim` values out `lead` apart.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lead: Option<usize>,
    /// An integer of the vocabulary (a count, an index, a type code) that the routine declares
    /// double precision: the shims and host mode convert it, exactly, both ways.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub real: bool,
    /// A dummy bound to a value of the manifest's `values` (a switch, a logical, a constant):
    /// the Fortran type and literal the shim passes at every call.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub value: Option<(String, String)>,
}

/// One value blastsph passes to a shim (`ptrs[k]`, `sizes[k]`).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct BindingInfo {
    pub name: String,
    pub kind: Kind,
    pub shape: Shape,
    pub base: Base,
    pub unit: String,
}

/// One mapped routine, as built.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct RoutineInfo {
    pub name: String,
    /// The routine's linker symbol (gfortran's: `name_`; `__module_MOD_name` in a module).
    pub symbol: String,
    /// The module that holds the routine (the shims `use` it); None: an external procedure.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub module: Option<String>,
    /// The shim's C symbol.
    pub shim: String,
    pub modules: Vec<String>,
    pub call: CallMode,
    /// The source file that defines it.
    pub file: String,
    pub args: Vec<ArgInfo>,
    pub bindings: Vec<BindingInfo>,
    /// Its variables in COMMON blocks or modules (bound as `bindings` are; copied in before
    /// the call and back after).
    #[serde(default)]
    pub globals: Vec<GlobalInfo>,
    /// `virt_part` only: "held" or "integrated", the kind of the boundary particles it makes.
    #[serde(default)]
    pub virtual_kind: Option<String>,
    /// The arrays it adds into (the manifest's `adds`): zeroed by the shim before each call.
    #[serde(default)]
    pub adds: Vec<String>,
}

/// A routine's global variable, as built.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct GlobalInfo {
    /// Vocabulary name.
    pub name: String,
    /// The variable's name in the legacy code.
    pub var: String,
    /// Where it is declared: `include 'common.inc'` or `module particles`.
    pub from: String,
}

/// One source file, as built.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct SourceInfo {
    pub path: String,
    pub object: String,
    /// Holds a main program (linked into `program`, not into the library).
    pub program_unit: bool,
    /// External procedures it defines.
    pub procedures: Vec<String>,
}

/// The flags of each kind of compile.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Flags {
    pub fixed_form: Vec<String>,
    pub free_form: Vec<String>,
    pub shims: Vec<String>,
    pub link: Vec<String>,
}

/// `DIR/build.json`: what a build made.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct BuildInfo {
    pub format: u32,
    pub manifest: String,
    pub library: String,
    /// The user's own main program, built with the same objects and flags (`null` when the
    /// sources have none, or it did not link: `program_note` says why).
    pub program: Option<String>,
    pub program_note: Option<String>,
    pub dim: usize,
    pub maxn: usize,
    pub max_interaction: usize,
    pub param_include: String,
    pub compiler: String,
    pub flags: Flags,
    pub sources: Vec<SourceInfo>,
    pub routines: Vec<RoutineInfo>,
    /// The manifest's `[itype]` table: the code's type code of each material, by material name
    /// or EOS kind (empty: the book's codes, ideal gas 1, water 2).
    #[serde(default)]
    pub itype: std::collections::BTreeMap<String, i32>,
    /// The manifest's `run_dirs`: folders made inside `DIR/work` before the routines run.
    #[serde(default)]
    pub run_dirs: Vec<String>,
    /// The manifest's `density_clamp`: the bounds the code clamps ρ to (kg/m³), the case's
    /// `sph.density_clamp` under `--legacy`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density_clamp: Option<[f64; 2]>,
    /// The manifest's routine that `includes_gravity`: the case's `physics.gravity_in_forces` is
    /// set under `--legacy`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gravity_in: Option<String>,
    /// What the build noticed and let through (`legacy build` prints them): a dummy argument
    /// named as another argument of the manifest's list (swapped arguments?).
    #[serde(default)]
    pub warnings: Vec<String>,
    /// The host program (`libhost.so`: the main program with every mapped routine interposed,
    /// run by `blastsph legacy host`), or `null` and `host_note` saying why there is none.
    #[serde(default)]
    pub host: Option<String>,
    #[serde(default)]
    pub host_note: Option<String>,
    /// The mapped routines the host program cannot interpose, one line each with why.
    #[serde(default)]
    pub host_refused: Vec<String>,
}

impl BuildInfo {
    /// The file name of the include that sets the sizes (param.inc, or the manifest's
    /// `param_include`), for messages.
    pub fn include_name(&self) -> String {
        Path::new(&self.param_include)
            .file_name()
            .map_or(self.param_include.clone(), |f| f.to_string_lossy().into_owned())
    }

    /// Reads `DIR/build.json`.
    pub fn read(dir: &Path) -> Result<BuildInfo> {
        let p = dir.join(BUILD_JSON);
        let text = std::fs::read_to_string(&p).map_err(|e| {
            input(format!("{}: {e} (not a legacy build folder: run `blastsph legacy build`)", p.display()))
        })?;
        serde_json::from_str(&text).map_err(|e| input(format!("{}: {e}", p.display())))
    }
    pub fn routine(&self, name: &str) -> Option<&RoutineInfo> {
        let n = name.to_ascii_lowercase();
        self.routines.iter().find(|r| r.name == n)
    }
    /// [`manifest::check_capacity`] against this build's sizes.
    pub fn check_capacity(&self, particles: usize, pairs: Option<usize>) -> Result<()> {
        manifest::check_capacity(self.maxn, self.max_interaction, particles, pairs, &self.include_name())
    }
}

/// The build log: every command with its output.
struct Log {
    path: PathBuf,
    text: String,
}

impl Log {
    fn flush(&self) {
        let _ = std::fs::write(&self.path, &self.text);
    }
    /// Runs a command, logs it; returns (success, stdout, stderr).
    fn run(&mut self, cmd: &mut Command) -> Result<(bool, String, String)> {
        let shown = format!(
            "{} {}",
            cmd.get_program().to_string_lossy(),
            cmd.get_args().map(|a| a.to_string_lossy().into_owned()).collect::<Vec<_>>().join(" ")
        );
        let _ = writeln!(self.text, "$ {shown}");
        let out = match cmd.output() {
            Ok(o) => o,
            Err(e) => {
                self.flush();
                return Err(input(format!(
                    "legacy build: cannot run {}: {e} (is gfortran installed? scripts/setup)",
                    cmd.get_program().to_string_lossy()
                )));
            }
        };
        let so = String::from_utf8_lossy(&out.stdout).into_owned();
        let se = String::from_utf8_lossy(&out.stderr).into_owned();
        if !se.is_empty() {
            self.text.push_str(&se);
            if !se.ends_with('\n') {
                self.text.push('\n');
            }
        }
        let _ = writeln!(self.text, "[exit {}]\n", out.status.code().map_or("signal".into(), |c| c.to_string()));
        self.flush();
        Ok((out.status.success(), so, se))
    }
}

/// The first error in gfortran's or the linker's output, as one line (`file:line:col: Error: ...`).
pub fn first_error(stderr: &str) -> String {
    let lines: Vec<&str> = stderr.lines().collect();
    for (k, l) in lines.iter().enumerate() {
        let t = l.trim_start();
        if t.starts_with("Error:") || t.starts_with("Fatal Error:") {
            // the location is the last `file:line:col:` line above it
            let loc = lines[..k].iter().rev().find(|p| {
                let p = p.trim_end();
                p.ends_with(':') && p.matches(':').count() >= 3 && !p.starts_with(' ')
            });
            return match loc {
                Some(p) => format!("{} {}", p.trim_end(), t),
                None => t.to_string(),
            };
        }
        if t.contains("undefined reference to") || t.contains("multiple definition of") {
            return t.to_string();
        }
    }
    lines.iter().rev().find(|l| !l.trim().is_empty()).map(|l| l.trim().to_string()).unwrap_or_default()
}

fn rel(p: &Path, base: &Path) -> String {
    p.strip_prefix(base).unwrap_or(p).display().to_string()
}

/// Builds the manifest's code into `out`; returns what was built (also in `out/build.json`).
pub fn build(manifest_path: &Path, out: &Path) -> Result<BuildInfo> {
    let m = manifest::load(manifest_path)?;
    let out = prepare_out(&m, out)?;
    let obj = out.join("obj");
    let mut log = Log { path: out.join(BUILD_LOG), text: String::new() };
    let _ = writeln!(log.text, "blastsph legacy build {} --out {}\n", m.path.display(), out.display());
    log.flush();
    let logp = log.path.display().to_string();
    let fail = |what: String| input(format!("legacy build: {what} (log: {logp})"));

    // the compiler
    let (ok, so, _) = log.run(Command::new("gfortran").arg("--version"))?;
    if !ok {
        return Err(fail("gfortran --version failed".into()));
    }
    let compiler = so.lines().next().unwrap_or("gfortran").trim().to_string();

    let incs: Vec<String> = m.include_dirs.iter().map(|d| format!("-I{}", d.display())).collect();
    let fixed: Vec<String> =
        BASE_FLAGS.iter().chain(FIXED_FLAGS).map(|s| s.to_string()).chain(m.fflags.clone()).collect();
    let free: Vec<String> = BASE_FLAGS.iter().map(|s| s.to_string()).chain(m.fflags.clone()).collect();

    // the sizes (the sources compiled first when they are in a module or need one)
    let fl = probe::Flags { fixed: &fixed, free: &free, incs: &incs };
    let found = probe::sizes(&m, &obj, &fl, &mut log, &fail)?;
    let (sizes, inc) = (found.sizes, found.file);
    if sizes.dim != m.dim {
        return Err(input(format!(
            "{}: dim = {} but {} says {} = {}",
            m.path.display(),
            m.dim,
            inc.display(),
            m.param_names.dim,
            sizes.dim
        )));
    }

    // compile the sources (module dependencies: retry what needs a module another file makes)
    let (objects, mut protos) = match found.compiled {
        Some(c) => c,
        None => compile_sources(&m, &obj, (&fixed, &free), &incs, &mut log, &fail)?,
    };
    // the mapped routines that are module procedures: their prototypes from gfortran's dump
    modproc::add(&m, &obj, &fl, &objects, &mut protos, &mut log, &fail)?;

    // main programs: an object that defines `main`
    let mut is_program = vec![false; m.sources.len()];
    for (k, o) in objects.iter().enumerate() {
        let (ok, so, _) = log.run(Command::new("nm").arg("--defined-only").arg(o))?;
        is_program[k] = ok && so.lines().any(|l| l.split_whitespace().collect::<Vec<_>>().ends_with(&["T", "main"]));
    }

    // each mapped routine: defined once, with the manifest's arguments
    let global_texts = GlobalTexts::read(&m)?;
    let mut copies: Vec<(String, &'static str, shim::GlobalCopy)> = Vec::new();
    let mut routines = Vec::new();
    let mut warnings = Vec::new();
    for r in &m.routines {
        let (info, c, w) = check::routine(&m, r, &protos, &is_program, sizes, &global_texts, routines.len())?;
        copies.extend(c);
        warnings.extend(w);
        routines.push(info);
    }

    // the globals' copy routines: fixed form first (the include files of old codes), else free
    let extra_objs = build_globals(&m, &copies, &obj, (&fixed, &free), &incs, &mut log, &fail)?;

    // the shims
    let shim_flags: Vec<String> = free.clone();
    // the shims lay out each argument as the routine declares it (its leading extent)
    let mut laid = m.routines.clone();
    for (r, info) in laid.iter_mut().zip(&routines) {
        for (a, ai) in r.args.iter_mut().zip(info.args.iter().filter(|ai| ai.value.is_none())) {
            a.lead = ai.lead;
            a.real = ai.real;
        }
        for c in r.values.iter_mut() {
            c.fortran = info.args.get(c.pos).and_then(|ai| ai.value.clone());
        }
    }
    let hosts: Vec<Option<String>> = routines.iter().map(|r| r.module.clone()).collect();
    let shim_text = shim::source(&laid, &hosts, sizes, &m.path.display().to_string());
    let shim_obj = compile_generated(&mut log, &obj, "blastsph_shims", &shim_text, &shim_flags)?
        .map_err(|e| fail(format!("the generated shims do not compile: {e}")))?;

    // the library
    let lib = out.join(LIBRARY);
    let lib_objs: Vec<&PathBuf> = objects.iter().zip(&is_program).filter(|(_, p)| !**p).map(|(o, _)| o).collect();
    let link: Vec<String> = LINK_FLAGS.iter().map(|s| s.to_string()).collect();
    let (ok, _, se) = log.run(
        Command::new("gfortran")
            .args(&link)
            .args(&free)
            .arg("-o")
            .arg(&lib)
            .args(&lib_objs)
            .args(&extra_objs)
            .arg(&shim_obj),
    )?;
    if !ok {
        return Err(fail(format!("the library does not link: {}", first_error(&se))));
    }

    // the user's own program, if the sources have one
    let (program, program_note) = link_program(&out, &free, &objects, &is_program, &mut log)?;
    // (a host program that cannot be made leaves the library and `program` as they are)
    let host = host::link_host(&out, &free, &objects, &is_program, &routines, &mut log)
        .unwrap_or_else(|e| host::Host { library: None, note: Some(e.to_string()), refused: Vec::new() });

    let info = BuildInfo {
        format: 1,
        manifest: m.path.display().to_string(),
        library: LIBRARY.to_string(),
        program,
        program_note,
        dim: sizes.dim,
        maxn: sizes.maxn,
        max_interaction: sizes.max_interaction,
        param_include: inc.display().to_string(),
        compiler,
        flags: Flags { fixed_form: fixed, free_form: free, shims: shim_flags, link },
        sources: m
            .sources
            .iter()
            .enumerate()
            .map(|(k, s)| SourceInfo {
                path: s.display().to_string(),
                object: rel(&objects[k], &out),
                program_unit: is_program[k],
                procedures: protos[k].iter().filter(|p| p.module.is_none()).map(|p| p.name.clone()).collect(),
            })
            .collect(),
        routines,
        itype: m.itype.clone(),
        run_dirs: m.run_dirs.clone(),
        density_clamp: m.density_clamp,
        gravity_in: m.gravity_in.clone(),
        warnings,
        host: host.library,
        host_note: host.note,
        host_refused: host.refused,
    };
    let jp = out.join(BUILD_JSON);
    std::fs::write(&jp, serde_json::to_string_pretty(&info).unwrap_or_default())
        .map_err(|e| SphError::Io(format!("{}: {e}", jp.display())))?;
    Ok(info)
}

/// Makes build folder `out` (refused if it is the folder of the sources or the manifest), its
/// `obj/mod`, and removes what an earlier build left; the folder's absolute path.
fn prepare_out(m: &Manifest, out: &Path) -> Result<PathBuf> {
    // never write beside the user's sources
    let out_abs: PathBuf = std::path::absolute(out).map_err(|e| SphError::Io(format!("{}: {e}", out.display())))?;
    let out_abs: PathBuf = out_abs.components().collect();
    if out_abs == m.dir || m.sources.iter().any(|s| s.parent() == Some(out_abs.as_path())) {
        return Err(input(format!(
            "legacy build: --out {}: the folder of the sources or the manifest; give a build folder of its own",
            out.display()
        )));
    }
    std::fs::create_dir_all(out).map_err(|e| SphError::Io(format!("{}: {e}", out.display())))?;
    let out = std::path::absolute(out).map_err(|e| SphError::Io(format!("{}: {e}", out.display())))?;
    let obj = out.join("obj");
    // an earlier build's module files would let a source compile against old values before
    // the file that defines its module is compiled again
    let _ = std::fs::remove_dir_all(obj.join("mod"));
    std::fs::create_dir_all(obj.join("mod")).map_err(|e| SphError::Io(format!("{}: {e}", obj.display())))?;
    let _ = std::fs::remove_file(out.join(BUILD_JSON));
    let _ = std::fs::remove_file(out.join(LIBRARY));
    let _ = std::fs::remove_file(out.join("program"));
    Ok(out)
}

/// Compiles every source into `obj`, retrying what needs a module another file makes: the
/// objects and the prototypes gfortran printed for each.
fn compile_sources(
    m: &Manifest,
    obj: &Path,
    flags: (&[String], &[String]),
    incs: &[String],
    log: &mut Log,
    fail: &dyn Fn(String) -> SphError,
) -> Result<(Vec<PathBuf>, Vec<Vec<Proto>>)> {
    let (fixed, free) = flags;
    let mut pending: Vec<usize> = (0..m.sources.len()).collect();
    let mut protos: Vec<Vec<Proto>> = vec![Vec::new(); m.sources.len()];
    let objects: Vec<PathBuf> = m
        .sources
        .iter()
        .enumerate()
        .map(|(k, s)| obj.join(format!("{k:03}_{}.o", s.file_stem().map(|x| x.to_string_lossy()).unwrap_or_default())))
        .collect();
    while !pending.is_empty() {
        let mut next = Vec::new();
        let mut last_err: Option<(usize, String)> = None;
        for &k in &pending {
            let src = &m.sources[k];
            let ext = src.extension().and_then(|e| e.to_str()).unwrap_or("");
            let flags = if FIXED_FORM.contains(&ext) { fixed } else { free };
            let mut cmd = Command::new("gfortran");
            cmd.arg("-c").arg("-fc-prototypes-external").args(flags).args(incs);
            cmd.arg(format!("-J{}", obj.join("mod").display())).arg("-o").arg(&objects[k]).arg(src);
            let (ok, so, se) = log.run(&mut cmd)?;
            if ok {
                protos[k] = parse_protos(&so);
            } else if se.contains("Cannot open module file") {
                next.push(k);
                last_err = Some((k, first_error(&se)));
            } else {
                return Err(fail(format!("{}: compile error: {}", rel(src, &m.dir), first_error(&se))));
            }
        }
        if next.len() == pending.len() {
            let (k, e) = last_err.unwrap_or((next[0], String::new()));
            return Err(fail(format!("{}: compile error: {e}", rel(&m.sources[k], &m.dir))));
        }
        pending = next;
    }
    Ok((objects, protos))
}

/// Compiles the generated copy module and the globals' copy routines: their objects (none when
/// no routine binds a global).
fn build_globals(
    m: &Manifest,
    copies: &[(String, &'static str, shim::GlobalCopy)],
    obj: &Path,
    flags: (&[String], &[String]),
    incs: &[String],
    log: &mut Log,
    fail: &dyn Fn(String) -> SphError,
) -> Result<Vec<PathBuf>> {
    let (fixed, free) = flags;
    let mut extra_objs: Vec<PathBuf> = Vec::new();
    if !copies.is_empty() {
        let gobj = compile_generated(log, obj, "bs9_gcopy", &shim::gcopy_source(), free)?
            .map_err(|e| fail(format!("the generated copy module does not compile: {e}")))?;
        extra_objs.push(gobj);
        let items: Vec<shim::GlobalCopy> = copies.iter().map(|(_, _, c)| c.clone()).collect();
        // which attempt's error to report: the free form's when every include is a free-form file
        let all_free = !m.global_includes.is_empty()
            && m.global_includes
                .iter()
                .all(|(_, p)| p.extension().and_then(|e| e.to_str()).is_some_and(|e| manifest::FREE_FORM.contains(&e)));
        let mut errors = Vec::new();
        let mut built = None;
        for fixed_try in [true, false] {
            let (text, spans) = shim::globals_source(&items, fixed_try);
            let src = obj.join(if fixed_try { "blastsph_globals.f" } else { "blastsph_globals.f90" });
            std::fs::write(&src, text).map_err(|e| SphError::Io(format!("{}: {e}", src.display())))?;
            let o = obj.join("blastsph_globals.o");
            let (ok, _, se) = log.run(
                Command::new("gfortran")
                    .arg("-c")
                    .args(if fixed_try { fixed } else { free })
                    .args(incs)
                    .arg(format!("-I{}", m.dir.display()))
                    .arg(format!("-J{}", obj.join("mod").display()))
                    .arg("-o")
                    .arg(&o)
                    .arg(&src),
            )?;
            if ok {
                built = Some(o);
                break;
            }
            // the global whose copy routine the first error is in
            let file = src.file_name().and_then(|f| f.to_str()).unwrap_or_default().to_string();
            let line = se.lines().find_map(|l| {
                let rest = l.split_once(&format!("{file}:"))?.1;
                rest.split(':').next()?.parse::<usize>().ok()
            });
            let which = line.and_then(|n| spans.iter().position(|(a, b)| (*a..=*b).contains(&n)));
            let e = first_error(&se);
            errors.push(match which {
                Some(q) => {
                    let (rname, vname, c) = &copies[q];
                    format!(
                        "routine {rname}: global `{}` (\"{vname}\", {}) from {}: {e}",
                        c.var,
                        c.kind.described(),
                        c.site
                    )
                }
                None => e,
            });
        }
        let Some(o) = built else {
            let e = if all_free { errors.pop() } else { errors.into_iter().next() };
            return Err(fail(format!("the globals' copy routines do not compile: {}", e.unwrap_or_default())));
        };
        extra_objs.push(o);
    }
    Ok(extra_objs)
}

/// Links the user's own main program into `out/program` when the sources hold exactly one: its
/// name in `out`, or why there is none.
fn link_program(
    out: &Path,
    free: &[String],
    objects: &[PathBuf],
    is_program: &[bool],
    log: &mut Log,
) -> Result<(Option<String>, Option<String>)> {
    let (program, program_note) = match is_program.iter().filter(|p| **p).count() {
        0 => (None, Some("the sources hold no main program".to_string())),
        1 => {
            let exe = out.join("program");
            let (ok, _, se) = log.run(Command::new("gfortran").args(free).arg("-o").arg(&exe).args(objects))?;
            if ok {
                (Some("program".to_string()), None)
            } else {
                (None, Some(format!("the main program does not link: {}", first_error(&se))))
            }
        }
        n => (None, Some(format!("the sources hold {n} main programs: none linked"))),
    };
    Ok((program, program_note))
}

/// Writes the generated free-form source `text` to `obj/<name>.f90` and compiles it with
/// `flags` into `obj/<name>.o` (its module files into `obj/mod`): the object, or gfortran's
/// first error.
fn compile_generated(
    log: &mut Log,
    obj: &Path,
    name: &str,
    text: &str,
    flags: &[String],
) -> Result<std::result::Result<PathBuf, String>> {
    let src = obj.join(format!("{name}.f90"));
    std::fs::write(&src, text).map_err(|e| SphError::Io(format!("{}: {e}", src.display())))?;
    let o = obj.join(format!("{name}.o"));
    let (ok, _, se) = log.run(
        Command::new("gfortran")
            .arg("-c")
            .args(flags)
            .arg(format!("-J{}", obj.join("mod").display()))
            .arg("-o")
            .arg(&o)
            .arg(&src),
    )?;
    Ok(if ok { Ok(o) } else { Err(first_error(&se)) })
}
