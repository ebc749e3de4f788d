//! Data mapping at the hand-off (paper §3.2): FE nodal state → rigid-body
//! poses and velocities.
//!
//! Inputs, per model node (slice indexed like `model.nodes`), a [`NodeState`]: the FE
//! displacement `u` (m) and rotation vector `theta` (rad), velocity `v` (m/s) and
//! rotational velocity `omega` (rad/s), all **relative to the ground** (the FE runs
//! uniform excitation in relative coordinates), plus the ground's [`GroundState`]
//! (translation only). Poses are absolute: x = X + u_ground + u, v_abs = v_ground + v;
//! rotations and rotational velocities are unchanged by a translating ground.
//!
//! **Line members** (beam-columns). Nodal triads R_k = exp(\[θ_k\]×) (Rodrigues): the
//! nodal rotation DOFs are taken as a *finite rotation vector*. This is exact for a
//! rotation imposed as one vector and the usual approximation for OpenSees's summed
//! rotational DOFs (their sum differs from the compound rotation at second order in the
//! increments). The deformed element frame (Crisfield's corotational frame, *Non-linear
//! finite element analysis of solids and structures* vol. 2 §17.2): x = chord
//! (x_j − x_i)/L; y = the mean of the end triads' local y axes (R_i y₀ + R_j y₀)/2 with
//! its x component removed, normalised (the roll is the mean of the end twists about
//! the chord); z = x × y. The body's rotation = that frame × the constant rotation of
//! the box relative to the element's undeformed frame; its centre = chord midpoint +
//! R·[`RigidBox::trim_offset_local`] (the trimmed box rides on the element).
//! Velocity of the box centre p: the node velocities interpolated linearly at p's
//! projection s on the chord, v = (1 − s)v_i + s v_j, plus ω × r, r = p − (x_i + sLx).
//! Angular velocity ω = x × (v_j − v_i)/L (chord rotation rate) + x·(ω_i + ω_j)/2 x
//! (twist rate; the nodal rotational velocities are taken as angular velocities, exact
//! for rigid motion and to first order otherwise).
//!
//! **Quads** (panels, shells). The frame of the four deformed nodes by the same rule as
//! [`super::geometry`] (normal from the diagonals, x along the mean of the opposite edges
//! projected on the plane), centre = node mean + R·trim offset. Velocity: the rigid
//! motion that best fits the four node velocities in least squares: v̄ = mean v_k and
//! ω solving [Σ(|r_k|² I − r_k r_kᵀ)] ω = Σ r_k × (v_k − v̄), r_k = x_k − x̄.
//!
//! All of the above are exact for a rigid motion of the node field: every body then
//! moves by that motion (tests `handoff_*`).
//!
//! The paper's own velocity is a secant through keyframes: [`secant_velocity`].

use super::error::{MappingError, Result};
use super::geometry::RigidBox;
use super::Mapping;
use crate::body::BodyId;
use crate::model::Model;
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

/// FE state of one node, relative to the ground (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NodeState {
    /// Displacement (m).
    pub u: [f64; 3],
    /// Rotation vector (rad).
    pub theta: [f64; 3],
    /// Velocity (m/s).
    pub v: [f64; 3],
    /// Rotational velocity (rad/s).
    pub omega: [f64; 3],
}

/// The ground's absolute translation and velocity.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct GroundState {
    /// Displacement (m).
    pub displacement: [f64; 3],
    /// Velocity (m/s).
    pub velocity: [f64; 3],
}

/// A body's absolute pose and velocity.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyState {
    /// Body identity (as in the mapping).
    pub id: BodyId,
    /// Box centre (m).
    pub centre: [f64; 3],
    /// Box orientation (local x, y, z → global).
    pub rotation: UnitQuaternion<f64>,
    /// Linear velocity of the centre (m/s).
    pub linear_velocity: [f64; 3],
    /// Angular velocity (rad/s, global components).
    pub angular_velocity: [f64; 3],
}

#[derive(Debug, Clone)]
enum Plan {
    Line {
        nodes: [usize; 2],
        /// The element's undeformed local y (global components).
        y0: Vector3<f64>,
    },
    Quad {
        nodes: [usize; 4],
    },
}

#[derive(Debug, Clone)]
struct BodyPlan {
    id: BodyId,
    plan: Plan,
    /// Box rotation relative to the element frame: q_box = q_frame · rel.
    rel: UnitQuaternion<f64>,
    /// Trim offset in the box axes (m).
    offset: Vector3<f64>,
}

