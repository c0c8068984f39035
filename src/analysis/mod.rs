//! Measurements of finished runs: craters, ejecta, blast-wave radii, air blast against Kinney &
//! Graham, and the exact solutions of
//! the verification problems (Riemann, Sedov–Taylor, Noh and wall reflection, the CJ detonation
//! and its Taylor wave).

#[cfg(feature = "io")]
mod axis;
pub use crate::modules::detonation::cj;
pub mod airblast;
pub mod crater;
pub mod noh;
pub mod riemann;
pub mod sedov;
#[cfg(feature = "io")]
pub mod sedov_edge;
#[cfg(feature = "io")]
pub mod verify;

/// The side of each particle's square on a map (m), from the positions' first coordinate (r in
/// RZ), masses and densities: √(m/ρ) in 2D, √(m/(2π r ρ)) axisymmetric, capped at twice the
/// median (the maps of `blast_report` and the verification report).
#[cfg(feature = "plot")]
pub(crate) fn sides_of(x: &[f64], mass: &[f64], rho: &[f64], rz: bool) -> Vec<f64> {
    let area = |i: usize| {
        let a = mass[i] / rho[i];
        if rz { a / (2.0 * std::f64::consts::PI * x[i].abs()) } else { a }
    };
    let mut s: Vec<f64> = (0..x.len()).map(|i| if rho[i] > 0.0 { area(i).sqrt() } else { 0.0 }).collect();
    let mut sorted: Vec<f64> = s.iter().copied().filter(|v| v.is_finite()).collect();
    sorted.sort_by(|a, b| a.total_cmp(b));
    let med = sorted.get(sorted.len() / 2).copied().unwrap_or(0.01);
    for v in s.iter_mut() {
        if !v.is_finite() {
            *v = med;
        }
        // 15 % larger than the particle's own area, so neighbours overlap instead of leaving
        // hairline gaps between rounded pixel edges
        *v = 1.15 * v.min(2.0 * med);
    }
    s
}
