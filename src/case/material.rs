//! A material's table: its equation of state ([`EosCfg`]) and, for soils, its strength.

use crate::modules::param::EosKind;
use serde::Deserialize;

/// One material: its equation of state and, for soils, its strength. A `preset` fills in the keys
/// the table does not give ([`crate::presets`]).
#[derive(Debug, Clone, Deserialize)]
#[serde(try_from = "toml::Table")]
pub struct MaterialCfg {
    pub name: String,
    /// The preset the material was built from, if any.
    pub preset: Option<String>,
    pub eos: EosCfg,
    pub strength: Option<StrengthCfg>,
    /// Pressure floor (Pa): tension cut-off of soils, cavitation of water. Absent = none.
    pub pmin_pa: Option<f64>,
    /// Specific internal energy at the start (J/kg) for regions of this material that give none.
    pub e0_jkg: Option<f64>,
    /// Materials with the same penalty group feel no penalty force between them
    /// (default: each material its own group).
    pub penalty_group: Option<String>,
}

/// The keys of a `[[material]]` table once its preset is merged in.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialFields {
    name: String,
    preset: Option<String>,
    eos: EosCfg,
    strength: Option<StrengthCfg>,
    pmin_pa: Option<f64>,
    e0_jkg: Option<f64>,
    penalty_group: Option<String>,
}

impl TryFrom<toml::Table> for MaterialCfg {
    type Error = String;
    fn try_from(mut t: toml::Table) -> std::result::Result<MaterialCfg, String> {
        let name = t.get("name").and_then(|n| n.as_str()).unwrap_or("?").to_string();
        let preset = match t.get("preset") {
            None => None,
            Some(toml::Value::String(p)) => Some(p.clone()),
            Some(v) => {
                return Err(format!(
                    "material `{name}`: preset = {v}: must be a preset name ({})",
                    crate::presets::names()
                ));
            }
        };
        if let Some(p) = &preset {
            let mut base = crate::presets::get(p).ok_or_else(|| {
                format!("material `{name}`: preset = \"{p}\": no such preset (presets: {})", crate::presets::names())
            })?;
            t.remove("preset");
            crate::presets::merge(&mut base, t);
            t = base;
            t.insert("preset".into(), toml::Value::String(p.clone()));
        }
        let f = MaterialFields::deserialize(toml::Value::Table(t))
            .map_err(|e| format!("material `{name}`: {}", e.message().replace('\n', " ")))?;
        Ok(MaterialCfg {
            name: f.name,
            preset: f.preset,
            eos: f.eos,
            strength: f.strength,
            pmin_pa: f.pmin_pa,
            e0_jkg: f.e0_jkg,
            penalty_group: f.penalty_group,
        })
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum EosCfg {
    /// Ideal gas p = (γ−1)ρe.
    IdealGas { gamma: f64, rho0_kgm3: Option<f64> },
    /// JWL (4-39); optionally the unreacted explosive's Mie–Grüneisen EOS with a linear Us–Up
    /// Hugoniot (C, S, Γ), which carries the explosive until it burns (theory.md §9).
    Jwl {
        rho0_kgm3: f64,
        a_pa: f64,
        b_pa: f64,
        r1: f64,
        r2: f64,
        omega: f64,
        d_ms: f64,
        unreacted_c_ms: Option<f64>,
        unreacted_s: Option<f64>,
        unreacted_gamma: Option<f64>,
    },
    /// Water polynomial (4-40, 4-41).
    Water { rho0_kgm3: f64, a1_pa: f64, a2_pa: f64, a3_pa: f64, b0: f64, b1: f64, c0_ms: f64 },
    /// Soil Mie–Grüneisen with a linear Us–Up Hugoniot (4-42…4-46).
    Soil { rho0_kgm3: f64, c_ms: f64, s: f64, gamma: f64 },
}

impl EosCfg {
    pub fn rho0(&self) -> Option<f64> {
        match self {
            EosCfg::IdealGas { rho0_kgm3, .. } => *rho0_kgm3,
            EosCfg::Jwl { rho0_kgm3, .. } | EosCfg::Water { rho0_kgm3, .. } | EosCfg::Soil { rho0_kgm3, .. } => {
                Some(*rho0_kgm3)
            }
        }
    }
    /// Every name [`EosCfg::kind`] gives: the material table's kinds
    /// (`fortran/include/material_table.txt`, [`EosKind`]) but `none`.
    pub const KINDS: [&'static str; EosKind::ALL.len() - 1] = {
        let mut out = [""; EosKind::ALL.len() - 1];
        let (mut i, mut k) = (0, 0);
        while i < EosKind::ALL.len() {
            if !matches!(EosKind::ALL[i], EosKind::None) {
                out[k] = EosKind::ALL[i].name();
                k += 1;
            }
            i += 1;
        }
        out
    };

    /// The material table's kind of this equation of state (its `mtype` code).
    pub fn eos_kind(&self) -> EosKind {
        match self {
            EosCfg::IdealGas { .. } => EosKind::IdealGas,
            EosCfg::Jwl { .. } => EosKind::Jwl,
            EosCfg::Water { .. } => EosKind::Water,
            EosCfg::Soil { .. } => EosKind::Soil,
        }
    }

    /// The kind's name, as the case file's `type` writes it.
    pub fn kind(&self) -> &'static str {
        self.eos_kind().name()
    }
}

/// Drucker–Prager strength (4-29…4-32).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StrengthCfg {
    /// Shear modulus G (Pa).
    pub shear_modulus_pa: f64,
    /// α_φ of the yield surface √J2 = 3 α_φ p + k.
    pub alpha_phi: f64,
    /// k of the yield surface (Pa).
    pub cohesion_pa: f64,
    /// Friction angle φ (degrees) for the earth pressure at rest K0 = 1 − sin φ of the geostatic
    /// start; absent: from α_φ by the compression-cone match, sin φ = 3√3 α_φ/(2 + √3 α_φ).
    pub friction_angle_deg: Option<f64>,
}

impl StrengthCfg {
    /// sin φ: of `friction_angle_deg`, else of the Drucker–Prager cone through the Mohr–Coulomb
    /// compression meridian, α_φ = 2 sin φ/(√3 (3 − sin φ)) (32.3° at α_φ = 0.25).
    pub fn sin_phi(&self) -> f64 {
        match self.friction_angle_deg {
            Some(d) => d.to_radians().sin(),
            None => {
                let a = 3f64.sqrt() * self.alpha_phi;
                3.0 * a / (2.0 + a)
            }
        }
    }
}

#[cfg(test)]
#[test]
fn every_kind_of_the_table_is_a_case_kind() {
    // a kind of the material table that the case's `EosCfg` cannot read would be refused as an
    // unknown variant; a known one only lacks its keys here
    for k in EosCfg::KINDS {
        let e = toml::from_str::<EosCfg>(&format!("kind = \"{k}\"")).unwrap_err().to_string();
        assert!(!e.contains("unknown variant"), "{k}: {e}");
    }
}
