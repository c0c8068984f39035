//! Safe wrappers over the legacy Fortran core (`fortran/src/*.f90`), one per `bind(C)` routine.
//!
//! This is the only module of the crate with `unsafe`: each wrapper checks the lengths of the
//! slices it is handed against the explicit shapes that the Fortran routine declares, then makes
//! the foreign call. Arrays are in the Fortran layout (`x[d + dim*i]`), indices are 0-based at
//! the C boundary, and integers are `i32` (`c_int`).
#![allow(unsafe_code)]
#![allow(clippy::too_many_arguments)]

#[allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]
mod ffi {
    include!(concat!(env!("OUT_DIR"), "/legacy_bindings.rs"));
}

pub use ffi::{
    SPH_EOS_IDEAL_GAS, SPH_EOS_JWL, SPH_EOS_NONE, SPH_EOS_SOIL, SPH_EOS_WATER, SPH_MP_ALPHA_PHI, SPH_MP_COHESION,
    SPH_MP_E1, SPH_MP_PMIN, SPH_MP_RHO0, SPH_MP_SHEAR, SPH_NPAR, SPH_NSTR, SPH_SKF_CUBIC, SPH_SKF_GAUSS,
    SPH_SKF_QUINTIC, SPH_SKF_WENDLAND,
};

/// The material table passed to every routine that dispatches per material.
#[derive(Debug, Clone, PartialEq)]
pub struct MatTable {
    /// `SPH_EOS_*` code per material.
    pub mtype: Vec<i32>,
    /// `mpar(SPH_NPAR, nmat)`, rows as `SPH_MP_*` (1-based rows: row r is `mpar[r-1 + NPAR*m]`).
    pub mpar: Vec<f64>,
    /// Penalty group per material: pairs in different groups feel the penalty force.
    pub group: Vec<i32>,
}

impl MatTable {
    pub fn nmat(&self) -> usize {
        self.mtype.len()
    }
    /// The value of row `row` (a 1-based `SPH_MP_*` index) for material `m`.
    pub fn par(&self, m: usize, row: u32) -> f64 {
        self.mpar[(row as usize - 1) + NPAR * m]
    }
}

pub const NPAR: usize = SPH_NPAR as usize;
pub const NSTR: usize = SPH_NSTR as usize;

fn n32(n: usize) -> i32 {
    i32::try_from(n).expect("array size exceeds the C int range of the legacy core")
}

fn chk(name: &str, len: usize, need: usize) {
    assert!(len >= need, "legacy call: array `{name}` has {len} values, the routine needs {need}");
}

/// Every index in `idx` must lie in `0..bound` (the Fortran dereferences them).
fn chk_idx(name: &str, idx: &[i32], bound: usize) {
    let (lo, hi) = idx.iter().fold((i32::MAX, i32::MIN), |(a, b), &v| (a.min(v), b.max(v)));
    assert!(
        idx.is_empty() || (lo >= 0 && (hi as usize) < bound),
        "legacy call: `{name}` holds an index outside 0..{bound} (range {lo}..={hi})"
    );
}

/// A pair list over `nt` particles.
fn chk_pairs(pi: &[i32], pj: &[i32], nt: usize) {
    assert_eq!(pi.len(), pj.len(), "legacy call: pair_i and pair_j differ in length");
    chk_idx("pair_i", pi, nt);
    chk_idx("pair_j", pj, nt);
}

/// A material table and the materials of `mat`.
fn chk_mat(mt: &MatTable, mat: &[i32]) {
    let nm = mt.nmat();
    chk("mpar", mt.mpar.len(), NPAR * nm);
    chk("group", mt.group.len(), nm);
    chk_idx("mat", mat, nm);
}

/// A pointer to a slice for an argument declared `max(k,1)` long: a dummy when empty.
fn ptr_or_dummy(s: &[f64], dummy: &f64) -> *const f64 {
    if s.is_empty() { dummy } else { s.as_ptr() }
}

fn mptr_or_dummy(s: &mut [f64], dummy: &mut f64) -> *mut f64 {
    if s.is_empty() { dummy } else { s.as_mut_ptr() }
}

