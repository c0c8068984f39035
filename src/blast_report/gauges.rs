//! The gauges: their records read back, their pressure histories drawn, their peaks printed.

use super::*;

/// A gauge's record read back from gauges.csv: (time s, pressure Pa, speed |v| m/s).
#[derive(Debug, Clone, Default)]
pub struct GaugeRecord {
    pub name: String,
    pub samples: Vec<(f64, f64, f64)>,
    /// The indices of the samples that follow a void (a point gauge with no particle in reach):
    /// the plots break their line there rather than draw readings across it.
    pub after_void: Vec<usize>,
}

/// Reads gauges.csv (docs/reference/cases.md `[[gauge]]` lists its columns); empty fields (a point
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
pub(super) fn draw_gauges(
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

/// A charge in air (an ideal gas beside a JWL): each gauge's peak overpressure and positive
/// impulse (over its first reading, the ambient) against Kinney & Graham's fits at its scaled
/// distance from the charge's centre (`crate::analysis::airblast`), printed and returned, for
/// the gauges in the air (the particle nearest the point at t = 0 an ideal gas); None for a case
/// without air, a charge or such gauges.
pub fn air_blast(dir: &Path, case: &Case, frames: &[Frame]) -> Result<Option<Value>> {
    use crate::analysis::airblast;
    use crate::case::EosCfg;
    let gpath = dir.join("gauges.csv");
    if !super::peaks::charge_in_air(case) || frames.is_empty() || case.dim < 2 || !gpath.exists() {
        return Ok(None);
    }
    let charge = charge_of(case, frames);
    let Some(centre) = charge.centre.clone().filter(|_| charge.mass_kg > 0.0 && charge.dim == 3) else {
        return Ok(None);
    };
    let w = charge.mass_kg;
    // a gauge in the air: the particle nearest its point at t = 0 is an ideal gas (a gauge in
    // the soil, the water or the charge reads no air blast)
    let f0 = &frames[0];
    let in_air = |pt: &[f64]| -> bool {
        let d2 = |i: usize| -> f64 {
            let q = [f0.x[i], f0.y[i], f0.z[i]];
            pt.iter().zip(q).map(|(a, b)| (a - b) * (a - b)).sum()
        };
        let near = (0..f0.x.len()).min_by(|&a, &b| d2(a).total_cmp(&d2(b)));
        near.and_then(|i| case.materials.get(f0.mat[i] as usize))
            .is_some_and(|m| matches!(m.eos, EosCfg::IdealGas { .. }))
    };
    let gauges: Vec<_> = read_gauges(&gpath)?
        .into_iter()
        .filter(|rec| case.gauges.iter().any(|g| g.name == rec.name && in_air(&g.point_m)))
        .collect();
    if gauges.is_empty() {
        return Ok(None);
    }
    println!("air blast against Kinney & Graham (1985), charge {}:", charge.mass_text());
    let mut rows = Vec::new();
    for rec in gauges {
        let Some(g) = case.gauges.iter().find(|g| g.name == rec.name) else { continue };
        let r = g.point_m.iter().zip(&centre).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
        let t: Vec<f64> = rec.samples.iter().map(|s| s.0).collect();
        let p: Vec<Option<f64>> = rec.samples.iter().map(|s| Some(s.1)).collect();
        let (Some(amb), true) = (rec.samples.first().map(|s| s.1), r > 0.0) else { continue };
        let z = r / w.cbrt();
        let (kp, ki) = (airblast::overpressure(z), airblast::impulse(z, w));
        let Some((peak, imp)) = airblast::measure(&t, &p, amb) else { continue };
        println!(
            "  gauge {} at Z = {z:.2} m/kg^(1/3): peak overpressure {:.1} kPa against {:.1} ({:.2}), positive impulse {:.2} Pa·s against {:.2} ({:.2})",
            rec.name,
            peak / 1e3,
            kp / 1e3,
            peak / kp,
            imp,
            ki,
            imp / ki
        );
        rows.push(json!({"gauge": rec.name, "scaled_distance": z, "peak_overpressure_pa": peak,
            "kinney_graham_pa": kp, "impulse_pa_s": imp, "kinney_graham_impulse_pa_s": ki}));
    }
    Ok(Some(json!({"charge_kg": w, "gauges": rows})))
}
