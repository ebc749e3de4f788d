//! `fem2rbd scene` end to end: determinism, output format, and bad input.
use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_fem2rbd")
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn run(scene: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    Command::new(bin())
        .arg("scene")
        .arg(scene)
        .arg("--out")
        .arg(out)
        .args(extra)
        .output()
        .expect("run fem2rbd")
}

#[test]
fn shipped_scenes_run_and_two_runs_are_bit_identical() {
    let dir = tempfile::tempdir().unwrap();
    for name in [
        "drop.json",
        "slide.json",
        "tumble.json",
        "hanging_spring.json",
        "pile.json",
        "conveyor.json",
    ] {
        let scene = root().join("data/scenes").join(name);
        let a = dir.path().join(format!("{name}.a.csv"));
        let b = dir.path().join(format!("{name}.b.csv"));
        for out in [&a, &b] {
            let o = run(&scene, out, &["--frames", "60"]);
            assert!(
                o.status.success(),
                "{name}: {}",
                String::from_utf8_lossy(&o.stderr)
            );
        }
        let (ta, tb) = (std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
        assert!(!ta.is_empty());
        assert_eq!(ta, tb, "{name}: two runs differ");
    }
}

#[test]
fn hanging_spring_scene_sags_m_g_over_k_and_the_generic_holds() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("hs.csv");
    let o = run(&root().join("data/scenes/hanging_spring.json"), &out, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), fem2rbd::scene::CSV_HEADER);
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 4);
    let z = |name: &str| -> f64 {
        let r = rows.iter().find(|r| r[2] == name).unwrap();
        assert_eq!(r[0], "720");
        r[5].parse().unwrap()
    };
    // 1 kg on k = 1000 N/m: sag m·g/k = 9.81 mm below the rest position 3.9 m.
    assert!(
        (z("weight") - (3.9 - 0.00981)).abs() < 1e-8,
        "{}",
        z("weight")
    );
    // 5 kg held rigidly: its per-substep impulse at rest is 5·9.81/240 = 0.204 N·s, below
    // the 0.5 N·s threshold also during the start-up transient of the soft limit rows.
    assert!((z("held") - 3.9).abs() < 1e-6, "{}", z("held"));
}

/// data/scenes/conveyor.json: a kinematic belt moving at v = 0.3 m/s under a resting box.
/// The belt is where its motion puts it (x = v·t); the box, dragged by friction at
/// μ·g = 0.25·9.81 m/s² until it moves with the belt, is at v·t − v²/(2μg) = 0.43165 m.
#[test]
fn conveyor_scene_drags_the_box_by_coulomb_friction() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c.csv");
    let o = run(&root().join("data/scenes/conveyor.json"), &out, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&out).unwrap();
    let row = |name: &str| -> Vec<f64> {
        let l = text
            .lines()
            .find(|l| l.split(',').nth(2) == Some(name))
            .unwrap();
        l.split(',').skip(3).map(|x| x.parse().unwrap()).collect()
    };
    let (v, t, mu_g) = (0.3, 1.5, 0.25 * 9.81);
    let belt = row("belt");
    assert!((belt[0] - v * t).abs() < 1e-12, "belt x = {}", belt[0]);
    let bx = row("box");
    let expected = v * t - v * v / (2.0 * mu_g);
    assert!(
        (bx[0] - expected).abs() < 2e-3,
        "box x = {} vs {expected}",
        bx[0]
    );
    assert!((bx[7] - v).abs() < 1e-5, "box vx = {}", bx[7]);
}

fn write_scene(dir: &Path, body: &str) -> PathBuf {
    let p = dir.join("bad.json");
    std::fs::write(&p, body).unwrap();
    p
}

const GROUND: &str =
    r#"{ "name": "ground", "half_extents": [5, 5, 0.5], "mass": 0, "position": [0, 0, -0.5] }"#;

fn scene_with(bodies: &str, constraints: &str) -> String {
    format!(
        "{{\n  \"duration\": 0.5,\n  \"substeps_per_second\": 240,\n  \"bodies\": [\n    {GROUND},\n    {bodies}\n  ],\n  \"constraints\": [\n    {constraints}\n  ]\n}}\n"
    )
}

const BOX: &str =
    r#"{ "name": "box", "half_extents": [0.5, 0.5, 0.5], "mass": 1, "position": [0, 0, 2] }"#;