pub fn kernel_pairs(
    dim: usize,
    skf: i32,
    pi: &[i32],
    pj: &[i32],
    x: &[f64],
    h: &[f64],
    w: &mut [f64],
    dwdx: &mut [f64],
) {
    let np = pi.len();
    let nt = h.len();
    chk("pair_j", pj.len(), np);
    chk("x", x.len(), dim * nt);
    chk("w", w.len(), np);
    chk("dwdx", dwdx.len(), dim * np);
    chk("h", h.len(), nt);
    chk_pairs(pi, pj, nt);
    unsafe {
        ffi::sph_kernel_pairs(
            n32(dim),
            n32(nt),
            n32(np),
            skf,
            pi.as_ptr(),
            pj.as_ptr(),
            x.as_ptr(),
            h.as_ptr(),
            w.as_mut_ptr(),
            dwdx.as_mut_ptr(),
        )
    }
}

pub fn kernel_self(dim: usize, skf: i32, h: &[f64], w0: &mut [f64]) {
    chk("w0", w0.len(), h.len());
    unsafe { ffi::sph_kernel_self(n32(dim), n32(h.len()), skf, h.as_ptr(), w0.as_mut_ptr()) }
}

/// W and grad W at one separation `dx` (length `dim`).
pub fn kernel_point(dim: usize, skf: i32, dx: &[f64], h: f64) -> (f64, Vec<f64>) {
    chk("dx", dx.len(), dim);
    let mut w = 0.0;
    let mut g = vec![0.0; dim];
    unsafe { ffi::sph_kernel_point(n32(dim), skf, dx.as_ptr(), h, &mut w, g.as_mut_ptr()) }
    (w, g)
}

/// Neighbour search; returns the number of pairs found (may exceed the capacity of `pi`).
pub fn nnps(
    cell: bool,
    dim: usize,
    nreal: usize,
    x: &[f64],
    h: &[f64],
    kappa: f64,
    pi: &mut [i32],
    pj: &mut [i32],
) -> usize {
    let nt = h.len();
    chk("x", x.len(), dim * nt);
    let maxpair = pi.len().min(pj.len());
    let mut npair: i32 = 0;
    let mut di = 0i32;
    let mut dj = 0i32;
    let (ip, jp) =
        if maxpair == 0 { (&mut di as *mut i32, &mut dj as *mut i32) } else { (pi.as_mut_ptr(), pj.as_mut_ptr()) };
    unsafe {
        if cell {
            ffi::sph_nnps_cell(
                n32(dim),
                n32(nreal),
                n32(nt),
                x.as_ptr(),
                h.as_ptr(),
                kappa,
                n32(maxpair),
                &mut npair,
                ip,
                jp,
            )
        } else {
            ffi::sph_nnps_direct(
                n32(dim),
                n32(nreal),
                n32(nt),
                x.as_ptr(),
                h.as_ptr(),
                kappa,
                n32(maxpair),
                &mut npair,
                ip,
                jp,
            )
        }
    }
    npair as usize
}

pub fn density_sum(pi: &[i32], pj: &[i32], w: &[f64], w0: &[f64], mass: &[f64], rho: &mut [f64]) {
    let nt = mass.len();
    chk("w0", w0.len(), nt);
    chk("rho", rho.len(), nt);
    chk("w", w.len(), pi.len());
    chk_pairs(pi, pj, nt);
    unsafe {
        ffi::sph_density_sum(
            n32(nt),
            n32(pi.len()),
            pi.as_ptr(),
            pj.as_ptr(),
            w.as_ptr(),
            w0.as_ptr(),
            mass.as_ptr(),
            rho.as_mut_ptr(),
        )
    }
}

pub fn density_rate(dim: usize, pi: &[i32], pj: &[i32], dwdx: &[f64], mass: &[f64], v: &[f64], drho: &mut [f64]) {
    let nt = mass.len();
    chk("dwdx", dwdx.len(), dim * pi.len());
    chk("v", v.len(), dim * nt);
    chk("drho", drho.len(), nt);
    chk_pairs(pi, pj, nt);
    unsafe {
        ffi::sph_density_rate(
            n32(dim),
            n32(nt),
            n32(pi.len()),
            pi.as_ptr(),
            pj.as_ptr(),
            dwdx.as_ptr(),
            mass.as_ptr(),
            v.as_ptr(),
            drho.as_mut_ptr(),
        )
    }
}

