use super::*;

/// Soil on a lattice of spacing `ds` over [0, w] × [0, hgt], less the points `cut` removes.
fn lattice(ds: f64, w: f64, hgt: f64, cut: &dyn Fn(f64, f64) -> bool) -> (Vec<f64>, Vec<f64>) {
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    let (nx, ny) = ((w / ds).round() as usize, (hgt / ds).round() as usize);
    for j in 0..ny {
        for i in 0..nx {
            let (x, y) = ((i as f64 + 0.5) * ds, (j as f64 + 0.5) * ds);
            if !cut(x, y) {
                xs.push(x);
                ys.push(y);
            }
        }
    }
    (xs, ys)
}

/// Cracks low in the soil are not the ground's surface: the row on the floor of the box
/// pulled 2.1 spacings below the rest (a gap the raster sees as solid, which used to end the
/// walk and read the crater as deep as the box), and a crack 4 spacings tall across the
/// whole soil that reaches the box's side walls (open only through the margins beyond them,
/// where the ground is taken to go on). Lifted particles 2.2 spacings over the ground's top
/// are still not ground.
#[test]
fn cracks_in_the_soil_and_a_row_off_the_floor_do_not_end_the_ground() {
    let ds = 0.01;
    let soil0 = lattice(ds, 1.0, 1.0, &|_, _| false);
    let bowl = |x: f64, y: f64| (x - 0.5).abs() < 0.1 && y > 0.9;
    let (mut x1, mut y1) = lattice(ds, 1.0, 1.0, &bowl);
    for y in y1.iter_mut() {
        // the floor row stays, everything above rises by 1.1 ds; above y = 0.4 by 4 ds more
        if *y > 0.01 {
            *y += 0.011;
        }
        if *y > 0.4 {
            *y += 0.04;
        }
    }
    // and a few lifted particles over the ground outside the bowl
    for k in 0..5 {
        x1.push(0.105 + 0.01 * k as f64);
        y1.push(1.051 + 0.022);
    }
    let inp = CraterInput { soil0, soil1: (x1, y1), charge0: (Vec::new(), Vec::new()) };
    let c = measure_xy(&inp, ds).unwrap();
    // the bowl's floor rose with the soil by 5.1 ds: 10 − 5.1 = 4.9 cm deep
    assert!((c.depth_m - 0.049).abs() < 1e-9, "depth {}", c.depth_m);
    assert!((c.diameter_m - 0.20).abs() < 1e-9, "diameter {}", c.diameter_m);
    let k = c.columns_m.iter().position(|x| (x - 0.125).abs() < 1e-9).unwrap();
    assert!((c.surface_m[k] - 1.046).abs() < 1e-9, "lifted particles read as ground: {}", c.surface_m[k]);
}

/// The crater of a flat lattice of soil `w` × `hgt` m (spacing `ds`) whose particles `cut`
/// removes later, without an explosive.
fn measure_cut(ds: f64, w: f64, hgt: f64, cut: &dyn Fn(f64, f64) -> bool) -> Crater {
    let inp = CraterInput {
        soil0: lattice(ds, w, hgt, &|_, _| false),
        soil1: lattice(ds, w, hgt, cut),
        charge0: (Vec::new(), Vec::new()),
    };
    measure_xy(&inp, ds).unwrap()
}

/// A 2D crater that reaches the soil's first or last column (not a mirror wall there), or
/// whose floor reaches the soil's bottom, is named as the box's measure, a lower bound.
#[test]
fn a_crater_the_box_ends_is_named() {
    let ds = 0.05;
    let measure = |cut: &dyn Fn(f64, f64) -> bool| measure_cut(ds, 1.0, 0.5, cut);
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/cases/surface_loose_tnt6.toml")).unwrap();
    let plane = crate::case::parse(&text, "test", &[], None).unwrap();
    // a bowl inside the box
    let c = measure(&|x, y| (x - 0.5).abs() < 0.2 && y > 0.35);
    assert!(c.note.is_none() && box_bound(&plane, &c, None).is_none(), "{c:?}");
    // a bowl across the whole box: its width is the box's
    let c = measure(&|_, y| y > 0.35);
    let b = box_bound(&plane, &c, None).unwrap_or_else(|| panic!("{c:?}"));
    assert!(b.contains("x = 0.000 m") && b.contains("x = 1.000 m") && b.contains("diameter is a lower bound"), "{b}");
    // a bowl down to the soil's bottom row
    let c = measure(&|x, y| (x - 0.5).abs() < 0.3 && y > 0.05);
    let b = box_bound(&plane, &c, None).unwrap_or_else(|| panic!("{c:?}"));
    assert!(
        b.starts_with("the crater's floor reaches the soil's bottom (y = 0.000 m)")
            && b.contains("depth is a lower bound"),
        "{b}"
    );
    // a half model: the edge at x = 0 is a mirror wall (a symmetry plane), not the box
    let half = crate::case::parse(
        &text.replacen(
            "[[wall]]\nfrom_m = [0.0, 1.0]\nto_m = [0.0, 0.0]",
            "[[wall]]\nfrom_m = [0.0, 1.0]\nto_m = [0.0, 0.0]\nkind = \"mirror\"",
            1,
        ),
        "test",
        &[],
        None,
    )
    .unwrap();
    let c = measure(&|x, y| x < 0.4 && y > 0.35);
    assert!(c.touches[0] && box_bound(&half, &c, None).is_none(), "{c:?}");
    assert!(box_bound(&plane, &c, None).is_some());
}

