//! What `blastsph check` warns about and what the unstable-run diagnostic suggests: settings that
//! are known to fail, each with the evidence in docs/validation.md ("Safe defaults: what `check` and `run` warn of"), and the
//! likely fix of a run that stopped.

use crate::case::{
    AnalysisKind, BurnMode, Case, ContinuityForm, DensityKind, EnergyForm, EosCfg, GaugeKind, Geometry, KernelKind,
    StepRule, WallKind,
};
use crate::state::Particles;

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
    // water beside a charge's products, without a cavitation floor
    if jwl {
        for m in case.materials.iter().filter(|m| matches!(m.eos, EosCfg::Water { .. }) && m.pmin_pa.is_none()) {
            w.push(format!(
                "material `{}` (water) has no pmin_pa: beside the detonation products it takes tension without limit (down to -690 MPa at a 0.11 kg charge's products, RZ at 5 mm; real water cavitates near 0); set material.{}.pmin_pa = 0 for a bubble, cavitation or a free surface's spall (in that run the gauges' peaks moved by under 2 %, their impulses by up to 5 %, and it took 978 steps instead of 1448; docs/cases.md, the water preset)",
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
        w.push(format!("sph.h_over_dx = {}: below 0.9 the thesis's runs failed (THESIS.md s.1)", s.h_over_dx));
    }
    for r in &case.regions {
        if let Some(h) = r.h_m.filter(|h| *h < 0.9 * r.spacing_m) {
            w.push(format!(
                "region {}: h_m = {h:e} m is {:.3} of its spacing: below 0.9 the thesis's runs failed (THESIS.md s.1), and the particles have few neighbours",
                r.name,
                h / r.spacing_m
            ));
        }
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
        .chain(crate::analysis::verify::sedov_edge_warning(case, case.time.end_s, p.nreal, &|i| {
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
            let (c0, rho0) = match m.eos {
                EosCfg::Soil { c_ms, rho0_kgm3, .. } => (c_ms, rho0_kgm3),
                EosCfg::Water { c0_ms, rho0_kgm3, .. } => (c0_ms, rho0_kgm3),
                _ => return None,
            };
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
        .filter(|(_, w)| w.from_m[0] == w.to_m[0] && w.from_m[0] > 0.0)
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
/// [`crate::setup::cells`] counts): one line each. The box keeps its lattice points outside the
/// cut, the cut region keeps its own lattice, and off the cell faces the seam between them is
/// not one spacing (from Δx/2 to 5Δx/2: docs/cases.md, the paragraph on `subtract`), which the
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
                    "region {}: its face at {an} = {f} m is {k:.3} spacings of region {} from that region's lo_m, not a whole number: the seam between them is not one spacing (a gap or a squeeze in the first steps); put the faces on {}'s cell faces, lo_m + k x {dx} m (docs/cases.md, `subtract`)",
                    cut.name, host.name, host.name
                ));
            }
        }
    }
    out
}

/// Each explosive region (JWL) shaped as a box, cylinder or sphere, with no `subtract`, no
/// `keep_below` planes (the clipped shape's volume is not computed) and no `mass_kg` of its own
/// (a mass the case sets is the user's choice: the thesis's C4 charge holds 6.4/6 of its box on
/// purpose), whose particles hold more than 2 % more or less mass than the
/// shape (its volume, clipped to its `lo_m`/`hi_m`, times the region's density; in RZ the volume
/// of revolution, in 2D plane per metre): one line each. A lattice fills a round shape by whole
/// cells (a staircase), and a box by whole spacings from its corner: a charge of 2 spacings per
/// radius in 3D holds a few per cent more or less than its cylinder, and its energy with it. The
/// shape's volume is a midpoint sum over a grid of its bounding box, about 200 points along its
/// longest side (its error well below the 2 %).
pub fn charge_mass_warnings(case: &Case, p: &Particles, region: &[u32]) -> Vec<String> {
    use crate::case::{EosCfg, Shape};
    let d = case.dim;
    let mut out = Vec::new();
    for (r, rc) in case.regions.iter().enumerate() {
        let Some(m) = case.material_index(&rc.material) else { continue };
        let mc = &case.materials[m];
        if !matches!(mc.eos, EosCfg::Jwl { .. })
            || !rc.subtract.is_empty()
            || !rc.keep_below.is_empty()
            || rc.mass_kg.is_some()
            || !matches!(rc.shape, Shape::Box | Shape::Cylinder | Shape::Sphere)
        {
            continue;
        }
        let Some((lo, hi)) = crate::setup::region_box(case, r) else { continue };
        let rho = rc.rho_kgm3.or(mc.eos.rho0()).unwrap_or(1.0);
        let (held, count) = region_mass(p, region, r);
        if count == 0 {
            continue;
        }
        let shape_mass = rho * shape_volume(case, r, &lo, &hi);
        let dev = held / shape_mass - 1.0;
        if shape_mass > 0.0 && dev.abs() > 0.02 {
            let unit = match (d, case.axisymmetric()) {
                (1, _) => "kg/m2",
                (2, false) => "kg/m",
                _ => "kg",
            };
            let fix = if case.axisymmetric() {
                "put the charge's faces on whole spacings from the axis and the ground, or refine the spacing"
                    .to_string()
            } else {
                format!(
                    "refine the spacing, or set region.{}.mass_kg = {:.6e} (each particle's mass) to hold the shape's mass",
                    rc.name,
                    shape_mass / count as f64
                )
            };
            out.push(format!(
                "region {} ({}): its {count} particles hold {held:.4} {unit}, its {} {shape_mass:.4} {unit} ({:+.1} %): a lattice fills a shape by whole cells, and the blast's energy follows the particles' mass; {fix}",
                rc.name,
                mc.name,
                match rc.shape {
                    Shape::Cylinder => "cylinder",
                    Shape::Sphere => "sphere",
                    _ => "box",
                },
                100.0 * dev
            ));
        }
    }
    out
}

/// A 2D plane point blast (`[analysis] kind = "sedov"`) grown past 50 spacings from its centre
/// by the end, with the default h cap and no conductivity: one line, or None. The cap holds the
/// deposit's h at 4 h0 while its neighbours are blown out of reach, so the deposit keeps heat the
/// shock should carry, and the more so the finer the lattice: the case file's blast peaks at
/// 0.994 of the exact radius at 104² (33 spacings) and 0.965 at 208² (66); with the conductivity
/// (which leaves the cap out) 0.991 and 0.990 (docs/validation.md, "Sedov–Taylor in 2D: resolution").
/// The radius and Δx are the report's (`verify::sedov_end_radius`: its energy, ambient density
/// and finest spacing).
pub fn stranded_deposit_warning(case: &Case) -> Option<String> {
    if case.dim != 2 || case.geometry == Geometry::Axisymmetric || case.conductivity.alpha > 0.0 {
        return None;
    }
    let cap = case.sph.h_max_ratio?;
    let (r, dx) = crate::analysis::verify::sedov_end_radius(case)?;
    let spacings = r / dx;
    (spacings.is_finite() && spacings > 50.0).then(|| {
        format!(
            "a 2D point blast {spacings:.0} spacings from its centre at the end, with the h cap (sph.h_max_ratio = {cap}) and no conductivity: the cap strands the deposit's heat and the shock lags more the finer the lattice (peak 0.994 of the exact radius at 33 spacings, 0.965 at 66); set [conductivity] alpha = 1 (0.990 at 66; docs/validation.md, \"Sedov–Taylor in 2D: resolution\")"
        )
    })
}

/// The mass region `r`'s real particles hold at the start (kg; per metre in 2D plane) and their
/// count.
fn region_mass(p: &Particles, region: &[u32], r: usize) -> (f64, usize) {
    (0..p.nreal.min(region.len()))
        .filter(|&i| region[i] as usize == r)
        .fold((0.0, 0usize), |(s, c), i| (s + p.mass[i], c + 1))
}

/// The volume of region `r`'s shape within its box `lo`..`hi` (m³; in RZ the volume of
/// revolution, in 2D plane m² per metre): a midpoint sum over a grid of the box, about 200
/// points along its longest side (its error well below 2 %); 0 for an empty box.
fn shape_volume(case: &Case, r: usize, lo: &[f64; 3], hi: &[f64; 3]) -> f64 {
    let d = case.dim;
    let longest = (0..d).map(|a| hi[a] - lo[a]).fold(0.0, f64::max);
    if longest.is_nan() || longest <= 0.0 {
        return 0.0;
    }
    let step = longest / 200.0;
    let cnt: Vec<usize> = (0..d).map(|a| (((hi[a] - lo[a]) / step).ceil() as usize).max(1)).collect();
    let cell: Vec<f64> = (0..d).map(|a| (hi[a] - lo[a]) / cnt[a] as f64).collect();
    let mut vol = 0.0;
    let mut idx = vec![0usize; d];
    'grid: loop {
        let mut q = [0.0; 3];
        for a in 0..d {
            q[a] = lo[a] + (idx[a] as f64 + 0.5) * cell[a];
        }
        if crate::setup::inside(case, r, &q) && !(case.axisymmetric() && q[0] < 0.0) {
            let w: f64 = cell.iter().product();
            vol += if case.axisymmetric() { 2.0 * std::f64::consts::PI * q[0] * w } else { w };
        }
        for a in 0..d {
            idx[a] += 1;
            if idx[a] < cnt[a] {
                continue 'grid;
            }
            idx[a] = 0;
        }
        break;
    }
    vol
}

