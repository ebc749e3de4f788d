//! `mapping::from_model` and `fem2rbd map` on the shipped frame3 model.
use fem2rbd::mapping::{self, overlap::max_pairwise_overlap, MapOptions, Role};
use fem2rbd::model::{ElementKind, Model, SectionKind};
use std::collections::BTreeSet;

const TOML: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/data/frame3-standin/model.toml"
);

fn frame3() -> Model {
    Model::load(TOML).unwrap()
}

#[test]
fn frame3_maps_to_60_bodies_named_by_type_story_and_element() {
    let model = frame3();
    let input = mapping::from_model(&model).unwrap();
    assert_eq!(
        input.members.len(),
        48,
        "24 columns + 24 beams; strips are FE only"
    );
    assert_eq!(input.quads.len(), 12, "4 quarter panels per floor");
    let m = mapping::map_to_boxes(&input, &MapOptions::default()).unwrap();
    let b = &m.bodies;
    assert_eq!(b.len(), 60);
    let count = |k: Role| b.iter().filter(|x| x.kind == k).count();
    assert_eq!(
        (count(Role::Column), count(Role::Beam), count(Role::Slab)),
        (24, 24, 12)
    );
    assert_eq!(b[0].id.name(), "Column:1:1");
    assert_eq!(b[4].id.name(), "Column:1:5");
    assert_eq!(b[8].id.name(), "Column:2:9");
    assert_eq!(b[24].id.name(), "Beam:1:25");
    assert_eq!(b[48].id.name(), "Slab:1:61");
    assert_eq!(b[59].id.name(), "Slab:3:72");
    // groups are the stories (one per material group)
    let groups: Vec<String> = mapping::groups(b).into_keys().collect();
    assert_eq!(groups, ["1", "2", "3"]);
    for x in b {
        let e = model
            .elements
            .iter()
            .find(|e| Some(e.tag) == x.id.element_tag())
            .unwrap();
        assert_eq!(x.id.name(), e.body_name());
        assert_eq!(x.id.group(), e.group.0);
        assert!(e.rigid_body);
    }
    // section outlines: columns 0.1 x 0.1, beams 0.075 x 0.15 (untrimmed), slabs 0.03 thick
    let c = &b[0];
    assert_eq!(c.untrimmed_half_extents, [0.25, 0.05, 0.05]);
    let beam = &b[24];
    assert_eq!(beam.untrimmed_half_extents, [0.375, 0.0375, 0.075]);
    let slab = &b[48];
    assert!((slab.untrimmed_half_extents[0] - 0.375).abs() < 1e-12);
    assert!((slab.untrimmed_half_extents[1] - 0.375).abs() < 1e-12);
    assert!((slab.untrimmed_half_extents[2] - 0.015).abs() < 1e-12);
    // quarter panel of floor 1 at the (0,0) corner: centre (0.375, 0.375, 1)
    for (u, v) in slab.untrimmed_centre.iter().zip([0.375, 0.375, 1.0]) {
        assert!((u - v).abs() < 1e-12, "{:?}", slab.untrimmed_centre);
    }
}

