//! The debris phase against pybullet 3.2.7: 30 boxes of a two-storey
//! frame, swayed and tilted as at a collapse moment, with linear and angular velocities
//! and **no** constraints, fall onto a still ground for 3 s — once in fem2rbd's ruin
//! stage (`RuinStage` with `connect: false`, the physics preset `WorldSettings::pybullet()`,
//! 50 iterations, 200 substeps/s, BCB body settings) and once in pybullet with the same
//! settings (`tests/pybullet/debris.py`: useMaximalCoordinates=True, same margins, damping,
//! friction, no sleeping, deterministic overlapping pairs). Poses are compared after the
//! first frame (0.04 s), at 0.2 s and at the end (3 s); the bounds are asserted.
//!
//! What agrees and what cannot (measured, see the report): both sides run the same
//! Bullet solver, but pybullet's world is a `btMultiBodyDynamicsWorld` and ours a plain
//! `btDiscreteDynamicsWorld`. With separated boxes they agree to the bit
//! (`tests/pybullet/crosscheck.py`); here the boxes start in contact as a frame at Tc does,
//! and the contact islands they form are solved slightly differently: 0 m with up to 8 of
//! these boxes, 7e-8 m after one substep from 9 on, 5e-3 m per body after the first frame
//! with all 30 (independent of margin, damping and friction, which were varied). Tumbling
//! debris amplifies that chaotically, to metres per body by 3 s. So per-body poses are
//! compared early (0.04 s, 0.2 s), and the final ruin distribution through what a ruin
//! scenario reports: the debris' mass centroid, plan extent and top height.
//! Measured: 5.3e-3 m / 8.8e-3 rad at 0.04 s, 4.2e-2 m at 0.2 s; at 3 s centroid 0.26 m,
//! plan extent 0.26 m, top 0.12 m apart, for debris that moved up to 8.4 m.
//!
//! Needs `python3` with pybullet==3.2.7 and numpy (scripts/setup.sh installs them).

use fem2rbd::bullet::{Pose, Velocity, WorldSettings};
use fem2rbd::ruin::connection::RuinSettings;
use fem2rbd::ruin::ground::GroundSpec;
use fem2rbd::ruin::stage::{to_pose, RuinStage, StageInput, StageSettings, StopRule};
use fem2rbd::ruin::BodyGeom;
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector3};
use serde_json::json;
use std::process::Command;

const DURATION_S: f64 = 3.0;
const SPS: f64 = 200.0;

fn frame_bodies() -> (Vec<BodyGeom>, Vec<f64>) {
    let mut v: Vec<(String, [f64; 3], [f64; 3])> = Vec::new();
    let (hs, col, beam, slab) = (3.0, 0.2, (0.15, 0.25), 0.06);
    for s in 0..2 {
        let z0 = s as f64 * (hs + 2.0 * slab);
        for (i, x) in [0.0, 3.0, 6.0].iter().enumerate() {
            for (j, y) in [0.0, 3.0].iter().enumerate() {
                v.push((
                    format!("col{s}{i}{j}"),
                    [*x, *y, z0 + hs / 2.0],
                    [col, col, hs / 2.0],
                ));
            }
        }
        let zb = z0 + hs - beam.1;
        for y in [0.0, 3.0] {
            for x in [1.5, 4.5] {
                v.push((
                    format!("bx{s}{x}{y}"),
                    [x, y, zb],
                    [1.5 - col, beam.0, beam.1],
                ));
            }
        }
        for x in [0.0, 3.0, 6.0] {
            v.push((
                format!("by{s}{x}"),
                [x, 1.5, zb],
                [beam.0, 1.5 - col, beam.1],
            ));
        }
        for x in [1.5, 4.5] {
            v.push((
                format!("slab{s}{x}"),
                [x, 1.5, z0 + hs + slab],
                [1.5, 1.5, slab],
            ));
        }
    }
    let bodies: Vec<BodyGeom> = v
        .into_iter()
        .map(|(name, c, he)| BodyGeom {
            name,
            group: "rc".into(),
            centre: c,
            rotation: UnitQuaternion::identity(),
            half_extents: he,
            passive: false,
        })
        .collect();
    // ρ = 2400 kg/m³ × volume.
    let masses = bodies
        .iter()
        .map(|b| 2400.0 * 8.0 * b.half_extents.iter().product::<f64>())
        .collect();
    (bodies, masses)
}

