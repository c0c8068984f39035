//! The kernel as Liu & Liu's book code computes it (`--compat`; docs/compat-liu-book.md §3):
//! items `kernel` (the book's expressions, their association, the `q ≤ 1`, `q ≤ 2` (`q ≤ 3`)
//! branches), `quintic_gradient` (the book's gradient below q = 1), `literals` (2./3. and π in
//! single precision), `real_power` (the cubic's q³ as libm's pow of q and 3) and `global_h` (link_list's one h: the first particle's). No Fortran twin in
//! blastsph's core: the dual run compares it with the user's legacy `kernel` (`dual --legacy`).

use super::{Flags, Item, single};
use crate::case::KernelKind;
use crate::modules::kernel::{PairsStage, w_dw};
use crate::modules::{Backend, Contribution, Counterpart, Module, Phase, PlanCtx, Stage, par_rows, par_rows2};
use crate::state::{Clock, Field, Particles, Work};
use std::f64::consts::PI;

/// x⁴ and x⁵ as gfortran expands `x**4`, `x**5` at -O2 (docs/compat-liu-book.md §1).
fn pow4(x: f64) -> f64 {
    let x2 = x * x;
    x2 * x2
}
fn pow5(x: f64) -> f64 {
    let x2 = x * x;
    (x2 * x) * x2
}

/// W and ∇W of the book's `kernel(r, dx, hsml, w, dwdx)`: `dx` the separation (dim values), `r`
/// its length, `h` the kernel's h. Without the `kernel` item, blastsph's kernel (`w_dw`).
pub fn book(dim: usize, kind: KernelKind, r: f64, dx: &[f64], h: f64, f: Flags, dwdx: &mut [f64]) -> f64 {
    if !f.has(Item::Kernel) || kind == KernelKind::Wendland {
        return w_dw(dim, kind, r, dx, h, dwdx);
    }
    let lit = f.has(Item::KernelLiterals);
    let pi = if lit { single(PI) } else { PI };
    let q = r / h;
    let mut w = 0.0;
    dwdx[..dim].iter_mut().for_each(|g| *g = 0.0);
    match kind {
        KernelKind::Cubic => {
            let factor = match dim {
                1 => 1.0 / h,
                2 => 15.0 / (7.0 * pi * h * h),
                _ => 3.0 / (2.0 * pi * h * h * h),
            };
            if (0.0..=1.0).contains(&q) {
                let c = if lit { (2.0f32 / 3.0f32) as f64 } else { 2.0 / 3.0 };
                // `q**3` is multiplied out by gfortran; `q**3._rk` calls libm's pow (item real_power)
                let q3 = if f.has(Item::RealPower) { q.powf(3.0) } else { q * q * q };
                w = factor * ((c - q * q) + q3 / 2.0);
                for d in 0..dim {
                    dwdx[d] = ((factor * (-2.0 + 1.5 * q)) / (h * h)) * dx[d];
                }
            } else if q > 1.0 && q <= 2.0 {
                let a = 2.0 - q;
                w = (factor / 6.0) * (a * a * a);
                for d in 0..dim {
                    dwdx[d] = -((((factor / 6.0) * 3.0) * (a * a)) / h * (dx[d] / r));
                }
            }
        }
        KernelKind::Gauss => {
            // hsml**dim * pi**(dim/2.): the power of pi is a constant gfortran folds, correctly
            // rounded (libm's pow gives the same value for these two arguments)
            let (hd, pd) = match dim {
                1 => (h, pi.sqrt()),
                2 => (h * h, pi),
                _ => (h * h * h, pi.powf(1.5)),
            };
            let factor = 1.0 / (hd * pd);
            if (0.0..=3.0).contains(&q) {
                w = factor * (-(q * q)).exp();
                for d in 0..dim {
                    dwdx[d] = w * (((-2.0 * dx[d]) / h) / h);
                }
            }
        }
        KernelKind::Quintic => {
            let factor = match dim {
                1 => 1.0 / (120.0 * h),
                2 => 7.0 / (478.0 * pi * h * h),
                _ => 1.0 / (120.0 * pi * h * h * h),
            };
            let (a, b) = (3.0 - q, 2.0 - q);
            if (0.0..=1.0).contains(&q) {
                let c = 1.0 - q;
                w = factor * ((pow5(a) - 6.0 * pow5(b)) + 15.0 * pow5(c));
                let bracket = if f.has(Item::QuinticGradient) {
                    (-120.0 + 120.0 * q) - 50.0 * (q * q)
                } else {
                    (-120.0 + 120.0 * (q * q)) - 50.0 * ((q * q) * q)
                };
                for d in 0..dim {
                    dwdx[d] = factor * ((bracket / (h * h)) * dx[d]);
                }
            } else if q > 1.0 && q <= 2.0 {
                w = factor * (pow5(a) - 6.0 * pow5(b));
                for d in 0..dim {
                    dwdx[d] = ((factor * (-(5.0 * pow4(a)) + 30.0 * pow4(b))) / h) * (dx[d] / r);
                }
            } else if q > 2.0 && q <= 3.0 {
                w = factor * pow5(a);
                for d in 0..dim {
                    dwdx[d] = ((factor * -(5.0 * pow4(a))) / h) * (dx[d] / r);
                }
            }
        }
        KernelKind::Wendland => unreachable!("handled above"),
    }
    w
}

