//! Scale slips: a case whose numbers no blast in soil or water can have, refused before it runs
//! (`check` and `run`), and a charge that touches nothing in a scene that measures a crater,
//! warned of.
//!
//! What is refused (one line each, exit status 2), in a scene that holds a condensed material (an
//! explosive, water or a soil):
//! - lengths in millimetres: a finest spacing of [`MAX_SPACING_M`] or more, or particles that span
//!   [`MAX_EXTENT_M`] or more (a 1 m domain at 1 cm reads as 1000 m at 10 m);
//! - a density in g/cm³: a condensed material's (or region's) density below
//!   [`MIN_CONDENSED_RHO`] kg/m³ (TNT 1.63 for 1630);
//! - a charge mass off any plausible range: in 3D and RZ outside [`CHARGE_KG`] (a 1 kg charge in
//!   mm reads as 10⁹ kg); in 2D plane (kg per metre of depth) outside [`CHARGE_KG_PER_M`]; a
//!   charge that fills more than half of its scene's volume while soil or water surrounds it; a
//!   charge too small to move its scene (the scene's size over W^(1/3) above
//!   [`MAX_SCALED_EXTENT`] m/kg^(1/3)).

use super::{AnalysisKind, Case, EosCfg, Geometry, Matter};
use crate::error::{Result, input};
use crate::state::Particles;

/// The coarsest spacing a blast scene in soil or water takes (m).
pub const MAX_SPACING_M: f64 = 0.5;
/// The largest extent a blast scene in soil or water takes (m).
pub const MAX_EXTENT_M: f64 = 200.0;
/// The lowest density of an explosive, water or a soil (kg/m³): the lightest, a loose dry soil or
/// a low-density explosive, is near 1000.
pub const MIN_CONDENSED_RHO: f64 = 100.0;
/// The range of a charge's mass in 3D and RZ (kg): a 0.1 g detonator to 10 kt.
pub const CHARGE_KG: (f64, f64) = (1e-4, 1e7);
/// The range of a line charge's mass in 2D plane (kg per metre of depth).
pub const CHARGE_KG_PER_M: (f64, f64) = (1e-3, 1e6);
/// The largest size of a scene (its longest extent, m) over the cube root of its charge's mass
/// (kg) in 3D and RZ, m/kg^(1/3): beyond it the charge cannot move its scene (a shipped crater
/// case is near 1; a 1 g charge in a 20 m domain is 200).
pub const MAX_SCALED_EXTENT: f64 = 200.0;

fn condensed(e: &EosCfg) -> bool {
    e.matter().condensed()
}

/// What the slips are measured on: the real particles' extent, the charge's mass and volume, the
/// rest's volume.
#[derive(Debug, Clone, Copy, Default)]
pub struct Scene {
    /// Longest side of the particles' bounding box (m).
    pub extent_m: f64,
    /// Finest initial spacing (m).
    pub dx_m: f64,
    /// Explosive (JWL) mass in the model (kg; kg/m in 2D plane; kg/m² in 1D), completed across
    /// the symmetry planes it abuts (a quarter's charge × 4).
    pub charge_kg: f64,
    /// Explosive volume and the volume of every other condensed particle (m³, or per metre).
    pub charge_vol: f64,
    pub other_vol: f64,
    /// Whether any particle is soil or water.
    pub ground: bool,
}

/// The scene of `case`'s particles `p` (finest spacing `dx_m`).
pub fn scene(case: &Case, p: &Particles, dx_m: f64) -> Scene {
    let d = case.dim;
    let n = p.nreal;
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    let mut s = Scene { dx_m, ..Default::default() };
    for i in 0..n {
        for a in 0..d {
            lo[a] = lo[a].min(p.x[d * i + a]);
            hi[a] = hi[a].max(p.x[d * i + a]);
        }
        let Some(m) = case.materials.get(p.mat[i] as usize) else { continue };
        let vol = if p.rho[i] > 0.0 { p.mass[i] / p.rho[i] } else { 0.0 };
        match m.eos.matter() {
            Matter::Explosive => {
                s.charge_kg += p.mass[i];
                s.charge_vol += vol;
            }
            Matter::Water | Matter::Soil => {
                s.other_vol += vol;
                s.ground = true;
            }
            Matter::Gas => s.other_vol += vol,
        }
    }
    s.extent_m = (0..d).map(|a| hi[a] - lo[a]).fold(0.0, f64::max);
    // the charge's images across the symmetry planes it abuts (not the axis of RZ)
    let mirrors = case.axis_mirrors();
    let mut factor = 1.0;
    for (k, c) in mirrors {
        if k == 0 && case.axisymmetric() {
            continue;
        }
        let touches = (0..n).any(|i| {
            matches!(case.materials.get(p.mat[i] as usize).map(|m| &m.eos), Some(EosCfg::Jwl { .. }))
                && (p.x[d * i + k] - c).abs() < dx_m
        });
        if touches {
            factor *= 2.0;
        }
    }
    s.charge_kg *= factor;
    s
}

