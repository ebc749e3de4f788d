//! Shared helpers of the frame3 verification tests (`tests/fe_verify_*.rs`): the
//! project's frame3 model (`data/frame3-standin/model.toml`), the El Centro records
//! (`data/ground-motions/`) scaled to a load case, and the OpenSees reference
//! series (`tests/fixtures/opensees-frame3/`, copied from
//! the OpenSees outputs of `tests/fixtures/opensees-frame3/run_frame3.py`, see its README).
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use fem2rbd_fe::fe::analysis::transient::{StepControl, StopReason};
use fem2rbd_fe::fe::build::{BuildOptions, Variant};
use fem2rbd_fe::fe::run::{run_ground_motion, RunOptions, RunResult};
use fem2rbd_fe::model::Model;
use fem2rbd_fe::motion::{Format, GroundMotion};

pub fn root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

pub fn fixture(name: &str) -> PathBuf {
    root().join("tests/fixtures/opensees-frame3").join(name)
}

pub fn frame3() -> Model {
    Model::load(root().join("data/frame3-standin/model.toml"))
        .expect("data/frame3-standin/model.toml")
}

/// El Centro 1940 (RSN6): X ← ELC180, Y ← ELC270, Z ← ELC-UP, each scaled to its PGA (g).
pub fn el_centro(pga_g: [f64; 3]) -> GroundMotion {
    let gm_dir = root().join("data/ground-motions");
    let p = |n: &str| gm_dir.join(n);
    let (x, y, z) = (
        p("RSN6_IMPVALL.I_I-ELC180.AT2"),
        p("RSN6_IMPVALL.I_I-ELC270.AT2"),
        p("RSN6_IMPVALL.I_I-ELC-UP.AT2"),
    );
    let mut gm = GroundMotion::from_files(
        [Some(x.as_path()), Some(y.as_path()), Some(z.as_path())],
        Format::Auto,
    )
    .expect("El Centro records");
    gm.scale_to_pga(pga_g.map(Some)).expect("scale");
    gm
}

pub const LC1: [f64; 3] = [0.10, 0.08, 0.06];
pub const LC5: [f64; 3] = [0.93, 1.19, 0.57];

/// Runs `model` under `motion` to `t_end` (s) with Δt = 0.005 s, recording every step
/// of the listed node tags; `stop` is the observer's collapse test on the domain.
pub fn run(
    model: &Model,
    motion: &GroundMotion,
    variant: Variant,
    t_end: f64,
    nodes: &[u32],
    stop: &mut dyn FnMut(&fem2rbd_fe::fe::domain::Domain) -> bool,
) -> RunResult {
    let options = RunOptions {
        build: BuildOptions {
            variant,
            ..Default::default()
        },
        duration: Some(t_end),
        record_nodes: Some(nodes.to_vec()),
        ..Default::default()
    };
    let r = run_ground_motion(model, motion, &options, &mut |_, d| {
        if stop(d) {
            StepControl::Stop
        } else {
            StepControl::Continue
        }
    })
    .expect("run");
    if let StopReason::Diverged { time, reason, .. } = &r.transient.stop {
        panic!("diverged at {time} s: {reason}");
    }
    r
}

/// Reads an OpenSees reference CSV (header line, then numbers): columns by name.
pub fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let head: Vec<String> = lines
        .next()
        .expect("header")
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split(',').map(|x| x.trim().parse().unwrap()).collect())
        .collect();
    (head, rows)
}

/// Value of series `y` (sampled at times `t`) at time `at`, linearly interpolated.
pub fn at(t: &[f64], y: &[f64], at: f64) -> f64 {
    let i = t.partition_point(|&x| x < at);
    if i == 0 {
        return y[0];
    }
    if i >= t.len() {
        return *y.last().unwrap();
    }
    let (t0, t1) = (t[i - 1], t[i]);
    let w = if t1 > t0 { (at - t0) / (t1 - t0) } else { 1.0 };
    y[i - 1] + w * (y[i] - y[i - 1])
}
