//! The checks of the regions (shapes, spacings, materials, overlaps) and of the walls.

use super::*;

impl Case {
    pub(super) fn validate_regions(&self, v: &mut Checker) -> Result<()> {
        if self.regions.is_empty() {
            return Err(input("no [[region]]: a case needs at least one region of particles"));
        }
        let d = self.dim;
        let mut names = BTreeSet::new();
        for (k, r) in self.regions.iter().enumerate() {
            let at = At::entry("region", k, &r.name);
            v.name(&at, "name", &r.name)?;
            if !names.insert(r.name.as_str()) {
                return Err(input(format!("{}: the name is used twice", at.label)));
            }
            let mi = self.material_index(&r.material).ok_or_else(|| {
                input(format!(
                    "{}.material = \"{}\": no [[material]] of that name (a material needs an eos)",
                    at.label,
                    shown(&r.material)
                ))
            })?;
            v.any(&at, "material");
            v.any(&at, "shape");
            v.num(&at, "spacing_m", r.spacing_m, Range::above(0.0, X_MAX))?;
            let reach = shape_reach(v, &at, r, d)?;
            if r.spacing_m < SPACING_REL * reach {
                return Err(input(format!(
                    "{} = {:e}: too fine for coordinates of {reach:e} m (neighbouring particles would not be distinct in double precision; at least {:e})",
                    at.key("spacing_m"),
                    r.spacing_m,
                    SPACING_REL * reach
                )));
            }
            let mat = &self.materials[mi];
            let rho = match (r.rho_kgm3, mat.eos.rho0()) {
                (Some(x), _) => {
                    v.num(&at, "rho_kgm3", x, Range::within(RHO_MIN, RHO_MAX))?;
                    x
                }
                (None, Some(x)) => x,
                (None, None) => {
                    return Err(input(format!(
                        "{}: required (material `{}` has no rho0_kgm3)",
                        at.key("rho_kgm3"),
                        shown(&r.material)
                    )));
                }
            };
            v.opt(&at, "e_jkg", r.e_jkg, Range::within(0.0, E_MAX))?;
            if let Some(vel) = &r.velocity_ms {
                v.vec(&at, "velocity_ms", vel, d, Range::abs(C_MAX))?;
            }
            v.opt(&at, "radial_velocity_ms", r.radial_velocity_ms, Range::abs(C_MAX))?;
            if let Some(c) = &r.radial_center_m {
                v.vec(&at, "radial_center_m", c, d, Range::abs(X_MAX))?;
            }
            if let Some(m) = r.mass_kg {
                v.num(&at, "mass_kg", m, Range::above(0.0, f64::MAX))?;
                // within a factor 1000 of ρ Δx^d (the lattice's own mass)
                let own = rho * r.spacing_m.powi(d as i32);
                let ratio = m / own;
                if !(1e-3..=1e3).contains(&ratio) {
                    return Err(input(format!(
                        "{} = {m:e}: {ratio:.3e} times rho Δx^d = {own:e} kg (must be within a factor 1000 of it)",
                        at.key("mass_kg")
                    )));
                }
            }
            if let Some(h) = r.h_m {
                v.num(&at, "h_m", h, Range::above(0.0, X_MAX))?;
                let ratio = h / r.spacing_m;
                if !(H_OVER_DX.0..=h_over_dx_max(d)).contains(&ratio) {
                    return Err(input(format!(
                        "{} = {h:e}: {ratio:.3e} spacings (h / spacing_m must be from {} to {} in {d}D)",
                        at.key("h_m"),
                        H_OVER_DX.0,
                        h_over_dx_max(d)
                    )));
                }
                let kappa = self.sph.kernel.support();
                if kappa * ratio <= 1.0 {
                    return Err(input(format!(
                        "{} = {h:e}: the kernel's support {kappa} h = {:e} m does not reach the next particle, {:e} m away: no particle of the region would have a neighbour of its own (h_m must be above {:e} m)",
                        at.key("h_m"),
                        kappa * h,
                        r.spacing_m,
                        r.spacing_m / kappa
                    )));
                }
            }
            crate::case::dims::clip_planes(v, &at, r, d)?;
            v.any(&at, "subtract");
            for s in &r.subtract {
                if !self.regions.iter().any(|q| &q.name == s) || s == &r.name {
                    return Err(input(format!("{}: no other region named `{}`", at.key("subtract"), shown(s))));
                }
            }
            v.any(&at, "boundary_particles");
            if r.boundary_particles == Some(crate::case::BoundaryKind::Held)
                && self.sph.smoothing == crate::case::SmoothingKind::Rate
            {
                return Err(input(format!(
                    "{} = \"held\" with sph.smoothing = \"rate\": dh/dt would change h while the leapfrog holds rho (use smoothing = \"constant\" or \"density\", or \"integrated\" particles)",
                    at.key("boundary_particles")
                )));
            }
        }
        Ok(())
    }

