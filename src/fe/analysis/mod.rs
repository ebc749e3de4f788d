//! Analyses: gravity (load control) and pushover (displacement control), modal
//! (eigen), Rayleigh damping, transient (Newmark + Newton with OpenSees-style
//! fallbacks), on a [`crate::fe::domain::Domain`].
pub mod algorithm;
pub mod modal;
pub mod rayleigh;
pub mod static_analysis;
pub mod transient;

pub use algorithm::{Algorithm, ConvergenceTest, IterationFailure};

/// Failure of an analysis that is not a reported stop.
#[derive(Debug, Clone, thiserror::Error, PartialEq)]
pub enum AnalysisError {
    /// Bad settings or model (names the item).
    #[error("invalid analysis input: {0}")]
    Input(String),
    /// The sparse solver could not be set up or the matrix is singular.
    #[error("linear solver: {0}")]
    Solver(#[from] crate::fe::linalg::SolverError),
    /// A static step did not converge; the domain keeps the last converged state.
    #[error("static step {step} (load factor {load_factor}) failed: {reason}")]
    StaticStepFailed {
        /// 1-based step number.
        step: usize,
        /// λ of the failed step's target.
        load_factor: f64,
        /// The last algorithm's failure.
        reason: IterationFailure,
    },
    /// The eigen solver failed.
    #[error("eigen analysis: {0}")]
    Eigen(String),
}
