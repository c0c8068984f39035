//! What `blastsph check` warns about and what the unstable-run diagnostic suggests: settings that
//! are known to fail, each with the evidence in docs/validation.md ("Safe defaults: what `check` and `run` warn of"), and the
//! likely fix of a run that stopped.

use crate::case::{
    AnalysisKind, BurnMode, Case, ContinuityForm, DensityKind, EnergyForm, EosCfg, GaugeKind, Geometry, KernelKind,
    StepRule, WallKind,
};
use crate::state::Particles;

mod charge;
pub use charge::*;

/// A gas beside a condensed material (air around a charge or above the ground) with a density or
/// pressure form that cannot hold their density ratio (docs/theory.md §4, §5).
fn gas_beside_condensed(case: &Case) -> Vec<String> {
    let gas = case.materials.iter().any(|m| matches!(m.eos, EosCfg::IdealGas { .. }));
    let other = case.materials.iter().any(|m| !matches!(m.eos, EosCfg::IdealGas { .. }));
    let s = &case.sph;
    let mut w = Vec::new();
    if !(gas && other) {
        return w;
    }
    if s.density == DensityKind::Summation {
        w.push("sph.density = \"summation\" with a gas beside a denser material: each neighbour's mass enters the gas's density, so air beside TNT reads hundreds of times its density, its h shrinks 20-fold and the step collapses (docs/theory.md s.4); \"number\" (the default there) reads each particle's own mass".into());
    }
    if s.density == DensityKind::Continuity && s.continuity_form == ContinuityForm::Mass {
        w.push("sph.continuity_form = \"mass\" with a gas beside a denser material: the gas's density rate carries the heavy neighbours' masses; use sph.density = \"number\" (the default there)".into());
    }
    if s.pressure_form == crate::case::PressureForm::Standard {
        w.push("sph.pressure_form = \"standard\" with a gas beside a denser material: the gas's pressure term carries the heavy neighbour's mass over the gas's density squared, and a uniform pressure pushes the gas off the interface (docs/theory.md s.5); \"interface\" is the default with number density".into());
    }
    w
}

