//! Geometric (coordinate) transformations of 3D beam-columns, with OpenSees' conventions.
//!
//! A transformation maps the 12 global end displacements of a two-node element to the six
//! *basic* (natural) deformations of the element, free of rigid-body motion,
//!
//! `v = [elongation (m), θz_i, θz_j, θy_i, θy_j, twist (rad)]`,
//!
//! and maps the basic forces `q = [N (N), Mz_i, Mz_j, My_i, My_j, T (N·m)]` back to global
//! end forces, with the consistent tangent `K = Tᵀ kb T + K_geometric`.
//!
//! Local axes (OpenSees `geomTransf`): local x runs from node i to node j; local
//! y = vecxz × x (normalised); local z = x × y. So `vecxz` is any vector in the local x-z
//! plane, not parallel to x.
//!
//! Three kinds: [`linear::LinearTransf`] (small displacements), [`pdelta::PDeltaTransf`]
//! (adds the P-Δ geometric stiffness of the chord) and [`corotational::CorotTransf`]
//! (large displacements and rotations, OpenSees `CorotCrdTransf3d`).

pub mod corotational;
pub mod linear;
pub mod pdelta;

use crate::fe::element::{Mat12, Vec12};
use nalgebra::{Matrix3, SMatrix, Vector3, Vector6};

/// 6 × 6 matrix in the basic system (basic stiffness or flexibility).
pub(crate) type Mat6 = SMatrix<f64, 6, 6>;
/// 6 × 12 matrix: basic deformations from global end displacements.
pub(crate) type Mat6x12 = SMatrix<f64, 6, 12>;

/// Which geometric transformation an element uses (OpenSees `geomTransf` type).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TransformKind {
    /// `geomTransf Linear`: small displacements.
    Linear,
    /// `geomTransf PDelta`: linear plus the P-Δ effect of the axial force on the chord.
    PDelta,
    /// `geomTransf Corotational`: large displacements and rotations.
    Corotational,
}

/// The element's current (deformed) placement, for the hand-off to rigid bodies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeformedFrame {
    /// Current position of node i (m, global).
    pub node_i: Vector3<f64>,
    /// Current position of node j (m, global).
    pub node_j: Vector3<f64>,
    /// Current local axes as columns `[x y z]` (an orthonormal rotation matrix, global
    /// components). For the linear and P-Δ transformations the axes rotate rigidly with the
    /// chord and the mean end twist (small-rotation estimate); for the corotational
    /// transformation they are the corotated frame `e` (orthonormalised).
    pub axes: Matrix3<f64>,
}

impl DeformedFrame {
    /// Current centroid (mid-point of the deformed chord), m.
    pub fn centroid(&self) -> Vector3<f64> {
        0.5 * (self.node_i + self.node_j)
    }
}

/// Errors from building or updating a transformation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TransformError {
    /// Nodes i and j coincide.
    #[error("element has zero length (nodes i and j coincide)")]
    ZeroLength,
    /// `vecxz` is parallel to the element axis (or zero).
    #[error("vecxz {0:?} is parallel to the element's local x axis (or zero)")]
    VecxzParallel([f64; 3]),
    /// The deformed length became zero.
    #[error("deformed length became zero")]
    ZeroDeformedLength,
    /// A non-finite displacement was handed in.
    #[error("non-finite end displacement")]
    NonFinite,
}

