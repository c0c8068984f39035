//! Crater, cavity and ejecta of a blast in soil (2D, RZ, 3D), measured from the soil's own particles.
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
//!   border, enclosed otherwise; the raster's margins below the soil and beside it below the
//!   original ground's top are solid (the ground goes on beyond the box's walls). A gap the
//!   raster sees as solid all along ends the walk only where most of the column's particles lie
//!   below it (lifted particles over the ground), not above it (a crack low in the soil);
//! - the original ground surface s0(x) is the same measure at t = 0, except over a charge that
//!   sits in a pit of the ground (an explosive particle above the soil's top in that column at
//!   t = 0, within ±Δs of its centre as its soil is gathered): there the ground level is
//!   interpolated linearly between the nearest columns on each side with no explosive above them;
//! - apparent crater depth = max over columns of s0 − s; diameter = width of the run of columns
//!   around the deepest one whose surface lies more than Δs/2 below the original surface; bowl
//!   width = the same where it lies more than half the depth below;
//! - the cavity (reported apart) = the largest enclosed void of the soil raster below the
//!   surface: its width, height and area;
//! - ejecta height = highest soil particle above the highest point of the original surface;
//! - 3D: the crater also in vertical sections through the charge's axis (`sections_3d`) and as
//!   a surface, the ground's height on a horizontal grid of Δs × Δs cells read by the same rules
//!   with a voxel raster for the voids (`surface_map`: depth, volume, plan area, equivalent
//!   diameter, the edge's distance from the axis).
//!
//! A quantity that cannot be measured is not reported as a number: `measure_xy` returns the
//! reason (no soil particles, positions that are not finite after an unstable run, not 2D).

use crate::sim::Sim;
use serde::Serialize;

mod raster;
mod sections;
use raster::*;
pub use sections::*;

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

/// A 3D crater as a surface: the ground's height on a horizontal grid of Δs × Δs cells over the
/// whole scene (a quarter or half model completed by its images in the symmetry planes), each
/// cell read as a 2D column is, at t = 0 and now (docs/validation.md, "Crater and ejecta
/// definitions"), and the crater's measures from it.
#[derive(Clone, Default, Serialize)]
pub struct SurfaceMap {
    /// Cell side Δs (m): the coarsest soil spacing.
    pub cell_m: f64,
    /// Cells along x and along y.
    pub cells: [usize; 2],
    /// The charge's vertical axis (x, y; m), which the radii are measured from.
    pub axis_m: [f64; 2],
    /// Deepest drop of the surface below the original (m).
    pub depth_m: f64,
    /// Centre (x, y; m) of the deepest cell.
    pub deepest_m: [f64; 2],
    /// Apparent crater volume (m³): Σ (s0 − s) Δs² over the crater's cells (the cells deeper
    /// than Δs/2 connected through their sides to the deepest one).
    pub volume_m3: f64,
    /// Plan area of the crater's cells (m²).
    pub plan_area_m2: f64,
    /// 2 √(A/π) of the plan area A (m).
    pub equivalent_diameter_m: f64,
    /// The crater's outer edge from the charge's axis (m): its least and its largest distance
    /// over the azimuths (rays every 0.5°; an azimuth that meets no crater cell counts 0).
    pub radius_min_m: f64,
    pub radius_max_m: f64,
    /// Highest rise of the surface above the original (m; a mound over a contained charge).
    pub mound_height_m: f64,
    /// Relief of the original ground about the charge (m): the highest less the lowest original
    /// height of the cells whose centres lie within twice the crater's outer edge of the axis
    /// (`radius_max_m`; without a crater, of every cell). Zero on level ground; above a cell's
    /// side the ground is not level (a slope, a step), and the crater of revolution, which takes
    /// the highest original ground at each distance from the axis, misreads it.
    pub ground_relief_m: f64,
    /// Why there is no apparent crater (or no map), when there is none.
    pub note: Option<String>,
    /// Cell centres (m): x of the columns, y of the rows; cell (i, j) is entry i + nx j below.
    #[serde(skip)]
    pub x_m: Vec<f64>,
    #[serde(skip)]
    pub y_m: Vec<f64>,
    /// Original and current surface heights (m; NaN for a cell without soil).
    #[serde(skip)]
    pub surface0_m: Vec<f64>,
    #[serde(skip)]
    pub surface_m: Vec<f64>,
    /// s − s0 as the measure reads it (m; where a cell is empty now, the original soil's bottom
    /// less s0; NaN where it held no soil at t = 0).
    #[serde(skip)]
    pub change_m: Vec<f64>,
    /// The crater's cells.
    #[serde(skip)]
    pub crater_cells: Vec<bool>,
}

