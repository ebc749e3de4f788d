//! The ruin stage in Bullet: BCB's five steps as one builder ([`RuinStage::build`]) and a
//! stepping loop with the per-frame monitor ([`RuinStage::run`]).
//!
//! Build (docs/bcb.md §1, §6, §7.1, §11; docs/ruin-model.md):
//!
//! 1. **Ground**: a large box, friction 1, top at the model's base ([`GroundSpec`]);
//!    kinematic when a ground motion is given, static otherwise. It is body 0 of the world.
//! 2. **Bodies**: every [`BodyGeom`] as a box at its start pose with its start velocity
//!    (linear and angular, world frame), in input order (world body i + 1). Active bodies
//!    are dynamic, with BCB's body settings ([`BodySettings`]: friction 1, restitution 0,
//!    damping 0.04 / 0.1, never deactivated, margin 0.04). Passive bodies (foundation
//!    blocks) are kinematic and ride on the ground.
//! 3. **Remaining ground motion**: before every substep the ground (and the passive bodies)
//!    are placed by the record's absolute displacement at the substep's end ([`super::ground`]).
//!    With `start_time_s` = Tc this continues the FE stage's ground in position and velocity.
//! 4. **Connections** (BCB's steps 4 and 5): [`find_contacts`] on the undeformed bodies,
//!    [`super::connection::build_connections`] with frames from the start poses (nothing fires at the start),
//!    then each connection's starting state ([`start_state_from_damage`] of the FE damage
//!    given per body pair): broken → no constraint enabled; plastic → spring on (its
//!    equilibrium is the start pose), generics off. The seven Bullet constraints of each
//!    connection are created in spec order with `addConstraint(c, disable_collisions)`.
//!
//! Run: substeps of h = time_scale / steps_per_second; every 1/frame_rate s the monitor
//! ([`Monitor::check`]) reads the poses and Bullet's enabled flags and its actions are
//! applied before the next substep; each frame is recorded ([`Frame`]). The run ends at
//! [`StopRule::max_time_s`] or when the debris is at rest ([`RestTest`]).
//!
//! **Bullet's locked rows** (measured in `tests/it/ruin/stage_statics.rs`): a
//! `btGeneric6DofConstraint` axis with lo = hi only produces a solver row while its error
//! is strictly outside the limit; a joint that starts exactly in place (frames from the
//! start poses) carries nothing in its first substep, and under load the row now and then
//! drops out for a substep, after which it needs about twice the static impulse. So a
//! CT 22 generic breaks between 1/2 and 1 times the force or moment its threshold stands
//! for (BCB runs the same Bullet code; its empirical corrections 2.2/1.5 include this).
//! A load switched on at once (no warm-up) is the worst case. Static joint forces, once
//! settled, equal the closed-form ones to 0.25 % (column test).
//!
//! **Wall time**: [`RuinResult::wall`] splits the run's wall time into the time inside
//! `World::step` and the rest (monitor, pose reads, ground updates). Measured (debug
//! profile): 98–99 % inside Bullet for a 5-body portal frame under ground motion, 99.7 %
//! for 30 debris boxes.
//!
//! **Physics-only mode** (BCB alone): [`StageInput::physics_only`] — undeformed start poses,
//! zero velocities, all connections elastic, start at t = 0 under the whole record.

use super::connection::{
    build_connections_with, BodyCapacity, ConnectionSpec, ConnectionState,
    ConstraintClass as SpecKind, ConstraintRole, GroupStrength, RuinSettings, BENDING_ROWS,
    GENERIC_COUNT,
};
use super::energy::{mechanical, substep_balance, EnergyFrame, MassProps};
use super::ground::GroundSpec;
use super::monitor::{start_state_from_damage, AngleRule, FeDamage, Monitor, StateCounts};
use super::rest::{body_energy_speed, frame_mean_speed, RestBody, RestSpeed, RestTest};
use super::search::{find_contacts, Contact};
use super::{BodyGeom, RuinError};
use crate::physics::{
    BodyHandle, BoxDesc, ConstraintDesc, ConstraintHandle, ConstraintKind, ConstraintParam,
    PhysicsError, Pose, SolverSettings, Spring, Velocity, World, WorldSettings,
};
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use std::collections::BTreeMap;
use std::time::{Duration, Instant};

/// Errors of the ruin stage.
#[derive(Debug, thiserror::Error)]
pub enum StageError {
    /// Bad model input.
    #[error(transparent)]
    Ruin(#[from] RuinError),
    /// Bullet refused something.
    #[error(transparent)]
    Physics(#[from] PhysicsError),
}

/// Body settings (BCB/Blender defaults, docs/bcb.md §5 and §11.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodySettings {
    /// Friction of the active bodies (BCB RC group: 1.0).
    pub friction: f64,
    /// Restitution (0).
    pub restitution: f64,
    /// Linear damping (Blender 0.04).
    pub linear_damping: f64,
    /// Angular damping (Blender 0.1).
    pub angular_damping: f64,
    /// Collision margin, m (0.04; kept inside the half extents as Blender does).
    pub margin: f64,
    /// Largest margin as a share of the box's smallest half extent (1 = BCB/Blender: the
    /// margin is only capped at the half extent). Bullet rounds a box's edges and corners
    /// with the margin's radius, so a 0.04 m margin makes a 0.1 m-thick member almost a
    /// cylinder, which rolls and rocks instead of coming to rest.
    pub margin_max_share: f64,
    /// Never deactivate (sleep) bodies (BCB: deactivation off). `false`: Bullet may put an
    /// island to sleep when every body in it has stayed below [`BodySettings::sleep_speed_mps`]
    /// for Bullet's `gDeactivationTime` (2 s); it wakes when an awake body touches it. The
    /// ground and the foundation blocks are put to sleep once the ground motion has ended
    /// (a moving kinematic body keeps everything it touches awake).
    pub disable_deactivation: bool,
    /// Sleeping threshold as a point speed, m/s: a body counts as still for Bullet when
    /// |v| < s/2 and |ω|·r < s/2 (r = half diagonal), so a sleeping body always passes the
    /// rest test's point-speed check (|v − v_g| + |ω|·r < v_tol, `super::rest`) for
    /// s ≤ v_tol. Used only when `disable_deactivation` is false. Default 0.05 (= v_tol).
    pub sleep_speed_mps: f64,
}

impl Default for BodySettings {
    fn default() -> Self {
        BodySettings {
            friction: 1.0,
            restitution: 0.0,
            linear_damping: 0.04,
            angular_damping: 0.1,
            margin: 0.04,
            margin_max_share: 1.0,
            disable_deactivation: true,
            sleep_speed_mps: 0.05,
        }
    }
}

/// Everything a ruin stage is built with.
#[derive(Debug, Clone, PartialEq)]
pub struct StageSettings {
    /// The constraint model and the stepping rates (200 substeps/s, 25 frames/s, ...).
    pub ruin: RuinSettings,
    /// The Bullet world. The solver's iteration count is replaced by
    /// `ruin.solver_iterations`.
    pub world: WorldSettings,
    /// Body settings.
    pub body: BodySettings,
    /// How the monitor measures rotation.
    pub angle_rule: AngleRule,
    /// Warm-up, s: gravity grows from 0 to its full value over this time after the start,
    /// as g·s(τ) with the smoothstep s(τ) = 3τ² − 2τ³, τ = (t − t_start)/warm-up (BCB's
    /// warm-up period: 20 frames = 0.8 s, a Bezier ease ≈ smoothstep, docs/bcb.md §4). 0 = off,
    /// the default: at a hand-off the structure is already loaded (docs/bcb.md §10.6).
    pub warmup_s: f64,
    /// Build the CT 22 connections (default). `false`: loose debris only, no constraints
    /// (e.g. the debris phase of the pybullet cross-check).
    pub connect: bool,
    /// When the monitor switches a connection to plastic, make the spring's rest pose the
    /// current relative pose (`btGeneric6DofSpring2Constraint::setEquilibriumPoint()`),
    /// as the monitor resets its own reference d₀ := d. `false` (BCB/Blender): the spring
    /// keeps the rest pose of its creation (the start), so it is switched on already
    /// stretched by the elastic stage's deformation (up to tol1D = 10 % of the centre
    /// distance) and releases that energy into the debris (docs/ruin-numerics.md).
    pub spring_rest_at_plastic_onset: bool,
    /// A ductile bending row ([`ConnectionSpec::ductile`]) that yielded in a substep is
    /// locked again at its present rotation before it is re-enabled
    /// ([`crate::physics::World::relock_constraint`]): the hinge keeps its plastic
    /// rotation, as a rigid–plastic hinge does. `false` (the first FE-derived version):
    /// the row keeps its lock at the start pose, so after yielding it drives the hinge
    /// back with the velocity bias ERP·θ/h up to its full moment — a motor that feeds
    /// energy into the frame (docs/ruin-numerics.md).
    pub hinge_keeps_rotation: bool,
    /// With `hinge_keeps_rotation`: re-lock a yielded hinge by a return mapping, at its
    /// present rotation minus the rotation error it had at its first yield, instead of at
    /// its present rotation. Re-locking at the present rotation throws away the error
    /// through which the not fully converged solver carries the moment, so the row's
    /// impulse falls to a quarter and builds back: a saw-tooth that carries 58 % of the
    /// capacity on average (frame3's base under a slow ramp); the return mapping keeps
    /// 97 % (docs/handoff.md §5, session 15). `false`: the present rotation (sessions 5–14).
    pub hinge_return_mapping: bool,
    /// How the connections' locked rows correct their error ([`JointRows`]).
    pub joint_rows: JointRows,
    /// Warm start of the connections' generic rows, 0..=1
    /// ([`crate::physics::World::set_joint_warmstart`]): each row's Gauss–Seidel solve
    /// starts from this share of its impulse in the last substep. 0 (BCB/Bullet): every
    /// joint row starts from zero in every substep, as Bullet 3.24's
    /// `btSequentialImpulseConstraintSolver::convertJoint` does (it warm-starts contacts
    /// only), so a statically loaded joint is never converged and its residual error is
    /// pulled back by the Baumgarte velocity ERP·e/h (docs/ruin-numerics.md §11).
    pub joint_warmstart: f64,
    /// Gauss–Seidel iterations of the connections' generic rows
    /// (`btTypedConstraint::setOverrideNumSolverIterations`; Bullet then runs
    /// max(this, `solver_iterations`) sweeps, contacts only in the first
    /// `solver_iterations`). `None` (BCB): the world's `solver_iterations`.
    pub joint_iterations: Option<u32>,
    /// How the joints' bilateral rows are solved at each substep
    /// ([`crate::physics::World::set_joint_solve`]): Bullet's projected Gauss–Seidel
    /// ([`crate::physics::JointSolve::Pgs`], BCB), or first a sparse LDLᵀ solve of the
    /// linear system those iterations converge to, (A + diag(Cᵢ/Dᵢ)) λ = rhsᵢ/Dᵢ − Jᵢ·Δv₀
    /// ([`crate::physics::JointSolve::Direct`]; docs/ruin-numerics.md §11.1).
    pub joint_solve: crate::physics::JointSolve,
    /// Regularisation ε of the direct solve (ε·Aᵢᵢ added to each diagonal entry: a relative
    /// CFM ε on every row), [0, 1]; default 1e-3 (docs/ruin-numerics.md §11.1).
    pub joint_solve_regularisation: f64,
    /// Mass-proportional damping relative to the moving ground, a₀ in 1/s (0: none, BCB):
    /// after every substep each active body's linear velocity relative to the ground
    /// decays by exp(−a₀·h). It is the a₀·M term of the FE's Rayleigh damping
    /// C = a₀·M + a₁·K (uniform excitation: the FE damps velocities relative to the
    /// ground; Chopra, *Dynamics of Structures*, §11.4), a dashpot from each body to the
    /// ground, so its impulse counts as the ground's in the energy ledger: the moving
    /// ground's share of its work is ground work, the rest is dissipated
    /// (docs/handoff.md §5, session 10).
    pub ground_damping_per_s: f64,
    /// Cap every plastic spring's stiffness and damping for the explicit stability of the
    /// lighter body it acts on, counting all springs on that body ([`body_spring_cap`]).
    /// `false` (BCB/Blender): only Bullet's per-spring `limitIfNeeded` cap, which takes
    /// each spring alone and the pair's mass at the centre, so a light column piece held
    /// by four plastic springs (up to 24 explicit spring rows) at lever arms is beyond
    /// explicit stability and never comes to rest (docs/ruin-numerics.md).
    pub spring_cap_per_body: bool,
    /// The substep rate whose step the per-body spring cap uses, 1/s (default 0 = the
    /// run's own substep h; option: 200, BCB's rate). The cap k ≤ 1/(16·h²·w·n) grows as
    /// h shrinks, so with h a finer substep carries stiffer springs — a different model,
    /// whose light pieces the springs whip faster; with a rate the cap takes
    /// max(h, 1/rate) and the springs are those that rate carries, at every finer substep
    /// (docs/ruin-numerics.md §19: it keeps every piece within the speed bound at 400 and
    /// 800 substeps/s but moves the ruin further from the 200-substep one, so it is an
    /// option).
    pub spring_cap_steps_per_second: f64,
    /// Run the monitor's tolerance check ([`super::monitor`]) after every substep instead
    /// of once per frame (BCB: 25 Hz). A connection whose rows leave it a mechanism (e.g.
    /// a shear row broken: the other rows become a slider) can be carried far beyond its
    /// tolerances within one frame; its locked rows then see errors of decimetres and ask
    /// for the velocity ERP·e/h (Bullet's `get_limit_motor_info2`), up to tens of m/s on a
    /// light piece (docs/ruin-numerics.md §15).
    pub monitor_every_substep: bool,
    /// When two bodies a connection holds together start touching each other
    /// ([`super::separation`]): never (BCB/Blender, the default: Bullet's exemption stays
    /// for the whole run, so broken pieces pass through each other), once nothing holds
    /// them, or once only springs do (docs/ruin-numerics.md §16).
    pub pairs_touch: super::separation::PairsTouch,
    /// Pieces joined to a foundation block touch the ground box from the start (BCB, the
    /// default). `false`: only once none of their foundation connections carries
    /// compression ([`super::separation`]).
    pub ground_under_connected_bases: bool,
    /// Solver threads (island-parallel solving, `crate::physics::speed`): the same bytes for
    /// any number. Default `FEM2RBD_THREADS`, else the machine's cores (as the FE).
    pub solver_threads: usize,
    /// The solver's sweep ([`crate::physics::World::set_sweep`]): every kind gives the same
    /// bits. Default [`crate::physics::Sweep::Packed`]; `FEM2RBD_SWEEP=bullet`, `lean` or
    /// `threads` selects another (for `bench_ruin`'s before/after).
    pub sweep: crate::physics::Sweep,
}

/// The error correction of the connections' locked (generic) rows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointRows {
    /// BCB/Blender: every row uses the world's joint ERP (`m_erp`, 0.2) and CFM 0 — a rigid
    /// lock whose error is pulled back by the velocity bias ERP·e/h.
    Locked,
    /// Each locked axis of a connection is an implicit spring–damper of the members'
    /// stiffness, given to Bullet through the row's ERP and CFM (the ODE/Bullet mapping,
    /// ERP = h·k/(h·k + c), CFM = 1/(h·k + c) for an absolute compliance): with the row's
    /// effective inverse mass K (1/m_a + 1/m_b along a linear axis, 1/I_a + 1/I_b about an
    /// angular one, passive partners 0), ω = √(k·K), x = ω·h and c = 2·ζ·√(k/K),
    /// ERP = x/(x + 2ζ) and, since Bullet's joint rows take CFM relative to K
    /// ([`crate::physics::World::set_constraint_param`]), CFM = 1/(x·(x + 2ζ)).
    /// k along the normal E·A/L, across it G·A/L, about the cross axes E·I/L, about the
    /// normal G·J/L (A = h·w the contact area, I = w·h³/12 or h·w³/12, J ≈ h·w·(h² + w²)/12,
    /// L the centre distance, G = E/(2(1 + ν)), ν = 0.2). An implicit spring–damper is
    /// stable for any k, but Bullet's Gauss–Seidel update of a joint row is not for any
    /// CFM: rows softer than [`MEMBER_ROW_MAX_CFM`] allows are stiffened to it
    /// ([`member_row_erp_cfm`]).
    Member {
        /// Young's modulus E, Pa.
        modulus_pa: f64,
        /// Damping ratio ζ of each row (dimensionless).
        damping_ratio: f64,
    },
}