pub fn density_rate_vol(
    dim: usize,
    pi: &[i32],
    pj: &[i32],
    dwdx: &[f64],
    mass: &[f64],
    rho: &[f64],
    v: &[f64],
    drho: &mut [f64],
) {
    let nt = mass.len();
    chk("dwdx", dwdx.len(), dim * pi.len());
    chk("rho", rho.len(), nt);
    chk("v", v.len(), dim * nt);
    chk("drho", drho.len(), nt);
    chk_pairs(pi, pj, nt);
    unsafe {
        ffi::sph_density_rate_vol(
            n32(dim),
            n32(nt),
            n32(pi.len()),
            pi.as_ptr(),
            pj.as_ptr(),
            dwdx.as_ptr(),
            mass.as_ptr(),
            rho.as_ptr(),
            v.as_ptr(),
            drho.as_mut_ptr(),
        )
    }
}

pub fn eos_eval(mt: &MatTable, mat: &[i32], burn: &[f64], rho: &[f64], e: &[f64], p: &mut [f64], c: &mut [f64]) {
    let n = mat.len();
    for (name, l) in [("rho", rho.len()), ("e", e.len()), ("p", p.len()), ("c", c.len())] {
        chk(name, l, n);
    }
    let nburn = if burn.is_empty() { 0 } else { n };
    chk("burn", burn.len(), nburn);
    chk_mat(mt, mat);
    let dummy = 1.0;
    unsafe {
        ffi::sph_eos_eval(
            n32(n),
            n32(mt.nmat()),
            mt.mtype.as_ptr(),
            mt.mpar.as_ptr(),
            mat.as_ptr(),
            n32(nburn),
            ptr_or_dummy(burn, &dummy),
            rho.as_ptr(),
            e.as_ptr(),
            p.as_mut_ptr(),
            c.as_mut_ptr(),
        )
    }
}

pub fn force_internal(
    dim: usize,
    pi: &[i32],
    pj: &[i32],
    dwdx: &[f64],
    mass: &[f64],
    rho: &[f64],
    p: &[f64],
    v: &[f64],
    tau: &[f64],
    dvdt: &mut [f64],
    dedt: &mut [f64],
) {
    let nt = mass.len();
    chk("dwdx", dwdx.len(), dim * pi.len());
    chk("v", v.len(), dim * nt);
    chk("dvdt", dvdt.len(), dim * nt);
    chk("dedt", dedt.len(), nt);
    chk("rho", rho.len(), nt);
    chk("p", p.len(), nt);
    chk_pairs(pi, pj, nt);
    let ntau = if tau.is_empty() { 0 } else { nt };
    chk("tau", tau.len(), NSTR * ntau);
    let dummy = 0.0;
    unsafe {
        ffi::sph_force_internal(
            n32(dim),
            n32(nt),
            n32(pi.len()),
            pi.as_ptr(),
            pj.as_ptr(),
            dwdx.as_ptr(),
            mass.as_ptr(),
            rho.as_ptr(),
            p.as_ptr(),
            v.as_ptr(),
            n32(ntau),
            ptr_or_dummy(tau, &dummy),
            dvdt.as_mut_ptr(),
            dedt.as_mut_ptr(),
        )
    }
}

pub fn viscosity_monaghan(
    dim: usize,
    pi: &[i32],
    pj: &[i32],
    dwdx: &[f64],
    x: &[f64],
    v: &[f64],
    h: &[f64],
    rho: &[f64],
    c: &[f64],
    mass: &[f64],
    coef: (f64, f64, f64),
    dvdt: &mut [f64],
    dedt: &mut [f64],
) {
    let nt = mass.len();
    chk("x", x.len(), dim * nt);
    chk("dvdt", dvdt.len(), dim * nt);
    chk("dedt", dedt.len(), nt);
    chk("dwdx", dwdx.len(), dim * pi.len());
    chk("v", v.len(), dim * nt);
    for (name, l) in [("h", h.len()), ("rho", rho.len()), ("c", c.len())] {
        chk(name, l, nt);
    }
    chk_pairs(pi, pj, nt);
    unsafe {
        ffi::sph_viscosity_monaghan(
            n32(dim),
            n32(nt),
            n32(pi.len()),
            pi.as_ptr(),
            pj.as_ptr(),
            dwdx.as_ptr(),
            x.as_ptr(),
            v.as_ptr(),
            h.as_ptr(),
            rho.as_ptr(),
            c.as_ptr(),
            mass.as_ptr(),
            coef.0,
            coef.1,
            coef.2,
            dvdt.as_mut_ptr(),
            dedt.as_mut_ptr(),
        )
    }
}

