//! BCB's per-frame monitor (`monitor.py`, `monitor_checkForChange`; docs/bcb.md §4, §11.5) as a
//! pure state machine. Re-implemented, not copied.
//!
//! Run [`Monitor::check`] once per frame (BCB: 25 Hz, not per substep) with the bodies'
//! current poses and the enabled flags Bullet reports (Bullet disables a constraint whose
//! row impulse reached its breaking threshold). It returns the [`Action`]s to apply.
//!
//! Per connection, with d = |c_B − c_A| the centre distance and d₀ its reference value:
//!
//! * distDif = |1 − d₀/d| (1 if d = 0).
//! * anglDif, by [`AngleRule`]:
//!   - [`AngleRule::RelativeRotation`] (default): Δ = the angle of the change of the
//!     relative rotation q_A⁻¹·q_B since the reference, in [0, π]. Elastic: anglDif = Δ;
//!     plastic: anglDif = asin(sin(Δ/2)) = Δ/2 (BCB's plastic-mode half angle).
//!   - [`AngleRule::BcbZAxis`] (BCB verbatim): θ₀ = angle of q_A⁻¹·q_B at the reference;
//!     elastic: anglDif = |θ₀ − ∠(Z_A, Z_B)| (the angle between the bodies' local z axes);
//!     plastic: anglDif = asin(sin(|θ₀ − θ|/2)), θ the current relative-rotation angle.
//!     Right only when the bodies start with equal orientations (BCB's applied-rotation
//!     meshes); a beam turned 90° about z against a column would start "deformed".
//!     Twist about a common z axis goes unseen in the elastic check.
//! * **Elastic → plastic**: distDif > tol1D + anglDif/π or anglDif > tol1R → disable the six
//!   generics, enable the spring, d₀ := d. Without a spring → broken.
//! * **Plastic → broken**: distDif > tol2D + anglDif/π or anglDif > tol2R → disable the
//!   spring.
//! * A disabled (`None`) tolerance is not checked.
//! * **Beyond BCB**: an elastic connection whose six generics have all been broken by
//!   Bullet is broken (BCB would keep it "intact" and could later switch its spring on);
//!   this check comes before the tolerance check. A plastic connection whose spring
//!   broke by impulse is broken.
//!
//! The reference (d₀ and the relative rotation) is the pose when the monitor starts — Tc
//! in the hybrid mode, so the FE deformation before Tc counts through the starting state
//! instead ([`start_state_from_damage`]).

use super::connection::{ConnectionSpec, ConnectionState, ResolvedTolerances, GENERIC_COUNT};
use super::RuinError;
use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// How the monitor measures the rotation of a connection (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AngleRule {
    /// The angle of the change of the relative rotation (frame-invariant).
    #[default]
    RelativeRotation,
    /// BCB's own measures (z-axis angle when elastic, quaternion-angle difference when
    /// plastic).
    BcbZAxis,
}

/// The FE damage at Tc at a connection (the worse of the two element ends it joins).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FeDamage {
    /// No reinforcement yielded.
    Intact,
    /// Reinforcement yielded (steel strain beyond yield).
    Yielded,
    /// Reinforcement ruptured (steel strain beyond its ultimate elongation) or the
    /// concrete section crushed through.
    Ruptured,
}

/// The documented hand-off rule: the FE damage at Tc sets a connection's starting state.
/// Intact → elastic (BCB's start); yielded → plastic (the rebar already flows, so the
/// connection starts on its plastic spring, equilibrium at the Tc pose); ruptured →
/// broken (nothing left to hold).
pub fn start_state_from_damage(damage: FeDamage) -> ConnectionState {
    match damage {
        FeDamage::Intact => ConnectionState::Elastic,
        FeDamage::Yielded => ConnectionState::Plastic,
        FeDamage::Ruptured => ConnectionState::Broken,
    }
}

/// One enable/disable order for the Bullet layer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct Action {
    /// Index of the connection (in the slice the monitor was built from).
    pub connection: usize,
    /// Index of the constraint within the connection (0–5 generics, 6 the spring).
    pub constraint: usize,
    /// `true` = enable, `false` = disable.
    pub enable: bool,
}

