//! The legacy manifest (`legacy.toml`): where a user's unmodified legacy code is, how to compile
//! it, and which of its routines stand for which blastsph modules, with their arguments named in
//! the vocabulary of [`super::vocab`].
//!
//! ```toml
//! dim = 1                        # the compile-time dimension of this build (param.inc's dim)
//! sources = ["src/*.f"]          # globs relative to this file: .f .for .f77 .F .f90 .F90
//! # exclude = ["src/time_print.f"] # files the globs match that are not to be compiled
//! include_dirs = ["src"]         # where param.inc and the other includes are
//! fflags = ["-finit-local-zero"] # extra gfortran flags
//! # param_include = "param.inc"  # the include file that defines the three parameters below
//! # param_module = "parameter"   # or: the module of the sources that defines them
//! # [param_names]                # their names there (or integer expressions of them)
//! # maxn = "nmax"
//!
//! [[routine]]
//! name = "art_visc"              # the subroutine, as written in the sources
//! module = "viscosity"           # blastsph module(s) it stands for: "eos,force"; "init" for a
//!                                # routine that fills COMMON blocks, called once before the rest
//! args = ["ntotal", "hsml", ...] # one vocabulary name per dummy argument, in order
//! # call = "each_particle"       # or "each_pair"; whole arrays by default
//! # globals = { dens = "rho" }   # variables in COMMON blocks or modules: legacy name → vocabulary
//! ```
//!
//! `density_clamp`, `includes_gravity` and `adds` ([`super::adds`]) are told at their fields.
//! `globals` need, at the top, `global_includes = ["common.inc"]` (the include files that
//! declare their COMMON blocks) or `global_modules = ["particles"]` (modules of the sources).
//!
//! Every problem is one line naming the file and the key, an input error (exit status 2).

use super::vocab::{self, CallMode, Shape, Term};
use crate::error::{Result, SphError, input};
use serde::Deserialize;
use std::path::{Path, PathBuf};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawManifest {
    dim: i64,
    sources: Vec<String>,
    /// Files the `sources` globs match that are not to be compiled (a timing routine that
    /// needs another compiler's module, say); globs relative to the manifest.
    #[serde(default)]
    exclude: Vec<String>,
    #[serde(default)]
    include_dirs: Vec<String>,
    #[serde(default)]
    fflags: Vec<String>,
    #[serde(default)]
    param_include: Option<String>,
    /// A module of the sources that defines the sizes (the probe `use`s it).
    #[serde(default)]
    param_module: Option<String>,
    #[serde(default)]
    param_names: Option<RawParamNames>,
    #[serde(default, rename = "routine")]
    routines: Vec<RawRoutine>,
    #[serde(default)]
    itype: std::collections::BTreeMap<String, i32>,
    #[serde(default)]
    run_dirs: Vec<String>,
    /// Include files that declare the COMMON blocks the routines' `globals` live in.
    #[serde(default)]
    global_includes: Vec<String>,
    /// Fortran modules of the sources whose variables the routines' `globals` are.
    #[serde(default)]
    global_modules: Vec<String>,
    /// The bounds the code clamps ρ to after each density update (kg/m³).
    #[serde(default)]
    density_clamp: Option<Vec<f64>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawParamNames {
    dim: Option<String>,
    maxn: Option<String>,
    max_interaction: Option<String>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRoutine {
    name: String,
    module: String,
    /// Absent: the routine has no arguments (its variables are `globals`, or it takes none).
    #[serde(default)]
    args: Vec<String>,
    #[serde(default)]
    call: Option<String>,
    /// The routine's variables that are not arguments (in a COMMON block of `global_includes`, or
    /// of a module of `global_modules`): legacy name → vocabulary name.
    #[serde(default)]
    globals: std::collections::BTreeMap<String, String>,
    /// Dummies blastsph has no name for (switches, logicals, constants): the name as `args`
    /// writes it → the value passed at every call.
    #[serde(default)]
    values: std::collections::BTreeMap<String, toml::Value>,
    /// The routine adds gravity to its acceleration (the book's `ext_force`).
    #[serde(default)]
    includes_gravity: bool,
    /// `virt_part` only: the kind of boundary particle it makes, "held" (the default) or
    /// "integrated".
    #[serde(default, rename = "virtual")]
    virtual_kind: Option<String>,
    /// The arrays it adds into without zeroing them (vocabulary names): zeroed before each call.
    #[serde(default)]
    adds: Vec<String>,
}

/// The names of the three compile-time parameters in the user's include file, or integer
/// expressions of its parameters (`100*nmax`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParamNames {
    pub dim: String,
    pub maxn: String,
    pub max_interaction: String,
}

/// The value of a dummy argument bound in the manifest's `values`.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Int(i64),
    Real(f64),
    Logical(bool),
}

