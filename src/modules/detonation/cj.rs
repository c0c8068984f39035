//! The Chapman–Jouguet state of a JWL explosive and the Taylor wave behind a planar detonation lit
//! at a rigid wall (Fickett & Davis, *Detonation*, ch. 2 and 4).
//!
//! JWL products (thesis 4-39), η = ρ/ρ0:
//! p(ρ, e) = A(1 − ωη/R1) e^{−R1/η} + B(1 − ωη/R2) e^{−R2/η} + ω ρ e (Pa), with e (J/kg) counting the
//! chemical energy: the explosive starts at ρ0, e0, p = 0 (unreacted, at rest).
//!
//! **CJ state.** On the products' Hugoniot from (ρ0, p = 0, e0), e = e0 + ½ p (1/ρ0 − 1/ρ), and the
//! JWL is linear in e, so p_H(η) = (cold(η) + ω ρ e0)/(1 − ½ ω (η − 1)). The Rayleigh line from the
//! initial state to a point of it has slope −ρ0² D², so D²(η) = p_H(η) η/(ρ0 (η − 1)); the CJ
//! detonation is the slowest, the minimum of D² over η (golden-section search), where the Rayleigh line
//! touches the Hugoniot. Then u_CJ = D (1 − 1/η), and the CJ point is sonic: u_CJ + c_CJ = D, which
//! the tests check with the EOS's own isentropic sound speed c² = ∂p/∂ρ|_e + (p/ρ²) ∂p/∂e|_ρ.
//!
//! **Taylor wave.** Lit at a rigid wall x = 0 at t = 0, the front runs at D; behind it a centred
//! simple wave brings the products to rest. Along the products' isentrope through the CJ state,
//! de/dρ = p/ρ² (integrated by fourth-order Runge–Kutta in ρ), the Riemann invariant u − F(ρ),
//! F = ∫ c dρ/ρ, is uniform, so u(ρ) = u_CJ − (F(ρ_CJ) − F(ρ)); the wave is the fan x/t = u + c, from
//! the plateau (u = 0, reached at ρ_p, x/t = c_p) to the front (x/t = D). For the thesis's TNT set:
//! p_CJ = 20.98 GPa, ρ_CJ = 2227.5 kg/m³, D_CJ = 6927.8 m/s, plateau ≈ 5.63 GPa.

/// JWL constants (SI): ρ0 (kg/m³), A, B (Pa), R1, R2, ω, and e0 (J/kg), the energy at ρ0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jwl {
    pub rho0: f64,
    pub a: f64,
    pub b: f64,
    pub r1: f64,
    pub r2: f64,
    pub omega: f64,
    pub e0: f64,
}

impl Jwl {
    /// The thesis's TNT (Table 4-2 with A = 3.712e11 Pa; theory.md §8).
    pub const TNT: Jwl = Jwl { rho0: 1630.0, a: 3.712e11, b: 3.21e9, r1: 4.15, r2: 0.95, omega: 0.30, e0: 4.29e6 };

    fn cold(&self, eta: f64) -> f64 {
        self.a * (1.0 - self.omega * eta / self.r1) * (-self.r1 / eta).exp()
            + self.b * (1.0 - self.omega * eta / self.r2) * (-self.r2 / eta).exp()
    }

    /// Pressure (Pa) at ρ (kg/m³), e (J/kg).
    pub fn p(&self, rho: f64, e: f64) -> f64 {
        self.cold(rho / self.rho0) + self.omega * rho * e
    }

    /// Isentropic sound speed squared (m²/s²) at ρ, e.
    pub fn c2(&self, rho: f64, e: f64) -> f64 {
        let eta = rho / self.rho0;
        let (om, r1, r2) = (self.omega, self.r1, self.r2);
        // d(cold)/dη
        let dcold = self.a * (-r1 / eta).exp() * (-om / r1 + (1.0 - om * eta / r1) * r1 / (eta * eta))
            + self.b * (-r2 / eta).exp() * (-om / r2 + (1.0 - om * eta / r2) * r2 / (eta * eta));
        let dpdrho = dcold / self.rho0 + om * e;
        let dpde = om * rho;
        dpdrho + self.p(rho, e) / (rho * rho) * dpde
    }

    /// Pressure on the products' Hugoniot from (ρ0, 0, e0) at η = ρ/ρ0.
    pub fn hugoniot_p(&self, eta: f64) -> f64 {
        (self.cold(eta) + self.omega * eta * self.rho0 * self.e0) / (1.0 - 0.5 * self.omega * (eta - 1.0))
    }

    /// D² (m²/s²) of the Rayleigh line to the Hugoniot point at η.
    fn d2(&self, eta: f64) -> f64 {
        self.hugoniot_p(eta) * eta / (self.rho0 * (eta - 1.0))
    }
}

