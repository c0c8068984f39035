//! The report's text: the crater's headline, its scaled radius, the thesis's values beside ours.

use super::*;

/// The crater's radius scaled by the charge, R/W^⅓ (m/kg^⅓), and the report's line for it: for
/// a charge whose blast spreads in 3D (RZ, 3D; not a plane-strain line charge) and a crater with
/// a diameter. R is half the crater's diameter at the original ground level: in 3D the surface
/// map's equivalent diameter 2√(A/π) (the revolved headline reads the crater's narrowest
/// direction), else the headline's. W is the whole scene's explosive (kg; the modelled part times
/// its symmetry planes' copies), whatever the explosive: TNT data want its TNT equivalence.
pub(super) fn scaled_crater(charge: &Charge, crater: &Value, map: Option<&SurfaceMap>) -> Option<(f64, String)> {
    if charge.dim != 3 || charge.mass_kg.is_nan() || charge.mass_kg <= 0.0 || !crater["note"].is_null() {
        return None;
    }
    let (d, from) = match map {
        Some(m) if m.note.is_none() && m.equivalent_diameter_m > 0.0 => {
            (m.equivalent_diameter_m, "the surface map's equivalent diameter")
        }
        _ => (crater["diameter_m"].as_f64()?, "the headline diameter"),
    };
    if d.is_nan() || d <= 0.0 {
        return None;
    }
    let scaled = 0.5 * d / charge.mass_kg.cbrt();
    Some((
        scaled,
        format!(
            "crater scaled by the charge: R/W^(1/3) = {scaled:.3} m/kg^(1/3) (R = {} cm, half {from}; W = {:.4} kg of explosive in the whole scene); a crater grows until its flow stops: compare a final crater only (docs/validation.md, \"Crater scaling against surface-burst data\")",
            cm1(0.5 * d),
            charge.mass_kg
        ),
    ))
}

/// Why the crater of revolution misreads a 3D crater whose original ground is not level about
/// the charge (its relief within twice the crater's edge, [`SurfaceMap::ground_relief_m`], above
/// one cell), if it does.
pub(super) fn uneven_ground(m: &SurfaceMap) -> Option<String> {
    (!m.ground_is_level()).then(|| {
        format!(
            "the original ground is not level about the charge: its height varies by {} cm {}; the crater revolved about the charge's axis (the headline diameter and depth, crater_profile.png) takes the highest original ground at each distance from the axis, so it misreads the crater where the ground falls away: measure it by the surface (crater_map.png) and the sections",
            cm1(m.ground_relief_m),
            if m.radius_max_m > 0.0 {
                format!("within {} cm of the axis (twice the crater's edge)", cm1(2.0 * m.radius_max_m))
            } else {
                "over the scene".to_string()
            }
        )
    })
}

/// The report's text (crater, cavity, thesis comparisons, gauges), printed; returns the crater's
/// JSON, the thesis growth and the thesis gauges.
pub(super) fn print_text(
    case: &Case,
    summary: &Value,
    hist: &[(f64, std::result::Result<Crater, String>)],
    map: Option<&std::result::Result<SurfaceMap, String>>,
) -> (Value, Vec<Value>, Vec<Value>) {
    let mut last = hist.last().map(|h| h.1.clone());
    if let Some(Ok(c)) = &mut last {
        c.bounded = crate::analysis::crater::box_bound(case, c, map.and_then(|m| m.as_ref().ok()));
    }
    let crater_json = crater_headline(case, hist, &last);
    let measured = matches!(&last, Some(Ok(c)) if c.note.is_none());
    print_3d(summary, &last, map);
    let gauge_list = summary["gauges"].as_array().cloned().unwrap_or_default();
    print_gauge_lines(summary, true);
    // a point gauge inside the contained charge's cavity at the end reads the products
    if let Some(Ok(Crater { cavity: Some(cv), .. })) = &last {
        let axis = map.and_then(|m| m.as_ref().ok()).map(|m| m.axis_m);
        for g in case.gauges.iter().filter(|g| g.kind == crate::case::GaugeKind::Point) {
            let p = &g.point_m;
            // the gauge in the measure's section: (x, y) in 2D plane; (±r, z) in RZ and 3D
            let (s, z) = match (case.dim, axis) {
                (3, Some(a)) => ((p[0] - a[0]).hypot(p[1] - a[1]), p[2]),
                (3, None) => continue,
                _ => (p[0], p[1]),
            };
            let across = |u: f64| (u - cv.centre_m[0]).abs() <= 0.5 * cv.width_m;
            let inside = (across(s) || ((case.axisymmetric() || case.dim == 3) && across(-s)))
                && (z - cv.centre_m[1]).abs() <= 0.5 * cv.height_m;
            if inside {
                println!(
                    "gauge {}: its point lies inside the cavity's bounding box at the end: its late record is the detonation products' pressure, not the soil's",
                    g.name
                );
            }
        }
    }
    // (a blast's shock; not a piston's elastic wave, whose peak is a plateau)
    if !gauge_list.is_empty() && case.materials.iter().any(|m| matches!(m.eos, crate::case::EosCfg::Jwl { .. })) {
        println!(
            "gauges: the peaks rise as the spacing shrinks (the shock's front is smeared over a few smoothing lengths); arrival and impulse converge first (docs/validation.md, \"Why the peaks do not agree\")"
        );
    }
    let (growth, gauges) = print_thesis(case, summary, hist, (&last, measured));
    (crater_json, growth, gauges)
}