fn pose_from(row: &serde_json::Value) -> Pose {
    let r: Vec<f64> = row
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    Pose {
        position: [r[0], r[1], r[2]],
        orientation: [r[3], r[4], r[5], r[6]],
    }
}

/// Largest position (m) and orientation (rad) difference between two pose lists.
fn pose_difference(a: &[Pose], b: &[Pose]) -> (f64, f64) {
    let q = |p: &Pose| {
        let [w, x, y, z] = p.orientation;
        UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z))
    };
    a.iter()
        .zip(b)
        .fold((0.0_f64, 0.0_f64), |(dp, da), (pa, pb)| {
            let d = (Vector3::from(pa.position) - Vector3::from(pb.position)).norm();
            (dp.max(d), da.max(q(pa).angle_to(&q(pb))))
        })
}

/// Mass centroid (m), plan extent of the body centres (m, x and y) and highest centre (m).
fn distribution(poses: &[Pose], masses: &[f64]) -> ([f64; 3], [f64; 2], f64) {
    let mt: f64 = masses.iter().sum();
    let mut c = [0.0; 3];
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    let mut top = f64::NEG_INFINITY;
    for (p, m) in poses.iter().zip(masses) {
        for (cj, x) in c.iter_mut().zip(&p.position) {
            *cj += m * x / mt;
        }
        for j in 0..2 {
            lo[j] = lo[j].min(p.position[j]);
            hi[j] = hi[j].max(p.position[j]);
        }
        top = top.max(p.position[2]);
    }
    (c, [hi[0] - lo[0], hi[1] - lo[1]], top)
}

