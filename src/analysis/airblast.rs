//! Free-air blast of a TNT sphere against Kinney & Graham (1985), *Explosive Shocks in Air*, 2nd
//! ed., Springer, their fits at sea level (Z = R/W^⅓ in m/kg^⅓, W the TNT mass in kg):
//! peak side-on overpressure p_s/p_a = 808 [1 + (Z/4.5)²] / (√(1 + (Z/0.048)²) √(1 + (Z/0.32)²)
//! √(1 + (Z/1.35)²)), and positive impulse I/W^⅓ = 0.067 √(1 + (Z/0.23)⁴) / (Z² ∛(1 + (Z/1.55)³))
//! in bar·ms/kg^⅓ (1 bar·ms = 100 Pa·s). A gauge's record gives the measured pair: its peak
//! overpressure and the time integral of its overpressure over the positive phase.

/// Sea-level ambient pressure of the fits (Pa).
pub const P_AMBIENT: f64 = 101_325.0;

/// Kinney & Graham's peak side-on overpressure (Pa) at scaled distance `z` (m/kg^⅓).
pub fn overpressure(z: f64) -> f64 {
    let q = |a: f64| (1.0 + (z / a).powi(2)).sqrt();
    P_AMBIENT * 808.0 * (1.0 + (z / 4.5).powi(2)) / (q(0.048) * q(0.32) * q(1.35))
}

/// Kinney & Graham's positive-phase impulse (Pa·s) at scaled distance `z` (m/kg^⅓) from a charge
/// of `w_kg` of TNT.
pub fn impulse(z: f64, w_kg: f64) -> f64 {
    let scaled = 0.067 * (1.0 + (z / 0.23).powi(4)).sqrt() / (z * z * (1.0 + (z / 1.55).powi(3)).cbrt());
    scaled * 100.0 * w_kg.cbrt()
}

/// Peak overpressure (Pa) and positive impulse (Pa·s) of a pressure record (`t` in s, `p`
/// absolute in Pa; None where the gauge read nothing): the largest p − `p_amb`, and the
/// trapezoidal integral of p − `p_amb` from the last sample at or below zero before the peak to
/// the first one after it.
pub fn measure(t: &[f64], p: &[Option<f64>], p_amb: f64) -> Option<(f64, f64)> {
    let dp: Vec<(f64, f64)> = t.iter().zip(p).filter_map(|(&t, p)| p.map(|p| (t, p - p_amb))).collect();
    let (k, &(_, peak)) = dp.iter().enumerate().max_by(|a, b| a.1.1.total_cmp(&b.1.1))?;
    if peak <= 0.0 {
        return None;
    }
    let start = dp[..k].iter().rposition(|s| s.1 <= 0.0).unwrap_or(0);
    let end = dp[k..].iter().position(|s| s.1 <= 0.0).map_or(dp.len() - 1, |e| k + e);
    let imp = dp[start..=end].windows(2).map(|w| 0.5 * (w[0].1.max(0.0) + w[1].1.max(0.0)) * (w[1].0 - w[0].0)).sum();
    Some((peak, imp))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The overpressure fit at Z = 1 m/kg^⅓ (1.0088 MPa, worked by hand from the formula), and
    /// both fits fall with Z.
    #[test]
    fn the_fits_fall_with_distance() {
        let p1 = overpressure(1.0);
        assert!((p1 / 1.008e6 - 1.0).abs() < 0.01, "p_s(Z = 1) = {p1}");
        let mut last = (f64::INFINITY, f64::INFINITY);
        for k in 1..=20 {
            let z = 0.5 * k as f64;
            let now = (overpressure(z), impulse(z, 1.0));
            assert!(now.0 < last.0 && now.1 < last.1, "not falling at Z = {z}");
            last = now;
        }
    }

    #[test]
    fn a_triangular_pulse_measures_its_area() {
        let t: Vec<f64> = (0..=40).map(|k| k as f64 * 1e-4).collect();
        // ambient until 1 ms, a jump to +100 kPa falling linearly to 0 at 2 ms, then −10 kPa
        let p: Vec<Option<f64>> = t
            .iter()
            .map(|&t| {
                let dp = if t < 0.95e-3 {
                    0.0
                } else if t <= 2e-3 {
                    1e5 * (2e-3 - t) / 1.05e-3
                } else {
                    -1e4
                };
                Some(P_AMBIENT + dp)
            })
            .collect();
        let (peak, imp) = measure(&t, &p, P_AMBIENT).unwrap();
        assert!((peak / 1e5 - 1.0).abs() < 0.05, "peak {peak}");
        assert!((imp / 52.5 - 1.0).abs() < 0.05, "impulse {imp}");
    }
}
