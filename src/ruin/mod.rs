//! The ruin stage's pure model: BCB-equivalent connections between rigid boxes.
//!
//! This module reproduces the constraint model of the Bullet Constraints Builder (BCB,
//! K. Kostack; see `docs/bcb.md`, §2–§4, §7.3 and §11), which the paper (Zheng et
//! al. 2020) used for its ruin stage, as plain data and pure functions. It knows nothing
//! of Bullet: the Bullet layer turns the [`connection::ConstraintSpec`]s into
//! `btGeneric6DofConstraint` / `btGeneric6DofSpring2Constraint` objects and applies the
//! [`monitor::Action`]s the monitor returns once per frame.
//!
//! * [`search`]: which boxes touch (sort-and-sweep over enlarged AABBs) and the contact
//!   rectangle, pivot and normal of each touching pair.
//! * [`strength`]: the Formula Assistant's RC strengths per mm² of contact area.
//! * [`connection`]: per connection, BCB's connection type 22 — six generic 6-DOF
//!   constraints and one disabled 6-DOF spring — with breaking impulses, limits, frames.
//! * [`monitor`]: the per-frame elastic → plastic → broken state machine.
//!
//! The Bullet layer is the ruin stage ([`stage`]): a world (`world`: the ground box, the
//! members' boxes, the connections' constraints) built by `build` (ground, bodies,
//! connections) from [`settings`], stepped by an ordered list of substep passes (`pass`,
//! one file per rule: the moving ground, Bullet's step, each connection rule, the
//! separations, the energy ledger, the speed bound, the monitor, the at-rest test) with
//! the debug traces as observers (`observer`), and recorded as a [`record::RuinResult`].
//!
//! Units: SI (m, kg, s, N, N·m, N·s) except where BCB's own inputs are in mm and N/mm²
//! (the Formula Assistant); every such field says so.
//! The whole model is described in `docs/ruin-model.md`.

pub mod axial;
pub(crate) mod body_trace;
mod build;
pub mod connection;
pub mod energy;
pub mod ground;
pub mod groups;
pub mod monitor;
pub(crate) mod observer;
pub(crate) mod pass;
pub mod record;
pub mod rest;
pub mod search;
pub mod separation;
pub mod settings;
pub mod stage;
pub mod strength;
pub(crate) mod world;

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

/// Errors of the ruin model: bad input, named by the item it concerns.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum RuinError {
    /// A body's geometry is unusable (NaN, non-positive half extent, ...).
    #[error("rigid body {index} ('{name}'): {message}")]
    BadBody {
        /// Index of the body in the input slice.
        index: usize,
        /// Its name.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// A body names a group that has no strength definition.
    #[error(
        "rigid body {index} ('{name}') is in group '{group}', which has no strength definition"
    )]
    UnknownGroup {
        /// Index of the body.
        index: usize,
        /// Its name.
        name: String,
        /// The missing group.
        group: String,
    },
    /// A group's strength definition or a setting is unusable.
    #[error("{item}: {message}")]
    BadSetting {
        /// The group or setting concerned.
        item: String,
        /// What is wrong.
        message: String,
    },
    /// Slices that must have one entry per body or per connection do not.
    #[error("{what}: expected {expected} entries, got {got}")]
    LengthMismatch {
        /// Which input.
        what: String,
        /// Expected length.
        expected: usize,
        /// Actual length.
        got: usize,
    },
}

/// A rigid box as the ruin stage sees it (the mapping stage's boxes convert to this).
#[derive(Debug, Clone, PartialEq)]
pub struct BodyGeom {
    /// Object name, e.g. `Beam:1:234`.
    pub name: String,
    /// Element group (BCB material group), the key into the group strengths.
    pub group: String,
    /// Box centre in world coordinates, m (also the body's origin).
    pub centre: [f64; 3],
    /// Orientation of the box (local → world).
    pub rotation: UnitQuaternion<f64>,
    /// Half extents along the box's local x, y, z, m.
    pub half_extents: [f64; 3],
    /// Passive body (BCB CT 0 group: foundation, kinematic ground). Connections to it get
    /// ×2 thresholds; two passive bodies are never connected.
    pub passive: bool,
}

impl BodyGeom {
    /// The body's pose (centre and rotation) as an isometry, local → world.
    pub fn pose(&self) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::new(self.centre[0], self.centre[1], self.centre[2]),
            self.rotation,
        )
    }

    /// World axis-aligned bounding box: centre ± |R|·half_extents.
    pub fn aabb(&self) -> Aabb {
        let r = self.rotation.to_rotation_matrix();
        let m = r.matrix();
        let he = Vector3::from(self.half_extents);
        let mut ext = [0.0; 3];
        for (i, e) in ext.iter_mut().enumerate() {
            *e = m[(i, 0)].abs() * he.x + m[(i, 1)].abs() * he.y + m[(i, 2)].abs() * he.z;
        }
        Aabb {
            min: [
                self.centre[0] - ext[0],
                self.centre[1] - ext[1],
                self.centre[2] - ext[2],
            ],
            max: [
                self.centre[0] + ext[0],
                self.centre[1] + ext[1],
                self.centre[2] + ext[2],
            ],
        }
    }

    /// Checks the geometry is finite with positive half extents.
    pub fn validate(&self, index: usize) -> Result<(), RuinError> {
        let bad = |message: String| RuinError::BadBody {
            index,
            name: self.name.clone(),
            message,
        };
        if self.centre.iter().any(|v| !v.is_finite()) {
            return Err(bad(format!("centre {:?} is not finite", self.centre)));
        }
        let q = self.rotation.quaternion();
        if !(q.w.is_finite() && q.i.is_finite() && q.j.is_finite() && q.k.is_finite()) {
            return Err(bad("rotation is not finite".into()));
        }
        if self
            .half_extents
            .iter()
            .any(|v| !v.is_finite() || *v <= 0.0)
        {
            return Err(bad(format!(
                "half extents {:?} must be finite and > 0",
                self.half_extents
            )));
        }
        Ok(())
    }
}

/// An axis-aligned box in world coordinates, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: [f64; 3],
    /// Upper corner.
    pub max: [f64; 3],
}

impl Aabb {
    /// The box grown by `margin` on every side.
    pub fn enlarged(&self, margin: f64) -> Aabb {
        Aabb {
            min: self.min.map(|v| v - margin),
            max: self.max.map(|v| v + margin),
        }
    }
}
