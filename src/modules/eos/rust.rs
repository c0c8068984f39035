//! The Rust twin of the EOS: same operations in the same order as `sph_eos.f90`.

use super::Eval;
use crate::modules::{fmax, par_rows2};
use crate::modules::param::row::{E1, ECHEM, PMIN, RHO0, UNR_C, UNR_GAMMA, UNR_S};
use crate::modules::param::{EosKind, NPAR};

/// p and c of one particle: material type `itype`, parameters `par` (one column of mpar),
/// burn fraction `lam`.
#[inline]
pub fn point(itype: i32, par: &[f64], rho: f64, e: f64, lam: f64) -> (f64, f64) {
    let rho0 = par[RHO0];
    let mut p = 0.0;
    let mut c2 = 0.0;
    let mut cref = 0.0;
    match EosKind::of_code(itype) {
    Some(EosKind::IdealGas) => {
        let g = par[E1];
        p = (g - 1.0) * rho * e;
        c2 = g * (g - 1.0) * e;
    }
    Some(EosKind::Jwl) => {
        let (a, b, r1, r2, om) = (par[E1], par[E1 + 1], par[E1 + 2], par[E1 + 3], par[E1 + 4]);
        let eta = rho / rho0;
        let x1 = (-r1 / eta).exp();
        let x2 = (-r2 / eta).exp();
        p = a * (1.0 - om * eta / r1) * x1 + b * (1.0 - om * eta / r2) * x2 + om * eta * rho0 * e;
        let dpdr = (a * x1 * (-om / r1 + (1.0 - om * eta / r1) * r1 / (eta * eta))
            + b * x2 * (-om / r2 + (1.0 - om * eta / r2) * r2 / (eta * eta))
            + om * rho0 * e)
            / rho0;
        let dpde = om * rho;
        c2 = dpdr + p / (rho * rho) * dpde;
        cref = par[E1 + 5];
        if par[UNR_C] > 0.0 {
            // the unreacted explosive: Mie–Grüneisen, linear Us–Up, energy above e_chem
            let s = par[UNR_S];
            let gam = par[UNR_GAMMA];
            let a0 = rho0 * par[UNR_C] * par[UNR_C];
            let b0 = a0 * (1.0 + 2.0 * (s - 1.0));
            let c0 = a0 * (2.0 * (s - 1.0) + 3.0 * (s - 1.0) * (s - 1.0));
            let mu = eta - 1.0;
            let (ph, dph) = if mu > 0.0 {
                (a0 * mu + b0 * mu * mu + c0 * mu * mu * mu, a0 + 2.0 * b0 * mu + 3.0 * c0 * mu * mu)
            } else {
                (a0 * mu, a0)
            };
            let eu = e - par[ECHEM];
            let pu = (1.0 - 0.5 * gam * mu) * ph + gam * rho * eu;
            let c2u =
                ((1.0 - 0.5 * gam * mu) * dph - 0.5 * gam * ph) / rho0 + gam * eu + pu / (rho * rho) * (gam * rho);
            p = lam * p + (1.0 - lam) * pu;
            c2 = lam * c2 + (1.0 - lam) * c2u;
        } else {
            p *= lam;
        }
    }
    Some(EosKind::Water) => {
        let mu = rho / rho0 - 1.0;
        let (wa1, wa2, wa3, wb0, wb1) = (par[E1], par[E1 + 1], par[E1 + 2], par[E1 + 3], par[E1 + 4]);
        let dpdr;
        if mu > 0.0 {
            p = wa1 * mu + wa2 * mu * mu + wa3 * mu * mu * mu + (wb0 + wb1 * mu) * rho0 * e;
            dpdr = (wa1 + 2.0 * wa2 * mu + 3.0 * wa3 * mu * mu + wb1 * rho0 * e) / rho0;
        } else {
            p = wa1 * mu + (wb0 + wb1 * mu) * rho0 * e;
            dpdr = (wa1 + wb1 * rho0 * e) / rho0;
        }
        let dpde = (wb0 + wb1 * mu) * rho0;
        c2 = dpdr + p / (rho * rho) * dpde;
        cref = par[E1 + 5];
    }
    Some(EosKind::Soil) => {
        cref = par[E1];
        let s = par[E1 + 1];
        let gam = par[E1 + 2];
        let a0 = rho0 * cref * cref;
        let b0 = a0 * (1.0 + 2.0 * (s - 1.0));
        let c0 = a0 * (2.0 * (s - 1.0) + 3.0 * (s - 1.0) * (s - 1.0));
        let mu = rho / rho0 - 1.0;
        let (ph, dph) = if mu > 0.0 {
            (a0 * mu + b0 * mu * mu + c0 * mu * mu * mu, a0 + 2.0 * b0 * mu + 3.0 * c0 * mu * mu)
        } else {
            (a0 * mu, a0)
        };
        p = (1.0 - 0.5 * gam * mu) * ph + gam * rho * e;
        let dpdr = ((1.0 - 0.5 * gam * mu) * dph - 0.5 * gam * ph) / rho0 + gam * e;
        let dpde = gam * rho;
        c2 = dpdr + p / (rho * rho) * dpde;
    }
    Some(EosKind::Tait) => {
        let b = par[E1];
        let gam = par[E1 + 1];
        cref = par[E1 + 2];
        p = b * ((rho / rho0).powf(gam) - 1.0);
        c2 = cref * cref;
    }
    // no equation of state: p = 0 before the floor, c = 0
    Some(EosKind::None) => {}
    None => panic!("eos: material type {itype} is no EosKind code"),
    }
    p = fmax(p, par[PMIN]);
    let c = fmax(c2, 1.0e-4 * cref * cref).sqrt();
    (p, c)
}

/// p and c for the first `mat.len()` particles.
pub(super) fn eval(a: &mut Eval) {
    let Eval { mt, mat, burn, rho, e, p, c } = a;
    let n = mat.len();
    par_rows2(&mut p[..n], 1, &mut c[..n], 1, |i, pi, ci| {
        let m = mat[i] as usize;
        let lam = if burn.is_empty() { 1.0 } else { burn[i] };
        let (pp, cc) = point(mt.mtype[m], &mt.mpar[NPAR * m..NPAR * (m + 1)], rho[i], e[i], lam);
        pi[0] = pp;
        ci[0] = cc;
    });
}
