//! The Fortran twin of the smoothing module (`sph_smoothing_density`, `_rate`, `_advance`).
#![allow(unsafe_code)]

use super::{Advance, FromDensity, Rate};
use crate::modules::ffi_util::{chk, chk_opt, n32, ptr_or};

#[allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/ffi_smoothing.rs"));
}

pub(super) fn from_density(a: &mut FromDensity) {
    let n = a.h.len();
    chk("rho", a.rho.len(), n);
    chk("h0", a.h0.len(), n);
    chk("rho0", a.rho0.len(), n);
    let nr = chk_opt("rinv", a.rinv.len(), n, 1);
    let dummy = 0.0;
    // SAFETY: every array holds the n values the routine reads or writes (checked above); rinv
    // is a one-value dummy in plane geometry (nr = 0).
    unsafe {
        sys::sph_smoothing_density(
            n32(a.dim),
            n32(n),
            a.rho.as_ptr(),
            a.h0.as_ptr(),
            a.rho0.as_ptr(),
            n32(nr),
            ptr_or(a.rinv, &dummy),
            a.hmax,
            a.h.as_mut_ptr(),
        )
    }
}

pub(super) fn rate(a: &mut Rate) {
    let n = a.dhdt.len();
    chk("rho", a.rho.len(), n);
    chk("h", a.h.len(), n);
    chk("drho", a.drho.len(), n);
    // SAFETY: every array holds the n values the routine reads or writes (checked above).
    unsafe {
        sys::sph_smoothing_rate(n32(a.dim), n32(n), a.rho.as_ptr(), a.h.as_ptr(), a.drho.as_ptr(), a.dhdt.as_mut_ptr())
    }
}

pub(super) fn advance(a: &mut Advance) {
    let n = a.dhdt.len();
    chk("h", a.h.len(), n);
    // SAFETY: h holds the n values the routine updates (checked above).
    unsafe { sys::sph_smoothing_advance(n32(n), a.dt, a.theta, a.hmax, a.dhdt.as_ptr(), a.h.as_mut_ptr()) }
}
