//! The scenario file (`fem2rbd run scenario.toml`): one TOML file that says which model,
//! which earthquake, which collapse criterion, which mode and which physics settings.
//! The format is documented field by field in `docs/scenario-format.md`.
//!
//! Paths inside the file (model, records) are relative to the scenario file's folder;
//! the output folder is relative to the current directory. Every error names the file,
//! and the line (TOML syntax and types, from the `toml` crate) or the item at fault.

use super::error::ScenarioError;
use crate::collapse::Criterion;
use crate::fe::build::Variant;
use crate::fe::shell::layers::ConcreteIntegration;
use crate::motion::Direction;
use crate::ruin::rest::RestTest;
use serde::Deserialize;
use std::path::{Path, PathBuf};

pub use crate::mode::Mode;

/// How the bodies' velocities at Tc are obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum VelocityHandoff {
    /// From the FE nodal velocities at Tc (default).
    #[default]
    Instantaneous,
    /// The paper's secant through the last two 25 fps keyframes.
    Secant,
}

/// One ground-motion component as written in the file.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ComponentSpec {
    /// Record file (AT2 or two-column), relative to the scenario file.
    pub file: PathBuf,
    /// `X`, `Y` or `Z` (either case).
    pub direction: Direction,
    /// Target PGA, g; absent = as recorded.
    pub pga_g: Option<f64>,
    /// Time-scale factor t' = f·t (1 = as recorded; 0.5 for a 1/4-scale model by
    /// similitude).
    #[serde(default = "one")]
    pub time_scale: f64,
}

fn one() -> f64 {
    1.0
}

/// FE settings.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub(crate) struct FeSpec {
    /// Time step, s.
    pub dt: f64,
    /// `model`, `force`, `disp` or `elastic`.
    pub variant: Variant,
    /// Analysis length, s; absent = the record's length.
    pub duration: Option<f64>,
    /// `implicit` (OpenSees' law, default) or `implex` for the shells' concrete layers
    /// ([`crate::fe::shell::layers::ConcreteIntegration`]).
    pub concrete_integration: ConcreteIntegration,
}

impl Default for FeSpec {
    fn default() -> Self {
        FeSpec {
            dt: 0.005,
            variant: Variant::AsModel,
            duration: None,
            concrete_integration: ConcreteIntegration::Implicit,
        }
    }
}

/// The collapse criterion as written.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub(crate) struct CollapseSpec {
    /// `vertical_drop` (default), `drift_1_50` (GB 50011), `drift_4pct` (FEMA 356) or
    /// `drift` (with `ratio`).
    pub criterion: CriterionName,
    /// Vertical-drop threshold, m; default 1 m × model scale (paper Criterion 4).
    pub threshold_m: Option<f64>,
    /// Drift ratio of `criterion = "drift"`.
    pub ratio: Option<f64>,
}

impl Default for CollapseSpec {
    fn default() -> Self {
        CollapseSpec {
            criterion: CriterionName::VerticalDrop,
            threshold_m: None,
            ratio: None,
        }
    }
}

/// The collapse criteria a scenario can name (`[collapse] criterion`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum CriterionName {
    /// `vertical_drop`: a main member's vertical drop (paper Criterion 4).
    VerticalDrop,
    /// `drift_1_50`: story drift ratio 1/50 (GB 50011).
    Drift1In50,
    /// `drift_4pct`: story drift ratio 4 % (FEMA 356).
    Drift4Pct,
    /// `drift`: story drift ratio `ratio`.
    Drift,
}

impl CriterionName {
    /// The name as written in the file.
    pub fn name(self) -> &'static str {
        match self {
            CriterionName::VerticalDrop => "vertical_drop",
            CriterionName::Drift1In50 => "drift_1_50",
            CriterionName::Drift4Pct => "drift_4pct",
            CriterionName::Drift => "drift",
        }
    }
}

impl<'de> Deserialize<'de> for CriterionName {
    /// One of the four names; anything else is an error naming the value and the choices.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        [
            CriterionName::VerticalDrop,
            CriterionName::Drift1In50,
            CriterionName::Drift4Pct,
            CriterionName::Drift,
        ]
        .into_iter()
        .find(|c| c.name() == s)
        .ok_or_else(|| {
            serde::de::Error::custom(format!(
                "collapse.criterion {s:?} is not vertical_drop, drift_1_50, drift_4pct or drift"
            ))
        })
    }
}

/// Where the ruin stage's connection strengths come from (`[physics] connections`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ConnectionModel {
    /// BCB's Formula Assistant per element group (`crate::ruin::groups`).
    Formula,
    /// From the FE model's own sections: capacities at the gravity axial load, residual
    /// at Tc (`crate::fe::capacity`, docs/handoff.md).
    Fe,
}

/// How the connections' locked rows correct their error (`crate::ruin::stage::JointRows`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JointRowsSpec {
    /// BCB: the world's joint ERP, CFM 0.
    Locked,
    /// ERP/CFM from the members' stiffness.
    Member,
}

/// How the solver sweeps its Gauss–Seidel iterations (`[physics.experimental] sweep`,
/// [`crate::bullet::Sweep`]): every choice gives the same bits; the others are for
/// `bench_ruin`'s before/after (docs/performance.md, "Ruin stage").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SweepSpec {
    /// The lean sweep over packed copies of the joint rows ([`crate::bullet::Sweep::Packed`]).
    Packed,
    /// Bullet 3.24's own sweep ([`crate::bullet::Sweep::Bullet`]).
    Bullet,
    /// Bullet's sweep without its empty per-iteration walk ([`crate::bullet::Sweep::Lean`]).
    Lean,
    /// The packed sweep with the joints' set-up on the solver threads
    /// ([`crate::bullet::Sweep::PackedThreads`]).
    Threads,
}

impl SweepSpec {
    /// The solver's sweep.
    pub fn sweep(self) -> crate::bullet::Sweep {
        match self {
            SweepSpec::Packed => crate::bullet::Sweep::Packed,
            SweepSpec::Bullet => crate::bullet::Sweep::Bullet,
            SweepSpec::Lean => crate::bullet::Sweep::Lean,
            SweepSpec::Threads => crate::bullet::Sweep::PackedThreads,
        }
    }

    /// The choice of a sweep.
    pub fn of(sweep: crate::bullet::Sweep) -> SweepSpec {
        match sweep {
            crate::bullet::Sweep::Packed => SweepSpec::Packed,
            crate::bullet::Sweep::Bullet => SweepSpec::Bullet,
            crate::bullet::Sweep::Lean => SweepSpec::Lean,
            crate::bullet::Sweep::PackedThreads => SweepSpec::Threads,
        }
    }
}

