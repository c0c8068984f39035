//! The blast part of `blastsph report`: crater growth and profile (with the cavity of a
//! contained charge), ejecta, gauge histories (pressure and particle velocity), peak pressure
//! against scaled distance, and particle maps: by material, pressure, velocity magnitude and
//! peak particle velocity; in 3D the crater's plan view (`crater_map.png`). Reference values
//! the case carries (`analysis.thesis_*`) are drawn on the plots and printed beside ours.
//! `--animate` adds animation.gif.
//!
//! Units on every plot: m, cm, MPa, m/s, and time in µs (ms for a run of 20 ms or more, s from 20 s:
//! `TimeUnit`). Colour maps are viridis (perceptually uniform),
//! logarithmic for pressure and speeds, with a colour bar in those units.

use crate::analysis::crater::{Crater, CraterInput, SurfaceMap, explosive_mask, measure_xy, soil_mask, soil_spacing};
use crate::case::Case;
use crate::error::Result;
use crate::output::Frame;
use crate::plot::{self, Colouring, MapSpec, Reference, Scale};
use plotters::style::RGBColor;
use serde_json::{Value, json};
use std::collections::HashMap;
use std::path::Path;

mod gauges;
mod peaks;
mod scene;
mod text;
pub use gauges::*;
use peaks::gauge_plots;
pub use scene::*;
pub use text::*;

/// Crater of every frame: Ok, or the reason it cannot be measured.
pub fn crater_history(case: &Case, frames: &[Frame]) -> Vec<(f64, std::result::Result<Crater, String>)> {
    let Some(ds) = soil_spacing(case) else {
        return frames.iter().map(|f| (f.time, Err("no region of a soil material".to_string()))).collect();
    };
    let f0 = &frames[0];
    let idx0 = ids(f0);
    // 3D (z up): every point as (r, z) about the charge's vertical axis (crater::measure)
    let d3 = case.dim == 3;
    let ax = if d3 {
        match axis_of(case, f0) {
            Ok(a) => a,
            Err(why) => return frames.iter().map(|f| (f.time, Err(why.clone()))).collect(),
        }
    } else {
        (0.0, 0.0)
    };
    let pt = |p: &[f64; 3]| -> (f64, f64) {
        if d3 { crate::analysis::crater::about_axis(ax, p[0], p[1], p[2]) } else { (p[0], p[1]) }
    };
    let charge0: (Vec<f64>, Vec<f64>) = charge_points(case, f0).iter().map(pt).unzip();
    frames
        .iter()
        .map(|f| {
            let (s0, s1) = soil_points(case, f0, &idx0, f);
            let mut inp = CraterInput {
                soil0: s0.iter().map(pt).unzip(),
                soil1: s1.iter().map(pt).unzip(),
                charge0: charge0.clone(),
            };
            if case.axisymmetric() || d3 {
                inp = inp.through_the_axis();
            }
            (f.time, measure_xy(&inp, ds))
        })
        .collect()
}

/// Each particle's index in a frame by its id.
fn ids(f: &Frame) -> HashMap<i64, usize> {
    f.id.iter().enumerate().map(|(k, id)| (*id, k)).collect()
}

/// A particle's position (x, y, z; m; z = 0 below 3D).
fn point(f: &Frame, k: usize) -> [f64; 3] {
    [f.x[k], f.y[k], f.z.get(k).copied().unwrap_or(0.0)]
}

/// The explosive's positions in frame `f`.
fn charge_points(case: &Case, f: &Frame) -> Vec<[f64; 3]> {
    let expl = explosive_mask(case);
    (0..f.x.len()).filter(|&k| expl.get(f.mat[k] as usize).copied().unwrap_or(false)).map(|k| point(f, k)).collect()
}

/// The soil's particles of frame `f` that the first frame `f0` holds (matched by id through
/// `idx0`, [`ids`] of `f0`): their positions at t = 0 and in `f`.
fn soil_points(case: &Case, f0: &Frame, idx0: &HashMap<i64, usize>, f: &Frame) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let soil = soil_mask(case);
    (0..f.x.len())
        .filter(|&i| soil.get(f.mat[i] as usize).copied().unwrap_or(false))
        .filter_map(|i| idx0.get(&f.id[i]).map(|&k| (point(f0, k), point(f, i))))
        .unzip()
}

