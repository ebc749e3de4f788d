//! The one safe wrapper over `bullet-sys` (Debian's double-precision Bullet 3.24): a
//! [`World`] owning box bodies and constraints in arenas addressed by typed handles
//! ([`BodyHandle`], [`ConstraintHandle`]). This crate and `bullet-sys` are the only
//! places with `unsafe` in fem2rbd; no raw pointer leaves this crate.
//!
//! What Bullet does, in this layer's terms (source: Bullet 3.24, btDiscreteDynamicsWorld,
//! btSequentialImpulseConstraintSolver):
//! - each substep h: gravity and damping, then the velocity solve of contacts and joints
//!   (sequential impulses), then x ← x + v·h (semi-implicit Euler);
//! - a constraint breaks (is disabled) at the end of the substep in which any one of its
//!   solver rows' impulse |λ| ≥ its breaking impulse threshold [N·s];
//! - `gDbvtMargin` and `gContactBreakingThreshold` are process-global (see
//!   [`set_global_dbvt_margin`], [`set_global_contact_breaking_threshold`]).
#![warn(missing_docs)]

pub mod jointsolve;
pub mod settings;
pub mod speed;
pub mod types;
mod warmstart;
pub mod world;

pub use jointsolve::{JointSolve, JointSolveStats};
pub use settings::{
    SolverSettings, WorldSettings, SOLVER_SIMD, SOLVER_USE_2_FRICTION_DIRECTIONS,
    SOLVER_USE_WARMSTARTING,
};
pub use speed::{
    global_deactivation_time, profile_read, profile_start, profile_stop,
    set_global_deactivation_time, IslandStats, ParallelCounts, ProfileZone, Sweep,
};
pub use types::{
    BodyHandle, BodyKind, BoxDesc, ConstraintDesc, ConstraintHandle, ConstraintKind,
    ConstraintParam, ContactPair, ContactSummary, JointFeedback, PhysicsError, Pose, Spring,
    Velocity,
};
pub use world::{
    abi_self_check, bullet_default_solver_settings, bullet_version,
    global_contact_breaking_threshold, global_dbvt_margin, set_global_contact_breaking_threshold,
    set_global_dbvt_margin, whole_substeps, World, LINKED_BULLET_PKG_VERSION,
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn abi_check_passes_and_defaults_match_bullet() {
        abi_self_check().unwrap();
        assert_eq!(bullet_version(), 324);
        // pkg-config's "3.24" (build time) is btGetVersion()'s 324 (run time).
        let digits: String = LINKED_BULLET_PKG_VERSION.split('.').take(2).collect();
        assert_eq!(digits, bullet_version().to_string());
        assert_eq!(
            bullet_default_solver_settings().unwrap(),
            SolverSettings::default()
        );
    }

    #[test]
    fn settings_round_trip_through_the_world() {
        let s = WorldSettings {
            solver: SolverSettings::pybullet(),
            ..WorldSettings::default()
        };
        let w = World::new(&s).unwrap();
        assert_eq!(w.solver().unwrap(), SolverSettings::pybullet());
        assert_eq!(w.gravity().unwrap(), [0.0, 0.0, -9.81]);
    }

    #[test]
    fn foreign_handles_and_bad_arguments_are_errors() {
        let mut w1 = World::new(&WorldSettings::default()).unwrap();
        let w2 = World::new(&WorldSettings::default()).unwrap();
        let b = w1
            .add_box(&BoxDesc::dynamic([0.5; 3], 1.0, Pose::IDENTITY))
            .unwrap();
        assert!(matches!(w2.pose(b), Err(PhysicsError::ForeignHandle(_))));
        let err = w1
            .add_box(&BoxDesc::dynamic([0.5, 0.0, 0.5], 1.0, Pose::IDENTITY))
            .unwrap_err();
        assert!(err.to_string().contains("half extents"), "{err}");
        let err = w1
            .add_box(&BoxDesc::dynamic([0.5; 3], -1.0, Pose::IDENTITY))
            .unwrap_err();
        assert!(err.to_string().contains("mass"), "{err}");
        assert!(whole_substeps(1.0, 0.3).is_err());
        assert_eq!(whole_substeps(2.0, 1.0 / 240.0).unwrap(), 480);
    }

    #[test]
    fn box_inertia_comes_from_the_shape() {
        let mut w = World::new(&WorldSettings::default()).unwrap();
        let b = w
            .add_box(&BoxDesc::dynamic([0.5, 1.0, 1.5], 12.0, Pose::IDENTITY))
            .unwrap();
        let (m, i) = w.mass_inertia(b).unwrap();
        assert_eq!(m, 12.0);
        // I_x = m (l_y² + l_z²)/12 with full lengths 1, 2, 3 m.
        assert_eq!(i, [13.0, 10.0, 5.0]);
    }
}
