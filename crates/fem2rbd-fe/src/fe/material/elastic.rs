//! Linear elastic uniaxial material, OpenSees `uniaxialMaterial Elastic $tag $E <$eta> <$Eneg>`
//! (class `ElasticMaterial`).
//!
//! σ = E·ε for ε ≥ 0 and σ = E_neg·ε for ε < 0; the tangent is E or E_neg on the same
//! split (at ε = 0 the tension modulus E, as OpenSees). OpenSees' optional viscous
//! term η·ε̇ is not modelled: this program's materials are rate independent and damping
//! comes from the Rayleigh matrix, so `eta` is accepted by [`super::build`] and ignored.

use super::MaterialError;
use super::UniaxialMaterial;

/// Linear elastic material with possibly different moduli in tension and compression.
#[derive(Debug, Clone)]
pub struct Elastic {
    /// Modulus for ε ≥ 0 (Pa).
    e_pos: f64,
    /// Modulus for ε < 0 (Pa).
    e_neg: f64,
    trial_strain: f64,
    committed_strain: f64,
}

impl Elastic {
    /// An elastic material with modulus `e` (Pa) in tension and `e_neg` (Pa) in
    /// compression (pass `e` twice for the symmetric law). Both must be finite; OpenSees
    /// allows any sign, this constructor requires `e > 0` and `e_neg > 0`.
    pub fn new(e: f64, e_neg: f64) -> Result<Self, MaterialError> {
        if !(e.is_finite() && e > 0.0) {
            return Err(MaterialError::Parameter(format!(
                "Elastic: E must be a finite positive modulus in Pa, got {e}"
            )));
        }
        if !(e_neg.is_finite() && e_neg > 0.0) {
            return Err(MaterialError::Parameter(format!(
                "Elastic: Eneg must be a finite positive modulus in Pa, got {e_neg}"
            )));
        }
        Ok(Self {
            e_pos: e,
            e_neg,
            trial_strain: 0.0,
            committed_strain: 0.0,
        })
    }

    /// Modulus in tension E (Pa).
    pub fn e(&self) -> f64 {
        self.e_pos
    }

    /// Modulus in compression E_neg (Pa).
    pub fn e_neg(&self) -> f64 {
        self.e_neg
    }
}

impl UniaxialMaterial for Elastic {
    fn set_trial_strain(&mut self, strain: f64) {
        self.trial_strain = strain;
    }
    fn strain(&self) -> f64 {
        self.trial_strain
    }
    fn stress(&self) -> f64 {
        self.tangent() * self.trial_strain
    }
    fn tangent(&self) -> f64 {
        if self.trial_strain >= 0.0 {
            self.e_pos
        } else {
            self.e_neg
        }
    }
    fn initial_tangent(&self) -> f64 {
        self.e_pos
    }
    fn commit_state(&mut self) {
        self.committed_strain = self.trial_strain;
    }
    /// Restores the committed strain (OpenSees' `ElasticMaterial` keeps no committed
    /// strain and leaves the trial strain as it is; restoring it is the protocol's intent).
    fn revert_to_last_commit(&mut self) {
        self.trial_strain = self.committed_strain;
    }
    fn revert_to_start(&mut self) {
        self.trial_strain = 0.0;
        self.committed_strain = 0.0;
    }
    fn boxed_clone(&self) -> Box<dyn UniaxialMaterial> {
        Box::new(self.clone())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_in_tension_and_compression() {
        let mut m = Elastic::new(200e9, 100e9).unwrap();
        m.set_trial_strain(1e-3);
        assert_eq!(m.stress(), 200e6);
        assert_eq!(m.tangent(), 200e9);
        m.set_trial_strain(-2e-3);
        assert_eq!(m.stress(), -200e6);
        assert_eq!(m.tangent(), 100e9);
        m.set_trial_strain(0.0);
        assert_eq!(m.tangent(), 200e9);
        assert_eq!(m.initial_tangent(), 200e9);
    }

    #[test]
    fn revert_restores_committed_strain() {
        let mut m = Elastic::new(30e9, 30e9).unwrap();
        m.set_trial_strain(1e-4);
        m.commit_state();
        m.set_trial_strain(5e-4);
        m.revert_to_last_commit();
        assert_eq!(m.strain(), 1e-4);
        assert_eq!(m.stress(), 30e9 * 1e-4);
        m.revert_to_start();
        assert_eq!(m.stress(), 0.0);
    }

    #[test]
    fn rejects_bad_moduli() {
        assert!(Elastic::new(0.0, 1.0)
            .unwrap_err()
            .to_string()
            .contains("E must"));
        assert!(Elastic::new(1.0, f64::NAN)
            .unwrap_err()
            .to_string()
            .contains("Eneg"));
    }
}