/// A 3D crater that reaches the surface map's border names the sides, and says where a
/// wall of the case stands there (the shipped quarter's far walls; their images across the
/// symmetry planes at the map's other border).
#[test]
fn a_3d_crater_at_the_map_border_names_the_side_and_its_wall() {
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/cases/surface_loose_tnt1kg_3d.toml")).unwrap();
    let case = crate::case::parse(&text, "test", &[], None).unwrap();
    let (n, cell) = (12usize, 0.092);
    let centres: Vec<f64> = (0..n).map(|i| -0.552 + (i as f64 + 0.5) * cell).collect();
    let mut cells = vec![false; n * n];
    cells[5 * n + n - 1] = true; // the row through the axis, the last column (x = 0.552 m)
    cells[5 * n + 5] = true;
    let map = SurfaceMap {
        cell_m: cell,
        cells: [n, n],
        x_m: centres.clone(),
        y_m: centres,
        crater_cells: cells,
        ..Default::default()
    };
    let c = Crater { columns_m: vec![0.0, 0.092], column_m: 0.092, ..Default::default() };
    let b = box_bound(&case, &c, Some(&map)).unwrap_or_else(|| panic!("a crater at the border"));
    assert!(b.contains("x = 0.552 m, where a wall of the case stands") && b.contains("widen the soil"), "{b}");
    // the first column (x = -0.552 m): the wall's image in the symmetry plane x = 0
    let mut first = vec![false; n * n];
    first[5 * n] = true;
    let b = box_bound(&case, &c, Some(&SurfaceMap { crater_cells: first, ..map.clone() })).unwrap();
    assert!(b.contains("x = -0.552 m, where a wall of the case stands"), "{b}");
    // inside the map: no bound
    let mut inner = vec![false; n * n];
    inner[5 * n + 5] = true;
    assert!(box_bound(&case, &c, Some(&SurfaceMap { crater_cells: inner, ..map })).is_none());
}

