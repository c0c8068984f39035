//! `blastsph legacy build MANIFEST --out DIR`: compiles a user's legacy sources, unmodified, with
//! generated shims into one shared library, and records what it built in `DIR/build.json`.
//!
//! Steps: read the manifest; evaluate `dim`, `maxn`, `max_interaction` by compiling and running a
//! probe program that includes the user's `param.inc` (gfortran evaluates it, whatever its
//! expressions); compile every source to an object (`-std=legacy` for fixed form, `-fPIC -O2
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
    /// The routine's linker symbol (gfortran's: `name_`).
    pub symbol: String,
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
    /// What the build noticed and let through (`legacy build` prints them): a dummy argument
    /// named as another argument of the manifest's list (swapped arguments?).
    #[serde(default)]
    pub warnings: Vec<String>,
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

/// One external procedure from `-fc-prototypes-external`.
#[derive(Debug, Clone)]
struct Proto {
    symbol: String,
    name: String,
    returns: String,
    /// (C type, dummy name); a `*` pointer for every Fortran dummy.
    params: Vec<(String, String)>,
}

fn parse_protos(text: &str) -> Vec<Proto> {
    let mut out = Vec::new();
    for l in text.lines() {
        let l = l.trim();
        if !l.ends_with(");") || l.starts_with('#') || l.starts_with("/*") {
            continue;
        }
        let Some(open) = l.find('(') else { continue };
        let head = l[..open].trim();
        let Some((ret, sym)) = head.rsplit_once(' ') else { continue };
        let body = &l[open + 1..l.len() - 2];
        let mut params = Vec::new();
        for p in body.split(',').map(str::trim).filter(|p| !p.is_empty() && *p != "void") {
            let (ty, name) = match p.rsplit_once(' ') {
                Some((ty, name)) => (ty.trim().to_string(), name.trim().to_string()),
                None => (p.to_string(), String::new()),
            };
            let (ty, name) = match name.strip_prefix('*') {
                Some(n) => (format!("{ty} *"), n.to_string()),
                None => (ty, name),
            };
            params.push((ty, name));
        }
        let sym = sym.trim().to_string();
        let name = sym.trim_end_matches('_').to_ascii_lowercase();
        out.push(Proto { symbol: sym, name, returns: ret.trim().to_string(), params });
    }
    out
}

/// The arguments of routine `name` (in `file`) whose dummy is named as another argument of the
/// manifest's list (its written name or its vocabulary name, any case) and not as its own: one
/// line per such argument, a swapped pair once. Names are positional, so a build cannot refuse
/// them, but two reals swapped in the manifest (or in the source) compile, link and run, and only
/// the dual run's differences would show them.
fn swapped_arguments(name: &str, file: &str, args: &[ArgInfo]) -> Vec<String> {
    let named = |a: &ArgInfo, d: &str| a.written.eq_ignore_ascii_case(d) || a.name.eq_ignore_ascii_case(d);
    let mut out = Vec::new();
    for (p, a) in args.iter().enumerate() {
        if named(a, &a.dummy) {
            continue;
        }
        let Some((q, b)) = args.iter().enumerate().find(|(q, b)| *q != p && named(b, &a.dummy)) else { continue };
        if q < p && named(a, &b.dummy) {
            // the pair, already said at q
            continue;
        }
        out.push(format!(
            "routine {name}: argument {} is `{}` in the manifest, but its dummy in {file} is `{}`, the name the manifest gives argument {} (whose dummy is `{}`): swapped? Names are positional: the manifest's order is the one that counts",
            p + 1,
            a.written,
            a.dummy,
            q + 1,
            b.dummy
        ));
    }
    out
}

/// Whether a source is fixed form (by its extension, as the build compiles it).
fn fixed_form(p: &Path) -> bool {
    p.extension().and_then(|e| e.to_str()).is_some_and(|e| FIXED_FORM.contains(&e))
}

/// The statements of subroutine `name` in the source `text` (lower case, comments dropped,
/// continuation lines joined: `&` at a free-form line's end, a character in column 6 of fixed
/// form), from its `subroutine` statement to its `end` or its `contains` (an internal
/// procedure's declarations are not its own), one a line; None when the text defines no such
/// subroutine.
fn routine_text(text: &str, name: &str, fixed: bool) -> Option<String> {
    unit_text(text, "subroutine", name, fixed)
}