/// The vertical axis (x, y; m) of a 3D crater ([`crate::analysis::crater::axis_3d`]) from the
/// first frame.
fn axis_of(case: &Case, f0: &Frame) -> std::result::Result<(f64, f64), String> {
    let ch: Vec<(f64, f64)> = charge_points(case, f0).iter().map(|p| (p[0], p[1])).collect();
    crate::analysis::crater::axis_3d(case, &ch)
}

/// The 3D crater of frame `f` as a surface ([`crate::analysis::crater::surface_map`]), the
/// scene completed across its symmetry planes.
pub fn surface_map_of(case: &Case, f0: &Frame, f: &Frame) -> std::result::Result<SurfaceMap, String> {
    let ds = soil_spacing(case).ok_or("no region of a soil material")?;
    let ax = axis_of(case, f0)?;
    let (s0, s1) = soil_points(case, f0, &ids(f0), f);
    let mirrors = crate::analysis::crater::mirror_planes(case, ax, ds);
    crate::analysis::crater::surface_map(ax, ds, &mirrors, &s0, &s1, &charge_points(case, f0))
}

/// The plan view of a 3D crater: s − s0 in each cell (cm), the crater's outline and the
/// charge's axis.
fn draw_surface_map(path: &Path, case: &Case, t: f64, m: &SurfaceMap) -> Result<()> {
    let (nx, ny) = (m.x_m.len(), m.y_m.len());
    let ds = m.cell_m;
    let cells: Vec<usize> = (0..nx * ny).filter(|&k| m.change_m.get(k).is_some_and(|v| v.is_finite())).collect();
    let x: Vec<f64> = cells.iter().map(|&k| m.x_m[k % nx]).collect();
    let y: Vec<f64> = cells.iter().map(|&k| m.y_m[k / nx]).collect();
    let cm: Vec<f64> = cells.iter().map(|&k| 100.0 * m.change_m[k]).collect();
    // a scale symmetric about 0 (the undisturbed ground in its middle colour), to a round number
    let top = cm.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let step = if top > 20.0 {
        10.0
    } else if top > 4.0 {
        2.0
    } else {
        0.5
    };
    let top = (top / step).ceil().max(1.0) * step;
    let scale = Scale { lo: -top, hi: top, log: false, label: "s − s0 (cm)".into() };
    // the outline: the sides between a crater cell and one that is not
    let inside = |i: i64, j: i64| {
        i >= 0 && j >= 0 && i < nx as i64 && j < ny as i64 && m.crater_cells[i as usize + nx * j as usize]
    };
    let mut ov = plot::Overlay { marks: vec![(m.axis_m[0], m.axis_m[1])], ..Default::default() };
    for k in (0..nx * ny).filter(|&k| m.crater_cells[k]) {
        let (i, j) = ((k % nx) as i64, (k / nx) as i64);
        let (xa, xb, ya, yb) =
            (m.x_m[k % nx] - 0.5 * ds, m.x_m[k % nx] + 0.5 * ds, m.y_m[k / nx] - 0.5 * ds, m.y_m[k / nx] + 0.5 * ds);
        for (di, dj, side) in [
            (-1, 0, [(xa, ya), (xa, yb)]),
            (1, 0, [(xb, ya), (xb, yb)]),
            (0, -1, [(xa, ya), (xb, ya)]),
            (0, 1, [(xa, yb), (xb, yb)]),
        ] {
            if !inside(i + di, j + dj) {
                ov.segments.push(side);
            }
        }
    }
    let pad = 0.02 * ds;
    let bounds = (
        (m.x_m[0] - 0.5 * ds - pad, m.x_m[nx - 1] + 0.5 * ds + pad),
        (m.y_m[0] - 0.5 * ds - pad, m.y_m[ny - 1] + 0.5 * ds + pad),
    );
    let side = vec![ds; cells.len()];
    let what = match &m.note {
        None => format!(
            "red: the crater (> {:.1} cm below the original ground), equivalent diameter {} cm; ×: the charge's axis",
            50.0 * ds,
            cm1(m.equivalent_diameter_m)
        ),
        Some(why) => format!("{why}; ×: the charge's axis"),
    };
    plot::map_png(
        path,
        &MapSpec {
            title: format!(
                "{}  t = {}: ground surface s − s0, plan view (cells {})",
                case.name(),
                TimeUnit::for_end(t).text(t),
                crate::converge::spacing_text(ds)
            ),
            x: &x,
            y: &y,
            side: &side,
            colouring: Colouring::Field { values: &cm, scale: &scale },
            bounds,
            note: Some(what),
            axes: ["x (m)", "y (m)"],
            overlay: Some(&ov),
        },
    )
}

