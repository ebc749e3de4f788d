//! Connection search and contact geometry (BCB `builder_prep.py`, docs/bcb.md §7.3 and §11.3).
//!
//! 1. **Candidates.** Every body's world AABB is enlarged by half the search distance on
//!    each side (BCB's `searchDistance` = 0.02 m total, so 0.01 m per side: gaps up to
//!    0.02 m connect). A pair is a candidate if the enlarged boxes overlap with positive
//!    volume (strictly, on all three axes). Broad phase: sort-and-sweep on x
//!    (O(n log n + k)), then a y/z test.
//! 2. **Contact box.** The overlap of the two *raw* AABBs per axis,
//!    `o_i = max(0, min(maxA, maxB) − max(minA, minB))`; its centre (the midpoint of the
//!    two inner faces, also for a small gap) is the **pivot**.
//! 3. **Axes.** The axis of the smallest overlap is the contact **normal**, the middle one
//!    is **h**, the largest **w** (so h ≤ w); ties go to the lower axis index, as BCB's
//!    sort of (value, axis) pairs does. The normal points from A to B: its sign is the
//!    sign of (centre_B − centre_A) along the normal axis (BCB's 90° axis snapping).
//! 4. **Area.** Default [`ContactAreaRule::Rectangle`]: a = h·w (docs/bcb.md §11.3).
//!    [`ContactAreaRule::ProjectionSum`] is BCB's bbox fallback: a = oy·oz + ox·oz + ox·oy
//!    with every overlap widened by 2e-6 m (BCB widens each box by 1e-6 m). For a clean face
//!    contact the two agree up to that widening; they differ for interpenetrating boxes
//!    (the projection sum counts all three faces of the overlap box) and for long edge
//!    contacts (the widening gives an edge of length L an area of about 4e-6·L).
//! 5. Connections with a < `min_contact_area` (BCB's `minimumContactArea`, 1e-6 m²) are
//!    dropped; two passive bodies are never connected.
//! 6. Joints ([`JointContacts`], option): with `ColumnAbove`, a beam or slab body that
//!    touches two column pieces stacked at a floor keeps its contact with the upper piece
//!    only (docs/handoff.md §2.7).
//!
//! Not reproduced: BCB's mesh-face ("accurate") contact area — for cuboids it agrees with
//! the rectangle — and its volume correction, which is 1 for cuboids. Rotated boxes are
//! handled through their world AABBs, as in BCB: exact for axis-aligned boxes and boxes
//! turned by multiples of 90°, an over-estimate for inclined members.

use super::{Aabb, BodyGeom, RuinError};
use serde::{Deserialize, Serialize};

/// How the contact area is measured from the overlap box.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum ContactAreaRule {
    /// a = h·w, the two larger overlaps (docs/bcb.md §11.3).
    #[default]
    Rectangle,
    /// BCB's bbox fallback: sum of the three projections of the overlap box, each
    /// overlap widened by 2e-6 m.
    ProjectionSum,
}

/// Settings of the connection search, with BCB's defaults.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SearchSettings {
    /// Total search distance, m (BCB `searchDistance`, 0.02): each AABB grows by half of it
    /// per side.
    pub search_distance: f64,
    /// Smallest contact area kept, m² (BCB `minimumContactArea`, 1e-6).
    pub min_contact_area: f64,
    /// Area rule.
    pub area_rule: ContactAreaRule,
    /// Joint rule (BCB: [`JointContacts::Faces`]).
    pub joints: JointContacts,
}

impl Default for SearchSettings {
    fn default() -> Self {
        SearchSettings {
            search_distance: 0.02,
            min_contact_area: 1e-6,
            area_rule: ContactAreaRule::Rectangle,
            joints: JointContacts::Faces,
        }
    }
}

