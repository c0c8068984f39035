//! [`Case::validate`]: everything serde cannot check, one-line errors naming the key.

use super::*;
use crate::error::{Result, input};
use std::collections::BTreeMap;

impl Case {
    /// Checks what serde cannot; errors are one line naming the key.
    pub fn validate(&self) -> Result<()> {
        let d = self.dim;
        if !(1..=3).contains(&d) {
            return Err(input(format!("dim = {d}: must be 1, 2 or 3")));
        }
        let t = &self.time;
        pos("time.end_s", t.end_s)?;
        if t.output_interval_s < 0.0 || !t.output_interval_s.is_finite() {
            return Err(input("time.output_interval_s: must be zero or positive"));
        }
        match t.step {
            StepRule::Fixed => {
                pos("time.dt_s", t.dt_s.ok_or_else(|| input("time.dt_s: required when time.step = \"fixed\""))?)?
            }
            StepRule::Cfl => {
                pos("time.cfl", t.cfl)?;
                if t.cfl > 1.0 {
                    return Err(input(format!("time.cfl = {}: must not exceed 1", t.cfl)));
                }
            }
        }
        if let Some(m) = t.dt_max_s {
            pos("time.dt_max_s", m)?;
        }
        pos("sph.h_over_dx", self.sph.h_over_dx)?;
        pos("sph.theta", self.sph.theta)?;
        if self.sph.xsph_eps < 0.0 {
            return Err(input("sph.xsph_eps: must not be negative"));
        }
        nonneg("viscosity.alpha", self.viscosity.alpha)?;
        nonneg("viscosity.beta", self.viscosity.beta)?;
        pos("viscosity.phi_over_h", self.viscosity.phi_over_h)?;
        if let Some(p) = &self.penalty {
            pos("penalty.pbar", p.pbar)?;
            if p.n1 <= p.n2 || p.n2 < 1 {
                return Err(input(format!("penalty: need n1 > n2 >= 1 (got n1 = {}, n2 = {})", p.n1, p.n2)));
            }
        }
        let b = &self.boundary;
        if let Some(s) = b.wall_spacing_m {
            pos("boundary.wall_spacing_m", s)?;
        }
        if let Some(s) = b.r0_m {
            pos("boundary.r0_m", s)?;
        }
        nonneg("boundary.d_m2s2", b.d_m2s2)?;
        if b.n1 <= b.n2 || b.n2 < 1 {
            return Err(input(format!("boundary: need n1 > n2 >= 1 (got n1 = {}, n2 = {})", b.n1, b.n2)));
        }
        if let Some(g) = &self.physics.gravity_ms2 {
            vecd("physics.gravity_ms2", g, d)?;
        }

        if self.materials.is_empty() {
            return Err(input("no [[material]]: a case needs at least one material with an eos"));
        }
        let mut names = std::collections::BTreeSet::new();
        for (k, m) in self.materials.iter().enumerate() {
            let key = format!("material[{k}] ({})", m.name);
            if !names.insert(m.name.as_str()) {
                return Err(input(format!("{key}: the name is used twice")));
            }
            match &m.eos {
                EosCfg::IdealGas { gamma, rho0_kgm3 } => {
                    if *gamma <= 1.0 || !gamma.is_finite() {
                        return Err(input(format!("{key}.eos.gamma = {gamma}: must exceed 1")));
                    }
                    if let Some(r) = rho0_kgm3 {
                        pos(&format!("{key}.eos.rho0_kgm3"), *r)?;
                    }
                }
                EosCfg::Jwl { rho0_kgm3, a_pa, b_pa, r1, r2, omega, d_ms } => {
                    pos(&format!("{key}.eos.rho0_kgm3"), *rho0_kgm3)?;
                    nonneg(&format!("{key}.eos.a_pa"), *a_pa)?;
                    nonneg(&format!("{key}.eos.b_pa"), *b_pa)?;
                    pos(&format!("{key}.eos.r1"), *r1)?;
                    pos(&format!("{key}.eos.r2"), *r2)?;
                    pos(&format!("{key}.eos.omega"), *omega)?;
                    pos(&format!("{key}.eos.d_ms"), *d_ms)?;
                }
                EosCfg::Water { rho0_kgm3, a1_pa, c0_ms, .. } => {
                    pos(&format!("{key}.eos.rho0_kgm3"), *rho0_kgm3)?;
                    pos(&format!("{key}.eos.a1_pa"), *a1_pa)?;
                    pos(&format!("{key}.eos.c0_ms"), *c0_ms)?;
                }
                EosCfg::Soil { rho0_kgm3, c_ms, s, gamma } => {
                    pos(&format!("{key}.eos.rho0_kgm3"), *rho0_kgm3)?;
                    pos(&format!("{key}.eos.c_ms"), *c_ms)?;
                    pos(&format!("{key}.eos.s"), *s)?;
                    nonneg(&format!("{key}.eos.gamma"), *gamma)?;
                }
            }
            if let Some(s) = &m.strength {
                pos(&format!("{key}.strength.shear_modulus_pa"), s.shear_modulus_pa)?;
                nonneg(&format!("{key}.strength.alpha_phi"), s.alpha_phi)?;
                nonneg(&format!("{key}.strength.cohesion_pa"), s.cohesion_pa)?;
            }
            if let Some(e) = m.e0_jkg {
                finite(&format!("{key}.e0_jkg"), e)?;
            }
        }

        if self.regions.is_empty() {
            return Err(input("no [[region]]: a case needs at least one region of particles"));
        }
        let mut rnames = std::collections::BTreeSet::new();
        for (k, r) in self.regions.iter().enumerate() {
            let key = format!("region[{k}] ({})", r.name);
            if !rnames.insert(r.name.as_str()) {
                return Err(input(format!("{key}: the name is used twice")));
            }
            let mi = self.material_index(&r.material).ok_or_else(|| {
                input(format!(
                    "{key}.material = \"{}\": no [[material]] of that name (a material needs an eos)",
                    r.material
                ))
            })?;
            pos(&format!("{key}.spacing_m"), r.spacing_m)?;
            match r.shape {
                Shape::Box => {
                    let lo =
                        r.lo_m.as_ref().ok_or_else(|| input(format!("{key}.lo_m: required for shape = \"box\"")))?;
                    let hi =
                        r.hi_m.as_ref().ok_or_else(|| input(format!("{key}.hi_m: required for shape = \"box\"")))?;
                    vecd(&format!("{key}.lo_m"), lo, d)?;
                    vecd(&format!("{key}.hi_m"), hi, d)?;
                    for a in 0..d {
                        if hi[a] <= lo[a] {
                            return Err(input(format!(
                                "{key}: hi_m[{a}] = {} must exceed lo_m[{a}] = {}",
                                hi[a], lo[a]
                            )));
                        }
                    }
                }
                Shape::Polygon => {
                    if d != 2 {
                        return Err(input(format!("{key}: shape = \"polygon\" needs dim = 2")));
                    }
                    let v = r
                        .vertices_m
                        .as_ref()
                        .ok_or_else(|| input(format!("{key}.vertices_m: required for shape = \"polygon\"")))?;
                    if v.len() < 3 {
                        return Err(input(format!("{key}.vertices_m: a polygon needs at least 3 vertices")));
                    }
                    for (q, p) in v.iter().enumerate() {
                        vecd(&format!("{key}.vertices_m[{q}]"), p, 2)?;
                    }
                }
                Shape::Cylinder | Shape::Sphere => super::geom::round_shape(&key, r, d)?,
                Shape::Lattice => {
                    let o = r
                        .origin_m
                        .as_ref()
                        .ok_or_else(|| input(format!("{key}.origin_m: required for shape = \"lattice\"")))?;
                    vecd(&format!("{key}.origin_m"), o, d)?;
                    let c = r
                        .count
                        .as_ref()
                        .ok_or_else(|| input(format!("{key}.count: required for shape = \"lattice\"")))?;
                    if c.len() != d || c.contains(&0) {
                        return Err(input(format!("{key}.count: need {d} positive counts")));
                    }
                }
            }
            if let Some(rho) = r.rho_kgm3 {
                pos(&format!("{key}.rho_kgm3"), rho)?;
            } else if self.materials[mi].eos.rho0().is_none() {
                return Err(input(format!("{key}.rho_kgm3: required (material `{}` has no rho0_kgm3)", r.material)));
            }
            if let Some(e) = r.e_jkg {
                finite(&format!("{key}.e_jkg"), e)?;
            }
            if let Some(v) = &r.velocity_ms {
                vecd(&format!("{key}.velocity_ms"), v, d)?;
            }
            if let Some(m) = r.mass_kg {
                pos(&format!("{key}.mass_kg"), m)?;
            }
            if let Some(h) = r.h_m {
                pos(&format!("{key}.h_m"), h)?;
            }
            for s in &r.subtract {
                if !self.regions.iter().any(|q| &q.name == s) || s == &r.name {
                    return Err(input(format!("{key}.subtract: no other region named `{s}`")));
                }
            }
        }

        for (k, w) in self.walls.iter().enumerate() {
            vecd(&format!("wall[{k}].from_m"), &w.from_m, d)?;
            vecd(&format!("wall[{k}].to_m"), &w.to_m, d)?;
            if d == 3 {
                super::geom::plane_wall(k, w)?;
            } else if w.edge_m.is_some() {
                return Err(input(format!("wall[{k}].edge_m: only 3D walls (planes) have one")));
            }
            if d == 2 && w.from_m == w.to_m {
                return Err(input(format!("wall[{k}]: from_m and to_m coincide")));
            }
        }
        if let Some(det) = &self.detonation {
            if det.mode == BurnMode::Programmed {
                let p = det
                    .point_m
                    .as_ref()
                    .ok_or_else(|| input("detonation.point_m: required for mode = \"programmed\""))?;
                vecd("detonation.point_m", p, d)?;
            }
            nonneg("detonation.width_h", det.width_h)?;
            if !self.materials.iter().any(|m| matches!(m.eos, EosCfg::Jwl { .. })) {
                return Err(input("detonation: no material has eos kind = \"jwl\""));
            }
        }
        let mut gnames = std::collections::BTreeSet::new();
        for (k, g) in self.gauges.iter().enumerate() {
            vecd(&format!("gauge[{k}].point_m"), &g.point_m, d)?;
            if !gnames.insert(g.name.as_str()) {
                return Err(input(format!("gauge[{k}] ({}): the name is used twice", g.name)));
            }
        }
        if self.analysis.kind == AnalysisKind::Riemann {
            if d != 1 {
                return Err(input("analysis.kind = \"riemann\" needs dim = 1"));
            }
            if self.analysis.diaphragm_m.is_none() {
                return Err(input("analysis.diaphragm_m: required for kind = \"riemann\""));
            }
            if let Some(w) = &self.analysis.window_m
                && (w.len() != 2 || w[1] <= w[0])
            {
                return Err(input("analysis.window_m: need [lo, hi] with hi > lo"));
            }
        }
        for (k, t) in self.analysis.thesis_gauge.iter().enumerate() {
            if !self.gauges.iter().any(|g| g.name == t.gauge) {
                return Err(input(format!(
                    "analysis.thesis_gauge[{k}].gauge = \"{}\": no [[gauge]] of that name",
                    t.gauge
                )));
            }
        }
        if let Some(h) = &self.analysis.thesis_crater_history
            && h.iter().any(|r| r.len() != 3)
        {
            return Err(input("analysis.thesis_crater_history: rows must be [time_s, diameter_m, depth_m]"));
        }
        if let Some(sm) = &self.analysis.soil_materials {
            for s in sm {
                if self.material_index(s).is_none() {
                    return Err(input(format!("analysis.soil_materials: no material named `{s}`")));
                }
            }
        }
        if let Some(dm) = &self.domain {
            vecd("domain.lo_m", &dm.lo_m, d)?;
            vecd("domain.hi_m", &dm.hi_m, d)?;
        }
        let mods: BTreeMap<&str, ()> = crate::modules::Module::ALL.iter().map(|m| (m.name(), ())).collect();
        for (key, list) in [("backend.rust", &self.backend.rust), ("backend.fortran", &self.backend.fortran)] {
            for m in list {
                if !mods.contains_key(m.as_str()) {
                    return Err(input(format!(
                        "{key}: unknown module `{m}` (modules: {})",
                        crate::modules::Module::names()
                    )));
                }
            }
        }
        if let Some(dft) = &self.backend.default
            && dft != "fortran"
            && dft != "rust"
        {
            return Err(input(format!("backend.default = \"{dft}\": must be \"fortran\" or \"rust\"")));
        }
        super::geom::geometry(self)
    }
}

pub(super) fn finite(key: &str, v: f64) -> Result<()> {
    if v.is_finite() { Ok(()) } else { Err(input(format!("{key} = {v}: must be a finite number"))) }
}

pub(super) fn pos(key: &str, v: f64) -> Result<()> {
    if v > 0.0 && v.is_finite() { Ok(()) } else { Err(input(format!("{key} = {v}: must be positive"))) }
}

pub(super) fn nonneg(key: &str, v: f64) -> Result<()> {
    if v >= 0.0 && v.is_finite() { Ok(()) } else { Err(input(format!("{key} = {v}: must not be negative"))) }
}

pub(super) fn vecd(key: &str, v: &[f64], d: usize) -> Result<()> {
    if v.len() != d {
        return Err(input(format!("{key}: needs {d} components (dim = {d}), got {}", v.len())));
    }
    for x in v {
        finite(key, *x)?;
    }
    Ok(())
}
