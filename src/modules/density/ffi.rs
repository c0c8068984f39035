//! The Fortran twin of the density (`sph_density_sum`, `sph_density_number`, `sph_density_rate`, `sph_density_rate_vol`).
#![allow(unsafe_code)]

use super::{Rate, Summation};
use crate::modules::ffi_util::{chk, chk_pairs, n32};

#[allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/ffi_density.rs"));
}

pub(super) fn summation(a: &mut Summation) {
    let pl = a.pairs;
    let nt = a.mass.len();
    chk("w0", a.w0.len(), nt);
    chk("rho", a.rho.len(), nt);
    chk("w", a.w.len(), pl.len());
    chk_pairs(&pl.i, &pl.j, nt);
    let f = if a.number { sys::sph_density_number } else { sys::sph_density_sum };
    // SAFETY: the arrays hold the values the explicit shapes declare and every pair index is in
    // 0..ntotal (checked above).
    unsafe {
        f(
            n32(nt),
            n32(pl.len()),
            pl.i.as_ptr(),
            pl.j.as_ptr(),
            a.w.as_ptr(),
            a.w0.as_ptr(),
            a.mass.as_ptr(),
            a.rho.as_mut_ptr(),
        )
    }
}

pub(super) fn rate(a: &mut Rate) {
    let (dim, pl) = (a.dim, a.pairs);
    let nt = a.mass.len();
    chk("dwdx", a.dwdx.len(), dim * pl.len());
    chk("v", a.v.len(), dim * nt);
    chk("drho", a.drho.len(), nt);
    chk_pairs(&pl.i, &pl.j, nt);
    if a.volume {
        chk("rho", a.rho.len(), nt);
        // SAFETY: as below, and rho holds ntotal values (checked above).
        unsafe {
            sys::sph_density_rate_vol(
                n32(dim),
                n32(nt),
                n32(pl.len()),
                pl.i.as_ptr(),
                pl.j.as_ptr(),
                a.dwdx.as_ptr(),
                a.mass.as_ptr(),
                a.rho.as_ptr(),
                a.v.as_ptr(),
                a.drho.as_mut_ptr(),
            )
        }
    } else {
        // SAFETY: the arrays hold the values the explicit shapes declare and every pair index is
        // in 0..ntotal (checked above).
        unsafe {
            sys::sph_density_rate(
                n32(dim),
                n32(nt),
                n32(pl.len()),
                pl.i.as_ptr(),
                pl.j.as_ptr(),
                a.dwdx.as_ptr(),
                a.mass.as_ptr(),
                a.v.as_ptr(),
                a.drho.as_mut_ptr(),
            )
        }
    }
}