/// How the joints' bilateral rows are solved at each substep
/// (`crate::bullet::JointSolve`, docs/ruin-numerics.md, "A direct solve").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JointSolveSpec {
    /// Bullet's projected Gauss–Seidel only.
    #[default]
    Pgs,
    /// A sparse LDLᵀ solve of the bilateral rows first, then Gauss–Seidel.
    Direct,
}

/// The ruin stage's settings of a run, every key resolved (`[physics]` in the file,
/// [`PhysicsTable::resolve`]). Each field's default is its value in the run's preset
/// ([`super::preset`]): the `bcb` preset takes the ruin stage's own defaults
/// ([`crate::ruin::stage::StageSettings::bcb`], documented next to each type), the
/// `fem2rbd` preset changes the keys listed there.
#[derive(Debug, Clone, PartialEq)]
pub struct PhysicsSpec {
    /// The preset the other values start from (`bcb` or `fem2rbd`).
    pub preset: super::preset::Preset,
    /// Substeps per simulated second (BCB 200).
    pub steps_per_second: f64,
    /// Solver iterations (100 in `bcb`, BCB's; 400 in `fem2rbd`, docs/ruin-numerics.md §13).
    pub solver_iterations: u32,
    /// Body friction (1).
    pub friction: f64,
    /// Restitution (0).
    pub restitution: f64,
    /// Linear damping (0.04).
    pub linear_damping: f64,
    /// Angular damping (0.1).
    pub angular_damping: f64,
    /// BCB's spring correction factor of the plastic-spring stiffness (2).
    pub spring_correction: f64,
    /// BCB's empirical correction of the linear generic rows' breaking impulses (2.2:
    /// threshold = force · 2.2 · Δt; docs/bcb.md §3.1): `crate::ruin::connection::
    /// RuinSettings::linear_correction`.
    pub linear_correction: f64,
    /// BCB's correction of the bending rows' breaking impulses (1.5):
    /// `crate::ruin::connection::RuinSettings::bending_correction`.
    pub bending_correction: f64,
    /// Plastic-spring damping (BCB 20).
    pub spring_damping: f64,
    /// Bullet's per-substep cap of the plastic springs' stiffness and damping (true, as
    /// Blender/BCB: `crate::ruin::connection::RuinSettings::spring_limit_if_needed`).
    pub spring_limit: bool,
    /// Angular stiffness of the plastic springs: `"lever"` (default, k·r²) or `"bcb"` (k as
    /// N·m/rad) — `crate::ruin::connection::AngularSpring`.
    pub angular_spring: crate::ruin::connection::AngularSpring,
    /// Bullet's split impulse (false, as BCB): penetration recovery by a separate
    /// position correction that adds no kinetic energy, instead of a velocity bias.
    pub split_impulse: bool,
    /// Bullet's `m_splitImpulsePenetrationThreshold`, m (Bullet −0.04): with split impulse
    /// on, only contacts deeper than this are corrected by position; shallower ones get
    /// the velocity bias (Baumgarte, `contact_erp`). 0 = every penetration by position.
    pub split_impulse_threshold_m: f64,
    /// Bullet's contact ERP `m_erp2` (0.2): the fraction of a penetration removed per
    /// substep (by velocity without split impulse).
    pub contact_erp: f64,
    /// Bullet's joint ERP `m_erp` (0.2): the same for the connections' constraint rows.
    pub joint_erp: f64,
    /// The substep rate at which `contact_erp` and `joint_erp` hold, 1/s (200, BCB's
    /// rate; 0 = as Bullet and BCB, per substep at any rate). At another rate each ERP
    /// becomes ERP·`erp_steps_per_second`/`steps_per_second` (at most 1), so the
    /// Baumgarte bias ERP·e/h removes an error at the same rate per second whatever the
    /// substep h: [`Self::erp_scale`], docs/ruin-numerics.md, "The error reduction per second".
    pub erp_steps_per_second: f64,
    /// Collision margin of every body, m (Blender/BCB 0.04; capped at the smallest half
    /// extent of each box).
    pub margin_m: f64,
    /// Largest margin as a share of each box's smallest half extent (1 = BCB):
    /// `crate::ruin::stage::BodySettings::margin_max_share`.
    pub margin_max_share: f64,
    /// A plastic spring's rest pose is the pose at the onset of plasticity (true) or at
    /// the stage's start as in BCB (false):
    /// `crate::ruin::stage::PlasticSettings::spring_rest_at_onset`.
    pub spring_rest_at_plastic_onset: bool,
    /// A yielded ductile hinge (FE-derived connections) keeps its plastic rotation (true,
    /// the default: no energy fed in by a hinge driving itself back, docs/ruin-numerics.md
    /// §8.1) or drives back to its start pose (false: the first FE-derived version):
    /// `crate::ruin::stage::PlasticSettings::hinge_keeps_rotation`.
    pub hinge_keeps_rotation: bool,
    /// With `hinge_keeps_rotation`: re-lock a yielded hinge at its present rotation minus
    /// the rotation error of its first yield (a return mapping; false: at its present
    /// rotation): `crate::ruin::stage::PlasticSettings::hinge_return_mapping`.
    pub hinge_return_mapping: bool,
    /// The connections' locked rows: `"locked"` (BCB: the world's joint ERP, CFM 0) or
    /// `"member"` (each row an implicit spring–damper of the members' stiffness through
    /// its ERP/CFM): `crate::ruin::stage::JointRows`.
    pub joint_rows: JointRowsSpec,
    /// Young's modulus of the `"member"` rows, Pa (25 GPa: frame3's Concrete02,
    /// 2·f′c/ε_c0 = 2·22.5 MPa/0.0018).
    pub joint_modulus_pa: f64,
    /// Damping ratio of the `"member"` rows (1).
    pub joint_damping_ratio: f64,
    /// Warm start of the connections' generic rows, 0..=1
    /// (`crate::ruin::stage::JointSettings::warmstart`): 0 (Bullet/BCB) in `bcb`, 0.5 in
    /// `fem2rbd` (docs/handoff.md §4.1); follows `connections` ([`PhysicsTable::resolve`]).
    pub joint_warmstart: f64,
    /// Gauss–Seidel iterations of the connections' generic rows (≥ 1; absent = the world's
    /// `solver_iterations`): `crate::ruin::stage::JointSettings::iterations`.
    pub joint_iterations: Option<u32>,
    /// How the joints' bilateral rows are solved: `"pgs"` (Bullet's Gauss–Seidel, the
    /// default) or `"direct"` (a sparse LDLᵀ solve first):
    /// `crate::ruin::stage::JointSettings::solve`.
    pub joint_solve: JointSolveSpec,
    /// Regularisation ε of the direct solve, in [0, 1] (ε·Aᵢᵢ added to each diagonal
    /// entry, a relative CFM ε on every row; 1e-3, docs/ruin-numerics.md, "A direct solve"):
    /// `crate::ruin::stage::JointSettings::solve_regularisation`.
    pub joint_solve_regularisation: f64,
    /// The connections' axial rows: `"bcb"` (BCB's one-way compression and tension rows)
    /// or `"two_way"` (one two-way row, broken in the sense it pushes):
    /// `crate::ruin::axial::AxialRows`: `"bcb"` in `bcb`, `"two_way"` in `fem2rbd`;
    /// follows `connections` ([`PhysicsTable::resolve`]).
    pub axial_rows: crate::ruin::axial::AxialRows,
    /// Cap the plastic springs for the explicit stability of each body they act on, all
    /// its springs together (true, the default: docs/ruin-numerics.md, "Plastic springs capped per body"), or only per
    /// spring as Bullet/BCB (false):
    /// `crate::ruin::stage::PlasticSettings::spring_cap_per_body`.
    pub spring_cap_per_body: bool,
    /// The substep rate whose step the per-body spring cap uses, 1/s (0 = the run's own
    /// substep; option 200):
    /// `crate::ruin::stage::PlasticSettings::spring_cap_steps_per_second`.
    pub spring_cap_steps_per_second: f64,
    /// Check the monitor's tolerances after every substep (true) or once per 25 Hz frame
    /// as BCB (false): `crate::ruin::stage::StageSettings::monitor_every_substep`.
    pub monitor_every_substep: bool,
    /// When two pieces a connection holds together start touching: `"never"` (BCB:
    /// broken pieces pass through each other), `"once_broken"` or `"once_yielded"` (once
    /// only the plastic spring holds): `crate::ruin::separation::PairsTouch`
    /// (docs/ruin-numerics.md, "Which bodies touch"): `"never"` in `bcb`, `"once_yielded"`
    /// in `fem2rbd`; follows `connections` ([`PhysicsTable::resolve`]).
    pub connected_pairs_touch: crate::ruin::separation::PairsTouch,
    /// Pieces joined to a foundation block also rest on the ground box while joined (BCB,
    /// true), or touch it only once no foundation connection carries their compression
    /// (false): `crate::ruin::stage::TouchSettings::ground_under_connected_bases`; true in
    /// `bcb`, false in `fem2rbd`; follows `connections` ([`PhysicsTable::resolve`]).
    pub ground_under_connected_bases: bool,
    /// BCB's connection search distance, m (0.02: bodies whose boxes are at most this far
    /// apart are connected; docs/bcb.md §7.3): `crate::ruin::search::SearchSettings`.
    pub search_distance_m: f64,
    /// The solver's sweep (`"packed"`, the default, `"bullet"`, `"lean"` or `"threads"`):
    /// the same bits for each, [`SweepSpec`].
    pub sweep: SweepSpec,
    /// Let Bullet put islands of bodies at rest to sleep (false, as BCB): a speed option,
    /// `crate::ruin::stage::BodySettings::disable_deactivation` (docs/performance.md).
    pub sleeping: bool,
    /// Absolute end time of the timeline, s; absent = end of the record + `settle_s`.
    pub time_limit_s: Option<f64>,
    /// Extra time after the record when `time_limit_s` is absent, s (5).
    pub settle_s: f64,
    /// Stop when the debris is at rest (true).
    pub stop_at_rest: bool,
    /// The at-rest test (`crate::ruin::rest::RestTest`).
    pub rest: RestTest,
    /// Connection strengths: `"formula"` (BCB's Formula Assistant, the `bcb` preset) or
    /// `"fe"` (from the FE model's sections, the `fem2rbd` preset).
    pub connections: ConnectionModel,
    /// How the slab panels' connections are limited with FE-derived connections:
    /// `"group"` (the panels' group strengths, the default) or `"elastic"` (the FE's slab
    /// is elastic, so a panel never limits a connection; needs `connections = "fe"`).
    pub panel_connections: PanelConnections,
    /// What a ductile hinge (FE-derived connections) becomes past its 1st rotation
    /// tolerance: `"spring"` (BCB's plastic spring, the default) or `"rupture"` (it holds
    /// to BCB's 2nd tolerances, then breaks): `crate::ruin::connection::HingeEnd`.
    pub hinge_end: crate::ruin::connection::HingeEnd,
    /// Which column pieces the beams and slab panels at a joint connect to: `"faces"`
    /// (every touching pair, BCB; the default) or `"column_above"` (the piece above the
    /// floor only, so the column below can hinge at the floor as in the FE):
    /// `crate::ruin::search::JointContacts`.
    pub joints: crate::ruin::search::JointContacts,
    /// Mass-proportional damping of the bodies relative to the moving ground: `"none"`
    /// (BCB, the default) or `"fe"` (the model's Rayleigh a₀, as the FE damps):
    /// `crate::ruin::stage::StageSettings::ground_damping_per_s`.
    pub ground_damping: GroundDamping,
}

