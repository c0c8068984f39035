//! The size probe of `legacy build`: `dim`, `maxn` and `max_interaction` (the manifest's
//! `[param_names]`, names or integer expressions of them) evaluated by gfortran in a tiny program.
//!
//! Three layouts are read:
//! - an include file alone (the book's `param.inc`): the probe `include`s it, and the sources are
//!   compiled after it;
//! - a module of the sources (`param_module`): the sources are compiled first, then the probe
//!   `use`s the module;
//! - an include file that needs a module (a `real(rk)` constant, `rk` from a kind module): when
//!   the include alone does not compile, the sources are compiled and the probe is tried again
//!   with the `use` statements that the routines write before their `include` of that file.

use super::text::Proto;
use super::text::{fixed_form, read_source};
use super::{Log, compile_sources};
use crate::error::{Result, SphError, input};
use crate::migration::manifest::Manifest;
use crate::migration::shim::Sizes;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The compiled sources: their objects and the prototypes gfortran printed for each.
pub(super) type Compiled = (Vec<PathBuf>, Vec<Vec<Proto>>);

/// What the probe reads the sizes from, for `build.json` and messages.
pub(super) struct Found {
    pub(super) sizes: Sizes,
    /// The include file, or the source that defines `param_module`.
    pub(super) file: PathBuf,
    /// The sources, when the probe needed them compiled first.
    pub(super) compiled: Option<Compiled>,
}

/// The flags of the build: fixed form, free form, and the `-I` of the include folders.
pub(super) struct Flags<'a> {
    pub(super) fixed: &'a [String],
    pub(super) free: &'a [String],
    pub(super) incs: &'a [String],
}

/// Evaluates the sizes of manifest `m`, compiling the sources first when the layout needs it.
pub(super) fn sizes(
    m: &Manifest,
    obj: &Path,
    fl: &Flags,
    log: &mut Log,
    fail: &dyn Fn(String) -> SphError,
) -> Result<Found> {
    let inc = if m.param_include.is_empty() { None } else { Some(param_include(m)?) };
    let modfiles = obj.join("mod");
    if let Some(module) = &m.param_module {
        let file = module_source(m, module)?;
        let compiled = compile_sources(m, obj, (fl.fixed, fl.free), fl.incs, log, fail)?;
        let uses = vec![format!("use {module}")];
        let sizes = run(m, inc.as_deref(), &uses, &modfiles, obj, fl, log).map_err(|e| lift(e, fail))?;
        return Ok(Found { sizes, file, compiled: Some(compiled) });
    }
    let inc = inc.expect("param_include without param_module");
    let plain = run(m, Some(&inc), &[], &modfiles, obj, fl, log);
    let first = match plain {
        Ok(sizes) => return Ok(Found { sizes, file: inc, compiled: None }),
        Err(e) => e,
    };
    // the include may need the modules its routines use before including it
    let uses = uses_before_include(m);
    if uses.is_empty() {
        return Err(lift(first, fail));
    }
    let _ = writeln!(log.text, "probe: the include alone does not compile; the sources first, then with {uses:?}\n");
    let Ok(compiled) = compile_sources(m, obj, (fl.fixed, fl.free), fl.incs, log, fail) else {
        return Err(lift(first, fail));
    };
    let sizes = run(m, Some(&inc), &uses, &modfiles, obj, fl, log).map_err(|e| lift(e, fail))?;
    Ok(Found { sizes, file: inc, compiled: Some(compiled) })
}

/// An input error's message passed through `fail` (which names the log).
fn lift(e: SphError, fail: &dyn Fn(String) -> SphError) -> SphError {
    match e {
        SphError::Input(s) => fail(s),
        o => o,
    }
}

/// The manifest's `param_include`: the first of the include folders, then the manifest's folder,
/// that holds it.
fn param_include(m: &Manifest) -> Result<PathBuf> {
    m.include_dirs
        .iter()
        .map(|d| d.join(&m.param_include))
        .chain(std::iter::once(m.dir.join(&m.param_include)))
        .find(|p| p.is_file())
        .ok_or_else(|| {
            input(format!(
                "{}: param_include \"{}\" is in none of include_dirs (nor beside the manifest); sizes in a module are named by param_module",
                m.path.display(),
                m.param_include
            ))
        })
}

