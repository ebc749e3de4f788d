//! The ruin stage's energy ledger: where the debris's mechanical energy comes from and
//! where it goes, per recorded frame (docs/ruin-numerics.md).
//!
//! All energies in J, absolute frame (not relative to the moving ground), dynamic bodies
//! only (passive foundations ride with the ground and are part of it):
//!
//! * **kinetic**, translational T_t = Σ ½·m·|v|² and rotational T_r = Σ ½·Σₖ Iₖ·(Rᵀω)ₖ²
//!   (I the principal inertia of the box in its own frame, R its rotation);
//! * **potential** V = −Σ m·g·(x − x_ref), x_ref on the ground's top face at rest (so V is
//!   "relative to the ground": m·|g|·(height of the centre above the base) for g = −z);
//! * **ground work** W_g: the work done on the bodies by the moving kinematic ground and
//!   the passive foundations riding on it, summed over substeps;
//! * **damping** D: what Bullet's linear and angular velocity damping takes out;
//! * **dissipated** = E(0) + W_g − E(t), E = T_t + T_r + V: everything else (contact and
//!   joint impulses, friction, broken constraints, plastic springs' stored and damped
//!   energy, and — with a negative sign — whatever the solver injects).
//!
//! **How W_g is measured (momentum balance).** Bullet 3.24's substep h
//! (`btDiscreteDynamicsWorld::internalSingleStepSimulation`): `predictUnconstraintMotion`
//! first damps every dynamic body's velocity (`btRigidBody::applyDamping`:
//! v ← v·(1 − d_lin)^h, ω ← ω·(1 − d_ang)^h), then the sequential-impulse solver adds
//! gravity (`m_externalForceImpulse` = g·h) and all contact and joint impulses, then
//! `integrateTransforms` moves the bodies with the new velocities. So for every dynamic
//! body the impulse it received from contacts and joints during the substep is
//!
//! J_i = m_i·(v_i⁺ − (1 − d_lin)^h·v_i⁻ − g·h)   (N·s),
//!
//! from its velocities v⁻, v⁺ before and after the substep. Impulses between two dynamic
//! bodies cancel in Σ J_i (action = reaction), so Σ J_i is the impulse of the ground and
//! the passive bodies. They translate rigidly with the velocity Bullet gives a kinematic
//! body for that substep (`btRigidBody::saveKinematicState`: the secant
//! v_g = (d(t + h) − d(t))/h), so the power of their contact and joint forces is v_g·F and
//!
//! ΔW_g = v_g · Σ_i J_i   per substep.
//!
//! The damping loss per substep is ½·m·|v⁻|²·(1 − λ_lin²) + T_r⁻·(1 − λ_ang²),
//! λ = (1 − d)^h. With split impulse (off in BCB) Bullet corrects penetrations by moving
//! positions directly: that energy shows up in V with no velocity change, i.e. in
//! "dissipated" with a negative sign.
//!
//! The ledger assumes constant gravity; during a warm-up ([`super::stage::StageSettings`])
//! the gravity work is not V's change and the dissipated column is not meaningful.
use crate::bullet::{Pose, Velocity};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

/// Mass properties of one dynamic body for the ledger.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct MassProps {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Principal inertia in the body frame, kg·m².
    pub inertia: [f64; 3],
}

/// The ledger at one recorded frame (module docs); J.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EnergyFrame {
    /// Translational kinetic energy T_t, J.
    pub kinetic_translational_j: f64,
    /// Rotational kinetic energy T_r, J.
    pub kinetic_rotational_j: f64,
    /// Potential energy V relative to the ground's top at rest, J.
    pub potential_j: f64,
    /// Work done by the moving ground (and the passive bodies) since the stage's start, J.
    pub ground_work_j: f64,
    /// Energy taken out by Bullet's velocity damping since the start, J.
    pub damping_j: f64,
    /// Energy added by the solver since the start: Σ over substeps of the positive part
    /// of ΔE − ΔW_g + ΔD_damping, J (0 for a solver that only dissipates).
    pub injected_j: f64,
}

impl EnergyFrame {
    /// Mechanical energy E = T_t + T_r + V, J.
    pub fn mechanical_j(&self) -> f64 {
        self.kinetic_translational_j + self.kinetic_rotational_j + self.potential_j
    }

    /// Dissipated = E(start) + W_g − E, J (`start` = the stage's first frame).
    pub fn dissipated_j(&self, start: &EnergyFrame) -> f64 {
        start.mechanical_j() + self.ground_work_j - self.mechanical_j()
    }
}

fn quat(p: &Pose) -> UnitQuaternion<f64> {
    let [w, x, y, z] = p.orientation;
    UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z))
}

/// Rotational kinetic energy ½·Σₖ Iₖ·(Rᵀω)ₖ² of one body, J.
pub(crate) fn rotational_j(props: &MassProps, pose: &Pose, angular: [f64; 3]) -> f64 {
    let w = quat(pose).inverse() * Vector3::from(angular);
    0.5 * (props.inertia[0] * w.x * w.x
        + props.inertia[1] * w.y * w.y
        + props.inertia[2] * w.z * w.z)
}

