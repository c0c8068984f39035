//! Crater and ejecta of a blast in soil (2D).
//!
//! Definitions (docs/validation.md):
//! - the soil is the particles of the soil materials (`analysis.soil_materials`, default: every
//!   material with strength);
//! - the ground surface is measured in vertical columns Δx apart (Δx the finest spacing), each
//!   gathering the soil particles within ±Δx of its centre: they are walked upward from the
//!   lowest; the surface is the highest particle reached before a vertical gap larger than 2Δx
//!   (particles above such a gap are ejecta, not ground). The original surface s0(x) is the same
//!   measure at t = 0;
//! - crater depth = max over columns of s0 − s;
//! - crater diameter = width of the run of columns around the deepest one whose surface lies
//!   more than Δx/2 below the original surface (the apparent crater at the original ground level);
//! - bowl width = the same run where the surface lies more than half the depth below (it tells a
//!   bowl from a broad settlement of a soft soil);
//! - ejecta height = highest soil particle above the original surface (m).

use crate::sim::Sim;
use serde::Serialize;

#[derive(Debug, Clone, Default, Serialize)]
pub struct Crater {
    pub diameter_m: f64,
    pub depth_m: f64,
    /// Width of the bowl where the surface lies more than half the depth below the original (m).
    pub width_half_depth_m: f64,
    /// Horizontal position of the deepest column (m).
    pub centre_m: f64,
    pub ejecta_height_m: f64,
    /// Column centres (m), original and final surface heights (m).
    #[serde(skip)]
    pub columns_m: Vec<f64>,
    #[serde(skip)]
    pub surface0_m: Vec<f64>,
    #[serde(skip)]
    pub surface_m: Vec<f64>,
}

/// Which materials count as soil (per material index).
pub fn soil_mask(case: &crate::case::Case) -> Vec<bool> {
    match &case.analysis.soil_materials {
        Some(list) => case.materials.iter().map(|m| list.contains(&m.name)).collect(),
        None => case.materials.iter().map(|m| m.strength.is_some()).collect(),
    }
}

/// Ground surface per column from positions (x, y) of the soil particles. Column k is centred at
/// x0 + (k + 1/2) dx and gathers the particles within ±dx of its centre (two spacings wide, so a
/// smooth lateral shift of the lattice cannot empty it); the particles are walked upward from the
/// lowest and the surface is the last one before a vertical gap larger than 2 dx.
pub fn surface(xs: &[f64], ys: &[f64], x0: f64, dx: f64, ncol: usize) -> Vec<f64> {
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); ncol];
    for (x, y) in xs.iter().zip(ys) {
        let u = (x - x0) / dx - 0.5;
        let (a, b) = ((u - 1.0).ceil(), (u + 1.0).floor());
        let mut k = a.max(0.0);
        while k <= b && (k as usize) < ncol {
            cols[k as usize].push(*y);
            k += 1.0;
        }
    }
    cols.into_iter()
        .map(|mut c| {
            if c.is_empty() {
                return f64::NAN;
            }
            c.sort_by(|a, b| a.total_cmp(b));
            let mut top = c[0];
            for y in &c[1..] {
                if *y - top > 2.0 * dx {
                    break;
                }
                top = *y;
            }
            top
        })
        .collect()
}

/// Measures the crater of a 2D run from the soil particles' initial and current positions.
pub fn measure(sim: &Sim) -> Crater {
    if sim.cfg.dim != 2 {
        return Crater::default();
    }
    let soil = soil_mask(&sim.case);
    let n = sim.p.nreal;
    let pick = |x: &[f64]| -> (Vec<f64>, Vec<f64>) {
        let mut xs = Vec::new();
        let mut ys = Vec::new();
        for i in 0..n {
            if soil[sim.p.mat[i] as usize] {
                xs.push(x[2 * i]);
                ys.push(x[2 * i + 1]);
            }
        }
        (xs, ys)
    };
    let (x0s, y0s) = pick(&sim.x_init);
    let (x1s, y1s) = pick(&sim.p.x);
    measure_xy(&x0s, &y0s, &x1s, &y1s, sim.cfg.dx_min)
}

/// The crater from soil positions at t = 0 (`x0s`, `y0s`) and now (`x1s`, `y1s`); `dx` is the
/// column width (the finest initial spacing).
pub fn measure_xy(x0s: &[f64], y0s: &[f64], x1s: &[f64], y1s: &[f64], dx: f64) -> Crater {
    if x0s.is_empty() {
        return Crater::default();
    }
    let lo = x0s.iter().cloned().fold(f64::INFINITY, f64::min) - 0.5 * dx;
    let hi = x0s.iter().cloned().fold(f64::NEG_INFINITY, f64::max) + 0.5 * dx;
    let ncol = ((hi - lo) / dx).round().max(1.0) as usize;
    let s0 = surface(x0s, y0s, lo, dx, ncol);
    let s1 = surface(x1s, y1s, lo, dx, ncol);
    let drop: Vec<f64> = s0
        .iter()
        .zip(&s1)
        .map(|(a, b)| {
            if a.is_finite() && b.is_finite() {
                a - b
            } else if a.is_finite() {
                *a
            } else {
                0.0
            }
        })
        .collect();
    let (kmax, depth) =
        drop.iter().enumerate().fold((0, f64::NEG_INFINITY), |acc, (k, d)| if *d > acc.1 { (k, *d) } else { acc });
    let mut diameter = 0.0;
    if depth > 0.5 * dx {
        let mut a = kmax;
        while a > 0 && drop[a - 1] > 0.5 * dx {
            a -= 1;
        }
        let mut b = kmax;
        while b + 1 < ncol && drop[b + 1] > 0.5 * dx {
            b += 1;
        }
        diameter = (b - a + 1) as f64 * dx;
    }
    let mut half = 0.0;
    if depth > 0.5 * dx {
        let lim = 0.5 * depth;
        let (mut a, mut b) = (kmax, kmax);
        while a > 0 && drop[a - 1] > lim {
            a -= 1;
        }
        while b + 1 < ncol && drop[b + 1] > lim {
            b += 1;
        }
        half = (b - a + 1) as f64 * dx;
    }
    let smax = s0.iter().cloned().filter(|v| v.is_finite()).fold(f64::NEG_INFINITY, f64::max);
    let ejecta = y1s.iter().cloned().fold(f64::NEG_INFINITY, f64::max) - smax;
    Crater {
        diameter_m: diameter,
        depth_m: depth.max(0.0),
        width_half_depth_m: half,
        centre_m: lo + (kmax as f64 + 0.5) * dx,
        ejecta_height_m: ejecta.max(0.0),
        columns_m: (0..ncol).map(|k| lo + (k as f64 + 0.5) * dx).collect(),
        surface0_m: s0,
        surface_m: s1,
    }
}
