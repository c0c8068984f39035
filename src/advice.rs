//! What `blastsph check` warns about and what the unstable-run diagnostic suggests: settings that
//! are known to fail, each with the evidence in docs/validation.md ("Safe defaults"), and the
//! likely fix of a run that stopped.

use crate::case::{BurnMode, Case, ContinuityForm, DensityKind, EnergyForm, EosCfg, Geometry, StepRule};

/// One line per setting of `case` that is known to fail, naming the evidence.
pub fn warnings(case: &Case) -> Vec<String> {
    let mut w = Vec::new();
    let jwl = case.materials.iter().any(|m| matches!(m.eos, EosCfg::Jwl { .. }));
    let several = case.materials.len() > 1;
    let s = &case.sph;
    if s.density == DensityKind::Continuity && s.continuity_form == ContinuityForm::Mass && (jwl || several) {
        w.push(
            "sph.continuity_form = \"mass\" with several materials: it drove detonation products to a negative density in 5 of the 13 thesis scenes (docs/validation.md, \"The continuity form: evidence\"); \"volume\" (the default) ran all 13"
                .into(),
        );
    }
    if s.energy_form == EnergyForm::Symmetric {
        w.push(
            "sph.energy_form = \"symmetric\": the neighbours of hot particles (a point blast, soil beside detonation products) get negative internal energy (docs/validation.md, \"Verification problems\", \"Negative internal energy\"); \"asymmetric\" (the default) keeps e >= 0 where p >= 0"
                .into(),
        );
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
    if s.h_over_dx < 0.9 {
        w.push(format!("sph.h_over_dx = {}: below 0.9 the thesis's runs failed (THESIS.md s.1)", s.h_over_dx));
    }
    if case.geometry == Geometry::Axisymmetric && s.h_over_dx > 1.05 {
        w.push(format!(
            "sph.h_over_dx = {} in axisymmetric geometry: a ring next to the axis can be driven onto it and ride up as a jet (the RZ Sedov blast at h = 1.2 dx, beta = 10: one ring at 19 x the exact peak density; docs/validation.md, \"Other deposits in RZ and 3D\"); at h_over_dx = 1 (the default) the rings that reach the axis stay near the exact peak density",
            s.h_over_dx
        ));
    }
    if let Some(d) = case.detonation.as_ref().filter(|d| d.mode == BurnMode::Programmed) {
        if d.width_h <= 0.0 && !d.beta_burn {
            w.push(
                "detonation: width_h = 0 without the beta burn: the unlit explosive ahead of the front is crushed and the front pressure runs away after about 500 spacings of travel (4.2 p_CJ at 2000; docs/validation.md, \"Detonation\")"
                    .into(),
            );
        } else if !d.beta_burn || d.lighting_speed_factor >= 1.0 {
            w.push(
                "detonation: a programmed front at the full speed D without the beta burn (or with lighting_speed_factor = 1) can outrun the front the explosive sustains and leave a weak detonation (0.85 p_CJ at h/dx = 1.5; docs/validation.md, \"Detonation\"); the defaults are beta_burn = true, lighting_speed_factor = 0.95"
                    .into(),
            );
        }
        for m in &case.materials {
            if let EosCfg::Jwl { unreacted_c_ms: None, .. } = m.eos {
                w.push(format!(
                    "material {}: no unreacted EOS (unreacted_c_ms, unreacted_s, unreacted_gamma): the unlit explosive carries no pressure until it burns; with the beta burn the front still holds p_CJ within 3 % (docs/validation.md, \"Detonation\")",
                    m.name
                ));
            }
        }
    }
    w
}

/// The likely fix of a run that stopped with the diagnostic `msg`, from the case's settings.
pub fn hint(case: &Case, msg: &str) -> String {
    let s = &case.sph;
    let mut out = Vec::new();
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
    if msg.contains("smoothing length") {
        out.push("cap h with sph.h_max_ratio, or use sph.smoothing = \"density\"");
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
    if out.is_empty() {
        out.push(if case.time.step == StepRule::Cfl { "lower time.cfl (e.g. 0.15)" } else { "lower time.dt_s" });
    }
    format!("likely fix: {} (docs/validation.md, \"Safe defaults\")", out.join("; "))
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

    #[test]
    fn hints_name_the_setting() {
        let c = case("parity = \"thesis\"");
        assert!(hint(&c, "step 11: total energy 2 J exceeds").contains("time.viscous_step = true"));
        assert!(hint(&case(""), "particle 3 crossed wall 0").contains("boundary.d_m2s2"));
        assert!(hint(&case(""), "something else").contains("time.cfl"));
    }
}
