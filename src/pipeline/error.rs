//! The errors of a scenario run: [`ScenarioError`] (the scenario file) and
//! [`PipelineError`] (a stage of the run, the scenario or input file named).
use crate::collapse::CollapseError;
use crate::fe::FeError;
use crate::mapping::MappingError;
use crate::model::limits::{InputFileError, LimitError, RangeError};
use crate::model::ModelError;
use crate::motion::{Direction, MotionError};
use crate::output::run_folder::RunFolderError;
use crate::output::{AnimationError, OutputError};
use crate::ruin::groups::GroupError;
use crate::ruin::stage::StageError;
use std::path::PathBuf;

/// A scenario file that cannot be used: unreadable, TOML that does not parse, or a value
/// or reference that breaks the format. Every variant names the file (and the line, the
/// item or the referenced file).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ScenarioError {
    /// The scenario file is missing, not a file, or too large.
    #[error(transparent)]
    File(#[from] InputFileError),
    /// The scenario file cannot be read.
    #[error("cannot read scenario file {}: {error}", path.display())]
    Read {
        /// The scenario file.
        path: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
    /// TOML that does not parse or does not follow the format.
    #[error("{file}:{line}:{column}: {message}")]
    Syntax {
        /// The scenario file.
        file: String,
        /// Line (1-based; 0 when unknown).
        line: usize,
        /// Column (1-based; 0 when unknown).
        column: usize,
        /// The parser's message.
        message: String,
    },
    /// A file the scenario refers to (model, record) cannot be used.
    #[error("{item}: {error}")]
    Input {
        /// The scenario file and its item (`model`, `ground_motion[i]`).
        item: String,
        /// Why.
        error: InputFileError,
    },
    /// A value outside its physical range.
    #[error("{file}: {error}")]
    Range {
        /// The scenario file.
        file: String,
        /// The value, its item and its range.
        error: RangeError,
    },
    /// A value or combination of values that the format does not allow.
    #[error("{file}: {message}")]
    Invalid {
        /// The scenario file.
        file: String,
        /// The item and what is wrong.
        message: String,
    },
}

/// A run that failed: the scenario, one of its input files, or a stage. Messages name
/// the scenario or input file and the stage; inner errors are fields named `error`
/// (printed in the message, not as a `source()`).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PipelineError {
    /// The scenario file.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// The model file.
    #[error("model {}: {error}", path.display())]
    Model {
        /// The model file.
        path: PathBuf,
        /// Why it cannot be used.
        error: Box<ModelError>,
    },
    /// A ground-motion record of the scenario.
    #[error("{}: ground_motion {direction}: {error}", scenario.display())]
    Record {
        /// The scenario file.
        scenario: PathBuf,
        /// The component.
        direction: Direction,
        /// Why the record cannot be used.
        error: Box<MotionError>,
    },
    /// A record file gave no record.
    #[error("{}: no record read", .0.display())]
    NoRecord(PathBuf),
    /// A record cannot be scaled to its PGA.
    #[error("{}: scaling to {pga_g} g: {error}", file.display())]
    Scale {
        /// The record file.
        file: PathBuf,
        /// The target PGA, g.
        pga_g: f64,
        /// Why.
        error: Box<MotionError>,
    },
    /// The ground motion (time scaling, integration).
    #[error("{what}: {error}")]
    Motion {
        /// What was being done.
        what: &'static str,
        /// Why it failed.
        error: Box<MotionError>,
    },
    /// The run is larger than a resource bound (steps, samples, substeps).
    #[error(transparent)]
    Limit(#[from] LimitError),
    /// The model's elements cannot be mapped to bodies.
    #[error("mapping {}: {error}", path.display())]
    Mapping {
        /// The model file.
        path: PathBuf,
        /// Why.
        error: Box<MappingError>,
    },
    /// The mapped bodies cannot be posed at the hand-off.
    #[error(transparent)]
    HandOff(Box<MappingError>),
    /// The contact search between the bodies failed.
    #[error(transparent)]
    Contacts(#[from] crate::ruin::RuinError),
    /// The model's groups have no connection strengths.
    #[error("{}: {error}", path.display())]
    Groups {
        /// The model file.
        path: PathBuf,
        /// Why.
        error: Box<GroupError>,
    },
    /// The collapse monitor cannot be set up.
    #[error(transparent)]
    Collapse(#[from] CollapseError),
    /// An FE stage failed (building the domain, the time history, capacities).
    #[error("{stage}: {error}")]
    Fe {
        /// The stage ("building the FE domain", "FE-derived connection strengths", …).
        stage: &'static str,
        /// Why.
        error: Box<FeError>,
    },
    /// The FE time history failed to run (divergence is not an error, see
    /// `StopReason::Diverged`).
    #[error(transparent)]
    FeRun(Box<FeError>),
    /// The FE domain lacks a node of the model.
    #[error("{at}node {node} is not in the FE domain")]
    MissingNode {
        /// "hand-off: " or "".
        at: &'static str,
        /// The node's tag.
        node: u32,
    },
    /// The secant velocity has no keyframe before Tc.
    #[error("secant velocity: no keyframe before Tc = {tc_s} s")]
    NoKeyframe {
        /// Tc, s.
        tc_s: f64,
    },
    /// The ruin stage failed.
    #[error("{stage}: {error}")]
    Ruin {
        /// "building the ruin stage" or "running the ruin stage".
        stage: &'static str,
        /// Why.
        error: Box<StageError>,
    },
    /// The ruin stage blew up (a non-finite pose); names the body, the time and the
    /// settings that bear on it.
    #[error("{}: the ruin stage blew up: {message}", scenario.display())]
    BlewUp {
        /// The scenario file.
        scenario: PathBuf,
        /// The body, the time and the settings.
        message: String,
    },
    /// `collapse.glb` cannot be rebuilt from the run's own tables.
    #[error("cannot build collapse.glb from the run's own tables: {0}")]
    OwnTables(Box<RunFolderError>),
    /// `collapse.glb` cannot be encoded.
    #[error("cannot build collapse.glb from the run's own tables: {0}")]
    OwnScene(Box<AnimationError>),
    /// The rescue analysis (`voids.csv`, `voids.json`, `rubble_height.csv`) of the run's
    /// own tables failed.
    #[error("rescue analysis of the run's own tables: {0}")]
    Rescue(Box<crate::rescue::RescueError>),
    /// The run folder cannot be written.
    #[error("cannot write the run folder {}: {error}", path.display())]
    RunFolder {
        /// The run folder.
        path: PathBuf,
        /// Why.
        error: Box<OutputError>,
    },
    /// An output file cannot be written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// A JSON file cannot be encoded.
    #[error("JSON encoding: {0}")]
    Encode(#[from] serde_json::Error),
    /// An ensemble needs at least one member.
    #[error("an ensemble needs at least 1 member")]
    NoMembers,
    /// An ensemble over [`super::ensemble::MAX_MEMBERS`] members.
    #[error("--ensemble {0} exceeds the limit of {max} members (docs/reliability.md, resource bounds)", max = super::ensemble::MAX_MEMBERS)]
    TooManyMembers(usize),
    /// An ensemble member failed.
    #[error("ensemble member {member}: {error}")]
    Member {
        /// The member's number.
        member: usize,
        /// Why.
        error: Box<PipelineError>,
    },
    /// An ensemble member did not run (its thread stopped).
    #[error("member {0} did not run")]
    NotRun(usize),
}

/// What the pipeline returns.
pub type Result<T> = std::result::Result<T, PipelineError>;