const FIXED_OK: &str = r#"{ "kind": "fixed", "body_a": "ground", "body_b": "box", "frame_a": { "position": [0, 0, 2.5] }, "frame_b": { "position": [0, 0, 0] } }"#;

/// Each case: scene text and fragments the error message must contain.
fn bad_cases() -> Vec<(&'static str, String, Vec<&'static str>)> {
    vec![
        (
            "negative mass",
            scene_with(&BOX.replace("\"mass\": 1", "\"mass\": -2"), FIXED_OK),
            vec!["body 1 \"box\"", "line 6", "mass -2"],
        ),
        (
            "NaN mass",
            scene_with(&BOX.replace("\"mass\": 1", "\"mass\": NaN"), FIXED_OK),
            vec!["line 6", "in body 1", "NaN"],
        ),
        (
            "zero half extent",
            scene_with(&BOX.replace("[0.5, 0.5, 0.5]", "[0.5, 0, 0.5]"), FIXED_OK),
            vec!["body 1 \"box\"", "line 6", "half_extents"],
        ),
        (
            "NaN pose",
            scene_with(&BOX.replace("[0, 0, 2]", "[0, NaN, 2]"), FIXED_OK),
            vec!["line 6", "in body 1", "NaN"],
        ),
        (
            "non-unit orientation",
            scene_with(
                &BOX.replace("\"mass\": 1", "\"mass\": 1, \"orientation\": [1, 1, 0, 0]"),
                FIXED_OK,
            ),
            vec!["body 1 \"box\"", "unit quaternion"],
        ),
        (
            "unknown constraint kind",
            scene_with(BOX, &FIXED_OK.replace("\"fixed\"", "\"hinge\"")),
            vec!["constraint 0", "line 9", "unknown kind \"hinge\""],
        ),
        (
            "missing body",
            scene_with(BOX, &FIXED_OK.replace("\"box\"", "\"bx\"")),
            vec!["constraint 0", "line 9", "body_b \"bx\" does not exist"],
        ),
        (
            "unknown field",
            scene_with(
                &BOX.replace("\"mass\"", "\"colour\": 3, \"mass\""),
                FIXED_OK,
            ),
            vec!["line 6", "in body 1", "unknown field `colour`"],
        ),
        (
            "duplicate name",
            scene_with(&BOX.replace("\"box\"", "\"ground\""), ""),
            vec!["body 1 \"ground\"", "already used"],
        ),
        (
            "motion on a dynamic body",
            scene_with(
                &BOX.replace(
                    "\"mass\": 1",
                    "\"mass\": 1, \"motion\": {\"linear_velocity\": [1, 0, 0]}",
                ),
                FIXED_OK,
            ),
            vec!["body 1 \"box\"", "motion is only for kinematic bodies"],
        ),
        (
            "duration not whole substeps",
            scene_with(BOX, FIXED_OK).replace("\"duration\": 0.5", "\"duration\": 0.5001"),
            vec!["duration", "whole number of substeps"],
        ),
    ]
}

#[test]
fn bad_input_names_the_item_exits_nonzero_and_writes_nothing() {
    for (what, text, needles) in bad_cases() {
        let dir = tempfile::tempdir().unwrap();
        let scene = write_scene(dir.path(), &text);
        let out = dir.path().join("poses.csv");
        let o = run(&scene, &out, &[]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{what}: accepted\n{text}");
        for n in needles {
            assert!(err.contains(n), "{what}: message lacks {n:?}:\n{err}");
        }
        assert!(
            err.contains("bad.json"),
            "{what}: message lacks the file name:\n{err}"
        );
        let left: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        assert_eq!(
            left,
            vec!["bad.json".to_string()],
            "{what}: files left behind"
        );
    }
}

#[test]
fn the_good_variant_of_the_bad_cases_runs() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), &scene_with(BOX, FIXED_OK));
    let out = dir.path().join("poses.csv");
    let o = run(&scene, &out, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&out).unwrap();
    // The fixed constraint holds the box where it was.
    let z: f64 = text
        .lines()
        .nth(2)
        .unwrap()
        .split(',')
        .nth(5)
        .unwrap()
        .parse()
        .unwrap();
    assert!((z - 2.0).abs() < 1e-9, "{z}");
}