/// Snapshot colour of a material, by its kind: explosive red, water blue, soil tan, gas grey
/// (materials of one kind get darker shades).
fn material_colours(case: &Case) -> Vec<RGBColor> {
    let mut seen = std::collections::HashMap::new();
    case.materials
        .iter()
        .map(|m| {
            let (r, g, b) = match m.eos.matter() {
                crate::case::Matter::Explosive => (210, 30, 30),
                crate::case::Matter::Water => (40, 110, 210),
                crate::case::Matter::Soil => (196, 164, 96),
                crate::case::Matter::Gas => (140, 140, 140),
            };
            let k = seen.entry(m.eos.kind()).or_insert(0u32);
            let f = 1.0 - 0.3 * (*k as f64).min(2.0);
            *k += 1;
            RGBColor((r as f64 * f) as u8, (g as f64 * f) as u8, (b as f64 * f) as u8)
        })
        .collect()
}

/// The unit of the report's times (plot axes, titles, the crater's and the products' lines): µs
/// for a blast's first milliseconds, ms for a run to a fraction of a second (a late crater), s
/// beyond; chosen from the run's end time. A blast's gauge lines keep µs ([`print_gauge_lines`]).
#[derive(Debug, Clone, Copy)]
struct TimeUnit {
    per_s: f64,
    name: &'static str,
    decimals: usize,
}

impl TimeUnit {
    fn for_end(t_end: f64) -> TimeUnit {
        let (per_s, name) = if t_end < 0.02 {
            (1e6, "µs")
        } else if t_end < 20.0 {
            (1e3, "ms")
        } else {
            (1.0, "s")
        };
        // whole units from 200 up (and always in µs, as before), else one decimal
        let decimals = if per_s == 1e6 || t_end * per_s >= 200.0 { 0 } else { 1 };
        TimeUnit { per_s, name, decimals }
    }
    /// `t` (s) in this unit.
    fn of(self, t: f64) -> f64 {
        t * self.per_s
    }
    /// The axis label, "t (ms)".
    fn axis(self) -> String {
        format!("t ({})", self.name)
    }
    /// "t" as text: "300 ms", "1250 µs", "75.0 ms".
    fn text(self, t: f64) -> String {
        format!("{:.*} {}", self.decimals, self.of(t), self.name)
    }
}

/// A length in cm with one decimal, or "-" when not a number.
fn cm1(v: f64) -> String {
    if v.is_finite() { format!("{:.1}", 100.0 * v) } else { "-".into() }
}

/// A height as text: in cm below 10 m ("29.0 cm"), in m from 10 m (a late run's ejecta: "124.2 m").
fn height_text(v: f64) -> String {
    if v.is_finite() && v.abs() >= 10.0 { format!("{v:.1} m") } else { format!("{} cm", cm1(v)) }
}

/// The side of each particle's square on a map: √(m/ρ) in 2D (its area); axisymmetric, the
/// area of the ring's section √(m/(2π r ρ)) (m/ρ is the ring's volume); capped at twice the
/// median so a stretched particle does not cover its neighbours. (A 3D section's frame carries
/// ρ V^⅔ as its mass, so that this is V^⅓.)
fn sides(f: &Frame, rz: bool) -> Vec<f64> {
    crate::analysis::sides_of(&f.x, &f.mass, &f.rho, rz)
}

