//! A legacy code whose `ext_force` adds gravity as well as the boundary repulsion, as Liu and
//! Liu's does: the manifest's `includes_gravity` makes `run --legacy` end in the state of the
//! code's own program, bit for bit, and without it gravity is counted twice.

mod legacy_kit;
use legacy_kit::*;

const CALL: &str = "      call ext_force(ntotal + nvirt, mass, x, niac, pair_i, pair_j,
     &               itype, hsml, exdvxdt)

";

/// The manifest's entry of `ext_force` mapped to `module`, with `extra` after it.
fn entry(module: &str, extra: &str) -> String {
    format!(
        "\n[[routine]]\nname = \"ext_force\"\nmodule = \"{module}\"\n{extra}args = [\"ntotal\", \"mass\", \"x\", \"niac\", \"pair_i\", \"pair_j\", \"itype\", \"hsml\", \"dvxdt\"]\n"
    )
}

/// The fixture with the gravity `ext_force` called after `art_visc`, its manifest entry mapped
/// to `module` with `extra`, built into DIR/build; returns DIR.
fn gravity_variant(name: &str, module: &str, extra: &str) -> PathBuf {
    let d = variant(name, |m| format!("{m}{}", entry(module, extra)));
    // the book's ext_force: gravity, then the repulsion with r0 = 1.25e-5 m
    std::fs::write(d.join("ext_force.f"), ext_force_f(true, "1.25d-5", "1.d-2")).unwrap();
    let f = d.join("single_step.f");
    let text = std::fs::read_to_string(&f).unwrap();
    let at = "      if (sle .ne. 0) call h_upgrade";
    assert!(text.contains(at));
    std::fs::write(&f, text.replace(at, &format!("{CALL}{at}"))).unwrap();
    build(&d.join("legacy.toml"), &d.join("build")).expect("the gravity variant builds");
    d
}

/// cases/shock_tube.toml with the book's gravity, -9.8 m/s² along x, and `more`, written into
/// `dir`.
fn gravity_case_with(dir: &Path, more: &str) -> PathBuf {
    let text = std::fs::read_to_string(root().join("cases/shock_tube.toml")).unwrap();
    let p = dir.join("shock_tube_gravity.toml");
    std::fs::write(&p, format!("{text}\n[physics]\ngravity_ms2 = [-9.8]\n{more}")).unwrap();
    p
}

fn gravity_case(dir: &Path) -> PathBuf {
    gravity_case_with(dir, "")
}

#[test]
fn a_code_whose_ext_force_adds_gravity_is_run_by_blastsph_as_its_program_runs() {
    let d = gravity_variant("gravity", "force", "includes_gravity = true\n");
    let b = d.join("build");
    let case = gravity_case(&d);
    let case = case.to_str().unwrap();
    let prog = program_rows_of(&b, "gravity_program", 40);
    // check says the rate sum leaves gravity to the routine
    let so = blastsph_ok(&["check", case, "--legacy", b.to_str().unwrap(), "--compat", "liu-book"], 0);
    assert!(so.contains("gravity left to the force stage"), "{so}");
    assert!(so.contains("legacy.ext_force"), "{so}");
    assert_run_ends_as(&b, case, "liu-book", &prog, "gravity_run");
}

#[test]
fn without_includes_gravity_the_run_counts_gravity_twice() {
    let d = gravity_variant("gravity_twice", "force", "");
    let b = d.join("build");
    let case = gravity_case(&d);
    let prog = program_rows_of(&b, "gravity_twice_program", 40);
    let out = scratch("gravity_twice_run");
    let args = ["run", case.to_str().unwrap(), "--legacy", b.to_str().unwrap(), "--compat", "liu-book"];
    blastsph_ok(&[&args[..], &["--out", out.to_str().unwrap(), "--quiet"]].concat(), 0);
    let frames = blastsph::output::read_frames(&out.join("particles.h5")).expect("particles.h5");
    let f = frames.last().unwrap();
    let differ = (0..f.x.len()).filter(|&i| f.vx[i] != prog[f.id[i] as usize][3]).count();
    assert!(differ > 0, "the run without the key ends as the program");
}

