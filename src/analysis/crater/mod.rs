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
//! - 3D: the crater also in vertical sections through the charge's axis ([`sections_3d`]) and as
//!   a surface, the ground's height on a horizontal grid of Δs × Δs cells read by the same rules
//!   with a voxel raster for the voids ([`surface_map`]: depth, volume, plan area, equivalent
//!   diameter, the edge's distance from the axis).
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
    pub fn ground_is_level(&self) -> bool {
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
    /// or the bottom of the soil the scene models ([`box_bound`]): its diameter or depth is then
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

/// Soil occupancy on a raster of square (2D) or cubic (3D) cells of side `ds`, the last axis
/// vertical: a cell is solid where a soil particle lies within one cell size of its centre;
/// `open` marks the empty cells connected to the raster's border (the sky) through empty cells
/// sharing a face (a flood fill), the other empty cells are enclosed voids.
struct Raster {
    /// Number of axes (2 or 3).
    d: usize,
    /// Lower corner (m) and cells along each axis (1 along the axes beyond `d`).
    lo: [f64; 3],
    n: [usize; 3],
    ds: f64,
    solid: Vec<bool>,
    open: Vec<bool>,
}

impl Raster {
    /// The raster of the points whose coordinates along each axis are `pts[axis]` (2 or 3 axes,
    /// the last vertical), covering `lims[axis]` (m) and two cells more on every side. The
    /// margin below the limits, and the margins beside them below the height `ground` (m), are
    /// solid: beyond the measured soil the ground is taken to go on (a wall of the box, or soil
    /// the scene does not model), so a crack in the soil that reaches its side or bottom is not
    /// open to the sky there.
    fn new(pts: &[&[f64]], ds: f64, lims: &[(f64, f64)], ground: f64) -> Raster {
        let d = pts.len().min(3);
        let (mut lo, mut n) = ([0.0; 3], [1usize; 3]);
        for a in 0..d {
            lo[a] = lims[a].0 - 2.0 * ds;
            // (cells to the limits' span, an exact multiple of ds within rounding not rounded up
            // to one more: that column, outside the soil and inside the margin, was a void)
            let m = (lims[a].1 - lims[a].0) / ds;
            let cells = if (m - m.round()).abs() <= 1e-9 * m.abs().max(1.0) { m.round() } else { m.ceil() };
            n[a] = (cells as usize + 4).max(1);
        }
        let stride = [1, n[0], n[0] * n[1]];
        let total = n[0] * n[1] * n[2];
        let mut solid = vec![false; total];
        'points: for i in 0..pts[0].len() {
            let mut iu = [0i64; 3];
            for a in 0..d {
                let u = (pts[a][i] - lo[a]) / ds;
                if u < -1.0 || u > n[a] as f64 + 1.0 {
                    continue 'points;
                }
                iu[a] = u.floor() as i64;
            }
            'cells: for o in 0..3usize.pow(d as u32) {
                let (mut k, mut r2, mut rest) = (0, 0.0, o);
                for a in 0..d {
                    let c = iu[a] + (rest % 3) as i64 - 1;
                    rest /= 3;
                    if c < 0 || c >= n[a] as i64 {
                        continue 'cells;
                    }
                    r2 += (lo[a] + (c as f64 + 0.5) * ds - pts[a][i]).powi(2);
                    k += c as usize * stride[a];
                }
                if r2 <= ds * ds {
                    solid[k] = true;
                }
            }
        }
        // the margins taken as ground
        let v = d - 1;
        for (k, cell) in solid.iter_mut().enumerate() {
            let idx = |a: usize| k / stride[a] % n[a];
            let z = lo[v] + (idx(v) as f64 + 0.5) * ds;
            let beside = (0..v).any(|a| idx(a) < 2 || idx(a) + 2 >= n[a]);
            if idx(v) < 2 || (beside && z < ground) {
                *cell = true;
            }
        }
        // flood the empty cells from the border, through faces
        let mut open = vec![false; total];
        let on_border = |k: usize| (0..d).any(|a| [0, n[a] - 1].contains(&(k / stride[a] % n[a])));
        flood(&n[..d], (0..total).filter(|&k| on_border(k)).collect(), |k| !solid[k], &mut open);
        Raster { d, lo, n, ds, solid, open }
    }

    /// The cell holding the point `p` (its first `d` coordinates), if the raster covers it.
    fn cell(&self, p: &[f64]) -> Option<usize> {
        let (mut k, mut stride) = (0, 1);
        for a in 0..self.d {
            let u = (p[a] - self.lo[a]) / self.ds;
            if u < 0.0 || u >= self.n[a] as f64 {
                return None;
            }
            k += u as usize * stride;
            stride *= self.n[a];
        }
        Some(k)
    }

    /// What the vertical gap from height `za` to `zb` over the horizontal point `h` is in the
    /// raster: open to the sky (an open cell along it, or a point beyond the raster, which ends
    /// above the ground), an enclosed void (empty cells, none open), or solid all along (too
    /// thin to hold a cell farther than Δs from every particle).
    fn gap(&self, h: &[f64], za: f64, zb: f64) -> Gap {
        let mut p = [0.0; 3];
        p[..self.d - 1].copy_from_slice(&h[..self.d - 1]);
        let mut any_void = false;
        let mut z = za + self.ds;
        while z < zb - 0.5 * self.ds {
            p[self.d - 1] = z;
            match self.cell(&p) {
                None => return Gap::Open,
                Some(k) if self.open[k] => return Gap::Open,
                Some(k) if !self.solid[k] => any_void = true,
                _ => {}
            }
            z += 0.5 * self.ds;
        }
        if any_void { Gap::Enclosed } else { Gap::Solid }
    }

    /// The cell holding the point `p` (m, one coordinate per axis), if the raster covers it.
    fn cell_of(&self, p: &[f64]) -> Option<usize> {
        let stride = [1, self.n[0], self.n[0] * self.n[1]];
        let mut k = 0;
        for a in 0..self.d {
            let u = ((p[a] - self.lo[a]) / self.ds).floor();
            if !(u >= 0.0 && u < self.n[a] as f64) {
                return None;
            }
            k += u as usize * stride[a];
        }
        Some(k)
    }

    /// The largest enclosed void (a face-connected component of empty, not open cells) that
    /// holds one of the cells `holding` (any void when it is empty): its number of cells and its
    /// bounding box (m, lower and upper bound along each axis).
    fn largest_void(&self, holding: &[usize]) -> Option<(usize, [(f64, f64); 3])> {
        let stride = [1, self.n[0], self.n[0] * self.n[1]];
        let total = self.solid.len();
        let void = |k: usize| !self.solid[k] && !self.open[k];
        let mut seen = vec![false; total];
        let mut mark = vec![holding.is_empty(); total];
        for &k in holding {
            mark[k] = true;
        }
        let mut best: Option<(usize, [(f64, f64); 3])> = None;
        for k0 in 0..total {
            if seen[k0] || !void(k0) {
                continue;
            }
            let cells = flood(&self.n[..self.d], vec![k0], void, &mut seen);
            if !cells.iter().any(|&k| mark[k]) {
                continue;
            }
            let count = cells.len();
            let (mut ilo, mut ihi) = ([usize::MAX; 3], [0usize; 3]);
            for k in cells {
                for a in 0..self.d {
                    let i = k / stride[a] % self.n[a];
                    ilo[a] = ilo[a].min(i);
                    ihi[a] = ihi[a].max(i);
                }
            }
            let mut bb = [(0.0, 0.0); 3];
            for a in 0..self.d {
                bb[a] = (self.lo[a] + ilo[a] as f64 * self.ds, self.lo[a] + (ihi[a] + 1) as f64 * self.ds);
            }
            if best.as_ref().is_none_or(|b| count > b.0) {
                best = Some((count, bb));
            }
        }
        best
    }
}

