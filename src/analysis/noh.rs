//! The Noh implosion (Noh 1987) and the reflection of a shock from a rigid wall, for an ideal gas.
//!
//! **Noh.** Cold gas (p = 0) of density ρ0 (kg/m³) streams towards the centre (planar j = 1: a plane;
//! cylindrical j = 2: an axis; spherical j = 3: a point) at speed u0 (m/s). A shock leaves the centre
//! at D = ½ (γ − 1) u0 (m/s); behind it the gas is at rest with
//!
//! ρ₂ = ρ0 ((γ + 1)/(γ − 1))^j,  e₂ = ½ u0² (J/kg),  p₂ = (γ − 1) ρ₂ e₂ (Pa);
//!
//! ahead of it the converging stream has ρ = ρ0 (1 + u0 t/r)^{j−1}, u = −u0, p = 0.
//!
//! **Reflection.** Gas of density ρ1, pressure p1 moving at speed u1 towards a rigid wall is brought
//! to rest by a reflected shock. From the shock relation of the gas ahead of it (Toro 2009, eq. 4.21,
//! with A = 2/((γ + 1) ρ1), B = (γ − 1) p1/(γ + 1)):
//!
//! u1 = (p5 − p1) √(A/(p5 + B)),
//!
//! solved for p5 by Newton's method; then ρ5 = ρ1 (p5/p1 + k)/(k p5/p1 + 1), k = (γ − 1)/(γ + 1)
//! (the strong limit p1 → 0 is taken by ρ5 = ρ1/k), e5 = p5/((γ − 1) ρ5), and the shock moves away
//! from the wall at S = ρ1 u1/(ρ5 − ρ1) (m/s) — mass conservation across it. With p1 → 0 it is the
//! planar Noh state. The excess of the computed e (and the deficit of ρ) at the wall over e5, ρ5 is
//! the "wall heating" of a shock-capturing scheme.

/// A state behind a shock at rest: density (kg/m³), pressure (Pa), specific internal energy (J/kg),
/// and the speed at which the shock leaves the wall or centre (m/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shocked {
    pub rho: f64,
    pub p: f64,
    pub e: f64,
    pub speed: f64,
}

/// The Noh problem.
#[derive(Debug, Clone, Copy)]
pub struct Noh {
    pub j: u32,
    pub gamma: f64,
    pub rho0: f64,
    /// Inflow speed (m/s), positive.
    pub u0: f64,
}

/// A point of the Noh solution: density, radial velocity (negative inward), pressure, energy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NohPoint {
    pub rho: f64,
    pub u: f64,
    pub p: f64,
    pub e: f64,
}

impl Noh {
    /// The state behind the shock.
    pub fn shocked(&self) -> Shocked {
        let g = self.gamma;
        let rho = self.rho0 * ((g + 1.0) / (g - 1.0)).powi(self.j as i32);
        let e = 0.5 * self.u0 * self.u0;
        Shocked { rho, p: (g - 1.0) * rho * e, e, speed: 0.5 * (g - 1.0) * self.u0 }
    }

    /// Shock radius (m) at time t (s).
    pub fn radius(&self, t: f64) -> f64 {
        self.shocked().speed * t
    }

    /// The solution at distance `r` (m) from the centre at time `t` (s).
    pub fn sample(&self, r: f64, t: f64) -> NohPoint {
        let s = self.shocked();
        if r < s.speed * t {
            NohPoint { rho: s.rho, u: 0.0, p: s.p, e: s.e }
        } else {
            let rho = self.rho0 * (1.0 + self.u0 * t / r.max(1e-300)).powi(self.j as i32 - 1);
            NohPoint { rho, u: -self.u0, p: 0.0, e: 0.0 }
        }
    }
}

