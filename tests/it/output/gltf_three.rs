//! Opens a file written by `output::gltf::write_glb` in three.js (npm `three`, pinned in
//! tests/gltf/package.json, installed by scripts/setup-node.sh): its GLTFLoader and
//! AnimationMixer play the animation, and every box's world matrix — between keyframes
//! too — must be the closed-form pose seen through the Z-up → Y-up root rotation.
//! Needs `node`; fails (does not skip) when node or three is missing.
use super::gltf_common as common;

use common::{falling_scene, ground_pose, Throw};
use fem2rbd::output::gltf::write_glb;
use serde_json::Value;
use std::path::Path;
use std::process::Command;

/// Rotation matrix (row-major) of a unit quaternion `[w, x, y, z]`.
fn rot(q: [f64; 4]) -> [[f64; 3]; 3] {
    let [w, x, y, z] = q;
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

/// Expected world matrix, column-major as three.js stores it: glTF world = Root · T · R · S
/// with Root mapping our (x, y, z) to glTF (x, z, −y).
fn world(p: [f64; 3], q: [f64; 4], h: [f64; 3]) -> [f64; 16] {
    let r = rot(q);
    let root = |v: [f64; 3]| [v[0], v[2], -v[1]];
    let mut m = [0.0; 16];
    for col in 0..3 {
        let c = root([r[0][col] * h[col], r[1][col] * h[col], r[2][col] * h[col]]);
        m[4 * col..4 * col + 3].copy_from_slice(&c);
    }
    m[12..15].copy_from_slice(&root(p));
    m[15] = 1.0;
    m
}

/// Linear interpolation of keyframe values at `t`, as glTF's LINEAR sampler does.
fn lerp_keys(times: &[f64], t: f64, at: impl Fn(f64) -> [f64; 3]) -> [f64; 3] {
    let k = times
        .partition_point(|&tk| tk <= t)
        .clamp(1, times.len() - 1);
    let (t0, t1) = (times[k - 1], times[k]);
    let f = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
    let (a, b) = (at(t0), at(t1));
    [0, 1, 2].map(|c| a[c] + f * (b[c] - a[c]))
}

#[test]
fn three_js_plays_the_closed_form_motion() {
    let scene = falling_scene(30, 100, true);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.glb");
    write_glb(&scene, &path).unwrap();

    // Keyframe times, times between keyframes, and the clamped end.
    let sample_t = [0.0, 0.013, 0.37, 0.5, 1.0101, 1.23456, 1.999, 2.0];
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/gltf/three_sample.mjs");
    let out = Command::new("node")
        .arg(&script)
        .arg(&path)
        .args(sample_t.iter().map(|t| t.to_string()))
        .output()
        .unwrap_or_else(|e| {
            panic!("cannot run `node` ({e}): install Node.js >= 18, then run scripts/setup-node.sh")
        });
    let stderr = String::from_utf8_lossy(&out.stderr);
    if out.status.code() == Some(3) {
        panic!("three.js is not installed: run scripts/setup-node.sh\n{stderr}");
    }
    assert!(out.status.success(), "three_sample.mjs failed: {stderr}");
    let report: Value = serde_json::from_slice(&out.stdout).expect("JSON from three_sample.mjs");
    assert_eq!(report["clipDuration"], 2.0);
    let nodes = report["nodes"].as_object().unwrap();
    assert_eq!(nodes.len(), 31, "30 bodies + ground as meshes");

    let mut worst = 0.0f64;
    let mut check = |name: &str, expected: &dyn Fn(f64) -> [f64; 16]| {
        let got = nodes[name].as_array().unwrap();
        for (j, &t) in sample_t.iter().enumerate() {
            let e = expected(t);
            for (i, v) in got[j].as_array().unwrap().iter().enumerate() {
                let err = (v.as_f64().unwrap() - e[i]).abs();
                worst = worst.max(err);
                assert!(
                    err < 2e-5,
                    "{name} t={t}: element {i} = {v}, expected {}",
                    e[i]
                );
            }
        }
    };
    for (i, body) in scene.bodies.iter().enumerate() {
        let throw = Throw::of_body(i);
        check(&body.name, &|t| {
            // f32 keyframe positions, linearly interpolated; the spin is uniform about a
            // fixed axis, so slerp between keyframes gives the closed-form rotation.
            let p = lerp_keys(&scene.times_s, t, |tk| {
                throw.position(tk).map(|c| f64::from(c as f32))
            });
            world(p, throw.quaternion(t), body.half_extents)
        });
    }
    let ground = scene.ground.as_ref().unwrap();
    check("ground", &|t| {
        let p = lerp_keys(&scene.times_s, t, |tk| {
            ground_pose(tk).position.map(|c| f64::from(c as f32))
        });
        world(p, [1.0, 0.0, 0.0, 0.0], ground.half_extents)
    });
    eprintln!("three.js world matrices vs closed form: max |error| = {worst:.2e}");
}
