//! Crater, cavity and ejecta of a blast in soil (2D), measured from the soil's own particles.
//!
//! Definitions (docs/validation.md, "Crater and ejecta definitions"):
//! - the soil is the particles of the soil materials (`analysis.soil_materials`, default: every
//!   material with strength); Δs is the coarsest initial spacing of the soil's regions, so the
//!   measure does not depend on the spacing of any other material (a finer charge lattice);
//! - the ground surface is measured in vertical columns Δs apart, each gathering the soil
//!   particles within ±Δs of its centre: they are walked upward from the lowest to the first
//!   vertical gap larger than 2Δs that opens to the sky (particles above such a gap are ejecta,
//!   not ground); the surface is the highest particle within ±3Δs/4 of the column's centre no more
//!   than 2Δs above where the walk stopped (so a bowl's edge is not read at the rim beside it). A gap that is an enclosed void of the
//!   soil (a cavity: gas under an intact dome, or the charge's hole at t = 0) does not end the
//!   ground. "Enclosed" is decided on a raster of Δs cells, solid where a soil particle lies within
//!   Δs of the cell's centre: a void cell is open when the empty cells connect it to the raster's
//!   border, enclosed otherwise;
//! - the original ground surface s0(x) is the same measure at t = 0, except over a charge that
//!   sits in a pit of the ground (an explosive particle above the soil's top in that column at
//!   t = 0): there the ground level is interpolated linearly between the nearest columns on each
//!   side with no explosive above them;
//! - apparent crater depth = max over columns of s0 − s; diameter = width of the run of columns
//!   around the deepest one whose surface lies more than Δs/2 below the original surface; bowl
//!   width = the same where it lies more than half the depth below;
//! - the cavity (reported apart) = the largest enclosed void of the soil raster below the
//!   surface: its width, height and area;
//! - ejecta height = highest soil particle above the highest point of the original surface.
//!
//! A quantity that cannot be measured is not reported as a number: [`measure_xy`] returns the
//! reason (no soil particles, positions that are not finite after an unstable run, not 2D).

use crate::sim::Sim;
use serde::Serialize;

/// An enclosed void in the soil (a cavity).
#[derive(Debug, Clone, Default, Serialize)]
pub struct Cavity {
    /// Horizontal and vertical extent (m) and area (m²; per metre of depth, a cross-section).
    pub width_m: f64,
    pub height_m: f64,
    pub area_m2: f64,
    /// Centre of its bounding box (m).
    pub centre_m: [f64; 2],
    /// Depth of its top below the original surface above it (m).
    pub top_depth_m: f64,
}

/// A vertical section of a 3D crater through the charge's vertical axis: the crater as the 2D
/// measure reads it on the soil particles within one spacing of that plane (docs/validation.md,
/// "Crater and ejecta definitions").
#[derive(Debug, Clone, Default, Serialize)]
pub struct Section {
    /// Direction of the section's plane in the horizontal, degrees from +x towards +y.
    pub azimuth_deg: f64,
    /// Width of the crater along the section (m; 0 without a crater).
    pub diameter_m: f64,
    /// Deepest drop of the surface in the section (m).
    pub depth_m: f64,
    /// Where the deepest column lies along the section, from the axis (m, signed: + towards the
    /// azimuth).
    pub centre_m: f64,
    /// Why the section shows no crater, when it shows none.
    pub note: Option<String>,
}

