//! The internal force as Liu & Liu's book code computes it (`--compat`;
//! docs/compat-liu-book.md §6), item `force_energy`: the acceleration has blastsph's bits
//! (`h = −(p_i/ρ_i² + p_j/ρ_j²) ∂W/∂x_d`, `+ m_j h` at i, `− m_i h` at j), the energy rate is the
//! book's: per pair `he = Σ_d (v_j − v_i)_d h_d` (from 0), `dedt_i += m_j he`, `dedt_j += m_i he`
//! in pair order, then `dedt = tdsdt + 0.5 dedt` with the book's tdsdt = 0 for an inviscid gas.
//! Item `pa_sph1` is the book's other form (param.inc's `pa_sph = 1`): per pair and component
//! `h = -(p_i + p_j) ∂W/∂x_d`, `he += (v_j − v_i)_d h`, then `h·(1/(ρ_iρ_j))` scattered as
//! above, and `he·(1/(ρ_iρ_j))` into both energies, halved at the end (m/s², J/kg/s).
//! With a material's `dynamic_viscosity_pa_s` > 0 (the book's `visc`), the book's viscous terms join
//! the pair term after `he` took it: `h += (η_i ε_i^{dβ}/ρ_i² + η_j ε_j^{dβ}/ρ_j²) ∂W/∂x_β`, β
//! ascending (`pa_sph = 1`: η ε undivided, before the scaling), ε the strain rate of
//! `force.newtonian` with the 2/3 rounded to single precision under `literals`; the energy is then
//! `dedt = tdsdt + 0.5 dedt`, tdsdt = ((½η)/ρ) ε:ε.
//! Fluids only (the book has no stress): with strength the module keeps blastsph's twin. No
//! Fortran twin in blastsph's core.

use super::{Flags, Item};
use crate::modules::force::ForceStage;
use crate::modules::force::newtonian::{IV, Strain};
use crate::modules::grow;
use crate::modules::param::NSTR;
use crate::modules::{
    Backend, Contribution, Counterpart, Phase, PlanCtx, Slots, Stage, by_dim, gather_signed, par_rows,
};
use crate::state::{Clock, Particles, Work};

/// The book's int_force (pa_sph = 2, or 1 with `pa_sph1`; inviscid), after its EOS.
pub struct ForceCompat {
    normal: ForceStage,
    pa1: bool,
    why: &'static str,
    /// The book's `visc`: η per material (Pa s) and the 2/3 of the strain rate.
    visc: Option<(Vec<f64>, f64)>,
}

/// The book's viscous shear of `int_force`, when `visc` is on: per particle the quotients q
/// (NSTR values) and tdsdt; none and zeros when it is off.
fn shear<const D: usize>(
    p: &Particles,
    pl: &crate::modules::nnps::PairList,
    dwdx: &[f64],
    hsb: &mut Vec<f64>,
    visc: Option<(&[f64], f64)>,
    pa1: bool,
) -> (Vec<f64>, Vec<f64>) {
    let nt = p.ntotal;
    let mut tds = vec![0.0; nt];
    let Some((eta_mat, c23)) = visc else { return (Vec::new(), tds) };
    let eta: Vec<f64> = p.mat[..nt].iter().map(|&m| eta_mat[m as usize]).collect();
    let mut q = vec![0.0; NSTR * nt];
    let (mass, rho, v) = (&p.mass[..nt], &p.rho[..nt], &p.v[..D * nt]);
    Strain { pl, dwdx, mass, rho, v, eta: &eta, c23, per_rho2: !pa1 }.rates::<D>(hsb, &mut q, &mut tds);
    (q, tds)
}

/// `h` plus the book's viscous terms of component `d` (β ascending), when `q` is not empty.
#[inline]
fn with_visc<const D: usize>(h: f64, d: usize, q: &[f64], i: usize, j: usize, g: &[f64]) -> f64 {
    let mut h = h;
    if !q.is_empty() {
        for b in 0..D {
            let c = IV[d][b];
            h += (q[NSTR * i + c] + q[NSTR * j + c]) * g[b];
        }
    }
    h
}

