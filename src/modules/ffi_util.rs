//! Checks the per-module FFI files make before every foreign call (safe code): each argument's
//! length against the explicit shape the Fortran routine declares, indices against their bounds,
//! sizes against the C `int` range. A failed check is a bug in the caller, so it panics with the
//! argument's name instead of letting the Fortran read or write out of bounds.

use super::param::{MatTable, NPAR};

/// A size as a C `int`.
pub(crate) fn n32(n: usize) -> i32 {
    i32::try_from(n).expect("array size exceeds the C int range of the legacy core")
}

/// `name` holds at least `need` values.
pub(crate) fn chk(name: &str, len: usize, need: usize) {
    assert!(len >= need, "legacy call: array `{name}` has {len} values, the routine needs {need}");
}

/// An optional array of `per` values per particle over `n` particles (empty = absent): checks it
/// holds them all when present; returns the particle extent the Fortran declares it with, `n` or 0.
pub(crate) fn chk_opt(name: &str, len: usize, n: usize, per: usize) -> usize {
    let ext = if len == 0 { 0 } else { n };
    chk(name, len, per * ext);
    ext
}

/// Every index in `idx` lies in `0..bound` (the Fortran dereferences them).
pub(crate) fn chk_idx(name: &str, idx: &[i32], bound: usize) {
    let (lo, hi) = idx.iter().fold((i32::MAX, i32::MIN), |(a, b), &v| (a.min(v), b.max(v)));
    assert!(
        idx.is_empty() || (lo >= 0 && (hi as usize) < bound),
        "legacy call: `{name}` holds an index outside 0..{bound} (range {lo}..={hi})"
    );
}

/// A pair list over `nt` particles.
pub(crate) fn chk_pairs(pi: &[i32], pj: &[i32], nt: usize) {
    assert_eq!(pi.len(), pj.len(), "legacy call: pair_i and pair_j differ in length");
    chk_idx("pair_i", pi, nt);
    chk_idx("pair_j", pj, nt);
}

/// A material table and the materials of `mat`.
pub(crate) fn chk_mat(mt: &MatTable, mat: &[i32]) {
    let nm = mt.nmat();
    chk("mpar", mt.mpar.len(), NPAR * nm);
    chk("group", mt.group.len(), nm);
    chk_idx("mat", mat, nm);
}

/// A pointer to a slice for an argument declared `max(k,1)` long: `dummy` when empty.
pub(crate) fn ptr_or<T>(s: &[T], dummy: &T) -> *const T {
    if s.is_empty() { dummy } else { s.as_ptr() }
}

/// As [`ptr_or`], for an output.
pub(crate) fn mptr_or<T>(s: &mut [T], dummy: &mut T) -> *mut T {
    if s.is_empty() { dummy } else { s.as_mut_ptr() }
}