/// The first scale slip of `case` (its particles `p`, finest spacing `dx_m`), as one line; None
/// when there is none.
pub fn refusal(case: &Case, p: &Particles, dx_m: f64) -> Option<String> {
    if !case.materials.iter().any(|m| condensed(&m.eos)) {
        return None;
    }
    for mc in case.materials.iter().filter(|m| condensed(&m.eos)) {
        if let Some(r0) = mc.eos.rho0().filter(|r| *r < MIN_CONDENSED_RHO) {
            return Some(format!(
                "material {}: rho0_kgm3 = {r0} kg/m³, below any {} (1000–3000 kg/m³): a density in g/cm³? Densities are in kg/m³ (× 1000)",
                mc.name,
                kind_name(&mc.eos)
            ));
        }
    }
    for rc in &case.regions {
        let Some(mc) = case.material_index(&rc.material).map(|m| &case.materials[m]) else { continue };
        if let Some(rho) = rc.rho_kgm3.filter(|r| *r < MIN_CONDENSED_RHO)
            && condensed(&mc.eos)
        {
            return Some(format!(
                "region {} ({}): rho_kgm3 = {rho} kg/m³, below any {} (1000–3000 kg/m³): a density in g/cm³? Densities are in kg/m³ (× 1000)",
                rc.name,
                mc.name,
                kind_name(&mc.eos)
            ));
        }
    }
    let s = scene(case, p, dx_m);
    if s.dx_m >= MAX_SPACING_M || s.extent_m >= MAX_EXTENT_M {
        return Some(format!(
            "the particles span {:.4} m at a spacing of {:.4} m, while a blast in soil or water spans centimetres to tens of metres (spacing under {MAX_SPACING_M} m, extent under {MAX_EXTENT_M} m): lengths in millimetres? Every length key is in metres (÷ 1000)",
            s.extent_m, s.dx_m
        ));
    }
    charge_refusal(case, &s)
}

/// The charge-mass part of [`refusal`].
fn charge_refusal(case: &Case, s: &Scene) -> Option<String> {
    if s.charge_kg <= 0.0 || case.dim == 1 {
        return None;
    }
    let plane = case.dim == 2 && case.geometry != Geometry::Axisymmetric;
    let ((lo, hi), unit) = if plane { (CHARGE_KG_PER_M, "kg/m") } else { (CHARGE_KG, "kg") };
    if !(lo..=hi).contains(&s.charge_kg) {
        let why = if s.charge_kg > hi {
            "lengths in millimetres (a 1 kg charge reads as 10⁹ kg), or a density or mass_kg 1000 × too large?"
        } else {
            "the charge's size in metres where centimetres or millimetres were meant, or a density in g/cm³?"
        };
        return Some(format!(
            "the explosive holds {:.4e} {unit}, outside any blast in soil or water ({lo:e} to {hi:e} {unit}): {why}",
            s.charge_kg
        ));
    }
    if s.ground && s.charge_vol > s.other_vol {
        return Some(format!(
            "the explosive fills {:.0} % of the scene's volume ({:.4e} of {:.4e} {}): a charge's lengths in millimetres in a scene in metres?",
            100.0 * s.charge_vol / (s.charge_vol + s.other_vol),
            s.charge_vol,
            s.charge_vol + s.other_vol,
            if plane { "m³/m" } else { "m³" }
        ));
    }
    let scaled = s.extent_m / s.charge_kg.cbrt();
    if s.ground && !plane && scaled > MAX_SCALED_EXTENT {
        return Some(format!(
            "the scene spans {:.4} m around {:.4e} kg of explosive, {scaled:.0} m/kg^(1/3): a charge this small moves nothing at this distance (the shipped crater cases are near 1; above {MAX_SCALED_EXTENT} is refused): a charge in grams, or a scene in millimetres?",
            s.extent_m, s.charge_kg
        ));
    }
    None
}

fn kind_name(e: &EosCfg) -> &'static str {
    e.matter().name()
}

/// [`refusal`] as an error (exit status 2).
pub fn check(case: &Case, p: &Particles, dx_m: f64) -> Result<()> {
    refusal(case, p, dx_m).map_or(Ok(()), |m| Err(input(m)))
}

/// A scene that measures a crater (`[analysis] kind = "crater"`) whose explosive touches no soil
/// or water: the nearest such particle is more than 1.5 spacings (the coarser of the two) from
/// every explosive particle. One line naming the gap (m, and in spacings), or None.
pub fn charge_gap_warning(case: &Case, p: &Particles) -> Option<String> {
    if case.analysis.kind != AnalysisKind::Crater {
        return None;
    }
    let d = case.dim;
    let n = p.nreal;
    let kind = |i: usize| case.materials.get(p.mat[i] as usize).map(|m| &m.eos);
    let charge: Vec<usize> = (0..n).filter(|&i| matches!(kind(i), Some(EosCfg::Jwl { .. }))).collect();
    let ground: Vec<usize> = (0..n).filter(|&i| kind(i).is_some_and(|e| e.matter().ground())).collect();
    if charge.is_empty() || ground.is_empty() {
        return None;
    }
    // the spacing of a particle from its mass and density: (m/ρ)^(1/d), a ring's r·2π out in RZ
    let spacing = |i: usize| {
        let mut v = p.mass[i] / p.rho[i];
        if case.axisymmetric() {
            v /= 2.0 * std::f64::consts::PI * p.x[d * i].max(f64::MIN_POSITIVE);
        }
        v.powf(1.0 / d as f64)
    };
    let mut best = (f64::INFINITY, 0.0);
    for &i in &charge {
        for &j in &ground {
            let r2: f64 = (0..d).map(|a| (p.x[d * i + a] - p.x[d * j + a]).powi(2)).sum();
            if r2 < best.0 {
                best = (r2, spacing(i).max(spacing(j)));
            }
        }
    }
    let (dist, dx) = (best.0.sqrt(), best.1);
    (dist > 1.5 * dx).then(|| {
        let gap = dist - dx;
        format!(
            "the explosive touches no soil or water: the nearest lies {gap:.4} m ({:.1} spacings) beyond its surface, so the blast reaches the ground through air or empty space and the crater, ejecta and gauges see little of it; move the charge onto (or into) the ground, or set [analysis] kind to what the scene measures",
            gap / dx
        )
    })
}