/// The state at rest behind the shock reflected from a rigid wall by gas of density `rho1`
/// (kg/m³) and pressure `p1` (Pa, ≥ 0) arriving at speed `u1` (m/s, > 0), for the ideal gas γ.
/// `None` if u1 ≤ 0 or the data are not finite.
pub(crate) fn reflect(gamma: f64, rho1: f64, p1: f64, u1: f64) -> Option<Shocked> {
    let g = gamma;
    if !(u1 > 0.0 && rho1 > 0.0 && p1 >= 0.0 && g > 1.0 && u1.is_finite()) {
        return None;
    }
    let k = (g - 1.0) / (g + 1.0);
    let a = 2.0 / ((g + 1.0) * rho1);
    let b = k * p1;
    // f(p) = (p − p1) √(A/(p + B)) − u1, increasing in p ≥ p1; start from the strong-shock value
    let mut p = p1 + 0.5 * (g + 1.0) * rho1 * u1 * u1;
    for _ in 0..200 {
        let q = (a / (p + b)).sqrt();
        let f = (p - p1) * q - u1;
        let df = q * (1.0 - 0.5 * (p - p1) / (p + b));
        let pn = (p - f / df).max(p1 + 1e-300);
        let done = (pn - p).abs() <= 1e-15 * pn;
        p = pn;
        if done {
            break;
        }
    }
    let rho = if p1 > 0.0 {
        let r = p / p1;
        rho1 * (r + k) / (k * r + 1.0)
    } else {
        rho1 / k
    };
    let e = p / ((g - 1.0) * rho);
    let speed = rho1 * u1 / (rho - rho1);
    (p.is_finite() && rho.is_finite()).then_some(Shocked { rho, p, e, speed })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Rankine–Hugoniot fluxes across a shock moving at `s` (lab frame) between the states
    /// (ρa, ua, pa, ea) ahead and (ρb, ub, pb, eb) behind: mass, momentum, energy residuals.
    fn rh(s: f64, a: (f64, f64, f64, f64), b: (f64, f64, f64, f64)) -> [f64; 3] {
        let f = |q: (f64, f64, f64, f64)| {
            let (rho, u, p, e) = q;
            let w = u - s;
            [rho * w, rho * w * u + p, rho * w * (e + 0.5 * u * u) + p * u]
        };
        let (fa, fb) = (f(a), f(b));
        [fa[0] - fb[0], fa[1] - fb[1], fa[2] - fb[2]]
    }

    #[test]
    fn noh_post_shock_state_satisfies_rankine_hugoniot() {
        for j in 1..=3 {
            for g in [1.4, 5.0 / 3.0] {
                let n = Noh { j, gamma: g, rho0: 1.0, u0: 1.0 };
                let s = n.shocked();
                let t = 0.6;
                let r = n.radius(t);
                let ahead = n.sample(r * (1.0 + 1e-12), t);
                let behind = n.sample(r * (1.0 - 1e-12), t);
                // the shock moves outward at +D; the stream arrives at −u0
                let res = rh(s.speed, (ahead.rho, ahead.u, ahead.p, ahead.e), (behind.rho, 0.0, behind.p, behind.e));
                for (q, v) in res.iter().enumerate() {
                    assert!(v.abs() < 1e-9 * behind.rho.max(1.0), "j = {j}, gamma = {g}: flux {q} off by {v}");
                }
            }
        }
        // the classic numbers: 2D, γ = 5/3: ρ = 16, D = 1/3; 3D: ρ = 64
        let n = Noh { j: 2, gamma: 5.0 / 3.0, rho0: 1.0, u0: 1.0 };
        assert!((n.shocked().rho - 16.0).abs() < 1e-12 && (n.shocked().speed - 1.0 / 3.0).abs() < 1e-15);
        assert!((Noh { j: 3, ..n }.shocked().rho - 64.0).abs() < 1e-12);
    }

    #[test]
    fn reflection_satisfies_rankine_hugoniot_and_has_the_strong_limit() {
        let g = 1.4;
        for (rho1, p1, u1) in [(1.0, 1.0, 0.5), (2.0, 0.1, 3.0), (1.0, 1e-6, 1.0)] {
            let s = reflect(g, rho1, p1, u1).unwrap();
            let e1 = p1 / ((g - 1.0) * rho1);
            // in the lab frame the wall is at rest, the gas arrives at −u1, the shock moves at +S
            let res = rh(s.speed, (rho1, -u1, p1, e1), (s.rho, 0.0, s.p, s.e));
            for (q, v) in res.iter().enumerate() {
                assert!(v.abs() < 1e-9 * s.p.max(1.0), "state {rho1}/{p1}/{u1}: flux {q} off by {v}");
            }
        }
        // p1 → 0: the planar Noh state
        let s = reflect(5.0 / 3.0, 1.0, 0.0, 1.0).unwrap();
        assert!((s.rho - 4.0).abs() < 1e-12 && (s.e - 0.5).abs() < 1e-12 && (s.speed - 1.0 / 3.0).abs() < 1e-12);
        assert!(reflect(1.4, 1.0, 1.0, -1.0).is_none());
    }
}
