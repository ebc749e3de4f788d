//! When the debris is at rest: the kinetic-energy test that ends a ruin stage.
//!
//! Checked once per frame (1/25 s), on the dynamic bodies only, **relative to the
//! ground** (the ground's angular velocity is zero):
//!
//! * E_k = Σ ½·m·|v − v_g|² + ½·Σᵢ Iᵢ·(Rᵀω)ᵢ²   (J; I the principal inertia of the box in its
//!   own frame, R its rotation), from the velocities at the frame, and
//! * the largest point speed of any body, a bound on the speed of its corners (m/s; r the
//!   half diagonal of the box), measured as [`RestSpeed`] says:
//!   - `frame_mean` (default): from the pose change over the frame just ended,
//!     (|Δx − Δx_g| + θ(q₀, q₁)·r) / Δt, with Δx_g the ground's displacement and θ the
//!     angle of the rotation from q₀ to q₁. It is the motion the frames record;
//!   - `instantaneous`: from the velocities at the frame, |v − v_g| + |ω|·r.
//!
//! Why the frame mean: in a resting pile the projected Gauss–Seidel solver does not
//! converge within a substep, and bodies chatter from one substep to the next without
//! moving. Traced on frame3 (docs/ruin-numerics.md, "Rest"): a beam on the ground whose angular
//! velocity alternates between 0 and 0.07 rad/s every substep while its centre moves
//! 0.5 mm in 0.3 s. Sampled at one substep, that chatter is 0.05–0.1 m/s and holds off
//! the test for the whole settle window; averaged over a frame (8 substeps at 200/s) it is
//! gone, while a body that really creeps or slides counts in full, and one that rocks
//! with a period T ≥ 0.2 s at no less than sin(πΔt/T)/(πΔt/T) ≥ 93 % of its peak speed.
//!
//! The debris is **at rest** when E_k < ε·M·g·L_ref **and** the largest point speed is
//! below v_tol, at every frame for [`RestTest::hold_s`] seconds in a row, and only after
//! the ground has stopped shaking (the record's end): a pile resting on a shaking ground
//! may still be thrown down. M is the total dynamic mass, g = |gravity|, L_ref the height
//! of the undeformed model (or [`RestTest::reference_length_m`]). Defaults ε = 1e-5,
//! v_tol = 0.05 m/s, hold 1 s: for a 3 m-tall model this bounds the mean speed by
//! √(2·ε·g·L_ref) ≈ 0.024 m/s.
//!
//! A body is flagged at rest at the end when its own point speed (the same measure, over
//! the last frame) is below v_tol.

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
    /// How a body's point speed is measured (module docs).
    pub speed: RestSpeed,
}

/// How the rest test measures a body's point speed (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RestSpeed {
    /// From the pose change over the frame just ended (default).
    #[default]
    FrameMean,
    /// From the velocities at the frame, which also count the solver's substep chatter.
    Instantaneous,
}

impl RestSpeed {
    /// The name written in `summary.json` and read from a scenario.
    pub fn name(self) -> &'static str {
        match self {
            RestSpeed::FrameMean => "frame_mean",
            RestSpeed::Instantaneous => "instantaneous",
        }
    }
}

impl Default for RestTest {
    fn default() -> Self {
        RestTest {
            energy_ratio: 1e-5,
            max_speed_mps: 0.05,
            hold_s: 1.0,
            reference_length_m: None,
            speed: RestSpeed::FrameMean,
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

/// Frame-mean point speed of one body relative to the ground, m/s:
/// (|Δx − Δx_g| + θ·r) / Δt, with Δx = x₁ − x₀ the centre's displacement over the frame,
/// Δx_g the ground's, θ the angle of the rotation q₀ → q₁ (rad) and r the half diagonal.
/// An upper bound on the mean speed of the box's corners over the frame.
pub fn frame_mean_speed(
    b: &RestBody,
    (x0, q0): ([f64; 3], [f64; 4]),
    (x1, q1): ([f64; 3], [f64; 4]),
    ground_shift: [f64; 3],
    dt_s: f64,
) -> f64 {
    let d = nalgebra::Vector3::new(
        x1[0] - x0[0] - ground_shift[0],
        x1[1] - x0[1] - ground_shift[1],
        x1[2] - x0[2] - ground_shift[2],
    );
    let unit = |q: [f64; 4]| {
        nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]))
    };
    let theta = unit(q0).angle_to(&unit(q1));
    (d.norm() + theta * b.radius_m) / dt_s
}

#[cfg(test)]
mod tests {
    use super::*;

    const CUBE: RestBody = RestBody {
        mass_kg: 100.0,
        inertia: [1.0, 1.0, 1.0],
        radius_m: 0.5,
    };
    const ID: [f64; 4] = [1.0, 0.0, 0.0, 0.0];

    #[test]
    fn frame_mean_speed_of_a_shift_and_a_turn() {
        // 2 mm across a 0.04 s frame: 0.05 m/s.
        let v = frame_mean_speed(
            &CUBE,
            ([0.0; 3], ID),
            ([0.0, 0.002, 0.0], ID),
            [0.0; 3],
            0.04,
        );
        assert!((v - 0.05).abs() < 1e-12, "{v}");
        // The same shift carried by the ground is no motion.
        let v = frame_mean_speed(
            &CUBE,
            ([1.0, 0.0, 0.0], ID),
            ([1.0, 0.002, 0.0], ID),
            [0.0, 0.002, 0.0],
            0.04,
        );
        assert!(v.abs() < 1e-12, "{v}");
        // A turn of 0.004 rad about z: corners at r = 0.5 m move 2 mm, 0.05 m/s; the sign
        // of the quaternion (q and −q are the same rotation) does not matter.
        let h = 0.002_f64;
        for s in [1.0, -1.0] {
            let q1 = [s * h.cos(), 0.0, 0.0, s * h.sin()];
            let v = frame_mean_speed(&CUBE, ([0.0; 3], ID), ([0.0; 3], q1), [0.0; 3], 0.04);
            assert!((v - 0.05).abs() < 1e-9, "{v}");
        }
    }

    #[test]
    fn instantaneous_speed_and_energy_of_a_spinning_box() {
        // ω = 2 rad/s about z, v = 0.3 m/s in x on a ground moving at 0.1 m/s in x:
        // E = ½·100·0.2² + ½·1·2² = 4 J; speed 0.2 + 2·0.5 = 1.2 m/s.
        let (e, s) =
            body_energy_speed(&CUBE, ID, [0.3, 0.0, 0.0], [0.0, 0.0, 2.0], [0.1, 0.0, 0.0]);
        assert!(
            (e - 4.0).abs() < 1e-12 && (s - 1.2).abs() < 1e-12,
            "{e} {s}"
        );
    }

    #[test]
    fn the_speed_measure_is_read_by_name() {
        #[derive(Deserialize)]
        struct T {
            speed: RestSpeed,
        }
        let t: T = toml::from_str("speed = \"instantaneous\"").unwrap();
        assert_eq!(t.speed, RestSpeed::Instantaneous);
        assert_eq!(RestTest::default().speed.name(), "frame_mean");
        assert!(toml::from_str::<T>("speed = \"sampled\"").is_err());
    }
}
