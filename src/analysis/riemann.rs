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
        let g = self.gamma;
        let cr = sound(self.right, g);
        self.right.u + cr * ((g + 1.0) / (2.0 * g) * self.p_star / self.right.p + (g - 1.0) / (2.0 * g)).sqrt()
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
                let sl = l.u - cl * ((g + 1.0) / (2.0 * g) * ps / l.p + (g - 1.0) / (2.0 * g)).sqrt();
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
