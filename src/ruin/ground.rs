//! The ruin stage's ground: a large rigid box whose top face is the model's base, moved
//! kinematically by the rest of the earthquake record (BCB step 3, docs/bcb.md §6 and §11.6).
//!
//! * **Box** (BCB's `Ground_Motion` object): it spans the undeformed model's plan AABB
//!   grown by [`GroundSpec::plan_margin_m`] (BCB: 500 m) on every side and is
//!   [`GroundSpec::thickness_m`] thick (BCB: 10 m); its top is at `top_z` (default: the
//!   lowest point of the undeformed bodies, the model's base z = 0 plane). Friction 1.
//! * **Motion**: with a [`GroundHistory`] the ground is a kinematic body whose position at
//!   time t is `rest position + d(t)`, d the record's **absolute** ground displacement
//!   (`GroundHistory::ground_state_at`). Starting at Tc, the ground is therefore where the
//!   FE stage's ground is at Tc, with the same velocity (d and v are continuous in t).
//!   Passive bodies (foundation blocks) ride along: `start pose + d(t) − d(t_start)`.
//! * **Stepping**: before every substep [t_k, t_k + h] the ground is placed at d(t_k + h).
//!   Bullet's `saveKinematicState` then gives it the secant velocity (d(t_k+h) − d(t_k))/h
//!   during that substep's solve, so a body resting on it is carried by exactly the
//!   record's displacement increment (BCB/Blender 2.79 set the transform once per frame
//!   instead, docs/bcb.md §10.12; per substep is our documented option).
//! * Without a history the ground is a **static** box (nothing moves it).

use crate::motion::GroundHistory;

/// The ground of a ruin stage.
#[derive(Debug, Clone, PartialEq)]
pub struct GroundSpec {
    /// The ground motion (absolute ground displacement from t = 0); `None` = still ground
    /// (a static box).
    pub history: Option<GroundHistory>,
    /// z of the ground's top face, m; `None` = the lowest point of the undeformed bodies.
    pub top_z: Option<f64>,
    /// How far the box reaches beyond the undeformed model's plan AABB on every side, m
    /// (BCB 500).
    pub plan_margin_m: f64,
    /// Thickness of the box, m (BCB 10).
    pub thickness_m: f64,
    /// Friction coefficient (BCB 1.0 for ground and foundation objects).
    pub friction: f64,
}

impl Default for GroundSpec {
    fn default() -> Self {
        GroundSpec {
            history: None,
            top_z: None,
            plan_margin_m: 500.0,
            thickness_m: 10.0,
            friction: 1.0,
        }
    }
}

impl GroundSpec {
    /// A ground moved by `history`, otherwise BCB's defaults.
    pub fn moving(history: GroundHistory) -> Self {
        GroundSpec {
            history: Some(history),
            ..GroundSpec::default()
        }
    }

    /// Absolute ground displacement at time `t`, m (zero without a history).
    pub fn displacement_at(&self, t: f64) -> [f64; 3] {
        match &self.history {
            Some(h) => h.ground_state_at(t).0,
            None => [0.0; 3],
        }
    }

    /// Absolute ground velocity at time `t`, m/s (zero without a history).
    pub fn velocity_at(&self, t: f64) -> [f64; 3] {
        match &self.history {
            Some(h) => h.ground_state_at(t).1,
            None => [0.0; 3],
        }
    }

    /// The time after which the ground no longer shakes, s (the record's end; 0 without
    /// a history). After it the ground moves at most uniformly (zero with the default
    /// `Baseline::ZeroEnd`).
    pub fn motion_end_s(&self) -> f64 {
        self.history.as_ref().map_or(0.0, |h| h.end_time_s())
    }
}