/// Which column pieces the beams and slab panels framing into a beam–column joint connect
/// to (docs/handoff.md §2.7).
///
/// In the FE a joint is a node: the column element below ends there, and its end section
/// (the section of a sway mechanism's largest moment) can turn against everything else at
/// the node. With one rigid body per element the joint has no body of its own; BCB
/// connects every touching pair, so the beams and slab panels hold the column's top piece
/// as well as the piece above, the top piece turns with the joint and the column below
/// can hinge only one piece lower (0.25 m under the floor in frame3): its mechanism is
/// shorter than the FE's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum JointContacts {
    /// Every touching pair (BCB).
    #[default]
    Faces,
    /// A beam or slab body touching two column pieces stacked at a floor (the lower one's
    /// top face on the upper one's bottom face) connects to the upper piece only, so the
    /// lower piece's top face is the column's end section at the joint, as in the FE. The
    /// story above then hinges one piece above its floor. Where no piece stands above (the
    /// roof), nothing changes.
    ColumnAbove,
}

/// A vertical member piece: its longest box axis (undeformed) is within 45° of world z.
fn is_vertical_member(b: &BodyGeom) -> bool {
    let he = b.half_extents;
    let k = (0..3).fold(0, |k, i| if he[i] > he[k] { i } else { k });
    if !(0..3).filter(|&i| i != k).all(|i| he[k] > he[i]) {
        return false;
    }
    let mut e = nalgebra::Vector3::zeros();
    e[k] = 1.0;
    (b.rotation * e).z.abs() > std::f64::consts::FRAC_1_SQRT_2
}

/// [`JointContacts::ColumnAbove`]: drops the contact of a non-vertical active body H with
/// the lower piece L of two vertical member pieces stacked along z (a contact of L and U
/// with normal z, U above) when H also touches U. The order of the rest is kept.
pub fn attach_joints_above(bodies: &[BodyGeom], contacts: Vec<Contact>) -> Vec<Contact> {
    let vertical: Vec<bool> = bodies.iter().map(is_vertical_member).collect();
    // Each body's partners, sorted (the contacts are sorted by (a, b)).
    let mut partners: Vec<Vec<usize>> = vec![Vec::new(); bodies.len()];
    for c in &contacts {
        partners[c.a].push(c.b);
        partners[c.b].push(c.a);
    }
    for p in &mut partners {
        p.sort_unstable();
    }
    let mut drop = std::collections::BTreeSet::new();
    for c in &contacts {
        if c.normal_axis != 2 || !vertical[c.a] || !vertical[c.b] {
            continue;
        }
        // The normal points from a to b: b is above when the sign is +.
        let (lower, upper) = if c.normal_sign > 0.0 {
            (c.a, c.b)
        } else {
            (c.b, c.a)
        };
        for &h in &partners[lower] {
            if h != upper
                && !vertical[h]
                && !bodies[h].passive
                && partners[upper].binary_search(&h).is_ok()
            {
                drop.insert((lower.min(h), lower.max(h)));
            }
        }
    }
    contacts
        .into_iter()
        .filter(|c| !drop.contains(&(c.a, c.b)))
        .collect()
}

/// BCB widens each box by this much per side for the projection-sum area, m.
const BCB_AREA_WIDENING: f64 = 1e-6;

/// One contact between two bodies, in the (undeformed) configuration it was found in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Index of body A (the lower index).
    pub a: usize,
    /// Index of body B (the higher index).
    pub b: usize,
    /// Pivot: centre of the overlap box, world, m.
    pub pivot: [f64; 3],
    /// World axis of the normal (0 = x, 1 = y, 2 = z).
    pub normal_axis: usize,
    /// +1 or −1: the normal is `normal_sign · e[normal_axis]`, pointing from A to B.
    pub normal_sign: f64,
    /// World axis along which the contact side h lies.
    pub h_axis: usize,
    /// World axis along which the contact side w lies.
    pub w_axis: usize,
    /// Contact side h, m (h ≤ w).
    pub h: f64,
    /// Contact side w, m.
    pub w: f64,
    /// Overlap along the normal, m (0 for touching faces or a gap).
    pub normal_overlap: f64,
    /// Contact area, m².
    pub area: f64,
    /// Centre-to-centre distance of the two bodies, m (BCB `geoLengthApprox`).
    pub centre_distance: f64,
}