/// The thesis's values (`analysis.thesis_*`) beside ours, in a section of their own after our
/// results: the final crater (`last`, and whether it was `measured`), its growth and the gauges'
/// peaks. Returns the growth rows and the gauge rows ([`thesis_growth`], [`thesis_gauges`]).
fn print_thesis(
    case: &Case,
    summary: &Value,
    hist: &[(f64, std::result::Result<Crater, String>)],
    (last, measured): (&Option<std::result::Result<Crater, String>>, bool),
) -> (Vec<Value>, Vec<Value>) {
    let growth = thesis_growth(case, hist);
    let gauges = thesis_gauges(case, summary);
    let crater = case.analysis.thesis_crater_m.as_ref().is_some_and(|th| th.len() == 2);
    if !crater && growth.is_empty() && gauges.is_empty() {
        return (growth, gauges);
    }
    println!("Comparison with the thesis (Karimi Farzaghi 2017):");
    if let Some(th) = &case.analysis.thesis_crater_m
        && th.len() == 2
    {
        match &last {
            Some(Ok(c)) if measured => println!(
                "  crater (thesis Table 5-3/5-4): diameter {:.1} cm, depth {:.1} cm; ours/thesis: diameter {:.2}, depth {:.2}",
                100.0 * th[0],
                100.0 * th[1],
                c.diameter_m / th[0],
                c.depth_m / th[1]
            ),
            _ => println!(
                "  crater (thesis Table 5-3/5-4): diameter {:.1} cm, depth {:.1} cm; ours: no apparent crater to compare",
                100.0 * th[0],
                100.0 * th[1]
            ),
        }
    }
    for g in &growth {
        println!(
            "  crater growth: thesis at {:.0} µs: diameter {} cm, depth {} cm; ours at {:.0} µs: diameter {} cm, depth {} cm",
            g["thesis_t_s"].as_f64().unwrap_or(0.0) * 1e6,
            fmt_cm(g["thesis_diameter_m"].as_f64()),
            fmt_cm(g["thesis_depth_m"].as_f64()),
            g["our_t_s"].as_f64().unwrap_or(0.0) * 1e6,
            fmt_cm1(g["diameter_m"].as_f64()),
            fmt_cm1(g["depth_m"].as_f64())
        );
    }
    for g in &gauges {
        println!(
            "  gauge {}: thesis peak {} at {}; ours {} at {} (arrival {})",
            g["gauge"].as_str().unwrap_or("?"),
            g["thesis_peak_pa"].as_f64().map_or("(pressure not given)".to_string(), |p| format!("{:.1} MPa", p / 1e6)),
            g["thesis_peak_time_s"].as_f64().map_or("-".to_string(), |t| format!("{:.0} µs", t * 1e6)),
            g["peak_pa"].as_f64().map_or("-".to_string(), |p| format!("{:.2} MPa", p / 1e6)),
            g["peak_time_s"].as_f64().map_or("-".to_string(), |t| format!("{:.0} µs", t * 1e6)),
            g["arrival_s"].as_f64().map_or("-".to_string(), |t| format!("{:.0} µs", t * 1e6))
        );
    }
    (growth, gauges)
}