/// The hand-off map of a model's rigid bodies (built once, applied per output step).
#[derive(Debug, Clone)]
pub struct Handoff {
    plans: Vec<BodyPlan>,
    /// Undeformed node positions (m), model order.
    x0: Vec<Vector3<f64>>,
}

fn v3(a: [f64; 3]) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

fn arr(v: Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// Deformed frame of a line element (module docs): columns x, y, z.
fn line_frame(
    xi: Vector3<f64>,
    xj: Vector3<f64>,
    yi: Vector3<f64>,
    yj: Vector3<f64>,
) -> Matrix3<f64> {
    let x = (xj - xi).normalize();
    let ym = (yi + yj) * 0.5;
    let y = (ym - x * ym.dot(&x)).normalize();
    let z = x.cross(&y);
    Matrix3::from_columns(&[x, y, z])
}

/// Frame of a quad's four nodes (as [`super::geometry::quad_box`]): columns x, y, z.
fn quad_frame(n: &[Vector3<f64>; 4]) -> Matrix3<f64> {
    let z = (n[2] - n[0]).cross(&(n[3] - n[1])).normalize();
    let ex = (n[1] - n[0]) + (n[2] - n[3]);
    let x = (ex - z * ex.dot(&z)).normalize();
    let y = z.cross(&x);
    Matrix3::from_columns(&[x, y, z])
}

fn quat(m: Matrix3<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m))
}

impl Handoff {
    /// Prepares the hand-off of the mapped bodies of `model` (the mapping from
    /// [`super::from_model()`] + [`super::map_to_boxes`]). Errors name the body whose element
    /// is missing or of the wrong kind.
    pub fn new(model: &Model, mapping: &Mapping) -> Result<Handoff> {
        let index: std::collections::BTreeMap<u32, usize> = model
            .nodes
            .iter()
            .enumerate()
            .map(|(i, n)| (n.tag, i))
            .collect();
        let elems: std::collections::BTreeMap<u32, &crate::model::Element> =
            model.elements.iter().map(|e| (e.tag, e)).collect();
        let x0: Vec<Vector3<f64>> = model.nodes.iter().map(|n| v3(n.xyz())).collect();
        let (node_map, transfs) = (model.node_map(), model.transformation_map());
        let mut plans = Vec::with_capacity(mapping.bodies.len());
        for b in &mapping.bodies {
            let tag = b.id.element_tag();
            let body_error = |message: String| MappingError::Body {
                body: b.id.clone(),
                message,
            };
            let e = tag.and_then(|t| elems.get(&t)).ok_or_else(|| {
                body_error(format!("no element {} in the model", b.id.element_field()))
            })?;
            let idx = |t: &u32| {
                index
                    .get(t)
                    .copied()
                    .ok_or_else(|| body_error(format!("unknown node {t}")))
            };
            let (plan, frame) = match e.nodes() {
                [i, j] => {
                    let axes = Model::local_axes_in(&node_map, &transfs, e).ok_or_else(|| {
                        body_error(format!("element {} has no local axes", e.tag))
                    })?;
                    let y0 = v3(axes[1]);
                    let nodes = [idx(i)?, idx(j)?];
                    let f = line_frame(x0[nodes[0]], x0[nodes[1]], y0, y0);
                    (Plan::Line { nodes, y0 }, f)
                }
                [a, bb, c, d] => {
                    let nodes = [idx(a)?, idx(bb)?, idx(c)?, idx(d)?];
                    let f = quad_frame(&nodes.map(|k| x0[k]));
                    (Plan::Quad { nodes }, f)
                }
                _ => {
                    return Err(body_error(format!(
                        "element {} has {} nodes",
                        e.tag,
                        e.nodes().len()
                    )))
                }
            };
            plans.push(BodyPlan {
                id: b.id.clone(),
                plan,
                rel: quat(frame).inverse() * b.rotation,
                offset: v3(RigidBox::trim_offset_local(b)),
            });
        }
        Ok(Handoff { plans, x0 })
    }

