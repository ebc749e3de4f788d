//! The rows of a CT 22 connection as plain data: the six `btGeneric6DofConstraint`s and the
//! plastic `btGeneric6DofSpring2Constraint` (the table of [`super`]), their frames carried
//! from the undeformed bodies to the start poses ("Frames"), their breaking impulses from
//! the connection's capacities (force × correction × Δt) and the plastic spring's stiffness
//! per axis ("Spring stiffness").
use super::{AngularSpring, ConnectionForces, RuinSettings};
use crate::ruin::search::Contact;
use crate::ruin::BodyGeom;
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};
use serde::Serialize;

/// Bullet's "free" limit pair (lower > upper), as Blender passes for unused axes.
pub(crate) const FREE: (f64, f64) = (0.0, -1.0);
/// BCB's "unlimited" linear bound for the one-sided compression/tension rows, m.
pub const BCB_UNLIMITED: f64 = 99999.0;

/// Which Bullet constraint class a spec stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ConstraintClass {
    /// `btGeneric6DofConstraint(A, B, frame_a, frame_b, useLinearReferenceFrameA = true)`.
    Generic6Dof,
    /// `btGeneric6DofSpring2Constraint(A, B, frame_a, frame_b)` (rotation order XYZ).
    Spring2,
}

/// What a constraint of a CT 22 connection models.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ConstraintRole {
    /// Compression along the normal.
    Compression,
    /// Tension along the normal.
    Tension,
    /// Shear along h.
    ShearH,
    /// Shear along w.
    ShearW,
    /// Bending about the w-axis (section depth h) plus torsion.
    BendH,
    /// Bending about the h-axis (section depth w) plus torsion.
    BendW,
    /// The plastic 6-DOF spring (2nd mode).
    PlasticSpring,
}

impl ConstraintRole {
    /// Its name in the outputs (`connections.csv`): `compression`, `tension`, `shear_h`,
    /// `shear_w`, `bend_h`, `bend_w`, `spring`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Compression => "compression",
            Self::Tension => "tension",
            Self::ShearH => "shear_h",
            Self::ShearW => "shear_w",
            Self::BendH => "bend_h",
            Self::BendW => "bend_w",
            Self::PlasticSpring => "spring",
        }
    }
}

/// One Bullet constraint as plain data. Axis index i: 0–2 linear X, Y, Z, 3–5 angular X,
/// Y, Z of the constraint frame. `lower[i] > upper[i]` means free.
#[derive(Debug, Clone, PartialEq)]
pub struct ConstraintSpec {
    /// Its role in the connection.
    pub role: ConstraintRole,
    /// The Bullet class.
    pub kind: ConstraintClass,
    /// Constraint frame in body A's local frame.
    pub frame_a: Isometry3<f64>,
    /// Constraint frame in body B's local frame.
    pub frame_b: Isometry3<f64>,
    /// Lower limits (m, rad).
    pub lower: [f64; 6],
    /// Upper limits (m, rad).
    pub upper: [f64; 6],
    /// Spring enabled per axis (Spring2 only).
    pub spring: [bool; 6],
    /// Spring stiffness per axis, N/m (linear), N·m/rad (angular).
    pub stiffness: [f64; 6],
    /// Spring damping per axis (btGeneric6DofSpring2 damping).
    pub damping: [f64; 6],
    /// `setBreakingImpulseThreshold`, N·s (linear rows) or N·m·s (bending rows).
    pub breaking_impulse: f64,
    /// Enabled at creation.
    pub enabled: bool,
    /// The row's strength is zero (an FE-derived residual capacity gone in this sense):
    /// it never carries load, so no state enables it (threshold kept at the smallest
    /// positive value Bullet accepts).
    pub no_strength: bool,
}