/// One line per setting of `case` that is known to fail, naming the evidence.
pub fn warnings(case: &Case) -> Vec<String> {
    let mut w = Vec::new();
    let jwl = case.materials.iter().any(|m| matches!(m.eos, EosCfg::Jwl { .. }));
    let several = case.materials.len() > 1;
    let s = &case.sph;
    if s.density == DensityKind::Continuity && s.continuity_form == ContinuityForm::Mass && (jwl || several) {
        w.push(
            "sph.continuity_form = \"mass\" with several materials: it drove detonation products to a negative density in 5 of the 13 thesis scenes (docs/validation.md, \"The continuity form: evidence for the decision\"); \"volume\" (the default) ran all 13"
                .into(),
        );
    }
    if s.energy_form == EnergyForm::Symmetric {
        w.push(
            "sph.energy_form = \"symmetric\": the neighbours of hot particles (a point blast, soil beside detonation products) get negative internal energy (docs/validation.md, \"Verification problems\", its tests; docs/theory.md, \"Energy book-keeping\"); \"asymmetric\" (the default) keeps e >= 0 where p >= 0"
                .into(),
        );
    }
    w.extend(gas_beside_condensed(case));
    // water beside a charge's products, without a cavitation floor
    if jwl {
        for m in case.materials.iter().filter(|m| m.eos.matter() == crate::case::Matter::Water && m.pmin_pa.is_none()) {
            w.push(format!(
                "material `{}` (water) has no pmin_pa: beside the detonation products it takes tension without limit (down to -690 MPa at a 0.11 kg charge's products, RZ at 5 mm; real water cavitates near 0); set material.{}.pmin_pa = 0 for a bubble, cavitation or a free surface's spall (in that run the gauges' peaks moved by under 2 %, their impulses by up to 5 %, and it took 978 steps instead of 1448; docs/reference/cases.md, the water preset)",
                m.name, m.name
            ));
        }
    }
    let beta = case.viscosity.beta;
    if case.time.step == StepRule::Cfl && !case.time.viscous_step && beta > 1.0 {
        w.push(format!(
            "time.viscous_step = false with viscosity.beta = {beta}: the CFL rule ignores the viscosity's signal speed and the run is unstable in cold converging flow (Noh, a wall reflection: the energy doubles within 20 steps at time.cfl = 0.25; docs/validation.md, \"Verification problems\")"
        ));
    }
    if case.time.step == StepRule::Cfl && case.time.cfl > 0.3 {
        w.push(format!(
            "time.cfl = {}: above the thesis's 0.2-0.3; the verification problems are measured at 0.25",
            case.time.cfl
        ));
    }
    if s.kernel == KernelKind::Wendland && s.h_over_dx < 1.3 {
        w.push(format!(
            "sph.kernel = \"wendland\" with sph.h_over_dx = {}: the Wendland C2 kernel's support 2h holds too few neighbours at h = Δx (the 2D Sedov blast, γ = 5/3, 100², read its shock 3.2 % short, 1.3 % at h = 1.3 Δx: docs/validation.md, \"Verification problems\"); use sph.h_over_dx = 1.3 or more with it",
            s.h_over_dx
        ));
    }
    if s.h_over_dx < 0.9 {
        w.push(format!("sph.h_over_dx = {}: below 0.9 the thesis's runs failed (docs/validation.md, \"Stability of the thesis's runs\")", s.h_over_dx));
    }
    for r in &case.regions {
        if let Some(h) = r.h_m.filter(|h| *h < 0.9 * r.spacing_m) {
            w.push(format!(
                "region {}: h_m = {h:e} m is {:.3} of its spacing: below 0.9 the thesis's runs failed (docs/validation.md, \"Stability of the thesis's runs\"), and the particles have few neighbours",
                r.name,
                h / r.spacing_m
            ));
        }
    }
    let integrated: Vec<&str> = case
        .regions
        .iter()
        .filter(|r| r.boundary_particles == Some(crate::case::BoundaryKind::Integrated))
        .map(|r| r.name.as_str())
        .collect();
    if !integrated.is_empty() {
        let clamp = if s.density_clamp.is_some() { "" } else { " without sph.density_clamp" };
        w.push(format!(
            "region {}: \"integrated\" boundary particles{clamp} advance rho, e and v with x fixed, which conserves no energy: the shipped dam break with integrated walls stops unstable at t = 0.124 s, and with sph.density_clamp = [990, 1015] (the codes that integrate their walls clamp so) it ends with 3.9 x the kinetic energy of held walls (docs/theory.md, \"Boundary particles\"); use \"held\" for a wall at rest",
            integrated.join(", ")
        ));
    }
    if case.geometry == Geometry::Axisymmetric
        && beta > 2.0
        && case.regions.iter().any(|r| r.radial_velocity_ms.is_some_and(|u| u < 0.0))
    {
        w.push(format!(
            "viscosity.beta = {beta} with a flow converging in axisymmetric geometry: the rings next to the axis clump and run ahead along it (spherical Noh in RZ at 1 cm: the densest ring 11 x the exact peak density, 1.36 shock radii up the axis, post-shock density 0.85 of the exact; at beta = 2: 1.86 x and 0.96; docs/validation.md, \"Noh in RZ\"; cases/verify/noh_rz.toml)"
        ));
    }
    if case.geometry == Geometry::Axisymmetric && s.h_over_dx > 1.05 {
        w.push(format!(
            "sph.h_over_dx = {} in axisymmetric geometry: a ring next to the axis can be driven onto it and ride up as a jet (the RZ Sedov blast at h = 1.2 dx, beta = 10: one ring at 19 x the exact peak density; docs/validation.md, \"Other deposits in RZ and 3D\"); at h_over_dx = 1 (the default) the densest rings stay below 1.7 x the exact peak density",
            s.h_over_dx
        ));
    }
    // a crater followed past the blast into its slow, gravity-driven flow, in a soil with a
    // tension cut-off: loosened soil carries no pressure, so no friction, and the viscosity
    // (ν ≈ α c h/8, c the soil's c0 even where p is clamped) holds the crater back
    if case.analysis.kind == AnalysisKind::Crater && case.time.end_s >= 0.01 && case.viscosity.alpha > 0.0 {
        let cut = |m: &&crate::case::MaterialCfg| matches!(m.eos, EosCfg::Soil { .. }) && m.pmin_pa == Some(0.0);
        if let Some(m) = case.materials.iter().find(cut) {
            w.push(format!(
                "time.end_s = {} s with a crater in material {} (a soil with pmin_pa = 0): after the blast, soil loosened below its reference density carries no pressure and so no friction, and the late crater is held back by the artificial viscosity, not by the soil; it widens with refinement and with less viscosity (the 1 kg charge at 0.3 s: 179 -> 227 cm wide from dx = 23 to 15.3 mm; docs/validation.md, \"Crater scaling against surface-burst data\")",
                case.time.end_s, m.name
            ));
        }
    }
    if let Some(d) = case.detonation.as_ref().filter(|d| d.mode == BurnMode::Programmed) {
        if d.width_h <= 0.0 && !d.beta_burn {
            w.push(
                "detonation: width_h = 0 without the beta burn: the unlit explosive ahead of the front is crushed and the front pressure runs away after about 500 spacings of travel (4.2 p_CJ at 2000; docs/theory.md, \"Lighting the charge\"; docs/validation.md, the tnt_slab rows)"
                    .into(),
            );
        } else if !d.beta_burn || d.lighting_speed_factor >= 1.0 {
            w.push(
                "detonation: a programmed front at the full speed D without the beta burn (or with lighting_speed_factor = 1) can outrun the front the explosive sustains and leave a weak detonation (0.85 p_CJ at h/dx = 1.5; docs/theory.md, \"Lighting the charge\"; docs/validation.md, the tnt_slab rows); the defaults are beta_burn = true, lighting_speed_factor = 0.95"
                    .into(),
            );
        }
        for m in &case.materials {
            if let EosCfg::Jwl { unreacted_c_ms: None, .. } = m.eos {
                w.push(format!(
                    "material {}: no unreacted EOS (unreacted_c_ms, unreacted_s, unreacted_gamma): the unlit explosive carries no pressure until it burns; with the beta burn the front still holds p_CJ within 3 % (docs/theory.md, \"Lighting the charge\"; docs/validation.md, the tnt_slab rows)",
                    m.name
                ));
            }
        }
    }
    w
}