/// The statements of program unit `unit name` (`subroutine` or `module`) as [`routine_text`]
/// gives a subroutine's: a module's are its specification part, up to its `contains` or `end`.
fn unit_text(text: &str, unit: &str, name: &str, fixed: bool) -> Option<String> {
    let name = name.to_ascii_lowercase();
    let header = format!("{unit} ");
    // the statements, continuations joined
    let mut stmts: Vec<String> = Vec::new();
    let mut open = false;
    for raw in text.lines() {
        if fixed && matches!(raw.chars().next(), Some('c' | 'C' | '*' | '!')) {
            continue;
        }
        let l = raw.to_ascii_lowercase();
        // fixed form: columns 1-5 a label, 6 a continuation mark; or a tab then the statement
        // (a digit right after the tab marks a continuation, the DEC form gfortran takes)
        let (cont_fixed, body) = if !fixed {
            (false, l.as_str())
        } else if let Some(r) = l.strip_prefix('\t') {
            match r.chars().next() {
                Some(c @ '1'..='9') => (true, &r[c.len_utf8()..]),
                _ => (false, r),
            }
        } else if l.len() > 6 && l.is_char_boundary(6) {
            let b = l.as_bytes()[5];
            (b != b' ' && b != b'0', &l[6..])
        } else {
            (false, "")
        };
        let t = body.split('!').next().unwrap_or("").trim();
        if t.is_empty() && !cont_fixed {
            continue;
        }
        let t = t.strip_prefix('&').unwrap_or(t).trim();
        if (open || cont_fixed) && !stmts.is_empty() {
            let last = stmts.last_mut().expect("a statement");
            last.push(' ');
            last.push_str(t.trim_end_matches('&'));
        } else {
            stmts.push(t.trim_end_matches('&').to_string());
        }
        open = !fixed && t.ends_with('&');
    }
    let mut out: Option<String> = None;
    for t in stmts {
        let t = t.trim();
        match &mut out {
            None => {
                let mut head = t;
                while let Some(r) = ["recursive ", "pure ", "elemental ", "impure ", "module "]
                    .iter()
                    .filter(|_| unit == "subroutine")
                    .find_map(|p| head.strip_prefix(p))
                {
                    head = r.trim_start();
                }
                if let Some(rest) = head.strip_prefix(header.as_str())
                    && rest.trim_start().strip_prefix(&name).is_some_and(|r| r.is_empty() || r.starts_with([' ', '(']))
                {
                    out = Some(format!("{t}\n"));
                }
            }
            Some(o) => {
                let flat: String = t.chars().filter(|c| !c.is_whitespace()).collect();
                if flat == "end"
                    || flat.starts_with("endsubroutine")
                    || flat.starts_with("endmodule")
                    || flat == "contains"
                {
                    break;
                }
                o.push_str(t);
                o.push('\n');
            }
        }
    }
    out
}

/// Whether `dummy` is declared assumed-shape in a routine's statements from [`routine_text`]:
/// its extents ([`declaration`]) begin with `:` (`x(:)`, `x(:, :)`, `dimension(:) :: x`).
fn assumed_shape(body: &str, dummy: &str) -> bool {
    matches!(declaration(body, dummy), Decl::Array(g) if g.starts_with(':'))
}

/// Why a whole array of vectors (`x(dim,maxn)`, `dwdx(dim,max_interaction)`) cannot be passed
/// as blastsph lays it out, or `None`. The shims pass `dim` values per particle or pair, one after
/// the other; a leading extent other than `dim` (`x(maxdim,maxn)` with maxdim = 3 in a 2D code)
/// makes the routine read them at other places. The extent is taken as `dim` only when it is the
/// include's name of `dim` or the number `dim` itself: anything else is not provably the same.
fn leading_extent_refusal(decl: &Decl, call: CallMode, shape: Shape, dim_name: &str, dim: usize) -> Option<String> {
    let vec = matches!(shape, Shape::ParticleVec | Shape::PairVec);
    let Decl::Array(g) = decl else { return None };
    if call != CallMode::Whole || !vec {
        return None;
    }
    let extents: Vec<&str> = g.split(',').collect();
    if extents.len() < 2 {
        // one extent (`x(*)`, `x(n)`): the routine indexes it itself, as laid out
        return None;
    }
    let lead = extents[0].trim();
    let is_dim = lead.eq_ignore_ascii_case(dim_name) || lead.parse::<usize>().is_ok_and(|v| v == dim);
    (!is_dim).then(|| {
        format!(
            "is declared `({g})`: its leading extent `{lead}` is not provably {dim_name} (= {dim}), and blastsph passes {dim} values per particle or pair one after the other, so the routine would read them at other places: refused rather than computed wrong"
        )
    })
}

/// How a dummy argument is declared in a routine's statements from [`routine_text`].
#[derive(Debug, Clone, PartialEq, Eq)]
enum Decl {
    /// With extents (the text between the parentheses, spaces dropped: `dim,maxn`, `*`, `1`).
    Array(String),
    /// In a type statement, with no extents anywhere.
    Scalar,
    /// In no declaration the routine's own text holds: a scalar by implicit typing, unless an
    /// `include` declares it.
    Undeclared,
}

