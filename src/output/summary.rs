//! `summary.json`: what a run found, every field documented with its unit in
//! `docs/scenario-format.md`. Geometric measures of the ruins:
//!
//! * a body's **plan projection** is the convex hull of its 8 box corners projected on
//!   the ground plane (x, y);
//! * areas of unions and intersections of projections are counted on a square raster
//!   (cell = the smallest plan-AABB side of the measured projections / [`CELLS_PER_SIDE`];
//!   a cell counts when its centre lies inside), exact to about one cell along the edges;
//! * the **original footprint** is the plan AABB of the undeformed active bodies;
//! * the **floors** are the slab bodies grouped by their undeformed centre height (mm);
//!   a floor's centroid is the mass-weighted mean of its slab centres;
//! * the **pancake measure** (paper §4: stacked vs offset slabs) of two consecutive
//!   floors is the area of the intersection of their final slab projections divided by
//!   the upper floor's undeformed slab area (1 = fully stacked, 0 = no overlap).
use crate::body::Body;
use crate::mapping::Role;
use crate::mode::Mode;
use crate::motion::GroundHistory;
use crate::physics::Pose;
use crate::ruin::rest::RestSpeed;
use crate::ruin::stage::{to_isometry, RuinResult, RuinStop};
use nalgebra::{Point3, Vector3};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Raster resolution of the area measures: cells across the smallest projection side.
pub(crate) const CELLS_PER_SIDE: f64 = 20.0;

/// The 8 corners of a box of half extents `he` at `pose`, m.
pub fn corners(pose: &Pose, he: [f64; 3]) -> Vec<[f64; 3]> {
    let iso = to_isometry(pose);
    let mut out = Vec::with_capacity(8);
    for sx in [-1.0, 1.0] {
        for sy in [-1.0, 1.0] {
            for sz in [-1.0, 1.0] {
                let p = iso * Point3::from(Vector3::new(sx * he[0], sy * he[1], sz * he[2]));
                out.push([p.x, p.y, p.z]);
            }
        }
    }
    out
}

/// Convex hull (counter-clockwise, Andrew's monotone chain) of plan points.
pub fn hull(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut p: Vec<[f64; 2]> = points.to_vec();
    p.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut lower: Vec<[f64; 2]> = Vec::new();
    for &q in &p {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], q) <= 0.0 {
            lower.pop();
        }
        lower.push(q);
    }
    let mut upper: Vec<[f64; 2]> = Vec::new();
    for &q in p.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], q) <= 0.0 {
            upper.pop();
        }
        upper.push(q);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

fn inside(poly: &[[f64; 2]], x: f64, y: f64) -> bool {
    if poly.len() < 3 {
        return false;
    }
    (0..poly.len()).all(|i| {
        let a = poly[i];
        let b = poly[(i + 1) % poly.len()];
        (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]) >= 0.0
    })
}

/// Plan projection of a box.
pub fn projection(pose: &Pose, he: [f64; 3]) -> Vec<[f64; 2]> {
    let c: Vec<[f64; 2]> = corners(pose, he).iter().map(|c| [c[0], c[1]]).collect();
    hull(&c)
}

/// The raster cell of a set of projections, m: 1/[`CELLS_PER_SIDE`] of the smallest
/// plan-AABB side among them (so every body is resolved, however far the debris spreads).
fn cell_of(polys: &[&Vec<[f64; 2]>]) -> f64 {
    let mut side = f64::INFINITY;
    for p in polys {
        let (lo, hi) = bbox(p);
        side = side.min((hi[0] - lo[0]).min(hi[1] - lo[1]));
    }
    (side.max(1e-4)) / CELLS_PER_SIDE
}