pub fn strength_rates(
    dim: usize,
    nreal: usize,
    pi: &[i32],
    pj: &[i32],
    dwdx: &[f64],
    mass: &[f64],
    rho: &[f64],
    v: &[f64],
    mat: &[i32],
    mt: &MatTable,
    tau: &[f64],
    eps: &mut [f64],
    rot: &mut [f64],
    dtau: &mut [f64],
    dedt: &mut [f64],
) {
    let nt = mass.len();
    chk("tau", tau.len(), NSTR * nt);
    chk("eps", eps.len(), NSTR * nt);
    chk("rot", rot.len(), 3 * nt);
    chk("dtau", dtau.len(), NSTR * nreal);
    chk("dedt", dedt.len(), nreal);
    assert!(nreal <= nt, "legacy call: nreal exceeds ntotal");
    chk("dwdx", dwdx.len(), dim * pi.len());
    chk("rho", rho.len(), nt);
    chk("v", v.len(), dim * nt);
    chk("mat", mat.len(), nt);
    chk_mat(mt, &mat[..nt]);
    chk_pairs(pi, pj, nt);
    unsafe {
        ffi::sph_strength_rates(
            n32(dim),
            n32(nt),
            n32(nreal),
            n32(pi.len()),
            pi.as_ptr(),
            pj.as_ptr(),
            dwdx.as_ptr(),
            mass.as_ptr(),
            rho.as_ptr(),
            v.as_ptr(),
            mat.as_ptr(),
            n32(mt.nmat()),
            mt.mpar.as_ptr(),
            tau.as_ptr(),
            eps.as_mut_ptr(),
            rot.as_mut_ptr(),
            dtau.as_mut_ptr(),
            dedt.as_mut_ptr(),
        )
    }
}

pub fn strength_yield(mat: &[i32], mt: &MatTable, p: &[f64], tau: &mut [f64]) {
    let n = mat.len();
    chk("p", p.len(), n);
    chk("tau", tau.len(), NSTR * n);
    chk_mat(mt, mat);
    unsafe {
        ffi::sph_strength_yield(n32(n), mat.as_ptr(), n32(mt.nmat()), mt.mpar.as_ptr(), p.as_ptr(), tau.as_mut_ptr())
    }
}

pub fn penalty_force(
    dim: usize,
    pi: &[i32],
    pj: &[i32],
    x: &[f64],
    h: &[f64],
    mass: &[f64],
    mat: &[i32],
    mt: &MatTable,
    pbar: f64,
    n1: i32,
    n2: i32,
    dvdt: &mut [f64],
) {
    let nt = mass.len();
    chk("x", x.len(), dim * nt);
    chk("dvdt", dvdt.len(), dim * nt);
    chk("h", h.len(), nt);
    chk("mat", mat.len(), nt);
    chk_mat(mt, &mat[..nt]);
    chk_pairs(pi, pj, nt);
    unsafe {
        ffi::sph_penalty_force(
            n32(dim),
            n32(nt),
            n32(pi.len()),
            pi.as_ptr(),
            pj.as_ptr(),
            x.as_ptr(),
            h.as_ptr(),
            mass.as_ptr(),
            mat.as_ptr(),
            n32(mt.nmat()),
            mt.group.as_ptr(),
            pbar,
            n1,
            n2,
            dvdt.as_mut_ptr(),
        )
    }
}

/// Wall segments as the boundary routines take them: `seg(3*dim, nseg)` (start, end, inward
/// unit normal) and the end-node flag of each.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Segments {
    pub seg: Vec<f64>,
    pub endnode: Vec<i32>,
}

impl Segments {
    pub fn len(&self) -> usize {
        self.endnode.len()
    }
    pub fn is_empty(&self) -> bool {
        self.endnode.is_empty()
    }
}

