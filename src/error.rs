//! Errors. `Input` errors (bad case files, bad flags) end the program with status 2 and one line;
//! `Unstable` ends a run with status 3 after the output written so far is flushed.

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
}

impl SphError {
    pub fn exit_code(&self) -> i32 {
        match self {
            SphError::Input(_) => 2,
            SphError::Unstable(_) => 3,
            SphError::Divergence(_) => 4,
            SphError::Io(_) => 1,
        }
    }
}

pub fn input<S: Into<String>>(s: S) -> SphError {
    SphError::Input(s.into())
}

pub type Result<T> = std::result::Result<T, SphError>;
