//! Errors for people: every error names what was wrong (file, field, allowed range) so that a
//! user can fix the input without reading the source.

use std::path::Path;

/// The one error type of the library.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad user input: a file or parameter that is malformed or out of range (exit code 2).
    #[error("{source_name}: field `{field}`: {message}")]
    Input {
        /// The file (or "command line") the bad value came from.
        source_name: String,
        /// The field or option that is wrong.
        field: String,
        /// What is wrong, with the allowed range.
        message: String,
    },
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The path that failed.
        path: String,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A mesh that cannot be used (inverted element, empty node set, ...).
    #[error("mesh: {0}")]
    Mesh(String),
    /// A numerical failure (no convergence, factorisation failure, instability).
    #[error("numerical: {0}")]
    Numerical(String),
    /// The user asked the run to stop (Ctrl-C, SIGTERM) before it reached a point it could
    /// keep: what it wrote is flushed, and the message says what can be resumed (exit code 130,
    /// the shell's code for an interrupted command).
    #[error("interrupted: {0}")]
    Interrupted(String),
}

impl Error {
    /// Shorthand for an [`Error::Input`].
    pub fn input(
        source_name: impl Into<String>,
        field: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        Error::Input {
            source_name: source_name.into(),
            field: field.into(),
            message: message.into(),
        }
    }

    /// Shorthand for an [`Error::Io`] on `path`.
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        Error::Io {
            path: path.display().to_string(),
            source,
        }
    }

    /// Process exit code: 2 for bad input (as the issues require), 130 for an interrupted run,
    /// 1 otherwise.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Input { .. } | Error::Mesh(_) => 2,
            Error::Interrupted(_) => 130,
            _ => 1,
        }
    }
}

/// Library result type.
pub type Result<T> = std::result::Result<T, Error>;
