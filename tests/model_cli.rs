//! `fem2rbd generate frame` with no options writes data/frame3/model.toml byte for byte.
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
        "/data/frame3/model.toml"
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
