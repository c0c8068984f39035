//! Mapped routines defined inside a module (`module sph_force ... contains ... subroutine
//! int_force`): a module procedure, whose linker symbol is gfortran's `__sph_force_MOD_int_force`
//! and whose interface is explicit.
//!
//! `-fc-prototypes-external` prints no prototype for a module procedure. So each source whose
//! text defines a mapped routine that no external procedure is named as is compiled again with
//! `-fsyntax-only -fdump-fortran-original`: gfortran's parse tree names the module that holds the
//! routine, its dummies in order, and each dummy's type, kind and array specification. From it a
//! prototype is made as `-fc-prototypes-external` would print it (`double *` for
//! `double precision`, `int *` for `integer`), and the routine is checked as an external one is.
//! The shims then `use` the module (`only:` the routine) in place of `external`.

use super::*;

/// The prototype of module procedure `name` of `module`, from gfortran's parse-tree dump of the
/// file that defines the module; None when the dump holds no such module procedure.
pub(super) fn from_dump(dump: &str, module: &str, name: &str) -> Option<Proto> {
    let lines: Vec<&str> = dump.lines().collect();
    let indent = |l: &str| l.len() - l.trim_start().len();
    // the module's namespace: from its `procedure name` line to the next top-level namespace
    let start = lines.iter().position(|l| indent(l) == 0 && l.trim_end() == format!("procedure name = {module}"))?;
    let end =
        lines[start + 1..].iter().position(|l| l.starts_with("Namespace:")).map_or(lines.len(), |k| start + 1 + k);
    let ns = &lines[start..end];
    // the routine's symtree in the module: a module procedure of the module's own (not used)
    let head = ns.iter().position(|l| indent(l) == 2 && symtree_name(l) == Some(name))?;
    let attrs = field(&ns[head + 1..], 4, "attributes:")?;
    if !attrs.contains("MODULE-PROC") || attrs.contains("USE-ASSOC") {
        return None;
    }
    let returns = if attrs.contains(" SUBROUTINE") {
        "void".to_string()
    } else {
        c_type(&field(&ns[head + 1..], 4, "type spec :")?)
    };
    let formals: Vec<String> = field(&ns[head + 1..], 4, "Formal arglist:")
        .map(|f| f.split_whitespace().map(str::to_string).collect())
        .unwrap_or_default();
    // the routine's own namespace: its dummies' types
    let body = ns.iter().position(|l| indent(l) == 2 && l.trim_end() == format!("  procedure name = {name}"))?;
    let body = &ns[body + 1..];
    let mut params = Vec::new();
    for d in formals {
        let at = body.iter().position(|l| indent(l) == 4 && symtree_name(l) == Some(d.as_str()))?;
        let ty = c_type(&field(&body[at + 1..], 6, "type spec :")?);
        let attrs = field(&body[at + 1..], 6, "attributes:").unwrap_or_default();
        let by_value = attrs.split(|c: char| !c.is_ascii_alphanumeric() && c != '-').any(|w| w == "VALUE");
        params.push((if by_value { ty } else { format!("{ty} *") }, d));
    }
    Some(Proto {
        symbol: format!("__{module}_MOD_{name}"),
        name: name.to_string(),
        returns,
        params,
        module: Some(module.to_string()),
    })
}

/// The name a dump's `symtree: 'x' || symbol: 'x'` line gives (its symbol's own line, not a
/// symbol `from namespace` another).
fn symtree_name(l: &str) -> Option<&str> {
    let rest = l.trim_start().strip_prefix("symtree: '")?;
    let (n, after) = rest.split_once('\'')?;
    (!after.contains("from namespace")).then_some(n)
}

/// The text after `key` on the first line at indentation `at` of a symbol's description (the
/// lines after its `symtree:` line, up to the next line indented less deeply).
fn field(lines: &[&str], at: usize, key: &str) -> Option<String> {
    for l in lines {
        let ind = l.len() - l.trim_start().len();
        if ind < at {
            return None;
        }
        if ind == at
            && let Some(v) = l.trim_start().strip_prefix(key)
        {
            return Some(v.trim().to_string());
        }
    }
    None
}

/// The C type `-fc-prototypes-external` prints for a dump's type spec (`(REAL 8)`: `double`).
fn c_type(spec: &str) -> String {
    let s = spec.trim_matches(|c| c == '(' || c == ')');
    let mut w = s.split_whitespace();
    match (w.next().unwrap_or(""), w.next().unwrap_or("")) {
        ("REAL", "4") => "float".into(),
        ("REAL", "8") => "double".into(),
        ("REAL", "10") => "long_double".into(),
        ("REAL", "16") => "__float128".into(),
        ("INTEGER", "1") => "signed char".into(),
        ("INTEGER", "2") => "short".into(),
        ("INTEGER", "4") => "int".into(),
        ("INTEGER", "8") => "long".into(),
        ("LOGICAL", "1") => "int_fast8_t".into(),
        ("LOGICAL", "4") => "int_least32_t".into(),
        _ => s.to_ascii_lowercase(),
    }
}

/// The modules of a source's text that open with a `module NAME` statement (not `module
/// procedure`), lower case, in order.
fn modules_of(text: &str, fixed: bool) -> Vec<String> {
    let mut out = Vec::new();
    for st in probe::statements(text, fixed) {
        let mut w = st.split_whitespace();
        if w.next() == Some("module")
            && let Some(n) = w.next()
            && n != "procedure"
            && w.next().is_none()
        {
            out.push(n.to_string());
        }
    }
    out
}

