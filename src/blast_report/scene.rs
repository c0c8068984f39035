//! What the report measures on the whole scene: the charge (mass, centre, symmetry copies), the
//! products' bubble, and the vertical section of a 3D scene the maps are drawn on.

use super::*;

/// Equivalent radius √(A/π) of the detonation products (2D: A = Σ m_i/ρ_i over the JWL
/// particles, m²) at every frame; empty without an explosive.
pub fn bubble_history(case: &Case, frames: &[Frame]) -> Vec<(f64, f64)> {
    let jwl = explosive_mask(case);
    if !jwl.iter().any(|j| *j) {
        return Vec::new();
    }
    let pi = std::f64::consts::PI;
    let images = charge_of(case, frames).images;
    frames
        .iter()
        .map(|f| {
            let own = |i: usize| jwl.get(f.mat[i] as usize).copied().unwrap_or(false);
            // m/ρ: each particle's area in 2D plane (per metre of depth), its ring's or its own
            // volume in RZ and 3D
            let a: f64 = (0..f.mass.len()).filter(|&i| own(i)).map(|i| f.mass[i] / f.rho[i]).sum();
            let r = if case.dim == 3 || case.axisymmetric() {
                (3.0 * images * a / (4.0 * pi)).cbrt()
            } else {
                (images * a / pi).sqrt()
            };
            (f.time, r)
        })
        .collect()
}

/// What [`bubble_history`]'s radius is, for the plot's title.
pub(super) fn bubble_measure(case: &Case) -> &'static str {
    if case.dim == 3 || case.axisymmetric() { "equivalent radius (3V/4π)^⅓" } else { "equivalent radius √(A/π)" }
}

/// The charge a report scales its distances by.
pub(super) struct Charge {
    /// Its centre: the detonation point, else the explosive's initial centroid (m).
    pub(super) centre: Option<Vec<f64>>,
    /// The whole charge's mass: kg per metre of depth in 2D plane, kg in RZ and 3D (the model's
    /// explosive times `images`).
    pub(super) mass_kg: f64,
    /// The dimension its blast spreads in: 2 in plane strain (a line charge), 3 in RZ and 3D.
    pub(super) dim: usize,
    /// How many copies of the modelled charge its symmetry planes make (2 for each plane of
    /// [`crate::analysis::crater::charge_planes`]: 4
    /// for a quarter, 2 for an RZ half space); 1 without.
    pub(super) images: f64,
}

impl Charge {
    pub(super) fn mass_text(&self) -> String {
        match self.dim {
            2 if self.images > 1.0 => {
                format!("{:.3} kg per m of depth: {:.0} × the modelled part", self.mass_kg, self.images)
            }
            2 => format!("{:.3} kg per m of depth", self.mass_kg),
            _ if self.images > 1.0 => format!("{:.3} kg: {:.0} × the modelled part", self.mass_kg, self.images),
            _ => format!("{:.3} kg", self.mass_kg),
        }
    }
    pub(super) fn scaled_label(&self) -> &'static str {
        match self.dim {
            2 => "scaled distance R/√(W/L)  (m/(kg/m)^½, plane strain: a line charge)",
            3 => "scaled distance R/W^⅓  (m/kg^⅓)",
            _ => "scaled distance R/(W/A)",
        }
    }
}

