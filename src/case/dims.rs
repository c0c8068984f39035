//! Validation of what depends on the dimension and the geometry: the axisymmetric (RZ) geometry,
//! the round shapes (cylinder, sphere) and the 3D walls (planes). One-line errors naming the key.

use super::types::*;
use super::validate::{At, Checker, Range, X_MAX};
use crate::error::{Result, input};

/// A `cylinder` or `sphere` region: its centre, radius (and height) and optional clip box.
pub(super) fn round_shape(v: &mut Checker, at: &At, label: &str, r: &RegionCfg, d: usize) -> Result<()> {
    let what = if r.shape == Shape::Cylinder { "cylinder" } else { "sphere" };
    if r.shape == Shape::Cylinder && d != 3 {
        return Err(input(format!(
            "{label}: shape = \"cylinder\" needs dim = 3 (in 2D a cylinder's section is a box, plane or axisymmetric)"
        )));
    }
    if d < 2 {
        return Err(input(format!("{label}: shape = \"sphere\" needs dim = 2 or 3")));
    }
    let c = r.center_m.as_ref().ok_or_else(|| input(format!("{label}.center_m: required for shape = \"{what}\"")))?;
    v.vec(at, "center_m", c, d, Range::abs(X_MAX))?;
    let rad = r.radius_m.ok_or_else(|| input(format!("{label}.radius_m: required for shape = \"{what}\"")))?;
    v.num(at, "radius_m", rad, Range::above(0.0, X_MAX))?;
    if r.shape == Shape::Cylinder {
        let h = r.height_m.ok_or_else(|| input(format!("{label}.height_m: required for shape = \"cylinder\"")))?;
        v.num(at, "height_m", h, Range::above(0.0, X_MAX))?;
    } else if r.height_m.is_some() {
        return Err(input(format!("{label}.height_m: only a cylinder has a height")));
    }
    match (&r.lo_m, &r.hi_m) {
        (None, None) => Ok(()),
        (Some(lo), Some(hi)) => {
            v.vec(at, "lo_m", lo, d, Range::abs(X_MAX))?;
            v.vec(at, "hi_m", hi, d, Range::abs(X_MAX))?;
            match (0..d).find(|&a| hi[a] <= lo[a]) {
                Some(a) => Err(input(format!("{label}: hi_m[{a}] = {} must exceed lo_m[{a}] = {}", hi[a], lo[a]))),
                None => Ok(()),
            }
        }
        _ => Err(input(format!("{label}: the clip box of a {what} needs both lo_m and hi_m"))),
    }
}

/// A region's `keep_below` planes: `point_m` (m) and `normal` of `d` components each, finite,
/// the point within [`X_MAX`]; a normal that cannot be normalised, n̂ = n/|n| with
/// |n|² = Σ n_a², is refused: the zero vector, and one whose |n|² overflows or underflows.
pub(super) fn clip_planes(v: &mut Checker, at: &At, r: &RegionCfg, d: usize) -> Result<()> {
    v.any(at, "keep_below");
    for (k, c) in r.keep_below.iter().enumerate() {
        let pa = at.nested("keep_below", k);
        v.vec(&pa, "point_m", &c.point_m, d, Range::abs(X_MAX))?;
        v.vec(&pa, "normal", &c.normal, d, Range::FINITE)?;
        // |n|² as ClipPlane::signed_distance forms it
        let len2: f64 = c.normal.iter().map(|x| x * x).sum();
        let why = if c.normal.iter().all(|x| *x == 0.0) {
            "a zero vector has no direction (the normal points out of the kept side)"
        } else if !len2.is_finite() {
            "too long to normalise (its squared length overflows)"
        } else if !len2.is_normal() {
            "too short to normalise (its squared length underflows)"
        } else {
            continue;
        };
        let shown: Vec<String> = c.normal.iter().map(|x| super::validate::num_text(*x)).collect();
        return Err(input(format!("{}.normal = [{}]: {why}", pa.label(), shown.join(", "))));
    }
    Ok(())
}

