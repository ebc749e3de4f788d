//! The ParaView time series written by `output::vtk::write_pvd`, read back by meshio (an
//! independent VTK XML reader, `pip install meshio==5.3.5`), against the closed-form
//! trajectories. Needs `python3` with meshio; fails (does not skip) when it is missing.
use super::gltf_common as common;

use common::{falling_scene, ground_pose, Throw};
use fem2rbd::output::vtk::{write_pvd, HEX_CORNERS};
use serde_json::Value;
use std::path::Path;
use std::process::Command;

/// Each file as meshio reads it (one python3 call for all).
fn read_vtus(paths: &[std::path::PathBuf]) -> Vec<Value> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/gltf/read_vtu.py");
    let out = Command::new("python3")
        .arg(script)
        .args(paths)
        .output()
        .unwrap_or_else(|e| panic!("cannot run python3: {e}"));
    let stderr = String::from_utf8_lossy(&out.stderr);
    if out.status.code() == Some(3) {
        panic!("meshio is missing: pip install meshio==5.3.5\n{stderr}");
    }
    assert!(
        out.status.success(),
        "meshio cannot read {paths:?}: {stderr}"
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

/// Corner `c` of a box of half sizes `h` at position `p`, rotation `q = [w, x, y, z]`
/// (unit), by the rotation formula v' = v + 2w (u×v) + 2 u×(u×v).
fn corner(p: [f64; 3], q: [f64; 4], h: [f64; 3], c: usize) -> [f64; 3] {
    let v = [0, 1, 2].map(|i| HEX_CORNERS[c][i] * h[i]);
    let (w, u) = (q[0], [q[1], q[2], q[3]]);
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let uv = cross(u, v);
    let uuv = cross(u, uv);
    [0, 1, 2].map(|i| p[i] + v[i] + 2.0 * w * uv[i] + 2.0 * uuv[i])
}

#[test]
fn paraview_series_matches_the_closed_form_motion() {
    let scene = falling_scene(30, 12, true);
    let dir = tempfile::tempdir().unwrap();
    let pvd = dir.path().join("collapse.pvd");
    let files = write_pvd(&scene, &pvd).unwrap();
    assert_eq!(files.len(), 12);

    // The collection lists every file with its time, in order.
    let text = std::fs::read_to_string(&pvd).unwrap();
    let entries: Vec<(f64, String)> = text
        .lines()
        .filter(|l| l.contains("<DataSet"))
        .map(|l| {
            let attr = |name: &str| {
                let start = l.find(&format!("{name}=\"")).unwrap() + name.len() + 2;
                l[start..start + l[start..].find('"').unwrap()].to_string()
            };
            (attr("timestep").parse().unwrap(), attr("file"))
        })
        .collect();
    assert_eq!(entries.len(), 12);
    for (k, (t, file)) in entries.iter().enumerate() {
        assert_eq!(*t, scene.times_s[k], "timestep round-trips exactly");
        assert_eq!(dir.path().join(file), files[k]);
    }

    let mut worst = 0.0f64;
    for (k, mesh) in read_vtus(&files).iter().enumerate() {
        let t = scene.times_s[k];
        let cells = mesh["cells"].as_array().unwrap();
        assert_eq!(cells.len(), 1);
        assert_eq!(cells[0]["type"], "hexahedron");
        let conn = cells[0]["data"].as_array().unwrap();
        assert_eq!(conn.len(), 31, "30 bodies + ground");
        let points = mesh["points"].as_array().unwrap();
        let point = |i: &Value| -> Vec<f64> {
            points[i.as_u64().unwrap() as usize]
                .as_array()
                .unwrap()
                .iter()
                .map(|c| c.as_f64().unwrap())
                .collect()
        };
        let body_id = &mesh["cell_data"]["body_id"][0];
        let element_type = &mesh["cell_data"]["element_type"][0];
        for (i, body) in scene.bodies.iter().enumerate() {
            assert_eq!(body_id[i], i as i64);
            // Sorted types: 0 Beam, 1 Column, 2 Ground, 3 Slab.
            let expected_type = ["Beam", "Column", "Ground", "Slab"]
                .iter()
                .position(|n| *n == body.type_name)
                .unwrap();
            assert_eq!(element_type[i], expected_type as i64);
            let throw = Throw::of_body(i);
            let (p, q) = (throw.position(t), throw.quaternion(t));
            for (c, id) in conn[i].as_array().unwrap().iter().enumerate() {
                let got = point(id);
                let want = corner(p, q, body.half_extents, c);
                for d in 0..3 {
                    let err = (got[d] - want[d]).abs();
                    worst = worst.max(err);
                    assert!(
                        err < 1e-12,
                        "body {i} t={t} corner {c}: {got:?} vs {want:?}"
                    );
                }
            }
        }
        assert_eq!(body_id[30], -1);
        assert_eq!(element_type[30], 2);
        let g0 = ground_pose(t);
        let (gp, gq) = (g0.position, g0.orientation);
        let g = scene.ground.as_ref().unwrap();
        for (c, id) in conn[30].as_array().unwrap().iter().enumerate() {
            let (got, want) = (point(id), corner(gp, gq, g.half_extents, c));
            for d in 0..3 {
                assert!(
                    (got[d] - want[d]).abs() < 1e-12,
                    "ground corner {c} at t={t}"
                );
            }
        }
    }
    eprintln!("meshio corners vs closed form: max |error| = {worst:.2e} m");

    // Deterministic: a second write gives the same bytes.
    let dir2 = tempfile::tempdir().unwrap();
    let files2 = write_pvd(&scene, dir2.path().join("collapse.pvd")).unwrap();
    for (a, b) in files.iter().zip(&files2) {
        assert_eq!(std::fs::read(a).unwrap(), std::fs::read(b).unwrap());
    }
}

#[test]
fn bad_input_names_the_item_and_writes_no_collection() {
    let mut scene = falling_scene(3, 4, false);
    scene.bodies[2].poses[1].orientation = [0.0; 4];
    let dir = tempfile::tempdir().unwrap();
    let pvd = dir.path().join("bad.pvd");
    let err = format!("{:#}", write_pvd(&scene, &pvd).unwrap_err());
    assert!(
        err.contains("body 'E102' (#2) at keyframe 1") && err.contains("zero"),
        "{err}"
    );
    assert!(!pvd.exists());
}
