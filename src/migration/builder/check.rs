//! Checks of each mapped routine against what gfortran compiled: defined once, an external
//! subroutine, with the manifest's number, shapes and types of arguments.

use super::*;

/// What `routine` returns: the routine's record, its globals' copies, its warnings.
type Checked = (RoutineInfo, Vec<(String, &'static str, shim::GlobalCopy)>, Vec<String>);

/// Checks mapped routine `r` (the `ri`-th) against the prototypes gfortran printed.
pub(super) fn routine(
    m: &Manifest,
    r: &manifest::Routine,
    protos: &[Vec<Proto>],
    is_program: &[bool],
    sizes: Sizes,
    global_texts: &GlobalTexts,
    ri: usize,
) -> Result<Checked> {
    let mut copies = Vec::new();
    let mut warnings = Vec::new();
    let (k, p) = find_proto(m, r, protos)?;
    let file = rel(&m.sources[k], &m.dir);
    if p.returns != "void" {
        return Err(input(format!(
            "{}: routine {} ({file}) is a FUNCTION returning {}: only subroutines can be mapped",
            m.path.display(),
            r.name,
            p.returns
        )));
    }
    if p.params.len() != r.args.len() + r.values.len() {
        let dummies: Vec<&str> = p.params.iter().map(|(_, n)| n.as_str()).collect();
        return Err(input(format!(
            "{}: routine {}: the manifest names {} arguments, {file} declares {} ({})",
            m.path.display(),
            r.name,
            r.args.len() + r.values.len(),
            p.params.len(),
            dummies.join(", ")
        )));
    }
    let args = check_args(m, r, p, k, &file, sizes)?;
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
    let bound = r.bindings();
    for g in &r.globals {
        let k = bound.iter().position(|t| t.name == g.term.name).expect("a global is bound");
        let (site, allocatable) = locate_global(m, &r.name, g, global_texts)?;
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
    let info = RoutineInfo {
        name: r.name.clone(),
        symbol: p.symbol.clone(),
        module: p.module.clone(),
        shim: shim::symbol(&r.name),
        modules: r.modules.clone(),
        call: r.call,
        file,
        args,
        bindings,
        globals,
        virtual_kind: r.virtual_kind.clone(),
        adds: r.adds.iter().map(|s| s.to_string()).collect(),
    };
    Ok((info, copies, warnings))
}

/// The one prototype of mapped routine `r`: its source's index and the prototype.
fn find_proto<'a>(m: &Manifest, r: &manifest::Routine, protos: &'a [Vec<Proto>]) -> Result<(usize, &'a Proto)> {
    let found: Vec<(usize, &Proto)> = protos
        .iter()
        .enumerate()
        .flat_map(|(k, ps)| ps.iter().map(move |p| (k, p)))
        .filter(|(_, p)| p.name == r.name)
        .collect();
    match found.as_slice() {
        [] => {
            // defined, but neither as an external procedure nor as a module procedure
            let inner = m
                .sources
                .iter()
                .find(|f| read_source(f).is_some_and(|t| routine_text(&t, &r.name, fixed_form(f)).is_some()));
            if let Some(f) = inner {
                return Err(input(format!(
                    "{}: routine {}: defined in {} as neither an external subroutine nor a module procedure (an internal procedure after CONTAINS?): only those two can be mapped",
                    m.path.display(),
                    r.name,
                    rel(f, &m.dir)
                )));
            }
            // an ENTRY statement of another subroutine (gfortran prints no prototype for it)
            let entry = m.sources.iter().find(|f| read_source(f).is_some_and(|t| has_entry(&t, &r.name)));
            if let Some(f) = entry {
                return Err(input(format!(
                    "{}: routine {}: an ENTRY point (in {}), not a SUBROUTINE: entries cannot be mapped; map the SUBROUTINE that holds it, or a SUBROUTINE of your own in a new file that calls the entry",
                    m.path.display(),
                    r.name,
                    rel(f, &m.dir)
                )));
            }
            Err(input(format!(
                "{}: routine {}: not found in the sources ({} files compiled)",
                m.path.display(),
                r.name,
                m.sources.len()
            )))
        }
        [one] => Ok(*one),
        more => {
            let files: Vec<String> = more
                .iter()
                .map(|(k, p)| {
                    let f = rel(&m.sources[*k], &m.dir);
                    p.module.as_ref().map_or(f.clone(), |md| format!("{f} (module {md})"))
                })
                .collect();
            Err(input(format!("{}: routine {}: defined twice ({})", m.path.display(), r.name, files.join(", "))))
        }
    }
}

/// The arguments of mapped routine `r`, each checked against its dummy in prototype `p` (of
/// source `k`, named `file`).
fn check_args(
    m: &Manifest,
    r: &manifest::Routine,
    p: &Proto,
    k: usize,
    file: &str,
    sizes: Sizes,
) -> Result<Vec<ArgInfo>> {
    let mut args = Vec::new();
    // the routine's statements with its includes' declarations, and whether each include
    // was found (else a dummy that no statement declares may be declared in the one not read)
    let fixed_src = fixed_form(&m.sources[k]);
    let beside = m.sources[k].parent().unwrap_or(Path::new("."));
    let (decls, included) =
        read_source(&m.sources[k]).and_then(|t| routine_text(&t, &r.name, fixed_src)).map_or((None, false), |b| {
            let (d, all) = with_includes(&b, beside, &m.include_dirs, fixed_src, 0);
            (Some(d), all)
        });
    let mut named = r.args.iter();
    for (pos, (cty, dummy)) in p.params.iter().enumerate() {
        if let Some(c) = r.values.iter().find(|c| c.pos == pos) {
            args.push(constant(m, r, c, (cty, dummy), file)?);
            continue;
        }
        let Some(a) = named.next() else { break };
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
        // the book's link_list declares hsml a scalar: it reads the first particle's h (global_h)
        let global_h = r.call == CallMode::Whole && a.term.name == "hsml" && decl == Decl::Scalar;
        let mismatch = !either
            && !global_h
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
        let dims = (m.param_names.dim.as_str(), sizes.dim);
        let lead =
            leading_extent(&decl, r.call, a.term.shape, dims, decls.as_deref().unwrap_or("")).map_err(|why| {
                input(format!(
                    "{}: routine {}: argument {} (\"{}\" in the manifest, dummy `{dummy}` in {file}) {why}",
                    m.path.display(),
                    r.name,
                    pos + 1,
                    a.written,
                ))
            })?;
        // an integer (a count, an index, a type code) that the code declares double precision
        // under the vocabulary's name: the shim converts it both ways, exactly for |n| < 2^53
        // (under another name it is more likely a misplaced argument, and refused)
        let own = [a.term.name, a.written.as_str()].into_iter().chain(a.term.aliases.iter().copied());
        let real =
            a.term.kind == Kind::Int && cty == "double *" && own.into_iter().any(|n| dummy.eq_ignore_ascii_case(n));
        if cty != want && !real {
            let hint = if cty.contains("float128") || cty.contains("long double") {
                " (-fdefault-real-8 alone makes double precision 16 bytes: add -fdefault-double-8)"
            } else if a.term.kind == Kind::Int && cty == "double *" {
                " (a count declared double precision is taken under the vocabulary's name only)"
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
            lead,
            value: None,
            real,
        });
    }
    Ok(args)
}

/// Dummy `dummy` (C type `cty`, as gfortran's prototype gives it) of routine `r` bound to
/// value `c` of the manifest: its Fortran type and literal, or a refusal in one line when the
/// value's type is not the dummy's.
fn constant(
    m: &Manifest,
    r: &manifest::Routine,
    c: &manifest::Constant,
    (cty, dummy): (&str, &str),
    file: &str,
) -> Result<ArgInfo> {
    use manifest::Value;
    let cty = cty.strip_prefix("const ").unwrap_or(cty).trim_end_matches(" *");
    let real = |x: f64| format!("{x:e}").replace('e', "d");
    let fortran = match (&c.value, cty) {
        (Value::Int(i), "int") => Some(("integer".to_string(), i.to_string())),
        (Value::Int(i), "long" | "int64_t") => Some(("integer(8)".to_string(), format!("{i}_8"))),
        (Value::Logical(b), "int_least32_t") => {
            Some(("logical".to_string(), if *b { ".true." } else { ".false." }.to_string()))
        }
        (Value::Logical(b), "int_fast8_t") => {
            Some(("logical(1)".to_string(), if *b { ".true." } else { ".false." }.to_string()))
        }
        (Value::Real(x), "double") => Some(("double precision".to_string(), real(*x))),
        (Value::Int(i), "double") => Some(("double precision".to_string(), real(*i as f64))),
        (Value::Real(x), "float") => Some(("real".to_string(), format!("{x:e}"))),
        (Value::Int(i), "float") => Some(("real".to_string(), format!("{:e}", *i as f64))),
        _ => None,
    };
    let Some((ty, lit)) = fortran else {
        let given = match c.value {
            Value::Int(_) => "an integer",
            Value::Real(_) => "a real",
            Value::Logical(_) => "a logical",
        };
        return Err(input(format!(
            "{}: routine {}: argument {} (\"{}\" in values) is declared {cty} in {file} (dummy `{dummy}`); the manifest gives {given}",
            m.path.display(),
            r.name,
            c.pos + 1,
            c.name,
        )));
    };
    Ok(ArgInfo {
        name: c.name.clone(),
        written: c.name.clone(),
        dummy: dummy.to_string(),
        kind: if ty.contains("precision") || ty == "real" { Kind::Real } else { Kind::Int },
        shape: Shape::Scalar,
        unit: String::new(),
        lead: None,
        value: Some((ty, lit)),
        real: false,
    })
}
