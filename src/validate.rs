//! `blastsph validate`: runs every thesis scene of `cases/`, measures each (as `blastsph report`
//! does) and writes the comparison with the thesis (docs/validation.md, "Thesis scenes") and the checks of the trends
//! the thesis draws, as Markdown (`validation.md`) and JSON (`validation.json`) in DIR.

use crate::error::{IoAt, Result, SphError};
use crate::runner::{self, RunOptions};
use serde_json::{Value, json};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The thesis scenes, in the order of docs/validation.md, "Thesis scenes".
pub const SCENES: [&str; 13] = [
    "underwater_box",
    "buried_c4",
    "surface_loose_tnt4",
    "surface_loose_tnt6",
    "surface_loose_tnt10",
    "surface_dense_tnt4",
    "surface_dense_tnt6",
    "surface_dense_tnt10",
    "two_layer_10",
    "two_layer_15",
    "two_layer_20",
    "slope_45",
    "saturated_underwater",
];

/// One scene's measured values.
#[derive(Debug, Clone, Default)]
struct Scene {
    name: String,
    summary: Value,
    report: Value,
}

impl Scene {
    fn crater(&self) -> (f64, f64) {
        let c = &self.report["crater"];
        (c["diameter_m"].as_f64().unwrap_or(f64::NAN), c["depth_m"].as_f64().unwrap_or(f64::NAN))
    }
    fn thesis(&self) -> Option<(f64, f64)> {
        let t = self.report["thesis_crater_m"].as_array()?;
        Some((t.first()?.as_f64()?, t.get(1)?.as_f64()?))
    }
    fn gauge(&self, name: &str) -> Option<&Value> {
        self.summary["gauges"].as_array()?.iter().find(|g| g["name"] == name)
    }
    fn peak(&self, name: &str) -> f64 {
        self.gauge(name).and_then(|g| g["peak_pa"].as_f64()).unwrap_or(f64::NAN)
    }
    fn arrival(&self, name: &str) -> f64 {
        self.gauge(name).and_then(|g| g["arrival_s"].as_f64()).unwrap_or(f64::NAN)
    }
}

/// Runs the scenes (all, or those named) into `out`, returns the Markdown text.
pub fn validate(cases_dir: &Path, out: &Path, opts: &RunOptions, only: &[String]) -> Result<String> {
    // every scene's case file is there before anything is written or run (an empty folder was
    // found one scene in, after validation.md was written)
    let missing: Vec<String> = SCENES
        .iter()
        .filter(|n| only.is_empty() || only.iter().any(|o| o == *n))
        .map(|n| format!("{n}.toml"))
        .filter(|f| !cases_dir.join(f).is_file())
        .collect();
    if !missing.is_empty() {
        return Err(crate::error::input(format!(
            "--cases {}: no {} (the thesis's scenes, as in cases/)",
            cases_dir.display(),
            if missing.len() > 3 {
                format!("{}, … ({} of the scenes)", missing[..3].join(", "), missing.len())
            } else {
                missing.join(", ")
            }
        )));
    }
    std::fs::create_dir_all(out).io_at(out.display())?;
    // the folder is validate's from now on (a validation stopped half-way can be run again into
    // it): validation.md says so until the results replace it
    std::fs::write(out.join("validation.md"), "(validation running)\n").io_at(out.display())?;
    let mut scenes = Vec::new();
    for name in SCENES {
        if !only.is_empty() && !only.iter().any(|o| o == name) {
            continue;
        }
        let path = cases_dir.join(format!("{name}.toml"));
        let mut o = opts.clone();
        o.out = Some(out.join(name));
        eprintln!("validate: {name}");
        let (summary, dir) = match runner::run(&path, &o) {
            Ok(r) => (r.summary, r.dir),
            Err(e) => {
                // an unstable run still leaves its summary and output: report it as such
                let dir: PathBuf = out.join(name);
                let s = std::fs::read_to_string(dir.join("summary.json")).map_err(|_| e)?;
                (serde_json::from_str(&s).unwrap_or(Value::Null), dir)
            }
        };
        let report = crate::report::report(&dir).unwrap_or(Value::Null);
        scenes.push(Scene { name: name.to_string(), summary, report });
    }
    let md = markdown(&scenes);
    let js = json!({
        "scenes": scenes.iter().map(|s| json!({"case": s.name, "summary": s.summary, "report": s.report})).collect::<Vec<_>>(),
        "trends": trends(&scenes).iter().map(|(t, ok, why)| json!({"trend": t, "holds": ok, "detail": why})).collect::<Vec<_>>(),
    });
    std::fs::write(out.join("validation.md"), &md).map_err(|e| SphError::Io(e.to_string()))?;
    std::fs::write(out.join("validation.json"), serde_json::to_string_pretty(&js).unwrap_or_default())
        .map_err(|e| SphError::Io(e.to_string()))?;
    Ok(md)
}

