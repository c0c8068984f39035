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

/// A gauge's record read back from gauges.csv: (time s, pressure Pa, speed |v| m/s).
#[derive(Debug, Clone, Default)]
pub struct GaugeRecord {
    pub name: String,
    pub samples: Vec<(f64, f64, f64)>,
    /// The indices of the samples that follow a void (a point gauge with no particle in reach):
    /// the plots break their line there rather than draw readings across it.
    pub after_void: Vec<usize>,
}

/// Reads gauges.csv (docs/cases.md `[[gauge]]` lists its columns); empty fields (a point
/// gauge in a void) are left out.
pub fn read_gauges(path: &Path) -> Result<Vec<GaugeRecord>> {
    let bytes = std::fs::read(path).map_err(|e| crate::error::input(format!("{}: {e}", path.display())))?;
    // a line cut by a kill (or bytes that are not text) is skipped below, not an error
    let text = String::from_utf8_lossy(&bytes);
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let names: Vec<String> = head.iter().filter_map(|h| h.strip_suffix("_p_pa")).map(String::from).collect::<Vec<_>>();
    let col = |n: &str, q: &str| head.iter().position(|h| *h == format!("{n}_{q}"));
    let cols: Vec<(Option<usize>, Vec<usize>)> = names
        .iter()
        .map(|n| (col(n, "p_pa"), ["vx_ms", "vy_ms", "vz_ms"].iter().filter_map(|q| col(n, q)).collect()))
        .collect();
    let mut out: Vec<GaugeRecord> =
        names.iter().map(|n| GaugeRecord { name: n.clone(), ..Default::default() }).collect();
    let mut void = vec![false; names.len()];
    for l in lines {
        if l.starts_with('#') {
            continue;
        }
        let f: Vec<&str> = l.split(',').collect();
        let Some(t) = f.first().and_then(|s| s.parse::<f64>().ok()) else { continue };
        for (g, (pc, vc)) in cols.iter().enumerate() {
            let Some(p) = pc.and_then(|c| f.get(c)).and_then(|s| s.parse::<f64>().ok()) else {
                void[g] = true;
                continue;
            };
            let v2: f64 = vc.iter().filter_map(|&c| f.get(c).and_then(|s| s.parse::<f64>().ok())).map(|v| v * v).sum();
            if std::mem::take(&mut void[g]) && !out[g].samples.is_empty() {
                let k = out[g].samples.len();
                out[g].after_void.push(k);
            }
            out[g].samples.push((t, p, v2.sqrt()));
        }
    }
    Ok(out)
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

/// The unit of a list of pressures whose largest is `max` (Pa): the factor from Pa and its
/// name — MPa from 1 MPa up (a blast's gauges), kPa from 1 kPa, else Pa (a gas-dynamics case).
pub fn pressure_unit(max: f64) -> (f64, &'static str) {
    if max >= 1e6 {
        (1e-6, "MPa")
    } else if max >= 1e3 {
        (1e-3, "kPa")
    } else {
        (1.0, "Pa")
    }
}

/// One line per gauge of summary.json: peak pressure and its time, arrival, impulse, PPV. A
/// blast's report (`blast`) keeps MPa, kPa·s and µs, as its gauges.png; another case's pressure
/// unit follows its largest peak ([`pressure_unit`]) and its times are in µs up to 20 ms, else
/// in ms.
pub fn print_gauge_lines(summary: &Value, blast: bool) {
    let gl = summary["gauges"].as_array().cloned().unwrap_or_default();
    let max_of = |k: &str| gl.iter().filter_map(|g| g[k].as_f64()).filter(|v| v.is_finite()).fold(0.0f64, f64::max);
    let (ps, pu) = if blast { (1e-6, "MPa") } else { pressure_unit(max_of("peak_pa")) };
    let (is, iu, id) =
        if pu == "MPa" { (1e-3, "kPa·s", 3) } else { (ps, if pu == "kPa" { "kPa·s" } else { "Pa·s" }, 4) };
    let late = !blast && max_of("peak_time_s").max(max_of("arrival_s")) >= 0.02;
    let (ts, tu, td) = if late { (1e3, "ms", 2) } else { (1e6, "µs", 0) };
    for g in &gl {
        let f = |k: &str, scale: f64, unit: &str, digits: usize| -> String {
            g[k].as_f64().filter(|v| v.is_finite()).map_or("-".into(), |v| format!("{:.*} {unit}", digits, v * scale))
        };
        if g["reached"] == json!(false) {
            println!(
                "gauge {} ({}): not reached by the wave (its largest reading {}, at most {:.0e} of the strongest gauge's rise above its first reading)",
                g["name"].as_str().unwrap_or("?"),
                g["kind"].as_str().unwrap_or("particle"),
                f("peak_pa", ps, pu, 2),
                crate::gauges::REACHED
            );
            continue;
        }
        println!(
            "gauge {} ({}): peak {} at {}, arrival {}, impulse {}, PPV {}",
            g["name"].as_str().unwrap_or("?"),
            g["kind"].as_str().unwrap_or("particle"),
            f("peak_pa", ps, pu, 2),
            f("peak_time_s", ts, tu, td),
            f("arrival_s", ts, tu, td),
            f("impulse_pa_s", is, iu, id),
            f("ppv_ms", 1.0, "m/s", 2)
        );
    }
}

/// gauges.png (pressure, in `unit` = (factor from Pa, name), with `refs` as triangles) and
/// gauges_velocity.png (|v|) from the records of gauges.csv; returns the files written.
fn draw_gauges(
    dir: &Path,
    case: &Case,
    recs: &[GaugeRecord],
    tu: TimeUnit,
    unit: (f64, &str),
    refs: &[Reference],
) -> Result<Vec<String>> {
    let series = |f: &dyn Fn(&(f64, f64, f64)) -> f64| -> Vec<(String, Vec<(f64, f64)>)> {
        recs.iter()
            .map(|g| {
                // a NaN point where a void was: the plot breaks its line there
                let mut pts = Vec::with_capacity(g.samples.len() + g.after_void.len());
                for (k, x) in g.samples.iter().enumerate() {
                    if g.after_void.binary_search(&k).is_ok() {
                        pts.push((tu.of(x.0), f64::NAN));
                    }
                    pts.push((tu.of(x.0), f(x)));
                }
                (format!("gauge {}", g.name), pts)
            })
            .collect()
    };
    plot::lines_with_refs(
        &dir.join("gauges.png"),
        &format!(
            "{}: pressure at the gauges{}",
            case.name(),
            if refs.is_empty() { "" } else { " (thesis values as triangles)" }
        ),
        &tu.axis(),
        &format!("p ({})", unit.1),
        &series(&|x| x.1 * unit.0),
        refs,
    )?;
    plot::lines_with_refs(
        &dir.join("gauges_velocity.png"),
        &format!("{}: particle velocity |v| at the gauges", case.name()),
        &tu.axis(),
        "|v| (m/s)",
        &series(&|x| x.2),
        &[],
    )?;
    Ok(vec!["gauges.png".into(), "gauges_velocity.png".into()])
}

/// The gauges of a case that is not a blast (a verification problem, a 1D case): their lines
/// and plots, as a blast's report gives them; the files written.
pub fn gauges_only(dir: &Path, case: &Case, summary: &Value, t_end: f64) -> Result<Vec<String>> {
    let gpath = dir.join("gauges.csv");
    if case.gauges.is_empty() || !gpath.exists() {
        return Ok(Vec::new());
    }
    print_gauge_lines(summary, false);
    let recs = read_gauges(&gpath)?;
    let sg = summary["gauges"].as_array().cloned().unwrap_or_default();
    let max = sg.iter().filter_map(|g| g["peak_pa"].as_f64()).filter(|v| v.is_finite()).fold(0.0f64, f64::max);
    draw_gauges(dir, case, &recs, TimeUnit::for_end(t_end), pressure_unit(max), &[])
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
    sides_of(&f.x, &f.mass, &f.rho, rz)
}

/// [`sides`] from the positions' first coordinate (r in RZ), masses and densities.
pub(crate) fn sides_of(x: &[f64], mass: &[f64], rho: &[f64], rz: bool) -> Vec<f64> {
    let area = |i: usize| {
        let a = mass[i] / rho[i];
        if rz { a / (2.0 * std::f64::consts::PI * x[i].abs()) } else { a }
    };
    let mut s: Vec<f64> = (0..x.len()).map(|i| if rho[i] > 0.0 { area(i).sqrt() } else { 0.0 }).collect();
    let mut sorted: Vec<f64> = s.iter().copied().filter(|v| v.is_finite()).collect();
    sorted.sort_by(|a, b| a.total_cmp(b));
    let med = sorted.get(sorted.len() / 2).copied().unwrap_or(0.01);
    for v in s.iter_mut() {
        if !v.is_finite() {
            *v = med;
        }
        // 15 % larger than the particle's own area, so neighbours overlap instead of leaving
        // hairline gaps between rounded pixel edges
        *v = 1.15 * v.min(2.0 * med);
    }
    s
}

/// Scaled distance of a gauge at `r` m from the charge: R/√(W/L) in plane strain (W/L in kg per
/// metre of depth, a line charge), R/W^(1/3) in 3D, R/(W/A) in 1D.
fn scaled(r: f64, w: f64, dim: usize) -> f64 {
    match dim {
        2 => r / w.sqrt(),
        3 => r / w.cbrt(),
        _ => r / w,
    }
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
    if !bubble.is_empty() {
        plot::lines(
            &dir.join("bubble_growth.png"),
            &format!("{}: detonation products, {}", case.name(), bubble_measure(case)),
            &t_axis,
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
                    " (Σm/ρ of their particles: once they vent through the crater their density stops changing and the radius stops growing; read bubble_growth.png up to the venting only, docs/output.md)"
                } else {
                    ""
                }
            );
        }
    }
    if crater && !ok_hist.is_empty() {
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
                &t_axis,
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
            &t_axis,
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
    }
    if let Some(Ok(m)) = &map {
        draw_surface_map(&dir.join("crater_map.png"), case, frames[n - 1].time, m)?;
        written.push("crater_map.png".into());
    }
    // gauges
    let gpath = dir.join("gauges.csv");
    let mut peaks_out = Vec::new();
    let mut peaks = Vec::new();
    if gpath.exists() {
        let recs = read_gauges(&gpath)?;
        let sg: Vec<Value> = summary["gauges"].as_array().cloned().unwrap_or_default();
        let mut refs = Vec::new();
        for tg in &case.analysis.thesis_gauge {
            let ours = sg.iter().find(|g| g["name"] == tg.gauge.as_str());
            let y = tg.peak_pa.map(|p| p / 1e6).or_else(|| ours.and_then(|g| g["peak_pa"].as_f64()).map(|p| p / 1e6));
            if let (Some(t), Some(y)) = (tg.peak_time_s, y) {
                let what = if tg.peak_pa.is_some() { "peak" } else { "time of the peak (height: ours)" };
                refs.push(Reference { label: format!("thesis {}: {what}", tg.gauge), points: vec![(tu.of(t), y)] });
            }
        }
        written.extend(draw_gauges(dir, case, &recs, tu, (1e-6, "MPa"), &refs)?);
        // peak pressure against scaled distance from the charge's centre (the detonation point,
        // else the explosive's initial centroid) over the whole charge's mass
        let (centre, w) = (charge.centre.clone(), charge.mass_kg);
        if let Some(centre) = centre {
            // a gauge the wave has not reached reads the ambient state's noise: not a peak
            for gg in sg.iter().filter(|g| g["reached"] != json!(false)) {
                let pt: Vec<f64> =
                    gg["point_m"].as_array().map(|a| a.iter().filter_map(|v| v.as_f64()).collect()).unwrap_or_default();
                let r = pt.iter().zip(&centre).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
                let p = gg["peak_pa"].as_f64().unwrap_or(f64::NAN) / 1e6;
                peaks.push((100.0 * r, p));
                let z = if w > 0.0 { scaled(r, w, charge.dim) } else { f64::NAN };
                peaks_out.push((
                    z,
                    p,
                    format!("{} ({:.0} cm, {})", gg["name"].as_str().unwrap_or("?"), 100.0 * r, tick(p)),
                ));
            }
            if w > 0.0 {
                plot::loglog_on_data(
                    &dir.join("peaks.png"),
                    &format!("{}: peak pressure against scaled distance (charge {})", case.name(), charge.mass_text()),
                    charge.scaled_label(),
                    "peak p (MPa)",
                    &peaks_out,
                    None,
                )?;
                written.push("peaks.png".into());
            }
        }
    }
    // particle maps
    // the window: the scene at t = 0 (the ground's extent, room above for ejecta); a scene of
    // gases alone (a charge in a void: nothing stays where it began) spans every frame
    let gases = case
        .materials
        .iter()
        .all(|m| matches!(m.eos, crate::case::EosCfg::Jwl { .. } | crate::case::EosCfg::IdealGas { .. }));
    let f0 = &frames[0];
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
    for &k in &picks {
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
                bounds: ((bounds.0.0, bounds.0.1), (bounds.1.0, yhi + 0.03 * wdt)),
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
                colouring: Colouring::Field { values: &pmpa_all[k], scale: &pscale },
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

/// The crater's radius scaled by the charge, R/W^⅓ (m/kg^⅓), and the report's line for it: for
/// a charge whose blast spreads in 3D (RZ, 3D; not a plane-strain line charge) and a crater with
/// a diameter. R is half the crater's diameter at the original ground level: in 3D the surface
/// map's equivalent diameter 2√(A/π) (the revolved headline reads the crater's narrowest
/// direction), else the headline's. W is the whole scene's explosive (kg; the modelled part times
/// its symmetry planes' copies), whatever the explosive: TNT data want its TNT equivalence.
fn scaled_crater(charge: &Charge, crater: &Value, map: Option<&SurfaceMap>) -> Option<(f64, String)> {
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
fn uneven_ground(m: &SurfaceMap) -> Option<String> {
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
fn print_text(
    case: &Case,
    summary: &Value,
    hist: &[(f64, std::result::Result<Crater, String>)],
    map: Option<&std::result::Result<SurfaceMap, String>>,
) -> (Value, Vec<Value>, Vec<Value>) {
    let mut last = hist.last().map(|h| h.1.clone());
    if let Some(Ok(c)) = &mut last {
        c.bounded = crate::analysis::crater::box_bound(case, c, map.and_then(|m| m.as_ref().ok()));
    }
    let crater_json = match &last {
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
    };
    let measured = matches!(&last, Some(Ok(c)) if c.note.is_none());
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
    if let (Some(Ok(c)), Some(Ok(m))) = (&last, map)
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
    if let Some(th) = &case.analysis.thesis_crater_m
        && th.len() == 2
    {
        match &last {
            Some(Ok(c)) if measured => println!(
                "thesis (Table 5-3/5-4): diameter {:.1} cm, depth {:.1} cm; ours/thesis: diameter {:.2}, depth {:.2}",
                100.0 * th[0],
                100.0 * th[1],
                c.diameter_m / th[0],
                c.depth_m / th[1]
            ),
            _ => println!(
                "thesis (Table 5-3/5-4): diameter {:.1} cm, depth {:.1} cm; ours: no apparent crater to compare",
                100.0 * th[0],
                100.0 * th[1]
            ),
        }
    }
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
    let growth = thesis_growth(case, hist);
    for g in &growth {
        println!(
            "thesis at {:.0} µs: diameter {} cm, depth {} cm; ours at {:.0} µs: diameter {} cm, depth {} cm",
            g["thesis_t_s"].as_f64().unwrap_or(0.0) * 1e6,
            fmt_cm(g["thesis_diameter_m"].as_f64()),
            fmt_cm(g["thesis_depth_m"].as_f64()),
            g["our_t_s"].as_f64().unwrap_or(0.0) * 1e6,
            fmt_cm1(g["diameter_m"].as_f64()),
            fmt_cm1(g["depth_m"].as_f64())
        );
    }
    let gauges = thesis_gauges(case, summary);
    for g in &gauges {
        println!(
            "gauge {}: thesis peak {} at {}; ours {} at {} (arrival {})",
            g["gauge"].as_str().unwrap_or("?"),
            g["thesis_peak_pa"].as_f64().map_or("-".to_string(), |p| format!("{:.1} MPa", p / 1e6)),
            g["thesis_peak_time_s"].as_f64().map_or("-".to_string(), |t| format!("{:.0} µs", t * 1e6)),
            g["peak_pa"].as_f64().map_or("-".to_string(), |p| format!("{:.2} MPa", p / 1e6)),
            g["peak_time_s"].as_f64().map_or("-".to_string(), |t| format!("{:.0} µs", t * 1e6)),
            g["arrival_s"].as_f64().map_or("-".to_string(), |t| format!("{:.0} µs", t * 1e6))
        );
    }
    (crater_json, growth, gauges)
}

/// The crater history as JSON rows.
fn history_json(hist: &[(f64, std::result::Result<Crater, String>)]) -> Vec<Value> {
    hist.iter()
        .map(|(t, c)| match c {
            Ok(c) => json!({"t_s": t, "diameter_m": c.diameter_m, "depth_m": c.depth_m, "ejecta_height_m": c.ejecta_height_m, "cavity": c.cavity}),
            Err(why) => json!({"t_s": t, "measured": false, "reason": why}),
        })
        .collect()
}

/// A peak's label on peaks.png: four significant digits in MPa (365.9, 51.91, 0.1234; the
/// peaks are not converged beyond that), "-" when there is none.
fn tick(p: f64) -> String {
    if !p.is_finite() {
        return "-".into();
    }
    let decimals = if p == 0.0 { 0 } else { plot::decimals_for(p, 4, 6) };
    format!("{p:.decimals$} MPa")
}

fn fmt_cm(v: Option<f64>) -> String {
    match v {
        Some(x) if x.is_finite() => format!("{:.0}", 100.0 * x),
        _ => "-".into(),
    }
}

fn fmt_cm1(v: Option<f64>) -> String {
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

/// Equivalent radius √(A/π) of the detonation products (2D: A = Σ m_i/ρ_i over the JWL
/// particles, m²) at every frame; empty without an explosive.
pub fn bubble_history(case: &Case, frames: &[Frame]) -> Vec<(f64, f64)> {
    let jwl = explosive_mask(case);
    if !jwl.iter().any(|j| *j) {
        return Vec::new();
    }
    let pi = std::f64::consts::PI;
    let images = charge_of(case, frames).images;
    frames
        .iter()
        .map(|f| {
            let own = |i: usize| jwl.get(f.mat[i] as usize).copied().unwrap_or(false);
            // m/ρ: each particle's area in 2D plane (per metre of depth), its ring's or its own
            // volume in RZ and 3D
            let a: f64 = (0..f.mass.len()).filter(|&i| own(i)).map(|i| f.mass[i] / f.rho[i]).sum();
            let r = if case.dim == 3 || case.axisymmetric() {
                (3.0 * images * a / (4.0 * pi)).cbrt()
            } else {
                (images * a / pi).sqrt()
            };
            (f.time, r)
        })
        .collect()
}

/// What [`bubble_history`]'s radius is, for the plot's title.
fn bubble_measure(case: &Case) -> &'static str {
    if case.dim == 3 || case.axisymmetric() { "equivalent radius (3V/4π)^⅓" } else { "equivalent radius √(A/π)" }
}

/// The charge a report scales its distances by.
struct Charge {
    /// Its centre: the detonation point, else the explosive's initial centroid (m).
    centre: Option<Vec<f64>>,
    /// The whole charge's mass: kg per metre of depth in 2D plane, kg in RZ and 3D (the model's
    /// explosive times `images`).
    mass_kg: f64,
    /// The dimension its blast spreads in: 2 in plane strain (a line charge), 3 in RZ and 3D.
    dim: usize,
    /// How many copies of the modelled charge its symmetry planes make (2 for each plane of
    /// [`crate::analysis::crater::charge_planes`]: 4
    /// for a quarter, 2 for an RZ half space); 1 without.
    images: f64,
}

impl Charge {
    fn mass_text(&self) -> String {
        match self.dim {
            2 if self.images > 1.0 => {
                format!("{:.3} kg per m of depth: {:.0} × the modelled part", self.mass_kg, self.images)
            }
            2 => format!("{:.3} kg per m of depth", self.mass_kg),
            _ if self.images > 1.0 => format!("{:.3} kg: {:.0} × the modelled part", self.mass_kg, self.images),
            _ => format!("{:.3} kg", self.mass_kg),
        }
    }
    fn scaled_label(&self) -> &'static str {
        match self.dim {
            2 => "scaled distance R/√(W/L)  (m/(kg/m)^½, plane strain: a line charge)",
            3 => "scaled distance R/W^⅓  (m/kg^⅓)",
            _ => "scaled distance R/(W/A)",
        }
    }
}

/// The charge of a run from its first frame.
fn charge_of(case: &Case, frames: &[Frame]) -> Charge {
    let ex = explosive_mask(case);
    let f0 = &frames[0];
    let k: Vec<usize> = (0..f0.x.len()).filter(|&i| ex.get(f0.mat[i] as usize).copied().unwrap_or(false)).collect();
    let d = case.dim;
    let coords = |i: usize| -> Vec<f64> {
        match d {
            3 => vec![f0.x[i], f0.y[i], f0.z[i]],
            2 => vec![f0.x[i], f0.y[i]],
            _ => vec![f0.x[i]],
        }
    };
    let pts: Vec<Vec<f64>> = k.iter().map(|&i| coords(i)).collect();
    // the symmetry planes the charge abuts: 2 copies of the modelled charge for each (a half,
    // a quarter, an octant), and the whole charge's centroid on each
    let planes = crate::analysis::crater::charge_planes(case, &pts);
    let centre = case.detonation.as_ref().and_then(|dt| dt.point_m.clone()).or_else(|| {
        (!k.is_empty()).then(|| {
            let mut c = crate::analysis::crater::centroid(&pts, d);
            if case.axisymmetric() {
                c[0] = 0.0; // a charge of rings is centred on the axis
            }
            for &(a, at) in &planes {
                c[a] = at;
            }
            c
        })
    });
    let images = 2f64.powi(planes.len() as i32);
    let mass: f64 = k.iter().map(|&i| f0.mass[i]).sum::<f64>() * images;
    Charge { centre, mass_kg: mass, dim: if d == 3 || case.axisymmetric() { 3 } else { d }, images }
}

/// The vertical section of a 3D run through the charge's axis along x (the plane y = the axis's
/// y), as 2D frames (x, z) for the report's maps: the soil, charge and everything else that lay
/// within 0.75 spacing of the plane at t = 0 (the first layer beside it when the plane is a
/// symmetry plane of a quarter model; every particle, projected, when none lies there), followed
/// wherever they go and drawn projected onto the plane; speeds in the plane; each particle's
/// `mass` set to ρ V^⅔ so that its drawn side is V^⅓.
fn section_frames(case: &Case, frames: &[Frame]) -> Vec<Frame> {
    let charge = charge_of(case, frames);
    let ay = charge.centre.as_ref().map_or(0.0, |c| c[1]);
    let f0 = &frames[0];
    let ds = soil_spacing(case).unwrap_or_else(|| f0.h.iter().cloned().fold(f64::INFINITY, f64::min));
    let cx = charge.centre.as_ref().map_or(0.0, |c| c[0]);
    let mirrored = crate::analysis::crater::mirror_planes(case, (cx, ay), ds).iter().any(|&(k, _)| k == 1);
    let slab = |y: f64| if mirrored { (y - ay) >= 0.0 && (y - ay) < ds } else { (y - ay).abs() < 0.75 * ds };
    // the section is Lagrangian: the particles that lay in the slab at t = 0, followed (an
    // expanding cloud's particles leave a fixed slab: a free sphere's section was empty from
    // 30 µs); a scene with no particle on that plane is drawn projected onto it, whole
    let on: std::collections::HashSet<i64> = (0..f0.y.len()).filter(|&i| slab(f0.y[i])).map(|i| f0.id[i]).collect();
    let whole = on.is_empty();
    frames
        .iter()
        .map(|f| {
            let idx: Vec<usize> = (0..f.x.len()).filter(|&i| whole || on.contains(&f.id[i])).collect();
            let pick =
                |v: &[f64]| -> Vec<f64> { if v.is_empty() { Vec::new() } else { idx.iter().map(|&i| v[i]).collect() } };
            Frame {
                time: f.time,
                x: pick(&f.x),
                y: pick(&f.z),
                z: vec![0.0; idx.len()],
                vx: pick(&f.vx),
                vy: pick(&f.vz),
                vz: vec![0.0; idx.len()],
                rho: pick(&f.rho),
                p: pick(&f.p),
                e: pick(&f.e),
                h: pick(&f.h),
                mass: idx.iter().map(|&i| f.rho[i] * (f.mass[i] / f.rho[i]).powf(2.0 / 3.0)).collect(),
                mat: idx.iter().map(|&i| f.mat[i]).collect(),
                id: idx.iter().map(|&i| f.id[i]).collect(),
                ppv: pick(&f.ppv),
                p_peak: pick(&f.p_peak),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
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
}
