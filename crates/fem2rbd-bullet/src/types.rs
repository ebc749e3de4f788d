//! Plain data exchanged with [`crate::World`]: handles, poses, body and
//! constraint descriptions, contact summaries, errors.
use thiserror::Error;

/// A rigid body in one [`crate::World`]. Handles are only valid in the world
/// that issued them (checked).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct BodyHandle {
    pub(crate) world: u32,
    pub(crate) index: u32,
}

impl BodyHandle {
    /// Creation order in its world: 0, 1, 2, …
    pub fn index(self) -> usize {
        self.index as usize
    }
}

/// A constraint in one [`crate::World`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ConstraintHandle {
    pub(crate) world: u32,
    pub(crate) index: u32,
}

impl ConstraintHandle {
    /// Creation order in its world: 0, 1, 2, …
    pub fn index(self) -> usize {
        self.index as usize
    }
}

/// A rigid transform: position \[m\] and unit quaternion (w, x, y, z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Position of the frame origin \[m\] (a body's pose: its centre, world frame; a joint
    /// frame: in the body's local frame).
    pub position: [f64; 3],
    /// Unit quaternion (w, x, y, z) rotating the local frame into the reference frame.
    pub orientation: [f64; 4],
}

impl Pose {
    /// The identity pose.
    pub const IDENTITY: Pose = Pose {
        position: [0.0; 3],
        orientation: [1.0, 0.0, 0.0, 0.0],
    };

    /// A pose at `position` with no rotation.
    pub fn at(position: [f64; 3]) -> Pose {
        Pose {
            position,
            orientation: [1.0, 0.0, 0.0, 0.0],
        }
    }
}

/// Linear [m/s] and angular [rad/s] velocity, world frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Velocity {
    /// Linear velocity of the centre [m/s], world frame.
    pub linear: [f64; 3],
    /// Angular velocity [rad/s], world frame.
    pub angular: [f64; 3],
}

/// How a body moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyKind {
    /// Never moves (mass 0).
    Static,
    /// Moved by the program (mass 0, `CF_KINEMATIC_OBJECT`): set its pose before each
    /// substep with [`crate::World::set_kinematic_target`].
    Kinematic,
    /// Moved by Bullet (mass > 0).
    Dynamic,
}

/// A box body to create (`btBoxShape` + `btRigidBody`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxDesc {
    /// Static, kinematic or dynamic.
    pub kind: BodyKind,
    /// Outer half extents \[m\], margin included (Bullet keeps them when the margin changes).
    pub half_extents: [f64; 3],
    /// Collision margin \[m\] (Bullet default 0.04, pybullet 0.001).
    pub margin: f64,
    /// Mass \[kg\]: > 0 for dynamic bodies, 0 otherwise. Inertia comes from the box:
    /// I_x = m (l_y² + l_z²)/12 with full lengths l (`btBoxShape::calculateLocalInertia`).
    pub mass: f64,
    /// Initial pose of the box centre, world frame.
    pub pose: Pose,
    /// Initial velocity (dynamic bodies only).
    pub velocity: Velocity,
    /// Friction coefficient (`setFriction`, dimensionless); Bullet combines the two bodies'
    /// values of a contact as the product.
    pub friction: f64,
    /// Rolling friction coefficient (`setRollingFriction`): resists rolling about the
    /// contact's tangent axes; 0 = none.
    pub rolling_friction: f64,
    /// Spinning (torsional) friction coefficient (`setSpinningFriction`): resists spinning
    /// about the contact normal; 0 = none.
    pub spinning_friction: f64,
    /// Restitution coefficient (`setRestitution`, dimensionless; 0 = no bounce); Bullet
    /// combines the two bodies' values of a contact as the product.
    pub restitution: f64,
    /// `btRigidBody::setDamping` linear factor in [0, 1] (velocity × (1−d)^h per substep).
    pub linear_damping: f64,
    /// `btRigidBody::setDamping` angular factor in [0, 1] (angular velocity × (1−d)^h per
    /// substep).
    pub angular_damping: f64,
    /// `DISABLE_DEACTIVATION` (never sleeps) instead of `ACTIVE_TAG`.
    pub disable_deactivation: bool,
}