fn bbox(p: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for q in p {
        for k in 0..2 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    (lo, hi)
}

/// The cells of side `cell` whose centres lie in the union of `polys`, as row runs: for
/// every row j, sorted and merged inclusive column ranges `(j, i_first, i_last)`, in
/// increasing (j, i) order.
///
/// A convex polygon meets a row of cell centres in one run of cells; the run's ends come
/// from the polygon's edges crossing the row's centre line y = (j + ½)·cell and are then
/// settled with the same inside test a cell-by-cell count uses, so the runs hold exactly
/// the cells such a count would (this is the raster of the module docs). Memory and time
/// grow with the rows the polygons span, not with their cells: the debris of a
/// seven-story building at centimetre cells would otherwise be 10⁸ cells.
fn row_runs(polys: &[&Vec<[f64; 2]>], cell: f64) -> Vec<(i64, i64, i64)> {
    let mut runs: Vec<(i64, i64, i64)> = Vec::new();
    for p in polys {
        if p.len() < 3 {
            continue;
        }
        let (lo, hi) = bbox(p);
        let (i0, i1) = ((lo[0] / cell).floor() as i64, (hi[0] / cell).ceil() as i64);
        let (j0, j1) = ((lo[1] / cell).floor() as i64, (hi[1] / cell).ceil() as i64);
        for j in j0..=j1 {
            let y = (j as f64 + 0.5) * cell;
            let Some((xa, xb)) = chord(p, y) else {
                continue;
            };
            let centre = |i: i64| (i as f64 + 0.5) * cell;
            let inside_i = |i: i64| inside(p, centre(i), y);
            // First guess from the chord, clamped to the bounding box's columns.
            let mut a = ((xa / cell - 0.5).ceil() as i64).clamp(i0, i1);
            let mut b = ((xb / cell - 0.5).floor() as i64).clamp(i0, i1);
            // Settle both ends with the inside test itself.
            while a > i0 && inside_i(a - 1) {
                a -= 1;
            }
            while a <= i1 && !inside_i(a) {
                a += 1;
            }
            if a > i1 {
                continue;
            }
            b = b.max(a);
            while b < i1 && inside_i(b + 1) {
                b += 1;
            }
            while b > a && !inside_i(b) {
                b -= 1;
            }
            runs.push((j, a, b));
        }
    }
    runs.sort_unstable();
    let mut merged: Vec<(i64, i64, i64)> = Vec::with_capacity(runs.len());
    for (j, a, b) in runs {
        match merged.last_mut() {
            Some(last) if last.0 == j && a <= last.2 + 1 => last.2 = last.2.max(b),
            _ => merged.push((j, a, b)),
        }
    }
    merged
}

/// The x-extent of the convex polygon `p` (counter-clockwise) on the line y = `y`, or
/// `None` if the line misses it: the intersection of the edges' half-planes, each edge
/// a→b bounding x through (b_x − a_x)(y − a_y) − (b_y − a_y)(x − a_x) ≥ 0.
fn chord(p: &[[f64; 2]], y: f64) -> Option<(f64, f64)> {
    let (mut xa, mut xb) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..p.len() {
        let a = p[k];
        let b = p[(k + 1) % p.len()];
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let c = dx * (y - a[1]);
        if dy > 0.0 {
            xb = xb.min(a[0] + c / dy);
        } else if dy < 0.0 {
            xa = xa.max(a[0] + c / dy);
        } else if c < 0.0 {
            return None;
        }
    }
    (xa <= xb).then_some((xa, xb))
}

/// Number of cells in row runs.
fn run_cells(runs: &[(i64, i64, i64)]) -> usize {
    runs.iter().map(|&(_, a, b)| (b - a + 1) as usize).sum()
}

/// Plan area of the union of `polys`, m².
pub fn union_area(polys: &[&Vec<[f64; 2]>]) -> f64 {
    if polys.is_empty() {
        return 0.0;
    }
    let cell = cell_of(polys);
    run_cells(&row_runs(polys, cell)) as f64 * cell * cell
}

/// Area of (∪ a) ∩ (∪ b), m².
pub fn intersection_area(a: &[&Vec<[f64; 2]>], b: &[&Vec<[f64; 2]>]) -> f64 {
    if a.is_empty() || b.is_empty() {
        return 0.0;
    }
    let all: Vec<&Vec<[f64; 2]>> = a.iter().chain(b.iter()).copied().collect();
    let cell = cell_of(&all);
    let (ra, rb) = (row_runs(a, cell), row_runs(b, cell));
    // Both lists are sorted by (row, first column) and disjoint within a row: walk them
    // together, counting the overlap of every pair of runs of the same row.
    let (mut i, mut k, mut n) = (0, 0, 0usize);
    while i < ra.len() && k < rb.len() {
        let ((ja, a0, a1), (jb, b0, b1)) = (ra[i], rb[k]);
        if ja != jb {
            if ja < jb {
                i += 1;
            } else {
                k += 1;
            }
            continue;
        }
        let (lo, hi) = (a0.max(b0), a1.min(b1));
        if lo <= hi {
            n += (hi - lo + 1) as usize;
        }
        if a1 < b1 {
            i += 1;
        } else {
            k += 1;
        }
    }
    n as f64 * cell * cell
}

/// Rounds to 6 decimals (and −0 to 0), as every number of `summary.json`.
pub(crate) fn r6(x: f64) -> f64 {
    (x * 1e6).round() / 1e6 + 0.0
}

/// The floors: the active slab bodies grouped by their undeformed centre height (mm), bottom
/// up.
fn slab_floors(bodies: &[Body]) -> BTreeMap<i64, Vec<usize>> {
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
fn mass_centroid(bodies: &[Body], ids: &[usize], at: impl Fn(usize) -> [f64; 3]) -> [f64; 3] {
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
fn base_level(bodies: &[Body]) -> f64 {
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
/// hybrid and a physics-only run (docs/handoff.md, "The FE's own collapse and ruin"). Floors as in
/// [`ruin_measures`] (slab bodies by undeformed height, mass-weighted centroids); the base
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

fn floor_index(list: &[(i64, Vec<usize>)], z: i64) -> usize {
    list.iter().position(|(k, _)| *k == z).map_or(0, |i| i + 1)
}

/// Settle-phase energy rises larger than this share of the initial potential energy fail
/// the check of docs/ruin-numerics.md.
pub(crate) const SETTLE_RISE_LIMIT: f64 = 1e-3;

/// The energy ledger's summary (docs/ruin-numerics.md): start and end energies, ground
/// work, damping, dissipated (J); the settle phase's largest rise of the mechanical energy
/// between two frames (t ≥ the record's end, ground still) against
/// [`SETTLE_RISE_LIMIT`] × the undeformed building's potential energy; the fastest body
/// against √(v_Tc,max² + 2·g·H) + the record's peak ground speed (m/s). `None` without
/// frames.
pub(crate) fn energy_summary(
    bodies: &[Body],
    ground: &GroundHistory,
    r: &RuinResult,
) -> Option<EnergySummary> {
    let l = &r.ledger;
    let (first, last) = (r.frames.first()?, r.frames.last()?);
    let (e0, e1) = (&first.energy, &last.energy);
    let motion_end = ground.end_time_s();
    let mut rise = (0.0_f64, None::<f64>);
    let mut settle_frames = 0usize;
    for w in r.frames.windows(2) {
        if w[0].time_s < motion_end - 1e-9 {
            continue;
        }
        settle_frames += 1;
        let d = w[1].energy.mechanical_j() - w[0].energy.mechanical_j();
        if d > rise.0 {
            rise = (d, Some(w[1].time_s));
        }
    }
    let peak_ground = ground
        .vel
        .iter()
        .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
        .fold(0.0, f64::max);
    let bound = (l.start_max_speed_mps.powi(2) + 2.0 * l.gravity_mps2 * l.model_height_m).sqrt()
        + peak_ground;
    let ratio = if l.initial_potential_j > 0.0 {
        rise.0 / l.initial_potential_j
    } else {
        0.0
    };
    Some(EnergySummary {
        initial_potential_j: r6(l.initial_potential_j),
        start: StartEnergy {
            kinetic_j: r6(e0.kinetic_translational_j + e0.kinetic_rotational_j),
            potential_j: r6(e0.potential_j),
        },
        end: EndEnergy {
            kinetic_j: r6(e1.kinetic_translational_j + e1.kinetic_rotational_j),
            potential_j: r6(e1.potential_j),
            ground_work_j: r6(e1.ground_work_j),
            damping_j: r6(e1.damping_j),
            dissipated_j: r6(e1.dissipated_j(e0)),
        },
        injected_j: r6(l.injected_j),
        max_substep_injection_j: r6(l.max_injection.0),
        max_substep_injection_at_s: r6(l.max_injection.1),
        settle_phase: SettlePhase {
            from_s: r6(motion_end),
            frames: settle_frames,
            max_rise_j: r6(rise.0),
            max_rise_at_s: rise.1.map(r6),
            max_rise_ratio: r6(ratio),
            limit_ratio: SETTLE_RISE_LIMIT,
            ok: ratio <= SETTLE_RISE_LIMIT,
        },
        speed: SpeedCheck {
            max_mps: r6(l.max_speed_mps),
            max_body: l.max_speed_at.map(|(i, _)| bodies[i].id.name()),
            max_at_s: l.max_speed_at.map(|(_, t)| r6(t)),
            start_max_mps: r6(l.start_max_speed_mps),
            peak_ground_mps: r6(peak_ground),
            bound_mps: r6(bound),
            ok: l.max_speed_mps <= bound,
        },
    })
}

/// The dynamic body with the largest instantaneous point speed at the end (`None` without
/// dynamic bodies).
pub(crate) fn instantaneous_at_end(bodies: &[Body], r: &RuinResult) -> Option<UnsettledBody> {
    r.ledger
        .final_instantaneous_speeds_mps
        .iter()
        .enumerate()
        .filter(|(i, _)| !bodies[*i].passive)
        .fold(None, |best: Option<(usize, f64)>, (i, v)| match best {
            Some((_, b)) if b >= *v => best,
            _ => Some((i, *v)),
        })
        .map(|(i, v)| UnsettledBody {
            body: bodies[i].id.name(),
            speed_mps: r6(v),
        })
}

/// The bodies not at rest at the end (name and point speed relative to the ground, m/s),
/// in body order.
pub(crate) fn unsettled(bodies: &[Body], r: &RuinResult) -> Vec<UnsettledBody> {
    r.at_rest
        .iter()
        .enumerate()
        .filter(|(_, ok)| !**ok)
        .map(|(i, _)| UnsettledBody {
            body: bodies[i].id.name(),
            speed_mps: r6(r.ledger.final_point_speeds_mps[i]),
        })
        .collect()
}

/// `summary.json` as a type: what the run writer serialises and every reader (the run
/// folder, `fem2rbd plot`, study collection, tests) deserialises. Field by field with units
/// in docs/scenario-format.md "Outputs". The file is written through a
/// [`serde_json::Value`], whose keys are ordered by name, so the bytes do not depend on the
/// field order here; numbers are rounded to 6 decimals (times 4 in `tc_detail`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    /// `hybrid`, `physics` or `fe`.
    pub mode: Mode,
    /// Collapse moment Tc, s (`None`: no collapse, or the physics mode).
    pub tc_s: Option<f64>,
    /// Why the FE stage ended.
    pub tc_reason: TcKind,
    /// The reason in words (criterion and values, or the diverged step).
    pub tc_detail: String,
    /// End time of the FE stage, s (`None` in the physics mode).
    pub fe_end_s: Option<f64>,
    /// Geometric scale of the model against its prototype (the model's `scale`; absent in
    /// run folders written before it was recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f64>,
    /// Active bodies.
    pub bodies: usize,
    /// Passive foundation blocks.
    pub foundation_blocks: usize,
    /// FE keyframes (25 fps up to Tc).
    pub keyframes_fe: usize,
    /// The ruin stage (absent when none ran).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ruin_stage: Option<RuinStageSummary>,
    /// Connection states at the end of the ruin stage (absent when none ran).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub connections: Option<ConnectionCounts>,
    /// Geometric measures of the ruins (module docs).
    pub ruins: RuinMeasures,
    /// FE-only runs: the FE's state where its bodies would first touch ([`first_contact`])
    /// and its ruin measures there (absent in runs with a ruin stage, or when no frame
    /// gets there).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fe_first_contact: Option<FeFirstContact>,
    /// The floors when the lowest floor is first 70 % of its height down ([`floors_down`];
    /// absent if it never gets there).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub floors_down: Option<FloorsDown>,
    /// Wall times, s (only with timing on: not byte-stable).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_time_s: Option<WallTimes>,
    /// The model's values outside their plausible ranges that the run accepted with
    /// `--allow-unusual` (absent when there are none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub unusual_values: Vec<String>,
}

/// `floors_down` ([`floors_down`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FloorsDown {
    /// The share of the lowest floor's height (0.7).
    pub share: f64,
    /// Time of the frame, s.
    pub t_s: f64,
    /// Each floor's drop, bottom up, m.
    pub floor_drops_m: Vec<f64>,
    /// Plan distance of each floor from the one below (floors 2–1, 3–2, …), m.
    pub story_offsets_m: Vec<f64>,
    /// The first story folds and the stories above come down whole.
    pub stories_above_whole: bool,
}

/// `fe_first_contact`: where the FE alone stops describing the building (a model without
/// contact), and the ruin measures of its bodies there.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FeFirstContact {
    /// Time of the keyframe, s.
    pub t_s: f64,
    /// What touches (`Slab:1:85 reaches the ground`, `floor 2 comes down onto floor 1`).
    pub detail: String,
    /// The ruin measures of the bodies at that keyframe.
    pub ruins: RuinMeasures,
}

/// `tc_reason`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TcKind {
    /// The collapse criterion was met.
    Criterion,
    /// A step did not converge first: hand-off at the last converged step.
    FeDiverged,
    /// The FE stage ended without collapse.
    NoCollapse,
    /// No FE stage (physics mode).
    PhysicsOnly,
}