    pub(super) fn validate_walls(&self, v: &mut Checker) -> Result<()> {
        let d = self.dim;
        let dx_min = self.regions.iter().map(|r| r.spacing_m).fold(f64::INFINITY, f64::min);
        let spacing = self.boundary.wall_spacing_m.unwrap_or(0.25 * dx_min);
        for (k, w) in self.walls.iter().enumerate() {
            let at = At { path: "wall".into(), label: format!("wall[{k}]") };
            v.vec(&at, "from_m", &w.from_m, d, Range::abs(X_MAX))?;
            v.vec(&at, "to_m", &w.to_m, d, Range::abs(X_MAX))?;
            v.any(&at, "kind");
            if d == 3 {
                crate::case::dims::plane_wall(v, k, w)?;
            } else if w.edge_m.is_some() {
                return Err(input(format!("wall[{k}].edge_m: only 3D walls (planes) have one")));
            }
            if d == 1 && w.from_m != w.to_m {
                return Err(input(format!(
                    "wall[{k}].to_m: in 1D a wall is a point, to_m must equal from_m ({:?} against {:?})",
                    w.to_m, w.from_m
                )));
            }
            if d == 2 && w.from_m == w.to_m {
                return Err(input(format!("wall[{k}]: from_m and to_m coincide")));
            }
            // the type I force visits every wall node for every particle near the wall
            let len: f64 = w.from_m.iter().zip(&w.to_m).map(|(a, b)| (b - a) * (b - a)).sum::<f64>().sqrt();
            if w.kind.repels() && len / spacing > 1e6 {
                return Err(input(format!(
                    "wall[{k}]: {:.3e} wall particles (length {len:e} m / boundary.wall_spacing_m {spacing:e} m; at most 1e6)",
                    len / spacing
                )));
            }
        }
        let absorbing = self.walls.iter().any(|w| w.kind == WallKind::Absorbing);
        if let (Some(l), true) = (self.boundary.absorb_layer_m, absorbing && dx_min.is_finite())
            && l < dx_min
        {
            return Err(input(format!(
                "boundary.absorb_layer_m = {l:e}: thinner than the finest spacing ({dx_min:e} m), the layer of an absorbing wall would hold no particle"
            )));
        }
        if !self.walls.is_empty() && dx_min.is_finite() {
            let b = &self.boundary;
            for (key, val) in [("wall_spacing_m", b.wall_spacing_m), ("r0_m", b.r0_m)] {
                if let Some(x) = val
                    && !(1e-3..=1e3).contains(&(x / dx_min))
                {
                    return Err(input(format!(
                        "boundary.{key} = {x:e}: {:.3e} times the finest spacing {dx_min:e} m (must be within a factor 1000 of it)",
                        x / dx_min
                    )));
                }
            }
        }
        Ok(())
    }
}