pub fn report(
    dir: &Path,
    case: &Case,
    summary: &Value,
    frames: &[Frame],
    times: &[f64],
    animate: bool,
) -> Result<Value> {
    if frames.is_empty() || case.dim == 1 {
        return Ok(json!({}));
    }
    let crater = case.analysis.kind == crate::case::AnalysisKind::Crater;
    // the crater is measured on the whole scene (3D: about the charge's axis); the plots below
    // are drawn on the plane section, in 3D the vertical section through the charge's axis
    let hist = if crater { crater_history(case, frames) } else { Vec::new() };
    // 3D: the final crater as a surface, on the whole scene
    let map = if crater && case.dim == 3 { frames.last().map(|f| surface_map_of(case, &frames[0], f)) } else { None };
    let charge = charge_of(case, frames);
    // a half or quarter model (symmetry planes through the charge's axis): the sums above are
    // the modelled part's
    if charge.images > 1.0 {
        println!(
            "  (mass and energies above: the modelled part, 1/{:.0} of the scene its symmetry planes complete)",
            charge.images
        );
    }
    let bubble = bubble_history(case, frames);
    let tu = TimeUnit::for_end(frames[frames.len() - 1].time);
    let t_axis = tu.axis();
    // 3D: how many particles each frame has, to say what share of them its section draws
    let totals: Vec<usize> = frames.iter().map(|f| f.x.len()).collect();
    let sections;
    // (the whole scene's last frame: a particle's peak velocity is looked up there, in 3D too,
    // where the section's last frame holds only the particles that began on its slab)
    let whole_last = &frames[frames.len() - 1];
    let frames: &[Frame] = if case.dim == 3 {
        sections = section_frames(case, frames);
        &sections
    } else {
        frames
    };
    let ok_hist: Vec<(f64, &Crater)> = hist.iter().filter_map(|(t, c)| c.as_ref().ok().map(|c| (*t, c))).collect();
    let last = hist.last().map(|h| h.1.clone());
    let n = frames.len();
    let cx = Ctx { dir, case, frames, tu, t_axis: t_axis.clone() };
    // the frame nearest each time (the first of two as near)
    let nearest =
        |t: f64| (0..n).min_by(|&a, &b| (frames[a].time - t).abs().total_cmp(&(frames[b].time - t).abs())).unwrap_or(0);
    // the start, the frames nearest a quarter, a half and three quarters of the run's time, the end
    let quarters: Vec<usize> = {
        let (t0, t1) = (frames[0].time, frames[n - 1].time);
        let mut v: Vec<usize> = (0..5).map(|q| nearest(t0 + (t1 - t0) * q as f64 / 4.0)).collect();
        v.dedup();
        v
    };
    let picks: Vec<usize> = {
        let mut v = if times.is_empty() { quarters.clone() } else { times.iter().map(|&t| nearest(t)).collect() };
        v.sort_unstable();
        v.dedup();
        v
    };
    let mut written: Vec<String> = Vec::new();
    draw_bubble(&cx, &bubble, crater, &ok_hist, &mut written)?;
    if crater && !ok_hist.is_empty() {
        draw_crater(&cx, &hist, &ok_hist, &quarters, &map, &mut written)?;
    }
    if let Some(Ok(m)) = &map {
        draw_surface_map(&dir.join("crater_map.png"), case, frames[n - 1].time, m)?;
        written.push("crater_map.png".into());
    }
    // gauges
    let (peaks, peaks_out) = gauge_plots(&cx, summary, &charge, &mut written)?;
    // particle maps
    let snaps = particle_maps(&cx, &charge, (&picks, &totals), whole_last, animate, &mut written)?;
    // text
    let (mut crater_json, growth, gauges) = print_text(case, summary, &hist, map.as_ref());
    if let (Some(Ok(m)), Some(c)) = (&map, crater_json.as_object_mut()) {
        c.insert("surface".into(), serde_json::to_value(m).unwrap_or(Value::Null));
    }
    if let Some((scaled, line)) = scaled_crater(&charge, &crater_json, map.as_ref().and_then(|m| m.as_ref().ok()))
        && let Some(c) = crater_json.as_object_mut()
    {
        println!("{line}");
        c.insert("charge_mass_kg".into(), json!(charge.mass_kg));
        c.insert("scaled_radius_m_per_kg_cbrt".into(), json!(scaled));
    }
    println!("plots in {}: {}", dir.display(), written.iter().chain(&snaps).cloned().collect::<Vec<_>>().join(", "));
    Ok(json!({
        "crater": crater_json,
        "thesis_crater_m": case.analysis.thesis_crater_m,
        "history": history_json(&hist),
        "profile": match &last { Some(Ok(c)) => json!({ "x_m": c.columns_m, "surface0_m": c.surface0_m.iter().map(|v| v.is_finite().then_some(*v)).collect::<Vec<_>>(), "surface_m": c.surface_m.iter().map(|v| v.is_finite().then_some(*v)).collect::<Vec<_>>() }), _ => Value::Null },
        "peaks_cm_mpa": peaks,
        "peaks_scaled": peaks_out.iter().map(|(z, p, l)| json!({"scaled_distance": z, "peak_mpa": p, "gauge": l})).collect::<Vec<_>>(),
        "thesis_growth": growth,
        "thesis_gauges": gauges,
        "bubble": bubble.iter().map(|(t, r)| json!({"t_s": t, "equivalent_radius_m": r})).collect::<Vec<_>>(),
        "plots": written,
        "snapshots": snaps,
    }))
}

