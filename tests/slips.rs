//! Scale slips (src/case/slips.rs): `check` and `run` refuse, in one line with exit status 2, a
//! case in millimetres, a density in g/cm³ and a charge mass no blast in soil or water has; they
//! warn of a charge that touches no soil in a scene that measures a crater. None of these fires
//! on a shipped case or on the README's complete case.

mod common;

use std::path::Path;
use std::process::{Command, Output};

fn blastsph(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_blastsph")).args(args).current_dir(common::root()).output().expect("blastsph")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// A buried TNT charge in RZ (the shape of cases/buried_tnt_rz.toml, 2 cm rings) with every
/// length × `s` and the charge's top `lift` m above where it is buried (0: buried 0.2 m).
fn rz_charge(s: f64, lift: f64) -> String {
    let (c0, c1) = (0.7 + lift, 0.8 + lift);
    let top = if lift > 0.0 { 1.0 + lift + 0.2 } else { 1.0 };
    common::rz_charge_case(&common::RzCharge {
        name: "slip",
        end_s: 1.0e-4,
        output_s: 5.0e-5,
        charge_r: 0.06 * s,
        charge_z: (c0 * s, c1 * s),
        block: (1.0 * s, 1.0 * s),
        wall_top: top * s,
        spacing: 0.02 * s,
        det_z: 0.75 * s + lift * s,
        gauge_z: None,
    })
}

fn write(dir: &Path, name: &str, body: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, body).unwrap();
    p.to_str().unwrap().to_string()
}

/// `check` of `case` with `--set`s: (exit status, stdout + stderr).
fn check(case: &str, sets: &[&str]) -> (Option<i32>, String, String) {
    let mut a = vec!["check", case];
    for s in sets {
        a.extend(["--set", s]);
    }
    let o = blastsph(&a);
    (o.status.code(), text(&o.stdout), text(&o.stderr))
}

/// Refused: exit 2, one line on stderr starting `error: ` and holding `want`.
fn refused(case: &str, sets: &[&str], want: &str) {
    let (code, out, err) = check(case, sets);
    assert_eq!(code, Some(2), "{sets:?}: stdout {out}\nstderr {err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with("error: ") && err.contains(want), "{sets:?}: {err}");
}

/// The same case in metres passes; in millimetres it is refused by `check` and by `run`
/// (which then writes nothing).
#[test]
fn a_case_in_millimetres_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let metres = write(dir.path(), "m.toml", &rz_charge(1.0, 0.0));
    let (code, out, err) = check(&metres, &[]);
    assert_eq!(code, Some(0), "{out}{err}");
    let mm = write(dir.path(), "mm.toml", &rz_charge(1000.0, 0.0));
    refused(&mm, &[], "lengths in millimetres?");
    let out = dir.path().join("run");
    let o = blastsph(&["run", &mm, "--out", out.to_str().unwrap(), "--quiet"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert_eq!(text(&o.stderr).lines().count(), 1, "{}", text(&o.stderr));
    assert!(!out.join("particles.h5").exists());
}

/// A density in g/cm³, of a material's EOS or of a region, is refused (no longer a warning).
#[test]
fn a_density_in_grams_per_cubic_centimetre_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let case = write(dir.path(), "m.toml", &rz_charge(1.0, 0.0));
    refused(&case, &["material.sand.eos.rho0_kgm3=1.65"], "a density in g/cm³?");
    refused(&case, &["material.tnt.eos.rho0_kgm3=1.63"], "a density in g/cm³?");
    refused(&case, &["region.soil.rho_kgm3=1.65"], "a density in g/cm³?");
    // a light soil at 1200 kg/m³ is no slip
    let (code, out, err) = check(&case, &["material.sand.eos.rho0_kgm3=1200"]);
    assert_eq!(code, Some(0), "{out}{err}");
}

/// A charge mass off any blast's range for its scene is refused, naming the mass: a charge of
/// 2 × 2 rings of 1 mm (41 mg), and a charge that fills most of its scene (a cylinder 0.9 m
/// across in a 1 m block); the case's own 1.84 kg passes.
#[test]
fn a_charge_mass_off_any_plausible_range_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let case = write(dir.path(), "m.toml", &rz_charge(1.0, 0.0));
    let (code, out, err) = check(&case, &[]);
    assert_eq!(code, Some(0), "{out}{err}");
    refused(
        &case,
        &["region.charge.spacing_m=0.001", "region.charge.hi_m=[0.002, 0.702]", "detonation.point_m=[0.001, 0.701]"],
        "the explosive holds 4.0966e-5 kg, outside any blast in soil or water",
    );
    refused(
        &case,
        &["region.charge.lo_m=[0.0, 0.05]", "region.charge.hi_m=[0.9, 0.95]", "detonation.point_m=[0.01, 0.5]"],
        "the explosive fills 73 % of the scene's volume",
    );
}

