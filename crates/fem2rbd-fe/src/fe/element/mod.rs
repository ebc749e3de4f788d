//! Structural elements (3D, 6 DOF per node): beam-columns with two nodes (elastic,
//! displacement-based fiber with Gauss-Legendre, force-based fiber with Gauss-Lobatto
//! points) and the four-node layered shell ([`crate::fe::shell::ShellElement`]).
//!
//! The contract between elements and the analysis layer is [`Element`]: the domain
//! hands each element the trial displacements of its nodes (6 per node, in the element's
//! node order), and reads back the resisting force and tangent stiffness in global
//! coordinates, `6 n` components for `n` nodes.

use nalgebra::{DMatrix, DVector, SMatrix, SVector};

/// 12-component vector of element end quantities, global axes:
/// `[ux_i, uy_i, uz_i, rx_i, ry_i, rz_i, ux_j, uy_j, uz_j, rx_j, ry_j, rz_j]` (m, rad / N, N·m).
pub type Vec12 = SVector<f64, 12>;
/// 12 × 12 matrix in the DOF order of [`Vec12`].
pub type Mat12 = SMatrix<f64, 12, 12>;

/// Most nodes an element of the domain may have.
pub const MAX_ELEMENT_NODES: usize = 4;

/// Nodal kinematics handed to an element for one Newton iteration: `6 n` components,
/// `[ux uy uz rx ry rz]` of each of the element's `n` nodes in its node order (global).
#[derive(Debug, Clone, Copy)]
pub struct EndDisplacements<'a> {
    /// Total trial displacements and rotations of the nodes since the start (global).
    pub total: &'a [f64],
    /// Increment since the previous iteration (global). Corotational formulations
    /// compound the rotational part onto their nodal triads, as OpenSees'
    /// `CorotCrdTransf3d` does with `getIncrDeltaDisp()`.
    pub delta: &'a [f64],
}

impl EndDisplacements<'_> {
    /// The totals of a two-node element as a [`Vec12`] (panics on another length).
    pub fn total12(&self) -> Vec12 {
        Vec12::from_column_slice(self.total)
    }
}

/// A fixed-size vector as a dynamic one (the [`Element`] interface).
pub fn dvec<const N: usize>(v: &SVector<f64, N>) -> DVector<f64> {
    DVector::from_column_slice(v.as_slice())
}

/// A fixed-size matrix as a dynamic one (the [`Element`] interface).
pub fn dmat<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> DMatrix<f64> {
    DMatrix::from_column_slice(R, C, m.as_slice())
}

/// What [`Element::prepare`] forms ahead of the assembly.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Prepare {
    /// The tangent stiffness ([`Element::tangent_stiffness`]).
    Tangent,
    /// The trial-geometry damping stiffness ([`Element::damping_stiffness`]).
    Damping,
}

/// Damage state of an element, for the collapse criteria and the hand-off.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ElementDamage {
    /// Some fiber has yielded (steel) or passed peak (concrete).
    pub yielded: bool,
    /// Some steel fiber has ruptured / the section has lost its capacity.
    pub ruptured: bool,
}

/// Error from an element's state determination (e.g. the force-based element's
/// internal iterations did not converge). The analysis treats it like a failed
/// Newton iteration.
#[derive(Debug, Clone, thiserror::Error)]
#[error("element {element}: {reason}")]
pub struct ElementError {
    /// The element's tag.
    pub element: i64,
    /// What went wrong.
    pub reason: String,
}

