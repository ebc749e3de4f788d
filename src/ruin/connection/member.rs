//! FE-derived capacities of the bodies (docs/handoff.md §2.3, §2.6): what a member's end
//! section can still carry, mapped onto a contact's axes, and what limits a body's
//! connections (its group, its member ends, or nothing for an elastic panel).
use crate::ruin::search::Contact;

/// FE-derived strengths of one member end (from `fe::capacity`, plain
/// numbers): what the section at that end can still carry. Local axes as the member's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EndStrength {
    /// Compressive capacity along the member axis, N.
    pub compression_n: f64,
    /// Tensile capacity along the member axis, N.
    pub tension_n: f64,
    /// Shear capacity along local y and local z, N.
    pub shear_n: [f64; 2],
    /// Moment capacity about local z and about local y, N·m.
    pub moment_nm: [f64; 2],
    /// Remaining rotation capacity of the end, rad (`None`: BCB's tolerance stays).
    pub rotation_left: Option<f64>,
    /// The end has lost its load path at the start (the FE's rule, `fe::capacity`): every
    /// connection at this end starts broken.
    pub lost: bool,
}

/// FE-derived strengths of one rigid body (a whole member): its undeformed local axes and
/// its two ends. [`super::build_connections_with`] uses the end nearer to the contact's pivot.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyStrength {
    /// Local axes [x (member axis), y, z], unit, world components, undeformed.
    pub axes: [[f64; 3]; 3],
    /// (undeformed position of the end node, m; its strengths), end i then end j.
    pub ends: [([f64; 3], EndStrength); 2],
}

impl BodyStrength {
    /// The end nearer to `p` (undeformed world point).
    pub fn end_near(&self, p: [f64; 3]) -> &EndStrength {
        let d = |q: [f64; 3]| (0..3).map(|k| (q[k] - p[k]).powi(2)).sum::<f64>();
        if d(self.ends[0].0) <= d(self.ends[1].0) {
            &self.ends[0].1
        } else {
            &self.ends[1].1
        }
    }

    /// Whether the contact cuts this member's section: its normal runs along the member
    /// axis (an end face). A contact on the member's side (a beam end against a column,
    /// a slab on a beam) does not cut the member, so the member does not limit it.
    pub fn cut_by(&self, c: &Contact) -> bool {
        self.local_axis(c.normal_axis) == 0
    }

    /// Which local axis (0 = x, 1 = y, 2 = z) is closest to the world axis `world`.
    fn local_axis(&self, world: usize) -> usize {
        (0..3)
            .max_by(|&i, &j| {
                self.axes[i][world]
                    .abs()
                    .total_cmp(&self.axes[j][world].abs())
                    .then(j.cmp(&i))
            })
            .unwrap_or(0)
    }

    /// The connection forces this body's end can carry for contact `c` (module docs of
    /// [`super::build_connections_with`]): [compression, tension, shear-h, shear-w, bend-h,
    /// bend-w], N and N·m.
    pub fn forces_for(&self, c: &Contact) -> [f64; 6] {
        let e = self.end_near(c.pivot);
        // A force along world axis `w`: axial along the member, else the shear capacity
        // in that local direction.
        let force = |w: usize, axial: f64| match self.local_axis(w) {
            0 => axial,
            1 => e.shear_n[0],
            _ => e.shear_n[1],
        };
        // A moment about world axis `w`: about the member axis (torsion) the weaker
        // bending capacity stands in; about local y → My, about local z → Mz.
        let moment = |w: usize| match self.local_axis(w) {
            0 => e.moment_nm[0].min(e.moment_nm[1]),
            1 => e.moment_nm[1],
            _ => e.moment_nm[0],
        };
        let n = c.normal_axis;
        let (sh, sw) = (
            force(c.h_axis, e.compression_n),
            force(c.w_axis, e.compression_n),
        );
        [
            force(n, e.compression_n),
            force(n, e.tension_n),
            sh.min(sw),
            sh.max(sw),
            moment(c.w_axis).min(moment(c.h_axis)),
            moment(c.w_axis).max(moment(c.h_axis)),
        ]
    }
}

/// What limits the connections of one body when the strengths are FE-derived
/// ([`super::build_connections_with`]; docs/handoff.md §2.3, §2.6).
#[derive(Debug, Clone, PartialEq)]
pub enum BodyCapacity {
    /// Its group's strength (BCB's Formula Assistant, or ACI per area for walls): bodies
    /// the FE gives no member-end capacities for, and foundation blocks.
    Group,
    /// A beam-column member: its fibre sections' capacities where a contact cuts it.
    Member(Box<BodyStrength>),
    /// A part the FE models as elastic (slab panels: in the FE lumped mass on elastic
    /// strips, or nothing): it never limits a connection. A connection that nothing
    /// limits (two panels, a panel on a member's side) is unbreakable and has no
    /// tolerances: the FE building's slab does not fail.
    Elastic,
}

impl BodyCapacity {
    /// The member strengths, if this is a member.
    pub fn member(&self) -> Option<&BodyStrength> {
        match self {
            BodyCapacity::Member(s) => Some(s),
            _ => None,
        }
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// A member end with C 300 N, T 50 N, shears 40 / 45 N, moments 2 / 3 N·m and 0.05 rad
    /// of rotation left.
    pub(in crate::ruin::connection) fn test_end() -> EndStrength {
        EndStrength {
            compression_n: 300.0,
            tension_n: 50.0,
            shear_n: [40.0, 45.0],
            moment_nm: [2.0, 3.0],
            rotation_left: Some(0.05),
            lost: false,
        }
    }

    /// The FE-derived mapping by hand: a vertical column (local x = Z, y = X, z = Y)
    /// cut by a horizontal contact at its top end (normal Z, h along X, w along Y) gives
    /// C, T along its axis, the sliding shears, and bending about Y (local z → Mz) and X
    /// (local y → My); a contact on its side (normal X) does not cut it.
    #[test]
    fn fe_strengths_map_onto_the_contact_axes() {
        let end = test_end();
        let lost = EndStrength { lost: true, ..end };
        let col = BodyStrength {
            axes: [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            ends: [([0.0, 0.0, 0.0], lost), ([0.0, 0.0, 1.0], end)],
        };
        let mut c = Contact {
            a: 0,
            b: 1,
            pivot: [0.0, 0.0, 0.99],
            normal_axis: 2,
            normal_sign: 1.0,
            h_axis: 0,
            w_axis: 1,
            h: 0.1,
            w: 0.1,
            normal_overlap: 0.0,
            area: 0.01,
            centre_distance: 0.25,
        };
        assert!(col.cut_by(&c));
        assert!(!col.end_near(c.pivot).lost);
        // shear along X (local y) 40, along Y (local z) 45; moment about Y (local z) 2,
        // about X (local y) 3.
        assert_eq!(col.forces_for(&c), [300.0, 50.0, 40.0, 45.0, 2.0, 3.0]);
        c.pivot = [0.0, 0.0, 0.01];
        assert!(col.end_near(c.pivot).lost);
        c.normal_axis = 0;
        c.h_axis = 1;
        c.w_axis = 2;
        assert!(!col.cut_by(&c));
    }
}
