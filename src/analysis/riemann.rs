//! Exact solution of the Riemann problem for an ideal gas (Toro, *Riemann Solvers and Numerical
//! Methods for Fluid Dynamics*, ch. 4): Newton iteration for the star pressure p*, then sampling of
//! the self-similar solution at ξ = (x − x0)/t. Units: SI (kg/m³, m/s, Pa, J/kg).

/// One side of the diaphragm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Side {
    pub rho: f64,
    pub u: f64,
    pub p: f64,
}

/// The solved problem.
#[derive(Debug, Clone, Copy)]
pub struct Riemann {
    pub left: Side,
    pub right: Side,
    pub gamma: f64,
    pub p_star: f64,
    pub u_star: f64,
}

/// Primitive state at a point: density, velocity, pressure, specific internal energy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State {
    pub rho: f64,
    pub u: f64,
    pub p: f64,
    pub e: f64,
}

fn sound(s: Side, g: f64) -> f64 {
    (g * s.p / s.rho).sqrt()
}

/// f_K(p) and its derivative (Toro 4.6, 4.7, 4.37).
fn f_k(p: f64, s: Side, g: f64) -> (f64, f64) {
    let c = sound(s, g);
    if p > s.p {
        let a = 2.0 / ((g + 1.0) * s.rho);
        let b = (g - 1.0) / (g + 1.0) * s.p;
        let q = (a / (p + b)).sqrt();
        ((p - s.p) * q, q * (1.0 - 0.5 * (p - s.p) / (b + p)))
    } else {
        let r = p / s.p;
        (2.0 * c / (g - 1.0) * (r.powf((g - 1.0) / (2.0 * g)) - 1.0), r.powf(-(g + 1.0) / (2.0 * g)) / (s.rho * c))
    }
}

impl Riemann {
    /// Solves for p* and u*; `None` if the data generate a vacuum or do not converge.
    pub fn solve(left: Side, right: Side, gamma: f64) -> Option<Riemann> {
        let g = gamma;
        let (cl, cr) = (sound(left, g), sound(right, g));
        if 2.0 * (cl + cr) / (g - 1.0) <= right.u - left.u {
            return None;
        }
        // two-rarefaction guess (Toro 4.46), then Newton
        let z = (g - 1.0) / (2.0 * g);
        let mut p = ((cl + cr - 0.5 * (g - 1.0) * (right.u - left.u)) / (cl / left.p.powf(z) + cr / right.p.powf(z)))
            .powf(1.0 / z);
        for _ in 0..100 {
            let (fl, dl) = f_k(p, left, g);
            let (fr, dr) = f_k(p, right, g);
            let f = fl + fr + (right.u - left.u);
            let mut pn = p - f / (dl + dr);
            if pn <= 0.0 {
                pn = 1e-8 * p;
            }
            let done = (pn - p).abs() / (0.5 * (pn + p)) < 1e-14;
            p = pn;
            if done {
                let (fl, _) = f_k(p, left, g);
                let (fr, _) = f_k(p, right, g);
                let u = 0.5 * (left.u + right.u) + 0.5 * (fr - fl);
                return Some(Riemann { left, right, gamma, p_star: p, u_star: u });
            }
        }
        None
    }

    /// Density left and right of the contact.
    pub fn rho_star(&self) -> (f64, f64) {
        let g = self.gamma;
        let side = |s: Side| {
            let r = self.p_star / s.p;
            if self.p_star > s.p {
                let k = (g - 1.0) / (g + 1.0);
                s.rho * (r + k) / (k * r + 1.0)
            } else {
                s.rho * r.powf(1.0 / g)
            }
        };
        (side(self.left), side(self.right))
    }

    /// Shock speed on the right (if a right shock).
    pub fn right_shock_speed(&self) -> f64 {
        self.shock_speed(self.right, 1.0)
    }

    /// The speed of a shock into side `s` (sign −1 left, +1 right; Toro 4.52, 4.59).
    fn shock_speed(&self, s: Side, sign: f64) -> f64 {
        let g = self.gamma;
        s.u + sign * sound(s, g) * ((g + 1.0) / (2.0 * g) * self.p_star / s.p + (g - 1.0) / (2.0 * g)).sqrt()
    }

