//! `export opensees` → the script's `print-json` (OpenSees' `printModel -JSON`) →
//! `import opensees-json --fix-lowest` gives the same model: nodes, supports, masses,
//! materials, sections, transformations and elements, every number within the rounding of
//! the six significant digits OpenSees prints. Needs python3 with openseespy 3.7.1.
use fem2rbd::model::{ElementKind, Formulation, Integration, Model, SectionKind, ShellLayer};
use std::path::Path;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_fem2rbd");

/// Six significant digits: a printed number is within 5e-6 of the exact one, relative to
/// its own size.
const REL: f64 = 5e-6;

fn run(cmd: &mut Command) {
    let out = cmd.output().expect("run");
    assert!(
        out.status.success(),
        "{cmd:?} failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The model of `model_file` after export → OpenSees print → import.
fn round_trip(model_file: &Path, dir: &Path) -> Model {
    let script = dir.join("model.py");
    let printed = dir.join("printed.json");
    let imported = dir.join("imported.toml");
    run(Command::new(BIN)
        .args(["export", "opensees"])
        .arg(model_file)
        .arg("-o")
        .arg(&script));
    run(Command::new("python3")
        .arg(&script)
        .arg("print-json")
        .arg(&printed));
    run(Command::new(BIN)
        .args(["import", "opensees-json"])
        .arg(&printed)
        .arg("--fix-lowest")
        .arg("-o")
        .arg(&imported));
    Model::load(&imported).unwrap()
}

#[track_caller]
fn close(what: &str, got: f64, want: f64) {
    assert!(
        (got - want).abs() <= REL * want.abs(),
        "{what}: imported {got}, exported {want}"
    );
}

#[track_caller]
fn close_all(what: &str, got: &[f64], want: &[f64]) {
    assert_eq!(got.len(), want.len(), "{what}: lengths");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        close(&format!("{what}[{k}]"), *g, *w);
    }
}

/// (E, G, A, Iy, Iz, J) of an elastic line element.
fn elastic_props(m: &Model, kind: &ElementKind) -> Option<[f64; 6]> {
    match kind {
        ElementKind::ElasticBeamColumn { section, .. } => match &m.section_map()[section].kind {
            SectionKind::Elastic {
                e, g, a, iy, iz, j, ..
            } => Some([*e, *g, *a, *iy, *iz, *j]),
            _ => None,
        },
        ElementKind::ElasticStrip {
            e,
            g,
            width,
            thickness,
            ..
        } => {
            let (a, iy, iz, j) = fem2rbd::model::strip_properties(*width, *thickness);
            Some([*e, *g, a, iy, iz, j])
        }
        _ => None,
    }
}

/// (kind, thickness, parameters) of a shell layer.
fn layer(l: &ShellLayer) -> (u8, Vec<f64>) {
    match l {
        ShellLayer::Elastic { thickness, e, nu } => (0, vec![*thickness, *e, *nu]),
        ShellLayer::Concrete {
            thickness,
            e,
            nu,
            fc,
            ft,
        } => (1, vec![*thickness, *e, *nu, *fc, *ft]),
        ShellLayer::Rebar {
            thickness,
            material,
            angle,
        } => (2, vec![*thickness, f64::from(*material), *angle]),
    }
}

/// Asserts that `got` (imported) is `want` (the model exported) as OpenSees holds it.
fn assert_same_model(got: &Model, want: &Model) {
    // nodes
    assert_eq!(got.nodes.len(), want.nodes.len(), "node count");
    let gn = got.node_map();
    for n in &want.nodes {
        let g = gn
            .get(&n.tag)
            .unwrap_or_else(|| panic!("node {} missing", n.tag));
        close_all(&format!("node {}", n.tag), &g.xyz(), &n.xyz());
    }
    // supports: the exported model's are the fully fixed nodes at its lowest z
    assert_eq!(got.fixity(), want.fixity(), "supports");
    // masses: the export lumps element self-weight into the nodes (fully fixed nodes left
    // out); the import reads them as nodal masses
    let fix = want.fixity();
    let want_m: Vec<(u32, [f64; 6])> = want
        .lumped_masses()
        .into_iter()
        .filter(|(t, m)| fix.get(t) != Some(&[1; 6]) && m.iter().any(|x| *x != 0.0))
        .collect();
    let got_m: Vec<(u32, [f64; 6])> = got.lumped_masses().into_iter().collect();
    assert_eq!(
        got_m.iter().map(|m| m.0).collect::<Vec<_>>(),
        want_m.iter().map(|m| m.0).collect::<Vec<_>>(),
        "nodes with mass"
    );
    for ((t, g), (_, w)) in got_m.iter().zip(&want_m) {
        close_all(&format!("mass of node {t}"), g, w);
    }
    // materials: those the export writes (used by fibre and layered sections)
    for m in &got.materials {
        let w = want.material_map()[&m.tag];
        assert_eq!(m.type_name(), w.type_name(), "material {}", m.tag);
        let p = |x: &fem2rbd::model::Material| -> Vec<f64> {
            x.parameters()
                .into_iter()
                .filter(|(n, _)| *n != "density")
                .map(|(_, v)| v)
                .collect()
        };
        close_all(&format!("material {}", m.tag), &p(m), &p(w));
    }
    // sections and elements, element by element; panels belong to the rigid-body model
    // only and are not exported
    let fe_elements: Vec<_> = want
        .elements
        .iter()
        .filter(|e| !matches!(e.kind, ElementKind::Panel { .. }))
        .collect();
    assert_eq!(got.elements.len(), fe_elements.len(), "element count");
    let (gs, ws) = (got.section_map(), want.section_map());
    let (gt, wt) = (got.transformation_map(), want.transformation_map());
    let ge: std::collections::BTreeMap<u32, _> = got.elements.iter().map(|e| (e.tag, e)).collect();
    let mut sections_seen = std::collections::BTreeSet::new();
    for w in fe_elements {
        let g = ge
            .get(&w.tag)
            .unwrap_or_else(|| panic!("element {} missing", w.tag));
        let what = format!("element {}", w.tag);
        assert_eq!(g.nodes(), w.nodes(), "{what}: nodes");
        if let (Some(a), Some(b)) = (g.transf(), w.transf()) {
            assert_eq!(gt[&a].kind, wt[&b].kind, "{what}: transformation kind");
            close_all(&format!("{what}: vecxz"), &gt[&a].vecxz, &wt[&b].vecxz);
        }
        match (&g.kind, &w.kind) {
            (
                ElementKind::BeamColumn {
                    section: gsec,
                    formulation: gf,
                    points: gp,
                    integration: gi,
                    ..
                },
                ElementKind::BeamColumn {
                    section: wsec,
                    formulation: wf,
                    points: wp,
                    integration: wi,
                    ..
                },
            ) => {
                let rule = |f: &Formulation, i: &Option<Integration>| {
                    i.unwrap_or(match f {
                        Formulation::Force => Integration::Lobatto,
                        Formulation::Disp => Integration::Legendre,
                    })
                };
                assert_eq!((gf, gp), (wf, wp), "{what}: formulation, points");
                assert_eq!(rule(gf, gi), rule(wf, wi), "{what}: integration");
                assert_eq!(gsec, wsec, "{what}: section tag");
                if sections_seen.insert(*gsec) {
                    let (a, b) = (gs[gsec], ws[wsec]);
                    close(
                        &format!("section {gsec}: GJ"),
                        a.gj().unwrap(),
                        b.gj().unwrap(),
                    );
                    let (fa, fb) = (a.fibers().unwrap(), b.fibers().unwrap());
                    assert_eq!(fa.len(), fb.len(), "section {gsec}: fibre count");
                    for (k, (x, y)) in fa.iter().zip(&fb).enumerate() {
                        let s = format!("section {gsec} fibre {k}");
                        close_all(&s, &[x.y(), x.z(), x.area()], &[y.y(), y.z(), y.area()]);
                        assert_eq!(x.material(), y.material(), "{s}: material");
                    }
                }
            }
            (
                ElementKind::Shell { section: gsec, .. },
                ElementKind::Shell { section: wsec, .. },
            ) => {
                assert_eq!(gsec, wsec, "{what}: section tag");
                let ElementKind::Shell {
                    local_x,
                    corotational,
                    ..
                } = &w.kind
                else {
                    unreachable!()
                };
                assert!(
                    local_x.is_none() && !corotational,
                    "{what}: the fixture has the print's default shell axes and kinematics"
                );
                match (&gs[gsec].kind, &ws[wsec].kind) {
                    (
                        SectionKind::LayeredShell { layers: a, .. },
                        SectionKind::LayeredShell { layers: b, .. },
                    ) => {
                        assert_eq!(a.len(), b.len(), "section {gsec}: layer count");
                        for (k, (x, y)) in a.iter().zip(b).enumerate() {
                            let ((ka, pa), (kb, pb)) = (layer(x), layer(y));
                            assert_eq!(ka, kb, "section {gsec} layer {k}: kind");
                            close_all(&format!("section {gsec} layer {k}"), &pa, &pb);
                        }
                    }
                    (a, b) => panic!("{what}: sections {a:?} and {b:?}"),
                }
            }
            (gk, wk) => {
                let (a, b) = (elastic_props(got, gk), elastic_props(want, wk));
                let (Some(a), Some(b)) = (a, b) else {
                    panic!("{what}: imported {gk:?}, exported {wk:?}");
                };
                close_all(&format!("{what}: E G A Iy Iz J"), &a, &b);
            }
        }
    }
}

#[test]
fn frame3_comes_back_from_opensees_print_json_as_the_same_model() {
    let dir = tempfile::tempdir().unwrap();
    let file = crate::support::root().join("data/frame3/model.toml");
    let want = Model::load(&file).unwrap();
    let got = round_trip(&file, dir.path());
    assert_same_model(&got, &want);
    // the 84 FE elements: 72 fibre beam-columns, 12 elastic slab strips (as elastic
    // beam-columns)
    let fibre = got
        .elements
        .iter()
        .filter(|e| matches!(e.kind, ElementKind::BeamColumn { .. }))
        .count();
    assert_eq!((got.elements.len(), fibre), (84, 72));
}

#[test]
fn layered_walls_come_back_from_opensees_print_json_as_the_same_model() {
    let root = crate::support::root();
    // elastic and rebar layers; concrete (plastic-damage) and rebar layers
    for f in [
        "tests/fixtures/wall-layered-1x6.toml",
        "tests/fixtures/rw2/model.toml",
    ] {
        let dir = tempfile::tempdir().unwrap();
        let file = root.join(f);
        let want = Model::load(&file).unwrap();
        let got = round_trip(&file, dir.path());
        assert_same_model(&got, &want);
        assert!(got.elements.iter().all(|e| e.type_name == "Wall"), "{f}");
    }
}

/// A cantilever as OpenSees prints it: node 1 at the base, node 2 three metres up with
/// 1000 kg, one elastic beam-column on a linear transformation.
const CANTILEVER: &str = r#"{
"StructuralAnalysisModel": {
	"BIM": "unknown",
	"description": "",
	"engineer": "",
	"units": {"force": "", "length": "", "time": "", "temperature": ""},
	"properties": {
		"uniaxialMaterials": [],
		"ndMaterials": [],
		"sections": [],
		"crdTransformations": [
			{"name": "1", "type": "LinearCrdTransf3d", "vecInLocXZPlane": [1, 0, 0]}
		]
	},
	"geometry": {
		"nodes": [
			{"name": 1, "ndf": 6, "crd": [0, 0, 0]},
			{"name": 2, "ndf": 6, "crd": [0, 0, 3], "mass": [1000, 1000, 1000, 0, 0, 0]}
		],
		"elements": [
			{"name": 1, "type": "ElasticBeam3d", "nodes": [1, 2], "E": 3e+10, "G": 1.25e+10, "A": 0.09, "Jx": 0.00114, "Iy": 0.000675, "Iz": 0.000675, "massperlength": 0, "releasez": 0, "releasey": 0, "crdTransformation": "1"}
		]
	}
}
}
"#;

