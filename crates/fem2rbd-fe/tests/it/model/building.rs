//! The frame–shear-wall generator (`fem2rbd_fe::model::building`): counts, areas and
//! masses against hand computation, sharing of the frame's nodes, openings, the soft
//! story, errors; the exported script builds in openseespy and the wall stiffens the
//! frame along its line.
use fem2rbd_fe::export::{opensees_script, OpenSeesOptions};
use fem2rbd_fe::model::building::{building, BuildingParams, Opening, WallLine, WallSpec};
use fem2rbd_fe::model::generate::{frame, FrameParams};
use fem2rbd_fe::model::{ElementKind, Model, SectionKind, ShellLayer};
use std::process::Command;

/// Two 6 m bays in X, one 5 m bay in Y, two 3 m stories, full scale (also the frame of
/// `fe::shell::building`).
pub(crate) fn small_frame() -> FrameParams {
    FrameParams {
        name: "wall-test".into(),
        spans_x: vec![6.0, 6.0],
        spans_y: vec![5.0],
        story_heights: vec![3.0, 3.0],
        column: [0.5, 0.5],
        beam: [0.3, 0.6],
        slab_thickness: 0.12,
        cover: 0.03,
        bar_offset: 0.04,
        column_bar_diameter: 0.025,
        beam_bar_diameter: 0.02,
        ec: vec![32.5e9],
        fc: vec![26.8e6],
        fy: 400e6,
        added_mass: vec![30_000.0],
        column_elements: 2,
        beam_elements: 1,
        scale: 1.0,
        ..FrameParams::default()
    }
}

fn params(walls: &[&str]) -> BuildingParams {
    BuildingParams {
        frame: small_frame(),
        walls: walls.iter().map(|w| WallSpec::parse(w).unwrap()).collect(),
        wall_thickness: vec![0.2],
        ..BuildingParams::default()
    }
}

fn walls(m: &Model) -> Vec<&fem2rbd_fe::model::Element> {
    m.elements
        .iter()
        .filter(|e| e.type_name == "Wall")
        .collect()
}

/// One wall along X on line 0, bay 1, both stories: 2 × 2 shells per story on the frame's
/// nodes (column mid-height nodes, the beam's mid-span node), 3 new nodes ((3, 0, 0)
/// fixed, (3, 0, 1.5), (3, 0, 4.5)); the wall's mass is ρ·t·A = 2500 · 0.2 · 6 · 6 =
/// 18 000 kg on top of the frame's; the layered section sums to t with half of each
/// ratio per face.
#[test]
fn one_wall_counts_areas_masses_and_shared_nodes() {
    let p = params(&["x0:1:1-2"]);
    let bare = frame(&p.frame).unwrap();
    let m = building(&p).unwrap();
    let w = walls(&m);
    assert_eq!(w.len(), 8);
    assert_eq!(m.nodes.len(), bare.nodes.len() + 3);
    assert_eq!(m.supports.len(), bare.supports.len() + 1);
    let area: f64 = w.iter().map(|e| m.shell_area(e).unwrap()).sum();
    assert!((area - 36.0).abs() < 1e-9, "{area}");
    let dm = m.total_mass() - bare.total_mass();
    assert!((dm - 18_000.0).abs() < 1e-6, "{dm}");
    for e in &w {
        assert!(["W1", "W2"].contains(&e.group.0.as_str()));
        let ElementKind::Shell { nodes, .. } = e.kind else {
            panic!()
        };
        for n in nodes {
            let y = m.nodes.iter().find(|x| x.tag == n).unwrap().y;
            assert_eq!(y, 0.0);
        }
    }
    // A column mid-height node at (0, 0, 1.5) is a wall node.
    let mid = m
        .nodes
        .iter()
        .find(|n| n.xyz() == [0.0, 0.0, 1.5])
        .unwrap()
        .tag;
    assert!(w.iter().any(|e| e.nodes().contains(&mid)));
    // Section: 0.02 cover, 0.00025 + 0.00025 bars per face, 4 core layers.
    let sec = m.sections.iter().find(|s| s.name == "wall_S1").unwrap();
    let SectionKind::LayeredShell { layers, density } = &sec.kind else {
        panic!()
    };
    assert_eq!(layers.len(), 10);
    assert!((sec.shell_thickness().unwrap() - 0.2).abs() < 1e-12);
    assert_eq!(*density, 2500.0);
    let bars: f64 = layers
        .iter()
        .filter(|l| matches!(l, ShellLayer::Rebar { .. }))
        .map(ShellLayer::thickness)
        .sum();
    assert!((bars - 2.0 * 0.0025 * 0.2).abs() < 1e-12, "{bars}");
    let core = (0.2 - 2.0 * 0.02 - bars) / 4.0;
    assert!((layers[4].thickness() - core).abs() < 1e-12);
    // The model round-trips through its TOML text.
    let again = Model::parse(&m.to_toml().unwrap(), "b.toml", false).unwrap();
    assert_eq!(again.elements.len(), m.elements.len());
}