impl TcKind {
    /// The name written in the file.
    pub fn name(self) -> &'static str {
        match self {
            TcKind::Criterion => "criterion",
            TcKind::FeDiverged => "fe_diverged",
            TcKind::NoCollapse => "no_collapse",
            TcKind::PhysicsOnly => "physics_only",
        }
    }
}

/// `ruin_stage`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RuinStageSummary {
    /// Start time (Tc, or 0), s.
    pub start_s: f64,
    /// End time, s.
    pub end_s: f64,
    /// Why it stopped.
    pub stop: RuinStop,
    /// Frames (25 fps), the start included.
    pub frames: usize,
    /// Bodies at rest at the end.
    pub bodies_at_rest: usize,
    /// Deepest penetration after the first frame, m.
    pub first_frame_penetration_m: f64,
    /// Deepest penetration at the end of any frame, m.
    pub max_penetration_m: f64,
    /// The energy ledger (`None` without frames).
    pub energy: Option<EnergySummary>,
    /// Bodies not at rest at the end, in body order.
    pub unsettled_bodies: Vec<UnsettledBody>,
    /// How the rest test measured point speeds (`frame_mean`, `instantaneous`;
    /// `crate::ruin::rest::RestSpeed`); absent in run folders of versions without it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rest_speed: Option<RestSpeed>,
    /// The dynamic body with the largest point speed from its velocities at the end, and
    /// that speed (m/s): the solver's substep chatter, which the frame-mean test leaves out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub instantaneous_at_end: Option<UnsettledBody>,
}

