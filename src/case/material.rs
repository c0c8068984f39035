//! A material's table: its equation of state ([`EosCfg`]) and, for soils, its strength.

use super::validate::{At, C_MAX, Checker, P_MAX, RHO_MAX, RHO_MIN, Range};
use crate::error::{Result, input};
use crate::param::EosKind;
use crate::param::row::{CMP_C, CMP_CRHO, CMP_N, CMP_P, CMP_RHO, CMP_RMAX0, E1, ECHEM, RHO0, UNR_C, UNR_GAMMA, UNR_S};
use serde::Deserialize;

/// The penalty group of a material that feels no penalty force with any other (4-53).
pub const PENALTY_EXEMPT: &str = "none";

/// One material: its equation of state and, for soils, its strength. A `preset` fills in the keys
/// the table does not give (`crate::presets`).
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
    /// (default: each material its own group); [`PENALTY_EXEMPT`] feels none with any material.
    pub penalty_group: Option<String>,
    /// Dynamic viscosity η (Pa s) of the physical (Newtonian) viscosity, `force.newtonian`
    /// (docs/reference/cases.md). Absent or 0: none.
    pub dynamic_viscosity_pa_s: Option<f64>,
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
    dynamic_viscosity_pa_s: Option<f64>,
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
            dynamic_viscosity_pa_s: f.dynamic_viscosity_pa_s,
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
    /// Tait, for weakly compressible water: p = B ((ρ/ρ0)^γ − 1) (Pa), independent of e, with a
    /// constant sound speed c (m/s). Every key defaults to the artificial water of G.R. Liu and
    /// M.B. Liu, *Smoothed Particle Hydrodynamics: a Meshfree Particle Method* (World Scientific,
    /// 2003): [`TAIT_WATER`].
    Tait {
        #[serde(default = "tait_rho0")]
        rho0_kgm3: f64,
        #[serde(default = "tait_b")]
        b_pa: f64,
        #[serde(default = "tait_gamma")]
        gamma: f64,
        #[serde(default = "tait_c")]
        c_ms: f64,
    },
    /// Morris, Fox & Zhu (1997)'s artificial compressibility, the active form of the book's
    /// `p_art_water`: p = c² ρ (Pa), independent of e, with a constant sound speed c (m/s).
    /// `rho0_kgm3` is the default density of its regions.
    Morris {
        #[serde(default = "tait_rho0")]
        rho0_kgm3: f64,
        c_ms: f64,
    },
    /// Porous compaction of the Laine–Sandvik kind (a sand): the plastic compaction curve
    /// p_c(ρ) (`rho_kgm3`, `p_pa`), the bulk sound speed c_u(ρ) of the elastic unloading and
    /// reloading line (`c_rho_kgm3`, `c_ms`), 2–10 points each, ρ ascending. The sand starts
    /// compacted to `rho_max0_kgm3` (default: the curve's first density) and at rest on its
    /// unloading line, ρ0 = ρ_max0 − p_c(ρ_max0)/c_u(ρ_max0)².
    Compaction { rho_kgm3: Vec<f64>, p_pa: Vec<f64>, c_rho_kgm3: Vec<f64>, c_ms: Vec<f64>, rho_max0_kgm3: Option<f64> },
}

/// The most points of a compaction table (the material table's rows).
pub const COMPACTION_POINTS: usize = 10;

/// The compaction density at the start (kg/m³) and the density at rest on its unloading line.
fn compaction_start(rho: &[f64], p: &[f64], c_rho: &[f64], c: &[f64], rmax0: Option<f64>) -> (f64, f64) {
    let r = rmax0.unwrap_or_else(|| rho.first().copied().unwrap_or(0.0));
    if rho.len() < 2 || rho.len() != p.len() || c_rho.len() < 2 || c_rho.len() != c.len() {
        return (r, r);
    }
    let cu = crate::param::tab_lin(c_rho, c, r, false);
    let pc = crate::param::tab_lin(rho, p, r, true);
    (r, r - pc / (cu * cu))
}

/// The Tait defaults, the artificial water of Liu and Liu (2003): ρ0 = 1000 kg/m³, B = 1.013e5 Pa,
/// γ = 7, c = 1480 m/s.
pub const TAIT_WATER: [f64; 4] = [1000.0, 1.013e5, 7.0, 1480.0];
fn tait_rho0() -> f64 {
    TAIT_WATER[0]
}
fn tait_b() -> f64 {
    TAIT_WATER[1]
}
fn tait_gamma() -> f64 {
    TAIT_WATER[2]
}
fn tait_c() -> f64 {
    TAIT_WATER[3]
}

