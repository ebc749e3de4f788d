//! FE element → box (paper §3.1, Module 1).
//!
//! **Line elements.** The box has the element's length along its local x (node i → j) and
//! the section's width and depth along local y and z. Orientation by the paper's rule:
//! l1 = node_j − node_i (for a line element its longest edge), l2 its projection on XOY;
//! α = angle from X to l2 (atan2(l1y, l1x)), β = angle between l2 and l1
//! (atan2(l1z, |l2|), positive when l1 points up). The box is rotated by α about global Z,
//! then by −β about the rotated Y′ (Y′ rotation by +β would tilt x̂ downward: R_y(θ)x̂ =
//! (cos θ, 0, −sin θ)), so that its x axis points along the member. The paper leaves out
//! the section's roll about the member axis; we add it: a rotation γ about the box's own
//! x so that its y axis equals the OpenSees local y = (vecxz × x)/|vecxz × x|
//! (z = x × y). R = R_z(α)·R_y(−β)·R_x(γ).
//! Vertical members (|l2| ≤ 1e-9·|l1|): α is undefined and taken as 0, β = ±90°; γ then
//! carries the whole in-plane orientation.
//!
//! **Quads.** Centre = mean of the four nodes; normal (local z) = (n2 − n0) × (n3 − n1)
//! normalised (the diagonals; well defined for warped quads); local x along the mean of the
//! two opposite edges (n1 − n0) + (n2 − n3), projected on the plane; y = z × x. Sizes: the
//! mean projected lengths of those edge pairs, a = ((n1−n0)+(n2−n3))·x/2 and
//! b = ((n3−n0)+(n2−n1))·y/2; exact for rectangles, and the same area as the quad for any
//! parallelogram or trapezoid with its parallel sides along x (a = mean base, b = height).
//! For a trapezoid the centre (node mean) differs slightly from the area centroid.

use super::error::{MappingError, Result};
use super::input::{LineMember, Quad};
use crate::body::{BodyId, Role};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

/// One rigid body: an oriented box.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidBox {
    /// Identity: named `Type:material:element`, e.g. `Beam:1:234` (paper §3.1); its
    /// rigid-body group is its material.
    pub id: BodyId,
    /// Geometric role, for overlap removal and mass mapping.
    pub kind: Role,
    /// Box centre (m), after trimming.
    pub centre: [f64; 3],
    /// Orientation: box local axes (x = member axis / quad x, y, z) in global coordinates.
    pub rotation: UnitQuaternion<f64>,
    /// Half sizes along local x, y, z (m), after trimming.
    pub half_extents: [f64; 3],
    /// Centre before trimming (m): the element's own midpoint / node mean.
    pub untrimmed_centre: [f64; 3],
    /// Half sizes before trimming (m).
    pub untrimmed_half_extents: [f64; 3],
    /// FE nodes of the element (m), for mass mapping.
    pub nodes: Vec<[f64; 3]>,
    /// Mass (kg): the element's self-weight plus its share of nodal masses ([`super::mass`]).
    pub mass_kg: f64,
}

impl RigidBox {
    /// Unit quaternion (w, x, y, z).
    pub fn quaternion_wxyz(&self) -> [f64; 4] {
        let q = self.rotation.quaternion();
        [q.w, q.i, q.j, q.k]
    }

    /// Rotation matrix; its columns are the local x, y, z axes in global coordinates.
    pub fn matrix(&self) -> [[f64; 3]; 3] {
        let m = self.rotation.to_rotation_matrix().into_inner();
        [
            [m[(0, 0)], m[(0, 1)], m[(0, 2)]],
            [m[(1, 0)], m[(1, 1)], m[(1, 2)]],
            [m[(2, 0)], m[(2, 1)], m[(2, 2)]],
        ]
    }

    /// Offset of the (trimmed) box centre from the element's own centre, in the box's
    /// local axes (m). Constant while the element moves rigidly, so a later stage can place
    /// the box from the element's deformed end nodes: centre = element centre + R·offset.
    pub fn trim_offset_local(&self) -> [f64; 3] {
        let d = Vector3::from(self.centre) - Vector3::from(self.untrimmed_centre);
        let l = self.rotation.inverse() * d;
        [l.x, l.y, l.z]
    }