impl BoxDesc {
    /// A dynamic box with Bullet's defaults: margin 0.04, friction 0.5, no damping,
    /// no restitution, never sleeping.
    pub fn dynamic(half_extents: [f64; 3], mass: f64, pose: Pose) -> Self {
        Self {
            kind: BodyKind::Dynamic,
            half_extents,
            margin: 0.04,
            mass,
            pose,
            velocity: Velocity::default(),
            friction: 0.5,
            rolling_friction: 0.0,
            spinning_friction: 0.0,
            restitution: 0.0,
            linear_damping: 0.0,
            angular_damping: 0.0,
            disable_deactivation: true,
        }
    }

    /// A static box (mass 0), otherwise as [`BoxDesc::dynamic`].
    pub fn fixed(half_extents: [f64; 3], pose: Pose) -> Self {
        Self {
            kind: BodyKind::Static,
            mass: 0.0,
            ..Self::dynamic(half_extents, 0.0, pose)
        }
    }

    /// A kinematic box (mass 0), otherwise as [`BoxDesc::dynamic`].
    pub fn kinematic(half_extents: [f64; 3], pose: Pose) -> Self {
        Self {
            kind: BodyKind::Kinematic,
            mass: 0.0,
            ..Self::dynamic(half_extents, 0.0, pose)
        }
    }
}

/// One Spring2 axis spring (`enableSpring(i, true)`, `setStiffness(i, k, limit_if_needed)`,
/// `setDamping(i, d, limit_if_needed)`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spring {
    /// Stiffness [N/m] on axes 0..2, [N·m/rad] on axes 3..5.
    pub stiffness: f64,
    /// Damping [N·s/m] or [N·m·s/rad].
    pub damping: f64,
    /// Bullet's `limitIfNeeded` (its default, and what Blender — hence BCB — uses): each
    /// substep h, with m the smaller effective mass of the two bodies on that axis
    /// (linear: the mass; angular: m·r² + 1/|I⁻¹·axis| about the joint frame), the
    /// stiffness is capped at m/(16·h²) (the spring is sampled at least 4 times per
    /// radian of its period, ω·h ≤ 1/4) and the damping at m/h
    /// (`btGeneric6DofSpring2Constraint::get_limit_motor_info2`). `false`: the springs act
    /// with exactly the given numbers (and can be unstable).
    pub limit_if_needed: bool,
}

/// The Bullet constraint class and its class-specific settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConstraintKind {
    /// `btGeneric6DofConstraint(A, B, frameA, frameB, use_linear_reference_frame_a)`.
    Generic6Dof {
        /// Bullet's `useLinearReferenceFrameA`: the linear axes and limits are expressed in
        /// frame A (`true`) or frame B (`false`).
        use_linear_reference_frame_a: bool,
    },
    /// `btGeneric6DofSpring2Constraint(A, B, frameA, frameB, RO_XYZ)`; then
    /// `setEquilibriumPoint()` when asked (the current relative pose becomes the rest pose).
    Spring2 {
        /// Per-axis springs (0..2 linear, 3..5 angular); `None` = no spring on that axis.
        springs: [Option<Spring>; 6],
        /// Call `setEquilibriumPoint()` after creation.
        set_equilibrium_point: bool,
    },
    /// `btFixedConstraint(A, B, frameA, frameB)` (a Spring2 with all six axes locked).
    Fixed,
    /// `btPoint2PointConstraint(A, B, pivotInA, pivotInB)`: the frames' positions are the
    /// pivots, which stay together (three linear rows; rotation free). The frames'
    /// orientations must be the identity; no limits.
    PointToPoint,
}

/// A per-axis constraint parameter (`btConstraintParams`) for
/// [`crate::World::set_constraint_param`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConstraintParam {
    /// `BT_CONSTRAINT_STOP_ERP`: the fraction of a limit row's error corrected per substep
    /// by the velocity bias ERP·e/h (dimensionless, default the world's `m_erp`).
    StopErp,
    /// `BT_CONSTRAINT_STOP_CFM`: the limit row's constraint force mixing (dimensionless in
    /// Bullet's joint rows, relative to the row's effective mass; default `m_globalCfm`).
    StopCfm,
}

