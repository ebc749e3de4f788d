//! Sections: fiber sections integrating uniaxial materials; elastic sections.
//!
//! A 3D beam section here has four generalised deformations and forces, in OpenSees'
//! order P, Mz, My, T:
//! `e = [ε0 (–), κz (1/m), κy (1/m), ϑ (rad/m)]`, `s = [N (N), Mz (N·m), My (N·m), T (N·m)]`.
//! Fiber strain `ε = ε0 − y κz + z κy` (OpenSees `FiberSection3d`), so `Mz = −Σ σ A y` and
//! `My = Σ σ A z`. Torsion is uncoupled and elastic (`T = GJ ϑ`).

pub mod elastic;
pub mod fiber;

use nalgebra::{Matrix4, Vector4};

/// Damage and extreme strains of a section, for the collapse criteria and the hand-off.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SectionDamage {
    /// Some fiber has yielded (steel) / passed peak (concrete) at least once.
    pub yielded: bool,
    /// Some fiber has ruptured / crushed to its residual strength.
    pub ruptured: bool,
    /// Smallest (most compressive) trial fiber strain (–); 0 for sections without fibers.
    pub min_strain: f64,
    /// Largest (most tensile) trial fiber strain (–); 0 for sections without fibers.
    pub max_strain: f64,
}

/// A 3D beam-column section with the trial/commit protocol of its materials.
pub trait Section: std::fmt::Debug + Send + Sync {
    /// Sets the trial section deformations `[ε0, κz, κy, ϑ]` and updates the resultants.
    fn set_trial_deformation(&mut self, e: &Vector4<f64>);
    /// Trial section deformations.
    fn deformation(&self) -> Vector4<f64>;
    /// Trial stress resultants `[N, Mz, My, T]`.
    fn resultant(&self) -> Vector4<f64>;
    /// Trial tangent `∂s/∂e` (4 × 4).
    fn tangent(&self) -> Matrix4<f64>;
    /// Initial tangent (4 × 4).
    fn initial_tangent(&self) -> Matrix4<f64>;
    /// Accepts the trial state.
    fn commit_state(&mut self);
    /// Returns to the last committed state.
    fn revert_to_last_commit(&mut self);
    /// Returns to the virgin state.
    fn revert_to_start(&mut self);
    /// Damage flags and extreme fiber strains.
    fn damage(&self) -> SectionDamage;
    /// A boxed copy (each integration point owns its section).
    fn boxed_clone(&self) -> Box<dyn Section>;
}

/// Inverse of a section tangent (its flexibility). Torsion is uncoupled, so the 3 × 3
/// axial-bending block and the torsional term are inverted separately. Returns `None`
/// when the block is singular.
pub fn flexibility(k: &Matrix4<f64>) -> Option<Matrix4<f64>> {
    let kb = k.fixed_view::<3, 3>(0, 0).into_owned();
    let fb = kb.try_inverse()?;
    if k[(3, 3)] == 0.0 || !k[(3, 3)].is_finite() || fb.iter().any(|x| !x.is_finite()) {
        return None;
    }
    let mut f = Matrix4::zeros();
    f.fixed_view_mut::<3, 3>(0, 0).copy_from(&fb);
    f[(3, 3)] = 1.0 / k[(3, 3)];
    Some(f)
}
