//! An element taken out of the analysis after it lost its load path: OpenSees'
//! `remove element` after a failure criterion, MSC.Marc's element deactivation.
//!
//! A removed element keeps its tag and nodes (so the equation numbering, the sparse
//! pattern and every per-element list keep their order) and contributes nothing: zero
//! resisting force, zero tangent, zero initial stiffness (so neither the stiffness-
//! proportional Rayleigh damping nor modified Newton on the initial stiffness sees it).
//! Its mass is not the element's: the model lumps every member's mass on the nodes
//! ([`crate::fe::domain::Domain::set_mass`]), so the mass stays where it was.
//! [`crate::fe::domain::Domain::remove_element`] puts it in place of the failed element.

use nalgebra::{DMatrix, DVector};

use super::{Element, ElementDamage, ElementError, EndDisplacements};
use crate::fe::domain::NDF;

/// An element removed from the analysis at `time` (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct RemovedElement {
    tag: i64,
    nodes: Vec<usize>,
    time: f64,
}

impl RemovedElement {
    /// The removed stand-in of element `tag` on `nodes`, removed at `time` (s).
    pub fn new(tag: i64, nodes: &[usize], time: f64) -> Self {
        Self {
            tag,
            nodes: nodes.to_vec(),
            time,
        }
    }

    /// When it was removed (s): the time of the last converged state before the step
    /// that it could not follow.
    pub fn time(&self) -> f64 {
        self.time
    }

    fn dofs(&self) -> usize {
        NDF * self.nodes.len()
    }
}

impl Element for RemovedElement {
    fn tag(&self) -> i64 {
        self.tag
    }
    fn nodes(&self) -> &[usize] {
        &self.nodes
    }
    fn set_trial(&mut self, _disp: &EndDisplacements<'_>) -> Result<(), ElementError> {
        Ok(())
    }
    fn resisting_force(&self) -> DVector<f64> {
        DVector::zeros(self.dofs())
    }
    fn tangent_stiffness(&self) -> DMatrix<f64> {
        DMatrix::zeros(self.dofs(), self.dofs())
    }
    fn initial_stiffness(&self) -> DMatrix<f64> {
        DMatrix::zeros(self.dofs(), self.dofs())
    }
    fn resisting_force_into(&self, out: &mut [f64]) {
        out.fill(0.0);
    }
    fn tangent_stiffness_into(&self, out: &mut [f64]) {
        out.fill(0.0);
    }
    fn has_trial_damping_stiffness(&self) -> bool {
        false
    }
    fn commit_state(&mut self) {}
    fn revert_to_last_commit(&mut self) {}
    /// A removed element has lost its load path: yielded and ruptured.
    fn damage(&self) -> ElementDamage {
        ElementDamage {
            yielded: true,
            ruptured: true,
        }
    }
    fn removed_at(&self) -> Option<f64> {
        Some(self.time)
    }
}
