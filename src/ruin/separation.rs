//! Which bodies may touch: the pieces a connection holds together are one solid, and
//! become separate solids when it is gone.
//!
//! BCB adds every connection's constraints with `addConstraint(c, disable_collisions =
//! true)` (docs/bcb.md §11.2), so that the contact of two joined pieces does not fight
//! their connection. Bullet 3.24 keeps that exemption for as long as the constraint is in
//! the world, broken or not (`btRigidBody::addConstraintRef` puts each body on the other's
//! ignore list; only `removeConstraint` takes it off), and Blender never removes a broken
//! constraint. So in BCB a column piece whose connection to a beam has broken falls
//! through that beam: in the frame3 LC5 ruins with BCB's exemption every pair of bodies
//! overlapping by more than 10 mm was a connected pair, up to 0.14 m deep
//! (docs/ruin-numerics.md, "Which bodies touch").
//!
//! Two exemptions are kept here, each lifted when nothing holds any more: every constraint
//! of the connections that justify it is disabled (broken by Bullet or by the monitor):
//!
//! * **connected pairs** ([`PairsTouch`]): a pair of bodies joined by connections with
//!   `disable_collisions` touches again once every one of them is broken (or, with
//!   [`PairsTouch::OnceYielded`], has lost its rigid rows);
//! * **connected bases and the ground** (`!ground_under_connected_bases`): a piece joined to
//!   a passive foundation block does not touch the ground box while one of those
//!   connections carries compression ([`Until::CompressionLost`]). Its bottom face *is* the connected section, which the connection
//!   already carries; the ground contact under it was a second, unlimited compression path
//!   whose warm-started impulse pushed the base up and broke its tension row under gravity
//!   alone (docs/handoff.md, "The static lateral strength"). Once the connection no longer carries
//!   compression the ground must: a base left to its tension, shear or spring rows alone
//!   would sink into the ground.
//!
//! Pure bookkeeping: the stage applies the lifts with
//! [`crate::bullet::World::set_collision_with`].

use std::collections::BTreeMap;

/// When two pieces a connection holds together start touching each other
/// (`[physics] connected_pairs_touch`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PairsTouch {
    /// Never (BCB/Blender, the default): Bullet's exemption stays for the whole run, so
    /// pieces whose connection broke pass through each other.
    #[default]
    Never,
    /// Once every constraint of their connections is disabled: nothing holds them.
    OnceBroken,
    /// Once no rigid (generic) row of their connections is enabled: only BCB's plastic
    /// spring, or nothing, holds them, and the contact carries the compression of a
    /// yielded joint.
    OnceYielded,
}

/// The other side of an exemption.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Other {
    /// An input body (index).
    Body(usize),
    /// The ground box.
    Ground,
}

/// What of a connection must be gone before its exemption is lifted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Until {
    /// Every constraint: nothing holds ([`PairsTouch::OnceBroken`]).
    Broken,
    /// Every rigid (generic) row: at most the plastic spring holds
    /// ([`PairsTouch::OnceYielded`]).
    Yielded,
    /// The compression its axial row carried: from then on the ground carries it.
    CompressionLost,
}

/// One pair of bodies that may not touch while any of its connections holds.
#[derive(Debug, Clone, PartialEq)]
pub struct Exemption {
    /// The input body (index).
    pub body: usize,
    /// The body or the ground it may not touch.
    pub other: Other,
    /// The connections (indices) whose breaking lifts the exemption.
    pub connections: Vec<usize>,
    /// What of each must be gone.
    pub until: Until,
    /// Lifted: the two touch again.
    pub lifted: bool,
}

/// The exemptions of one ruin stage, in (body, other) order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Separation {
    exemptions: Vec<Exemption>,
    /// Exemptions not lifted yet.
    left: usize,
}