/// A 3D geometric transformation (OpenSees `CrdTransf` for 3D frames).
///
/// Protocol: [`update`](Self::update) with the total trial end displacements, then read
/// [`basic_deformations`](Self::basic_deformations) and map forces/stiffness; then
/// [`commit`](Self::commit) or [`revert`](Self::revert).
pub trait CrdTransf: std::fmt::Debug + Send + Sync {
    /// Sets the trial configuration from the total end displacements (global; rotations
    /// are the nodal rotation DOFs, which the corotational transformation compounds as
    /// increments onto its nodal triads, as OpenSees does).
    fn update(&mut self, total: &Vec12) -> Result<(), TransformError>;
    /// Initial (undeformed) length L (m).
    fn initial_length(&self) -> f64;
    /// Basic deformations `[Δl, θz_i, θz_j, θy_i, θy_j, φ]` of the trial state.
    fn basic_deformations(&self) -> Vector6<f64>;
    /// Global end forces from the basic forces `q` (N, N·m).
    fn global_resisting_force(&self, q: &Vector6<f64>) -> Vec12;
    /// Consistent global tangent from the basic tangent `kb` and basic forces `q`
    /// (material part `Tᵀ kb T` plus the geometric part).
    fn global_stiffness(&self, kb: &Mat6, q: &Vector6<f64>) -> Mat12;
    /// Global stiffness of the undeformed configuration with basic stiffness `kb0`
    /// (no geometric part).
    fn initial_global_stiffness(&self, kb0: &Mat6) -> Mat12;
    /// Basic stiffness `kb0` carried to global axes with the *trial* configuration's
    /// basic-to-global map, without the geometric part: `Tbᵀ kb0 Tb`.
    ///
    /// This is what OpenSees's `getInitialGlobalStiffMatrix` returns when called after
    /// `update()` (CorotCrdTransf3d.cpp: `kl = Tpᵀ kb Tp; kg = Tᵀ kl T` with the `T` of
    /// the last update), and `DispBeamColumn3d::getInitialStiff` calls it on every
    /// Rayleigh damping force evaluation. `None` where it equals
    /// [`Self::initial_global_stiffness`] (linear and P-Delta transformations).
    fn trial_initial_global_stiffness(&self, _kb0: &Mat6) -> Option<Mat12> {
        None
    }
    /// Whether [`Self::trial_initial_global_stiffness`] is `Some` (without forming it).
    fn has_trial_initial_global_stiffness(&self) -> bool {
        false
    }
    /// Accepts the trial configuration.
    fn commit(&mut self);
    /// Returns to the last committed configuration.
    fn revert(&mut self);
    /// Current node positions and local axes.
    fn deformed_frame(&self) -> DeformedFrame;
    /// Undeformed local axes as columns `[x y z]`.
    fn initial_axes(&self) -> Matrix3<f64>;
    /// A boxed copy.
    fn boxed_clone(&self) -> Box<dyn CrdTransf>;
}

/// Builds a transformation of the given kind for an element from `xi` to `xj` (m, global).
pub fn new_transform(
    kind: TransformKind,
    xi: Vector3<f64>,
    xj: Vector3<f64>,
    vecxz: Vector3<f64>,
) -> Result<Box<dyn CrdTransf>, TransformError> {
    Ok(match kind {
        TransformKind::Linear => Box::new(linear::LinearTransf::new(xi, xj, vecxz)?),
        TransformKind::PDelta => Box::new(pdelta::PDeltaTransf::new(xi, xj, vecxz)?),
        TransformKind::Corotational => Box::new(corotational::CorotTransf::new(xi, xj, vecxz)?),
    })
}

/// Local axes `[x y z]` as matrix columns and the length, OpenSees convention:
/// x = (xj − xi)/L, y = vecxz × x / |vecxz × x|, z = x × y.
pub fn local_axes(
    xi: &Vector3<f64>,
    xj: &Vector3<f64>,
    vecxz: &Vector3<f64>,
) -> Result<(Matrix3<f64>, f64), TransformError> {
    let dx = xj - xi;
    let l = dx.norm();
    if !l.is_finite() || l <= 0.0 {
        return Err(TransformError::ZeroLength);
    }
    let x = dx / l;
    let y = vecxz.cross(&x);
    let yn = y.norm();
    if !yn.is_finite() || yn <= 1e-12 * vecxz.norm() || yn <= 0.0 {
        return Err(TransformError::VecxzParallel([vecxz.x, vecxz.y, vecxz.z]));
    }
    let y = y / yn;
    let z = x.cross(&y);
    Ok((Matrix3::from_columns(&[x, y, z]), l))
}