/// A one-column crack 30 spacings deep beside a bowl 10 deep (a buried charge's RZ run, in a
/// docs-only check: the depth read the crack) is left out of the depth and named; a crack
/// alone is no crater, nor is a hole narrower than it is deep (a vent through the dome), nor
/// a notch in a raised rim.
#[test]
fn cracks_and_vents_are_not_the_crater() {
    let ds = 0.01;
    let soil0 = lattice(ds, 1.0, 1.0, &|_, _| false);
    let measure = |cut: &dyn Fn(f64, f64) -> bool| measure_cut(ds, 1.0, 1.0, cut);
    let bowl = |x: f64, y: f64| (x - 0.5).abs() < 0.2 && y > 0.9;
    let crack = |x: f64, y: f64| (x - 0.555).abs() < 0.005 && y > 0.6;
    let c = measure(&|x, y| bowl(x, y) || crack(x, y));
    assert!((c.depth_m - 0.10).abs() < 1e-9 && (c.diameter_m - 0.40).abs() < 1e-9, "{c:?}");
    assert!(c.note.is_none());
    let k = c.crack.as_deref().unwrap_or_else(|| panic!("{c:?}"));
    assert!(k.contains("1.0 cm wide centred at 55.5 cm") && k.contains("drops 40.0 cm"), "{k}");
    // the crack alone: no crater, and the crack named
    let c = measure(&crack);
    assert_eq!((c.depth_m, c.diameter_m), (0.0, 0.0), "{c:?}");
    assert!(c.note.is_some() && c.crack.is_some(), "{c:?}");
    // a gap of one column 1 spacing deep: no bowl
    let c = measure(&|x, y| (x - 0.555).abs() < 0.005 && y > 0.99);
    assert_eq!((c.depth_m, c.diameter_m), (0.0, 0.0), "{c:?}");
    assert!(c.note.as_deref().is_some_and(|n| n.contains("one column")), "{c:?}");
    // a vent 4 columns wide and 30 deep
    let c = measure(&|x, y| (x - 0.5).abs() < 0.02 && y > 0.7);
    assert_eq!((c.depth_m, c.diameter_m), (0.0, 0.0), "{c:?}");
    assert!(c.note.as_deref().is_some_and(|n| n.contains("narrower than it is deep")), "{c:?}");
    // a bowl with a 2-column dip of one spacing at its floor (within 2 spacings of the columns
    // beside it) is the bowl, read at its deepest
    let c = measure(&|x, y| bowl(x, y) || ((x - 0.5).abs() < 0.01 && y > 0.885));
    assert!((c.depth_m - 0.11).abs() < 1e-9 && c.crack.is_none(), "{c:?}");
    // a rim raised 5 cm beside the bowl with a notch one column wide raised only 1 cm: above
    // the original ground, no crack (it was named, "drops -1.0 cm")
    let (mut x1, mut y1) = lattice(ds, 1.0, 1.0, &bowl);
    for i in 70..90 {
        let x = (i as f64 + 0.5) * ds;
        let rows = if i == 80 { 1 } else { 5 };
        for j in 0..rows {
            x1.push(x);
            y1.push(1.0 + (j as f64 + 0.5) * ds);
        }
    }
    let inp = CraterInput { soil0: soil0.clone(), soil1: (x1, y1), charge0: (Vec::new(), Vec::new()) };
    let c = measure_xy(&inp, ds).unwrap();
    assert!((c.depth_m - 0.10).abs() < 1e-9 && c.crack.is_none(), "{c:?}");
}

#[test]
fn a_bowl_is_measured_against_the_ground_over_the_charge_pit() {
    let ds = 0.01;
    // t = 0: a 6 cm pit in the top of the ground, holding a charge on a 0.5 cm lattice
    let pit = |x: f64, y: f64| (x - 0.5).abs() < 0.03 && y > 0.94;
    let soil0 = lattice(ds, 1.0, 1.0, &pit);
    let mut charge0 = (Vec::new(), Vec::new());
    for j in 0..12 {
        for i in 0..12 {
            charge0.0.push(0.47 + 0.0025 + 0.005 * i as f64);
            charge0.1.push(0.94 + 0.0025 + 0.005 * j as f64);
        }
    }
    // later: a bowl 20 cm wide and 10 cm deep below the original ground (y = 1)
    let bowl = |x: f64, y: f64| (x - 0.5).abs() < 0.1 && y > 0.9;
    let soil1 = lattice(ds, 1.0, 1.0, &bowl);
    // the same particles must be matched one to one: keep the counts comparable by measuring
    // each state against its own t = 0 lattice (the measure only uses positions)
    let inp = CraterInput { soil0: soil0.clone(), soil1, charge0 };
    let c = measure_xy(&inp, ds).unwrap();
    assert!((c.depth_m - 0.10).abs() < 1e-9, "depth {} against the ground, not the pit floor", c.depth_m);
    assert!((c.diameter_m - 0.20).abs() < 1e-9, "diameter {}", c.diameter_m);
    assert!(c.note.is_none());
    // the original ground over the pit is the ground's level beside it
    let k = c.columns_m.iter().position(|x| (x - 0.505).abs() < 1e-9).unwrap();
    assert!((c.surface0_m[k] - 0.995).abs() < 1e-9, "{}", c.surface0_m[k]);
}

#[test]
fn a_3d_bowl_is_measured_about_its_vertical_axis() {
    // a quarter block 0.3 x 0.3 x 0.5 m (z up, surface z = 0.5) with a hemispherical bowl of
    // radius 10 cm about the axis x = y = 0: diameter 20 cm, depth 10 cm, read on (r, z)
    let ds = 0.01;
    let n = 30;
    let (mut s0, mut s1) = ((Vec::new(), Vec::new()), (Vec::new(), Vec::new()));
    for k in 0..50 {
        for j in 0..n {
            for i in 0..n {
                let (x, y, z) = ((i as f64 + 0.5) * ds, (j as f64 + 0.5) * ds, (k as f64 + 0.5) * ds);
                let (r, h) = about_axis((0.0, 0.0), x, y, z);
                s0.0.push(r);
                s0.1.push(h);
                if (r * r + (z - 0.5) * (z - 0.5)).sqrt() >= 0.1 {
                    s1.0.push(r);
                    s1.1.push(h);
                }
            }
        }
    }
    let inp = CraterInput { soil0: s0, soil1: s1, charge0: (Vec::new(), Vec::new()) }.through_the_axis();
    let c = measure_xy(&inp, ds).unwrap();
    assert!((c.diameter_m - 0.20).abs() <= 2.0 * ds, "diameter {}", c.diameter_m);
    assert!((c.depth_m - 0.10).abs() <= ds, "depth {}", c.depth_m);
}

