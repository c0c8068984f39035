//! The Fortran twin of the internal force (`sph_force_internal`).
#![allow(unsafe_code)]

use super::{Internal, Newtonian};
use crate::modules::ffi_util::{chk, chk_opt, chk_pairs, n32, ptr_or};
use crate::modules::param::NSTR;

#[allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/ffi_force.rs"));
}

pub(super) fn internal(a: &mut Internal) {
    let (dim, pl) = (a.dim, a.pairs);
    let nt = a.mass.len();
    chk("dwdx", a.dwdx.len(), dim * pl.len());
    chk("v", a.v.len(), dim * nt);
    chk("dvdt", a.dvdt.len(), dim * nt);
    chk("dedt", a.dedt.len(), nt);
    chk("rho", a.rho.len(), nt);
    chk("p", a.p.len(), nt);
    chk_pairs(&pl.i, &pl.j, nt);
    let ntau = chk_opt("tau", a.tau.len(), nt, NSTR);
    let nrinv = chk_opt("rinv", a.rinv.len(), nt, 1);
    let dummy = 0.0;
    // SAFETY: the arrays hold the values the explicit shapes declare, pair indices are in
    // 0..ntotal (checked above), and tau (ntau = 0) and rinv (nrinv = 0) are one-value dummies
    // when empty (extents max(n, 1)).
    unsafe {
        sys::sph_force_internal(
            n32(dim),
            n32(nt),
            n32(pl.len()),
            pl.i.as_ptr(),
            pl.j.as_ptr(),
            a.dwdx.as_ptr(),
            a.mass.as_ptr(),
            a.rho.as_ptr(),
            a.p.as_ptr(),
            a.v.as_ptr(),
            n32(ntau),
            ptr_or(a.tau, &dummy),
            i32::from(a.asym),
            i32::from(a.iface),
            n32(nrinv),
            ptr_or(a.rinv, &dummy),
            a.dvdt.as_mut_ptr(),
            a.dedt.as_mut_ptr(),
        )
    }
}

pub(super) fn newtonian(a: &mut Newtonian) {
    let (dim, pl) = (a.dim, a.pairs);
    let nt = a.mass.len();
    chk("dwdx", a.dwdx.len(), dim * pl.len());
    chk("v", a.v.len(), dim * nt);
    chk("rho", a.rho.len(), nt);
    chk("eta", a.eta.len(), nt);
    chk("dvdt", a.dvdt.len(), dim * nt);
    chk("dedt", a.dedt.len(), nt);
    chk_pairs(&pl.i, &pl.j, nt);
    // SAFETY: the arrays hold the values the explicit shapes declare and every pair index is in
    // 0..ntotal (checked above).
    unsafe {
        sys::sph_force_newtonian(
            n32(dim),
            n32(nt),
            n32(pl.len()),
            pl.i.as_ptr(),
            pl.j.as_ptr(),
            a.dwdx.as_ptr(),
            a.mass.as_ptr(),
            a.rho.as_ptr(),
            a.v.as_ptr(),
            a.eta.as_ptr(),
            a.dvdt.as_mut_ptr(),
            a.dedt.as_mut_ptr(),
        )
    }
}
