//! The Rust twin of the EOS: same operations in the same order as `sph_eos.f90`.

use super::Eval;
use crate::modules::param::tab_lin;
use crate::modules::{fmax, par_rows, par_rows2};
use crate::modules::param::row::{
    CMP_C, CMP_CRHO, CMP_N, CMP_P, CMP_RHO, CMP_RMAX0, E1, ECHEM, PMIN, RHO0, UNR_C, UNR_GAMMA, UNR_S,
};
use crate::modules::param::{EosKind, NPAR};

/// p and c of one particle: material type `itype`, parameters `par` (one column of mpar),
/// burn fraction `lam`; a compaction material on its loading curve (no history: ρ_max = ρ).
#[inline]
pub fn point(itype: i32, par: &[f64], rho: f64, e: f64, lam: f64) -> (f64, f64) {
    let (p, c, _) = point_hist(itype, par, rho, e, lam, rho);
    (p, c)
}

/// p, c and the updated compaction history ρ_max (kg/m³) of one particle whose history is
/// `rmax` (only the compaction kind reads and changes it).
#[inline]
pub fn point_hist(itype: i32, par: &[f64], rho: f64, e: f64, lam: f64, rmax: f64) -> (f64, f64, f64) {
    let mut rmax = rmax;
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
    Some(EosKind::Morris) => {
        // Morris et al. (1997)'s artificial compressibility, the book's p_art_water: p = c² ρ
        cref = par[E1];
        c2 = cref * cref;
        p = c2 * rho;
    }
    Some(EosKind::Compaction) => {
        // Laine–Sandvik: the plastic compaction curve p_c at ρ_max, the elastic line of slope c_u²
        let nk = par[CMP_N] as usize;
        if rho > rmax {
            rmax = rho;
        }
        if par[CMP_RMAX0] > rmax {
            rmax = par[CMP_RMAX0];
        }
        cref = tab_lin(&par[CMP_CRHO..CMP_CRHO + nk], &par[CMP_C..CMP_C + nk], rmax, false);
        p = tab_lin(&par[CMP_RHO..CMP_RHO + nk], &par[CMP_P..CMP_P + nk], rmax, true) + cref * cref * (rho - rmax);
        c2 = cref * cref;
    }
    // no equation of state: p = 0 before the floor, c = 0
    Some(EosKind::None) => {}
    None => panic!("eos: material type {itype} is no EosKind code"),
    }
    p = fmax(p, par[PMIN]);
    let c = fmax(c2, 1.0e-4 * cref * cref).sqrt();
    (p, c, rmax)
}

/// p and c for the first `mat.len()` particles, then their compaction history.
pub(super) fn eval(a: &mut Eval) {
    let Eval { mt, mat, burn, rho_max, rho, e, p, c } = a;
    let n = mat.len();
    let hist: &[f64] = rho_max;
    let col = |i: usize| {
        let m = mat[i] as usize;
        let lam = if burn.is_empty() { 1.0 } else { burn[i] };
        let r = if hist.is_empty() { rho[i] } else { hist[i] };
        point_hist(mt.mtype[m], &mt.mpar[NPAR * m..NPAR * (m + 1)], rho[i], e[i], lam, r)
    };
    par_rows2(&mut p[..n], 1, &mut c[..n], 1, |i, pi, ci| {
        let (pp, cc, _) = col(i);
        pi[0] = pp;
        ci[0] = cc;
    });
    if !rho_max.is_empty() {
        let mut next = vec![0.0; n];
        par_rows(&mut next, 1, |i, r| r[0] = col(i).2);
        rho_max[..n].copy_from_slice(&next);
    }
}
