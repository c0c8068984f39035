//! The blast part of `blastsph report`: crater growth and profile, ejecta, gauge pressure–time
//! curves, peak pressure against distance, and particle snapshots coloured by material and by
//! pressure. Thesis values (analysis.thesis_crater_m) are printed beside ours.

use crate::analysis::crater::{Crater, measure_xy, soil_mask};
use crate::case::Case;
use crate::error::{Result, SphError};
use crate::output::Frame;
use crate::plot;
use plotters::style::RGBColor;
use serde_json::{Value, json};
use std::collections::HashMap;
use std::path::Path;

/// Soil positions of a frame, and the initial positions of the same particles (matched by id).
fn soil_xy(
    f: &Frame,
    f0: &Frame,
    soil: &[bool],
    idx0: &HashMap<i64, usize>,
) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
    let (mut x0, mut y0, mut x1, mut y1) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for i in 0..f.x.len() {
        if !soil.get(f.mat[i] as usize).copied().unwrap_or(false) {
            continue;
        }
        if let Some(&k) = idx0.get(&f.id[i]) {
            x0.push(f0.x[k]);
            y0.push(f0.y[k]);
            x1.push(f.x[i]);
            y1.push(f.y[i]);
        }
    }
    (x0, y0, x1, y1)
}

/// Crater of every frame.
pub fn crater_history(case: &Case, frames: &[Frame], dx: f64) -> Vec<(f64, Crater)> {
    let soil = soil_mask(case);
    let f0 = &frames[0];
    let idx0: HashMap<i64, usize> = f0.id.iter().enumerate().map(|(k, id)| (*id, k)).collect();
    frames
        .iter()
        .map(|f| {
            let (x0, y0, x1, y1) = soil_xy(f, f0, &soil, &idx0);
            (f.time, measure_xy(&x0, &y0, &x1, &y1, dx))
        })
        .collect()
}

/// Gauge names and their (time s, pressure Pa) records.
type GaugeRecords = (Vec<String>, Vec<Vec<(f64, f64)>>);

fn read_gauges(path: &Path) -> Result<GaugeRecords> {
    let text = std::fs::read_to_string(path).map_err(|e| SphError::Io(format!("{}: {e}", path.display())))?;
    let mut lines = text.lines();
    let head: Vec<String> =
        lines.next().unwrap_or("").split(',').skip(1).map(|s| s.trim_end_matches("_p_pa").to_string()).collect();
    let mut series = vec![Vec::new(); head.len()];
    for l in lines {
        if l.starts_with('#') {
            continue;
        }
        let v: Vec<f64> = l.split(',').filter_map(|s| s.parse().ok()).collect();
        if v.len() == head.len() + 1 {
            for k in 0..head.len() {
                series[k].push((v[0], v[k + 1]));
            }
        }
    }
    Ok((head, series))
}

/// Snapshot colour of a material, by its kind: explosive red, water blue, soil tan, gas grey
/// (materials of one kind get darker shades).
fn material_colours(case: &Case) -> Vec<RGBColor> {
    let mut seen = std::collections::HashMap::new();
    case.materials
        .iter()
        .map(|m| {
            let (r, g, b) = match m.eos {
                crate::case::EosCfg::Jwl { .. } => (210, 30, 30),
                crate::case::EosCfg::Water { .. } => (40, 110, 210),
                crate::case::EosCfg::Soil { .. } => (196, 164, 96),
                crate::case::EosCfg::IdealGas { .. } => (140, 140, 140),
            };
            let k = seen.entry(m.eos.kind()).or_insert(0u32);
            let f = 1.0 - 0.3 * (*k as f64).min(2.0);
            *k += 1;
            RGBColor((r as f64 * f) as u8, (g as f64 * f) as u8, (b as f64 * f) as u8)
        })
        .collect()
}

