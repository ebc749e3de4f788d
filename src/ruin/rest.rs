//! When the debris is at rest: the kinetic-energy test that ends a ruin stage.
//!
//! Checked once per frame (1/25 s), on the dynamic bodies only, with velocities taken
//! **relative to the ground** (v − v_ground; the ground's angular velocity is zero):
//!
//! * E_k = Σ ½·m·|v − v_g|² + ½·Σᵢ Iᵢ·(Rᵀω)ᵢ²   (J; I the principal inertia of the box in its
//!   own frame, R its rotation), and
//! * the largest point speed of any body, |v − v_g| + |ω|·r (m/s; r the half diagonal of
//!   the box, a bound on the speed of its corners).
//!
//! The debris is **at rest** when E_k < ε·M·g·L_ref **and** the largest point speed is
//! below v_tol, at every frame for [`RestTest::hold_s`] seconds in a row, and only after
//! the ground has stopped shaking (the record's end): a pile resting on a shaking ground
//! may still be thrown down. M is the total dynamic mass, g = |gravity|, L_ref the height
//! of the undeformed model (or [`RestTest::reference_length_m`]). Defaults ε = 1e-5,
//! v_tol = 0.05 m/s, hold 1 s: for a 3 m-tall model this bounds the mean speed by
//! √(2·ε·g·L_ref) ≈ 0.024 m/s.
//!
//! A body is flagged at rest at the end when its own point speed is below v_tol.

use serde::{Deserialize, Serialize};

/// The at-rest test (module docs); every field can be overridden.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RestTest {
    /// ε: the energy bound relative to M·g·L_ref (dimensionless).
    pub energy_ratio: f64,
    /// v_tol, m/s: bound on every body's largest point speed.
    pub max_speed_mps: f64,
    /// How long both bounds must hold without a break, s.
    pub hold_s: f64,
    /// L_ref, m; `None` = the height of the undeformed model's AABB (at least 1 m).
    pub reference_length_m: Option<f64>,
}

impl Default for RestTest {
    fn default() -> Self {
        RestTest {
            energy_ratio: 1e-5,
            max_speed_mps: 0.05,
            hold_s: 1.0,
            reference_length_m: None,
        }
    }
}

/// One body's mass properties for the test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestBody {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Principal inertia in the body frame, kg·m².
    pub inertia: [f64; 3],
    /// Half diagonal of the box, m.
    pub radius_m: f64,
}

/// Kinetic energy relative to the ground (J) and point speed (m/s) of one body.
pub fn body_energy_speed(
    b: &RestBody,
    orientation_wxyz: [f64; 4],
    linear: [f64; 3],
    angular: [f64; 3],
    ground_velocity: [f64; 3],
) -> (f64, f64) {
    let v = [
        linear[0] - ground_velocity[0],
        linear[1] - ground_velocity[1],
        linear[2] - ground_velocity[2],
    ];
    let v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    let q = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
        orientation_wxyz[0],
        orientation_wxyz[1],
        orientation_wxyz[2],
        orientation_wxyz[3],
    ));
    let w_local = q.inverse() * nalgebra::Vector3::from(angular);
    let rot = 0.5
        * (b.inertia[0] * w_local.x * w_local.x
            + b.inertia[1] * w_local.y * w_local.y
            + b.inertia[2] * w_local.z * w_local.z);
    let speed = v2.sqrt() + w_local.norm() * b.radius_m;
    (0.5 * b.mass_kg * v2 + rot, speed)
}
