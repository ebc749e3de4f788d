//! `fem2rbd export gltf RUN_DIR` (and `export vtk`) on real run folders: frame3 under LC5
//! (hybrid, FEMA 356 4 % drift criterion: FE keyframes up to Tc, then the ruin
//! stage to 2.5 s, three-component moving ground) and a no-collapse FE-only run.
//!
//! * the exported file is byte-identical to the run's own `collapse.glb` (both are built
//!   from the folder's tables by `output::gltf::run_scene`);
//! * decoded independently (tests/gltf/common.rs), its nodes (the bodies, the ground and
//!   the survivable voids of `voids.json`), materials, times,
//!   translations and rotations equal `keyframes.csv`/`history.csv` within f32 rounding,
//!   and the simulation's own full-precision poses within the CSVs' 6/8 decimals + f32;
//! * the Khronos validator reports 0 errors and 0 warnings;
//! * a missing or garbled run folder gives an error naming the file (and line), and no
//!   output file is written.
use super::gltf_common as common;

use common::Glb;
use fem2rbd::bullet::Pose;
use fem2rbd::pipeline::{self, write, Scenario, Silent};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

fn scenario_text(mode: &str, collapse: &str, fe: &str, physics: &str) -> String {
    format!(
        r#"model = "{ROOT}/data/frame3/model.toml"
mode = "{mode}"

[[ground_motion]]
file = "{ROOT}/data/ground-motions/RSN6_IMPVALL.I_I-ELC180.AT2"
direction = "X"
pga_g = 0.93

[[ground_motion]]
file = "{ROOT}/data/ground-motions/RSN6_IMPVALL.I_I-ELC270.AT2"
direction = "Y"
pga_g = 1.19

[[ground_motion]]
file = "{ROOT}/data/ground-motions/RSN6_IMPVALL.I_I-ELC-UP.AT2"
direction = "Z"
pga_g = 0.57

[fe]
dt = 0.005
{fe}

[collapse]
{collapse}

[physics]
{physics}
"#
    )
}

/// A run folder and the run's full-precision timeline and ground displacement per frame.
struct Run {
    dir: PathBuf,
    frames: Vec<(f64, Vec<Pose>)>,
    ground: Vec<[f64; 3]>,
    n_fe: usize,
}

/// Runs `text` in-process and writes its folder under the test's target tmp dir.
fn make_run(name: &str, text: &str) -> Run {
    let base = Path::new(env!("CARGO_TARGET_TMPDIR")).join("export_gltf");
    let dir = base.join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&base).unwrap();
    let sc_path = base.join(format!("{name}.toml"));
    std::fs::write(&sc_path, text).unwrap();
    let sc = Scenario::load(&sc_path).unwrap();
    let rec = pipeline::run(&sc, &Silent).unwrap();
    write::write(&rec, &dir, false).unwrap();
    let frames: Vec<(f64, Vec<_>)> = write::timeline(&rec)
        .into_iter()
        .map(|(t, p)| (t, p.to_vec()))
        .collect();
    let ground = frames
        .iter()
        .map(|(t, _)| rec.ground.ground_state_at(*t).0)
        .collect();
    Run {
        dir,
        frames,
        ground,
        n_fe: rec.fe_frames.len(),
    }
}

fn hybrid() -> &'static Run {
    static RUN: OnceLock<Run> = OnceLock::new();
    RUN.get_or_init(|| {
        make_run(
            "hybrid",
            &scenario_text(
                "hybrid",
                "criterion = \"drift_4pct\"",
                "",
                "time_limit_s = 2.5",
            ),
        )
    })
}

fn no_collapse() -> &'static Run {
    static RUN: OnceLock<Run> = OnceLock::new();
    RUN.get_or_init(|| {
        make_run(
            "no_collapse",
            &scenario_text("hybrid", "", "duration = 0.5", ""),
        )
    })
}

