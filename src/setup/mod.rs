//! Builds the initial particles of a case: lattices per region, cut-outs, overlap checks, masses,
//! smoothing lengths, the material table and the wall segments.

mod geometry;

use crate::case::size::cells;
use crate::case::{BurnMode, Case, EosCfg, Shape};
pub use crate::case::{has_strength, programmed};
use crate::error::{Result, input};
pub use crate::modules::boundary::walls::{corners, segments};
use crate::param::{MatTable, NPAR, SPH_MP_ETA_CJ};

/// Particles as generated, before the solver takes them.
#[derive(Debug, Clone, Default)]
pub struct Initial {
    pub x: Vec<f64>,
    pub v: Vec<f64>,
    pub rho: Vec<f64>,
    pub e: Vec<f64>,
    pub h: Vec<f64>,
    pub mass: Vec<f64>,
    pub mat: Vec<i32>,
    /// Region index of each particle.
    pub region: Vec<u32>,
    /// Per region: number of particles.
    pub counts: Vec<usize>,
    /// Finest initial spacing (m).
    pub dx_min: f64,
    /// Boundary kind of each particle (0 ordinary, 1 integrated, 2 held), where something other
    /// than the regions' `boundary_particles` sets it; empty: the regions say.
    pub bnd: Vec<i32>,
}

/// The material table of the legacy interface, built from the case's materials.
pub fn material_table(case: &Case) -> MatTable {
    let nm = case.materials.len();
    let mut mtype = vec![0i32; nm];
    let mut mpar = vec![0.0f64; NPAR * nm];
    let mut groups: Vec<String> = Vec::new();
    let mut group = vec![0i32; nm];
    for (m, mc) in case.materials.iter().enumerate() {
        let col = &mut mpar[NPAR * m..NPAR * (m + 1)];
        mtype[m] = mc.eos.eos_kind() as i32;
        // the energy of the explosive at rest: the material's e0, else its first region's
        let e0 = mc
            .e0_jkg
            .or_else(|| case.regions.iter().find(|r| r.material == mc.name).and_then(|r| r.e_jkg))
            .unwrap_or(0.0);
        mc.eos.fill_column(col, e0);
        let beta = case.detonation.as_ref().is_some_and(|d| d.mode == BurnMode::Programmed && d.beta_burn);
        if let EosCfg::Jwl { rho0_kgm3, a_pa, b_pa, r1, r2, omega, .. } = &mc.eos
            && beta
        {
            let jwl = crate::modules::detonation::cj::Jwl {
                rho0: *rho0_kgm3,
                a: *a_pa,
                b: *b_pa,
                r1: *r1,
                r2: *r2,
                omega: *omega,
                e0,
            };
            if let Some(s) = crate::modules::detonation::cj::cj(&jwl) {
                col[SPH_MP_ETA_CJ as usize - 1] = s.rho / rho0_kgm3;
            }
        }
        col[7] = mc.pmin_pa.unwrap_or(-f64::MAX);
        if let Some(s) = &mc.strength {
            col[8] = s.shear_modulus_pa;
            col[9] = s.alpha_phi;
            col[10] = s.cohesion_pa;
        }
        let gname = mc.penalty_group.clone().unwrap_or_else(|| format!("\u{0}{}", mc.name));
        group[m] = match groups.iter().position(|g| *g == gname) {
            // exempt: no penalty force with any material
            _ if gname == crate::case::PENALTY_EXEMPT => -1,
            Some(k) => k as i32,
            None => {
                groups.push(gname);
                (groups.len() - 1) as i32
            }
        };
    }
    MatTable { mtype, mpar, group }
}

fn point_in_polygon(p: &[f64], poly: &[Vec<f64>]) -> bool {
    let mut inside = false;
    let n = poly.len();
    let mut j = n - 1;
    for i in 0..n {
        let (xi, yi) = (poly[i][0], poly[i][1]);
        let (xj, yj) = (poly[j][0], poly[j][1]);
        if (yi > p[1]) != (yj > p[1]) && p[0] < (xj - xi) * (p[1] - yi) / (yj - yi) + xi {
            inside = !inside;
        }
        j = i;
    }
    inside
}

/// Is point `p` inside the shape of region `r`, clipped by its `keep_below` planes (every plane's
/// (p − point_m)·n̂ ≤ 0)?
pub(crate) fn inside(case: &Case, r: usize, p: &[f64]) -> bool {
    inside_shape(case, r, p) && kept_by_planes(&case.regions[r], p)
}

/// Is `p` on the kept side of every `keep_below` plane of the region, (p − point_m)·n̂ ≤ 0 (m)?
/// True for a region without planes.
pub(crate) fn kept_by_planes(rc: &crate::case::RegionCfg, p: &[f64]) -> bool {
    rc.keep_below.iter().all(|c| c.keeps(p))
}