#[test]
fn frame3_rigid_mass_equals_model_mass_and_overlaps_are_trimmed() {
    let model = frame3();
    let m = mapping::map_to_boxes(
        &mapping::from_model(&model).unwrap(),
        &MapOptions::default(),
    )
    .unwrap();
    let total: f64 = m.bodies.iter().map(|b| b.mass_kg).sum();
    let want = model.total_mass();
    assert!(
        (total / want - 1.0).abs() < 1e-9,
        "rigid {total} kg vs model {want} kg"
    );
    // 3 floors x 2699.75 kg ballast + slabs + frame: 9411.75 kg incl. the base column halves
    assert!((want - 9411.75).abs() < 1e-9, "{want}");
    // the slab panels carry the floor masses (the rule prefers slabs at a node)
    let slabs: f64 = m
        .bodies
        .iter()
        .filter(|b| b.kind == Role::Slab)
        .map(|b| b.mass_kg)
        .sum();
    let nodal: f64 = model.masses.iter().map(|x| x.m).sum();
    assert!((slabs / nodal - 1.0).abs() < 1e-12, "{slabs} vs {nodal}");
    let (worst, _) = max_pairwise_overlap(&m.bodies);
    assert!(worst <= 1e-4, "max overlap {worst} m³");
    assert!(worst <= 1e-9, "max overlap {worst} m³ (default tolerance)");
    // without trimming the slab panels overlap the beams
    let raw = mapping::map_to_boxes(
        &mapping::from_model(&model).unwrap(),
        &MapOptions {
            remove_overlaps: false,
            ..MapOptions::default()
        },
    )
    .unwrap();
    assert!(max_pairwise_overlap(&raw.bodies).0 > 1e-5);
}

#[test]
fn fe_only_mass_goes_to_nodes_and_unknown_outlines_are_named() {
    let mut model = frame3();
    // give the FE-only strips a density: their weight must still reach the bodies
    for e in &mut model.elements {
        if let ElementKind::ElasticStrip { density, .. } = &mut e.kind {
            *density = 2400.0;
        }
    }
    let strips: f64 = model
        .elements
        .iter()
        .filter(|e| !e.rigid_body)
        .map(|e| model.element_mass(e))
        .sum();
    assert!(strips > 1.0);
    let m = mapping::map_to_boxes(
        &mapping::from_model(&model).unwrap(),
        &MapOptions::default(),
    )
    .unwrap();
    let total: f64 = m.bodies.iter().map(|b| b.mass_kg).sum();
    assert!((total / model.total_mass() - 1.0).abs() < 1e-9);
    assert_eq!(m.bodies.len(), 60);

    // a beam-column whose section has no outline: the error names the element
    let mut model = frame3();
    model.sections[0].kind = SectionKind::Elastic {
        e: 25e9,
        g: 10e9,
        a: 0.01,
        iy: 1e-5,
        iz: 1e-5,
        j: 1e-5,
        mass_per_length: 0.0,
        width: None,
        depth: None,
    };
    let tag = model.sections[0].tag;
    let first = model
        .elements
        .iter()
        .find(|e| e.section() == Some(tag))
        .unwrap()
        .tag;
    let err = mapping::from_model(&model).unwrap_err().to_string();
    assert!(err.contains(&format!("element {first}")), "{err}");
    assert!(err.contains("no outline"), "{err}");
}

#[test]
fn map_cli_writes_the_table_atomically() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bodies.csv");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
        .args(["map", TOML, "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(stdout.contains("60 rigid bodies in 3 groups"), "{stdout}");
    assert!(stdout.contains("total mass 9411.750000 kg"), "{stdout}");
    let text = std::fs::read_to_string(&out).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 61);
    assert_eq!(lines[0], mapping::table::HEADER);
    assert!(lines[1].starts_with("Column:1:1,1,Column,1,1,Column,0,0,0.25,"));
    let names: BTreeSet<&str> = lines[1..]
        .iter()
        .map(|l| l.split(',').next().unwrap())
        .collect();
    assert_eq!(names.len(), 60);
    // same input, same bytes
    let out2 = dir.path().join("again.csv");
    let run2 = std::process::Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
        .args(["map", TOML, "--quiet", "-o"])
        .arg(&out2)
        .output()
        .unwrap();
    assert!(run2.status.success());
    assert!(run2.stdout.is_empty());
    assert_eq!(std::fs::read(&out2).unwrap(), text.as_bytes());
    // a missing model: error, nothing written
    let out3 = dir.path().join("none.csv");
    let bad = std::process::Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
        .args(["map", "no-such-model.toml", "-o"])
        .arg(&out3)
        .output()
        .unwrap();
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("no-such-model.toml"));
    assert!(!out3.exists());
}