/// A constraint to create between two bodies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConstraintDesc {
    /// The constraint class and its class-specific settings.
    pub kind: ConstraintKind,
    /// Body A (the body of `frame_a`).
    pub body_a: BodyHandle,
    /// Body B (the body of `frame_b`).
    pub body_b: BodyHandle,
    /// The joint frame in body A's local frame.
    pub frame_a: Pose,
    /// The joint frame in body B's local frame.
    pub frame_b: Pose,
    /// `setLimit(i, lo, hi)` per axis (0..2 linear \[m\], 3..5 angular \[rad\]); `None` keeps
    /// the class default. lo > hi frees the axis; lo == hi locks it. Ignored for `Fixed`.
    pub limits: [Option<(f64, f64)>; 6],
    /// `setBreakingImpulseThreshold` [N·s]: the constraint is disabled at the end of the
    /// substep in which any one of its rows' impulse |λ| reaches it (so it scales with the
    /// substep: a force F breaks it when F·h ≥ threshold). Bullet also clamps every row's
    /// impulse to ±threshold, so in its last substep the joint transmits at most the
    /// threshold (`tests/it/bullet/world.rs` checks both). `f64::INFINITY` = unbreakable.
    pub breaking_impulse_threshold: f64,
    /// `addConstraint(c, true)`: no contacts between the two bodies.
    pub disable_collisions_between: bool,
    /// Initially enabled.
    pub enabled: bool,
    /// `setOverrideNumSolverIterations`; `None` = the world's iteration count.
    pub override_solver_iterations: Option<u32>,
}

impl ConstraintDesc {
    /// A constraint of `kind` with no limits set, unbreakable, enabled, colliding bodies.
    pub fn new(
        kind: ConstraintKind,
        body_a: BodyHandle,
        body_b: BodyHandle,
        frame_a: Pose,
        frame_b: Pose,
    ) -> Self {
        Self {
            kind,
            body_a,
            body_b,
            frame_a,
            frame_b,
            limits: [None; 6],
            breaking_impulse_threshold: f64::INFINITY,
            disable_collisions_between: false,
            enabled: true,
            override_solver_iterations: None,
        }
    }
}

/// `btJointFeedback` of the last substep: the constraint's force \[N\] and torque [N·m] on
/// each body (Bullet sums the rows' impulse / h; the shim zeroes it before each substep).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JointFeedback {
    /// Force on body A \[N\], world frame.
    pub force_a: [f64; 3],
    /// Torque on body A about its centre [N·m], world frame.
    pub torque_a: [f64; 3],
    /// Force on body B \[N\], world frame.
    pub force_b: [f64; 3],
    /// Torque on body B about its centre [N·m], world frame.
    pub torque_b: [f64; 3],
}

/// The contact between two bodies after the last substep (all of their manifolds).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactSummary {
    /// Contact points (including those up to the contact breaking threshold apart).
    pub num_points: usize,
    /// Smallest signed distance \[m\]; negative = penetration. +inf with no points.
    pub min_distance: f64,
    /// Sum of the points' normal impulses of the last substep [N·s].
    pub total_normal_impulse: f64,
}

impl ContactSummary {
    /// No contact.
    pub const NONE: ContactSummary = ContactSummary {
        num_points: 0,
        min_distance: f64::INFINITY,
        total_normal_impulse: 0.0,
    };
}

/// One pair of bodies in contact, `body_a.index() < body_b.index()`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPair {
    /// The body with the smaller index.
    pub body_a: BodyHandle,
    /// The body with the larger index.
    pub body_b: BodyHandle,
    /// Their contact after the last substep.
    pub contact: ContactSummary,
}

/// Errors from the physics layer.
#[derive(Debug, Error)]
pub enum PhysicsError {
    /// The shim refused a call (bad argument) or caught a C++ exception.
    #[error("Bullet {call}: {message} (code {code})")]
    Bullet {
        /// The shim call that failed (e.g. `feedback`).
        call: &'static str,
        /// The shim's status code (`BS_ERR_*`).
        code: i32,
        /// The shim's error message.
        message: String,
    },
    /// The linked library is not the double-precision Bullet 3.24 the shim was built for.
    #[error("Bullet ABI check failed: {0}")]
    Abi(String),
    /// A handle from another world.
    #[error("{0} does not belong to this world")]
    ForeignHandle(String),
    /// A duration that is not a whole number of substeps.
    #[error("duration {duration} s is not a whole number of substeps of {substep} s ({ratio} substeps); no time is dropped silently")]
    NotWholeSubsteps {
        /// The requested duration \[s\].
        duration: f64,
        /// The substep h \[s\].
        substep: f64,
        /// duration / substep (not a whole number).
        ratio: f64,
    },
    /// A bad argument caught on the Rust side.
    #[error("{0}")]
    Invalid(String),
}
