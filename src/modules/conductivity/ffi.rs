//! The Fortran twin of the conductivity (`sph_conductivity_price`, `sph_conductivity_noh`).
#![allow(unsafe_code)]

use super::{Noh, Price};
use crate::modules::ffi_util::{chk, chk_opt, chk_pairs, n32, ptr_or};

#[allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/ffi_conductivity.rs"));
}

pub(super) fn price(a: &mut Price) {
    let (dim, pl) = (a.dim, a.pairs);
    let nt = a.mass.len();
    chk("x", a.x.len(), dim * nt);
    chk("v", a.v.len(), dim * nt);
    chk("dwdx", a.dwdx.len(), dim * pl.len());
    for (name, l) in [("rho", a.rho.len()), ("p", a.p.len()), ("e", a.e.len()), ("dedt", a.dedt.len())] {
        chk(name, l, nt);
    }
    chk_pairs(&pl.i, &pl.j, nt);
    let nrinv = chk_opt("rinv", a.rinv.len(), nt, 1);
    let dummy = 0.0;
    // SAFETY: the arrays hold the values the explicit shapes declare (dim × ntotal, ntotal,
    // dim × npair), every pair index is in 0..ntotal (checked above), and rinv is a one-value
    // dummy when nrinv = 0 (extent max(nrinv, 1)).
    unsafe {
        sys::sph_conductivity_price(
            n32(dim),
            n32(nt),
            n32(pl.len()),
            pl.i.as_ptr(),
            pl.j.as_ptr(),
            a.dwdx.as_ptr(),
            a.x.as_ptr(),
            a.v.as_ptr(),
            a.rho.as_ptr(),
            a.p.as_ptr(),
            a.e.as_ptr(),
            a.mass.as_ptr(),
            a.alpha,
            a.signal,
            n32(nrinv),
            ptr_or(a.rinv, &dummy),
            a.dedt.as_mut_ptr(),
        )
    }
}

pub(super) fn noh(a: &mut Noh) {
    let (dim, pl) = (a.dim, a.pairs);
    let nt = a.mass.len();
    chk("x", a.x.len(), dim * nt);
    chk("v", a.v.len(), dim * nt);
    chk("dwdx", a.dwdx.len(), dim * pl.len());
    for (name, l) in
        [("h", a.h.len()), ("rho", a.rho.len()), ("c", a.c.len()), ("e", a.e.len()), ("dedt", a.dedt.len())]
    {
        chk(name, l, nt);
    }
    chk_pairs(&pl.i, &pl.j, nt);
    // SAFETY: the arrays hold the values the explicit shapes declare (dim × ntotal, ntotal,
    // dim × npair) and every pair index is in 0..ntotal (checked above).
    unsafe {
        sys::sph_conductivity_noh(
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
            a.e.as_ptr(),
            a.mass.as_ptr(),
            a.coef.g1,
            a.coef.g2,
            a.coef.phi2,
            a.dedt.as_mut_ptr(),
        )
    }
}
