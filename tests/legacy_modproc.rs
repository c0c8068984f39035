//! Legacy routines that live inside a Fortran module (`module sph_mod ... contains ... subroutine
//! int_force`): built, checked, called by the dual run, `run --legacy` and host mode as the same
//! routines built as external procedures are (docs/reference/legacy.md, "Routines in modules").

mod legacy_kit;
use legacy_kit::*;

/// The fixture's files whose routines the module variant puts inside `module sph_mod`.
const IN_MODULE: &[&str] = &["kernel.f", "direct_find.f", "density.f", "eos.f", "int_force.f", "art_visc.f"];

/// The fixture with the search, the kernel, the density, the EOS, the force and the artificial
/// viscosity as module procedures of one fixed-form file (`sph_mod.f`), their texts unchanged;
/// `single_step.f`, which calls them, `use`s the module. Built into `DIR/build`; returns DIR.
fn module_variant(name: &str) -> PathBuf {
    let d = variant(name, |m| m.to_string());
    let mut text =
        String::from("      module sph_mod\nc     the book's routines as module procedures\n      contains\n");
    for f in IN_MODULE {
        text.push_str(&std::fs::read_to_string(d.join(f)).unwrap());
        std::fs::remove_file(d.join(f)).unwrap();
    }
    text.push_str("      end module sph_mod\n");
    std::fs::write(d.join("sph_mod.f"), text).unwrap();
    let s = d.join("single_step.f");
    let old = std::fs::read_to_string(&s).unwrap();
    let new = old.replacen("      implicit none\n", "      use sph_mod\n      implicit none\n", 1);
    assert_ne!(new, old, "single_step.f uses the module");
    std::fs::write(&s, new).unwrap();
    build(&d.join("legacy.toml"), &d.join("build")).expect("the module variant builds");
    d
}

fn module_build() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| module_variant("modproc_book").join("build"))
}

/// The build records each routine's module and gfortran's symbol of a module procedure; the
/// routines outside the module stay external; `check --legacy` maps them.
#[test]
fn routines_in_a_module_are_built_with_their_module_and_symbol() {
    let info = blastsph::migration::BuildInfo::read(module_build()).unwrap();
    for name in ["direct_find", "kernel", "sum_density", "p_gas", "int_force", "art_visc"] {
        let r = info.routine(name).unwrap();
        assert_eq!(r.module.as_deref(), Some("sph_mod"), "{name}");
        assert_eq!(r.symbol, format!("__sph_mod_MOD_{name}"), "{name}");
    }
    let r = info.routine("av_vel").unwrap();
    assert_eq!((r.module.as_deref(), r.symbol.as_str()), (None, "av_vel_"));
    let shims = std::fs::read_to_string(module_build().join("obj/blastsph_shims.f90")).unwrap();
    assert!(shims.contains("  use sph_mod, only: int_force\n"), "the shim uses the module");
    assert!(!shims.contains("external int_force"), "and declares no external");
    // check --legacy maps them as it maps external routines
    let lg = module_build().to_str().unwrap().to_string();
    let so = blastsph_ok(&["check", "shock_tube", "--legacy", &lg, "--compat", "liu-book"], 0);
    assert!(so.contains("int_force      run      stands for eos.eval + force.internal"), "{so}");
}

/// The dual run with the book's profile: every legacy routine of the module at 0 ULP.
#[test]
fn the_dual_run_of_module_procedures_is_zero_ulp_with_the_books_profile() {
    let out = scratch("modproc_dual");
    let o = dual_book(module_build(), None, &out);
    let se = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{se}");
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    for (stage, fields) in MAPPED {
        for f in *fields {
            let r = row(&rows, stage, f);
            assert!(r["compared"].as_u64().unwrap() > 0, "{r}");
            assert_eq!((r["max_ulp"].as_u64(), r["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{r}");
        }
    }
}

/// `run --legacy` with the module's routines ends where the same routines built as external
/// procedures end, bit for bit, and where the fixture's own program ends.
#[test]
fn run_legacy_with_module_procedures_equals_the_external_build_bit_for_bit() {
    let m = assert_run_ends_as_the_program(module_build(), "modproc_run");
    let e = assert_run_ends_as_the_program(shared(), "modproc_run_external");
    let bits = |f: &blastsph::output::Frame| -> Vec<Vec<u64>> {
        [&f.x, &f.vx, &f.rho, &f.p, &f.e, &f.h].iter().map(|v| v.iter().map(|x| x.to_bits()).collect()).collect()
    };
    assert_eq!(m.id, e.id);
    assert_eq!(bits(&m), bits(&e));
    // the module variant's own program (its callers use the module) agrees with the fixture's
    let own = program_rows_of(module_build(), "modproc_program", 40);
    let b =
        |rows: &[Vec<f64>]| -> Vec<Vec<u64>> { rows.iter().map(|r| r.iter().map(|v| v.to_bits()).collect()).collect() };
    assert_eq!(b(&own), b(program_final_state()));
}

/// Host mode interposes `__sph_mod_MOD_<name>` as it does `<name>_`: the program's calls, the
/// module's own (direct_find and sum_density call the kernel inside the module) included.
#[test]
fn host_mode_interposes_module_procedures() {
    let out = scratch("modproc_host");
    let lg = module_build().to_str().unwrap().to_string();
    let o = blastsph_40_steps(&[
        "legacy",
        "host",
        "shock_tube",
        "--legacy",
        &lg,
        "--compat",
        "liu-book",
        "--out",
        out.to_str().unwrap(),
    ]);
    let (so, se) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert_eq!(o.status.code(), Some(0), "{so}{se}");
    assert!(so.contains("6 routines at 0 ULP at every compared call"), "{so}");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("host_report.json")).unwrap()).unwrap();
    // the kernel: once per pair from direct_find, once per particle from sum_density
    let k = &r["routines"]["kernel"];
    assert!(k["calls"].as_u64().unwrap() > 178_213, "{k}");
    assert_eq!(k["calls"], k["compared_calls"], "{k}");
    assert_eq!(r["routines"]["int_force"]["calls"], 40);
}