#[test]
fn against_the_wall_force_twin_the_dual_says_why_the_rows_differ() {
    let d = gravity_variant("gravity_wall", "boundary", "includes_gravity = true\n");
    let b = d.join("build");
    // a wall far from the tube: the boundary module runs, its force is zero on every particle
    let case = gravity_case_with(&d, "\n[[wall]]\nfrom_m = [-5.0]\nto_m = [-5.0]\nkind = \"repulsive\"\n");
    let out = scratch("gravity_wall_dual");
    let mut args = dual_book_args(&b, Some(2), &out);
    args[1] = case.to_str().unwrap().to_string();
    let so = blastsph_ok(&args, 4);
    let row = so.lines().find(|l| l.starts_with("legacy.ext_force ")).unwrap_or_else(|| panic!("{so}"));
    assert!(row.contains("legacy -9.8e0, rust 0e0") && row.contains("includes gravity"), "{row}");
}

#[test]
fn includes_gravity_on_a_routine_that_is_not_a_force_is_refused() {
    let d = variant("gravity_bad", |m| {
        let old = "module = \"viscosity\"\n";
        assert!(m.contains(old));
        m.replace(old, &format!("{old}includes_gravity = true\n"))
    });
    refused(&d, &["art_visc", "includes_gravity", "viscosity"]);
}

#[test]
fn gravity_in_forces_without_a_legacy_build_is_refused() {
    let d = scratch("gravity_in_forces_alone");
    let case = gravity_case_with(&d, "gravity_in_forces = true\n");
    let (case, run) = (case.to_str().unwrap(), d.join("run"));
    for args in [vec!["check", case], vec!["run", case, "--out", run.to_str().unwrap()]] {
        let (cmd, out) = (args[0], blastsph(&args));
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{cmd}: {err}");
        assert!(err.contains("gravity_in_forces") && err.lines().count() == 1, "{cmd}: {err}");
    }
}

/// With `[boundary] repulsion` and a held boundary particle, the book's `ext_force` mapped to
/// `force` stands for `boundary.repulsion`, which adds the gravity itself under
/// `physics.gravity_in_forces`: its row is at 0 ULP, a particle pushed among those compared. The
/// boundary particle lies 1.1e-5 m beyond a lone gas particle past the tube, within the fixture's
/// r0, 1.25e-5 m.
#[test]
fn against_the_repulsion_twin_the_gravity_ext_force_is_at_zero_ulp() {
    let d = gravity_variant("gravity_repulsion", "force", "includes_gravity = true\n");
    let b = d.join("build");
    let lattice = |name: &str, x: f64, held: bool| {
        format!(
            "\n[[region]]\nname = \"{name}\"\nmaterial = \"gas\"\nshape = \"lattice\"\norigin_m = [{x}]\ncount = [1]\nspacing_m = 1e-5\nrho_kgm3 = 0.25\ne_jkg = 1.795\nmass_kg = 0.001875\nh_m = 1e-3\n{}",
            if held { "boundary_particles = \"held\"\n" } else { "" }
        )
    };
    let more = format!(
        "\n[boundary]\nrepulsion = {{ r0_m = 1.25e-5, d_m2s2 = 1e-2 }}\n{}{}",
        lattice("lone", 0.65, false),
        lattice("end", 0.650011, true)
    );
    let case = gravity_case_with(&d, &more);
    let so = blastsph_ok(&["check", case.to_str().unwrap(), "--legacy", b.to_str().unwrap()], 0);
    assert!(so.contains("boundary.repulsion") && so.contains("legacy.ext_force"), "{so}");
    let out = scratch("gravity_repulsion_dual");
    let mut args: Vec<String> = dual_book_args(&b, Some(2), &out);
    args[1] = case.to_str().unwrap().to_string();
    args.retain(|a| a != "--compat" && a != "liu-book");
    let o = blastsph(&args);
    assert!(matches!(o.status.code(), Some(0 | 4)), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(out.join("dual_report.json")).expect("dual_report.json");
    let rep: serde_json::Value = serde_json::from_str(&text).unwrap();
    let rows = rep["rows"].as_array().unwrap();
    let ext: Vec<_> = rows.iter().filter(|r| r["stage"] == "legacy.ext_force").collect();
    assert!(!ext.is_empty(), "no ext_force row: {text}");
    for r in ext {
        assert_eq!(r["max_ulp"].as_u64(), Some(0), "{r}");
        assert!(r["compared"].as_u64().unwrap_or(0) > 0, "{r}");
    }
}
