//! The Fortran twin of the neighbour search (`sph_nnps_direct`, `sph_nnps_cell`).
#![allow(unsafe_code)]

use super::Search;
use crate::modules::ffi_util::{chk, n32};

#[allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/ffi_nnps.rs"));
}

/// One call of the Fortran search into `pi`, `pj`: it stores at most their length of pairs
/// (the prefix of the canonical list) and returns how many pairs there are.
pub(super) fn search_into(a: &Search, pi: &mut [i32], pj: &mut [i32]) -> usize {
    let (dim, nt) = (a.dim, a.h.len());
    chk("x", a.x.len(), dim * nt);
    assert!(a.nreal <= nt, "legacy call: nreal exceeds ntotal");
    let cap = pi.len().min(pj.len());
    let (mut di, mut dj) = (0i32, 0i32);
    let (ip, jp) = if cap == 0 { (&mut di as *mut i32, &mut dj as *mut i32) } else { (pi.as_mut_ptr(), pj.as_mut_ptr()) };
    let mut np: i32 = 0;
    let f = if a.cell { sys::sph_nnps_cell } else { sys::sph_nnps_direct };
    // SAFETY: x holds dim × ntotal values and h ntotal (checked above); pair_i and pair_j hold
    // cap values (one-value dummies when cap = 0) and the routine stores at most maxpair = cap.
    unsafe { f(n32(dim), n32(a.nreal), n32(nt), a.x.as_ptr(), a.h.as_ptr(), a.kappa, n32(cap), &mut np, ip, jp) }
    np as usize
}

/// The capacity protocol: the lists grow and the call is repeated until every pair fits.
pub(super) fn search(a: &mut Search) {
    let mut pl = std::mem::take(&mut *a.pairs);
    let mut cap = pl.i.capacity().max(16 * a.h.len()).max(16);
    loop {
        pl.i.resize(cap, 0);
        pl.j.resize(cap, 0);
        let np = search_into(a, &mut pl.i, &mut pl.j);
        if np <= cap {
            pl.i.truncate(np);
            pl.j.truncate(np);
            *a.pairs = pl;
            return;
        }
        cap = np + np / 4;
    }
}
