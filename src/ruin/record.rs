//! What a ruin stage records: its frames, each connection's outcome, the energy and speed
//! figures, why it stopped ([`RuinResult`]), and its errors ([`StageError`]).

use super::connection::{ConnectionState, ConstraintRole};
use super::energy::EnergyFrame;
use super::monitor::StateCounts;
use super::rest::RestSpeed;
use super::RuinError;
use crate::bullet::{PhysicsError, Pose, Velocity};
use std::time::Duration;

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

/// The result of [`super::stage::RuinStage::run`].
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
    /// Per connection (in [`super::stage::RuinStage::connections`] order).
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
    /// holds, which bounds the island-parallel speed-up); `None` for a world of Bullet's
    /// stock classes, whose solver keeps no such statistics
    /// ([`crate::bullet::WorldSettings::stock_solver`]).
    pub islands: Option<crate::bullet::IslandStats>,
    /// Dynamic bodies asleep at the end (0 unless sleeping is on).
    pub sleeping_at_end: usize,
    /// The direct joint solve's mode and counts over the run
    /// ([`crate::ruin::settings::JointSettings::solve`]).
    pub joint_solve: crate::bullet::JointSolveStats,
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
