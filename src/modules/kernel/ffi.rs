//! The Fortran twin of the kernel (`sph_kernel_pairs`, `sph_kernel_self`, `sph_kernel_point`).
#![allow(unsafe_code)]

use super::{Pairs, Point, SelfW};
use crate::modules::ffi_util::{chk, chk_pairs, n32};

#[allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/ffi_kernel.rs"));
}

pub(super) fn pairs(a: &mut Pairs) {
    let (dim, pl) = (a.dim, a.pairs);
    let np = pl.len();
    let nt = a.h.len();
    chk("x", a.x.len(), dim * nt);
    chk("w", a.w.len(), np);
    chk("dwdx", a.dwdx.len(), dim * np);
    chk_pairs(&pl.i, &pl.j, nt);
    // SAFETY: the arrays hold the values the explicit shapes declare (dim × ntotal, npair,
    // dim × npair) and every pair index is in 0..ntotal (checked above).
    unsafe {
        sys::sph_kernel_pairs(
            n32(dim),
            n32(nt),
            n32(np),
            a.kind.skf(),
            a.gscale,
            pl.i.as_ptr(),
            pl.j.as_ptr(),
            a.x.as_ptr(),
            a.h.as_ptr(),
            a.w.as_mut_ptr(),
            a.dwdx.as_mut_ptr(),
        )
    }
}

pub(super) fn self_w(a: &mut SelfW) {
    chk("w0", a.w0.len(), a.h.len());
    // SAFETY: w0 holds at least the n = h.len() values the routine writes.
    unsafe { sys::sph_kernel_self(n32(a.dim), n32(a.h.len()), a.kind.skf(), a.h.as_ptr(), a.w0.as_mut_ptr()) }
}

pub(super) fn point(a: &mut Point) {
    chk("dx", a.dx.len(), a.dim);
    chk("dwdx", a.dwdx.len(), a.dim);
    // SAFETY: dx and dwdx hold dim values; w is one value.
    unsafe { sys::sph_kernel_point(n32(a.dim), a.kind.skf(), a.dx.as_ptr(), a.h, a.w, a.dwdx.as_mut_ptr()) }
}