/// Is point `p` inside the shape of region `r`, its `keep_below` planes left out?
fn inside_shape(case: &Case, r: usize, p: &[f64]) -> bool {
    let rc = &case.regions[r];
    let d = case.dim;
    match rc.shape {
        Shape::Box => {
            let (lo, hi) = (rc.lo_m.as_ref().unwrap(), rc.hi_m.as_ref().unwrap());
            (0..d).all(|a| p[a] >= lo[a] && p[a] < hi[a])
        }
        Shape::Polygon => point_in_polygon(p, rc.vertices_m.as_ref().unwrap()),
        Shape::Lattice => {
            let (o, c) = (rc.origin_m.as_ref().unwrap(), rc.count.as_ref().unwrap());
            (0..d).all(|a| p[a] >= o[a] - 0.5 * rc.spacing_m && p[a] < o[a] + (c[a] as f64 - 0.5) * rc.spacing_m)
        }
        Shape::Cylinder | Shape::Sphere => {
            let (c, r) = (rc.center_m.as_ref().unwrap(), rc.radius_m.unwrap());
            let clip = match (&rc.lo_m, &rc.hi_m) {
                (Some(lo), Some(hi)) => (0..d).all(|a| p[a] >= lo[a] && p[a] < hi[a]),
                _ => true,
            };
            let round = if rc.shape == Shape::Sphere {
                (0..d).map(|a| (p[a] - c[a]) * (p[a] - c[a])).sum::<f64>() < r * r
            } else {
                let (dx, dy) = (p[0] - c[0], p[1] - c[1]);
                dx * dx + dy * dy < r * r && p[2] >= c[2] && p[2] < c[2] + rc.height_m.unwrap()
            };
            clip && round
        }
    }
}

/// The box a region fills (a box's `lo_m`..`hi_m`; a cylinder's or sphere's bounding box clipped
/// to its `lo_m`..`hi_m`), for the first `case.dim` axes; None for other shapes. (For the
/// advice on a run's charges.)
#[cfg(feature = "io")]
pub(crate) fn region_box(case: &Case, r: usize) -> Option<([f64; 3], [f64; 3])> {
    let rc = &case.regions[r];
    let d = case.dim;
    match rc.shape {
        Shape::Box => {
            let (l, h) = (rc.lo_m.as_ref()?, rc.hi_m.as_ref()?);
            let (mut lo, mut hi) = ([0.0; 3], [0.0; 3]);
            lo[..d].copy_from_slice(&l[..d]);
            hi[..d].copy_from_slice(&h[..d]);
            Some((lo, hi))
        }
        Shape::Cylinder | Shape::Sphere => {
            let (_, lo, hi) = round_box(rc, d);
            Some((lo, hi))
        }
        _ => None,
    }
}

/// The bounding box of a cylinder or sphere region, clipped to its `lo_m`..`hi_m` when given,
/// and the origin of its lattice (the clip box's lower corner, else the bounding box's).
fn round_box(rc: &crate::case::RegionCfg, d: usize) -> ([f64; 3], [f64; 3], [f64; 3]) {
    let (c, r) = (rc.center_m.as_ref().unwrap(), rc.radius_m.unwrap());
    let (mut lo, mut hi) = ([0.0; 3], [0.0; 3]);
    for a in 0..d {
        lo[a] = c[a] - r;
        hi[a] = c[a] + r;
    }
    if rc.shape == Shape::Cylinder {
        lo[2] = c[2];
        hi[2] = c[2] + rc.height_m.unwrap();
    }
    let mut org = lo;
    if let (Some(l), Some(h)) = (&rc.lo_m, &rc.hi_m) {
        for a in 0..d {
            org[a] = l[a];
            lo[a] = lo[a].max(l[a]);
            hi[a] = hi[a].min(h[a]);
        }
    }
    (org, lo, hi)
}

