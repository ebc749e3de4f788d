//! `fem2rbd generate frame` with no options writes data/frame3-standin/model.toml byte for byte.
use std::process::Command;

#[test]
fn generate_frame_defaults_write_the_shipped_frame3() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.toml");
    let st = Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
        .args(["generate", "frame", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let shipped = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/frame3-standin/model.toml"
    ))
    .unwrap();
    assert_eq!(std::fs::read(&out).unwrap(), shipped);
    // JSON output of the same model loads back equal
    let js = dir.path().join("x.json");
    let st = Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
        .args(["generate", "frame", "-o"])
        .arg(&js)
        .output()
        .unwrap();
    assert!(st.status.success());
    let a = fem2rbd::model::Model::load(&out).unwrap();
    let b = fem2rbd::model::Model::load(&js).unwrap();
    assert!(a == b, "TOML and JSON forms of the generated model differ");
}

#[test]
fn generate_frame_rejects_bad_options_with_a_message() {
    let dir = tempfile::tempdir().unwrap();
    let st = Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
        .args(["generate", "frame", "--stories", "1.0,abc", "-o"])
        .arg(dir.path().join("y.toml"))
        .output()
        .unwrap();
    assert!(!st.status.success());
    let err = String::from_utf8_lossy(&st.stderr);
    assert!(
        err.contains("--stories") && err.contains("\"abc\" is not a number"),
        "{err}"
    );
    assert!(!dir.path().join("y.toml").exists());
}

/// The options that write the calibrated Case 1 frame (docs/case1.md, "Regenerate").
const CASE1_OPTIONS: &[&str] = &[
    "--name",
    "frame3-case1",
    "--column-bars-per-face",
    "4",
    "--beam-bars",
    "4",
    "--column-elements",
    "4",
    "--core-epscu",
    "-0.008",
    "--formulation",
    "disp",
    "--added-mass",
    "2784",
    "--ballast-centre",
    "0.036",
];

#[test]
fn generate_frame_with_the_case1_options_writes_the_shipped_calibrated_frame() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("case1.toml");
    let st = Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
        .args(["generate", "frame"])
        .args(CASE1_OPTIONS)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let shipped = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/frame3/model.toml"
    ))
    .unwrap();
    assert!(
        std::fs::read(&out).unwrap() == shipped,
        "data/frame3/model.toml differs from `fem2rbd generate frame` with the Case 1 options"
    );
}

#[test]
fn generate_frame_rejects_reinforcement_that_does_not_fit() {
    let dir = tempfile::tempdir().unwrap();
    for (args, want) in [
        (
            &["--column-bars-per-face", "12", "--bar-diameter", "0.008"][..],
            "12 column bars of 0.008 m do not fit on a 0.1 m face",
        ),
        (
            &["--core-epscu", "-0.001"][..],
            "story 1: core crushing strain -0.001 must be negative and beyond the peak strain",
        ),
        (&["--beam-bars", "4,x"][..], "--beam-bars"),
        (&["--ballast-centre", "1.5"][..], "ballast centre share 1.5"),
        (&["--residual", "-0.1"][..], "concrete residual share -0.1"),
    ] {
        let out = dir.path().join("z.toml");
        let st = Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
            .args(["generate", "frame"])
            .args(args)
            .arg("-o")
            .arg(&out)
            .output()
            .unwrap();
        assert!(!st.status.success(), "{args:?} accepted");
        let err = String::from_utf8_lossy(&st.stderr);
        assert!(err.contains(want), "{args:?}: {err}");
        assert!(!out.exists());
    }
}
