//! Linear geometric transformation (OpenSees `LinearCrdTransf3d`, no rigid offsets):
//! equilibrium and compatibility in the undeformed configuration.
//!
//! `v = A Tlg u` with `Tlg` the block-diagonal rotation to local axes and `A` the chord
//! compatibility matrix ([`super::basic_from_local`]); `p = (A Tlg)ᵀ q`, `K = (A Tlg)ᵀ kb (A Tlg)`.

use super::{
    basic_from_local, local_axes, local_from_global, orthonormalize, rotation_from_vector,
    CrdTransf, DeformedFrame, Mat6, Mat6x12, TransformError,
};
use crate::fe::element::{Mat12, Vec12};
use nalgebra::{Matrix3, Vector3, Vector6};

/// State shared by the linear and P-Δ transformations.
#[derive(Debug, Clone)]
pub(crate) struct SmallDisp {
    pub xi: Vector3<f64>,
    pub xj: Vector3<f64>,
    pub r0: Matrix3<f64>,
    pub l: f64,
    /// `A Tlg`: basic deformations from global displacements.
    pub tbg: Mat6x12,
    /// Global → local rotation (12 × 12).
    pub tlg: Mat12,
    /// Trial total global displacements.
    pub u: Vec12,
    /// Committed total global displacements.
    pub u_c: Vec12,
}

impl SmallDisp {
    pub fn new(
        xi: Vector3<f64>,
        xj: Vector3<f64>,
        vecxz: Vector3<f64>,
    ) -> Result<Self, TransformError> {
        let (r0, l) = local_axes(&xi, &xj, &vecxz)?;
        let tlg = local_from_global(&r0);
        let tbg = basic_from_local(l) * tlg;
        Ok(Self {
            xi,
            xj,
            r0,
            l,
            tbg,
            tlg,
            u: Vec12::zeros(),
            u_c: Vec12::zeros(),
        })
    }

    pub fn update(&mut self, total: &Vec12) -> Result<(), TransformError> {
        if total.iter().any(|x| !x.is_finite()) {
            return Err(TransformError::NonFinite);
        }
        self.u = *total;
        Ok(())
    }

    pub fn commit(&mut self) {
        self.u_c = self.u;
    }

    pub fn revert(&mut self) {
        self.u = self.u_c;
    }

    pub fn deformed_frame(&self) -> DeformedFrame {
        let node_i = self.xi + self.u.fixed_rows::<3>(0);
        let node_j = self.xj + self.u.fixed_rows::<3>(6);
        let mean_rot: Vector3<f64> = 0.5 * (self.u.fixed_rows::<3>(3) + self.u.fixed_rows::<3>(9));
        let rm = rotation_from_vector(&mean_rot) * self.r0;
        let dx = node_j - node_i;
        let x = if dx.norm() > 0.0 {
            dx.normalize()
        } else {
            rm.column(0).into()
        };
        let axes = orthonormalize(&Matrix3::from_columns(&[
            x,
            rm.column(1).into(),
            rm.column(2).into(),
        ]));
        DeformedFrame {
            node_i,
            node_j,
            axes,
        }
    }
}

/// Linear transformation (small displacements and rotations).
#[derive(Debug, Clone)]
pub(crate) struct LinearTransf {
    core: SmallDisp,
}

impl LinearTransf {
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
}

impl CrdTransf for LinearTransf {
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
        self.core.tbg.transpose() * q
    }
    fn global_stiffness(&self, kb: &Mat6, _q: &Vector6<f64>) -> Mat12 {
        self.core.tbg.transpose() * kb * self.core.tbg
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