/// The largest relative CFM a member row is given ([`member_row_erp_cfm`]). Bullet 3.24
/// updates a joint row by Δλ = rhs − C·λ − D·(J·Δv) with its CFM C unscaled
/// (`gResolveSingleConstraintRowGeneric_scalar_reference`; `crate::physics::jointsolve`
/// module docs). The row's own impulse enters its next value with the factor −C, so the
/// sweeps diverge when C ≥ 1. On frame3 with elastic slab panels, the slab–column angular
/// rows (k ≈ 10² N·m/rad on a 6.25 kg column piece) got C = 1.4–1.6, and the first
/// substep after a hand-off threw them to 10⁵¹ N·s (docs/ruin-numerics.md §8.3). With
/// C ≤ 0.5 the factor leaves half the error per sweep.
pub const MEMBER_ROW_MAX_CFM: f64 = 0.5;

/// ERP and CFM (relative to the row's effective mass, Bullet's joint convention) of an
/// implicit spring–damper of stiffness `k` (N/m or N·m/rad) on a row of effective inverse
/// mass `inv_mass` (1/kg or 1/(kg·m²)) at the substep `h` (s) with damping ratio `zeta`
/// ([`JointRows::Member`]): x = √(k·K)·h, ERP = x/(x + 2ζ), CFM = 1/(x·(x + 2ζ)). A row
/// whose CFM would exceed [`MEMBER_ROW_MAX_CFM`] gets the x at which it equals it,
/// x = −ζ + √(ζ² + 1/CFM_max) (0.732 for ζ = 1): it is stiffer than k, so that Bullet's
/// sweeps converge. Returns (ERP, CFM).
pub fn member_row_erp_cfm(k: f64, inv_mass: f64, h: f64, zeta: f64) -> (f64, f64) {
    let x_min = -zeta + (zeta * zeta + 1.0 / MEMBER_ROW_MAX_CFM).sqrt();
    let x = ((k * inv_mass).sqrt() * h).max(x_min);
    (x / (x + 2.0 * zeta), 1.0 / (x * (x + 2.0 * zeta)))
}

impl Default for StageSettings {
    /// BCB's world (docs/bcb.md §11.1): sequential impulses, 100 iterations, split impulse
    /// off, gravity (0, 0, −9.81); Bullet's process-globals set to Bullet's own values
    /// (gDbvtMargin 0.05, gContactBreakingThreshold 0.02) so a stage never depends on
    /// what ran before it in the process.
    fn default() -> Self {
        StageSettings {
            ruin: RuinSettings::default(),
            world: WorldSettings {
                gravity: [0.0, 0.0, -9.81],
                solver: SolverSettings {
                    split_impulse: false,
                    ..SolverSettings::default()
                },
                dbvt_margin: Some(0.05),
                contact_breaking_threshold: Some(0.02),
            },
            body: BodySettings::default(),
            angle_rule: AngleRule::default(),
            warmup_s: 0.0,
            connect: true,
            spring_rest_at_plastic_onset: false,
            hinge_keeps_rotation: true,
            hinge_return_mapping: false,
            joint_rows: JointRows::Locked,
            joint_warmstart: 0.0,
            joint_iterations: None,
            joint_solve: crate::physics::JointSolve::Pgs,
            joint_solve_regularisation: crate::physics::jointsolve::DEFAULT_REGULARISATION,
            ground_damping_per_s: 0.0,
            spring_cap_per_body: true,
            spring_cap_steps_per_second: 0.0,
            monitor_every_substep: false,
            pairs_touch: super::separation::PairsTouch::Never,
            ground_under_connected_bases: true,
            solver_threads: crate::fe::domain::default_threads(),
            sweep: match std::env::var("FEM2RBD_SWEEP").as_deref() {
                Ok("bullet") => crate::physics::Sweep::Bullet,
                Ok("lean") => crate::physics::Sweep::Lean,
                Ok("threads") => crate::physics::Sweep::PackedThreads,
                _ => crate::physics::Sweep::Packed,
            },
        }
    }
}

/// The input of [`RuinStage::build`]: one entry per body in every per-body slice.
#[derive(Debug, Clone)]
pub struct StageInput<'a> {
    /// The undeformed boxes (contacts and connection geometry come from these).
    pub bodies: &'a [BodyGeom],
    /// Masses, kg (> 0 for active bodies; ignored for passive ones).
    pub masses_kg: &'a [f64],
    /// Poses at the start (Tc), local → world.
    pub start_poses: Vec<Isometry3<f64>>,
    /// Velocities at the start, world frame (ignored for passive bodies).
    pub start_velocities: Vec<Velocity>,
    /// Group strengths.
    pub groups: &'a [GroupStrength],
    /// Start time, s (Tc; 0 in the physics-only mode).
    pub start_time_s: f64,
    /// FE damage at the start per connected body pair (a, b) with a < b (input indices);
    /// missing = intact; a pair that has no connection is ignored (a pair with a ≥ b or
    /// an index out of range is an error).
    pub start_damage: BTreeMap<(usize, usize), FeDamage>,
    /// FE-derived strengths per body (empty: BCB's group strengths only; else one entry
    /// per body) — [`super::connection::build_connections_with`].
    pub body_strengths: Vec<BodyCapacity>,
}