/// The import of `text` written to a file, or its error message.
fn import(text: &str, supports: fem2rbd::model::Supports) -> Result<Model, String> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("print.json");
    std::fs::write(&path, text).unwrap();
    fem2rbd::model::import_opensees_json(&path, supports).map_err(|e| e.to_string())
}

#[test]
fn a_printed_cantilever_imports_with_its_numbers_and_the_supports_asked_for() {
    use fem2rbd::model::Supports;
    let m = import(CANTILEVER, Supports::FixLowest).unwrap();
    assert_eq!(m.fixity().into_iter().collect::<Vec<_>>(), [(1, [1; 6])]);
    assert_eq!((m.nodes[1].tag, m.nodes[1].z), (2, 3.0));
    assert_eq!((m.masses[0].node, m.masses[0].m), (2, 1000.0));
    assert_eq!(m.total_mass(), 1000.0);
    let e = &m.elements[0];
    assert_eq!((e.type_name.as_str(), e.group.0.as_str()), ("Column", "1"));
    let ElementKind::ElasticBeamColumn {
        section, transf, ..
    } = e.kind
    else {
        panic!("{:?}", e.kind)
    };
    assert_eq!((section, transf), (1, 1));
    let SectionKind::Elastic {
        e, g, a, iy, iz, j, ..
    } = m.section_map()[&1].kind
    else {
        panic!()
    };
    assert_eq!(
        [e, g, a, iy, iz, j],
        [3e10, 1.25e10, 0.09, 6.75e-4, 6.75e-4, 1.14e-3]
    );
    // without supports the model is imported as printed
    assert!(import(CANTILEVER, Supports::None)
        .unwrap()
        .supports
        .is_empty());
}