/// A dummy argument bound to a value (`values = { skf = 1, visc = true }`), not to a vocabulary
/// name: the shim passes the value at every call.
#[derive(Debug, Clone, PartialEq)]
pub struct Constant {
    /// Its position in the routine's argument list (0-based).
    pub pos: usize,
    /// As `args` writes it, lower case.
    pub name: String,
    pub value: Value,
    /// The Fortran type and literal the shim declares it with, found by `legacy build` from the
    /// dummy's type (`None` in a manifest as read).
    pub fortran: Option<(String, String)>,
}

/// One argument of a routine: the name as the manifest writes it and the term it stands for.
#[derive(Debug, Clone)]
pub struct Arg {
    pub written: String,
    pub term: &'static Term,
    /// Found by `legacy build` from the routine's declaration: the leading extent of a whole
    /// array of vectors when it is not `dim`; an integer of the vocabulary declared double (`real`).
    pub lead: Option<usize>,
    pub real: bool,
}

/// A variable a routine reads or writes that is not one of its arguments: a member of a COMMON
/// block (declared in one of the manifest's `global_includes`) or a variable of a Fortran module
/// (one of `global_modules`). The shim copies blastsph's array into it before the call and back
/// after, as it does its argument buffers.
#[derive(Debug, Clone)]
pub struct Global {
    /// The variable's name in the legacy code, lower case.
    pub var: String,
    pub term: &'static Term,
}

/// One mapped routine.
#[derive(Debug, Clone)]
pub struct Routine {
    /// Lower case, as Fortran sees it.
    pub name: String,
    pub modules: Vec<String>,
    pub call: CallMode,
    pub args: Vec<Arg>,
    /// Its variables in COMMON blocks or modules (whole-array calls only), in the manifest's
    /// order of their legacy names.
    pub globals: Vec<Global>,
    /// Its dummies bound to values (`values`), not among `args`.
    pub values: Vec<Constant>,
    /// `virt_part` only: "held" or "integrated", the kind of the boundary particles it makes.
    pub virtual_kind: Option<String>,
    /// The arrays it adds into (`adds`, canonical names): the shim zeroes them before each call.
    pub adds: Vec<&'static str>,
}

/// What blastsph passes to a routine's shim, in order: a vocabulary name with its whole-array shape.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Binding {
    pub term: &'static Term,
}

impl Routine {
    /// The arrays and scalars blastsph hands the shim, in the order of the pointer array.
    /// Whole-array calls: the manifest's arguments. `each_particle`: `ntotal`, then the
    /// arguments. `each_pair`: `niac`, `pair_i`, `pair_j`, then the sources of the arguments
    /// (`r` and `dx` come from `x`, the pair's `hsml` from `hsml`), each once.
    pub fn bindings(&self) -> Vec<&'static Term> {
        let mut out: Vec<&'static Term> = Vec::new();
        let mut push = |t: &'static Term| {
            if !out.iter().any(|o| o.name == t.name) {
                out.push(t);
            }
        };
        let whole = |n: &str| vocab::lookup(n).expect("vocabulary name");
        match self.call {
            CallMode::Whole => {
                self.args.iter().for_each(|a| push(a.term));
                self.globals.iter().for_each(|g| push(g.term));
            }
            CallMode::EachParticle => {
                push(whole("ntotal"));
                self.args.iter().for_each(|a| push(a.term));
            }
            CallMode::EachPair => {
                for n in ["niac", "pair_i", "pair_j"] {
                    push(whole(n));
                }
                for a in &self.args {
                    match a.term.name {
                        "r" | "dx" => push(whole("x")),
                        "hsml" => push(whole("hsml")),
                        "w" => push(whole("w")),
                        "dwdx" => push(whole("dwdx")),
                        _ => push(a.term),
                    }
                }
            }
        }
        out
    }
}