#[derive(Debug, Clone, Default, Serialize)]
pub struct Crater {
    pub diameter_m: f64,
    pub depth_m: f64,
    /// Width of the bowl where the surface lies more than half the depth below the original (m).
    pub width_half_depth_m: f64,
    /// Horizontal position of the deepest column (m).
    pub centre_m: f64,
    pub ejecta_height_m: f64,
    /// Highest rise of the ground surface above the original (a mound over a contained charge).
    pub mound_height_m: f64,
    /// Column width Δs (m): the coarsest soil spacing.
    pub column_m: f64,
    /// The largest enclosed void of the soil, if any.
    pub cavity: Option<Cavity>,
    /// Why there is no apparent crater, when there is none.
    pub note: Option<String>,
    /// 3D: the crater in vertical sections through the charge's axis at 0°, 45°, 90° and 135°
    /// (a scene that is not symmetric about the axis shows it here); empty in 2D and RZ.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub sections: Vec<Section>,
    /// Column centres (m), original and current surface heights (m; NaN for an empty column).
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

/// Which materials are explosives (JWL).
pub fn explosive_mask(case: &crate::case::Case) -> Vec<bool> {
    case.materials.iter().map(|m| matches!(m.eos, crate::case::EosCfg::Jwl { .. })).collect()
}

/// Δs: the coarsest initial spacing of the regions of soil materials.
pub fn soil_spacing(case: &crate::case::Case) -> Option<f64> {
    let soil = soil_mask(case);
    case.regions
        .iter()
        .filter(|r| case.material_index(&r.material).is_some_and(|m| soil[m]))
        .map(|r| r.spacing_m)
        .fold(None, |a: Option<f64>, s| Some(a.map_or(s, |a| a.max(s))))
}

/// Soil occupancy on a raster of square cells: solid where a soil particle lies within one cell
/// size of the cell's centre; `open` marks the empty cells connected to the border.
struct Raster {
    x0: f64,
    y0: f64,
    ds: f64,
    nx: usize,
    ny: usize,
    solid: Vec<bool>,
    open: Vec<bool>,
}

impl Raster {
    fn new(xs: &[f64], ys: &[f64], ds: f64, xlim: (f64, f64), ylim: (f64, f64)) -> Raster {
        let x0 = xlim.0 - 2.0 * ds;
        let y0 = ylim.0 - 2.0 * ds;
        let nx = (((xlim.1 - xlim.0) / ds).ceil() as usize + 4).max(1);
        let ny = (((ylim.1 - ylim.0) / ds).ceil() as usize + 4).max(1);
        let mut solid = vec![false; nx * ny];
        for (x, y) in xs.iter().zip(ys) {
            let (u, v) = ((x - x0) / ds, (y - y0) / ds);
            if u < -1.0 || v < -1.0 || u > nx as f64 + 1.0 || v > ny as f64 + 1.0 {
                continue;
            }
            let (iu, iv) = (u.floor() as i64, v.floor() as i64);
            for dj in -1..=1 {
                for di in -1..=1 {
                    let (i, j) = (iu + di, iv + dj);
                    if i < 0 || j < 0 || i >= nx as i64 || j >= ny as i64 {
                        continue;
                    }
                    let (cx, cy) = (x0 + (i as f64 + 0.5) * ds, y0 + (j as f64 + 0.5) * ds);
                    if (cx - x).powi(2) + (cy - y).powi(2) <= ds * ds {
                        solid[i as usize + nx * j as usize] = true;
                    }
                }
            }
        }
        // flood the empty cells from the border (4-connected)
        let mut open = vec![false; nx * ny];
        let mut stack = Vec::new();
        for i in 0..nx {
            for j in [0, ny - 1] {
                stack.push((i, j));
            }
        }
        for j in 0..ny {
            for i in [0, nx - 1] {
                stack.push((i, j));
            }
        }
        while let Some((i, j)) = stack.pop() {
            let k = i + nx * j;
            if solid[k] || open[k] {
                continue;
            }
            open[k] = true;
            if i > 0 {
                stack.push((i - 1, j));
            }
            if i + 1 < nx {
                stack.push((i + 1, j));
            }
            if j > 0 {
                stack.push((i, j - 1));
            }
            if j + 1 < ny {
                stack.push((i, j + 1));
            }
        }
        Raster { x0, y0, ds, nx, ny, solid, open }
    }

    fn cell(&self, x: f64, y: f64) -> Option<usize> {
        let (u, v) = ((x - self.x0) / self.ds, (y - self.y0) / self.ds);
        if u < 0.0 || v < 0.0 || u >= self.nx as f64 || v >= self.ny as f64 {
            return None;
        }
        Some(u as usize + self.nx * v as usize)
    }

    /// Is the vertical gap (x, ya..yb) an enclosed void: no open cell along it, and some empty?
    fn enclosed_gap(&self, x: f64, ya: f64, yb: f64) -> bool {
        let mut any_void = false;
        let mut y = ya + self.ds;
        while y < yb - 0.5 * self.ds {
            match self.cell(x, y) {
                None => return false,
                Some(k) if self.open[k] => return false,
                Some(k) if !self.solid[k] => any_void = true,
                _ => {}
            }
            y += 0.5 * self.ds;
        }
        any_void
    }

