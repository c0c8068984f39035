//! The Fortran twin of the strength module (`sph_strength_rates`, `sph_strength_yield`).
#![allow(unsafe_code)]

use super::{Rates, Yield};
use crate::modules::ffi_util::{chk, chk_mat, chk_opt, chk_pairs, n32, ptr_or};
use crate::modules::param::NSTR;

#[allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/ffi_strength.rs"));
}

pub(super) fn rates(a: &mut Rates) {
    let (dim, nreal, pl) = (a.dim, a.nreal, a.pairs);
    let nt = a.mass.len();
    chk("tau", a.tau.len(), NSTR * nt);
    chk("eps", a.eps.len(), NSTR * nt);
    chk("rot", a.rot.len(), 3 * nt);
    chk("dtau", a.dtau.len(), NSTR * nreal);
    chk("dedt", a.dedt.len(), nreal);
    assert!(nreal <= nt, "legacy call: nreal exceeds ntotal");
    chk("dwdx", a.dwdx.len(), dim * pl.len());
    chk("rho", a.rho.len(), nt);
    chk("v", a.v.len(), dim * nt);
    chk("mat", a.mat.len(), nt);
    chk_mat(a.mt, &a.mat[..nt]);
    chk_pairs(&pl.i, &pl.j, nt);
    let nr = chk_opt("rinv", a.rinv.len(), nt, 1);
    let dummy = 0.0;
    // SAFETY: the arrays hold the values the explicit shapes declare (NSTR × ntotal, 3 × ntotal,
    // NSTR × n, ...), pair indices are in 0..ntotal and material indices in 0..nmat (checked);
    // rinv holds ntotal values or, in plane geometry (nr = 0), a one-value dummy stands for it.
    unsafe {
        sys::sph_strength_rates(
            n32(dim),
            n32(nt),
            n32(nreal),
            n32(pl.len()),
            pl.i.as_ptr(),
            pl.j.as_ptr(),
            a.dwdx.as_ptr(),
            a.mass.as_ptr(),
            a.rho.as_ptr(),
            a.v.as_ptr(),
            a.mat.as_ptr(),
            n32(a.mt.nmat()),
            a.mt.mpar.as_ptr(),
            a.tau.as_ptr(),
            n32(nr),
            ptr_or(a.rinv, &dummy),
            a.eps.as_mut_ptr(),
            a.rot.as_mut_ptr(),
            a.dtau.as_mut_ptr(),
            a.dedt.as_mut_ptr(),
        )
    }
}

pub(super) fn yield_return(a: &mut Yield) {
    let n = a.mat.len();
    chk("p", a.p.len(), n);
    chk("tau", a.tau.len(), NSTR * n);
    chk_mat(a.mt, a.mat);
    // SAFETY: p holds n values, tau NSTR × n, material indices are in 0..nmat (checked above).
    unsafe {
        sys::sph_strength_yield(
            n32(n),
            a.mat.as_ptr(),
            n32(a.mt.nmat()),
            a.mt.mpar.as_ptr(),
            a.p.as_ptr(),
            a.tau.as_mut_ptr(),
        )
    }
}