/// What a material of an equation of state is, for the checks and the advice that read a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Matter {
    Gas,
    Explosive,
    Water,
    Soil,
}

impl Matter {
    /// As messages name it.
    pub fn name(self) -> &'static str {
        match self {
            Matter::Gas => "gas",
            Matter::Explosive => "condensed explosive",
            Matter::Water => "water",
            Matter::Soil => "soil",
        }
    }
    /// An explosive, water or a soil: densities of 1000–3000 kg/m³.
    pub fn condensed(self) -> bool {
        self != Matter::Gas
    }
    /// Water or a soil: the medium a blast moves.
    pub fn ground(self) -> bool {
        matches!(self, Matter::Water | Matter::Soil)
    }
}

impl EosCfg {
    pub fn rho0(&self) -> Option<f64> {
        match self {
            EosCfg::IdealGas { rho0_kgm3, .. } => *rho0_kgm3,
            EosCfg::Jwl { rho0_kgm3, .. }
            | EosCfg::Water { rho0_kgm3, .. }
            | EosCfg::Soil { rho0_kgm3, .. }
            | EosCfg::Tait { rho0_kgm3, .. }
            | EosCfg::Morris { rho0_kgm3, .. } => Some(*rho0_kgm3),
            EosCfg::Compaction { rho_kgm3, p_pa, c_rho_kgm3, c_ms, rho_max0_kgm3 } => {
                Some(compaction_start(rho_kgm3, p_pa, c_rho_kgm3, c_ms, *rho_max0_kgm3).1)
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
            EosCfg::Tait { .. } => EosKind::Tait,
            EosCfg::Morris { .. } => EosKind::Morris,
            EosCfg::Compaction { .. } => EosKind::Compaction,
        }
    }

    /// What a material of this equation of state is.
    pub fn matter(&self) -> Matter {
        match self {
            EosCfg::IdealGas { .. } => Matter::Gas,
            EosCfg::Jwl { .. } => Matter::Explosive,
            EosCfg::Water { .. } | EosCfg::Tait { .. } | EosCfg::Morris { .. } => Matter::Water,
            EosCfg::Soil { .. } | EosCfg::Compaction { .. } => Matter::Soil,
        }
    }

    /// The bulk sound speed at rest of water or a soil (m/s); None for a gas or an explosive.
    pub fn bulk_sound_speed(&self) -> Option<f64> {
        match self {
            EosCfg::Soil { c_ms, .. } | EosCfg::Tait { c_ms, .. } | EosCfg::Morris { c_ms, .. } => Some(*c_ms),
            EosCfg::Water { c0_ms, .. } => Some(*c0_ms),
            EosCfg::Compaction { c_rho_kgm3, c_ms, rho_kgm3, p_pa, rho_max0_kgm3 } => {
                let r = compaction_start(rho_kgm3, p_pa, c_rho_kgm3, c_ms, *rho_max0_kgm3).0;
                (c_ms.len() >= 2 && c_ms.len() == c_rho_kgm3.len())
                    .then(|| crate::param::tab_lin(c_rho_kgm3, c_ms, r, false))
            }
            EosCfg::IdealGas { .. } | EosCfg::Jwl { .. } => None,
        }
    }

    /// Writes this equation of state's rows of a material-table column (`col`, the rows of
    /// `fortran/include/material_table.txt`): ρ0 and the EOS constants; for a JWL with an
    /// unreacted explosive, its Hugoniot and `e_rest`, the specific energy of the explosive at
    /// rest (J/kg). The other rows are the caller's.
    pub fn fill_column(&self, col: &mut [f64], e_rest: f64) {
        match self {
            EosCfg::IdealGas { gamma, rho0_kgm3 } => {
                col[RHO0] = rho0_kgm3.unwrap_or(1.0);
                col[E1] = *gamma;
            }
            EosCfg::Jwl {
                rho0_kgm3,
                a_pa,
                b_pa,
                r1,
                r2,
                omega,
                d_ms,
                unreacted_c_ms,
                unreacted_s,
                unreacted_gamma,
            } => {
                col[RHO0] = *rho0_kgm3;
                col[E1..E1 + 6].copy_from_slice(&[*a_pa, *b_pa, *r1, *r2, *omega, *d_ms]);
                if let (Some(c), Some(s), Some(g)) = (unreacted_c_ms, unreacted_s, unreacted_gamma) {
                    col[UNR_C] = *c;
                    col[UNR_S] = *s;
                    col[UNR_GAMMA] = *g;
                    col[ECHEM] = e_rest;
                }
            }
            EosCfg::Water { rho0_kgm3, a1_pa, a2_pa, a3_pa, b0, b1, c0_ms } => {
                col[RHO0] = *rho0_kgm3;
                col[E1..E1 + 6].copy_from_slice(&[*a1_pa, *a2_pa, *a3_pa, *b0, *b1, *c0_ms]);
            }
            EosCfg::Soil { rho0_kgm3, c_ms, s, gamma } => {
                col[RHO0] = *rho0_kgm3;
                col[E1..E1 + 3].copy_from_slice(&[*c_ms, *s, *gamma]);
            }
            EosCfg::Tait { rho0_kgm3, b_pa, gamma, c_ms } => {
                col[RHO0] = *rho0_kgm3;
                col[E1..E1 + 3].copy_from_slice(&[*b_pa, *gamma, *c_ms]);
            }
            EosCfg::Morris { rho0_kgm3, c_ms } => {
                col[RHO0] = *rho0_kgm3;
                col[E1] = *c_ms;
            }
            EosCfg::Compaction { rho_kgm3, p_pa, c_rho_kgm3, c_ms, rho_max0_kgm3 } => {
                let (r, rho0) = compaction_start(rho_kgm3, p_pa, c_rho_kgm3, c_ms, *rho_max0_kgm3);
                col[RHO0] = rho0;
                col[CMP_N] = rho_kgm3.len() as f64;
                col[CMP_RHO..CMP_RHO + rho_kgm3.len()].copy_from_slice(rho_kgm3);
                col[CMP_P..CMP_P + p_pa.len()].copy_from_slice(p_pa);
                col[CMP_CRHO..CMP_CRHO + c_rho_kgm3.len()].copy_from_slice(c_rho_kgm3);
                col[CMP_C..CMP_C + c_ms.len()].copy_from_slice(c_ms);
                col[CMP_RMAX0] = r;
            }
        }
    }

    /// Checks this equation of state's keys (`e`: the `material[k].eos` table), recording each.
    pub(crate) fn check(&self, v: &mut Checker, e: &At) -> Result<()> {
        let rho = Range::within(RHO_MIN, RHO_MAX);
        match self {
            EosCfg::IdealGas { gamma, rho0_kgm3 } => {
                v.num(e, "gamma", *gamma, Range::above(1.0, 10.0))?;
                v.opt(e, "rho0_kgm3", *rho0_kgm3, rho)?;
            }
            EosCfg::Jwl {
                rho0_kgm3,
                a_pa,
                b_pa,
                r1,
                r2,
                omega,
                d_ms,
                unreacted_c_ms,
                unreacted_s,
                unreacted_gamma,
            } => {
                let u = [unreacted_c_ms, unreacted_s, unreacted_gamma];
                if u.iter().any(|x| x.is_some()) && !u.iter().all(|x| x.is_some()) {
                    return Err(input(format!(
                        "{}: unreacted_c_ms, unreacted_s and unreacted_gamma go together (all three or none)",
                        e.label()
                    )));
                }
                v.opt(e, "unreacted_c_ms", *unreacted_c_ms, Range::above(0.0, C_MAX))?;
                v.opt(e, "unreacted_s", *unreacted_s, Range::above(0.0, 100.0))?;
                v.opt(e, "unreacted_gamma", *unreacted_gamma, Range::within(0.0, 100.0))?;
                v.num(e, "rho0_kgm3", *rho0_kgm3, rho)?;
                v.num(e, "a_pa", *a_pa, Range::within(0.0, P_MAX))?;
                v.num(e, "b_pa", *b_pa, Range::within(0.0, P_MAX))?;
                v.num(e, "r1", *r1, Range::above(0.0, 100.0))?;
                v.num(e, "r2", *r2, Range::above(0.0, 100.0))?;
                v.num(e, "omega", *omega, Range::above(0.0, 10.0))?;
                v.num(e, "d_ms", *d_ms, Range::above(0.0, C_MAX))?;
            }
            EosCfg::Water { rho0_kgm3, a1_pa, a2_pa, a3_pa, b0, b1, c0_ms } => {
                v.num(e, "rho0_kgm3", *rho0_kgm3, rho)?;
                v.num(e, "a1_pa", *a1_pa, Range::above(0.0, P_MAX))?;
                v.num(e, "a2_pa", *a2_pa, Range::abs(P_MAX))?;
                v.num(e, "a3_pa", *a3_pa, Range::abs(P_MAX))?;
                v.num(e, "b0", *b0, Range::within(0.0, 100.0))?;
                v.num(e, "b1", *b1, Range::within(0.0, 100.0))?;
                v.num(e, "c0_ms", *c0_ms, Range::above(0.0, C_MAX))?;
            }
            EosCfg::Soil { rho0_kgm3, c_ms, s, gamma } => {
                v.num(e, "rho0_kgm3", *rho0_kgm3, rho)?;
                v.num(e, "c_ms", *c_ms, Range::above(0.0, C_MAX))?;
                v.num(e, "s", *s, Range::above(0.0, 100.0))?;
                v.num(e, "gamma", *gamma, Range::within(0.0, 100.0))?;
            }
            EosCfg::Tait { rho0_kgm3, b_pa, gamma, c_ms } => {
                v.num(e, "rho0_kgm3", *rho0_kgm3, rho)?;
                v.num(e, "b_pa", *b_pa, Range::above(0.0, P_MAX))?;
                v.num(e, "gamma", *gamma, Range::within(1.0, 100.0))?;
                v.num(e, "c_ms", *c_ms, Range::above(0.0, C_MAX))?;
            }
            EosCfg::Morris { rho0_kgm3, c_ms } => {
                v.num(e, "rho0_kgm3", *rho0_kgm3, rho)?;
                v.num(e, "c_ms", *c_ms, Range::above(0.0, C_MAX))?;
            }
            EosCfg::Compaction { rho_kgm3, p_pa, c_rho_kgm3, c_ms, rho_max0_kgm3 } => {
                check_table(v, e, ("rho_kgm3", rho_kgm3), ("p_pa", p_pa), Range::within(0.0, P_MAX))?;
                check_table(v, e, ("c_rho_kgm3", c_rho_kgm3), ("c_ms", c_ms), Range::above(0.0, C_MAX))?;
                v.opt(e, "rho_max0_kgm3", *rho_max0_kgm3, rho)?;
                let (r, rho0) = compaction_start(rho_kgm3, p_pa, c_rho_kgm3, c_ms, *rho_max0_kgm3);
                if r < rho_kgm3[0] || rho0.is_nan() || rho0 <= 0.0 {
                    return Err(input(format!(
                        "{}: rho_max0_kgm3 = {r}: must lie on the compaction curve (at least {}) with a positive density at rest (got {rho0})",
                        e.label(),
                        rho_kgm3[0]
                    )));
                }
            }
        }
        Ok(())
    }

    /// The kind's name, as the case file's `type` writes it.
    pub fn kind(&self) -> &'static str {
        self.eos_kind().name()
    }
}

