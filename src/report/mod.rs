//! The report of a run folder (`fem2rbd report RUN_DIR`): one self-contained HTML file
//! that a browser opens offline — no server, no network — holding
//!
//! * a 3-D view of the whole timeline (`keyframes.csv`: the FE stage and the ruin stage on
//!   one time axis, Tc marked) with play/pause, a time slider, speed and orbit/zoom
//!   (three.js and its OrbitControls, inlined: [`script`]); bodies coloured by element
//!   type, by story or by the state of their connections (`connections.csv`, when a ruin
//!   stage ran); the ground motion (`history.csv`) as a strip under the slider
//!   ([`ground_strip`]);
//! * the final ruin: picking a body shows its row of the body table (name, type, size,
//!   final position from `ruins.csv`);
//! * the voids of the final ruin (`voids.json`, `voids.csv`: [`voids`]) as translucent
//!   volumes in the 3-D view, with the rescuer's entry and breach markers and a voids
//!   table; picking a void or its row highlights the other;
//! * the run's key figures from `summary.json` ([`figures`]) and the run's figures
//!   `RUN_DIR/plots/*.svg`, inlined ([`plots`]).
//!
//! The data the page animates ([`data`]) is JSON inside the page, with the per-frame poses
//! as 16-bit integers in base64 ([`quantise`], [`base64`]): every keyframe is kept (no
//! decimation), each centre coordinate to half a step of 1/65 535 of the run's largest
//! span, each rotation to 6.1·10⁻⁵ rad.
//!
//! The run folder is read through [`RunFolder::load`], which checks every file; the
//! report adds its own checks (`summary.json` against the tables, `connections.csv`, the
//! plots) and every error names the file. The page is built in memory and written
//! atomically: on an error nothing is written. The same run folder gives the same bytes.
//!
//! An ensemble folder (`ensemble.json` + `member-NNN/`) gets its own page: the members'
//! final ruins overlaid, their key figures, the debris-density map and the rescue map
//! ([`ensemble`], [`rescue_map`]). A collected study folder (`results/study.json`) gets
//! one too: its fragilities, IDA and fragility figures and per intensity the
//! debris-density and rescue maps ([`study`]).
//!
//! The page is laid out in sections (`<section id=...>`: view, figures, voids, bodies, plots) so
//! that further sections of a run folder's results can be added beside them.
pub mod base64;
pub mod connections;
pub mod data;
pub mod ensemble;
pub mod figures;
pub mod ground_strip;
pub mod html;
pub mod page;
pub mod plots;
pub mod quantise;
pub mod rescue_map;
pub mod script;
pub mod study;
pub mod voids;

use crate::output::run_folder::{RunFolder, RunFolderError};
use crate::output::OutputError;
use std::path::{Path, PathBuf};

/// A report that cannot be made: the run folder cannot be read or is inconsistent (the
/// file named), or the report file cannot be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReportError {
    /// A file of the run folder cannot be read or breaks its format.
    #[error("{error}")]
    RunFolder {
        /// What `RunFolder::load` said (it names the file and line).
        error: RunFolderError,
    },
    /// A file of the run folder disagrees with the others, or a line of a file the report
    /// reads itself (`connections.csv`) breaks its format.
    #[error("{}: {message}", file.display())]
    Inconsistent {
        /// The file (with `:line` where one is meant).
        file: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A file cannot be read.
    #[error("cannot read {}: {error}", path.display())]
    Read {
        /// The file or folder.
        path: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
    /// The report file cannot be written.
    #[error("writing {}: {error}", path.display())]
    Write {
        /// The report file.
        path: PathBuf,
        /// What failed.
        error: OutputError,
    },
}

impl From<RunFolderError> for ReportError {
    fn from(error: RunFolderError) -> Self {
        ReportError::RunFolder { error }
    }
}

/// What report building returns.
pub type Result<T> = std::result::Result<T, ReportError>;

/// An [`ReportError::Inconsistent`] error about `file`.
pub(crate) fn inconsistent(file: impl Into<PathBuf>, message: impl Into<String>) -> ReportError {
    ReportError::Inconsistent {
        file: file.into(),
        message: message.into(),
    }
}

/// The report page of the run folder `dir` (of the ensemble folder `dir` when it holds
/// `ensemble.json`: [`ensemble`]; of the collected study folder `dir` when it holds
/// `results/study.json`: [`study`]), as HTML text.
pub fn report_html(dir: &Path) -> Result<String> {
    if ensemble::is_ensemble(dir) {
        return ensemble::report_html(dir);
    }
    if study::is_study(dir) {
        return study::report_html(dir);
    }
    let run = RunFolder::load(dir)?;
    let connections = connections::load(dir, &run)?;
    let plots = plots::load(dir)?;
    let voids = voids::load(dir)?;
    page::render(&run, connections.as_deref(), &plots, &voids)
}

/// Writes the report of the run or ensemble folder `dir` to `out` atomically; nothing is
/// written when the folder cannot be read. Returns the number of bytes written.
pub fn write_report(dir: &Path, out: &Path) -> Result<usize> {
    let html = report_html(dir)?;
    crate::output::write_atomic(out, html.as_bytes()).map_err(|error| ReportError::Write {
        path: out.to_path_buf(),
        error,
    })?;
    Ok(html.len())
}
