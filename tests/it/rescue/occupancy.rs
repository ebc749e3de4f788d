//! The exact box–cell overlap (`src/rescue/occupancy.rs`) against an independent count in
//! numpy: each cell's covered fraction as the share of a 48³ lattice of the cell's points
//! (cell midpoints of a 48³ subdivision) inside the box, tested with the box's half-space
//! inequalities, for every cell the box cuts and every tenth of the others. The
//! tolerance is 0.015 (a plane cut moves the lattice count by at most a few 1/48 layers
//! of points, far less on average). Needs `python3` with numpy (`bash scripts/setup.sh`).
use fem2rbd::bullet::Pose;
use fem2rbd::rescue::occupancy::cube_box_overlap;
use fem2rbd::rescue::RuinBox;
use std::io::Write;
use std::process::{Command, Stdio};

const SCRIPT: &str = r#"
import json, sys
import numpy as np
d = json.load(sys.stdin)
h = d["h"]; c = np.array(d["centre"]); R = np.array(d["axes"]); e = np.array(d["half"])
n = 48
t = (np.arange(n) + 0.5) / n - 0.5
X, Y, Z = np.meshgrid(t, t, t, indexing="ij")
P = np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1) * h
out = []
for cell in d["cells"]:
    q = P + np.array(cell) - c
    local = q @ R  # coordinates along the box axes (columns of R)
    inside = np.all(np.abs(local) <= e, axis=1)
    out.append(float(inside.mean()))
print(json.dumps(out))
"#;

#[test]
fn overlaps_agree_with_a_numpy_lattice_count() {
    let pose = Pose {
        position: [0.031, -0.047, 0.52],
        // A turn of 0.7 rad about the axis (1, 2, 3)/√14.
        orientation: {
            let (s, c) = (0.35f64.sin(), 0.35f64.cos());
            let k = 14f64.sqrt();
            [c, s / k, 2.0 * s / k, 3.0 * s / k]
        },
    };
    let he = [0.42, 0.23, 0.11];
    let r = RuinBox::axes(&pose);
    let axes = [0, 1, 2].map(|k| [r[(0, k)], r[(1, k)], r[(2, k)]]);
    let h = 0.1;
    // The cells of a 12 × 12 × 12 block around the box: all cut ones, a tenth of the others.
    let mut cells = Vec::new();
    let mut exact = Vec::new();
    let mut total = 0.0;
    for i in -6..6 {
        for j in -6..6 {
            for k in -1..11 {
                let cc = [
                    (i as f64 + 0.5) * h,
                    (j as f64 + 0.5) * h,
                    (k as f64 + 0.5) * h,
                ];
                let rel = [0, 1, 2].map(|d| pose.position[d] - cc[d]);
                let f = cube_box_overlap(h, rel, axes, he) / (h * h * h);
                total += f;
                if (f > 0.0 && f < 1.0) || (i + j + k) % 10 == 0 {
                    cells.push(cc);
                    exact.push(f);
                }
            }
        }
    }
    let input = serde_json::json!({
        "h": h, "centre": pose.position, "half": he,
        "axes": [[r[(0, 0)], r[(0, 1)], r[(0, 2)]],
                 [r[(1, 0)], r[(1, 1)], r[(1, 2)]],
                 [r[(2, 0)], r[(2, 1)], r[(2, 2)]]],
        "cells": cells,
    });
    let mut child = Command::new("python3")
        .args(["-c", SCRIPT])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot run python3 ({e}): bash scripts/setup.sh"));
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.to_string().as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "numpy is not installed for python3 (bash scripts/setup.sh):\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let counted: Vec<f64> = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(counted.len(), exact.len());
    let mut cut = 0;
    for (n, (a, b)) in exact.iter().zip(&counted).enumerate() {
        assert!(
            (a - b).abs() <= 0.01,
            "cell {:?}: exact {a}, numpy {b}",
            cells[n]
        );
        if *a > 0.0 && *a < 1.0 {
            cut += 1;
        }
    }
    // The test covers many cut cells, and the exact fractions sum to the box's volume.
    assert!(cut > 150, "{cut} cut cells");
    let total = total * h * h * h;
    let volume = 8.0 * he[0] * he[1] * he[2];
    assert!((total - volume).abs() < 1e-12, "{total} vs {volume}");
}