#[test]
fn what_the_import_cannot_carry_is_refused_with_the_item_named() {
    use fem2rbd::model::Supports;
    let cases = [
        (
            r#""type": "ElasticBeam3d""#,
            r#""type": "ZeroLength""#,
            r#"element 1: type "ZeroLength" is not imported"#,
        ),
        (
            r#""vecInLocXZPlane": [1, 0, 0]"#,
            r#""vecInLocXZPlane": [1, 0, 0], "iOffset": [0, 0, 0.2]"#,
            "crdTransformation 1: `iOffset` not imported",
        ),
        (
            r#""releasez": 0"#,
            r#""releasez": 1"#,
            "element 1: `releasez` = 1; fem2rbd's elastic beam-columns have no end releases",
        ),
        (
            r#""mass": [1000, 1000, 1000"#,
            r#""mass": [1000, 1000, 500"#,
            "node 2: `mass` has mx, my, mz = 1000, 1000, 500",
        ),
        (
            r#""engineer": "","#,
            r#""engineer": "", "loadPatterns": [],"#,
            "`StructuralAnalysisModel`: `loadPatterns` not imported",
        ),
        (
            r#""force": """#,
            r#""force": "kN""#,
            r#"`units.force` = "kN": the model is read in SI"#,
        ),
    ];
    for (from, to, want) in cases {
        assert!(CANTILEVER.contains(from), "{from}");
        let err = import(&CANTILEVER.replace(from, to), Supports::FixLowest).unwrap_err();
        assert!(err.contains(want), "{to}: {err}");
        assert!(err.contains("print.json"), "the file is named: {err}");
    }
}

