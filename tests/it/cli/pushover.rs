//! `fem2rbd pushover` against openseespy on the exported model: the same frame3 model
//! (`data/frame3-standin/model.toml`, force-based), the same lateral loads (read from
//! `pushover.json`), the same control node and the same steps through a cyclic protocol;
//! OpenSees's base shear is the sum of its `nodeReaction`s after `reactions`.
use serde_json::Value;
use std::path::Path;
use std::process::Command;

const MODEL: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/data/frame3-standin/model.toml"
);
const BIN: &str = env!("CARGO_BIN_EXE_fem2rbd");

fn fem2rbd(args: &[&str]) -> std::process::Output {
    Command::new(BIN).args(args).output().expect("run fem2rbd")
}

fn read_capacity(path: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    assert!(header.starts_with("step,control_displacement_m,roof_drift,load_factor_n,base_shear_n"));
    lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect()
}

#[test]
fn cyclic_pushover_matches_openseespy_on_the_exported_frame3() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cyclic");
    let o = fem2rbd(&[
        "--quiet",
        "pushover",
        MODEL,
        "--variant",
        "force",
        "--cyclic",
        "0.002,0.004",
        "--cycles",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let ours = read_capacity(&out.join("capacity.csv"));
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("pushover.json")).unwrap()).unwrap();
    assert_eq!(summary["control_node"], 312);
    assert_eq!(summary["stop"]["kind"], "completed");
    let svg = std::fs::read_to_string(out.join("capacity.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("roof drift (%)"));

    let theirs = openseespy_pushover(dir.path(), Path::new(MODEL), Some("force"), &summary);
    assert!(theirs["stopped_at"].is_null(), "OpenSees stopped: {theirs}");
    let curve = theirs["curve"].as_array().unwrap();
    assert_eq!(curve.len(), ours.len(), "the same steps");
    let weight = summary["weight_n"].as_f64().unwrap();
    let peak = ours.iter().map(|r| r[4].abs()).fold(0.0, f64::max);
    let mut worst = 0.0f64;
    for (a, b) in ours.iter().zip(curve) {
        let u = b["u"].as_f64().unwrap();
        let v = -b["r"][0].as_f64().unwrap();
        let rz = b["r"][2].as_f64().unwrap();
        assert!((a[1] - u).abs() < 1e-9, "step {}: u {} vs {u}", a[0], a[1]);
        worst = worst.max((a[4] - v).abs());
        assert!(
            (rz - weight).abs() < 1e-6 * weight,
            "OpenSees ΣRz {rz}, W {weight}"
        );
        assert!(
            (a[8] - weight).abs() < 1e-6 * weight,
            "ΣRz {}, W {weight}",
            a[8]
        );
    }
    eprintln!(
        "cyclic ±0.2 %, ±0.4 %: {} steps, peak V = {peak:.1} N, max |ΔV| against OpenSees = \
         {worst:.2} N ({:.3} % of the peak)",
        ours.len() - 1,
        100.0 * worst / peak
    );
    assert!(
        worst < 0.01 * peak,
        "base shear differs by {worst} N (peak {peak} N)"
    );
}

/// Runs the exported openseespy script's `pushover` (the export in `variant`, or the
/// model's own elements) ; with the lateral loads, control node,
/// targets and step of `summary` (a `pushover.json`); returns its JSON answer.
fn openseespy_pushover(dir: &Path, model: &Path, variant: Option<&str>, summary: &Value) -> Value {
    let script = dir.join("model.py");
    let mut args = vec![
        "export",
        "opensees",
        model.to_str().unwrap(),
        "-o",
        script.to_str().unwrap(),
    ];
    if let Some(v) = variant {
        args.extend(["--variant", v]);
    }
    let o = fem2rbd(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let spec = serde_json::json!({
        "node": summary["control_node"],
        "dof": 1,
        "loads": summary["lateral_loads"],
        "targets": summary["targets_m"],
        "step": summary["step_m"],
    });
    let spec_path = dir.join("spec.json");
    std::fs::write(&spec_path, spec.to_string()).unwrap();
    let o = Command::new("python3")
        .arg(&script)
        .args(["pushover", spec_path.to_str().unwrap()])
        .output()
        .expect("python3 with openseespy");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "openseespy pushover failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let last = stdout.lines().rfind(|l| l.starts_with('{')).unwrap();
    serde_json::from_str(last).unwrap()
}

/// A full-scale frame–shear-wall building (2 × 1 bays of 6 m × 5 m, 2 stories of 3 m, a
/// 0.2 m layered-shell wall on column line x0, bay 1) pushed to 0.08 % roof drift in four
/// steps, against openseespy on its export (ASDShellQ4 with the plastic-damage concrete
/// layers): the same base shear at every step to 10⁻⁶ of the peak, most of it carried by
/// the wall.
#[test]
fn wall_building_pushover_matches_openseespy() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("wall.toml");
    let o = fem2rbd(&[
        "generate",
        "building",
        "--name",
        "wall-2x1x2",
        "--spans-x",
        "6,6",
        "--spans-y",
        "5",
        "--stories",
        "3,3",
        "--column",
        "0.5x0.5",
        "--beam",
        "0.3x0.6",
        "--slab-thickness",
        "0.12",
        "--cover",
        "0.03",
        "--bar-offset",
        "0.04",
        "--column-bar-diameter",
        "0.025",
        "--beam-bar-diameter",
        "0.02",
        "--ec",
        "32.5e9",
        "--fc",
        "26.8e6",
        "--fy",
        "400e6",
        "--added-mass",
        "30000",
        "--scale",
        "1",
        "--wall",
        "x0:1:1-2",
        "--wall-thickness",
        "0.2",
        "-o",
        model.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = dir.path().join("push");
    let o = fem2rbd(&[
        "--quiet",
        "pushover",
        model.to_str().unwrap(),
        "--drift",
        "0.0008",
        "--step",
        "0.0002",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let ours = read_capacity(&out.join("capacity.csv"));
    assert_eq!(ours.len(), 5, "gravity and four steps");
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("pushover.json")).unwrap()).unwrap();
    let theirs = openseespy_pushover(dir.path(), &model, None, &summary);
    assert!(theirs["stopped_at"].is_null(), "OpenSees stopped: {theirs}");
    let curve = theirs["curve"].as_array().unwrap();
    assert_eq!(curve.len(), ours.len());
    let peak = ours.iter().map(|r| r[4].abs()).fold(0.0, f64::max);
    let mut worst = 0.0f64;
    for (a, b) in ours.iter().zip(curve) {
        assert!((a[1] - b["u"].as_f64().unwrap()).abs() < 1e-9);
        worst = worst.max((a[4] + b["r"][0].as_f64().unwrap()).abs());
    }
    let last = ours.last().unwrap();
    eprintln!(
        "wall building to 0.08 %: V = {:.1} kN (wall {:.1} kN, frame {:.1} kN), max |ΔV| \
         against OpenSees {worst:.3e} N",
        last[4] / 1e3,
        last[10] / 1e3,
        last[9] / 1e3
    );
    assert!(
        worst < 1e-6 * peak,
        "base shear differs by {worst} N (peak {peak} N)"
    );
    assert!(
        last[10] > 0.7 * last[4],
        "the wall carries most of the base shear"
    );
    assert!((last[9] + last[10] - last[4]).abs() < 1e-6 * last[4]);
}

#[test]
fn pushover_refuses_bad_options_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p");
    let o = fem2rbd(&[
        "pushover",
        MODEL,
        "--drift",
        "0",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--drift = 0"), "{err}");
    let o = fem2rbd(&[
        "pushover",
        MODEL,
        "--node",
        "99999",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--node 99999: no such node"), "{err}");
    let o = fem2rbd(&[
        "pushover",
        MODEL,
        "--pattern",
        "parabolic",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("unknown load pattern `parabolic`"), "{err}");
    assert!(!out.exists(), "nothing written");
}