impl ConstraintSpec {
    /// Whether axis `i` is free (lower > upper).
    pub fn is_free(&self, i: usize) -> bool {
        self.lower[i] > self.upper[i]
    }
}
/// BCB's constraint rotation for a snapped normal: local X onto `sign·e[axis]`, as
/// Blender's `to_track_quat('X','Z')` gives it (docs/bcb.md §2.1; −Y worked out the same way):
/// +X → (X, Y, Z); −X → (−X, −Y, Z); +Y → (Y, −X, Z); −Y → (−Y, X, Z);
/// +Z → (Z, Y, −X); −Z → (−Z, Y, X) (columns = images of local X, Y, Z).
pub(crate) fn bcb_normal_rotation(axis: usize, sign: f64) -> UnitQuaternion<f64> {
    let e = |i: usize, s: f64| {
        let mut v = Vector3::zeros();
        v[i] = s;
        v
    };
    let pos = sign >= 0.0;
    let (x, y, z) = match (axis, pos) {
        (0, true) => (e(0, 1.0), e(1, 1.0), e(2, 1.0)),
        (0, false) => (e(0, -1.0), e(1, -1.0), e(2, 1.0)),
        (1, true) => (e(1, 1.0), e(0, -1.0), e(2, 1.0)),
        (1, false) => (e(1, -1.0), e(0, 1.0), e(2, 1.0)),
        (_, true) => (e(2, 1.0), e(1, 1.0), e(0, -1.0)),
        (_, false) => (e(2, -1.0), e(1, 1.0), e(0, 1.0)),
    };
    let m = Matrix3::from_columns(&[x, y, z]);
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m))
}
/// Carries a world frame `p0` defined on the undeformed bodies to the start poses and
/// returns (frame in A, frame in B) — module docs, "Frames".
pub(crate) fn frames_at_start(
    p0: &Isometry3<f64>,
    a0: &Isometry3<f64>,
    b0: &Isometry3<f64>,
    a_start: &Isometry3<f64>,
    b_start: &Isometry3<f64>,
) -> (Isometry3<f64>, Isometry3<f64>) {
    let pa = a_start * (a0.inverse() * p0);
    let pb = b_start * (b0.inverse() * p0);
    let pos = (pa.translation.vector + pb.translation.vector) * 0.5;
    let rot = pa.rotation.slerp(&pb.rotation, 0.5);
    let p = Isometry3::from_parts(Translation3::from(pos), rot);
    (a_start.inverse() * p, b_start.inverse() * p)
}