#[test]
fn loading_a_print_as_a_model_points_to_the_importer() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("print.json");
    std::fs::write(&path, CANTILEVER).unwrap();
    let err = Model::load(&path).unwrap_err().to_string();
    assert!(err.contains("fem2rbd import opensees-json"), "{err}");
}

/// The command says on stderr what the model has only because the print lacks it: its
/// supports (none, or the fixed lowest nodes), its shells' defaults, and no damping, ties,
/// loads or analysis; `--quiet` says nothing.
#[test]
fn the_import_says_what_the_print_does_not_carry() {
    let dir = tempfile::tempdir().unwrap();
    let print = dir.path().join("print.json");
    std::fs::write(&print, CANTILEVER).unwrap();
    let stderr = |extra: &[&str], out: &str| {
        let mut cmd = Command::new(BIN);
        cmd.args(["import", "opensees-json"])
            .arg(&print)
            .args(extra)
            .arg("-o")
            .arg(dir.path().join(out));
        let o = cmd.output().unwrap();
        assert!(
            o.status.success(),
            "{cmd:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        String::from_utf8(o.stderr).unwrap()
    };
    let none = stderr(&[], "a.toml");
    assert!(
        none.contains("import: the print has no supports, so neither has the model"),
        "{none}"
    );
    assert!(
        !none.contains("shell"),
        "the cantilever has no shells: {none}"
    );
    let fixed = stderr(&["--fix-lowest"], "b.toml");
    assert!(
        fixed.contains("import: 1 node at the lowest z = 0 m fixed in all six DOFs"),
        "{fixed}"
    );
    assert!(fixed.contains("import: no [damping], equalDOF ties, loads or analysis"));
    assert_eq!(stderr(&["--quiet"], "c.toml"), "");

    let walls = Model::load("tests/fixtures/wall-layered-1x6.toml").unwrap();
    let shells = walls
        .elements
        .iter()
        .filter(|e| matches!(e.kind, ElementKind::Shell { .. }))
        .count();
    assert!(shells > 1);
    let notes = fem2rbd::model::import_notes(&walls, fem2rbd::model::Supports::None);
    assert!(
        notes.iter().any(|l| l.starts_with(&format!(
            "{shells} shells with small displacements and the local x from the first node"
        ))),
        "{notes:?}"
    );
}