/// Every warning of a case with its particles generated: [`warnings`], then [`deposit_warning`]
/// (what `blastsph check` prints, and `run` before it starts).
pub fn all(case: &Case, p: &Particles, region: &[u32]) -> Vec<String> {
    warnings(case)
        .into_iter()
        .chain(ignored_keys(case))
        .chain(deposit_warning(case, p))
        .chain(analysis_warning(case, p))
        .chain(stranded_deposit_warning(case))
        .chain(crate::analysis::sedov_edge::sedov_edge_warning(case, case.time.end_s, p.nreal, &|i| {
            std::array::from_fn(|k| if k < case.dim { p.x[case.dim * i + k] } else { 0.0 })
        }))
        .chain(sedov_spacing_warning(case))
        .chain(charge_mass_warnings(case, p, region))
        .chain(unit_warnings(case, p, region))
        .chain(charge_image_warnings(case, p, region))
        .chain(seam_warnings(case))
        .chain(close_particle_warning(case, p, region))
        .chain(several_charges(case))
        .chain(gauge_in_charge_warnings(case, p))
        .chain(wall_reflection_warning(case))
        .chain(crate::case::slips::charge_gap_warning(case, p))
        .collect()
}

/// An RZ blast whose ground (or water) shock comes back from a wall along the axis before the
/// run's end: that wall is a cylinder about the charge, and its reflection converges on the axis
/// (a buried charge's soil there thrown up and apart: its crater 6 cm wide against a 3D box's
/// 53 cm). The time 2r/c for the nearest such wall and the fastest medium's P wave,
/// c = √(C² + 4G/(3ρ0)) (C the EOS's bulk sound speed (m/s), G the shear modulus (Pa), ρ0 the
/// density (kg/m³)). One line, for a case with an explosive and a soil or water.
pub fn wall_reflection_warning(case: &Case) -> Option<String> {
    if case.geometry != Geometry::Axisymmetric || !case.materials.iter().any(|m| matches!(m.eos, EosCfg::Jwl { .. })) {
        return None;
    }
    // the fastest medium's P-wave speed (m/s)
    let (c, medium) = case
        .materials
        .iter()
        .filter_map(|m| {
            let (c0, rho0) = (m.eos.bulk_sound_speed()?, m.eos.rho0()?);
            let g = m.strength.as_ref().map_or(0.0, |s| s.shear_modulus_pa);
            Some(((c0 * c0 + 4.0 * g / (3.0 * rho0)).sqrt(), m.name.clone()))
        })
        .filter(|(c, _)| c.is_finite() && *c > 0.0)
        .max_by(|a, b| a.0.total_cmp(&b.0))?;
    // the nearest wall along the axis (r constant along it; a charge in RZ is on the axis)
    let (r, wi) = case
        .walls
        .iter()
        .enumerate()
        .filter(|(_, w)| w.kind != WallKind::Absorbing && w.from_m[0] == w.to_m[0] && w.from_m[0] > 0.0)
        .map(|(wi, w)| (w.from_m[0], wi))
        .min_by(|a, b| a.0.total_cmp(&b.0))?;
    let back = 2.0 * r / c;
    let end = case.time.end_s;
    (back < end).then(|| {
        let tu = |t: f64| if end >= 2e-2 { format!("{:.1} ms", t * 1e3) } else { format!("{:.2} ms", t * 1e3) };
        format!(
            "the shock in the {medium} reaches wall[{wi}] at r = {r:.3} m, a cylinder about the axis in RZ, and its reflection converges on the axis at about 2r/c = {} (c = {c:.0} m/s, the P wave), before the run's end ({}): a converging reflection throws the ground on the axis up and apart, which a 3D box's plane walls do not; the crater, the cavity and the axis's later records then hold the box's reflection: widen the box (r) or read the results before then",
            tu(back),
            tu(end),
        )
    })
}