impl SurfaceMap {
    /// True when the original ground about the charge is level to within one cell
    /// ([`SurfaceMap::ground_relief_m`] ≤ Δs): then the crater of revolution about the charge's
    /// axis reads the crater; on a slope or a step it does not.
    pub(crate) fn ground_is_level(&self) -> bool {
        self.ground_relief_m <= self.cell_m
    }
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
    /// 2D and RZ (and each 3D section): the deepest crack left out of the crater's depth — a
    /// drop of one or two columns more than 2 Δs below both columns beside it and more than Δs/2
    /// below the original ground (a crack or a vent in the ground, not the bowl), read at the
    /// deeper of those two columns' drops instead.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub crack: Option<String>,
    /// Why the measure is the box's rather than the crater's, when the crater reaches the edge
    /// or the bottom of the soil the scene models (`box_bound`): its diameter or depth is then
    /// a lower bound.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bounded: Option<String>,
    /// The crater's columns reach the first column, the last column, the soil's bottom.
    #[serde(skip)]
    pub touches: [bool; 3],
    /// The soil's original bottom (m): its lowest particles' centre less half a spacing.
    #[serde(skip)]
    pub bottom_m: f64,
    /// 3D: the crater in vertical sections through the charge's axis at 0°, 45°, 90° and 135°
    /// (a scene that is not symmetric about the axis shows it here); empty in 2D and RZ.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub sections: Vec<Section>,
    /// 3D: the crater as a surface, the ground's height on a horizontal grid ([`SurfaceMap`]);
    /// none in 2D and RZ.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub surface: Option<SurfaceMap>,
    /// Column centres (m), original and current surface heights (m; NaN for an empty column).
    #[serde(skip)]
    pub columns_m: Vec<f64>,
    #[serde(skip)]
    pub surface0_m: Vec<f64>,
    #[serde(skip)]
    pub surface_m: Vec<f64>,
}

/// Which materials count as soil (per material index).
pub(crate) fn soil_mask(case: &crate::case::Case) -> Vec<bool> {
    match &case.analysis.soil_materials {
        Some(list) => case.materials.iter().map(|m| list.contains(&m.name)).collect(),
        None => case.materials.iter().map(|m| m.strength.is_some()).collect(),
    }
}

/// Which materials are explosives (JWL).
pub(crate) fn explosive_mask(case: &crate::case::Case) -> Vec<bool> {
    case.materials.iter().map(|m| matches!(m.eos, crate::case::EosCfg::Jwl { .. })).collect()
}

/// Δs: the coarsest initial spacing of the regions of soil materials.
pub(crate) fn soil_spacing(case: &crate::case::Case) -> Option<f64> {
    coarsest_spacing(case, &soil_mask(case))
}

/// The coarsest initial spacing of the regions whose material `mask` marks (m).
fn coarsest_spacing(case: &crate::case::Case, mask: &[bool]) -> Option<f64> {
    case.regions
        .iter()
        .filter(|r| case.material_index(&r.material).is_some_and(|m| mask[m]))
        .map(|r| r.spacing_m)
        .fold(None, |a: Option<f64>, s| Some(a.map_or(s, |a| a.max(s))))
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
    pub(crate) fn through_the_axis(self) -> CraterInput {
        let full = |(x, y): (Vec<f64>, Vec<f64>)| {
            let (mut fx, mut fy) = (x.clone(), y.clone());
            fx.extend(x.iter().map(|r| -r));
            fy.extend(y);
            (fx, fy)
        };
        CraterInput { soil0: full(self.soil0), soil1: full(self.soil1), charge0: full(self.charge0) }
    }
}