impl Separation {
    /// The exemptions of the connections `joins` — (body a, body b, disable_collisions) in
    /// connection order ([`super::connection::ConnectionSpec`]'s fields) — between bodies
    /// of which `passive` marks the foundation blocks. `pairs_touch`: when the connected pairs' exemptions
    /// are lifted (BCB: never); `ground_under_connected_bases`: let pieces joined to a
    /// foundation block touch the ground from the start (BCB).
    pub fn new(
        joins: impl IntoIterator<Item = (usize, usize, bool)>,
        passive: &[bool],
        pairs_touch: PairsTouch,
        ground_under_connected_bases: bool,
    ) -> Separation {
        let pair_until = if pairs_touch == PairsTouch::OnceYielded {
            Until::Yielded
        } else {
            Until::Broken
        };
        let mut map: BTreeMap<(usize, Other), Vec<usize>> = BTreeMap::new();
        for (i, (a, b, disable)) in joins.into_iter().enumerate() {
            if !disable {
                continue;
            }
            if pairs_touch != PairsTouch::Never {
                map.entry((a.min(b), Other::Body(a.max(b))))
                    .or_default()
                    .push(i);
            }
            if !ground_under_connected_bases {
                for (x, y) in [(a, b), (b, a)] {
                    if passive.get(y) == Some(&true) && passive.get(x) == Some(&false) {
                        map.entry((x, Other::Ground)).or_default().push(i);
                    }
                }
            }
        }
        let exemptions: Vec<Exemption> = map
            .into_iter()
            .map(|((body, other), connections)| Exemption {
                body,
                other,
                connections,
                until: match other {
                    Other::Body(_) => pair_until,
                    Other::Ground => Until::CompressionLost,
                },
                lifted: false,
            })
            .collect();
        Separation {
            left: exemptions.len(),
            exemptions,
        }
    }

    /// Whether an exemption is still to be lifted.
    pub fn pending(&self) -> bool {
        self.left > 0
    }

    /// Every exemption.
    pub fn exemptions(&self) -> &[Exemption] {
        &self.exemptions
    }

    /// The bodies that may not touch the ground at the start (Bullet knows nothing of
    /// these; the connected pairs it exempts itself).
    pub fn ground_exempt(&self) -> impl Iterator<Item = usize> + '_ {
        self.exemptions
            .iter()
            .filter(|e| e.other == Other::Ground)
            .map(|e| e.body)
    }

    /// Lifts every exemption none of whose connections holds any more and returns the
    /// newly lifted ones as (body, other). `holds(connection, until)`: whether what
    /// `until` names is still there ([`Until`]; the stage reads Bullet's enabled flags).
    /// Called after every substep, so a pair touches from the substep its last row broke
    /// in: had it waited for the monitor's frame, the two could have moved centimetres into
    /// each other and been pushed apart at the contact's Baumgarte velocity ERP·d/h (split
    /// impulse off): energy from nowhere.
    pub fn lift(&mut self, holds: impl Fn(usize, Until) -> bool) -> Vec<(usize, Other)> {
        let mut out = Vec::new();
        for e in self.exemptions.iter_mut().filter(|e| !e.lifted) {
            if !e.connections.iter().any(|&c| holds(c, e.until)) {
                e.lifted = true;
                self.left -= 1;
                out.push((e.body, e.other));
            }
        }
        out
    }
}

