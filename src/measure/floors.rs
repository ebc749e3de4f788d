//! The floors (the active slab bodies grouped by their undeformed centre height) and what
//! they show on a run's timeline: the first frame at which the FE alone stops describing
//! the building ([`first_contact`]) and the floors' shape when the lowest floor has come
//! most of the way down ([`floors_down`]).
use crate::body::Body;
use crate::body::Role;
use crate::bullet::Pose;
use crate::output::summary::{r6, FloorsDown};
use crate::plan_geometry::corners;
use std::collections::BTreeMap;

/// The floors: the active slab bodies grouped by their undeformed centre height (mm), bottom
/// up.
pub(super) fn slab_floors(bodies: &[Body]) -> BTreeMap<i64, Vec<usize>> {
    let mut floors: BTreeMap<i64, Vec<usize>> = BTreeMap::new();
    for (i, b) in bodies.iter().enumerate() {
        if !b.passive && b.kind == Some(Role::Slab) {
            floors
                .entry((b.pose0.position[2] * 1000.0).round() as i64)
                .or_default()
                .push(i);
        }
    }
    floors
}

/// The mass-weighted centroid of the bodies `ids` at the positions `at(i)`, m.
pub(super) fn mass_centroid(
    bodies: &[Body],
    ids: &[usize],
    at: impl Fn(usize) -> [f64; 3],
) -> [f64; 3] {
    let m: f64 = ids.iter().map(|&i| bodies[i].mass_kg).sum();
    let mut c = [0.0; 3];
    for &i in ids {
        let w = bodies[i].mass_kg / m;
        for (ck, pk) in c.iter_mut().zip(at(i)) {
            *ck += w * pk;
        }
    }
    c
}

/// The base level, m: the foundation blocks' highest undeformed top, else the active
/// bodies' lowest undeformed corner.
pub(super) fn base_level(bodies: &[Body]) -> f64 {
    let top = bodies
        .iter()
        .filter(|b| b.passive)
        .map(|b| b.pose0.position[2] + b.half_extents[2])
        .fold(f64::NAN, f64::max);
    if top.is_nan() {
        bodies
            .iter()
            .filter(|b| !b.passive)
            .flat_map(|b| corners(&b.pose0, b.half_extents))
            .map(|c| c[2])
            .fold(f64::INFINITY, f64::min)
    } else {
        top
    }
}

/// The first keyframe at which a model without contact (the FE alone) stops describing
/// the building: a slab's lowest corner reaches the ground's top (the highest foundation
/// top in that frame), or two consecutive floors have closed the story between them (the
/// upper floor's centroid no higher above the lower one's than their two slab half
/// thicknesses). Returns the frame's index and the reason in words; `None` when no frame
/// gets there (or the model has no slabs). The ruin measures at that frame are the FE's
/// own collapse mode, the reference of docs/handoff.md §5 (d).
pub(crate) fn first_contact(bodies: &[Body], frames: &[(f64, &[Pose])]) -> Option<(usize, String)> {
    let floors: Vec<Vec<usize>> = slab_floors(bodies).into_values().collect();
    let passive: Vec<usize> = (0..bodies.len()).filter(|&i| bodies[i].passive).collect();
    // Mean slab half thickness of each floor, m.
    let half_thickness: Vec<f64> = floors
        .iter()
        .map(|ids| ids.iter().map(|&i| bodies[i].half_extents[2]).sum::<f64>() / ids.len() as f64)
        .collect();
    for (k, (_, poses)) in frames.iter().enumerate() {
        let ground_top = passive
            .iter()
            .map(|&i| poses[i].position[2] + bodies[i].half_extents[2])
            .fold(f64::NEG_INFINITY, f64::max);
        if ground_top.is_finite() {
            for &i in floors.iter().flatten() {
                let low = corners(&poses[i], bodies[i].half_extents)
                    .iter()
                    .map(|c| c[2])
                    .fold(f64::INFINITY, f64::min);
                if low <= ground_top {
                    return Some((k, format!("{} reaches the ground", bodies[i].id.name())));
                }
            }
        }
        let z: Vec<f64> = floors
            .iter()
            .map(|ids| mass_centroid(bodies, ids, |i| poses[i].position)[2])
            .collect();
        for n in 1..floors.len() {
            if z[n] - z[n - 1] <= half_thickness[n - 1] + half_thickness[n] {
                return Some((k, format!("floor {} comes down onto floor {}", n + 1, n)));
            }
        }
    }
    None
}

/// Share of the lowest floor's height above the base at which [`floors_down`] looks.
pub(crate) const FLOORS_DOWN_SHARE: f64 = 0.7;