/// A compaction table's two columns: 2–10 points, the densities (kg/m³) in the density range and
/// strictly ascending, the values in `vals`.
fn check_table(v: &mut Checker, e: &At, xs: (&str, &[f64]), ys: (&str, &[f64]), vals: Range) -> Result<()> {
    let (n, m) = (xs.1.len(), ys.1.len());
    if !(2..=COMPACTION_POINTS).contains(&n) || n != m {
        return Err(input(format!(
            "{}: {} and {} must have the same number of points, 2 to {COMPACTION_POINTS} (got {n} and {m})",
            e.label(),
            xs.0,
            ys.0
        )));
    }
    for k in 0..n {
        v.num(e, xs.0, xs.1[k], Range::within(RHO_MIN, RHO_MAX))?;
        v.num(e, ys.0, ys.1[k], vals)?;
        if k > 0 && xs.1[k] <= xs.1[k - 1] {
            return Err(input(format!(
                "{}: {} must be strictly ascending ({} after {})",
                e.label(),
                xs.0,
                xs.1[k],
                xs.1[k - 1]
            )));
        }
    }
    Ok(())
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
    // unknown variant; a known one lacks its keys here, or (Tait) takes every key's default
    for k in EosCfg::KINDS {
        match toml::from_str::<EosCfg>(&format!("kind = \"{k}\"")) {
            Ok(e) => assert_eq!(e.kind(), k),
            Err(e) => assert!(!e.to_string().contains("unknown variant"), "{k}: {e}"),
        }
    }
    let tait = toml::from_str::<EosCfg>("kind = \"tait\"").unwrap();
    let EosCfg::Tait { rho0_kgm3, b_pa, gamma, c_ms } = tait else { panic!("{tait:?}") };
    assert_eq!([rho0_kgm3, b_pa, gamma, c_ms], TAIT_WATER);
}

#[cfg(test)]
#[test]
fn the_morris_kind_takes_c_and_a_default_density() {
    let m = toml::from_str::<EosCfg>("kind = \"morris\"\nc_ms = 0.01").unwrap();
    assert_eq!((m.eos_kind(), m.rho0(), m.bulk_sound_speed()), (EosKind::Morris, Some(1000.0), Some(0.01)));
    let e = toml::from_str::<EosCfg>("kind = \"morris\"").unwrap_err().to_string();
    assert!(e.contains("c_ms"), "{e}");
}
