//! A legacy EOS of ρ alone, the book's `p_art_water(rho, p, c)` in its Tait form
//! p = B ((ρ/ρ0)^γ − 1), c constant: where every material of the case is Tait water (an EOS that
//! does not read e), the routine stands for `eos.eval`, and the dual run compares it at 0 ULP.

mod legacy_kit;
use legacy_kit::*;

/// The book's artificial water in the fixture's dialect, with constants a 1D tube can carry:
/// ρ0 = 1000 kg/m³, B = 1 Pa, γ = 7, c = 1 m/s (each exact in single precision).
const TAIT: &str = "      subroutine p_art_water(rho, p, c)
c-----------------------------------------------------------------------
c     Artificial equation of state of water (Tait form):
c     p = b ((rho/rho0)**gamma - 1), with a constant sound speed c.
c-----------------------------------------------------------------------
      implicit none
      double precision rho, p, c
      double precision gamma, rho0, b

      gamma = 7.
      rho0 = 1000.
      b = 1.
      p = b*((rho/rho0)**gamma - 1)
      c = 1.

      end
";

/// The manifest's entry of `p_art_water`, called particle by particle.
const ENTRY: &str = "
[[routine]]
name = \"p_art_water\"
module = \"eos\"
call = \"each_particle\"
args = [\"rho\", \"p\", \"c\"]
";

/// Removes the `[[routine]]` entry named `name` from a manifest.
fn without(m: &str, name: &str) -> String {
    let parts: Vec<&str> = m.split("[[routine]]").collect();
    let mut out = parts[0].to_string();
    for p in &parts[1..] {
        if !p.trim_start().starts_with(&format!("name = \"{name}\"")) {
            out += "[[routine]]";
            out += p;
        }
    }
    assert_ne!(out, m, "no entry {name}");
    out
}

/// The fixture with `source` in place of its p_art_water, mapped, built into NAME/build; no
/// set-up routine (the case's particles) and no p_gas (the case has no ideal gas). The shock
/// tube's gas as water of the EOS `eos` (a case's `eos = ...` line), given the book's code 2,
/// written into NAME/NAME.toml: the folder and the case.
fn water_variant(name: &str, source: &str, eos: &str) -> (PathBuf, PathBuf) {
    let d = variant(name, |m| format!("{}{ENTRY}", without(&without(m, "input"), "p_gas")));
    let eos_f = d.join("eos.f");
    let text = std::fs::read_to_string(&eos_f).unwrap();
    let at = text.find("      subroutine p_art_water").expect("the fixture's p_art_water");
    std::fs::write(&eos_f, format!("{}{source}", &text[..at])).unwrap();
    build(&d.join("legacy.toml"), &d.join("build")).expect("the water variant builds");
    let tube = std::fs::read_to_string(root().join("cases/shock_tube.toml")).unwrap();
    let gas = "eos = { kind = \"ideal_gas\", gamma = 1.4 }";
    let analysis = tube.find("[analysis]").expect("the tube's analysis");
    let case = d.join(format!("{name}.toml"));
    let mut text = tube[..analysis].replace(gas, eos);
    // water at 1000 kg/m³ on the left, 1005 on the right (a pressure step of 0.036 Pa)
    for (from, to) in [
        ("rho_kgm3 = 1.0\ne_jkg = 2.5\nmass_kg = 0.001875", "rho_kgm3 = 1000.0\ne_jkg = 2.5\nmass_kg = 1.875"),
        ("rho_kgm3 = 0.25\ne_jkg = 1.795\nmass_kg = 0.001875", "rho_kgm3 = 1005.0\ne_jkg = 1.795\nmass_kg = 7.5375"),
    ] {
        assert!(text.contains(from), "{from}");
        text = text.replace(from, to);
    }
    std::fs::write(&case, text).unwrap();
    (d, case)
}

/// The dual run of `case` on BUILD, 40 steps: p_art_water and int_force (which calls it for
/// itype 2) at 0 ULP.
fn dual_at_zero_ulp(b: &Path, case: &Path, out: &Path) {
    let mut args = dual_book_args(b, None, out);
    args[1] = case.to_str().unwrap().to_string();
    let so = blastsph_ok(&args, 0);
    assert!(so.contains("40 steps compared; every compared stage within tolerance"), "{so}");
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    for (stage, field) in [
        ("legacy.p_art_water", "p"),
        ("legacy.p_art_water", "c"),
        ("legacy.int_force", "p"),
        ("legacy.int_force", "acc"),
    ] {
        let x = row(&rows, stage, field);
        assert!(x["compared"].as_u64().unwrap() > 0, "{x}");
        assert_eq!((x["max_ulp"].as_u64(), x["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{stage} {field}: {x}");
    }
}

#[test]
fn a_tait_eos_of_rho_alone_stands_for_the_eos_and_is_compared_at_zero_ulp() {
    let tait = "eos = { kind = \"tait\", rho0_kgm3 = 1000.0, b_pa = 1.0, gamma = 7.0, c_ms = 1.0 }";
    let (d, case) = water_variant("tait", TAIT, tait);
    let (b, cs) = (d.join("build"), case.to_str().unwrap().to_string());
    let so = blastsph_ok(&["check", &cs, "--legacy", b.to_str().unwrap(), "--compat", "liu-book"], 0);
    let line = so.lines().find(|l| l.trim_start().starts_with("p_art_water ")).unwrap_or_else(|| panic!("{so}"));
    assert!(line.contains(" run ") && line.contains("stands for eos.eval"), "{line}");
    assert!(!so.contains("warning: legacy p_art_water"), "{so}");
    // the ideal-gas tube with a density clamp: the routine cannot stand for the gas's EOS (it
    // reads e), and the clamp, which corrects the ρ any routine holds, is no module to suggest
    let so = blastsph_ok(
        &["check", "shock_tube", "--legacy", b.to_str().unwrap(), "--set", "sph.density_clamp=[0.1, 10.0]"],
        0,
    );
    let line = so.lines().find(|l| l.trim_start().starts_with("p_art_water ")).unwrap_or_else(|| panic!("{so}"));
    assert!(line.contains("not run") && line.contains("eos.eval reads e"), "{line}");
    assert!(!line.contains("integrator"), "{line}");
    // dual: p_art_water and int_force (which calls it for itype 2) at 0 ULP over 40 steps
    dual_at_zero_ulp(&b, &case, &scratch("tait_dual"));
}

/// The book's active form of p_art_water (Morris's), c = 0.01 a single-precision literal.
const MORRIS: &str = "      subroutine p_art_water(rho, p, c)
c-----------------------------------------------------------------------
c     Artificial equation of state of water (Morris's form):
c     p = c**2 rho, with a constant sound speed c.
c-----------------------------------------------------------------------
      implicit none
      double precision rho, p, c

      c = 0.01
      p = c**2*rho

      end
";

/// The case writes c = 0.01 as the code does; the book's profile (its item `literals`) rounds it
/// to single precision.
#[test]
fn the_books_morris_form_is_compared_at_zero_ulp_with_the_morris_kind() {
    let morris = "eos = { kind = \"morris\", rho0_kgm3 = 1000.0, c_ms = 0.01 }";
    let (d, case) = water_variant("morris", MORRIS, morris);
    dual_at_zero_ulp(&d.join("build"), &case, &scratch("morris_dual"));
}