/// Runs the binary; returns (success, stderr).
fn fem2rbd(args: &[&std::ffi::OsStr]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn export(what: &str, dir: &Path, output: Option<&Path>) -> (bool, String) {
    let mut args = vec!["export".as_ref(), what.as_ref(), dir.as_os_str()];
    if let Some(o) = output {
        args.push("-o".as_ref());
        args.push(o.as_os_str());
    }
    fem2rbd(&args)
}

/// A CSV file as rows of fields (header left out).
fn csv(path: &Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

fn num(s: &str) -> f64 {
    s.parse().unwrap()
}

/// The largest |a − b| of a glTF rotation (x, y, z, w) and a quaternion (w, x, y, z),
/// up to the sign of the whole quaternion.
fn rotation_diff(gltf: &[f32], q_wxyz: [f64; 4]) -> f64 {
    let q = [q_wxyz[1], q_wxyz[2], q_wxyz[3], q_wxyz[0]];
    let n = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    let d = |s: f64| {
        (0..4)
            .map(|i| (f64::from(gltf[i]) - s * q[i] / n).abs())
            .fold(0.0, f64::max)
    };
    d(1.0).min(d(-1.0))
}

/// Checks the exported file of `run` against its tables and its simulation; returns the
/// largest position and rotation differences from the full-precision poses.
fn check_against_run(run: &Run, glb: &Glb) -> (f64, f64) {
    let bodies = csv(&run.dir.join("bodies.csv"));
    let keyframes = csv(&run.dir.join("keyframes.csv"));
    let history = csv(&run.dir.join("history.csv"));
    let n = bodies.len();
    let n_frames = keyframes.len() / n;
    assert_eq!(n_frames, run.frames.len());
    assert_eq!(history.len(), n_frames);

    // The survivable voids of voids.json (number, pattern), when the run has one.
    let survivable: Vec<(u64, String)> = std::fs::read_to_string(run.dir.join("voids.json"))
        .ok()
        .map(|t| serde_json::from_str::<Value>(&t).unwrap())
        .and_then(|js| js["voids"].as_array().cloned())
        .unwrap_or_default()
        .iter()
        .filter(|v| v["survivable"] == true)
        .map(|v| {
            (
                v["void"].as_u64().unwrap(),
                v["pattern"].as_str().unwrap().to_string(),
            )
        })
        .collect();
    // The survivable voids a rescuer or a camera reaches (each one route line).
    let routed = std::fs::read_to_string(run.dir.join("voids.json"))
        .ok()
        .map(|t| serde_json::from_str::<Value>(&t).unwrap())
        .and_then(|js| js["voids"].as_array().cloned())
        .unwrap_or_default()
        .iter()
        .filter(|v| {
            v["survivable"] == true
                && (v["rescuer"]["reached"] == true || v["camera"]["reached"] == true)
        })
        .count();
    // Nodes: the root, one per body in body order, the ground, one per survivable void,
    // one per route.
    let nodes = glb.json["nodes"].as_array().unwrap();
    assert_eq!(nodes.len(), 1 + n + 1 + survivable.len() + routed);
    for (k, (number, pattern)) in survivable.iter().enumerate() {
        let name = nodes[2 + n + k]["name"].as_str().unwrap();
        assert!(
            name.starts_with(&format!("void-{number:02} {pattern} ")),
            "{name}"
        );
    }
    assert_eq!(nodes[0]["name"], fem2rbd::output::gltf::ROOT_NODE_NAME);
    for (i, b) in bodies.iter().enumerate() {
        assert_eq!(nodes[1 + i]["name"], b[0].as_str());
        let scale: Vec<f64> = nodes[1 + i]["scale"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert_eq!(scale, vec![num(&b[13]), num(&b[14]), num(&b[15])]);
        let mesh = &glb.json["meshes"][nodes[1 + i]["mesh"].as_u64().unwrap() as usize];
        let mat = mesh["primitives"][0]["material"].as_u64().unwrap() as usize;
        assert_eq!(glb.json["materials"][mat]["name"], b[2].as_str());
    }
    assert_eq!(nodes[1 + n]["name"], "ground");
    // One material per type (frame3: Beam, Column, Foundation, Slab) plus Ground, then
    // one per pattern of the survivable voids (`void <pattern>`, by name).
    let mut types: Vec<&str> = bodies.iter().map(|b| b[2].as_str()).collect();
    types.push("Ground");
    types.sort_unstable();
    types.dedup();
    let mut patterns: Vec<String> = survivable.iter().map(|v| format!("void {}", v.1)).collect();
    patterns.sort_unstable();
    patterns.dedup();
    types.extend(patterns.iter().map(String::as_str));
    let mut kinds: Vec<&str> = nodes
        .iter()
        .filter_map(|n| n["name"].as_str())
        .filter(|n| n.starts_with("route-"))
        .map(|n| {
            if n.contains(" rescuer ") {
                "route rescuer"
            } else {
                "route camera"
            }
        })
        .collect();
    kinds.sort_unstable();
    kinds.dedup();
    types.extend(kinds);
    let materials: Vec<&str> = glb.json["materials"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["name"].as_str().unwrap())
        .collect();
    assert_eq!(materials, types);

    let (mut max_dp, mut max_dq) = (0.0f64, 0.0f64);
    for i in 0..n {
        let (tin, tout) = glb.channel(1 + i, "translation").unwrap();
        let (rin, rout) = glb.channel(1 + i, "rotation").unwrap();
        assert_eq!(tin, rin);
        let times = glb.f32s(tin);
        let (tr, ro) = (glb.f32s(tout), glb.f32s(rout));
        assert_eq!(
            (times.len(), tr.len(), ro.len()),
            (n_frames, n_frames, n_frames)
        );
        for k in 0..n_frames {
            let row = &keyframes[k * n + i];
            assert_eq!(row[1], bodies[i][0]);
            // Times: the CSV's 4 decimals as f32; the run's time within 5e-5 s + f32.
            assert_eq!(times[k][0], num(&row[0]) as f32);
            assert!((f64::from(times[k][0]) - run.frames[k].0).abs() < 5e-5 + 1e-6);
            // Against the CSV: f32 rounding only.
            for d in 0..3 {
                assert_eq!(tr[k][d], num(&row[2 + d]) as f32, "frame {k} body {i}");
            }
            let q_csv = [num(&row[5]), num(&row[6]), num(&row[7]), num(&row[8])];
            assert!(rotation_diff(&ro[k], q_csv) < 1e-7, "frame {k} body {i}");
            // Against the simulation: 0.5e-6 m (6 decimals) + f32 (6e-8 relative).
            let p = run.frames[k].1[i];
            for (g, x) in tr[k].iter().zip(p.position) {
                let e = (f64::from(*g) - x).abs();
                assert!(
                    e <= 5e-7 + 6e-8 * x.abs() + 1e-12,
                    "frame {k} body {i}: {g} vs {x}"
                );
                max_dp = max_dp.max(e);
            }
            let e = rotation_diff(&ro[k], p.orientation);
            assert!(e < 1e-7, "frame {k} body {i}: rotation off by {e}");
            max_dq = max_dq.max(e);
        }
    }
    // The ground slab: moved by history.csv's ground displacement (and by the run's),
    // its top at frame 0 at the base level (top of the foundation blocks) + ground z.
    let (_, gout) = glb.channel(1 + n, "translation").unwrap();
    let g = glb.f32s(gout);
    let base = bodies
        .iter()
        .filter(|b| b[5] == "1")
        .map(|b| num(&b[8]) + num(&b[15]))
        .fold(f64::NEG_INFINITY, f64::max);
    let half_z = glb.json["nodes"][1 + n]["scale"][2].as_f64().unwrap();
    let g0 = [7, 8, 9].map(|c| num(&history[0][c]));
    assert!((f64::from(g[0][2]) + half_z - (base + g0[2])).abs() < 1e-6);
    for k in 0..n_frames {
        for d in 0..3 {
            let moved = f64::from(g[k][d]) - f64::from(g[0][d]);
            let want = num(&history[k][7 + d]) - g0[d];
            assert!((moved - want).abs() < 1e-6, "ground frame {k} axis {d}");
            let sim = run.ground[k][d] - run.ground[0][d];
            assert!((moved - sim).abs() < 2e-6, "ground frame {k} axis {d}");
        }
    }
    (max_dp, max_dq)
}

/// Validator report of `file`: (errors, warnings).
fn validate(file: &Path) -> (Vec<String>, Vec<String>) {
    let out = Command::new("node")
        .arg(Path::new(ROOT).join("tests/gltf/validate.mjs"))
        .arg(file)
        .output()
        .unwrap_or_else(|e| panic!("cannot run node ({e}): run scripts/setup-node.sh"));
    assert_ne!(
        out.status.code(),
        Some(3),
        "the Khronos glTF validator is not installed: run scripts/setup-node.sh"
    );
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    let of = |sev: u64| {
        report["issues"]["messages"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|m| m["severity"] == sev)
            .map(|m| format!("{} at {}: {}", m["code"], m["pointer"], m["message"]))
            .collect::<Vec<_>>()
    };
    (of(0), of(1))
}

#[test]
fn export_reproduces_the_runs_glb_and_validates() {
    for (what, run) in [("hybrid", hybrid()), ("no collapse", no_collapse())] {
        let tmp = tempfile::tempdir().unwrap();
        let out = tmp.path().join("export.glb");
        let (ok, err) = export("gltf", &run.dir, Some(&out));
        assert!(ok, "{err}");
        let exported = std::fs::read(&out).unwrap();
        let own = std::fs::read(run.dir.join("collapse.glb")).unwrap();
        assert!(
            exported == own,
            "{what}: exported glb ({} B) differs from the run's ({} B)",
            exported.len(),
            own.len()
        );
        let glb = Glb::parse(&exported);
        let (dp, dq) = check_against_run(run, &glb);
        eprintln!(
            "{what}: {} B, {} frames ({} FE), max |position − simulation| {dp:.3e} m, \
             max |rotation − simulation| {dq:.3e}",
            exported.len(),
            run.frames.len(),
            run.n_fe
        );
        let (errors, warnings) = validate(&out);
        assert!(
            errors.is_empty() && warnings.is_empty(),
            "{what}: {errors:#?} {warnings:#?}"
        );
    }
    // The hybrid run has both stages and a moving ground.
    let h = hybrid();
    assert!(h.n_fe > 10 && h.frames.len() > h.n_fe + 10, "{}", h.n_fe);
    assert!(h.ground.iter().any(|g| g[0].abs() > 1e-3));
}

#[test]
fn default_output_is_the_run_folders_collapse_glb() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("run");
    std::fs::create_dir(&dir).unwrap();
    for e in std::fs::read_dir(&no_collapse().dir).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, dir.join(p.file_name().unwrap())).unwrap();
    }
    let own = std::fs::read(dir.join("collapse.glb")).unwrap();
    std::fs::remove_file(dir.join("collapse.glb")).unwrap();
    let (ok, err) = export("gltf", &dir, None);
    assert!(ok, "{err}");
    assert!(std::fs::read(dir.join("collapse.glb")).unwrap() == own);
    // No temporary file left behind.
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    // The run's six files and its marker.
    assert_eq!(names.len(), 7, "{names:?}");
}