#[test]
fn a_3d_crater_that_is_not_round_is_measured_in_sections_and_a_quarter_is_completed() {
    // an elliptic bowl about the axis x = y = 0 (z up, surface z = 0.4): semi-axes 15 cm
    // along x and 8 cm along y, 10 cm deep; the whole block, and its quarter x, y > 0 with
    // the planes x = 0 and y = 0 as symmetry planes
    let ds = 0.01;
    let inside = |x: f64, y: f64, z: f64| (x / 0.15).powi(2) + (y / 0.08).powi(2) + ((z - 0.4) / 0.1).powi(2) < 1.0;
    let block = |lo: i32| {
        let (mut s0, mut s1) = (Vec::new(), Vec::new());
        for k in 0..40 {
            for j in lo..30 {
                for i in lo..30 {
                    let p = [(i as f64 + 0.5) * ds, (j as f64 + 0.5) * ds, (k as f64 + 0.5) * ds];
                    s0.push(p);
                    if !inside(p[0], p[1], p[2]) {
                        s1.push(p);
                    }
                }
            }
        }
        (s0, s1)
    };
    let (w0, w1) = block(-30);
    let whole = sections_3d((0.0, 0.0), ds, &[], &w0, &w1, &[]);
    let (q0, q1) = block(0);
    let quarter = sections_3d((0.0, 0.0), ds, &[(0, 0.0), (1, 0.0)], &q0, &q1, &[]);
    let alone = sections_3d((0.0, 0.0), ds, &[], &q0, &q1, &[]);
    for (w, q) in whole.iter().zip(&quarter) {
        assert!((w.diameter_m - q.diameter_m).abs() < 1e-9 && (w.depth_m - q.depth_m).abs() < 1e-9, "{w:?} {q:?}");
    }
    let by = |deg: f64| whole.iter().find(|s| s.azimuth_deg == deg).unwrap().clone();
    assert!((by(0.0).diameter_m - 0.30).abs() <= 2.0 * ds, "along x: {:?}", by(0.0));
    assert!((by(90.0).diameter_m - 0.16).abs() <= 2.0 * ds, "along y: {:?}", by(90.0));
    let diag = 2.0 / ((1.0 / 0.15f64).powi(2) + (1.0 / 0.08f64).powi(2)).sqrt() * 2f64.sqrt();
    assert!((by(45.0).diameter_m - diag).abs() <= 2.0 * ds, "diagonal {diag}: {:?}", by(45.0));
    assert!(whole.iter().all(|s| (s.depth_m - 0.10).abs() <= ds), "{whole:?}");
    // the quarter without its images reads half a crater along each plane
    assert!(alone[0].diameter_m < 0.17, "{:?}", alone[0]);
}

/// A block of soil points on a lattice of spacing `ds` (x, y in [lo ds, 30 ds], z in
/// [0, nz ds]), less the points `cut` removes.
fn block3(ds: f64, lo: i32, nz: i32, cut: &dyn Fn([f64; 3]) -> bool) -> Vec<[f64; 3]> {
    let mut v = Vec::new();
    for k in 0..nz {
        for j in lo..30 {
            for i in lo..30 {
                let p = [(i as f64 + 0.5) * ds, (j as f64 + 0.5) * ds, (k as f64 + 0.5) * ds];
                if !cut(p) {
                    v.push(p);
                }
            }
        }
    }
    v
}

