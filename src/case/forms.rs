//! The forms of the density and of the pressure term that `[sph]` picks (docs/theory.md §4, §5).

use super::DensityKind;
use serde::Deserialize;

impl DensityKind {
    /// Is the density a kernel sum (summation or number density), not integrated?
    pub fn summed(self) -> bool {
        self != DensityKind::Continuity
    }
}

/// Form of the pressure (and stress) term of the momentum equation.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum PressureForm {
    /// Σ_j m_j (σ_i/ρ_i² + σ_j/ρ_j²) ∇W (thesis 4-33).
    Standard,
    /// Σ_j m_j (σ_i + σ_j)/(ρ_i ρ_j) ∇W (Colagrossi & Landrini 2003), for interfaces at large
    /// density ratios.
    Interface,
}