/// Measures the crater of a run from the soil particles' initial and current positions: in 2D
/// plane directly; axisymmetric runs on their section through the axis
/// (`CraterInput::through_the_axis`); 3D runs (z up) as a crater of revolution about the
/// charge's vertical axis (`axis_3d`): every particle taken to (r, z) about it, all azimuths
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
        let mirrors = mirror_planes(&sim.case, ax, ds);
        c.sections = sections_3d(ax, ds, &mirrors, &s0, &s1, &c0);
        c.surface = Some(surface_map(ax, ds, &mirrors, &s0, &s1, &c0).unwrap_or_else(|why| SurfaceMap {
            cell_m: ds,
            axis_m: [ax.0, ax.1],
            note: Some(why),
            ..Default::default()
        }));
    }
    c.bounded = box_bound(&sim.case, &c, c.surface.as_ref());
    Ok(c)
}

/// The measures, without the grid's arrays.
impl std::fmt::Debug for SurfaceMap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&serde_json::to_string(self).unwrap_or_default())
    }
}

/// Why a crater cannot be measured from `n0` soil particles whose current coordinates are `now`
/// with columns `ds` wide (m), if it cannot: no soil, coordinates that are not finite numbers
/// (an unstable run), a spacing that is not a positive number.
fn measurable<'a>(n0: usize, now: impl Iterator<Item = &'a f64>, ds: f64) -> Result<(), String> {
    if n0 == 0 {
        return Err("no soil particles (analysis.soil_materials names no material with particles)".into());
    }
    let bad = now.filter(|v| !v.is_finite()).count();
    if bad > 0 {
        return Err(format!(
            "{} soil coordinates are not finite numbers (the run went unstable): no surface can be traced",
            bad
        ));
    }
    if !(ds.is_finite() && ds > 0.0) {
        return Err(format!("the soil spacing {ds} m is not a positive number"));
    }
    Ok(())
}