/// `[physics] ground_damping` (docs/handoff.md, "The FE's failure modes").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GroundDamping {
    /// No damping relative to the ground (BCB: only Blender's body damping).
    #[default]
    None,
    /// The a₀·M term of the FE model's Rayleigh damping (`[damping]` of the model).
    Fe,
}

/// How slab panels limit their connections with FE-derived connections
/// (`[physics] panel_connections`, docs/handoff.md §2.6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PanelConnections {
    /// As the FE's slab: elastic, never the weak link
    /// (`crate::ruin::connection::BodyCapacity::Elastic`).
    Elastic,
    /// The panels' group strengths (BCB's Formula Assistant).
    #[default]
    Group,
}

impl PhysicsSpec {
    /// The factor on `contact_erp` and `joint_erp` at this substep rate:
    /// `erp_steps_per_second / steps_per_second` (1 when `erp_steps_per_second` is 0).
    /// Bullet's bias velocity of a row with error e is ERP·e/h (Baumgarte stabilisation;
    /// Catto, "Iterative Dynamics with Temporal Coherence", GDC 2005), so with a fixed
    /// ERP the error is removed with the time constant h/ERP: 25 ms at BCB's 200
    /// substeps/s and ERP 0.2, 6.25 ms at 800 — a faster, different correction at every
    /// rate. Scaled, h/ERP stays 25 ms: the same correction at every substep
    /// (docs/ruin-numerics.md, "The error reduction per second").
    pub fn erp_scale(&self) -> f64 {
        if self.erp_steps_per_second > 0.0 {
            self.erp_steps_per_second / self.steps_per_second
        } else {
            1.0
        }
    }
}

