//! Bring your own legacy code: the layouts of the sizes (`dim`, `maxn`, `max_interaction`) that
//! the probe of `legacy build` reads (docs/reference/legacy.md): in a module of the sources, in
//! an include file that needs a kind from a module, and as integer expressions of other parameters.
//! Each variant of the fixture builds, and its routines agree with their twins at 0 ULP.

mod legacy_kit;
use legacy_kit::*;

/// Every `.f` of the fixture's copy in `d` edited by `edit`, which must change at least one.
fn edit_sources(d: &Path, edit: impl Fn(&str) -> String) {
    let mut changed = 0;
    for e in std::fs::read_dir(d).unwrap() {
        let p = e.unwrap().path();
        if p.extension().and_then(|x| x.to_str()) != Some("f") {
            continue;
        }
        let t = std::fs::read_to_string(&p).unwrap();
        let n = edit(&t);
        if n != t {
            std::fs::write(&p, n).unwrap();
            changed += 1;
        }
    }
    assert!(changed > 0, "the edit changes the sources");
}

/// The include line of the fixture's routines, after their `implicit none`.
const INCLUDE: &str = "      implicit none\n      include 'param.inc'\n";

/// The shock tube's dual run of build `lg` with the book's profile, over 10 steps: every mapped
/// routine at 0 ULP.
fn dual_at_zero_ulp(lg: &Path, out: &str) {
    let out = scratch(out);
    let o = dual_book(lg, Some(10), &out);
    let (so, se) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert_eq!(o.status.code(), Some(0), "{so}{se}");
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    for (stage, fields) in MAPPED {
        for f in *fields {
            let r = row(&rows, stage, f);
            assert!(r["compared"].as_u64().unwrap() > 0 && r["max_ulp"].as_u64() == Some(0), "{stage} {f}: {r}");
        }
    }
}

/// Sizes in a Fortran module (as free-form rewrites of the book keep them): the fixture's
/// param.inc becomes `module bookparam`, which every routine `use`s; there is no include file.
/// With `param_module = "bookparam"` the sources are compiled first and the probe `use`s the
/// module; without it the build is refused, naming the key. The module's file is compiled last
/// (the routines are retried after it), and a rebuild after an edit of the module gives the
/// routines its new values (the quintic kernel, which the dual run finds apart from its twin):
/// the module files of the earlier build are not read.
#[test]
fn sizes_in_a_module_are_read_by_the_probe() {
    let d = variant("sizes_module", |m| m.replacen("[[routine]]", "param_module = \"bookparam\"\n\n[[routine]]", 1));
    let inc = std::fs::read_to_string(d.join("param.inc")).unwrap();
    std::fs::remove_file(d.join("param.inc")).unwrap();
    let module = format!("      module bookparam\n      implicit none\n{inc}      end module bookparam\n");
    std::fs::write(d.join("zz_param.f"), &module).unwrap();
    edit_sources(&d, |t| t.replace(INCLUDE, "      use bookparam\n      implicit none\n"));
    for e in std::fs::read_dir(&d).unwrap() {
        let t = std::fs::read_to_string(e.unwrap().path()).unwrap_or_default();
        assert!(!t.contains("include 'param.inc'"), "no routine includes the sizes");
    }
    let info = build(&d.join("legacy.toml"), &d.join("build")).expect("the module variant builds");
    assert_eq!((info.dim, info.maxn, info.max_interaction), (1, 1000, 20000));
    assert!(info.param_include.ends_with("zz_param.f"), "{}", info.param_include);
    dual_at_zero_ulp(&d.join("build"), "sizes_module_dual");
    let quintic = module.replace("parameter (skf = 1)", "parameter (skf = 3)");
    assert_ne!(quintic, module);
    std::fs::write(d.join("zz_param.f"), &quintic).unwrap();
    build(&d.join("legacy.toml"), &d.join("build")).expect("the edited module builds");
    let out = scratch("sizes_module_gauss");
    let o = dual_book(&d.join("build"), Some(2), &out);
    assert_eq!(o.status.code(), Some(4), "{}", String::from_utf8_lossy(&o.stdout));
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    let r = row(&rows, "legacy.kernel", "w");
    assert!(r["out_of_tolerance"].as_u64().unwrap() > 0, "the quintic kernel: {r}");
    std::fs::write(d.join("zz_param.f"), &module).unwrap();

    // without the key the probe looks for param.inc; a module that is not in the sources
    let m = std::fs::read_to_string(d.join("legacy.toml")).unwrap();
    std::fs::write(d.join("legacy.toml"), m.replace("param_module = \"bookparam\"\n", "")).unwrap();
    refused(&d, &["param_include \"param.inc\"", "param_module"]);
    std::fs::write(d.join("legacy.toml"), m.replace("\"bookparam\"", "\"nosuch\"")).unwrap();
    refused(&d, &["param_module: \"nosuch\" is not a module of the sources"]);
}