    /// Box volume (m³).
    pub fn volume_m3(&self) -> f64 {
        8.0 * self.half_extents.iter().product::<f64>()
    }

    /// Principal moments of inertia about the centre along local x, y, z (kg·m²) of a
    /// uniform solid box of this mass: I_x = m(b² + c²)/3 with half sizes (a, b, c).
    pub fn principal_inertia_kgm2(&self) -> [f64; 3] {
        let [a, b, c] = self.half_extents.map(|h| h * h);
        let m = self.mass_kg / 3.0;
        [m * (b + c), m * (a + c), m * (a + b)]
    }
}

fn v3(a: [f64; 3]) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

fn finite(a: &[f64]) -> bool {
    a.iter().all(|x| x.is_finite())
}

/// The paper's angles (α, β) of a member axis `l1` (rad): α from X to the XOY projection,
/// β its elevation; α = 0 for a vertical member.
pub fn paper_angles(l1: [f64; 3]) -> (f64, f64) {
    let l2 = l1[0].hypot(l1[1]);
    let len = l2.hypot(l1[2]);
    let alpha = if l2 <= 1e-9 * len {
        0.0
    } else {
        l1[1].atan2(l1[0])
    };
    (alpha, l1[2].atan2(l2))
}

/// The OpenSees local frame of a line element: x = axis, y = vecxz × x (normalised),
/// z = x × y. Errors if the axis has zero length or vecxz is parallel to it.
pub fn opensees_frame(node_i: [f64; 3], node_j: [f64; 3], vecxz: [f64; 3]) -> Result<Matrix3<f64>> {
    let d = v3(node_j) - v3(node_i);
    let len = d.norm();
    if !(len > 0.0) {
        return Err(MappingError::Frame("zero-length element".into()));
    }
    let x = d / len;
    let y = v3(vecxz).cross(&x);
    if !(y.norm() > 1e-9 * v3(vecxz).norm()) {
        return Err(MappingError::Frame(format!(
            "vecxz {vecxz:?} is parallel to the element axis"
        )));
    }
    let y = y.normalize();
    let z = x.cross(&y);
    Ok(Matrix3::from_columns(&[x, y, z]))
}

/// Orientation of a line element by the paper's rule plus the vecxz roll (module docs):
/// R = R_z(α)·R_y(−β)·R_x(γ).
pub fn paper_rotation(
    node_i: [f64; 3],
    node_j: [f64; 3],
    vecxz: [f64; 3],
) -> Result<UnitQuaternion<f64>> {
    let frame = opensees_frame(node_i, node_j, vecxz)?;
    let l1 = [
        node_j[0] - node_i[0],
        node_j[1] - node_i[1],
        node_j[2] - node_i[2],
    ];
    let (alpha, beta) = paper_angles(l1);
    let r0 = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), alpha)
        * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -beta);
    // Roll: bring the box's y0 = R0·ŷ onto the OpenSees y about the common x axis.
    let y0 = r0 * Vector3::y();
    let z0 = r0 * Vector3::z();
    let y = frame.column(1).into_owned();
    let gamma = y.dot(&z0).atan2(y.dot(&y0));
    Ok(r0 * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), gamma))
}

fn kind_of_axis(axis_z: f64, vertical: Role, other: Role) -> Role {
    if axis_z.abs() >= std::f64::consts::FRAC_1_SQRT_2 {
        vertical
    } else {
        other
    }
}