pub fn wall_force(
    dim: usize,
    x: &[f64],
    segs: &Segments,
    spacing: f64,
    r0: f64,
    dcoef: f64,
    n1: i32,
    n2: i32,
    dvdt: &mut [f64],
) {
    let n = dvdt.len() / dim;
    chk("x", x.len(), dim * n);
    chk("seg", segs.seg.len(), 3 * dim * segs.len());
    let dummy = 0.0;
    let di = 0i32;
    unsafe {
        ffi::sph_boundary_wall_force(
            n32(dim),
            n32(n),
            x.as_ptr(),
            n32(segs.len()),
            if segs.is_empty() { &dummy } else { segs.seg.as_ptr() },
            if segs.is_empty() { &di } else { segs.endnode.as_ptr() },
            spacing,
            r0,
            dcoef,
            n1,
            n2,
            dvdt.as_mut_ptr(),
        )
    }
}

/// Lists the mirror particles; returns their number (may exceed the capacity of `gsrc`).
pub fn mirror_make(
    dim: usize,
    x: &[f64],
    h: &[f64],
    kappa: f64,
    segs: &Segments,
    gsrc: &mut [i32],
    gseg: &mut [i32],
) -> usize {
    let n = h.len();
    chk("x", x.len(), dim * n);
    chk("seg", segs.seg.len(), 3 * dim * segs.len());
    let maxg = gsrc.len().min(gseg.len() / 2);
    let mut ng = 0i32;
    let mut d1 = [0i32; 2];
    let mut d2 = [0i32; 2];
    let (gp, sp) = if maxg == 0 { (d1.as_mut_ptr(), d2.as_mut_ptr()) } else { (gsrc.as_mut_ptr(), gseg.as_mut_ptr()) };
    unsafe {
        ffi::sph_boundary_mirror_make(
            n32(dim),
            n32(n),
            x.as_ptr(),
            h.as_ptr(),
            kappa,
            n32(segs.len()),
            segs.seg.as_ptr(),
            n32(maxg),
            &mut ng,
            gp,
            sp,
        )
    }
    ng as usize
}

/// The particle arrays that the mirror fill writes (slots `n..n+ng`).
pub struct MirrorArrays<'a> {
    pub x: &'a mut [f64],
    pub v: &'a mut [f64],
    pub rho: &'a mut [f64],
    pub p: &'a mut [f64],
    pub c: &'a mut [f64],
    pub e: &'a mut [f64],
    pub h: &'a mut [f64],
    pub mass: &'a mut [f64],
    pub mat: &'a mut [i32],
    pub tau: &'a mut [f64],
}

