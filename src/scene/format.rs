//! The JSON scene file, as parsed (serde). Validation and defaults are in
//! [`super::assemble`]; see the module docs of [`crate::scene`] for the format.
use serde::Deserialize;

/// A whole scene file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SceneFile {
    /// What the scene is, for the reader (not used by the simulation).
    #[serde(default)]
    #[allow(dead_code)]
    pub name: Option<String>,
    /// A description for the reader (not used by the simulation).
    #[serde(default)]
    #[allow(dead_code)]
    pub description: Option<String>,
    /// World settings (preset and overrides); all optional.
    #[serde(default)]
    pub world: WorldSpec,
    /// Simulated time \[s\]; must be a whole number of substeps.
    pub duration: f64,
    /// The fixed substep h \[s\]. Exactly one of `substep` and `substeps_per_second`.
    #[serde(default)]
    pub substep: Option<f64>,
    /// h = 1 / substeps_per_second.
    #[serde(default)]
    pub substeps_per_second: Option<f64>,
    /// Box bodies, created in this order.
    pub bodies: Vec<BodySpec>,
    /// Constraints, created in this order after the bodies.
    #[serde(default)]
    pub constraints: Vec<ConstraintEntry>,
}

/// `"world"`: a preset plus overrides.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct WorldSpec {
    /// `"bullet"` (default) or `"pybullet"`.
    #[serde(default)]
    pub preset: Option<Preset>,
    /// Gravity [m/s²]; default (0, 0, −9.81).
    #[serde(default)]
    pub gravity: Option<[f64; 3]>,
    /// Process-global `gDbvtMargin` \[m\].
    #[serde(default)]
    pub dbvt_margin: Option<f64>,
    /// Process-global `gContactBreakingThreshold` \[m\].
    #[serde(default)]
    pub contact_breaking_threshold: Option<f64>,
    /// Solver overrides on top of the preset.
    #[serde(default)]
    pub solver: SolverSpec,
    /// Default collision margin of every body \[m\] (bullet 0.04, pybullet 0.001).
    #[serde(default)]
    pub default_margin: Option<f64>,
}

/// `"world.solver"`: each field overrides the preset's value (see
/// [`crate::bullet::SolverSettings`] for meanings).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SolverSpec {
    /// Overrides `num_iterations`: Gauss–Seidel iterations per substep.
    pub num_iterations: Option<u32>,
    /// Overrides `erp`: joint error reduction parameter.
    pub erp: Option<f64>,
    /// Overrides `erp2`: contact error reduction parameter.
    pub erp2: Option<f64>,
    /// Overrides `friction_erp`: friction error reduction parameter.
    pub friction_erp: Option<f64>,
    /// Overrides `global_cfm`: constraint force mixing.
    pub global_cfm: Option<f64>,
    /// Overrides `linear_slop`: allowed penetration \[m\].
    pub linear_slop: Option<f64>,
    /// Overrides `split_impulse`: split impulse on or off.
    pub split_impulse: Option<bool>,
    /// Overrides `split_impulse_penetration_threshold`: penetration depth \[m\] (negative)
    /// beyond which split impulse acts.
    pub split_impulse_penetration_threshold: Option<f64>,
    /// Overrides `split_impulse_turn_erp`: split-impulse turn ERP.
    pub split_impulse_turn_erp: Option<f64>,
    /// Overrides `solver_mode`: `btSolverMode` flags.
    pub solver_mode: Option<i32>,
    /// Overrides `warmstarting_factor`: warm-starting factor.
    pub warmstarting_factor: Option<f64>,
    /// Overrides `least_squares_residual_threshold`: residual for an early exit.
    pub least_squares_residual_threshold: Option<f64>,
    /// Overrides `minimum_solver_batch_size`: minimum solver batch size.
    pub minimum_solver_batch_size: Option<u32>,
    /// Overrides `restitution_velocity_threshold`: restitution velocity threshold [m/s].
    pub restitution_velocity_threshold: Option<f64>,
    /// Overrides `max_error_reduction`: maximum error reduction [m/s].
    pub max_error_reduction: Option<f64>,
    /// Overrides `sor`: successive over-relaxation factor.
    pub sor: Option<f64>,
    /// Overrides `damping`: damping of non-contact constraints.
    pub damping: Option<f64>,
}

/// One box body.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BodySpec {
    /// Unique name; constraints refer to bodies by it.
    pub name: String,
    /// Outer half extents \[m\].
    pub half_extents: [f64; 3],
    /// Mass \[kg\]; 0 = static (or kinematic with `"kinematic": true`).
    pub mass: f64,
    /// A kinematic body (mass must be 0); it stays where it is unless moved by a program.
    #[serde(default)]
    pub kinematic: bool,
    /// Centre \[m\].
    pub position: [f64; 3],
    /// Unit quaternion (w, x, y, z); default identity.
    #[serde(default)]
    pub orientation: Option<[f64; 4]>,
    #[serde(default)]
    /// Initial linear velocity [m/s], world frame; dynamic bodies only; default 0.
    pub linear_velocity: Option<[f64; 3]>,
    #[serde(default)]
    /// Initial angular velocity [rad/s], world frame; dynamic bodies only; default 0.
    pub angular_velocity: Option<[f64; 3]>,
    /// Default 0.5.
    #[serde(default)]
    pub friction: Option<f64>,
    #[serde(default)]
    /// Rolling friction coefficient; default 0.
    pub rolling_friction: Option<f64>,
    #[serde(default)]
    /// Spinning (torsional) friction coefficient; default 0.
    pub spinning_friction: Option<f64>,
    #[serde(default)]
    /// Restitution coefficient (0 = no bounce); default 0.
    pub restitution: Option<f64>,
    #[serde(default)]
    /// Linear damping factor in [0, 1] (`btRigidBody::setDamping`); default 0.
    pub linear_damping: Option<f64>,
    #[serde(default)]
    /// Angular damping factor in [0, 1] (`btRigidBody::setDamping`); default 0.
    pub angular_damping: Option<f64>,
    /// Collision margin \[m\]; default the world's `default_margin`.
    #[serde(default)]
    pub margin: Option<f64>,
    /// Never sleep (default true).
    #[serde(default)]
    pub disable_deactivation: Option<bool>,
    /// Kinematic bodies only: move at constant velocity (pose set before every substep).
    #[serde(default)]
    pub motion: Option<MotionSpec>,
}

