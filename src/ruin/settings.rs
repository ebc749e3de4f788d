//! What a ruin stage is built with: the body and world settings ([`StageSettings`],
//! [`BodySettings`], [`JointRows`]), the start state ([`StageInput`]) and when a run stops
//! ([`StopRule`]).

use super::connection::{BodyCapacity, GroupStrength, RuinSettings};
use super::monitor::{AngleRule, FeDamage};
use super::rest::RestTest;
use super::BodyGeom;
use crate::bullet::{SolverSettings, Velocity, WorldSettings};
use nalgebra::Isometry3;
use std::collections::BTreeMap;

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
    /// How the connections behave once they yield ([`PlasticSettings`]).
    pub plastic: PlasticSettings,
    /// How the connections' generic rows are solved ([`JointSettings`]).
    pub joints: JointSettings,
    /// Mass-proportional damping relative to the moving ground, a₀ in 1/s (0: none, BCB):
    /// after every substep each active body's linear velocity relative to the ground
    /// decays by exp(−a₀·h). It is the a₀·M term of the FE's Rayleigh damping
    /// C = a₀·M + a₁·K (uniform excitation: the FE damps velocities relative to the
    /// ground; Chopra, *Dynamics of Structures*, §11.4), a dashpot from each body to the
    /// ground, so its impulse counts as the ground's in the energy ledger: the moving
    /// ground's share of its work is ground work, the rest is dissipated
    /// (docs/handoff.md, "The FE's failure modes").
    pub ground_damping_per_s: f64,
    /// Run the monitor's tolerance check ([`super::monitor`]) after every substep instead
    /// of once per frame (BCB: 25 Hz). A connection whose rows leave it a mechanism (e.g.
    /// a shear row broken: the other rows become a slider) can be carried far beyond its
    /// tolerances within one frame; its locked rows then see errors of decimetres and ask
    /// for the velocity ERP·e/h (Bullet's `get_limit_motor_info2`), up to tens of m/s on a
    /// light piece (docs/ruin-numerics.md, "The monitor's frame").
    pub monitor_every_substep: bool,
    /// Which bodies touch ([`TouchSettings`]).
    pub touch: TouchSettings,
    /// The solver's threads and sweep ([`SpeedSettings`]): the same bits for any choice.
    pub speed: SpeedSettings,
    /// Debug traces ([`TraceSettings`]; none by default).
    pub traces: TraceSettings,
}

/// The stage's debug traces (part of [`StageSettings`]): observers that read the world
/// and change nothing in it, each written to its own file by the pipeline after the stage
/// (`fem2rbd run --trace-axial`, `--trace-body`). None by default.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TraceSettings {
    /// The axial rows' sign changes and the kicks after them ([`super::axial`]).
    pub axial: Option<AxialTraceSettings>,
    /// One body's substeps ([`super::body_trace`]).
    pub body: Option<BodyTraceSettings>,
}

/// The axial trace ([`super::axial`] module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct AxialTraceSettings {
    /// The file it is written to.
    pub path: std::path::PathBuf,
    /// Substeps from this time on, s.
    pub from_s: f64,
    /// A kick: a body's centre velocity changing by more than this in one substep, m/s
    /// (0.1 in `fem2rbd run`).
    pub kick_mps: f64,
}

/// The trace of one body ([`super::body_trace`]).
#[derive(Debug, Clone, PartialEq)]
pub struct BodyTraceSettings {
    /// The file it is written to.
    pub path: std::path::PathBuf,
    /// The body's name (`bodies.csv`'s `name`, e.g. `Column:3:34`).
    pub body: String,
    /// Substeps ending in [`from_s`, `to_s`], s.
    pub from_s: f64,
    /// See `from_s`.
    pub to_s: f64,
}