/// The declaration of `dummy` in a routine's statements: a type statement with or without `::`
/// (`real*8 x(dim,maxn), y`, `double precision, intent(in) :: x(maxn)`), a `dimension(...)`
/// attribute over a list that names it, or a DIMENSION statement (`dimension x(maxn)`); any
/// statement that gives it extents makes it an array.
fn declaration(body: &str, dummy: &str) -> Decl {
    const TYPES: [&str; 10] = [
        "doubleprecision",
        "doublecomplex",
        "real",
        "integer",
        "logical",
        "complex",
        "character",
        "dimension",
        "type(",
        "class(",
    ];
    let d = dummy.to_ascii_lowercase();
    // the text after a balanced group that `s` opens with `(`, and the group's inside
    let group = |s: &str| -> Option<(String, String)> {
        let mut depth = 0usize;
        for (k, c) in s.char_indices() {
            match c {
                '(' => depth += 1,
                ')' => {
                    depth = depth.checked_sub(1)?;
                    if depth == 0 {
                        return Some((s[1..k].to_string(), s[k + 1..].to_string()));
                    }
                }
                _ => {}
            }
        }
        None
    };
    // the entities of a list at top level: `x(dim,maxn)`, `y`, `z*8`, `w=1.0`
    let entities = |list: &str| -> Vec<(String, Option<String>)> {
        let (mut out, mut cur, mut depth) = (Vec::new(), String::new(), 0i32);
        for c in list.chars().chain(std::iter::once(',')) {
            match c {
                '(' => depth += 1,
                ')' => depth -= 1,
                ',' if depth == 0 => {
                    let name: String = cur.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
                    let dims = group(&cur[name.len()..]).map(|(g, _)| g);
                    out.push((name, dims));
                    cur.clear();
                    continue;
                }
                _ => {}
            }
            cur.push(c);
        }
        out
    };
    let mut found = Decl::Undeclared;
    for l in body.lines() {
        let st: String = l.chars().filter(|c| !c.is_whitespace()).collect();
        let Some(kw) = TYPES.iter().find(|k| st.starts_with(*k)) else { continue };
        // not a function statement, nor an assignment to a name that begins with a type's
        // (`integers(i) = 0`): a type statement without `::` has no `=` outside parentheses
        let mut depth = 0i32;
        let assigns = st.chars().any(|c| {
            depth += (c == '(') as i32 - (c == ')') as i32;
            c == '=' && depth == 0
        });
        if !st.contains("::") && (assigns || st.contains("function")) {
            continue;
        }
        let (attr_dims, list) = match st.split_once("::") {
            Some((attrs, ents)) => {
                let dims =
                    attrs.find("dimension(").and_then(|k| group(&attrs[k + "dimension".len()..]).map(|(g, _)| g));
                (dims, ents.to_string())
            }
            None => {
                if kw.ends_with('(') {
                    continue;
                }
                let rest = &st[kw.len()..];
                // the type's length or kind: real*8, character*(*), real(8), integer*4
                let rest = match (*kw, rest.strip_prefix('*')) {
                    ("dimension", _) => rest.to_string(),
                    (_, Some(r)) if r.starts_with('(') => group(r).map(|(_, after)| after).unwrap_or_default(),
                    (_, Some(r)) => r.trim_start_matches(|c: char| c.is_ascii_digit()).to_string(),
                    (_, None) if rest.starts_with('(') => group(rest).map(|(_, after)| after).unwrap_or_default(),
                    _ => rest.to_string(),
                };
                (None, rest)
            }
        };
        for (name, dims) in entities(&list) {
            if name != d {
                continue;
            }
            match dims.or_else(|| attr_dims.clone()) {
                Some(g) => return Decl::Array(g),
                None => found = Decl::Scalar,
            }
        }
    }
    found
}

/// A routine's statements with the declarations its `include` lines bring in (the files looked
/// up beside the source, then in `dirs`, their names matched in any case as the statements are
/// lower case; nested includes to a depth of 4), and whether every include was found.
fn with_includes(body: &str, beside: &Path, dirs: &[PathBuf], fixed: bool, depth: usize) -> (String, bool) {
    let mut out = body.to_string();
    let mut all = true;
    for l in body.lines() {
        let t = l.trim_start().trim_start_matches('#');
        let Some(rest) = t.strip_prefix("include") else { continue };
        let name = rest.trim().trim_matches(|c| c == '\'' || c == '"' || c == '<' || c == '>').trim();
        let found = std::iter::once(beside).chain(dirs.iter().map(|d| d.as_path())).find_map(|d| {
            std::fs::read_dir(d)
                .ok()?
                .filter_map(|e| e.ok())
                .map(|e| e.path())
                .find(|p| p.file_name().and_then(|f| f.to_str()).is_some_and(|f| f.eq_ignore_ascii_case(name)))
        });
        let text = found.and_then(|p| std::fs::read_to_string(p).ok());
        // the file's statements, as those of a routine of its own
        let inc = text.filter(|_| depth < 4).and_then(|t| {
            let wrapped = if fixed {
                format!("      subroutine blastsph_inc\n{t}\n      end\n")
            } else {
                format!("subroutine blastsph_inc\n{t}\nend\n")
            };
            routine_text(&wrapped, "blastsph_inc", fixed)
        });
        match inc {
            Some(i) => {
                let i = i.split_once('\n').map_or("", |(_, rest)| rest).to_string();
                let (i, ok) = with_includes(&i, beside, dirs, fixed, depth + 1);
                all &= ok;
                out.push_str(&i);
            }
            None => all = false,
        }
    }
    (out, all)
}

/// The declarations the routines' globals are looked up in: each of the manifest's
/// `global_includes` (its statements with the includes it names, read as fixed form and as free
/// form, since an include file's form is that of the file that includes it) and each of its
/// `global_modules` (the module's specification part, from the source that defines it).
struct GlobalTexts {
    includes: Vec<(String, String)>,
    modules: Vec<(String, String)>,
}

impl GlobalTexts {
    fn read(m: &Manifest) -> Result<Self> {
        let includes = m
            .global_includes
            .iter()
            .map(|(name, path)| {
                let text = std::fs::read_to_string(path).unwrap_or_default();
                let beside = path.parent().unwrap_or(Path::new("."));
                let mut all = String::new();
                for fixed in [true, false] {
                    let lead = if fixed { "      " } else { "" };
                    let wrapped = format!("{lead}subroutine blastsph_inc\n{text}\n{lead}end\n");
                    if let Some(b) = routine_text(&wrapped, "blastsph_inc", fixed) {
                        all.push_str(&with_includes(&b, beside, &m.include_dirs, fixed, 0).0);
                    }
                }
                (name.clone(), all)
            })
            .collect();
        let mut modules = Vec::new();
        for name in &m.global_modules {
            let found = m.sources.iter().find_map(|src| {
                let t = std::fs::read_to_string(src).ok()?;
                let fixed = fixed_form(src);
                let b = unit_text(&t, "module", name, fixed)?;
                Some(with_includes(&b, src.parent().unwrap_or(Path::new(".")), &m.include_dirs, fixed, 0).0)
            });
            let Some(text) = found else {
                return Err(input(format!(
                    "{}: global_modules: \"{name}\" is not a module of the sources",
                    m.path.display()
                )));
            };
            modules.push((name.clone(), text));
        }
        Ok(GlobalTexts { includes, modules })
    }
}