/// One body not at rest at the end.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct UnsettledBody {
    /// Body name.
    pub body: String,
    /// Point speed relative to the ground, m/s.
    pub speed_mps: f64,
}

/// `connections`: states at the end of the ruin stage.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct ConnectionCounts {
    /// All connections.
    pub total: usize,
    /// Elastic (intact).
    pub intact: usize,
    /// Plastic.
    pub plastic: usize,
    /// Broken.
    pub broken: usize,
}

/// `ruin_stage.energy` (docs/ruin-numerics.md), J unless named otherwise.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EnergySummary {
    /// Potential energy of the undeformed building above the ground's top.
    pub initial_potential_j: f64,
    /// Energies at the start of the ruin stage.
    pub start: StartEnergy,
    /// Energies at the end and the ledger's totals.
    pub end: EndEnergy,
    /// Added by the solver over the stage.
    pub injected_j: f64,
    /// Largest addition in one substep.
    pub max_substep_injection_j: f64,
    /// Its time, s.
    pub max_substep_injection_at_s: f64,
    /// The settle phase's energy check.
    pub settle_phase: SettlePhase,
    /// The speed check.
    pub speed: SpeedCheck,
}

/// `energy.start`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StartEnergy {
    /// Kinetic (translational + rotational).
    pub kinetic_j: f64,
    /// Potential.
    pub potential_j: f64,
}