/// A checked manifest. Paths are absolute.
#[derive(Debug, Clone)]
pub struct Manifest {
    pub path: PathBuf,
    pub dir: PathBuf,
    pub dim: usize,
    /// The files the globs matched, in a stable order (sorted by path), each once.
    pub sources: Vec<PathBuf>,
    pub include_dirs: Vec<PathBuf>,
    pub fflags: Vec<String>,
    /// The include file of the sizes; empty when `param_module` alone gives them.
    pub param_include: String,
    /// The module of the sources that defines the sizes, lower case.
    pub param_module: Option<String>,
    pub param_names: ParamNames,
    pub routines: Vec<Routine>,
    /// The code's `itype` of each blastsph material, by material name or EOS kind
    /// (`ideal_gas`, `jwl`, `water`, `soil`); default: the book's, ideal gas 1, water 2.
    pub itype: std::collections::BTreeMap<String, i32>,
    /// Folders made inside the folder the routines run in (`DIR/work`) before they run: the
    /// folders your code opens files in, relative to where your program runs (the book's
    /// `input` and `output` open `./TEST/data/...`).
    pub run_dirs: Vec<String>,
    /// The include files of the routines' globals: the name as an `include` line writes it, and
    /// the file found (in `include_dirs`, else beside the manifest).
    pub global_includes: Vec<(String, PathBuf)>,
    /// The modules of the routines' globals, lower case.
    pub global_modules: Vec<String>,
    /// The bounds the code clamps ρ to after each density update, lo < hi (kg/m³): the case's
    /// `sph.density_clamp` under `--legacy`.
    pub density_clamp: Option<[f64; 2]>,
    /// The routine (lower case) whose acceleration includes gravity (`includes_gravity = true`):
    /// the case's `physics.gravity_in_forces` under `--legacy`.
    pub gravity_in: Option<String>,
}

/// File endings of Fortran sources; the fixed-form ones get `-std=legacy`.
pub const FIXED_FORM: &[&str] = &["f", "for", "f77", "F", "FOR"];
pub const FREE_FORM: &[&str] = &["f90", "F90", "f95", "f03", "f08"];

/// Flags that would change the arithmetic of the build against blastsph's own core (docs/design.md:
/// no fast-math, no FMA contraction, no -march=native): refused in `fflags`.
pub const REFUSED_FLAGS: &[&str] = &[
    "-ffast-math",
    "-Ofast",
    "-funsafe-math-optimizations",
    "-fassociative-math",
    "-freciprocal-math",
    "-ffinite-math-only",
    "-fno-signed-zeros",
    "-fno-trapping-math",
    "-fcx-limited-range",
    "-ffp-contract=fast",
    "-ffp-contract=on",
    "-march=native",
    "-mtune=native",
    "-mfma",
    "-mfpmath=387",
    "-mfpmath=both",
    "-m80387",
];

/// Why a flag of `fflags` is refused, if it is.
fn refused_flag(f: &str) -> Option<&'static str> {
    if REFUSED_FLAGS.contains(&f) {
        return Some("it changes the arithmetic against blastsph's own core (docs/howto/migrate.md)");
    }
    if f.starts_with("-O") && f != "-O2" {
        return Some("the optimisation level is fixed at -O2, as blastsph's own core is built (docs/howto/migrate.md)");
    }
    if matches!(f, "-shared" | "-c" | "-o" | "-S" | "-E") || f.starts_with("-fsyntax-only") || f.starts_with("-Wl,") {
        return Some("blastsph compiles and links the library itself");
    }
    if f.starts_with("-fsanitize") || f == "-pg" || f.starts_with("-fprofile") || f == "--coverage" {
        return Some(
            "an instrumented library cannot be loaded into blastsph (its runtime must start with the program)",
        );
    }
    None
}