/// The book's W_ij and ∇_i W_ij of every pair: `dx = x_i − x_j`, r = sqrt(dx₁² + …) summed from
/// the first component, h = (h_i + h_j)/2 (with `global_h`, the first particle's h), as the book's
/// searches hand them to its kernel.
pub struct PairsCompat {
    /// blastsph's stage: what it reads, writes and sizes is the same.
    normal: PairsStage,
    kind: KernelKind,
    f: Flags,
    why: &'static str,
}

impl Stage for PairsCompat {
    super::as_its_normal_stage!();

    fn run(&self, _b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, nt, kind, f) = (p.dim, p.ntotal, self.kind, self.f);
        let (x, h) = (&p.x[..dim * nt], &p.h[..nt]);
        let global = f.has(Item::GlobalH);
        let (pi, pj) = (&w.pairs.i, &w.pairs.j);
        let np = pi.len();
        par_rows2(&mut w.w[..np], 1, &mut w.dwdx[..dim * np], dim, |k, wk, g| {
            let (i, j) = (pi[k] as usize, pj[k] as usize);
            let mut dx = [0.0; 3];
            for d in 0..dim {
                dx[d] = x[d + dim * i] - x[d + dim * j];
            }
            let mut r2 = dx[0] * dx[0];
            for e in &dx[1..dim] {
                r2 += e * e;
            }
            let hk = if global { h[0] } else { (h[i] + h[j]) / 2.0 };
            wk[0] = book(dim, kind, r2.sqrt(), &dx[..dim], hk, f, g);
        });
    }
    fn counterpart(&self) -> Counterpart {
        Counterpart::None(self.why)
    }
}

/// W(0, h_i): the book's `sum_density` calls its kernel at r = 0 with the particle's own h.
pub struct SelfCompat {
    kind: KernelKind,
    f: Flags,
    why: &'static str,
}

impl Stage for SelfCompat {
    fn module(&self) -> Module {
        Module::Kernel
    }
    fn name(&self) -> &'static str {
        "kernel.self"
    }
    fn reads(&self) -> &[Field] {
        &[Field::H]
    }
    fn writes(&self) -> &[Field] {
        &[Field::W0]
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        w.w0.resize(p.ntotal, 0.0);
    }
    fn run(&self, _b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, kind, f, h) = (p.dim, self.kind, self.f, &p.h[..p.ntotal]);
        par_rows(&mut w.w0[..h.len()], 1, |i, w0| {
            let mut g = [0.0; 3];
            w0[0] = book(dim, kind, 0.0, &[0.0; 3][..dim], h[i], f, &mut g[..dim]);
        });
    }
    fn counterpart(&self) -> Counterpart {
        Counterpart::None(self.why)
    }
}

/// The kernel's stages with the book's kernel, when an item of the kernel is on.
pub fn plan(ctx: &PlanCtx, f: Flags) -> Option<Contribution> {
    let touched = [Item::Kernel, Item::QuinticGradient, Item::GlobalH].iter().any(|&i| f.has(i));
    if !touched {
        return None;
    }
    let normal = crate::modules::kernel::plan(ctx);
    let kind = ctx.case.sph.kernel;
    let why: &'static str = Box::leak(format!("kernel: {}", f.label()).into_boxed_str());
    let stages = normal
        .stages
        .into_iter()
        .map(|(ph, s)| -> (Phase, Box<dyn Stage>) {
            if s.name() == "kernel.self" {
                (ph, Box::new(SelfCompat { kind, f, why }))
            } else {
                (ph, Box::new(PairsCompat { normal: PairsStage { kind, gscale: 1.0 }, kind, f, why }))
            }
        })
        .collect();
    Some(Contribution::run(format!("{} [compat {}]", normal.why, f.label()), stages))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_books_cubic_differs_where_the_doc_says() {
        let book = Flags::profile("liu-book").unwrap();
        let mut g = [0.0];
        // the inner branch: 2/3 in single precision
        let h = 0.015;
        let r = 0.4 * h;
        let w = super::book(1, KernelKind::Cubic, r, &[r], h, book, &mut g);
        let q = r / h;
        let want = (1.0 / h) * ((0.6666666865348816 - q * q) + q * q * q / 2.0);
        assert_eq!(w.to_bits(), want.to_bits());
        // q = 1 exactly is the inner branch in the book, the outer in blastsph: same value here
        let w1 = super::book(1, KernelKind::Cubic, h, &[h], h, book, &mut g);
        assert!((w1 - (1.0 / h) / 6.0).abs() < 1e-6 / h);
        // without the item: blastsph's kernel
        let mut g2 = [0.0];
        let wb = super::book(1, KernelKind::Cubic, r, &[r], h, Flags::default(), &mut g2);
        assert_eq!(wb, w_dw(1, KernelKind::Cubic, r, &[r], h, &mut [0.0]));
        assert_ne!(wb.to_bits(), w.to_bits());
        // the quintic gradient defect: the two brackets differ below q = 1
        let mut ga = [0.0];
        let mut gb = [0.0];
        super::book(1, KernelKind::Quintic, r, &[r], h, book, &mut ga);
        super::book(1, KernelKind::Quintic, r, &[r], h, book.with(Item::QuinticGradient, false), &mut gb);
        assert!((ga[0] - gb[0]).abs() > 1e-3 * gb[0].abs());
    }
}
