//! The C library calls blastsph makes itself (the legacy loader's are in
//! `migration::ffi`, the signal handlers' in the `signal-hook` crate).
#![allow(unsafe_code)]

/// Gives SIGPIPE back its default action, ending the process quietly when it writes into a pipe
/// whose reader has gone (`blastsph dual … | head -1`), as other command-line tools end. The Rust
/// runtime ignores SIGPIPE, and the failed write to standard output would then panic. Called
/// first thing in `main`, before any thread starts.
pub fn default_sigpipe() {
    #[cfg(unix)]
    // SAFETY: `signal` with SIG_DFL takes no pointer and installs no handler of ours; no other
    // thread exists yet to race with the change of disposition.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// Points standard output (file descriptor 1) at `/dev/null`, for the ranks after the first of an
/// MPI run: rank 0 prints for the run, and a legacy routine's own `write(*,*)` (Fortran unit 6,
/// descriptor 1) would otherwise repeat once per rank. Standard error stays. Returns whether the
/// descriptor was replaced.
pub fn silence_stdout() -> bool {
    #[cfg(unix)]
    {
        use std::io::Write;
        let _ = std::io::stdout().flush();
        // SAFETY: `open` takes a NUL-terminated literal path; `dup2` and `close` act on
        // descriptors this process owns (the one `open` returned, and 1, which `dup2` replaces
        // atomically for every thread).
        unsafe {
            let fd = libc::open(c"/dev/null".as_ptr(), libc::O_WRONLY);
            if fd < 0 {
                return false;
            }
            let ok = libc::dup2(fd, 1) >= 0;
            libc::close(fd);
            ok
        }
    }
    #[cfg(not(unix))]
    false
}
