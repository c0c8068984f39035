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
