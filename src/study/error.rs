//! The error of a study ([`StudyError`]): the study file (file, line, item), a run's
//! folder, the collected tables, a fit or a figure.
use crate::motion::MotionError;
use crate::output::run_folder::RunFolderError;
use crate::output::OutputError;
use crate::pipeline::{PipelineError, ScenarioError};
use crate::plot::PlotError;
use std::path::PathBuf;

/// A study that cannot be planned, run, collected or drawn. Messages name the study
/// file and line, the run, or the file; [`StudyError::At`] puts the item in front of an
/// inner error (as a field, printed in the message, not a `source()`).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StudyError {
    /// A study file, a table or an option that breaks a rule; the message names the file
    /// and line or the item.
    #[error("{0}")]
    Invalid(String),
    /// A fragility fit that is not defined by its data.
    #[error("fragility: {0}")]
    Fit(String),
    /// An inner error under the item it concerns (`path:line: base scenario`,
    /// `run <id>`, `cannot create <dir>`, …).
    #[error("{item}: {error}")]
    At {
        /// The item.
        item: String,
        /// The error.
        error: Box<StudyError>,
    },
    /// A file that is not the JSON it should be.
    #[error("{}: {what}: {error}", path.display())]
    Json {
        /// The file.
        path: PathBuf,
        /// What it should be ("not valid JSON", "not a run summary").
        what: &'static str,
        /// serde_json's message.
        error: serde_json::Error,
    },
    /// A JSON file cannot be encoded.
    #[error("JSON encoding: {0}")]
    Encode(#[from] serde_json::Error),
    /// A file-system call failed (the item in front names the path, [`StudyError::At`]).
    #[error(transparent)]
    Io(#[from] std::io::Error),
    /// A scenario (the study's base).
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// A run of the study.
    #[error(transparent)]
    Pipeline(#[from] PipelineError),
    /// A record file.
    #[error(transparent)]
    Motion(#[from] MotionError),
    /// A run folder read back.
    #[error(transparent)]
    RunFolder(#[from] RunFolderError),
    /// An output that cannot be written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// A figure.
    #[error(transparent)]
    Plot(#[from] PlotError),
}

/// What study functions return.
pub type Result<T> = std::result::Result<T, StudyError>;

/// Puts an item in front of an error ([`StudyError::At`]), as `anyhow`'s `with_context`
/// did.
pub(crate) trait At<T> {
    /// The error, if any, under `item()`.
    fn at(self, item: impl FnOnce() -> String) -> Result<T>;
}

impl<T, E: Into<StudyError>> At<T> for std::result::Result<T, E> {
    fn at(self, item: impl FnOnce() -> String) -> Result<T> {
        self.map_err(|e| StudyError::At {
            item: item(),
            error: Box::new(e.into()),
        })
    }
}

/// Returns [`StudyError::Invalid`] with the formatted message.
macro_rules! bail {
    ($($t:tt)*) => {
        return Err($crate::study::error::StudyError::Invalid(format!($($t)*)))
    };
}
pub(crate) use bail;