impl Contact {
    /// The unit normal from A to B, world.
    pub fn normal(&self) -> [f64; 3] {
        let mut n = [0.0; 3];
        n[self.normal_axis] = self.normal_sign;
        n
    }
}

/// Finds every connection between `bodies` (BCB's bbox search, module docs).
/// The result is sorted by (a, b). Errors name the first unusable body.
pub fn find_contacts(
    bodies: &[BodyGeom],
    settings: &SearchSettings,
) -> Result<Vec<Contact>, RuinError> {
    if !(settings.search_distance.is_finite() && settings.search_distance >= 0.0) {
        return Err(RuinError::BadSetting {
            item: "search_distance".into(),
            message: format!("{} must be finite and >= 0", settings.search_distance),
        });
    }
    if !(settings.min_contact_area.is_finite() && settings.min_contact_area >= 0.0) {
        return Err(RuinError::BadSetting {
            item: "min_contact_area".into(),
            message: format!("{} must be finite and >= 0", settings.min_contact_area),
        });
    }
    for (i, b) in bodies.iter().enumerate() {
        b.validate(i)?;
    }
    let raw: Vec<Aabb> = bodies.iter().map(BodyGeom::aabb).collect();
    let pairs = candidate_pairs(&raw, settings.search_distance / 2.0);
    let mut contacts = Vec::new();
    for (a, b) in pairs {
        if bodies[a].passive && bodies[b].passive {
            continue;
        }
        if let Some(c) = contact_geometry(a, &bodies[a], &raw[a], b, &bodies[b], &raw[b], settings)
        {
            contacts.push(c);
        }
    }
    Ok(match settings.joints {
        JointContacts::Faces => contacts,
        JointContacts::ColumnAbove => attach_joints_above(bodies, contacts),
    })
}

/// Sort-and-sweep on x over the AABBs enlarged by `margin`: all pairs (i < j) whose
/// enlarged boxes overlap with positive volume, sorted.
pub(crate) fn candidate_pairs(raw: &[Aabb], margin: f64) -> Vec<(usize, usize)> {
    let boxes: Vec<Aabb> = raw.iter().map(|b| b.enlarged(margin)).collect();
    let mut order: Vec<usize> = (0..boxes.len()).collect();
    order.sort_by(|&i, &j| boxes[i].min[0].total_cmp(&boxes[j].min[0]).then(i.cmp(&j)));
    let mut pairs = Vec::new();
    for (k, &i) in order.iter().enumerate() {
        let bi = &boxes[i];
        for &j in &order[k + 1..] {
            let bj = &boxes[j];
            if bj.min[0] >= bi.max[0] {
                break;
            }
            let overlaps = (1..3).all(|ax| bi.max[ax].min(bj.max[ax]) > bi.min[ax].max(bj.min[ax]));
            // x: bj.min ≥ bi.min by the sort and bj.min < bi.max, so the x overlap is
            // positive unless bj is degenerate (min == max), which validation excludes.
            if overlaps && bi.max[0].min(bj.max[0]) > bj.min[0] {
                pairs.push((i.min(j), i.max(j)));
            }
        }
    }
    pairs.sort_unstable();
    pairs
}