/// Whether `name` appears in `text` as a whole Fortran name.
fn mentions(text: &str, name: &str) -> bool {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).any(|w| w == name)
}

/// The extents a COMMON statement gives `var` (`common /part/ x(dim,maxn), rho(maxn)`).
fn common_extents(text: &str, var: &str) -> Option<String> {
    for l in text.lines() {
        let st: String = l.chars().filter(|c| !c.is_whitespace()).collect();
        let Some(rest) = st.strip_prefix("common") else { continue };
        // drop the block names: /part/ (and // of blank common)
        let mut list = String::new();
        let mut in_name = false;
        for c in rest.chars() {
            match c {
                '/' => {
                    in_name = !in_name;
                    list.push(',');
                }
                _ if in_name => {}
                _ => list.push(c),
            }
        }
        let decl = declaration(&format!("dimension {list}"), var);
        if let Decl::Array(g) = decl {
            return Some(g);
        }
    }
    None
}

/// Where a routine's global variable is declared, checked against its vocabulary name's
/// shape, and whether it is an allocatable module variable.
fn locate_global(m: &Manifest, routine: &str, g: &manifest::Global, texts: &GlobalTexts) -> Result<(shim::Site, bool)> {
    let var = g.var.as_str();
    let site = texts
        .includes
        .iter()
        .find(|(_, t)| mentions(t, var))
        .map(|(n, t)| (shim::Site::Include(n.clone()), t))
        .or_else(|| {
            texts.modules.iter().find(|(_, t)| mentions(t, var)).map(|(n, t)| (shim::Site::Module(n.clone()), t))
        });
    let Some((site, text)) = site else {
        let mut where_ = Vec::new();
        if !m.global_includes.is_empty() {
            let names: Vec<&str> = m.global_includes.iter().map(|(n, _)| n.as_str()).collect();
            where_.push(format!("global_includes ({})", names.join(", ")));
        }
        if !m.global_modules.is_empty() {
            where_.push(format!("global_modules ({})", m.global_modules.join(", ")));
        }
        return Err(input(format!(
            "{}: routine {routine}: global `{var}` (\"{}\") is declared in none of {}",
            m.path.display(),
            g.term.name,
            where_.join(" nor ")
        )));
    };
    let from = site.to_string();
    let decl = match declaration(text, var) {
        Decl::Undeclared => common_extents(text, var).map_or(Decl::Undeclared, Decl::Array),
        d => d,
    };
    let scalar = g.term.shape == Shape::Scalar;
    let bad = match &decl {
        Decl::Array(x) => scalar && x != "1",
        Decl::Scalar => !scalar,
        Decl::Undeclared => false,
    };
    if bad {
        let how = match &decl {
            Decl::Array(x) => format!("an array in {from} (`{var}({x})`)"),
            _ => format!("one value in {from}"),
        };
        return Err(input(format!(
            "{}: routine {routine}: global `{var}` is {how}, but the vocabulary's \"{}\" is {}",
            m.path.display(),
            g.term.name,
            if scalar { "one value" } else { "an array" }
        )));
    }
    let allocatable = matches!(site, shim::Site::Module(_))
        && text.lines().any(|l| {
            let flat: String = l.chars().filter(|c| !c.is_whitespace()).collect();
            flat.contains("allocatable")
                && (declaration(l, var) != Decl::Undeclared || (flat.starts_with("allocatable") && mentions(l, var)))
        });
    Ok((site, allocatable))
}

fn rel(p: &Path, base: &Path) -> String {
    p.strip_prefix(base).unwrap_or(p).display().to_string()
}

