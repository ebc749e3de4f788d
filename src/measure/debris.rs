//! The ruin at the end: its original footprint, its extent beyond it, the debris' plan
//! area and height, each floor's displacement, the slab overlap of consecutive floors and
//! the deepest interpenetration of two bodies (module docs of [`crate::measure`]).
use super::floors::{base_level, floor_index, mass_centroid, slab_floors};
use crate::body::Body;
use crate::bullet::Pose;
use crate::output::summary::{
    r6, Extent, FloorMeasure, Footprint, Interpenetration, RuinMeasures, SlabOverlap,
    INTERPENETRATION_COUNTED_M,
};
use crate::plan_geometry::{corners, intersection_area, projection, union_area};
use crate::ruin::stage::to_isometry;
use nalgebra::Vector3;

/// The ruin measures (module docs) of `bodies` at `final_poses`; `ground_z` is the
/// ground's vertical displacement at the end, m.
pub(crate) fn ruin_measures(bodies: &[Body], final_poses: &[Pose], ground_z: f64) -> RuinMeasures {
    let active: Vec<usize> = (0..bodies.len()).filter(|&i| !bodies[i].passive).collect();
    // Original footprint.
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for &i in &active {
        for c in corners(&bodies[i].pose0, bodies[i].half_extents) {
            for k in 0..2 {
                lo[k] = lo[k].min(c[k]);
                hi[k] = hi[k].max(c[k]);
            }
        }
    }
    let mut beyond = [0.0f64; 4];
    let mut top = f64::NEG_INFINITY;
    for &i in &active {
        for c in corners(&final_poses[i], bodies[i].half_extents) {
            beyond[0] = beyond[0].max(lo[0] - c[0]);
            beyond[1] = beyond[1].max(c[0] - hi[0]);
            beyond[2] = beyond[2].max(lo[1] - c[1]);
            beyond[3] = beyond[3].max(c[1] - hi[1]);
            top = top.max(c[2]);
        }
    }
    let base_z = base_level(bodies);
    let final_proj: Vec<Vec<[f64; 2]>> = (0..bodies.len())
        .map(|i| projection(&final_poses[i], bodies[i].half_extents))
        .collect();
    let init_proj: Vec<Vec<[f64; 2]>> = (0..bodies.len())
        .map(|i| projection(&bodies[i].pose0, bodies[i].half_extents))
        .collect();
    let debris: Vec<&Vec<[f64; 2]>> = active.iter().map(|&i| &final_proj[i]).collect();
    // Floors.
    let floor_list: Vec<(i64, Vec<usize>)> = slab_floors(bodies).into_iter().collect();
    let mut floor_out = Vec::new();
    for (n, (z, ids)) in floor_list.iter().enumerate() {
        let c0 = mass_centroid(bodies, ids, |i| bodies[i].pose0.position);
        let c1 = mass_centroid(bodies, ids, |i| final_poses[i].position);
        let d = [c1[0] - c0[0], c1[1] - c0[1], c1[2] - c0[2]];
        floor_out.push(FloorMeasure {
            floor: n + 1,
            level_m: r6(*z as f64 / 1000.0),
            slabs: ids.len(),
            centroid_displacement_m: [r6(d[0]), r6(d[1]), r6(d[2])],
            horizontal_offset_m: r6(d[0].hypot(d[1])),
        });
    }
    let mut overlap_out = Vec::new();
    for w in floor_list.windows(2) {
        let lower: Vec<&Vec<[f64; 2]>> = w[0].1.iter().map(|&i| &final_proj[i]).collect();
        let upper: Vec<&Vec<[f64; 2]>> = w[1].1.iter().map(|&i| &final_proj[i]).collect();
        let upper0: Vec<&Vec<[f64; 2]>> = w[1].1.iter().map(|&i| &init_proj[i]).collect();
        let a_int = intersection_area(&lower, &upper);
        let a0 = union_area(&upper0);
        overlap_out.push(SlabOverlap {
            floors: [
                floor_index(&floor_list, w[0].0),
                floor_index(&floor_list, w[1].0),
            ],
            overlap_area_m2: r6(a_int),
            upper_slab_area_m2: r6(a0),
            overlap_ratio: r6(if a0 > 0.0 { a_int / a0 } else { 0.0 }),
        });
    }
    RuinMeasures {
        original_footprint_m: Footprint {
            x: [r6(lo[0]), r6(hi[0])],
            y: [r6(lo[1]), r6(hi[1])],
        },
        extent_beyond_footprint_m: Extent {
            x_minus: r6(beyond[0]),
            x_plus: r6(beyond[1]),
            y_minus: r6(beyond[2]),
            y_plus: r6(beyond[3]),
            max: r6(beyond.iter().copied().fold(0.0, f64::max)),
        },
        debris_footprint_area_m2: r6(union_area(&debris)),
        original_footprint_area_m2: r6((hi[0] - lo[0]) * (hi[1] - lo[1])),
        max_debris_height_m: r6(top - (base_z + ground_z)),
        floors: floor_out,
        slab_overlap: overlap_out,
        interpenetration: interpenetration(bodies, final_poses, &active),
    }
}

/// [`Interpenetration`] of the `active` bodies at `final_poses`.
fn interpenetration(bodies: &[Body], final_poses: &[Pose], active: &[usize]) -> Interpenetration {
    use crate::ruin::separation::box_overlap;
    let iso: Vec<_> = final_poses.iter().map(to_isometry).collect();
    let radius = |i: usize| Vector3::from(bodies[i].half_extents).norm();
    let mut out = Interpenetration::default();
    for (n, &i) in active.iter().enumerate() {
        for &j in &active[n + 1..] {
            let d = iso[j].translation.vector - iso[i].translation.vector;
            if d.norm() >= radius(i) + radius(j) {
                continue;
            }
            let depth = box_overlap(
                (
                    &iso[i].rotation,
                    &iso[i].translation.vector,
                    &bodies[i].half_extents,
                ),
                (
                    &iso[j].rotation,
                    &iso[j].translation.vector,
                    &bodies[j].half_extents,
                ),
            );
            if depth > INTERPENETRATION_COUNTED_M {
                out.pairs_over_10mm += 1;
            }
            if depth > out.deepest_m {
                out.deepest_m = depth;
                out.deepest_pair = Some([bodies[i].id.name(), bodies[j].id.name()]);
            }
        }
    }
    out.deepest_m = r6(out.deepest_m);
    out
}
