//! The ruin stage's substep passes: each rule that acts on the world in a substep, with
//! its own state, in a file of its own. Their order is
//! `crate::ruin::stage::RuinStage::substep` (one substep) and
//! `crate::ruin::stage::RuinStage::run_with` (one frame):
//!
//! | order | pass | file |
//! |---|---|---|
//! | 1 | gravity warm-up | `gravity_warmup` |
//! | 2 | moving ground and foundations | `ground_motion` |
//! | 3 | ground and foundations asleep after the motion | `sleep` |
//! | 4 | Bullet's step | `bullet_step` |
//! | 5 | first row lost per elastic connection | `lost_rows` |
//! | 6 | ductile bending rows yield | `ductile_rows` |
//! | 7 | two-way axial rows break per sense | `two_way_axial` |
//! | 8 | separated pairs touch again | `separation` |
//! | 9 | damping relative to the ground | `ground_damping` |
//! | 10 | energy ledger | `energy` |
//! | 11 | largest body speed | `speed_bound` |
//! | 12 | connection monitor (per substep, or per frame) | `monitor` |
//! | frame | at-rest test | `rest` |
//!
//! The debug traces watch the substeps as observers (`crate::ruin::observer`).

pub(crate) mod bullet_step;
pub(crate) mod ductile_rows;
pub(crate) mod energy;
pub(crate) mod gravity_warmup;
pub(crate) mod ground_damping;
pub(crate) mod ground_motion;
pub(crate) mod lost_rows;
pub(crate) mod monitor;
pub(crate) mod rest;
pub(crate) mod separation;
pub(crate) mod sleep;
pub(crate) mod speed_bound;
pub(crate) mod two_way_axial;

use crate::bullet::{Pose, Velocity};

/// The input bodies' poses and velocities at one instant, input order.
pub(crate) struct BodyState {
    /// Poses.
    pub(crate) poses: Vec<Pose>,
    /// Velocities, world frame.
    pub(crate) vels: Vec<Velocity>,
}

/// Every substep pass of a stage, with its state.
pub(crate) struct Passes {
    /// 1.
    pub(crate) gravity: gravity_warmup::GravityWarmup,
    /// 2.
    pub(crate) ground_motion: ground_motion::GroundMotion,
    /// 3.
    pub(crate) sleep: sleep::KinematicSleep,
    /// 4.
    pub(crate) bullet_step: bullet_step::BulletStep,
    /// 5.
    pub(crate) lost_rows: lost_rows::LostRows,
    /// 6.
    pub(crate) ductile_rows: ductile_rows::DuctileRows,
    /// 7.
    pub(crate) two_way_axial: two_way_axial::TwoWayAxial,
    /// 8.
    pub(crate) separation: separation::Separations,
    /// 9.
    pub(crate) ground_damping: ground_damping::GroundDamping,
    /// 10.
    pub(crate) energy: energy::EnergyLedger,
    /// 11.
    pub(crate) speed_bound: speed_bound::SpeedBound,
    /// 12.
    pub(crate) monitor: monitor::MonitorPass,
}
