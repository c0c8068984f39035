//! The checks of a case that need its particles (run once they are generated, before the solver
//! takes them): every particle on the inner side of every wall and inside `[domain]`, the
//! detonation point inside a charge, every gauge in the material (or at least near it) and inside
//! `[domain]`. Errors are one line naming the key and the place.

use super::Initial;
use crate::case::{BurnMode, Case, EosCfg, GaugeKind};
use crate::error::{Result, input};

fn at(x: &[f64]) -> String {
    let c: Vec<String> = x.iter().map(|v| format!("{v:.6}")).collect();
    format!("[{}]", c.join(", "))
}

/// The checks above, on the particles `init` generated from `case`.
pub fn check(case: &Case, init: &Initial) -> Result<()> {
    let d = case.dim;
    let n = init.mass.len();
    let region_of = |i: usize| {
        let r = init.region[i] as usize;
        format!("region[{r}] ({})", case.regions[r].name)
    };
    if let Some(dm) = &case.domain
        && let Some(i) =
            (0..n).find(|&i| (0..d).any(|a| init.x[a + d * i] < dm.lo_m[a] || init.x[a + d * i] > dm.hi_m[a]))
    {
        return Err(input(format!(
            "{}: a particle at {} m lies outside [domain] {} .. {} m",
            region_of(i),
            at(&init.x[d * i..d * i + d]),
            at(&dm.lo_m),
            at(&dm.hi_m)
        )));
    }
    // a ring on the axis has no mass (m = 2 pi r rho dx^2)
    if case.axisymmetric()
        && let Some(i) = (0..n).find(|&i| init.x[d * i] <= 0.0)
    {
        return Err(input(format!(
            "{}: a particle at {} m lies on the axis r = 0, a ring of zero mass in axisymmetric geometry: start the region half a spacing off the axis (a `box` from r = 0 puts its first column at dx/2)",
            region_of(i),
            at(&init.x[d * i..d * i + d])
        )));
    }
    // the walls face the particles' centroid; a particle behind one (within its extent) is
    // outside the walls or cut by them
    let segs = super::segments(case, &init.x, |_| true);
    for s in 0..segs.len() {
        let sg = segs.get(d, s);
        let fr = crate::modules::boundary::frame(d, sg);
        if let Some(i) = (0..n).find(|&i| {
            crate::modules::boundary::walls::behind_wall(d, &init.x[d * i..d * i + d], sg, &fr).is_some_and(|b| b > 0.0)
        }) {
            return Err(input(format!(
                "{}: a particle at {} m lies behind wall[{s}] ({} to {} m; a wall's inner side faces the particles' centroid): the region crosses the wall or lies outside it",
                region_of(i),
                at(&init.x[d * i..d * i + d]),
                case.walls.get(s).map_or("[0, -inf]".to_string(), |w| at(&w.from_m)),
                case.walls.get(s).map_or("[0, +inf] (the axis)".to_string(), |w| at(&w.to_m))
            )));
        }
    }
    let dist = |i: usize, p: &[f64]| -> f64 {
        (0..d).map(|a| (init.x[a + d * i] - p[a]) * (init.x[a + d * i] - p[a])).sum::<f64>().sqrt()
    };
    if let Some(det) = &case.detonation
        && det.mode == BurnMode::Programmed
        && let Some(p) = &det.point_m
    {
        let jwl: Vec<bool> = case.materials.iter().map(|m| matches!(m.eos, EosCfg::Jwl { .. })).collect();
        // the nearest explosive particle, in units of its region's spacing
        let near = (0..n)
            .filter(|&i| jwl[init.mat[i] as usize])
            .map(|i| (dist(i, p) / case.regions[init.region[i] as usize].spacing_m, i))
            .fold(None, |m: Option<(f64, usize)>, q| if m.is_none_or(|m| q.0 < m.0) { Some(q) } else { m });
        match near {
            None => {
                return Err(input("detonation: no region is of a material with eos kind = \"jwl\" (nothing to light)"));
            }
            Some((r, i)) if r > 1.0 => {
                return Err(input(format!(
                    "detonation.point_m = {}: outside every charge (the nearest explosive particle, of {}, is {:.3e} m away: {r:.1} spacings; the point must lie within one spacing of a charge's particle)",
                    at(p),
                    region_of(i),
                    dist(i, p)
                )));
            }
            Some(_) => {}
        }
    }
    if n == 0 {
        return Ok(());
    }
    let kappa = case.sph.kernel.support();
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    let hmax = init.h.iter().fold(0.0f64, |m, h| m.max(*h));
    for i in 0..n {
        for a in 0..d {
            lo[a] = lo[a].min(init.x[a + d * i]);
            hi[a] = hi[a].max(init.x[a + d * i]);
        }
    }
    for (k, g) in case.gauges.iter().enumerate() {
        let key = format!("gauge[{k}] ({}).point_m = {}", g.name, at(&g.point_m));
        if let Some(dm) = &case.domain
            && (0..d).any(|a| g.point_m[a] < dm.lo_m[a] || g.point_m[a] > dm.hi_m[a])
        {
            return Err(input(format!("{key}: outside [domain] {} .. {} m", at(&dm.lo_m), at(&dm.hi_m))));
        }
        match g.kind {
            GaugeKind::Particle => {
                // the particle it follows must have the point within its kernel's reach
                let (r, i) = (0..n)
                    .map(|i| (dist(i, &g.point_m), i))
                    .fold((f64::INFINITY, 0), |m, q| if q.0 < m.0 { q } else { m });
                if r > kappa * init.h[i] {
                    return Err(input(format!(
                        "{key}: no particle there (the nearest, of {}, is {r:.3e} m away, beyond its kernel's reach {:.3e} m): a particle gauge must lie in the material",
                        region_of(i),
                        kappa * init.h[i]
                    )));
                }
            }
            GaugeKind::Point => {
                let reach = kappa * hmax;
                if let Some(a) = (0..d).find(|&a| g.point_m[a] < lo[a] - reach || g.point_m[a] > hi[a] + reach) {
                    return Err(input(format!(
                        "{key}: outside the particles' extent on axis {a} ({}): a point gauge may lie from {:.6} to {:.6} m (the particles' {:.6} .. {:.6} m and the kernel's reach {reach:.3e} m beyond)",
                        ["x", "y", "z"][a],
                        lo[a] - reach,
                        hi[a] + reach,
                        lo[a],
                        hi[a]
                    )));
                }
            }
        }
    }
    Ok(())
}