/// Why the crater's measure is the box's, if it is: the crater reaches a side of the soil the
/// scene models that is not a symmetry plane (2D plane: its first or last column, unless a
/// mirror wall stands within a spacing of it; RZ: the outer radius; 3D: the surface map's
/// border, the scene completed across its symmetry planes, else the revolution's outer radius),
/// or its floor lies within a spacing of the soil's original bottom. Its diameter or depth is
/// then a lower bound: what the soil beyond the box would have done is not modelled.
pub(crate) fn box_bound(case: &crate::case::Case, c: &Crater, map: Option<&SurfaceMap>) -> Option<String> {
    if c.note.is_some() || c.columns_m.is_empty() {
        return None;
    }
    let ds = c.column_m;
    let (first, last) = (c.columns_m[0] - 0.5 * ds, c.columns_m[c.columns_m.len() - 1] + 0.5 * ds);
    let mut why: Vec<String> = Vec::new();
    let map = map.filter(|m| case.dim == 3 && m.crater_cells.iter().any(|&x| x));
    // sides the crater reaches where a wall of the case stands: named (a retaining wall the
    // scene is about, or the box's own side); every side reached is such a one
    let mut walled = false;
    if let Some(m) = map
        && m.x_m.len() == m.cells[0]
        && m.y_m.len() == m.cells[1]
    {
        let (nx, ny) = (m.cells[0], m.cells[1]);
        let h = 0.5 * m.cell_m;
        // (axis, coordinate, the side: 0 low, 1 high)
        let sides = [(0, m.x_m[0] - h, 0), (0, m.x_m[nx - 1] + h, 1), (1, m.y_m[0] - h, 0), (1, m.y_m[ny - 1] + h, 1)];
        let on_side = |k: usize, axis: usize, side: usize| {
            let (i, n) = if axis == 0 { (k % nx, nx) } else { (k / nx, ny) };
            if side == 0 { i == 0 } else { i + 1 == n }
        };
        let mirrors = case.axis_mirrors();
        // a wall (not a mirror) that is the plane axis = at, or its image in a symmetry plane
        let wall_at = |axis: usize, at: f64| {
            case.walls.iter().filter(|w| w.kind.repels() && w.edge_m.is_none()).any(|w| {
                let (a, b) = (w.from_m.get(axis), w.to_m.get(axis));
                a.is_some() && a == b && {
                    let c = w.from_m[axis];
                    (c - at).abs() <= m.cell_m
                        || mirrors.iter().any(|&(k, p)| k == axis && (2.0 * p - c - at).abs() <= m.cell_m)
                }
            })
        };
        let mut named: Vec<String> = Vec::new();
        let mut walls = 0;
        for (axis, at, side) in sides {
            if (0..nx * ny).any(|k| m.crater_cells[k] && on_side(k, axis, side)) {
                let wall = wall_at(axis, at);
                walls += usize::from(wall);
                named.push(format!(
                    "{} = {at:.3} m{}",
                    ["x", "y"][axis],
                    if wall { ", where a wall of the case stands" } else { "" }
                ));
            }
        }
        if !named.is_empty() {
            why.push(format!(
                "reaches a side of the soil the scene models (the surface map's border: {})",
                named.join(", ")
            ));
        }
        walled = !named.is_empty() && walls == named.len();
    } else if case.dim == 3 || case.axisymmetric() {
        if c.touches[0] || c.touches[1] {
            why.push(format!("reaches the soil's outer radius (r = {:.3} m)", last.max(-first)));
        }
    } else {
        // a vertical mirror wall within a spacing of an edge: a symmetry plane, not the box
        let planes = case.axis_mirrors();
        let mirror_at = |x: f64| planes.iter().any(|&(k, c)| k == 0 && (c - x).abs() <= ds);
        for (t, x) in [(c.touches[0], first), (c.touches[1], last)] {
            if t && !mirror_at(x) {
                why.push(format!("reaches the edge of the soil the scene models (x = {x:.3} m)"));
            }
        }
    }
    let bottom = c.touches[2].then(|| {
        format!("floor reaches the soil's bottom ({} = {:.3} m)", if case.dim == 3 { "z" } else { "y" }, c.bottom_m)
    });
    let (what, so) = match (why.is_empty(), bottom) {
        (true, None) => return None,
        (false, None) if walled => (
            why.join(" and "),
            "its diameter is a lower bound: widen the soil, unless that wall is the scene's own (a retaining wall), which then holds the crater there",
        ),
        (false, None) => (why.join(" and "), "its diameter is a lower bound: widen the soil"),
        (true, Some(b)) => (format!("'s {b}"), "its depth is a lower bound: deepen the soil"),
        (false, Some(b)) => (
            format!("{} and its {b}", why.join(" and ")),
            "its diameter and depth are lower bounds: widen and deepen the soil",
        ),
    };
    let sep = if what.starts_with('\'') { "" } else { " " };
    Some(format!("the crater{sep}{what}: the box, not the crater, ends the measure; {so}"))
}

/// The note of a measure that finds no apparent crater with columns `ds` wide (m).
fn no_crater(ds: f64) -> String {
    format!("no apparent crater: the ground surface has not dropped by more than half a spacing ({:.1} cm)", 50.0 * ds)
}

/// The drop s0 − s of the surface in each column (m) from the original and current surface
/// heights: where a column of ground is empty now, down to the soil's original bottom `bottom`
/// (m); 0 where it held no ground at t = 0.
fn drops(s0: &[f64], s1: &[f64], bottom: f64) -> Vec<f64> {
    s0.iter()
        .zip(s1)
        .map(|(a, b)| {
            if a.is_finite() && b.is_finite() {
                a - b
            } else if a.is_finite() {
                *a - bottom
            } else {
                0.0
            }
        })
        .collect()
}

