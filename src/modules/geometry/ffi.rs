//! The Fortran twin of the axisymmetric geometry (`sph_geometry_ring`, `_hoop`, `_continuity`).
#![allow(unsafe_code)]

use super::{Continuity, Hoop, Ring};
use crate::modules::ffi_util::{chk, n32};
use crate::modules::param::NSTR;

#[allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/ffi_geometry.rs"));
}

pub(super) fn ring(a: &mut Ring) {
    let (dim, nt) = (a.dim, a.mass.len());
    chk("x", a.x.len(), dim * nt);
    chk("h", a.h.len(), nt);
    chk("rinv", a.rinv.len(), nt);
    chk("pmass", a.pmass.len(), nt);
    assert!(a.nreal <= nt, "legacy call: nreal > ntotal");
    // SAFETY: every array holds the ntotal rows the explicit shapes declare (checked above).
    unsafe {
        sys::sph_geometry_ring(
            n32(dim),
            n32(nt),
            n32(a.nreal),
            a.x.as_ptr(),
            a.h.as_ptr(),
            a.mass.as_ptr(),
            a.rinv.as_mut_ptr(),
            a.pmass.as_mut_ptr(),
        )
    }
}

pub(super) fn hoop(a: &mut Hoop) {
    let (dim, nt) = (a.dim, a.rho.len());
    let n = a.dvdt.len() / dim.max(1);
    assert!(dim == 2 && n <= nt, "legacy call: the hoop terms need dim = 2 and n <= ntotal");
    chk("dvdt", a.dvdt.len(), dim * n);
    chk("rinv", a.rinv.len(), nt);
    chk("tau", a.tau.len(), NSTR * nt);
    // SAFETY: rho and rinv hold ntotal values, tau NSTR × ntotal, dvdt dim × n with n ≤ ntotal
    // (checked above).
    unsafe {
        sys::sph_geometry_hoop(
            n32(dim),
            n32(nt),
            n32(n),
            a.rho.as_ptr(),
            a.rinv.as_ptr(),
            a.tau.as_ptr(),
            a.dvdt.as_mut_ptr(),
        )
    }
}

pub(super) fn continuity(a: &mut Continuity) {
    let (dim, nt, n) = (a.dim, a.rho.len(), a.drho.len());
    assert!(n <= nt, "legacy call: n exceeds ntotal");
    chk("v", a.v.len(), dim * nt);
    chk("rinv", a.rinv.len(), nt);
    // SAFETY: v holds dim × ntotal values, rho and rinv ntotal, drho n ≤ ntotal (checked above).
    unsafe {
        sys::sph_geometry_continuity(
            n32(dim),
            n32(nt),
            n32(n),
            a.v.as_ptr(),
            a.rho.as_ptr(),
            a.rinv.as_ptr(),
            a.drho.as_mut_ptr(),
        )
    }
}
