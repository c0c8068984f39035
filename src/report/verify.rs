//! `blastsph report` for the verification problems: the measures of `analysis::verify`, printed,
//! with their profile plot and the density map of a blast.

use crate::analysis::sedov_edge::{mirror_factor, setup_of};
use crate::analysis::verify::measure;
use crate::case::{AnalysisKind, Case};
use crate::error::Result;
use crate::output::Frame;
use serde_json::{Value, json};

/// `blastsph report` for a verification case: prints the measures and writes `profiles.png`.
pub fn report(dir: &std::path::Path, case: &Case, frames: &[Frame]) -> Result<Value> {
    // the initial positions: the first output (t = 0)
    let x0: Vec<f64> = frames
        .first()
        .map(|f| (0..f.x.len()).flat_map(|i| [f.x[i], f.y[i], f.z[i]].into_iter().take(case.dim.max(1))).collect())
        .unwrap_or_default();
    let (v, prof) = measure(case, frames, &x0)?;
    // a half, quarter or eighth of a point blast (symmetry planes through its centre): the
    // balance printed above is the modelled part's
    if case.analysis.kind == AnalysisKind::Sedov
        && let Ok(s) = setup_of(case)
    {
        let f = mirror_factor(case, &s.centre);
        if f > 1.0 {
            println!(
                "  (mass and energies above: the modelled part, 1/{f:.0} of the blast its symmetry planes complete; the measures' energy below is the whole blast's)"
            );
        }
    }
    let skip = ["history", "warning"];
    let mut line = String::new();
    if let Some(o) = v.as_object() {
        for (k, x) in o {
            if skip.contains(&k.as_str()) {
                continue;
            }
            let s = match x {
                Value::Number(n) => {
                    let f = n.as_f64().unwrap_or(0.0);
                    if f.fract() == 0.0 && f.abs() < 1e9 { format!("{f}") } else { format!("{f:.5e}") }
                }
                Value::Null => "-".into(),
                other => other.to_string(),
            };
            line.push_str(&format!("  {k} = {s}\n"));
        }
    }
    println!("verification ({}):\n{line}", case.analysis.kind.name());
    if let Some(w) = v["warning"].as_str() {
        println!("WARNING: {w}");
    }
    let mut out = v.clone();
    if let Some(p) = prof {
        let png = dir.join("profiles.png");
        let mk = |title: &str, unit: &str, q: usize| crate::plot::Panel {
            title: title.into(),
            xlabel: p.xlabel.into(),
            ylabel: unit.into(),
            points: p.particles.iter().map(|a| (a[0], a[q])).collect(),
            curve: p.exact.iter().map(|a| (a[0], a[q])).collect(),
            curve_label: "exact".into(),
            points_label: "SPH".into(),
        };
        let panels = [mk("density", "rho (kg/m3)", 1), mk("velocity", "v (m/s)", 2), mk("pressure", "p (Pa)", 3)];
        crate::plot::panels(&png, &panels, 3, (1500, 450))?;
        println!("plot: {}", png.display());
        out["plot"] = json!("profiles.png");
    }
    if let Some(last) = frames.last()
        && let Some(name) = density_map(dir, case, last, &v)?
    {
        println!("plot: {}", dir.join(&name).display());
        out["map"] = json!(name);
    }
    Ok(out)
}

