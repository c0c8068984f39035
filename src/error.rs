//! Errors and exit statuses (README "Exit statuses"):
//!
//! | status | error | what |
//! |---|---|---|
//! | 0 | — | done |
//! | 1 | `Io` | an I/O failure while a run writes (a full disk) |
//! | 2 | `Input` | refused input: a bad case file, flag, run directory or checkpoint; one line |
//! | 3 | `Unstable` | the run went unstable (or its step collapsed, or its end is out of reach); the output so far is kept |
//! | 4 | `Divergence` | a dual run found a module out of tolerance |
//! | 5 | `Stopped` | stopped cleanly by SIGINT or SIGTERM: checkpoint written, `blastsph resume DIR` continues |

use thiserror::Error;

#[derive(Debug, Error)]
pub enum SphError {
    /// Bad input: the message names the key, line or file.
    #[error("{0}")]
    Input(String),
    /// The run went unstable: the message names the step, the particle and the quantity.
    #[error("unstable: {0}")]
    Unstable(String),
    /// A dual run found a module out of tolerance.
    #[error("dual run: {0}")]
    Divergence(String),
    #[error("{0}")]
    Io(String),
    /// Stopped cleanly by a signal after a checkpoint.
    #[error("stopped {0}")]
    Stopped(String),
}

impl SphError {
    pub fn exit_code(&self) -> i32 {
        match self {
            SphError::Input(_) => 2,
            SphError::Unstable(_) => 3,
            SphError::Divergence(_) => 4,
            SphError::Io(_) => 1,
            SphError::Stopped(_) => 5,
        }
    }
}

pub fn input<S: Into<String>>(s: S) -> SphError {
    SphError::Input(s.into())
}

pub type Result<T> = std::result::Result<T, SphError>;

/// An I/O failure as the run's error (exit status 1), named by what failed: a path or a file's
/// name. `std::fs::rename(&tmp, path).io_at(path.display())` reads "PATH: the OS's message".
pub trait IoAt<T> {
    fn io_at(self, what: impl std::fmt::Display) -> Result<T>;
}

impl<T, E: std::fmt::Display> IoAt<T> for std::result::Result<T, E> {
    fn io_at(self, what: impl std::fmt::Display) -> Result<T> {
        self.map_err(|e| SphError::Io(format!("{what}: {e}")))
    }
}
