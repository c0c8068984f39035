//! `blastsph converge` end to end on a tiny RZ charge (three levels, seconds), `report` of one
//! of its levels showing the error bars, a run's frames at the requested output times, and the
//! report's window.

mod common;

use std::path::Path;
use std::process::{Command, Output};

fn blastsph(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_blastsph")).args(args).current_dir(common::root()).output().expect("blastsph")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// A TNT cylinder (R = 3 cm, H = 6 cm, 0.28 kg) flush with the top of a 0.3 × 0.3 m block of
/// dense sand, RZ, rings of 1.5 cm; a gauge on the axis 10 cm below the charge.
fn tiny_text() -> String {
    common::rz_charge_case(&common::RzCharge {
        name: "tiny_rz",
        end_s: 1.0e-4,
        output_s: 2.0e-5,
        charge_r: 0.03,
        charge_z: (0.24, 0.3),
        block: (0.3, 0.3),
        wall_top: 0.3,
        spacing: 0.015,
        det_z: 0.27,
        gauge_z: Some(0.14),
    })
}

fn tiny(dir: &Path) -> String {
    let p = dir.join("tiny_rz.toml");
    std::fs::write(&p, tiny_text()).unwrap();
    p.to_str().unwrap().to_string()
}

/// Every frame of particles.h5 lies on a requested output time k·Δt_out (within 1e-12 s), and
/// every one of them is there: the CFL step is shortened to land on each.
#[test]
fn frames_land_on_the_requested_output_times() {
    let dir = tempfile::tempdir().unwrap();
    let case = tiny(dir.path());
    let out = dir.path().join("run");
    let o =
        blastsph(&["run", &case, "--out", out.to_str().unwrap(), "--quiet", "--set", "time.output_interval_s=1.3e-5"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let frames = blastsph::output::read_frames(&out.join("particles.h5")).unwrap();
    let times: Vec<f64> = frames.iter().map(|f| f.time).collect();
    // 0, 13, 26, ..., 91 µs and the end, 100 µs
    let mut want: Vec<f64> = (0..8).map(|k| k as f64 * 1.3e-5).collect();
    want.push(1.0e-4);
    assert_eq!(times.len(), want.len(), "{times:?}");
    for (t, w) in times.iter().zip(&want) {
        assert!((t - w).abs() < 1e-12, "frame at {t:e} s, requested {w:e} s: {times:?}");
    }
    // the report's window: four numbers, refused otherwise; the case key is checked by `check`
    let run = out.to_str().unwrap();
    let o = blastsph(&["report", run, "--window", "0,0.2,0.1,0.45"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let o = blastsph(&["report", run, "--window", "0,0.2,0.45,0.1"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(text(&o.stderr).starts_with("error: --window"), "{}", text(&o.stderr));
    let o = blastsph(&["check", &case, "--set", "analysis.view_m=[0.0, 0.2, 0.1]"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    let o = blastsph(&["check", &case, "--set", "analysis.view_m=[0.0, 0.2, 0.1, 0.45]"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
}

/// `converge` on the tiny case: three levels (k = 1, 2, 4; 4× the particles each), the crater and
/// gauge figures each with an order, an extrapolated value and a GCI (or the reason there is
/// none), a plot per figure; `report` of a level prints the error bars.
#[test]
fn converge_gives_every_figure_its_order_extrapolation_and_gci() {
    let dir = tempfile::tempdir().unwrap();
    let case = tiny(dir.path());
    let out = dir.path().join("conv");
    let o = blastsph(&["converge", &case, "--out", out.to_str().unwrap()]);
    let stdout = text(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{stdout}{}", text(&o.stderr));
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("converge.json")).unwrap()).unwrap();
    let levels = doc["levels"].as_array().unwrap();
    assert_eq!(levels.len(), 3);
    let ks: Vec<f64> = levels.iter().map(|l| l["k"].as_f64().unwrap()).collect();
    assert_eq!(ks, [1.0, 2.0, 4.0]);
    let n: Vec<u64> = levels.iter().map(|l| l["particles"].as_u64().unwrap()).collect();
    assert!(n[1] > 3 * n[0] && n[2] > 3 * n[1], "{n:?}");
    for l in levels {
        assert_eq!(l["status"], "ok", "{l}");
        assert!(l["wall_s"].as_f64().unwrap() > 0.0);
    }
    let figs = doc["figures"].as_array().unwrap();
    let keys: Vec<&str> = figs.iter().map(|f| f["key"].as_str().unwrap()).collect();
    for k in
        ["crater.diameter_m", "crater.depth_m", "crater.mound_height_m", "gauges.A.peak_pa", "gauges.A.impulse_pa_s"]
    {
        assert!(keys.contains(&k), "{k} not in {keys:?}");
    }
    let peak = figs.iter().find(|f| f["key"] == "gauges.A.peak_pa").unwrap();
    let v: Vec<f64> = peak["values"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    assert!(v.iter().all(|p| *p > 1e6), "{v:?}");
    let e = &peak["estimate"];
    // the order, the extrapolated value and the GCI as Celik et al. compute them from the values
    let (e21, e32) = (v[1] - v[2], v[0] - v[1]);
    let p = e["order"].as_f64().unwrap();
    assert!(((e32 / e21).abs().ln() / 2f64.ln()).abs() - p < 1e-9, "{e}");
    // a change that grows with refinement is never called asymptotic
    if e21.abs() > e32.abs() {
        assert!(e["not_asymptotic"].as_str().is_some_and(|w| w.contains("grows with refinement")), "{e}");
    }
    let rp = 2f64.powf(p);
    let ext = (rp * v[2] - v[1]) / (rp - 1.0);
    assert!((e["extrapolated"].as_f64().unwrap() - ext).abs() < 1e-9 * ext.abs(), "{e}");
    let gci = 1.25 * (e21 / v[2]).abs() / (rp - 1.0);
    assert!((e["gci_fine"].as_f64().unwrap() - gci).abs() < 1e-12, "{e}");
    assert!(stdout.contains("gauge A peak") && stdout.contains("GCI fine"), "{stdout}");
    assert!(out.join("converge_gauges_A_peak_pa.png").is_file());
    let o = blastsph(&["report", out.join("level_4").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let rep = text(&o.stdout);
    assert!(rep.contains("error bars from") && rep.contains("this run is k = 4"), "{rep}");
    assert!(rep.lines().any(|l| l.contains("gauge A peak") && l.contains("(GCI)")), "{rep}");
}