/// A vertical gap between two particles of a column, as the raster sees it ([`Raster::gap`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Gap {
    Open,
    Enclosed,
    Solid,
}

/// A flood fill on a grid of `n[axis]` cells along each axis (cell (i0, i1, i2) is entry
/// i0 + n0 (i1 + n1 i2)): marks in `reached` the cells that `member` admits and that connect to
/// `seeds` through the faces of such cells, not already reached; returns them.
fn flood(n: &[usize], mut stack: Vec<usize>, member: impl Fn(usize) -> bool, reached: &mut [bool]) -> Vec<usize> {
    let mut out = Vec::new();
    while let Some(k) = stack.pop() {
        if reached[k] || !member(k) {
            continue;
        }
        reached[k] = true;
        out.push(k);
        let mut stride = 1;
        for &na in n {
            let i = k / stride % na;
            if i > 0 {
                stack.push(k - stride);
            }
            if i + 1 < na {
                stack.push(k + stride);
            }
            stride *= na;
        }
    }
    out
}

/// Ground surface per column from the positions of the soil particles, `pts[axis]` (2D: x, y;
/// 3D: x, y, z; the last axis vertical). The columns lie on a horizontal grid of `nc` columns
/// along each horizontal axis (2D: one axis), `ds` apart from the corner `lo` (m): column k is
/// centred at lo + (k + 1/2) ds along each axis and gathers the particles within ±ds of its
/// centre along each (two spacings wide, so a smooth lateral shift of the lattice cannot empty
/// it); the particles are walked upward from the lowest up to the first vertical gap larger
/// than 2 ds that is not an enclosed void of `raster`; the surface is the highest particle within
/// ±3ds/4 of the centre along each horizontal axis that lies at most 2 ds above the walk's top
/// (the band's top when there is none), NaN for an empty column. Column (k0, k1) is entry
/// k0 + nc[0] k1 of the result.
fn surface(pts: &[&[f64]], lo: &[f64], ds: f64, nc: &[usize], raster: &Raster) -> Vec<f64> {
    let dh = pts.len() - 1;
    let z = pts[dh];
    // each particle in the bin of the column nearest to it (bins -1..=nc along each axis): a
    // column's particles lie in its own bin and the bins beside it
    let nb: Vec<usize> = nc[..dh].iter().map(|n| n + 2).collect();
    let mut bins: Vec<Vec<u32>> = vec![Vec::new(); nb.iter().product()];
    let u = |i: usize, a: usize| (pts[a][i] - lo[a]) / ds - 0.5;
    'points: for i in 0..z.len() {
        let (mut b, mut stride) = (0, 1);
        for a in 0..dh {
            let v = (u(i, a) + 0.5).floor() + 1.0;
            if !(v >= 0.0 && v < nb[a] as f64) {
                continue 'points;
            }
            b += v as usize * stride;
            stride *= nb[a];
        }
        bins[b].push(i as u32);
    }
    let ncol: usize = nc[..dh].iter().product();
    let mut c: Vec<(f64, bool)> = Vec::new();
    (0..ncol)
        .map(|kc| {
            let mut k = [0usize; 2];
            let mut rest = kc;
            for a in 0..dh {
                k[a] = rest % nc[a];
                rest /= nc[a];
            }
            let centre: Vec<f64> = (0..dh).map(|a| lo[a] + (k[a] as f64 + 0.5) * ds).collect();
            // gather the band: the particles within ±ds of the centre along each axis
            c.clear();
            for o in 0..3usize.pow(dh as u32) {
                let (mut b, mut stride, mut rest) = (0, 1, o);
                for a in 0..dh {
                    b += (k[a] + rest % 3) * stride;
                    rest /= 3;
                    stride *= nb[a];
                }
                for &i in &bins[b] {
                    let i = i as usize;
                    let inside = (0..dh).all(|a| {
                        let v = u(i, a);
                        (v - 1.0).ceil() <= k[a] as f64 && k[a] as f64 <= (v + 1.0).floor()
                    });
                    if inside {
                        c.push((z[i], (0..dh).all(|a| (pts[a][i] - centre[a]).abs() <= 0.75 * ds)));
                    }
                }
            }
            if c.is_empty() {
                return f64::NAN;
            }
            c.sort_by(|a, b| a.0.total_cmp(&b.0));
            // walk the band up to the first gap open to the sky; a gap the raster sees as
            // solid ends it too where the band's particles lie mostly below it (a few lifted
            // particles over the ground), not where most lie above (a crack low in the soil, a
            // row pulled off the floor of the box)
            let mut top = 0;
            for q in 1..c.len() {
                if c[q].0 - c[top].0 > 2.0 * ds {
                    let ends = match raster.gap(&centre, c[top].0, c[q].0) {
                        Gap::Open => true,
                        Gap::Enclosed => false,
                        Gap::Solid => q >= c.len() - q,
                    };
                    if ends {
                        break;
                    }
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
                .filter(|(y, near)| *y <= lim && *near)
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
/// the centroid of the explosive's initial positions `charge_xy`, put on every symmetry plane
/// the charge abuts ([`charge_planes`]: the whole charge's centroid lies there, not the modelled
/// half's).
pub fn axis_3d(case: &crate::case::Case, charge_xy: &[(f64, f64)]) -> Result<(f64, f64), String> {
    if let Some(p) = case.detonation.as_ref().and_then(|d| d.point_m.as_ref()) {
        return Ok((p[0], p[1]));
    }
    if charge_xy.is_empty() {
        return Err("a 3D crater is measured about the charge's vertical axis: the case has no explosive and no detonation point".into());
    }
    let pts: Vec<[f64; 2]> = charge_xy.iter().map(|p| [p.0, p.1]).collect();
    let mut c = centroid(&pts, 2);
    for (k, at) in charge_planes(case, &pts) {
        c[k] = at;
    }
    Ok((c[0], c[1]))
}

/// The mean of the first `d` coordinates of `pts`.
pub fn centroid<P: AsRef<[f64]>>(pts: &[P], d: usize) -> Vec<f64> {
    let mut c = vec![0.0; d];
    for p in pts {
        for (a, b) in c.iter_mut().zip(p.as_ref()) {
            *a += b / pts.len() as f64;
        }
    }
    c
}

/// The symmetry planes a charge abuts, as (axis k, coordinate c; m): the mirror walls that are
/// axis-aligned planes (lines in 2D) with every explosive point of `pts` (m; points with fewer
/// coordinates than k + 1 leave the plane k out) on one side and the nearest within one
/// explosive spacing of it: their images complete the charge. In RZ the axis is not such a plane
/// (the rings are whole already); a plane perpendicular to it (y = c) is.
pub fn charge_planes<P: AsRef<[f64]>>(case: &crate::case::Case, pts: &[P]) -> Vec<(usize, f64)> {
    let sp = coarsest_spacing(case, &explosive_mask(case)).unwrap_or(0.0);
    let mut planes: Vec<(usize, f64)> = Vec::new();
    if pts.is_empty() {
        return planes;
    }
    for (k, c) in case.axis_mirrors() {
        if (k == 0 && case.axisymmetric()) || pts.iter().any(|p| p.as_ref().len() <= k) {
            continue;
        }
        let (lo, hi) = pts
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.as_ref()[k] - c), b.max(p.as_ref()[k] - c)));
        let one_side = lo >= 0.0 || hi <= 0.0;
        let near = lo.abs().min(hi.abs());
        if one_side && near <= sp.max(0.0) && !planes.iter().any(|&(q, e)| q == k && e == c) {
            planes.push((k, c));
        }
    }
    planes
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
    case.axis_mirrors()
        .into_iter()
        .filter(|&(k, c)| k < 2 && (c - if k == 0 { ax.0 } else { ax.1 }).abs() <= ds)
        .collect()
}

/// The points `pts` (x, y, z; m) and their images in the symmetry planes `mirrors` (0 for
/// x = c, 1 for y = c; c in m), each plane mirroring the points and the images of the planes
/// before it: a quarter with the planes x = 0 and y = 0 becomes the whole scene.
fn with_images(pts: &[[f64; 3]], mirrors: &[(usize, f64)]) -> Vec<[f64; 3]> {
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
    let complete = |pts: &[[f64; 3]]| with_images(pts, mirrors);
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

/// The crater of a 3D run as a surface ([`SurfaceMap`]) about the charge's vertical axis `ax`,
/// from the soil's initial and current positions and the explosive's initial ones (x, y, z; m;
/// z up), completed by their images in the symmetry planes `mirrors` ([`mirror_planes`]): the
/// ground's height on a horizontal grid of `ds` × `ds` cells covering the soil at t = 0, each
/// cell read as a 2D column ([`measure_xy`]) on the particles within ±ds of its centre along x
/// and y, with the enclosed voids on a voxel raster; at t = 0 a cell with an explosive particle
/// within ±Δs of its centre (x and y) above the soil (a charge in a pit) takes the mean original height of the
/// nearest cells (the nearest square ring of cells around it) that have none. The crater is the
/// region of cells deeper than ds/2, connected through their sides to the deepest cell.
pub fn surface_map(
    ax: (f64, f64),
    ds: f64,
    mirrors: &[(usize, f64)],
    soil0: &[[f64; 3]],
    soil1: &[[f64; 3]],
    charge0: &[[f64; 3]],
) -> Result<SurfaceMap, String> {
    measurable(soil0.len(), soil1.iter().flatten(), ds)?;
    if soil0.iter().flatten().any(|v| !v.is_finite()) {
        return Err("the soil's initial coordinates are not finite numbers".into());
    }
    let axes = |pts: &[[f64; 3]]| -> [Vec<f64>; 3] { std::array::from_fn(|a| pts.iter().map(|p| p[a]).collect()) };
    let (a0, a1, c0) =
        (axes(&with_images(soil0, mirrors)), axes(&with_images(soil1, mirrors)), with_images(charge0, mirrors));
    let range = |v: &[f64]| v.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |r, x| (r.0.min(*x), r.1.max(*x)));
    let ((xa, xb), (ya, yb), (za, zb)) = (range(&a0[0]), range(&a0[1]), range(&a0[2]));
    let (lo, hi) = ([xa - 0.5 * ds, ya - 0.5 * ds], [xb + 0.5 * ds, yb + 0.5 * ds]);
    let nc = [0, 1].map(|a| ((hi[a] - lo[a]) / ds).round().max(1.0) as usize);
    // the raster covers the ground and what lies just above it (ejecta higher up are ejecta),
    // down to the lowest soil particle but no further than that below the original bottom
    let reach = 0.5 * (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let zlo = range(&a1[2]).0.max(za - reach).min(za);
    let lims = [(lo[0], hi[0]), (lo[1], hi[1]), (zlo, zb + reach)];
    let voxels: f64 = lims.iter().map(|l| ((l.1 - l.0) / ds).ceil() + 4.0).product();
    if voxels > 5e7 {
        return Err(format!("the scene is {voxels:.1e} cells of {:.1} cm: too many for the surface map", 100.0 * ds));
    }
    let height = |a: &[Vec<f64>; 3]| {
        let pts = [&a[0][..], &a[1][..], &a[2][..]];
        surface(&pts, &lo, ds, &nc, &Raster::new(&pts, ds, &lims, zb))
    };
    let (mut s0, s1) = (height(&a0), height(&a1));
    let (nx, ny) = (nc[0], nc[1]);
    let centre = |k: usize| [lo[0] + ((k % nx) as f64 + 0.5) * ds, lo[1] + ((k / nx) as f64 + 0.5) * ds];
    // a charge in a pit of the ground: the original level over it from the nearest cells
    // (the charge over a cell: within ±Δs of its centre along x and y, the band its soil is
    // gathered from, as for a 2D column)
    let mut charge_top = vec![f64::NEG_INFINITY; nx * ny];
    // the cells i whose centre i + 1/2 lies within 1 of u (in cells): floor(u − 1/2) and the next
    let near = |u: f64, n: usize| {
        let i0 = (u - 0.5).floor() as i64;
        [i0, i0 + 1]
            .into_iter()
            .filter(move |&i| i >= 0 && i < n as i64 && (i as f64 + 0.5 - u).abs() < 1.0)
            .map(|i| i as usize)
    };
    for p in &c0 {
        let (u, v) = ((p[0] - lo[0]) / ds, (p[1] - lo[1]) / ds);
        if !(u.is_finite() && v.is_finite()) {
            continue;
        }
        for j in near(v, ny) {
            for i in near(u, nx) {
                let k = i + nx * j;
                charge_top[k] = charge_top[k].max(p[2]);
            }
        }
    }
    let covered: Vec<bool> = (0..nx * ny).map(|k| s0[k].is_finite() && charge_top[k] > s0[k]).collect();
    let base = s0.clone();
    for k in (0..nx * ny).filter(|&k| covered[k]) {
        let (i, j) = ((k % nx) as i64, (k / nx) as i64);
        for r in 1..nx.max(ny) as i64 {
            let ring: Vec<f64> = (-r..=r)
                .flat_map(|di| (-r..=r).map(move |dj| (di, dj)))
                .filter(|&(di, dj)| di.abs().max(dj.abs()) == r)
                .map(|(di, dj)| (i + di, j + dj))
                .filter(|&(a, b)| a >= 0 && b >= 0 && a < nx as i64 && b < ny as i64)
                .map(|(a, b)| a as usize + nx * b as usize)
                .filter(|&q| !covered[q] && base[q].is_finite())
                .map(|q| base[q])
                .collect();
            if !ring.is_empty() {
                s0[k] = ring.iter().sum::<f64>() / ring.len() as f64;
                break;
            }
        }
    }
    let drop = drops(&s0, &s1, za);
    let depth = drop.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    // the deepest cell: among those as deep (to 1e-9 ds: an image's sums may differ in the last
    // bits) one in the modelled part rather than an image, then the nearest the axis
    let side: Vec<f64> = mirrors.iter().map(|&(a, c)| (soil0.iter().map(|p| p[a] - c).sum::<f64>()).signum()).collect();
    let rank = |k: usize| {
        let q = centre(k);
        let image = mirrors.iter().zip(&side).any(|(&(a, c), sd)| (q[a] - c) * sd < 0.0);
        (image, (q[0] - ax.0).hypot(q[1] - ax.1))
    };
    let kmax = (0..drop.len())
        .filter(|&k| drop[k] >= depth - 1e-9 * ds)
        .min_by(|&a, &b| {
            let (ra, rb) = (rank(a), rank(b));
            ra.0.cmp(&rb.0).then(ra.1.total_cmp(&rb.1))
        })
        .unwrap_or(0);
    // the crater's cells: deeper than ds/2, connected through their sides to the deepest
    let mut cells = vec![false; nx * ny];
    let seed = if depth > 0.5 * ds { vec![kmax] } else { Vec::new() };
    let mut n_cells = flood(&nc, seed, |k| drop[k] > 0.5 * ds, &mut cells).len();
    // a bowl covers at least 2 x 2 columns (a crater on the axis of a quarter model does, with
    // its images); fewer are cracks or gaps in the ground (a contained charge's dome), not a
    // crater
    const MIN_CELLS: usize = 4;
    let crater = depth > 0.5 * ds && n_cells >= MIN_CELLS;
    let cracks = (depth > 0.5 * ds && !crater).then(|| {
        format!(
            "no apparent crater: the ground's deepest drop ({:.1} cm) is in {n_cells} column{} {:.1} cm wide, fewer than {MIN_CELLS}: a crack or gap in the ground, not a bowl",
            100.0 * depth,
            if n_cells == 1 { "" } else { "s" },
            100.0 * ds
        )
    });
    if !crater {
        cells.iter_mut().for_each(|c| *c = false);
        n_cells = 0;
    }
    let area = n_cells as f64 * ds * ds;
    let volume: f64 = (0..nx * ny).filter(|&k| cells[k]).map(|k| drop[k].max(0.0) * ds * ds).sum();
    // the crater's outer edge along rays from the axis every 0.5°, sampled every ds/8
    let reach_xy =
        (hi[0] - lo[0]).hypot(hi[1] - lo[1]) + (ax.0 - 0.5 * (lo[0] + hi[0])).hypot(ax.1 - 0.5 * (lo[1] + hi[1]));
    let edges: Vec<f64> = (0..720)
        .map(|q| {
            let (sn, cs) = (q as f64 * 0.5).to_radians().sin_cos();
            (0..=(reach_xy / (0.125 * ds)).ceil() as usize)
                .map(|m| m as f64 * 0.125 * ds)
                .filter(|t| {
                    let (u, v) = ((ax.0 + t * cs - lo[0]) / ds, (ax.1 + t * sn - lo[1]) / ds);
                    u >= 0.0 && v >= 0.0 && u < nx as f64 && v < ny as f64 && cells[u as usize + nx * v as usize]
                })
                .fold(0.0, f64::max)
        })
        .collect();
    let change: Vec<f64> = (0..nx * ny).map(|k| if s0[k].is_finite() { -drop[k] } else { f64::NAN }).collect();
    let r_max = edges.iter().cloned().fold(0.0, f64::max);
    let (g_lo, g_hi) = (0..nx * ny)
        .filter(|&k| s0[k].is_finite())
        .filter(|&k| {
            let q = centre(k);
            !crater || (q[0] - ax.0).hypot(q[1] - ax.1) <= 2.0 * r_max
        })
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), k| (a.min(s0[k]), b.max(s0[k])));
    Ok(SurfaceMap {
        cell_m: ds,
        cells: nc,
        axis_m: [ax.0, ax.1],
        depth_m: if cracks.is_some() { 0.0 } else { depth.max(0.0) },
        deepest_m: centre(kmax),
        volume_m3: volume,
        plan_area_m2: area,
        equivalent_diameter_m: 2.0 * (area / std::f64::consts::PI).sqrt(),
        radius_min_m: if crater { edges.iter().cloned().fold(f64::INFINITY, f64::min) } else { 0.0 },
        radius_max_m: r_max,
        mound_height_m: drop.iter().map(|d| -d).fold(0.0, f64::max),
        ground_relief_m: if g_hi >= g_lo { g_hi - g_lo } else { 0.0 },
        note: (!crater).then(|| cracks.clone().unwrap_or_else(|| no_crater(ds))),
        x_m: (0..nx).map(|i| lo[0] + (i as f64 + 0.5) * ds).collect(),
        y_m: (0..ny).map(|j| lo[1] + (j as f64 + 0.5) * ds).collect(),
        surface0_m: s0,
        surface_m: s1,
        change_m: change,
        crater_cells: cells,
    })
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
pub fn box_bound(case: &crate::case::Case, c: &Crater, map: Option<&SurfaceMap>) -> Option<String> {
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
            case.walls.iter().filter(|w| w.kind != crate::case::WallKind::Mirror && w.edge_m.is_none()).any(|w| {
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
pub fn measure_xy(inp: &CraterInput, ds: f64) -> Result<Crater, String> {
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
    let covered: Vec<bool> = (0..ncol)
        .map(|k| {
            let xc = lo + (k as f64 + 0.5) * ds;
            s0[k].is_finite()
                && inp.charge0.0.iter().zip(&inp.charge0.1).any(|(x, y)| (x - xc).abs() < ds && *y > s0[k])
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
    let mut drop = drops(&s0, &s1, ymin0);
    // cracks: a run of one or two columns whose drop is more than 2 ds below both columns beside
    // it (one, at the raster's edge) and below the original ground is a crack or a vent, not the
    // bowl: read at its flanks' drop (a notch in a raised rim, above the ground, is no crack: it
    // cannot be the depth)
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

    /// Cracks low in the soil are not the ground's surface: the row on the floor of the box
    /// pulled 2.1 spacings below the rest (a gap the raster sees as solid, which used to end the
    /// walk and read the crater as deep as the box), and a crack 4 spacings tall across the
    /// whole soil that reaches the box's side walls (open only through the margins beyond them,
    /// where the ground is taken to go on). Lifted particles 2.2 spacings over the ground's top
    /// are still not ground.
    #[test]
    fn cracks_in_the_soil_and_a_row_off_the_floor_do_not_end_the_ground() {
        let ds = 0.01;
        let soil0 = lattice(ds, 1.0, 1.0, &|_, _| false);
        let bowl = |x: f64, y: f64| (x - 0.5).abs() < 0.1 && y > 0.9;
        let (mut x1, mut y1) = lattice(ds, 1.0, 1.0, &bowl);
        for y in y1.iter_mut() {
            // the floor row stays, everything above rises by 1.1 ds; above y = 0.4 by 4 ds more
            if *y > 0.01 {
                *y += 0.011;
            }
            if *y > 0.4 {
                *y += 0.04;
            }
        }
        // and a few lifted particles over the ground outside the bowl
        for k in 0..5 {
            x1.push(0.105 + 0.01 * k as f64);
            y1.push(1.051 + 0.022);
        }
        let inp = CraterInput { soil0, soil1: (x1, y1), charge0: (Vec::new(), Vec::new()) };
        let c = measure_xy(&inp, ds).unwrap();
        // the bowl's floor rose with the soil by 5.1 ds: 10 − 5.1 = 4.9 cm deep
        assert!((c.depth_m - 0.049).abs() < 1e-9, "depth {}", c.depth_m);
        assert!((c.diameter_m - 0.20).abs() < 1e-9, "diameter {}", c.diameter_m);
        let k = c.columns_m.iter().position(|x| (x - 0.125).abs() < 1e-9).unwrap();
        assert!((c.surface_m[k] - 1.046).abs() < 1e-9, "lifted particles read as ground: {}", c.surface_m[k]);
    }

    /// The crater of a flat lattice of soil `w` × `hgt` m (spacing `ds`) whose particles `cut`
    /// removes later, without an explosive.
    fn measure_cut(ds: f64, w: f64, hgt: f64, cut: &dyn Fn(f64, f64) -> bool) -> Crater {
        let inp = CraterInput {
            soil0: lattice(ds, w, hgt, &|_, _| false),
            soil1: lattice(ds, w, hgt, cut),
            charge0: (Vec::new(), Vec::new()),
        };
        measure_xy(&inp, ds).unwrap()
    }

    /// A 2D crater that reaches the soil's first or last column (not a mirror wall there), or
    /// whose floor reaches the soil's bottom, is named as the box's measure, a lower bound.
    #[test]
    fn a_crater_the_box_ends_is_named() {
        let ds = 0.05;
        let measure = |cut: &dyn Fn(f64, f64) -> bool| measure_cut(ds, 1.0, 0.5, cut);
        let text =
            std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/cases/surface_loose_tnt6.toml")).unwrap();
        let plane = crate::case::parse(&text, "test", &[], None).unwrap();
        // a bowl inside the box
        let c = measure(&|x, y| (x - 0.5).abs() < 0.2 && y > 0.35);
        assert!(c.note.is_none() && box_bound(&plane, &c, None).is_none(), "{c:?}");
        // a bowl across the whole box: its width is the box's
        let c = measure(&|_, y| y > 0.35);
        let b = box_bound(&plane, &c, None).unwrap_or_else(|| panic!("{c:?}"));
        assert!(
            b.contains("x = 0.000 m") && b.contains("x = 1.000 m") && b.contains("diameter is a lower bound"),
            "{b}"
        );
        // a bowl down to the soil's bottom row
        let c = measure(&|x, y| (x - 0.5).abs() < 0.3 && y > 0.05);
        let b = box_bound(&plane, &c, None).unwrap_or_else(|| panic!("{c:?}"));
        assert!(
            b.starts_with("the crater's floor reaches the soil's bottom (y = 0.000 m)")
                && b.contains("depth is a lower bound"),
            "{b}"
        );
        // a half model: the edge at x = 0 is a mirror wall (a symmetry plane), not the box
        let half = crate::case::parse(
            &text.replacen(
                "[[wall]]\nfrom_m = [0.0, 1.0]\nto_m = [0.0, 0.0]",
                "[[wall]]\nfrom_m = [0.0, 1.0]\nto_m = [0.0, 0.0]\nkind = \"mirror\"",
                1,
            ),
            "test",
            &[],
            None,
        )
        .unwrap();
        let c = measure(&|x, y| x < 0.4 && y > 0.35);
        assert!(c.touches[0] && box_bound(&half, &c, None).is_none(), "{c:?}");
        assert!(box_bound(&plane, &c, None).is_some());
    }

    /// A 3D crater that reaches the surface map's border names the sides, and says where a
    /// wall of the case stands there (the shipped quarter's far walls; their images across the
    /// symmetry planes at the map's other border).
    #[test]
    fn a_3d_crater_at_the_map_border_names_the_side_and_its_wall() {
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/cases/surface_loose_tnt1kg_3d.toml"))
            .unwrap();
        let case = crate::case::parse(&text, "test", &[], None).unwrap();
        let (n, cell) = (12usize, 0.092);
        let centres: Vec<f64> = (0..n).map(|i| -0.552 + (i as f64 + 0.5) * cell).collect();
        let mut cells = vec![false; n * n];
        cells[5 * n + n - 1] = true; // the row through the axis, the last column (x = 0.552 m)
        cells[5 * n + 5] = true;
        let map = SurfaceMap {
            cell_m: cell,
            cells: [n, n],
            x_m: centres.clone(),
            y_m: centres,
            crater_cells: cells,
            ..Default::default()
        };
        let c = Crater { columns_m: vec![0.0, 0.092], column_m: 0.092, ..Default::default() };
        let b = box_bound(&case, &c, Some(&map)).unwrap_or_else(|| panic!("a crater at the border"));
        assert!(b.contains("x = 0.552 m, where a wall of the case stands") && b.contains("widen the soil"), "{b}");
        // the first column (x = -0.552 m): the wall's image in the symmetry plane x = 0
        let mut first = vec![false; n * n];
        first[5 * n] = true;
        let b = box_bound(&case, &c, Some(&SurfaceMap { crater_cells: first, ..map.clone() })).unwrap();
        assert!(b.contains("x = -0.552 m, where a wall of the case stands"), "{b}");
        // inside the map: no bound
        let mut inner = vec![false; n * n];
        inner[5 * n + 5] = true;
        assert!(box_bound(&case, &c, Some(&SurfaceMap { crater_cells: inner, ..map })).is_none());
    }

    /// A one-column crack 30 spacings deep beside a bowl 10 deep (a buried charge's RZ run, in a
    /// docs-only check: the depth read the crack) is left out of the depth and named; a crack
    /// alone is no crater, nor is a hole narrower than it is deep (a vent through the dome), nor
    /// a notch in a raised rim.
    #[test]
    fn cracks_and_vents_are_not_the_crater() {
        let ds = 0.01;
        let soil0 = lattice(ds, 1.0, 1.0, &|_, _| false);
        let measure = |cut: &dyn Fn(f64, f64) -> bool| measure_cut(ds, 1.0, 1.0, cut);
        let bowl = |x: f64, y: f64| (x - 0.5).abs() < 0.2 && y > 0.9;
        let crack = |x: f64, y: f64| (x - 0.555).abs() < 0.005 && y > 0.6;
        let c = measure(&|x, y| bowl(x, y) || crack(x, y));
        assert!((c.depth_m - 0.10).abs() < 1e-9 && (c.diameter_m - 0.40).abs() < 1e-9, "{c:?}");
        assert!(c.note.is_none());
        let k = c.crack.as_deref().unwrap_or_else(|| panic!("{c:?}"));
        assert!(k.contains("1.0 cm wide centred at 55.5 cm") && k.contains("drops 40.0 cm"), "{k}");
        // the crack alone: no crater, and the crack named
        let c = measure(&crack);
        assert_eq!((c.depth_m, c.diameter_m), (0.0, 0.0), "{c:?}");
        assert!(c.note.is_some() && c.crack.is_some(), "{c:?}");
        // a gap of one column 1 spacing deep: no bowl
        let c = measure(&|x, y| (x - 0.555).abs() < 0.005 && y > 0.99);
        assert_eq!((c.depth_m, c.diameter_m), (0.0, 0.0), "{c:?}");
        assert!(c.note.as_deref().is_some_and(|n| n.contains("one column")), "{c:?}");
        // a vent 4 columns wide and 30 deep
        let c = measure(&|x, y| (x - 0.5).abs() < 0.02 && y > 0.7);
        assert_eq!((c.depth_m, c.diameter_m), (0.0, 0.0), "{c:?}");
        assert!(c.note.as_deref().is_some_and(|n| n.contains("narrower than it is deep")), "{c:?}");
        // a bowl with a 2-column dip of one spacing at its floor (within 2 spacings of the columns
        // beside it) is the bowl, read at its deepest
        let c = measure(&|x, y| bowl(x, y) || ((x - 0.5).abs() < 0.01 && y > 0.885));
        assert!((c.depth_m - 0.11).abs() < 1e-9 && c.crack.is_none(), "{c:?}");
        // a rim raised 5 cm beside the bowl with a notch one column wide raised only 1 cm: above
        // the original ground, no crack (it was named, "drops -1.0 cm")
        let (mut x1, mut y1) = lattice(ds, 1.0, 1.0, &bowl);
        for i in 70..90 {
            let x = (i as f64 + 0.5) * ds;
            let rows = if i == 80 { 1 } else { 5 };
            for j in 0..rows {
                x1.push(x);
                y1.push(1.0 + (j as f64 + 0.5) * ds);
            }
        }
        let inp = CraterInput { soil0: soil0.clone(), soil1: (x1, y1), charge0: (Vec::new(), Vec::new()) };
        let c = measure_xy(&inp, ds).unwrap();
        assert!((c.depth_m - 0.10).abs() < 1e-9 && c.crack.is_none(), "{c:?}");
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

    /// A block of soil points on a lattice of spacing `ds` (x, y in [lo ds, 30 ds], z in
    /// [0, nz ds]), less the points `cut` removes.
    fn block3(ds: f64, lo: i32, nz: i32, cut: &dyn Fn([f64; 3]) -> bool) -> Vec<[f64; 3]> {
        let mut v = Vec::new();
        for k in 0..nz {
            for j in lo..30 {
                for i in lo..30 {
                    let p = [(i as f64 + 0.5) * ds, (j as f64 + 0.5) * ds, (k as f64 + 0.5) * ds];
                    if !cut(p) {
                        v.push(p);
                    }
                }
            }
        }
        v
    }

    #[test]
    fn a_quarter_in_revolution_reads_the_ground_over_the_charge_pit_on_the_axis() {
        // a quarter x, y > 0 of ground at z = 0.4 with a 6 x 6 x 4 cm pit about the axis holding
        // a charge (its nearest particles Δs/√2 from the axis), later a round bowl 12 cm in radius
        // and 10 cm deep: measured in revolution (r, z) about the axis, completed through it, the
        // depth is the bowl's against the ground, not against the pit's floor (before the pit
        // test took the column's ±Δs band, the column on the axis kept the floor, z = 0.355)
        let ds = 0.01;
        let pit = |p: [f64; 3]| p[0].abs() < 0.03 && p[1].abs() < 0.03 && p[2] > 0.36;
        let bowl = |p: [f64; 3]| (p[0].hypot(p[1]) / 0.12).powi(2) + ((p[2] - 0.4) / 0.1).powi(2) < 1.0;
        let rz = |pts: Vec<[f64; 3]>| -> (Vec<f64>, Vec<f64>) {
            pts.iter().map(|p| about_axis((0.0, 0.0), p[0], p[1], p[2])).unzip()
        };
        let charge: Vec<[f64; 3]> = (0..4)
            .flat_map(|k| (0..3).flat_map(move |j| (0..3).map(move |i| (i, j, k))))
            .map(|(i, j, k)| [(i as f64 + 0.5) * ds, (j as f64 + 0.5) * ds, 0.36 + (k as f64 + 0.5) * ds])
            .collect();
        // one more soil particle, deep and far out at r = 45 Δs: the columns then lie centred on
        // whole multiples of Δs from the axis, one centred on the axis itself, with no charge
        // particle within Δs/2 of its centre (as on the 3D case's quarter lattice)
        let with_far = |mut v: Vec<[f64; 3]>| {
            v.push([45.0 * ds, 0.0, 0.5 * ds]);
            v
        };
        let inp = CraterInput {
            soil0: rz(with_far(block3(ds, 0, 40, &pit))),
            soil1: rz(with_far(block3(ds, 0, 40, &bowl))),
            charge0: rz(charge),
        }
        .through_the_axis();
        let c = measure_xy(&inp, ds).unwrap();
        let k = c.columns_m.iter().position(|x| x.abs() < 1e-9).expect("a column centred on the axis");
        assert!((c.surface0_m[k] - 0.395).abs() < 1e-9, "original ground on the axis {}", c.surface0_m[k]);
        assert!((c.depth_m - 0.10).abs() <= ds, "depth {} (the bowl's 0.10)", c.depth_m);
        // (the bowl's floor is nearly flat: its deepest column lies within a few cells of the axis)
        assert!(c.centre_m.abs() <= 4.0 * ds, "deepest column {} from the axis", c.centre_m);
        assert!((c.diameter_m - 0.24).abs() <= 2.0 * ds, "diameter {}", c.diameter_m);
    }

    #[test]
    fn a_3d_crater_is_measured_as_a_surface_and_a_quarter_is_completed() {
        // t = 0: ground at z = 0.4 with a pit 6 x 6 cm and 4 cm deep about the axis x = y = 0,
        // holding a charge; later an elliptic bowl (semi-axes 15 cm along x, 8 cm along y, 10 cm
        // deep); the whole block, and its quarter x, y > 0 with the symmetry planes x = 0, y = 0
        let ds = 0.01;
        let pit = |p: [f64; 3]| p[0].abs() < 0.03 && p[1].abs() < 0.03 && p[2] > 0.36;
        let bowl = |p: [f64; 3]| (p[0] / 0.15).powi(2) + (p[1] / 0.08).powi(2) + ((p[2] - 0.4) / 0.1).powi(2) < 1.0;
        let charge = |lo: i32| -> Vec<[f64; 3]> {
            (0..4)
                .flat_map(|k| (lo..3).flat_map(move |j| (lo..3).map(move |i| (i, j, k))))
                .map(|(i, j, k)| [(i as f64 + 0.5) * ds, (j as f64 + 0.5) * ds, 0.36 + (k as f64 + 0.5) * ds])
                .collect()
        };
        let map = |lo: i32, mirrors: &[(usize, f64)]| {
            surface_map(
                (0.0, 0.0),
                ds,
                mirrors,
                &block3(ds, lo, 40, &pit),
                &block3(ds, lo, 40, &bowl),
                &charge(lo / 10),
            )
            .unwrap()
        };
        let whole = map(-30, &[]);
        let quarter = map(0, &[(0, 0.0), (1, 0.0)]);
        assert_eq!(whole.cells, [60, 60]);
        assert_eq!(quarter.cells, whole.cells);
        // the quarter's deepest cell is one of its own (x, y > 0), not an image; the bowl's
        // floor is flat over the four cells about the axis: one of those
        assert!(quarter.deepest_m[0] > 0.0 && quarter.deepest_m[1] > 0.0, "{:?}", quarter.deepest_m);
        assert!(quarter.deepest_m[0].hypot(quarter.deepest_m[1]) < ds, "{:?}", quarter.deepest_m);
        for (a, b) in [
            (whole.depth_m, quarter.depth_m),
            (whole.volume_m3, quarter.volume_m3),
            (whole.plan_area_m2, quarter.plan_area_m2),
            (whole.radius_min_m, quarter.radius_min_m),
            (whole.radius_max_m, quarter.radius_max_m),
        ] {
            assert!((a - b).abs() < 1e-12, "whole {whole:?}\nquarter {quarter:?}");
        }
        // the original ground over the charge's pit is the ground beside it (top particles at
        // z = 0.395), not the pit's floor
        let k = whole.x_m.iter().position(|x| (x - 0.005).abs() < 1e-9).unwrap() + 60 * 30;
        assert!((whole.surface0_m[k] - 0.395).abs() < 1e-9, "{}", whole.surface0_m[k]);
        // against the ellipsoid: depth 10 cm within a cell; volume (2/3) pi a b c = 2.513 L
        // within 1 % and plan area pi a b = 377 cm2 within 2 % (measured: 2.512 L, 376 cm2:
        // the lattice's columns count the removed particles, unbiased; the area's staircase
        // on a rim of 75 cm at 1 cm cancels to 0.3 %); the edge from the axis 8 and 15 cm
        // within a cell (measured 7.9 and 15.1 cm)
        let c = &whole;
        assert!(c.note.is_none(), "{c:?}");
        assert!((c.depth_m - 0.10).abs() <= ds, "depth {}", c.depth_m);
        // (the deepest of the cells 10 cm deep: one where the bowl is more than 9 cm deep)
        assert!((c.deepest_m[0] / 0.15).powi(2) + (c.deepest_m[1] / 0.08).powi(2) < 0.19, "{:?}", c.deepest_m);
        let v = 2.0 / 3.0 * std::f64::consts::PI * 0.15 * 0.08 * 0.1;
        assert!((c.volume_m3 / v - 1.0).abs() < 0.01, "volume {} against {v}", c.volume_m3);
        let a = std::f64::consts::PI * 0.15 * 0.08;
        assert!((c.plan_area_m2 / a - 1.0).abs() < 0.02, "area {} against {a}", c.plan_area_m2);
        assert!((c.equivalent_diameter_m - 2.0 * (0.15f64 * 0.08).sqrt()).abs() < 0.01, "{}", c.equivalent_diameter_m);
        assert!((c.radius_min_m - 0.08).abs() <= ds, "radius min {}", c.radius_min_m);
        assert!((c.radius_max_m - 0.15).abs() <= ds, "radius max {}", c.radius_max_m);
        // the quarter without its images: a quarter of the bowl, its edge 0 from the axis
        // towards -x and -y
        let alone = map(0, &[]);
        assert!((alone.plan_area_m2 - 0.25 * c.plan_area_m2).abs() < 0.1 * c.plan_area_m2, "{alone:?}");
        assert_eq!(alone.radius_min_m, 0.0);
    }

    #[test]
    fn the_relief_of_the_original_ground_about_the_charge_is_measured() {
        // the same bowl (semi-axes 15 cm, 10 cm deep) in level ground and in ground whose top
        // falls 30 cm per metre along +x beyond x = 0.1 m (a crest and a slope face)
        let ds = 0.01;
        let bowl = |p: [f64; 3]| p[0].hypot(p[1]).powi(2) / 0.0225 + ((p[2] - 0.4) / 0.1).powi(2) < 1.0;
        let slope = |p: [f64; 3]| p[2] > 0.4 - 0.3 * (p[0] - 0.1).max(0.0);
        let level =
            surface_map((0.0, 0.0), ds, &[], &block3(ds, -30, 40, &|_| false), &block3(ds, -30, 40, &bowl), &[])
                .unwrap();
        assert!(level.note.is_none() && level.ground_relief_m < 1e-12, "{level:?}");
        let s0 = block3(ds, -30, 40, &slope);
        let s1 = block3(ds, -30, 40, &|p| slope(p) || bowl(p));
        let sloped = surface_map((0.0, 0.0), ds, &[], &s0, &s1, &[]).unwrap();
        // within twice the edge (about 30 cm) of the axis the top falls from x = 0.1 to 0.3 m:
        // about 6 cm, a few cells (the lattice's staircase within a cell of it)
        assert!((sloped.ground_relief_m - 0.06).abs() <= ds, "relief {}", sloped.ground_relief_m);
        assert!(level.ground_is_level() && !sloped.ground_is_level());
    }

    #[test]
    fn a_3d_dome_over_a_cavity_is_ground_not_a_crater() {
        // a charge's hole 5 cm below the surface at t = 0 (top particles at z = 0.315); later a
        // cavity 12 x 12 x 6 cm under a dome two particles thick, raised by 2 cm: ground, not a
        // crater, and not ejecta over a crater
        let ds = 0.01;
        let near = |p: [f64; 3], w: f64, h: f64| p[0].abs() < w && p[1].abs() < w && (p[2] - 0.27).abs() < h;
        let soil0 = block3(ds, -20, 32, &|p| near(p, 0.03, 0.01));
        let mut soil1 = block3(ds, -20, 32, &|p| near(p, 0.06, 0.03));
        for p in soil1.iter_mut().filter(|p| p[0].abs() < 0.06 && p[1].abs() < 0.06 && p[2] > 0.3) {
            p[2] += 0.02;
        }
        let c = surface_map((0.0, 0.0), ds, &[], &soil0, &soil1, &[]).unwrap();
        assert!(c.note.as_deref().is_some_and(|n| n.contains("no apparent crater")), "{c:?}");
        assert_eq!((c.plan_area_m2, c.volume_m3, c.equivalent_diameter_m), (0.0, 0.0, 0.0));
        assert!((c.mound_height_m - 0.02).abs() < 1e-9, "the dome read as ground: {}", c.mound_height_m);
        // a vent through the dome over the cavity's centre opens it to the sky: a crater
        let vent: Vec<[f64; 3]> = soil1.iter().filter(|p| !(p[0].abs() < 0.02 && p[1].abs() < 0.02)).cloned().collect();
        let v = surface_map((0.0, 0.0), ds, &[], &soil0, &vent, &[]).unwrap();
        assert!(v.note.is_none() && v.depth_m > 0.05, "{v:?}");
        // a crack of one column, 4 cm deep, beside the dome is not a crater (a docs-only check's
        // 3D dome read as a crater 35 cm deep and 2.6 cm wide): no crater, depth 0, the note says
        // why
        let crack: Vec<[f64; 3]> =
            soil1.iter().filter(|p| !(p[0] == 0.155 && p[1] == 0.155 && p[2] > 0.28)).cloned().collect();
        let k = surface_map((0.0, 0.0), ds, &[], &soil0, &crack, &[]).unwrap();
        assert!(
            k.note.as_deref().is_some_and(|n| n.contains("crack or gap")),
            "{:?} {} {} {}",
            k.note,
            k.depth_m,
            k.plan_area_m2,
            k.cell_m
        );
        assert_eq!((k.depth_m, k.plan_area_m2, k.volume_m3), (0.0, 0.0, 0.0));
    }

    #[test]
    fn a_surface_map_of_positions_that_are_not_numbers_gives_a_reason() {
        let s0 = block3(0.01, 0, 10, &|_| false);
        let mut s1 = s0.clone();
        s1[5][2] = f64::NAN;
        let e = surface_map((0.0, 0.0), 0.01, &[], &s0, &s1, &[]).unwrap_err();
        assert!(e.contains("not finite"), "{e}");
        let e = surface_map((0.0, 0.0), 0.01, &[], &[], &[], &[]).unwrap_err();
        assert!(e.contains("no soil particles"), "{e}");
        let e = surface_map((0.0, 0.0), f64::NAN, &[], &s0, &s0, &[]).unwrap_err();
        assert!(e.contains("not a positive number"), "{e}");
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

    /// The charge's cavity is the void that holds its initial positions: a larger void the blast
    /// opened elsewhere (a gap at the box's floor) is not it.
    #[test]
    fn the_cavity_is_the_void_that_holds_the_charge() {
        let ds = 0.01;
        let hole = |x: f64, y: f64| (x - 0.35).abs() < 0.03 && (y - 0.45).abs() < 0.02;
        let soil0 = lattice(ds, 0.7, 0.62, &hole);
        // later: the charge's hole a little larger, and a wider gap low in the box, far off
        let gaps = |x: f64, y: f64| {
            ((x - 0.35).abs() < 0.04 && (y - 0.45).abs() < 0.03) || ((x - 0.6).abs() < 0.06 && (y - 0.1).abs() < 0.04)
        };
        let soil1 = lattice(ds, 0.7, 0.62, &gaps);
        let mut charge0 = (Vec::new(), Vec::new());
        for x in [0.335, 0.345, 0.355, 0.365] {
            for y in [0.435, 0.445, 0.455, 0.465] {
                charge0.0.push(x);
                charge0.1.push(y);
            }
        }
        let c = measure_xy(&CraterInput { soil0: soil0.clone(), soil1: soil1.clone(), charge0 }, ds).unwrap();
        let cav = c.cavity.expect("the charge's cavity");
        assert!((cav.centre_m[0] - 0.35).abs() < 0.011 && (cav.centre_m[1] - 0.45).abs() < 0.011, "{cav:?}");
        // a charge elsewhere (in no void): no cavity at all
        let away = (vec![0.1], vec![0.3]);
        let c = measure_xy(&CraterInput { soil0, soil1, charge0: away }, ds).unwrap();
        assert!(c.cavity.is_none(), "{:?}", c.cavity);
    }

    /// Soil whose width is an exact multiple of the spacing (0.552 m of 11.5 mm columns, whose
    /// quotient rounds to 48.00000000000001) has no void beside its last column when that column
    /// moves in a little under a particle thrown over the side (the raster had one column more,
    /// outside the soil, inside its margin: a void under that particle).
    #[test]
    fn a_box_of_whole_columns_has_no_void_beside_it() {
        let ds = 0.0115;
        let soil0 = lattice(ds, 0.552, 0.552, &|_, _| false);
        // the outer column drawn in by a third of a spacing (the soil at a box's free side)
        let mut soil1 = soil0.clone();
        for x in soil1.0.iter_mut().filter(|x| **x > 0.552 - ds) {
            *x -= 0.3 * ds;
        }
        // and a particle of the rim thrown out over the side, at the ground's level
        soil1.0.push(0.552 + 0.5 * ds);
        soil1.1.push(0.552 - 0.5 * ds);
        let c = measure_xy(&CraterInput { soil0, soil1, charge0: Default::default() }, ds).unwrap();
        assert!(c.cavity.is_none(), "{:?}", c.cavity);
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
