//! Analyses: gravity (load control) and pushover (displacement control), modal
//! (eigen), Rayleigh damping, transient (Newmark + Newton with OpenSees-style
//! fallbacks), on a [`crate::fe::domain::Domain`].
//!
//! Typical sequence (as `tests/fixtures/opensees-frame3/run_frame3.py`):
//!
//! ```text
//! let mut d = Domain::new();                      // add_node, fix, set_mass,
//!                                                 // add_element, add_nodal_load (gravity)
//! let modes = modal::modal_analysis(&mut d, &ModalSettings { modes: 3, ..Default::default() })?;
//! static_analysis::load_control(&mut d, &LoadControl::default())?;   // 10 steps, 1e-10/50
//! d.load_const();                                 // gravity held, λ = 0, t = 0
//! let damping = RayleighDamping::default_for_period(modes.periods[0])?;  // 5 % at T1, T1/3
//! let settings = TransientSettings { dt: 0.005, t_end: 53.45, ..Default::default() };
//! let result = transient::run_transient(&mut d, Some(damping), &|t| motion.accel(t),
//!                                       &settings, &mut |step, domain| StepControl::Continue)?;
//! match result.stop { StopReason::Completed | StopReason::Diverged { .. } | StopReason::Stopped { .. } => .. }
//! ```
//!
//! All sparse work goes through [`crate::fe::linalg`]: the matrix pattern and the
//! symbolic LU are computed once per analysis and reused by every iteration and step.
pub mod algorithm;
pub mod building_modes;
pub mod lanczos;
pub mod modal;
pub mod rayleigh;
mod ritz;
mod shift_invert;
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
