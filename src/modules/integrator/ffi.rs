//! The Fortran twin of the leapfrog (`sph_integrator_sum_rates`, `_predict`, `_advance`, `_cfl`,
//! `_efloor`, `_clamp`).
#![allow(unsafe_code)]

use super::{Advance, Cfl, Clamp, Efloor, Leapfrog, Predict, Rates, SumRates};
use crate::modules::ffi_util::{chk, chk_opt, mptr_or, n32, ptr_or};
use crate::modules::param::NSTR;

#[allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/ffi_integrator.rs"));
}

pub(super) fn sum_rates(a: &mut SumRates) {
    let (dim, n, lda, nterm) = (a.dim, a.n, a.lda, a.nterm);
    chk("acc", a.acc.len(), lda * nterm);
    chk("grav", a.grav.len(), dim);
    chk("out", a.out.len(), dim * n);
    assert!(lda >= dim * n, "legacy call: lda too small");
    let nbnd = chk_opt("bnd", a.bnd.len(), n, 1);
    let dummy = 0.0;
    // SAFETY: acc holds nterm × lda values (a one-value dummy when nterm = 0: the routine then
    // reads none), grav dim, out dim × n, bnd n or a one-value dummy (checked above).
    unsafe {
        sys::sph_integrator_sum_rates(
            n32(dim),
            n32(n),
            n32(lda),
            n32(nterm),
            ptr_or(a.acc, &dummy),
            a.grav.as_ptr(),
            a.out.as_mut_ptr(),
            n32(nbnd),
            ptr_or(a.bnd, &0),
        )
    }
}

/// Checks the leapfrog arrays of `n` particles; returns the number with a stress (0 or n).
fn check_leapfrog(dim: usize, n: usize, s: &Leapfrog, r: &Rates) -> usize {
    for (name, l) in [
        ("rho", s.rho.len()),
        ("e", s.e.len()),
        ("rho_min", s.rho_min.len()),
        ("e_min", s.e_min.len()),
        ("drho", r.drho.len()),
        ("de", r.de.len()),
    ] {
        chk(name, l, n);
    }
    chk("v", s.v.len(), dim * n);
    chk("v_min", s.v_min.len(), dim * n);
    chk("dv", r.dv.len(), dim * n);
    let ntau = chk_opt("tau", s.tau.len(), n, NSTR);
    chk("tau_min", s.tau_min.len(), NSTR * ntau);
    chk("dtau", r.dtau.len(), NSTR * ntau);
    ntau
}

pub(super) fn predict(a: &mut Predict) {
    let (dim, n) = (a.dim, a.n);
    let ntau = check_leapfrog(dim, n, &a.lf, &a.rates);
    let nbnd = chk_opt("bnd", a.bnd.len(), n, 1);
    let (s, r) = (&mut a.lf, &a.rates);
    let (mut d1, mut d2, d3) = (0.0, 0.0, 0.0);
    // SAFETY: every array holds the n (dim × n, NSTR × n) values the explicit shapes declare
    // (checked above); the stress arrays are one-value dummies when ntau = 0, bnd when nbnd = 0.
    unsafe {
        sys::sph_integrator_predict(
            n32(dim),
            n32(n),
            n32(ntau),
            a.dt_prev,
            i32::from(a.cont),
            s.rho.as_mut_ptr(),
            r.drho.as_ptr(),
            s.e.as_mut_ptr(),
            r.de.as_ptr(),
            s.v.as_mut_ptr(),
            r.dv.as_ptr(),
            mptr_or(s.tau, &mut d1),
            ptr_or(r.dtau, &d3),
            s.rho_min.as_mut_ptr(),
            s.e_min.as_mut_ptr(),
            s.v_min.as_mut_ptr(),
            mptr_or(s.tau_min, &mut d2),
            n32(nbnd),
            ptr_or(a.bnd, &0),
        )
    }
}

pub(super) fn advance(a: &mut Advance) {
    let (dim, n) = (a.dim, a.n);
    let ntau = check_leapfrog(dim, n, &a.lf, &a.rates);
    chk("x", a.x.len(), dim * n);
    let nav = chk_opt("av", a.av.len(), n, dim);
    let nbnd = chk_opt("bnd", a.bnd.len(), n, 1);
    let (s, r) = (&mut a.lf, &a.rates);
    let (mut d1, d2, d3, d4) = (0.0, 0.0, 0.0, 0.0);
    // SAFETY: every array holds the values the explicit shapes declare (checked above); the
    // stress arrays, av and bnd are one-value dummies when ntau, nav or nbnd is 0.
    unsafe {
        sys::sph_integrator_advance(
            n32(dim),
            n32(n),
            n32(ntau),
            i32::from(a.first),
            a.dt_prev,
            a.dt,
            i32::from(a.cont),
            s.rho.as_mut_ptr(),
            r.drho.as_ptr(),
            s.e.as_mut_ptr(),
            r.de.as_ptr(),
            s.v.as_mut_ptr(),
            r.dv.as_ptr(),
            mptr_or(s.tau, &mut d1),
            ptr_or(r.dtau, &d2),
            s.rho_min.as_ptr(),
            s.e_min.as_ptr(),
            s.v_min.as_ptr(),
            ptr_or(s.tau_min, &d3),
            n32(nav),
            ptr_or(a.av, &d4),
            a.x.as_mut_ptr(),
            n32(nbnd),
            ptr_or(a.bnd, &0),
        )
    }
}

pub(super) fn cfl(a: &mut Cfl) {
    let (dim, n) = (a.dim, a.h.len());
    chk("c", a.c.len(), n);
    chk("v", a.v.len(), dim * n);
    chk("dv", a.dv.len(), dim * n);
    let nmu = chk_opt("mumax", a.mumax.len(), n, 1);
    let neta = a.eta.len();
    if neta > 0 {
        chk("mat", a.mat.len(), n);
        chk("rho", a.rho.len(), n);
        assert!(a.mat[..n].iter().all(|&m| (m as usize) < neta), "legacy call: mat out of eta's range");
    }
    let (dummy, idummy) = (0.0, 0i32);
    // SAFETY: h and c hold n values, v and dv dim × n, mumax n or none (a one-value dummy for the
    // extent max(nmu, 1)); eta neta values, mat and rho n each where neta > 0, else one-value
    // dummies that the routine does not read (checked above); dt is one value.
    unsafe {
        sys::sph_integrator_cfl(
            n32(dim),
            n32(n),
            a.cfl,
            a.h.as_ptr(),
            a.c.as_ptr(),
            a.v.as_ptr(),
            a.dv.as_ptr(),
            n32(nmu),
            a.kv,
            ptr_or(a.mumax, &dummy),
            n32(neta),
            ptr_or(a.eta, &dummy),
            if neta > 0 { a.mat.as_ptr() } else { &idummy },
            if neta > 0 { a.rho.as_ptr() } else { &dummy },
            a.dt,
        )
    }
}

pub(super) fn efloor(a: &mut Efloor) {
    let n = a.e.len();
    chk("mass", a.mass.len(), n);
    // SAFETY: mass and e hold the n values the routine reads and updates (checked above); added is
    // one value.
    unsafe { sys::sph_integrator_efloor(n32(n), a.mass.as_ptr(), a.e.as_mut_ptr(), a.added) }
}

pub(super) fn clamp(a: &mut Clamp) {
    let n = a.rho.len();
    // SAFETY: rho holds the n values the routine updates; lo and hi are passed by value.
    unsafe { sys::sph_integrator_clamp(n32(n), a.lo, a.hi, a.rho.as_mut_ptr()) }
}
