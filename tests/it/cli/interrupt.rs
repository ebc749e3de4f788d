//! An interrupted command leaves nothing of its own: `fem2rbd scene` streams its poses into
//! `.p.csv.tmp-PID` beside the output, `fem2rbd export vtk` its frames into a staged
//! `.run.tmp-PID` folder; SIGINT or SIGTERM while they work removes the temporary, leaves
//! the earlier output byte for byte, and ends the process with 128 + the signal.
use fem2rbd::body::BodyId;
use fem2rbd::bullet::Pose;
use fem2rbd::output::history::{bodies_csv, history_csv, BodyRow, HistoryFrame};
use fem2rbd::output::keyframes::keyframes_csv;
use fem2rbd::output::ruins::{ruins_csv, RuinRow};
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

/// Starts `fem2rbd --quiet ARGS`, waits (at most 120 s) until `started()` says the command
/// is writing, sends it `signal`, and returns its exit code and stderr.
fn interrupt_when(
    args: &[&std::ffi::OsStr],
    started: impl Fn() -> bool,
    signal: &str,
) -> (Option<i32>, String) {
    let mut child = Command::new(BIN)
        .arg("--quiet")
        .args(args)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    while !started() {
        assert!(
            t0.elapsed() < Duration::from_secs(120),
            "{args:?}: no temporary output appeared"
        );
        if let Some(status) = child.try_wait().unwrap() {
            panic!("{args:?} ended before it was interrupted: {status}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let killed = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let output = child.wait_with_output().unwrap();
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
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
    let (code, stderr) = interrupt_when(
        &[
            "scene".as_ref(),
            scene.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ],
        || !temporaries(w.path()).is_empty(),
        signal,
    );
    assert_eq!(
        fs::read_to_string(&out).unwrap(),
        "the earlier output\n",
        "{stderr}"
    );
    assert_eq!(temporaries(w.path()), Vec::<String>::new(), "{stderr}");
    (code, stderr, w)
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

/// A rigid-mode run folder in `dir`, written with the project's writers: one column that
/// sinks 1 mm a frame for `frames` frames at 25 frames/s.
fn sinking_column_run(dir: &Path, frames: usize) {
    let id: BodyId = "Column:1:1".parse().unwrap();
    let pose = |z: f64| Pose {
        position: [0.0, 0.0, z],
        orientation: [1.0, 0.0, 0.0, 0.0],
    };
    let row = BodyRow {
        id: &id,
        passive: false,
        pose0: pose(1.5),
        half_extents: [0.15, 0.15, 1.5],
        mass_kg: 100.0,
    };
    let poses: Vec<(f64, [Pose; 1])> = (0..frames)
        .map(|k| (k as f64 * 0.04, [pose(1.5 - 0.001 * k as f64)]))
        .collect();
    let key: Vec<(f64, &[Pose])> = poses.iter().map(|(t, p)| (*t, p.as_slice())).collect();
    let history: Vec<HistoryFrame> = poses
        .iter()
        .map(|(t, p)| HistoryFrame {
            t_s: *t,
            fe: false,
            poses: p,
            counts: Some((0, 0, 0)),
            ground_m: [0.0; 3],
            energy: None,
        })
        .collect();
    let last = poses.last().unwrap().1[0];
    fs::write(
        dir.join("bodies.csv"),
        bodies_csv(std::slice::from_ref(&row)),
    )
    .unwrap();
    fs::write(
        dir.join("keyframes.csv"),
        keyframes_csv(&["Column:1:1"], &key),
    )
    .unwrap();
    fs::write(dir.join("history.csv"), history_csv(&[row], &history)).unwrap();
    let ruin = RuinRow {
        id: &id,
        pose: last,
        at_rest: Some(true),
    };
    fs::write(dir.join("ruins.csv"), ruins_csv(&[ruin])).unwrap();
    fs::write(
        dir.join("summary.json"),
        "{\"mode\": \"rigid\", \"tc_s\": null, \"tc_reason\": \"rigid_only\", \"tc_detail\": \"\", \
         \"fe_end_s\": null, \"bodies\": 1, \"foundation_blocks\": 0, \"keyframes_fe\": 0, \
         \"ruins\": {\"original_footprint_m\": {\"x\": [-0.15, 0.15], \"y\": [-0.15, 0.15]}, \
         \"extent_beyond_footprint_m\": {\"x_minus\": 0, \"x_plus\": 0, \"y_minus\": 0, \"y_plus\": 0, \"max\": 0}, \
         \"debris_footprint_area_m2\": 0, \"original_footprint_area_m2\": 0, \"max_debris_height_m\": 0, \
         \"floors\": [], \"slab_overlap\": []}}\n",
    )
    .unwrap();
}

/// The names in `dir` that start with a dot (the staged folders and files of a write).
fn hidden(dir: &Path) -> Vec<String> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect()
}

/// `export vtk` of a long run over an earlier export, interrupted by `signal` once its
/// staged folder holds frames: the staged folder is removed and the earlier `run.pvd` and
/// `run/` are left byte for byte. Returns the exit code and stderr.
fn interrupt_vtk_export(signal: &str) -> (Option<i32>, String) {
    let w = tempfile::tempdir().unwrap();
    let run = w.path().join("run-folder");
    fs::create_dir(&run).unwrap();
    // Every frame file is synced before the next one, so 20 000 frames take far longer
    // than the test waits.
    sinking_column_run(&run, 20_000);
    let out = w.path().join("vtk");
    fs::create_dir(&out).unwrap();
    let pvd = out.join("run.pvd");
    // The earlier export: a short run of the same column.
    let short = w.path().join("short");
    fs::create_dir(&short).unwrap();
    sinking_column_run(&short, 3);
    let first = Command::new(BIN)
        .args(["--quiet", "export", "vtk"])
        .arg(&short)
        .arg("-o")
        .arg(&pvd)
        .output()
        .unwrap();
    assert!(
        first.status.success(),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let frames_dir = out.join("run");
    let earlier: Vec<(String, Vec<u8>)> = std::iter::once(pvd.clone())
        .chain(
            fs::read_dir(&frames_dir)
                .unwrap()
                .map(|e| e.unwrap().path()),
        )
        .map(|p| (p.display().to_string(), fs::read(&p).unwrap()))
        .collect();
    assert_eq!(
        earlier.len(),
        1 + 3 + 1,
        "run.pvd, 3 frames and the folder's marker"
    );
    assert_eq!(hidden(&out), Vec::<String>::new());

    let staged_files = || -> usize {
        hidden(&out)
            .iter()
            .filter_map(|n| fs::read_dir(out.join(n)).ok())
            .map(|d| d.count())
            .sum()
    };
    let (code, stderr) = interrupt_when(
        &[
            "export".as_ref(),
            "vtk".as_ref(),
            run.as_os_str(),
            "-o".as_ref(),
            pvd.as_os_str(),
        ],
        || staged_files() >= 5,
        signal,
    );
    assert_eq!(hidden(&out), Vec::<String>::new(), "{stderr}");
    for (path, bytes) in &earlier {
        assert_eq!(&fs::read(path).unwrap(), bytes, "{path}: {stderr}");
    }
    assert_eq!(
        fs::read_dir(&frames_dir).unwrap().count(),
        4,
        "the earlier frames and marker only: {stderr}"
    );
    (code, stderr)
}

#[test]
fn sigint_during_a_vtk_export_removes_its_staged_frames_and_keeps_the_earlier_export() {
    let (code, stderr) = interrupt_vtk_export("INT");
    assert_eq!(code, Some(128 + 2), "{stderr}");
    assert!(stderr.contains("interrupted (SIGINT)"), "{stderr}");
}

#[test]
fn sigterm_during_a_vtk_export_removes_its_staged_frames_and_keeps_the_earlier_export() {
    let (code, stderr) = interrupt_vtk_export("TERM");
    assert_eq!(code, Some(128 + 15), "{stderr}");
    assert!(stderr.contains("interrupted (SIGTERM)"), "{stderr}");
}
