//! The geostatic start (`initial.geostatic`; docs/theory.md, "Geostatic start"): soil at rest
//! under its own weight at t = 0. For each particle i, with ĝ the unit vector along gravity and
//! the column of i the particles within half a spacing of it across ĝ and above it:
//!
//! - σ_v,i = |g| (Σ_{j above i in its column} ρ_j Δx_j^d / Δx_i^{d−1} + ρ_i Δx_i / 2) (Pa), the
//!   weight of the column above the particle's centre per unit area;
//! - σ_h,i = K0 σ_v,i, K0 = 1 − sin φ (Jaky 1944) for a material with strength, 1 for a fluid;
//! - the mean stress p_i = (σ_v + 2 σ_h)/3 (Pa), the density ρ_i that gives it through the
//!   material's EOS at the particle's energy (bisection), the mass scaled by the same factor (the
//!   particle keeps its lattice volume);
//! - the deviator τ_i = (p − σ_h) I + (σ_h − σ_v) ĝĝᵀ (Pa), brought back to the Drucker–Prager
//!   surface where it lies outside it, as the strength module's return would.
//!
//! It is set-up, done once on the generated particles before the plan's first stage, like the
//! lattice itself: no module computes it, so it has no Fortran twin, and both implementations of
//! every stage start from the same state. An explosive (JWL) keeps its density (its weight counts
//! in the columns above it).

use crate::case::Case;
use crate::modules::eos::point;
use crate::modules::param::{EosKind, MatTable, NPAR, NSTR, SPH_MP_ALPHA_PHI, SPH_MP_COHESION};
use crate::setup::Initial;
use rayon::prelude::*;

/// The geostatic state of the particles: their density (kg/m³) and mass (kg) are changed in
/// `init`; the returned deviatoric stress (Pa, NSTR per particle) goes into the state's τ once
/// the strength module has allocated it. None when the case does not ask for it.
pub fn apply(case: &Case, mt: &MatTable, init: &mut Initial) -> Option<Vec<f64>> {
    if !case.geostatic() {
        return None;
    }
    let d = case.dim;
    let n = init.mass.len();
    let g = case.physics.gravity_ms2.clone().unwrap_or_default();
    let gmag = g.iter().map(|a| a * a).sum::<f64>().sqrt();
    let mut down = [0.0; 3];
    for a in 0..d {
        down[a] = g[a] / gmag;
    }
    let across = lateral_axes(d, down);
    let spacing: Vec<f64> = init.region.iter().map(|&r| case.regions[r as usize].spacing_m).collect();
    let dx_max = spacing.iter().fold(0.0f64, |a, &b| a.max(b));
    // height along −ĝ and the coordinates across it, per particle
    let up: Vec<f64> = (0..n).map(|i| -(0..d).map(|a| init.x[a + d * i] * down[a]).sum::<f64>()).collect();
    let lat: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let mut l = [0.0; 2];
            for (k, ax) in across.iter().enumerate().take(d - 1) {
                l[k] = (0..d).map(|a| init.x[a + d * i] * ax[a]).sum();
            }
            l
        })
        .collect();
    let sv = overburden(d, &up, &lat, &spacing, &init.rho, dx_max);
    let k0: Vec<f64> =
        case.materials.iter().map(|m| m.strength.as_ref().map_or(1.0, |s| 1.0 - s.sin_phi().clamp(0.0, 1.0))).collect();
    let strength = crate::case::has_strength(case);
    let mut tau = vec![0.0; if strength { NSTR * n } else { 0 }];
    for i in 0..n {
        let m = init.mat[i] as usize;
        let s_v = gmag * sv[i];
        let s_h = k0[m] * s_v;
        let p = (s_v + 2.0 * s_h) / 3.0;
        let par = &mt.mpar[NPAR * m..NPAR * (m + 1)];
        let kind = EosKind::of_code(mt.mtype[m]);
        if !matches!(kind, Some(EosKind::Jwl) | Some(EosKind::None) | None)
            && let Some(rho) = density_at(mt.mtype[m], par, init.rho[i], init.e[i], p)
        {
            init.mass[i] *= rho / init.rho[i];
            init.rho[i] = rho;
        }
        if strength && case.materials[m].strength.is_some() {
            let t = &mut tau[NSTR * i..NSTR * i + NSTR];
            let iso = p - s_h;
            let dev = s_h - s_v;
            // xx, yy, zz, xy, xz, yz of (p − σ_h) I + (σ_h − σ_v) ĝĝᵀ
            let pairs = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];
            for (c, &(a, b)) in pairs.iter().enumerate() {
                t[c] = dev * down[a] * down[b] + if a == b { iso } else { 0.0 };
            }
            let y = 3.0 * mt.par(m, SPH_MP_ALPHA_PHI) * p + mt.par(m, SPH_MP_COHESION);
            let sj = (s_v - s_h).abs() / 3f64.sqrt();
            if y <= 0.0 {
                t.fill(0.0);
            } else if sj > y {
                t.iter_mut().for_each(|x| *x *= y / sj);
            }
        }
    }
    Some(tau)
}