/// Copies the hybrid folder into a temp dir with `file` changed by `f`, exports, and
/// returns the error text; asserts that nothing was written.
fn garbled(file: &str, f: impl Fn(&str) -> Option<String>) -> String {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("run");
    std::fs::create_dir(&dir).unwrap();
    for e in std::fs::read_dir(&hybrid().dir).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, dir.join(p.file_name().unwrap())).unwrap();
    }
    let p = dir.join(file);
    match f(&std::fs::read_to_string(&p).unwrap()) {
        Some(text) => std::fs::write(&p, text).unwrap(),
        None => std::fs::remove_file(&p).unwrap(),
    }
    let out = tmp.path().join("out.glb");
    let (ok, err) = export("gltf", &dir, Some(&out));
    assert!(!ok, "export of a garbled {file} succeeded");
    assert!(!out.exists(), "nothing may be written");
    let (ok, _) = export("vtk", &dir, None);
    assert!(!ok);
    assert!(!dir.join("vtk").exists(), "nothing may be written");
    assert_eq!(std::fs::read_dir(tmp.path()).unwrap().count(), 1);
    err
}

#[test]
fn missing_or_garbled_run_folder_is_named_and_nothing_is_written() {
    let tmp = tempfile::tempdir().unwrap();
    let none = tmp.path().join("no-such-run");
    let out = tmp.path().join("x.glb");
    let (ok, err) = export("gltf", &none, Some(&out));
    assert!(
        !ok && err.contains("no-such-run") && err.contains("does not exist"),
        "{err}"
    );
    assert!(!out.exists());

    let e = garbled("history.csv", |_| None);
    assert!(
        e.contains("history.csv") && e.contains("cannot read"),
        "{e}"
    );
    // keyframes.csv line 100: its z replaced by text.
    let e = garbled("keyframes.csv", |s| {
        let mut lines: Vec<String> = s.lines().map(str::to_string).collect();
        let mut f: Vec<&str> = lines[99].split(',').collect();
        f[4] = "1.2.3";
        lines[99] = f.join(",");
        Some(lines.join("\n") + "\n")
    });
    assert!(e.contains("keyframes.csv:100: column z: \"1.2.3\""), "{e}");
    // A frame cut short: the file ends mid-frame.
    let n = hybrid().frames[0].1.len();
    let cut = 1 + n + n / 2;
    let e = garbled("keyframes.csv", |s| {
        Some(s.lines().take(cut).map(|l| format!("{l}\n")).collect())
    });
    assert!(
        e.contains(&format!("keyframes.csv:{cut}: the last frame"))
            && e.contains(&format!("lists {} of the {n} bodies", n / 2)),
        "{e}"
    );
    // Two bodies swapped in bodies.csv: keyframes.csv no longer follows its order.
    let e = garbled("bodies.csv", |s| {
        let mut lines: Vec<&str> = s.lines().collect();
        lines.swap(2, 3);
        Some(lines.join("\n") + "\n")
    });
    assert!(e.contains("keyframes.csv:3: column name"), "{e}");
    // history.csv's ground column garbled.
    let e = garbled("history.csv", |s| Some(s.replacen(",ruin,", ",rubble,", 1)));
    assert!(
        e.contains("history.csv:") && e.contains("column stage"),
        "{e}"
    );
    let e = garbled("summary.json", |s| Some(s.replacen('{', "[", 1)));
    assert!(e.contains("summary.json:"), "{e}");
}