/// T_t, T_r and V of the bodies with `Some` mass properties (module docs), J.
/// `gravity` in m/s², `reference` a point of the ground's top at rest (m).
pub(crate) fn mechanical(
    props: &[Option<MassProps>],
    poses: &[Pose],
    vels: &[Velocity],
    gravity: [f64; 3],
    reference: [f64; 3],
) -> (f64, f64, f64) {
    let (mut tt, mut tr, mut v) = (0.0, 0.0, 0.0);
    for ((p, pose), vel) in props.iter().zip(poses).zip(vels) {
        let Some(p) = p else { continue };
        let l = vel.linear;
        tt += 0.5 * p.mass_kg * (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
        tr += rotational_j(p, pose, vel.angular);
        let x = pose.position;
        v -= p.mass_kg
            * (gravity[0] * (x[0] - reference[0])
                + gravity[1] * (x[1] - reference[1])
                + gravity[2] * (x[2] - reference[2]));
    }
    (tt, tr, v)
}

/// One substep's contribution to the ledger (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct SubstepBalance {
    /// Σ J_i, the impulse of the ground and passive bodies on the dynamic bodies, N·s.
    pub ground_impulse: [f64; 3],
    /// ΔW_g = v_g·Σ J_i, J.
    pub ground_work_j: f64,
    /// Damping loss, J.
    pub damping_j: f64,
}

/// The balance of one substep of length `h` (s) from the states before (`poses0`,
/// `vels0`) and the velocities after (`vels1`); `gravity` is the gravity of that
/// substep, `ground_velocity` the kinematic ground's (secant) velocity, damping factors
/// per second as Bullet's `setDamping`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn substep_balance(
    props: &[Option<MassProps>],
    poses0: &[Pose],
    vels0: &[Velocity],
    vels1: &[Velocity],
    h: f64,
    gravity: [f64; 3],
    ground_velocity: [f64; 3],
    linear_damping: f64,
    angular_damping: f64,
) -> SubstepBalance {
    let ll = (1.0 - linear_damping).powf(h);
    let la = (1.0 - angular_damping).powf(h);
    let mut out = SubstepBalance::default();
    for (((p, pose), v0), v1) in props.iter().zip(poses0).zip(vels0).zip(vels1) {
        let Some(p) = p else { continue };
        let mut v2 = 0.0;
        for (k, (j, g)) in out.ground_impulse.iter_mut().zip(gravity).enumerate() {
            *j += p.mass_kg * (v1.linear[k] - ll * v0.linear[k] - g * h);
            v2 += v0.linear[k] * v0.linear[k];
        }
        out.damping_j += 0.5 * p.mass_kg * v2 * (1.0 - ll * ll)
            + rotational_j(p, pose, v0.angular) * (1.0 - la * la);
    }
    out.ground_work_j = (0..3)
        .map(|k| ground_velocity[k] * out.ground_impulse[k])
        .sum();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_turned_box_rotational_energy_by_hand() {
        // Box 1 × 2 × 3 m, 12 kg: I = (13, 10, 5) kg·m². Turned 90° about z, spinning at
        // 2 rad/s about world x = body −y: T_r = ½·10·4 = 20 J.
        let p = MassProps {
            mass_kg: 12.0,
            inertia: [13.0, 10.0, 5.0],
        };
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let pose = Pose {
            position: [0.0, 0.0, 2.0],
            orientation: [s, 0.0, 0.0, s],
        };
        assert!((rotational_j(&p, &pose, [2.0, 0.0, 0.0]) - 20.0).abs() < 1e-12);
        let vel = Velocity {
            linear: [3.0, 0.0, 4.0],
            angular: [2.0, 0.0, 0.0],
        };
        let (tt, tr, v) = mechanical(
            &[Some(p), None],
            &[pose, pose],
            &[vel, vel],
            [0.0, 0.0, -9.81],
            [0.0, 0.0, 0.5],
        );
        assert!((tt - 150.0).abs() < 1e-12);
        assert!((tr - 20.0).abs() < 1e-12);
        assert!((v - 12.0 * 9.81 * 1.5).abs() < 1e-9);
    }

    #[test]
    fn free_flight_has_no_ground_impulse_and_damping_by_hand() {
        // v⁺ = λ·v⁻ + g·h exactly: no impulse; the damping loss is ½m|v|²(1 − λ²).
        let p = MassProps {
            mass_kg: 2.0,
            inertia: [1.0; 3],
        };
        let h = 0.005;
        let (dl, da): (f64, f64) = (0.04, 0.1);
        let ll = (1.0 - dl).powf(h);
        let v0 = Velocity {
            linear: [1.0, 0.0, 2.0],
            angular: [0.0, 0.0, 3.0],
        };
        let v1 = Velocity {
            linear: [ll, 0.0, 2.0 * ll - 9.81 * h],
            angular: [0.0, 0.0, 3.0],
        };
        let b = substep_balance(
            &[Some(p)],
            &[Pose::IDENTITY],
            &[v0],
            &[v1],
            h,
            [0.0, 0.0, -9.81],
            [0.3, 0.0, 0.0],
            dl,
            da,
        );
        assert!(b.ground_impulse.iter().all(|j| j.abs() < 1e-14));
        assert!(b.ground_work_j.abs() < 1e-14);
        let la = (1.0 - da).powf(h);
        let want = 0.5 * 2.0 * 5.0 * (1.0 - ll * ll) + 0.5 * 9.0 * (1.0 - la * la);
        assert!((b.damping_j - want).abs() < 1e-15);
    }
}
