//! `collapse.glb` holds the survivable voids of the final ruin: on the CI-sized frame3 run
//! folder of [`super::frame3`], one node per survivable void of `voids.json`, named
//! `void-NN <pattern> <volume> m3`, in its order; each node's mesh is the void's boxes
//! (12 triangles per box, its POSITION bounds the union of the boxes from the grid of
//! `voids.json`) with the translucent material of its pattern; after them one node per
//! survivable void a rescuer or a camera reaches, `route-NN <kind> <crawl> m`, a `LINES`
//! primitive whose points are the route's `path_m` (as f32) joined in order, with the
//! material of its kind (the rescuer's where the rescuer reaches the void); the Khronos validator
//! finds no error and no warning in the file; `fem2rbd export gltf` writes the same bytes,
//! and so does `fem2rbd voids` rewriting the folder.
use super::frame3::{fem2rbd, run_dir};
use crate::output::gltf_common::Glb;
use serde_json::Value;
use std::path::Path;
use std::process::Command;

#[test]
fn collapse_glb_holds_the_survivable_voids_of_voids_json() {
    let dir = run_dir();
    let vj: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("voids.json")).unwrap()).unwrap();
    let bytes = std::fs::read(dir.join("collapse.glb")).unwrap();
    let glb = Glb::parse(&bytes);
    let nodes = glb.json["nodes"].as_array().unwrap();
    let drawn: Vec<&Value> = nodes
        .iter()
        .filter(|n| n["name"].as_str().unwrap_or("").starts_with("void-"))
        .collect();
    let survivable: Vec<&Value> = vj["voids"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|v| v["survivable"] == true)
        .collect();
    eprintln!(
        "{} voids, {} survivable, {} void nodes",
        vj["voids_count"],
        survivable.len(),
        drawn.len()
    );
    assert!(!survivable.is_empty(), "the CI ruin has survivable voids");
    assert_eq!(drawn.len(), survivable.len());
    assert_eq!(vj["survivable_count"], survivable.len());
    let origin: Vec<f64> = vj["grid"]["origin_m"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    let h = vj["grid"]["cell_m"].as_f64().unwrap();
    for (node, v) in drawn.iter().zip(&survivable) {
        let name = format!(
            "void-{:02} {} {:.4} m3",
            v["void"].as_u64().unwrap(),
            v["pattern"].as_str().unwrap(),
            v["volume_m3"].as_f64().unwrap()
        );
        assert_eq!(node["name"], name.as_str());
        let mesh = &glb.json["meshes"][node["mesh"].as_u64().unwrap() as usize];
        let prim = &mesh["primitives"][0];
        let material = &glb.json["materials"][prim["material"].as_u64().unwrap() as usize];
        assert_eq!(
            material["name"],
            format!("void {}", v["pattern"].as_str().unwrap())
        );
        assert_eq!(material["alphaMode"], "BLEND");
        let boxes = v["boxes"].as_array().unwrap();
        let index = glb.accessor(prim["indices"].as_u64().unwrap() as usize);
        assert_eq!(
            index["count"],
            36 * boxes.len(),
            "{name}: 12 triangles a box"
        );
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for b in boxes {
            for d in 0..3 {
                lo[d] = lo[d].min(origin[d] + b[d].as_f64().unwrap() * h);
                hi[d] = hi[d].max(origin[d] + b[d + 3].as_f64().unwrap() * h);
            }
        }
        let pos = glb.accessor(prim["attributes"]["POSITION"].as_u64().unwrap() as usize);
        for d in 0..3 {
            assert_eq!(
                pos["min"][d].as_f64().unwrap(),
                f64::from(lo[d] as f32),
                "{name}"
            );
            assert_eq!(
                pos["max"][d].as_f64().unwrap(),
                f64::from(hi[d] as f32),
                "{name}"
            );
        }
    }
    // The route lines: one per survivable void a rescuer or a camera reaches, after the
    // voids, its points those of path_m.
    let lines: Vec<&Value> = nodes
        .iter()
        .filter(|n| n["name"].as_str().unwrap_or("").starts_with("route-"))
        .collect();
    let routed: Vec<(&Value, &str)> = survivable
        .iter()
        .filter_map(|v| {
            ["rescuer", "camera"]
                .into_iter()
                .find(|k| v[*k]["reached"] == true)
                .map(|k| (*v, k))
        })
        .collect();
    eprintln!(
        "{} route lines, {} of the rescuer",
        lines.len(),
        routed.iter().filter(|r| r.1 == "rescuer").count()
    );
    assert!(
        !routed.is_empty(),
        "the CI ruin has reached survivable voids"
    );
    assert_eq!(lines.len(), routed.len());
    for (node, (v, kind)) in lines.iter().zip(&routed) {
        let name = format!(
            "route-{:02} {kind} {:.3} m",
            v["void"].as_u64().unwrap(),
            v[*kind]["route_m"].as_f64().unwrap()
        );
        assert_eq!(node["name"], name.as_str());
        let mesh = &glb.json["meshes"][node["mesh"].as_u64().unwrap() as usize];
        let prim = &mesh["primitives"][0];
        assert_eq!(prim["mode"], 1, "{name}: LINES");
        let material = &glb.json["materials"][prim["material"].as_u64().unwrap() as usize];
        assert_eq!(material["name"], format!("route {kind}"));
        let want: Vec<[f32; 3]> = v[*kind]["path_m"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| [0, 1, 2].map(|d| p[d].as_f64().unwrap() as f32))
            .collect();
        assert!(want.len() >= 2, "{name}");
        let points = glb.f32s(prim["attributes"]["POSITION"].as_u64().unwrap() as usize);
        let points: Vec<[f32; 3]> = points.iter().map(|p| [p[0], p[1], p[2]]).collect();
        assert_eq!(points, want, "{name}");
        let index = glb.u32s(prim["indices"].as_u64().unwrap() as usize);
        let pairs: Vec<u32> = (1..want.len() as u32).flat_map(|i| [i - 1, i]).collect();
        assert_eq!(index, pairs, "{name}: segments 0-1, 1-2, ...");
    }

    // The void and route nodes are children of the root, like the bodies.
    let root = &nodes[0]["children"];
    for (i, n) in nodes.iter().enumerate() {
        let name = n["name"].as_str().unwrap_or("");
        if name.starts_with("void-") || name.starts_with("route-") {
            assert!(root.as_array().unwrap().contains(&Value::from(i)));
        }
    }

    // The Khronos validator: no error, no warning.
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/gltf/validate.mjs");
    let out = Command::new("node")
        .arg(&script)
        .arg(dir.join("collapse.glb"))
        .output()
        .expect("node (scripts/setup-node.sh)");
    let report: Value = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "validator gave no report ({e}): {}",
            String::from_utf8_lossy(&out.stderr)
        )
    });
    assert_eq!(report["issues"]["numErrors"], 0, "{report:#}");
    assert_eq!(report["issues"]["numWarnings"], 0, "{report:#}");

    // export gltf and voids give the same bytes.
    let tmp = tempfile::tempdir().unwrap();
    let exported = tmp.path().join("export.glb");
    fem2rbd(&[
        "export".as_ref(),
        "gltf".as_ref(),
        dir.as_os_str(),
        "-o".as_ref(),
        exported.as_os_str(),
    ]);
    assert!(std::fs::read(&exported).unwrap() == bytes, "export gltf");
    let copy = tmp.path().join("run");
    std::fs::create_dir(&copy).unwrap();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_file() {
            std::fs::copy(&p, copy.join(p.file_name().unwrap())).unwrap();
        }
    }
    fem2rbd(&["voids".as_ref(), copy.as_os_str()]);
    assert!(
        std::fs::read(copy.join("collapse.glb")).unwrap() == bytes,
        "voids rewrites the same collapse.glb"
    );
}