/// Gauges placed in an explosive: the real particle nearest the gauge's point is of a JWL
/// material. A particle gauge then follows a products particle; a point gauge reads the
/// products until they pass. One line each (a gauge in the ground beside the charge, whose
/// nearest particle is the ground's, is not named).
pub fn gauge_in_charge_warnings(case: &Case, p: &Particles) -> Vec<String> {
    let d = case.dim;
    let n = p.nreal.min(p.mat.len());
    let mut w = Vec::new();
    for g in case.gauges.iter().filter(|g| g.point_m.len() == d) {
        let dist2 = |i: usize| (0..d).map(|a| (p.x[d * i + a] - g.point_m[a]).powi(2)).sum::<f64>();
        let Some(i) = (0..n).min_by(|&a, &b| dist2(a).total_cmp(&dist2(b))) else { continue };
        let Some(m) = usize::try_from(p.mat[i]).ok().and_then(|m| case.materials.get(m)) else { continue };
        if !matches!(m.eos, EosCfg::Jwl { .. }) {
            continue;
        }
        let what = match g.kind {
            GaugeKind::Particle => "it follows a particle of the detonation products",
            GaugeKind::Point => "it reads the detonation products, not the ground or water, until they pass",
        };
        let at = g.point_m.iter().map(|v| format!("{v}")).collect::<Vec<_>>().join(", ");
        w.push(format!(
            "gauge `{}` at ({at}) m is inside the explosive `{}` (the nearest particle is of it): {what}; place it in the medium whose shock it is to record",
            g.name, m.name
        ));
    }
    w
}

/// Explosive regions whose boxes lie more than two spacings apart: several charges. The crater
/// measure, the charge's axis and the peaks' scaled distances are made for one charge (about
/// the explosive's centroid, with its whole mass), and a programmed burn has one lighting point;
/// one line saying so, for `check`, `run` and `report`.
pub fn several_charges(case: &Case) -> Option<String> {
    let boxes: Vec<(usize, [f64; 3], [f64; 3])> = case
        .regions
        .iter()
        .enumerate()
        .filter(|(_, r)| {
            case.material_index(&r.material).is_some_and(|m| matches!(case.materials[m].eos, EosCfg::Jwl { .. }))
        })
        .filter_map(|(k, _)| crate::setup::region_box(case, k).map(|(lo, hi)| (k, lo, hi)))
        .collect();
    // groups of boxes that touch (within two spacings), by a simple merge
    let d = case.dim;
    let near = |a: &(usize, [f64; 3], [f64; 3]), b: &(usize, [f64; 3], [f64; 3])| {
        let gap = 2.0 * case.regions[a.0].spacing_m.max(case.regions[b.0].spacing_m);
        (0..d).all(|x| a.1[x] <= b.2[x] + gap && b.1[x] <= a.2[x] + gap)
    };
    let mut group: Vec<usize> = (0..boxes.len()).collect();
    for i in 0..boxes.len() {
        for j in 0..i {
            if near(&boxes[i], &boxes[j]) {
                let (gi, gj) = (group[i], group[j]);
                group.iter_mut().filter(|g| **g == gi).for_each(|g| *g = gj);
            }
        }
    }
    let mut ids = group.clone();
    ids.sort_unstable();
    ids.dedup();
    if ids.len() < 2 {
        return None;
    }
    let names: Vec<String> = boxes.iter().map(|b| format!("`{}`", case.regions[b.0].name)).collect();
    let burn = match &case.detonation {
        Some(det) if det.mode == BurnMode::Programmed => {
            "; a programmed burn has one lighting point, so the other charges are lit by the first's shock through what lies between (detonation.mode = \"instant\" fires them all at t = 0)"
        }
        _ => "",
    };
    Some(format!(
        "{} separate charges (explosive regions {}): the crater, the charge's axis and the peaks' scaled distances are measured for one charge, about detonation.point_m where given (else the explosive's centroid, between the charges) with the whole explosive's mass, so summary.json's crater and peaks.png describe at most the charge at that point (read the others from crater_map.png, the sections and the particles){burn}",
        ids.len(),
        names.join(", ")
    ))
}

