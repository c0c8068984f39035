//! The wall segments the boundary stages and the set-up read: 1D points, 2D lines, 3D planes,
//! each with its inward normal and the nodes it counts.

use crate::case::{Case, WallKind};
use super::WallFrame as Frame;
use crate::modules::param::Segments;

/// Wall segments of the kinds wanted, with inward normals (towards the particles' centroid) and
/// end-node flags (an end that is the start of another wall is not counted twice); 3D walls
/// (`plane_walls`); in axisymmetric geometry the axis r = 0 as a mirror (reflective ghosts),
/// after the case's walls, when mirrors are wanted.
pub fn segments(case: &Case, x: &[f64], keep: impl Fn(WallKind) -> bool) -> Segments {
    let d = case.dim;
    let n = x.len() / d;
    let mut cen = [0.0; 3];
    for i in 0..n {
        for a in 0..d {
            cen[a] += x[a + d * i] / n as f64;
        }
    }
    let mut segs = Segments::default();
    let walls: Vec<_> = case.walls.iter().filter(|w| keep(w.kind)).collect();
    if d == 3 {
        plane_walls(&walls, cen, &mut segs);
        return segs;
    }
    for w in &walls {
        let a = &w.from_m;
        let b = &w.to_m;
        let mut nrm = [0.0; 3];
        if d == 1 {
            nrm[0] = if cen[0] >= a[0] { 1.0 } else { -1.0 };
        } else {
            let (tx, ty) = (b[0] - a[0], b[1] - a[1]);
            let l = (tx * tx + ty * ty).sqrt();
            let (nx, ny) = (-ty / l, tx / l);
            let side = (cen[0] - a[0]) * nx + (cen[1] - a[1]) * ny;
            let sgn = if side >= 0.0 { 1.0 } else { -1.0 };
            nrm[0] = sgn * nx;
            nrm[1] = sgn * ny;
        }
        segs.seg.extend_from_slice(&a[..d]);
        segs.seg.extend_from_slice(&b[..d]);
        segs.seg.extend_from_slice(&nrm[..d]);
        let shared = walls.iter().any(|o| o.from_m.iter().zip(b).all(|(p, q)| (p - q).abs() < 1e-12));
        segs.endnode.push(if d == 1 || !shared { 1 } else { 0 });
    }
    if case.axisymmetric() && keep(WallKind::Mirror) && n > 0 {
        // the axis: a segment along x = 0 far beyond anything the particles can reach
        let (lo, hi) =
            (0..n).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), i| (a.min(x[1 + 2 * i]), b.max(x[1 + 2 * i])));
        let reach = 1e3 * (hi - lo).max(1.0);
        segs.seg.extend_from_slice(&[0.0, lo - reach, 0.0, hi + reach, 1.0, 0.0]);
        segs.endnode.push(1);
    }
    segs
}

/// The corners of a 3D wall: from_m, the corner after the first edge, and to_m.
pub fn corners(w: &crate::case::WallCfg) -> [[f64; 3]; 3] {
    let (a, b) = ([w.from_m[0], w.from_m[1], w.from_m[2]], [w.to_m[0], w.to_m[1], w.to_m[2]]);
    let e = match &w.edge_m {
        Some(e) => [e[0], e[1], e[2]],
        None => {
            // axis-aligned: the first edge along the first of the two axes in the wall's plane
            let ax = (0..3).find(|&k| a[k] != b[k]).unwrap_or(0);
            let mut e = a;
            e[ax] = b[ax];
            e
        }
    };
    [a, e, b]
}

/// 3D walls as `seg(12, nseg)`: corner a, edge vectors u = e − a and v = b − e, the unit normal
/// ±u×v towards the centroid `cen`; the edge mask of each wall: an edge that lies on an earlier
/// wall is that wall's (its nodes are not counted twice).
fn plane_walls(walls: &[&crate::case::WallCfg], cen: [f64; 3], segs: &mut Segments) {
    let frames: Vec<[[f64; 3]; 4]> = walls
        .iter()
        .map(|w| {
            let [a, e, b] = corners(w);
            let u = [e[0] - a[0], e[1] - a[1], e[2] - a[2]];
            let v = [b[0] - e[0], b[1] - e[1], b[2] - e[2]];
            let c = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
            let l = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
            let side = (0..3).map(|k| (cen[k] - a[k]) * c[k]).sum::<f64>();
            let sgn = if side >= 0.0 { 1.0 } else { -1.0 };
            [a, u, v, [sgn * c[0] / l, sgn * c[1] / l, sgn * c[2] / l]]
        })
        .collect();
    // is point p on wall t (in its plane, within its extent)?
    let on = |t: usize, p: [f64; 3]| -> bool {
        let [a, u, v, n] = frames[t];
        let r = [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
        let dot = |x: [f64; 3], y: [f64; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
        let (uu, vv) = (dot(u, u), dot(v, v));
        let tol = 1e-9 * (uu.sqrt() + vv.sqrt());
        dot(r, n).abs() <= tol
            && (-tol..=uu + tol * uu.sqrt()).contains(&dot(r, u))
            && (-tol..=vv + tol * vv.sqrt()).contains(&dot(r, v))
    };
    for (s, &[a, u, v, n]) in frames.iter().enumerate() {
        segs.seg.extend_from_slice(&a);
        segs.seg.extend_from_slice(&u);
        segs.seg.extend_from_slice(&v);
        segs.seg.extend_from_slice(&n);
        let at = |su: f64, sv: f64| {
            [a[0] + su * u[0] + sv * v[0], a[1] + su * u[1] + sv * v[1], a[2] + su * u[2] + sv * v[2]]
        };
        // the four edges as (mask bit, its two ends): far along u, far along v, near u, near v
        let edges = [
            (1, at(1.0, 0.0), at(1.0, 1.0)),
            (2, at(0.0, 1.0), at(1.0, 1.0)),
            (4, at(0.0, 0.0), at(0.0, 1.0)),
            (8, at(0.0, 0.0), at(1.0, 0.0)),
        ];
        let mut mask = 0;
        for (bit, p, q) in edges {
            if !(0..s).any(|t| on(t, p) && on(t, q)) {
                mask |= bit;
            }
        }
        segs.endnode.push(mask);
    }
}

/// How far (m) the point `x` lies behind the line (plane, in 3D) of the wall `sg` (its first
/// point, then its frame `fr`), if it is behind it and within the wall's extent along it.
#[inline]
pub fn behind_wall(dim: usize, x: &[f64], sg: &[f64], fr: &Frame) -> Option<f64> {
    let (mut dn, mut tp, mut tp2) = (0.0, 0.0, 0.0);
    for d in 0..dim {
        let r = x[d] - sg[d];
        dn += r * fr.nrm[d];
        tp += r * fr.t[0][d];
        tp2 += r * fr.t[1][d];
    }
    let along = tp >= 0.0 && tp <= fr.el[0] && (dim < 3 || (tp2 >= 0.0 && tp2 <= fr.el[1]));
    (along && dn < 0.0).then_some(-dn)
}