/// The `[physics]` table as written: every key optional, absent = the preset's value
/// ([`PhysicsTable::resolve`]; each key's meaning and default: [`PhysicsSpec`]).
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PhysicsTable {
    /// The preset the run starts from; absent = the mode's ([`super::preset::Preset::for_mode`]).
    pub preset: Option<super::preset::Preset>,
    /// [`PhysicsSpec::steps_per_second`].
    pub steps_per_second: Option<f64>,
    /// [`PhysicsSpec::solver_iterations`].
    pub solver_iterations: Option<u32>,
    /// [`PhysicsSpec::friction`].
    pub friction: Option<f64>,
    /// [`PhysicsSpec::restitution`].
    pub restitution: Option<f64>,
    /// [`PhysicsSpec::linear_damping`].
    pub linear_damping: Option<f64>,
    /// [`PhysicsSpec::angular_damping`].
    pub angular_damping: Option<f64>,
    #[serde(deserialize_with = "moved::spring_correction")]
    #[doc(hidden)]
    pub spring_correction: Option<moved::Moved>,
    /// [`PhysicsSpec::linear_correction`].
    pub linear_correction: Option<f64>,
    /// [`PhysicsSpec::bending_correction`].
    pub bending_correction: Option<f64>,
    #[serde(deserialize_with = "moved::spring_damping")]
    #[doc(hidden)]
    pub spring_damping: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::spring_limit")]
    #[doc(hidden)]
    pub spring_limit: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::angular_spring")]
    #[doc(hidden)]
    pub angular_spring: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::split_impulse")]
    #[doc(hidden)]
    pub split_impulse: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::split_impulse_threshold_m")]
    #[doc(hidden)]
    pub split_impulse_threshold_m: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::contact_erp")]
    #[doc(hidden)]
    pub contact_erp: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::joint_erp")]
    #[doc(hidden)]
    pub joint_erp: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::erp_steps_per_second")]
    #[doc(hidden)]
    pub erp_steps_per_second: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::margin_m")]
    #[doc(hidden)]
    pub margin_m: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::margin_max_share")]
    #[doc(hidden)]
    pub margin_max_share: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::spring_rest_at_plastic_onset")]
    #[doc(hidden)]
    pub spring_rest_at_plastic_onset: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::hinge_keeps_rotation")]
    #[doc(hidden)]
    pub hinge_keeps_rotation: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::hinge_return_mapping")]
    #[doc(hidden)]
    pub hinge_return_mapping: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::joint_rows")]
    #[doc(hidden)]
    pub joint_rows: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::joint_modulus_pa")]
    #[doc(hidden)]
    pub joint_modulus_pa: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::joint_damping_ratio")]
    #[doc(hidden)]
    pub joint_damping_ratio: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::joint_warmstart")]
    #[doc(hidden)]
    pub joint_warmstart: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::joint_iterations")]
    #[doc(hidden)]
    pub joint_iterations: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::joint_solve")]
    #[doc(hidden)]
    pub joint_solve: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::joint_solve_regularisation")]
    #[doc(hidden)]
    pub joint_solve_regularisation: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::axial_rows")]
    #[doc(hidden)]
    pub axial_rows: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::spring_cap_per_body")]
    #[doc(hidden)]
    pub spring_cap_per_body: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::spring_cap_steps_per_second")]
    #[doc(hidden)]
    pub spring_cap_steps_per_second: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::monitor_every_substep")]
    #[doc(hidden)]
    pub monitor_every_substep: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::connected_pairs_touch")]
    #[doc(hidden)]
    pub connected_pairs_touch: Option<moved::Moved>,
    #[serde(deserialize_with = "moved::ground_under_connected_bases")]
    #[doc(hidden)]
    pub ground_under_connected_bases: Option<moved::Moved>,
    /// [`PhysicsSpec::search_distance_m`].
    pub search_distance_m: Option<f64>,
    /// [`PhysicsSpec::sleeping`].
    pub sleeping: Option<bool>,
    /// [`PhysicsSpec::time_limit_s`].
    pub time_limit_s: Option<f64>,
    /// [`PhysicsSpec::settle_s`].
    pub settle_s: Option<f64>,
    /// [`PhysicsSpec::stop_at_rest`].
    pub stop_at_rest: Option<bool>,
    /// [`PhysicsSpec::rest`].
    pub rest: Option<RestTest>,
    /// [`PhysicsSpec::connections`].
    pub connections: Option<ConnectionModel>,
    /// [`PhysicsSpec::panel_connections`].
    pub panel_connections: Option<PanelConnections>,
    /// [`PhysicsSpec::hinge_end`].
    pub hinge_end: Option<crate::ruin::connection::HingeEnd>,
    /// [`PhysicsSpec::joints`].
    pub joints: Option<crate::ruin::search::JointContacts>,
    /// [`PhysicsSpec::ground_damping`].
    pub ground_damping: Option<GroundDamping>,
    /// `[physics.experimental]`: research and numerical keys ([`ExperimentalTable`]).
    pub experimental: ExperimentalTable,
}