/// `pa_sph = 1`: the pair terms -(p_i + p_j) ∂W/∂x_d and their energy, scaled by 1/(ρ_i ρ_j).
fn run_pa1_d<const D: usize, const W: usize>(p: &Particles, w: &mut Work, slots: Slots, visc: Option<(&[f64], f64)>) {
    let nt = p.ntotal;
    let (mass, rho, pr, v) = (&p.mass[..nt], &p.rho[..nt], &p.p[..nt], &p.v[..D * nt]);
    let Work { pairs: pl, dwdx, acc, dde, .. } = w;
    let np = pl.len();
    let mut guard = pl.scratch.lock();
    let buf = &mut *guard;
    let (q, tds) = shear::<D>(p, pl, dwdx, &mut buf.pair, visc, true);
    grow(&mut buf.pair, W * np);
    let (pi, pj) = (&pl.i, &pl.j);
    par_rows(&mut buf.pair[..W * np], W, |k, t| {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        let g = &dwdx[D * k..D * k + D];
        // rhoij = 1.e0/(rho(i)*rho(j))
        let rhoij = 1.0 / (rho[i] * rho[j]);
        let mut he = 0.0;
        for d in 0..D {
            // h = -(p(i) + p(j))*dwdx(d,k); he = he + (vx(d,j) - vx(d,i))*h; h = h*rhoij
            let h = -(pr[i] + pr[j]) * g[d];
            he += (v[d + D * j] - v[d + D * i]) * h;
            t[d] = with_visc::<D>(h, d, &q, i, j, g) * rhoij;
        }
        t[D] = he * rhoij;
    });
    let (dvdt, dedt) = (&mut acc[slots.acc_range(D * nt)], &mut dde[slots.de_range(nt)]);
    gather_signed::<D, W>(pl, &buf.pair, mass, None, dvdt, dedt);
    // dedt(i) = tdsdt(i) + 0.5e0*dedt(i)
    par_rows(&mut dedt[..nt], 1, |i, e| e[0] = tds[i] + 0.5 * e[0]);
}

fn run_d<const D: usize, const W: usize>(p: &Particles, w: &mut Work, slots: Slots, visc: Option<(&[f64], f64)>) {
    let nt = p.ntotal;
    let (mass, rho, pr, v) = (&p.mass[..nt], &p.rho[..nt], &p.p[..nt], &p.v[..D * nt]);
    let Work { pairs: pl, dwdx, acc, dde, .. } = w;
    let np = pl.len();
    let mut guard = pl.scratch.lock();
    let buf = &mut *guard;
    let (q, tds) = shear::<D>(p, pl, dwdx, &mut buf.pair, visc, false);
    grow(&mut buf.part, nt);
    // p(i)/rho(i)**2 per particle: the same operations as per pair
    par_rows(&mut buf.part[..nt], 1, |i, s| s[0] = pr[i] / (rho[i] * rho[i]));
    grow(&mut buf.pair, W * np);
    let sig: &[f64] = &buf.part;
    let (pi, pj) = (&pl.i, &pl.j);
    par_rows(&mut buf.pair[..W * np], W, |k, t| {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        let g = &dwdx[D * k..D * k + D];
        let s = sig[i] + sig[j];
        let mut he = 0.0;
        for d in 0..D {
            let h = -(s * g[d]);
            he += (v[d + D * j] - v[d + D * i]) * h;
            t[d] = with_visc::<D>(h, d, &q, i, j, g);
        }
        t[D] = he;
    });
    let (dvdt, dedt) = (&mut acc[slots.acc_range(D * nt)], &mut dde[slots.de_range(nt)]);
    gather_signed::<D, W>(pl, &buf.pair, mass, None, dvdt, dedt);
    // dedt(i) = tdsdt(i) + 0.5e0*dedt(i)
    par_rows(&mut dedt[..nt], 1, |i, e| e[0] = tds[i] + 0.5 * e[0]);
}

impl Stage for ForceCompat {
    super::as_its_normal_stage!();

    fn run(&self, _b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let slots = self.normal.slots;
        let visc = self.visc.as_ref().map(|(e, c)| (e.as_slice(), *c));
        if self.pa1 {
            by_dim!(p.dim, 1, run_pa1_d(p, w, slots, visc))
        } else {
            by_dim!(p.dim, 1, run_d(p, w, slots, visc))
        }
    }
    fn counterpart(&self) -> Counterpart {
        Counterpart::None(self.why)
    }
}

/// The book's energy rate, when `force_energy` is on, or its pa_sph = 1 form (`pa_sph1`), and the
/// case has no strength.
pub fn plan(ctx: &PlanCtx, f: Flags) -> Option<Contribution> {
    let pa1 = f.has(Item::PaSph1);
    // the book is planar: an axisymmetric case keeps blastsph's twin
    if !(f.has(Item::ForceEnergy) || pa1) || crate::setup::has_strength(ctx.case) || ctx.case.axisymmetric() {
        return None;
    }
    let why: &'static str = Box::leak(format!("force: {}", f.label()).into_boxed_str());
    let eta: Vec<f64> = ctx.case.materials.iter().map(|m| m.dynamic_viscosity_pa_s.unwrap_or(0.0)).collect();
    // int_force's 2.e0/3.e0, a default-real constant
    let c23 = if f.has(Item::Literals) { f64::from(2.0f32 / 3.0f32) } else { 2.0 / 3.0 };
    let vtext = if eta.iter().any(|&e| e > 0.0) {
        format!(", physical viscosity (eta = {eta:?} Pa s, 2/3 = {c23})")
    } else {
        String::new()
    };
    let visc = eta.iter().any(|&e| e > 0.0).then_some((eta, c23));
    let normal = ForceStage { slots: Slots::default(), rz: false, asym: false, iface: false };
    let stage = ForceCompat { normal, pa1, why, visc };
    Some(Contribution::run(
        format!("pressure only{}{vtext} [compat {}]", if pa1 { ", pa_sph = 1" } else { "" }, f.label()),
        vec![(Phase::Rates, Box::new(stage) as Box<dyn Stage>)],
    ))
}
