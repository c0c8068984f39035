//! Reading the user's Fortran text: gfortran's prototypes, a routine's statements with its
//! includes, its dummies' declarations, an `ENTRY` statement, and where a global lives.

use super::*;

/// One external procedure from `-fc-prototypes-external`.
#[derive(Debug, Clone)]
pub(super) struct Proto {
    pub(super) symbol: String,
    pub(super) name: String,
    pub(super) returns: String,
    /// (C type, dummy name); a `*` pointer for every Fortran dummy.
    pub(super) params: Vec<(String, String)>,
    /// The module that holds it (a module procedure, [`super::modproc`]); None: external.
    pub(super) module: Option<String>,
}

pub(super) fn parse_protos(text: &str) -> Vec<Proto> {
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
        out.push(Proto { symbol: sym, name, returns: ret.trim().to_string(), params, module: None });
    }
    out
}

/// The arguments of routine `name` (in `file`) whose dummy is named as another argument of the
/// manifest's list (its written name or its vocabulary name, any case) and not as its own: one
/// line per such argument, a swapped pair once. Names are positional, so a build cannot refuse
/// them, but two reals swapped in the manifest (or in the source) compile, link and run, and only
/// the dual run's differences would show them.
pub(super) fn swapped_arguments(name: &str, file: &str, args: &[ArgInfo]) -> Vec<String> {
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

/// A Fortran source or include file as text, its bytes that are not UTF-8 (comments in GBK or
/// Latin-1) replaced: gfortran reads such files, and their statements are ASCII.
pub(super) fn read_source(p: &Path) -> Option<String> {
    std::fs::read(p).ok().map(|b| String::from_utf8_lossy(&b).into_owned())
}

/// Whether a source is fixed form (by its extension, as the build compiles it).
pub(super) fn fixed_form(p: &Path) -> bool {
    p.extension().and_then(|e| e.to_str()).is_some_and(|e| FIXED_FORM.contains(&e))
}

/// The statements of subroutine `name` in the source `text` (lower case, comments dropped,
/// continuation lines joined: `&` at a free-form line's end, a character in column 6 of fixed
/// form), from its `subroutine` statement to its `end` or its `contains` (an internal
/// procedure's declarations are not its own), one a line; None when the text defines no such
/// subroutine.
pub(super) fn routine_text(text: &str, name: &str, fixed: bool) -> Option<String> {
    unit_text(text, "subroutine", name, fixed)
}

/// The statements of program unit `unit name` (`subroutine` or `module`) as [`routine_text`]
/// gives a subroutine's: a module's are its specification part, up to its `contains` or `end`.
pub(super) fn unit_text(text: &str, unit: &str, name: &str, fixed: bool) -> Option<String> {
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
pub(super) fn assumed_shape(body: &str, dummy: &str) -> bool {
    matches!(declaration(body, dummy), Decl::Array(g) if g.starts_with(':'))
}

/// The leading extent of a whole array of vectors (`x(dim,maxn)`, `dwdx(dim,max_interaction)`)
/// when it is not `dim`: `Ok(None)` for `dim` itself (or an array that is not of vectors),
/// `Ok(Some(lead))` for an extent whose value the routine's statements or its includes give
/// (`x(maxdim,maxn)` with `parameter (maxdim = 3)`), which the shims lay the values out with,
/// and `Err(why)` for one that cannot be proved: its value not found, or below `dim`.
pub(super) fn leading_extent(
    decl: &Decl,
    call: CallMode,
    shape: Shape,
    (dim_name, dim): (&str, usize),
    body: &str,
) -> std::result::Result<Option<usize>, String> {
    let vec = matches!(shape, Shape::ParticleVec | Shape::PairVec);
    let Decl::Array(g) = decl else { return Ok(None) };
    if call != CallMode::Whole || !vec {
        return Ok(None);
    }
    let extents: Vec<&str> = g.split(',').collect();
    if extents.len() < 2 {
        // one extent (`x(*)`, `x(n)`): the routine indexes it itself, as laid out
        return Ok(None);
    }
    let lead = extents[0].trim();
    if lead.eq_ignore_ascii_case(dim_name) {
        return Ok(None);
    }
    match lead.parse::<usize>().ok().or_else(|| parameter_value(body, lead, 0)) {
        Some(v) if v == dim => Ok(None),
        Some(v) if v > dim => Ok(Some(v)),
        Some(v) => Err(format!(
            "is declared `({g})`: its leading extent `{lead}` = {v} is below {dim_name} (= {dim}), so a particle's {dim} values do not fit: refused rather than computed wrong"
        )),
        None => Err(format!(
            "is declared `({g})`: the value of its leading extent `{lead}` is not a number or a `parameter` of the routine or its includes, so blastsph cannot lay the {dim} values per particle or pair out as the routine reads them: refused rather than computed wrong"
        )),
    }
}

/// The value of integer constant `name` in a routine's statements (lower case): a `parameter
/// (name = 3)` statement or an `integer, parameter :: name = 3` declaration whose value is a
/// number or another such constant (to a depth of 4).
pub(super) fn parameter_value(body: &str, name: &str, depth: usize) -> Option<usize> {
    let name = name.to_ascii_lowercase();
    for l in body.lines() {
        let st: String = l.chars().filter(|c| !c.is_whitespace()).collect();
        let list = if let Some(r) = st.strip_prefix("parameter(") {
            r.strip_suffix(')').unwrap_or(r).to_string()
        } else if let Some((attrs, ents)) = st.split_once("::")
            && attrs.contains(",parameter")
        {
            ents.to_string()
        } else {
            continue;
        };
        for item in list.split(',') {
            let Some((n, v)) = item.split_once('=') else { continue };
            if n != name {
                continue;
            }
            return v.parse::<usize>().ok().or_else(|| {
                (depth < 4 && v.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
                    .then(|| parameter_value(body, v, depth + 1))
                    .flatten()
            });
        }
    }
    None
}

/// How a dummy argument is declared in a routine's statements from [`routine_text`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum Decl {
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
pub(super) fn declaration(body: &str, dummy: &str) -> Decl {
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
pub(super) fn with_includes(body: &str, beside: &Path, dirs: &[PathBuf], fixed: bool, depth: usize) -> (String, bool) {
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
        let text = found.and_then(|p| read_source(&p));
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
pub(super) struct GlobalTexts {
    pub(super) includes: Vec<(String, String)>,
    pub(super) modules: Vec<(String, String)>,
}

impl GlobalTexts {
    pub(super) fn read(m: &Manifest) -> Result<Self> {
        let includes = m
            .global_includes
            .iter()
            .map(|(name, path)| {
                let text = read_source(path).unwrap_or_default();
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
                let t = read_source(src)?;
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
pub(super) fn mentions(text: &str, name: &str) -> bool {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).any(|w| w == name)
}

/// The extents a COMMON statement gives `var` (`common /part/ x(dim,maxn), rho(maxn)`).
pub(super) fn common_extents(text: &str, var: &str) -> Option<String> {
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
pub(super) fn locate_global(
    m: &Manifest,
    routine: &str,
    g: &manifest::Global,
    texts: &GlobalTexts,
) -> Result<(shim::Site, bool)> {
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

/// Whether Fortran source `text` has an `ENTRY name` statement (any case, either form; a
/// comment line of fixed form is skipped).
pub(super) fn has_entry(text: &str, name: &str) -> bool {
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
    fn a_leading_extent_is_found_in_parameter_statements_or_refused() {
        let body = "integer maxdim, two\nparameter (two = 2, maxdim = 3)\ninteger, parameter :: nd = maxdim\n";
        assert_eq!(parameter_value(body, "maxdim", 0), Some(3));
        assert_eq!(parameter_value(body, "nd", 0), Some(3));
        assert_eq!(parameter_value(body, "other", 0), None);
        let decl = |g: &str| Decl::Array(g.to_string());
        let lead =
            |g: &str, dim: usize| leading_extent(&decl(g), CallMode::Whole, Shape::ParticleVec, ("dim", dim), body);
        assert_eq!(lead("dim,maxn", 2), Ok(None));
        assert_eq!(lead("2,maxn", 2), Ok(None));
        assert_eq!(lead("maxdim,maxn", 2), Ok(Some(3)));
        assert_eq!(lead("nd,maxn", 3), Ok(None));
        assert!(lead("two,maxn", 3).is_err_and(|e| e.contains("below dim (= 3)")));
        assert!(lead("n+1,maxn", 2).is_err_and(|e| e.contains("not a number or a `parameter`")));
        // one extent, or a per-particle call: the routine indexes it itself
        assert_eq!(lead("*", 2), Ok(None));
        let each = leading_extent(&decl("maxdim"), CallMode::EachParticle, Shape::ParticleVec, ("dim", 2), body);
        assert_eq!(each, Ok(None));
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
            lead: None,
            value: None,
            real: false,
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
