//! Reads back the `.glb` that `output::gltf::write_glb` writes, with an independent parser
//! (tests/gltf/common.rs), and checks its numbers against the closed-form trajectories it
//! was made from.
use super::gltf_common as common;

use common::{falling_scene, ground_pose, Glb, Throw};
use fem2rbd::output::gltf::{write_glb, AnimBody, AnimatedScene, GroundBox, ROOT_NODE_NAME};

const BODIES: usize = 30;
const KEYS: usize = 100;

fn write_and_read(scene: &AnimatedScene) -> (Vec<u8>, Glb) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.glb");
    write_glb(scene, &path).expect("write_glb");
    let bytes = std::fs::read(&path).unwrap();
    let glb = Glb::parse(&bytes);
    (bytes, glb)
}

/// `a == b` up to the last-bit error of serde_json's default (not round-trip exact) float
/// parser; an f32-versus-f64 difference (~1e-8 relative) still fails.
fn same_f64(a: f64, b: f64) -> bool {
    (a - b).abs() <= 4.0 * f64::EPSILON * b.abs()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// glTF `[x, y, z, w]` of a `[w, x, y, z]` quaternion.
fn xyzw(q: [f64; 4]) -> [f64; 4] {
    [q[1], q[2], q[3], q[0]]
}

#[test]
fn container_layout_follows_the_glb_rules() {
    let (bytes, glb) = write_and_read(&falling_scene(BODIES, KEYS, true));
    assert_eq!(glb.version, 2);
    assert_eq!(glb.declared_length as usize, bytes.len());
    assert_eq!(glb.json_chunk_len % 4, 0, "JSON chunk padded to 4 bytes");
    assert_eq!(glb.bin.len() % 4, 0, "BIN chunk padded to 4 bytes");
    let j = &glb.json;
    assert_eq!(j["asset"]["version"], "2.0");
    assert_eq!(j["buffers"].as_array().unwrap().len(), 1);
    assert_eq!(j["buffers"][0]["byteLength"], glb.bin.len());
    for (k, view) in j["bufferViews"].as_array().unwrap().iter().enumerate() {
        let offset = view["byteOffset"].as_u64().unwrap();
        let len = view["byteLength"].as_u64().unwrap();
        assert_eq!(offset % 4, 0, "bufferView {k} starts on a 4-byte boundary");
        assert!(
            offset + len <= glb.bin.len() as u64,
            "bufferView {k} inside BIN"
        );
    }
    // Every accessor that declares bounds has exactly the bounds of its data.
    for (k, acc) in j["accessors"].as_array().unwrap().iter().enumerate() {
        if acc.get("min").is_none() {
            continue;
        }
        let data = glb.f32s(k);
        let n = data[0].len();
        for c in 0..n {
            let lo = data.iter().map(|e| e[c]).fold(f32::INFINITY, f32::min);
            let hi = data.iter().map(|e| e[c]).fold(f32::NEG_INFINITY, f32::max);
            assert_eq!(
                acc["min"][c].as_f64().unwrap(),
                f64::from(lo),
                "accessor {k} min"
            );
            assert_eq!(
                acc["max"][c].as_f64().unwrap(),
                f64::from(hi),
                "accessor {k} max"
            );
        }
    }
}

#[test]
fn nodes_meshes_materials_and_accessor_counts() {
    let scene = falling_scene(BODIES, KEYS, true);
    let (_, glb) = write_and_read(&scene);
    let j = &glb.json;
    let nodes = j["nodes"].as_array().unwrap();
    assert_eq!(nodes.len(), 1 + BODIES + 1, "root + bodies + ground");
    assert_eq!(j["scenes"][0]["nodes"], serde_json::json!([0]));
    assert_eq!(nodes[0]["name"], ROOT_NODE_NAME);
    let children: Vec<u64> = nodes[0]["children"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_u64().unwrap())
        .collect();
    assert_eq!(children, (1..=BODIES as u64 + 1).collect::<Vec<_>>());

    // One material and one mesh per type, sorted by name.
    let names: Vec<&str> = j["materials"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["Beam", "Column", "Ground", "Slab"]);
    assert_eq!(j["meshes"].as_array().unwrap().len(), 4);

    // The shared cube: 24 vertices at ±1, 36 indices, POSITION bounds ±1.
    let prim = &j["meshes"][0]["primitives"][0];
    let pos = prim["attributes"]["POSITION"].as_u64().unwrap() as usize;
    let nrm = prim["attributes"]["NORMAL"].as_u64().unwrap() as usize;
    let idx = prim["indices"].as_u64().unwrap() as usize;
    assert_eq!(glb.accessor(pos)["count"], 24);
    assert_eq!(
        glb.accessor(pos)["min"],
        serde_json::json!([-1.0, -1.0, -1.0])
    );
    assert_eq!(glb.accessor(pos)["max"], serde_json::json!([1.0, 1.0, 1.0]));
    assert_eq!(glb.accessor(nrm)["count"], 24);
    assert_eq!(glb.u16s(idx).len(), 36);
    assert!(glb.u16s(idx).iter().all(|&i| i < 24));
    for m in j["meshes"].as_array().unwrap() {
        let p = &m["primitives"][0];
        assert_eq!(p["attributes"]["POSITION"], pos);
        assert_eq!(p["indices"], idx);
    }

    // Each body node: its type's mesh, scale = half extents.
    for (i, body) in scene.bodies.iter().enumerate() {
        let node = &nodes[1 + i];
        assert_eq!(node["name"], body.name.as_str());
        let mesh = node["mesh"].as_u64().unwrap() as usize;
        let material = j["meshes"][mesh]["primitives"][0]["material"]
            .as_u64()
            .unwrap() as usize;
        assert_eq!(j["materials"][material]["name"], body.type_name.as_str());
        for c in 0..3 {
            let scale = node["scale"][c].as_f64().unwrap();
            assert!(same_f64(scale, body.half_extents[c]), "{scale}");
            // The node's rest pose is the first keyframe, in full precision.
            let x = node["translation"][c].as_f64().unwrap();
            assert!(same_f64(x, body.poses[0].position[c]), "{x}");
        }
    }

    // Animation: translation + rotation per body and for the moving ground; one shared
    // input of the 100 times with min/max.
    let anim = &j["animations"][0];
    assert_eq!(anim["channels"].as_array().unwrap().len(), 2 * (BODIES + 1));
    assert_eq!(anim["samplers"].as_array().unwrap().len(), 2 * (BODIES + 1));
    let (input, _) = glb.channel(1, "translation").unwrap();
    for s in anim["samplers"].as_array().unwrap() {
        assert_eq!(s["input"], input);
        assert_eq!(
            glb.accessor(s["output"].as_u64().unwrap() as usize)["count"],
            KEYS
        );
    }
    let t = glb.f32s(input);
    assert_eq!(t.len(), KEYS);
    for (k, tk) in t.iter().enumerate() {
        assert_eq!(tk[0], scene.times_s[k] as f32);
    }
    assert_eq!(glb.accessor(input)["min"][0], 0.0);
    assert_eq!(glb.accessor(input)["max"][0], 2.0);
}

#[test]
fn keyframe_positions_equal_the_closed_form_trajectories() {
    let scene = falling_scene(BODIES, KEYS, true);
    let (_, glb) = write_and_read(&scene);
    let mut worst = 0.0f64;
    for (i, body) in scene.bodies.iter().enumerate() {
        let node = glb.node_named(&body.name);
        let (_, out) = glb.channel(node, "translation").unwrap();
        let throw = Throw::of_body(i);
        for (k, p) in glb.f32s(out).iter().enumerate() {
            let exact = throw.position(scene.times_s[k]);
            for c in 0..3 {
                assert_eq!(p[c], exact[c] as f32, "body {i} key {k} component {c}");
                let err = (f64::from(p[c]) - exact[c]).abs();
                assert!(err <= f64::from(f32::EPSILON) * exact[c].abs().max(1e-30));
                worst = worst.max(err);
            }
        }
    }
    eprintln!("largest position error after f32 rounding: {worst:.3e} m");
    // The moving ground: x(t) = 0.1 sin(2π·1.5 t).
    let ground = glb.node_named("ground");
    let (_, out) = glb.channel(ground, "translation").unwrap();
    for (k, p) in glb.f32s(out).iter().enumerate() {
        let exact = ground_pose(scene.times_s[k]).position;
        assert_eq!(p, &exact.map(|c| c as f32).to_vec(), "ground key {k}");
    }
}

#[test]
fn rotations_are_unit_sign_continuous_and_interpolate_the_short_way() {
    let scene = falling_scene(BODIES, KEYS, true);
    let (_, glb) = write_and_read(&scene);
    let mut input_flips = 0;
    let (mut worst_norm, mut worst_mid) = (0.0f64, 0.0f64);
    for (i, body) in scene.bodies.iter().enumerate() {
        let node = glb.node_named(&body.name);
        let (_, out) = glb.channel(node, "rotation").unwrap();
        let q: Vec<Vec<f64>> = glb
            .f32s(out)
            .iter()
            .map(|e| e.iter().map(|&c| f64::from(c)).collect())
            .collect();
        let throw = Throw::of_body(i);
        for (k, qk) in q.iter().enumerate() {
            worst_norm = worst_norm.max((dot(qk, qk).sqrt() - 1.0).abs());
            // Same rotation as the input, up to sign.
            let exact = xyzw(throw.quaternion(scene.times_s[k]));
            let s = dot(qk, &exact).signum();
            for c in 0..4 {
                assert!((qk[c] - s * exact[c]).abs() < 1e-6, "body {i} key {k}");
            }
            if k == 0 {
                continue;
            }
            assert!(dot(&q[k - 1], qk) >= 0.0, "body {i}: sign jump at key {k}");
            let raw = |kk: usize| body.poses[kk].orientation;
            if dot(&raw(k - 1), &raw(k)) < 0.0 {
                input_flips += 1;
            }
            // Slerp halfway between two keys of a uniform spin about a fixed axis is the
            // spin at the mid time: (q0 + q1)/|q0 + q1| when the two have dot >= 0.
            let sum: Vec<f64> = q[k - 1].iter().zip(qk).map(|(a, b)| a + b).collect();
            let n = dot(&sum, &sum).sqrt();
            let mid: Vec<f64> = sum.iter().map(|c| c / n).collect();
            let t_mid = 0.5 * (scene.times_s[k - 1] + scene.times_s[k]);
            let exact_mid = xyzw(throw.quaternion(t_mid));
            let s = dot(&mid, &exact_mid).signum();
            let err = (0..4)
                .map(|c| (mid[c] - s * exact_mid[c]).abs())
                .fold(0.0, f64::max);
            worst_mid = worst_mid.max(err);
        }
    }
    eprintln!(
        "input sign jumps: {input_flips}; max |‖q‖−1| = {worst_norm:.2e}; \
         max midpoint-slerp error = {worst_mid:.2e}"
    );
    assert!(input_flips > 30, "the input must exercise sign jumps");
    assert!(worst_norm < 1e-6);
    assert!(worst_mid < 1e-6);
}

#[test]
fn root_node_turns_z_up_into_y_up() {
    let (_, glb) = write_and_read(&falling_scene(2, 3, false));
    let r: Vec<f64> = glb.json["nodes"][0]["rotation"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_f64().unwrap())
        .collect();
    // Rotate v by q = (x, y, z, w): v' = v + 2w (u×v) + 2 u×(u×v), u = (x, y, z).
    let rotate = |v: [f64; 3]| {
        let (u, w) = ([r[0], r[1], r[2]], r[3]);
        let cross = |a: [f64; 3], b: [f64; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let uv = cross(u, v);
        let uuv = cross(u, uv);
        [0, 1, 2].map(|c| v[c] + 2.0 * w * uv[c] + 2.0 * uuv[c])
    };
    let close = |a: [f64; 3], b: [f64; 3]| a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-6);
    assert!(
        close(rotate([0.0, 0.0, 1.0]), [0.0, 1.0, 0.0]),
        "our up is glTF +Y"
    );
    assert!(
        close(rotate([0.0, 1.0, 0.0]), [0.0, 0.0, -1.0]),
        "our +Y is glTF −Z"
    );
    assert!(
        close(rotate([1.0, 0.0, 0.0]), [1.0, 0.0, 0.0]),
        "x unchanged"
    );
}

#[test]
fn two_writes_give_identical_bytes() {
    let scene = falling_scene(BODIES, KEYS, true);
    let (a, _) = write_and_read(&scene);
    let (b, _) = write_and_read(&scene.clone());
    assert_eq!(a, b);
}

#[test]
fn fixed_ground_is_not_animated_and_a_bodyless_scene_has_no_animation() {
    let (_, glb) = write_and_read(&falling_scene(4, 10, false));
    let ground = glb.node_named("ground");
    assert!(glb.channel(ground, "translation").is_none());
    assert_eq!(
        glb.json["animations"][0]["channels"]
            .as_array()
            .unwrap()
            .len(),
        8
    );
    assert_eq!(glb.json["nodes"][ground]["translation"][2], -0.25);

    let (_, glb) = write_and_read(&falling_scene(0, 10, false));
    assert!(glb.json.get("animations").is_none());
    // Only the cube's three accessors: no unused keyframe-time accessor.
    assert_eq!(glb.json["accessors"].as_array().unwrap().len(), 3);
}

fn error_of(scene: &AnimatedScene) -> String {
    let dir = tempfile::tempdir().unwrap();
    let err = write_glb(scene, dir.path().join("bad.glb")).unwrap_err();
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert!(left.is_empty(), "a failed write leaves no file");
    format!("{err:#}")
}

#[test]
fn bad_input_is_a_clear_error_and_no_file() {
    let good = falling_scene(3, 5, true);

    let mut s = good.clone();
    s.bodies[1].poses.pop();
    let e = error_of(&s);
    assert!(
        e.contains("body 'E101' (#1) has 4 poses") && e.contains("5 keyframe times"),
        "{e}"
    );

    let mut s = good.clone();
    s.times_s[3] = s.times_s[2];
    let e = error_of(&s);
    assert!(
        e.contains("times_s[3]") && e.contains("increase strictly"),
        "{e}"
    );

    let mut s = good.clone();
    s.times_s[0] = -0.1;
    assert!(error_of(&s).contains("times_s[0] = -0.1 s must be finite and >= 0"));

    let mut s = good.clone();
    s.bodies[2].poses[4].orientation = [0.0; 4];
    let e = error_of(&s);
    assert!(
        e.contains("body 'E102' (#2) at keyframe 4 (t = 2 s)") && e.contains("zero"),
        "{e}"
    );

    let mut s = good.clone();
    s.bodies[0].poses[1].position[2] = f64::NAN;
    assert!(error_of(&s).contains("body 'E100' (#0) at keyframe 1"));

    let mut s = good.clone();
    s.bodies[0].half_extents[1] = 0.0;
    assert!(error_of(&s).contains("body 'E100' (#0): half_extents"));

    let mut s = good.clone();
    s.ground = Some(GroundBox {
        half_extents: [1.0; 3],
        poses: vec![ground_pose(0.0); 2],
    });
    assert!(error_of(&s).contains("the ground has 2 poses"));

    let mut s = good.clone();
    s.bodies.push(AnimBody {
        name: "X".into(),
        type_name: " ".into(),
        half_extents: [1.0; 3],
        poses: good.bodies[0].poses.clone(),
    });
    assert!(error_of(&s).contains("body 'X' (#3) has an empty type_name"));

    let s = AnimatedScene::default();
    assert!(error_of(&s).contains("no keyframe times"));

    let s = AnimatedScene {
        times_s: vec![0.0],
        ..Default::default()
    };
    assert!(error_of(&s).contains("no bodies and no ground"));
}
