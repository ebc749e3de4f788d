//! Runs the Khronos glTF validator (npm `gltf-validator`, pinned in tests/gltf/package.json,
//! installed by scripts/setup-node.sh) on files written by `output::gltf::write_glb` and
//! requires zero errors and zero warnings. Needs `node` on PATH; fails (does not skip)
//! when node or the validator is missing.
use super::gltf_common as common;

use common::{falling_scene, Glb};
use fem2rbd::output::gltf::write_glb;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn validate_script() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/gltf/validate.mjs")
}

/// Runs tests/gltf/validate.mjs on `file`; returns its exit code and parsed report.
fn run_validator(file: &Path) -> (i32, Value) {
    let out = Command::new("node")
        .arg(validate_script())
        .arg(file)
        .output()
        .unwrap_or_else(|e| {
            panic!("cannot run `node` ({e}): install Node.js >= 18, then run scripts/setup-node.sh")
        });
    let code = out.status.code().unwrap_or(-1);
    let stderr = String::from_utf8_lossy(&out.stderr);
    if code == 3 {
        panic!("the Khronos glTF validator is not installed: run scripts/setup-node.sh\n{stderr}");
    }
    let report: Value = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!("validator gave no JSON report (exit {code}): {e}\nstderr: {stderr}")
    });
    (code, report)
}

/// Issues of one severity (0 error, 1 warning, 2 info, 3 hint) as "CODE at POINTER: message".
fn issues(report: &Value, severity: u64) -> Vec<String> {
    report["issues"]["messages"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["severity"] == severity)
        .map(|m| format!("{} at {}: {}", m["code"], m["pointer"], m["message"]))
        .collect()
}

fn assert_clean(scene: &fem2rbd::output::gltf::AnimatedScene, what: &str) -> Value {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.glb");
    write_glb(scene, &path).unwrap();
    let (code, report) = run_validator(&path);
    let (errors, warnings) = (issues(&report, 0), issues(&report, 1));
    eprintln!(
        "{what}: validator {} — {} errors, {} warnings, {} infos, {} hints",
        report["validatorVersion"],
        report["issues"]["numErrors"],
        report["issues"]["numWarnings"],
        report["issues"]["numInfos"],
        report["issues"]["numHints"]
    );
    for line in issues(&report, 2).iter().chain(&issues(&report, 3)) {
        eprintln!("  info/hint: {line}");
    }
    assert!(
        errors.is_empty() && warnings.is_empty(),
        "{what}: errors {errors:#?}, warnings {warnings:#?}"
    );
    assert_eq!(report["issues"]["numErrors"], 0);
    assert_eq!(report["issues"]["numWarnings"], 0);
    assert_eq!(code, 0, "validate.mjs exit code");
    report
}

#[test]
fn thirty_tumbling_boxes_on_a_moving_ground_validate_cleanly() {
    let scene = falling_scene(30, 100, true);
    let report = assert_clean(&scene, "30 boxes, 100 keyframes, moving ground");
    eprintln!("full report: {report:#}");
    let info = &report["info"];
    assert_eq!(info["version"], "2.0");
    assert_eq!(info["animationCount"], 1);
    assert_eq!(info["materialCount"], 4);
    assert_eq!(info["hasMorphTargets"], false);
    assert_eq!(info["hasSkins"], false);
    assert_eq!(info["hasTextures"], false);
    // The validator counts per mesh: one box mesh for each of the 4 types.
    assert_eq!(info["drawCallCount"], 4);
    assert_eq!(info["totalTriangleCount"], 4 * 12);
    assert_eq!(info["totalVertexCount"], 4 * 24);
    // BIN: cube (24 positions + 24 normals × 12 B, 36 × 2 B indices), 100 times × 4 B,
    // and per animated node (30 bodies + ground) 100 × (12 B translation + 16 B rotation).
    let bin_bytes = 2 * 24 * 12 + 36 * 2 + 100 * 4 + 31 * 100 * (12 + 16);
    assert_eq!(info["resources"][0]["byteLength"], bin_bytes);
}

#[test]
fn fixed_ground_and_bodyless_scenes_validate_cleanly() {
    assert_clean(&falling_scene(5, 20, false), "5 boxes, fixed ground");
    assert_clean(&falling_scene(0, 2, false), "ground only, no animation");
    let mut single_key = falling_scene(3, 1, false);
    single_key.ground = None;
    assert_clean(&single_key, "3 boxes, one keyframe, no ground");
}

#[test]
fn void_volumes_validate_cleanly_and_add_a_material_per_pattern() {
    use fem2rbd::output::gltf::VoidVolume;
    let base = falling_scene(5, 20, false);
    let plain = assert_clean(&base, "5 boxes");
    let mut scene = base.clone();
    // An L of two boxes (pattern v) and one box (pancake).
    scene.voids = vec![
        VoidVolume {
            name: "void-01 v 0.3000 m3".into(),
            pattern: "v".into(),
            colour: [0.0, 0.34, 0.17],
            boxes: vec![
                [[0.0, 0.0, 0.0], [1.0, 0.5, 0.4]],
                [[0.0, 0.5, 0.0], [0.5, 1.0, 0.4]],
            ],
        },
        VoidVolume {
            name: "void-02 pancake 0.1000 m3".into(),
            pattern: "pancake".into(),
            colour: [0.0, 0.17, 0.44],
            boxes: vec![[[2.0, 0.0, 0.0], [3.0, 1.0, 0.1]]],
        },
    ];
    let with = assert_clean(&scene, "5 boxes and 2 voids");
    let n = |r: &Value, k: &str| r["info"][k].as_u64().unwrap();
    assert_eq!(n(&with, "materialCount"), n(&plain, "materialCount") + 2);
    assert_eq!(n(&with, "drawCallCount"), n(&plain, "drawCallCount") + 2);
    assert_eq!(
        n(&with, "totalTriangleCount"),
        n(&plain, "totalTriangleCount") + 3 * 12
    );
    assert_eq!(
        n(&with, "totalVertexCount"),
        n(&plain, "totalVertexCount") + 3 * 24
    );
}

/// The check can fail: a file whose POSITION data no longer match their declared max
/// is reported as an error by the validator and by validate.mjs's exit code.
#[test]
fn the_validator_reports_a_corrupted_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.glb");
    write_glb(&falling_scene(2, 5, false), &path).unwrap();
    let mut bytes = std::fs::read(&path).unwrap();
    let glb = Glb::parse(&bytes);
    let pos = glb.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
        .as_u64()
        .unwrap() as usize;
    let view = glb.accessor(pos)["bufferView"].as_u64().unwrap() as usize;
    let offset = glb.json["bufferViews"][view]["byteOffset"]
        .as_u64()
        .unwrap() as usize;
    let bin_start = 12 + 8 + glb.json_chunk_len + 8;
    bytes[bin_start + offset..bin_start + offset + 4].copy_from_slice(&3.0f32.to_le_bytes());
    std::fs::write(&path, &bytes).unwrap();
    let (code, report) = run_validator(&path);
    let codes: Vec<&str> = report["issues"]["messages"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["severity"] == 0)
        .map(|m| m["code"].as_str().unwrap())
        .collect();
    assert!(codes.contains(&"ACCESSOR_MAX_MISMATCH"), "{codes:?}");
    assert_eq!(code, 1);
}