impl<'a> StageInput<'a> {
    /// The physics-only mode (BCB alone): undeformed poses, at rest, t = 0, no damage.
    pub fn physics_only(
        bodies: &'a [BodyGeom],
        masses_kg: &'a [f64],
        groups: &'a [GroupStrength],
    ) -> Self {
        StageInput {
            bodies,
            masses_kg,
            start_poses: bodies.iter().map(BodyGeom::pose).collect(),
            start_velocities: vec![Velocity::default(); bodies.len()],
            groups,
            start_time_s: 0.0,
            start_damage: BTreeMap::new(),
            body_strengths: Vec::new(),
        }
    }
}

/// When a run stops.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StopRule {
    /// Absolute end time, s (the run stops at the first frame at or after it).
    pub max_time_s: f64,
    /// The at-rest test; `None` = run until `max_time_s`.
    pub rest: Option<RestTest>,
}

/// One recorded frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Absolute time, s.
    pub time_s: f64,
    /// Every input body's pose, in input order.
    pub poses: Vec<Pose>,
    /// Connections per state after this frame's monitor check.
    pub counts: StateCounts,
    /// The energy ledger at this frame ([`super::energy`]).
    pub energy: EnergyFrame,
}

/// Why a ruin stage ended (`summary.json`: `at_rest`, `time_limit`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RuinStop {
    /// The rest test held for its hold time.
    AtRest,
    /// The time limit.
    TimeLimit,
}

impl RuinStop {
    /// The name written in `summary.json` (`at_rest`, `time_limit`).
    pub fn name(self) -> &'static str {
        match self {
            RuinStop::AtRest => "at_rest",
            RuinStop::TimeLimit => "time_limit",
        }
    }
}

/// Final state of one connection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConnectionOutcome {
    /// Body indices (input order).
    pub a: usize,
    /// Body B.
    pub b: usize,
    /// State at the start.
    pub start_state: ConnectionState,
    /// Final state.
    pub state: ConnectionState,
    /// Time of the frame at which it was found broken, s (`None`: not broken in the run;
    /// a connection broken from the start has `None`).
    pub broke_at_s: Option<f64>,
    /// Time it became plastic, s.
    pub plastic_at_s: Option<f64>,
    /// The first of its generic rows that Bullet let go while the connection was elastic
    /// (the row's impulse reached its breaking threshold: a brittle row broke, or a ductile
    /// bending row first yielded), and the end time of that substep, s. `None`: no row
    /// reached its threshold (the connection never was elastic, or turned plastic or broke
    /// by the monitor's tolerances first).
    pub first_row_lost: Option<(ConstraintRole, f64)>,
}

/// Wall-clock time of a run.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WallTime {
    /// Inside `World::step` (Bullet).
    pub in_bullet: Duration,
    /// The whole `run` call.
    pub total: Duration,
}

impl WallTime {
    /// in_bullet / total (1 for an empty run).
    pub fn bullet_share(&self) -> f64 {
        if self.total.is_zero() {
            1.0
        } else {
            self.in_bullet.as_secs_f64() / self.total.as_secs_f64()
        }
    }
}

/// The result of [`RuinStage::run`].
#[derive(Debug, Clone, PartialEq)]
pub struct RuinResult {
    /// Frames from the start (frame 0 = the start state), every 1/frame_rate s.
    pub frames: Vec<Frame>,
    /// Final poses, input order.
    pub final_poses: Vec<Pose>,
    /// Final velocities, input order.
    pub final_velocities: Vec<Velocity>,
    /// Per body: point speed relative to the ground below the rest test's v_tol at the
    /// end (passive bodies: true).
    pub at_rest: Vec<bool>,
    /// Per connection (in [`RuinStage::connections`] order).
    pub connections: Vec<ConnectionOutcome>,
    /// Deepest penetration between any two bodies (ground included) at the end of the
    /// first frame, m (≥ 0; Bullet's most negative contact distance, negated). Large
    /// values mean the start poses overlap (e.g. deformed boxes at Tc).
    pub first_frame_penetration_m: f64,
    /// Deepest penetration at the end of any frame, m.
    pub max_penetration_m: f64,
    /// Why it ended.
    pub stop: RuinStop,
    /// End time, s.
    pub end_time_s: f64,
    /// Wall time.
    pub wall: WallTime,
    /// Energy and speed figures of the whole run.
    pub ledger: LedgerSummary,
    /// The solver's island batches over the run (how much of the work the largest island
    /// holds, which bounds the island-parallel speed-up) and the bodies asleep at the end.
    pub islands: crate::physics::IslandStats,
    /// Dynamic bodies asleep at the end (0 unless sleeping is on).
    pub sleeping_at_end: usize,
    /// The direct joint solve's mode and counts over the run
    /// ([`StageSettings::joint_solve`]).
    pub joint_solve: crate::physics::JointSolveStats,
}

/// Energy and speed figures of a run ([`super::energy`]; the bounds of docs/ruin-numerics.md).
#[derive(Debug, Clone, PartialEq)]
pub struct LedgerSummary {
    /// Potential energy of the undeformed building relative to the ground's top, J
    /// (Σ m·|g|·height of the centre): the scale of the settle-phase energy check.
    pub initial_potential_j: f64,
    /// Height of the undeformed model, m (H of the speed bound).
    pub model_height_m: f64,
    /// |g|, m/s².
    pub gravity_mps2: f64,
    /// Largest centre speed of a dynamic body at the start (v_Tc,max), m/s.
    pub start_max_speed_mps: f64,
    /// Largest centre speed (absolute) of any dynamic body after any substep, m/s.
    pub max_speed_mps: f64,
    /// The body (input index) and time (s) of that speed (`None` without dynamic bodies).
    pub max_speed_at: Option<(usize, f64)>,
    /// Every body's point speed relative to the ground at the end, as the rest test
    /// measures it ([`LedgerSummary::rest_speed`]), m/s (passive: 0).
    pub final_point_speeds_mps: Vec<f64>,
    /// Every body's point speed from its velocities at the end (the solver's substep
    /// chatter included), m/s (passive: 0).
    pub final_instantaneous_speeds_mps: Vec<f64>,
    /// How the rest test measured the point speeds.
    pub rest_speed: RestSpeed,
    /// Energy added by the solver: the sum over substeps of the positive part of
    /// ΔE − ΔW_g + ΔD (a substep that dissipates nothing and injects nothing gives 0), J.
    pub injected_j: f64,
    /// The largest single-substep injection, J, and the time at its end, s.
    pub max_injection: (f64, f64),
}

/// A built ruin stage: the Bullet world, its handles, the connections and the monitor.
pub struct RuinStage {
    world: World,
    ground: BodyHandle,
    ground_rest: Pose,
    ground_half_extents: [f64; 3],
    ground_spec: GroundSpec,
    handles: Vec<BodyHandle>,
    passive: Vec<bool>,
    passive_start: Vec<Isometry3<f64>>,
    rest_bodies: Vec<Option<RestBody>>,
    total_mass_kg: f64,
    model_height_m: f64,
    connections: Vec<ConnectionSpec>,
    constraint_handles: Vec<Vec<ConstraintHandle>>,
    monitor: Monitor,
    start_states: Vec<ConnectionState>,
    settings: StageSettings,
    start_time_s: f64,
    substep_s: f64,
    substeps_per_frame: u64,
    substeps_done: u64,
    in_bullet: Duration,
    any_ductile: bool,
    /// Per connection, the first generic row Bullet disabled while the connection was
    /// elastic: (constraint index, time s) — [`ConnectionOutcome::first_row_lost`].
    first_lost: Vec<Option<(usize, f64)>>,
    props: Vec<Option<MassProps>>,
    ground_reference: [f64; 3],
    ground_work_j: f64,
    damping_j: f64,
    initial_potential_j: f64,
    start_max_speed_mps: f64,
    max_speed: (f64, Option<(usize, f64)>),
    last_mechanical_j: Option<f64>,
    injected_j: f64,
    max_injection: (f64, f64),
    kinematic_asleep: bool,
    axial_trace: Option<super::axial::AxialTrace>,
    body_trace: Option<super::body_trace::BodyTrace>,
    axial_left: Vec<super::axial::AxialLeft>,
    /// State changes found by the monitor inside [`Self::substeps`]
    /// ([`StageSettings::monitor_every_substep`]) with their times, s, for `run_with`.
    pending_changes: Vec<(super::monitor::StateChange, f64)>,
    /// Which bodies may not touch yet, and when they may ([`super::separation`]).
    separation: super::separation::Separation,
    /// Per (connection, bending row): the rotation error at its first yield
    /// ([`StageSettings::hinge_return_mapping`]).
    hinge_error: BTreeMap<(usize, usize), [f64; 6]>,
    axial_threshold: Vec<f64>,
}

/// Bullet's activation state `ISLAND_SLEEPING`.
const ISLAND_SLEEPING: i32 = 2;

/// nalgebra isometry → physics pose.
pub fn to_pose(p: &Isometry3<f64>) -> Pose {
    let q = p.rotation.quaternion();
    Pose {
        position: [p.translation.x, p.translation.y, p.translation.z],
        orientation: [q.w, q.i, q.j, q.k],
    }
}

/// Physics pose → nalgebra isometry.
pub fn to_isometry(p: &Pose) -> Isometry3<f64> {
    let [w, x, y, z] = p.orientation;
    Isometry3::from_parts(
        Translation3::new(p.position[0], p.position[1], p.position[2]),
        UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z)),
    )
}

fn bad(item: &str, message: String) -> StageError {
    StageError::Ruin(RuinError::BadSetting {
        item: item.into(),
        message,
    })
}

fn check_len(what: &str, expected: usize, got: usize) -> Result<(), StageError> {
    if expected != got {
        return Err(StageError::Ruin(RuinError::LengthMismatch {
            what: what.into(),
            expected,
            got,
        }));
    }
    Ok(())
}