/// `density_map.png` of a Sedov or Noh blast in 2D plane, RZ or 3D (None otherwise): the last
/// frame's particles coloured by ρ on a linear scale from 0 to the exact peak (ρ0 × the jump;
/// Noh: the post-shock density), with the exact shock radius drawn as a red circle about the
/// centre, over 1.3 exact radii about it (clipped to where particles are: an octant shows its
/// quadrant). In 3D the section is the layer of particles nearest the plane z = the centre's z
/// (within half a spacing of the nearest): a ring against a star of jets shows at a glance.
fn density_map(dir: &std::path::Path, case: &Case, f: &Frame, v: &Value) -> Result<Option<String>> {
    let peak = match case.analysis.kind {
        AnalysisKind::Sedov => v["density_jump_exact"].as_f64().zip(v["rho0"].as_f64()).map(|(j, r)| j * r),
        AnalysisKind::Noh => v["post_shock_density_exact"].as_f64(),
        _ => None,
    };
    let (Some(peak), Some(rex), Some(dx)) = (peak, v["shock_radius_exact_m"].as_f64(), v["dx_m"].as_f64()) else {
        return Ok(None);
    };
    if case.dim < 2 || f.x.is_empty() || !(rex > 0.0 && dx > 0.0 && peak > 0.0) {
        return Ok(None);
    }
    let mut c = [0.0; 3];
    if let Some(cm) = &case.analysis.center_m {
        c[..case.dim].copy_from_slice(&cm[..case.dim]);
    }
    let n = f.x.len();
    let keep: Vec<usize> = if case.dim == 3 {
        let near = f.z.iter().map(|z| (z - c[2]).abs()).fold(f64::INFINITY, f64::min);
        (0..n).filter(|&i| (f.z[i] - c[2]).abs() <= near + 0.5 * dx).collect()
    } else {
        (0..n).collect()
    };
    if keep.is_empty() {
        return Ok(None);
    }
    let pick = |a: &[f64]| -> Vec<f64> { keep.iter().map(|&i| a[i]).collect() };
    let (x, y, rho) = (pick(&f.x), pick(&f.y), pick(&f.rho));
    // drawn as the report's snapshots draw particles: their area (2D), their ring's section (RZ),
    // their volume's side (3D: the mass passed as ρ V^⅔, as the report's sections do)
    let rz = case.axisymmetric();
    let mass: Vec<f64> = if case.dim == 3 {
        keep.iter().map(|&i| f.rho[i] * (f.mass[i] / f.rho[i]).powf(2.0 / 3.0)).collect()
    } else {
        pick(&f.mass)
    };
    let side = crate::analysis::sides_of(&x, &mass, &rho, rz);
    let ext = |a: &[f64]| a.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &q| (l.min(q), h.max(q)));
    let ((xl, xh), (yl, yh)) = (ext(&x), ext(&y));
    let bounds = (
        ((c[0] - 1.3 * rex).max(xl - dx), (c[0] + 1.3 * rex).min(xh + dx)),
        ((c[1] - 1.3 * rex).max(yl - dx), (c[1] + 1.3 * rex).min(yh + dx)),
    );
    if !(bounds.0.0 < bounds.0.1 && bounds.1.0 < bounds.1.1) {
        return Ok(None);
    }
    let circle: Vec<[(f64, f64); 2]> = (0..360)
        .map(|k| {
            let (a, b) = (k as f64 * std::f64::consts::PI / 180.0, (k + 1) as f64 * std::f64::consts::PI / 180.0);
            [(c[0] + rex * a.cos(), c[1] + rex * a.sin()), (c[0] + rex * b.cos(), c[1] + rex * b.sin())]
        })
        .filter(|sg| {
            sg.iter()
                .all(|&(px, py)| (bounds.0.0..=bounds.0.1).contains(&px) && (bounds.1.0..=bounds.1.1).contains(&py))
        })
        .collect();
    let overlay = crate::plot::Overlay { segments: circle, marks: Vec::new() };
    let scale = crate::plot::Scale { lo: 0.0, hi: peak, log: false, label: "rho (kg/m3)".into() };
    let note = match case.dim {
        3 => format!(
            "red: the exact shock radius {rex:.4} m; the layer of {} particles nearest z = {} m",
            keep.len(),
            c[2]
        ),
        _ => format!("red: the exact shock radius {rex:.4} m; colours up to the exact peak density {peak:.3}"),
    };
    let name = "density_map.png".to_string();
    crate::plot::map_png(
        &dir.join(&name),
        &crate::plot::MapSpec {
            title: format!("{}  t = {:.4} s: density", case.name(), f.time),
            x: &x,
            y: &y,
            side: &side,
            colouring: crate::plot::Colouring::Field { values: &rho, scale: &scale },
            bounds,
            note: Some(note),
            axes: if rz { ["r (m)", "z (m)"] } else { ["x (m)", "y (m)"] },
            overlay: Some(&overlay),
        },
    )?;
    Ok(Some(name))
}