/// A `run_dirs` entry names a folder inside the build: relative to `work`, where the routines
/// run, climbing at most to `work`'s parent (the build folder, `../data`), and not that folder
/// itself.
fn stays_in_build(d: &str) -> bool {
    use std::path::Component;
    let mut depth = 0i32;
    for c in Path::new(d).components() {
        match c {
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
            Component::ParentDir => depth -= 1,
            Component::RootDir | Component::Prefix(_) => return false,
        }
        if depth < -1 {
            return false;
        }
    }
    !d.is_empty() && depth >= 0
}

fn is_ident(s: &str) -> bool {
    let mut ch = s.chars();
    matches!(ch.next(), Some(c) if c.is_ascii_alphabetic()) && ch.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// Whether `s` is a size the probe can write as `parameter (bs_i = s)`: a name, or an integer
/// expression of names and numbers with `+ - * / ( )`, parentheses balanced, at most 100 characters.
fn is_size_expression(s: &str) -> bool {
    let mut depth = 0i32;
    for c in s.chars() {
        match c {
            '(' => depth += 1,
            ')' => depth -= 1,
            c if c.is_ascii_alphanumeric() || "_+-*/ ".contains(c) => {}
            _ => return false,
        }
        if depth < 0 {
            return false;
        }
    }
    depth == 0 && !s.trim().is_empty() && s.len() <= 100
}

/// Reads and checks a manifest; the sources must exist (globs expanded here).
pub fn load(path: &Path) -> Result<Manifest> {
    let shown = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| input(format!("{shown}: cannot read the manifest: {e}")))?;
    let raw: RawManifest = toml::from_str(&text).map_err(|e| {
        let line = e.span().map(|s| text[..s.start.min(text.len())].matches('\n').count() + 1);
        let msg = e.message().replace('\n', " ");
        match line {
            Some(l) => input(format!("{shown}:{l}: {msg}")),
            None => input(format!("{shown}: {msg}")),
        }
    })?;
    let path = std::path::absolute(path).map_err(|e| input(format!("{shown}: {e}")))?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_else(|| PathBuf::from("."));
    let err = |key: &str, msg: String| input(format!("{shown}: {key}: {msg}"));

    let density_clamp = match raw.density_clamp.as_deref() {
        None => None,
        Some(&[lo, hi]) if lo.is_finite() && hi.is_finite() && 0.0 < lo && lo < hi => Some([lo, hi]),
        Some(b) => return Err(err("density_clamp", format!("{b:?} is not two densities 0 < lo < hi (kg/m3)"))),
    };
    if !(1..=3).contains(&raw.dim) {
        return Err(err("dim", format!("{} is not 1, 2 or 3", raw.dim)));
    }
    if raw.sources.is_empty() {
        return Err(err("sources", "no source given".into()));
    }
    let sources = sources_of(&raw, &dir, &err)?;

    let mut include_dirs = Vec::new();
    for d in &raw.include_dirs {
        let p: PathBuf = dir.join(d).components().collect();
        if !p.is_dir() {
            return Err(err("include_dirs", format!("\"{d}\": no such folder ({})", p.display())));
        }
        include_dirs.push(p);
    }

    for f in &raw.fflags {
        if let Some(why) = refused_flag(f) {
            return Err(err("fflags", format!("\"{f}\" is refused: {why}")));
        }
        if !f.starts_with('-') {
            return Err(err("fflags", format!("\"{f}\" is not a compiler flag (flags start with -)")));
        }
    }

    let param_module = match raw.param_module.as_deref().map(|s| s.trim().to_ascii_lowercase()) {
        Some(n) if !is_ident(&n) => {
            return Err(err("param_module", format!("\"{n}\" is not a Fortran module name")));
        }
        other => other,
    };
    let default_include = if param_module.is_some() { "" } else { "param.inc" };
    let param_include = raw.param_include.clone().unwrap_or_else(|| default_include.into());
    let pn = raw.param_names.as_ref();
    let param_names = ParamNames {
        dim: pn.and_then(|p| p.dim.clone()).unwrap_or_else(|| "dim".into()),
        maxn: pn.and_then(|p| p.maxn.clone()).unwrap_or_else(|| "maxn".into()),
        max_interaction: pn.and_then(|p| p.max_interaction.clone()).unwrap_or_else(|| "max_interaction".into()),
    };
    for (k, v) in
        [("dim", &param_names.dim), ("maxn", &param_names.maxn), ("max_interaction", &param_names.max_interaction)]
    {
        if !is_size_expression(v) {
            return Err(err(
                &format!("param_names.{k}"),
                format!("\"{v}\" is not a Fortran name or an integer expression of names and numbers (\"100*nmax\")"),
            ));
        }
    }

    let mut routines: Vec<Routine> = Vec::new();
    for (ix, r) in raw.routines.iter().enumerate() {
        let routine = routine_of(&raw, (ix, r), &routines, &err)?;
        routines.push(routine);
    }

    let gravity_in = gravity_in(&raw, &err)?;

    let mut global_includes = Vec::new();
    for g in &raw.global_includes {
        let name = g.trim();
        if name.is_empty() || name.len() > 50 || name.chars().any(|c| c.is_control() || c == '\'' || c == '"') {
            return Err(err("global_includes", format!("\"{g}\" is not a file name an include line can give")));
        }
        let found =
            include_dirs.iter().map(|d| d.join(name)).chain(std::iter::once(dir.join(name))).find(|p| p.is_file());
        let Some(found) = found else {
            return Err(err(
                "global_includes",
                format!("\"{g}\" is in none of include_dirs (nor beside the manifest)"),
            ));
        };
        global_includes.push((name.to_string(), found));
    }
    let mut global_modules = Vec::new();
    for g in &raw.global_modules {
        let name = g.trim().to_ascii_lowercase();
        if !is_ident(&name) {
            return Err(err("global_modules", format!("\"{g}\" is not a Fortran module name")));
        }
        global_modules.push(name);
    }

    for d in &raw.run_dirs {
        if !stays_in_build(d) {
            return Err(err(
                "run_dirs",
                format!(
                    "\"{d}\": a folder of the build's, relative to where the routines run (`../data` at most one level up)"
                ),
            ));
        }
    }
    Ok(Manifest {
        path,
        dir,
        dim: raw.dim as usize,
        sources,
        include_dirs,
        fflags: raw.fflags.clone(),
        param_include,
        param_module,
        param_names,
        routines,
        itype: raw.itype.clone(),
        run_dirs: raw.run_dirs.clone(),
        global_includes,
        global_modules,
        density_clamp,
        gravity_in,
    })
}