/// The Chapman–Jouguet state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cj {
    /// Detonation speed D_CJ (m/s).
    pub d: f64,
    pub p: f64,
    pub rho: f64,
    /// Particle velocity behind the front (m/s).
    pub u: f64,
    pub e: f64,
    /// Sound speed (m/s).
    pub c: f64,
}

/// The CJ state of `jwl`, or `None` if the Hugoniot has no minimum of D in range.
pub fn cj(jwl: &Jwl) -> Option<Cj> {
    // the Hugoniot exists for 1 < η < 1 + 2/ω (its denominator stays positive)
    let (mut lo, mut hi) = (1.0 + 1e-9, 1.0 + 2.0 / jwl.omega - 1e-9);
    let phi = 0.5 * (5f64.sqrt() - 1.0);
    let mut x1 = hi - phi * (hi - lo);
    let mut x2 = lo + phi * (hi - lo);
    let (mut f1, mut f2) = (jwl.d2(x1), jwl.d2(x2));
    for _ in 0..300 {
        if f1 < f2 {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - phi * (hi - lo);
            f1 = jwl.d2(x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + phi * (hi - lo);
            f2 = jwl.d2(x2);
        }
        if hi - lo < 1e-13 {
            break;
        }
    }
    let eta = 0.5 * (lo + hi);
    let d = jwl.d2(eta).sqrt();
    let p = jwl.hugoniot_p(eta);
    let rho = eta * jwl.rho0;
    let u = d * (1.0 - 1.0 / eta);
    let e = jwl.e0 + 0.5 * p * (1.0 / jwl.rho0 - 1.0 / rho);
    let c = jwl.c2(rho, e).max(0.0).sqrt();
    (d.is_finite() && p > 0.0 && eta > 1.0 + 1e-6 && eta < 1.0 + 2.0 / jwl.omega - 1e-6).then_some(Cj {
        d,
        p,
        rho,
        u,
        e,
        c,
    })
}

/// A point of the solution: density (kg/m³), velocity (m/s), pressure (Pa), energy (J/kg).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WavePoint {
    pub rho: f64,
    pub u: f64,
    pub p: f64,
    pub e: f64,
}

/// The CJ detonation lit at a rigid wall, with its Taylor wave.
#[derive(Debug, Clone)]
pub struct TaylorWave {
    pub jwl: Jwl,
    pub cj: Cj,
    /// The plateau at the wall: u = 0.
    pub plateau: WavePoint,
    /// Sound speed of the plateau (m/s): the plateau reaches x = c_p t.
    pub c_plateau: f64,
    /// The isentrope from ρ_CJ down to ρ_p, ρ descending: (ρ, e, p, u, u + c).
    table: Vec<[f64; 5]>,
}