#[test]
fn a_quarter_in_revolution_reads_the_ground_over_the_charge_pit_on_the_axis() {
    // a quarter x, y > 0 of ground at z = 0.4 with a 6 x 6 x 4 cm pit about the axis holding
    // a charge (its nearest particles Δs/√2 from the axis), later a round bowl 12 cm in radius
    // and 10 cm deep: measured in revolution (r, z) about the axis, completed through it, the
    // depth is the bowl's against the ground, not against the pit's floor (before the pit
    // test took the column's ±Δs band, the column on the axis kept the floor, z = 0.355)
    let ds = 0.01;
    let pit = |p: [f64; 3]| p[0].abs() < 0.03 && p[1].abs() < 0.03 && p[2] > 0.36;
    let bowl = |p: [f64; 3]| (p[0].hypot(p[1]) / 0.12).powi(2) + ((p[2] - 0.4) / 0.1).powi(2) < 1.0;
    let rz = |pts: Vec<[f64; 3]>| -> (Vec<f64>, Vec<f64>) {
        pts.iter().map(|p| about_axis((0.0, 0.0), p[0], p[1], p[2])).unzip()
    };
    let charge: Vec<[f64; 3]> = (0..4)
        .flat_map(|k| (0..3).flat_map(move |j| (0..3).map(move |i| (i, j, k))))
        .map(|(i, j, k)| [(i as f64 + 0.5) * ds, (j as f64 + 0.5) * ds, 0.36 + (k as f64 + 0.5) * ds])
        .collect();
    // one more soil particle, deep and far out at r = 45 Δs: the columns then lie centred on
    // whole multiples of Δs from the axis, one centred on the axis itself, with no charge
    // particle within Δs/2 of its centre (as on the 3D case's quarter lattice)
    let with_far = |mut v: Vec<[f64; 3]>| {
        v.push([45.0 * ds, 0.0, 0.5 * ds]);
        v
    };
    let inp = CraterInput {
        soil0: rz(with_far(block3(ds, 0, 40, &pit))),
        soil1: rz(with_far(block3(ds, 0, 40, &bowl))),
        charge0: rz(charge),
    }
    .through_the_axis();
    let c = measure_xy(&inp, ds).unwrap();
    let k = c.columns_m.iter().position(|x| x.abs() < 1e-9).expect("a column centred on the axis");
    assert!((c.surface0_m[k] - 0.395).abs() < 1e-9, "original ground on the axis {}", c.surface0_m[k]);
    assert!((c.depth_m - 0.10).abs() <= ds, "depth {} (the bowl's 0.10)", c.depth_m);
    // (the bowl's floor is nearly flat: its deepest column lies within a few cells of the axis)
    assert!(c.centre_m.abs() <= 4.0 * ds, "deepest column {} from the axis", c.centre_m);
    assert!((c.diameter_m - 0.24).abs() <= 2.0 * ds, "diameter {}", c.diameter_m);
}

