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

/// An animated scene (glTF, VTK) that cannot be written: the scene breaks a rule of the
/// format (the body, ground or keyframe named), or the output cannot be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum AnimationError {
    /// The scene breaks a rule (times, poses, half extents, names); names the body or
    /// keyframe.
    #[error("{0}")]
    Scene(String),
    /// The glTF of a scene cannot be built; names the file.
    #[error("cannot write glTF {}: {error}", path.display())]
    Gltf {
        /// The `.glb` file.
        path: PathBuf,
        /// Why.
        error: Box<AnimationError>,
    },
    /// The output location or a file-system call failed.
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// `bail!`/`ensure!` of the scene checks: an [`AnimationError::Scene`] with the
/// formatted message.
macro_rules! scene_bail {
    ($($t:tt)*) => {
        return Err($crate::output::AnimationError::Scene(format!($($t)*)))
    };
}
pub(crate) use scene_bail;

/// Returns [`AnimationError::Scene`] with the message unless the condition holds.
macro_rules! scene_ensure {
    ($cond:expr, $($t:tt)*) => {
        if !$cond {
            $crate::output::error::scene_bail!($($t)*);
        }
    };
}
pub(crate) use scene_ensure;

/// What output functions return.
pub type Result<T> = std::result::Result<T, OutputError>;