/// What every plot of the report shares: the run directory, the case, the frames drawn (in 3D
/// the vertical section's), the time unit and its axis label.
struct Ctx<'a> {
    dir: &'a Path,
    case: &'a Case,
    frames: &'a [Frame],
    tu: TimeUnit,
    t_axis: String,
}

/// `bubble_growth.png`: the detonation products' equivalent radius against time, and its line.
fn draw_bubble(
    cx: &Ctx,
    bubble: &[(f64, f64)],
    crater: bool,
    ok_hist: &[(f64, &Crater)],
    written: &mut Vec<String>,
) -> Result<()> {
    let (dir, case, tu, t_axis) = (cx.dir, cx.case, cx.tu, &cx.t_axis);
    if bubble.is_empty() {
        return Ok(());
    }
    plot::lines(
        &dir.join("bubble_growth.png"),
        &format!("{}: detonation products, {}", case.name(), bubble_measure(case)),
        t_axis,
        "radius (cm)",
        &[("products".to_string(), bubble.iter().map(|(t, r)| (tu.of(*t), 100.0 * r)).collect())],
        false,
    )?;
    written.push("bubble_growth.png".into());
    if let Some((t, r)) = bubble.last() {
        // products vented into a void: isolated particles keep their density, the radius
        // stops growing (output.md, bubble_growth.png)
        let vented = crater && ok_hist.last().is_some_and(|(_, c)| c.note.is_none());
        println!(
            "detonation products at t = {}: equivalent radius {:.1} cm{}",
            tu.text(*t),
            100.0 * r,
            if vented {
                " (Σm/ρ of their particles: once they vent through the crater their density stops changing and the radius stops growing; read bubble_growth.png up to the venting only, docs/reference/output.md)"
            } else {
                ""
            }
        );
    }
    Ok(())
}