#[test]
fn a_3d_crater_is_measured_as_a_surface_and_a_quarter_is_completed() {
    // t = 0: ground at z = 0.4 with a pit 6 x 6 cm and 4 cm deep about the axis x = y = 0,
    // holding a charge; later an elliptic bowl (semi-axes 15 cm along x, 8 cm along y, 10 cm
    // deep); the whole block, and its quarter x, y > 0 with the symmetry planes x = 0, y = 0
    let ds = 0.01;
    let pit = |p: [f64; 3]| p[0].abs() < 0.03 && p[1].abs() < 0.03 && p[2] > 0.36;
    let bowl = |p: [f64; 3]| (p[0] / 0.15).powi(2) + (p[1] / 0.08).powi(2) + ((p[2] - 0.4) / 0.1).powi(2) < 1.0;
    let charge = |lo: i32| -> Vec<[f64; 3]> {
        (0..4)
            .flat_map(|k| (lo..3).flat_map(move |j| (lo..3).map(move |i| (i, j, k))))
            .map(|(i, j, k)| [(i as f64 + 0.5) * ds, (j as f64 + 0.5) * ds, 0.36 + (k as f64 + 0.5) * ds])
            .collect()
    };
    let map = |lo: i32, mirrors: &[(usize, f64)]| {
        surface_map((0.0, 0.0), ds, mirrors, &block3(ds, lo, 40, &pit), &block3(ds, lo, 40, &bowl), &charge(lo / 10))
            .unwrap()
    };
    let whole = map(-30, &[]);
    let quarter = map(0, &[(0, 0.0), (1, 0.0)]);
    assert_eq!(whole.cells, [60, 60]);
    assert_eq!(quarter.cells, whole.cells);
    // the quarter's deepest cell is one of its own (x, y > 0), not an image; the bowl's
    // floor is flat over the four cells about the axis: one of those
    assert!(quarter.deepest_m[0] > 0.0 && quarter.deepest_m[1] > 0.0, "{:?}", quarter.deepest_m);
    assert!(quarter.deepest_m[0].hypot(quarter.deepest_m[1]) < ds, "{:?}", quarter.deepest_m);
    for (a, b) in [
        (whole.depth_m, quarter.depth_m),
        (whole.volume_m3, quarter.volume_m3),
        (whole.plan_area_m2, quarter.plan_area_m2),
        (whole.radius_min_m, quarter.radius_min_m),
        (whole.radius_max_m, quarter.radius_max_m),
    ] {
        assert!((a - b).abs() < 1e-12, "whole {whole:?}\nquarter {quarter:?}");
    }
    // the original ground over the charge's pit is the ground beside it (top particles at
    // z = 0.395), not the pit's floor
    let k = whole.x_m.iter().position(|x| (x - 0.005).abs() < 1e-9).unwrap() + 60 * 30;
    assert!((whole.surface0_m[k] - 0.395).abs() < 1e-9, "{}", whole.surface0_m[k]);
    // against the ellipsoid: depth 10 cm within a cell; volume (2/3) pi a b c = 2.513 L
    // within 1 % and plan area pi a b = 377 cm2 within 2 % (measured: 2.512 L, 376 cm2:
    // the lattice's columns count the removed particles, unbiased; the area's staircase
    // on a rim of 75 cm at 1 cm cancels to 0.3 %); the edge from the axis 8 and 15 cm
    // within a cell (measured 7.9 and 15.1 cm)
    let c = &whole;
    assert!(c.note.is_none(), "{c:?}");
    assert!((c.depth_m - 0.10).abs() <= ds, "depth {}", c.depth_m);
    // (the deepest of the cells 10 cm deep: one where the bowl is more than 9 cm deep)
    assert!((c.deepest_m[0] / 0.15).powi(2) + (c.deepest_m[1] / 0.08).powi(2) < 0.19, "{:?}", c.deepest_m);
    let v = 2.0 / 3.0 * std::f64::consts::PI * 0.15 * 0.08 * 0.1;
    assert!((c.volume_m3 / v - 1.0).abs() < 0.01, "volume {} against {v}", c.volume_m3);
    let a = std::f64::consts::PI * 0.15 * 0.08;
    assert!((c.plan_area_m2 / a - 1.0).abs() < 0.02, "area {} against {a}", c.plan_area_m2);
    assert!((c.equivalent_diameter_m - 2.0 * (0.15f64 * 0.08).sqrt()).abs() < 0.01, "{}", c.equivalent_diameter_m);
    assert!((c.radius_min_m - 0.08).abs() <= ds, "radius min {}", c.radius_min_m);
    assert!((c.radius_max_m - 0.15).abs() <= ds, "radius max {}", c.radius_max_m);
    // the quarter without its images: a quarter of the bowl, its edge 0 from the axis
    // towards -x and -y
    let alone = map(0, &[]);
    assert!((alone.plan_area_m2 - 0.25 * c.plan_area_m2).abs() < 0.1 * c.plan_area_m2, "{alone:?}");
    assert_eq!(alone.radius_min_m, 0.0);
}

#[test]
fn the_relief_of_the_original_ground_about_the_charge_is_measured() {
    // the same bowl (semi-axes 15 cm, 10 cm deep) in level ground and in ground whose top
    // falls 30 cm per metre along +x beyond x = 0.1 m (a crest and a slope face)
    let ds = 0.01;
    let bowl = |p: [f64; 3]| p[0].hypot(p[1]).powi(2) / 0.0225 + ((p[2] - 0.4) / 0.1).powi(2) < 1.0;
    let slope = |p: [f64; 3]| p[2] > 0.4 - 0.3 * (p[0] - 0.1).max(0.0);
    let level =
        surface_map((0.0, 0.0), ds, &[], &block3(ds, -30, 40, &|_| false), &block3(ds, -30, 40, &bowl), &[]).unwrap();
    assert!(level.note.is_none() && level.ground_relief_m < 1e-12, "{level:?}");
    let s0 = block3(ds, -30, 40, &slope);
    let s1 = block3(ds, -30, 40, &|p| slope(p) || bowl(p));
    let sloped = surface_map((0.0, 0.0), ds, &[], &s0, &s1, &[]).unwrap();
    // within twice the edge (about 30 cm) of the axis the top falls from x = 0.1 to 0.3 m:
    // about 6 cm, a few cells (the lattice's staircase within a cell of it)
    assert!((sloped.ground_relief_m - 0.06).abs() <= ds, "relief {}", sloped.ground_relief_m);
    assert!(level.ground_is_level() && !sloped.ground_is_level());
}