/// The routine that says `includes_gravity = true`, lower case: one at most, mapped to a force
/// stage (`force`, or `boundary` for a wall force such as the book's `ext_force`).
fn gravity_in(raw: &RawManifest, err: &dyn Fn(&str, String) -> SphError) -> Result<Option<String>> {
    let mut found: Option<String> = None;
    for r in raw.routines.iter().filter(|r| r.includes_gravity) {
        let key = format!("routine {}: includes_gravity", r.name);
        if !r.module.split(',').any(|m| matches!(m.trim(), "force" | "boundary")) {
            let why = "only a routine mapped to a force stage (force, boundary) can add gravity";
            return Err(err(&key, format!("module \"{}\": {why}", r.module)));
        }
        if let Some(first) = &found {
            return Err(err(&key, format!("{first} includes it already: gravity is added once")));
        }
        found = Some(r.name.trim().to_ascii_lowercase());
    }
    Ok(found)
}

/// The manifest's sources: the files its patterns match, less those `exclude` matches, sorted.
fn sources_of(raw: &RawManifest, dir: &Path, err: &dyn Fn(&str, String) -> SphError) -> Result<Vec<PathBuf>> {
    let mut excluded = Vec::new();
    for pat in &raw.exclude {
        let full: PathBuf = dir.join(pat).components().collect();
        let paths =
            glob::glob(&full.to_string_lossy()).map_err(|e| err("exclude", format!("\"{pat}\": bad pattern: {e}")))?;
        let before = excluded.len();
        excluded.extend(paths.filter_map(|p| p.ok()));
        if excluded.len() == before {
            return Err(err("exclude", format!("\"{pat}\" matches no file (relative to {})", dir.display())));
        }
    }
    let mut sources = Vec::new();
    for pat in &raw.sources {
        let full: PathBuf = dir.join(pat).components().collect();
        let full_s = full.to_string_lossy().to_string();
        let paths = glob::glob(&full_s).map_err(|e| err("sources", format!("\"{pat}\": bad pattern: {e}")))?;
        let (mut found, mut left_out) = (0, 0);
        for p in paths {
            let p = p.map_err(|e| err("sources", format!("\"{pat}\": {e}")))?;
            if !p.is_file() {
                continue;
            }
            if excluded.contains(&p) {
                left_out += 1;
                continue;
            }
            let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
            if !FIXED_FORM.contains(&ext) && !FREE_FORM.contains(&ext) {
                return Err(err(
                    "sources",
                    format!("{}: not a Fortran source (endings .f .for .f77 .F .f90 .F90)", p.display()),
                ));
            }
            found += 1;
            if !sources.contains(&p) {
                sources.push(p);
            }
        }
        // A pattern whose every file is excluded (the book's `*.f90`: its two dfport timers) is
        // what the user asked for, not a typo.
        if found == 0 && left_out == 0 {
            return Err(err("sources", format!("\"{pat}\" matches no file (relative to {})", dir.display())));
        }
    }
    sources.sort();
    Ok(sources)
}

