//! The command line under mpirun: MPI started before anything else, one voice (rank 0) for
//! what is printed, and an end that leaves no rank waiting. Without the `mpi` feature, or in a
//! process no launcher started, every function here does nothing.

use super::Cmd;
use crate::error::{Result, SphError, input};
use crate::modules::ranks;

/// MPI while the command runs (dropping it finalises MPI).
#[cfg(feature = "mpi")]
pub(super) type Session = Option<crate::mpirun::Session>;
#[cfg(not(feature = "mpi"))]
pub(super) type Session = ();

/// Starts MPI when a launcher started this process.
pub(super) fn start() -> Session {
    #[cfg(feature = "mpi")]
    {
        crate::mpirun::start()
    }
}

/// True on the rank that prints (rank 0, or the only process).
pub(super) fn speaks() -> bool {
    ranks::is_root()
}

/// Only `run` and `resume` use the ranks, and `check` runs whole on every rank with rank 0
/// printing; every other command is refused under more than one.
pub(super) fn supported(cmd: &Cmd) -> Result<()> {
    if ranks::size() > 1 && !matches!(cmd, Cmd::Run { .. } | Cmd::Resume { .. } | Cmd::Check { .. }) {
        return Err(input(format!(
            "{} ranks: under mpirun only `blastsph run`, `resume` and `check` run; run this command in one process (or with mpirun -np 1)",
            ranks::size()
        )));
    }
    Ok(())
}

/// A rank ending with `e`: a failure this rank may have met alone (a file it could not write)
/// ends every rank at once, with the same status; the others (refused input, an unstable step,
/// a clean stop) every rank meets at the same point, and each ends by itself.
pub(super) fn end(e: &SphError) {
    #[cfg(feature = "mpi")]
    if ranks::size() > 1 && !matches!(e, SphError::Input(_) | SphError::Unstable(_) | SphError::Stopped(_)) {
        crate::mpirun::abort(e.exit_code());
    }
    let _ = e;
}

/// A panic under mpirun ends every rank (the others would wait for this one).
pub(super) fn on_panic() {
    #[cfg(feature = "mpi")]
    if ranks::size() > 1 {
        crate::mpirun::abort(70);
    }
}

/// Worker threads of a rank when `--threads` is not given: the node's cores shared among its
/// ranks (`None`: one per core, as in one process).
pub(super) fn default_threads() -> Option<usize> {
    #[cfg(feature = "mpi")]
    {
        crate::mpirun::default_threads()
    }
    #[cfg(not(feature = "mpi"))]
    None
}