#[test]
fn a_3d_dome_over_a_cavity_is_ground_not_a_crater() {
    // a charge's hole 5 cm below the surface at t = 0 (top particles at z = 0.315); later a
    // cavity 12 x 12 x 6 cm under a dome two particles thick, raised by 2 cm: ground, not a
    // crater, and not ejecta over a crater
    let ds = 0.01;
    let near = |p: [f64; 3], w: f64, h: f64| p[0].abs() < w && p[1].abs() < w && (p[2] - 0.27).abs() < h;
    let soil0 = block3(ds, -20, 32, &|p| near(p, 0.03, 0.01));
    let mut soil1 = block3(ds, -20, 32, &|p| near(p, 0.06, 0.03));
    for p in soil1.iter_mut().filter(|p| p[0].abs() < 0.06 && p[1].abs() < 0.06 && p[2] > 0.3) {
        p[2] += 0.02;
    }
    let c = surface_map((0.0, 0.0), ds, &[], &soil0, &soil1, &[]).unwrap();
    assert!(c.note.as_deref().is_some_and(|n| n.contains("no apparent crater")), "{c:?}");
    assert_eq!((c.plan_area_m2, c.volume_m3, c.equivalent_diameter_m), (0.0, 0.0, 0.0));
    assert!((c.mound_height_m - 0.02).abs() < 1e-9, "the dome read as ground: {}", c.mound_height_m);
    // a vent through the dome over the cavity's centre opens it to the sky: a crater
    let vent: Vec<[f64; 3]> = soil1.iter().filter(|p| !(p[0].abs() < 0.02 && p[1].abs() < 0.02)).cloned().collect();
    let v = surface_map((0.0, 0.0), ds, &[], &soil0, &vent, &[]).unwrap();
    assert!(v.note.is_none() && v.depth_m > 0.05, "{v:?}");
    // a crack of one column, 4 cm deep, beside the dome is not a crater (a docs-only check's
    // 3D dome read as a crater 35 cm deep and 2.6 cm wide): no crater, depth 0, the note says
    // why
    let crack: Vec<[f64; 3]> =
        soil1.iter().filter(|p| !(p[0] == 0.155 && p[1] == 0.155 && p[2] > 0.28)).cloned().collect();
    let k = surface_map((0.0, 0.0), ds, &[], &soil0, &crack, &[]).unwrap();
    assert!(
        k.note.as_deref().is_some_and(|n| n.contains("crack or gap")),
        "{:?} {} {} {}",
        k.note,
        k.depth_m,
        k.plan_area_m2,
        k.cell_m
    );
    assert_eq!((k.depth_m, k.plan_area_m2, k.volume_m3), (0.0, 0.0, 0.0));
}

#[test]
fn a_surface_map_of_positions_that_are_not_numbers_gives_a_reason() {
    let s0 = block3(0.01, 0, 10, &|_| false);
    let mut s1 = s0.clone();
    s1[5][2] = f64::NAN;
    let e = surface_map((0.0, 0.0), 0.01, &[], &s0, &s1, &[]).unwrap_err();
    assert!(e.contains("not finite"), "{e}");
    let e = surface_map((0.0, 0.0), 0.01, &[], &[], &[], &[]).unwrap_err();
    assert!(e.contains("no soil particles"), "{e}");
    let e = surface_map((0.0, 0.0), f64::NAN, &[], &s0, &s0, &[]).unwrap_err();
    assert!(e.contains("not a positive number"), "{e}");
}

#[test]
fn an_axisymmetric_section_is_measured_through_the_axis() {
    // the half section r in [0, 0.5] of a bowl of radius 10 cm, 10 cm deep: diameter 20 cm
    let ds = 0.01;
    let soil0 = lattice(ds, 0.5, 1.0, &|_, _| false);
    let soil1 = lattice(ds, 0.5, 1.0, &|r, y| r < 0.1 && y > 0.9);
    let half = CraterInput { soil0, soil1, charge0: (Vec::new(), Vec::new()) };
    let c = measure_xy(&half.clone().through_the_axis(), ds).unwrap();
    assert!((c.diameter_m - 0.20).abs() < 1e-9, "diameter {}", c.diameter_m);
    assert!((c.depth_m - 0.10).abs() < 1e-9, "depth {}", c.depth_m);
    // the half section alone reads its radius as a width
    let h = measure_xy(&half, ds).unwrap();
    assert!(h.diameter_m < 0.11, "half section {}", h.diameter_m);
}