/// The untrimmed box of a line element, carrying the element's own mass (nodal masses
/// are added by [`super::mass`]).
pub fn member_box(m: &LineMember) -> Result<RigidBox> {
    let ctx = |msg: String| MappingError::typed(m.element, &m.body_type, msg);
    if !finite(&m.node_i) || !finite(&m.node_j) || !finite(&m.vecxz) {
        return Err(ctx("node coordinates and vecxz must be finite".into()));
    }
    if !(m.width_m > 0.0 && m.depth_m > 0.0 && m.width_m.is_finite() && m.depth_m.is_finite()) {
        return Err(ctx(format!(
            "section width and depth must be positive, got {} × {} m",
            m.width_m, m.depth_m
        )));
    }
    if !(m.mass_kg >= 0.0 && m.mass_kg.is_finite()) {
        return Err(ctx(format!("mass must be ≥ 0 kg, got {}", m.mass_kg)));
    }
    let rotation = paper_rotation(m.node_i, m.node_j, m.vecxz).map_err(|e| ctx(e.to_string()))?;
    let len = (v3(m.node_j) - v3(m.node_i)).norm();
    let c = (v3(m.node_i) + v3(m.node_j)) * 0.5;
    let axis_z = (m.node_j[2] - m.node_i[2]) / len;
    let half = [0.5 * len, 0.5 * m.width_m, 0.5 * m.depth_m];
    Ok(RigidBox {
        id: BodyId::element(m.body_type.clone(), m.material.clone(), m.element),
        kind: kind_of_axis(axis_z, Role::Column, Role::Beam),
        centre: [c.x, c.y, c.z],
        rotation,
        half_extents: half,
        untrimmed_centre: [c.x, c.y, c.z],
        untrimmed_half_extents: half,
        nodes: vec![m.node_i, m.node_j],
        mass_kg: m.mass_kg,
    })
}

/// The untrimmed box of a quad (module docs), carrying the element's own mass.
pub fn quad_box(q: &Quad) -> Result<RigidBox> {
    let ctx = |msg: String| MappingError::typed(q.element, &q.body_type, msg);
    if !q.nodes.iter().all(|n| finite(n)) {
        return Err(ctx("node coordinates must be finite".into()));
    }
    if !(q.thickness_m > 0.0 && q.thickness_m.is_finite()) {
        return Err(ctx(format!(
            "thickness must be positive, got {} m",
            q.thickness_m
        )));
    }
    if !(q.mass_kg >= 0.0 && q.mass_kg.is_finite()) {
        return Err(ctx(format!("mass must be ≥ 0 kg, got {}", q.mass_kg)));
    }
    let n = q.nodes.map(v3);
    let c = (n[0] + n[1] + n[2] + n[3]) * 0.25;
    let normal = (n[2] - n[0]).cross(&(n[3] - n[1]));
    let scale = (n[2] - n[0]).norm() * (n[3] - n[1]).norm();
    if !(normal.norm() > 1e-9 * scale) || scale == 0.0 {
        return Err(ctx("degenerate quadrilateral (zero area)".into()));
    }
    let z = normal.normalize();
    for i in 0..4 {
        let turn = (n[(i + 1) % 4] - n[i]).cross(&(n[(i + 2) % 4] - n[(i + 1) % 4]));
        if !(turn.dot(&z) > 0.0) {
            return Err(ctx(format!(
                "nodes are not in cyclic order around a convex quad (corner {})",
                (i + 1) % 4
            )));
        }
    }
    let ex = (n[1] - n[0]) + (n[2] - n[3]);
    let ex = ex - z * ex.dot(&z);
    if !(ex.norm() > 0.0) {
        return Err(ctx(
            "degenerate quadrilateral (no in-plane edge direction)".into()
        ));
    }
    let x = ex.normalize();
    let y = z.cross(&x);
    let a = ((n[1] - n[0]) + (n[2] - n[3])).dot(&x) * 0.5;
    let b = ((n[3] - n[0]) + (n[2] - n[1])).dot(&y) * 0.5;
    if !(a > 0.0 && b > 0.0) {
        return Err(ctx(format!(
            "nodes are not in cyclic order around the quad (mean edge sizes {a} × {b} m)"
        )));
    }
    let rot = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[x, y, z]));
    let half = [0.5 * a, 0.5 * b, 0.5 * q.thickness_m];
    Ok(RigidBox {
        id: BodyId::element(q.body_type.clone(), q.material.clone(), q.element),
        kind: kind_of_axis(z.z, Role::Slab, Role::Wall),
        centre: [c.x, c.y, c.z],
        rotation: UnitQuaternion::from_rotation_matrix(&rot),
        half_extents: half,
        untrimmed_centre: [c.x, c.y, c.z],
        untrimmed_half_extents: half,
        nodes: q.nodes.to_vec(),
        mass_kg: q.mass_kg,
    })
}