/// Builds the manifest's code into `out`; returns what was built (also in `out/build.json`).
pub fn build(manifest_path: &Path, out: &Path) -> Result<BuildInfo> {
    let m = manifest::load(manifest_path)?;
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
    std::fs::create_dir_all(obj.join("mod")).map_err(|e| SphError::Io(format!("{}: {e}", obj.display())))?;
    let _ = std::fs::remove_file(out.join(BUILD_JSON));
    let _ = std::fs::remove_file(out.join(LIBRARY));
    let _ = std::fs::remove_file(out.join("program"));
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

    // the include file and the probe
    let inc = m
        .include_dirs
        .iter()
        .map(|d| d.join(&m.param_include))
        .chain(std::iter::once(m.dir.join(&m.param_include)))
        .find(|p| p.is_file())
        .ok_or_else(|| {
            input(format!(
                "{}: param_include \"{}\" is in none of include_dirs (nor beside the manifest)",
                m.path.display(),
                m.param_include
            ))
        })?;
    let sizes = probe(&m, &inc, &obj, (&fixed, &free), &mut log).map_err(|e| match e {
        SphError::Input(s) => fail(s),
        o => o,
    })?;
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
            let flags = if FIXED_FORM.contains(&ext) { &fixed } else { &free };
            let mut cmd = Command::new("gfortran");
            cmd.arg("-c").arg("-fc-prototypes-external").args(flags).args(&incs);
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
        let found: Vec<(usize, &Proto)> = protos
            .iter()
            .enumerate()
            .flat_map(|(k, ps)| ps.iter().map(move |p| (k, p)))
            .filter(|(_, p)| p.name == r.name)
            .collect();
        let (k, p) = match found.as_slice() {
            [] => {
                // defined, but not as an external procedure: inside a module or a CONTAINS
                let inner = m.sources.iter().find(|f| {
                    std::fs::read_to_string(f).is_ok_and(|t| routine_text(&t, &r.name, fixed_form(f)).is_some())
                });
                if let Some(f) = inner {
                    return Err(input(format!(
                        "{}: routine {}: defined in {} inside a module or after CONTAINS: only external subroutines (outside any module) can be mapped",
                        m.path.display(),
                        r.name,
                        rel(f, &m.dir)
                    )));
                }
                // an ENTRY statement of another subroutine (gfortran prints no prototype for it)
                let entry = m.sources.iter().find(|f| std::fs::read_to_string(f).is_ok_and(|t| has_entry(&t, &r.name)));
                if let Some(f) = entry {
                    return Err(input(format!(
                        "{}: routine {}: an ENTRY point (in {}), not a SUBROUTINE: entries cannot be mapped; map the SUBROUTINE that holds it, or a SUBROUTINE of your own in a new file that calls the entry",
                        m.path.display(),
                        r.name,
                        rel(f, &m.dir)
                    )));
                }
                return Err(input(format!(
                    "{}: routine {}: not found in the sources ({} files compiled)",
                    m.path.display(),
                    r.name,
                    m.sources.len()
                )));
            }
            [one] => *one,
            more => {
                let files: Vec<String> = more.iter().map(|(k, _)| rel(&m.sources[*k], &m.dir)).collect();
                return Err(input(format!(
                    "{}: routine {}: defined twice ({})",
                    m.path.display(),
                    r.name,
                    files.join(", ")
                )));
            }
        };
        let file = rel(&m.sources[k], &m.dir);
        if p.returns != "void" {
            return Err(input(format!(
                "{}: routine {} ({file}) is a FUNCTION returning {}: only subroutines can be mapped",
                m.path.display(),
                r.name,
                p.returns
            )));
        }
        if p.params.len() != r.args.len() {
            let dummies: Vec<&str> = p.params.iter().map(|(_, n)| n.as_str()).collect();
            return Err(input(format!(
                "{}: routine {}: the manifest names {} arguments, {file} declares {} ({})",
                m.path.display(),
                r.name,
                r.args.len(),
                p.params.len(),
                dummies.join(", ")
            )));
        }
        let mut args = Vec::new();
        // the routine's statements with its includes' declarations, and whether each include
        // was found (else a dummy that no statement declares may be declared in the one not read)
        let fixed_src = fixed_form(&m.sources[k]);
        let beside = m.sources[k].parent().unwrap_or(Path::new("."));
        let (decls, included) = std::fs::read_to_string(&m.sources[k])
            .ok()
            .and_then(|t| routine_text(&t, &r.name, fixed_src))
            .map_or((None, false), |b| {
                let (d, all) = with_includes(&b, beside, &m.include_dirs, fixed_src, 0);
                (Some(d), all)
            });
        for (pos, (a, (cty, dummy))) in r.args.iter().zip(&p.params).enumerate() {
            let want = format!("{} *", a.term.kind.c_type());
            // `intent(in)` makes the pointer const: the same argument to the shim
            let cty = cty.strip_prefix("const ").unwrap_or(cty);
            if decls.as_deref().is_some_and(|b| assumed_shape(b, dummy)) {
                return Err(input(format!(
                    "{}: routine {}: argument {} (dummy `{}` in {file}) is an assumed-shape array (`(:)`): the shims pass an address, as to FORTRAN 77 code; declare it explicit-shape (`{}(maxn)`) or assumed-size (`{}(*)`)",
                    m.path.display(),
                    r.name,
                    pos + 1,
                    dummy,
                    dummy,
                    dummy
                )));
            }
            // a scalar bound to an array dummy (or the reverse): positional names compile and
            // link whatever they are, and the routine reads past a one-value buffer (or sees one
            // value of an array); `x(1)`, the old idiom for an array of any size, is either
            let call_shape = match (r.call, a.term.shape) {
                (CallMode::Whole, s) => s,
                (_, Shape::ParticleVec | Shape::PairVec) => Shape::ParticleVec,
                _ => Shape::Scalar,
            };
            let array_here = call_shape != Shape::Scalar;
            // one particle's or pair's vector in a 1D build may be declared either way
            let either = r.call != CallMode::Whole && array_here && sizes.dim == 1;
            let decl = decls.as_deref().map_or(Decl::Undeclared, |b| declaration(b, dummy));
            let mismatch = !either
                && match &decl {
                    Decl::Array(g) => !array_here && g != "1",
                    Decl::Scalar => array_here,
                    Decl::Undeclared => array_here && included,
                };
            if mismatch {
                let how = match &decl {
                    Decl::Array(g) => format!("an array in {file} (`{dummy}({g})`)"),
                    Decl::Scalar => format!("a scalar in {file} (dummy `{dummy}`)"),
                    Decl::Undeclared => format!("a scalar in {file} (dummy `{dummy}`, typed implicitly)"),
                };
                let swapped = r
                    .args
                    .iter()
                    .position(|b| b.written.eq_ignore_ascii_case(dummy) || b.term.name.eq_ignore_ascii_case(dummy))
                    .filter(|&q| q != pos);
                let advice = match (swapped, r.call, a.term.shape) {
                    (Some(q), _, _) => format!(
                        "names are positional, so the manifest's list must follow the dummies' order (the manifest gives `{dummy}` as argument {}: swapped?)",
                        q + 1
                    ),
                    (None, CallMode::Whole, Shape::Particle | Shape::ParticleVec) if array_here => {
                        "a routine of one particle's values is mapped with call = \"each_particle\"".to_string()
                    }
                    (None, CallMode::Whole, Shape::Pair | Shape::PairVec) if array_here => {
                        "a routine of one pair's values is mapped with call = \"each_pair\"".to_string()
                    }
                    _ => "names are positional, so the manifest's list must follow the dummies' order".to_string(),
                };
                return Err(input(format!(
                    "{}: routine {}: argument {} (\"{}\" in the manifest, {}) is {how}: {advice}",
                    m.path.display(),
                    r.name,
                    pos + 1,
                    a.written,
                    if array_here { "an array" } else { "one value" },
                )));
            }
            if let Some(why) = leading_extent_refusal(&decl, r.call, a.term.shape, &m.param_names.dim, sizes.dim) {
                return Err(input(format!(
                    "{}: routine {}: argument {} (\"{}\" in the manifest, dummy `{dummy}` in {file}) {why}",
                    m.path.display(),
                    r.name,
                    pos + 1,
                    a.written,
                )));
            }
            if cty != want {
                let hint = if cty.contains("float128") || cty.contains("long double") {
                    " (-fdefault-real-8 alone makes double precision 16 bytes: add -fdefault-double-8)"
                } else {
                    ""
                };
                return Err(input(format!(
                    "{}: routine {}: argument {} (\"{}\" in the manifest) is declared {} in {file} (dummy `{}`); the vocabulary's {} is {}{}",
                    m.path.display(),
                    r.name,
                    pos + 1,
                    a.written,
                    cty.trim_end_matches(" *"),
                    dummy,
                    a.term.name,
                    a.term.kind.described(),
                    hint
                )));
            }
            args.push(ArgInfo {
                name: a.term.name.to_string(),
                written: a.written.clone(),
                dummy: dummy.clone(),
                kind: a.term.kind,
                shape: call_shape,
                unit: a.term.unit.to_string(),
            });
        }
        if is_program[k] {
            return Err(input(format!("{}: routine {}: {file} holds the main program", m.path.display(), r.name)));
        }
        for w in swapped_arguments(&r.name, &file, &args) {
            warnings.push(format!("{}: {w}", m.path.display()));
        }
        let bindings = r
            .bindings()
            .into_iter()
            .map(|t| BindingInfo {
                name: t.name.to_string(),
                kind: t.kind,
                shape: t.shape,
                base: t.base,
                unit: t.unit.to_string(),
            })
            .collect();
        let mut globals = Vec::new();
        let ri = routines.len();
        let bound = r.bindings();
        for g in &r.globals {
            let k = bound.iter().position(|t| t.name == g.term.name).expect("a global is bound");
            let (site, allocatable) = locate_global(&m, &r.name, g, &global_texts)?;
            globals.push(GlobalInfo { name: g.term.name.to_string(), var: g.var.clone(), from: site.to_string() });
            copies.push((
                r.name.clone(),
                g.term.name,
                shim::GlobalCopy {
                    sym: shim::global_symbol(ri, k),
                    var: g.var.clone(),
                    kind: g.term.kind,
                    site,
                    allocatable,
                },
            ));
        }
        routines.push(RoutineInfo {
            name: r.name.clone(),
            symbol: p.symbol.clone(),
            shim: shim::symbol(&r.name),
            modules: r.modules.clone(),
            call: r.call,
            file,
            args,
            bindings,
            globals,
        });
    }

    // the globals' copy routines: fixed form first (the include files of old codes), else free
    let mut extra_objs: Vec<PathBuf> = Vec::new();
    if !copies.is_empty() {
        let gobj = compile_generated(&mut log, &obj, "bs9_gcopy", &shim::gcopy_source(), &free)?
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
                    .args(if fixed_try { &fixed } else { &free })
                    .args(&incs)
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

    // the shims
    let shim_flags: Vec<String> = free.clone();
    let shim_text = shim::source(&m.routines, sizes, &m.path.display().to_string());
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
    let (program, program_note) = match is_program.iter().filter(|p| **p).count() {
        0 => (None, Some("the sources hold no main program".to_string())),
        1 => {
            let exe = out.join("program");
            let (ok, _, se) = log.run(Command::new("gfortran").args(&free).arg("-o").arg(&exe).args(&objects))?;
            if ok {
                (Some("program".to_string()), None)
            } else {
                (None, Some(format!("the main program does not link: {}", first_error(&se))))
            }
        }
        n => (None, Some(format!("the sources hold {n} main programs: none linked"))),
    };

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
                procedures: protos[k].iter().map(|p| p.name.clone()).collect(),
            })
            .collect(),
        routines,
        itype: m.itype.clone(),
        run_dirs: m.run_dirs.clone(),
        warnings,
    };
    let jp = out.join(BUILD_JSON);
    std::fs::write(&jp, serde_json::to_string_pretty(&info).unwrap_or_default())
        .map_err(|e| SphError::Io(format!("{}: {e}", jp.display())))?;
    Ok(info)
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