    /// Absolute pose and velocity of every body (mapping order) from the FE nodal state
    /// (`nodes[i]` for the model's i-th node) and the ground (module docs). Errors if the
    /// slice length differs from the node count or a member degenerates (zero chord).
    pub fn states(&self, nodes: &[NodeState], ground: &GroundState) -> Result<Vec<BodyState>> {
        if nodes.len() != self.x0.len() {
            return Err(MappingError::NodeCount {
                given: nodes.len(),
                nodes: self.x0.len(),
            });
        }
        let (ug, vg) = (v3(ground.displacement), v3(ground.velocity));
        let x = |k: usize| self.x0[k] + ug + v3(nodes[k].u);
        let v = |k: usize| vg + v3(nodes[k].v);
        let mut out = Vec::with_capacity(self.plans.len());
        for p in &self.plans {
            let (rotation, centre, lin, ang) = match p.plan {
                Plan::Line { nodes: [i, j], y0 } => {
                    let (xi, xj) = (x(i), x(j));
                    let len = (xj - xi).norm();
                    if !(len > 0.0) {
                        return Err(MappingError::Degenerate {
                            body: p.id.clone(),
                            what: "its element's chord has zero length",
                        });
                    }
                    let ri = Rotation3::new(v3(nodes[i].theta));
                    let rj = Rotation3::new(v3(nodes[j].theta));
                    let f = line_frame(xi, xj, ri * y0, rj * y0);
                    let ax: Vector3<f64> = f.column(0).into();
                    let rotation = quat(f) * p.rel;
                    let centre = (xi + xj) * 0.5 + rotation * p.offset;
                    let omega = ax.cross(&(v(j) - v(i))) / len
                        + ax * (ax.dot(&(v3(nodes[i].omega) + v3(nodes[j].omega))) * 0.5);
                    let s = (centre - xi).dot(&ax) / len;
                    let r = centre - (xi + ax * (s * len));
                    let lin = v(i) * (1.0 - s) + v(j) * s + omega.cross(&r);
                    (rotation, centre, lin, omega)
                }
                Plan::Quad { nodes: q } => {
                    let xs = q.map(x);
                    let vs = q.map(v);
                    let xm = (xs[0] + xs[1] + xs[2] + xs[3]) * 0.25;
                    let vm = (vs[0] + vs[1] + vs[2] + vs[3]) * 0.25;
                    let rotation = quat(quad_frame(&xs)) * p.rel;
                    let centre = xm + rotation * p.offset;
                    let mut a = Matrix3::zeros();
                    let mut b = Vector3::zeros();
                    for k in 0..4 {
                        let r = xs[k] - xm;
                        a += Matrix3::identity() * r.norm_squared() - r * r.transpose();
                        b += r.cross(&(vs[k] - vm));
                    }
                    let omega = a.lu().solve(&b).ok_or_else(|| MappingError::Degenerate {
                        body: p.id.clone(),
                        what: "degenerate quad (collinear nodes)",
                    })?;
                    let lin = vm + omega.cross(&(centre - xm));
                    (rotation, centre, lin, omega)
                }
            };
            out.push(BodyState {
                id: p.id.clone(),
                centre: arr(centre),
                rotation,
                linear_velocity: arr(lin),
                angular_velocity: arr(ang),
            });
        }
        Ok(out)
    }
}

/// The translations of node states, for [`crate::collapse::CollapseMonitor::observe`].
pub fn translations(nodes: &[NodeState]) -> Vec<[f64; 3]> {
    nodes.iter().map(|n| n.u).collect()
}

/// The paper's secant velocity (`--velocity secant`): through the last `n` + 1 keyframes
/// `poses` (oldest first, equally spaced by `dt` s), v = (x_last − x_first)/(n·dt) and
/// ω = log(q_last · q_first⁻¹)/(n·dt) (the rotation vector of the relative rotation
/// over the interval, spatial frame). Returns (linear m/s, angular rad/s).
pub fn secant_velocity(
    poses: &[([f64; 3], UnitQuaternion<f64>)],
    dt: f64,
    n: usize,
) -> Result<([f64; 3], [f64; 3])> {
    if n == 0 || poses.len() < n + 1 {
        return Err(MappingError::Secant(format!(
            "secant velocity over {n} intervals needs {} keyframes, got {}",
            n + 1,
            poses.len()
        )));
    }
    if !(dt > 0.0 && dt.is_finite()) {
        return Err(MappingError::Secant(format!(
            "keyframe interval must be > 0 s, got {dt}"
        )));
    }
    let (x1, q1) = poses[poses.len() - 1];
    let (x0, q0) = poses[poses.len() - 1 - n];
    let span = n as f64 * dt;
    let lin = (v3(x1) - v3(x0)) / span;
    let ang = (q1 * q0.inverse()).scaled_axis() / span;
    Ok((arr(lin), arr(ang)))
}
