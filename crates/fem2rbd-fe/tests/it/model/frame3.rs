//! The frame generator's defaults reproduce the reference frame3.json exactly.
use fem2rbd_fe::model::{self, generate, Model};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;

const REF: &str = concat!(
    concat!(env!("CARGO_MANIFEST_DIR"), "/../.."),
    "/data/frame3-standin/reference-frame3.json"
);
const TOML: &str = concat!(
    concat!(env!("CARGO_MANIFEST_DIR"), "/../.."),
    "/data/frame3-standin/model.toml"
);

fn close(a: f64, b: f64, what: &str) {
    let tol = 1e-12 * a.abs().max(b.abs()) + 1e-300;
    assert!(
        (a - b).abs() <= tol,
        "{what}: {a} vs {b} (rel {:e})",
        (a - b).abs() / b.abs().max(1e-300)
    );
}

fn reference() -> Value {
    serde_json::from_str(&std::fs::read_to_string(REF).unwrap()).unwrap()
}

fn check_against_reference(m: &Model) {
    let r = reference();
    // nodes
    let nodes = m.node_map();
    let rn = r["nodes"].as_array().unwrap();
    assert_eq!(rn.len(), m.nodes.len());
    for (k, n) in rn.iter().enumerate() {
        let t = n["tag"].as_u64().unwrap() as u32;
        assert_eq!(m.nodes[k].tag, t, "node order");
        let p = nodes[&t];
        for (c, v) in [("x", p.x), ("y", p.y), ("z", p.z)] {
            close(v, n[c].as_f64().unwrap(), &format!("node {t} {c}"));
        }
    }
    // supports
    let fix: Vec<u32> = r["fixed_nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["tag"].as_u64().unwrap() as u32)
        .collect();
    assert_eq!(m.supports.iter().map(|s| s.node).collect::<Vec<_>>(), fix);
    assert!(m.supports.iter().all(|s| s.dofs == [1; 6]));
    // materials
    let mats = m.material_map();
    let rm = r["uniaxial_materials"].as_array().unwrap();
    assert_eq!(rm.len(), m.materials.len());
    for mt in rm {
        let t = mt["tag"].as_u64().unwrap() as u32;
        let ours = mats[&t];
        assert_eq!(ours.type_name(), mt["type"].as_str().unwrap());
        for (name, v) in ours.parameters() {
            if name == "density" {
                continue;
            }
            close(
                v,
                mt[name].as_f64().unwrap(),
                &format!("material {t} {name}"),
            );
        }
    }
    // sections: fibers, GJ, elastic equivalent
    let secs = m.section_map();
    let rs = r["sections"].as_array().unwrap();
    for s in rs {
        let t = s["tag"].as_u64().unwrap() as u32;
        let ours = secs[&t];
        close(
            ours.gj().unwrap(),
            s["GJ"].as_f64().unwrap(),
            &format!("section {t} GJ"),
        );
        let fib = ours.fibers().unwrap();
        let rf = s["fibers"].as_array().unwrap();
        assert_eq!(fib.len(), rf.len(), "section {t} fiber count");
        for (k, (a, b)) in fib.iter().zip(rf).enumerate() {
            let b = b.as_array().unwrap();
            for (c, v) in [a.y(), a.z(), a.area()].iter().enumerate() {
                let w = b[c].as_f64().unwrap();
                if w == 0.0 {
                    assert!(v.abs() < 1e-15, "section {t} fiber {k}");
                } else {
                    close(*v, w, &format!("section {t} fiber {k}[{c}]"));
                }
            }
            assert_eq!(a.material() as u64, b[3].as_u64().unwrap());
        }
        let eq = ours.elastic_equivalent(&mats);
        let q = &s["elastic_equivalent"];
        for (name, v) in [
            ("EA", eq.ea),
            ("EIz", eq.eiz),
            ("EIy", eq.eiy),
            ("GJ", eq.gj),
        ] {
            let tol = 1e-11 * v.abs();
            assert!(
                (v - q[name].as_f64().unwrap()).abs() <= tol,
                "section {t} {name}"
            );
        }
    }
    // transformations
    let tr = m.transformation_map();
    for g in r["geom_transforms"].as_array().unwrap() {
        let t = g["tag"].as_u64().unwrap() as u32;
        assert_eq!(tr[&t].kind.opensees_name(), g["type"].as_str().unwrap());
        let v: Vec<f64> = g["vecxz"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        assert_eq!(tr[&t].vecxz.to_vec(), v);
    }
    // elements
    // FE content: the slab panels are rigid-body-only elements, absent from the reference
    let re = r["elements"].as_array().unwrap();
    let fe: Vec<_> = m.elements.iter().filter(|e| e.in_fe()).collect();
    assert_eq!(re.len(), fe.len());
    for (e, q) in fe.into_iter().zip(re) {
        assert_eq!(e.tag as u64, q["tag"].as_u64().unwrap());
        let qn: Vec<u32> = q["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_u64().unwrap() as u32)
            .collect();
        assert_eq!(e.nodes(), &qn[..], "element {} nodes", e.tag);
        assert_eq!(e.transf().unwrap() as u64, q["transf"].as_u64().unwrap());
        let grp = q
            .get("story")
            .or_else(|| q.get("floor"))
            .unwrap()
            .as_u64()
            .unwrap()
            .to_string();
        assert_eq!(e.group.0, grp, "element {} group", e.tag);
        match &e.kind {
            model::ElementKind::BeamColumn { section, .. } => {
                assert_eq!(q["type"], "beam_column");
                assert_eq!(*section as u64, q["section"].as_u64().unwrap());
                let want = if q["group"] == "column" {
                    "Column"
                } else {
                    "Beam"
                };
                assert_eq!(e.type_name, want);
            }
            model::ElementKind::ElasticStrip {
                e: em,
                g,
                width,
                thickness,
                ..
            } => {
                assert_eq!(q["type"], "elastic_beam_column");
                assert_eq!(e.type_name, "Slab");
                let (a, iy, iz, j) = model::strip_properties(*width, *thickness);
                for (name, v) in [
                    ("E", *em),
                    ("G", *g),
                    ("A", a),
                    ("Iy", iy),
                    ("Iz", iz),
                    ("J", j),
                ] {
                    close(
                        v,
                        q[name].as_f64().unwrap(),
                        &format!("element {} {name}", e.tag),
                    );
                }
            }
            other => panic!("unexpected element kind {other:?}"),
        }
    }
    // masses: every reference nodal mass; extra lumped mass only at fully fixed nodes
    let lumped = m.lumped_masses();
    let fixity = m.fixity();
    let mut seen = BTreeMap::new();
    for q in r["nodal_masses"].as_array().unwrap() {
        let t = q["tag"].as_u64().unwrap() as u32;
        let ours = lumped[&t];
        for (k, name) in ["mx", "my", "mz", "mrx", "mry", "mrz"].iter().enumerate() {
            close(
                ours[k],
                q[name].as_f64().unwrap(),
                &format!("mass of node {t} {name}"),
            );
        }
        seen.insert(t, ());
    }
    for t in lumped.keys() {
        if !seen.contains_key(t) {
            assert_eq!(
                fixity.get(t),
                Some(&[1; 6]),
                "mass at node {t} not in the reference"
            );
        }
    }
    // gravity loads
    let loads = m.gravity_loads();
    let rl = r["gravity_loads"]["loads"].as_array().unwrap();
    assert_eq!(loads.len(), rl.len());
    for ((t, fz), q) in loads.iter().zip(rl) {
        assert_eq!(*t as u64, q["tag"].as_u64().unwrap());
        close(
            *fz,
            q["Fz"].as_f64().unwrap(),
            &format!("gravity load at node {t}"),
        );
    }
    close(m.gravity.g, r["gravity"].as_f64().unwrap(), "g");
    // damping
    let (a0, a1) = m.rayleigh().unwrap();
    close(a0, r["damping"]["a0_mass"].as_f64().unwrap(), "a0");
    close(
        a1,
        r["damping"]["a1_initial_stiffness"].as_f64().unwrap(),
        "a1",
    );
}

#[test]
fn generator_defaults_reproduce_reference_frame3() {
    let m = generate::frame(&generate::FrameParams::default()).unwrap();
    check_against_reference(&m);
    // total above the base as in the reference (9386.75 kg), plus the base column halves
    let above: f64 = m
        .lumped_masses()
        .iter()
        .filter(|(t, _)| !m.fixity().contains_key(t))
        .map(|(_, v)| v[2])
        .sum();
    close(
        above,
        reference()["total_mass_kg"].as_f64().unwrap(),
        "total mass",
    );
}

#[test]
fn shipped_model_toml_is_frame3_and_regenerates_byte_for_byte() {
    let text = std::fs::read_to_string(TOML).unwrap();
    let m = generate::frame(&generate::FrameParams::default()).unwrap();
    assert_eq!(
        m.to_toml().unwrap(),
        text,
        "data/frame3-standin/model.toml differs from the generator output"
    );
    let loaded = Model::load(Path::new(TOML)).unwrap();
    assert_eq!(loaded, m);
    check_against_reference(&loaded);
    assert_eq!(loaded.scale, 0.25);
}

#[test]
fn reference_json_import_matches_generator() {
    let imp = model::import_reference_json(REF).unwrap();
    let gen = generate::frame(&generate::FrameParams::default()).unwrap();
    assert_eq!(imp.nodes, gen.nodes);
    assert_eq!(imp.elements.len(), 60);
    let gen_fe: Vec<_> = gen.elements.iter().filter(|e| e.in_fe()).collect();
    assert_eq!(gen_fe.len(), 60);
    for (a, b) in imp.elements.iter().zip(gen_fe) {
        assert_eq!(
            (a.tag, a.nodes(), a.rigid_body),
            (b.tag, b.nodes(), b.rigid_body)
        );
    }
    let (li, lg) = (imp.lumped_masses(), gen.lumped_masses());
    for (t, m) in &li {
        close(m[2], lg[t][2], &format!("node {t} mass"));
    }
    let (a0, a1) = imp.rayleigh().unwrap();
    let (b0, b1) = gen.rayleigh().unwrap();
    close(a0, b0, "a0");
    close(a1, b1, "a1");
    let gi = imp.gravity_loads();
    assert_eq!(gi.len(), gen.gravity_loads().len());
}

#[test]
fn model_load_accepts_the_reference_layout() {
    let m = Model::load(REF).unwrap();
    assert_eq!(m.nodes.len(), 43);
    assert_eq!(m.elements.len(), 60);
    assert_eq!(m.elements[59].body_name(), "Slab:3:60");
}

#[test]
fn local_axes_follow_the_opensees_convention() {
    let m = generate::frame(&generate::FrameParams::default()).unwrap();
    // column 1 (node 1 -> 51, vecxz = X): x = Z, y = X x Z = -Y, z = x × y = X
    let ax = m.local_axes(&m.elements[0]).unwrap();
    assert_eq!(ax, [[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]]);
    // beam 25 (101 -> 111 along X, vecxz = Z): y = Z x X = Y, z = X x Y = Z (depth vertical)
    let ax = m.local_axes(&m.elements[24]).unwrap();
    assert_eq!(ax, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    // beam 29 (101 -> 102 along Y): y = Z x Y = -X, z = Y x -X = Z
    let ax = m.local_axes(&m.elements[28]).unwrap();
    assert_eq!(ax, [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]);
    // section outlines for the rigid-body boxes: columns 0.1 x 0.1, beams 0.075 x 0.15
    let secs = m.section_map();
    assert_eq!(secs[&1].outline(), Some((0.1, 0.1)));
    assert_eq!(secs[&2].outline(), Some((0.075, 0.15)));
}
