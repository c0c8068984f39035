//! A legacy code with the book's physical viscosity (param.inc's `visc`, the routines `viscosity`
//! and `int_force`): the fixture's gas given η = 1.0e-4 Pa s (param.inc's `eta_gas`, a
//! default-real literal as the book's water's 1.0e-3 is), the case's gas
//! `dynamic_viscosity_pa_s = 1.0e-4`, which the item `literals` rounds the same way. `int_force` stands for `eos.eval` and `force.internal`
//! of the book's profile, whose force then adds the viscous terms in the book's order; the dual
//! run compares them at 0 ULP, and `run --legacy` ends in the state of the variant's own program,
//! bit for bit.

mod legacy_kit;
use legacy_kit::*;

/// The manifest's entry of `viscosity`.
const ENTRY: &str = "
[[routine]]
name = \"viscosity\"
module = \"force\"
args = [\"ntotal\", \"itype\", \"x\", \"rho\", \"eta\"]
";

/// The fixture with `visc = .true.`, the gas at η = 1.0e-4 Pa s and `viscosity` mapped, built
/// into DIR/build; returns DIR.
fn visc_variant(name: &str) -> PathBuf {
    let d = variant(name, |m| format!("{m}{ENTRY}"));
    let f = d.join("param.inc");
    let text = std::fs::read_to_string(&f).unwrap();
    let mut new = text.clone();
    for (from, to) in [
        ("parameter (visc              = .false.)", "parameter (visc              = .true.)"),
        ("parameter (eta_gas = 0.d0)", "parameter (eta_gas = 1.0e-4)"),
    ] {
        assert!(new.contains(from), "{from}");
        new = new.replace(from, to);
    }
    std::fs::write(&f, new).unwrap();
    build(&d.join("legacy.toml"), &d.join("build")).expect("the viscous variant builds");
    d
}

/// cases/shock_tube.toml with the gas at η = 1.0e-4 Pa s, written into `dir`.
fn visc_case(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(root().join("cases/shock_tube.toml")).unwrap();
    let line = "eos = { kind = \"ideal_gas\", gamma = 1.4 }\n";
    assert!(text.contains(line));
    let p = dir.join("shock_tube_visc.toml");
    std::fs::write(&p, text.replace(line, &format!("{line}dynamic_viscosity_pa_s = 1.0e-4\n"))).unwrap();
    p
}

#[test]
fn the_books_physical_viscosity_is_compared_at_zero_ulp_and_run_as_its_program_runs() {
    let d = visc_variant("visc");
    let (b, case) = (d.join("build"), visc_case(&d));
    let (bs, cs) = (b.to_str().unwrap(), case.to_str().unwrap());
    // check: int_force stands for the force with the viscous terms, the 2/3 in single precision
    let so = blastsph_ok(&["check", cs, "--legacy", bs, "--compat", "liu-book"], 0);
    assert!(so.contains("physical viscosity"), "{so}");
    assert!(so.contains(&format!("2/3 = {}", f64::from(2.0f32 / 3.0f32))), "{so}");
    // the case's η rounded to single precision by `literals`, as param.inc's literal is
    assert!(so.contains(&format!("eta = [{:?}]", f64::from(1.0e-4f32))), "{so}");
    // dual: every mapped routine at 0 ULP over the 40 steps, int_force's rates with the viscosity
    let out = d.join("dual");
    let so = blastsph_ok(&["dual", cs, "--legacy", bs, "--compat", "liu-book", "--out", out.to_str().unwrap()], 0);
    assert!(so.contains("40 steps compared; every compared stage within tolerance"), "{so}");
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    for (stage, fields) in MAPPED {
        for f in *fields {
            let x = row(&rows, stage, f);
            assert!(x["compared"].as_u64().unwrap() > 0, "{x}");
            assert_eq!((x["max_ulp"].as_u64(), x["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{stage} {f}: {x}");
        }
    }
    // the viscosity changes the program's end state, and run --legacy ends in it
    let prog = program_rows_of(&b, "visc_program", 40);
    let plain = program_final_state();
    let moved = (0..prog.len()).filter(|&i| prog[i][3] != plain[i][3]).count();
    assert!(moved > 0, "the viscosity changes no particle's velocity");
    eprintln!("the viscosity moved the velocity of {moved} of {} particles", prog.len());
    assert_run_ends_as(&b, cs, "liu-book", &prog, "visc_run");
}

/// The physical viscosity in axisymmetric geometry, and a negative η: each refused in one line,
/// exit status 2.
#[test]
fn misplaced_physical_viscosity_is_refused_in_one_line() {
    for (case, set, needle) in [
        ("cases/underwater_tnt_rz.toml", "material.water.dynamic_viscosity_pa_s=1.0e-3", "axisymmetric"),
        ("cases/shock_tube.toml", "material.gas.dynamic_viscosity_pa_s=-1.0", "dynamic_viscosity_pa_s"),
    ] {
        let o = blastsph(&["check", case, "--set", set]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{set}: {err}");
        assert!(err.contains(needle) && err.lines().count() == 1, "{set}: {err}");
    }
}