impl RuinStage {
    /// Builds the Bullet world of a ruin stage (module docs). Errors name the body,
    /// group or setting at fault.
    pub fn build(
        input: &StageInput,
        ground: GroundSpec,
        settings: &StageSettings,
    ) -> Result<RuinStage, StageError> {
        let n = input.bodies.len();
        check_len("body masses", n, input.masses_kg.len())?;
        check_len("start poses", n, input.start_poses.len())?;
        check_len("start velocities", n, input.start_velocities.len())?;
        for (i, b) in input.bodies.iter().enumerate() {
            b.validate(i)?;
            let m = input.masses_kg[i];
            let usable = m.is_finite() && m > 0.0;
            if !b.passive && !usable {
                return Err(StageError::Ruin(RuinError::BadBody {
                    index: i,
                    name: b.name.clone(),
                    message: format!("mass {m} kg must be finite and > 0"),
                }));
            }
            let v = &input.start_velocities[i];
            if v.linear.iter().chain(&v.angular).any(|x| !x.is_finite()) {
                return Err(StageError::Ruin(RuinError::BadBody {
                    index: i,
                    name: b.name.clone(),
                    message: "start velocity is not finite".into(),
                }));
            }
        }
        let r = &settings.ruin;
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if [r.steps_per_second, r.frame_rate, r.time_scale]
            .iter()
            .any(|v| !positive(*v))
        {
            return Err(bad(
                "ruin settings",
                "steps_per_second, frame_rate and time_scale must be finite and > 0".into(),
            ));
        }
        let h = r.substep();
        let frame_sim = r.time_scale / r.frame_rate;
        let spf = (frame_sim / h).round();
        if spf < 1.0 || (frame_sim / h - spf).abs() > 1e-9 * spf {
            return Err(bad(
                "steps_per_second",
                format!(
                    "{} substeps/s is not a whole multiple of the frame rate {} frames/s",
                    r.steps_per_second, r.frame_rate
                ),
            ));
        }
        if !(settings.warmup_s.is_finite() && settings.warmup_s >= 0.0) {
            return Err(bad(
                "warmup_s",
                format!("{} must be finite and >= 0", settings.warmup_s),
            ));
        }
        if !input.start_time_s.is_finite() || input.start_time_s < 0.0 {
            return Err(bad(
                "start_time_s",
                format!("{} must be finite and >= 0", input.start_time_s),
            ));
        }
        for (name, v) in [
            ("ground plan_margin_m", ground.plan_margin_m),
            ("ground thickness_m", ground.thickness_m),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(bad(name, format!("{v} must be finite and > 0")));
            }
        }

        let mut ws = settings.world.clone();
        ws.solver.num_iterations = r.solver_iterations;
        if settings.warmup_s > 0.0 {
            ws.gravity = [0.0; 3];
        }
        let mut world = World::new(&ws)?;
        world.set_solver_threads(settings.solver_threads.max(1))?;
        if !(settings.joint_warmstart.is_finite()
            && (0.0..=1.0).contains(&settings.joint_warmstart))
        {
            return Err(bad(
                "joint_warmstart",
                format!("{} must be in [0, 1]", settings.joint_warmstart),
            ));
        }
        if settings.joint_iterations == Some(0) {
            return Err(bad("joint_iterations", "must be >= 1".into()));
        }
        world.set_joint_warmstart(settings.joint_warmstart)?;
        // ε is checked by the wrapper (and by the scenario, with its file and line).
        world.set_joint_solve(settings.joint_solve, settings.joint_solve_regularisation)?;
        world.set_sweep(settings.sweep)?;

        // 1. Ground.
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for b in input.bodies {
            let bb = b.aabb();
            for k in 0..3 {
                lo[k] = lo[k].min(bb.min[k]);
                hi[k] = hi[k].max(bb.max[k]);
            }
        }
        if n == 0 {
            lo = [0.0; 3];
            hi = [0.0; 3];
        }
        let top = ground.top_z.unwrap_or(lo[2]);
        let half = [
            0.5 * (hi[0] - lo[0]) + ground.plan_margin_m,
            0.5 * (hi[1] - lo[1]) + ground.plan_margin_m,
            0.5 * ground.thickness_m,
        ];
        let ground_rest = Pose::at([
            0.5 * (lo[0] + hi[0]),
            0.5 * (lo[1] + hi[1]),
            top - 0.5 * ground.thickness_m,
        ]);
        let t0 = input.start_time_s;
        let d0 = ground.displacement_at(t0);
        let ground_start = shifted(&ground_rest, d0);
        let mut gdesc = if ground.history.is_some() {
            BoxDesc::kinematic(half, ground_start)
        } else {
            BoxDesc::fixed(half, ground_start)
        };
        gdesc.friction = ground.friction;
        gdesc.margin = settings.body.margin;
        gdesc.restitution = settings.body.restitution;
        let ground_handle = world.add_box(&gdesc)?;

        // 2. Bodies.
        let bs = &settings.body;
        let mut handles = Vec::with_capacity(n);
        let mut rest_bodies = Vec::with_capacity(n);
        let mut total_mass = 0.0;
        for (i, b) in input.bodies.iter().enumerate() {
            let pose = to_pose(&input.start_poses[i]);
            let mut d = if b.passive {
                BoxDesc::kinematic(b.half_extents, pose)
            } else {
                BoxDesc::dynamic(b.half_extents, input.masses_kg[i], pose)
            };
            if !b.passive {
                d.velocity = input.start_velocities[i];
            }
            d.friction = if b.passive {
                ground.friction
            } else {
                bs.friction
            };
            d.restitution = bs.restitution;
            d.linear_damping = bs.linear_damping;
            d.angular_damping = bs.angular_damping;
            d.margin = bs.margin.min(
                bs.margin_max_share * b.half_extents.iter().copied().fold(f64::INFINITY, f64::min),
            );
            d.disable_deactivation = bs.disable_deactivation;
            let hnd = world.add_box(&d).map_err(|e| {
                StageError::Ruin(RuinError::BadBody {
                    index: i,
                    name: b.name.clone(),
                    message: e.to_string(),
                })
            })?;
            if !b.passive && !bs.disable_deactivation {
                let he = b.half_extents;
                let r = (he[0] * he[0] + he[1] * he[1] + he[2] * he[2]).sqrt();
                let s = 0.5 * bs.sleep_speed_mps;
                world.set_sleeping_thresholds(hnd, s, s / r)?;
            }
            handles.push(hnd);
            if b.passive {
                rest_bodies.push(None);
            } else {
                let (m, inertia) = world.mass_inertia(hnd)?;
                total_mass += m;
                let he = b.half_extents;
                rest_bodies.push(Some(RestBody {
                    mass_kg: m,
                    inertia,
                    radius_m: (he[0] * he[0] + he[1] * he[1] + he[2] * he[2]).sqrt(),
                }));
            }
        }

        // 4. + 5. Connections.
        let contacts: Vec<Contact> = if settings.connect {
            find_contacts(input.bodies, &r.search)?
        } else {
            Vec::new()
        };
        let mut connections = build_connections_with(
            input.bodies,
            input.groups,
            &contacts,
            &input.start_poses,
            r,
            &input.body_strengths,
        )?;
        for &(a, b) in input.start_damage.keys() {
            if a >= b || b >= n {
                return Err(bad(
                    "start damage",
                    format!("body pair ({a}, {b}) must have a < b < {n}"),
                ));
            }
        }
        let mut start_states = Vec::with_capacity(connections.len());
        for c in connections.iter_mut() {
            let dmg = input
                .start_damage
                .get(&(c.a, c.b))
                .copied()
                .unwrap_or(FeDamage::Intact);
            let mut s = if c.lost_at_start {
                ConnectionState::Broken
            } else {
                start_state_from_damage(dmg)
            };
            if s == ConnectionState::Plastic && !c.has_spring() {
                s = ConnectionState::Broken;
            }
            c.set_state(s);
            start_states.push(s);
        }
        // Plastic springs per body (for the per-body stability cap).
        let mut springs_on = vec![0usize; n];
        for c in connections.iter().filter(|c| c.has_spring()) {
            for b in [c.a, c.b] {
                if !input.bodies[b].passive {
                    springs_on[b] += 1;
                }
            }
        }
        let mut constraint_handles = Vec::with_capacity(connections.len());
        for c in &connections {
            let mut hs = Vec::with_capacity(c.constraints.len());
            for spec in &c.constraints {
                let kind = match spec.kind {
                    SpecKind::Generic6Dof => ConstraintKind::Generic6Dof {
                        use_linear_reference_frame_a: true,
                    },
                    SpecKind::Spring2 => {
                        let mut springs = [None; 6];
                        for (k, s) in springs.iter_mut().enumerate() {
                            if spec.spring[k] {
                                let (mut stiffness, mut damping) =
                                    (spec.stiffness[k], spec.damping[k]);
                                if settings.spring_cap_per_body {
                                    let (kc, dc) = body_spring_cap(
                                        &world,
                                        c,
                                        spec,
                                        k,
                                        &handles,
                                        input,
                                        spring_cap_step(h, settings.spring_cap_steps_per_second),
                                        springs_on[c.a].max(springs_on[c.b]),
                                    )?;
                                    stiffness = stiffness.min(kc);
                                    damping = damping.min(dc);
                                }
                                *s = Some(Spring {
                                    stiffness,
                                    damping,
                                    limit_if_needed: settings.ruin.spring_limit_if_needed,
                                });
                            }
                        }
                        ConstraintKind::Spring2 {
                            springs,
                            set_equilibrium_point: true,
                        }
                    }
                };
                let mut desc = ConstraintDesc::new(
                    kind,
                    handles[c.a],
                    handles[c.b],
                    to_pose(&spec.frame_a),
                    to_pose(&spec.frame_b),
                );
                for k in 0..6 {
                    desc.limits[k] = Some((spec.lower[k], spec.upper[k]));
                }
                desc.breaking_impulse_threshold = spec.breaking_impulse;
                desc.disable_collisions_between = c.disable_collisions;
                desc.enabled = spec.enabled;
                if spec.kind == SpecKind::Generic6Dof {
                    desc.override_solver_iterations = settings.joint_iterations;
                }
                let hnd = world.add_constraint(&desc).map_err(|e| {
                    bad(
                        &format!(
                            "connection {} – {} ({:?} row)",
                            input.bodies[c.a].name, input.bodies[c.b].name, spec.role
                        ),
                        e.to_string(),
                    )
                })?;
                if let (
                    JointRows::Member {
                        modulus_pa,
                        damping_ratio,
                    },
                    SpecKind::Generic6Dof,
                ) = (settings.joint_rows, spec.kind)
                {
                    for axis in (0..6).filter(|&a| spec.lower[a] <= spec.upper[a]) {
                        let (k, inv_m) = member_row(
                            &world,
                            c,
                            spec,
                            axis,
                            &handles,
                            input,
                            modulus_pa,
                            passive_of(input, c),
                        )?;
                        let (erp, cfm) = member_row_erp_cfm(k, inv_m, h, damping_ratio);
                        world.set_constraint_param(hnd, ConstraintParam::StopErp, axis, erp)?;
                        world.set_constraint_param(hnd, ConstraintParam::StopCfm, axis, cfm)?;
                    }
                }
                hs.push(hnd);
            }
            constraint_handles.push(hs);
        }
        let monitor = Monitor::new(
            &connections,
            &input.start_poses,
            &start_states,
            settings.angle_rule,
        )?;
        let passive: Vec<bool> = input.bodies.iter().map(|b| b.passive).collect();
        let separation = super::separation::Separation::new(
            connections.iter().map(|c| (c.a, c.b, c.disable_collisions)),
            &passive,
            settings.pairs_touch,
            settings.ground_under_connected_bases,
        );
        for i in separation.ground_exempt() {
            world.set_collision_with(handles[i], ground_handle, false)?;
        }
        let model_height_m = (hi[2] - lo[2]).max(0.0);
        let any_ductile = connections.iter().any(|c| c.ductile);
        let connections_len = connections.len();
        let props: Vec<Option<MassProps>> = rest_bodies
            .iter()
            .map(|r| {
                r.map(|r| MassProps {
                    mass_kg: r.mass_kg,
                    inertia: r.inertia,
                })
            })
            .collect();
        let ground_reference = [ground_rest.position[0], ground_rest.position[1], top];
        let undeformed: Vec<Pose> = input.bodies.iter().map(|b| to_pose(&b.pose())).collect();
        let still = vec![Velocity::default(); n];
        let (_, _, initial_potential_j) = mechanical(
            &props,
            &undeformed,
            &still,
            settings.world.gravity,
            ground_reference,
        );
        let start_max_speed_mps = (0..n)
            .filter(|&i| props[i].is_some())
            .map(|i| {
                let l = input.start_velocities[i].linear;
                (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt()
            })
            .fold(0.0, f64::max);
        let names: Vec<String> = input.bodies.iter().map(|b| b.name.clone()).collect();
        let body_trace =
            super::body_trace::BodyTrace::from_env(&names).map_err(|(item, m)| bad(item, m))?;
        let mut stage = RuinStage {
            world,
            ground: ground_handle,
            ground_rest,
            ground_half_extents: half,
            ground_spec: ground,
            handles,
            passive,
            passive_start: input.start_poses.clone(),
            rest_bodies,
            total_mass_kg: total_mass,
            model_height_m,
            constraint_handles,
            monitor,
            start_states,
            settings: settings.clone(),
            start_time_s: t0,
            substep_s: h,
            substeps_per_frame: spf as u64,
            substeps_done: 0,
            in_bullet: Duration::ZERO,
            any_ductile,
            first_lost: vec![None; connections_len],
            props,
            ground_reference,
            ground_work_j: 0.0,
            damping_j: 0.0,
            initial_potential_j,
            start_max_speed_mps,
            max_speed: (start_max_speed_mps, None),
            last_mechanical_j: None,
            injected_j: 0.0,
            max_injection: (0.0, t0),
            kinematic_asleep: false,
            axial_trace: super::axial::AxialTrace::from_env(names.clone(), connections.len()),
            body_trace,
            // Two-way rows (constraint 0 locked at [0, 0] on the normal); a connection
            // built with BCB's rows (a sense without strength) is left to Bullet.
            axial_left: connections
                .iter()
                .map(|c| match c.constraints.first() {
                    Some(k)
                        if settings.ruin.axial_rows == super::axial::AxialRows::TwoWay
                            && k.lower[0] == k.upper[0] =>
                    {
                        super::axial::AxialLeft::Both
                    }
                    _ => super::axial::AxialLeft::None,
                })
                .collect(),
            axial_threshold: connections
                .iter()
                .map(|c| c.constraints.first().map_or(0.0, |k| k.breaking_impulse))
                .collect(),
            pending_changes: Vec::new(),
            separation,
            hinge_error: Default::default(),
            connections,
        };
        let enabled = stage.world.constraints_enabled()?;
        stage.lift_separations(&enabled)?;
        Ok(stage)
    }