/// `crater_growth.png`, `ejecta_height.png` (ejecta far above the crater) and
/// `crater_profile.png`: the crater's history, the thesis's values beside it.
fn draw_crater(
    cx: &Ctx,
    hist: &[(f64, std::result::Result<Crater, String>)],
    ok_hist: &[(f64, &Crater)],
    quarters: &[usize],
    map: &Option<std::result::Result<SurfaceMap, String>>,
    written: &mut Vec<String>,
) -> Result<()> {
    let (dir, case, tu, t_axis, frames) = (cx.dir, cx.case, cx.tu, &cx.t_axis, cx.frames);
    let n = frames.len();
    let mut grow = vec![
        ("diameter (cm)".to_string(), ok_hist.iter().map(|(t, c)| (tu.of(*t), 100.0 * c.diameter_m)).collect()),
        ("depth (cm)".to_string(), ok_hist.iter().map(|(t, c)| (tu.of(*t), 100.0 * c.depth_m)).collect()),
    ];
    let ejecta: Vec<(f64, f64)> = ok_hist.iter().map(|(t, c)| (tu.of(*t), 100.0 * c.ejecta_height_m)).collect();
    // ejecta flying far above a crater (a long run: metres against decimetres) would flatten
    // the crater's curves: then they get a plot of their own
    let widest = ok_hist.iter().map(|(_, c)| c.diameter_m).fold(0.0, f64::max);
    // (no crater at all, a contained charge: the dome over it, the surface's rise, is drawn
    // beside the zero crater so that the plot has a scale)
    let ejecta_apart = widest > 0.0 && ok_hist.iter().any(|(_, c)| c.ejecta_height_m > 5.0 * widest);
    if ejecta_apart {
        plot::lines(
            &dir.join("ejecta_height.png"),
            &format!("{}: ejecta height (the highest soil particle above the original ground)", case.name()),
            t_axis,
            "cm",
            &[("ejecta height (cm)".to_string(), ejecta)],
            false,
        )?;
        written.push("ejecta_height.png".into());
    } else if widest > 0.0 {
        grow.push(("ejecta height (cm)".to_string(), ejecta));
    } else {
        // no crater: the dome, the ground surface's highest rise (the text's figure), not
        // the highest soil particle (a grain thrown off the dome)
        let dome = ok_hist.iter().map(|(t, c)| (tu.of(*t), 100.0 * c.mound_height_m)).collect();
        grow.push(("no crater: the dome, the ground surface's highest rise (cm)".to_string(), dome));
    }
    let mut refs = Vec::new();
    let rows = case.analysis.thesis_crater_history.clone().unwrap_or_default();
    let mut dref: Vec<(f64, f64)> = rows.iter().map(|r| (tu.of(r[0]), 100.0 * r[1])).collect();
    let mut zref: Vec<(f64, f64)> = rows.iter().map(|r| (tu.of(r[0]), 100.0 * r[2])).collect();
    if let Some(th) = &case.analysis.thesis_crater_m
        && th.len() == 2
    {
        let tend = tu.of(frames[n - 1].time);
        dref.push((tend, 100.0 * th[0]));
        zref.push((tend, 100.0 * th[1]));
    }
    if dref.iter().any(|p| p.1.is_finite()) {
        refs.push(Reference { label: "thesis: diameter (cm)".into(), points: dref });
    }
    if zref.iter().any(|p| p.1.is_finite()) {
        refs.push(Reference { label: "thesis: depth (cm)".into(), points: zref });
    }
    // 3D on ground that is not level: the growth is the crater of revolution's (its title says so)
    let uneven = matches!(&map, Some(Ok(m)) if uneven_ground(m).is_some());
    plot::lines_with_refs(
        &dir.join("crater_growth.png"),
        &format!(
            "{}: apparent crater{}{}{}",
            case.name(),
            if uneven { " revolved (the ground is not level: crater_map.png)" } else { "" },
            if ejecta_apart { " (ejecta: ejecta_height.png)" } else { " and ejecta" },
            if refs.is_empty() { "" } else { " (thesis values as triangles)" }
        ),
        t_axis,
        "cm",
        &grow,
        &refs,
    )?;
    written.push("crater_growth.png".into());
    // crater profile at a few times
    let (_, c_end) = ok_hist[ok_hist.len() - 1];
    let mut prof = vec![(
        "original ground".to_string(),
        c_end
            .columns_m
            .iter()
            .zip(&c_end.surface0_m)
            .filter(|p| p.1.is_finite())
            .map(|(x, y)| (*x, *y))
            .collect::<Vec<_>>(),
    )];
    for &k in quarters.iter().skip(1) {
        if let Ok(c) = &hist[k].1 {
            prof.push((
                format!("t = {}", tu.text(hist[k].0)),
                c.columns_m.iter().zip(&c.surface_m).filter(|p| p.1.is_finite()).map(|(x, y)| (*x, *y)).collect(),
            ));
        }
    }
    let mut crefs = Vec::new();
    if let Some(cv) = &c_end.cavity {
        let (x0, x1) = (cv.centre_m[0] - 0.5 * cv.width_m, cv.centre_m[0] + 0.5 * cv.width_m);
        let (y0, y1) = (cv.centre_m[1] - 0.5 * cv.height_m, cv.centre_m[1] + 0.5 * cv.height_m);
        crefs.push(Reference {
            label: "cavity (bounding box corners)".into(),
            points: vec![(x0, y0), (x1, y0), (x0, y1), (x1, y1)],
        });
    }
    plot::lines_with_refs(
        &dir.join("crater_profile.png"),
        &if uneven {
            format!(
                "{}: ground surface revolved (the highest at each distance); the ground is not level: read crater_map.png",
                case.name()
            )
        } else {
            format!(
                "{}: ground surface, the top soil particles' centres (Δx/2 under its face; columns {} wide)",
                case.name(),
                crate::converge::spacing_text(c_end.column_m)
            )
        },
        if case.dim == 3 || case.axisymmetric() {
            "distance from the charge's axis (m; drawn on both sides: the crater revolved about the axis)"
        } else {
            "x (m)"
        },
        "surface height (m)",
        &prof,
        &crefs,
    )?;
    written.push("crater_profile.png".into());
    Ok(())
}