/// Skew-symmetric matrix `S(a)` with `S(a) b = a × b`.
pub fn skew(a: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// Rotation matrix of a rotation vector θ (Rodrigues / exponential map).
pub(crate) fn rotation_from_vector(theta: &Vector3<f64>) -> Matrix3<f64> {
    let t = theta.norm();
    let s = skew(theta);
    if t < 1e-8 {
        Matrix3::identity() + s + 0.5 * s * s
    } else {
        Matrix3::identity() + (t.sin() / t) * s + ((1.0 - t.cos()) / (t * t)) * s * s
    }
}

/// Gram-Schmidt orthonormalisation of a nearly orthonormal frame, keeping column x.
pub(crate) fn orthonormalize(m: &Matrix3<f64>) -> Matrix3<f64> {
    let x = m.column(0).normalize();
    let y0: Vector3<f64> = m.column(1).into();
    let y = (y0 - x * x.dot(&y0)).normalize();
    let z = x.cross(&y);
    Matrix3::from_columns(&[x, y, z])
}

/// The 6 × 12 compatibility matrix of the small-displacement basic system in local
/// coordinates: `v = A ul` with the chord rotations `(u_yj − u_yi)/L` and `(u_zj − u_zi)/L`
/// (OpenSees `LinearCrdTransf3d`):
/// `v0 = u_xj − u_xi`, `v1 = θz_i − (u_yj−u_yi)/L`, `v2 = θz_j − (u_yj−u_yi)/L`,
/// `v3 = θy_i + (u_zj−u_zi)/L`, `v4 = θy_j + (u_zj−u_zi)/L`, `v5 = θx_j − θx_i`.
pub(crate) fn basic_from_local(l: f64) -> Mat6x12 {
    let mut a = Mat6x12::zeros();
    let il = 1.0 / l;
    a[(0, 0)] = -1.0;
    a[(0, 6)] = 1.0;
    a[(1, 1)] = il;
    a[(1, 7)] = -il;
    a[(1, 5)] = 1.0;
    a[(2, 1)] = il;
    a[(2, 7)] = -il;
    a[(2, 11)] = 1.0;
    a[(3, 2)] = -il;
    a[(3, 8)] = il;
    a[(3, 4)] = 1.0;
    a[(4, 2)] = -il;
    a[(4, 8)] = il;
    a[(4, 10)] = 1.0;
    a[(5, 3)] = -1.0;
    a[(5, 9)] = 1.0;
    a
}

/// Block-diagonal 12 × 12 rotation `ul = Tlg ug` with four copies of `R0ᵀ`.
pub(crate) fn local_from_global(r0: &Matrix3<f64>) -> Mat12 {
    let mut t = Mat12::zeros();
    let rt = r0.transpose();
    for b in 0..4 {
        t.fixed_view_mut::<3, 3>(3 * b, 3 * b).copy_from(&rt);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_follow_opensees_convention() {
        // Column along global Z with vecxz = X: local y = X × Z = −Y, local z = X.
        let (r, l) = local_axes(
            &Vector3::zeros(),
            &Vector3::new(0.0, 0.0, 2.0),
            &Vector3::new(1.0, 0.0, 0.0),
        )
        .unwrap();
        assert_eq!(l, 2.0);
        assert!((r.column(1) - Vector3::new(0.0, -1.0, 0.0)).norm() < 1e-15);
        assert!((r.column(2) - Vector3::new(1.0, 0.0, 0.0)).norm() < 1e-15);
        assert!(matches!(
            local_axes(&Vector3::zeros(), &Vector3::x(), &Vector3::x()),
            Err(TransformError::VecxzParallel(_))
        ));
        assert!(matches!(
            local_axes(&Vector3::x(), &Vector3::x(), &Vector3::z()),
            Err(TransformError::ZeroLength)
        ));
    }
}