/// A 3D wall: an axis-aligned rectangle (`from_m`, `to_m` opposite corners in a plane x, y or z =
/// const), or with `edge_m` a parallelogram.
pub(super) fn plane_wall(v: &mut Checker, k: usize, w: &WallCfg) -> Result<()> {
    let (a, b) = (&w.from_m, &w.to_m);
    let at = At::top("wall");
    match &w.edge_m {
        Some(e) => {
            v.vec(&at, "edge_m", e, 3, Range::abs(X_MAX))?;
            let u: Vec<f64> = (0..3).map(|d| e[d] - a[d]).collect();
            let q: Vec<f64> = (0..3).map(|d| b[d] - e[d]).collect();
            let n = [u[1] * q[2] - u[2] * q[1], u[2] * q[0] - u[0] * q[2], u[0] * q[1] - u[1] * q[0]];
            let len = |x: &[f64]| x.iter().map(|c| c * c).sum::<f64>().sqrt();
            if len(&u) == 0.0 || len(&q) == 0.0 || len(&n) <= 1e-9 * len(&u) * len(&q) {
                return Err(input(format!(
                    "wall[{k}]: from_m, edge_m and to_m must be three corners of a parallelogram (two edges that are not parallel)"
                )));
            }
            Ok(())
        }
        None => {
            let same = (0..3).filter(|&d| a[d] == b[d]).count();
            if same != 1 {
                return Err(input(format!(
                    "wall[{k}]: a 3D wall without edge_m is an axis-aligned rectangle: from_m and to_m are opposite corners and differ in exactly two coordinates"
                )));
            }
            Ok(())
        }
    }
}

/// The checks of `geometry = "axisymmetric"`.
pub(super) fn geometry(c: &Case, v: &mut Checker) -> Result<()> {
    v.any(&At::top(""), "geometry");
    if !c.axisymmetric() {
        return Ok(());
    }
    if c.dim != 2 {
        return Err(input(format!("geometry = \"axisymmetric\" needs dim = 2 (x = r, y = z), got dim = {}", c.dim)));
    }
    let neg = |key: String, x: f64| -> Result<()> {
        if x < 0.0 {
            Err(input(format!("{key} = {x}: in axisymmetric geometry x is the radius r >= 0")))
        } else {
            Ok(())
        }
    };
    for (k, r) in c.regions.iter().enumerate() {
        let key = format!("region[{k}] ({})", r.name);
        match r.shape {
            Shape::Box => neg(format!("{key}.lo_m[0]"), r.lo_m.as_ref().map_or(0.0, |v| v[0]))?,
            Shape::Lattice => {
                let x0 = r.origin_m.as_ref().map_or(0.0, |v| v[0]);
                neg(format!("{key}.origin_m[0]"), x0)?;
                if x0 == 0.0 {
                    return Err(input(format!(
                        "{key}.origin_m[0] = 0: the lattice's first column lies on the axis r = 0, rings of zero mass in axisymmetric geometry: start it half a spacing off the axis"
                    )));
                }
            }
            Shape::Polygon => {
                for (q, p) in r.vertices_m.iter().flatten().enumerate() {
                    neg(format!("{key}.vertices_m[{q}][0]"), p[0])?;
                }
            }
            // a disc about a centre at r < 0 revolves into a lens, not a sphere: the sign
            // slip of a centre gave a charge a fifth of the sphere's mass, silently
            Shape::Sphere => {
                if let Some(cm) = &r.center_m
                    && cm[0] < 0.0
                {
                    return Err(input(format!(
                        "{key}.center_m[0] = {}: in axisymmetric geometry x is the radius r >= 0 (a sphere is centred on the axis, r = 0; a centre at r > 0 revolves into a torus)",
                        cm[0]
                    )));
                }
            }
            Shape::Cylinder => {}
        }
        if r.mass_kg.is_some() {
            return Err(input(format!(
                "{key}.mass_kg: not in axisymmetric geometry (each particle is a ring of mass 2 pi r rho dx^2)"
            )));
        }
    }
    if let Some(g) = &c.physics.gravity_ms2
        && g[0] != 0.0
    {
        return Err(input("physics.gravity_ms2: in axisymmetric geometry gravity is along the axis: [0, g_z]"));
    }
    for (k, w) in c.walls.iter().enumerate() {
        neg(format!("wall[{k}].from_m[0]"), w.from_m[0])?;
        neg(format!("wall[{k}].to_m[0]"), w.to_m[0])?;
        if w.from_m[0] == 0.0 && w.to_m[0] == 0.0 {
            return Err(input(format!(
                "wall[{k}]: lies on the axis r = 0, which is a mirror already in axisymmetric geometry"
            )));
        }
    }
    if let Some(d) = &c.detonation
        && let Some(p) = &d.point_m
    {
        neg("detonation.point_m[0]".into(), p[0])?;
    }
    for (k, g) in c.gauges.iter().enumerate() {
        neg(format!("gauge[{k}].point_m[0]"), g.point_m[0])?;
    }
    Ok(())
}