/// Contact geometry of a candidate pair (module docs, steps 2–5), or `None` if the area
/// is below the minimum.
fn contact_geometry(
    a: usize,
    body_a: &BodyGeom,
    box_a: &Aabb,
    b: usize,
    body_b: &BodyGeom,
    box_b: &Aabb,
    settings: &SearchSettings,
) -> Option<Contact> {
    let mut overlap = [0.0; 3];
    let mut pivot = [0.0; 3];
    for ax in 0..3 {
        let lo = box_a.min[ax].max(box_b.min[ax]);
        let hi = box_a.max[ax].min(box_b.max[ax]);
        overlap[ax] = (hi - lo).max(0.0);
        pivot[ax] = 0.5 * (lo + hi);
    }
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&i, &j| overlap[i].total_cmp(&overlap[j]).then(i.cmp(&j)));
    let [normal_axis, h_axis, w_axis] = axes;
    let h = overlap[h_axis];
    let w = overlap[w_axis];
    let area = match settings.area_rule {
        ContactAreaRule::Rectangle => h * w,
        ContactAreaRule::ProjectionSum => {
            let o = overlap.map(|v| v + 2.0 * BCB_AREA_WIDENING);
            o[1] * o[2] + o[0] * o[2] + o[0] * o[1]
        }
    };
    if area < settings.min_contact_area {
        return None;
    }
    let d: Vec<f64> = (0..3)
        .map(|i| body_b.centre[i] - body_a.centre[i])
        .collect();
    let normal_sign = if d[normal_axis] < 0.0 { -1.0 } else { 1.0 };
    let centre_distance = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    Some(Contact {
        a,
        b,
        pivot,
        normal_axis,
        normal_sign,
        h_axis,
        w_axis,
        h,
        w,
        normal_overlap: overlap[normal_axis],
        area,
        centre_distance,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::UnitQuaternion;

    fn cuboid(name: &str, min: [f64; 3], max: [f64; 3]) -> BodyGeom {
        BodyGeom {
            name: name.into(),
            group: "g".into(),
            centre: [0, 1, 2].map(|i| 0.5 * (min[i] + max[i])),
            rotation: UnitQuaternion::identity(),
            half_extents: [0, 1, 2].map(|i| 0.5 * (max[i] - min[i])),
            passive: false,
        }
    }

    /// Brute force O(n²) reference for the sweep.
    #[test]
    fn sweep_equals_brute_force() {
        // A deterministic pseudo-random cloud of boxes (LCG).
        let mut state: u64 = 12345;
        let mut rnd = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut boxes = Vec::new();
        for _ in 0..300 {
            let c = [rnd() * 5.0, rnd() * 5.0, rnd() * 5.0];
            let h = [rnd() * 0.3 + 0.01, rnd() * 0.3 + 0.01, rnd() * 0.3 + 0.01];
            boxes.push(Aabb {
                min: [c[0] - h[0], c[1] - h[1], c[2] - h[2]],
                max: [c[0] + h[0], c[1] + h[1], c[2] + h[2]],
            });
        }
        let margin = 0.01;
        let fast = candidate_pairs(&boxes, margin);
        let mut slow = Vec::new();
        for i in 0..boxes.len() {
            for j in i + 1..boxes.len() {
                let (a, b) = (boxes[i].enlarged(margin), boxes[j].enlarged(margin));
                if (0..3).all(|ax| a.max[ax].min(b.max[ax]) > a.min[ax].max(b.min[ax])) {
                    slow.push((i, j));
                }
            }
        }
        assert!(slow.len() > 50, "test cloud too sparse: {}", slow.len());
        assert_eq!(fast, slow);
    }

    /// A gap of 0.019 m connects, 0.021 m does not (search distance 0.02 m).
    #[test]
    fn gap_threshold_is_the_search_distance() {
        let s = SearchSettings::default();
        for (gap, expect) in [(0.019, 1), (0.021, 0)] {
            let a = cuboid("a", [0.0, 0.0, 0.0], [1.0, 1.0, 1.0]);
            let b = cuboid("b", [1.0 + gap, 0.0, 0.0], [2.0 + gap, 1.0, 1.0]);
            let c = find_contacts(&[a, b], &s).unwrap();
            assert_eq!(c.len(), expect, "gap {gap}");
            if expect == 1 {
                assert!((c[0].pivot[0] - (1.0 + gap / 2.0)).abs() < 1e-12);
                assert_eq!(c[0].area, 1.0);
            }
        }
    }

    #[test]
    fn bad_body_is_named() {
        let mut a = cuboid("Beam:1:7", [0.0; 3], [1.0; 3]);
        a.half_extents[1] = 0.0;
        let err = find_contacts(
            &[cuboid("x", [0.0; 3], [1.0; 3]), a],
            &SearchSettings::default(),
        )
        .unwrap_err();
        assert!(
            err.to_string().contains("rigid body 1 ('Beam:1:7')"),
            "{err}"
        );
    }
}