/// A structural element with `n` nodes of 6 DOFs (`n` = 2 for beam-columns, 4 for
/// shells); vectors and matrices have `6 n` rows in the order of [`EndDisplacements`].
/// `Sync` so that the analysis can read the elements' forces and stiffnesses on several
/// threads at once ([`crate::fe::domain::Domain::map_elements`]).
pub trait Element: std::fmt::Debug + Send + Sync {
    /// The element's tag (id in the model).
    fn tag(&self) -> i64;
    /// Indices of the nodes in the domain's node arrays (end nodes i, j of a beam-column;
    /// the four corners of a shell), at most [`MAX_ELEMENT_NODES`].
    fn nodes(&self) -> &[usize];
    /// Sets the trial state from the nodal displacements.
    fn set_trial(&mut self, disp: &EndDisplacements<'_>) -> Result<(), ElementError>;
    /// Resisting force of the trial state, global axes (N, N·m), `6 n` components.
    fn resisting_force(&self) -> DVector<f64>;
    /// Tangent stiffness of the trial state, global axes (material + geometric).
    fn tangent_stiffness(&self) -> DMatrix<f64>;
    /// Stiffness of the undeformed, undamaged element (for initial-stiffness Rayleigh
    /// damping and modified Newton with the initial tangent).
    fn initial_stiffness(&self) -> DMatrix<f64>;
    /// Stiffness for the stiffness-proportional part of initial-stiffness Rayleigh
    /// damping when it follows the trial configuration, `None` (the default) when it is
    /// [`Self::initial_stiffness`]. OpenSees's `DispBeamColumn3d` re-evaluates its
    /// initial stiffness with the corotational transformation's trial geometry each time
    /// the damping force is formed (`Element::getRayleighDampingForces` →
    /// `getInitialStiff`), whereas `ForceBeamColumn3d` caches it once.
    fn damping_stiffness(&self) -> Option<DMatrix<f64>> {
        None
    }
    /// [`Self::resisting_force`] written into `out` (`6 n` components) without
    /// allocating: the form the assembly reads on every Newton iteration.
    fn resisting_force_into(&self, out: &mut [f64]) {
        out.copy_from_slice(self.resisting_force().as_slice());
    }
    /// [`Self::tangent_stiffness`] written into `out` (`(6 n)²` entries, column-major)
    /// without allocating.
    fn tangent_stiffness_into(&self, out: &mut [f64]) {
        out.copy_from_slice(self.tangent_stiffness().as_slice());
    }
    /// [`Self::damping_stiffness`] written into `out` (`(6 n)²` entries, column-major)
    /// when it is `Some`; returns whether it was (`out` is untouched otherwise).
    fn damping_stiffness_into(&self, out: &mut [f64]) -> bool {
        match self.damping_stiffness() {
            Some(k) => {
                out.copy_from_slice(k.as_slice());
                true
            }
            None => false,
        }
    }
    /// Whether [`Self::damping_stiffness`] is `Some`, without forming it.
    fn has_trial_damping_stiffness(&self) -> bool {
        self.damping_stiffness().is_some()
    }
    /// Forms the matrices of the trial state that `what` names and keeps them until the
    /// state changes, so that the reads after it are copies. A pure cache: the values read
    /// are the same bits whether or not this ran first, and on which thread
    /// ([`crate::fe::domain::Domain::prepare_elements`] runs it on the domain's threads).
    /// The default does nothing (the reads form the matrices themselves).
    fn prepare(&self, _what: Prepare) {}
    /// The time increment Δt (s) of the step about to be iterated, for materials that
    /// extrapolate their internal variables in time (IMPL-EX concrete layers,
    /// [`crate::fe::shell::layers::ConcreteIntegration`]). Default: ignored.
    fn set_time_increment(&mut self, _dt: f64) {}
    /// Accepts the trial state.
    fn commit_state(&mut self);
    /// Returns to the last committed state.
    fn revert_to_last_commit(&mut self);
    /// Damage reached so far.
    fn damage(&self) -> ElementDamage {
        ElementDamage::default()
    }
    /// The element's sections (committed state after a converged step) with their
    /// positions ξ = x/L ∈ [0, 1], in integration-point order; empty for elements without
    /// sections (elastic). Read by the FE capacity analysis ([`crate::fe::capacity`]).
    fn sections(&self) -> Vec<(f64, &dyn crate::fe::section::Section)> {
        Vec::new()
    }
    /// When the element was removed from the analysis (s), `None` while it takes part
    /// ([`removed::RemovedElement`]).
    fn removed_at(&self) -> Option<f64> {
        None
    }
}

pub mod beam;
pub mod disp_beam;
pub mod elastic_beam;
pub mod force_beam;
pub mod quadrature;
pub mod removed;

pub use beam::{BeamColumnSpec, Formulation, SectionState};
pub use disp_beam::DispBeam3d;
pub use elastic_beam::{ElasticBeam3d, ElasticProps};
pub use force_beam::{ForceBeam3d, ForceBeamOptions};
pub use removed::RemovedElement;