/// Compiles and runs a program that includes the user's parameter file and prints the three sizes.
fn probe(m: &Manifest, inc: &Path, obj: &Path, flags: (&[String], &[String]), log: &mut Log) -> Result<Sizes> {
    let n = &m.param_names;
    let body = |lead: &str, end: &str| {
        format!(
            "{lead}program blastsph_probe\n\
             {lead}include '{inc}'\n\
             {lead}integer bs_d, bs_m, bs_i\n\
             {lead}parameter (bs_d = {d})\n\
             {lead}parameter (bs_m = {mx})\n\
             {lead}parameter (bs_i = {mi})\n\
             {lead}write(*,'(3i20)') bs_d, bs_m, bs_i\n\
             {lead}{end}\n",
            inc = m.param_include,
            d = n.dim,
            mx = n.maxn,
            mi = n.max_interaction
        )
    };
    let exe = obj.join("blastsph_probe");
    let dir = inc.parent().unwrap_or(Path::new("."));
    // the include file in fixed form (the book's), else in free form
    let mut first_err: Option<String> = None;
    for (file, text, fl) in
        [("blastsph_probe.f", body("      ", "end"), flags.0), ("blastsph_probe.f90", body("", "end program"), flags.1)]
    {
        let src = obj.join(file);
        std::fs::write(&src, text).map_err(|e| SphError::Io(format!("{}: {e}", src.display())))?;
        let mut cmd = Command::new("gfortran");
        cmd.args(fl).arg(format!("-I{}", dir.display()));
        for d in &m.include_dirs {
            cmd.arg(format!("-I{}", d.display()));
        }
        cmd.arg("-o").arg(&exe).arg(&src);
        let (ok, _, se) = log.run(&mut cmd)?;
        if ok {
            first_err = None;
            break;
        }
        // keep the message that names a parameter (the form that got that far), else the first
        let e = first_error(&se);
        let names = [&n.dim, &n.maxn, &n.max_interaction];
        match &first_err {
            Some(prev) if names.iter().any(|x| prev.contains(x.as_str())) => {}
            Some(_) if !names.iter().any(|x| e.contains(x.as_str())) => {}
            _ => first_err = Some(e),
        }
    }
    if let Some(e) = first_err {
        return Err(input(format!(
            "{}: cannot evaluate {}, {}, {} with a probe program: {e} (if your include file names its sizes otherwise, give their names in the manifest's [param_names]: dim, maxn, max_interaction; docs/reference/legacy.md)",
            inc.display(),
            n.dim,
            n.maxn,
            n.max_interaction
        )));
    }
    let (ok, so, _) = log.run(&mut Command::new(&exe))?;
    let v: Vec<i64> = so.split_whitespace().filter_map(|w| w.parse().ok()).collect();
    if !ok || v.len() != 3 {
        return Err(input(format!("{}: the probe program printed \"{}\"", inc.display(), so.trim())));
    }
    let _ =
        writeln!(log.text, "probe: {} = {}, {} = {}, {} = {}\n", n.dim, v[0], n.maxn, v[1], n.max_interaction, v[2]);
    log.flush();
    if !(1..=3).contains(&v[0]) || v[1] < 1 || v[2] < 1 {
        return Err(input(format!(
            "{}: {} = {}, {} = {}, {} = {}: not a usable size",
            inc.display(),
            n.dim,
            v[0],
            n.maxn,
            v[1],
            n.max_interaction,
            v[2]
        )));
    }
    Ok(Sizes { dim: v[0] as usize, maxn: v[1] as usize, max_interaction: v[2] as usize })
}

