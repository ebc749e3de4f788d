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

    let script = dir.path().join("frame3.py");
    let o = fem2rbd(&[
        "export",
        "opensees",
        MODEL,
        "-o",
        script.to_str().unwrap(),
        "--variant",
        "force",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let spec = serde_json::json!({
        "node": summary["control_node"],
        "dof": 1,
        "loads": summary["lateral_loads"],
        "targets": summary["targets_m"],
        "step": summary["step_m"],
    });
    let spec_path = dir.path().join("spec.json");
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
    let theirs: Value = serde_json::from_str(last).unwrap();
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
