//! The radius of a point blast's shock, measured from the particles, in every geometry: the
//! measurement of the Sedov–Taylor verification cases (`cases/verify/sedov_*.toml`,
//! docs/validation.md "Sedov–Taylor in 3D, RZ and 2D plane"). It measures only; the similarity
//! solution itself (profiles, any γ) is `src/analysis/sedov.rs` of issue 12 — here the shock
//! radius is held against R = ξ0 (E t²/ρ0)^{1/(j+2)} with ξ0 from REFERENCES.md.
//!
//! Definitions (the same as issue 12's, so the two can be compared):
//! - distance from the centre: |x − c| in 2D plane (cylindrical, j = 2) and 3D (spherical,
//!   j = 3); in RZ √(r² + (z − z_c)²) (spherical, the centre on the axis);
//! - radial profile: the particles binned by distance in bins one initial spacing wide, a bin's
//!   density the mean of its particles' ρ;
//! - R_peak: the centre of the bin of largest mean density;
//! - R_half: outward from that bin, where the binned density falls through the middle between
//!   the peak and the ambient density (linear between bin centres): the mid-rise of the front.

use crate::output::Frame;

/// The shock of one frame.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct Shock {
    /// Centre of the bin of largest mean density (m).
    pub r_peak_m: f64,
    /// Where the binned density falls through the middle between peak and ambient (m).
    pub r_half_m: f64,
    /// The largest binned mean density (kg/m³).
    pub rho_peak_kgm3: f64,
}

/// The distance of every particle of `f` from `centre` (m): spherical in 3D and in RZ
/// (`axisymmetric`: x is r, y is z), cylindrical in 2D plane.
pub fn distances(f: &Frame, dim: usize, axisymmetric: bool, centre: [f64; 3]) -> Vec<f64> {
    (0..f.x.len())
        .map(|i| {
            let dx = if axisymmetric { f.x[i] } else { f.x[i] - centre[0] };
            let dy = if dim > 1 { f.y[i] - centre[1] } else { 0.0 };
            let dz = if dim > 2 { f.z[i] - centre[2] } else { 0.0 };
            (dx * dx + dy * dy + dz * dz).sqrt()
        })
        .collect()
}

/// Binned mean density against distance: (bin centre, mean ρ, count), non-empty bins only.
pub fn profile(r: &[f64], rho: &[f64], dr: f64) -> Vec<(f64, f64, usize)> {
    let rmax = r.iter().cloned().filter(|v| v.is_finite()).fold(0.0, f64::max);
    let nb = ((rmax / dr) as usize + 1).min(10_000_000);
    let mut sum = vec![0.0; nb];
    let mut cnt = vec![0usize; nb];
    for (k, &ri) in r.iter().enumerate() {
        if !ri.is_finite() {
            continue;
        }
        let b = ((ri / dr) as usize).min(nb - 1);
        sum[b] += rho[k];
        cnt[b] += 1;
    }
    (0..nb).filter(|&b| cnt[b] > 0).map(|b| ((b as f64 + 0.5) * dr, sum[b] / cnt[b] as f64, cnt[b])).collect()
}

/// R_peak, R_half and the peak density of a profile, `ambient` the density ahead of the shock.
pub fn shock(prof: &[(f64, f64, usize)], ambient: f64) -> Shock {
    let Some(kmax) = (0..prof.len()).max_by(|&a, &b| prof[a].1.total_cmp(&prof[b].1)) else {
        return Shock { r_peak_m: f64::NAN, r_half_m: f64::NAN, rho_peak_kgm3: f64::NAN };
    };
    let (rp, peak) = (prof[kmax].0, prof[kmax].1);
    let mid = 0.5 * (peak + ambient);
    let mut rhalf = f64::NAN;
    for k in kmax..prof.len().saturating_sub(1) {
        let (ra, da) = (prof[k].0, prof[k].1);
        let (rb, db) = (prof[k + 1].0, prof[k + 1].1);
        if da >= mid && db < mid {
            rhalf = ra + (da - mid) / (da - db) * (rb - ra);
            break;
        }
    }
    Shock { r_peak_m: rp, r_half_m: rhalf, rho_peak_kgm3: peak }
}

/// The Sedov–Taylor shock radius R = ξ0 (E t²/ρ0)^{1/(j+2)} (m): E in J (j = 3), J/m (j = 2).
pub fn sedov_radius(xi0: f64, energy: f64, t: f64, rho0: f64, j: u32) -> f64 {
    xi0 * (energy * t * t / rho0).powf(1.0 / (j as f64 + 2.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A synthetic front: ρ = 1 outside 0.29 m, a plateau of 6 in the last bin inside, a ramp below.
    #[test]
    fn the_measures_find_a_synthetic_front() {
        let dr = 0.01;
        let r: Vec<f64> = (0..1000).map(|k| (k as f64 + 0.5) * 0.0005).collect();
        let rho: Vec<f64> = r
            .iter()
            .map(|&x| {
                if x < 0.28 {
                    0.5 + 10.0 * x
                } else if x < 0.29 {
                    6.0
                } else {
                    1.0
                }
            })
            .collect();
        let s = shock(&profile(&r, &rho, dr), 1.0);
        assert!((s.r_peak_m - 0.285).abs() < 1e-9, "{s:?}");
        assert!(s.r_half_m > 0.285 && s.r_half_m < 0.305, "{s:?}");
        assert_eq!(s.rho_peak_kgm3, 6.0);
        // REFERENCES.md: the 2D cylindrical case of issue 12, 1.0040 (1 × 0.01/1)^(1/4) = 0.3175
        assert!((sedov_radius(1.0040, 1.0, 0.1, 1.0, 2) - 0.3175).abs() < 5e-5);
    }
}