    /// The Bullet world (read access, e.g. for contacts).
    pub fn world(&self) -> &World {
        &self.world
    }

    /// The ground's handle.
    pub fn ground(&self) -> BodyHandle {
        self.ground
    }

    /// The ground's pose with zero displacement.
    pub fn ground_rest_pose(&self) -> Pose {
        self.ground_rest
    }

    /// The ground box's half extents, m.
    pub fn ground_half_extents(&self) -> [f64; 3] {
        self.ground_half_extents
    }

    /// The settings the stage was built with.
    pub fn settings(&self) -> &StageSettings {
        &self.settings
    }

    /// The world handle of input body `i`.
    pub fn body(&self, i: usize) -> BodyHandle {
        self.handles[i]
    }

    /// The connections (specs as created, with their starting `enabled` flags).
    pub fn connections(&self) -> &[ConnectionSpec] {
        &self.connections
    }

    /// The Bullet handles of connection `i`'s constraints, in spec order.
    pub fn constraint_handles(&self, i: usize) -> &[ConstraintHandle] {
        &self.constraint_handles[i]
    }

    /// The monitor.
    pub fn monitor(&self) -> &Monitor {
        &self.monitor
    }

    /// Current absolute time, s.
    pub fn time_s(&self) -> f64 {
        self.start_time_s + self.substeps_done as f64 * self.substep_s
    }

    /// The substep h, s.
    pub fn substep_s(&self) -> f64 {
        self.substep_s
    }

    /// Substeps per monitor frame.
    pub fn substeps_per_frame(&self) -> u64 {
        self.substeps_per_frame
    }

    /// Runs `count` substeps, moving the ground and the passive bodies before each one
    /// (no monitor: [`RuinStage::run`] calls it once per frame). After every substep the
    /// energy ledger's ground work and damping loss ([`super::energy`]) and the largest
    /// body speed are updated from the velocities before and after it.
    pub fn substeps(&mut self, count: u64) -> Result<(), StageError> {
        let h = self.substep_s;
        let warmup = self.settings.warmup_s;
        let t0 = self.start_time_s;
        let d_start = self.ground_spec.displacement_at(t0);
        let has_motion = self.ground_spec.history.is_some();
        let g_full = self.settings.world.gravity;
        let (ld, ad) = (
            self.settings.body.linear_damping,
            self.settings.body.angular_damping,
        );
        let mut poses0 = self.body_poses()?;
        let mut vels0 = self.body_velocities()?;
        if self.last_mechanical_j.is_none() {
            let (a, b, c) = mechanical(&self.props, &poses0, &vels0, g_full, self.ground_reference);
            self.last_mechanical_j = Some(a + b + c);
        }
        for _ in 0..count {
            let t_cur = self.time_s();
            let t_next = t0 + (self.substeps_done + 1) as f64 * h;
            let mut g = g_full;
            if warmup > 0.0 && (self.substeps_done as f64) * h < warmup {
                let tau = ((self.substeps_done + 1) as f64 * h / warmup).min(1.0);
                let f = tau * tau * (3.0 - 2.0 * tau);
                g = [g_full[0] * f, g_full[1] * f, g_full[2] * f];
                self.world.set_gravity(g)?;
            }
            let mut vg = [0.0; 3];
            if has_motion {
                let d = self.ground_spec.displacement_at(t_next);
                let d_prev = self.ground_spec.displacement_at(t_cur);
                vg = [
                    (d[0] - d_prev[0]) / h,
                    (d[1] - d_prev[1]) / h,
                    (d[2] - d_prev[2]) / h,
                ];
                self.world.set_kinematic_target(
                    self.ground,
                    shifted(&self.ground_rest, d),
                    None,
                )?;
                let dd = [d[0] - d_start[0], d[1] - d_start[1], d[2] - d_start[2]];
                for i in 0..self.handles.len() {
                    if self.passive[i] {
                        let p = shifted(&to_pose(&self.passive_start[i]), dd);
                        self.world.set_kinematic_target(self.handles[i], p, None)?;
                    }
                }
            }
            if !self.settings.body.disable_deactivation
                && !self.kinematic_asleep
                && t_cur >= self.ground_spec.motion_end_s() + h
            {
                // The ground has stopped (its velocity from the last substep is 0): let it
                // and the foundations sleep so they stop waking what rests on them.
                self.world
                    .set_activation_state(self.ground, ISLAND_SLEEPING)?;
                for i in 0..self.handles.len() {
                    if self.passive[i] {
                        self.world
                            .set_activation_state(self.handles[i], ISLAND_SLEEPING)?;
                    }
                }
                self.kinematic_asleep = true;
            }
            let traced_before = match &self.body_trace {
                Some(tr) if tr.wants(t_next) => Some((
                    self.world.constraints_enabled()?,
                    self.world.velocity(self.handles[tr.body])?,
                )),
                _ => None,
            };
            let t = Instant::now();
            self.world.step(h, 1)?;
            self.in_bullet += t.elapsed();
            self.substeps_done += 1;
            let enabled = self.world.constraints_enabled()?;
            self.note_lost_rows(&enabled, t_next);
            self.restore_ductile_rows(&enabled)?;
            self.check_two_way_axial(&enabled, t_next)?;
            if self.separation.pending() {
                self.lift_separations(&self.world.constraints_enabled()?)?;
            }
            self.damp_relative_to_ground(vg, h)?;
            let vels1 = self.body_velocities()?;
            let b = substep_balance(&self.props, &poses0, &vels0, &vels1, h, g, vg, ld, ad);
            self.ground_work_j += b.ground_work_j;
            self.damping_j += b.damping_j;
            for (i, v) in vels1.iter().enumerate() {
                if self.props[i].is_some() {
                    let l = v.linear;
                    let s = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
                    if s > self.max_speed.0 {
                        self.max_speed = (s, Some((i, t_next)));
                    }
                }
            }
            let poses1 = self.body_poses()?;
            let gref = self.ground_reference;
            let (t1, r1, v1) = mechanical(&self.props, &poses1, &vels1, g_full, gref);
            let e1 = t1 + r1 + v1;
            let mut added = 0.0;
            if let Some(e0) = self.last_mechanical_j {
                // Energy the substep added beyond the ground's work (the balance's
                // negative part; damping is a loss, so it is added back).
                added = e1 - e0 - b.ground_work_j + b.damping_j;
                if added > 0.0 {
                    self.injected_j += added;
                    if added > self.max_injection.0 {
                        self.max_injection = (added, t_next);
                    }
                }
            }
            self.last_mechanical_j = Some(e1);
            if self.axial_trace.is_some() {
                self.trace_axial(t_next, &poses1, &vels1)?;
            }
            if let Some((en0, v0)) = traced_before {
                self.trace_body(t_next, &en0, &enabled, v0, added)?;
            }
            if self.settings.monitor_every_substep {
                for ch in self.monitor_at(&poses1)? {
                    self.pending_changes.push((ch, t_next));
                }
            }
            poses0 = poses1;
            vels0 = vels1;
        }
        Ok(())
    }