/// The charge of a run from its first frame.
pub(super) fn charge_of(case: &Case, frames: &[Frame]) -> Charge {
    let ex = explosive_mask(case);
    let f0 = &frames[0];
    let k: Vec<usize> = (0..f0.x.len()).filter(|&i| ex.get(f0.mat[i] as usize).copied().unwrap_or(false)).collect();
    let d = case.dim;
    let coords = |i: usize| -> Vec<f64> {
        match d {
            3 => vec![f0.x[i], f0.y[i], f0.z[i]],
            2 => vec![f0.x[i], f0.y[i]],
            _ => vec![f0.x[i]],
        }
    };
    let pts: Vec<Vec<f64>> = k.iter().map(|&i| coords(i)).collect();
    // the symmetry planes the charge abuts: 2 copies of the modelled charge for each (a half,
    // a quarter, an octant), and the whole charge's centroid on each
    let planes = crate::analysis::crater::charge_planes(case, &pts);
    let centre = case.detonation.as_ref().and_then(|dt| dt.point_m.clone()).or_else(|| {
        (!k.is_empty()).then(|| {
            let mut c = crate::analysis::crater::centroid(&pts, d);
            if case.axisymmetric() {
                c[0] = 0.0; // a charge of rings is centred on the axis
            }
            for &(a, at) in &planes {
                c[a] = at;
            }
            c
        })
    });
    let images = 2f64.powi(planes.len() as i32);
    let mass: f64 = k.iter().map(|&i| f0.mass[i]).sum::<f64>() * images;
    Charge { centre, mass_kg: mass, dim: if d == 3 || case.axisymmetric() { 3 } else { d }, images }
}

/// The vertical section of a 3D run through the charge's axis along x (the plane y = the axis's
/// y), as 2D frames (x, z) for the report's maps: the soil, charge and everything else that lay
/// within 0.75 spacing of the plane at t = 0 (the first layer beside it when the plane is a
/// symmetry plane of a quarter model; every particle, projected, when none lies there), followed
/// wherever they go and drawn projected onto the plane; speeds in the plane; each particle's
/// `mass` set to ρ V^⅔ so that its drawn side is V^⅓.
pub(super) fn section_frames(case: &Case, frames: &[Frame]) -> Vec<Frame> {
    let charge = charge_of(case, frames);
    let ay = charge.centre.as_ref().map_or(0.0, |c| c[1]);
    let f0 = &frames[0];
    let ds = soil_spacing(case).unwrap_or_else(|| f0.h.iter().cloned().fold(f64::INFINITY, f64::min));
    let cx = charge.centre.as_ref().map_or(0.0, |c| c[0]);
    let mirrored = crate::analysis::crater::mirror_planes(case, (cx, ay), ds).iter().any(|&(k, _)| k == 1);
    let slab = |y: f64| if mirrored { (y - ay) >= 0.0 && (y - ay) < ds } else { (y - ay).abs() < 0.75 * ds };
    // the section is Lagrangian: the particles that lay in the slab at t = 0, followed (an
    // expanding cloud's particles leave a fixed slab: a free sphere's section was empty from
    // 30 µs); a scene with no particle on that plane is drawn projected onto it, whole
    let on: std::collections::HashSet<i64> = (0..f0.y.len()).filter(|&i| slab(f0.y[i])).map(|i| f0.id[i]).collect();
    let whole = on.is_empty();
    frames
        .iter()
        .map(|f| {
            let idx: Vec<usize> = (0..f.x.len()).filter(|&i| whole || on.contains(&f.id[i])).collect();
            let pick =
                |v: &[f64]| -> Vec<f64> { if v.is_empty() { Vec::new() } else { idx.iter().map(|&i| v[i]).collect() } };
            Frame {
                time: f.time,
                x: pick(&f.x),
                y: pick(&f.z),
                z: vec![0.0; idx.len()],
                vx: pick(&f.vx),
                vy: pick(&f.vz),
                vz: vec![0.0; idx.len()],
                rho: pick(&f.rho),
                p: pick(&f.p),
                e: pick(&f.e),
                h: pick(&f.h),
                mass: idx.iter().map(|&i| f.rho[i] * (f.mass[i] / f.rho[i]).powf(2.0 / 3.0)).collect(),
                mat: idx.iter().map(|&i| f.mat[i]).collect(),
                id: idx.iter().map(|&i| f.id[i]).collect(),
                ppv: pick(&f.ppv),
                p_peak: pick(&f.p_peak),
                bnd: if f.bnd.is_empty() { Vec::new() } else { idx.iter().map(|&i| f.bnd[i]).collect() },
            }
        })
        .collect()
}