/// `energy.end`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EndEnergy {
    /// Kinetic (translational + rotational).
    pub kinetic_j: f64,
    /// Potential.
    pub potential_j: f64,
    /// Work done by the moving ground since the start.
    pub ground_work_j: f64,
    /// Taken out by Bullet's velocity damping since the start.
    pub damping_j: f64,
    /// E(start) + W_ground − E(end).
    pub dissipated_j: f64,
}

/// `energy.settle_phase`: the largest rise of the mechanical energy between two frames
/// after the record's end, against [`SETTLE_RISE_LIMIT`] × the initial potential energy.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SettlePhase {
    /// Start of the settle phase (end of the record), s.
    pub from_s: f64,
    /// Frames in it.
    pub frames: usize,
    /// Largest rise.
    pub max_rise_j: f64,
    /// Its time, s (`None`: no rise).
    pub max_rise_at_s: Option<f64>,
    /// Largest rise / initial potential energy.
    pub max_rise_ratio: f64,
    /// [`SETTLE_RISE_LIMIT`].
    pub limit_ratio: f64,
    /// `max_rise_ratio <= limit_ratio`.
    pub ok: bool,
}

/// `energy.speed`: the fastest body against √(v_Tc,max² + 2·g·H) + the peak ground speed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpeedCheck {
    /// Largest centre speed of any dynamic body, m/s.
    pub max_mps: f64,
    /// Its body.
    pub max_body: Option<String>,
    /// Its time, s.
    pub max_at_s: Option<f64>,
    /// Largest centre speed at the start, m/s.
    pub start_max_mps: f64,
    /// Peak ground speed of the record, m/s.
    pub peak_ground_mps: f64,
    /// The bound, m/s.
    pub bound_mps: f64,
    /// `max_mps <= bound_mps`.
    pub ok: bool,
}