/// The `ix`-th routine of the manifest, checked (`routines`: those read before it).
fn routine_of(
    raw: &RawManifest,
    (ix, r): (usize, &RawRoutine),
    routines: &[Routine],
    err: &dyn Fn(&str, String) -> SphError,
) -> Result<Routine> {
    let key = format!("routine[{ix}] ({})", r.name);
    let name = r.name.trim().to_ascii_lowercase();
    if !is_ident(&name) {
        return Err(err(&format!("routine[{ix}].name"), format!("\"{}\" is not a Fortran name", r.name)));
    }
    if routines.iter().any(|o| o.name == name) {
        return Err(err(&key, "mapped twice".into()));
    }
    let call = match &r.call {
        None => CallMode::Whole,
        Some(c) => CallMode::parse(c.trim()).ok_or_else(|| {
            err(&format!("{key}.call"), format!("\"{c}\": must be \"whole\", \"each_particle\" or \"each_pair\""))
        })?,
    };
    let mut modules = Vec::new();
    let known = vocab::modules();
    for m in r.module.split(',').map(str::trim) {
        if !known.contains(&m) {
            return Err(err(
                &format!("{key}.module"),
                format!("\"{m}\" is not a blastsph module ({})", known.join(", ")),
            ));
        }
        if !modules.iter().any(|x: &String| x == m) {
            modules.push(m.to_string());
        }
    }
    if modules.len() > 1 && modules.iter().any(|m| m == "init") {
        return Err(err(
            &format!("{key}.module"),
            format!(
                "\"{}\": an init routine stands alone (it is called once, before the set-up and the first step)",
                r.module
            ),
        ));
    }
    let values = values_of(r, &key, err)?;
    let args = args_of(r, &key, call, err)?;
    if call == CallMode::EachParticle && args.iter().any(|a| a.term.name == "ntotal") {
        return Err(err(&format!("{key}.args"), "an each_particle call takes one particle: no \"ntotal\"".into()));
    }
    let globals = globals_of(r, &key, call, &args, err)?;
    // a vector's components: within the build's dim, and not beside the whole vector
    let names: Vec<&str> = args.iter().map(|a| a.term.name).chain(globals.iter().map(|g| g.term.name)).collect();
    for n in &names {
        if let Some((base, k)) = vocab::vector_component(n) {
            if k >= raw.dim as usize {
                return Err(err(
                    &key,
                    format!("\"{n}\" is component {} of {base}, but this build has dim = {}", k + 1, raw.dim),
                ));
            }
            if names.contains(&base) {
                return Err(err(
                    &key,
                    format!(
                        "\"{n}\" is a component of \"{base}\", which the routine also takes whole: give one or the other"
                    ),
                ));
            }
        }
    }
    if !globals.is_empty() && raw.global_includes.is_empty() && raw.global_modules.is_empty() {
        return Err(err(
            &format!("{key}.globals"),
            "name the include file of their COMMON blocks (global_includes) or their module (global_modules)".into(),
        ));
    }
    let virtual_kind = virtual_of(r, &name, &modules, &key, err)?;
    let adds = super::adds::of(&r.adds, (call, &modules), (&args, &globals), &key, err)?;
    Ok(Routine { name, modules, call, args, globals, values, virtual_kind, adds })
}

