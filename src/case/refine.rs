//! Refinement by k: every spacing Δx of a case becomes Δx/k, with what follows from it.

use crate::error::Result;

use crate::case;
use crate::case::AnalysisKind;
use crate::case::Case;
use crate::case::Shape;
use crate::case::StepRule;
use crate::error::input;

/// A float as TOML text that reads back to the same f64 (Debug prints the shortest round-trip
/// form, always with a `.` or an exponent, so TOML reads a float, never an integer).
pub(super) fn num(x: f64) -> String {
    format!("{x:?}")
}

/// The `--set` overrides that refine `case` by the factor `k` (Δx → Δx/k):
///
/// - every region: `spacing_m` / k; `mass_kg` / k^dim and `h_m` / k where the region gives them
///   (otherwise their defaults ρΔx^d and h_over_dx·Δx follow the spacing by themselves);
/// - lattice regions: `count` × k per axis (it must come out whole) and the origin moved so that
///   the lattice covers the same cells. Lattice points are cell centres (the extent that
///   docs/reference/cases.md gives a lattice), so origin' = origin − Δx/2 + Δx'/2 — except in a 1D Riemann
///   case (`analysis.kind = "riemann"`), where each point is taken at the end of its cell away
///   from the diaphragm x0: origin' = origin left of x0, origin − Δx + Δx' right of it. That
///   is the book's shock tube (its first particles one spacing from the diaphragm on either
///   side) at every resolution; read as cell centres, its two lattices leave a gap of fixed width
///   (−Δx_L/2 … Δx_R/2 = 4.7 mm) between the gases, which h/k soon fails to bridge (at k = 2 the
///   run blows up);
/// - box and polygon regions are cell-centred lattices of their shape: the shape stays, and a box
///   whose sides are whole multiples of Δx/k is filled exactly;
/// - `time.dt_s` / k for fixed steps, `time.dt_max_s` / k where given, and `time.max_steps` × k
///   (a safety limit, not a physical time) for k > 1;
/// - `boundary.wall_spacing_m` and `boundary.r0_m` / k where given (their defaults follow the
///   finest spacing by themselves);
/// - everything else stays: gauges, walls, charges, the detonation point, the analysis, and a
///   region's `keep_below` planes (a plane is a place, not a count of spacings: the refined
///   lattice is clipped by the same planes, and an inclined one cuts it in a finer staircase, so
///   its count is k^dim times the coarse one only where the plane lies on cell faces of both).
///
/// k = 1 gives no overrides. Regions are named by index, so any region name works.
pub fn refinement_sets(case: &Case, k: f64) -> Result<Vec<String>> {
    if !(k.is_finite() && k > 0.0) {
        return Err(input(format!("refinement factor {k}: must be a positive number")));
    }
    if k == 1.0 {
        return Ok(Vec::new());
    }
    let d = case.dim as i32;
    let mut s = Vec::new();
    for (i, r) in case.regions.iter().enumerate() {
        let sp = r.spacing_m / k;
        s.push(format!("region.{i}.spacing_m={}", num(sp)));
        if r.shape == Shape::Lattice {
            let mut counts = Vec::new();
            for &n in r.count.as_deref().unwrap_or(&[]) {
                let nk = n as f64 * k;
                if (nk - nk.round()).abs() > 1e-9 * nk.max(1.0) || nk.round() < 1.0 {
                    return Err(input(format!(
                        "region[{i}] ({}): count {n} × k = {k} is not a whole number of particles: choose another refinement",
                        r.name
                    )));
                }
                counts.push(format!("{}", nk.round() as u64));
            }
            let diaphragm = match (case.analysis.kind, case.analysis.diaphragm_m) {
                (AnalysisKind::Riemann, Some(x0)) if case.dim == 1 => Some(x0),
                _ => None,
            };
            let origin: Vec<String> = r
                .origin_m
                .as_deref()
                .unwrap_or(&[])
                .iter()
                .map(|&o| {
                    num(match diaphragm {
                        // the point at the end of its cell away from the diaphragm
                        Some(x0) if o < x0 => o,
                        Some(_) => o - r.spacing_m + sp,
                        // the point at the centre of its cell
                        None => o - 0.5 * r.spacing_m + 0.5 * sp,
                    })
                })
                .collect();
            s.push(format!("region.{i}.count=[{}]", counts.join(", ")));
            s.push(format!("region.{i}.origin_m=[{}]", origin.join(", ")));
        }
        if let Some(m) = r.mass_kg {
            s.push(format!("region.{i}.mass_kg={}", num(m / k.powi(d))));
        }
        if let Some(h) = r.h_m {
            s.push(format!("region.{i}.h_m={}", num(h / k)));
        }
    }
    let t = &case.time;
    if t.step == StepRule::Fixed
        && let Some(dt) = t.dt_s
    {
        s.push(format!("time.dt_s={}", num(dt / k)));
    }
    if let Some(m) = t.dt_max_s {
        s.push(format!("time.dt_max_s={}", num(m / k)));
    }
    if k > 1.0 {
        let ms = (t.max_steps as f64 * k).ceil().min(i64::MAX as f64) as i64;
        s.push(format!("time.max_steps={ms}"));
    }
    if let Some(w) = case.boundary.wall_spacing_m {
        s.push(format!("boundary.wall_spacing_m={}", num(w / k)));
    }
    if let Some(r0) = case.boundary.r0_m {
        s.push(format!("boundary.r0_m={}", num(r0 / k)));
    }
    Ok(s)
}

/// The case in `text` (after the `sets` overrides) refined by `k`, with every override that made
/// it (`sets` first, then those of [`refinement_sets`]): handing these to `blastsph run --set`
/// (or `RunOptions::sets`) gives the same case, and summary.json records them.
pub fn refine(text: &str, origin: &str, stem: Option<&str>, sets: &[String], k: f64) -> Result<(Case, Vec<String>)> {
    let base = case::parse(text, origin, sets, stem)?;
    let mut all = sets.to_vec();
    all.extend(refinement_sets(&base, k)?);
    let refined = case::parse(text, origin, &all, stem)?;
    Ok((refined, all))
}
