//! Monaghan's viscosity as Liu & Liu's book code computes it (`--compat`;
//! docs/compat-liu-book.md §7): items `visc_mu` (μ = h̄ v·x/(r² + ((h̄ h̄) η) η), where blastsph
//! has (η h̄)(η h̄)) and `visc_energy` (the energy rate `dedt −= (m_other dv_d) h_d` for each
//! component into both particles of the pair, in pair order, halved at the end, where blastsph
//! adds m_other ½ Π v·∇W once per pair). The acceleration has blastsph's bits. With `literals` the
//! case's α, β and φ/h (the book's `etq = 0.1e0`) are single precision
//! (`migration::compat::apply_case`). No Fortran twin in blastsph's core.

use super::{Flags, Item};
use crate::modules::grow;
use crate::modules::viscosity::{Coef, ViscosityStage};
use crate::modules::{Backend, Contribution, Counterpart, Phase, PlanCtx, Slots, Stage, by_dim, par_rows, par_rows2};
use crate::state::{Clock, Particles, Work};

/// The book's art_visc.
pub struct ViscosityCompat {
    normal: ViscosityStage,
    f: Flags,
    why: &'static str,
}

fn run_d<const D: usize, const W: usize>(p: &Particles, w: &mut Work, coef: Coef, slots: Slots, f: Flags) {
    let nt = p.ntotal;
    let (x, v, h, rho, c, mass) = (&p.x[..D * nt], &p.v[..D * nt], &p.h[..nt], &p.rho[..nt], &p.c[..nt], &p.mass[..nt]);
    let Work { pairs: pl, dwdx, acc, dde, .. } = w;
    let Coef { alpha, beta, etq } = coef;
    let (book_mu, book_e) = (f.has(Item::ViscMu), f.has(Item::ViscEnergy));
    let np = pl.len();
    // per pair: h_d = −Π ∂W/∂x_d (D), dv_d (D), ½ Π v·∇W (1); zeros for a receding pair
    let wd = 2 * D + 1;
    let mut guard = pl.scratch.lock();
    let buf = &mut *guard;
    grow(&mut buf.pair, wd * np);
    let (pi, pj) = (&pl.i, &pl.j);
    par_rows(&mut buf.pair[..wd * np], wd, |k, t| {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        let g = &dwdx[D * k..D * k + D];
        let (mut vr, mut rr, mut vd) = (0.0, 0.0, 0.0);
        let mut dv = [0.0; D];
        for d in 0..D {
            dv[d] = v[d + D * i] - v[d + D * j];
            let dx = x[d + D * i] - x[d + D * j];
            vr += dv[d] * dx;
            rr += dx * dx;
            vd += dv[d] * g[d];
        }
        t.iter_mut().for_each(|e| *e = 0.0);
        if vr < 0.0 {
            let hij = (h[i] + h[j]) / 2.0;
            let muv = if book_mu {
                hij * vr / (rr + hij * hij * etq * etq)
            } else {
                hij * vr / (rr + (etq * hij) * (etq * hij))
            };
            let mc = 0.5 * (c[i] + c[j]);
            let mrho = 0.5 * (rho[i] + rho[j]);
            let piv = (beta * muv - alpha * mc) * muv / mrho;
            for d in 0..D {
                t[d] = -(piv * g[d]);
                t[D + d] = dv[d];
            }
            t[2 * D] = 0.5 * piv * vd;
        }
    });
    let terms: &[f64] = &buf.pair;
    let (dvdt, dedt) = (&mut acc[slots.acc_range(D * nt)], &mut dde[slots.de_range(nt)]);
    par_rows2(&mut dvdt[..D * nt], D, &mut dedt[..nt], 1, |a, ac, e| {
        let mut sa = [0.0f64; D];
        let mut se = 0.0;
        for inc in pl.incident(a) {
            let t = &terms[wd * inc.pair()..wd * inc.pair() + wd];
            let m = mass[inc.other()];
            let ms = if inc.is_i() { m } else { -m };
            for d in 0..D {
                sa[d] += ms * t[d];
            }
            if book_e {
                for d in 0..D {
                    se -= m * t[D + d] * t[d];
                }
            } else {
                se += m * t[2 * D];
            }
        }
        ac.copy_from_slice(&sa);
        e[0] = if book_e { 0.5 * se } else { se };
    });
}

impl Stage for ViscosityCompat {
    super::as_its_normal_stage!();

    fn run(&self, _b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (coef, slots, f) = (self.normal.coef, self.normal.slots, self.f);
        by_dim!(p.dim, 1, run_d(p, w, coef, slots, f))
    }
    fn counterpart(&self) -> Counterpart {
        Counterpart::None(self.why)
    }
}

/// The book's viscosity, when `visc_mu` or `visc_energy` is on (and the case has a viscosity).
pub fn plan(ctx: &PlanCtx, f: Flags) -> Option<Contribution> {
    // the book is planar: an axisymmetric case keeps blastsph's twin
    if !(f.has(Item::ViscMu) || f.has(Item::ViscEnergy)) || ctx.case.axisymmetric() {
        return None;
    }
    // the book's routine gives no max|μ|: a CFL step that reads it keeps blastsph's twin; the
    // book has no viscosity switch (α_i per particle): a case with one keeps blastsph's twin too
    let v = &ctx.case.viscosity;
    if v.switch != crate::case::ViscSwitch::None {
        return None;
    }
    let coef = Coef { alpha: v.alpha, beta: v.beta, etq: v.phi_over_h };
    let stage = ViscosityStage::of_case(coef, ctx.case, false);
    if stage.signal {
        return None;
    }
    let normal = crate::modules::viscosity::plan(ctx);
    if normal.stages.is_empty() {
        return None;
    }
    let why: &'static str = Box::leak(format!("viscosity: {}", f.label()).into_boxed_str());
    let st = ViscosityCompat { normal: stage, f, why };
    Some(Contribution::run(
        format!("{} [compat {}]", normal.why, f.label()),
        vec![(Phase::Rates, Box::new(st) as Box<dyn Stage>)],
    ))
}