fn cm(v: f64) -> String {
    if v.is_finite() { format!("{:.1}", 100.0 * v) } else { "-".into() }
}

fn markdown(scenes: &[Scene]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| case | status | steps | wall (s) | crater D (cm) | depth (cm) | bowl width at half depth (cm) | thesis D | thesis depth | D ours/thesis | depth ours/thesis | ejecta (cm) | energy residual | wall penetration (m) | closest interface gap (dx) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for sc in scenes {
        let (d, z) = sc.crater();
        let (td, tz) = sc.thesis().unwrap_or((f64::NAN, f64::NAN));
        let st = &sc.summary["stability"];
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.1} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2e} | {:.1e} | {} |",
            sc.name,
            sc.summary["status"].as_str().unwrap_or("?"),
            sc.summary["steps"],
            sc.summary["wall_seconds"].as_f64().unwrap_or(0.0),
            cm(d),
            cm(z),
            cm(sc.report["crater"]["width_half_depth_m"].as_f64().unwrap_or(f64::NAN)),
            cm(td),
            cm(tz),
            if td.is_finite() { format!("{:.2}", d / td) } else { "-".into() },
            if tz.is_finite() { format!("{:.2}", z / tz) } else { "-".into() },
            cm(sc.report["crater"]["ejecta_height_m"].as_f64().unwrap_or(f64::NAN)),
            sc.summary["energy"]["balance_residual_relative"].as_f64().unwrap_or(f64::NAN),
            st["max_wall_penetration_m"].as_f64().unwrap_or(f64::NAN),
            st["min_interface_gap_dx"].as_f64().map_or("-".into(), |g| format!("{g:.2}"))
        );
    }
    for sc in scenes {
        let c = &sc.report["crater"];
        if c["measured"] == false {
            let _ =
                writeln!(s, "\n{}: the crater cannot be measured: {}", sc.name, c["reason"].as_str().unwrap_or("?"));
        } else if let Some(note) = c["note"].as_str() {
            let _ = writeln!(s, "\n{}: {note}", sc.name);
        }
    }
    let _ = writeln!(
        s,
        "\nParticles with negative specific internal energy at the end time (per material: count, smallest e in J/kg):\n"
    );
    let _ = writeln!(s, "| case | e < 0 (all) | per material |");
    let _ = writeln!(s, "|---|---|---|");
    for sc in scenes {
        let ne = &sc.summary["negative_e"];
        let per: Vec<String> = ne["by_material"]
            .as_object()
            .map(|o| {
                o.iter()
                    .map(|(k, v)| {
                        let c = v["count"].as_u64().unwrap_or(0);
                        if c > 0 {
                            format!("{k}: {c} (min {:.3e})", v["min_e_jkg"].as_f64().unwrap_or(f64::NAN))
                        } else {
                            format!("{k}: 0")
                        }
                    })
                    .collect()
            })
            .unwrap_or_default();
        let _ = writeln!(
            s,
            "| {} | {} | {} |",
            sc.name,
            ne["count"].as_u64().map_or("-".into(), |c| c.to_string()),
            per.join(", ")
        );
    }
    let _ =
        writeln!(s, "\nGauges (peak pressure in MPa at peak time in µs; arrival = first time above half the peak):\n");
    let _ = writeln!(s, "| case | gauge | distance (cm) | ours: peak | at | arrival | thesis: peak | at |");
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    for sc in scenes {
        let th = sc.report["thesis_gauges"].as_array().cloned().unwrap_or_default();
        for g in sc.summary["gauges"].as_array().cloned().unwrap_or_default() {
            let name = g["name"].as_str().unwrap_or("?");
            let t = th.iter().find(|t| t["gauge"] == name);
            let dist = sc.report["peaks_cm_mpa"]
                .as_array()
                .and_then(|a| {
                    let k = sc.summary["gauges"].as_array()?.iter().position(|x| x["name"] == name)?;
                    a.get(k)?.get(0)?.as_f64()
                })
                .map_or("-".into(), |d| format!("{d:.0}"));
            let _ = writeln!(
                s,
                "| {} | {} | {} | {:.1} | {:.0} | {:.0} | {} | {} |",
                sc.name,
                name,
                dist,
                g["peak_pa"].as_f64().unwrap_or(f64::NAN) / 1e6,
                g["peak_time_s"].as_f64().unwrap_or(f64::NAN) * 1e6,
                g["arrival_s"].as_f64().unwrap_or(f64::NAN) * 1e6,
                t.and_then(|t| t["thesis_peak_pa"].as_f64()).map_or("-".into(), |p| format!("{:.1}", p / 1e6)),
                t.and_then(|t| t["thesis_peak_time_s"].as_f64()).map_or("-".into(), |p| format!("{:.0}", p * 1e6)),
            );
        }
    }
    let growth: Vec<_> =
        scenes.iter().filter(|s| s.report["thesis_growth"].as_array().is_some_and(|a| !a.is_empty())).collect();
    if !growth.is_empty() {
        let _ = writeln!(s, "\nCrater growth (cm) at the thesis's times:\n");
        let _ = writeln!(s, "| case | t (µs) | thesis D | thesis depth | ours D | ours depth |");
        let _ = writeln!(s, "|---|---|---|---|---|---|");
        for sc in growth {
            for g in sc.report["thesis_growth"].as_array().cloned().unwrap_or_default() {
                let _ = writeln!(
                    s,
                    "| {} | {:.0} | {} | {} | {} | {} |",
                    sc.name,
                    g["our_t_s"].as_f64().unwrap_or(0.0) * 1e6,
                    cm(g["thesis_diameter_m"].as_f64().unwrap_or(f64::NAN)),
                    cm(g["thesis_depth_m"].as_f64().unwrap_or(f64::NAN)),
                    cm(g["diameter_m"].as_f64().unwrap_or(f64::NAN)),
                    cm(g["depth_m"].as_f64().unwrap_or(f64::NAN)),
                );
            }
        }
    }
    let _ = writeln!(s, "\nThe thesis's trends, checked on these runs:\n");
    for (t, ok, why) in trends(scenes) {
        let _ = writeln!(s, "- **{}** — {}: {}", t, if ok { "holds" } else { "does not hold" }, why);
    }
    s
}