/// A state change seen in one [`Monitor::check`] frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct StateChange {
    /// Index of the connection.
    pub connection: usize,
    /// State before the frame.
    pub from: ConnectionState,
    /// State after the frame.
    pub to: ConnectionState,
}

/// Counts of connections per state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct StateCounts {
    /// Elastic (intact) connections.
    pub elastic: usize,
    /// Plastic connections.
    pub plastic: usize,
    /// Broken connections.
    pub broken: usize,
}

#[derive(Debug, Clone)]
struct Entry {
    a: usize,
    b: usize,
    has_spring: bool,
    tol: ResolvedTolerances,
    d0: f64,
    rel0: UnitQuaternion<f64>,
    state: ConnectionState,
}

/// The monitor: one entry per connection.
#[derive(Debug, Clone)]
pub struct Monitor {
    entries: Vec<Entry>,
    rule: AngleRule,
    changes: Vec<StateChange>,
}

/// The deformation measures of one connection (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Deformation {
    /// Current centre distance d, m.
    pub dist: f64,
    /// distDif = |1 − d₀/d|.
    pub dist_dif: f64,
    /// anglDif, rad, as the state's check uses it.
    pub angl_dif: f64,
}

impl Monitor {
    /// Starts the monitor. `reference_poses` (one per body) fix d₀ and the reference
    /// relative rotation; `start` gives each connection's starting state (the specs'
    /// `enabled` flags should match: [`ConnectionSpec::set_state`]). A plastic start
    /// without a spring is broken.
    pub fn new(
        connections: &[ConnectionSpec],
        reference_poses: &[Isometry3<f64>],
        start: &[ConnectionState],
        rule: AngleRule,
    ) -> Result<Monitor, RuinError> {
        if start.len() != connections.len() {
            return Err(RuinError::LengthMismatch {
                what: "monitor starting states".into(),
                expected: connections.len(),
                got: start.len(),
            });
        }
        let mut entries = Vec::with_capacity(connections.len());
        for (i, (c, &s)) in connections.iter().zip(start).enumerate() {
            if c.a >= reference_poses.len() || c.b >= reference_poses.len() {
                return Err(RuinError::BadSetting {
                    item: format!("connection {i}"),
                    message: format!(
                        "body index ({}, {}) beyond the {} reference poses",
                        c.a,
                        c.b,
                        reference_poses.len()
                    ),
                });
            }
            let (pa, pb) = (&reference_poses[c.a], &reference_poses[c.b]);
            let state = if s == ConnectionState::Plastic && !c.has_spring() {
                ConnectionState::Broken
            } else {
                s
            };
            entries.push(Entry {
                a: c.a,
                b: c.b,
                has_spring: c.has_spring(),
                tol: c.tolerances,
                d0: (pb.translation.vector - pa.translation.vector).norm(),
                rel0: pa.rotation.inverse() * pb.rotation,
                state,
            });
        }
        Ok(Monitor {
            entries,
            rule,
            changes: Vec::new(),
        })
    }

    /// The current state of every connection.
    pub fn states(&self) -> Vec<ConnectionState> {
        self.entries.iter().map(|e| e.state).collect()
    }

    /// The state of connection `i`.
    pub fn state(&self, i: usize) -> ConnectionState {
        self.entries[i].state
    }

    /// The state changes of the last [`Self::check`] call, in connection order (including
    /// those caused by Bullet's impulse breaking, which need no action).
    pub fn last_changes(&self) -> &[StateChange] {
        &self.changes
    }

    /// Counts per state.
    pub fn counts(&self) -> StateCounts {
        let mut c = StateCounts::default();
        for e in &self.entries {
            match e.state {
                ConnectionState::Elastic => c.elastic += 1,
                ConnectionState::Plastic => c.plastic += 1,
                ConnectionState::Broken => c.broken += 1,
            }
        }
        c
    }

    /// The deformation measures of connection `i` at `poses`, as its current state's
    /// check would compute them.
    pub fn deformation(&self, i: usize, poses: &[Isometry3<f64>]) -> Deformation {
        let e = &self.entries[i];
        measure(e, &poses[e.a], &poses[e.b], self.rule)
    }