/// The keys of a region's shape checked (a key of another shape refused): the largest
/// coordinate the region reaches (m), for the spacing's resolution.
fn shape_reach(v: &mut Checker, at: &At, r: &RegionCfg, d: usize) -> Result<f64> {
    let xr = Range::abs(X_MAX);
    // the largest coordinate of the region, for the spacing's resolution
    let mut reach = 0.0f64;
    let mut coords = |c: &[f64]| reach = c.iter().fold(reach, |m, x| m.max(x.abs()));
    // a key of another shape is a mistake (the shape would ignore it)
    let foreign: &[(&str, bool)] = &[
        ("lo_m", r.lo_m.is_some() && matches!(r.shape, Shape::Polygon | Shape::Lattice)),
        ("hi_m", r.hi_m.is_some() && matches!(r.shape, Shape::Polygon | Shape::Lattice)),
        ("vertices_m", r.vertices_m.is_some() && r.shape != Shape::Polygon),
        ("origin_m", r.origin_m.is_some() && r.shape != Shape::Lattice),
        ("count", r.count.is_some() && r.shape != Shape::Lattice),
        ("center_m", r.center_m.is_some() && !matches!(r.shape, Shape::Cylinder | Shape::Sphere)),
        ("radius_m", r.radius_m.is_some() && !matches!(r.shape, Shape::Cylinder | Shape::Sphere)),
        ("height_m", r.height_m.is_some() && !matches!(r.shape, Shape::Cylinder | Shape::Sphere)),
    ];
    if let Some((k, _)) = foreign.iter().find(|(_, bad)| *bad) {
        let name = match r.shape {
            Shape::Box => "box",
            Shape::Polygon => "polygon",
            Shape::Lattice => "lattice",
            Shape::Cylinder => "cylinder",
            Shape::Sphere => "sphere",
        };
        return Err(input(format!("{}: not a key of shape = \"{name}\"", at.key(k))));
    }
    match r.shape {
        Shape::Box => {
            let lo =
                r.lo_m.as_ref().ok_or_else(|| input(format!("{}: required for shape = \"box\"", at.key("lo_m"))))?;
            let hi =
                r.hi_m.as_ref().ok_or_else(|| input(format!("{}: required for shape = \"box\"", at.key("hi_m"))))?;
            v.vec(at, "lo_m", lo, d, xr)?;
            v.vec(at, "hi_m", hi, d, xr)?;
            for a in 0..d {
                if hi[a] <= lo[a] {
                    return Err(input(format!(
                        "{}: hi_m[{a}] = {} must exceed lo_m[{a}] = {}",
                        at.label, hi[a], lo[a]
                    )));
                }
            }
            coords(lo);
            coords(hi);
        }
        Shape::Polygon => {
            if d != 2 {
                return Err(input(format!("{}: shape = \"polygon\" needs dim = 2", at.label)));
            }
            let vs = r
                .vertices_m
                .as_ref()
                .ok_or_else(|| input(format!("{}: required for shape = \"polygon\"", at.key("vertices_m"))))?;
            if vs.len() < 3 || vs.len() > MAX_VERTICES {
                return Err(input(format!(
                    "{}: a polygon needs 3 to {MAX_VERTICES} vertices (got {})",
                    at.key("vertices_m"),
                    vs.len()
                )));
            }
            for p in vs {
                v.vec(at, "vertices_m", p, 2, xr)?;
                coords(p);
            }
        }
        Shape::Lattice => {
            let o = r
                .origin_m
                .as_ref()
                .ok_or_else(|| input(format!("{}: required for shape = \"lattice\"", at.key("origin_m"))))?;
            v.vec(at, "origin_m", o, d, xr)?;
            coords(o);
            let c = r
                .count
                .as_ref()
                .ok_or_else(|| input(format!("{}: required for shape = \"lattice\"", at.key("count"))))?;
            v.any(at, "count");
            if c.len() != d || c.contains(&0) {
                return Err(input(format!("{}: need {d} positive counts", at.key("count"))));
            }
            // the far corner, in floating point (a count may be any size here; the
            // size check bounds it before anything is generated)
            let far: Vec<f64> = o.iter().zip(c).map(|(x, &n)| x + n as f64 * r.spacing_m).collect();
            if let Some(a) = far.iter().position(|x| !xr.holds(*x)) {
                return Err(input(format!(
                    "{}: the lattice reaches {:e} m on axis {a} (origin + count × spacing_m), beyond {X_MAX:e} m",
                    at.label, far[a]
                )));
            }
            coords(&far);
        }
        Shape::Cylinder | Shape::Sphere => {
            crate::case::dims::round_shape(v, at, &at.label, r, d)?;
            let (c, rad) = (r.center_m.as_deref().unwrap_or(&[]), r.radius_m.unwrap_or(0.0));
            coords(&c.iter().map(|x| x.abs() + rad + r.height_m.unwrap_or(0.0)).collect::<Vec<_>>());
        }
    }
    Ok(reach)
}