/// The crater's headline (printed) and its JSON: the last measure of the history, with its
/// notes, the box's bound and the cavity.
fn crater_headline(
    case: &Case,
    hist: &[(f64, std::result::Result<Crater, String>)],
    last: &Option<std::result::Result<Crater, String>>,
) -> Value {
    match last {
        Some(Ok(c)) => {
            let t_last = hist.last().map(|h| h.0).unwrap_or(0.0);
            let t_end = TimeUnit::for_end(t_last).text(t_last);
            // (3D: the crater of revolution about the charge's axis, all azimuths together)
            let how = if case.dim == 3 { " (revolved about the charge's axis)" } else { "" };
            match &c.note {
                None => println!(
                    "crater{how} at t = {}: diameter {} cm, depth {} cm (bowl {} cm wide at half depth), ejecta height {} (columns {} wide, the soil's spacing)",
                    t_end,
                    cm1(c.diameter_m),
                    cm1(c.depth_m),
                    cm1(c.width_half_depth_m),
                    height_text(c.ejecta_height_m),
                    crate::converge::spacing_text(c.column_m)
                ),
                Some(why) => println!("crater{how} at t = {t_end}: {why}"),
            }
            if let Some(k) = &c.crack {
                println!("note: {k}");
            }
            if let Some(b) = &c.bounded {
                println!("warning: {b}");
            }
            if let Some(w) = crate::advice::several_charges(case) {
                println!("note: {w}");
            }
            if let Some(cv) = &c.cavity {
                println!(
                    "cavity: {} cm wide, {} cm tall, {:.1} cm² in section, its top {} cm {} the original surface",
                    cm1(cv.width_m),
                    cm1(cv.height_m),
                    cv.area_m2 * 1e4,
                    cm1(cv.top_depth_m.abs()),
                    if cv.top_depth_m >= 0.0 { "below" } else { "above" }
                );
            }
            let mut v = serde_json::to_value(c).unwrap_or(Value::Null);
            v["measured"] = json!(true);
            v
        }
        Some(Err(why)) => {
            println!("crater: cannot be measured: {why}");
            json!({ "measured": false, "reason": why })
        }
        None => Value::Null,
    }
}

/// A 3D crater's lines: its sections through the charge's axis, its surface, a crater that is
/// not axisymmetric and ground that is not level.
fn print_3d(
    summary: &Value,
    last: &Option<std::result::Result<Crater, String>>,
    map: Option<&std::result::Result<SurfaceMap, String>>,
) {
    // 3D: the run's final crater in vertical sections through the charge's axis (summary.json)
    let sections = summary["crater"]["sections"].as_array().cloned().unwrap_or_default();
    if !sections.is_empty() {
        let each: Vec<String> = sections
            .iter()
            .map(|x| {
                let deg = x["azimuth_deg"].as_f64().unwrap_or(f64::NAN);
                match x["note"].as_str() {
                    Some(why) if x["diameter_m"].as_f64() == Some(0.0) => format!("{deg:.0}°: {why}"),
                    _ => format!(
                        "{deg:.0}°: {} cm wide, {} cm deep",
                        cm1(x["diameter_m"].as_f64().unwrap_or(f64::NAN)),
                        cm1(x["depth_m"].as_f64().unwrap_or(f64::NAN))
                    ),
                }
            })
            .collect();
        println!("crater in sections through the charge's axis (the run's end): {}", each.join("; "));
    }
    // 3D: the final crater as a surface (crater_map.png)
    match map {
        Some(Ok(m)) => match &m.note {
            None => println!(
                "crater as a surface (the run's end, cells {}, the whole scene): equivalent diameter {} cm (plan area {:.0} cm²), depth {} cm at ({}, {}) cm from the charge's axis, volume {:.2} L, its edge {} to {} cm from the axis",
                crate::converge::spacing_text(m.cell_m),
                cm1(m.equivalent_diameter_m),
                m.plan_area_m2 * 1e4,
                cm1(m.depth_m),
                cm1(m.deepest_m[0] - m.axis_m[0]),
                cm1(m.deepest_m[1] - m.axis_m[1]),
                m.volume_m3 * 1e3,
                cm1(m.radius_min_m),
                cm1(m.radius_max_m)
            ),
            Some(why) => println!("crater as a surface (the run's end): {why}"),
        },
        Some(Err(why)) => println!("crater as a surface: cannot be measured: {why}"),
        None => {}
    }
    // 3D: a crater that is not axisymmetric about the charge's axis (a wall beside it, a slope,
    // two charges): the revolved headline reads its narrowest, shallowest direction
    if let (Some(Ok(c)), Some(Ok(m))) = (last, map)
        && c.note.is_none()
        && m.note.is_none()
    {
        let widths: Vec<f64> = sections.iter().filter_map(|x| x["diameter_m"].as_f64()).filter(|w| *w > 0.0).collect();
        let (wmin, wmax) = widths.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &w| (a.min(w), b.max(w)));
        let wide = m.equivalent_diameter_m > 1.1 * c.diameter_m || m.depth_m > 1.1 * c.depth_m;
        if wide || (!widths.is_empty() && wmax > 1.1 * wmin) {
            println!(
                "note: the crater is not axisymmetric about the charge's axis: the revolved crater ({} cm wide, {} cm deep) reads its narrowest, shallowest direction; measure it by the surface ({} cm equivalent diameter, {} cm deep) and the sections ({}–{} cm wide)",
                cm1(c.diameter_m),
                cm1(c.depth_m),
                cm1(m.equivalent_diameter_m),
                cm1(m.depth_m),
                cm1(if wmin.is_finite() { wmin } else { 0.0 }),
                cm1(wmax)
            );
        }
    }
    // 3D: ground that is not level about the charge (a slope, a step): the crater of revolution
    // takes the highest original ground at each distance from the axis
    if let Some(Ok(m)) = map
        && let Some(why) = uneven_ground(m)
    {
        println!("note: {why}");
    }
}