/// The crater from `inp` with columns `ds` wide (the coarsest soil spacing).
pub(crate) fn measure_xy(inp: &CraterInput, ds: f64) -> Result<Crater, String> {
    let (x0s, y0s) = (&inp.soil0.0, &inp.soil0.1);
    let (x1s, y1s) = (&inp.soil1.0, &inp.soil1.1);
    measurable(x0s.len(), x1s.iter().chain(y1s), ds)?;
    let lo = x0s.iter().cloned().fold(f64::INFINITY, f64::min) - 0.5 * ds;
    let hi = x0s.iter().cloned().fold(f64::NEG_INFINITY, f64::max) + 0.5 * ds;
    let ncol = ((hi - lo) / ds).round().max(1.0) as usize;
    let ymin0 = y0s.iter().cloned().fold(f64::INFINITY, f64::min);
    let ymax0 = y0s.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let ymin1 = y1s.iter().cloned().fold(f64::INFINITY, f64::min);
    // the raster covers the ground and what lies just above it (ejecta higher up are ejecta)
    let ytop = ymax0 + 0.5 * (hi - lo);
    let lims = [(lo, hi), (ymin0.min(ymin1), ytop)];
    let r0 = Raster::new(&[x0s, y0s], ds, &lims, ymax0);
    let r1 = Raster::new(&[x1s, y1s], ds, &lims, ymax0);
    let mut s0 = surface(&[x0s, y0s], &[lo], ds, &[ncol], &r0);
    let s1 = surface(&[x1s, y1s], &[lo], ds, &[ncol], &r1);
    // a charge in a pit of the ground: the ground level over it is interpolated
    fill_pits(&mut s0, inp, (lo, ds, ncol));
    let mut drop = drops(&s0, &s1, ymin0);
    // cracks: a run of one or two columns whose drop is more than 2 ds below both columns beside
    // it (one, at the raster's edge) and below the original ground is a crack or a vent, not the
    // bowl: read at its flanks' drop (a notch in a raised rim, above the ground, is no crack: it
    // cannot be the depth)
    let crack = cut_cracks(&mut drop, (lo, ds, ncol));
    let (kmax, depth) =
        drop.iter().enumerate().fold((0, f64::NEG_INFINITY), |acc, (k, d)| if *d > acc.1 { (k, *d) } else { acc });
    // the columns about the deepest one whose drop exceeds `lim`: first and last
    let span = |lim: f64| -> (usize, usize) {
        let (mut a, mut b) = (kmax, kmax);
        while a > 0 && drop[a - 1] > lim {
            a -= 1;
        }
        while b + 1 < ncol && drop[b + 1] > lim {
            b += 1;
        }
        (a, b)
    };
    let run = |lim: f64| -> f64 {
        let (a, b) = span(lim);
        (b - a + 1) as f64 * ds
    };
    // a bowl spans at least two columns (a crater on the axis of an RZ section does, with its
    // mirror image); one alone is a crack or a gap in the ground, as in 3D
    let narrow = depth > 0.5 * ds && run(0.5 * ds) < 1.5 * ds;
    // and is wider than it is deep (an apparent crater's diameter is several times its depth): a
    // narrower hole is a vent or a crack through the ground (a buried charge's dome breaking),
    // not the bowl
    let vent = depth > 0.5 * ds && !narrow && run(0.5 * ds) < depth;
    let crater = depth > 0.5 * ds && !narrow && !vent;
    let (diameter, half) = if crater { (run(0.5 * ds), run(0.5 * depth)) } else { (0.0, 0.0) };
    // the crater's columns reach the raster's first or last column, or its floor is within a
    // spacing of the soil's original bottom (or empty down to it)
    let touches = if crater {
        let (a, b) = span(0.5 * ds);
        [a == 0, b + 1 == ncol, (a..=b).any(|k| !s1[k].is_finite() || s1[k] < ymin0 + ds)]
    } else {
        [false; 3]
    };
    let smax = s0.iter().cloned().filter(|v| v.is_finite()).fold(f64::NEG_INFINITY, f64::max);
    let ejecta = y1s.iter().cloned().fold(f64::NEG_INFINITY, f64::max) - smax;
    let mound = drop.iter().cloned().map(|d| -d).fold(0.0, f64::max);
    // the cavity is the charge's: the void that holds a cell of the explosive's initial
    // positions (a gap the blast opened elsewhere, at the box's floor or a far corner, is not)
    let holding: Vec<usize> =
        inp.charge0.0.iter().zip(&inp.charge0.1).filter_map(|(&x, &y)| r1.cell_of(&[x, y])).collect();
    let cavity = (inp.charge0.0.is_empty() || !holding.is_empty())
        .then(|| r1.largest_void(&holding))
        .flatten()
        .filter(|(cells, _)| *cells >= 4)
        .map(|(cells, [(xa, xb), (ya, yb), _])| {
            let bb = [xa, xb, ya, yb];
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
    } else if narrow {
        Some(format!(
            "no apparent crater: the ground's deepest drop ({:.1} cm) is in one column {:.1} cm wide, fewer than 2: a crack or gap in the ground, not a bowl",
            100.0 * depth,
            100.0 * ds
        ))
    } else if vent {
        Some(format!(
            "no apparent crater: the ground's deepest drop ({:.1} cm) is a hole {:.1} cm wide, narrower than it is deep: a vent or crack through the ground, not a bowl",
            100.0 * depth,
            100.0 * run(0.5 * ds)
        ))
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
            None => no_crater(ds),
        })
    };
    let crack = crack.map(|(deep, at, wide)| {
        format!(
            "a crack {:.1} cm wide centred at {:.1} cm on the section (its distance from the axis in RZ and in a 3D section) drops {:.1} cm below the original ground, more than 2 spacings below the ground beside it: left out of the depth",
            100.0 * wide,
            100.0 * if at.abs() < 0.5 * ds { 0.0 } else { at },
            100.0 * deep
        )
    });
    Ok(Crater {
        diameter_m: diameter,
        depth_m: if crater {
            depth
        } else if narrow || vent {
            0.0
        } else {
            depth.max(0.0)
        },
        crack,
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
        bounded: None,
        touches,
        bottom_m: ymin0 - 0.5 * ds,
        sections: Vec::new(),
        surface: None,
        columns_m: (0..ncol).map(|k| lo + (k as f64 + 0.5) * ds).collect(),
        surface0_m: s0,
        surface_m: s1,
    })
}