/// How the connections behave once they yield (part of [`StageSettings`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlasticSettings {
    /// When the monitor switches a connection to plastic, make the spring's rest pose the
    /// current relative pose (`btGeneric6DofSpring2Constraint::setEquilibriumPoint()`),
    /// as the monitor resets its own reference d₀ := d. `false` (BCB/Blender): the spring
    /// keeps the rest pose of its creation (the start), so it is switched on already
    /// stretched by the elastic stage's deformation (up to tol1D = 10 % of the centre
    /// distance) and releases that energy into the debris (docs/ruin-numerics.md).
    pub spring_rest_at_onset: bool,
    /// A ductile bending row ([`super::connection::ConnectionSpec::ductile`]) that yielded
    /// in a substep is locked again at its present rotation before it is re-enabled
    /// ([`crate::bullet::World::relock_constraint`]): the hinge keeps its plastic
    /// rotation, as a rigid–plastic hinge does. `false` (the first FE-derived version): the
    /// row keeps its lock at the start pose, so after yielding it drives the hinge back
    /// with the velocity bias ERP·θ/h up to its full moment — a motor that feeds energy
    /// into the frame (docs/ruin-numerics.md).
    pub hinge_keeps_rotation: bool,
    /// With [`Self::hinge_keeps_rotation`]: re-lock a yielded hinge by a return mapping, at
    /// its present rotation minus the rotation error it had at its first yield, instead of
    /// at its present rotation. Re-locking at the present rotation throws away the error
    /// through which the not fully converged solver carries the moment, so the row's
    /// impulse falls to a quarter and builds back: a saw-tooth that carries 58 % of the
    /// capacity on average (frame3's base under a slow ramp); the return mapping keeps 97 %
    /// (docs/handoff.md, "On the connections alone"). `false`: the present rotation.
    pub hinge_return_mapping: bool,
    /// Cap every plastic spring's stiffness and damping for the explicit stability of the
    /// lighter body it acts on, counting all springs on that body
    /// (`build::connections::body_spring_cap`). `false` (BCB/Blender): only Bullet's
    /// per-spring `limitIfNeeded` cap, which takes each spring alone and the pair's mass at
    /// the centre, so a light column piece held by four plastic springs (up to 24 explicit
    /// spring rows) at lever arms is beyond explicit stability and never comes to rest
    /// (docs/ruin-numerics.md).
    pub spring_cap_per_body: bool,
    /// The substep rate whose step the per-body spring cap uses, 1/s (default 0 = the
    /// run's own substep h; option: 200, BCB's rate). The cap k ≤ 1/(16·h²·w·n) grows as
    /// h shrinks, so with h a finer substep carries stiffer springs — a different model,
    /// whose light pieces the springs whip faster; with a rate the cap takes
    /// max(h, 1/rate) and the springs are those that rate carries, at every finer substep
    /// (docs/ruin-numerics.md, "The error reduction per second": it keeps every piece within the speed bound at 400 and
    /// 800 substeps/s but moves the ruin further from the 200-substep one, so it is an
    /// option).
    pub spring_cap_steps_per_second: f64,
}

/// How the connections' generic (locked) rows are solved (part of [`StageSettings`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointSettings {
    /// How the connections' locked rows correct their error ([`JointRows`]).
    pub rows: JointRows,
    /// Warm start of the connections' generic rows, 0..=1
    /// ([`crate::bullet::World::set_joint_warmstart`]): each row's Gauss–Seidel solve
    /// starts from this share of its impulse in the last substep. 0 (BCB/Bullet): every
    /// joint row starts from zero in every substep, as Bullet 3.24's
    /// `btSequentialImpulseConstraintSolver::convertJoint` does (it warm-starts contacts
    /// only), so a statically loaded joint is never converged and its residual error is
    /// pulled back by the Baumgarte velocity ERP·e/h (docs/ruin-numerics.md, "The joint warm start").
    pub warmstart: f64,
    /// Gauss–Seidel iterations of the connections' generic rows
    /// (`btTypedConstraint::setOverrideNumSolverIterations`; Bullet then runs
    /// max(this, `solver_iterations`) sweeps, contacts only in the first
    /// `solver_iterations`). `None` (BCB): the world's `solver_iterations`.
    pub iterations: Option<u32>,
    /// How the joints' bilateral rows are solved at each substep
    /// ([`crate::bullet::World::set_joint_solve`]): Bullet's projected Gauss–Seidel
    /// ([`crate::bullet::JointSolve::Pgs`], BCB), or first a sparse LDLᵀ solve of the
    /// linear system those iterations converge to, (A + diag(Cᵢ/Dᵢ)) λ = rhsᵢ/Dᵢ − Jᵢ·Δv₀
    /// ([`crate::bullet::JointSolve::Direct`]; docs/ruin-numerics.md, "A direct solve").
    pub solve: crate::bullet::JointSolve,
    /// Regularisation ε of the direct solve (ε·Aᵢᵢ added to each diagonal entry: a relative
    /// CFM ε on every row), [0, 1]; default 1e-3 (docs/ruin-numerics.md, "A direct solve").
    pub solve_regularisation: f64,
}

