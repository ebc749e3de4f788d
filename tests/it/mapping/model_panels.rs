//! Slab panels (rigid bodies only) and FE-only elements: file format, validation, FE
//! domain, OpenSees export and the hand-off read from a built FE domain.
use fem2rbd::collapse::{CollapseMonitor, Criterion, Trigger};
use fem2rbd::export::{opensees_script, OpenSeesOptions};
use fem2rbd::fe::build::{build_domain, BuildOptions};
use fem2rbd::mapping::handoff::{translations, GroundState, Handoff};
use fem2rbd::mapping::{self, MapOptions};
use fem2rbd::model::{ElementKind, Model};
use fem2rbd::pipeline::node_states;

const TOML: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/data/frame3-standin/model.toml"
);

#[test]
fn frame3_panels_and_fe_only_strips_in_the_file() {
    let text = std::fs::read_to_string(TOML).unwrap();
    let m = Model::parse(&text, "model.toml", false).unwrap();
    let panels: Vec<_> = m
        .elements
        .iter()
        .filter(|e| matches!(e.kind, ElementKind::Panel { .. }))
        .collect();
    assert_eq!(panels.len(), 12);
    assert_eq!(panels[0].tag, 61);
    assert_eq!(panels[0].nodes(), [101, 111, 112, 102]);
    assert!(panels.iter().all(|p| p.type_name == "Slab" && p.rigid_body));
    // quarter panels of 0.75 m x 0.75 m, no self-weight (density 0)
    for p in &panels {
        assert!((m.shell_area(p).unwrap() - 0.5625).abs() < 1e-12);
        assert_eq!(m.element_mass(p), 0.0);
    }
    let strips = m.elements.iter().filter(|e| !e.rigid_body).count();
    assert_eq!(strips, 12);
    assert_eq!(text.matches("rigid_body = false").count(), 12);
    // a density gives the panel self-weight rho t A
    let mut m2 = m.clone();
    if let ElementKind::Panel { density, .. } = &mut m2.elements[60].kind {
        *density = 2400.0;
    }
    assert!((m2.element_mass(&m2.elements[60]) - 2400.0 * 0.03 * 0.5625).abs() < 1e-9);
    assert!((m2.total_mass() - m.total_mass() - 40.5).abs() < 1e-9);
}

#[test]
fn bad_panels_are_errors_naming_file_line_and_element() {
    let base = "[[node]]\ntag = 1\nx = 0.0\ny = 0.0\nz = 0.0\n[[node]]\ntag = 2\nx = 1.0\ny = 0.0\nz = 0.0\n\
                [[node]]\ntag = 3\nx = 1.0\ny = 1.0\nz = 0.0\n[[node]]\ntag = 4\nx = 0.0\ny = 1.0\nz = 0.0\n";
    let ok = format!(
        "{base}[[element]]\ntag = 7\ntype_name = \"Slab\"\ngroup = 1\ntype = \"panel\"\nnodes = [1, 2, 3, 4]\nthickness = 0.1\n"
    );
    let m = Model::parse(&ok, "p.toml", false).unwrap();
    assert!(m.elements[0].rigid_body);
    assert!(!m.elements[0].in_fe());
    for (bad, want) in [
        ("thickness = 0.1", "thickness = 0.0"),
        ("thickness = 0.1", "thickness = 0.1\ndensity = -1.0"),
        ("nodes = [1, 2, 3, 4]", "nodes = [1, 2, 3, 9]"),
        ("nodes = [1, 2, 3, 4]", "nodes = [1, 2, 2, 4]"),
    ] {
        let text = ok.replace(bad, want);
        let e = Model::parse(&text, "p.toml", false)
            .unwrap_err()
            .to_string();
        assert!(e.contains("p.toml") && e.contains("element 7"), "{e}");
    }
    let e = Model::parse(
        &ok.replace("thickness = 0.1", "thickness = 0.0"),
        "p.toml",
        false,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("thickness") && e.contains("positive"), "{e}");
    let e = Model::parse(
        &ok.replace("thickness = 0.1", "thickness = 0.1\nrigid_body = 3"),
        "p.toml",
        false,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("p.toml:"), "{e}");
}

#[test]
fn fe_and_opensees_skip_panels() {
    let m = Model::load(TOML).unwrap();
    let built = build_domain(&m, &BuildOptions::default()).unwrap();
    assert_eq!(built.domain.elements().len(), 60);
    assert!(built.element_index.keys().all(|&t| t <= 60));
    let script = opensees_script(&m, "model.toml", &OpenSeesOptions::default()).unwrap();
    assert_eq!(
        script.matches("ops.element(").count(),
        60,
        "60 FE elements exported"
    );
    assert!(!script.contains("ops.element(\"elasticBeamColumn\", 61,"));
}

#[test]
fn handoff_and_collapse_read_a_built_domain() {
    let m = Model::load(TOML).unwrap();
    let mut built = build_domain(&m, &BuildOptions::default()).unwrap();
    let n = built.domain.num_equations();
    // every free DOF: uz = -0.3 m, vx = 0.2 m/s
    let mut u = vec![0.0; n];
    let mut v = vec![0.0; n];
    for k in 0..built.domain.nodes().len() {
        if let Some(q) = built.domain.equation(k, 2) {
            u[q] = -0.3;
        }
        if let Some(q) = built.domain.equation(k, 0) {
            v[q] = 0.2;
        }
    }
    built
        .domain
        .set_initial_state(&u, &v, &vec![0.0; n])
        .unwrap();
    let states = node_states(&m, &built).unwrap();
    let k121 = m.nodes.iter().position(|x| x.tag == 121).unwrap();
    assert_eq!(states[k121].u, [0.0, 0.0, -0.3]);
    assert_eq!(states[k121].v, [0.2, 0.0, 0.0]);
    assert_eq!(states[0].u, [0.0; 3], "base node fixed");
    let mut mon = CollapseMonitor::new(&m, Criterion::paper_default(&m)).unwrap();
    let ev = *mon.observe(10, 0.1, &translations(&states)).unwrap();
    assert!(matches!(ev.trigger, Trigger::VerticalDrop { drop_m, .. } if drop_m == 0.3));
    // the floor-3 slab panels translate rigidly: down 0.3 m + ground, at 0.2 m/s + ground
    let mapped =
        mapping::map_to_boxes(&mapping::from_model(&m).unwrap(), &MapOptions::default()).unwrap();
    let h = Handoff::new(&m, &mapped).unwrap();
    let g = GroundState {
        displacement: [0.01, 0.0, 0.0],
        velocity: [0.05, 0.0, 0.0],
    };
    let bs = h.states(&states, &g).unwrap();
    for (s, b) in bs.iter().zip(&mapped.bodies).skip(56) {
        assert_eq!(s.id.name(), b.id.name());
        for k in 0..3 {
            let want = b.centre[k] + [0.01, 0.0, -0.3][k];
            assert!((s.centre[k] - want).abs() < 1e-12, "{} {k}", s.id.name());
            let wv = [0.25, 0.0, 0.0][k];
            assert!(
                (s.linear_velocity[k] - wv).abs() < 1e-12,
                "{} v{k}",
                s.id.name()
            );
        }
        assert!(s.rotation.angle_to(&b.rotation) < 1e-12);
    }
}