/// Input that reads as a slip of units (every check a factor of about 1000 or more off what the
/// material can be): a condensed material's (explosive, water, soil) density below 100 kg/m³
/// (g/cm³ for kg/m³: TNT 1.63 for 1630); an explosive region's specific energy between 0 and
/// 10⁵ J/kg (high explosives release 2–10 MJ/kg: kJ/kg for J/kg); a region whose `mass_kg` gives
/// its particles more than 3 × or less than a third of its shape's mass at its density (g for
/// kg: a per-particle mass 1000 × too large); a cylinder or sphere whose radius does not cut its
/// `lo_m`/`hi_m` box at all (mm for m: the region is then the box). One line each.
pub fn unit_warnings(case: &Case, p: &Particles, region: &[u32]) -> Vec<String> {
    use crate::case::{EosCfg, Shape};
    let condensed = |e: &EosCfg| matches!(e, EosCfg::Jwl { .. } | EosCfg::Water { .. } | EosCfg::Soil { .. });
    let mut out = Vec::new();
    for mc in &case.materials {
        if let Some(r0) = mc.eos.rho0()
            && condensed(&mc.eos)
            && r0 < 100.0
        {
            out.push(format!(
                "material {}: rho0_kgm3 = {r0} kg/m³, below any {} (1000–3000 kg/m³): a density in g/cm³? (× 1000)",
                mc.name,
                match mc.eos {
                    EosCfg::Jwl { .. } => "condensed explosive",
                    EosCfg::Water { .. } => "water",
                    _ => "soil",
                }
            ));
        }
    }
    let d = case.dim;
    for (r, rc) in case.regions.iter().enumerate() {
        let Some(m) = case.material_index(&rc.material) else { continue };
        let mc = &case.materials[m];
        if let Some(rho) = rc.rho_kgm3
            && condensed(&mc.eos)
            && rho < 100.0
            && mc.eos.rho0().is_none_or(|r0| r0 >= 100.0)
        {
            out.push(format!(
                "region {} ({}): rho_kgm3 = {rho} kg/m³, below any condensed material's (1000–3000 kg/m³): a density in g/cm³? (× 1000)",
                rc.name, mc.name
            ));
        }
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

/// An explosive region beside a symmetry plane (an axis-aligned `mirror` wall; not the axis of
/// an RZ run) that it does not abut, within five of its own sizes of it: the plane's image of the
/// charge is a second charge, so the scene holds 2^k charges (k such planes) — what a quarter
/// model of one charge off its planes' intersection silently became (a docs-only engineer's
/// 0.5 kg quarter centred 0.1 m off both planes ran as four charges, 2 kg). One line per region,
/// naming the planes, the gap and the scene's charges; a charge that abuts its planes (a half,
/// quarter or octant of one charge) or straddles one is not named here.
pub fn charge_image_warnings(case: &Case, p: &Particles, region: &[u32]) -> Vec<String> {
    let axis = ["x", "y", "z"];
    let mut out = Vec::new();
    for (r, rc) in case.regions.iter().enumerate() {
        let Some(m) = case.material_index(&rc.material) else { continue };
        if !matches!(case.materials[m].eos, EosCfg::Jwl { .. }) {
            continue;
        }
        let Some((lo, hi)) = crate::setup::region_box(case, r) else { continue };
        let size = (0..case.dim).map(|a| hi[a] - lo[a]).fold(0.0, f64::max);
        let mut near: Vec<(usize, f64, f64)> = Vec::new();
        for (k, c) in case.axis_mirrors() {
            if k == 0 && case.axisymmetric() {
                continue;
            }
            let gap = if lo[k] >= c {
                lo[k] - c
            } else if hi[k] <= c {
                c - hi[k]
            } else {
                continue;
            };
            if gap > 0.5 * rc.spacing_m && gap < 5.0 * size && !near.iter().any(|q| q.0 == k && q.1 == c) {
                near.push((k, c, gap));
            }
        }
        if near.is_empty() {
            continue;
        }
        let held = region_mass(p, region, r).0;
        let copies = 1usize << near.len();
        let planes: Vec<String> =
            near.iter().map(|(k, c, g)| format!("{} = {c} m ({:.3} m from it)", axis[*k], g)).collect();
        out.push(format!(
            "region {} (explosive) does not abut the symmetry plane{} {}: each plane's image of it is another charge, so the scene holds {copies} charges ({:.4} kg in all, {:.4} kg each); a half or quarter model of one charge puts the charge's centre on its planes",
            rc.name,
            if near.len() == 1 { "" } else { "s" },
            planes.join(" and "),
            held * copies as f64,
            held
        ));
    }
    out
}

/// A point blast (`[analysis] kind = "sedov"`) fewer than 20 spacings from its centre at the
/// end: its smeared front and the particles thrown ahead of it weigh on the measures (a docs-only
/// check's 3D octant at 14 spacings: peak 0.976, half-jump 1.068 of the exact radius, particles
/// up to 1.33 R ahead; the docs' figures are at 25 spacings or more). One line, or None.
pub fn sedov_spacing_warning(case: &Case) -> Option<String> {
    let (r, dx) = crate::analysis::verify::sedov_end_radius(case)?;
    let spacings = r / dx;
    (spacings.is_finite() && spacings < 20.0).then(|| {
        format!(
            "a point blast {spacings:.1} spacings from its centre at the end: the front is smeared over 3-4 spacings and particles run ahead of it (a 3D octant at 14 spacings: density peak 0.976 and half-jump 1.068 of the exact radius, particles up to 1.33 R ahead); aim for 25 spacings or more (docs/validation.md, Sedov-Taylor)"
        )
    })
}

/// A point deposit (a few particles far hotter than the rest) centred on a particle of a lattice
/// jittered less than gas dynamics' default (`sph.jitter` below `case::GAS_JITTER`), in 2D plane
/// or 3D: one line naming the evidence, or None. The deposit is the particles whose specific energy e exceeds 100 × the median e (at most 32 of them, and at most 2 % of
/// the particles); its centre is their centroid, moved onto any symmetry plane (a mirror wall)
/// within 0.75 Δx of it (the wall's images complete the deposit). It is "on a particle" when a
/// particle lies within Δx/4 of that centre (an odd lattice about the centre): there the rows
/// of particles along the lattice's mirror lines through the deposit run ahead of the front as
/// jets (at h = 1.2 Δx too). Measured in docs/validation.md, "Jets along the lattice's symmetry
/// lines", "Deposits in a few particles" (2D) and "Other deposits in RZ and 3D".
pub fn deposit_warning(case: &Case, p: &Particles) -> Option<String> {
    let (d, n) = (case.dim, p.nreal);
    if d < 2 || case.geometry == Geometry::Axisymmetric || case.sph.jitter >= crate::case::GAS_JITTER || n < 64 {
        return None;
    }
    let (hot, c, dx) = deposit(case, p, 0.75)?;
    if hot.len() > 32 {
        return None;
    }
    let on = (0..n).find(|&i| (0..d).map(|k| (p.x[d * i + k] - c[k]).powi(2)).sum::<f64>().sqrt() < 0.25 * dx)?;
    let evidence = if d == 2 {
        "on an exact lattice the rows along the axes through it run ahead of the front as jets and the shock lags 3.4-7.7 % by the density peak (101 x 101 to 105 x 105, 1 to 13 hot particles; jets at h = 1.2 dx too)"
    } else {
        "on an exact lattice the single centre particle lagged 5.6 % by the density peak (41^3)"
    };
    Some(format!(
        "point deposit centred on particle {} ({} hot particle{} at h = {} dx, sph.jitter = {:e}): {evidence}; sph.jitter = 5e-2 (the default of gas dynamics) breaks the lattice's symmetry and puts it within 2 % by the peak, without jets (docs/validation.md, \"Jets along the lattice's symmetry lines\")",
        p.id[on],
        hot.len(),
        if hot.len() == 1 { "" } else { "s" },
        case.sph.h_over_dx,
        case.sph.jitter
    ))
}

/// A point deposit of energy: the particles whose e exceeds 100 × the median (none, or more than
/// 2 % of the real particles: no point deposit), their spacing Δx (h / `h_over_dx`) and their
/// centroid, moved onto every mirror wall's plane within `snap` Δx of it (the images complete the
/// deposit there).
fn deposit(case: &Case, p: &Particles, snap: f64) -> Option<(Vec<usize>, Vec<f64>, f64)> {
    let (d, n) = (case.dim, p.nreal);
    let mut es: Vec<f64> = p.e[..n].iter().copied().filter(|e| e.is_finite()).collect();
    if n == 0 || es.len() < n {
        return None;
    }
    let med = es.select_nth_unstable_by(n / 2, f64::total_cmp).1.max(f64::MIN_POSITIVE);
    let hot: Vec<usize> = (0..n).filter(|&i| p.e[i] > 100.0 * med).collect();
    if hot.is_empty() || hot.len() * 50 > n {
        return None;
    }
    let dx = p.h[hot[0]] / case.sph.h_over_dx;
    if !(dx > 0.0 && dx.is_finite()) {
        return None;
    }
    let mut c = vec![0.0; d];
    for &i in &hot {
        for k in 0..d {
            c[k] += p.x[d * i + k] / hot.len() as f64;
        }
    }
    for w in case.walls.iter().filter(|w| w.kind != WallKind::Repulsive) {
        if let Some((o, nrm)) = wall_plane(d, w) {
            let s: f64 = (0..d).map(|k| (c[k] - o[k]) * nrm[k]).sum();
            if s.abs() < snap * dx {
                for k in 0..d {
                    c[k] -= s * nrm[k];
                }
            }
        }
    }
    Some((hot, c, dx))
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
mod tests {
    use super::*;

    fn case(extra: &str) -> Case {
        let text = format!(
            "dim = 1\n{extra}\n[time]\nend_s = 1.0\n[[material]]\nname = \"gas\"\neos = {{ kind = \"ideal_gas\", gamma = 1.4 }}\n[[region]]\nname = \"g\"\nmaterial = \"gas\"\nshape = \"lattice\"\norigin_m = [0.0]\ncount = [10]\nspacing_m = 0.1\nrho_kgm3 = 1.0\ne_jkg = 1.0\n"
        );
        crate::case::parse(&text, "test", &[], Some("t")).unwrap()
    }

    #[test]
    fn the_step_limit_is_not_answered_with_a_smaller_step() {
        let h = hint(&case(""), "step 40: time.max_steps reached at t = 6.4e-5 s before the end time");
        assert!(h.contains("raise time.max_steps"), "{h}");
        assert!(!h.contains("lower time.cfl"), "{h}");
        let h = hint(
            &case(""),
            "step 200 (t = 1e-3 s): at the pace of the last 100 steps (mean dt = 1e-5 s) the run needs about 1e11 more steps to reach 1e6 s, more than 10 × time.max_steps = 1e7 in all: the end is out of reach",
        );
        assert!(h.contains("--end-time") && !h.contains("lower time.cfl"), "{h}");
    }

    #[test]
    fn keys_that_the_other_settings_leave_unused_are_named() {
        assert!(ignored_keys(&case("")).is_empty());
        let with = |sets: &[&str]| {
            let text = "dim = 1\n[time]\nend_s = 1.0\n[[material]]\nname = \"gas\"\neos = { kind = \"ideal_gas\", gamma = 1.4 }\n[[region]]\nname = \"g\"\nmaterial = \"gas\"\nshape = \"lattice\"\norigin_m = [0.0]\ncount = [10]\nspacing_m = 0.1\nrho_kgm3 = 1.0\ne_jkg = 1.0\n";
            let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
            ignored_keys(&crate::case::parse(text, "test", &sets, Some("t")).unwrap())
        };
        let w = with(&["time.dt_s=0.01"]);
        assert!(w.len() == 1 && w[0].contains("time.dt_s") && w[0].contains("not used"), "{w:?}");
        assert!(with(&["time.dt_s=0.01", "time.step=fixed"]).is_empty());
        let w = with(&["sph.smoothing=constant", "sph.h_max_ratio=4"]);
        assert!(w.len() == 1 && w[0].contains("h_max_ratio"), "{w:?}");
        let w = with(&["region.g.radial_center_m=[0.5]"]);
        assert!(w.len() == 1 && w[0].contains("radial_center_m"), "{w:?}");
    }

    #[test]
    fn defaults_warn_of_nothing_and_the_parity_preset_of_its_known_failures() {
        assert!(warnings(&case("")).is_empty(), "{:?}", warnings(&case("")));
        let w = warnings(&case("parity = \"thesis\""));
        assert!(w.iter().any(|l| l.contains("energy_form")), "{w:?}");
        assert!(w.iter().any(|l| l.contains("viscous_step")), "{w:?}");
    }

    #[test]
    fn axisymmetric_with_a_wide_kernel_warns_of_the_axis_jet() {
        let rz = |h: &str| {
            let text = format!(
                "dim = 2\ngeometry = \"axisymmetric\"\n[sph]\nh_over_dx = {h}\n[time]\nend_s = 1.0\n[[material]]\nname = \"gas\"\neos = {{ kind = \"ideal_gas\", gamma = 1.4 }}\n[[region]]\nname = \"g\"\nmaterial = \"gas\"\nshape = \"box\"\nlo_m = [0.0, 0.0]\nhi_m = [1.0, 1.0]\nspacing_m = 0.1\nrho_kgm3 = 1.0\ne_jkg = 1.0\n"
            );
            warnings(&crate::case::parse(&text, "test", &[], Some("t")).unwrap())
        };
        assert!(rz("1.0").is_empty(), "{:?}", rz("1.0"));
        assert!(rz("1.2").iter().any(|l| l.contains("onto it")), "{:?}", rz("1.2"));
    }

    /// A gas box of n^dim particles at spacing 0.1 m, the hot ones `hot_lo`..`hot_hi` (a box
    /// region subtracted from the ambient one), with `extra` TOML appended.
    fn deposit(dim: usize, n: usize, hot_lo: f64, hot_hi: f64, lo: f64, extra: &str) -> Option<String> {
        let v = |a: f64| format!("[{}]", vec![format!("{a:?}"); dim].join(", "));
        let text = format!(
            "dim = {dim}\n[time]\nend_s = 1.0\n[[material]]\nname = \"gas\"\neos = {{ kind = \"ideal_gas\", gamma = 1.4 }}\n\
             [[region]]\nname = \"hot\"\nmaterial = \"gas\"\nshape = \"box\"\nlo_m = {}\nhi_m = {}\nspacing_m = 0.1\nrho_kgm3 = 1.0\ne_jkg = 1000.0\n\
             [[region]]\nname = \"amb\"\nmaterial = \"gas\"\nshape = \"box\"\nlo_m = {}\nhi_m = {}\nspacing_m = 0.1\nrho_kgm3 = 1.0\ne_jkg = 1e-6\nsubtract = [\"hot\"]\n{extra}",
            v(hot_lo),
            v(hot_hi),
            v(lo),
            v(lo + 0.1 * n as f64)
        );
        let c = crate::case::parse(&text, "test", &[], Some("t")).unwrap();
        let sim = crate::sim::Sim::new(c, &crate::sim::Overrides::default()).unwrap();
        deposit_warning(&sim.case, &sim.p)
    }

    /// A 2D point blast (E = 1 J/m, ρ = 1, 40 × 40 at 0.01 m) run to `end` s, with `extra` TOML.
    fn stranded(end: f64, extra: &str) -> Option<String> {
        let text = format!(
            "dim = 2\n[time]\nend_s = {end:?}\n[[material]]\nname = \"gas\"\neos = {{ kind = \"ideal_gas\", gamma = 1.4 }}\n\
             [[region]]\nname = \"amb\"\nmaterial = \"gas\"\nshape = \"box\"\nlo_m = [-0.2, -0.2]\nhi_m = [0.2, 0.2]\nspacing_m = 0.01\nrho_kgm3 = 1.0\ne_jkg = 1e-9\n\
             [analysis]\nkind = \"sedov\"\nenergy_j = 1.0\n{extra}"
        );
        let c = crate::case::parse(&text, "test", &[], Some("t")).unwrap();
        stranded_deposit_warning(&c)
    }

    #[test]
    fn a_2d_point_blast_grown_past_50_spacings_with_the_h_cap_warns() {
        // R = 1.004 (t²)^(1/4): 0.1 s -> 0.32 m (32 spacings), 0.3 s -> 0.55 m (55)
        assert!(stranded(0.1, "").is_none());
        let w = stranded(0.3, "");
        assert!(
            w.as_deref().is_some_and(|l| l.contains("55 spacings") && l.contains("[conductivity] alpha = 1")),
            "{w:?}"
        );
        // with the conductivity (no cap by default) or no cap, no warning
        assert!(stranded(0.3, "[conductivity]\nalpha = 1.0\n").is_none());
        assert!(stranded(0.3, "[sph]\nsmoothing = \"constant\"\n").is_none());
    }

    #[test]
    fn a_deposit_centred_on_a_particle_warns_and_one_about_a_lattice_corner_does_not() {
        let exact = "[sph]\njitter = 0.0\n";
        // 2D, 21 x 21 from -1.05: a particle at the origin, the hot one alone, on an exact lattice
        let w = deposit(2, 21, -0.05, 0.05, -1.05, exact);
        assert!(
            w.as_deref().is_some_and(|l| l.contains("1 hot particle ") && l.contains("sph.jitter = 5e-2")),
            "{w:?}"
        );
        // the default jitter of gas dynamics breaks the symmetry: no warning
        assert!(deposit(2, 21, -0.05, 0.05, -1.05, "").is_none());
        assert!(deposit(2, 21, -0.05, 0.05, -1.05, "[sph]\njitter = 1e-2\n").is_some());
        // the nine of a 3 x 3 block about it (41 x 41) are centred on it too
        assert!(deposit(2, 41, -0.15, 0.15, -2.05, exact).is_some_and(|l| l.contains("9 hot particles")));
        // whatever the smoothing-length rule (the thesis's "rate" keeps no initial h0) and h
        assert!(deposit(2, 21, -0.05, 0.05, -1.05, &format!("{exact}smoothing = \"rate\"")).is_some());
        assert!(deposit(2, 21, -0.05, 0.05, -1.05, &format!("{exact}smoothing = \"constant\"")).is_some());
        assert!(deposit(2, 21, -0.05, 0.05, -1.05, &format!("{exact}h_over_dx = 1.2")).is_some());
        // 20 x 20 from -1.0: the four about the origin (a lattice corner)
        assert!(deposit(2, 20, -0.1, 0.1, -1.0, exact).is_none());
        // 3D octant: one particle beside three mirror planes through the origin
        let mirrors = "[[wall]]\nfrom_m = [0.0, 0.0, 0.0]\nto_m = [0.0, 1.0, 1.0]\nkind = \"mirror\"\n\
                       [[wall]]\nfrom_m = [0.0, 0.0, 0.0]\nto_m = [1.0, 0.0, 1.0]\nkind = \"mirror\"\n\
                       [[wall]]\nfrom_m = [0.0, 0.0, 0.0]\nto_m = [1.0, 1.0, 0.0]\nkind = \"mirror\"\n";
        assert!(deposit(3, 10, 0.0, 0.1, 0.0, &format!("{exact}{mirrors}")).is_none());
        // without the mirrors the same particle is a deposit centred on itself
        assert!(deposit(3, 10, 0.0, 0.1, 0.0, exact).is_some_and(|l| l.contains("(41^3)")));
    }

    /// A case of `cases/` with `--set` overrides.
    fn shipped_case(name: &str, sets: &[&str]) -> Case {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("cases").join(name);
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        crate::case::load(&path, &sets).unwrap()
    }

    #[test]
    fn a_late_crater_in_a_soil_with_a_tension_cut_off_warns_of_the_viscosity() {
        let load = |name: &str, sets: &[&str]| warnings(&shipped_case(name, sets));
        let late = load("surface_loose_tnt1kg_rz_final.toml", &[]);
        assert!(late.iter().any(|l| l.contains("held back by the artificial viscosity")), "{late:?}");
        // the thesis's scenes (1 ms) do not warn; nor a late run without the cut-off
        assert!(load("surface_loose_tnt6.toml", &[]).is_empty(), "{:?}", load("surface_loose_tnt6.toml", &[]));
        let unclamped = load("surface_loose_tnt1kg_rz_final.toml", &["material.loose_sand.pmin_pa=-1e5"]);
        assert!(!unclamped.iter().any(|l| l.contains("artificial viscosity")), "{unclamped:?}");
    }

    /// An RZ blast whose outer wall's reflection converges on the axis before the end warns (a
    /// buried charge's soil there was thrown up and apart: crater 6 cm against 3D's 53 cm); the
    /// same scene ended before it, and the plane-strain original, do not.
    #[test]
    fn an_rz_wall_whose_reflection_converges_on_the_axis_in_the_run_warns() {
        let load = |name: &str, sets: &[&str]| wall_reflection_warning(&shipped_case(name, sets));
        // the wall at r = 0.5 m, loose sand's P wave √(C² + 4G/3ρ0): back on the axis at 0.68 ms
        let w = load("surface_loose_tnt6_rz.toml", &[]);
        assert!(
            w.as_deref().is_some_and(|l| l.contains("wall[1] at r = 0.500 m")
                && l.contains("0.68 ms")
                && l.contains("(1.00 ms)")),
            "{w:?}"
        );
        assert!(load("surface_loose_tnt6_rz.toml", &["time.end_s=6e-4"]).is_none());
        assert!(load("surface_loose_tnt6.toml", &[]).is_none());
    }

    #[test]
    fn the_wendland_kernel_at_h_equal_to_the_spacing_is_warned_of() {
        let w = |extra: &str| warnings(&case(extra)).into_iter().filter(|l| l.contains("Wendland")).count();
        assert_eq!(w("[sph]\nkernel = \"wendland\""), 1);
        assert_eq!(w("[sph]\nkernel = \"wendland\"\nh_over_dx = 1.3"), 0);
        assert_eq!(w(""), 0);
    }

    #[test]
    fn hints_name_the_setting() {
        let c = case("parity = \"thesis\"");
        assert!(hint(&c, "step 11: total energy 2 J exceeds").contains("time.viscous_step = true"));
        assert!(hint(&case(""), "particle 3 crossed wall 0").contains("boundary.d_m2s2"));
        let axis = hint(&case(""), "step 124: particle 3 crossed the axis r = 0 (a mirror) by 6e-3 m");
        assert!(axis.contains("lower time.cfl") && !axis.contains("d_m2s2"), "{axis}");
        assert!(hint(&case(""), "something else").contains("time.cfl"));
        let first = hint(&case(""), "step 1 (t = 4.8e-9 s): total energy 1.3e8 J exceeds the initial 8.0e6 J");
        assert!(first.contains("check`'s warnings first") && first.contains("time.cfl"), "{first}");
        assert!(!hint(&case(""), "step 40: particle 3 velocity").contains("warnings first"));
    }

    /// Two TNT boxes 0.2 m apart are two charges (the programmed burn's single point named); two
    /// boxes that touch are one.
    #[test]
    fn several_charges_are_named() {
        let two = |x0: f64, burn: &str| {
            let text = format!(
                "dim = 2\n[time]\nend_s = 1e-6\n[[material]]\nname = \"tnt\"\npreset = \"tnt\"\n\
                 [[region]]\nname = \"a\"\nmaterial = \"tnt\"\nshape = \"box\"\nlo_m = [0.0, 0.0]\nhi_m = [0.04, 0.04]\nspacing_m = 0.01\n\
                 [[region]]\nname = \"b\"\nmaterial = \"tnt\"\nshape = \"box\"\nlo_m = [{x0}, 0.0]\nhi_m = [{}, 0.04]\nspacing_m = 0.01\n{burn}",
                x0 + 0.04
            );
            several_charges(&crate::case::parse(&text, "test", &[], Some("t")).unwrap())
        };
        let w = two(0.24, "[detonation]\nmode = \"programmed\"\npoint_m = [0.02, 0.02]\n").expect("two charges");
        assert!(
            w.starts_with("2 separate charges (explosive regions `a`, `b`)") && w.contains("one lighting point"),
            "{w}"
        );
        assert!(!two(0.24, "").unwrap().contains("lighting"));
        assert_eq!(two(0.04, ""), None, "boxes that touch are one charge");
    }

    /// A TNT sphere in water on its own lattice (the docs-only check's case, coarser) puts a water
    /// particle within half a spacing of the charge; given the water's cells as its clip box, not.
    #[test]
    fn particles_of_two_regions_closer_than_half_a_spacing_warn() {
        let close = |clip: &str| {
            let text = format!(
                "dim = 2\ngeometry = \"axisymmetric\"\n[time]\nend_s = 1e-6\n\
                 [[material]]\nname = \"tnt\"\npreset = \"tnt\"\n[[material]]\nname = \"water\"\npreset = \"water\"\n\
                 [[region]]\nname = \"charge\"\nmaterial = \"tnt\"\nshape = \"sphere\"\ncenter_m = [0.0, 0.3]\nradius_m = 0.0527\nspacing_m = 0.01\n{clip}\n\
                 [[region]]\nname = \"water\"\nmaterial = \"water\"\nshape = \"box\"\nlo_m = [0.0, 0.0]\nhi_m = [0.3, 0.6]\nspacing_m = 0.01\nsubtract = [\"charge\"]\n"
            );
            let c = crate::case::parse(&text, "test", &[], Some("t")).unwrap();
            let sim = crate::sim::Sim::new(c, &crate::sim::Overrides::default()).unwrap();
            close_particle_warning(&sim.case, &sim.p, &sim.region)
        };
        let w = close("").expect("a warning");
        assert!(w.contains("region `charge`") && w.contains("region `water`") && w.contains("0.38 spacings"), "{w}");
        assert_eq!(close("lo_m = [0.0, 0.24]\nhi_m = [0.06, 0.36]"), None);
    }

    /// A TNT charge alone: a quarter cylinder of radius 2 spacings in 3D (`mass` sets
    /// region.charge.mass_kg), or the same section in RZ as rings.
    fn charge(dim3: bool, mass: &str) -> Vec<String> {
        let (geo, shape) = if dim3 {
            (
                "dim = 3",
                "shape = \"cylinder\"\ncenter_m = [0.0, 0.0, -0.04]\nradius_m = 0.02\nheight_m = 0.04\nlo_m = [0.0, 0.0, -0.04]\nhi_m = [0.02, 0.02, 0.0]",
            )
        } else {
            ("dim = 2\ngeometry = \"axisymmetric\"", "shape = \"box\"\nlo_m = [0.0, -0.04]\nhi_m = [0.02, 0.0]")
        };
        let text = format!(
            "{geo}\n[time]\nend_s = 1e-6\n[[material]]\nname = \"tnt\"\npreset = \"tnt\"\n\
             [[region]]\nname = \"charge\"\nmaterial = \"tnt\"\n{shape}\nspacing_m = 0.01\n{mass}\n"
        );
        let c = crate::case::parse(&text, "test", &[], Some("t")).unwrap();
        let sim = crate::sim::Sim::new(c, &crate::sim::Overrides::default()).unwrap();
        charge_mass_warnings(&sim.case, &sim.p, &sim.region)
    }

    #[test]
    fn a_charge_whose_lattice_misses_its_shape_by_more_than_2_percent_warns_with_the_mass_that_mends_it() {
        // 3D: a quarter cylinder of 2 x 2 x 4 cells keeps 3 of its 4 columns (12 particles): the
        // quarter disc's area is pi/4 of 4 cells, 3 cells hold 3/pi = 0.955 of it
        let w = charge(true, "");
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].contains("its 12 particles") && w[0].contains("(-4.5 %)"), "{w:?}");
        // the mass it proposes silences it (as any mass the case sets)
        let per = w[0].split("mass_kg = ").nth(1).and_then(|t| t.split_whitespace().next()).unwrap();
        assert!(charge(true, &format!("mass_kg = {per}")).is_empty());
        // RZ rings on whole spacings hold the cylinder's mass exactly
        assert!(charge(false, "").is_empty());
    }

    #[test]
    fn a_charge_cut_out_of_the_soil_off_its_cell_faces_warns_of_the_seam() {
        let clipped = |top: &str, clip: &str| {
            let text = format!(
                "dim = 2\ngeometry = \"axisymmetric\"\n[time]\nend_s = 1e-6\n[[material]]\nname = \"tnt\"\npreset = \"tnt\"\n\
                 [[material]]\nname = \"sand\"\npreset = \"dense_sand\"\n\
                 [[region]]\nname = \"charge\"\nmaterial = \"tnt\"\nshape = \"box\"\nlo_m = [0.0, -0.299]\nhi_m = [0.046, {top}]\nspacing_m = 0.023\n{clip}\n\
                 [[region]]\nname = \"soil\"\nmaterial = \"sand\"\nshape = \"box\"\nlo_m = [0.0, -1.012]\nhi_m = [1.012, 0.0]\nspacing_m = 0.023\nsubtract = [\"charge\"]\n"
            );
            seam_warnings(&crate::case::parse(&text, "test", &[], Some("t")).unwrap())
        };
        let scene = |top: &str| clipped(top, "");
        // on the soil's cell faces (-0.207 = -1.012 + 35 x 0.023): no seam
        assert!(scene("-0.207").is_empty());
        // 0.2 m under the ground is 35.304 spacings from the soil's bottom
        let w = scene("-0.2");
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].contains("z = -0.2 m") && w[0].contains("35.304 spacings"), "{w:?}");
        // a keep_below plane normal to the axis is a face: on the soil's cells (-0.23 = -1.012 +
        // 34 x 0.023) no seam, off them (-0.25: 33.130 spacings) a seam; an inclined plane is
        // not checked
        let plane = |z: &str, n: &str| format!("keep_below = [{{ point_m = [0.0, {z}], normal = {n} }}]");
        assert!(clipped("-0.207", &plane("-0.23", "[0.0, 1.0]")).is_empty());
        let w = clipped("-0.207", &plane("-0.25", "[0.0, 1.0]"));
        assert!(w.len() == 1 && w[0].contains("z = -0.25 m") && w[0].contains("33.130 spacings"), "{w:?}");
        assert!(clipped("-0.207", &plane("-0.25", "[1.0, 1.0]")).is_empty());
        // 3D: a quarter cylinder's clip planes through its axis and a loose clip beside it are no
        // seam; its base off the soil's cells is
        let quarter = |base: &str, hi: &str| {
            let text = format!(
                "dim = 3\n[time]\nend_s = 1e-6\n[[material]]\nname = \"tnt\"\npreset = \"tnt\"\n\
                 [[material]]\nname = \"sand\"\npreset = \"dense_sand\"\n\
                 [[region]]\nname = \"charge\"\nmaterial = \"tnt\"\nshape = \"cylinder\"\ncenter_m = [0.0, 0.0, {base}]\nradius_m = 0.046\nheight_m = 0.092\nlo_m = [0.0, 0.0, {base}]\nhi_m = [{hi}, {hi}, 0.552]\nspacing_m = 0.0115\n\
                 [[region]]\nname = \"soil\"\nmaterial = \"sand\"\nshape = \"box\"\nlo_m = [0.0, 0.0, 0.0]\nhi_m = [0.552, 0.552, 0.552]\nspacing_m = 0.0115\nsubtract = [\"charge\"]\n"
            );
            seam_warnings(&crate::case::parse(&text, "test", &[], Some("t")).unwrap())
        };
        assert!(quarter("0.46", "0.046").is_empty());
        assert!(quarter("0.46", "0.05").is_empty(), "a clip beside the side is no face");
        let w = quarter("0.455", "0.046");
        assert!(w.len() == 1 && w[0].contains("z = 0.455 m"), "{w:?}");
    }
}
