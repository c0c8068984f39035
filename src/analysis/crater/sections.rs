//! The 3D crater: its axis, the symmetry planes the charge abuts, vertical sections through the
//! axis and the ground's height as a surface map.

use super::*;

/// The vertical axis (x, y) a 3D crater is measured about (z up): the detonation point's, else
/// the centroid of the explosive's initial positions `charge_xy`, put on every symmetry plane
/// the charge abuts ([`charge_planes`]: the whole charge's centroid lies there, not the modelled
/// half's).
pub(crate) fn axis_3d(case: &crate::case::Case, charge_xy: &[(f64, f64)]) -> Result<(f64, f64), String> {
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
pub(crate) fn charge_planes<P: AsRef<[f64]>>(case: &crate::case::Case, pts: &[P]) -> Vec<(usize, f64)> {
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
pub(crate) fn about_axis(ax: (f64, f64), x: f64, y: f64, z: f64) -> (f64, f64) {
    ((x - ax.0).hypot(y - ax.1), z)
}

/// The symmetry planes of a 3D case that a crater about the vertical axis `ax` is completed
/// across: its `mirror` walls that are vertical, axis-aligned (x = c or y = c) and pass within
/// `ds` of the axis, as (0 for x, 1 for y; c in m). A mirror wall away from the axis is a rigid
/// free-slip wall beside the crater, not a plane the scene is the half of.
pub(crate) fn mirror_planes(case: &crate::case::Case, ax: (f64, f64), ds: f64) -> Vec<(usize, f64)> {
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
pub(super) fn with_images(pts: &[[f64; 3]], mirrors: &[(usize, f64)]) -> Vec<[f64; 3]> {
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
pub(crate) fn sections_3d(
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
pub(crate) fn surface_map(
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
    fill_pits_3d(&mut s0, &c0, (&lo, ds, nc));
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

/// Over a charge in a pit of the ground, the original height `s0` of a cell from the nearest
/// square ring of cells with no explosive above them (grid from `lo`, cells `ds` wide, `nc`
/// per axis; the charge's initial positions `c0`).
fn fill_pits_3d(s0: &mut [f64], c0: &[[f64; 3]], (lo, ds, nc): (&[f64; 2], f64, [usize; 2])) {
    let (nx, ny) = (nc[0], nc[1]);
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
    for p in c0 {
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
    let base = s0.to_vec();
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
}
