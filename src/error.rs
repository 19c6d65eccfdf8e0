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
    /// A file could not be read or written: the path as the user named it (a hidden stage
    /// folder's name replaced by its target's) and the failure in words, without the raw OS
    /// error number.
    #[error("{path}: {}", io_words(.source))]
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
            path: user_path(path),
            source,
        }
    }

    /// A failed read of an input file the user named: a path that names no file, or a
    /// folder, is a mistake in the input (exit 2); any other failure is I/O (exit 1), as the
    /// bad-input table (tests/cli_bad_input.rs) holds for every command.
    pub fn reading(path: &Path, source: std::io::Error) -> Self {
        use std::io::ErrorKind as K;
        match source.kind() {
            K::NotFound => Error::input(
                user_path(path),
                "file",
                "does not exist: expected an existing input file (check the path)",
            ),
            K::IsADirectory => Error::input(
                user_path(path),
                "file",
                "is a folder: expected an input file",
            ),
            _ => Error::io(path, source),
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

/// `path` as the user named it: a component that is an output's hidden stage
/// (`.<name>.partial-<pid>`, `crate::output`) becomes `<name>`, the file or folder the user
/// asked for, so that an error while writing names the user's path, not the temporary one.
pub fn user_path(path: &Path) -> String {
    path.components()
        .map(|c| {
            let part = c.as_os_str().to_string_lossy();
            match stage_target_name(&part) {
                Some(name) => name.to_string(),
                None => part.to_string(),
            }
        })
        .collect::<std::path::PathBuf>()
        .display()
        .to_string()
}

/// The target name of a stage component `.<name>.partial-<pid>`, or None.
fn stage_target_name(part: &str) -> Option<&str> {
    let rest = part.strip_prefix('.')?;
    let at = rest.rfind(".partial-")?;
    let pid = &rest[at + ".partial-".len()..];
    (at > 0 && !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit())).then(|| &rest[..at])
}

/// An I/O failure in words: what the file system said, without Rust's " (os error N)" suffix,
/// and with what to do for the failures a user can fix.
pub fn io_words(e: &std::io::Error) -> String {
    use std::io::ErrorKind as K;
    let words = match e.kind() {
        K::NotFound => "no such file or folder",
        K::PermissionDenied => "permission denied",
        K::AlreadyExists => "already exists (choose another name or remove it)",
        K::DirectoryNotEmpty => "a folder that is not empty is in the way",
        K::NotADirectory => "a part of this path is a file, not a folder",
        K::IsADirectory => "is a folder, where a file is needed",
        K::ReadOnlyFilesystem => "the file system is read-only",
        K::StorageFull => "no space left on the disk",
        K::InvalidInput => "the file system refused this path (invalid argument)",
        K::InvalidData => "the file is not valid text or data",
        K::UnexpectedEof => "the file ends early",
        _ => "",
    };
    if !words.is_empty() {
        return words.to_string();
    }
    let text = e.to_string();
    match text.find(" (os error ") {
        Some(at) => text[..at].to_string(),
        None => text,
    }
}

/// Library result type.
pub type Result<T> = std::result::Result<T, Error>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stage_component_is_named_as_the_users_path() {
        assert_eq!(
            user_path(Path::new("runs/.case3.partial-4242/histories.csv")),
            "runs/case3/histories.csv"
        );
        assert_eq!(user_path(Path::new("./.out.json.partial-7")), "./out.json");
        // Not stages: no pid, a non-numeric pid, nothing before the suffix.
        for p in [".a.partial-", ".a.partial-x1", "..partial-3", "a.partial-3"] {
            assert_eq!(user_path(Path::new(p)), p);
        }
    }

    #[test]
    fn an_io_error_carries_no_raw_os_number() {
        for code in [17, 22, 39, 2, 13, 20, 21, 28, 30, 5] {
            let e = Error::io(Path::new("x"), std::io::Error::from_raw_os_error(code));
            let text = e.to_string();
            assert!(!text.contains("os error"), "{code}: {text}");
            assert!(text.len() > "x: ".len(), "{code}: {text}");
        }
    }
}
