//! Runs `tests/pybullet/crosscheck.py`: the same scenes in `fem2rbd scene` and in pybullet
//! 3.2.7 (free fall, drop, slide with friction, tumbling throw, a pile of 24 boxes, two
//! boxes welded by a fixed constraint, a column of four boxes hanging from a static anchor
//! by fixed joints and struck sideways, a chain of six boxes welded end to end and
//! cantilevered from an anchor, a box swinging on a point-to-point joint, a bouncing box with restitution, damping and rolling
//! friction) must agree to 1e-9 m / 1e-9 rad at every substep,
//! and a negative control (solver mode 260 instead of pybullet's 276) must differ. Needs `python3` with pybullet and numpy
//! (scripts/setup.sh installs them); fails, never skips, when they are missing.
use std::process::Command;

#[test]
fn fem2rbd_scene_agrees_with_pybullet() {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/pybullet/crosscheck.py");
    let out = Command::new("python3")
        .arg(script)
        .arg("--bin")
        .arg(env!("CARGO_BIN_EXE_fem2rbd"))
        .output()
        .unwrap_or_else(|e| {
            panic!("cannot run python3 ({e}): install Python 3 with pybullet==3.2.7 and numpy (bash scripts/setup.sh)")
        });
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    println!("{stdout}");
    match out.status.code() {
        Some(0) => {}
        Some(2) => panic!(
            "pybullet or numpy is not installed for python3: run `bash scripts/setup.sh` \
             (or `python3 -m pip install pybullet==3.2.7 numpy`)\n{stderr}"
        ),
        _ => panic!("fem2rbd and pybullet disagree or the cross-check failed:\n{stdout}\n{stderr}"),
    }
    for name in [
        "freefall",
        "drop",
        "slide",
        "tumble",
        "pile",
        "welded",
        "hanging",
        "chain",
        "pendulum",
        "bounce",
        "control_tumble_mode260",
    ] {
        assert!(
            stdout
                .lines()
                .any(|l| l.starts_with(name) && l.ends_with("ok")),
            "scenario {name} missing from the cross-check output:\n{stdout}"
        );
    }
}