/// The particle maps: materials, pressure and velocity at the picked frames (their files
/// returned), the peak particle velocity at the initial positions and the animation.
fn particle_maps(
    cx: &Ctx,
    charge: &Charge,
    (picks, totals): (&[usize], &[usize]),
    whole_last: &Frame,
    animate: bool,
    written: &mut Vec<String>,
) -> Result<Vec<String>> {
    let (dir, case, tu, frames) = (cx.dir, cx.case, cx.tu, cx.frames);
    // the window: the scene at t = 0 (the ground's extent, room above for ejecta); a scene of
    // gases alone (a charge in a void: nothing stays where it began) spans every frame
    let gases = case
        .materials
        .iter()
        .all(|m| matches!(m.eos, crate::case::EosCfg::Jwl { .. } | crate::case::EosCfg::IdealGas { .. }));
    let spanned: &[Frame] = if gases { frames } else { &frames[..1] };
    let fin = |get: fn(&Frame) -> &Vec<f64>| {
        spanned.iter().flat_map(|f| get(f).iter().cloned().filter(|x| x.is_finite())).collect::<Vec<_>>()
    };
    let (xs0, ys0) = (fin(|f| &f.x), fin(|f| &f.y));
    let (xlo, xhi) =
        (xs0.iter().cloned().fold(f64::INFINITY, f64::min), xs0.iter().cloned().fold(f64::NEG_INFINITY, f64::max));
    let (ylo, yhi) =
        (ys0.iter().cloned().fold(f64::INFINITY, f64::min), ys0.iter().cloned().fold(f64::NEG_INFINITY, f64::max));
    let wdt = (xhi - xlo).max(1e-9);
    // `analysis.view_m` (or `report --window`) sets the window
    let bounds = match case.analysis.view_m.as_deref() {
        Some(&[x0, x1, y0, y1]) => ((x0, x1), (y0, y1)),
        _ => ((xlo - 0.03 * wdt, xhi + 0.03 * wdt), (ylo - 0.03 * wdt, yhi + 0.4 * wdt)),
    };
    let section_label =
        format!("x (m), on the vertical section y = {:.4} m", charge.centre.as_ref().map_or(0.0, |c| c[1]));
    let axes = match (case.dim, case.axisymmetric()) {
        (3, _) => [section_label.as_str(), "z (m)"],
        (_, true) => ["r (m)", "z (m)"],
        _ => ["x (m)", "y (m)"],
    };
    let colours = material_colours(case);
    let names: Vec<String> = case
        .materials
        .iter()
        .map(|m| match &m.preset {
            Some(p) if *p != m.name => format!("{} ({p})", m.name),
            _ => m.name.clone(),
        })
        .collect();
    // one pressure scale for all maps: MPa on a log scale over the six decades below the highest
    // pressure after t = 0 (GPa in the products down to kPa ahead of the wave in the ground)
    let pscale = Scale::log_of(frames.iter().skip(1).flat_map(|f| f.p.iter().map(|p| p / 1e6)), 6.0, "p (MPa)");
    let speeds =
        |f: &Frame| -> Vec<f64> { (0..f.x.len()).map(|i| (f.vx[i] * f.vx[i] + f.vy[i] * f.vy[i]).sqrt()).collect() };
    let vscale = Scale::log_of(frames.iter().skip(1).flat_map(&speeds), 4.0, "|v| (m/s)");
    let mut snaps = Vec::new();
    for &k in picks {
        let f = &frames[k];
        let tag = format!("{:05.0}us", f.time * 1e6);
        let side = sides(f, case.axisymmetric());
        let mat: Vec<usize> = f.mat.iter().map(|m| (*m).max(0) as usize).collect();
        // in 3D the section's share of the scene (the particles that lay on it at t = 0)
        let share = (case.dim == 3).then(|| {
            format!(
                "the vertical section through the charge's axis: {} of the scene's {} particles (those on it at t = 0, followed)",
                f.x.len(),
                totals.get(k).copied().unwrap_or(0)
            )
        });
        let pm = format!("snap_material_{tag}.png");
        plot::map_png(
            &dir.join(&pm),
            &MapSpec {
                title: format!("{}  t = {}: materials", case.name(), tu.text(f.time)),
                x: &f.x,
                y: &f.y,
                side: &side,
                colouring: Colouring::Material { index: &mat, colours: &colours, names: &names },
                bounds,
                note: share.clone(),
                axes,
                overlay: None,
            },
        )?;
        let pmpa: Vec<f64> = f.p.iter().map(|p| p / 1e6).collect();
        let pp = format!("snap_pressure_{tag}.png");
        plot::map_png(
            &dir.join(&pp),
            &MapSpec {
                title: format!("{}  t = {}: pressure", case.name(), tu.text(f.time)),
                x: &f.x,
                y: &f.y,
                side: &side,
                colouring: Colouring::Field { values: &pmpa, scale: &pscale },
                bounds,
                note: share.clone(),
                axes,
                overlay: None,
            },
        )?;
        let sp = speeds(f);
        let pv = format!("snap_velocity_{tag}.png");
        plot::map_png(
            &dir.join(&pv),
            &MapSpec {
                title: format!("{}  t = {}: velocity magnitude", case.name(), tu.text(f.time)),
                x: &f.x,
                y: &f.y,
                side: &side,
                colouring: Colouring::Field { values: &sp, scale: &vscale },
                bounds,
                note: share.clone(),
                axes,
                overlay: None,
            },
        )?;
        snaps.extend([pm, pp, pv]);
    }
    let view = View { bounds, axes, top: yhi + 0.03 * wdt, pscale: &pscale };
    ppv_and_animation(cx, &view, whole_last, animate, written)?;
    Ok(snaps)
}

