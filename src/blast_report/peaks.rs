//! `gauges.png` with the thesis's values and `peaks.png`: peak pressure against scaled distance.

use super::*;

/// Gauge peaks: (distance (cm), peak (MPa)) and (scaled distance, peak (MPa), label).
pub(super) type Peaks = (Vec<(f64, f64)>, Vec<(f64, f64, String)>);

/// Scaled distance of a gauge at `r` m from the charge: R/√(W/L) in plane strain (W/L in kg per
/// metre of depth, a line charge), R/W^(1/3) in 3D, R/(W/A) in 1D.
fn scaled(r: f64, w: f64, dim: usize) -> f64 {
    match dim {
        2 => r / w.sqrt(),
        3 => r / w.cbrt(),
        _ => r / w,
    }
}

/// The gauges' pressure histories and `peaks.png`: peak pressure against scaled distance. Returns
/// the peaks (cm, MPa) and the scaled ones (scaled distance, MPa, label).
pub(super) fn gauge_plots(cx: &Ctx, summary: &Value, charge: &Charge, written: &mut Vec<String>) -> Result<Peaks> {
    let (dir, case, tu) = (cx.dir, cx.case, cx.tu);
    let gpath = dir.join("gauges.csv");
    let mut peaks_out = Vec::new();
    let mut peaks = Vec::new();
    if gpath.exists() {
        let recs = read_gauges(&gpath)?;
        let sg: Vec<Value> = summary["gauges"].as_array().cloned().unwrap_or_default();
        let mut refs = Vec::new();
        // a thesis peak is drawn where the thesis gives both its time and its pressure; a time
        // alone is left to the text (a marker at our pressure would read as the thesis's value)
        for tg in &case.analysis.thesis_gauge {
            if let (Some(t), Some(p)) = (tg.peak_time_s, tg.peak_pa) {
                refs.push(Reference { label: format!("thesis {}: peak", tg.gauge), points: vec![(tu.of(t), p / 1e6)] });
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
                let curves = if charge.dim != 3 {
                    Vec::new()
                } else if charge_in_air(case) {
                    kinney_graham_curve(&peaks_out)
                } else if dry_sand(case) {
                    tm5_855_1_curves(&peaks_out)
                } else {
                    Vec::new()
                };
                plot::loglog_on_data(
                    &dir.join("peaks.png"),
                    &format!("{}: peak pressure against scaled distance (charge {})", case.name(), charge.mass_text()),
                    charge.scaled_label(),
                    "peak p (MPa)",
                    &peaks_out,
                    &curves,
                )?;
                written.push("peaks.png".into());
            }
        }
    }
    Ok((peaks, peaks_out))
}

/// One psi in Pa, one foot in m and one pound in kg.
const PSI_PA: f64 = 6_894.757_293_168_361;
const FT_M: f64 = 0.3048;
const LB_KG: f64 = 0.453_592_37;

/// The acoustic impedance ρc (psi/(ft/s)) and the attenuation coefficients n (least and most) of
/// "loose, dry sands and gravels with low relative density" in TM 5-855-1 (1986), chapter 5.
pub(super) const TM_LOOSE_DRY_SAND: (f64, [f64; 2]) = (12.0, [3.0, 3.25]);

/// The peak ground-shock pressure (MPa) of TM 5-855-1 (1986), chapter 5 (ground shock):
/// P0 = f · ρc · 160 · (R/W^⅓)^(−n) psi, with R in ft, W in lb of TNT, `rho_c` in psi/(ft/s).
/// `z` is the scaled distance R/W^⅓ in m/kg^⅓ (1 m/kg^⅓ = 2.521 ft/lb^⅓); `f` the coupling factor.
pub(super) fn tm5_855_1_mpa(z: f64, f: f64, rho_c: f64, n: f64) -> f64 {
    let z_ft = z / FT_M * LB_KG.cbrt();
    f * rho_c * 160.0 * z_ft.powf(-n) * PSI_PA / 1e6
}

/// Whether every soil material of the case is a dry sand (its name or preset says sand, and not
/// saturated): the scenes that [`TM_LOOSE_DRY_SAND`] describes.
fn dry_sand(case: &Case) -> bool {
    let soil = crate::analysis::crater::soil_mask(case);
    let sands: Vec<bool> = case
        .materials
        .iter()
        .zip(&soil)
        .filter(|(_, s)| **s)
        .map(|(m, _)| {
            let what = format!("{} {}", m.name, m.preset.as_deref().unwrap_or("")).to_lowercase();
            what.contains("sand") && !what.contains("saturated") && !what.contains("wet")
        })
        .collect();
    !sands.is_empty() && sands.iter().all(|s| *s)
}

/// A charge in air: an ideal gas beside a JWL explosive.
pub(super) fn charge_in_air(case: &Case) -> bool {
    use crate::case::EosCfg;
    let has = |f: &dyn Fn(&EosCfg) -> bool| case.materials.iter().any(|m| f(&m.eos));
    has(&|e| matches!(e, EosCfg::IdealGas { .. })) && has(&|e| matches!(e, EosCfg::Jwl { .. }))
}

/// The scaled distances of `peaks` (and a little beyond) at which a reference curve is drawn:
/// 61 points spaced evenly in log; empty without a finite positive distance.
fn curve_span(peaks: &[(f64, f64, String)]) -> Vec<f64> {
    let zs: Vec<f64> = peaks.iter().map(|p| p.0).filter(|z| z.is_finite() && *z > 0.0).collect();
    if zs.is_empty() {
        return Vec::new();
    }
    let (lo, hi) = zs.iter().fold((f64::INFINITY, 0.0f64), |a, z| (a.0.min(*z), a.1.max(*z)));
    let (lo, hi) = (lo / 1.3, hi * 1.3);
    (0..=60).map(|k| lo * (hi / lo).powf(k as f64 / 60.0)).collect()
}

/// Sea-level air pressure (Pa): the ambient of Kinney & Graham's fit and of the `air` preset.
const SEA_LEVEL_PA: f64 = 101_325.0;

/// Kinney & Graham's free-air TNT curve (`crate::analysis::airblast::overpressure`) as an
/// absolute peak pressure (MPa, the overpressure plus sea-level air), the measure the gauges'
/// peaks are, over the scaled distances of `peaks`.
fn kinney_graham_curve(peaks: &[(f64, f64, String)]) -> Vec<(String, Vec<(f64, f64)>)> {
    let zs = curve_span(peaks);
    if zs.is_empty() {
        return Vec::new();
    }
    let pts = zs.iter().map(|&z| (z, (crate::analysis::airblast::overpressure(z) + SEA_LEVEL_PA) / 1e6)).collect();
    vec![("Kinney & Graham (1985) free-air TNT, peak overpressure + 101.325 kPa".to_string(), pts)]
}

/// The TM 5-855-1 loose dry sand curves (MPa against m/kg^⅓) for n = 3 and 3.25, fully coupled
/// (f = 1), over the scaled distances of `peaks` (and a little beyond).
fn tm5_855_1_curves(peaks: &[(f64, f64, String)]) -> Vec<(String, Vec<(f64, f64)>)> {
    let zs = curve_span(peaks);
    if zs.is_empty() {
        return Vec::new();
    }
    let (rho_c, ns) = TM_LOOSE_DRY_SAND;
    ns.iter()
        .map(|&n| {
            let pts = zs.iter().map(|&z| (z, tm5_855_1_mpa(z, 1.0, rho_c, n))).collect();
            (format!("TM 5-855-1 (1986) loose dry sand, f = 1, ρc = {rho_c} psi/(ft/s), n = {n}"), pts)
        })
        .collect()
}
