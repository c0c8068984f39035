//! The Fortran twin of the EOS (`sph_eos_eval`): lengths checked, then one foreign call.
#![allow(unsafe_code)]

use super::Eval;
use crate::modules::ffi_util::{chk, chk_opt, chk_mat, n32, ptr_or};

#[allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/ffi_eos.rs"));
}

pub(super) fn eval(a: &mut Eval) {
    let n = a.mat.len();
    for (name, l) in [("rho", a.rho.len()), ("e", a.e.len()), ("p", a.p.len()), ("c", a.c.len())] {
        chk(name, l, n);
    }
    let nburn = chk_opt("burn", a.burn.len(), n, 1);
    let nhist = chk_opt("rho_max", a.rho_max.len(), n, 1);
    chk_mat(a.mt, a.mat);
    let dummy = 1.0;
    let mut hdummy = 0.0;
    let rmax: *mut f64 = if nhist == 0 { &mut hdummy } else { a.rho_max.as_mut_ptr() };
    // SAFETY: every array holds at least the n values (nmat columns for the table) that the
    // explicit shapes of sph_eos_eval declare, material indices are in 0..nmat (checked above),
    // and burn and rmax are one-value dummies when nburn = 0 and nhist = 0, as their declared
    // extents max(nburn, 1) and max(nhist, 1) allow.
    unsafe {
        sys::sph_eos_eval(
            n32(n),
            n32(a.mt.nmat()),
            a.mt.mtype.as_ptr(),
            a.mt.mpar.as_ptr(),
            a.mat.as_ptr(),
            n32(nburn),
            ptr_or(a.burn, &dummy),
            n32(nhist),
            rmax,
            a.rho.as_ptr(),
            a.e.as_ptr(),
            a.p.as_mut_ptr(),
            a.c.as_mut_ptr(),
        )
    }
}