/// A free-form module of explicit-shape arrays whose size comes from another module, mapped as
/// a whole-array routine of module `eos` beside the fixture's `p_gas`.
fn eos90_variant(name: &str, text: &str) -> PathBuf {
    let d = variant(name, |t| {
        t.replace("sources = [\"*.f\"]", "sources = [\"*.f\", \"eos90.f90\"]").replace(
            "[[routine]]\nname = \"p_gas\"",
            "[[routine]]\nname = \"eos90\"\nmodule = \"eos\"\nargs = [\"ntotal\", \"rho\", \"u\", \"p\", \"c\"]\n\n[[routine]]\nname = \"p_gas\"",
        )
    });
    std::fs::write(d.join("eos90.f90"), text).unwrap();
    d
}

/// eos90 in module `name` (free form), its arrays declared `decl` (`nmax` from module sizes90).
fn eos90_module(name: &str, decl: &str) -> String {
    format!(
        "module {name}
  use sizes90, only: nmax
  implicit none
contains
  subroutine eos90(n, dens, ene, pr, cs)
    integer, intent(in) :: n
    double precision, intent(in) :: {decl}
    double precision, intent(out) :: pr(nmax), cs(nmax)
    integer :: i
    do i = 1, n
      pr(i) = 0.4d0*dens(i)*ene(i)
      cs(i) = sqrt(0.4d0*ene(i))
    end do
  end subroutine eos90
end module {name}
"
    )
}

const SIZES90: &str = "module sizes90\n  implicit none\n  integer, parameter :: nmax = 1000\nend module sizes90\n";

#[test]
fn a_free_form_module_procedure_is_called_through_its_module() {
    let d = eos90_variant("modproc_eos90", &format!("{SIZES90}{}", eos90_module("eosmod", "dens(nmax), ene(nmax)")));
    build(&d.join("legacy.toml"), &d.join("build")).expect("builds");
    let lib = LegacyLib::open(&d.join("build")).unwrap();
    let info = lib.info().routine("eos90").unwrap().clone();
    assert_eq!((info.module.as_deref(), info.symbol.as_str()), (Some("eosmod"), "__eosmod_MOD_eos90"));
    let n = 7;
    let rho: Vec<f64> = (0..n).map(|i| 1.0 + 0.37 * i as f64).collect();
    let u: Vec<f64> = (0..n).map(|i| 2.5 - 0.11 * i as f64).collect();
    let (mut p, mut c, mut nt) = (vec![0.0; n], vec![0.0; n], [n as i32]);
    let (mut r2, mut u2) = (rho.clone(), u.clone());
    let mut a = blastsph::migration::Args::new()
        .int("ntotal", &mut nt)
        .real("rho", &mut r2)
        .real("u", &mut u2)
        .real("p", &mut p)
        .real("c", &mut c);
    lib.routine("eos90").unwrap().call(&mut a).unwrap();
    let wp: Vec<f64> = (0..n).map(|i| 0.4 * rho[i] * u[i]).collect();
    let wc: Vec<f64> = (0..n).map(|i| (0.4 * u[i]).sqrt()).collect();
    same_bits("p", &p, &wp);
    same_bits("c", &c, &wc);
}

/// Refused in one line: an assumed-shape dummy of a module procedure (named with its routine),
/// a routine that two modules define (both named), and a private module procedure.
#[test]
fn assumed_shape_dummies_and_a_routine_in_two_modules_are_refused() {
    let d = eos90_variant("modproc_assumed", &format!("{SIZES90}{}", eos90_module("eosmod", "dens(:), ene(nmax)")));
    refused(&d, &["routine eos90", "dummy `dens`", "assumed-shape"]);
    let two = format!(
        "{SIZES90}{}{}",
        eos90_module("eosmod", "dens(nmax), ene(nmax)"),
        eos90_module("eosmod2", "dens(nmax), ene(nmax)")
    );
    let d = eos90_variant("modproc_twice", &two);
    refused(&d, &["routine eos90", "defined twice", "module eosmod", "module eosmod2"]);
    let private = eos90_module("eosmod", "dens(nmax), ene(nmax)").replace("contains\n", "  private\ncontains\n");
    let d = eos90_variant("modproc_private", &format!("{SIZES90}{private}"));
    refused(&d, &["routine eos90", "private procedure of module eosmod", "__eosmod_MOD_eos90"]);
}