fn lattice_points(case: &Case, r: usize) -> Result<Vec<[f64; 3]>> {
    let rc = &case.regions[r];
    let d = case.dim;
    let dx = rc.spacing_m;
    let (org, cnt): ([f64; 3], [usize; 3]) = match rc.shape {
        Shape::Box => {
            let (lo, hi) = (rc.lo_m.as_ref().unwrap(), rc.hi_m.as_ref().unwrap());
            let mut o = [0.0; 3];
            let mut c = [1usize; 3];
            for a in 0..d {
                o[a] = lo[a] + 0.5 * dx;
                c[a] = cells(hi[a] - lo[a], dx);
            }
            (o, c)
        }
        Shape::Polygon => {
            let v = rc.vertices_m.as_ref().unwrap();
            let mut lo = [f64::INFINITY; 3];
            let mut hi = [f64::NEG_INFINITY; 3];
            for p in v {
                for a in 0..2 {
                    lo[a] = lo[a].min(p[a]);
                    hi[a] = hi[a].max(p[a]);
                }
            }
            let mut o = [0.0; 3];
            let mut c = [1usize; 3];
            for a in 0..2 {
                o[a] = lo[a] + 0.5 * dx;
                c[a] = cells(hi[a] - lo[a], dx);
            }
            (o, c)
        }
        Shape::Lattice => {
            let (o0, c0) = (rc.origin_m.as_ref().unwrap(), rc.count.as_ref().unwrap());
            let mut o = [0.0; 3];
            let mut c = [1usize; 3];
            o[..d].copy_from_slice(&o0[..d]);
            c[..d].copy_from_slice(&c0[..d]);
            (o, c)
        }
        Shape::Cylinder | Shape::Sphere => {
            // the cell-centred lattice from the origin, over the (clipped) bounding box: every
            // node org + (i + 1/2) dx below its top, and one more (the shape's test clips them;
            // counting whole cells from the clip box's corner lost the nodes in the top half cell)
            let (org, _, hi) = round_box(rc, d);
            let mut o = [0.0; 3];
            let mut c = [1usize; 3];
            for a in 0..d {
                o[a] = org[a] + 0.5 * dx;
                c[a] = ((hi[a] - org[a]) / dx).ceil().max(0.0) as usize + 1;
            }
            (o, c)
        }
    };
    let keep = |p: &[f64; 3]| -> bool {
        let shaped = matches!(rc.shape, Shape::Polygon | Shape::Cylinder | Shape::Sphere);
        // axisymmetric: x is the radius, r >= 0; the keep_below planes clip every shape
        (!shaped || inside_shape(case, r, p)) && kept_by_planes(rc, p) && !(case.axisymmetric() && p[0] < 0.0)
    };
    // bounded by the size check; the product is checked all the same
    let cap = cnt[0].checked_mul(cnt[1]).and_then(|c| c.checked_mul(cnt[2])).unwrap_or(0);
    let mut pts = Vec::new();
    if rc.shape != Shape::Polygon {
        pts.try_reserve_exact(cap).map_err(|e| input(format!("region[{r}] ({}): {cap} particles: {e}", rc.name)))?;
    }
    for k in 0..cnt[2] {
        for j in 0..cnt[1] {
            for i in 0..cnt[0] {
                let idx = [i, j, k];
                let mut p = [0.0; 3];
                for a in 0..d {
                    p[a] = org[a] + idx[a] as f64 * dx;
                }
                if !keep(&p) {
                    continue;
                }
                pts.push(p);
            }
        }
    }
    Ok(pts)
}

/// The boundary-particle kind of each particle from its region (`[[region]]
/// boundary_particles`: 0 ordinary, 1 integrated, 2 held), `region` the particles' region indices.
pub fn boundary_kinds(case: &Case, region: &[u32]) -> Vec<i32> {
    let kind = |r: &u32| case.regions.get(*r as usize).and_then(|rg| rg.boundary_particles).map_or(0, |k| k as i32);
    region.iter().map(kind).collect()
}

/// Generates the particles of every region; refuses overlapping or empty regions. The size is
/// checked first ([`crate::case::size::check`], the default limit from the machine's memory) and
/// the geometry after (walls, `[domain]`, the detonation point and the gauges, against the
/// particles: `setup/geometry.rs`).
pub fn particles(case: &Case) -> Result<Initial> {
    particles_limited(case, None)
}

/// [`particles`], with `max_particles` (`--max-particles`) as the limit instead of the memory.
pub(crate) fn particles_limited(case: &Case, max_particles: Option<u64>) -> Result<Initial> {
    crate::case::size::check(case, max_particles)?;
    let init = generate(case)?;
    geometry::check(case, &init)?;
    Ok(init)
}