/// Particles of two regions closer than half the finer region's spacing at the start (a
/// sphere's or a lattice's own points beside a box's, a charge off the soil's cells): one line
/// naming the closest pair, since the first steps see such a pair as a squeeze (a TNT sphere in
/// water on its own lattice put a water particle 0.38 spacings from the charge and the run
/// failed at its first step). Cell-list search over the real particles, O(N).
pub fn close_particle_warning(case: &Case, p: &Particles, region: &[u32]) -> Option<String> {
    let (d, n) = (case.dim, p.nreal.min(region.len()));
    let dx_of = |i: usize| case.regions.get(region[i] as usize).map_or(f64::INFINITY, |r| r.spacing_m);
    let h = (0..n).map(dx_of).fold(f64::INFINITY, f64::min);
    if n < 2 || !h.is_finite() || h <= 0.0 {
        return None;
    }
    let key = |i: usize| -> [i64; 3] {
        let mut k = [0i64; 3];
        for a in 0..d {
            k[a] = (p.x[d * i + a] / h).floor() as i64;
        }
        k
    };
    let mut cells: std::collections::HashMap<[i64; 3], Vec<usize>> = std::collections::HashMap::new();
    for i in 0..n {
        cells.entry(key(i)).or_default().push(i);
    }
    let (mut count, mut worst): (usize, Option<(f64, usize, usize)>) = (0, None);
    let reach = -1i64..=1;
    for i in 0..n {
        let k = key(i);
        for dz in if d == 3 { reach.clone() } else { 0..=0 } {
            for dy in if d >= 2 { reach.clone() } else { 0..=0 } {
                for dxk in reach.clone() {
                    let Some(list) = cells.get(&[k[0] + dxk, k[1] + dy, k[2] + dz]) else { continue };
                    for &j in list {
                        if j <= i || region[j] == region[i] {
                            continue;
                        }
                        let lim = 0.5 * dx_of(i).min(dx_of(j));
                        let r2: f64 = (0..d).map(|a| (p.x[d * i + a] - p.x[d * j + a]).powi(2)).sum();
                        if r2 < lim * lim {
                            count += 1;
                            let q = r2.sqrt() / (2.0 * lim);
                            if worst.is_none_or(|w| q < w.0) {
                                worst = Some((q, i, j));
                            }
                        }
                    }
                }
            }
        }
    }
    let (q, i, j) = worst?;
    let name = |k: usize| case.regions.get(region[k] as usize).map_or("?", |r| r.name.as_str());
    let at = |k: usize| (0..d).map(|a| format!("{:.4}", p.x[d * k + a])).collect::<Vec<_>>().join(", ");
    Some(format!(
        "{count} pairs of particles of different regions start closer than half a spacing: the closest, region `{}` at ({}) m and region `{}` at ({}) m, {q:.2} spacings apart; the first steps see such a pair as a squeeze (a round charge builds its own lattice: give it lo_m/hi_m on the surrounding box's cells, or subtract it from a box of its own spacing)",
        name(i),
        at(i),
        name(j),
        at(j)
    ))
}

/// Keys the case gives that its other settings leave unused (a value that does nothing is a
/// mistake more often than not): one line each.
pub fn ignored_keys(case: &Case) -> Vec<String> {
    let mut out = Vec::new();
    if case.time.step == StepRule::Cfl && case.time.dt_s.is_some() {
        out.push("time.dt_s is given but time.step = \"cfl\" (the default) sets every step: dt_s is not used (set time.step = \"fixed\" to use it)".to_string());
    }
    if case.sph.smoothing == crate::case::SmoothingKind::Constant && case.sph.h_max_ratio.is_some() {
        out.push("sph.h_max_ratio is given but sph.smoothing = \"constant\" keeps h at its initial value: the cap is not used".to_string());
    }
    for r in &case.regions {
        if r.radial_center_m.is_some() && r.radial_velocity_ms.is_none() {
            out.push(format!(
                "region `{}`: radial_center_m is given without radial_velocity_ms: the centre is not used",
                r.name
            ));
        }
        let mut seen = Vec::new();
        for s in &r.subtract {
            if seen.contains(&s) {
                out.push(format!("region `{}`: subtract names `{s}` twice", r.name));
            }
            seen.push(s);
        }
    }
    out
}

