//! The `[conductivity]` table: Price's artificial conductivity or the artificial heat of Noh and
//! Monaghan as Liu & Liu's book code computes it (theory.md §6, docs/reference/cases.md).

use serde::Deserialize;

/// Signal speed of the artificial conductivity.
#[derive(Debug, Clone, Copy, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum ConductivitySignal {
    /// √(|p_i − p_j|/ρ̄) (Price 2008): contact discontinuities.
    #[default]
    Pressure,
    /// |v_ij·x̂_ij|: shocks, wall heating.
    Velocity,
}

/// Which energy exchange the conductivity module computes.
#[derive(Debug, Clone, Copy, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum ConductivityKind {
    /// Price (2008): α_u v_sig (e_i − e_j)/ρ̄ (x̂·∇W); on while `alpha` > 0.
    #[default]
    Price,
    /// The artificial heat of Noh (1987) and Monaghan (1992), the book's `art_heat`; on while
    /// g1 > 0 or g2 > 0.
    Noh,
}

/// Artificial conductivity (theory.md §6): off while `alpha = 0` with the default kind.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConductivityCfg {
    #[serde(default)]
    pub kind: ConductivityKind,
    /// α_u (dimensionless; 0 = off; Price uses 1).
    #[serde(default)]
    pub alpha: f64,
    #[serde(default)]
    pub signal: ConductivitySignal,
    /// g1 of the artificial heat (dimensionless; the book's 0.1): the linear term g1 h c (m²/s).
    pub g1: Option<f64>,
    /// g2 of the artificial heat (dimensionless; the book's 1.0): the quadratic term
    /// g2 h² (|∇·v| − ∇·v) (m²/s).
    pub g2: Option<f64>,
}

impl ConductivityCfg {
    /// The book's g1.
    pub const G1: f64 = 0.1;
    /// The book's g2.
    pub const G2: f64 = 1.0;

    /// g1, the book's where the case gives none.
    pub fn g1(&self) -> f64 {
        self.g1.unwrap_or(Self::G1)
    }
    /// g2, the book's where the case gives none.
    pub fn g2(&self) -> f64 {
        self.g2.unwrap_or(Self::G2)
    }
    /// Whether the module runs.
    pub fn on(&self) -> bool {
        match self.kind {
            ConductivityKind::Price => self.alpha > 0.0,
            ConductivityKind::Noh => self.g1() > 0.0 || self.g2() > 0.0,
        }
    }
}