/// Over a charge in a pit of the ground (an explosive particle above the soil's top in a column
/// at t = 0), the original ground `s0` interpolated between the nearest uncovered columns.
fn fill_pits(s0: &mut [f64], inp: &CraterInput, (lo, ds, ncol): (f64, f64, usize)) {
    let covered: Vec<bool> = (0..ncol)
        .map(|k| {
            let xc = lo + (k as f64 + 0.5) * ds;
            s0[k].is_finite()
                && inp.charge0.0.iter().zip(&inp.charge0.1).any(|(x, y)| (x - xc).abs() < ds && *y > s0[k])
        })
        .collect();
    if covered.iter().any(|c| *c) {
        let base = s0.to_vec();
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
}

/// Cracks and vents cut out of the drops (read at their flanks' drop): the deepest one as
/// (drop, centre, width) (m).
fn cut_cracks(drop: &mut [f64], (lo, ds, ncol): (f64, f64, usize)) -> Option<(f64, f64, f64)> {
    let mut crack: Option<(f64, f64, f64)> = None;
    for w in 1..=2usize {
        for k in 0..=ncol.saturating_sub(w) {
            let flanks = [k.checked_sub(1), (k + w < ncol).then_some(k + w)];
            let Some(fmax) = flanks.iter().flatten().map(|&f| drop[f]).reduce(f64::max) else { continue };
            let inner = drop[k..k + w].iter().cloned().fold(f64::INFINITY, f64::min);
            if inner > fmax + 2.0 * ds && inner > 0.5 * ds {
                let deep = drop[k..k + w].iter().cloned().fold(f64::NEG_INFINITY, f64::max);
                if crack.is_none_or(|c| deep > c.0) {
                    crack = Some((deep, lo + (k as f64 + 0.5 * w as f64) * ds, w as f64 * ds));
                }
                drop[k..k + w].iter_mut().for_each(|d| *d = fmax);
            }
        }
    }
    crack
}

#[cfg(test)]
mod tests;