/// Each region cut out of a box region (`subtract`) whose flat faces do not lie on that box's
/// cell faces (lo + k Δx of the box's lattice, to 10⁻⁴ of a spacing per spacing, as
/// `crate::case::size::cells` counts): one line each. The box keeps its lattice points outside the
/// cut, the cut region keeps its own lattice, and off the cell faces the seam between them is
/// not one spacing (from Δx/2 to 5Δx/2: docs/reference/cases.md, the paragraph on `subtract`), which the
/// first steps see as a gap or a squeeze. A box's faces are checked on every axis; a cylinder's
/// base and top (z) and the planes of its `lo_m`/`hi_m` that cut it; a sphere is round; a
/// `keep_below` plane normal to an axis is a face where it cuts the box's or cylinder's span
/// (an inclined one cuts the lattice in a staircase and is not checked).
pub fn seam_warnings(case: &Case) -> Vec<String> {
    use crate::case::Shape;
    let d = case.dim;
    let axis = ["x", "y", "z"];
    let axis_rz = ["r", "z", ""];
    let mut out = Vec::new();
    for host in case.regions.iter().filter(|h| h.shape == Shape::Box && !h.subtract.is_empty()) {
        let (Some(hlo), Some(hhi)) = (&host.lo_m, &host.hi_m) else { continue };
        let dx = host.spacing_m;
        for name in &host.subtract {
            let Some(cut) = case.regions.iter().find(|r| &r.name == name) else { continue };
            // the flat faces: (axis, coordinate)
            let mut faces: Vec<(usize, f64)> = Vec::new();
            // a keep_below plane normal to an axis is a face where it cuts the shape's span on
            // that axis
            let clip_faces = |faces: &mut Vec<(usize, f64)>, span: &dyn Fn(usize) -> (f64, f64)| {
                for c in &cut.keep_below {
                    let axes: Vec<usize> = (0..d.min(c.normal.len())).filter(|&a| c.normal[a] != 0.0).collect();
                    if let [a] = axes[..]
                        && let Some(&f) = c.point_m.get(a)
                        && f > span(a).0
                        && f < span(a).1
                    {
                        faces.push((a, f));
                    }
                }
            };
            match cut.shape {
                Shape::Box => {
                    if let (Some(l), Some(h)) = (&cut.lo_m, &cut.hi_m) {
                        for a in 0..d {
                            faces.push((a, l[a]));
                            faces.push((a, h[a]));
                        }
                        clip_faces(&mut faces, &|a| (l[a], h[a]));
                    }
                }
                Shape::Cylinder if d == 3 => {
                    if let (Some(c), Some(r), Some(ht)) = (&cut.center_m, cut.radius_m, cut.height_m) {
                        faces.push((2, c[2]));
                        faces.push((2, c[2] + ht));
                        // a clip plane is a face only where it cuts the cylinder (a loose
                        // bounding clip at or beyond its side or ends is none)
                        let span = [(c[0] - r, c[0] + r), (c[1] - r, c[1] + r), (c[2], c[2] + ht)];
                        if let (Some(l), Some(h)) = (&cut.lo_m, &cut.hi_m) {
                            for a in 0..d {
                                for f in [l[a], h[a]] {
                                    if f > span[a].0 && f < span[a].1 {
                                        faces.push((a, f));
                                    }
                                }
                            }
                        }
                        clip_faces(&mut faces, &|a| span[a]);
                    }
                }
                _ => {}
            }
            // a face inside the host's span (one on or beyond its boundary leaves no seam)
            let off = faces.into_iter().find(|&(a, f)| {
                if !(f > hlo[a] && f < hhi[a]) {
                    return false;
                }
                let k = (f - hlo[a]) / dx;
                let tol = 1e-9 + 1e-4 * k.abs();
                (k - k.round()).abs() > tol
            });
            if let Some((a, f)) = off {
                let k = (f - hlo[a]) / dx;
                let an = if case.axisymmetric() { axis_rz[a] } else { axis[a] };
                out.push(format!(
                    "region {}: its face at {an} = {f} m is {k:.3} spacings of region {} from that region's lo_m, not a whole number: the seam between them is not one spacing (a gap or a squeeze in the first steps); put the faces on {}'s cell faces, lo_m + k x {dx} m (docs/reference/cases.md, `subtract`)",
                    cut.name, host.name, host.name
                ));
            }
        }
    }
    out
}

/// Input that reads as a slip of units (every check a factor of about 1000 or more off what the
/// material can be): an explosive region's specific energy between 0 and
/// 10⁵ J/kg (high explosives release 2–10 MJ/kg: kJ/kg for J/kg); a region whose `mass_kg` gives
/// its particles more than 3 × or less than a third of its shape's mass at its density (g for
/// kg: a per-particle mass 1000 × too large); a cylinder or sphere whose radius does not cut its
/// `lo_m`/`hi_m` box at all (mm for m: the region is then the box). One line each. (A density in
/// g/cm³ never gets here: [`crate::case::slips`] refuses it.)
pub fn unit_warnings(case: &Case, p: &Particles, region: &[u32]) -> Vec<String> {
    use crate::case::{EosCfg, Shape};
    let mut out = Vec::new();
    let d = case.dim;
    for (r, rc) in case.regions.iter().enumerate() {
        let Some(m) = case.material_index(&rc.material) else { continue };
        let mc = &case.materials[m];
        if let Some(e) = rc.e_jkg
            && matches!(mc.eos, EosCfg::Jwl { .. })
            && e > 0.0
            && e < 1e5
        {
            out.push(format!(
                "region {} ({}): e_jkg = {e} J/kg, while high explosives release 2–10 MJ/kg (TNT 4.29e6 J/kg): an energy in kJ/kg? (× 1000)",
                rc.name, mc.name
            ));
        }
        if matches!(rc.shape, Shape::Cylinder | Shape::Sphere)
            && let (Some(lo), Some(hi), Some(c), Some(rad)) = (&rc.lo_m, &rc.hi_m, &rc.center_m, rc.radius_m)
        {
            // every corner of the clip box (in the plane of the round section) within the radius
            let axes = if rc.shape == Shape::Cylinder { 2 } else { d };
            let corners_in = (0..1usize << axes).all(|k| {
                (0..axes).map(|a| (if k >> a & 1 == 1 { hi[a] } else { lo[a] } - c[a]).powi(2)).sum::<f64>() < rad * rad
            });
            if corners_in {
                out.push(format!(
                    "region {}: its radius_m = {rad} m does not cut its lo_m/hi_m box (every corner lies within it): the region is the box, not a {}; a radius in mm? (÷ 1000)",
                    rc.name,
                    if rc.shape == Shape::Cylinder { "cylinder" } else { "sphere" }
                ));
            }
        }
        if let Some(mk) = rc.mass_kg
            && rc.subtract.is_empty()
            && rc.keep_below.is_empty()
            && matches!(rc.shape, Shape::Box | Shape::Cylinder | Shape::Sphere)
            && let Some((lo, hi)) = crate::setup::region_box(case, r)
        {
            let rho = rc.rho_kgm3.or(mc.eos.rho0()).unwrap_or(0.0);
            let (held, count) = region_mass(p, region, r);
            let shape_mass = rho * shape_volume(case, r, &lo, &hi);
            let ratio = held / shape_mass;
            if count > 0 && shape_mass > 0.0 && !(1.0 / 3.0..=3.0).contains(&ratio) {
                let unit = match (d, case.axisymmetric()) {
                    (1, _) => "kg/m²",
                    (2, false) => "kg/m",
                    _ => "kg",
                };
                out.push(format!(
                    "region {} ({}): mass_kg = {mk} kg per particle gives its {count} particles {held:.4e} {unit}, {ratio:.3e} × its shape's {shape_mass:.4e} {unit} at {rho} kg/m³: mass_kg is each particle's mass, in kg",
                    rc.name, mc.name
                ));
            }
        }
    }
    out
}