/// Which bodies touch (part of [`StageSettings`]; [`super::separation`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TouchSettings {
    /// When two bodies a connection holds together start touching each other
    /// ([`super::separation`]): never (BCB/Blender, the default: Bullet's exemption stays
    /// for the whole run, so broken pieces pass through each other), once nothing holds
    /// them, or once only springs do (docs/ruin-numerics.md, "Which bodies touch").
    pub pairs: super::separation::PairsTouch,
    /// Pieces joined to a foundation block touch the ground box from the start (BCB, the
    /// default). `false`: only once none of their foundation connections carries
    /// compression ([`super::separation`]).
    pub ground_under_connected_bases: bool,
}

/// The solver's threads and sweep (part of [`StageSettings`]): every choice gives the
/// same bits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedSettings {
    /// Solver threads (island-parallel solving, `crate::bullet::speed`): the same bytes for
    /// any number. Default the machine's cores (as the FE); `fem2rbd run --threads`.
    pub solver_threads: usize,
    /// The solver's sweep ([`crate::bullet::World::set_sweep`]): every kind gives the same
    /// bits. Default [`crate::bullet::Sweep::Packed`]; `[physics.experimental] sweep`
    /// selects another (for `bench_ruin`'s before/after).
    pub sweep: crate::bullet::Sweep,
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
    /// ([`crate::bullet::World::set_constraint_param`]), CFM = 1/(x·(x + 2ζ)).
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
/// (`gResolveSingleConstraintRowGeneric_scalar_reference`; `crate::bullet::jointsolve`
/// module docs). The row's own impulse enters its next value with the factor −C, so the
/// sweeps diverge when C ≥ 1. On frame3 with elastic slab panels, the slab–column angular
/// rows (k ≈ 10² N·m/rad on a 6.25 kg column piece) got C = 1.4–1.6, and the first
/// substep after a hand-off threw them to 10⁵¹ N·s (docs/ruin-numerics.md, "Member stiffness"). With
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

impl StageSettings {
    /// The paper's settings (BCB), the ruin stage's defaults and the scenario's `bcb`
    /// preset (`crate::pipeline::preset`): each value is documented at its field's type.
    /// BCB's world (docs/bcb.md §11.1): sequential impulses, 100 iterations, split impulse
    /// off, gravity (0, 0, −9.81); Bullet's process-globals set to Bullet's own values
    /// (gDbvtMargin 0.05, gContactBreakingThreshold 0.02) so a stage never depends on
    /// what ran before it in the process.
    pub fn bcb() -> Self {
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
                stock_solver: false,
            },
            body: BodySettings::default(),
            angle_rule: AngleRule::default(),
            warmup_s: 0.0,
            connect: true,
            plastic: PlasticSettings::default(),
            joints: JointSettings::default(),
            ground_damping_per_s: 0.0,
            monitor_every_substep: false,
            touch: TouchSettings::default(),
            speed: SpeedSettings::default(),
            traces: TraceSettings::default(),
        }
    }
}

impl Default for PlasticSettings {
    /// The spring's rest pose from its creation (BCB), hinges that keep their rotation
    /// without the return mapping, the per-body spring cap at the run's own substep.
    fn default() -> Self {
        PlasticSettings {
            spring_rest_at_onset: false,
            hinge_keeps_rotation: true,
            hinge_return_mapping: false,
            spring_cap_per_body: true,
            spring_cap_steps_per_second: 0.0,
        }
    }
}

impl Default for JointSettings {
    /// BCB's: locked rows, no warm start, the world's iterations, Gauss–Seidel.
    fn default() -> Self {
        JointSettings {
            rows: JointRows::Locked,
            warmstart: 0.0,
            iterations: None,
            solve: crate::bullet::JointSolve::Pgs,
            solve_regularisation: crate::bullet::jointsolve::DEFAULT_REGULARISATION,
        }
    }
}

impl Default for TouchSettings {
    /// BCB's: connected pairs never touch, bases touch the ground from the start.
    fn default() -> Self {
        TouchSettings {
            pairs: super::separation::PairsTouch::Never,
            ground_under_connected_bases: true,
        }
    }
}

impl Default for SpeedSettings {
    /// The machine's cores; the packed sweep.
    fn default() -> Self {
        SpeedSettings {
            solver_threads: crate::fe::domain::default_threads(),
            sweep: crate::bullet::Sweep::Packed,
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
    /// Start time, s (Tc; 0 in the rigid-only mode).
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
    /// The rigid-only mode (BCB alone): undeformed poses, at rest, t = 0, no damage.
    pub fn rigid_only(
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
