//! The calibrated Case 1 frame (`data/frame3/model.toml`, docs/case1.md) against OpenSees
//! runs of the same model (`data/frame3/opensees-case1.json`, written by
//! `scripts/case1-opensees.py` from `fem2rbd export opensees`; openseespy 3.7.1).
//!
//! * Periods of the initial stiffness, modes identified by shape: X, Y and torsion within
//!   0.05 % of OpenSees, and the calibration targets of the paper (T1 = T2 = 0.316 s,
//!   torsion 0.178 s) within 0.05 %.
//! * LC1 (El Centro RSN6: X ← ELC180 0.10 g, Y ← ELC270 0.08 g, Z ← UP 0.06 g, time
//!   compressed by 0.5, Δt = 0.005 s, the model's displacement-based fibre elements): the
//!   first 3 s (600 steps, the LC1 peak of |ux| lies at 2.9 s), roof-centre node 312: at
//!   every OpenSees step |fem2rbd − OpenSees| ≤ 0.2 % of the window's peak |ux| resp.
//!   |uy|, and the window peaks agree within 0.2 % at the same step.
//!
//! Debug profile: about 1 s for the periods, ~30 s for the LC1 window (2 cores shared).
use std::path::PathBuf;

use fem2rbd_fe::fe::analysis::modal::{modal_analysis, ModalSettings, ModeSelection};
use fem2rbd_fe::fe::analysis::transient::StopReason;
use fem2rbd_fe::fe::build::{build_domain, BuildOptions};
use fem2rbd_fe::fe::run::{mode_character, run_ground_motion, ModeCharacter, RunOptions};
use fem2rbd_fe::model::Model;
use fem2rbd_fe::motion::{Format, GroundMotion};
use serde_json::Value;

fn root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn model() -> Model {
    Model::load(root().join("data/frame3/model.toml")).expect("data/frame3/model.toml")
}

fn reference() -> Value {
    let p = root().join("data/frame3/opensees-case1.json");
    let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    serde_json::from_str(&text).expect("opensees-case1.json")
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn case1_periods_match_opensees_and_the_paper() {
    let r = reference();
    let model = model();
    let mut built = build_domain(&model, &BuildOptions::default()).unwrap();
    let modal = modal_analysis(
        &mut built.domain,
        &ModalSettings {
            selection: ModeSelection::Lowest,
            modes: 9,
            ..Default::default()
        },
    )
    .unwrap();
    let chars: Vec<ModeCharacter> = (0..9)
        .map(|k| mode_character(&built.domain, &modal, k))
        .collect();
    for (c, key, paper) in [
        (ModeCharacter::X, "x", 0.316),
        (ModeCharacter::Y, "y", 0.316),
        (ModeCharacter::Torsion, "torsion", 0.178),
    ] {
        let k = chars
            .iter()
            .position(|&x| x == c)
            .unwrap_or_else(|| panic!("no {c} mode among {chars:?}"));
        let t = modal.periods[k];
        let t_os = r["periods"][key].as_f64().unwrap();
        let (d_os, d_paper) = ((t - t_os) / t_os, (t - paper) / paper);
        eprintln!(
            "mode {} ({c}): T = {t:.5} s, OpenSees {t_os:.5} s ({:+.4} %), paper {paper} s ({:+.4} %)",
            k + 1,
            d_os * 100.0,
            d_paper * 100.0
        );
        assert!(d_os.abs() < 5e-4, "{c}: {t} s vs OpenSees {t_os} s");
        assert!(d_paper.abs() < 5e-4, "{c}: {t} s vs the paper's {paper} s");
    }
}

#[test]
fn case1_lc1_first_3s_matches_opensees() {
    let r = reference();
    let w = &r["lc1_window"];
    let (t_ref, ux_ref, uy_ref) = (floats(&w["t"]), floats(&w["ux"]), floats(&w["uy"]));
    let window = w["duration_s"].as_f64().unwrap();
    let ts = r["time_scale"].as_f64().unwrap();
    assert_eq!(ts, 0.5);
    let pga = floats(&r["load_cases"]["LC1"]["pga_g"]);
    assert_eq!(pga, [0.10, 0.08, 0.06]);

    let gm_dir = root().join("data/ground-motions");
    let files =
        ["ELC180", "ELC270", "ELC-UP"].map(|c| gm_dir.join(format!("RSN6_IMPVALL.I_I-{c}.AT2")));
    let mut gm = GroundMotion::from_files(
        [
            Some(files[0].as_path()),
            Some(files[1].as_path()),
            Some(files[2].as_path()),
        ],
        Format::Auto,
    )
    .unwrap();
    gm.scale_to_pga([Some(pga[0]), Some(pga[1]), Some(pga[2])])
        .unwrap();
    gm.time_scale(ts).unwrap();

    let options = RunOptions {
        duration: Some(window),
        record_nodes: Some(vec![312]),
        ..Default::default()
    };
    let res = run_ground_motion(&model(), &gm, &options, &mut |_, _| {
        fem2rbd_fe::fe::analysis::transient::StepControl::Continue
    })
    .unwrap();
    assert!(
        !matches!(res.transient.stop, StopReason::Diverged { .. }),
        "{:?}",
        res.transient.stop
    );
    let h = &res.transient.history;
    // history row 0 is t = 0; OpenSees's rows start at the first step
    let rows: Vec<(f64, f64, f64)> = h
        .time
        .iter()
        .zip(&h.disp)
        .filter(|(t, _)| **t > 0.0)
        .map(|(t, d)| (*t, d[0][0], d[0][1]))
        .collect();
    assert_eq!(rows.len(), t_ref.len(), "steps in the window");
    let peak = |v: &[f64]| {
        v.iter().enumerate().fold(
            (0, 0.0f64),
            |a, (i, &x)| if x.abs() > a.1.abs() { (i, x) } else { a },
        )
    };
    let (ix_ref, px_ref) = peak(&ux_ref);
    let (iy_ref, py_ref) = peak(&uy_ref);
    let ux: Vec<f64> = rows.iter().map(|r| r.1).collect();
    let uy: Vec<f64> = rows.iter().map(|r| r.2).collect();
    let (ix, px) = peak(&ux);
    let (iy, py) = peak(&uy);
    let mut worst = (0.0f64, 0.0f64);
    for (k, &(t, x, y)) in rows.iter().enumerate() {
        assert!(
            (t - t_ref[k]).abs() < 1e-9,
            "step {k}: t {t} vs {}",
            t_ref[k]
        );
        worst.0 = worst.0.max((x - ux_ref[k]).abs() / px_ref.abs());
        worst.1 = worst.1.max((y - uy_ref[k]).abs() / py_ref.abs());
    }
    eprintln!(
        "LC1 0-{window} s, node 312: peak ux {:.4} mm at {:.3} s (OpenSees {:.4} mm at {:.3} s), \
         peak uy {:.4} mm at {:.3} s (OpenSees {:.4} mm at {:.3} s); max difference {:.4} % / {:.4} % \
         of the peaks",
        px * 1e3,
        rows[ix].0,
        px_ref * 1e3,
        t_ref[ix_ref],
        py * 1e3,
        rows[iy].0,
        py_ref * 1e3,
        t_ref[iy_ref],
        worst.0 * 100.0,
        worst.1 * 100.0
    );
    assert!(worst.0 < 2e-3 && worst.1 < 2e-3, "{worst:?}");
    assert_eq!((ix, iy), (ix_ref, iy_ref), "peak steps");
    assert!(((px - px_ref) / px_ref).abs() < 2e-3);
    assert!(((py - py_ref) / py_ref).abs() < 2e-3);
}