/// A point blast (`[analysis] kind = "sedov"`) fewer than 20 spacings from its centre at the
/// end: its smeared front and the particles thrown ahead of it weigh on the measures (a docs-only
/// check's 3D octant at 14 spacings: peak 0.976, half-jump 1.068 of the exact radius, particles
/// up to 1.33 R ahead; the docs' figures are at 25 spacings or more). One line, or None.
pub fn sedov_spacing_warning(case: &Case) -> Option<String> {
    let (r, dx) = crate::analysis::sedov_edge::sedov_end_radius(case)?;
    let spacings = r / dx;
    (spacings.is_finite() && spacings < 20.0).then(|| {
        format!(
            "a point blast {spacings:.1} spacings from its centre at the end: the front is smeared over 3-4 spacings and particles run ahead of it (a 3D octant at 14 spacings: density peak 0.976 and half-jump 1.068 of the exact radius, particles up to 1.33 R ahead); aim for 25 spacings or more (docs/validation.md, Sedov-Taylor)"
        )
    })
}

/// An analysis that measures about the wrong point: a point blast's `analysis.center_m` more
/// than two spacings from its energy deposit (the particles whose e exceeds 100 × the median, at
/// most 2 % of them; their centroid moved onto a symmetry plane within Δx, whose images complete
/// it), or a Noh analysis of a case with no radial inflow. Both read as a code that failed (a
/// docs-only check's centre 0.1 m off read the shock radius 0.727 of exact).
pub fn analysis_warning(case: &Case, p: &Particles) -> Option<String> {
    let (d, n) = (case.dim, p.nreal);
    match case.analysis.kind {
        AnalysisKind::Noh if case.regions.iter().all(|r| r.radial_velocity_ms.is_none_or(|v| v == 0.0)) => {
            return Some(
                "analysis.kind = \"noh\" but no region has a radial_velocity_ms: the Noh problem is a cold gas falling onto a centre, and its measures (the post-shock density, the shock radius) mean nothing here".into(),
            );
        }
        AnalysisKind::Sedov => {}
        _ => return None,
    }
    let c0 = case.analysis.center_m.as_ref()?;
    if n < 8 || c0.len() < d {
        return None;
    }
    let (_, mut c, dx) = deposit(case, p, 1.0)?;
    if case.geometry == Geometry::Axisymmetric {
        c[0] = 0.0;
    }
    let off = (0..d).map(|k| (c[k] - c0[k]).powi(2)).sum::<f64>().sqrt();
    (off > 2.0 * dx).then(|| {
        let cs: Vec<String> = c.iter().map(|v| format!("{v:.4}")).collect();
        format!(
            "analysis.center_m is {off:.3e} m ({:.1} spacings) from the energy deposit's centre [{}] m: the shock radius is measured about the wrong point",
            off / dx,
            cs.join(", ")
        )
    })
}

