//! The Fortran twin of the detonation (`sph_detonation_light`, `sph_detonation_burn`).
#![allow(unsafe_code)]

use super::{Burn, Light};
use crate::modules::ffi_util::{chk, chk_mat, n32};

#[allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/ffi_detonation.rs"));
}

pub(super) fn light(a: &mut Light) {
    let (dim, n) = (a.dim, a.mat.len());
    chk("x", a.x.len(), dim * n);
    chk("xdet", a.xdet.len(), dim);
    let zero = vec![0.0; dim];
    let nrm = a.nrm.unwrap_or(&zero);
    chk("nrm", nrm.len(), dim);
    chk("tlight", a.tlight.len(), n);
    chk_mat(a.mt, a.mat);
    // SAFETY: the arrays hold the values the explicit shapes declare and every material index is
    // in 0..nmat (checked above).
    unsafe {
        sys::sph_detonation_light(
            n32(dim),
            n32(n),
            a.x.as_ptr(),
            a.mat.as_ptr(),
            n32(a.mt.nmat()),
            a.mt.mtype.as_ptr(),
            a.mt.mpar.as_ptr(),
            a.xdet.as_ptr(),
            nrm.as_ptr(),
            i32::from(a.nrm.is_some()),
            a.sf,
            a.tlight.as_mut_ptr(),
        )
    }
}

pub(super) fn burn(a: &mut Burn) {
    let n = a.mat.len();
    chk("tlight", a.tlight.len(), n);
    chk("h", a.h.len(), n);
    chk("rho", a.rho.len(), n);
    chk("burn", a.burn.len(), n);
    chk_mat(a.mt, a.mat);
    // SAFETY: the arrays hold the n values the routine reads or writes and every material index
    // is in 0..nmat (checked above).
    unsafe {
        sys::sph_detonation_burn(
            n32(n),
            a.t,
            a.mat.as_ptr(),
            n32(a.mt.nmat()),
            a.mt.mpar.as_ptr(),
            a.tlight.as_ptr(),
            a.h.as_ptr(),
            a.rho.as_ptr(),
            a.width,
            a.burn.as_mut_ptr(),
        )
    }
}