/// The crater history as JSON rows.
pub(super) fn history_json(hist: &[(f64, std::result::Result<Crater, String>)]) -> Vec<Value> {
    hist.iter()
        .map(|(t, c)| match c {
            Ok(c) => json!({"t_s": t, "diameter_m": c.diameter_m, "depth_m": c.depth_m, "ejecta_height_m": c.ejecta_height_m, "cavity": c.cavity}),
            Err(why) => json!({"t_s": t, "measured": false, "reason": why}),
        })
        .collect()
}

/// A peak's label on peaks.png: four significant digits in MPa (365.9, 51.91, 0.1234; the
/// peaks are not converged beyond that), "-" when there is none.
pub(super) fn tick(p: f64) -> String {
    if !p.is_finite() {
        return "-".into();
    }
    let decimals = if p == 0.0 { 0 } else { plot::decimals_for(p, 4, 6) };
    format!("{p:.decimals$} MPa")
}

pub(super) fn fmt_cm(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{:.0}", 100.0 * x),
        _ => "-".into(),
    }
}

pub(super) fn fmt_cm1(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{:.1}", 100.0 * x),
        _ => "-".into(),
    }
}

/// Our crater at each time of the thesis's crater-growth rows (the nearest output).
pub fn thesis_growth(case: &Case, hist: &[(f64, std::result::Result<Crater, String>)]) -> Vec<Value> {
    let rows = case.analysis.thesis_crater_history.clone().unwrap_or_default();
    rows.iter()
        .filter_map(|r| {
            let (t, d, z) = (r[0], r[1], r[2]);
            let (tt, c) = hist.iter().min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()))?;
            let (dm, zm) = match c {
                Ok(c) => (json!(c.diameter_m), json!(c.depth_m)),
                Err(_) => (Value::Null, Value::Null),
            };
            Some(json!({
                "thesis_t_s": t,
                "thesis_diameter_m": if d.is_finite() { json!(d) } else { Value::Null },
                "thesis_depth_m": if z.is_finite() { json!(z) } else { Value::Null },
                "our_t_s": tt,
                "diameter_m": dm,
                "depth_m": zm,
            }))
        })
        .collect()
}

/// Our gauge peaks beside the thesis's readings.
pub fn thesis_gauges(case: &Case, summary: &Value) -> Vec<Value> {
    let ours = summary["gauges"].as_array().cloned().unwrap_or_default();
    case.analysis
        .thesis_gauge
        .iter()
        .filter_map(|t| {
            let g = ours.iter().find(|g| g["name"] == t.gauge.as_str())?;
            Some(json!({
                "gauge": t.gauge,
                "thesis_peak_time_s": t.peak_time_s,
                "thesis_peak_pa": t.peak_pa,
                "peak_time_s": g["peak_time_s"],
                "peak_pa": g["peak_pa"],
                "arrival_s": g["arrival_s"],
            }))
        })
        .collect()
}
