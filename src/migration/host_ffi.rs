//! The run-time side of host mode that touches raw memory: loads `DIR/libhost.so` (the user's
//! program with its mapped routines interposed, [`super::builder`]), sets the hook its wrappers
//! call, starts its main program, and reads and writes the argument values whose addresses the
//! wrappers hand over. The logic is in `legacy/host.rs`; this file and `ffi.rs` hold the only
//! `unsafe` code of the migration path.
#![allow(unsafe_code)]

use super::bind::Buf;
use super::builder::HOOK_SYMBOL;
use super::vocab::Kind;
use crate::error::{Result, input};
use libloading::os::unix::{Library, RTLD_LOCAL, RTLD_NOW, Symbol};
use std::ffi::{CString, c_void};
use std::os::raw::{c_char, c_int};
use std::path::Path;

/// What the wrappers call: the routine's index in the build, 0 before the call and 1 after
/// it, and the addresses of its arguments.
pub type Hook = extern "C" fn(routine: c_int, phase: c_int, args: RawArgs);

/// The wrapper's array of argument addresses, as the hook receives it.
#[repr(transparent)]
pub struct RawArgs(*mut *mut c_void);

/// The address of one actual argument, as a wrapper handed it over (made only by [`arg_ptrs`]).
#[derive(Clone, Copy)]
pub struct ArgPtr(*mut c_void);

/// Loads the host library `lib`, sets its hook and runs its main program with `argv` (the
/// program's name first): the main program's return value. A `STOP` in the program ends the
/// process inside this call (an `atexit` handler, [`at_exit`], sees it).
pub fn run_main(lib: &Path, argv: &[String], hook: Hook) -> Result<i32> {
    // SAFETY: the library is the build's own libhost.so, whose initialisers are gfortran's and
    // the generated wrappers' (none); it stays loaded for the rest of the process (forgotten
    // below), as the program's atexit handlers and Fortran units may refer to it.
    let l = unsafe { Library::open(Some(lib), RTLD_NOW | RTLD_LOCAL) }
        .map_err(|e| input(format!("{}: {e}", lib.display())))?;
    let name = format!("{HOOK_SYMBOL}\0");
    // SAFETY: the symbol is the wrappers' hook variable, a C function pointer (`bs_hook_t`),
    // which has the layout of `Option<Hook>`; nothing reads it until main starts below.
    unsafe {
        let var: Symbol<*mut Option<Hook>> =
            l.get(name.as_bytes()).map_err(|e| input(format!("{}: {e}", lib.display())))?;
        **var = Some(hook);
    }
    let args: Vec<CString> = argv.iter().map(|a| CString::new(a.as_str()).unwrap_or_default()).collect();
    let mut ptrs: Vec<*const c_char> = args.iter().map(|a| a.as_ptr()).collect();
    ptrs.push(std::ptr::null());
    // SAFETY: `main` is gfortran's C main of the user's program (int main(int, char **));
    // argv is a null-terminated array of C strings that outlive the call.
    let rc = unsafe {
        let main: Symbol<unsafe extern "C" fn(c_int, *const *const c_char) -> c_int> =
            l.get(b"main\0").map_err(|e| input(format!("{}: {e}", lib.display())))?;
        main(args.len() as c_int, ptrs.as_ptr())
    };
    std::mem::forget(l);
    Ok(rc)
}

/// The `n` argument addresses a wrapper hands over.
pub fn arg_ptrs(args: RawArgs, n: usize) -> Vec<ArgPtr> {
    if args.0.is_null() || n == 0 {
        return Vec::new();
    }
    // SAFETY: the wrapper's array `a` holds exactly the routine's number of arguments (the
    // build generated it from the same routine list), and lives for the hook's call.
    unsafe { std::slice::from_raw_parts(args.0, n).iter().map(|p| ArgPtr(*p)).collect() }
}

/// `n` values of `kind` at the address `p` of an actual argument (None for a null address).
/// The caller bounds `n` by what the routine's own counts (`ntotal`, `niac`) say the array
/// holds, at most the build's `maxn` or `max_interaction` (times `dim`).
pub fn read(p: ArgPtr, kind: Kind, n: usize) -> Option<Buf> {
    let p = p.0;
    if p.is_null() {
        return None;
    }
    // SAFETY: `p` is the address the caller passed for this dummy, an array of at least `n`
    // values of this kind in a Liu-style code (declared with maxn or max_interaction, and
    // filled up to its ntotal or niac); the values are copied out before anything else runs.
    Some(unsafe {
        match kind {
            Kind::Real => Buf::R(std::slice::from_raw_parts(p as *const f64, n).to_vec()),
            Kind::Int => Buf::I(std::slice::from_raw_parts(p as *const i32, n).to_vec()),
        }
    })
}

/// Writes `b` at the address `p` of an actual argument (the Rust twins' outputs in place of
/// the routine's); nothing for a null address.
pub fn write(p: ArgPtr, b: &Buf) {
    let p = p.0;
    if p.is_null() {
        return;
    }
    // SAFETY: as [`read`]: `p` holds at least as many values as the routine itself wrote
    // there, and `b` holds no more (its counts are the routine's, or the twin's pairs checked
    // against max_interaction by the caller).
    unsafe {
        match b {
            Buf::R(v) => std::ptr::copy_nonoverlapping(v.as_ptr(), p as *mut f64, v.len()),
            Buf::I(v) => std::ptr::copy_nonoverlapping(v.as_ptr(), p as *mut i32, v.len()),
        }
    }
}

/// Registers `f` to run at `exit` (a `STOP` in the user's program).
pub fn at_exit(f: extern "C" fn()) {
    // SAFETY: `f` is an `extern "C" fn()` that lives as long as the program.
    unsafe {
        libc::atexit(f);
    }
}

/// Ends the process now with `code`, after the Fortran units are flushed (from an exit
/// handler: the status of the program's `STOP` is replaced).
pub fn exit_now(code: i32) -> ! {
    super::ffi::flush_fortran_at_exit();
    // SAFETY: `_exit` ends the process at once; the Fortran units were flushed above and the
    // report written by the caller.
    unsafe { libc::_exit(code) }
}