/// An include file that declares a constant of a kind from a module (`real(rk)`, `rk` from
/// `module bookkind`, which every routine `use`s before its include, in a statement continued
/// over two lines): the include alone does not compile, so the probe compiles the sources and is
/// tried again with that `use` statement, its lines joined.
#[test]
fn an_include_that_needs_a_modules_kind_is_probed_with_that_module() {
    let d = variant("sizes_kind", |m| m.to_string());
    let kinds = "      module bookkind\n      implicit none\n      integer, parameter :: rk = kind(1.d0)\n      end module bookkind\n";
    std::fs::write(d.join("bookkind.f"), kinds).unwrap();
    let p = d.join("param.inc");
    let inc = std::fs::read_to_string(&p).unwrap();
    std::fs::write(&p, format!("{inc}\n      real(rk) tiny_r\n      parameter (tiny_r = 1.e-30_rk)\n")).unwrap();
    edit_sources(&d, |t| t.replace(INCLUDE, &format!("      use bookkind,\n     &    only: rk\n{INCLUDE}")));
    let info = build(&d.join("legacy.toml"), &d.join("build")).expect("the kind variant builds");
    assert_eq!((info.dim, info.maxn, info.max_interaction), (1, 1000, 20000));
    let log = std::fs::read_to_string(d.join("build/build.log")).unwrap();
    let alone = log.split("probe: the include alone does not compile").next().unwrap();
    assert!(alone.contains("rk") && alone.contains("has not been declared"), "the include alone fails on rk: {log}");
    assert!(log.contains("then with [\"use bookkind, only: rk\"]"), "{log}");
    dual_at_zero_ulp(&d.join("build"), "sizes_kind_dual");
}

/// A code with no `max_interaction` (a neighbour table of `npmax` pairs per particle): the
/// manifest gives the size as an expression, `max_interaction = "npmax*maxn"`, which the probe
/// evaluates. Without it the build is refused with a line that shows such an expression.
#[test]
fn sizes_given_as_expressions_are_evaluated_by_the_probe() {
    let d = variant("sizes_expr", |m| {
        m.replacen("[[routine]]", "[param_names]\nmax_interaction = \"npmax*maxn\"\n\n[[routine]]", 1)
    });
    let p = d.join("param.inc");
    let inc = std::fs::read_to_string(&p).unwrap();
    let old = "      integer maxn, max_interaction\n      parameter (maxn = 1000, max_interaction = 20*maxn)\n";
    assert!(inc.contains(old), "{inc}");
    std::fs::write(&p, inc.replace(old, "      integer maxn, npmax\n      parameter (maxn = 1000, npmax = 20)\n"))
        .unwrap();
    edit_sources(&d, |t| t.replace("max_interaction", "npmax*maxn"));
    let info = build(&d.join("legacy.toml"), &d.join("build")).expect("the expression variant builds");
    assert_eq!((info.dim, info.maxn, info.max_interaction), (1, 1000, 20000));
    dual_at_zero_ulp(&d.join("build"), "sizes_expr_dual");

    let m = std::fs::read_to_string(d.join("legacy.toml")).unwrap();
    std::fs::write(d.join("legacy.toml"), m.replace("[param_names]\nmax_interaction = \"npmax*maxn\"\n", "")).unwrap();
    refused(&d, &["max_interaction", "[param_names]", "\"100*nmax\"", "build.log"]);
    // what is not an expression of names and numbers is refused by the manifest
    std::fs::write(d.join("legacy.toml"), m.replace("\"npmax*maxn\"", "\"npmax*maxn; x\"")).unwrap();
    refused(&d, &["param_names.max_interaction", "integer expression"]);
}