/// The floors' shape when the lowest floor has first come [`FLOORS_DOWN_SHARE`] of its
/// height above the base down, on a run's timeline (FE keyframes, then the ruin stage's
/// frames): the last moments before a floor lands, the same measure for the FE alone, a
/// hybrid and a rigid-only run (docs/handoff.md, "The FE's own collapse and ruin"). Floors as in
/// [`crate::measure::ruin_measures`] (slab bodies by undeformed height, mass-weighted centroids); the base
/// is the foundations' highest top (else the lowest undeformed corner). **Stories above
/// whole**: every floor's drop within 0.15 × the lowest floor's height of the lowest
/// floor's drop, and every floor within 0.25 × that height of the floor below in plan (the
/// first story folds and carries the rest down, as frame3's FE does). `None` without two
/// floors, or if the lowest floor never gets that far down.
pub(crate) fn floors_down(bodies: &[Body], frames: &[(f64, &[Pose])]) -> Option<FloorsDown> {
    let floors: Vec<Vec<usize>> = slab_floors(bodies).into_values().collect();
    if floors.len() < 2 {
        return None;
    }
    let base = base_level(bodies);
    let c0: Vec<[f64; 3]> = floors
        .iter()
        .map(|ids| mass_centroid(bodies, ids, |i| bodies[i].pose0.position))
        .collect();
    let height = c0[0][2] - base;
    if height.is_nan() || height <= 0.0 {
        return None;
    }
    for (t, poses) in frames {
        let d: Vec<[f64; 3]> = floors
            .iter()
            .zip(&c0)
            .map(|(ids, c0)| {
                let c = mass_centroid(bodies, ids, |i| poses[i].position);
                [c[0] - c0[0], c[1] - c0[1], c[2] - c0[2]]
            })
            .collect();
        if -d[0][2] >= FLOORS_DOWN_SHARE * height {
            let drops: Vec<f64> = d.iter().map(|x| -x[2]).collect();
            let offsets: Vec<f64> = d
                .windows(2)
                .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
                .collect();
            let whole = drops.iter().all(|z| (z - drops[0]).abs() <= 0.15 * height)
                && offsets.iter().all(|o| *o <= 0.25 * height);
            return Some(FloorsDown {
                share: FLOORS_DOWN_SHARE,
                t_s: r6(*t),
                floor_drops_m: drops.into_iter().map(r6).collect(),
                story_offsets_m: offsets.into_iter().map(r6).collect(),
                stories_above_whole: whole,
            });
        }
    }
    None
}