/// Constant-velocity motion of a kinematic body: at time t its pose is
/// (p0 + v·t, rot(ω·t)·q0), with ω in the world frame.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MotionSpec {
    /// [m/s]
    #[serde(default)]
    pub linear_velocity: Option<[f64; 3]>,
    /// [rad/s], world frame
    #[serde(default)]
    pub angular_velocity: Option<[f64; 3]>,
}

/// A joint frame in a body's local frame.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FrameSpec {
    /// Origin of the joint frame in the body's local frame \[m\].
    pub position: [f64; 3],
    #[serde(default)]
    /// Unit quaternion (w, x, y, z) of the joint frame relative to the body frame; default
    /// identity.
    pub orientation: Option<[f64; 4]>,
}

/// A spring on one axis.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SpringSpec {
    /// [N/m] or [N·m/rad].
    pub stiffness: f64,
    /// [N·s/m] or [N·m·s/rad]; default 0.
    #[serde(default)]
    pub damping: f64,
    /// Bullet's `limitIfNeeded` for this spring (see [`crate::bullet::Spring`]); default
    /// false (the exact stiffness, as pybullet's `changeConstraint` gives it).
    #[serde(default)]
    pub limit_if_needed: bool,
}

/// The constraint classes a scene can name (`kind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ConstraintType {
    /// `"generic6dof"`: btGeneric6DofConstraint.
    Generic6dof,
    /// `"spring2"`: btGeneric6DofSpring2Constraint.
    Spring2,
    /// `"fixed"`: btFixedConstraint.
    Fixed,
    /// `"point2point"`: btPoint2PointConstraint (the frames' positions are the pivots).
    PointToPoint,
}

impl<'de> Deserialize<'de> for ConstraintType {
    /// One of the three names; anything else is an error naming it and the choices.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        match s.as_str() {
            "generic6dof" => Ok(ConstraintType::Generic6dof),
            "spring2" => Ok(ConstraintType::Spring2),
            "fixed" => Ok(ConstraintType::Fixed),
            "point2point" => Ok(ConstraintType::PointToPoint),
            other => Err(serde::de::Error::custom(format!(
                "unknown kind \"{other}\" (expected \"generic6dof\", \"spring2\", \"fixed\" or \"point2point\")"
            ))),
        }
    }
}

/// The world presets (`world.preset`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub(crate) enum Preset {
    /// `"bullet"`: Bullet's own defaults (default).
    #[default]
    Bullet,
    /// `"pybullet"`: pybullet's defaults.
    Pybullet,
}

impl<'de> Deserialize<'de> for Preset {
    /// `bullet` or `pybullet`; anything else is an error naming it and the choices.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        match s.as_str() {
            "bullet" => Ok(Preset::Bullet),
            "pybullet" => Ok(Preset::Pybullet),
            other => Err(serde::de::Error::custom(format!(
                "world.preset \"{other}\" is unknown (expected \"bullet\" or \"pybullet\")"
            ))),
        }
    }
}

/// One constraint.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ConstraintEntry {
    /// `"generic6dof"`, `"spring2"` or `"fixed"`.
    pub kind: ConstraintType,
    /// Body names.
    pub body_a: String,
    /// Name of the second body (not `body_a`).
    pub body_b: String,
    /// The joint frame in `body_a`'s local frame.
    pub frame_a: FrameSpec,
    /// The joint frame in `body_b`'s local frame.
    pub frame_b: FrameSpec,
    /// generic6dof only (default true).
    #[serde(default)]
    pub use_linear_reference_frame_a: Option<bool>,
    /// Six entries (axes x, y, z, rx, ry, rz): `null` or `[lower, upper]`.
    #[serde(default)]
    pub limits: Option<[Option<[f64; 2]>; 6]>,
    /// spring2 only: six entries, `null` or `{"stiffness": k, "damping": d}`.
    #[serde(default)]
    pub springs: Option<[Option<SpringSpec>; 6]>,
    /// spring2 only (default true): the initial relative pose is the springs' rest pose.
    #[serde(default)]
    pub set_equilibrium_point: Option<bool>,
    /// [N·s] per substep; absent or null = unbreakable.
    #[serde(default)]
    pub breaking_impulse_threshold: Option<f64>,
    /// Default true.
    #[serde(default)]
    pub disable_collisions_between: Option<bool>,
    /// Default true.
    #[serde(default)]
    pub enabled: Option<bool>,
    #[serde(default)]
    /// Solver iterations for this constraint (`setOverrideNumSolverIterations`); default
    /// the world's `num_iterations`.
    pub override_solver_iterations: Option<u32>,
}
