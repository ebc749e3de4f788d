//! Uniaxial materials with OpenSees' laws, parameter meanings and trial/commit protocol.
//! Sign convention as in OpenSees: tension positive, compression negative.

/// Damage flags a material reports, used by the collapse criteria and the hand-off.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MaterialDamage {
    /// Steel has yielded / concrete has passed its peak compressive strength at least once.
    pub yielded: bool,
    /// Steel has ruptured / concrete is crushed to its residual strength.
    pub ruptured: bool,
}

/// A uniaxial stress–strain law (strain in –, stress and moduli in Pa).
///
/// Protocol (as OpenSees `UniaxialMaterial`): [`set_trial_strain`](Self::set_trial_strain)
/// any number of times, then either [`commit_state`](Self::commit_state) when the global
/// step converged or [`revert_to_last_commit`](Self::revert_to_last_commit) when it failed.
pub trait UniaxialMaterial: std::fmt::Debug + Send + Sync {
    /// Sets the trial strain and updates the trial stress and tangent from the last
    /// committed state.
    fn set_trial_strain(&mut self, strain: f64);
    /// Trial strain (–).
    fn strain(&self) -> f64;
    /// Trial stress (Pa).
    fn stress(&self) -> f64;
    /// Trial tangent modulus dσ/dε (Pa).
    fn tangent(&self) -> f64;
    /// Initial tangent modulus (Pa).
    fn initial_tangent(&self) -> f64;
    /// Accepts the trial state as the new committed state.
    fn commit_state(&mut self);
    /// Discards the trial state.
    fn revert_to_last_commit(&mut self);
    /// Returns to the virgin state.
    fn revert_to_start(&mut self);
    /// A boxed copy (each fiber owns its own material state).
    fn boxed_clone(&self) -> Box<dyn UniaxialMaterial>;
    /// Damage reached so far (committed history).
    fn damage(&self) -> MaterialDamage {
        MaterialDamage::default()
    }
}