/// The seven constraint specs of a CT 22 connection (six if there is no plastic value).
pub(super) fn constraint_specs(
    c: &Contact,
    ba: &BodyGeom,
    bb: &BodyGeom,
    a_start: &Isometry3<f64>,
    b_start: &Isometry3<f64>,
    f: &ConnectionForces,
    s: &RuinSettings,
) -> Vec<ConstraintSpec> {
    let rot_n = bcb_normal_rotation(c.normal_axis, c.normal_sign);
    let pivot = Translation3::new(c.pivot[0], c.pivot[1], c.pivot[2]);
    let p0 = Isometry3::from_parts(pivot, rot_n);
    let (a0, b0) = (ba.pose(), bb.pose());
    let (fa, fb) = frames_at_start(&p0, &a0, &b0, a_start, b_start);

    // Local axis (1 = Y, 2 = Z) of the constraint frame parallel to h, and the other (w).
    let m = rot_n.to_rotation_matrix();
    let h_local = if m.matrix()[(c.h_axis, 1)].abs() >= m.matrix()[(c.h_axis, 2)].abs() {
        1
    } else {
        2
    };
    let w_local = 3 - h_local;

    let dt = s.substep();
    let lin = |force: f64| force * s.linear_correction * dt;
    let ang = |moment: f64| moment * s.bending_correction * dt;
    // A row whose strength is zero (an FE-derived residual capacity that is gone in
    // that sense only, e.g. shear friction across a section pulled apart, or a residual
    // moment about one axis; docs/handoff.md §3) can carry nothing: it starts broken
    // (disabled), like a row Bullet broke in the first substep. Bullet takes only a
    // positive threshold, so the disabled row keeps the smallest one.
    let generic = |role, locks: &[(usize, f64, f64)], impulse: f64| {
        let no_strength = impulse == 0.0;
        let impulse = if no_strength {
            f64::MIN_POSITIVE
        } else {
            impulse
        };
        let mut lower = [FREE.0; 6];
        let mut upper = [FREE.1; 6];
        for &(i, lo, hi) in locks {
            lower[i] = lo;
            upper[i] = hi;
        }
        ConstraintSpec {
            role,
            kind: ConstraintClass::Generic6Dof,
            frame_a: fa,
            frame_b: fb,
            lower,
            upper,
            spring: [false; 6],
            stiffness: [0.0; 6],
            damping: [0.0; 6],
            breaking_impulse: impulse,
            enabled: !no_strength,
            no_strength,
        }
    };
    // One two-way row when both senses have a strength (Bullet's threshold the smaller of
    // the two at the start; the stage sets it per substep and checks the sense; the tension
    // constraint stays without locked axes, no solver rows); BCB's two one-way rows
    // otherwise (a sense without strength starts broken, the other one-way row is left).
    let two_way = s.axial_rows == crate::ruin::axial::AxialRows::TwoWay
        && f.compression_n > 0.0
        && f.tension_n > 0.0;
    let (compression, tension) = if two_way {
        (
            generic(
                ConstraintRole::Compression,
                &[(0, 0.0, 0.0)],
                lin(f.compression_n.min(f.tension_n)),
            ),
            generic(ConstraintRole::Tension, &[], lin(f.tension_n)),
        )
    } else {
        (
            generic(
                ConstraintRole::Compression,
                &[(0, 0.0, BCB_UNLIMITED)],
                lin(f.compression_n),
            ),
            generic(
                ConstraintRole::Tension,
                &[(0, -BCB_UNLIMITED, 0.0)],
                lin(f.tension_n),
            ),
        )
    };
    let mut v = vec![
        compression,
        tension,
        generic(
            ConstraintRole::ShearH,
            &[(h_local, 0.0, 0.0)],
            lin(f.shear_h_n),
        ),
        generic(
            ConstraintRole::ShearW,
            &[(w_local, 0.0, 0.0)],
            lin(f.shear_w_n),
        ),
        generic(
            ConstraintRole::BendH,
            &[(3, 0.0, 0.0), (3 + w_local, 0.0, 0.0)],
            ang(f.bend_h_nm),
        ),
        generic(
            ConstraintRole::BendW,
            &[(3, 0.0, 0.0), (3 + h_local, 0.0, 0.0)],
            ang(f.bend_w_nm),
        ),
    ];
    if let (Some(p), Some(k)) = (f.plastic_n, f.spring_stiffness) {
        // World-aligned spring frame at the pivot (BCB never applies rotN to it).
        let p0s = Isometry3::from_parts(pivot, UnitQuaternion::identity());
        let (fsa, fsb) = frames_at_start(&p0s, &a0, &b0, a_start, b_start);
        v.push(ConstraintSpec {
            role: ConstraintRole::PlasticSpring,
            kind: ConstraintClass::Spring2,
            frame_a: fsa,
            frame_b: fsb,
            lower: [FREE.0; 6],
            upper: [FREE.1; 6],
            spring: [true; 6],
            stiffness: spring_stiffness_axes(k, c, s.angular_spring),
            damping: [s.spring_damping; 6],
            // A zero plastic strength: the spring breaks as soon as it is switched on.
            breaking_impulse: (p * s.spring_correction * dt).max(f64::MIN_POSITIVE),
            enabled: false,
            no_strength: false,
        });
    }
    v
}

