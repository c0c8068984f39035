//! The Fortran twin of the penalty force (`sph_penalty_force`).
#![allow(unsafe_code)]

use super::Force;
use crate::modules::ffi_util::{chk, chk_mat, chk_pairs, n32};

#[allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/ffi_penalty.rs"));
}

pub(super) fn force(a: &mut Force) {
    let (dim, pl) = (a.dim, a.pairs);
    let nt = a.mass.len();
    chk("x", a.x.len(), dim * nt);
    chk("dvdt", a.dvdt.len(), dim * nt);
    chk("h", a.h.len(), nt);
    chk("mat", a.mat.len(), nt);
    chk_mat(a.mt, &a.mat[..nt]);
    chk_pairs(&pl.i, &pl.j, nt);
    // SAFETY: the arrays hold the values the explicit shapes declare, pair indices are in
    // 0..ntotal and material indices in 0..nmat (checked above).
    unsafe {
        sys::sph_penalty_force(
            n32(dim),
            n32(nt),
            n32(pl.len()),
            pl.i.as_ptr(),
            pl.j.as_ptr(),
            a.x.as_ptr(),
            a.h.as_ptr(),
            a.mass.as_ptr(),
            a.mat.as_ptr(),
            n32(a.mt.nmat()),
            a.mt.group.as_ptr(),
            a.coef.pbar,
            a.coef.n1,
            a.coef.n2,
            a.dvdt.as_mut_ptr(),
        )
    }
}
