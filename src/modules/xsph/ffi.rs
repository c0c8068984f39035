//! The Fortran twin of XSPH (`sph_xsph_average`).
#![allow(unsafe_code)]

use super::Average;
use crate::modules::ffi_util::{chk, chk_pairs, n32};

#[allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/ffi_xsph.rs"));
}

pub(super) fn average(a: &mut Average) {
    let (dim, pl) = (a.dim, a.pairs);
    let nt = a.mass.len();
    chk("v", a.v.len(), dim * nt);
    chk("av", a.av.len(), dim * nt);
    chk("w", a.w.len(), pl.len());
    chk("rho", a.rho.len(), nt);
    chk_pairs(&pl.i, &pl.j, nt);
    // SAFETY: the arrays hold the values the explicit shapes declare and every pair index is in
    // 0..ntotal (checked above).
    unsafe {
        sys::sph_xsph_average(
            n32(dim),
            n32(nt),
            n32(pl.len()),
            pl.i.as_ptr(),
            pl.j.as_ptr(),
            a.w.as_ptr(),
            a.mass.as_ptr(),
            a.rho.as_ptr(),
            a.v.as_ptr(),
            a.eps,
            a.av.as_mut_ptr(),
        )
    }
}