    /// Two-way axial rows ([`super::axial::AxialRows::TwoWay`], elastic connections only):
    /// a two-way row whose impulse in the last substep reached the breaking impulse of the
    /// sense it pushed in ([`super::axial::two_way_breaks`]) becomes BCB's one-way row of
    /// the other sense with that sense's breaking impulse (BCB's rows break one at a time);
    /// when that row is gone too, the connection's tension constraint (which has no rows)
    /// is disabled with it. A row Bullet disabled below its sense's breaking impulse is
    /// enabled again; the Bullet threshold (and clamp) of the next substep is the breaking
    /// impulse of the sense the row pushed in (the smaller one after a substep without
    /// impulse).
    ///
    /// `enabled`: every constraint's flag right after the substep; `t`: its end time, s.
    fn check_two_way_axial(&mut self, enabled: &[bool], t: f64) -> Result<(), StageError> {
        use super::axial::{two_way_breaks, AxialLeft, COMPRESSION_SIGN};
        use super::connection::BCB_UNLIMITED;
        if self.settings.ruin.axial_rows != super::axial::AxialRows::TwoWay {
            return Ok(());
        }
        let kappa_h = self.settings.ruin.linear_correction * self.substep_s;
        for (i, c) in self.connections.iter().enumerate() {
            if self.monitor.state(i) != ConnectionState::Elastic {
                continue;
            }
            let hs = &self.constraint_handles[i];
            let (Some(&h0), Some(&h1)) = (hs.first(), hs.get(1)) else {
                continue;
            };
            let (c_ns, t_ns) = (
                c.forces.compression_n * kappa_h,
                c.forces.tension_n * kappa_h,
            );
            match self.axial_left[i] {
                AxialLeft::Both => {
                    let lambda = self.world.applied_impulse(h0)?;
                    let pushing = lambda * COMPRESSION_SIGN;
                    if two_way_breaks(lambda, c_ns, t_ns) {
                        if let Some(tr) = self.axial_trace.as_mut() {
                            tr.note_break(t, i, lambda, c_ns, t_ns);
                        }
                        let role = if pushing > 0.0 { 0 } else { 1 };
                        self.first_lost[i].get_or_insert((role, t));
                        let (lo, hi, t, left) = if pushing > 0.0 {
                            (-BCB_UNLIMITED, 0.0, t_ns, AxialLeft::Tension)
                        } else {
                            (0.0, BCB_UNLIMITED, c_ns, AxialLeft::Compression)
                        };
                        self.world.set_constraint_limit(h0, 0, lo, hi)?;
                        self.world.set_breaking_threshold(h0, t)?;
                        self.world.set_constraint_enabled(h0, true)?;
                        self.axial_left[i] = left;
                    } else {
                        if !enabled[h0.index()] {
                            // Bullet's sign-blind test at the other sense's threshold: not
                            // a break of this sense (the impulse was clamped there).
                            self.world.set_constraint_enabled(h0, true)?;
                        }
                        // Next substep: the threshold of the sense the row pushed in.
                        let next = if pushing > 0.0 {
                            c_ns
                        } else if pushing < 0.0 {
                            t_ns
                        } else {
                            c_ns.min(t_ns)
                        };
                        if next != self.axial_threshold[i] {
                            self.world.set_breaking_threshold(h0, next)?;
                            self.axial_threshold[i] = next;
                        }
                    }
                }
                AxialLeft::Compression | AxialLeft::Tension => {
                    if !enabled[h0.index()] {
                        let role = if self.axial_left[i] == AxialLeft::Compression {
                            0
                        } else {
                            1
                        };
                        self.first_lost[i].get_or_insert((role, t));
                        self.axial_left[i] = AxialLeft::None;
                        if enabled[h1.index()] {
                            self.world.set_constraint_enabled(h1, false)?;
                        }
                    }
                }
                AxialLeft::None => {}
            }
        }
        Ok(())
    }

    /// Feeds the debug trace of `super::body_trace` after the substep ending at `t`
    /// (`en0`, `en1`: every constraint's flag before and right after it, before the
    /// stage's own row checks; `v0`: the body's velocity before it; `added`: the energy
    /// the substep added beyond the ground's work, J, the ledger's balance).
    fn trace_body(
        &mut self,
        t: f64,
        en0: &[bool],
        en1: &[bool],
        v0: Velocity,
        added: f64,
    ) -> Result<(), StageError> {
        let Some(tr) = self.body_trace.as_ref() else {
            return Ok(());
        };
        let i = tr.body;
        let me = self.handles[i];
        let v1 = self.world.velocity(me)?;
        let p = self.world.pose(me)?;
        let mut lines = vec![format!(
            "t {t:.5} pos {:.4} {:.4} {:.4} v0 {:.3} {:.3} {:.3} v1 {:.3} {:.3} {:.3} w1 {:.2} {:.2} {:.2} added_j {added:.2}",
            p.position[0], p.position[1], p.position[2],
            v0.linear[0], v0.linear[1], v0.linear[2],
            v1.linear[0], v1.linear[1], v1.linear[2],
            v1.angular[0], v1.angular[1], v1.angular[2]
        )];
        for (ci, c) in self.connections.iter().enumerate() {
            if c.a != i && c.b != i {
                continue;
            }
            let other = if c.a == i { c.b } else { c.a };
            if let Some(f) = c.constraints.first() {
                let pa = to_isometry(&self.world.pose(self.handles[c.a])?) * f.frame_a;
                let pb = to_isometry(&self.world.pose(self.handles[c.b])?) * f.frame_b;
                let d = pa.rotation.inverse() * (pb.translation.vector - pa.translation.vector);
                let r = (pa.rotation.inverse() * pb.rotation).to_rotation_matrix();
                let m = r.matrix();
                // XYZ Euler angles (R = Rx·Ry·Rz): y = asin(m02), gimbal lock at ±π/2.
                let y = m[(0, 2)].clamp(-1.0, 1.0).asin();
                let x = (-m[(1, 2)]).atan2(m[(2, 2)]);
                let z = (-m[(0, 1)]).atan2(m[(0, 0)]);
                lines.push(format!(
                    "  frame {ci} {} d {:.4} {:.4} {:.4} xyz {x:.3} {y:.3} {z:.3}",
                    tr.names[other], d.x, d.y, d.z
                ));
            }
            for (k, &h) in self.constraint_handles[ci].iter().enumerate() {
                let (e0, e1) = (en0[h.index()], en1[h.index()]);
                if !e0 && !e1 {
                    continue;
                }
                let lambda = self.world.applied_impulse(h)?;
                let fb = self.world.joint_feedback(h)?;
                let f = if c.a == i { fb.force_a } else { fb.force_b };
                let fm = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
                lines.push(format!(
                    "  conn {ci} {} k{k} on {e0}->{e1} lambda {lambda:.4} thr {:.4} F {:.0} {:.0} {:.0} |F| {fm:.0}",
                    tr.names[other],
                    self.world.breaking_threshold(h)?,
                    f[0], f[1], f[2]
                ));
            }
        }
        for pair in self.world.contact_pairs()? {
            let (a, b) = (pair.body_a, pair.body_b);
            let other = if a == me {
                b
            } else if b == me {
                a
            } else {
                continue;
            };
            let name = self
                .handles
                .iter()
                .position(|&x| x == other)
                .map_or("ground".to_string(), |j| tr.names[j].clone());
            lines.push(format!(
                "  contact {name} n {} d {:.4} J {:.4}",
                pair.contact.num_points,
                pair.contact.min_distance,
                pair.contact.total_normal_impulse
            ));
        }
        if let Some(tr) = self.body_trace.as_mut() {
            for l in lines {
                tr.push(l);
            }
        }
        Ok(())
    }

    /// Feeds the debug trace of `super::axial` after one substep.
    fn trace_axial(&mut self, t: f64, poses: &[Pose], vels: &[Velocity]) -> Result<(), StageError> {
        let enabled = self.world.constraints_enabled()?;
        let iso: Vec<Isometry3<f64>> = poses.iter().map(to_isometry).collect();
        let mut axial = Vec::with_capacity(self.connections.len());
        let mut pairs = Vec::with_capacity(self.connections.len());
        for (i, c) in self.connections.iter().enumerate() {
            let hs = &self.constraint_handles[i];
            let on = hs.iter().take(2).any(|h| enabled[h.index()]);
            let x = on.then(|| {
                let f = &c.constraints[0];
                super::axial::axial_offset(&iso[c.a], &iso[c.b], &f.frame_a, &f.frame_b)
            });
            axial.push(x);
            pairs.push((c.a, c.b));
        }
        let v: Vec<Option<[f64; 3]>> = vels
            .iter()
            .zip(&self.passive)
            .map(|(v, p)| (!p).then_some(v.linear))
            .collect();
        if let Some(tr) = self.axial_trace.as_mut() {
            tr.after_substep(t, &axial, &pairs, &v);
        }
        Ok(())
    }
    /// Records, per elastic connection, the first generic row that Bullet disabled in the
    /// substep just taken (its impulse reached the breaking threshold,
    /// `btTypedConstraint::m_breakingImpulseThreshold`): a brittle row's break, or a ductile
    /// bending row's first yield (the row is enabled again by
    /// [`Self::restore_ductile_rows`]). The two-way axial row is recorded by
    /// [`Self::check_two_way_axial`], which tells its breaks from Bullet's sign-blind test.
    /// `enabled`: every constraint's flag after the substep; `t`: its end time, s.
    fn note_lost_rows(&mut self, enabled: &[bool], t: f64) {
        let two_way = self.settings.ruin.axial_rows == super::axial::AxialRows::TwoWay;
        for (i, c) in self.connections.iter().enumerate() {
            if self.first_lost[i].is_some() || self.monitor.state(i) != ConnectionState::Elastic {
                continue;
            }
            for (k, spec) in c.constraints.iter().enumerate().take(GENERIC_COUNT) {
                if !spec.enabled || spec.no_strength || (two_way && k < 2) {
                    continue;
                }
                if self.constraint_handles[i]
                    .get(k)
                    .is_some_and(|h| !enabled[h.index()])
                {
                    self.first_lost[i] = Some((k, t));
                    break;
                }
            }
        }
    }

    /// [`StageSettings::ground_damping_per_s`]: v ← v_g + (v − v_g)·exp(−a₀·h) for every
    /// active body's linear velocity (`vg`: the ground's velocity in the substep).
    fn damp_relative_to_ground(&mut self, vg: [f64; 3], h: f64) -> Result<(), StageError> {
        let a0 = self.settings.ground_damping_per_s;
        if a0 <= 0.0 {
            return Ok(());
        }
        let f = (-a0 * h).exp();
        let vels = self.body_velocities()?;
        for (i, v) in vels.iter().enumerate() {
            // A body whose velocity is no longer finite has blown up: it is left as it is,
            // so the run ends with the error naming it, the time and the settings
            // (`pipeline::check_finite`) rather than Bullet's refusal of a NaN here.
            let finite = v.linear.iter().chain(&v.angular).all(|x| x.is_finite());
            if self.props[i].is_none() || !finite {
                continue;
            }
            let linear = [0, 1, 2].map(|k| vg[k] + (v.linear[k] - vg[k]) * f);
            self.world.set_velocity(
                self.handles[i],
                Velocity {
                    linear,
                    angular: v.angular,
                },
            )?;
        }
        Ok(())
    }

