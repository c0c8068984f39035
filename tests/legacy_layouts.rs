//! Bring your own legacy code, part 3 (docs/howto/migrate.md): legacy codes of other layouts
//! (a soil strength code, initialisers, common blocks and modules, one array per component,
//! a density-and-force routine) run by blastsph and dual-checked against the Rust twins.

mod legacy_kit;
use legacy_kit::*;

/// The strength routines of a thesis-style soil code (tests/legacy_strength/: a plane-strain
/// strain and Jaumann stress rate with 4 stress components, and a Drucker–Prager return): the dual
/// run compares them with `strength.rates` and `strength.yield` at 0 ULP (before, the stress was
/// never allocated when its routines were legacy: the dual run panicked, and `run --legacy` ran
/// the soil without strength, exit 0), the stress rate included on a case with mirrors (it was
/// dropped there: its rows end at the real particles); `run --legacy` keeps the stress and ends
/// in blastsph's own state bit for bit; a wrong sign of the rotation term is found and named.
#[test]
fn a_legacy_soil_strength_code_runs_and_is_compared() {
    let d = strength_fixture("strength");
    build(&d.join("legacy.toml"), &d.join("build")).expect("the strength fixture builds");
    let (lg, case) = (d.join("build"), "cases/hard/soil_spall.toml");
    let out = d.join("dual");
    let o =
        blastsph(&["dual", case, "--legacy", lg.to_str().unwrap(), "--steps", "20", "--out", out.to_str().unwrap()]);
    let (so, se) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert_eq!(o.status.code(), Some(0), "{so}{se}");
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    for (stage, field) in [
        ("legacy.strain_rate", "eps"),
        ("legacy.strain_rate", "rot"),
        ("legacy.strain_rate", "dtau"),
        ("legacy.strain_rate", "dde"),
        ("legacy.dp_yield", "tau"),
    ] {
        let r = row(&rows, stage, field);
        assert!(r["compared"].as_u64().unwrap() > 0 && r["max_ulp"].as_u64() == Some(0), "{r}");
    }
    // the run: the stress is kept, and is blastsph's own, bit for bit
    let (a, b) = (d.join("run_legacy"), d.join("run_rust"));
    for (dir, leg) in [(&a, true), (&b, false)] {
        let mut args = vec!["run", case, "--end-time", "1e-4", "--quiet", "--out", dir.to_str().unwrap()];
        if leg {
            args.extend(["--legacy", lg.to_str().unwrap()]);
        }
        let o = blastsph(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let read = |dir: &Path| last_frame(dir, &["sxx", "sxy", "vy"]);
    let (ra, rb) = (read(&a), read(&b));
    assert!(rb[0].iter().any(|&s| s.abs() > 1.0), "the soil carries a deviatoric stress");
    for k in 0..3 {
        assert!(ra[k].iter().zip(&rb[k]).all(|(x, y)| x.to_bits() == y.to_bits()), "field {k}");
    }
    // a defect: the rotation term of the shear rate with the wrong sign
    let f = d.join("strain.f");
    let t = std::fs::read_to_string(&f).unwrap();
    let bad = t.replacen("- sxx(i)*rxy(i) + rxy(i)*syy(i)", "+ sxx(i)*rxy(i) + rxy(i)*syy(i)", 1);
    assert_ne!(bad, t);
    std::fs::write(&f, bad).unwrap();
    build(&d.join("legacy.toml"), &d.join("bad")).expect("the variant builds");
    let out = d.join("dual_bad");
    let o = blastsph(&[
        "dual",
        case,
        "--legacy",
        d.join("bad").to_str().unwrap(),
        "--steps",
        "5",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", String::from_utf8_lossy(&o.stderr));
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    let r = row(&rows, "legacy.strain_rate", "dtau");
    assert!(r["out_of_tolerance"].as_u64().unwrap() > 0, "{r}");
    assert!(r["first_divergence"]["at"].as_str().unwrap().contains("xy component"), "the xy component: {r}");
}

/// A copy of the soil-strength fixture (tests/legacy_strength) in scratch folder `name`.
fn strength_fixture(name: &str) -> PathBuf {
    let d = scratch(name);
    for e in std::fs::read_dir(root().join("tests/legacy_strength")).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, d.join(p.file_name().unwrap())).unwrap();
    }
    d
}

/// A code whose constants live in a COMMON block that its own initialiser fills (here the
/// strength fixture's G, α_φ and k, moved from PARAMETERs into `common /soil/` and set by a
/// `soil_init` with no arguments): mapped as `module = "init"`, the routine is called once before
/// the first step, and the dual run agrees at 0 ULP with no other change to the sources; without
/// the mapping the block stays zero and the dual run finds the strength rates wrong.
#[test]
fn a_legacy_initialiser_fills_its_common_blocks_before_the_first_step() {
    let d = strength_fixture("init_common");
    let inc = "c     soil.inc -- the soil's constants, set by soil_init\n      double precision gmod, alphi, coh\n      common /soil/ gmod, alphi, coh\n";
    std::fs::write(d.join("soil.inc"), inc).unwrap();
    let init = "      subroutine soil_init\n      implicit none\n      include 'soil.inc'\n      gmod = 63.58d6\n      alphi = 0.25d0\n      coh = 200.d0\n      return\n      end\n";
    std::fs::write(d.join("soilini.f"), init).unwrap();
    let m = std::fs::read_to_string(d.join("legacy.toml")).unwrap();
    let with_init = format!("{m}\n[[routine]]\nname = \"soil_init\"\nmodule = \"init\"\nargs = []\n");
    let case = "cases/hard/soil_spall.toml";
    for (name, manifest, code) in [("with", with_init.as_str(), 0), ("without", m.as_str(), 4)] {
        std::fs::write(d.join("legacy.toml"), manifest).unwrap();
        let lg = d.join(format!("build_{name}"));
        build(&d.join("legacy.toml"), &lg).expect("the variant builds");
        let out = d.join(format!("dual_{name}"));
        let args = ["dual", case, "--legacy", lg.to_str().unwrap(), "--steps", "5", "--out", out.to_str().unwrap()];
        let so = blastsph_ok(&args, code);
        let (_, rows) = report_rows(&out.join("dual_report.json"));
        let r = row(&rows, "legacy.strain_rate", "dtau");
        if code == 0 {
            assert!(r["compared"].as_u64().unwrap() > 0 && r["max_ulp"].as_u64() == Some(0), "{r}");
            let plan = blastsph_ok(&["check", case, "--legacy", lg.to_str().unwrap()], 0);
            assert!(plan.lines().any(|l| l.contains("soil_init") && l.contains("init")), "{plan}");
        } else {
            assert!(r["out_of_tolerance"].as_u64().unwrap() > 0, "G = 0 without the initialiser: {r}\n{so}");
        }
    }
}

/// A legacy EOS in 3D with mirror walls and smoothing lengths from the density: the run
/// evaluates the rates twice at t = 0 (for the output, then the first step), and the smoothing
/// lengths, so the mirrors, change between the two. The second evaluation used to replay the
/// first call's p and c at the old particle count, and the mirrors' copy then ran past them
/// (an internal error, exit 101); it now calls the routine again, and the run ends in blastsph's
/// own state bit for bit.
#[test]
fn a_legacy_eos_with_mirrors_and_smoothing_from_density_runs() {
    let d = variant("eos3d", |m| {
        let only_eos = m
            .split("[[routine]]")
            .filter(|r| !r.contains("name = \"") || r.contains("name = \"p_gas\""))
            .collect::<Vec<_>>()
            .join("[[routine]]");
        only_eos.replace("dim = 1", "dim = 3")
    });
    let inc = d.join("param.inc");
    let text = std::fs::read_to_string(&inc).unwrap();
    std::fs::write(&inc, text.replace("parameter (dim = 1)", "parameter (dim = 3)")).unwrap();
    // the book's p_gas with its two known defects mended (a double-precision γ, the adiabatic
    // sound speed): the ideal gas as blastsph computes it, the same operations in the same order
    let eos = d.join("eos.f");
    let text = std::fs::read_to_string(&eos).unwrap();
    let mended = text.replacen("gam = 1.4\n", "gam = 1.4d0\n", 1).replacen(
        "c = sqrt((gam - 1)*u)",
        "c = sqrt(gam*(gam - 1)*u)",
        1,
    );
    assert_ne!(mended, text);
    std::fs::write(&eos, mended).unwrap();
    build(&d.join("legacy.toml"), &d.join("build")).expect("the 3D variant builds");
    let mut case = String::from(
        "name = \"gas_octant\"\ndim = 3\n[time]\nend_s = 3.0e-4\nstep = \"fixed\"\ndt_s = 1.0e-4\n\
         [sph]\nnnps = \"direct\"\ndensity = \"summation\"\nsmoothing = \"density\"\njitter = 0.0\n\
         [[material]]\nname = \"gas\"\neos = { kind = \"ideal_gas\", gamma = 1.4 }\n\
         [[region]]\nname = \"hot\"\nmaterial = \"gas\"\nshape = \"box\"\nlo_m = [0.0, 0.0, 0.0]\nhi_m = [0.02, 0.02, 0.02]\n\
         spacing_m = 0.01\nrho_kgm3 = 1.0\ne_jkg = 250.0\n\
         [[region]]\nname = \"cold\"\nmaterial = \"gas\"\nshape = \"box\"\nlo_m = [0.0, 0.0, 0.0]\nhi_m = [0.06, 0.06, 0.06]\n\
         spacing_m = 0.01\nrho_kgm3 = 1.0\ne_jkg = 2.5\nsubtract = [\"hot\"]\n",
    );
    for to in ["[0.0, 0.06, 0.06]", "[0.06, 0.0, 0.06]", "[0.06, 0.06, 0.0]"] {
        case += &format!("[[wall]]\nfrom_m = [0.0, 0.0, 0.0]\nto_m = {to}\nkind = \"mirror\"\n");
    }
    let cf = d.join("gas_octant.toml");
    std::fs::write(&cf, case).unwrap();
    let (lg, cs) = (d.join("build"), cf.to_str().unwrap().to_string());
    let (a, b) = (d.join("run_legacy"), d.join("run_rust"));
    for (dir, leg) in [(&a, true), (&b, false)] {
        let mut args = vec!["run", &cs, "--quiet", "--out", dir.to_str().unwrap()];
        if leg {
            args.extend(["--legacy", lg.to_str().unwrap()]);
        }
        let o = blastsph(&args);
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let read = |dir: &Path| last_frame(dir, &["x", "rho", "p", "h"]);
    let (ra, rb) = (read(&a), read(&b));
    for k in 0..4 {
        assert!(!ra[k].is_empty() && ra[k].iter().zip(&rb[k]).all(|(x, y)| x.to_bits() == y.to_bits()), "field {k}");
    }
    let out = d.join("dual");
    let o = blastsph(&["dual", &cs, "--legacy", lg.to_str().unwrap(), "--steps", "3", "--out", out.to_str().unwrap()]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    let r = row(&rows, "legacy.p_gas", "p");
    assert!(r["compared"].as_u64().unwrap() > 0 && r["max_ulp"].as_u64() == Some(0), "{r}");
}

/// A manifest's `[itype]` key that names no material of the case and no EOS kind is a misspelt
/// name: the material it meant takes its kind's code instead, silently (the legacy density then
/// differs for no reason the dual run gives). It is warned of, with the codes the routines get.
#[test]
fn a_misspelt_itype_key_is_warned_of() {
    let d = variant("itype_typo", |m| m.replacen("[[routine]]", "[itype]\ngass = 3\n\n[[routine]]", 1));
    build(&d.join("legacy.toml"), &d.join("build")).expect("the variant builds");
    let o = blastsph(&["check", "shock_tube", "--legacy", d.join("build").to_str().unwrap()]);
    let se = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{se}");
    let w = se.lines().find(|l| l.contains("[itype] `gass`")).unwrap_or_else(|| panic!("{se}"));
    assert!(
        w.starts_with("warning:") && w.contains("names no material of this case") && w.contains("(ideal_gas) = "),
        "{w}"
    );
}

/// A routine mapped under another module than the one its arguments compute (the book's p_gas
/// given as `density`) is named NOT RUN with the module it fits, by `check` and in the dual's
/// verdict (it said "the case uses another formulation", and the verdict did not count it).
#[test]
fn a_routine_under_the_wrong_module_is_named_with_the_module_it_fits() {
    let d = variant("wrong_module", |m| {
        m.replacen("name = \"p_gas\"\nmodule = \"eos\"", "name = \"p_gas\"\nmodule = \"density\"", 1)
    });
    assert!(std::fs::read_to_string(d.join("legacy.toml")).unwrap().contains("module = \"density\""));
    build(&d.join("legacy.toml"), &d.join("build")).expect("the variant builds");
    let lg = d.join("build");
    let o = blastsph(&["check", "shock_tube", "--legacy", lg.to_str().unwrap()]);
    let se = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{se}");
    let w = se.lines().find(|l| l.starts_with("warning: legacy p_gas is not run")).unwrap_or_else(|| panic!("{se}"));
    assert!(w.contains("fit eos.eval of another module") && w.contains("module = \"eos\"?"), "{w}");
    let o = dual_plain(&lg, 3, &scratch("wrong_module_dual"));
    let so = String::from_utf8_lossy(&o.stdout);
    assert!(so.contains("1 mapped legacy routine(s) NOT RUN"), "{so}{}", String::from_utf8_lossy(&o.stderr));
}

/// `check` compares its estimate of the pairs with the legacy build's max_interaction, as the
/// docs ask the user to (the refusal, or the code's own STOP, came only at the first step).
#[test]
fn check_warns_when_the_pairs_outgrow_the_legacy_arrays() {
    let so = blastsph_ok(&["check", "shock_tube", "--legacy", shared().to_str().unwrap()], 0);
    assert!(!so.contains("warning: about"), "20000 pair slots for about 5440 pairs: {so}");
    let d = variant_built("small_pairs", "param.inc", |t| {
        t.replace("max_interaction = 20*maxn", "max_interaction = 2*maxn")
    });
    let so = blastsph_ok(&["check", "shock_tube", "--legacy", d.join("build").to_str().unwrap()], 0);
    let w = so.lines().find(|l| l.starts_with("warning: about")).unwrap_or_else(|| panic!("{so}"));
    assert!(w.contains("max_interaction = 2000 (its param.inc)") && w.contains("raise max_interaction"), "{w}");
}

/// A routine of another formulation than the case's (the book's con_density in the shock tube's
/// summation density) is no miss beside a mapped routine that stands for its module
/// (sum_density), but mapped without one nothing of the user's code runs for that module: it is
/// counted NOT RUN (a Tait EOS mapped alone gave "every module within tolerance").
#[test]
fn a_routine_of_another_formulation_alone_in_its_module_is_counted_not_run() {
    let d = shared().to_str().unwrap();
    let so = blastsph_ok(&["check", "shock_tube", "--legacy", d], 0);
    assert!(!so.contains("warning: legacy con_density"), "beside sum_density: {so}");
    let v = variant("con_density_alone", |m| {
        let (head, tail) = m.split_once("[[routine]]\nname = \"sum_density\"").expect("sum_density's entry");
        let rest = tail.split_once("[[routine]]").map_or(String::new(), |(_, r)| format!("[[routine]]{r}"));
        format!("{head}{rest}")
    });
    assert!(!std::fs::read_to_string(v.join("legacy.toml")).unwrap().contains("sum_density"));
    build(&v.join("legacy.toml"), &v.join("build")).expect("the variant builds");
    let lg = v.join("build");
    let so = blastsph_ok(&["check", "shock_tube", "--legacy", lg.to_str().unwrap()], 0);
    let w =
        so.lines().find(|l| l.starts_with("warning: legacy con_density is not run")).unwrap_or_else(|| panic!("{so}"));
    assert!(w.contains("another formulation") && w.contains("no mapped routine stands for density"), "{w}");
    let o = dual_plain(&lg, 2, &scratch("con_density_alone_dual"));
    let so = String::from_utf8_lossy(&o.stdout);
    assert!(so.contains("1 mapped legacy routine(s) NOT RUN"), "{so}{}", String::from_utf8_lossy(&o.stderr));
}

/// A routine of the user's own that forms the density rate and the pressure force in one pair
/// loop (as many thesis codes do): the mass form of the continuity equation and the symmetric
/// force and energy terms, p read from its argument.
const DENS_FORCE: &str = "      subroutine dens_force(ntotal, mass, niac, pair_i, pair_j, dwdx,
     &                      vx, rho, p, drhodt, dvxdt, dedt)
c-----------------------------------------------------------------------
c     Density rate and pressure force in one loop over the pairs.
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer ntotal, niac, pair_i(max_interaction),
     &        pair_j(max_interaction)
      double precision mass(maxn), dwdx(dim,max_interaction),
     &        vx(dim,maxn), rho(maxn), p(maxn), drhodt(maxn),
     &        dvxdt(dim,maxn), dedt(maxn)
      integer i, j, k, d
      double precision vd, pr, f, de

      do 10 i = 1, ntotal
        drhodt(i) = 0.d0
        dedt(i) = 0.d0
        do 5 d = 1, dim
          dvxdt(d,i) = 0.d0
    5   continue
   10 continue

      do 40 k = 1, niac
        i = pair_i(k)
        j = pair_j(k)
        vd = 0.d0
        do 20 d = 1, dim
          vd = vd + (vx(d,i) - vx(d,j))*dwdx(d,k)
   20   continue
        drhodt(i) = drhodt(i) + mass(j)*vd
        drhodt(j) = drhodt(j) + mass(i)*vd
        pr = p(i)/(rho(i)*rho(i)) + p(j)/(rho(j)*rho(j))
        do 30 d = 1, dim
          f = pr*dwdx(d,k)
          dvxdt(d,i) = dvxdt(d,i) - mass(j)*f
          dvxdt(d,j) = dvxdt(d,j) + mass(i)*f
   30   continue
        de = 0.5d0*pr*vd
        dedt(i) = dedt(i) + mass(j)*de
        dedt(j) = dedt(j) + mass(i)*de
   40 continue
      end
";

/// A routine that stands for the density rate and the force (`module = "density,force"`) runs
/// after the EOS, whose p it reads: it ran at the density rate's place, before the EOS, and
/// read the last step's p, while the dual run compared it with its twins on the same stale p
/// and found 0 ULP (a docs-only migration of a thesis-style code found `run --legacy` 11 % off
/// its own program in p). Now `run --legacy` gives the Rust run's bits and the dual run is at
/// 0 ULP.
#[test]
fn a_density_and_force_routine_runs_after_the_eos_whose_p_it_reads() {
    let d = variant("dens_force", |m| {
        // only the new routine is mapped (the fixture's sources are still built)
        let head = m.split("[[routine]]").next().unwrap();
        format!(
            "{head}[[routine]]\nname = \"dens_force\"\nmodule = \"density,force\"\nargs = [\"ntotal\", \"mass\", \"niac\", \"pair_i\", \"pair_j\", \"dwdx\", \"vx\", \"rho\", \"p\", \"drhodt\", \"dvxdt\", \"dedt\"]\n"
        )
    });
    std::fs::write(d.join("dens_force.f"), DENS_FORCE).unwrap();
    let lg = d.join("build");
    build(&d.join("legacy.toml"), &lg).expect("the variant builds");
    let lgs = lg.to_str().unwrap();
    let sets = [
        "--set",
        "sph.density=\"continuity\"",
        "--set",
        "sph.continuity_form=\"mass\"",
        "--set",
        "sph.energy_form=\"symmetric\"",
        "--set",
        "time.end_s=0.05",
    ];
    let with = |args: &[&str]| -> Vec<String> { args.iter().chain(&sets).map(|s| s.to_string()).collect() };
    let so = blastsph_ok(&with(&["check", "shock_tube", "--legacy", lgs]), 0);
    let line = so.lines().find(|l| l.trim_start().starts_with("dens_force")).unwrap_or_else(|| panic!("{so}"));
    assert!(
        line.contains("stands for density.rate + force.internal; phase eos, after eos.eval (which makes its p)"),
        "{line}"
    );
    // the step: the EOS, then the routine
    let (eos, df) = (so.find(" eos.eval ").unwrap(), so.find(" legacy.dens_force ").unwrap());
    assert!(so[..eos].contains("predict") && eos < df, "{so}");
    // with a mirror wall the mirrors' p is copied after the EOS (phase eosshare): the routine
    // runs after that copy (the place is the step's order, not the modules' order)
    let text = std::fs::read_to_string(root().join("cases/shock_tube.toml")).unwrap();
    let walled =
        text.replacen("[[region]]", "[[wall]]\nfrom_m = [-0.6]\nto_m = [-0.6]\nkind = \"mirror\"\n\n[[region]]", 1);
    let wcase = d.join("shock_tube_wall.toml");
    std::fs::write(&wcase, walled).unwrap();
    let so = blastsph_ok(&with(&["check", wcase.to_str().unwrap(), "--legacy", lgs]), 0);
    let line = so.lines().find(|l| l.trim_start().starts_with("dens_force")).unwrap_or_else(|| panic!("{so}"));
    assert!(line.contains("phase eosshare, after boundary.mirror_copy (which makes its p)"), "{line}");
    let (cp, df) = (so.find(" boundary.mirror_copy ").unwrap(), so.find(" legacy.dens_force ").unwrap());
    assert!(cp < df, "{so}");
    let (ra, rb) = (d.join("rust"), d.join("legacy"));
    blastsph_ok(&with(&["run", "shock_tube", "--out", ra.to_str().unwrap()]), 0);
    blastsph_ok(&with(&["run", "shock_tube", "--legacy", lgs, "--out", rb.to_str().unwrap()]), 0);
    let names = ["x", "vx", "rho", "p", "e"];
    let (a, b) = (last_frame(&ra, &names), last_frame(&rb, &names));
    for (k, n) in names.iter().enumerate() {
        assert!(a[k].iter().zip(&b[k]).all(|(x, y)| x.to_bits() == y.to_bits()), "{n} differs from the Rust run");
    }
    let out = d.join("dual");
    blastsph_ok(&with(&["dual", "shock_tube", "--legacy", lgs, "--out", out.to_str().unwrap()]), 0);
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    for f in ["drho", "acc", "dde"] {
        let x = row(&rows, "legacy.dens_force", f);
        assert_eq!((x["max_ulp"].as_u64(), x["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{f}: {x}");
    }
}

/// The dual run's rows of art_visc (field, max_ulp) of a build, with the book's profile.
fn art_visc_rows(lg: &Path, out: &str) -> Vec<(String, String)> {
    let d = scratch(out);
    let o = dual_book(lg, Some(3), &d);
    assert!(o.status.success(), "{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    let (_, rows) = report_rows(&d.join("dual_report.json"));
    let av: Vec<(String, String)> = rows
        .iter()
        .filter(|r| r["stage"] == "legacy.art_visc")
        .map(|r| (r["field"].to_string(), r["max_ulp"].to_string()))
        .collect();
    assert!(!av.is_empty(), "art_visc was compared: {rows:?}");
    av
}

/// A legacy routine that keeps its arrays in COMMON blocks (declared in an include file) or in
/// a Fortran module, with no arguments, is mapped by naming those variables as `globals`: the
/// shim copies blastsph's arrays into them before the call and back after. The dual run then
/// compares it exactly as the same routine with arguments.
#[test]
fn a_routine_whose_arrays_are_in_common_blocks_or_a_module_is_mapped_by_its_globals() {
    let plain = art_visc_rows(shared(), "av_plain_dual");

    // COMMON blocks in an include file
    let v = av_globals_variant("av_common", "global_includes = [\"avstate.inc\"]", AV_GLOBALS, |t| {
        av_without_arguments(t, "      implicit none\n      include 'avstate.inc'\n")
    });
    std::fs::write(v.join("avstate.inc"), AVSTATE_INC).unwrap();
    let info = build(&v.join("legacy.toml"), &v.join("build")).expect("the COMMON variant builds");
    let av = info.routines.iter().find(|r| r.name == "art_visc").unwrap();
    assert!(av.args.is_empty() && av.globals.len() == 14, "{av:?}");
    assert!(av.globals.iter().all(|g| g.from == "include 'avstate.inc'"), "{:?}", av.globals);
    assert_eq!(art_visc_rows(&v.join("build"), "av_common_dual"), plain);

    // a module of allocatable arrays, allocated by an initialiser mapped as init
    let module = "      module avmod
      implicit none
      include 'param.inc'
      integer ntotal, niac
      integer, allocatable :: pair_i(:), pair_j(:)
      double precision, allocatable :: hsml(:), mass(:), x(:,:),
     &        vx(:,:), rho(:), c(:)
      double precision, allocatable :: w(:), dwdx(:,:), dvxdt(:,:),
     &        dedt(:)
      end module avmod

      subroutine av_alloc
      use avmod
      implicit none
      allocate(pair_i(max_interaction), pair_j(max_interaction))
      allocate(w(max_interaction), dwdx(dim,max_interaction))
      allocate(hsml(maxn), mass(maxn), x(dim,maxn), vx(dim,maxn))
      allocate(rho(maxn), c(maxn), dvxdt(dim,maxn), dedt(maxn))
      end
";
    let entry = |init: bool| {
        let mut e = format!("{AV_GLOBALS}\n");
        if init {
            e.push_str("\n[[routine]]\nname = \"av_alloc\"\nmodule = \"init\"\nargs = []\n");
        }
        e
    };
    for init in [true, false] {
        let name = if init { "av_module" } else { "av_module_unallocated" };
        let v = av_globals_variant(name, "global_modules = [\"avmod\"]", &entry(init), |t| {
            av_without_arguments(t, "      use avmod\n      implicit none\n")
        });
        std::fs::write(v.join("avmod.f"), module).unwrap();
        let info = build(&v.join("legacy.toml"), &v.join("build")).expect("the module variant builds");
        let av = info.routines.iter().find(|r| r.name == "art_visc").unwrap();
        assert!(av.globals.iter().all(|g| g.from == "module avmod"), "{:?}", av.globals);
        if init {
            assert_eq!(art_visc_rows(&v.join("build"), "av_module_dual"), plain);
        } else {
            // without its initialiser the module's arrays are not allocated: one line, exit 2
            let o = dual_book(&v.join("build"), Some(3), &scratch("av_unallocated_dual"));
            let se = String::from_utf8_lossy(&o.stderr);
            assert_eq!(o.status.code(), Some(2), "{se}");
            assert!(se.contains("art_visc") && se.contains("not allocated") && se.contains("init"), "{se}");
        }
    }
}

/// What the build refuses of globals, each with one line naming the global.
#[test]
fn globals_that_are_not_declared_or_of_another_type_or_rank_are_refused() {
    let refused = |name: &str, head: &str, globals: &str, inc: &str| -> String {
        let v = av_globals_variant(name, head, globals, |t| {
            av_without_arguments(t, "      implicit none\n      include 'avstate.inc'\n")
        });
        std::fs::write(v.join("avstate.inc"), inc).unwrap();
        let e = build(&v.join("legacy.toml"), &v.join("build")).expect_err("refused");
        let e = e.to_string();
        assert!(!e.contains('\n'), "one line: {e}");
        e
    };
    // a name the include does not declare
    let e = refused(
        "g_undeclared",
        "global_includes = [\"avstate.inc\"]",
        &AV_GLOBALS.replace("dedt = \"dedt\"", "dedt = \"dedt\", eta_v = \"eta\""),
        AVSTATE_INC,
    );
    assert!(e.contains("global `eta_v`") && e.contains("declared in none of global_includes (avstate.inc)"), "{e}");
    // an integer array bound to a real name: gfortran's type check, named
    let e = refused(
        "g_type",
        "global_includes = [\"avstate.inc\"]",
        &AV_GLOBALS.replace("c = \"c\"", "c = \"mat\""),
        AVSTATE_INC,
    );
    assert!(
        e.contains("global `c`") && e.contains("\"mat\", a default integer") && e.contains("include 'avstate.inc'"),
        "{e}"
    );
    // an array bound to a one-value name
    let e = refused(
        "g_rank",
        "global_includes = [\"avstate.inc\"]",
        &AV_GLOBALS
            .replace("ntotal = \"ntotal\"", "ntotal = \"ntotal\", ri = \"time\"")
            .replace("hsml = \"hsml\"", "hsml = \"dt\""),
        &AVSTATE_INC.replace("dedt(maxn)\n", "dedt(maxn), ri\n"),
    );
    assert!(
        e.contains("global `hsml` is an array in include 'avstate.inc' (`hsml(maxn)`)")
            && e.contains("\"dt\" is one value"),
        "{e}"
    );
    // globals with nowhere to find them; in a per-particle call; a module that is not in the sources
    let e = refused("g_nowhere", "", AV_GLOBALS, AVSTATE_INC);
    assert!(e.contains("globals") && e.contains("global_includes") && e.contains("global_modules"), "{e}");
    let e = refused("g_module", "global_modules = [\"nosuch\"]", AV_GLOBALS, AVSTATE_INC);
    assert!(e.contains("global_modules: \"nosuch\" is not a module of the sources"), "{e}");
    let e = refused(
        "g_each",
        "global_includes = [\"avstate.inc\"]",
        &format!("call = \"each_particle\"\n{AV_GLOBALS}"),
        AVSTATE_INC,
    );
    assert!(e.contains("globals are copied in and out once per call"), "{e}");
    let e = refused("g_badname", "global_includes = [\"avstate.inc\"]", "globals = { \"x(1)\" = \"x\" }", AVSTATE_INC);
    assert!(e.contains("\"x(1)\" is not a Fortran name"), "{e}");
}

/// A plane-strain routine that keeps the velocity and the kernel gradient in one array per
/// component (`up(maxn)`, `wp(maxn)`, `dwx(max_interaction)`, `dwy(max_interaction)`) is mapped
/// with the components' names (`vx_1`, `vx_2`, `dwdx_1`, `dwdx_2`) and compares as the same
/// routine with whole vectors: every dim-th value, in 2D, where a stride slip would show.
#[test]
fn a_routine_with_one_array_per_component_is_mapped_by_the_components_names() {
    let d = strength_fixture("strength_split");
    let f = d.join("strain.f");
    let t = std::fs::read_to_string(&f).unwrap();
    let mut split = t.clone();
    for (a, b) in [
        ("pair_j, dwdx, mass,", "pair_j, mass,"),
        ("     &   rho, vx, itype,", "     &   dwx, dwy, rho, up, wp,\n     &   itype,"),
        ("dwdx(dim, max_interaction), ", ""),
        ("vx(dim, maxn), ", ""),
        (
            "      include 'soil.inc'\n",
            "      include 'soil.inc'\n      double precision up(maxn), wp(maxn), dwx(max_interaction),\n     &  dwy(max_interaction)\n",
        ),
        ("vx(1,", "up("),
        ("vx(2,", "wp("),
        ("dwdx(1,k)", "dwx(k)"),
        ("dwdx(2,k)", "dwy(k)"),
    ] {
        assert!(split.contains(a), "strain.f holds {a}");
        split = split.replace(a, b);
    }
    assert!(!split.contains("vx(") && !split.contains("dwdx("), "every use rewritten");
    std::fs::write(&f, split).unwrap();
    let m = d.join("legacy.toml");
    let mt = std::fs::read_to_string(&m).unwrap();
    let old = "\"pair_j\", \"dwdx\", \"mass\", \"rho\", \"vx\", \"itype\",";
    assert!(mt.contains(old), "{mt}");
    let with = |names: &str| mt.replace(old, names);
    // the manifest's names, built into d/<build>, then the soil spall's dual run over `steps`
    let dual_of = |names: &str, build_dir: &str, steps: &str| {
        std::fs::write(&m, with(names)).unwrap();
        let lg = d.join(build_dir);
        build(&m, &lg).expect("the split-array variant builds");
        let out = d.join(format!("dual_{build_dir}"));
        let a = ["dual", "cases/hard/soil_spall.toml", "--legacy", lg.to_str().unwrap(), "--steps", steps];
        (blastsph(&[&a[..], &["--out", out.to_str().unwrap()]].concat()), out)
    };
    let (o, out) =
        dual_of("\"pair_j\", \"mass\", \"dwdx_1\", \"dwdx_2\", \"rho\", \"vx_1\", \"vx_2\", \"itype\",", "build", "20");
    let (so, se) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert_eq!(o.status.code(), Some(0), "{so}{se}");
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    for field in ["eps", "rot", "dtau", "dde"] {
        let r = row(&rows, "legacy.strain_rate", field);
        assert!(r["compared"].as_u64().unwrap() > 0 && r["max_ulp"].as_u64() == Some(0), "{r}");
    }
    // the components with the y's and x's swapped: the shear and rotation rates differ
    let (o, _) = dual_of(
        "\"pair_j\", \"mass\", \"dwdx_2\", \"dwdx_1\", \"rho\", \"vx_1\", \"vx_2\", \"itype\",",
        "swapped",
        "5",
    );
    assert_eq!(o.status.code(), Some(4), "{}", String::from_utf8_lossy(&o.stdout));
    // refused: a third component in 2D; a vector beside its own component
    for (names, want) in [
        (
            "\"pair_j\", \"dwdx_1\", \"dwdx_3\", \"mass\", \"rho\", \"vx_1\", \"vx_2\", \"itype\",",
            "\"dwdx_3\" is component 3 of dwdx, but this build has dim = 2",
        ),
        (
            "\"pair_j\", \"dwdx_1\", \"dwdx\", \"mass\", \"rho\", \"vx_1\", \"vx_2\", \"itype\",",
            "\"dwdx_1\" is a component of \"dwdx\"",
        ),
    ] {
        std::fs::write(&m, with(names)).unwrap();
        let e = blastsph::migration::manifest::load(&m).expect_err("refused").to_string();
        assert!(e.contains(want), "{e}");
    }
}