/// The trends the thesis draws (docs/validation.md, "Thesis scenes"), each checked: (trend, holds, detail).
fn trends(scenes: &[Scene]) -> Vec<(String, bool, String)> {
    let get = |n: &str| scenes.iter().find(|s| s.name == n);
    let mut out = Vec::new();
    // a difference counts only when it exceeds what the measure resolves: a crater diameter is
    // counted in columns one spacing wide (1 cm), a depth is read from particle positions (a
    // quarter spacing, 2.5 mm, is taken as its resolution); pressures and times are resolved
    let mut cmp = |title: &str, pairs: Vec<(String, f64, f64)>, want_less: bool, resolution: f64| {
        if pairs.is_empty() {
            return;
        }
        let ok = pairs.iter().all(|(_, a, b)| if want_less { b - a > resolution } else { a - b > resolution });
        let detail = pairs
            .iter()
            .map(|(w, a, b)| {
                let tie = (a - b).abs() <= resolution;
                format!("{w}: {a:.4} vs {b:.4}{}", if tie { " (within the resolution of the measure)" } else { "" })
            })
            .collect::<Vec<_>>()
            .join("; ");
        out.push((title.to_string(), ok, detail));
    };
    let (res_d, res_z) = (0.01 * 0.999, 0.0025);
    let mut dd = Vec::new();
    let mut dz = Vec::new();
    let mut pa = Vec::new();
    let mut ar = Vec::new();
    for k in [4, 6, 10] {
        if let (Some(d), Some(l)) = (get(&format!("surface_dense_tnt{k}")), get(&format!("surface_loose_tnt{k}"))) {
            dd.push((format!("{k}x{k} D (m)"), d.crater().0, l.crater().0));
            dz.push((format!("{k}x{k} depth (m)"), d.crater().1, l.crater().1));
            pa.push((format!("{k}x{k} peak at A (MPa)"), d.peak("A") / 1e6, l.peak("A") / 1e6));
            ar.push((format!("{k}x{k} arrival at E (us)"), d.arrival("E") * 1e6, l.arrival("E") * 1e6));
        }
    }
    cmp("denser soil gives a smaller crater diameter (dense vs loose)", dd, true, res_d);
    cmp("denser soil gives a shallower crater (dense vs loose)", dz, true, res_z);
    cmp("denser soil gives higher peaks (dense vs loose, gauge A)", pa, false, 0.0);
    cmp("denser soil gives earlier arrival (dense vs loose, gauge E)", ar, true, 0.0);
    for soil in ["loose", "dense"] {
        let mut d = Vec::new();
        let mut z = Vec::new();
        let mut p = Vec::new();
        for (a, b) in [(4, 6), (6, 10)] {
            if let (Some(x), Some(y)) = (get(&format!("surface_{soil}_tnt{a}")), get(&format!("surface_{soil}_tnt{b}")))
            {
                d.push((format!("{a} vs {b} cm D (m)"), x.crater().0, y.crater().0));
                z.push((format!("{a} vs {b} cm depth (m)"), x.crater().1, y.crater().1));
                p.push((format!("{a} vs {b} cm peak at A (MPa)"), x.peak("A") / 1e6, y.peak("A") / 1e6));
            }
        }
        cmp(&format!("a bigger charge gives a wider crater ({soil} sand)"), d, true, res_d);
        cmp(&format!("a bigger charge gives a deeper crater ({soil} sand)"), z, true, res_z);
        cmp(&format!("a bigger charge gives higher peaks ({soil} sand)"), p, true, 0.0);
    }
    let mut z = Vec::new();
    for (a, b) in [(10, 15), (15, 20)] {
        if let (Some(x), Some(y)) = (get(&format!("two_layer_{a}")), get(&format!("two_layer_{b}"))) {
            z.push((format!("loose layer {a} vs {b} cm depth (m)"), x.crater().1, y.crater().1));
        }
    }
    cmp("a thicker loose layer gives a deeper crater (two-layer soil; thesis 18, 20, 22 cm)", z, true, res_z);
    let mut early = Vec::new();
    for sc in scenes {
        let h = sc.report["history"].as_array().cloned().unwrap_or_default();
        let end = sc.summary["time"].as_f64().unwrap_or(0.0);
        if h.len() < 3 || sc.crater().1 <= 0.0 || !sc.crater().1.is_finite() {
            continue;
        }
        let t3 = 0.3 * end;
        if let Some(r) = h.iter().min_by(|a, b| {
            (a["t_s"].as_f64().unwrap_or(0.0) - t3).abs().total_cmp(&(b["t_s"].as_f64().unwrap_or(0.0) - t3).abs())
        }) {
            early.push((
                format!("{} depth(0.3 t_end)/depth(t_end)", sc.name),
                r["depth_m"].as_f64().unwrap_or(0.0) / sc.crater().1,
                0.5,
            ));
        }
    }
    cmp("the crater shape is set early (over half the final depth by 30 % of the run)", early, false, 0.0);
    out
}
