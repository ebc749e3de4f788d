//! P-Δ geometric transformation (OpenSees `PDeltaCrdTransf3d`, no rigid offsets): the
//! linear transformation plus the moment of the axial force N on the relative transverse
//! end displacements of the chord, in local axes:
//!
//! `p_y,i += N (u_yj − u_yi)/L`, `p_y,j −= …`, same for z; geometric stiffness `N/L` on the
//! transverse translations (`[1 −1; −1 1] N/L` for y and for z).

use super::linear::SmallDisp;
use super::{CrdTransf, DeformedFrame, Mat6, TransformError};
use crate::fe::element::{Mat12, Vec12};
use nalgebra::{Matrix3, Vector3, Vector6};

/// P-Δ transformation.
#[derive(Debug, Clone)]
pub(crate) struct PDeltaTransf {
    core: SmallDisp,
}

impl PDeltaTransf {
    /// New transformation for an element from `xi` to `xj` (m) with the x-z plane vector `vecxz`.
    pub fn new(
        xi: Vector3<f64>,
        xj: Vector3<f64>,
        vecxz: Vector3<f64>,
    ) -> Result<Self, TransformError> {
        Ok(Self {
            core: SmallDisp::new(xi, xj, vecxz)?,
        })
    }

    /// Local geometric stiffness `N/L` on the transverse translations.
    fn local_geometric(&self, n: f64) -> Mat12 {
        let mut kl = Mat12::zeros();
        let k = n / self.core.l;
        for (a, b) in [(1, 7), (2, 8)] {
            kl[(a, a)] += k;
            kl[(b, b)] += k;
            kl[(a, b)] -= k;
            kl[(b, a)] -= k;
        }
        kl
    }
}

impl CrdTransf for PDeltaTransf {
    fn update(&mut self, total: &Vec12) -> Result<(), TransformError> {
        self.core.update(total)
    }
    fn initial_length(&self) -> f64 {
        self.core.l
    }
    fn basic_deformations(&self) -> Vector6<f64> {
        self.core.tbg * self.core.u
    }
    fn global_resisting_force(&self, q: &Vector6<f64>) -> Vec12 {
        let ul = self.core.tlg * self.core.u;
        let kg = self.local_geometric(q[0]);
        self.core.tbg.transpose() * q + self.core.tlg.transpose() * (kg * ul)
    }
    fn global_stiffness(&self, kb: &Mat6, q: &Vector6<f64>) -> Mat12 {
        let kg = self.local_geometric(q[0]);
        self.core.tbg.transpose() * kb * self.core.tbg
            + self.core.tlg.transpose() * kg * self.core.tlg
    }
    fn initial_global_stiffness(&self, kb0: &Mat6) -> Mat12 {
        self.core.tbg.transpose() * kb0 * self.core.tbg
    }
    fn commit(&mut self) {
        self.core.commit();
    }
    fn revert(&mut self) {
        self.core.revert();
    }
    fn deformed_frame(&self) -> DeformedFrame {
        self.core.deformed_frame()
    }
    fn initial_axes(&self) -> Matrix3<f64> {
        self.core.r0
    }
    fn boxed_clone(&self) -> Box<dyn CrdTransf> {
        Box::new(self.clone())
    }
}