pub fn mirror_fill(dim: usize, n: usize, gsrc: &[i32], gseg: &[i32], segs: &Segments, noslip: bool, a: MirrorArrays) {
    let ng = gsrc.len();
    let nt = n + ng;
    chk("gseg", gseg.len(), 2 * ng);
    chk("seg", segs.seg.len(), 3 * dim * segs.len());
    chk_idx("gsrc", gsrc, n);
    assert!(
        gseg[..2 * ng].iter().all(|&s| s >= -1 && s < segs.len() as i32) && gseg[..2 * ng].chunks(2).all(|c| c[0] >= 0),
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
    let ntau = if a.tau.is_empty() { 0 } else { nt };
    chk("tau", a.tau.len(), NSTR * ntau);
    let mut dummy = 0.0;
    unsafe {
        ffi::sph_boundary_mirror_fill(
            n32(dim),
            n32(nt),
            n32(n),
            n32(ng),
            gsrc.as_ptr(),
            gseg.as_ptr(),
            n32(segs.len()),
            segs.seg.as_ptr(),
            i32::from(noslip),
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
            mptr_or_dummy(a.tau, &mut dummy),
        )
    }
}

pub fn mirror_copy(n: usize, gsrc: &[i32], f: &mut [f64]) {
    let nt = n + gsrc.len();
    chk("f", f.len(), nt);
    chk_idx("gsrc", gsrc, n);
    unsafe { ffi::sph_boundary_mirror_copy(n32(nt), n32(n), n32(gsrc.len()), gsrc.as_ptr(), f.as_mut_ptr()) }
}

pub fn smoothing_density(dim: usize, rho: &[f64], h0: &[f64], rho0: &[f64], h: &mut [f64]) {
    let n = h.len();
    chk("rho", rho.len(), n);
    chk("h0", h0.len(), n);
    chk("rho0", rho0.len(), n);
    unsafe { ffi::sph_smoothing_density(n32(dim), n32(n), rho.as_ptr(), h0.as_ptr(), rho0.as_ptr(), h.as_mut_ptr()) }
}

pub fn smoothing_rate(dim: usize, rho: &[f64], h: &[f64], drho: &[f64], dhdt: &mut [f64]) {
    let n = dhdt.len();
    chk("rho", rho.len(), n);
    chk("h", h.len(), n);
    chk("drho", drho.len(), n);
    unsafe { ffi::sph_smoothing_rate(n32(dim), n32(n), rho.as_ptr(), h.as_ptr(), drho.as_ptr(), dhdt.as_mut_ptr()) }
}

pub fn smoothing_advance(dt: f64, theta: f64, dhdt: &[f64], h: &mut [f64]) {
    let n = dhdt.len();
    chk("h", h.len(), n);
    unsafe { ffi::sph_smoothing_advance(n32(n), dt, theta, dhdt.as_ptr(), h.as_mut_ptr()) }
}

pub fn xsph_average(
    dim: usize,
    pi: &[i32],
    pj: &[i32],
    w: &[f64],
    mass: &[f64],
    rho: &[f64],
    v: &[f64],
    eps: f64,
    av: &mut [f64],
) {
    let nt = mass.len();
    chk("v", v.len(), dim * nt);
    chk("av", av.len(), dim * nt);
    chk("w", w.len(), pi.len());
    chk("rho", rho.len(), nt);
    chk_pairs(pi, pj, nt);
    unsafe {
        ffi::sph_xsph_average(
            n32(dim),
            n32(nt),
            n32(pi.len()),
            pi.as_ptr(),
            pj.as_ptr(),
            w.as_ptr(),
            mass.as_ptr(),
            rho.as_ptr(),
            v.as_ptr(),
            eps,
            av.as_mut_ptr(),
        )
    }
}

pub fn detonation_light(dim: usize, x: &[f64], mat: &[i32], mt: &MatTable, xdet: &[f64], tlight: &mut [f64]) {
    let n = mat.len();
    chk("x", x.len(), dim * n);
    chk("xdet", xdet.len(), dim);
    chk("tlight", tlight.len(), n);
    chk_mat(mt, mat);
    unsafe {
        ffi::sph_detonation_light(
            n32(dim),
            n32(n),
            x.as_ptr(),
            mat.as_ptr(),
            n32(mt.nmat()),
            mt.mtype.as_ptr(),
            mt.mpar.as_ptr(),
            xdet.as_ptr(),
            tlight.as_mut_ptr(),
        )
    }
}

pub fn detonation_burn(t: f64, mat: &[i32], mt: &MatTable, tlight: &[f64], h: &[f64], width: f64, burn: &mut [f64]) {
    let n = mat.len();
    chk("tlight", tlight.len(), n);
    chk("h", h.len(), n);
    chk("burn", burn.len(), n);
    chk_mat(mt, mat);
    unsafe {
        ffi::sph_detonation_burn(
            n32(n),
            t,
            mat.as_ptr(),
            n32(mt.nmat()),
            mt.mpar.as_ptr(),
            tlight.as_ptr(),
            h.as_ptr(),
            width,
            burn.as_mut_ptr(),
        )
    }
}

/// `out(d,i) = sum_t acc_t(d,i) + grav(d)` for `i < n`; `acc` stacks `nterm` arrays of `lda`.
pub fn sum_rates(dim: usize, n: usize, lda: usize, nterm: usize, acc: &[f64], grav: &[f64], out: &mut [f64]) {
    chk("acc", acc.len(), lda * nterm);
    chk("grav", grav.len(), dim);
    chk("out", out.len(), dim * n);
    assert!(lda >= dim * n, "legacy call: lda too small");
    let dummy = 0.0;
    unsafe {
        ffi::sph_integrator_sum_rates(
            n32(dim),
            n32(n),
            n32(lda),
            n32(nterm),
            ptr_or_dummy(acc, &dummy),
            grav.as_ptr(),
            out.as_mut_ptr(),
        )
    }
}

/// The staggered leapfrog variables and their saved half-step values.
pub struct Leapfrog<'a> {
    pub rho: &'a mut [f64],
    pub e: &'a mut [f64],
    pub v: &'a mut [f64],
    pub tau: &'a mut [f64],
    pub rho_min: &'a mut [f64],
    pub e_min: &'a mut [f64],
    pub v_min: &'a mut [f64],
    pub tau_min: &'a mut [f64],
}