/// A wall's plane: a point on it and its unit normal (2D: the line through the segment; 3D: the
/// plane of the parallelogram or axis-aligned rectangle); None in 1D or when degenerate.
fn wall_plane(d: usize, w: &crate::case::WallCfg) -> Option<(Vec<f64>, Vec<f64>)> {
    let (a, b) = (&w.from_m, &w.to_m);
    let nrm: Vec<f64> = match d {
        2 => vec![-(b[1] - a[1]), b[0] - a[0]],
        3 => match &w.edge_m {
            Some(e) => {
                let (u, v) = ([e[0] - a[0], e[1] - a[1], e[2] - a[2]], [b[0] - e[0], b[1] - e[1], b[2] - e[2]]);
                vec![u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
            }
            None => {
                let flat: Vec<f64> = (0..3).map(|k| if a[k] == b[k] { 1.0 } else { 0.0 }).collect();
                if flat.iter().sum::<f64>() != 1.0 {
                    return None;
                }
                flat
            }
        },
        _ => return None,
    };
    let len = nrm.iter().map(|x| x * x).sum::<f64>().sqrt();
    (len > 0.0 && len.is_finite()).then(|| (a.clone(), nrm.iter().map(|x| x / len).collect()))
}

/// The likely fix of a run that stopped with the diagnostic `msg`, from the case's settings.
pub fn hint(case: &Case, msg: &str) -> String {
    let s = &case.sph;
    let mut out = Vec::new();
    if (msg.contains("density = -") || msg.contains("(not above zero)"))
        && s.density == DensityKind::Continuity
        && case.materials.iter().any(|m| matches!(m.eos, EosCfg::Jwl { .. }))
        && case.materials.iter().all(|m| matches!(m.eos, EosCfg::Jwl { .. } | EosCfg::IdealGas { .. }))
    {
        // (a charge with soil or water beside it keeps continuity: summation smooths the density
        // across the interface)
        out.push("detonation products alone in a void: set sph.density = \"summation\" (the default for them): by continuity their rarefied centre runs below zero density whatever the step (docs/validation.md, \"A charge alone in a void\")");
    }
    if msg.contains("density = -") || msg.contains("non-finite") {
        if s.density == DensityKind::Continuity && s.continuity_form == ContinuityForm::Mass {
            out.push("set sph.continuity_form = \"volume\" (the mass form drives low-density particles beside dense ones negative)");
        }
        if s.energy_form == EnergyForm::Symmetric {
            out.push("set sph.energy_form = \"asymmetric\"");
        }
    }
    if msg.contains("total energy") {
        if !case.time.viscous_step && case.time.step == StepRule::Cfl {
            out.push("set time.viscous_step = true (the step then sees the viscosity's signal speed)");
        }
        if s.energy_form == EnergyForm::Symmetric {
            out.push("set sph.energy_form = \"asymmetric\"");
        }
        if case.time.step == StepRule::Fixed {
            out.push("use time.step = \"cfl\" or a smaller time.dt_s");
        }
    }
    if msg.contains("smoothing length collapsed") {
        // h shrinks a hundredfold only where particles pile up or pass through each other
        if case.viscosity.alpha == 0.0 && case.viscosity.beta == 0.0 {
            out.push("turn the artificial viscosity back on (leave viscosity.alpha and beta at their defaults): without it particles pass through each other at a shock");
        } else {
            out.push("lower time.cfl (or time.dt_s for a fixed step): particles passed through each other");
        }
    } else if msg.contains("smoothing length") {
        out.push("cap h with sph.h_max_ratio, or use sph.smoothing = \"density\"");
    }
    if msg.contains("the end is out of reach") {
        // the step is what it is (a smaller CFL number would only need more of them): the end
        // time, the step's caps or the steps allowed are what to change
        out.push("give an end time the run can reach (--end-time), raise time.max_steps, or lift a cap on the step (time.dt_max_s)");
    }
    if msg.contains("max_steps reached") {
        // not a blow-up: the step limit (lowering the CFL number would only need more steps)
        out.push("raise time.max_steps (a safety limit: t over the steps taken shows whether the step has collapsed)");
    }
    if msg.contains("crossed the axis") {
        // no wall setting applies: the particle moved through the axis's mirrors in one step
        out.push(if case.time.step == StepRule::Cfl {
            "lower time.cfl and keep the artificial viscosity on: a particle moved across the axis's mirror images within one step"
        } else {
            "lower time.dt_s and keep the artificial viscosity on: a particle moved across the axis's mirror images within one step"
        });
    }
    if msg.contains("crossed wall") {
        out.push("raise boundary.d_m2s2 towards the square of the largest speed, or use kind = \"both\" walls");
    }
    if let Some(d) = case.detonation.as_ref().filter(|d| d.mode == BurnMode::Programmed)
        && (d.width_h <= 0.0 || !d.beta_burn)
        && case
            .materials
            .iter()
            .any(|m| msg.contains(&format!("material {}", m.name)) && matches!(m.eos, EosCfg::Jwl { .. }))
    {
        out.push("use detonation.width_h = 2 and beta_burn = true (the defaults)");
    }
    // a failure in the first steps is the set-up's more often than the step's
    let after = msg.find("step ").map(|k| &msg[k + 5..]).unwrap_or("");
    let digits: String = after.chars().take_while(|c| c.is_ascii_digit()).collect();
    let step: Option<u64> = digits.parse().ok();
    let early = step.is_some_and(|n| n <= 3) && !msg.contains("max_steps");
    if early {
        out.push("read `blastsph check`'s warnings first: a run that fails within its first steps usually starts from a bad set-up (particles of two regions too close, a charge off the soil's cells)");
    }
    if out.is_empty() || (early && out.len() == 1 && !msg.contains("the end is out of reach")) {
        out.push(if case.time.step == StepRule::Cfl { "lower time.cfl (e.g. 0.15)" } else { "lower time.dt_s" });
    }
    format!("likely fix: {} (docs/validation.md, \"Safe defaults: what `check` and `run` warn of\")", out.join("; "))
}

#[cfg(test)]
mod tests;