#[test]
fn a_cavity_under_an_intact_dome_is_no_crater() {
    let ds = 0.01;
    // a charge's hole 3 cm below the surface at t = 0; later a bigger cavity, and the dome
    // over it raised by 2 cm
    let hole = |x: f64, y: f64| (x - 0.35).abs() < 0.03 && (y - 0.58).abs() < 0.01;
    let soil0 = lattice(ds, 0.7, 0.62, &hole);
    let gas = |x: f64, y: f64| (x - 0.35).abs() < 0.06 && (y - 0.58).abs() < 0.03;
    let (x1, mut y1) = lattice(ds, 0.7, 0.62, &gas);
    for k in 0..x1.len() {
        if (x1[k] - 0.35).abs() < 0.06 && y1[k] > 0.61 {
            y1[k] += 0.02;
        }
    }
    let c = measure_xy(&CraterInput { soil0, soil1: (x1, y1), charge0: (Vec::new(), Vec::new()) }, ds).unwrap();
    assert_eq!(c.diameter_m, 0.0, "{c:?}");
    assert!(c.note.as_deref().unwrap().contains("contained"), "{:?}", c.note);
    let cav = c.cavity.expect("the cavity");
    assert!(cav.width_m >= 0.08 && cav.height_m >= 0.03, "{cav:?}");
    assert!(c.mound_height_m > 0.015, "{}", c.mound_height_m);
}

/// The charge's cavity is the void that holds its initial positions: a larger void the blast
/// opened elsewhere (a gap at the box's floor) is not it.
#[test]
fn the_cavity_is_the_void_that_holds_the_charge() {
    let ds = 0.01;
    let hole = |x: f64, y: f64| (x - 0.35).abs() < 0.03 && (y - 0.45).abs() < 0.02;
    let soil0 = lattice(ds, 0.7, 0.62, &hole);
    // later: the charge's hole a little larger, and a wider gap low in the box, far off
    let gaps = |x: f64, y: f64| {
        ((x - 0.35).abs() < 0.04 && (y - 0.45).abs() < 0.03) || ((x - 0.6).abs() < 0.06 && (y - 0.1).abs() < 0.04)
    };
    let soil1 = lattice(ds, 0.7, 0.62, &gaps);
    let mut charge0 = (Vec::new(), Vec::new());
    for x in [0.335, 0.345, 0.355, 0.365] {
        for y in [0.435, 0.445, 0.455, 0.465] {
            charge0.0.push(x);
            charge0.1.push(y);
        }
    }
    let c = measure_xy(&CraterInput { soil0: soil0.clone(), soil1: soil1.clone(), charge0 }, ds).unwrap();
    let cav = c.cavity.expect("the charge's cavity");
    assert!((cav.centre_m[0] - 0.35).abs() < 0.011 && (cav.centre_m[1] - 0.45).abs() < 0.011, "{cav:?}");
    // a charge elsewhere (in no void): no cavity at all
    let away = (vec![0.1], vec![0.3]);
    let c = measure_xy(&CraterInput { soil0, soil1, charge0: away }, ds).unwrap();
    assert!(c.cavity.is_none(), "{:?}", c.cavity);
}

/// Soil whose width is an exact multiple of the spacing (0.552 m of 11.5 mm columns, whose
/// quotient rounds to 48.00000000000001) has no void beside its last column when that column
/// moves in a little under a particle thrown over the side (the raster had one column more,
/// outside the soil, inside its margin: a void under that particle).
#[test]
fn a_box_of_whole_columns_has_no_void_beside_it() {
    let ds = 0.0115;
    let soil0 = lattice(ds, 0.552, 0.552, &|_, _| false);
    // the outer column drawn in by a third of a spacing (the soil at a box's free side)
    let mut soil1 = soil0.clone();
    for x in soil1.0.iter_mut().filter(|x| **x > 0.552 - ds) {
        *x -= 0.3 * ds;
    }
    // and a particle of the rim thrown out over the side, at the ground's level
    soil1.0.push(0.552 + 0.5 * ds);
    soil1.1.push(0.552 - 0.5 * ds);
    let c = measure_xy(&CraterInput { soil0, soil1, charge0: Default::default() }, ds).unwrap();
    assert!(c.cavity.is_none(), "{:?}", c.cavity);
}

#[test]
fn positions_that_are_not_numbers_give_a_reason() {
    let (x0, y0) = lattice(0.01, 0.2, 0.2, &|_, _| false);
    let mut y1 = y0.clone();
    y1[7] = f64::NAN;
    let e = measure_xy(&CraterInput { soil0: (x0.clone(), y0), soil1: (x0, y1), charge0: Default::default() }, 0.01)
        .unwrap_err();
    assert!(e.contains("not finite") && e.contains("unstable"), "{e}");
    let e = measure_xy(&CraterInput::default(), 0.01).unwrap_err();
    assert!(e.contains("no soil particles"), "{e}");
}