/// `wall_time_s` (s).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WallTimes {
    /// FE stage.
    pub fe: f64,
    /// Ruin stage (build + run).
    pub physics: f64,
    /// Inside Bullet's step.
    pub physics_in_bullet: f64,
    /// `physics_in_bullet / physics`.
    pub physics_bullet_share: f64,
}

/// `ruins`: geometric measures of the final state (module docs), m and m². Measures of an
/// empty set of bodies are not finite and written as `null` (read back as NaN).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RuinMeasures {
    /// Plan AABB of the undeformed active bodies.
    pub original_footprint_m: Footprint,
    /// How far the debris reaches beyond it on each side.
    pub extent_beyond_footprint_m: Extent,
    /// Plan area of the union of the final projections.
    #[serde(deserialize_with = "nan_if_null")]
    pub debris_footprint_area_m2: f64,
    /// Area of the original footprint.
    #[serde(deserialize_with = "nan_if_null")]
    pub original_footprint_area_m2: f64,
    /// Highest final corner above the ground's top.
    #[serde(deserialize_with = "nan_if_null")]
    pub max_debris_height_m: f64,
    /// The floors, bottom up.
    pub floors: Vec<FloorMeasure>,
    /// Slab overlap of consecutive floors.
    pub slab_overlap: Vec<SlabOverlap>,
    /// Bodies that end inside each other (absent in summaries of versions without it).
    #[serde(default)]
    pub interpenetration: Interpenetration,
}