    /// The two outer waves in words: on each side a shock with its speed when p* exceeds that
    /// side's pressure (Toro 4.52, 4.59), else a rarefaction with its head and tail speeds (m/s).
    pub fn waves(&self) -> String {
        let g = self.gamma;
        let (rl, rr) = self.rho_star();
        let wave = |s: Side, rho_star: f64, sign: f64| {
            let c = sound(s, g);
            if self.p_star > s.p {
                format!("shock at {:.5}", self.shock_speed(s, sign))
            } else {
                let c_star = (g * self.p_star / rho_star).sqrt();
                format!("rarefaction, head {:.5}, tail {:.5}", s.u + sign * c, self.u_star + sign * c_star)
            }
        };
        format!("left wave {}; right wave {}", wave(self.left, rl, -1.0), wave(self.right, rr, 1.0))
    }

    /// The solution at ξ = (x − x0)/t (Toro 4.5).
    pub fn sample(&self, xi: f64) -> State {
        let g = self.gamma;
        let (ps, us) = (self.p_star, self.u_star);
        let st = |rho: f64, u: f64, p: f64| State { rho, u, p, e: p / ((g - 1.0) * rho) };
        let (rl, rr) = self.rho_star();
        if xi <= us {
            let l = self.left;
            let cl = sound(l, g);
            if ps > l.p {
                let sl = self.shock_speed(l, -1.0);
                if xi <= sl { st(l.rho, l.u, l.p) } else { st(rl, us, ps) }
            } else {
                let shl = l.u - cl;
                let cs = cl * (ps / l.p).powf((g - 1.0) / (2.0 * g));
                let stl = us - cs;
                if xi <= shl {
                    st(l.rho, l.u, l.p)
                } else if xi >= stl {
                    st(rl, us, ps)
                } else {
                    let c = 2.0 / (g + 1.0) * (cl + 0.5 * (g - 1.0) * (l.u - xi));
                    let u = 2.0 / (g + 1.0) * (cl + 0.5 * (g - 1.0) * l.u + xi);
                    let rho = l.rho * (c / cl).powf(2.0 / (g - 1.0));
                    let p = l.p * (c / cl).powf(2.0 * g / (g - 1.0));
                    st(rho, u, p)
                }
            }
        } else {
            let r = self.right;
            let cr = sound(r, g);
            if ps > r.p {
                let sr = self.right_shock_speed();
                if xi >= sr { st(r.rho, r.u, r.p) } else { st(rr, us, ps) }
            } else {
                let shr = r.u + cr;
                let cs = cr * (ps / r.p).powf((g - 1.0) / (2.0 * g));
                let str_ = us + cs;
                if xi >= shr {
                    st(r.rho, r.u, r.p)
                } else if xi <= str_ {
                    st(rr, us, ps)
                } else {
                    let c = 2.0 / (g + 1.0) * (cr - 0.5 * (g - 1.0) * (r.u - xi));
                    let u = 2.0 / (g + 1.0) * (-cr + 0.5 * (g - 1.0) * r.u + xi);
                    let rho = r.rho * (c / cr).powf(2.0 / (g - 1.0));
                    let p = r.p * (c / cr).powf(2.0 * g / (g - 1.0));
                    st(rho, u, p)
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Toro's tests 1 (Sod: a left rarefaction, a right shock at 1.75216, p* 0.30313) and 2 (the
    /// "123" problem: two rarefactions, p* 0.00189), γ = 1.4 (Toro, Riemann Solvers, Table 4.2).
    #[test]
    fn the_waves_are_named_shock_or_rarefaction() {
        let sod = Riemann::solve(Side { rho: 1.0, u: 0.0, p: 1.0 }, Side { rho: 0.125, u: 0.0, p: 0.1 }, 1.4).unwrap();
        assert!((sod.p_star - 0.30313).abs() < 1e-5, "{}", sod.p_star);
        let w = sod.waves();
        assert!(
            w.starts_with("left wave rarefaction, head -1.18322") && w.ends_with("right wave shock at 1.75216"),
            "{w}"
        );
        let r123 = Riemann::solve(Side { rho: 1.0, u: -2.0, p: 0.4 }, Side { rho: 1.0, u: 2.0, p: 0.4 }, 1.4).unwrap();
        assert!((r123.p_star - 0.00189).abs() < 1e-5, "{}", r123.p_star);
        let w = r123.waves();
        assert!(
            w.contains("left wave rarefaction, head -2.74833") && w.contains("right wave rarefaction, head 2.74833"),
            "{w}"
        );
        assert!(!w.contains("shock"), "{w}");
    }
}
