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
use crate::physics::Pose;
use crate::pipeline::{RunRecord, TcReason};
use crate::ruin::connection::ConnectionState;
use crate::ruin::stage::to_isometry;
use nalgebra::{Point3, Vector3};
use serde_json::{json, Value};
use std::collections::BTreeMap;

/// Raster resolution of the area measures: cells across the smallest projection side.
pub const CELLS_PER_SIDE: f64 = 20.0;

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

/// The sorted, deduplicated cells (i, j) of side `cell` whose centres lie in the union.
fn cells(polys: &[&Vec<[f64; 2]>], cell: f64) -> Vec<(i64, i64)> {
    let mut out = Vec::new();
    for p in polys {
        if p.len() < 3 {
            continue;
        }
        let (lo, hi) = bbox(p);
        let (i0, i1) = ((lo[0] / cell).floor() as i64, (hi[0] / cell).ceil() as i64);
        let (j0, j1) = ((lo[1] / cell).floor() as i64, (hi[1] / cell).ceil() as i64);
        for j in j0..=j1 {
            let y = (j as f64 + 0.5) * cell;
            for i in i0..=i1 {
                if inside(p, (i as f64 + 0.5) * cell, y) {
                    out.push((i, j));
                }
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// Plan area of the union of `polys`, m².
pub fn union_area(polys: &[&Vec<[f64; 2]>]) -> f64 {
    if polys.is_empty() {
        return 0.0;
    }
    let cell = cell_of(polys);
    cells(polys, cell).len() as f64 * cell * cell
}

/// Area of (∪ a) ∩ (∪ b), m².
pub fn intersection_area(a: &[&Vec<[f64; 2]>], b: &[&Vec<[f64; 2]>]) -> f64 {
    if a.is_empty() || b.is_empty() {
        return 0.0;
    }
    let all: Vec<&Vec<[f64; 2]>> = a.iter().chain(b.iter()).copied().collect();
    let cell = cell_of(&all);
    let (ca, cb) = (cells(a, cell), cells(b, cell));
    let (mut i, mut j, mut n) = (0, 0, 0usize);
    while i < ca.len() && j < cb.len() {
        match ca[i].cmp(&cb[j]) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => {
                n += 1;
                i += 1;
                j += 1;
            }
        }
    }
    n as f64 * cell * cell
}

fn r6(x: f64) -> f64 {
    (x * 1e6).round() / 1e6 + 0.0
}

/// The ruin measures of a record (module docs), as JSON.
pub fn ruin_measures(rec: &RunRecord) -> Value {
    let active: Vec<usize> = (0..rec.bodies.len())
        .filter(|&i| !rec.bodies[i].passive)
        .collect();
    // Original footprint.
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for &i in &active {
        for c in corners(&rec.bodies[i].pose0, rec.bodies[i].half_extents) {
            for k in 0..2 {
                lo[k] = lo[k].min(c[k]);
                hi[k] = hi[k].max(c[k]);
            }
        }
    }
    let mut beyond = [0.0f64; 4];
    let mut top = f64::NEG_INFINITY;
    for &i in &active {
        for c in corners(&rec.final_poses[i], rec.bodies[i].half_extents) {
            beyond[0] = beyond[0].max(lo[0] - c[0]);
            beyond[1] = beyond[1].max(c[0] - hi[0]);
            beyond[2] = beyond[2].max(lo[1] - c[1]);
            beyond[3] = beyond[3].max(c[1] - hi[1]);
            top = top.max(c[2]);
        }
    }
    let base_z = rec
        .bodies
        .iter()
        .filter(|b| b.passive)
        .map(|b| b.pose0.position[2] + b.half_extents[2])
        .fold(f64::NAN, f64::max);
    let base_z = if base_z.is_nan() {
        active
            .iter()
            .flat_map(|&i| corners(&rec.bodies[i].pose0, rec.bodies[i].half_extents))
            .map(|c| c[2])
            .fold(f64::INFINITY, f64::min)
    } else {
        base_z
    };
    let t_end = rec
        .ruin
        .as_ref()
        .map(|r| r.end_time_s)
        .or(rec.fe_end_s)
        .unwrap_or(0.0);
    let ground_z = rec.ground.ground_state_at(t_end).0[2];
    let final_proj: Vec<Vec<[f64; 2]>> = (0..rec.bodies.len())
        .map(|i| projection(&rec.final_poses[i], rec.bodies[i].half_extents))
        .collect();
    let init_proj: Vec<Vec<[f64; 2]>> = (0..rec.bodies.len())
        .map(|i| projection(&rec.bodies[i].pose0, rec.bodies[i].half_extents))
        .collect();
    let debris: Vec<&Vec<[f64; 2]>> = active.iter().map(|&i| &final_proj[i]).collect();
    // Floors.
    let mut floors: BTreeMap<i64, Vec<usize>> = BTreeMap::new();
    for &i in &active {
        if rec.bodies[i].kind == Some(crate::mapping::Role::Slab) {
            let z = (rec.bodies[i].pose0.position[2] * 1000.0).round() as i64;
            floors.entry(z).or_default().push(i);
        }
    }
    let floor_list: Vec<(i64, Vec<usize>)> = floors.into_iter().collect();
    let mut floor_json = Vec::new();
    for (n, (z, ids)) in floor_list.iter().enumerate() {
        let m: f64 = ids.iter().map(|&i| rec.bodies[i].mass_kg).sum();
        let mut c0 = [0.0; 3];
        let mut c1 = [0.0; 3];
        for &i in ids {
            let w = rec.bodies[i].mass_kg / m;
            for k in 0..3 {
                c0[k] += w * rec.bodies[i].pose0.position[k];
                c1[k] += w * rec.final_poses[i].position[k];
            }
        }
        let d = [c1[0] - c0[0], c1[1] - c0[1], c1[2] - c0[2]];
        floor_json.push(json!({
            "floor": n + 1,
            "level_m": r6(*z as f64 / 1000.0),
            "slabs": ids.len(),
            "centroid_displacement_m": [r6(d[0]), r6(d[1]), r6(d[2])],
            "horizontal_offset_m": r6(d[0].hypot(d[1])),
        }));
    }
    let mut overlap_json = Vec::new();
    for w in floor_list.windows(2) {
        let lower: Vec<&Vec<[f64; 2]>> = w[0].1.iter().map(|&i| &final_proj[i]).collect();
        let upper: Vec<&Vec<[f64; 2]>> = w[1].1.iter().map(|&i| &final_proj[i]).collect();
        let upper0: Vec<&Vec<[f64; 2]>> = w[1].1.iter().map(|&i| &init_proj[i]).collect();
        let a_int = intersection_area(&lower, &upper);
        let a0 = union_area(&upper0);
        overlap_json.push(json!({
            "floors": [floor_index(&floor_list, w[0].0), floor_index(&floor_list, w[1].0)],
            "overlap_area_m2": r6(a_int),
            "upper_slab_area_m2": r6(a0),
            "overlap_ratio": r6(if a0 > 0.0 { a_int / a0 } else { 0.0 }),
        }));
    }
    json!({
        "original_footprint_m": {"x": [r6(lo[0]), r6(hi[0])], "y": [r6(lo[1]), r6(hi[1])]},
        "extent_beyond_footprint_m": {
            "x_minus": r6(beyond[0]), "x_plus": r6(beyond[1]),
            "y_minus": r6(beyond[2]), "y_plus": r6(beyond[3]),
            "max": r6(beyond.iter().copied().fold(0.0, f64::max)),
        },
        "debris_footprint_area_m2": r6(union_area(&debris)),
        "original_footprint_area_m2": r6((hi[0] - lo[0]) * (hi[1] - lo[1])),
        "max_debris_height_m": r6(top - (base_z + ground_z)),
        "floors": floor_json,
        "slab_overlap": overlap_json,
    })
}

fn floor_index(list: &[(i64, Vec<usize>)], z: i64) -> usize {
    list.iter().position(|(k, _)| *k == z).map_or(0, |i| i + 1)
}

/// Settle-phase energy rises larger than this share of the initial potential energy fail
/// the check of docs/ruin-numerics.md.
pub const SETTLE_RISE_LIMIT: f64 = 1e-3;

/// The energy ledger's summary (docs/ruin-numerics.md): start and end energies, ground
/// work, damping, dissipated (J); the settle phase's largest rise of the mechanical energy
/// between two frames (t ≥ the record's end, ground still) against
/// [`SETTLE_RISE_LIMIT`] × the undeformed building's potential energy; the fastest body
/// against √(v_Tc,max² + 2·g·H) + the record's peak ground speed (m/s).
pub fn energy_summary(rec: &RunRecord, r: &crate::ruin::stage::RuinResult) -> Value {
    let l = &r.ledger;
    let (Some(first), Some(last)) = (r.frames.first(), r.frames.last()) else {
        return Value::Null;
    };
    let (e0, e1) = (&first.energy, &last.energy);
    let motion_end = rec.ground.end_time_s();
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
    let peak_ground = rec
        .ground
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
    json!({
        "initial_potential_j": r6(l.initial_potential_j),
        "start": {"kinetic_j": r6(e0.kinetic_translational_j + e0.kinetic_rotational_j), "potential_j": r6(e0.potential_j)},
        "end": {
            "kinetic_j": r6(e1.kinetic_translational_j + e1.kinetic_rotational_j),
            "potential_j": r6(e1.potential_j),
            "ground_work_j": r6(e1.ground_work_j),
            "damping_j": r6(e1.damping_j),
            "dissipated_j": r6(e1.dissipated_j(e0)),
        },
        "injected_j": r6(l.injected_j),
        "max_substep_injection_j": r6(l.max_injection.0),
        "max_substep_injection_at_s": r6(l.max_injection.1),
        "settle_phase": {
            "from_s": r6(motion_end),
            "frames": settle_frames,
            "max_rise_j": r6(rise.0),
            "max_rise_at_s": rise.1.map(r6),
            "max_rise_ratio": r6(ratio),
            "limit_ratio": SETTLE_RISE_LIMIT,
            "ok": ratio <= SETTLE_RISE_LIMIT,
        },
        "speed": {
            "max_mps": r6(l.max_speed_mps),
            "max_body": l.max_speed_at.map(|(i, _)| rec.bodies[i].id.name()),
            "max_at_s": l.max_speed_at.map(|(_, t)| r6(t)),
            "start_max_mps": r6(l.start_max_speed_mps),
            "peak_ground_mps": r6(peak_ground),
            "bound_mps": r6(bound),
            "ok": l.max_speed_mps <= bound,
        },
    })
}

/// The bodies not at rest at the end (name and point speed relative to the ground, m/s),
/// in body order.
pub fn unsettled(rec: &RunRecord, r: &crate::ruin::stage::RuinResult) -> Value {
    Value::Array(
        r.at_rest
            .iter()
            .enumerate()
            .filter(|(_, ok)| !**ok)
            .map(|(i, _)| {
                json!({"body": rec.bodies[i].id.name(), "speed_mps": r6(r.ledger.final_point_speeds_mps[i])})
            })
            .collect(),
    )
}

/// The whole `summary.json` value. `timing` = include the wall times (not byte-stable).
pub fn summary(rec: &RunRecord, timing: bool) -> Value {
    let (reason, detail) = match &rec.tc_reason {
        TcReason::Criterion(s) => ("criterion", s.clone()),
        TcReason::Diverged(s) => ("fe_diverged", s.clone()),
        TcReason::NoCollapse => (
            "no_collapse",
            format!(
                "the criterion was not met before the FE stage ended at t = {:.4} s",
                rec.fe_end_s.unwrap_or(0.0)
            ),
        ),
        TcReason::PhysicsOnly => (
            "physics_only",
            "no FE stage; the ruin stage starts at t = 0".into(),
        ),
    };
    let mut v = json!({
        "mode": rec.mode.name(),
        "tc_s": rec.tc_s.map(r6),
        "tc_reason": reason,
        "tc_detail": detail,
        "fe_end_s": rec.fe_end_s.map(r6),
        "bodies": rec.bodies.iter().filter(|b| !b.passive).count(),
        "foundation_blocks": rec.bodies.iter().filter(|b| b.passive).count(),
        "keyframes_fe": rec.fe_frames.len(),
    });
    let m = v.as_object_mut().expect("object");
    if let Some(r) = &rec.ruin {
        let mut counts = [0usize; 3];
        for c in &r.connections {
            counts[match c.state {
                ConnectionState::Elastic => 0,
                ConnectionState::Plastic => 1,
                ConnectionState::Broken => 2,
            }] += 1;
        }
        m.insert(
            "ruin_stage".into(),
            json!({
                "start_s": r6(rec.tc_s.unwrap_or(0.0)),
                "end_s": r6(r.end_time_s),
                "stop": r.stop.name(),
                "frames": r.frames.len(),
                "bodies_at_rest": r.at_rest.iter().filter(|b| **b).count(),
                "first_frame_penetration_m": r6(r.first_frame_penetration_m),
                "max_penetration_m": r6(r.max_penetration_m),
                "energy": energy_summary(rec, r),
                "unsettled_bodies": unsettled(rec, r),
            }),
        );
        m.insert(
            "connections".into(),
            json!({"total": r.connections.len(), "intact": counts[0], "plastic": counts[1], "broken": counts[2]}),
        );
    }
    m.insert("ruins".into(), ruin_measures(rec));
    if timing {
        let fe = rec.fe_wall.as_secs_f64();
        let ph = rec.ruin_wall.as_secs_f64();
        let share = if ph > 0.0 {
            rec.ruin_in_bullet.as_secs_f64() / ph
        } else {
            0.0
        };
        m.insert(
            "wall_time_s".into(),
            json!({"fe": fe, "physics": ph, "physics_in_bullet": rec.ruin_in_bullet.as_secs_f64(), "physics_bullet_share": share}),
        );
    }
    v
}