    /// Ductile bending rows of elastic connections that Bullet disabled in the last
    /// substep are enabled again ([`ConnectionSpec::ductile`]).
    fn restore_ductile_rows(&mut self, enabled: &[bool]) -> Result<(), StageError> {
        if !self.any_ductile {
            return Ok(());
        }
        // (connection, bending row, constraint, locked-axis mask) of every yielded row.
        let mut yielded = Vec::new();
        for (i, c) in self.connections.iter().enumerate() {
            if !c.ductile || self.monitor.state(i) != ConnectionState::Elastic {
                continue;
            }
            for k in BENDING_ROWS {
                let Some(spec) = c.constraints.get(k) else {
                    continue;
                };
                if spec.no_strength {
                    continue;
                }
                if let Some(&h) = self.constraint_handles[i].get(k) {
                    if !enabled[h.index()] {
                        let mask = (0..6)
                            .filter(|&a| spec.lower[a] == spec.upper[a])
                            .fold(0u8, |m, a| m | (1 << a));
                        yielded.push((i, k, h, mask));
                    }
                }
            }
        }
        for (i, k, h, mask) in yielded {
            if self.settings.hinge_keeps_rotation {
                if self.settings.hinge_return_mapping {
                    self.relock_keeping_elastic_error(i, k, h, mask)?;
                } else {
                    self.world.relock_constraint(h, mask)?;
                }
            }
            self.world.set_constraint_enabled(h, true)?;
        }
        Ok(())
    }

    /// Re-locks the locked axes `mask` of the yielded ductile row `k` of connection `i`
    /// (constraint `h`) by a return
    /// mapping ([`StageSettings::hinge_return_mapping`]): at its first yield the lock stays
    /// and the row's rotation error e₀ = θ − θ_lock per locked axis is kept; at every later
    /// yield the lock moves to θ − sign(e)·min(|e₀|, |e|) (θ when the hinge turned back,
    /// sign(e) ≠ sign(e₀): a kept error of the other sign would drive it like a motor at
    /// ERP·e/h), so the row starts the next
    /// substep with the error through which the (not fully converged) solver carried its
    /// capacity, and θ_lock follows the plastic rotation (elastic–plastic return mapping;
    /// Simo and Hughes, *Computational Inelasticity*, 1998, §1.4), rad (m on linear axes).
    fn relock_keeping_elastic_error(
        &mut self,
        i: usize,
        k: usize,
        h: ConstraintHandle,
        mask: u8,
    ) -> Result<(), StageError> {
        let axes = (0..6).filter(|a| mask & (1 << a) != 0);
        let mut err = [0.0; 6];
        let mut lock = [0.0; 6];
        for a in axes.clone() {
            let (v, lo) = self.world.constraint_axis_value(h, a)?;
            err[a] = v - lo;
            lock[a] = lo;
        }
        match self.hinge_error.get(&(i, k)) {
            None => {
                self.hinge_error.insert((i, k), err);
            }
            Some(e0) => {
                for a in axes {
                    let keep = if err[a] * e0[a] > 0.0 {
                        e0[a].abs().min(err[a].abs()) * err[a].signum()
                    } else {
                        0.0
                    };
                    let l = lock[a] + err[a] - keep;
                    self.world.set_constraint_limit(h, a, l, l)?;
                }
            }
        }
        Ok(())
    }

    /// The debug trace of one body (`super::body_trace`, on only with
    /// `FEM2RBD_BODY_TRACE=<file>`): its file and text, for the caller to write.
    pub fn body_trace_report(&self) -> Option<(std::path::PathBuf, String)> {
        self.body_trace.as_ref().map(|t| t.report())
    }

    /// The debug trace of the axial rows (`super::axial`, on only with
    /// `FEM2RBD_AXIAL_TRACE=<file>`): its file and text, for the caller to write.
    pub fn axial_trace_report(&self) -> Option<(std::path::PathBuf, String)> {
        let pairs: Vec<(usize, usize)> = self.connections.iter().map(|c| (c.a, c.b)).collect();
        self.axial_trace.as_ref().map(|t| t.report(&pairs))
    }

    /// The energy ledger now ([`super::energy`]).
    pub fn energy(&self) -> Result<EnergyFrame, StageError> {
        let (tt, tr, v) = mechanical(
            &self.props,
            &self.body_poses()?,
            &self.body_velocities()?,
            self.settings.world.gravity,
            self.ground_reference,
        );
        Ok(EnergyFrame {
            kinetic_translational_j: tt,
            kinetic_rotational_j: tr,
            potential_j: v,
            ground_work_j: self.ground_work_j,
            damping_j: self.damping_j,
            injected_j: self.injected_j,
        })
    }

    /// The poses of the input bodies, input order.
    pub fn body_poses(&self) -> Result<Vec<Pose>, StageError> {
        let all = self.world.poses()?;
        Ok(self.handles.iter().map(|h| all[h.index()]).collect())
    }

    /// The velocities of the input bodies, input order.
    pub fn body_velocities(&self) -> Result<Vec<Velocity>, StageError> {
        let all = self.world.velocities()?;
        Ok(self.handles.iter().map(|h| all[h.index()]).collect())
    }

    /// One monitor frame: check the connections at the current poses, apply the actions.
    /// Returns the state changes (connection, from, to).
    pub fn monitor_frame(&mut self) -> Result<Vec<super::monitor::StateChange>, StageError> {
        let poses = self.body_poses()?;
        self.monitor_at(&poses)
    }

    /// [`Self::monitor_frame`] at the bodies' current `poses` (already read).
    fn monitor_at(
        &mut self,
        poses: &[Pose],
    ) -> Result<Vec<super::monitor::StateChange>, StageError> {
        let poses: Vec<Isometry3<f64>> = poses.iter().map(to_isometry).collect();
        let enabled = self.world.constraints_enabled()?;
        let handles = &self.constraint_handles;
        let actions = self.monitor.check(&poses, |c, k| {
            handles[c].get(k).is_some_and(|h| enabled[h.index()])
        })?;
        for a in actions {
            let h = self.constraint_handles[a.connection][a.constraint];
            self.world.set_constraint_enabled(h, a.enable)?;
            let spring =
                self.connections[a.connection].constraints[a.constraint].kind == SpecKind::Spring2;
            if a.enable && spring && self.settings.spring_rest_at_plastic_onset {
                self.world.set_equilibrium_point(h)?;
            }
        }
        let changes = self.monitor.last_changes().to_vec();
        if self.separation.pending() && !changes.is_empty() {
            let enabled = self.world.constraints_enabled()?;
            self.lift_separations(&enabled)?;
        }
        Ok(changes)
    }

    /// Lets the pairs none of whose connections holds any more touch again
    /// ([`super::separation`]). `enabled`: every constraint's flag now.
    fn lift_separations(&mut self, enabled: &[bool]) -> Result<(), StageError> {
        use super::axial::AxialLeft;
        use super::separation::{Other, Until};
        let handles = &self.constraint_handles;
        let axial_left = &self.axial_left;
        let lifted = self.separation.lift(|c, until| {
            let on = |k: usize| handles[c].get(k).is_some_and(|h| enabled[h.index()]);
            match until {
                Until::Broken => (0..handles[c].len()).any(on),
                Until::Yielded => (0..GENERIC_COUNT).any(on),
                // Constraint 0 is the axial row: BCB's compression row, or the two-way
                // row, which may have broken in compression and carry tension only.
                Until::CompressionLost => on(0) && axial_left.get(c) != Some(&AxialLeft::Tension),
            }
        });
        for (i, other) in lifted {
            let o = match other {
                Other::Body(j) => self.handles[j],
                Other::Ground => self.ground,
            };
            self.world.set_collision_with(self.handles[i], o, true)?;
        }
        Ok(())
    }

    /// Kinetic energy of the dynamic bodies relative to the ground (J), the largest point
    /// speed (m/s) and each body's point speed (passive: 0) — see [`super::rest`].
    pub fn motion_measures(&self) -> Result<(f64, f64, Vec<f64>), StageError> {
        let poses = self.body_poses()?;
        let vels = self.body_velocities()?;
        let vg = self.ground_spec.velocity_at(self.time_s());
        let mut e = 0.0;
        let mut vmax: f64 = 0.0;
        let mut speeds = vec![0.0; self.handles.len()];
        for i in 0..self.handles.len() {
            if let Some(rb) = &self.rest_bodies[i] {
                let (ei, si) = body_energy_speed(
                    rb,
                    poses[i].orientation,
                    vels[i].linear,
                    vels[i].angular,
                    vg,
                );
                e += ei;
                vmax = vmax.max(si);
                speeds[i] = si;
            }
        }
        Ok((e, vmax, speeds))
    }

    /// Each body's frame-mean point speed relative to the ground over the last of
    /// `frames` (m/s; passive: 0) — [`super::rest::frame_mean_speed`]; `None` before a
    /// frame has ended.
    fn last_frame_mean_speeds(&self, frames: &[Frame]) -> Option<Vec<f64>> {
        let [.., f0, f1] = frames else {
            return None;
        };
        let (t0, t1, p0, p1) = (f0.time_s, f1.time_s, &f0.poses, &f1.poses);
        let (g0, g1) = (
            self.ground_spec.displacement_at(t0),
            self.ground_spec.displacement_at(t1),
        );
        let shift = [g1[0] - g0[0], g1[1] - g0[1], g1[2] - g0[2]];
        Some(
            (0..self.handles.len())
                .map(|i| match &self.rest_bodies[i] {
                    Some(rb) => frame_mean_speed(
                        rb,
                        (p0[i].position, p0[i].orientation),
                        (p1[i].position, p1[i].orientation),
                        shift,
                        t1 - t0,
                    ),
                    None => 0.0,
                })
                .collect(),
        )
    }

    /// The deepest penetration between any two bodies after the last substep, m (≥ 0).
    pub fn deepest_penetration(&self) -> Result<f64, StageError> {
        Ok(self
            .world
            .contact_pairs()?
            .iter()
            .map(|p| -p.contact.min_distance)
            .filter(|d| d.is_finite())
            .fold(0.0, f64::max))
    }

    /// Runs frame by frame until `stop` (module docs) and returns the record.
    pub fn run(&mut self, stop: &StopRule) -> Result<RuinResult, StageError> {
        self.run_with(stop, &mut |_| {})
    }