/// Whether Fortran source `text` has an `ENTRY name` statement (any case, either form; a
/// comment line of fixed form is skipped).
fn has_entry(text: &str, name: &str) -> bool {
    let name = name.to_ascii_lowercase();
    text.lines().any(|l| {
        let fixed_comment = l.starts_with(['c', 'C', '*', '!']);
        let code = l.split('!').next().unwrap_or("").trim().to_ascii_lowercase();
        let code = code.trim_start_matches(|c: char| c.is_ascii_digit()).trim_start();
        !fixed_comment
            && code.strip_prefix("entry").is_some_and(|rest| {
                let rest = rest.trim_start();
                rest.strip_prefix(name.as_str())
                    .is_some_and(|after| after.trim_start().is_empty() || after.trim_start().starts_with('('))
            })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_entry_statement_is_found_in_either_form() {
        let fixed =
            "      SUBROUTINE EQSTAT(N,RHO,U,P,C)\nC     ENTRY EOSOLD(N)\n      ENTRY EOSALL (N,RHO)\n      END\n";
        assert!(has_entry(fixed, "eosall"));
        assert!(!has_entry(fixed, "eosold"), "a comment line");
        assert!(!has_entry(fixed, "eos"), "another name's prefix");
        assert!(has_entry("subroutine a(x)\n  entry b ! the other way in\nend\n", "B"));
        assert!(!has_entry("subroutine entryb(x)\nend\n", "b"));
    }

    #[test]
    fn a_dummys_rank_is_read_from_every_declaration_form() {
        let decl = |text: &str, fixed: bool, d: &str| declaration(&routine_text(text, "eos", fixed).unwrap(), d);
        let arr = |g: &str| Decl::Array(g.into());
        // F77: type statements with a length, a DIMENSION statement, implicit typing
        let f77 = "      subroutine eos(n, itype, x, rho, p, q)\n      include 'param.inc'\n      integer n, itype(maxn)\n      real*8 x(dim, maxn), rho(*)\n      double precision p\n      dimension p(maxn)\n      integers(3) = 0\n      end\n";
        assert_eq!(decl(f77, true, "n"), Decl::Scalar);
        assert_eq!(decl(f77, true, "itype"), arr("maxn"));
        assert_eq!(decl(f77, true, "x"), arr("dim,maxn"));
        assert_eq!(decl(f77, true, "rho"), arr("*"));
        assert_eq!(decl(f77, true, "p"), arr("maxn"), "typed in one statement, given extents in another");
        assert_eq!(decl(f77, true, "q"), Decl::Undeclared);
        // an assignment to a name that begins with a type's is not a declaration
        assert_eq!(decl(f77, true, "s"), Decl::Undeclared);
        // free form: attributes, a dimension attribute, a kind, a character length
        let f90 = "subroutine eos(a, b, c, s, k)\n  real(8), dimension(maxn), intent(in) :: a, b\n  real(kind=8), intent(out) :: c(dim,maxn)\n  character*(*) s\n  integer*4 :: k\nend subroutine\n";
        assert_eq!(decl(f90, false, "a"), arr("maxn"));
        assert_eq!(decl(f90, false, "b"), arr("maxn"));
        assert_eq!(decl(f90, false, "c"), arr("dim,maxn"));
        assert_eq!(decl(f90, false, "s"), Decl::Scalar);
        assert_eq!(decl(f90, false, "k"), Decl::Scalar);
        // another name that ends or begins with the dummy's is not it
        assert_eq!(
            decl("      subroutine eos(x)\n      real*8 dx(maxn), xx(maxn), x\n      end\n", true, "x"),
            Decl::Scalar
        );
    }

    #[test]
    fn assumed_shape_dummies_are_found_in_every_declaration_form() {
        let has =
            |text: &str, fixed: bool, d: &str| routine_text(text, "eos", fixed).is_some_and(|b| assumed_shape(&b, d));
        // free form: an attribute list, a type statement without ::, a DIMENSION statement, a
        // declaration continued with &
        assert!(has("subroutine eos(a, b)\n  double precision, dimension(:) :: a, b\nend subroutine\n", false, "b"));
        assert!(has("subroutine eos(a)\n  real*8 a(:)\nend\n", false, "a"));
        assert!(has("subroutine eos(a)\n  double precision a\n  dimension a(:, :)\nend\n", false, "a"));
        assert!(has("pure subroutine eos(a, b)\n  double precision :: b, &\n     a(:)\nendsubroutine\n", false, "a"));
        // explicit shape and assumed size are not assumed shape; neither is another name
        assert!(!has("subroutine eos(a, ab)\n  double precision :: a(maxn), ab(:)\nend\n", false, "a"));
        assert!(!has("subroutine eos(a)\n  double precision a(*)\nend\n", false, "a"));
        // an internal procedure's declarations after CONTAINS are not the routine's
        assert!(!has(
            "subroutine eos(a)\n  double precision a(10)\ncontains\n  subroutine h(a)\n  double precision :: a(:)\n  end subroutine\nend subroutine\n",
            false,
            "a"
        ));
        // fixed form: a continuation in column 6, a comment line, a label
        let f77 = "      subroutine eos(a, b)\nc     a comment: b(:)\n      double precision :: b,\n     &  a(:)\n   10 continue\n      end\n";
        assert!(has(f77, true, "a") && !has(f77, true, "b"));
        // a tab-formatted line
        assert!(has("\tsubroutine eos(a)\n\treal*8 a(:)\n\tend\n", true, "a"));
        assert!(routine_text("      subroutine other(a)\n      end\n", "eos", true).is_none());
    }

    #[test]
    fn prototypes_are_parsed() {
        let t = "#include <stddef.h>\nvoid kernel_ (double *r, double *dx, double *hsml, double *w, double *dwdx);\n\
                 double f_ (int *n);\nvoid z_ ();\n";
        let p = parse_protos(t);
        assert_eq!(p.len(), 3);
        assert_eq!(p[0].name, "kernel");
        assert_eq!(p[0].symbol, "kernel_");
        assert_eq!(p[0].params[1], ("double *".to_string(), "dx".to_string()));
        assert_eq!(p[1].returns, "double");
        assert!(p[2].params.is_empty());
    }

    #[test]
    fn a_dummy_named_as_another_argument_is_reported_once_per_swapped_pair() {
        let arg = |name: &str, written: &str, dummy: &str| ArgInfo {
            name: name.into(),
            written: written.into(),
            dummy: dummy.into(),
            kind: Kind::Real,
            shape: Shape::Scalar,
            unit: String::new(),
        };
        // p_gas(u, rho, p, c) mapped as ["rho", "u", "p", "c"]
        let swapped = [arg("rho", "rho", "u"), arg("u", "u", "rho"), arg("p", "p", "p"), arg("c", "c", "c")];
        let w = swapped_arguments("p_gas", "p_gas.f", &swapped);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].contains("argument 1 is `rho`") && w[0].contains("argument 2 (whose dummy is `rho`)"), "{w:?}");
        // the right order, dummies in upper case or other names: nothing
        let right = [arg("rho", "rho", "RHO"), arg("u", "u", "u"), arg("p", "p", "pres"), arg("c", "c", "cs")];
        assert!(swapped_arguments("p_gas", "p_gas.f", &right).is_empty());
    }

    #[test]
    fn first_error_joins_location_and_message() {
        let se = "k.f:17:17:\n\n   17 |       call foo(1,2d0,3.)\n      |                 1\nError: Rank mismatch\n";
        assert_eq!(first_error(se), "k.f:17:17: Error: Rank mismatch");
        assert_eq!(
            first_error("x.o: in function `a_':\nx.f:(.text+0x5): undefined reference to `b_'\n"),
            "x.f:(.text+0x5): undefined reference to `b_'"
        );
    }
}