/// The `virtual` key: only on `virt_part` (module `boundary`), "held" or "integrated"; "held"
/// where `virt_part` leaves it out.
fn virtual_of(
    r: &RawRoutine,
    name: &str,
    modules: &[String],
    key: &str,
    err: &dyn Fn(&str, String) -> SphError,
) -> Result<Option<String>> {
    let is_virt = name == "virt_part" && modules.iter().any(|m| m == "boundary");
    match (&r.virtual_kind, is_virt) {
        (None, false) => Ok(None),
        (None, true) => Ok(Some("held".into())),
        (Some(_), false) => Err(err(
            &format!("{key}.virtual"),
            "only the routine virt_part (module = \"boundary\") takes `virtual`".into(),
        )),
        (Some(k), true) if k == "held" || k == "integrated" => Ok(Some(k.clone())),
        (Some(k), true) => Err(err(&format!("{key}.virtual"), format!("\"{k}\": must be \"held\" or \"integrated\""))),
    }
}

/// The arguments of routine `r` (manifest key `key`), each a name of the vocabulary of its call.
fn args_of(r: &RawRoutine, key: &str, call: CallMode, err: &dyn Fn(&str, String) -> SphError) -> Result<Vec<Arg>> {
    let mut args: Vec<Arg> = Vec::new();
    for a in &r.args {
        let written = a.trim().to_ascii_lowercase();
        if r.values.keys().any(|k| k.trim().eq_ignore_ascii_case(&written)) {
            continue;
        }
        let term = match call {
            CallMode::EachPair => vocab::lookup_pair(&written).or_else(|| {
                // scalars keep their meaning in a per-pair call (dt, itimestep, ...)
                vocab::lookup(&written).filter(|t| t.shape == Shape::Scalar)
            }),
            _ => vocab::lookup(&written),
        };
        let term = term.ok_or_else(|| {
            // a name of the per-pair call's own vocabulary, written in another call mode
            if call != CallMode::EachPair && vocab::lookup_pair(&written).is_some() {
                return err(
                    &format!("{key}.args"),
                    format!(
                        "\"{a}\" is an argument of an each_pair call only (one pair's r, dx, hsml, w, dwdx): set call = \"each_pair\", or name the whole arrays of a {} call (docs/reference/legacy.md)",
                        call.name()
                    ),
                );
            }
            let hint = match call {
                CallMode::EachPair => "in an each_pair call: r, dx, hsml, w, dwdx and scalars".to_string(),
                _ => "see the argument table of docs/reference/legacy.md".to_string(),
            };
            err(&format!("{key}.args"), format!("unknown argument name \"{a}\" ({hint})"))
        })?;
        if call == CallMode::EachParticle && term.shape.per_pair() {
            return Err(err(
                &format!("{key}.args"),
                format!("\"{a}\" is a per-pair array: not an argument of an each_particle call"),
            ));
        }
        if args.iter().any(|o| o.term.name == term.name) {
            return Err(err(&format!("{key}.args"), format!("\"{a}\" given twice")));
        }
        args.push(Arg { written, term, lead: None, real: false });
    }
    Ok(args)
}