/// A charge lifted 0.6 m off the soil in a crater scene: a warning naming the gap (not a
/// refusal); buried, no such line.
#[test]
fn a_charge_that_touches_no_soil_is_warned_of_with_its_gap() {
    let dir = tempfile::tempdir().unwrap();
    let buried = write(dir.path(), "m.toml", &rz_charge(1.0, 0.0));
    let (code, out, err) = check(&buried, &[]);
    assert_eq!(code, Some(0), "{out}{err}");
    assert!(!out.contains("touches no soil"), "{out}");
    let lifted = write(dir.path(), "air.toml", &rz_charge(1.0, 0.5));
    let (code, out, err) = check(&lifted, &[]);
    assert_eq!(code, Some(0), "{out}{err}");
    let line = out.lines().find(|l| l.contains("touches no soil or water")).unwrap_or_else(|| panic!("{out}"));
    assert!(line.starts_with("warning: "), "{line}");
    // the charge's bottom ring at 1.21 m, the soil's top ring at 0.99 m: 0.22 m apart centre
    // to centre, a gap of 0.20 m (10 spacings) beyond a 2 cm ring
    assert!(line.contains("0.2000 m (10.0 spacings)"), "{line}");
}

/// Every shipped case (cases/**.toml) and every complete case in the docs (a ```toml block of
/// README.md or docs/ with `dim =` and a `[[region]]`) pass `check` with none of the slips above.
#[test]
fn no_slip_fires_on_a_shipped_case_or_a_docs_case() {
    let mut cases: Vec<String> = glob::glob(common::root().join("cases/**/*.toml").to_str().unwrap())
        .unwrap()
        .map(|p| p.unwrap().to_str().unwrap().to_string())
        .collect();
    assert!(cases.len() > 40, "{cases:?}");
    let mut docs = vec![common::root().join("README.md")];
    docs.extend(glob::glob(common::root().join("docs/**/*.md").to_str().unwrap()).unwrap().map(|p| p.unwrap()));
    let dir = tempfile::tempdir().unwrap();
    let mut blocks = 0;
    for d in &docs {
        let text = std::fs::read_to_string(d).unwrap();
        for (k, piece) in text.split("```toml\n").skip(1).enumerate() {
            let block = &piece[..piece.find("```").unwrap()];
            if block.contains("dim =") && block.contains("[[region]]") {
                blocks += 1;
                let name = format!("doc{blocks}_{k}.toml");
                let body =
                    if block.contains("name =") { block.to_string() } else { format!("name = \"doc\"\n{block}") };
                cases.push(write(dir.path(), &name, &body));
            }
        }
    }
    assert!(blocks >= 1, "no complete case found in the docs");
    for c in &cases {
        let (code, out, err) = check(c, &[]);
        assert_eq!(code, Some(0), "{c}: {out}{err}");
        for slip in ["touches no soil", "g/cm³", "millimetres", "the explosive holds", "the explosive fills"] {
            assert!(!out.contains(slip) && !err.contains(slip), "{c}: {slip}: {out}{err}");
        }
    }
}