pub fn report(dir: &Path, case: &Case, summary: &Value, frames: &[Frame], times: &[f64]) -> Result<Value> {
    if frames.is_empty() || case.dim != 2 {
        return Ok(json!({}));
    }
    let dx = case.regions.iter().map(|r| r.spacing_m).fold(f64::INFINITY, f64::min);
    let crater = case.analysis.kind == crate::case::AnalysisKind::Crater;
    let hist = if crater { crater_history(case, frames, dx) } else { Vec::new() };
    let last = &hist.last().map(|h| h.1.clone()).unwrap_or_default();
    let us = |t: f64| t * 1e6;
    let quarters: Vec<usize> = {
        let n = frames.len();
        let mut v = vec![0, n / 4, n / 2, 3 * n / 4, n - 1];
        v.dedup();
        v
    };
    // frames of the snapshots: the quarters, or the outputs nearest the times asked for
    let picks: Vec<usize> = {
        let n = frames.len();
        let mut v = if times.is_empty() {
            quarters.clone()
        } else {
            times
                .iter()
                .map(|t| {
                    (0..n)
                        .min_by(|&a, &b| (frames[a].time - t).abs().total_cmp(&(frames[b].time - t).abs()))
                        .unwrap_or(0)
                })
                .collect()
        };
        v.sort_unstable();
        v.dedup();
        v
    };
    let bubble = bubble_history(case, frames);
    if !bubble.is_empty() {
        plot::lines(
            &dir.join("bubble_growth.png"),
            &format!("{}: detonation products, equivalent radius sqrt(A/pi)", case.name()),
            "t (us)",
            "radius (cm)",
            &[("products".to_string(), bubble.iter().map(|(t, r)| (us(*t), 100.0 * r)).collect())],
            false,
        )?;
        if let Some((t, r)) = bubble.last() {
            println!("detonation products at t = {:.0} us: equivalent radius {:.1} cm", us(*t), 100.0 * r);
        }
    }
    if crater {
        // crater growth
        let grow = vec![
            ("diameter (cm)".to_string(), hist.iter().map(|(t, c)| (us(*t), 100.0 * c.diameter_m)).collect::<Vec<_>>()),
            ("depth (cm)".to_string(), hist.iter().map(|(t, c)| (us(*t), 100.0 * c.depth_m)).collect()),
            ("ejecta height (cm)".to_string(), hist.iter().map(|(t, c)| (us(*t), 100.0 * c.ejecta_height_m)).collect()),
        ];
        plot::lines(
            &dir.join("crater_growth.png"),
            &format!("{}: crater and ejecta", case.name()),
            "t (us)",
            "cm",
            &grow,
            false,
        )?;
        // crater profile at a few times
        let mut prof = vec![(
            "t = 0".to_string(),
            last.columns_m
                .iter()
                .zip(&last.surface0_m)
                .filter(|p| p.1.is_finite())
                .map(|(x, y)| (*x, *y))
                .collect::<Vec<_>>(),
        )];
        for &k in quarters.iter().skip(1) {
            let c = &hist[k].1;
            prof.push((
                format!("t = {:.0} us", us(hist[k].0)),
                c.columns_m.iter().zip(&c.surface_m).filter(|p| p.1.is_finite()).map(|(x, y)| (*x, *y)).collect(),
            ));
        }
        plot::lines(
            &dir.join("crater_profile.png"),
            &format!("{}: ground surface", case.name()),
            "x (m)",
            "surface height (m)",
            &prof,
            false,
        )?;
    }
    // gauges
    let gpath = dir.join("gauges.csv");
    let mut peaks = Vec::new();
    if gpath.exists() {
        let (names, series) = read_gauges(&gpath)?;
        let s: Vec<(String, Vec<(f64, f64)>)> = names
            .iter()
            .zip(&series)
            .map(|(n, v)| (format!("gauge {n}"), v.iter().map(|(t, p)| (us(*t), p / 1e6)).collect()))
            .collect();
        plot::lines(
            &dir.join("gauges.png"),
            &format!("{}: pressure at the gauges", case.name()),
            "t (us)",
            "p (MPa)",
            &s,
            false,
        )?;
        let centre: Vec<f64> =
            case.detonation.as_ref().and_then(|d| d.point_m.clone()).unwrap_or_else(|| vec![0.5, 1.0]);
        if let Some(g) = summary["gauges"].as_array() {
            for gg in g {
                let pt: Vec<f64> =
                    gg["point_m"].as_array().map(|a| a.iter().filter_map(|v| v.as_f64()).collect()).unwrap_or_default();
                let r = pt.iter().zip(&centre).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
                peaks.push((100.0 * r, gg["peak_pa"].as_f64().unwrap_or(0.0) / 1e6));
            }
            plot::lines(
                &dir.join("peaks.png"),
                &format!("{}: peak pressure against distance", case.name()),
                "distance from the charge centre (cm)",
                "peak p (MPa)",
                &[("SPH".to_string(), peaks.clone())],
                true,
            )?;
        }
    }
    // snapshots
    let f0 = &frames[0];
    let (xlo, xhi) =
        (f0.x.iter().cloned().fold(f64::INFINITY, f64::min), f0.x.iter().cloned().fold(f64::NEG_INFINITY, f64::max));
    let (ylo, yhi) =
        (f0.y.iter().cloned().fold(f64::INFINITY, f64::min), f0.y.iter().cloned().fold(f64::NEG_INFINITY, f64::max));
    let w = xhi - xlo;
    let bounds = ((xlo - 0.05 * w, xhi + 0.05 * w), (ylo - 0.05 * w, yhi + 0.5 * w));
    let mut snaps = Vec::new();
    let colours = material_colours(case);
    for &k in &picks {
        let f = &frames[k];
        let tag = format!("{:05.0}us", us(f.time));
        let pm = dir.join(format!("snap_material_{tag}.png"));
        plot::snapshot(
            &pm,
            &format!("{} t = {:.0} us, by material", case.name(), us(f.time)),
            &f.x,
            &f.y,
            &|i| colours[(f.mat[i].max(0) as usize).min(colours.len() - 1)],
            bounds,
        )?;
        let pp = dir.join(format!("snap_pressure_{tag}.png"));
        plot::snapshot(
            &pp,
            &format!("{} t = {:.0} us, pressure: log10(p/0.1 MPa) on [0, 5] (blue to red)", case.name(), us(f.time)),
            &f.x,
            &f.y,
            &|i| plot::heat((f.p[i].max(1e5) / 1e5).log10() / 5.0),
            bounds,
        )?;
        snaps.push(pm.file_name().map(|s| s.to_string_lossy().to_string()));
        snaps.push(pp.file_name().map(|s| s.to_string_lossy().to_string()));
    }
    if crater {
        println!(
            "crater at t = {:.0} us: diameter {:.1} cm, depth {:.1} cm (bowl {:.1} cm wide at half depth), ejecta height {:.1} cm",
            us(hist.last().map(|h| h.0).unwrap_or(0.0)),
            100.0 * last.diameter_m,
            100.0 * last.depth_m,
            100.0 * last.width_half_depth_m,
            100.0 * last.ejecta_height_m
        );
    }
    if let Some(th) = &case.analysis.thesis_crater_m
        && th.len() == 2
    {
        println!(
            "thesis (Table 5-3/5-4): diameter {:.1} cm, depth {:.1} cm; ours/thesis: diameter {:.2}, depth {:.2}",
            100.0 * th[0],
            100.0 * th[1],
            last.diameter_m / th[0],
            last.depth_m / th[1]
        );
    }
    for (r, p) in &peaks {
        println!("gauge at {r:.0} cm: peak {p:.2} MPa");
    }
    let growth = thesis_growth(case, &hist);
    for g in &growth {
        println!(
            "thesis at {:.0} us: diameter {} cm, depth {} cm; ours at {:.0} us: diameter {:.1} cm, depth {:.1} cm",
            g["thesis_t_s"].as_f64().unwrap_or(0.0) * 1e6,
            fmt_cm(g["thesis_diameter_m"].as_f64()),
            fmt_cm(g["thesis_depth_m"].as_f64()),
            g["our_t_s"].as_f64().unwrap_or(0.0) * 1e6,
            100.0 * g["diameter_m"].as_f64().unwrap_or(0.0),
            100.0 * g["depth_m"].as_f64().unwrap_or(0.0)
        );
    }
    let gauges = thesis_gauges(case, summary);
    for g in &gauges {
        println!(
            "gauge {}: thesis peak {} at {}; ours {:.2} MPa at {:.0} us (arrival {:.0} us)",
            g["gauge"].as_str().unwrap_or("?"),
            g["thesis_peak_pa"].as_f64().map_or("-".to_string(), |p| format!("{:.1} MPa", p / 1e6)),
            g["thesis_peak_time_s"].as_f64().map_or("-".to_string(), |t| format!("{:.0} us", t * 1e6)),
            g["peak_pa"].as_f64().unwrap_or(0.0) / 1e6,
            g["peak_time_s"].as_f64().unwrap_or(0.0) * 1e6,
            g["arrival_s"].as_f64().unwrap_or(0.0) * 1e6
        );
    }
    Ok(json!({
        "crater": { "diameter_m": last.diameter_m, "depth_m": last.depth_m, "width_half_depth_m": last.width_half_depth_m, "ejecta_height_m": last.ejecta_height_m },
        "thesis_crater_m": case.analysis.thesis_crater_m,
        "history": hist.iter().map(|(t, c)| json!({"t_s": t, "diameter_m": c.diameter_m, "depth_m": c.depth_m, "ejecta_height_m": c.ejecta_height_m})).collect::<Vec<_>>(),
        "profile": { "x_m": last.columns_m, "surface0_m": last.surface0_m, "surface_m": last.surface_m },
        "peaks_cm_mpa": peaks,
        "thesis_growth": growth,
        "thesis_gauges": gauges,
        "bubble": bubble.iter().map(|(t, r)| json!({"t_s": t, "equivalent_radius_m": r})).collect::<Vec<_>>(),
        "snapshots": snaps,
    }))
}