    /// The largest enclosed void (4-connected component of empty, not open cells).
    fn largest_void(&self) -> Option<(usize, [f64; 4])> {
        let mut seen = vec![false; self.nx * self.ny];
        let mut best: Option<(usize, [f64; 4])> = None;
        for k0 in 0..self.nx * self.ny {
            if seen[k0] || self.solid[k0] || self.open[k0] {
                continue;
            }
            let mut count = 0;
            let (mut ilo, mut ihi, mut jlo, mut jhi) = (usize::MAX, 0, usize::MAX, 0);
            let mut stack = vec![k0];
            while let Some(k) = stack.pop() {
                if seen[k] || self.solid[k] || self.open[k] {
                    continue;
                }
                seen[k] = true;
                count += 1;
                let (i, j) = (k % self.nx, k / self.nx);
                ilo = ilo.min(i);
                ihi = ihi.max(i);
                jlo = jlo.min(j);
                jhi = jhi.max(j);
                if i > 0 {
                    stack.push(k - 1);
                }
                if i + 1 < self.nx {
                    stack.push(k + 1);
                }
                if j > 0 {
                    stack.push(k - self.nx);
                }
                if j + 1 < self.ny {
                    stack.push(k + self.nx);
                }
            }
            let bb = [
                self.x0 + ilo as f64 * self.ds,
                self.x0 + (ihi + 1) as f64 * self.ds,
                self.y0 + jlo as f64 * self.ds,
                self.y0 + (jhi + 1) as f64 * self.ds,
            ];
            if best.as_ref().is_none_or(|b| count > b.0) {
                best = Some((count, bb));
            }
        }
        best
    }
}

/// Ground surface per column from positions (x, y) of the soil particles. Column k is centred at
/// x0 + (k + 1/2) ds and gathers the particles within ±ds of its centre (two spacings wide, so a
/// smooth lateral shift of the lattice cannot empty it); the particles are walked upward from the
/// lowest up to the first vertical gap larger than 2 ds that is not an enclosed void of `raster`;
/// the surface is the highest particle within ±3ds/4 of the centre that lies at most 2 ds above
/// the walk's top (the band's top when there is none), NaN for an empty column.
fn surface(xs: &[f64], ys: &[f64], x0: f64, ds: f64, ncol: usize, raster: &Raster) -> Vec<f64> {
    let mut cols: Vec<Vec<(f64, f64)>> = vec![Vec::new(); ncol];
    for (x, y) in xs.iter().zip(ys) {
        let u = (x - x0) / ds - 0.5;
        let (a, b) = ((u - 1.0).ceil(), (u + 1.0).floor());
        let mut k = a.max(0.0);
        while k <= b && (k as usize) < ncol {
            cols[k as usize].push((*y, *x));
            k += 1.0;
        }
    }
    cols.into_iter()
        .enumerate()
        .map(|(k, mut c)| {
            if c.is_empty() {
                return f64::NAN;
            }
            let xc = x0 + (k as f64 + 0.5) * ds;
            c.sort_by(|a, b| a.0.total_cmp(&b.0));
            // walk the two-spacing band up to the first gap open to the sky
            let mut top = 0;
            for q in 1..c.len() {
                if c[q].0 - c[top].0 > 2.0 * ds && !raster.enclosed_gap(xc, c[top].0, c[q].0) {
                    break;
                }
                top = q;
            }
            // the height is read from the particles within ±3ds/4 of the column's centre (the
            // band's ±ds would lift a crater's edge to the rim beside it; ±ds/2 finds no
            // particle near the top of a column whose own particles moved sideways, and then
            // reads a hole one or two spacings deep), up to 2 ds above the band's top (the gap
            // rule), else from the band
            let lim = c[top].0 + 2.0 * ds;
            c.iter()
                .filter(|(y, x)| *y <= lim && (x - xc).abs() <= 0.75 * ds)
                .map(|p| p.0)
                .fold(None, |a: Option<f64>, y| Some(a.map_or(y, |a| a.max(y))))
                .unwrap_or(c[top].0)
        })
        .collect()
}

/// The particles a crater is measured from: soil at t = 0 and now, explosive at t = 0.
#[derive(Debug, Clone, Default)]
pub struct CraterInput {
    pub soil0: (Vec<f64>, Vec<f64>),
    pub soil1: (Vec<f64>, Vec<f64>),
    pub charge0: (Vec<f64>, Vec<f64>),
}

impl CraterInput {
    /// An axisymmetric (RZ) section, x = r ≥ 0, completed by its mirror image x → −x: the plane
    /// section through the axis, whose crater width is the crater's diameter (the plane measure
    /// of the half section alone would give its radius, read as a diameter).
    pub fn through_the_axis(self) -> CraterInput {
        let full = |(x, y): (Vec<f64>, Vec<f64>)| {
            let (mut fx, mut fy) = (x.clone(), y.clone());
            fx.extend(x.iter().map(|r| -r));
            fy.extend(y);
            (fx, fy)
        };
        CraterInput { soil0: full(self.soil0), soil1: full(self.soil1), charge0: full(self.charge0) }
    }
}

/// The vertical axis (x, y) a 3D crater is measured about (z up): the detonation point's, else
/// the centroid of the explosive's initial positions `charge_xy`.
pub fn axis_3d(case: &crate::case::Case, charge_xy: &[(f64, f64)]) -> Result<(f64, f64), String> {
    if let Some(p) = case.detonation.as_ref().and_then(|d| d.point_m.as_ref()) {
        return Ok((p[0], p[1]));
    }
    if charge_xy.is_empty() {
        return Err("a 3D crater is measured about the charge's vertical axis: the case has no explosive and no detonation point".into());
    }
    let n = charge_xy.len() as f64;
    Ok((charge_xy.iter().map(|p| p.0).sum::<f64>() / n, charge_xy.iter().map(|p| p.1).sum::<f64>() / n))
}

/// A 3D point as (r, z) about the vertical axis `ax` (the half plane a 3D crater is measured on).
pub fn about_axis(ax: (f64, f64), x: f64, y: f64, z: f64) -> (f64, f64) {
    ((x - ax.0).hypot(y - ax.1), z)
}

/// The symmetry planes of a 3D case that a crater about the vertical axis `ax` is completed
/// across: its `mirror` walls that are vertical, axis-aligned (x = c or y = c) and pass within
/// `ds` of the axis, as (0 for x, 1 for y; c in m). A mirror wall away from the axis is a rigid
/// free-slip wall beside the crater, not a plane the scene is the half of.
pub fn mirror_planes(case: &crate::case::Case, ax: (f64, f64), ds: f64) -> Vec<(usize, f64)> {
    if case.dim != 3 {
        return Vec::new();
    }
    case.walls
        .iter()
        .filter(|w| w.kind == crate::case::WallKind::Mirror && w.edge_m.is_none())
        .filter_map(|w| {
            (0..2).find(|&k| w.from_m.get(k).is_some_and(|a| Some(a) == w.to_m.get(k))).map(|k| (k, w.from_m[k]))
        })
        .filter(|&(k, c)| (c - if k == 0 { ax.0 } else { ax.1 }).abs() <= ds)
        .collect()
}

/// The crater of a 3D run in vertical sections through the charge's vertical axis `ax` at 0°,
/// 45°, 90° and 135°, from the soil's initial and current positions and the explosive's initial
/// ones (x, y, z; z up): the points are first completed by their images in the symmetry planes
/// `mirrors` (a quarter with the planes x = 0 and y = 0 becomes the whole scene), then each
/// section takes the points within `ds` of its plane, at their signed distance from the axis
/// along it, and is measured as a plane crater ([`measure_xy`]) with columns `ds` wide.
pub fn sections_3d(
    ax: (f64, f64),
    ds: f64,
    mirrors: &[(usize, f64)],
    soil0: &[[f64; 3]],
    soil1: &[[f64; 3]],
    charge0: &[[f64; 3]],
) -> Vec<Section> {
    let complete = |pts: &[[f64; 3]]| -> Vec<[f64; 3]> {
        let mut all = pts.to_vec();
        for &(k, c) in mirrors {
            let images: Vec<[f64; 3]> = all
                .iter()
                .map(|p| {
                    let mut q = *p;
                    q[k] = 2.0 * c - p[k];
                    q
                })
                .collect();
            all.extend(images);
        }
        all
    };
    let (a0, a1, c0) = (complete(soil0), complete(soil1), complete(charge0));
    [0.0f64, 45.0, 90.0, 135.0]
        .iter()
        .map(|&deg| {
            let (sn, cs) = deg.to_radians().sin_cos();
            let cut = |pts: &[[f64; 3]]| -> (Vec<f64>, Vec<f64>) {
                pts.iter()
                    .filter(|p| (-(p[0] - ax.0) * sn + (p[1] - ax.1) * cs).abs() <= ds)
                    .map(|p| ((p[0] - ax.0) * cs + (p[1] - ax.1) * sn, p[2]))
                    .unzip()
            };
            let inp = CraterInput { soil0: cut(&a0), soil1: cut(&a1), charge0: cut(&c0) };
            match measure_xy(&inp, ds) {
                Ok(c) => Section {
                    azimuth_deg: deg,
                    diameter_m: c.diameter_m,
                    depth_m: c.depth_m,
                    centre_m: c.centre_m,
                    note: c.note,
                },
                Err(why) => Section { azimuth_deg: deg, note: Some(why), ..Default::default() },
            }
        })
        .collect()
}

/// Measures the crater of a run from the soil particles' initial and current positions: in 2D
/// plane directly; axisymmetric runs on their section through the axis
/// ([`CraterInput::through_the_axis`]); 3D runs (z up) as a crater of revolution about the
/// charge's vertical axis ([`axis_3d`]): every particle taken to (r, z) about it, all azimuths
/// together (a column's top is the highest particle at that r in any direction), then as RZ.
pub fn measure(sim: &Sim) -> Result<Crater, String> {
    let d = sim.cfg.dim;
    if d == 1 {
        return Err("the crater is measured in 2D and 3D only (this case has dim = 1)".to_string());
    }
    let soil = soil_mask(&sim.case);
    let expl = explosive_mask(&sim.case);
    let ds = soil_spacing(&sim.case).ok_or("no region of a soil material (analysis.soil_materials)")?;
    let n = sim.p.nreal;
    let ax = if d == 3 {
        let ch: Vec<(f64, f64)> = (0..n)
            .filter(|&i| expl[sim.p.mat[i] as usize])
            .map(|i| (sim.x_init[3 * i], sim.x_init[3 * i + 1]))
            .collect();
        axis_3d(&sim.case, &ch)?
    } else {
        (0.0, 0.0)
    };
    let pt = |x: &[f64], i: usize| -> (f64, f64) {
        if d == 3 { about_axis(ax, x[3 * i], x[3 * i + 1], x[3 * i + 2]) } else { (x[2 * i], x[2 * i + 1]) }
    };
    let mut inp = CraterInput::default();
    for i in 0..n {
        let m = sim.p.mat[i] as usize;
        if soil[m] {
            let (a, b) = (pt(&sim.x_init, i), pt(&sim.p.x, i));
            inp.soil0.0.push(a.0);
            inp.soil0.1.push(a.1);
            inp.soil1.0.push(b.0);
            inp.soil1.1.push(b.1);
        } else if expl[m] {
            let a = pt(&sim.x_init, i);
            inp.charge0.0.push(a.0);
            inp.charge0.1.push(a.1);
        }
    }
    if sim.case.axisymmetric() || d == 3 {
        inp = inp.through_the_axis();
    }
    let mut c = measure_xy(&inp, ds)?;
    if d == 3 {
        let p3 = |x: &[f64], i: usize| [x[3 * i], x[3 * i + 1], x[3 * i + 2]];
        let is = |i: &usize, mask: &[bool]| mask[sim.p.mat[*i] as usize];
        let soil_i: Vec<usize> = (0..n).filter(|i| is(i, &soil)).collect();
        let s0: Vec<[f64; 3]> = soil_i.iter().map(|&i| p3(&sim.x_init, i)).collect();
        let s1: Vec<[f64; 3]> = soil_i.iter().map(|&i| p3(&sim.p.x, i)).collect();
        let c0: Vec<[f64; 3]> = (0..n).filter(|i| is(i, &expl)).map(|i| p3(&sim.x_init, i)).collect();
        c.sections = sections_3d(ax, ds, &mirror_planes(&sim.case, ax, ds), &s0, &s1, &c0);
    }
    Ok(c)
}

/// The crater from `inp` with columns `ds` wide (the coarsest soil spacing).
pub fn measure_xy(inp: &CraterInput, ds: f64) -> Result<Crater, String> {
    let (x0s, y0s) = (&inp.soil0.0, &inp.soil0.1);
    let (x1s, y1s) = (&inp.soil1.0, &inp.soil1.1);
    if x0s.is_empty() {
        return Err("no soil particles (analysis.soil_materials names no material with particles)".into());
    }
    let bad = x1s.iter().chain(y1s).filter(|v| !v.is_finite()).count();
    if bad > 0 {
        return Err(format!(
            "{} soil coordinates are not finite numbers (the run went unstable): no surface can be traced",
            bad
        ));
    }
    if !(ds.is_finite() && ds > 0.0) {
        return Err(format!("the soil spacing {ds} m is not a positive number"));
    }
    let lo = x0s.iter().cloned().fold(f64::INFINITY, f64::min) - 0.5 * ds;
    let hi = x0s.iter().cloned().fold(f64::NEG_INFINITY, f64::max) + 0.5 * ds;
    let ncol = ((hi - lo) / ds).round().max(1.0) as usize;
    let ymin0 = y0s.iter().cloned().fold(f64::INFINITY, f64::min);
    let ymax0 = y0s.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let ymin1 = y1s.iter().cloned().fold(f64::INFINITY, f64::min);
    // the raster covers the ground and what lies just above it (ejecta higher up are ejecta)
    let ytop = ymax0 + 0.5 * (hi - lo);
    let r0 = Raster::new(x0s, y0s, ds, (lo, hi), (ymin0.min(ymin1), ytop));
    let r1 = Raster::new(x1s, y1s, ds, (lo, hi), (ymin0.min(ymin1), ytop));
    let mut s0 = surface(x0s, y0s, lo, ds, ncol, &r0);
    let s1 = surface(x1s, y1s, lo, ds, ncol, &r1);
    // a charge in a pit of the ground: the ground level over it is interpolated
    let covered: Vec<bool> = (0..ncol)
        .map(|k| {
            let xc = lo + (k as f64 + 0.5) * ds;
            s0[k].is_finite()
                && inp.charge0.0.iter().zip(&inp.charge0.1).any(|(x, y)| (x - xc).abs() < 0.5 * ds && *y > s0[k])
        })
        .collect();
    if covered.iter().any(|c| *c) {
        let base = s0.clone();
        for k in 0..ncol {
            if !covered[k] {
                continue;
            }
            let left = (0..k).rev().find(|&a| !covered[a] && base[a].is_finite());
            let right = (k + 1..ncol).find(|&b| !covered[b] && base[b].is_finite());
            s0[k] = match (left, right) {
                (Some(a), Some(b)) => base[a] + (base[b] - base[a]) * (k - a) as f64 / (b - a) as f64,
                (Some(a), None) => base[a],
                (None, Some(b)) => base[b],
                (None, None) => base[k],
            };
        }
    }
    let drop: Vec<f64> = s0
        .iter()
        .zip(&s1)
        .map(|(a, b)| {
            if a.is_finite() && b.is_finite() {
                a - b
            } else if a.is_finite() {
                *a - ymin0
            } else {
                0.0
            }
        })
        .collect();
    let (kmax, depth) =
        drop.iter().enumerate().fold((0, f64::NEG_INFINITY), |acc, (k, d)| if *d > acc.1 { (k, *d) } else { acc });
    let run = |lim: f64| -> f64 {
        let (mut a, mut b) = (kmax, kmax);
        while a > 0 && drop[a - 1] > lim {
            a -= 1;
        }
        while b + 1 < ncol && drop[b + 1] > lim {
            b += 1;
        }
        (b - a + 1) as f64 * ds
    };
    let crater = depth > 0.5 * ds;
    let (diameter, half) = if crater { (run(0.5 * ds), run(0.5 * depth)) } else { (0.0, 0.0) };
    let smax = s0.iter().cloned().filter(|v| v.is_finite()).fold(f64::NEG_INFINITY, f64::max);
    let ejecta = y1s.iter().cloned().fold(f64::NEG_INFINITY, f64::max) - smax;
    let mound = drop.iter().cloned().map(|d| -d).fold(0.0, f64::max);
    let cavity = r1.largest_void().filter(|(cells, _)| *cells >= 4).map(|(cells, bb)| {
        let xc = 0.5 * (bb[0] + bb[1]);
        let k = (((xc - lo) / ds).floor().max(0.0) as usize).min(ncol - 1);
        Cavity {
            width_m: bb[1] - bb[0],
            height_m: bb[3] - bb[2],
            area_m2: cells as f64 * ds * ds,
            centre_m: [xc, 0.5 * (bb[2] + bb[3])],
            top_depth_m: if s0[k].is_finite() { s0[k] - bb[3] } else { f64::NAN },
        }
    });
    let note = if crater {
        None
    } else {
        Some(match &cavity {
            Some(c) => format!(
                "no apparent crater: the ground surface has not dropped by more than half a spacing ({:.1} cm); \
                 the charge is contained in a cavity {:.1} cm wide and {:.1} cm tall under ground that rose up to {:.1} cm",
                50.0 * ds,
                100.0 * c.width_m,
                100.0 * c.height_m,
                100.0 * mound
            ),
            None => format!(
                "no apparent crater: the ground surface has not dropped by more than half a spacing ({:.1} cm)",
                50.0 * ds
            ),
        })
    };
    Ok(Crater {
        diameter_m: diameter,
        depth_m: if crater { depth } else { depth.max(0.0) },
        width_half_depth_m: half,
        centre_m: lo + (kmax as f64 + 0.5) * ds,
        ejecta_height_m: ejecta.max(0.0),
        mound_height_m: mound,
        column_m: ds,
        cavity: cavity.map(|mut c| {
            if !c.top_depth_m.is_finite() {
                c.top_depth_m = 0.0;
            }
            c
        }),
        note,
        sections: Vec::new(),
        columns_m: (0..ncol).map(|k| lo + (k as f64 + 0.5) * ds).collect(),
        surface0_m: s0,
        surface_m: s1,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Soil on a lattice of spacing `ds` over [0, w] × [0, hgt], less the points `cut` removes.
    fn lattice(ds: f64, w: f64, hgt: f64, cut: &dyn Fn(f64, f64) -> bool) -> (Vec<f64>, Vec<f64>) {
        let (mut xs, mut ys) = (Vec::new(), Vec::new());
        let (nx, ny) = ((w / ds).round() as usize, (hgt / ds).round() as usize);
        for j in 0..ny {
            for i in 0..nx {
                let (x, y) = ((i as f64 + 0.5) * ds, (j as f64 + 0.5) * ds);
                if !cut(x, y) {
                    xs.push(x);
                    ys.push(y);
                }
            }
        }
        (xs, ys)
    }

    #[test]
    fn a_bowl_is_measured_against_the_ground_over_the_charge_pit() {
        let ds = 0.01;
        // t = 0: a 6 cm pit in the top of the ground, holding a charge on a 0.5 cm lattice
        let pit = |x: f64, y: f64| (x - 0.5).abs() < 0.03 && y > 0.94;
        let soil0 = lattice(ds, 1.0, 1.0, &pit);
        let mut charge0 = (Vec::new(), Vec::new());
        for j in 0..12 {
            for i in 0..12 {
                charge0.0.push(0.47 + 0.0025 + 0.005 * i as f64);
                charge0.1.push(0.94 + 0.0025 + 0.005 * j as f64);
            }
        }
        // later: a bowl 20 cm wide and 10 cm deep below the original ground (y = 1)
        let bowl = |x: f64, y: f64| (x - 0.5).abs() < 0.1 && y > 0.9;
        let soil1 = lattice(ds, 1.0, 1.0, &bowl);
        // the same particles must be matched one to one: keep the counts comparable by measuring
        // each state against its own t = 0 lattice (the measure only uses positions)
        let inp = CraterInput { soil0: soil0.clone(), soil1, charge0 };
        let c = measure_xy(&inp, ds).unwrap();
        assert!((c.depth_m - 0.10).abs() < 1e-9, "depth {} against the ground, not the pit floor", c.depth_m);
        assert!((c.diameter_m - 0.20).abs() < 1e-9, "diameter {}", c.diameter_m);
        assert!(c.note.is_none());
        // the original ground over the pit is the ground's level beside it
        let k = c.columns_m.iter().position(|x| (x - 0.505).abs() < 1e-9).unwrap();
        assert!((c.surface0_m[k] - 0.995).abs() < 1e-9, "{}", c.surface0_m[k]);
    }

    #[test]
    fn a_3d_bowl_is_measured_about_its_vertical_axis() {
        // a quarter block 0.3 x 0.3 x 0.5 m (z up, surface z = 0.5) with a hemispherical bowl of
        // radius 10 cm about the axis x = y = 0: diameter 20 cm, depth 10 cm, read on (r, z)
        let ds = 0.01;
        let n = 30;
        let (mut s0, mut s1) = ((Vec::new(), Vec::new()), (Vec::new(), Vec::new()));
        for k in 0..50 {
            for j in 0..n {
                for i in 0..n {
                    let (x, y, z) = ((i as f64 + 0.5) * ds, (j as f64 + 0.5) * ds, (k as f64 + 0.5) * ds);
                    let (r, h) = about_axis((0.0, 0.0), x, y, z);
                    s0.0.push(r);
                    s0.1.push(h);
                    if (r * r + (z - 0.5) * (z - 0.5)).sqrt() >= 0.1 {
                        s1.0.push(r);
                        s1.1.push(h);
                    }
                }
            }
        }
        let inp = CraterInput { soil0: s0, soil1: s1, charge0: (Vec::new(), Vec::new()) }.through_the_axis();
        let c = measure_xy(&inp, ds).unwrap();
        assert!((c.diameter_m - 0.20).abs() <= 2.0 * ds, "diameter {}", c.diameter_m);
        assert!((c.depth_m - 0.10).abs() <= ds, "depth {}", c.depth_m);
    }

    #[test]
    fn a_3d_crater_that_is_not_round_is_measured_in_sections_and_a_quarter_is_completed() {
        // an elliptic bowl about the axis x = y = 0 (z up, surface z = 0.4): semi-axes 15 cm
        // along x and 8 cm along y, 10 cm deep; the whole block, and its quarter x, y > 0 with
        // the planes x = 0 and y = 0 as symmetry planes
        let ds = 0.01;
        let inside = |x: f64, y: f64, z: f64| (x / 0.15).powi(2) + (y / 0.08).powi(2) + ((z - 0.4) / 0.1).powi(2) < 1.0;
        let block = |lo: i32| {
            let (mut s0, mut s1) = (Vec::new(), Vec::new());
            for k in 0..40 {
                for j in lo..30 {
                    for i in lo..30 {
                        let p = [(i as f64 + 0.5) * ds, (j as f64 + 0.5) * ds, (k as f64 + 0.5) * ds];
                        s0.push(p);
                        if !inside(p[0], p[1], p[2]) {
                            s1.push(p);
                        }
                    }
                }
            }
            (s0, s1)
        };
        let (w0, w1) = block(-30);
        let whole = sections_3d((0.0, 0.0), ds, &[], &w0, &w1, &[]);
        let (q0, q1) = block(0);
        let quarter = sections_3d((0.0, 0.0), ds, &[(0, 0.0), (1, 0.0)], &q0, &q1, &[]);
        let alone = sections_3d((0.0, 0.0), ds, &[], &q0, &q1, &[]);
        for (w, q) in whole.iter().zip(&quarter) {
            assert!((w.diameter_m - q.diameter_m).abs() < 1e-9 && (w.depth_m - q.depth_m).abs() < 1e-9, "{w:?} {q:?}");
        }
        let by = |deg: f64| whole.iter().find(|s| s.azimuth_deg == deg).unwrap().clone();
        assert!((by(0.0).diameter_m - 0.30).abs() <= 2.0 * ds, "along x: {:?}", by(0.0));
        assert!((by(90.0).diameter_m - 0.16).abs() <= 2.0 * ds, "along y: {:?}", by(90.0));
        let diag = 2.0 / ((1.0 / 0.15f64).powi(2) + (1.0 / 0.08f64).powi(2)).sqrt() * 2f64.sqrt();
        assert!((by(45.0).diameter_m - diag).abs() <= 2.0 * ds, "diagonal {diag}: {:?}", by(45.0));
        assert!(whole.iter().all(|s| (s.depth_m - 0.10).abs() <= ds), "{whole:?}");
        // the quarter without its images reads half a crater along each plane
        assert!(alone[0].diameter_m < 0.17, "{:?}", alone[0]);
    }

    #[test]
    fn an_axisymmetric_section_is_measured_through_the_axis() {
        // the half section r in [0, 0.5] of a bowl of radius 10 cm, 10 cm deep: diameter 20 cm
        let ds = 0.01;
        let soil0 = lattice(ds, 0.5, 1.0, &|_, _| false);
        let soil1 = lattice(ds, 0.5, 1.0, &|r, y| r < 0.1 && y > 0.9);
        let half = CraterInput { soil0, soil1, charge0: (Vec::new(), Vec::new()) };
        let c = measure_xy(&half.clone().through_the_axis(), ds).unwrap();
        assert!((c.diameter_m - 0.20).abs() < 1e-9, "diameter {}", c.diameter_m);
        assert!((c.depth_m - 0.10).abs() < 1e-9, "depth {}", c.depth_m);
        // the half section alone reads its radius as a width
        let h = measure_xy(&half, ds).unwrap();
        assert!(h.diameter_m < 0.11, "half section {}", h.diameter_m);
    }

    #[test]
    fn a_cavity_under_an_intact_dome_is_no_crater() {
        let ds = 0.01;
        // a charge's hole 3 cm below the surface at t = 0; later a bigger cavity, and the dome
        // over it raised by 2 cm
        let hole = |x: f64, y: f64| (x - 0.35).abs() < 0.03 && (y - 0.58).abs() < 0.01;
        let soil0 = lattice(ds, 0.7, 0.62, &hole);
        let gas = |x: f64, y: f64| (x - 0.35).abs() < 0.06 && (y - 0.58).abs() < 0.03;
        let (x1, mut y1) = lattice(ds, 0.7, 0.62, &gas);
        for k in 0..x1.len() {
            if (x1[k] - 0.35).abs() < 0.06 && y1[k] > 0.61 {
                y1[k] += 0.02;
            }
        }
        let c = measure_xy(&CraterInput { soil0, soil1: (x1, y1), charge0: (Vec::new(), Vec::new()) }, ds).unwrap();
        assert_eq!(c.diameter_m, 0.0, "{c:?}");
        assert!(c.note.as_deref().unwrap().contains("contained"), "{:?}", c.note);
        let cav = c.cavity.expect("the cavity");
        assert!(cav.width_m >= 0.08 && cav.height_m >= 0.03, "{cav:?}");
        assert!(c.mound_height_m > 0.015, "{}", c.mound_height_m);
    }

    #[test]
    fn positions_that_are_not_numbers_give_a_reason() {
        let (x0, y0) = lattice(0.01, 0.2, 0.2, &|_, _| false);
        let mut y1 = y0.clone();
        y1[7] = f64::NAN;
        let e =
            measure_xy(&CraterInput { soil0: (x0.clone(), y0), soil1: (x0, y1), charge0: Default::default() }, 0.01)
                .unwrap_err();
        assert!(e.contains("not finite") && e.contains("unstable"), "{e}");
        let e = measure_xy(&CraterInput::default(), 0.01).unwrap_err();
        assert!(e.contains("no soil particles"), "{e}");
    }
}