/// Unit vectors across the unit vector `down` (d − 1 of them).
fn lateral_axes(d: usize, down: [f64; 3]) -> [[f64; 3]; 2] {
    match d {
        1 => [[0.0; 3]; 2],
        2 => [[-down[1], down[0], 0.0], [0.0; 3]],
        _ => {
            // the coordinate axis least along ĝ, made orthogonal to it, then ĝ × e1
            let k = (0..3).min_by(|&a, &b| down[a].abs().total_cmp(&down[b].abs())).unwrap_or(0);
            let mut e1 = [0.0; 3];
            e1[k] = 1.0;
            let dot = down[k];
            for a in 0..3 {
                e1[a] -= dot * down[a];
            }
            let l = (e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]).sqrt();
            e1.iter_mut().for_each(|x| *x /= l);
            let e2 = [
                down[1] * e1[2] - down[2] * e1[1],
                down[2] * e1[0] - down[0] * e1[2],
                down[0] * e1[1] - down[1] * e1[0],
            ];
            [e1, e2]
        }
    }
}

/// The mass per unit area above each particle's centre (kg/m²): its column's particles above it
/// (within half its spacing across ĝ, each counted with the share of its volume the column
/// holds) and the upper half of itself. Particles are binned across ĝ by the largest spacing, so
/// each looks at the 3^(d−1) bins around its own.
fn overburden(d: usize, up: &[f64], lat: &[[f64; 2]], dx: &[f64], rho: &[f64], bin: f64) -> Vec<f64> {
    use std::collections::HashMap;
    let n = up.len();
    let key = |l: &[f64; 2]| -> (i64, i64) {
        let k0 = (l[0] / bin).floor() as i64;
        let k1 = if d == 3 { (l[1] / bin).floor() as i64 } else { 0 };
        (k0, k1)
    };
    let mut bins: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (i, l) in lat.iter().enumerate() {
        bins.entry(key(l)).or_default().push(i);
    }
    let reach1 = if d == 3 { 1 } else { 0 };
    let reach0 = if d >= 2 { 1 } else { 0 };
    (0..n)
        .into_par_iter()
        .map(|i| {
            let (k0, k1) = key(&lat[i]);
            let half = 0.5 * dx[i];
            let area = dx[i].powi(d as i32 - 1);
            let mut w = 0.5 * rho[i] * dx[i];
            for a in -reach0..=reach0 {
                for b in -reach1..=reach1 {
                    let Some(list) = bins.get(&(k0 + a, k1 + b)) else { continue };
                    for &j in list {
                        let beside = (0..d - 1).all(|k| (lat[j][k] - lat[i][k]).abs() < half);
                        if j != i && beside && up[j] > up[i] + 1e-9 * dx[i] {
                            w += rho[j] * dx[j].powi(d as i32) / area;
                        }
                    }
                }
            }
            w
        })
        .collect()
}

/// The density (kg/m³) at which the EOS of the material (`itype`, its column `par`) gives the
/// pressure `p` (Pa) at energy `e` (J/kg): bisection on [ρ_start/2, 2 ρ_start], p(ρ) rising. None
/// where the bracket does not hold p (a pressure floored above it, or beyond a factor of 2).
fn density_at(itype: i32, par: &[f64], rho_start: f64, e: f64, p: f64) -> Option<f64> {
    let f = |r: f64| point(itype, par, r, e, 1.0).0 - p;
    let (mut lo, mut hi) = (0.5 * rho_start, 2.0 * rho_start);
    if !(f(lo) <= 0.0 && f(hi) >= 0.0) {
        return None;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if f(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_uniform_column_weighs_rho_g_z() {
        // five particles of a column 1 m apart, and one beside it that must not count
        let up = [0.5, 1.5, 2.5, 3.5, 4.5, 4.5];
        let lat = [[0.0; 2], [0.0; 2], [0.0; 2], [0.0; 2], [0.0; 2], [1.0, 0.0]];
        let dx = [1.0; 6];
        let rho = [1000.0; 6];
        let w = overburden(2, &up, &lat, &dx, &rho, 1.0);
        // depth of the centre below the top (5 m): 4.5, 3.5, ... m
        for (i, want) in [4.5, 3.5, 2.5, 1.5, 0.5, 0.5].iter().enumerate() {
            assert!((w[i] - 1000.0 * want).abs() < 1e-9, "{i}: {}", w[i]);
        }
    }

    #[test]
    fn the_compression_cone_gives_32_degrees_at_alpha_one_quarter() {
        let s = crate::case::StrengthCfg {
            shear_modulus_pa: 1e7,
            alpha_phi: 0.25,
            cohesion_pa: 0.0,
            friction_angle_deg: None,
        };
        let phi = s.sin_phi().asin().to_degrees();
        assert!((phi - 32.3).abs() < 0.05, "{phi}");
        // and α_φ = 2 sin φ/(√3 (3 − sin φ)) back
        let a = 2.0 * s.sin_phi() / (3f64.sqrt() * (3.0 - s.sin_phi()));
        assert!((a - 0.25).abs() < 1e-12);
    }
}