/// The plastic spring's stiffness on its six world-aligned axes (0–2 N/m, 3–5 N·m/rad)
/// from the linear k (see [`AngularSpring`]). The spring frame is world-aligned in the
/// undeformed configuration, so its axis i is the contact's normal, h or w axis.
pub(crate) fn spring_stiffness_axes(k: f64, c: &Contact, rule: AngularSpring) -> [f64; 6] {
    let mut out = [k; 6];
    if rule == AngularSpring::Lever {
        for i in 0..3 {
            let r2 = if i == c.normal_axis {
                (c.h * c.h + c.w * c.w) / 4.0
            } else if i == c.h_axis {
                c.w * c.w / 4.0
            } else {
                c.h * c.h / 4.0
            };
            out[3 + i] = k * r2;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A column-on-column contact (normal Z, h along X = 0.1 m, w along Y = 0.2 m) with
    /// k = 1000 N/m: Lever gives k·(w/2)² = 10 N·m/rad about X (the h axis), k·(h/2)² = 2.5
    /// about Y (the w axis), k·(h² + w²)/4 = 12.5 about Z (torsion); BCB gives 1000 on all.
    #[test]
    fn lever_angular_spring_by_hand() {
        let c = Contact {
            a: 0,
            b: 1,
            pivot: [0.0; 3],
            normal_axis: 2,
            normal_sign: 1.0,
            h_axis: 0,
            w_axis: 1,
            h: 0.1,
            w: 0.2,
            normal_overlap: 0.0,
            area: 0.02,
            centre_distance: 0.5,
        };
        let k = spring_stiffness_axes(1000.0, &c, AngularSpring::Lever);
        let want = [1000.0, 1000.0, 1000.0, 10.0, 2.5, 12.5];
        for i in 0..6 {
            assert!(
                (k[i] - want[i]).abs() < 1e-12,
                "axis {i}: {} vs {}",
                k[i],
                want[i]
            );
        }
        assert_eq!(
            spring_stiffness_axes(1000.0, &c, AngularSpring::Bcb),
            [1000.0; 6]
        );
    }
    #[test]
    fn normal_rotation_maps_x_onto_normal_and_is_proper() {
        for axis in 0..3 {
            for sign in [1.0, -1.0] {
                let q = bcb_normal_rotation(axis, sign);
                let x = q * Vector3::x();
                let mut n = Vector3::zeros();
                n[axis] = sign;
                assert!((x - n).norm() < 1e-12, "axis {axis} sign {sign}");
                let m = q.to_rotation_matrix();
                assert!((m.matrix().determinant() - 1.0).abs() < 1e-12);
            }
        }
        // +Z: local Z → −X (Blender's to_track_quat('X','Z')).
        let q = bcb_normal_rotation(2, 1.0);
        assert!((q * Vector3::z() - Vector3::new(-1.0, 0.0, 0.0)).norm() < 1e-12);
    }

    #[test]
    fn frames_coincide_at_start() {
        let p0 = Isometry3::new(Vector3::new(0.5, 0.0, 1.0), Vector3::new(0.0, 0.3, 0.0));
        let a0 = Isometry3::new(Vector3::new(0.0, 0.0, 0.5), Vector3::zeros());
        let b0 = Isometry3::new(Vector3::new(0.5, 0.0, 1.5), Vector3::zeros());
        let a1 = Isometry3::new(Vector3::new(0.1, 0.0, 0.5), Vector3::new(0.0, 0.05, 0.0));
        let b1 = Isometry3::new(Vector3::new(0.7, 0.02, 1.45), Vector3::new(0.01, 0.08, 0.0));
        let (fa, fb) = frames_at_start(&p0, &a0, &b0, &a1, &b1);
        let wa = a1 * fa;
        let wb = b1 * fb;
        assert!((wa.translation.vector - wb.translation.vector).norm() < 1e-12);
        assert!(wa.rotation.angle_to(&wb.rotation) < 1e-12);
        // Undeformed start poses give BCB's frames A⁻¹·P exactly.
        let (fa0, fb0) = frames_at_start(&p0, &a0, &b0, &a0, &b0);
        let ea = a0.inverse() * p0;
        let eb = b0.inverse() * p0;
        assert!((fa0.translation.vector - ea.translation.vector).norm() < 1e-12);
        assert!((fb0.translation.vector - eb.translation.vector).norm() < 1e-12);
        assert!(fa0.rotation.angle_to(&ea.rotation) < 1e-12);
    }
}