/// `[physics.experimental]` as written: the keys a scenario does not need to describe a
/// building and its earthquake — solver numerics, research toggles and the alternatives
/// the measurements in docs/ruin-numerics.md and docs/handoff.md compare (each key's
/// meaning and default: [`PhysicsSpec`]; absent = the preset's value).
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ExperimentalTable {
    /// [`PhysicsSpec::sweep`].
    pub sweep: Option<SweepSpec>,
    /// [`PhysicsSpec::spring_correction`].
    pub spring_correction: Option<f64>,
    /// [`PhysicsSpec::spring_damping`].
    pub spring_damping: Option<f64>,
    /// [`PhysicsSpec::spring_limit`].
    pub spring_limit: Option<bool>,
    /// [`PhysicsSpec::angular_spring`].
    pub angular_spring: Option<crate::ruin::connection::AngularSpring>,
    /// [`PhysicsSpec::split_impulse`].
    pub split_impulse: Option<bool>,
    /// [`PhysicsSpec::split_impulse_threshold_m`].
    pub split_impulse_threshold_m: Option<f64>,
    /// [`PhysicsSpec::contact_erp`].
    pub contact_erp: Option<f64>,
    /// [`PhysicsSpec::joint_erp`].
    pub joint_erp: Option<f64>,
    /// [`PhysicsSpec::erp_steps_per_second`].
    pub erp_steps_per_second: Option<f64>,
    /// [`PhysicsSpec::margin_m`].
    pub margin_m: Option<f64>,
    /// [`PhysicsSpec::margin_max_share`].
    pub margin_max_share: Option<f64>,
    /// [`PhysicsSpec::spring_rest_at_plastic_onset`].
    pub spring_rest_at_plastic_onset: Option<bool>,
    /// [`PhysicsSpec::hinge_keeps_rotation`].
    pub hinge_keeps_rotation: Option<bool>,
    /// [`PhysicsSpec::hinge_return_mapping`].
    pub hinge_return_mapping: Option<bool>,
    /// [`PhysicsSpec::joint_rows`].
    pub joint_rows: Option<JointRowsSpec>,
    /// [`PhysicsSpec::joint_modulus_pa`].
    pub joint_modulus_pa: Option<f64>,
    /// [`PhysicsSpec::joint_damping_ratio`].
    pub joint_damping_ratio: Option<f64>,
    /// [`PhysicsSpec::joint_warmstart`].
    pub joint_warmstart: Option<f64>,
    /// [`PhysicsSpec::joint_iterations`].
    pub joint_iterations: Option<u32>,
    /// [`PhysicsSpec::joint_solve`].
    pub joint_solve: Option<JointSolveSpec>,
    /// [`PhysicsSpec::joint_solve_regularisation`].
    pub joint_solve_regularisation: Option<f64>,
    /// [`PhysicsSpec::axial_rows`].
    pub axial_rows: Option<crate::ruin::axial::AxialRows>,
    /// [`PhysicsSpec::spring_cap_per_body`].
    pub spring_cap_per_body: Option<bool>,
    /// [`PhysicsSpec::spring_cap_steps_per_second`].
    pub spring_cap_steps_per_second: Option<f64>,
    /// [`PhysicsSpec::monitor_every_substep`].
    pub monitor_every_substep: Option<bool>,
    /// [`PhysicsSpec::connected_pairs_touch`].
    pub connected_pairs_touch: Option<crate::ruin::separation::PairsTouch>,
    /// [`PhysicsSpec::ground_under_connected_bases`].
    pub ground_under_connected_bases: Option<bool>,
}

/// The keys of `[physics.experimental]` written directly in `[physics]`: refused, naming
/// the key and its table (the error carries the file's line from the `toml` crate).
mod moved {
    use serde::Deserializer;

    /// Never built: a moved key's value is refused while it is read.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub enum Moved {}

    macro_rules! refuse {
        ($($key:ident)*) => {$(
            pub fn $key<'de, D: Deserializer<'de>>(_: D) -> Result<Option<Moved>, D::Error> {
                Err(serde::de::Error::custom(concat!(
                    "physics.", stringify!($key), " is an experimental key: write it in ",
                    "[physics.experimental] (docs/scenario-format.md)"
                )))
            }
        )*};
    }

    refuse!(spring_correction spring_damping spring_limit angular_spring split_impulse split_impulse_threshold_m contact_erp joint_erp erp_steps_per_second margin_m margin_max_share spring_rest_at_plastic_onset hinge_keeps_rotation hinge_return_mapping joint_rows joint_modulus_pa joint_damping_ratio joint_warmstart joint_iterations joint_solve joint_solve_regularisation axial_rows spring_cap_per_body spring_cap_steps_per_second monitor_every_substep connected_pairs_touch ground_under_connected_bases);
}