/// A door of 1 × 1 cells in story 1 removes a quarter of that story's wall (4.5 m²,
/// 2 250 kg); a wall only in story 1 (soft story above) has half the shells; without
/// beams over walls the 2 beam elements × 2 floors on that bay go (the half-span
/// beams: beam_elements = 1 per half span).
#[test]
fn openings_soft_story_and_beams_over_walls() {
    let full = building(&params(&["x0:1:1-2"])).unwrap();
    let door = building(&params(&["x0:1:1:open=0-1/0-1", "x0:1:2"])).unwrap();
    assert_eq!(walls(&door).len(), 7);
    let dm = full.total_mass() - door.total_mass();
    assert!((dm - 2250.0).abs() < 1e-6, "{dm}");
    let soft = building(&params(&["x0:1:1"])).unwrap();
    assert_eq!(walls(&soft).len(), 4);
    let mut p = params(&["x0:1:1-2"]);
    p.beams_over_walls = false;
    let nb = building(&p).unwrap();
    let beams = |m: &Model| m.elements.iter().filter(|e| e.type_name == "Beam").count();
    assert_eq!(beams(&full) - beams(&nb), 4);
    // Y walls and per-story thickness.
    let mut p = params(&["y2:1:1-2"]);
    p.wall_thickness = vec![0.3, 0.2];
    let y = building(&p).unwrap();
    let wall_mass: f64 = walls(&y).iter().map(|e| y.element_mass(e)).sum();
    assert!(
        (wall_mass - 2500.0 * 5.0 * 3.0 * (0.3 + 0.2)).abs() < 1e-6,
        "{wall_mass}"
    );
    assert_eq!(
        WallSpec::parse("x1:2:1-3:open=1-3/0-2").unwrap(),
        WallSpec {
            line: WallLine::X(1),
            bay: 2,
            stories: [1, 3],
            opening: Some(Opening {
                along: [1, 3],
                up: [0, 2]
            }),
        }
    );
}

#[test]
fn bad_walls_are_named() {
    let e = |w: &str| building(&params(&[w])).unwrap_err().to_string();
    assert!(e("x2:1:1").contains("column line 2 does not exist (0..=1)"));
    assert!(e("x0:3:1").contains("bay 3 does not exist (1..=2)"));
    assert!(e("y0:1:1-3").contains("stories 1-3 are not within 1..=2"));
    assert!(e("x0:1:1:open=0-3/0-1").contains("do not fit the 2x2 mesh"));
    assert!(WallSpec::parse("z0:1:1")
        .unwrap_err()
        .to_string()
        .contains("expected LINE:BAY:STORIES"));
    let mut p = params(&["x0:1:1"]);
    p.wall_mesh = Some([3, 2]);
    assert!(building(&p)
        .unwrap_err()
        .to_string()
        .contains("multiple of 2·beam_elements"));
    let mut p = params(&["x0:1:1"]);
    p.wall_cover = 0.1;
    assert!(format!("{:#}", building(&p).unwrap_err()).contains("leave no core"));
}

fn eigen(m: &Model) -> Vec<serde_json::Value> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("b.py");
    std::fs::write(
        &path,
        opensees_script(m, "b.toml", &OpenSeesOptions::default()).unwrap(),
    )
    .unwrap();
    let v: serde_json::Value =
        crate::openseespy_json(Command::new("python3").arg(&path).args(["eigen", "30"]));
    v["modes"].as_array().unwrap().clone()
}

/// The exported wall building builds in openseespy (ASDShellQ4 + LayeredShell beside the
/// fibre frame), and two walls along X make it far stiffer along X: the X-mass-weighted
/// mean period of the first 30 modes drops well below the bare frame's (a 6 m × 0.2 m
/// wall of E = 32.5 GPa is some 30 times stiffer in its plane than the frame's two
/// 0.5 m columns beside it). Measured 0.168 s bare, 0.039 s with the walls; bound 0.6×.
#[test]
fn exported_wall_building_runs_in_opensees_and_the_wall_stiffens_its_line() {
    let p = params(&["x0:1:1-2", "x1:1:1-2"]);
    // The X-mass-weighted mean period of the first 30 modes, Σ X_k T_k / Σ X_k (X_k the
    // effective-mass share in X), the 30 modes holding at least half the X mass.
    let tx = |modes: &[serde_json::Value]| {
        let (mut sx, mut sxt) = (0.0, 0.0);
        for m in modes {
            let (x, t) = (m["X"].as_f64().unwrap(), m["T"].as_f64().unwrap());
            sx += x;
            sxt += x * t;
        }
        assert!(sx > 0.5, "X share of 30 modes {sx}");
        sxt / sx
    };
    let bare = tx(&eigen(&frame(&p.frame).unwrap()));
    let wall = tx(&eigen(&building(&p).unwrap()));
    eprintln!("T_X: bare frame {bare:.4} s, with walls {wall:.4} s");
    assert!(wall < 0.6 * bare, "{wall} vs {bare}");
}