/// The dummies of routine `r` (manifest key `key`) bound to values: each key of `values` is a
/// name of `args` that is not a vocabulary name, and its value an integer, a real or a logical.
fn values_of(r: &RawRoutine, key: &str, err: &dyn Fn(&str, String) -> SphError) -> Result<Vec<Constant>> {
    let mut out = Vec::new();
    for (k, v) in &r.values {
        let vkey = format!("{key}.values.{k}");
        let name = k.trim().to_ascii_lowercase();
        if vocab::lookup(&name).is_some() || vocab::lookup_pair(&name).is_some() {
            return Err(err(
                &vkey,
                format!(
                    "\"{k}\" is a name of the argument vocabulary: blastsph passes its value; bind only dummies it has no name for"
                ),
            ));
        }
        let Some(pos) = r.args.iter().position(|a| a.trim().eq_ignore_ascii_case(&name)) else {
            return Err(err(&vkey, format!("\"{k}\" is not in args: write it there, at its dummy's position")));
        };
        let value = match v {
            toml::Value::Integer(i) => Value::Int(*i),
            toml::Value::Float(x) if x.is_finite() => Value::Real(*x),
            toml::Value::Boolean(b) => Value::Logical(*b),
            other => {
                return Err(err(&vkey, format!("{other} is not an integer, a finite real or true/false")));
            }
        };
        out.push(Constant { pos, name, value, fortran: None });
    }
    out.sort_by_key(|c| c.pos);
    Ok(out)
}

/// The globals of routine `r` (manifest key `key`): names of the vocabulary not among `args`.
fn globals_of(
    r: &RawRoutine,
    key: &str,
    call: CallMode,
    args: &[Arg],
    err: &dyn Fn(&str, String) -> SphError,
) -> Result<Vec<Global>> {
    let mut globals: Vec<Global> = Vec::new();
    for (v, n) in &r.globals {
        let gkey = format!("{key}.globals.{v}");
        let var = v.trim().to_ascii_lowercase();
        if !is_ident(&var) {
            return Err(err(&gkey, format!("\"{v}\" is not a Fortran name")));
        }
        if call != CallMode::Whole {
            return Err(err(
                &gkey,
                format!(
                    "globals are copied in and out once per call: a {} call cannot take them (map a whole-array routine)",
                    call.name()
                ),
            ));
        }
        let written = n.trim().to_ascii_lowercase();
        let term = vocab::lookup(&written).ok_or_else(|| {
            err(&gkey, format!("unknown name \"{n}\" (see the argument table of docs/reference/legacy.md)"))
        })?;
        if args.iter().any(|a| a.term.name == term.name) {
            return Err(err(&gkey, format!("\"{n}\" is also an argument of the routine")));
        }
        if let Some(o) = globals.iter().find(|g| g.term.name == term.name) {
            return Err(err(&gkey, format!("\"{n}\" is also the global {}", o.var)));
        }
        globals.push(Global { var, term });
    }
    Ok(globals)
}

/// Checks that a case fits the arrays of a legacy build: `particles` (real and virtual) against
/// its `maxn`, and `pairs`, where known, against its `max_interaction`, named in `include` (the
/// build's include file). One line, exit status 2.
pub fn check_capacity(
    maxn: usize,
    max_interaction: usize,
    particles: usize,
    pairs: Option<usize>,
    include: &str,
) -> Result<()> {
    if particles > maxn {
        return Err(SphError::Input(format!(
            "the case has {particles} particles, more than the legacy build's maxn = {maxn} (its {include}): raise maxn and rebuild"
        )));
    }
    if let Some(np) = pairs
        && np > max_interaction
    {
        return Err(SphError::Input(format!(
            "the case has {np} pairs, more than the legacy build's max_interaction = {max_interaction} (its {include}): raise it and rebuild"
        )));
    }
    Ok(())
}