    /// As [`RuinStage::run`], calling `on_frame` after every recorded frame (progress).
    pub fn run_with(
        &mut self,
        stop: &StopRule,
        on_frame: &mut dyn FnMut(&Frame),
    ) -> Result<RuinResult, StageError> {
        let start = Instant::now();
        let bullet_before = self.in_bullet;
        self.world.reset_island_stats()?;
        if !stop.max_time_s.is_finite() {
            return Err(bad(
                "max_time_s",
                format!("{} must be finite", stop.max_time_s),
            ));
        }
        let g = {
            let g = self.settings.world.gravity;
            (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt()
        };
        let rest = stop.rest;
        let energy_bound = rest.map(|r| {
            let l = r.reference_length_m.unwrap_or(self.model_height_m.max(1.0));
            r.energy_ratio * self.total_mass_kg * g * l
        });
        let frame_dt = self.substeps_per_frame as f64 * self.substep_s;
        let hold_frames = rest.map(|r| (r.hold_s / frame_dt - 1e-9).ceil().max(1.0) as u64);
        let motion_end = self.ground_spec.motion_end_s();

        let nconn = self.connections.len();
        let mut outcomes: Vec<ConnectionOutcome> = (0..nconn)
            .map(|i| ConnectionOutcome {
                a: self.connections[i].a,
                b: self.connections[i].b,
                start_state: self.start_states[i],
                state: self.monitor.state(i),
                broke_at_s: None,
                plastic_at_s: None,
                first_row_lost: None,
            })
            .collect();
        let mut frames = vec![Frame {
            time_s: self.time_s(),
            poses: self.body_poses()?,
            counts: self.monitor.counts(),
            energy: self.energy()?,
        }];
        let mut quiet = 0u64;
        let mut reason = RuinStop::TimeLimit;
        let mut first_pen: Option<f64> = None;
        let mut max_pen = 0.0_f64;
        while self.time_s() < stop.max_time_s - 1e-9 * frame_dt {
            self.substeps(self.substeps_per_frame)?;
            let t = self.time_s();
            if !self.settings.monitor_every_substep {
                for ch in self.monitor_frame()? {
                    self.pending_changes.push((ch, t));
                }
            }
            for (ch, t) in std::mem::take(&mut self.pending_changes) {
                let o = &mut outcomes[ch.connection];
                if ch.to == ConnectionState::Broken && o.broke_at_s.is_none() {
                    o.broke_at_s = Some(t);
                }
                if ch.to == ConnectionState::Plastic && o.plastic_at_s.is_none() {
                    o.plastic_at_s = Some(t);
                }
            }
            frames.push(Frame {
                time_s: t,
                poses: self.body_poses()?,
                counts: self.monitor.counts(),
                energy: self.energy()?,
            });
            on_frame(frames.last().expect("just pushed"));
            let pen = self.deepest_penetration()?;
            first_pen.get_or_insert(pen);
            max_pen = max_pen.max(pen);
            if let (Some(r), Some(eb), Some(hf)) = (rest, energy_bound, hold_frames) {
                let (e, vmax, _) = self.motion_measures()?;
                let vmax = match r.speed {
                    RestSpeed::Instantaneous => vmax,
                    // Frame 0 is pushed before the loop, so there is a last frame.
                    RestSpeed::FrameMean => self
                        .last_frame_mean_speeds(&frames)
                        .map_or(0.0, |v| v.into_iter().fold(0.0, f64::max)),
                };
                if t >= motion_end - 1e-12 && e < eb && vmax < r.max_speed_mps {
                    quiet += 1;
                } else {
                    quiet = 0;
                }
                if quiet >= hf {
                    reason = RuinStop::AtRest;
                    break;
                }
            }
        }
        for (i, o) in outcomes.iter_mut().enumerate() {
            o.state = self.monitor.state(i);
            o.first_row_lost = self.first_lost[i]
                .and_then(|(k, t)| self.connections[i].constraints.get(k).map(|c| (c.role, t)));
        }
        let (_, _, instantaneous) = self.motion_measures()?;
        let speed_measure = rest.unwrap_or_default().speed;
        let speeds = match speed_measure {
            RestSpeed::FrameMean => self.last_frame_mean_speeds(&frames),
            RestSpeed::Instantaneous => None,
        }
        .unwrap_or_else(|| instantaneous.clone());
        let vtol = rest.unwrap_or_default().max_speed_mps;
        let at_rest: Vec<bool> = speeds
            .iter()
            .zip(&self.passive)
            .map(|(s, p)| *p || *s < vtol)
            .collect();
        let wall = WallTime {
            in_bullet: self.in_bullet - bullet_before,
            total: start.elapsed(),
        };
        Ok(RuinResult {
            frames,
            final_poses: self.body_poses()?,
            final_velocities: self.body_velocities()?,
            at_rest,
            connections: outcomes,
            first_frame_penetration_m: first_pen.unwrap_or(0.0),
            max_penetration_m: max_pen,
            stop: reason,
            end_time_s: self.time_s(),
            wall,
            ledger: LedgerSummary {
                initial_potential_j: self.initial_potential_j,
                model_height_m: self.model_height_m,
                gravity_mps2: g,
                start_max_speed_mps: self.start_max_speed_mps,
                max_speed_mps: self.max_speed.0,
                max_speed_at: self.max_speed.1,
                final_point_speeds_mps: speeds,
                final_instantaneous_speeds_mps: instantaneous,
                rest_speed: speed_measure,
                injected_j: self.injected_j,
                max_injection: self.max_injection,
            },
            islands: self.world.island_stats()?,
            sleeping_at_end: self.world.num_sleeping()?,
            joint_solve: self.world.joint_solve()?,
        })
    }
}

/// The step the spring cap is computed for, s: max(h, 1/`rate`), or h when `rate` is 0
/// ([`StageSettings::spring_cap_steps_per_second`]). Never below h: a coarser substep
/// than the rate's needs its own, lower cap for stability.
fn spring_cap_step(h: f64, rate: f64) -> f64 {
    if rate > 0.0 {
        h.max(1.0 / rate)
    } else {
        h
    }
}

/// The per-body stability cap of plastic-spring axis `axis` (0..2 linear, 3..5 angular;
/// the spring frame is world-aligned on the undeformed bodies) of connection `c`, on which
/// `n` springs at most act per body ([`StageSettings::spring_cap_per_body`]). Bullet
/// integrates each spring explicitly (`btGeneric6DofSpring2Constraint`: the force k·e·h
/// from the error at the substep's start), stable for ω·h < 2 and sampled well for
/// ω·h ≤ 1/4 (Bullet's `limitIfNeeded`: k ≤ m/(16·h²), c ≤ m/h, m the pair's mass at the
/// centres). Here the effective inverse mass of the axis at the pivot is taken with the
/// lever arm, w = Σ_bodies 1/m + (r × e)·I⁻¹(r × e) (linear, r = pivot − centre) or
/// e·I⁻¹e (angular), and the n springs on the same body share the budget:
/// k ≤ 1/(16·h²·w·n), c ≤ 1/(h·w·n). Returns (k cap, c cap).
#[allow(clippy::too_many_arguments)]
fn body_spring_cap(
    world: &World,
    c: &ConnectionSpec,
    spec: &super::connection::ConstraintSpec,
    axis: usize,
    handles: &[BodyHandle],
    input: &StageInput,
    h: f64,
    n: usize,
) -> Result<(f64, f64), StageError> {
    let a0 = input.bodies[c.a].pose();
    let pivot = (a0 * spec.frame_a).translation.vector;
    let e = nalgebra::Vector3::ith(axis % 3, 1.0);
    let mut w = 0.0;
    for b in [c.a, c.b] {
        if input.bodies[b].passive {
            continue;
        }
        let (m, i) = world.mass_inertia(handles[b])?;
        let pose = input.bodies[b].pose();
        let rot_inv = pose.rotation.inverse();
        let inv_i = |v: nalgebra::Vector3<f64>| {
            let l = rot_inv * v;
            l.x * l.x / i[0] + l.y * l.y / i[1] + l.z * l.z / i[2]
        };
        if axis < 3 {
            let r = pivot - pose.translation.vector;
            w += 1.0 / m + inv_i(r.cross(&e));
        } else {
            w += inv_i(e);
        }
    }
    if w <= 0.0 {
        return Ok((f64::INFINITY, f64::INFINITY));
    }
    let n = n.max(1) as f64;
    Ok((1.0 / (16.0 * h * h * w * n), 1.0 / (h * w * n)))
}

fn passive_of(input: &StageInput, c: &ConnectionSpec) -> (bool, bool) {
    (input.bodies[c.a].passive, input.bodies[c.b].passive)
}

/// The member stiffness k and the effective inverse mass K of locked axis `axis` (0..2
/// linear, 3..5 angular, constraint frame: X = the contact normal) of a generic row of
/// connection `c` ([`JointRows::Member`]).
#[allow(clippy::too_many_arguments)]
fn member_row(
    world: &World,
    c: &ConnectionSpec,
    spec: &super::connection::ConstraintSpec,
    axis: usize,
    handles: &[BodyHandle],
    input: &StageInput,
    modulus_pa: f64,
    passive: (bool, bool),
) -> Result<(f64, f64), StageError> {
    let ct = &c.contact;
    let (hh, ww) = (ct.h.max(1e-6), ct.w.max(1e-6));
    let l = ct.centre_distance.max(1e-3);
    let g = modulus_pa / 2.4;
    // The constraint frame's axis `axis % 3` in world (undeformed: frames from BCB's rotN).
    let a0 = input.bodies[c.a].pose();
    let r = (a0 * spec.frame_a).rotation;
    let e = r * nalgebra::Vector3::ith(axis % 3, 1.0);
    // Which contact direction (normal, h or w) that axis runs along.
    let comp = |i: usize| e[i].abs();
    let along = if comp(ct.normal_axis) >= comp(ct.h_axis).max(comp(ct.w_axis)) {
        0
    } else if comp(ct.h_axis) >= comp(ct.w_axis) {
        1
    } else {
        2
    };
    let area = hh * ww;
    let k = if axis < 3 {
        if along == 0 {
            modulus_pa * area / l
        } else {
            g * area / l
        }
    } else {
        match along {
            0 => g * hh * ww * (hh * hh + ww * ww) / 12.0 / l,
            // About the h axis: the section's depth across it is w.
            1 => modulus_pa * hh * ww.powi(3) / 12.0 / l,
            _ => modulus_pa * ww * hh.powi(3) / 12.0 / l,
        }
    };
    let mut inv = 0.0;
    for (b, is_passive) in [(c.a, passive.0), (c.b, passive.1)] {
        if is_passive {
            continue;
        }
        let (m, i) = world.mass_inertia(handles[b])?;
        if axis < 3 {
            inv += 1.0 / m;
        } else {
            let rb = input.bodies[b].pose().rotation;
            let el = rb.inverse() * e;
            let ie = i[0] * el.x * el.x + i[1] * el.y * el.y + i[2] * el.z * el.z;
            inv += 1.0 / ie;
        }
    }
    Ok((k, inv))
}

/// `pose` translated by `d`.
fn shifted(pose: &Pose, d: [f64; 3]) -> Pose {
    Pose {
        position: [
            pose.position[0] + d[0],
            pose.position[1] + d[1],
            pose.position[2] + d[2],
        ],
        orientation: pose.orientation,
    }
}

#[cfg(test)]
mod tests {
    use super::spring_cap_step;

    /// The spring cap's step: BCB's 1/200 s at 400 and 800 substeps/s (so k ≤ 1/(16·h²·w·n)
    /// is the same at every finer substep), the run's own at 200 and coarser, and the
    /// run's own everywhere with the rate 0.
    #[test]
    fn the_spring_cap_uses_the_reference_step_at_finer_substeps() {
        assert_eq!(spring_cap_step(1.0 / 800.0, 200.0), 1.0 / 200.0);
        assert_eq!(spring_cap_step(1.0 / 400.0, 200.0), 1.0 / 200.0);
        assert_eq!(spring_cap_step(1.0 / 200.0, 200.0), 1.0 / 200.0);
        assert_eq!(spring_cap_step(1.0 / 100.0, 200.0), 1.0 / 100.0);
        assert_eq!(spring_cap_step(1.0 / 800.0, 0.0), 1.0 / 800.0);
    }
}