impl PhysicsTable {
    /// The settings of a run in `mode`. Every default that depends on the mode or on
    /// another key is resolved here, one rule each:
    ///
    /// 1. The preset: as named (`preset`), else `fem2rbd` for hybrid and fe runs and
    ///    `bcb` for rigid-only runs ([`super::preset::Preset::for_mode`]).
    /// 2. `connections` given and not the preset's: the keys that follow the connection
    ///    model (`axial_rows`, `connected_pairs_touch`, `ground_under_connected_bases`,
    ///    `joint_warmstart`) take the values of the preset built on that model
    ///    ([`super::preset::Preset::for_connections`]), so BCB's connections keep BCB's
    ///    rows in any mode.
    /// 3. Every key given in the file replaces the value of rules 1 and 2.
    ///
    /// Resolved later, where the value they depend on is known: `joint_iterations`
    /// absent = the world's `solver_iterations` (`crate::ruin::stage::JointSettings::
    /// iterations`); `time_limit_s` absent = the record's end + `settle_s`
    /// (`crate::pipeline::time_limit`); `contact_erp` and `joint_erp` scaled by
    /// `erp_steps_per_second`/`steps_per_second` ([`PhysicsSpec::erp_scale`]);
    /// `rest.reference_length_m` absent = the building's height (`crate::ruin::rest`);
    /// `[collapse] threshold_m` absent = 1 m × the model's scale ([`CriterionSpec::resolve`]).
    pub fn resolve(&self, mode: Mode) -> PhysicsSpec {
        use super::preset::Preset;
        // Rule 1.
        let mut p = self.preset.unwrap_or(Preset::for_mode(mode)).physics();
        // Rule 2.
        if let Some(c) = self.connections {
            if c != p.connections {
                let q = Preset::for_connections(c).physics();
                p.axial_rows = q.axial_rows;
                p.connected_pairs_touch = q.connected_pairs_touch;
                p.ground_under_connected_bases = q.ground_under_connected_bases;
                p.joint_warmstart = q.joint_warmstart;
            }
        }
        // Rule 3.
        if let Some(v) = self.steps_per_second {
            p.steps_per_second = v;
        }
        if let Some(v) = self.solver_iterations {
            p.solver_iterations = v;
        }
        if let Some(v) = self.friction {
            p.friction = v;
        }
        if let Some(v) = self.restitution {
            p.restitution = v;
        }
        if let Some(v) = self.linear_damping {
            p.linear_damping = v;
        }
        if let Some(v) = self.angular_damping {
            p.angular_damping = v;
        }
        if let Some(v) = self.experimental.sweep {
            p.sweep = v;
        }
        if let Some(v) = self.experimental.spring_correction {
            p.spring_correction = v;
        }
        if let Some(v) = self.linear_correction {
            p.linear_correction = v;
        }
        if let Some(v) = self.bending_correction {
            p.bending_correction = v;
        }
        if let Some(v) = self.experimental.spring_damping {
            p.spring_damping = v;
        }
        if let Some(v) = self.experimental.spring_limit {
            p.spring_limit = v;
        }
        if let Some(v) = self.experimental.angular_spring {
            p.angular_spring = v;
        }
        if let Some(v) = self.experimental.split_impulse {
            p.split_impulse = v;
        }
        if let Some(v) = self.experimental.split_impulse_threshold_m {
            p.split_impulse_threshold_m = v;
        }
        if let Some(v) = self.experimental.contact_erp {
            p.contact_erp = v;
        }
        if let Some(v) = self.experimental.joint_erp {
            p.joint_erp = v;
        }
        if let Some(v) = self.experimental.erp_steps_per_second {
            p.erp_steps_per_second = v;
        }
        if let Some(v) = self.experimental.margin_m {
            p.margin_m = v;
        }
        if let Some(v) = self.experimental.margin_max_share {
            p.margin_max_share = v;
        }
        if let Some(v) = self.experimental.spring_rest_at_plastic_onset {
            p.spring_rest_at_plastic_onset = v;
        }
        if let Some(v) = self.experimental.hinge_keeps_rotation {
            p.hinge_keeps_rotation = v;
        }
        if let Some(v) = self.experimental.hinge_return_mapping {
            p.hinge_return_mapping = v;
        }
        if let Some(v) = self.experimental.joint_rows {
            p.joint_rows = v;
        }
        if let Some(v) = self.experimental.joint_modulus_pa {
            p.joint_modulus_pa = v;
        }
        if let Some(v) = self.experimental.joint_damping_ratio {
            p.joint_damping_ratio = v;
        }
        if let Some(v) = self.experimental.joint_warmstart {
            p.joint_warmstart = v;
        }
        if let Some(v) = self.experimental.joint_iterations {
            p.joint_iterations = Some(v);
        }
        if let Some(v) = self.experimental.joint_solve {
            p.joint_solve = v;
        }
        if let Some(v) = self.experimental.joint_solve_regularisation {
            p.joint_solve_regularisation = v;
        }
        if let Some(v) = self.experimental.axial_rows {
            p.axial_rows = v;
        }
        if let Some(v) = self.experimental.spring_cap_per_body {
            p.spring_cap_per_body = v;
        }
        if let Some(v) = self.experimental.spring_cap_steps_per_second {
            p.spring_cap_steps_per_second = v;
        }
        if let Some(v) = self.experimental.monitor_every_substep {
            p.monitor_every_substep = v;
        }
        if let Some(v) = self.experimental.connected_pairs_touch {
            p.connected_pairs_touch = v;
        }
        if let Some(v) = self.experimental.ground_under_connected_bases {
            p.ground_under_connected_bases = v;
        }
        if let Some(v) = self.search_distance_m {
            p.search_distance_m = v;
        }
        if let Some(v) = self.sleeping {
            p.sleeping = v;
        }
        if let Some(v) = self.time_limit_s {
            p.time_limit_s = Some(v);
        }
        if let Some(v) = self.settle_s {
            p.settle_s = v;
        }
        if let Some(v) = self.stop_at_rest {
            p.stop_at_rest = v;
        }
        if let Some(v) = self.rest {
            p.rest = v;
        }
        if let Some(v) = self.connections {
            p.connections = v;
        }
        if let Some(v) = self.panel_connections {
            p.panel_connections = v;
        }
        if let Some(v) = self.hinge_end {
            p.hinge_end = v;
        }
        if let Some(v) = self.joints {
            p.joints = v;
        }
        if let Some(v) = self.ground_damping {
            p.ground_damping = v;
        }
        p
    }
}

/// The file's content.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScenario {
    model: PathBuf,
    #[serde(default = "default_mode")]
    mode: Mode,
    #[serde(default)]
    velocity: VelocityHandoff,
    output: Option<PathBuf>,
    #[serde(default)]
    ground_motion: Vec<ComponentSpec>,
    #[serde(default)]
    fe: FeSpec,
    #[serde(default)]
    collapse: CollapseSpec,
    #[serde(default)]
    physics: PhysicsTable,
}

fn default_mode() -> Mode {
    Mode::Hybrid
}

/// The collapse criterion before the model's scale is known.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CriterionSpec {
    /// Vertical drop; `None` = 1 m × model scale.
    VerticalDrop(Option<f64>),
    /// Story drift ratio.
    StoryDrift(f64),
}

impl CriterionSpec {
    /// The criterion for a model of `scale` (1 = full size).
    pub fn resolve(self, scale: f64) -> Criterion {
        match self {
            CriterionSpec::VerticalDrop(t) => Criterion::VerticalDrop {
                threshold_m: t.unwrap_or(scale),
            },
            CriterionSpec::StoryDrift(r) => Criterion::StoryDrift { ratio: r },
        }
    }
}

/// A checked scenario, paths resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// The scenario file.
    pub path: PathBuf,
    /// Model file.
    pub model: PathBuf,
    /// Mode.
    pub mode: Mode,
    /// Velocity hand-off.
    pub velocity: VelocityHandoff,
    /// Output folder.
    pub output: PathBuf,
    /// Components, axis 0..3 = X, Y, Z, files resolved.
    pub components: [Option<ComponentSpec>; 3],
    /// FE time step, s.
    pub dt: f64,
    /// FE element variant.
    pub variant: Variant,
    /// FE duration, s (`None` = record).
    pub duration: Option<f64>,
    /// Integration of the shells' concrete layers (`[fe] concrete_integration`).
    pub concrete_integration: ConcreteIntegration,
    /// Collapse criterion.
    pub criterion: CriterionSpec,
    /// The ruin stage's settings, resolved for `mode` ([`PhysicsTable::resolve`]; after
    /// changing the mode, [`Scenario::set_mode`] resolves them again).
    pub physics: PhysicsSpec,
    /// The `[physics]` table as written.
    physics_table: PhysicsTable,
    /// Threads for the FE and the ruin stage's solver (`fem2rbd run --threads`; not read
    /// from the file); `None` = the machine's cores. The same bytes for any number.
    pub threads: Option<usize>,
    /// The ruin stage's debug traces (`fem2rbd run --trace-axial`, `--trace-body`; not
    /// read from the file): none by default.
    pub traces: crate::ruin::stage::TraceSettings,
}

impl Scenario {
    /// Runs the scenario in `mode` instead of the file's (`fem2rbd run --mode`, a study
    /// entry's mode): the `[physics]` table is resolved again for it, so the settings are
    /// those of a file that says `mode = "<mode>"`.
    pub fn set_mode(&mut self, mode: Mode) {
        self.mode = mode;
        self.physics = self.physics_table.resolve(mode);
    }

