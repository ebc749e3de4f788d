//! The error of writing outputs ([`OutputError`]).
use std::path::PathBuf;

/// An output that cannot be written: a location refused before any work (empty, a file
/// where a folder is wanted, read-only, a folder of files fem2rbd did not write), or a
/// file-system call that failed, with its path.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OutputError {
    /// The output location cannot be used; the message names the option and the path.
    #[error("{0}")]
    Location(String),
    /// A file-system call failed: `action` ("cannot create", "cannot write", …) and path.
    /// The operating system's message is part of the text (not a `source()`: the binary
    /// prints the whole chain, which would repeat it).
    #[error("{action} {}: {error}", path.display())]
    Io {
        /// What was being done, e.g. "cannot create".
        action: &'static str,
        /// The path it was done to.
        path: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
    /// A file could not be serialised (JSON, glTF, …).
    #[error("{what}: {message}")]
    Encode {
        /// What was being written.
        what: String,
        /// The encoder's message.
        message: String,
    },
}

impl OutputError {
    /// A closure turning an I/O error on `path` into [`OutputError::Io`].
    pub fn io(
        action: &'static str,
        path: impl Into<PathBuf>,
    ) -> impl FnOnce(std::io::Error) -> OutputError {
        let path = path.into();
        move |error| OutputError::Io {
            action,
            path,
            error,
        }
    }
}

/// What output functions return.
pub type Result<T> = std::result::Result<T, OutputError>;