    /// One monitor frame. `poses`: every body's current pose. `is_enabled(connection,
    /// constraint)`: whether Bullet still has that constraint enabled. Returns the actions
    /// in (connection, constraint) order.
    pub fn check(
        &mut self,
        poses: &[Isometry3<f64>],
        is_enabled: impl Fn(usize, usize) -> bool,
    ) -> Result<Vec<Action>, RuinError> {
        let needed = self
            .entries
            .iter()
            .map(|e| e.a.max(e.b) + 1)
            .max()
            .unwrap_or(0);
        if poses.len() < needed {
            return Err(RuinError::LengthMismatch {
                what: "monitor poses".into(),
                expected: needed,
                got: poses.len(),
            });
        }
        let mut actions = Vec::new();
        let rule = self.rule;
        self.changes.clear();
        for (ci, e) in self.entries.iter_mut().enumerate() {
            let before = e.state;
            step_entry(ci, e, poses, &is_enabled, rule, &mut actions);
            if e.state != before {
                self.changes.push(StateChange {
                    connection: ci,
                    from: before,
                    to: e.state,
                });
            }
        }
        Ok(actions)
    }
}

/// One connection's monitor step (module docs); pushes its actions.
fn step_entry(
    ci: usize,
    e: &mut Entry,
    poses: &[Isometry3<f64>],
    is_enabled: &impl Fn(usize, usize) -> bool,
    rule: AngleRule,
    actions: &mut Vec<Action>,
) {
    match e.state {
        ConnectionState::Broken => {}
        ConnectionState::Elastic => {
            let any_generic = (0..GENERIC_COUNT).any(|k| is_enabled(ci, k));
            if !any_generic {
                e.state = ConnectionState::Broken;
                return;
            }
            let m = measure(e, &poses[e.a], &poses[e.b], rule);
            if exceeds(m, e.tol.dist1, e.tol.rot1) {
                for k in 0..GENERIC_COUNT {
                    if is_enabled(ci, k) {
                        actions.push(Action {
                            connection: ci,
                            constraint: k,
                            enable: false,
                        });
                    }
                }
                if e.has_spring {
                    actions.push(Action {
                        connection: ci,
                        constraint: GENERIC_COUNT,
                        enable: true,
                    });
                    e.d0 = m.dist;
                    e.state = ConnectionState::Plastic;
                } else {
                    e.state = ConnectionState::Broken;
                }
            }
        }
        ConnectionState::Plastic => {
            if !is_enabled(ci, GENERIC_COUNT) {
                e.state = ConnectionState::Broken;
                return;
            }
            let m = measure(e, &poses[e.a], &poses[e.b], rule);
            if exceeds(m, e.tol.dist2, e.tol.rot2) {
                actions.push(Action {
                    connection: ci,
                    constraint: GENERIC_COUNT,
                    enable: false,
                });
                e.state = ConnectionState::Broken;
            }
        }
    }
}

/// distDif > tolD + anglDif/π or anglDif > tolR (a `None` tolerance is not checked).
fn exceeds(m: Deformation, tol_dist: Option<f64>, tol_rot: Option<f64>) -> bool {
    tol_dist.is_some_and(|t| m.dist_dif > t + m.angl_dif / PI)
        || tol_rot.is_some_and(|t| m.angl_dif > t)
}

fn measure(e: &Entry, pa: &Isometry3<f64>, pb: &Isometry3<f64>, rule: AngleRule) -> Deformation {
    let dist = (pb.translation.vector - pa.translation.vector).norm();
    let dist_dif = if dist > 0.0 {
        (1.0 - e.d0 / dist).abs()
    } else {
        1.0
    };
    let rel = pa.rotation.inverse() * pb.rotation;
    let plastic = e.state == ConnectionState::Plastic;
    let angl_dif = match rule {
        AngleRule::RelativeRotation => {
            let delta = (e.rel0.inverse() * rel).angle();
            if plastic {
                (delta / 2.0).sin().asin()
            } else {
                delta
            }
        }
        AngleRule::BcbZAxis => {
            let theta0 = e.rel0.angle();
            if plastic {
                ((theta0 - rel.angle()).abs() / 2.0).sin().asin()
            } else {
                let za = pa.rotation * Vector3::z();
                let zb = pb.rotation * Vector3::z();
                (theta0 - za.angle(&zb)).abs()
            }
        }
    };
    Deformation {
        dist,
        dist_dif,
        angl_dif,
    }
}
