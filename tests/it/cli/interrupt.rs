//! An interrupted command leaves nothing of its own: `fem2rbd scene` streams its poses into
//! `.p.csv.tmp-PID` beside the output; SIGINT or SIGTERM while it works removes that file,
//! leaves the earlier `p.csv` byte for byte, and ends the process with 128 + the signal.
use std::fs;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_fem2rbd");

/// The temporaries beside `p.csv` in `dir`.
fn temporaries(dir: &Path) -> Vec<String> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".p.csv."))
        .collect()
}

/// Starts a long scene over an existing `p.csv`, sends `signal` once the temporary output
/// exists, and returns the exit code and stderr.
fn interrupt_scene(signal: &str) -> (Option<i32>, String, tempfile::TempDir) {
    let w = tempfile::tempdir().unwrap();
    let scene = w.path().join("long.json");
    // A box sliding for 8·10⁴ s: 1.92·10⁷ substeps, far longer than the test waits.
    fs::write(
        &scene,
        r#"{
  "world": { "preset": "pybullet" },
  "duration": 80000.0,
  "substeps_per_second": 240,
  "bodies": [
    { "name": "ground", "half_extents": [10, 10, 0.5], "mass": 0,
      "position": [0, 0, -0.5], "friction": 1.0 },
    { "name": "box", "half_extents": [0.5, 0.5, 0.5], "mass": 1,
      "position": [0, 0, 1.5], "friction": 0.5 }
  ]
}"#,
    )
    .unwrap();
    let out = w.path().join("p.csv");
    fs::write(&out, "the earlier output\n").unwrap();
    let mut child = Command::new(BIN)
        .args(["--quiet", "scene"])
        .arg(&scene)
        .arg("--out")
        .arg(&out)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    while temporaries(w.path()).is_empty() {
        assert!(
            t0.elapsed() < Duration::from_secs(120),
            "no temporary output appeared"
        );
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the scene ended before it was interrupted: {status}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let killed = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert_eq!(
        fs::read_to_string(&out).unwrap(),
        "the earlier output\n",
        "{stderr}"
    );
    assert_eq!(temporaries(w.path()), Vec::<String>::new(), "{stderr}");
    (output.status.code(), stderr, w)
}

#[test]
fn sigint_removes_the_temporary_and_keeps_the_earlier_output() {
    let (code, stderr, _w) = interrupt_scene("INT");
    assert_eq!(code, Some(128 + 2), "{stderr}");
    assert!(
        stderr.contains("interrupted (SIGINT): 1 temporary output removed"),
        "{stderr}"
    );
}

#[test]
fn sigterm_removes_the_temporary_and_keeps_the_earlier_output() {
    let (code, stderr, _w) = interrupt_scene("TERM");
    assert_eq!(code, Some(128 + 15), "{stderr}");
    assert!(stderr.contains("interrupted (SIGTERM)"), "{stderr}");
}
