//! The Fortran twin of the viscosity (`sph_viscosity_monaghan`).
#![allow(unsafe_code)]

use super::{Monaghan, Switch};
use crate::modules::ffi_util::{chk, chk_opt, chk_pairs, n32, ptr_or};

#[allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/ffi_viscosity.rs"));
}

pub(super) fn monaghan(a: &mut Monaghan) {
    let (dim, pl) = (a.dim, a.pairs);
    let nt = a.mass.len();
    chk("x", a.x.len(), dim * nt);
    chk("v", a.v.len(), dim * nt);
    chk("dvdt", a.dvdt.len(), dim * nt);
    chk("dedt", a.dedt.len(), nt);
    chk("mumax", a.mumax.len(), nt);
    chk("dwdx", a.dwdx.len(), dim * pl.len());
    for (name, l) in [("h", a.h.len()), ("rho", a.rho.len()), ("c", a.c.len())] {
        chk(name, l, nt);
    }
    chk_pairs(&pl.i, &pl.j, nt);
    let nrinv = chk_opt("rinv", a.rinv.len(), nt, 1);
    let nalpha = chk_opt("alpv", a.alpv.len(), nt, 1);
    let dummy = 0.0;
    // SAFETY: the arrays hold the values the explicit shapes declare (dim × ntotal, ntotal,
    // dim × npair), every pair index is in 0..ntotal (checked above), and rinv and alpv are
    // one-value dummies when nrinv = 0 and nalpha = 0 (extents max(n, 1)).
    unsafe {
        sys::sph_viscosity_monaghan(
            n32(dim),
            n32(nt),
            n32(pl.len()),
            pl.i.as_ptr(),
            pl.j.as_ptr(),
            a.dwdx.as_ptr(),
            a.x.as_ptr(),
            a.v.as_ptr(),
            a.h.as_ptr(),
            a.rho.as_ptr(),
            a.c.as_ptr(),
            a.mass.as_ptr(),
            a.coef.alpha,
            a.coef.beta,
            a.coef.etq,
            n32(nalpha),
            ptr_or(a.alpv, &dummy),
            a.amax,
            n32(nrinv),
            ptr_or(a.rinv, &dummy),
            a.dvdt.as_mut_ptr(),
            a.dedt.as_mut_ptr(),
            a.mumax.as_mut_ptr(),
        )
    }
}

pub(super) fn switch(a: &mut Switch) {
    let (dim, pl) = (a.dim, a.pairs);
    let nt = a.mass.len();
    assert!(a.n <= nt, "legacy call: n exceeds ntotal");
    chk("v", a.v.len(), dim * nt);
    chk("dwdx", a.dwdx.len(), dim * pl.len());
    for (name, l) in
        [("rho", a.rho.len()), ("h", a.h.len()), ("c", a.c.len()), ("alpv", a.alpv.len()), ("dv", a.dv.len())]
    {
        chk(name, l, nt);
    }
    chk_pairs(&pl.i, &pl.j, nt);
    // SAFETY: the arrays hold the values the explicit shapes declare (dim × ntotal, ntotal,
    // dim × npair), every pair index is in 0..ntotal and n ≤ ntotal (checked above).
    unsafe {
        sys::sph_viscosity_switch(
            n32(dim),
            n32(nt),
            n32(a.n),
            n32(pl.len()),
            pl.i.as_ptr(),
            pl.j.as_ptr(),
            a.dwdx.as_ptr(),
            a.mass.as_ptr(),
            a.rho.as_ptr(),
            a.v.as_ptr(),
            a.h.as_ptr(),
            a.c.as_ptr(),
            a.amin,
            a.amax,
            a.ell,
            a.dt,
            a.alpv.as_mut_ptr(),
            a.dv.as_mut_ptr(),
        )
    }
}
