//! A legacy code that clamps its density after each update, as the dam-break `time_integration`
//! of Liu and Liu does: the manifest's `density_clamp` makes `run --legacy` end in the state of the
//! code's own program, bit for bit.

mod legacy_kit;
use legacy_kit::*;

/// The clamp in the fixture's dialect, with loop label `label`.
fn clamp(label: u32) -> String {
    format!(
        "c       the density clamp of the dam-break time integration
          do {label} i = 1, ntotal
            if (rho(i) .lt. 0.375d0) rho(i) = 0.375d0
            if (rho(i) .gt. 0.875d0) rho(i) = 0.875d0
   {label}     continue
"
    )
}

#[test]
fn a_code_that_clamps_its_density_is_run_by_blastsph_as_its_program_runs() {
    let d = variant("clamp", |m| format!("density_clamp = [0.375, 0.875]\n{m}"));
    let f = d.join("time_integration.f");
    let text = std::fs::read_to_string(&f).unwrap();
    // after the predict, and after the advance of the first and of later steps
    let predicted = "   30     continue\n";
    let advanced = "   70     continue\n        endif\n";
    assert!(text.contains(predicted) && text.contains(advanced));
    let new = text
        .replace(predicted, &format!("{predicted}{}", clamp(35)))
        .replace(advanced, &format!("{advanced}{}", clamp(75)));
    std::fs::write(&f, new).unwrap();
    let b = d.join("build");
    let info = build(&d.join("legacy.toml"), &b).expect("the clamping variant builds");
    assert_eq!(info.density_clamp, Some([0.375, 0.875]));
    // the program's own end state: the clamp bites at both bounds
    let prog = program_rows_of(&b, "clamp_program", 40);
    let rho: Vec<f64> = prog.iter().map(|r| r[5]).collect();
    assert!(rho.iter().all(|&r| (0.375..=0.875).contains(&r)), "{rho:?}");
    assert!(rho.contains(&0.375) && rho.contains(&0.875), "{rho:?}");
    // check says so, and run --legacy ends where the program ends
    let so = blastsph_ok(&["check", "shock_tube", "--legacy", b.to_str().unwrap(), "--compat", "liu-book"], 0);
    assert!(so.contains("integrator.clamp"), "{so}");
    assert_run_ends_as(&b, "shock_tube", "liu-book", &prog, "clamp_run");
}

#[test]
fn a_density_clamp_whose_bounds_are_not_ordered_is_refused() {
    let d = variant("clamp_bad", |m| format!("density_clamp = [0.875, 0.375]\n{m}"));
    refused(&d, &["density_clamp"]);
}