/// The rates the leapfrog applies.
pub struct Rates<'a> {
    pub drho: &'a [f64],
    pub de: &'a [f64],
    pub dv: &'a [f64],
    pub dtau: &'a [f64],
}

fn check_leapfrog(dim: usize, n: usize, s: &Leapfrog, r: &Rates) -> usize {
    for (name, l) in [
        ("rho", s.rho.len()),
        ("e", s.e.len()),
        ("rho_min", s.rho_min.len()),
        ("e_min", s.e_min.len()),
        ("drho", r.drho.len()),
        ("de", r.de.len()),
    ] {
        chk(name, l, n);
    }
    chk("v", s.v.len(), dim * n);
    chk("v_min", s.v_min.len(), dim * n);
    chk("dv", r.dv.len(), dim * n);
    let ntau = if s.tau.is_empty() { 0 } else { n };
    chk("tau", s.tau.len(), NSTR * ntau);
    chk("tau_min", s.tau_min.len(), NSTR * ntau);
    chk("dtau", r.dtau.len(), NSTR * ntau);
    ntau
}

pub fn integrator_predict(dim: usize, n: usize, dt_prev: f64, cont: bool, s: Leapfrog, r: Rates) {
    let ntau = check_leapfrog(dim, n, &s, &r);
    let (mut d1, mut d2, d3) = (0.0, 0.0, 0.0);
    unsafe {
        ffi::sph_integrator_predict(
            n32(dim),
            n32(n),
            n32(ntau),
            dt_prev,
            i32::from(cont),
            s.rho.as_mut_ptr(),
            r.drho.as_ptr(),
            s.e.as_mut_ptr(),
            r.de.as_ptr(),
            s.v.as_mut_ptr(),
            r.dv.as_ptr(),
            mptr_or_dummy(s.tau, &mut d1),
            ptr_or_dummy(r.dtau, &d3),
            s.rho_min.as_mut_ptr(),
            s.e_min.as_mut_ptr(),
            s.v_min.as_mut_ptr(),
            mptr_or_dummy(s.tau_min, &mut d2),
        )
    }
}

pub fn integrator_advance(
    dim: usize,
    n: usize,
    first: bool,
    dt_prev: f64,
    dt: f64,
    cont: bool,
    s: Leapfrog,
    r: Rates,
    av: &[f64],
    x: &mut [f64],
) {
    let ntau = check_leapfrog(dim, n, &s, &r);
    chk("x", x.len(), dim * n);
    let nav = if av.is_empty() { 0 } else { n };
    chk("av", av.len(), dim * nav);
    let (mut d1, d2, d3, d4) = (0.0, 0.0, 0.0, 0.0);
    let tau_min: &[f64] = s.tau_min;
    unsafe {
        ffi::sph_integrator_advance(
            n32(dim),
            n32(n),
            n32(ntau),
            i32::from(first),
            dt_prev,
            dt,
            i32::from(cont),
            s.rho.as_mut_ptr(),
            r.drho.as_ptr(),
            s.e.as_mut_ptr(),
            r.de.as_ptr(),
            s.v.as_mut_ptr(),
            r.dv.as_ptr(),
            mptr_or_dummy(s.tau, &mut d1),
            ptr_or_dummy(r.dtau, &d2),
            s.rho_min.as_ptr(),
            s.e_min.as_ptr(),
            s.v_min.as_ptr(),
            ptr_or_dummy(tau_min, &d3),
            n32(nav),
            ptr_or_dummy(av, &d4),
            x.as_mut_ptr(),
        )
    }
}

pub fn integrator_cfl(dim: usize, cfl: f64, h: &[f64], c: &[f64], v: &[f64], dv: &[f64]) -> f64 {
    let n = h.len();
    chk("c", c.len(), n);
    chk("v", v.len(), dim * n);
    chk("dv", dv.len(), dim * n);
    let mut dt = 0.0;
    unsafe { ffi::sph_integrator_cfl(n32(dim), n32(n), cfl, h.as_ptr(), c.as_ptr(), v.as_ptr(), dv.as_ptr(), &mut dt) }
    dt
}
