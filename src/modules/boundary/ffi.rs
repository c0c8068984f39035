//! The Fortran twin of the boundaries (`sph_boundary_wall_force`, `_mirror_make`, `_mirror_fill`,
//! `_mirror_copy`, `_repulsion`).
#![allow(unsafe_code)]

use super::{MirrorCopy, MirrorFill, MirrorMake, Repulsion, WallForce};
use crate::modules::ffi_util::{chk, chk_idx, chk_opt, chk_pairs, mptr_or, n32, ptr_or};
use crate::modules::param::{NSTR, seg_len};

#[allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/ffi_boundary.rs"));
}

pub(super) fn wall_force(a: &mut WallForce) {
    let dim = a.dim;
    let n = a.dvdt.len() / dim;
    let segs = a.segs;
    chk("x", a.x.len(), dim * n);
    chk("seg", segs.seg.len(), seg_len(dim) * segs.len());
    let (dummy, di) = (0.0, 0i32);
    let c = a.coef;
    // SAFETY: x and dvdt hold dim × n values, seg nsv × nseg (checked above); with no segment
    // the routine reads nothing and one-value dummies stand for seg and endnode.
    unsafe {
        sys::sph_boundary_wall_force(
            n32(dim),
            n32(n),
            a.x.as_ptr(),
            n32(segs.len()),
            ptr_or(&segs.seg, &dummy),
            ptr_or(&segs.endnode, &di),
            c.spacing,
            c.r0,
            c.d,
            c.n1,
            c.n2,
            a.dvdt.as_mut_ptr(),
        )
    }
}

/// The capacity protocol: the routine stores at most `maxg` mirrors and returns how many it
/// found; the lists grow and the call is repeated until they fit.
pub(super) fn mirror_make(a: &mut MirrorMake) {
    let dim = a.dim;
    let n = a.h.len();
    let segs = a.segs;
    chk("x", a.x.len(), dim * n);
    chk("seg", segs.seg.len(), seg_len(dim) * segs.len());
    let ngen = 2 + dim / 3;
    let mut cap = a.gsrc.capacity().max(64);
    loop {
        a.gsrc.resize(cap, 0);
        a.gseg.resize(ngen * cap, 0);
        let mut ng = 0i32;
        // SAFETY: x holds dim × n values, h n, seg nsv × nseg (checked above); gsrc and gseg
        // hold cap and ngen·cap values, and the routine stores at most maxg = cap mirrors.
        unsafe {
            sys::sph_boundary_mirror_make(
                n32(dim),
                n32(n),
                a.x.as_ptr(),
                a.h.as_ptr(),
                a.kappa,
                n32(segs.len()),
                segs.seg.as_ptr(),
                n32(cap),
                &mut ng,
                a.gsrc.as_mut_ptr(),
                a.gseg.as_mut_ptr(),
            )
        }
        let ng = ng as usize;
        if ng <= cap {
            a.gsrc.truncate(ng);
            a.gseg.truncate(ngen * ng);
            return;
        }
        cap = ng + ng / 4;
    }
}

pub(super) fn mirror_fill(a: &mut MirrorFill) {
    let (dim, n, segs) = (a.dim, a.n, a.segs);
    let ng = a.gsrc.len();
    let nt = n + ng;
    let ngen = 2 + dim / 3;
    chk("gseg", a.gseg.len(), ngen * ng);
    chk("seg", segs.seg.len(), seg_len(dim) * segs.len());
    chk_idx("gsrc", a.gsrc, n);
    assert!(
        a.gseg[..ngen * ng].iter().all(|&s| s >= -1 && s < segs.len() as i32)
            && a.gseg[..ngen * ng].chunks(ngen).all(|c| c[0] >= 0),
        "legacy call: `gseg` names a wall that does not exist"
    );
    chk("x", a.x.len(), dim * nt);
    chk("v", a.v.len(), dim * nt);
    for (name, l) in [
        ("rho", a.rho.len()),
        ("p", a.p.len()),
        ("c", a.c.len()),
        ("e", a.e.len()),
        ("h", a.h.len()),
        ("mass", a.mass.len()),
        ("mat", a.mat.len()),
    ] {
        chk(name, l, nt);
    }
    let ntau = chk_opt("tau", a.tau.len(), nt, NSTR);
    let mut dummy = 0.0;
    // SAFETY: every particle array holds ntotal = n + ng rows, the mirror lists ng entries whose
    // sources are real particles and whose walls exist (checked above); tau is a one-value dummy
    // when ntau = 0.
    unsafe {
        sys::sph_boundary_mirror_fill(
            n32(dim),
            n32(nt),
            n32(n),
            n32(ng),
            a.gsrc.as_ptr(),
            a.gseg.as_ptr(),
            n32(segs.len()),
            segs.seg.as_ptr(),
            i32::from(a.noslip),
            a.x.as_mut_ptr(),
            a.v.as_mut_ptr(),
            a.rho.as_mut_ptr(),
            a.p.as_mut_ptr(),
            a.c.as_mut_ptr(),
            a.e.as_mut_ptr(),
            a.h.as_mut_ptr(),
            a.mass.as_mut_ptr(),
            a.mat.as_mut_ptr(),
            n32(ntau),
            mptr_or(a.tau, &mut dummy),
        )
    }
}

pub(super) fn mirror_copy(a: &mut MirrorCopy) {
    let nt = a.n + a.gsrc.len();
    chk("f", a.f.len(), nt);
    chk_idx("gsrc", a.gsrc, a.n);
    // SAFETY: f holds ntotal = n + ng values and every source is a real particle (checked above).
    unsafe { sys::sph_boundary_mirror_copy(n32(nt), n32(a.n), n32(a.gsrc.len()), a.gsrc.as_ptr(), a.f.as_mut_ptr()) }
}

pub(super) fn repulsion(a: &mut Repulsion) {
    let (dim, pl) = (a.dim, a.pairs);
    let nt = a.dvdt.len() / dim;
    let n = a.bnd.len();
    chk("x", a.x.len(), dim * nt);
    assert!(n <= nt, "legacy call: `bnd` has {n} values for {nt} particles");
    assert!(a.grav.is_empty() || a.grav.len() == dim, "legacy call: `grav` needs 0 or dim values");
    chk_pairs(&pl.i, &pl.j, nt);
    let (dummy, di) = (0.0, 0i32);
    let c = a.coef;
    // SAFETY: x and dvdt hold dim × nt values, bnd n ≤ nt, grav 0 or dim (a one-value dummy
    // when empty), the pair lists npair indices in 0..nt (checked above).
    unsafe {
        sys::sph_boundary_repulsion(
            n32(dim),
            n32(nt),
            n32(n),
            n32(pl.len()),
            ptr_or(&pl.i, &di),
            ptr_or(&pl.j, &di),
            a.x.as_ptr(),
            ptr_or(a.bnd, &di),
            c.r0,
            c.d,
            c.p1,
            c.p2,
            n32(a.grav.len()),
            ptr_or(a.grav, &dummy),
            a.dvdt.as_mut_ptr(),
        )
    }
}