#[test]
fn vtk_export_writes_one_file_per_frame() {
    let run = hybrid();
    let tmp = tempfile::tempdir().unwrap();
    let pvd = tmp.path().join("v").join("run.pvd");
    let (ok, err) = export("vtk", &run.dir, Some(&pvd));
    assert!(ok, "{err}");
    let text = std::fs::read_to_string(&pvd).unwrap();
    let keyframes = csv(&run.dir.join("keyframes.csv"));
    let n = csv(&run.dir.join("bodies.csv")).len();
    let times: Vec<f64> = text
        .lines()
        .filter_map(|l| l.split("timestep=\"").nth(1))
        .map(|r| num(r.split('"').next().unwrap()))
        .collect();
    let want: Vec<f64> = keyframes.iter().step_by(n).map(|r| num(&r[0])).collect();
    assert_eq!(times, want);
    let vtus = std::fs::read_dir(tmp.path().join("v").join("run"))
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .starts_with("step_")
        })
        .count();
    assert_eq!(vtus, want.len());
    // Each frame: one hexahedron per body and one for the ground.
    let first = std::fs::read_to_string(tmp.path().join("v/run/step_000000.vtu")).unwrap();
    assert!(
        first.contains(&format!(
            "NumberOfPoints=\"{}\" NumberOfCells=\"{}\"",
            8 * (n + 1),
            n + 1
        )),
        "{}",
        &first[..400]
    );
}
