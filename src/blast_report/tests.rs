use super::TimeUnit;

#[test]
fn peak_labels_have_four_significant_digits() {
    let t = super::tick;
    assert_eq!(
        [t(365.868), t(51.912), t(1234.5), t(0.12345), t(f64::NAN)],
        ["365.9 MPa", "51.91 MPa", "1234 MPa", "0.1235 MPa", "-"]
    );
}

#[test]
fn report_times_are_in_the_unit_of_the_run_length() {
    // a blast's first millisecond: µs, whole (as before the unit was chosen)
    assert_eq!(TimeUnit::for_end(5.0e-4).text(2.5e-4), "250 µs");
    assert_eq!(TimeUnit::for_end(5.0e-4).axis(), "t (µs)");
    // a late crater: ms, whole from 200 ms up, one decimal below
    assert_eq!(TimeUnit::for_end(0.3).text(0.075001), "75 ms");
    assert_eq!(TimeUnit::for_end(0.05).text(0.0125), "12.5 ms");
    assert_eq!(TimeUnit::for_end(0.05).of(0.05), 50.0);
    // beyond 20 s: s
    assert_eq!(TimeUnit::for_end(30.0).axis(), "t (s)");
    assert_eq!(TimeUnit::for_end(30.0).text(7.5), "7.5 s");
}

/// The 3D section follows the particles that lay on it at t = 0: a cloud expanding from the
/// plane y = 0 keeps its section (a fixed slab held only the particle at y = 0 once the
/// cloud had grown tenfold; a free sphere's section was empty from 30 µs).
#[test]
fn a_3d_section_follows_its_particles() {
    let text = std::fs::read_to_string("cases/hard/free_sphere_3d.toml").unwrap();
    let case = crate::case::parse(&text, "free_sphere_3d.toml", &[], Some("free_sphere_3d")).unwrap();
    let frame = |time: f64, grow: f64| {
        let y: Vec<f64> = [0.0, 0.001, -0.001, 0.01, -0.01].iter().map(|v| v * grow).collect();
        let n = y.len();
        crate::output::Frame {
            time,
            x: y.iter().map(|v| 0.5 * v).collect(),
            z: y.iter().map(|v| 0.25 * v).collect(),
            y,
            vx: vec![0.0; n],
            vy: vec![0.0; n],
            vz: vec![0.0; n],
            rho: vec![1630.0; n],
            p: vec![1e5; n],
            e: vec![1e6; n],
            h: vec![0.003; n],
            mass: vec![0.01; n],
            mat: vec![0; n],
            id: (1..=n as i64).collect(),
            ..Default::default()
        }
    };
    let frames = [frame(0.0, 1.0), frame(3e-5, 10.0)];
    let secs = super::section_frames(&case, &frames);
    // the slab is 0.75 of the smallest h (no soil) about y = 0 at t = 0: ids 1, 2 and 3
    assert_eq!(secs[0].id, [1, 2, 3]);
    assert_eq!(secs[1].id, [1, 2, 3], "the section at 30 µs");
    // drawn in x–z
    assert_eq!(secs[1].y, [0.0, 0.0025, -0.0025]);
}

/// A point gauge's void (empty fields) is remembered, so its plot breaks the line there
/// (gauges.png drew a 16 ms straight decay across a void of a buried charge's gauge).
#[test]
fn a_gauges_void_is_kept_as_a_break() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("gauges.csv");
    std::fs::write(&p, "t_s,A_p_pa,A_vx_ms,A_vy_ms\n0,1,0,0\n1,2,0,0\n2,,,\n3,,,\n4,5,0,0\n5,6,0,0\n").unwrap();
    let g = super::read_gauges(&p).unwrap();
    assert_eq!(g[0].samples.len(), 4);
    assert_eq!(g[0].after_void, [2]);
}

#[test]
fn heights_from_ten_metres_are_in_metres() {
    assert_eq!(super::height_text(0.29), "29.0 cm");
    assert_eq!(super::height_text(124.237), "124.2 m");
    assert_eq!(super::height_text(f64::NAN), "- cm");
}

/// TM 5-855-1 (chapter 5) in SI: at 1 ft/lb^⅓ (0.3967 m/kg^⅓) P0 = f ρc 160 psi whatever n, and
/// doubling the distance divides it by 2^n.
#[test]
fn the_tm5_855_1_curve_is_converted_to_si() {
    let z1 = 0.3048 / 0.453_592_37f64.cbrt();
    let (rho_c, ns) = super::peaks::TM_LOOSE_DRY_SAND;
    for n in ns {
        // 12 psi/(ft/s) · 160 = 1920 psi = 13.238 MPa
        let p = super::peaks::tm5_855_1_mpa(z1, 1.0, rho_c, n);
        assert!((p - 1920.0 * 6894.757 / 1e6).abs() < 1e-4, "{p}");
        let q = super::peaks::tm5_855_1_mpa(2.0 * z1, 0.5, rho_c, n);
        assert!((q / p - 0.5 * 2f64.powf(-n)).abs() < 1e-12, "{q} {p}");
    }
}