/// The window of the particle maps: its bounds, axis labels, the top of the maps at the initial
/// positions, and the pressure scale.
struct View<'a> {
    bounds: ((f64, f64), (f64, f64)),
    axes: [&'a str; 2],
    top: f64,
    pscale: &'a Scale,
}

/// `ppv_map.png` (the peak particle velocity at the initial positions) and, with `animate`,
/// `animation.gif` (the pressure at every frame).
fn ppv_and_animation(cx: &Ctx, v: &View, whole_last: &Frame, animate: bool, written: &mut Vec<String>) -> Result<()> {
    let (dir, case, tu, frames) = (cx.dir, cx.case, cx.tu, cx.frames);
    let (f0, bounds, axes, pscale) = (&frames[0], v.bounds, v.axes, v.pscale);
    // peak particle velocity, at each particle's initial position
    let fl = whole_last;
    if !fl.ppv.is_empty() {
        let by_id: HashMap<i64, f64> = fl.id.iter().zip(&fl.ppv).map(|(i, v)| (*i, *v)).collect();
        let ppv0: Vec<f64> = f0.id.iter().map(|i| by_id.get(i).copied().unwrap_or(0.0)).collect();
        let side0 = sides(f0, case.axisymmetric());
        let scale = Scale::log_of(ppv0.iter().copied(), 4.0, "PPV (m/s)");
        plot::map_png(
            &dir.join("ppv_map.png"),
            &MapSpec {
                title: format!(
                    "{}: peak particle velocity max |v| to t = {}, at initial positions",
                    case.name(),
                    tu.text(fl.time)
                ),
                x: &f0.x,
                y: &f0.y,
                side: &side0,
                colouring: Colouring::Field { values: &ppv0, scale: &scale },
                bounds: ((bounds.0.0, bounds.0.1), (bounds.1.0, v.top)),
                note: None,
                axes,
                overlay: None,
            },
        )?;
        written.push("ppv_map.png".into());
    }
    if animate {
        let sides_all: Vec<Vec<f64>> = frames.iter().map(|f| sides(f, case.axisymmetric())).collect();
        let pmpa_all: Vec<Vec<f64>> = frames.iter().map(|f| f.p.iter().map(|p| p / 1e6).collect()).collect();
        let maps: Vec<MapSpec> = frames
            .iter()
            .enumerate()
            .map(|(k, f)| MapSpec {
                title: format!("{}  t = {}: pressure", case.name(), tu.text(f.time)),
                x: &f.x,
                y: &f.y,
                side: &sides_all[k],
                colouring: Colouring::Field { values: &pmpa_all[k], scale: pscale },
                bounds,
                note: None,
                axes,
                overlay: None,
            })
            .collect();
        plot::animate(&dir.join("animation.gif"), &maps, 150)?;
        written.push("animation.gif".into());
        println!("animation: {} ({} frames)", dir.join("animation.gif").display(), maps.len());
    }
    Ok(())
}

#[cfg(test)]
mod tests;