    /// The `[physics]` table as written in the file.
    pub fn physics_table(&self) -> &PhysicsTable {
        &self.physics_table
    }

    /// The files a run reads: the scenario, its model and its records.
    pub fn inputs(&self) -> Vec<&std::path::Path> {
        let mut v = vec![self.path.as_path(), self.model.as_path()];
        v.extend(self.components.iter().flatten().map(|c| c.file.as_path()));
        v
    }
}

fn positive(v: f64) -> bool {
    v > 0.0 && v.is_finite()
}

use crate::model::limits::{FE_DT, MAX_PGA_G, MAX_TIME_S, TIME_SCALE};

/// `item = v` must lie in its range (`lo` excluded with `lo_open`), unit `unit`.
fn range(
    file: &dyn std::fmt::Display,
    item: &str,
    v: f64,
    lo: f64,
    lo_open: bool,
    hi: f64,
    unit: &'static str,
) -> Result<(), ScenarioError> {
    crate::model::limits::check_range(item, v, lo, lo_open, hi, unit).map_err(|error| {
        ScenarioError::Range {
            file: file.to_string(),
            error,
        }
    })
}

impl PhysicsSpec {
    /// Checks every field against its physical range (docs/scenario-format.md,
    /// docs/reliability.md): rates and counts that size the work, coefficients that
    /// Bullet clamps or that make no physical sense outside their range (a restitution
    /// above 1 creates energy; Bullet clamps damping to [0, 1] per second), and the
    /// at-rest test. Items are named `physics.<field>`.
    pub fn check(&self) -> std::result::Result<(), crate::model::limits::RangeError> {
        use crate::model::limits::check_range as r;
        r(
            "physics.steps_per_second",
            self.steps_per_second,
            10.0,
            false,
            1e5,
            "1/s",
        )?;
        r(
            "physics.solver_iterations",
            f64::from(self.solver_iterations),
            1.0,
            false,
            1e4,
            "",
        )?;
        r("physics.friction", self.friction, 0.0, false, 10.0, "")?;
        r("physics.restitution", self.restitution, 0.0, false, 1.0, "")?;
        r(
            "physics.linear_damping",
            self.linear_damping,
            0.0,
            false,
            1.0,
            "",
        )?;
        r(
            "physics.angular_damping",
            self.angular_damping,
            0.0,
            false,
            1.0,
            "",
        )?;
        r(
            "physics.experimental.spring_correction",
            self.spring_correction,
            0.0,
            false,
            100.0,
            "",
        )?;
        r(
            "physics.linear_correction",
            self.linear_correction,
            0.0,
            true,
            100.0,
            "",
        )?;
        r(
            "physics.bending_correction",
            self.bending_correction,
            0.0,
            true,
            100.0,
            "",
        )?;
        r(
            "physics.experimental.spring_damping",
            self.spring_damping,
            0.0,
            false,
            1e4,
            "",
        )?;
        r(
            "physics.settle_s",
            self.settle_s,
            0.0,
            false,
            MAX_TIME_S,
            "s",
        )?;
        if let Some(t) = self.time_limit_s {
            r("physics.time_limit_s", t, 0.0, true, MAX_TIME_S, "s")?;
        }
        // Contact and joint error reduction (Bullet: a share of the error per substep),
        // the split-impulse penetration threshold (≤ 0 m: Bullet's convention, default
        // −0.04 m) and the collision margin.
        r(
            "physics.experimental.contact_erp",
            self.contact_erp,
            0.0,
            true,
            1.0,
            "",
        )?;
        r(
            "physics.experimental.joint_erp",
            self.joint_erp,
            0.0,
            true,
            1.0,
            "",
        )?;
        r(
            "physics.experimental.spring_cap_steps_per_second",
            self.spring_cap_steps_per_second,
            0.0,
            false,
            1e5,
            "1/s",
        )?;
        r(
            "physics.experimental.erp_steps_per_second",
            self.erp_steps_per_second,
            0.0,
            false,
            1e5,
            "1/s",
        )?;
        r(
            "physics.experimental.joint_modulus_pa",
            self.joint_modulus_pa,
            0.0,
            true,
            1e13,
            "Pa",
        )?;
        r(
            "physics.experimental.joint_warmstart",
            self.joint_warmstart,
            0.0,
            false,
            1.0,
            "",
        )?;
        r(
            "physics.experimental.joint_solve_regularisation",
            self.joint_solve_regularisation,
            0.0,
            false,
            1.0,
            "",
        )?;
        if let Some(n) = self.joint_iterations {
            r(
                "physics.experimental.joint_iterations",
                f64::from(n),
                1.0,
                false,
                10_000.0,
                "",
            )?;
        }
        r(
            "physics.experimental.joint_damping_ratio",
            self.joint_damping_ratio,
            0.0,
            true,
            1e3,
            "",
        )?;
        r(
            "physics.experimental.split_impulse_threshold_m",
            self.split_impulse_threshold_m,
            -1.0,
            false,
            0.0,
            "m",
        )?;
        r(
            "physics.experimental.margin_m",
            self.margin_m,
            0.0,
            true,
            1.0,
            "m",
        )?;
        r(
            "physics.search_distance_m",
            self.search_distance_m,
            0.0,
            true,
            2.0,
            "m",
        )?;
        r(
            "physics.experimental.margin_max_share",
            self.margin_max_share,
            0.0,
            true,
            1.0,
            "",
        )?;
        let rest = &self.rest;
        r(
            "physics.rest.energy_ratio",
            rest.energy_ratio,
            0.0,
            true,
            1.0,
            "",
        )?;
        r(
            "physics.rest.max_speed_mps",
            rest.max_speed_mps,
            0.0,
            true,
            100.0,
            "m/s",
        )?;
        r("physics.rest.hold_s", rest.hold_s, 0.0, true, 600.0, "s")?;
        if let Some(l) = rest.reference_length_m {
            r("physics.rest.reference_length_m", l, 0.0, true, 1000.0, "m")?;
        }
        Ok(())
    }
}

impl Scenario {
    /// Reads and checks a scenario file (module docs). Nothing is written.
    pub fn load(path: impl AsRef<Path>) -> Result<Scenario, ScenarioError> {
        let path = path.as_ref();
        crate::model::limits::check_input_file(path, "scenario file")?;
        let text = std::fs::read_to_string(path).map_err(|error| ScenarioError::Read {
            path: path.to_path_buf(),
            error,
        })?;
        Self::parse(&text, path)
    }

