//! Rayleigh damping C = a0·M + a1·K_initial (OpenSees `rayleigh a0 0 a1 0`: mass- and
//! initial-stiffness-proportional).
//!
//! Modal damping ratio of mode ω: ξ(ω) = a0/(2ω) + a1·ω/2 (Chopra, *Dynamics of
//! Structures*, §11.4). Equal ratio ξ at ω_i and ω_j gives
//! a0 = 2ξ ω_i ω_j/(ω_i + ω_j) (s⁻¹), a1 = 2ξ/(ω_i + ω_j) (s).

use super::AnalysisError;
use std::f64::consts::PI;

/// Rayleigh coefficients.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayleighDamping {
    /// Mass-proportional coefficient a0 (1/s).
    pub a0: f64,
    /// Initial-stiffness-proportional coefficient a1 (s).
    pub a1: f64,
}

impl RayleighDamping {
    /// Ratio `xi` (e.g. 0.05) at the two periods `t_i`, `t_j` (s, positive, distinct).
    pub fn from_periods(xi: f64, t_i: f64, t_j: f64) -> Result<Self, AnalysisError> {
        let valid = xi >= 0.0
            && xi.is_finite()
            && t_i > 0.0
            && t_j > 0.0
            && t_i.is_finite()
            && t_j.is_finite();
        if !valid || t_i == t_j {
            return Err(AnalysisError::Input(format!(
                "Rayleigh damping: need ξ ≥ 0 and two distinct positive periods (ξ = {xi}, T = {t_i}, {t_j})"
            )));
        }
        let (wi, wj) = (2.0 * PI / t_i, 2.0 * PI / t_j);
        Ok(Self {
            a0: 2.0 * xi * wi * wj / (wi + wj),
            a1: 2.0 * xi / (wi + wj),
        })
    }

    /// The project default: 5 % at T1 and T1/3 (as the frame3 reference runs).
    pub fn default_for_period(t1: f64) -> Result<Self, AnalysisError> {
        Self::from_periods(0.05, t1, t1 / 3.0)
    }

    /// Damping ratio of a mode of circular frequency ω (rad/s).
    pub fn ratio(&self, omega: f64) -> f64 {
        self.a0 / (2.0 * omega) + self.a1 * omega / 2.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// frame3: 5 % at 0.316 s and 0.316/3 s gives OpenSees's a0 = 1.491262, a1 = 1.257324e-3
    /// (results.md uses the eigen T1 = 0.31603… so compare to 5 digits).
    #[test]
    fn frame3_coefficients() {
        let r = RayleighDamping::default_for_period(0.316).unwrap();
        assert!((r.a0 - 1.491262).abs() / 1.491262 < 2e-4, "{r:?}");
        assert!((r.a1 - 1.257324e-3).abs() / 1.257324e-3 < 2e-4, "{r:?}");
        for t in [0.316, 0.316 / 3.0] {
            assert!((r.ratio(2.0 * PI / t) - 0.05).abs() < 1e-14);
        }
        assert!(RayleighDamping::from_periods(0.05, 0.3, 0.3).is_err());
    }
}