/// `interpenetration`: pairs of active bodies whose final boxes overlap
/// ([`crate::ruin::separation::box_overlap`], the separating-axis depth), m. Bodies that
/// may not touch ([`crate::ruin::separation`]) can end inside each other; contact
/// penetrations are millimetres.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Interpenetration {
    /// Pairs overlapping by more than [`INTERPENETRATION_COUNTED_M`].
    pub pairs_over_10mm: usize,
    /// The deepest overlap, m (0 if none).
    pub deepest_m: f64,
    /// The two bodies of the deepest overlap.
    pub deepest_pair: Option<[String; 2]>,
}

/// Overlap depth from which a pair counts in [`Interpenetration::pairs_over_10mm`], m.
pub const INTERPENETRATION_COUNTED_M: f64 = 0.01;

/// `original_footprint_m`: [min, max] along x and y.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Footprint {
    /// x range.
    #[serde(deserialize_with = "nan_if_null_2")]
    pub x: [f64; 2],
    /// y range.
    #[serde(deserialize_with = "nan_if_null_2")]
    pub y: [f64; 2],
}

/// `extent_beyond_footprint_m`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Extent {
    /// Beyond the −x side.
    #[serde(deserialize_with = "nan_if_null")]
    pub x_minus: f64,
    /// Beyond the +x side.
    #[serde(deserialize_with = "nan_if_null")]
    pub x_plus: f64,
    /// Beyond the −y side.
    #[serde(deserialize_with = "nan_if_null")]
    pub y_minus: f64,
    /// Beyond the +y side.
    #[serde(deserialize_with = "nan_if_null")]
    pub y_plus: f64,
    /// The largest of the four.
    #[serde(deserialize_with = "nan_if_null")]
    pub max: f64,
}

/// One floor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FloorMeasure {
    /// Floor number from 1 (bottom).
    pub floor: usize,
    /// Undeformed level of its slab centres.
    pub level_m: f64,
    /// Slab bodies.
    pub slabs: usize,
    /// Displacement of the mass-weighted slab centroid.
    pub centroid_displacement_m: [f64; 3],
    /// Its horizontal length.
    pub horizontal_offset_m: f64,
}

/// The pancake measure of two consecutive floors.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SlabOverlap {
    /// Lower and upper floor numbers.
    pub floors: [usize; 2],
    /// Area of the intersection of their final slab projections.
    pub overlap_area_m2: f64,
    /// The upper floor's undeformed slab area.
    pub upper_slab_area_m2: f64,
    /// Their ratio (1 = fully stacked, 0 = no overlap).
    pub overlap_ratio: f64,
}

fn nan_if_null<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

fn nan_if_null_2<'de, D: serde::Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
    let v = <[Option<f64>; 2]>::deserialize(d)?;
    Ok(v.map(|x| x.unwrap_or(f64::NAN)))
}

impl RunSummary {
    /// The `summary.json` text: pretty JSON (keys ordered by name) and a newline.
    pub fn to_json(&self) -> serde_json::Result<String> {
        Ok(serde_json::to_string_pretty(&serde_json::to_value(self)?)? + "\n")
    }
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