impl TaylorWave {
    pub fn new(jwl: &Jwl) -> Option<TaylorWave> {
        let cj = cj(jwl)?;
        // isentrope de/dρ = p/ρ², F' = c/ρ, from ρ_CJ downward in N steps to 0.3 ρ0
        let n = 40_000;
        let (r0, r1) = (cj.rho, 0.3 * jwl.rho0);
        let hr = (r1 - r0) / n as f64;
        let f = |rho: f64, y: [f64; 2]| -> [f64; 2] {
            let c = jwl.c2(rho, y[0]).max(0.0).sqrt();
            [jwl.p(rho, y[0]) / (rho * rho), c / rho]
        };
        let mut y = [cj.e, 0.0]; // e, F(ρ) − F(ρ_CJ)
        let mut rho = r0;
        let mut table = Vec::with_capacity(n + 1);
        let row = |rho: f64, y: [f64; 2]| {
            let u = cj.u + y[1];
            [rho, y[0], jwl.p(rho, y[0]), u, u + jwl.c2(rho, y[0]).max(0.0).sqrt()]
        };
        table.push(row(rho, y));
        for _ in 0..n {
            let add = |y: [f64; 2], k: [f64; 2], s: f64| [y[0] + s * k[0], y[1] + s * k[1]];
            let k1 = f(rho, y);
            let k2 = f(rho + 0.5 * hr, add(y, k1, 0.5 * hr));
            let k3 = f(rho + 0.5 * hr, add(y, k2, 0.5 * hr));
            let k4 = f(rho + hr, add(y, k3, hr));
            y[0] += hr / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]);
            y[1] += hr / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1]);
            rho += hr;
            let r = row(rho, y);
            let stop = r[3] <= 0.0;
            table.push(r);
            if stop {
                break;
            }
        }
        // the plateau: where u crosses 0 (linear interpolation between the last two rows)
        let k = table.len() - 1;
        if table[k][3] > 0.0 {
            return None;
        }
        let (a, b) = (table[k - 1], table[k]);
        let s = a[3] / (a[3] - b[3]);
        let lerp = |q: usize| a[q] + s * (b[q] - a[q]);
        let (rp, ep) = (lerp(0), lerp(1));
        let plateau = WavePoint { rho: rp, u: 0.0, p: jwl.p(rp, ep), e: ep };
        let c_plateau = jwl.c2(rp, ep).max(0.0).sqrt();
        table.pop();
        table.push([rp, ep, plateau.p, 0.0, c_plateau]);
        Some(TaylorWave { jwl: *jwl, cj, plateau, c_plateau, table })
    }

    /// The solution at distance `x` (m) from the wall at time `t` (s) after lighting: the unreacted
    /// explosive at rest ahead of the front (x > D t), the fan, the plateau.
    pub fn sample(&self, x: f64, t: f64) -> WavePoint {
        let xi = if t > 0.0 { x / t } else { f64::INFINITY };
        if xi > self.cj.d {
            return WavePoint { rho: self.jwl.rho0, u: 0.0, p: 0.0, e: self.jwl.e0 };
        }
        if xi <= self.c_plateau {
            return self.plateau;
        }
        // u + c decreases down the table (ρ descending): bisection for u + c = ξ
        let (mut lo, mut hi) = (0usize, self.table.len() - 1);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if self.table[mid][4] >= xi { lo = mid } else { hi = mid }
        }
        let (a, b) = (self.table[lo], self.table[hi]);
        let s = if a[4] != b[4] { (a[4] - xi) / (a[4] - b[4]) } else { 0.0 };
        let l = |q: usize| a[q] + s * (b[q] - a[q]);
        WavePoint { rho: l(0), u: l(3), p: l(2), e: l(1) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tnt_cj_state_against_references() {
        // For the thesis's TNT set: p_CJ = 20.98 GPa, ρ_CJ = 2227.5 kg/m³, D_CJ = 6927.8 m/s
        let s = cj(&Jwl::TNT).unwrap();
        assert!((s.p / 20.98e9 - 1.0).abs() < 5e-4, "p_CJ = {}", s.p);
        assert!((s.rho - 2227.5).abs() < 0.5, "rho_CJ = {}", s.rho);
        assert!((s.d - 6927.8).abs() < 0.5, "D_CJ = {}", s.d);
    }

    #[test]
    fn cj_point_is_sonic_and_tangent() {
        for jwl in [
            Jwl::TNT,
            // C4, the LLNL set (the thesis's source): D = 8193 m/s, p_CJ = 28.0 GPa
            Jwl { rho0: 1601.0, a: 609.77e9, b: 12.95e9, r1: 4.5, r2: 1.4, omega: 0.25, e0: 9.0e9 / 1601.0 },
        ] {
            let s = cj(&jwl).unwrap();
            // the sound speed of the EOS, independent of the minimisation
            assert!(((s.u + s.c) / s.d - 1.0).abs() < 1e-5, "u + c = {} against D = {}", s.u + s.c, s.d);
            // tangency: the Hugoniot's slope dp/dv equals the Rayleigh line's −ρ0² D²
            let v = 1.0 / s.rho;
            let dv = 1e-6 * v;
            let pa = jwl.hugoniot_p(1.0 / ((v - dv) * jwl.rho0));
            let pb = jwl.hugoniot_p(1.0 / ((v + dv) * jwl.rho0));
            let slope = (pb - pa) / (2.0 * dv);
            let ray = -jwl.rho0 * jwl.rho0 * s.d * s.d;
            assert!((slope / ray - 1.0).abs() < 1e-4, "Hugoniot slope {slope:e}, Rayleigh {ray:e}");
        }
        let c4 = Jwl { rho0: 1601.0, a: 609.77e9, b: 12.95e9, r1: 4.5, r2: 1.4, omega: 0.25, e0: 9.0e9 / 1601.0 };
        let s = cj(&c4).unwrap();
        assert!((s.d - 8193.0).abs() < 30.0 && (s.p / 28.0e9 - 1.0).abs() < 0.01, "C4: D {} p {}", s.d, s.p);
    }

    #[test]
    fn taylor_wave_of_tnt() {
        let w = TaylorWave::new(&Jwl::TNT).unwrap();
        // the thesis's TNT set, derived independently: plateau ≈ 5.63 GPa
        assert!((w.plateau.p / 5.63e9 - 1.0).abs() < 3e-3, "plateau {}", w.plateau.p);
        let t = 1e-5;
        let front = w.sample(0.999999 * w.cj.d * t, t);
        assert!((front.p / w.cj.p - 1.0).abs() < 1e-3 && (front.u / w.cj.u - 1.0).abs() < 1e-3);
        assert_eq!(w.sample(1.01 * w.cj.d * t, t).p, 0.0);
        assert_eq!(w.sample(0.5 * w.c_plateau * t, t), w.plateau);
        // monotone through the fan, and the isentrope p ρ^-γ_eff falls with ρ
        let mut last = w.plateau.p;
        for k in 1..100 {
            let xi = w.c_plateau + (w.cj.d - w.c_plateau) * k as f64 / 100.0;
            let q = w.sample(xi * t, t);
            assert!(q.p >= last && q.u >= 0.0, "not monotone at x/t = {xi}");
            last = q.p;
        }
    }
}