/// The 1-based number of the floor at undeformed height `z` (mm) in `list` (0 if none).
pub(super) fn floor_index(list: &[(i64, Vec<usize>)], z: i64) -> usize {
    list.iter().position(|(k, _)| *k == z).map_or(0, |i| i + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`super::first_contact`] and [`super::floors_down`] on owned frames.
    fn borrowed(frames: &[(f64, Vec<Pose>)]) -> Vec<(f64, &[Pose])> {
        frames.iter().map(|(t, p)| (*t, p.as_slice())).collect()
    }
    fn first_contact(bodies: &[Body], frames: &[(f64, Vec<Pose>)]) -> Option<(usize, String)> {
        super::first_contact(bodies, &borrowed(frames))
    }
    fn floors_down(bodies: &[Body], frames: &[(f64, Vec<Pose>)]) -> Option<FloorsDown> {
        super::floors_down(bodies, &borrowed(frames))
    }

    /// A flat box body at `z` (m): a 100 kg slab of half thickness 15 mm, or a passive
    /// foundation block 50 mm deep.
    fn box_at(id: crate::body::BodyId, z: f64, slab: bool) -> Body {
        Body {
            id,
            kind: slab.then_some(Role::Slab),
            half_extents: if slab {
                [0.35, 0.35, 0.015]
            } else {
                [0.1, 0.1, 0.05]
            },
            pose0: Pose {
                position: [0.0, 0.0, z],
                orientation: [1.0, 0.0, 0.0, 0.0],
            },
            mass_kg: if slab { 100.0 } else { 0.0 },
            passive: !slab,
        }
    }

    /// A foundation block (top at 0) under two 100 kg slabs at 1 m and 2 m.
    fn two_floors() -> Vec<Body> {
        use crate::body::{BodyId, BodyType};
        vec![
            box_at(BodyId::Foundation { node: 1 }, -0.05, false),
            box_at(BodyId::element(BodyType::Slab, "1", 2), 1.0, true),
            box_at(BodyId::element(BodyType::Slab, "2", 3), 2.0, true),
        ]
    }

    /// Frames of the foundation (top at `ground`) and the two slabs at `z1`, `z2` (m).
    fn frame(bodies: &[Body], ground: f64, z1: f64, z2: f64) -> Vec<Pose> {
        bodies
            .iter()
            .zip([ground - 0.05, z1, z2])
            .map(|(b, z)| Pose {
                position: [0.0, 0.0, z],
                orientation: b.pose0.orientation,
            })
            .collect()
    }

    /// The FE's first contact: a slab whose lowest corner reaches the frame's foundation
    /// top (0.1 m per frame from 1 m: 1 − 0.015 − 0.1k ≤ 0 first at k = 10; with the
    /// ground 0.05 m down at k = 11), a tilted slab by its corner, and a story closing to
    /// the two half thicknesses (upper floor 0.2 m per frame: 1 − 0.2k ≤ 0.03 at k = 5).
    #[test]
    fn first_contact_is_a_slab_on_the_ground_or_a_story_closed() {
        let bodies = two_floors();
        let fall = |ground: f64| -> Vec<(f64, Vec<Pose>)> {
            (0..15)
                .map(|k| {
                    let d = 0.1 * k as f64;
                    (0.04 * k as f64, frame(&bodies, ground, 1.0 - d, 2.0 - d))
                })
                .collect()
        };
        assert_eq!(
            first_contact(&bodies, &fall(0.0)),
            Some((10, "Slab:1:2 reaches the ground".to_string()))
        );
        assert_eq!(first_contact(&bodies, &fall(-0.05)).map(|c| c.0), Some(11));
        // Tilted 90° about x at 0.3 m: its lowest corner is 0.3 − 0.35 m, below the ground.
        let mut tilted = frame(&bodies, 0.0, 0.3, 2.0);
        let h = std::f64::consts::FRAC_1_SQRT_2;
        tilted[1].orientation = [h, h, 0.0, 0.0];
        let upright = frame(&bodies, 0.0, 0.3, 2.0);
        assert_eq!(first_contact(&bodies, &[(0.0, upright)]), None);
        assert_eq!(
            first_contact(&bodies, &[(0.0, tilted)]).map(|c| c.0),
            Some(0)
        );
        let story: Vec<(f64, Vec<Pose>)> = (0..8)
            .map(|k| {
                (
                    0.04 * k as f64,
                    frame(&bodies, 0.0, 1.0, 2.0 - 0.2 * k as f64),
                )
            })
            .collect();
        assert_eq!(
            first_contact(&bodies, &story),
            Some((5, "floor 2 comes down onto floor 1".to_string()))
        );
        // Standing: no contact in any frame.
        let standing: Vec<(f64, Vec<Pose>)> = (0..4)
            .map(|k| (0.04 * k as f64, frame(&bodies, 0.0, 1.0, 2.0)))
            .collect();
        assert_eq!(first_contact(&bodies, &standing), None);
    }

    /// The floors when the lowest is 70 % down (base 0, floor 1 at 1 m: 0.7 m): falling
    /// together at 0.1 m per frame, first at k = 7 (drop 0.7), stories above whole;
    /// floor 2 lagging by 0.2 m: not whole (0.2 > 0.15 × 1 m); floor 2 shifted 0.3 m in
    /// plan: not whole (0.3 > 0.25 × 1 m); never that far down: none.
    #[test]
    fn floors_down_is_the_shape_when_floor_1_is_70_percent_down() {
        let bodies = two_floors();
        let run = |lag: f64, shift: f64| -> Vec<(f64, Vec<Pose>)> {
            (0..10)
                .map(|k| {
                    let d = 0.1 * k as f64;
                    let mut f = frame(&bodies, 0.0, 1.0 - d, 2.0 - d + lag.min(d));
                    f[2].position[0] = shift;
                    (0.04 * k as f64, f)
                })
                .collect()
        };
        let f = floors_down(&bodies, &run(0.0, 0.0)).unwrap();
        assert_eq!((f.t_s, f.share), (0.28, 0.7));
        assert!(f.stories_above_whole);
        assert!((f.floor_drops_m[0] - 0.7).abs() < 1e-9 && (f.floor_drops_m[1] - 0.7).abs() < 1e-9);
        assert!(
            !floors_down(&bodies, &run(0.2, 0.0))
                .unwrap()
                .stories_above_whole
        );
        let shifted = floors_down(&bodies, &run(0.0, 0.3)).unwrap();
        assert!((shifted.story_offsets_m[0] - 0.3).abs() < 1e-9 && !shifted.stories_above_whole);
        let standing: Vec<(f64, Vec<Pose>)> = (0..4)
            .map(|k| (0.04 * k as f64, frame(&bodies, 0.0, 1.0, 2.0)))
            .collect();
        assert_eq!(floors_down(&bodies, &standing), None);
    }
}