fn fmt_cm(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{:.0}", 100.0 * x),
        _ => "-".into(),
    }
}

/// Our crater at each time of the thesis's crater-growth rows (the nearest output).
pub fn thesis_growth(case: &Case, hist: &[(f64, Crater)]) -> Vec<Value> {
    let rows = case.analysis.thesis_crater_history.clone().unwrap_or_default();
    rows.iter()
        .filter_map(|r| {
            let (t, d, z) = (r[0], r[1], r[2]);
            let (tt, c) = hist.iter().min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()))?;
            Some(json!({
                "thesis_t_s": t,
                "thesis_diameter_m": if d.is_finite() { json!(d) } else { Value::Null },
                "thesis_depth_m": if z.is_finite() { json!(z) } else { Value::Null },
                "our_t_s": tt,
                "diameter_m": c.diameter_m,
                "depth_m": c.depth_m,
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

/// Equivalent radius √(A/π) of the detonation products (2D: A = Σ m_i/ρ_i over the JWL
/// particles, m²) at every frame; empty without an explosive.
pub fn bubble_history(case: &Case, frames: &[Frame]) -> Vec<(f64, f64)> {
    let jwl: Vec<bool> = case.materials.iter().map(|m| matches!(m.eos, crate::case::EosCfg::Jwl { .. })).collect();
    if !jwl.iter().any(|j| *j) {
        return Vec::new();
    }
    frames
        .iter()
        .map(|f| {
            let a: f64 = (0..f.mass.len())
                .filter(|&i| jwl.get(f.mat[i] as usize).copied().unwrap_or(false))
                .map(|i| f.mass[i] / f.rho[i])
                .sum();
            (f.time, (a / std::f64::consts::PI).sqrt())
        })
        .collect()
}