fn generate(case: &Case) -> Result<Initial> {
    let d = case.dim;
    let nr = case.regions.len();
    let mut init = Initial { dx_min: f64::INFINITY, ..Default::default() };
    let mut all: Vec<Vec<[f64; 3]>> = Vec::with_capacity(nr);
    for r in 0..nr {
        let rc = &case.regions[r];
        let cut: Vec<usize> =
            rc.subtract.iter().filter_map(|s| case.regions.iter().position(|q| &q.name == s)).collect();
        let pts: Vec<[f64; 3]> =
            lattice_points(case, r)?.into_iter().filter(|p| !cut.iter().any(|&c| inside(case, c, p))).collect();
        if pts.is_empty() {
            if !rc.keep_below.is_empty() {
                // the same lattice without the planes: did they remove it all?
                let mut bare = case.clone();
                bare.regions[r].keep_below.clear();
                let shaped = lattice_points(&bare, r)?;
                if !shaped.is_empty() {
                    return Err(input(format!(
                        "region[{r}] ({}).keep_below: the planes leave none of the shape's {} lattice points (each keeps the side (x - point_m).normal <= 0; the normal points out of the kept side: is one reversed?)",
                        rc.name,
                        shaped.len()
                    )));
                }
            }
            return Err(input(format!(
                "region[{r}] ({}): holds no particles (is spacing_m = {} larger than the region, or is it all cut out by subtract or keep_below?)",
                rc.name, rc.spacing_m
            )));
        }
        all.push(pts);
    }
    for a in 0..nr {
        for b in 0..nr {
            if a == b {
                continue;
            }
            let (ra, rb) = (&case.regions[a], &case.regions[b]);
            if ra.subtract.contains(&rb.name) || rb.subtract.contains(&ra.name) {
                continue;
            }
            if let Some(p) = all[a].iter().find(|p| inside(case, b, &p[..])) {
                return Err(input(format!(
                    "region[{a}] ({}) overlaps region[{b}] ({}) at {:?} m: cut one out of the other: add subtract = [\"{}\"] to region {} (the one that keeps its particles outside the other)",
                    ra.name,
                    rb.name,
                    &p[..d],
                    ra.name,
                    rb.name
                )));
            }
        }
    }
    for (r, pts) in all.iter().enumerate() {
        let rc = &case.regions[r];
        let m = case.material_index(&rc.material).unwrap();
        let mc = &case.materials[m];
        let rho = rc.rho_kgm3.or(mc.eos.rho0()).unwrap_or(1.0);
        let e = rc.e_jkg.or(mc.e0_jkg).unwrap_or(0.0);
        let mass = rc.mass_kg.unwrap_or(rho * rc.spacing_m.powi(d as i32));
        let h = rc.h_m.unwrap_or(case.sph.h_over_dx * rc.spacing_m);
        init.dx_min = init.dx_min.min(rc.spacing_m);
        // axisymmetric: each particle is a ring of mass 2π r ρ Δx² (kg)
        let ring = |p: &[f64; 3]| 2.0 * std::f64::consts::PI * p[0] * (rho * rc.spacing_m * rc.spacing_m);
        let cen = rc.radial_center_m.clone().unwrap_or_else(|| vec![0.0; d]);
        let jit = case.sph.jitter * rc.spacing_m;
        for (ip, p) in pts.iter().enumerate() {
            // the jitter moves the particle; its mass (a ring's too) stays that of its lattice node
            let mut y = *p;
            if jit > 0.0 {
                for (a, ya) in y.iter_mut().enumerate().take(d) {
                    *ya += jit * unit_noise(r, ip, a);
                }
            }
            init.x.extend_from_slice(&y[..d]);
            let mut v = rc.velocity_ms.clone().unwrap_or_else(|| vec![0.0; d]);
            if let Some(vr) = rc.radial_velocity_ms {
                // v += v_r (x − c)/|x − c| (zero at the centre): the Noh problem
                let r = (0..d).map(|a| (y[a] - cen[a]) * (y[a] - cen[a])).sum::<f64>().sqrt();
                if r > 0.0 {
                    for a in 0..d {
                        v[a] += vr * (y[a] - cen[a]) / r;
                    }
                }
            }
            init.v.extend_from_slice(&v);
            init.rho.push(rho);
            init.e.push(e);
            init.h.push(h);
            init.mass.push(if case.axisymmetric() { ring(p) } else { mass });
            init.mat.push(m as i32);
            init.region.push(r as u32);
        }
        init.counts.push(pts.len());
    }
    Ok(init)
}

/// A deterministic pseudo-random number in [−1/2, 1/2) for coordinate `axis` of point `point`
/// of region `region` (SplitMix64's finaliser over the three indices): the same on every machine
/// and thread count, so a jittered lattice (`sph.jitter`) is reproducible.
fn unit_noise(region: usize, point: usize, axis: usize) -> f64 {
    let mut z = (region as u64)
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add((point as u64).wrapping_mul(0xD1B5_4A32_D192_ED03))
        .wrapping_add((axis as u64 + 1).wrapping_mul(0x8CB9_2BA7_2F3D_8DD7));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64 - 0.5
}

#[cfg(test)]
mod tests {
    use super::cells;

    #[test]
    fn an_extent_written_to_a_few_digits_counts_its_whole_spacings() {
        // 4 x 0.01827416 = 0.07309664: 0.073096 (five digits) is 3.99996 spacings, four cells
        assert_eq!(cells(0.073096, 0.01827416), 4);
        assert_eq!(cells(0.4934, 0.01827416), 27);
        // an exact count, and a real remainder, stay as they were
        assert_eq!(cells(0.5, 0.1), 5);
        assert_eq!(cells(0.55, 0.1), 5);
        assert_eq!(cells(0.0999, 0.1), 0);
        assert_eq!(cells(0.0, 0.1), 0);
    }
}