/// The source that defines module `name`.
fn module_source(m: &Manifest, name: &str) -> Result<PathBuf> {
    m.sources
        .iter()
        .find(|s| {
            read_source(s).is_some_and(|t| statements(&t, fixed_form(s)).iter().any(|st| defines_module(st, name)))
        })
        .cloned()
        .ok_or_else(|| input(format!("{}: param_module: \"{name}\" is not a module of the sources", m.path.display())))
}

/// Whether statement `st` (lower case) opens module `name`.
fn defines_module(st: &str, name: &str) -> bool {
    let mut w = st.split_whitespace();
    w.next() == Some("module") && w.next() == Some(name) && w.next().is_none()
}

/// A source's statements: lower case, comments dropped, blank lines skipped, continuation lines
/// joined (free form: a trailing `&`, with an optional leading `&` on the next line; fixed form:
/// a character other than blank or zero in column 6), and `;`-separated statements apart.
pub(super) fn statements(text: &str, fixed: bool) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut open = false; // the last free-form statement ends with `&`
    for raw in text.lines() {
        if fixed && matches!(raw.chars().next(), Some('c' | 'C' | '*' | '!')) {
            continue;
        }
        let l = raw.to_ascii_lowercase();
        let cont_fixed = fixed && l.len() > 6 && l.is_char_boundary(6) && !matches!(l.as_bytes()[5], b' ' | b'0');
        let body = if fixed && l.len() > 6 && l.is_char_boundary(6) {
            &l[6..]
        } else if fixed {
            ""
        } else {
            &l
        };
        let body = body.split('!').next().unwrap_or("").trim();
        if body.is_empty() {
            continue;
        }
        let joins = cont_fixed || open;
        let body = if open { body.strip_prefix('&').unwrap_or(body).trim_start() } else { body };
        open = !fixed && body.ends_with('&');
        let body = body.strip_suffix('&').unwrap_or(body).trim_end();
        let mut parts = body.split(';').map(str::trim);
        if let Some(last) = out.last_mut().filter(|_| joins) {
            last.push(' ');
            last.push_str(parts.next().unwrap_or(""));
        }
        out.extend(parts.filter(|s| !s.is_empty()).map(str::to_string));
    }
    out
}

/// The `use` statements that the program units of the sources write before their `include` of
/// the size file, each once, in the order first met.
fn uses_before_include(m: &Manifest) -> Vec<String> {
    let file = m.param_include.to_ascii_lowercase();
    let mut found: Vec<String> = Vec::new();
    for src in &m.sources {
        let Some(text) = read_source(src) else { continue };
        let mut pending: Vec<String> = Vec::new();
        for st in statements(&text, fixed_form(src)) {
            let first = st.split(|c: char| !c.is_ascii_alphanumeric() && c != '_').next().unwrap_or("");
            if first == "use" {
                pending.push(st);
            } else if first == "include" && st.contains(&file) {
                for u in pending.drain(..) {
                    if !found.contains(&u) {
                        found.push(u);
                    }
                }
            } else if is_unit_start(&st) {
                pending.clear();
            }
        }
    }
    found
}

/// Whether statement `st` (lower case) opens a program unit or a procedure.
fn is_unit_start(st: &str) -> bool {
    let words: Vec<&str> = st.split(|c: char| !c.is_ascii_alphanumeric() && c != '_').collect();
    match words.first() {
        Some(&"end") | None => false,
        Some(&("program" | "module" | "submodule" | "contains")) => true,
        _ => words.iter().any(|w| matches!(*w, "subroutine" | "function")),
    }
}

