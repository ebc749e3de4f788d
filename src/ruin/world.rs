//! The ruin stage's world: Bullet's world with the ground box ([`Ground`]), the members'
//! boxes ([`Bodies`]) and the connections' constraints ([`Connections`]), each with the
//! handles that name it. The substep passes (`super::pass`) act on it, in the order of
//! `super::stage::RuinStage::substep`; it is built by `super::build`.

use super::connection::{ConnectionSpec, ConnectionState};
use super::energy::MassProps;
use super::ground::GroundSpec;
use super::record::StageError;
use super::rest::RestBody;
use crate::bullet::{BodyHandle, ConstraintHandle, Pose, Velocity, World};
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};

/// The Bullet world of a ruin stage and what is in it.
pub(crate) struct RuinWorld {
    /// Bullet's world.
    pub(crate) bullet: World,
    /// The ground box.
    pub(crate) ground: Ground,
    /// The members' boxes, in input order.
    pub(crate) bodies: Bodies,
    /// The connections and their constraints.
    pub(crate) connections: Connections,
}

/// The ground box (`super::ground`): body 0 of the world.
pub(crate) struct Ground {
    /// Its world handle.
    pub(crate) handle: BodyHandle,
    /// Its pose with zero displacement.
    pub(crate) rest: Pose,
    /// Its half extents, m.
    pub(crate) half_extents: [f64; 3],
    /// Its size and motion.
    pub(crate) spec: GroundSpec,
    /// A point of its top face at rest, m: the potential energy's reference
    /// (`super::energy`).
    pub(crate) reference: [f64; 3],
}

/// The members' boxes, in input order (world body i + 1).
pub(crate) struct Bodies {
    /// World handles.
    pub(crate) handles: Vec<BodyHandle>,
    /// Passive (kinematic, riding on the ground: foundation blocks) or dynamic.
    pub(crate) passive: Vec<bool>,
    /// Poses at the start, local → world.
    pub(crate) start_poses: Vec<Isometry3<f64>>,
    /// Mass, inertia and radius of each dynamic body for the rest test (passive: `None`).
    pub(crate) rest: Vec<Option<RestBody>>,
    /// Mass and inertia of each dynamic body for the energy ledger (passive: `None`).
    pub(crate) props: Vec<Option<MassProps>>,
    /// Total mass of the dynamic bodies, kg.
    pub(crate) total_mass_kg: f64,
    /// Height of the undeformed model, m.
    pub(crate) model_height_m: f64,
}

/// The connections (BCB's CT 22, `super::connection`) and their Bullet constraints.
pub(crate) struct Connections {
    /// The specs as created, with their starting `enabled` flags.
    pub(crate) specs: Vec<ConnectionSpec>,
    /// Per connection, the Bullet handles of its constraints, in spec order.
    pub(crate) handles: Vec<Vec<ConstraintHandle>>,
    /// Per connection, its state at the start.
    pub(crate) start_states: Vec<ConnectionState>,
    /// Per connection, the first generic row Bullet let go while the connection was
    /// elastic: (constraint index, end time of the substep, s) —
    /// [`super::record::ConnectionOutcome::first_row_lost`]. Written by the passes
    /// `lost_rows` and `two_way_axial`.
    pub(crate) first_lost: Vec<Option<(usize, f64)>>,
}

impl Connections {
    /// Whether constraint `k` of connection `c` exists and is enabled in `enabled` (every
    /// constraint's flag, by handle index).
    pub(crate) fn is_on(&self, enabled: &[bool], c: usize, k: usize) -> bool {
        self.handles[c].get(k).is_some_and(|h| enabled[h.index()])
    }
}

impl RuinWorld {
    /// The poses of the input bodies, input order.
    pub(crate) fn body_poses(&self) -> Result<Vec<Pose>, StageError> {
        let all = self.bullet.poses()?;
        Ok(self.bodies.handles.iter().map(|h| all[h.index()]).collect())
    }

    /// The velocities of the input bodies, input order.
    pub(crate) fn body_velocities(&self) -> Result<Vec<Velocity>, StageError> {
        let all = self.bullet.velocities()?;
        Ok(self.bodies.handles.iter().map(|h| all[h.index()]).collect())
    }

    /// The deepest penetration between any two bodies after the last substep, m (≥ 0;
    /// Bullet's most negative contact distance, negated).
    pub(crate) fn deepest_penetration(&self) -> Result<f64, StageError> {
        Ok(self
            .bullet
            .contact_pairs()?
            .iter()
            .map(|p| -p.contact.min_distance)
            .filter(|d| d.is_finite())
            .fold(0.0, f64::max))
    }
}

/// Bullet's activation state `ISLAND_SLEEPING`.
pub(crate) const ISLAND_SLEEPING: i32 = 2;

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

/// `pose` translated by `d`.
pub(crate) fn shifted(pose: &Pose, d: [f64; 3]) -> Pose {
    Pose {
        position: [
            pose.position[0] + d[0],
            pose.position[1] + d[1],
            pose.position[2] + d[2],
        ],
        orientation: pose.orientation,
    }
}