    /// Parses scenario text; `path` names the file in errors and anchors relative paths.
    pub fn parse(text: &str, path: &Path) -> Result<Scenario, ScenarioError> {
        let p = path.display();
        let invalid = |message: String| ScenarioError::Invalid {
            file: p.to_string(),
            message,
        };
        let raw: RawScenario = toml::from_str(text).map_err(|e| {
            let (line, col) = e
                .span()
                .map(|s| {
                    let before = &text[..s.start.min(text.len())];
                    let line = before.matches('\n').count() + 1;
                    let col = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
                    (line, col)
                })
                .unwrap_or((0, 0));
            ScenarioError::Syntax {
                file: p.to_string(),
                line,
                column: col,
                message: e.message().to_string(),
            }
        })?;
        Mode::warn_former_names(text, &p.to_string());
        let base = path.parent().unwrap_or(Path::new("."));
        let model = base.join(&raw.model);
        crate::model::limits::check_input_file(&model, "model file").map_err(|error| {
            ScenarioError::Input {
                item: format!("{p}: model"),
                error,
            }
        })?;
        if raw.ground_motion.is_empty() {
            return Err(invalid(
                "ground_motion: at least one component is needed".into(),
            ));
        }
        let mut components: [Option<ComponentSpec>; 3] = [None, None, None];
        for (i, c) in raw.ground_motion.iter().enumerate() {
            let item = format!("ground_motion[{i}]");
            let axis = c.direction.index();
            if components[axis].is_some() {
                return Err(invalid(format!(
                    "{item}: direction {} given twice",
                    c.direction
                )));
            }
            let file = base.join(&c.file);
            crate::model::limits::check_input_file(&file, "record file").map_err(|error| {
                ScenarioError::Input {
                    item: format!("{p}: {item}"),
                    error,
                }
            })?;
            if let Some(g) = c.pga_g {
                range(
                    &p,
                    &format!("ground_motion[{i}].pga_g"),
                    g,
                    0.0,
                    true,
                    MAX_PGA_G,
                    "g",
                )?;
            }
            range(
                &p,
                &format!("ground_motion[{i}].time_scale"),
                c.time_scale,
                TIME_SCALE.0,
                false,
                TIME_SCALE.1,
                "",
            )?;
            components[axis] = Some(ComponentSpec { file, ..c.clone() });
        }
        range(&p, "fe.dt", raw.fe.dt, FE_DT.0, false, FE_DT.1, "s")?;
        if let Some(d) = raw.fe.duration {
            range(&p, "fe.duration", d, 0.0, true, MAX_TIME_S, "s")?;
        }
        let variant = raw.fe.variant;
        let c = &raw.collapse;
        let criterion = match c.criterion {
            CriterionName::VerticalDrop => {
                if c.ratio.is_some() {
                    return Err(invalid(
                        "collapse.ratio is for a drift criterion, not vertical_drop".into(),
                    ));
                }
                if let Some(t) = c.threshold_m {
                    range(&p, "collapse.threshold_m", t, 0.0, true, 100.0, "m")?;
                }
                CriterionSpec::VerticalDrop(c.threshold_m)
            }
            CriterionName::Drift1In50 | CriterionName::Drift4Pct | CriterionName::Drift => {
                if c.threshold_m.is_some() {
                    return Err(invalid(
                        "collapse.threshold_m is for vertical_drop, not a drift criterion".into(),
                    ));
                }
                let r = match (c.criterion, c.ratio) {
                    (CriterionName::Drift, Some(r)) => r,
                    (CriterionName::Drift, None) => {
                        return Err(invalid("collapse.criterion = \"drift\" needs ratio".into()))
                    }
                    (_, Some(_)) => {
                        return Err(invalid(
                            "collapse.ratio is only for criterion = \"drift\"".into(),
                        ))
                    }
                    (CriterionName::Drift1In50, None) => 1.0 / 50.0,
                    _ => 0.04,
                };
                if !(positive(r) && r < 1.0) {
                    return Err(invalid(format!(
                        "collapse.ratio must be in (0, 1), got {r}"
                    )));
                }
                CriterionSpec::StoryDrift(r)
            }
        };
        let physics = raw.physics.resolve(raw.mode);
        physics.check().map_err(|error| ScenarioError::Range {
            file: p.to_string(),
            error,
        })?;
        // The ruin stage writes a keyframe every 1/frame_rate s and steps the world a
        // whole number of substeps between two keyframes (`ruin::build::check_rates`).
        let frame_rate = crate::ruin::connection::RuinSettings::default().frame_rate;
        let per_frame = physics.steps_per_second / frame_rate;
        if per_frame < 0.5 || (per_frame - per_frame.round()).abs() > 1e-9 * per_frame {
            return Err(invalid(format!(
                "physics.steps_per_second = {} substeps/s is not a whole multiple of the \
                 frame rate {frame_rate} frames/s: a keyframe is written every {} s of \
                 simulated time, and the world is stepped a whole number of substeps \
                 between two keyframes, so that every keyframe is a state Bullet computed; \
                 give a multiple of {frame_rate} substeps/s, e.g. {}",
                crate::model::limits::show_number(physics.steps_per_second),
                1.0 / frame_rate,
                per_frame.ceil().max(1.0) * frame_rate
            )));
        }
        if physics.panel_connections == PanelConnections::Elastic
            && physics.connections == ConnectionModel::Formula
        {
            return Err(invalid(
                "physics.panel_connections = \"elastic\" needs FE-derived connections \
                 (connections = \"fe\"); BCB's Formula Assistant limits every connection \
                 by its groups"
                    .into(),
            ));
        }
        if physics.hinge_return_mapping
            && !(physics.hinge_keeps_rotation && physics.connections == ConnectionModel::Fe)
        {
            return Err(invalid(
                "physics.experimental.hinge_return_mapping = true re-locks the ductile hinges of FE-derived \
                 connections: it needs connections = \"fe\" and hinge_keeps_rotation = true"
                    .into(),
            ));
        }
        if raw
            .output
            .as_ref()
            .is_some_and(|o| o.as_os_str().is_empty())
        {
            return Err(invalid(
                "output: the output folder is empty (give a folder name)".into(),
            ));
        }
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "scenario".into());
        let output = raw
            .output
            .clone()
            .unwrap_or_else(|| PathBuf::from("out").join(stem));
        Ok(Scenario {
            path: path.to_path_buf(),
            model,
            mode: raw.mode,
            velocity: raw.velocity,
            output,
            components,
            dt: raw.fe.dt,
            variant,
            duration: raw.fe.duration,
            concrete_integration: raw.fe.concrete_integration,
            criterion,
            physics,
            physics_table: raw.physics.clone(),
            threads: None,
            traces: Default::default(),
        })
    }
}
