//! The rigid-body model of a building: the mapped boxes ([`super::map_to_boxes`]) as
//! active bodies, then one passive (kinematic) foundation block under every column that
//! stands on the base — plan 2·a × 2·a, depth a, a = the larger cross-section size of the
//! column box, top at the base level — and a foundation strip under every wall body that
//! stands on it ([`bodies_of`]). The FE model's base nodes are fixed to the ground; the
//! bottom columns connect to their block with ×2 thresholds (BCB's passive group rule).

use super::{RigidBox, Role};
use crate::body::{Body, BodyId};
use crate::bullet::Pose;
use crate::model::Model;
use nalgebra::UnitQuaternion;

/// The model's bodies: mapped boxes then foundation blocks (module docs).
pub fn bodies_of(model: &Model, mapping: &super::Mapping) -> Vec<Body> {
    let mut out: Vec<Body> = mapping
        .bodies
        .iter()
        .map(|b| Body {
            id: b.id.clone(),
            kind: Some(b.kind),
            half_extents: b.half_extents,
            pose0: pose_of(b),
            mass_kg: b.mass_kg,
            passive: false,
        })
        .collect();
    let zmin = model
        .nodes
        .iter()
        .map(|n| n.xyz()[2])
        .fold(f64::INFINITY, f64::min);
    let mut feet = Vec::new();
    for b in &mapping.bodies {
        if b.kind == Role::Wall {
            if let Some(f) = wall_foot(b, zmin) {
                feet.push(f);
            }
            continue;
        }
        if b.kind != Role::Column {
            continue;
        }
        let Some(base) = b.nodes.iter().find(|n| (n[2] - zmin).abs() < 1e-9) else {
            continue;
        };
        let a = b.half_extents[1].max(b.half_extents[2]) * 2.0;
        let tag = model
            .nodes
            .iter()
            .find(|n| n.xyz() == *base)
            .map_or(0, |n| n.tag);
        feet.push(Body {
            id: BodyId::Foundation { node: tag },
            kind: None,
            half_extents: [a, a, a / 2.0],
            pose0: Pose::at([base[0], base[1], zmin - a / 2.0]),
            mass_kg: 0.0,
            passive: true,
        });
    }
    out.extend(feet);
    out
}

/// The passive foundation strip under a wall body whose element stands on the base
/// (two nodes at the lowest level): as long as the wall body (its trimmed length), as
/// wide as 2·a and a deep, a = the wall body's thickness, top at the base level, turned
/// with the wall in plan. Named `Foundation:wall:<element>`.
fn wall_foot(b: &RigidBox, zmin: f64) -> Option<Body> {
    let base = b
        .nodes
        .iter()
        .filter(|n| (n[2] - zmin).abs() < 1e-9)
        .count();
    if base < 2 {
        return None;
    }
    let element = b.id.element_tag()?;
    // The wall's horizontal in-plane axis (local x of the generator's walls; else the
    // local axis with the smallest vertical component among x and y).
    let m = b.rotation.to_rotation_matrix().into_inner();
    let (ax, half_len) = if m[(2, 0)].abs() <= m[(2, 1)].abs() {
        (0, b.half_extents[0])
    } else {
        (1, b.half_extents[1])
    };
    let yaw = m[(1, ax)].atan2(m[(0, ax)]);
    let a = 2.0 * b.half_extents[2];
    let q = UnitQuaternion::from_axis_angle(&nalgebra::Vector3::z_axis(), yaw);
    Some(Body {
        id: BodyId::WallFoundation { element },
        kind: None,
        half_extents: [half_len, a, a / 2.0],
        pose0: Pose {
            position: [b.centre[0], b.centre[1], zmin - a / 2.0],
            orientation: [q.w, q.i, q.j, q.k],
        },
        mass_kg: 0.0,
        passive: true,
    })
}

/// A mapped box's pose at rest: its centre and its rotation (w, x, y, z).
fn pose_of(b: &RigidBox) -> Pose {
    let q = b.rotation.quaternion();
    Pose {
        position: b.centre,
        orientation: [q.w, q.i, q.j, q.k],
    }
}