/// Adds to `protos` the module procedure of each mapped routine of `m` that no source defines as
/// an external procedure: the sources whose text defines it, dumped by gfortran (`fl`: the
/// build's flags), each module of theirs that holds it. A routine in two modules is then found
/// twice (refused as defined twice); one in none, not at all. A module procedure whose symbol
/// the source's object (of `objects`) does not export (a `private` one) is refused.
pub(super) fn add(
    m: &Manifest,
    obj: &Path,
    fl: &probe::Flags,
    objects: &[PathBuf],
    protos: &mut [Vec<Proto>],
    log: &mut Log,
    fail: &dyn Fn(String) -> SphError,
) -> Result<()> {
    let missing: Vec<&str> =
        m.routines.iter().map(|r| r.name.as_str()).filter(|n| !protos.iter().flatten().any(|p| p.name == *n)).collect();
    if missing.is_empty() {
        return Ok(());
    }
    let scratch = obj.join("modproc");
    std::fs::create_dir_all(&scratch).map_err(|e| SphError::Io(format!("{}: {e}", scratch.display())))?;
    for (k, src) in m.sources.iter().enumerate() {
        let Some(text) = read_source(src) else { continue };
        let fixed = fixed_form(src);
        let here: Vec<&str> = missing.iter().copied().filter(|n| routine_text(&text, n, fixed).is_some()).collect();
        let modules = modules_of(&text, fixed);
        if here.is_empty() || modules.is_empty() {
            continue;
        }
        let mut cmd = Command::new("gfortran");
        cmd.arg("-fsyntax-only").arg("-fdump-fortran-original").args(if fixed { fl.fixed } else { fl.free });
        cmd.args(fl.incs).arg(format!("-I{}", obj.join("mod").display()));
        cmd.arg(format!("-J{}", scratch.display())).arg(src);
        let (ok, dump, se) = log.run(&mut cmd)?;
        if !ok {
            return Err(fail(format!("{}: the parse-tree dump failed: {}", rel(src, &m.dir), first_error(&se))));
        }
        let (_, syms, _) = log.run(Command::new("nm").arg("--defined-only").arg(&objects[k]))?;
        for n in here {
            for module in &modules {
                let Some(p) = from_dump(&dump, module, n) else { continue };
                if !syms.lines().any(|l| l.split_whitespace().collect::<Vec<_>>().ends_with(&["T", &p.symbol])) {
                    return Err(fail(format!(
                        "routine {n}: a private procedure of module {module} in {} (its object exports no `{}`): only a public one can be called from outside the module",
                        rel(src, &m.dir),
                        p.symbol
                    )));
                }
                protos[k].push(p);
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const DUMP: &str = "Namespace: A-H: (REAL 4) I-N: (INTEGER 4) O-Z: (REAL 4)
procedure name = mm
  symtree: 'ee'          || symbol: 'ee'           
    type spec : (UNKNOWN 0)
    attributes: (PROCEDURE MODULE-PROC  SUBROUTINE CONTAINED)
    Formal arglist: a n x g
  symtree: 'mm'          || symbol: 'mm'           
    type spec : (UNKNOWN 0)
    attributes: (MODULE )
  code:
CONTAINS
  Namespace: A-H: (REAL 4) I-N: (INTEGER 4) O-Z: (REAL 4)
  procedure name = ee
    symtree: 'a'           || symbol: 'a'            
      type spec : (LOGICAL 4)
      attributes: (VARIABLE  DUMMY)
    symtree: 'ee'          || symbol: 'ee' from namespace 'mm'
    symtree: 'g'           || symbol: 'g'            
      type spec : (REAL 8)
      attributes: (VARIABLE  VALUE DUMMY)
    symtree: 'n'           || symbol: 'n'            
      type spec : (INTEGER 4)
      attributes: (VARIABLE  DUMMY(IN))
    symtree: 'x'           || symbol: 'x'            
      type spec : (REAL 8)
      attributes: (VARIABLE  DIMENSION DUMMY)
      Array spec:(2 [0] AS_EXPLICIT 1 1 1 100 )
    code:
";

    #[test]
    fn a_module_procedures_prototype_is_read_from_the_dump() {
        let p = from_dump(DUMP, "mm", "ee").expect("ee is a module procedure of mm");
        assert_eq!(p.symbol, "__mm_MOD_ee");
        assert_eq!(p.returns, "void");
        let want = [("int_least32_t *", "a"), ("int *", "n"), ("double *", "x"), ("double", "g")];
        let got: Vec<(&str, &str)> = p.params.iter().map(|(t, n)| (t.as_str(), n.as_str())).collect();
        assert_eq!(got, want);
        assert!(from_dump(DUMP, "mm", "a").is_none(), "a dummy is not a procedure");
        assert!(from_dump(DUMP, "other", "ee").is_none(), "nor is ee a procedure of another module");
    }

    #[test]
    fn modules_are_found_but_not_module_procedure_statements() {
        let t = "module sph_force\nuse param\ncontains\nsubroutine f()\nend subroutine\nend module\n\
                 module procedure g\nmodule kinds\nend module\n";
        assert_eq!(modules_of(t, false), ["sph_force", "kinds"]);
    }
}