/// Compiles and runs the probe program (`uses`, then the include line, then the three sizes).
fn run(
    m: &Manifest,
    inc: Option<&Path>,
    uses: &[String],
    modfiles: &Path,
    obj: &Path,
    fl: &Flags,
    log: &mut Log,
) -> Result<Sizes> {
    let n = &m.param_names;
    let body = |lead: &str, end: &str| {
        let mut s = format!("{lead}program blastsph_probe\n");
        for u in uses {
            let _ = writeln!(s, "{lead}{u}");
        }
        if inc.is_some() {
            let _ = writeln!(s, "{lead}include '{}'", m.param_include);
        }
        let _ = write!(
            s,
            "{lead}integer bs_d, bs_m, bs_i\n\
             {lead}parameter (bs_d = {d})\n\
             {lead}parameter (bs_m = {mx})\n\
             {lead}parameter (bs_i = {mi})\n\
             {lead}write(*,'(3i20)') bs_d, bs_m, bs_i\n\
             {lead}{end}\n",
            d = n.dim,
            mx = n.maxn,
            mi = n.max_interaction
        );
        s
    };
    let exe = obj.join("blastsph_probe");
    let shown =
        inc.map_or_else(|| format!("module {}", m.param_module.as_deref().unwrap_or("")), |p| p.display().to_string());
    // the include file in fixed form (the book's), else in free form
    let mut first_err: Option<String> = None;
    for (file, text, flags) in [
        ("blastsph_probe.f", body("      ", "end"), fl.fixed),
        ("blastsph_probe.f90", body("", "end program"), fl.free),
    ] {
        let src = obj.join(file);
        std::fs::write(&src, text).map_err(|e| SphError::Io(format!("{}: {e}", src.display())))?;
        let mut cmd = Command::new("gfortran");
        cmd.args(flags);
        if let Some(dir) = inc.and_then(Path::parent) {
            cmd.arg(format!("-I{}", dir.display()));
        }
        cmd.args(fl.incs).arg(format!("-I{}", modfiles.display()));
        cmd.arg("-o").arg(&exe).arg(&src);
        let (ok, _, se) = log.run(&mut cmd)?;
        if ok {
            first_err = None;
            break;
        }
        // keep the message that names a parameter (the form that got that far), else the first
        let e = super::first_error(&se);
        let names = [&n.dim, &n.maxn, &n.max_interaction];
        match &first_err {
            Some(prev) if names.iter().any(|x| prev.contains(x.as_str())) => {}
            Some(_) if !names.iter().any(|x| e.contains(x.as_str())) => {}
            _ => first_err = Some(e),
        }
    }
    if let Some(e) = first_err {
        return Err(input(format!(
            "{shown}: cannot evaluate {}, {}, {} with a probe program: {e} (give their names, or integer expressions of the parameters there such as max_interaction = \"100*nmax\", in the manifest's [param_names]; sizes in a module: param_module; docs/reference/legacy.md)",
            n.dim, n.maxn, n.max_interaction
        )));
    }
    let (ok, so, _) = log.run(&mut Command::new(&exe))?;
    let v: Vec<i64> = so.split_whitespace().filter_map(|w| w.parse().ok()).collect();
    if !ok || v.len() != 3 {
        return Err(input(format!("{shown}: the probe program printed \"{}\"", so.trim())));
    }
    let _ =
        writeln!(log.text, "probe: {} = {}, {} = {}, {} = {}\n", n.dim, v[0], n.maxn, v[1], n.max_interaction, v[2]);
    log.flush();
    if !(1..=3).contains(&v[0]) || v[1] < 1 || v[2] < 1 {
        return Err(input(format!(
            "{shown}: {} = {}, {} = {}, {} = {}: not a usable size",
            n.dim, v[0], n.maxn, v[1], n.max_interaction, v[2]
        )));
    }
    Ok(Sizes { dim: v[0] as usize, maxn: v[1] as usize, max_interaction: v[2] as usize })
}

#[cfg(test)]
mod tests {
    use super::statements;

    #[test]
    fn continued_statements_are_joined() {
        let fixed = "c a comment\n      use sph_kind,\n     &    only: rk\n      include 'param.inc'\n";
        assert_eq!(statements(fixed, true), ["use sph_kind, only: rk", "include 'param.inc'"]);
        let free = "use sph_kind, &  ! the kinds\n  & only: rk\nuse a; use b\n";
        assert_eq!(statements(free, false), ["use sph_kind, only: rk", "use a", "use b"]);
        assert_eq!(statements("      x = 1\n     0  y = 2\n", true), ["x = 1", "y = 2"]);
    }
}