    /// The cell-by-cell count the row runs replace: every cell of every polygon's bounding
    /// box whose centre passes the inside test, deduplicated.
    fn brute_force_cells(polys: &[&Vec<[f64; 2]>], cell: f64) -> Vec<(i64, i64)> {
        let mut out = Vec::new();
        for p in polys {
            if p.len() < 3 {
                continue;
            }
            let (lo, hi) = bbox(p);
            let (i0, i1) = ((lo[0] / cell).floor() as i64, (hi[0] / cell).ceil() as i64);
            let (j0, j1) = ((lo[1] / cell).floor() as i64, (hi[1] / cell).ceil() as i64);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    if inside(p, (i as f64 + 0.5) * cell, (j as f64 + 0.5) * cell) {
                        out.push((i, j));
                    }
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Rotated, overlapping boxes (a fixed linear congruential sequence), some touching
    /// cell centres exactly (axis-aligned on the grid): the row runs hold exactly the
    /// cells of the cell-by-cell count, for unions and intersections.
    #[test]
    fn row_runs_count_the_same_cells_as_the_cell_by_cell_raster() {
        let mut seed = 12345u64;
        let mut next = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut polys: Vec<Vec<[f64; 2]>> = Vec::new();
        for k in 0..60 {
            let he = [0.05 + 2.0 * next(), 0.05 + 0.5 * next(), 0.2];
            let angle = if k % 5 == 0 {
                0.0
            } else {
                std::f64::consts::TAU * next()
            };
            let pose = Pose {
                position: [10.0 * next() - 5.0, 10.0 * next() - 5.0, 0.0],
                orientation: [(angle / 2.0).cos(), 0.0, 0.0, (angle / 2.0).sin()],
            };
            polys.push(projection(&pose, he));
        }
        // Grid-aligned squares whose edges pass through cell centres.
        polys.push(vec![
            [0.025, 0.025],
            [1.025, 0.025],
            [1.025, 1.025],
            [0.025, 1.025],
        ]);
        polys.push(vec![
            [0.525, 0.025],
            [2.025, 0.025],
            [2.025, 0.525],
            [0.525, 0.525],
        ]);
        let all: Vec<&Vec<[f64; 2]>> = polys.iter().collect();
        let (a, b) = all.split_at(30);
        for cell in [0.05, 0.0137, cell_of(&all)] {
            let brute = brute_force_cells(&all, cell);
            let runs = row_runs(&all, cell);
            assert_eq!(run_cells(&runs), brute.len(), "cell {cell}");
            let expanded: Vec<(i64, i64)> = runs
                .iter()
                .flat_map(|&(j, a, b)| (a..=b).map(move |i| (i, j)))
                .collect();
            let mut sorted = expanded.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, brute, "cell {cell}");
            let (ba, bb) = (brute_force_cells(a, cell), brute_force_cells(b, cell));
            let n_int = ba.iter().filter(|c| bb.binary_search(c).is_ok()).count();
            let (ra, rb) = (row_runs(a, cell), row_runs(b, cell));
            let mut n = 0usize;
            for &(j, a0, a1) in &ra {
                for &(jb, b0, b1) in &rb {
                    if j == jb && a0.max(b0) <= a1.min(b1) {
                        n += (a1.min(b1) - a0.max(b0) + 1) as usize;
                    }
                }
            }
            assert_eq!(n, n_int, "cell {cell}");
            assert!(
                n_int > 0 && brute.len() > 1000,
                "the case must exercise overlaps"
            );
        }
        let cell = cell_of(&all);
        let n_int = {
            let (ba, bb) = (brute_force_cells(a, cell), brute_force_cells(b, cell));
            ba.iter().filter(|c| bb.binary_search(c).is_ok()).count()
        };
        assert_eq!(intersection_area(a, b), n_int as f64 * cell * cell);
    }
}