#[test]
fn debris_phase_agrees_with_pybullet() {
    let (bodies, masses) = frame_bodies();
    assert_eq!(bodies.len(), 30);
    let mut input = StageInput::rigid_only(&bodies, &masses, &[]);
    // "Tc": the frame turned rigidly about its base centre (no body penetrates another:
    // touching faces stay touching), lifted 0.12 m, each body moving on its own.
    let turn = Isometry3::from_parts(
        Translation3::new(3.0, 1.5, 0.12),
        UnitQuaternion::from_scaled_axis(Vector3::new(0.01, 0.03, 0.0)),
    ) * Isometry3::translation(-3.0, -1.5, 0.0);
    for (i, b) in bodies.iter().enumerate() {
        let z = b.centre[2];
        let k = i as f64;
        input.start_poses[i] = turn * b.pose();
        input.start_velocities[i] = Velocity {
            linear: [0.35 * z, 0.05 * (k % 3.0) - 0.05, -0.1 * z],
            angular: [0.02 * (k % 4.0), 0.1 + 0.02 * z, 0.05 * (k % 2.0)],
        };
    }
    let settings = StageSettings {
        ruin: RuinSettings {
            steps_per_second: SPS,
            solver_iterations: 50,
            ..RuinSettings::default()
        },
        world: WorldSettings::pybullet(),
        connect: false,
        ..StageSettings::bcb()
    };
    let mut stage = RuinStage::build(&input, GroundSpec::default(), &settings).unwrap();
    assert!(stage.connections().is_empty());
    let res = stage
        .run(&StopRule {
            max_time_s: DURATION_S,
            rest: None,
        })
        .unwrap();
    assert!((res.end_time_s - DURATION_S).abs() < 1e-9);
    let spf = stage.substeps_per_frame() as usize;
    // Frames compared: 1 (0.04 s), 5 (0.2 s) and the last (3 s).
    let frames = [1usize, 5, res.frames.len() - 1];

    // The same scene for pybullet.
    let b = &settings.body;
    let gp = stage.ground_rest_pose();
    let box_json = |he: [f64; 3], mass: f64, pose: &Pose, v: &Velocity, friction: f64| {
        json!({
            "half_extents": he, "mass": mass, "position": pose.position,
            "orientation": pose.orientation, "linear_velocity": v.linear,
            "angular_velocity": v.angular, "friction": friction,
            "restitution": b.restitution, "linear_damping": b.linear_damping,
            "angular_damping": b.angular_damping,
            "margin": b.margin.min(he.iter().copied().fold(f64::INFINITY, f64::min)),
        })
    };
    let scene = json!({
        "gravity": settings.world.gravity,
        "substep": stage.substep_s(),
        "solver_iterations": settings.ruin.solver_iterations,
        "report_substeps": frames.iter().map(|f| f * spf).collect::<Vec<_>>(),
        "ground": box_json(stage.ground_half_extents(), 0.0, &gp, &Velocity::default(), 1.0),
        "bodies": bodies.iter().enumerate().map(|(i, body)| box_json(
            body.half_extents, masses[i], &to_pose(&input.start_poses[i]),
            &input.start_velocities[i], b.friction)).collect::<Vec<_>>(),
    });
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("debris.json");
    std::fs::write(&path, serde_json::to_string_pretty(&scene).unwrap()).unwrap();
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/pybullet/debris.py");
    let out = Command::new("python3")
        .arg(script)
        .arg(&path)
        .output()
        .unwrap_or_else(|e| {
            panic!("cannot run python3 ({e}): install Python 3 with pybullet==3.2.7 and numpy (bash scripts/setup.sh)")
        });
    let stderr = String::from_utf8_lossy(&out.stderr);
    if out.status.code() == Some(2) {
        panic!(
            "pybullet or numpy is not installed for python3: run `bash scripts/setup.sh` \
             (or `python3 -m pip install pybullet==3.2.7 numpy`)\n{stderr}"
        );
    }
    assert!(out.status.success(), "debris.py failed:\n{stderr}");
    let theirs: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    println!("pybullet API {}", theirs["api"]);

    let mut diffs = Vec::new();
    for &f in &frames {
        let rows = theirs["poses"][(f * spf).to_string()].as_array().unwrap();
        let pb: Vec<Pose> = rows.iter().map(pose_from).collect();
        let ours = &res.frames[f].poses;
        let (dp, da) = pose_difference(ours, &pb);
        let (c0, e0, t0) = distribution(ours, &masses);
        let (c1, e1, t1) = distribution(&pb, &masses);
        let dc = (Vector3::from(c0) - Vector3::from(c1)).norm();
        let de = (e0[0] - e1[0]).abs().max((e0[1] - e1[1]).abs());
        println!(
            "t = {:.2} s: per body {dp:.3e} m / {da:.3e} rad; centroid {c0:.3?} vs {c1:.3?} \
             ({dc:.3e} m); plan extent {e0:.3?} vs {e1:.3?} ({de:.3e} m); top {t0:.3} vs {t1:.3} m",
            res.frames[f].time_s
        );
        diffs.push((dp, da, dc, de, (t0 - t1).abs()));
    }
    let moved = res
        .final_poses
        .iter()
        .zip(&input.start_poses)
        .map(|(p, s)| (Vector3::from(p.position) - s.translation.vector).norm())
        .fold(0.0, f64::max);
    println!(
        "bodies moved up to {moved:.2} m; Bullet's share of the ruin-stage wall time {:.1} %",
        100.0 * res.wall.bullet_share()
    );
    assert!(moved > 1.0, "the debris must really move (moved {moved} m)");
    // Bounds (measured values in the report / module docs, with margin).
    let (p1, a1, ..) = diffs[0];
    assert!(p1 < 1e-2 && a1 < 2e-2, "after 0.04 s: {p1} m, {a1} rad");
    let (p5, ..) = diffs[1];
    assert!(p5 < 0.1, "after 0.2 s: {p5} m");
    let (_, _, dc, de, dt) = diffs[2];
    assert!(dc < 0.5, "final centroid differs by {dc} m");
    assert!(de < 1.0, "final plan extent differs by {de} m");
    assert!(dt < 0.5, "final top differs by {dt} m");
}
