//! The Fortran twin of the absorbing walls (`sph_absorb_init`, `sph_absorb_dashpot`).
#![allow(unsafe_code)]

use super::{Dashpot, Init};
use crate::modules::ffi_util::{chk, chk_mat, chk_opt, n32, ptr_or};
use crate::modules::param::{NSTR, seg_len};

#[allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/ffi_absorb.rs"));
}

pub(super) fn init(a: &mut Init) {
    let n = a.p.len();
    chk("sigma0", a.sigma0.len(), NSTR * n);
    let ntau = chk_opt("tau", a.tau.len(), n, NSTR);
    let dummy = 0.0;
    // SAFETY: p holds n values and sigma0 NSTR × n; tau NSTR × n or, without strength (ntau = 0),
    // a one-value dummy stands for it (checked above).
    unsafe { sys::sph_absorb_init(n32(n), a.p.as_ptr(), n32(ntau), ptr_or(a.tau, &dummy), a.sigma0.as_mut_ptr()) }
}

pub(super) fn dashpot(a: &mut Dashpot) {
    let (dim, n, segs) = (a.dim, a.rho.len(), a.segs);
    chk("x", a.x.len(), dim * n);
    chk("v", a.v.len(), dim * n);
    chk("c", a.c.len(), n);
    chk("mat", a.mat.len(), n);
    chk_mat(a.mt, &a.mat[..n]);
    chk("sigma0", a.sigma0.len(), NSTR * n);
    chk("seg", segs.seg.len(), seg_len(dim) * segs.len());
    chk("dvdt", a.dvdt.len(), dim * n);
    let dummy = 0.0;
    // SAFETY: x, v and dvdt hold dim × n values, rho, c and mat n, sigma0 NSTR × n, seg nsv × nseg,
    // material indices are in 0..nmat (checked above); with no wall a one-value dummy stands for
    // seg and the routine reads none of it.
    unsafe {
        sys::sph_absorb_dashpot(
            n32(dim),
            n32(n),
            a.x.as_ptr(),
            a.v.as_ptr(),
            a.rho.as_ptr(),
            a.c.as_ptr(),
            a.mat.as_ptr(),
            n32(a.mt.nmat()),
            a.mt.mpar.as_ptr(),
            a.sigma0.as_ptr(),
            n32(segs.len()),
            ptr_or(&segs.seg, &dummy),
            a.layer,
            a.dvdt.as_mut_ptr(),
        )
    }
}
