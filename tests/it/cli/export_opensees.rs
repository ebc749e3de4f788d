//! The OpenSees export of frame3 reproduces the reference OpenSees results
//! (shared/reference/opensees-frame3/results.md). Needs python3 with openseespy 3.7.1.
use crate::support::opensees_json;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

const MODEL: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/data/frame3-standin/model.toml"
);
const BIN: &str = env!("CARGO_BIN_EXE_fem2rbd");

fn export(dir: &Path, name: &str, extra: &[&str]) -> PathBuf {
    let out = dir.join(name);
    let st = Command::new(BIN)
        .args(["export", "opensees", MODEL, "-o"])
        .arg(&out)
        .args(extra)
        .output()
        .expect("run fem2rbd");
    assert!(
        st.status.success(),
        "export failed: {}",
        String::from_utf8_lossy(&st.stderr)
    );
    out
}

/// Runs the script; returns the JSON printed on its last stdout line.
fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The mode with the largest share of `key`.
fn mode_by(modes: &[Value], key: &str) -> (f64, f64) {
    let m = modes
        .iter()
        .max_by(|a, b| {
            a[key]
                .as_f64()
                .unwrap()
                .total_cmp(&b[key].as_f64().unwrap())
        })
        .unwrap();
    (m["T"].as_f64().unwrap(), m[key].as_f64().unwrap())
}

#[test]
fn exported_frame3_has_the_reference_periods_in_every_variant() {
    let dir = tempfile::tempdir().unwrap();
    for variant in ["force", "disp", "elastic"] {
        let script = export(
            dir.path(),
            &format!("{variant}.py"),
            &["--variant", variant],
        );
        let v = opensees_json(&script, &["eigen", "9"]);
        let modes = v["modes"].as_array().unwrap();
        assert_eq!(modes.len(), 9);
        let (tx, sx) = mode_by(modes, "X");
        let (ty, sy) = mode_by(modes, "Y");
        let (tt, st) = mode_by(modes, "RZ");
        eprintln!(
            "{variant}: TX {tx:.5} ({sx:.2}) TY {ty:.5} ({sy:.2}) Ttorsion {tt:.5} ({st:.2})"
        );
        assert!(
            sx > 0.5 && sy > 0.5 && st > 0.5,
            "mode shapes not identified"
        );
        assert!(rel(tx, 0.3160) < 1e-3, "{variant}: T_X = {tx}");
        assert!(rel(ty, 0.3160) < 1e-3, "{variant}: T_Y = {ty}");
        assert!(rel(tt, 0.1806) < 1e-3, "{variant}: T_torsion = {tt}");
    }
}

#[test]
fn exported_frame3_gravity_sag_matches_reference() {
    let dir = tempfile::tempdir().unwrap();
    for (variant, want) in [("force", -8.9e-3), ("disp", -8.8e-3)] {
        let script = export(
            dir.path(),
            &format!("{variant}.py"),
            &["--variant", variant],
        );
        let v = opensees_json(&script, &["gravity"]);
        assert_eq!(v["ok"], true);
        let uz = v["disp"]["312"][2].as_f64().unwrap();
        eprintln!("{variant}: roof-centre sag {:.3} mm", uz * 1e3);
        assert!(
            rel(uz, want) < 0.02,
            "{variant}: uz(312) = {uz} m, reference {want}"
        );
    }
}

fn record(name: &str) -> PathBuf {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data/ground-motions")
        .join(name);
    assert!(
        path.exists(),
        "El Centro record {} not found",
        path.display()
    );
    path
}

/// Runs LC1 (0.10/0.08/0.06 g) for `duration` s with `variant` and compares the
/// roof-centre (node 312) displacements with the reference table of results.md §4
/// (values in mm, given to 3 decimals): `samples` = (t, ux, uy).
fn lc1_matches(variant: &str, duration: &str, samples: &[(f64, f64, f64)]) {
    let dir = tempfile::tempdir().unwrap();
    let gm = [
        format!("X={},0.10", record("RSN6_IMPVALL.I_I-ELC180.AT2").display()),
        format!("Y={},0.08", record("RSN6_IMPVALL.I_I-ELC270.AT2").display()),
        format!("Z={},0.06", record("RSN6_IMPVALL.I_I-ELC-UP.AT2").display()),
    ];
    let mut args = vec!["--variant", variant, "--duration", duration];
    for g in &gm {
        args.extend(["--gm", g.as_str()]);
    }
    let script = export(dir.path(), &format!("th_{variant}.py"), &args);
    let csv = dir.path().join(format!("th_{variant}.csv"));
    let v = opensees_json(&script, &["th", csv.to_str().unwrap()]);
    assert!(v["t_diverge"].is_null());
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let ix = header.iter().position(|h| *h == "ux_312").unwrap();
    let iy = header.iter().position(|h| *h == "uy_312").unwrap();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    for &(t, ux, uy) in samples {
        let row = rows
            .iter()
            .find(|r| (r[0] - t).abs() < 1e-9)
            .expect("sample time");
        let (gx, gy) = (row[ix] * 1e3, row[iy] * 1e3);
        eprintln!("{variant} t={t}: ux {gx:.4} (ref {ux}) uy {gy:.4} (ref {uy}) mm");
        assert!(
            (gx - ux).abs() < 0.002 + 2e-3 * ux.abs(),
            "{variant} ux at {t}"
        );
        assert!(
            (gy - uy).abs() < 0.002 + 2e-3 * uy.abs(),
            "{variant} uy at {t}"
        );
    }
}

#[test]
fn exported_frame3_lc1_elastic_history_matches_reference_samples() {
    lc1_matches(
        "elastic",
        "3.0",
        &[(2.0, 0.457, -1.740), (3.0, -5.047, 1.008)],
    );
}

#[test]
fn exported_frame3_lc1_force_history_matches_reference_samples() {
    lc1_matches("force", "2.0", &[(2.0, -0.161, -1.738)]);
}

#[test]
fn bad_export_options_are_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.py");
    for (args, msg) in [
        (
            vec!["--gm", "W=x.AT2,0.1"],
            "unknown direction \"W\" (use X, Y or Z)",
        ),
        (vec!["--gm", "X"], "expected DIR=PATH[,pga=G]"),
        (vec!["--gm", "X=x.AT2,abc"], "PGA \"abc\" is not a number"),
        (
            vec!["--gm", "X=/nonexistent/x.AT2,0.1"],
            "ground-motion file: /nonexistent/x.AT2 does not exist",
        ),
        (
            vec!["--variant", "fiber"],
            "--variant \"fiber\": use force, disp or elastic",
        ),
        (vec!["--dt", "0"], "--dt = 0 s: must be in [1e-6, 0.1] s"),
    ] {
        let st = Command::new(BIN)
            .args(["export", "opensees", MODEL, "-o"])
            .arg(&out)
            .args(&args)
            .output()
            .unwrap();
        assert!(!st.status.success(), "{args:?} should fail");
        let err = String::from_utf8_lossy(&st.stderr);
        assert!(err.contains(msg), "{args:?}: {err}");
        assert!(!out.exists());
    }
}