/// How deep two boxes overlap, m: the smallest overlap of their projections on the 15
/// separating axes of the separating-axis test (Gottschalk, Lin and Manocha 1996, OBBTree),
/// 0 when an axis separates them. `(rotation, centre, half extents)` per box.
pub fn box_overlap(
    a: (
        &nalgebra::UnitQuaternion<f64>,
        &nalgebra::Vector3<f64>,
        &[f64; 3],
    ),
    b: (
        &nalgebra::UnitQuaternion<f64>,
        &nalgebra::Vector3<f64>,
        &[f64; 3],
    ),
) -> f64 {
    use nalgebra::Vector3;
    let ra = a.0.to_rotation_matrix();
    let rb = b.0.to_rotation_matrix();
    let ax: [Vector3<f64>; 3] = [0, 1, 2].map(|k| ra.matrix().column(k).into_owned());
    let bx: [Vector3<f64>; 3] = [0, 1, 2].map(|k| rb.matrix().column(k).into_owned());
    let d = b.1 - a.1;
    let mut axes: Vec<Vector3<f64>> = ax.iter().chain(bx.iter()).copied().collect();
    for u in &ax {
        for v in &bx {
            let c = u.cross(v);
            let n = c.norm();
            if n > 1e-9 {
                axes.push(c / n);
            }
        }
    }
    let mut depth = f64::INFINITY;
    for n in &axes {
        let r: f64 = (0..3)
            .map(|k| a.2[k] * ax[k].dot(n).abs() + b.2[k] * bx[k].dot(n).abs())
            .sum();
        let o = r - d.dot(n).abs();
        if o <= 0.0 {
            return 0.0;
        }
        depth = depth.min(o);
    }
    depth
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pair_touches_once_all_its_connections_are_broken() {
        // Bodies 0, 1 joined twice; 1 and the foundation 2 once; 3 joined to nothing.
        let cs = [(0, 1, true), (1, 0, true), (2, 1, true)];
        let passive = [false, false, true, false];
        let mut s = Separation::new(cs, &passive, PairsTouch::OnceBroken, false);
        let keys: Vec<(usize, Other)> = s.exemptions().iter().map(|e| (e.body, e.other)).collect();
        assert_eq!(
            keys,
            vec![(0, Other::Body(1)), (1, Other::Body(2)), (1, Other::Ground)]
        );
        assert_eq!(s.ground_exempt().collect::<Vec<_>>(), vec![1]);
        let mut holds = [true; 3];
        holds[0] = false;
        assert!(
            s.lift(|c, _| holds[c]).is_empty(),
            "one of the pair's two holds"
        );
        holds[1] = false;
        holds[2] = false;
        assert_eq!(
            s.lift(|c, _| holds[c]),
            vec![(0, Other::Body(1)), (1, Other::Body(2)), (1, Other::Ground)]
        );
        assert!(s.lift(|c, _| holds[c]).is_empty(), "lifted once");
        assert!(!s.pending());
    }

    #[test]
    fn bcb_keeps_every_exemption_and_collision_enabled_connections_have_none() {
        let cs = [(0, 1, true), (1, 2, true), (0, 3, false)];
        let passive = [false, false, true, true];
        assert!(Separation::new(cs, &passive, PairsTouch::Never, true)
            .exemptions()
            .is_empty());
        let s = Separation::new(cs, &passive, PairsTouch::Never, false);
        let keys: Vec<(usize, Other)> = s.exemptions().iter().map(|e| (e.body, e.other)).collect();
        assert_eq!(keys, vec![(1, Other::Ground)], "0–3 lets them collide");
    }

    #[test]
    fn once_yielded_a_pair_touches_when_its_rigid_rows_are_gone() {
        let mut s = Separation::new(
            [(0, 1, true)],
            &[false, false],
            PairsTouch::OnceYielded,
            false,
        );
        // The spring holds, the rigid rows do not.
        assert_eq!(
            s.lift(|_, until| until != Until::Yielded),
            vec![(0, Other::Body(1))]
        );
        let mut s = Separation::new(
            [(0, 1, true)],
            &[false, false],
            PairsTouch::OnceBroken,
            false,
        );
        assert!(s.lift(|_, until| until != Until::Yielded).is_empty());
    }

    #[test]
    fn box_overlap_is_the_separating_axis_depth() {
        use nalgebra::{UnitQuaternion, Vector3};
        let id = UnitQuaternion::identity();
        let h = [0.5; 3];
        let o = Vector3::zeros();
        // Two unit cubes 0.7 m apart along x: 0.3 m deep.
        let d = box_overlap((&id, &o, &h), (&id, &Vector3::new(0.7, 0.0, 0.0), &h));
        assert!((d - 0.3).abs() < 1e-12, "{d}");
        // The second turned 45° about z at x = 1: its edge reaches 1 − √2/2 = 0.29289 m,
        // 0.5 − 0.29289 = 0.20711 m into the first (the deepest axis is x).
        let q = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_4);
        let d = box_overlap((&id, &o, &h), (&q, &Vector3::new(1.0, 0.0, 0.0), &h));
        assert!((d - (0.5 * 2f64.sqrt() - 0.5)).abs() < 1e-12, "{d}");
        // At x = 1.3 the edge stops 0.0929 m short: no overlap.
        let d = box_overlap((&id, &o, &h), (&q, &Vector3::new(1.3, 0.0, 0.0), &h));
        assert_eq!(d, 0.0);
    }
}
