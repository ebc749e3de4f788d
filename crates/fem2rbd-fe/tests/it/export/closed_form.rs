//! Exported scripts against closed-form results: a cantilever column with a tip mass
//! has T = 2π √(m L³ / (3 E I)) in each direction, with the I of the section axis the
//! transformation puts in that direction. Needs python3 with openseespy 3.7.1.
use fem2rbd_fe::export::{opensees_script, OpenSeesOptions};
use fem2rbd_fe::model::Model;
use serde_json::Value;
use std::process::Command;

fn run(model: &Model, args: &[&str]) -> Value {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("m.py");
    std::fs::write(
        &p,
        opensees_script(model, "test", &OpenSeesOptions::default()).unwrap(),
    )
    .unwrap();
    crate::openseespy_json(Command::new("python3").arg(&p).args(args))
}

fn period(v: &Value, key: &str) -> f64 {
    let m = v["modes"]
        .as_array()
        .unwrap()
        .iter()
        .max_by(|a, b| {
            a[key]
                .as_f64()
                .unwrap()
                .total_cmp(&b[key].as_f64().unwrap())
        })
        .unwrap();
    m["T"].as_f64().unwrap()
}

const L: f64 = 3.0;
const M: f64 = 1000.0;

fn cantilever(section: &str, element: &str) -> Model {
    let text = format!(
        r#"name = "cantilever"
material = [ {{ tag = 1, type = "Elastic", E = 30e9 }} ]
section = [ {section} ]
transformation = [ {{ tag = 1, type = "linear", vecxz = [1.0, 0.0, 0.0] }} ]
node = [ {{ tag = 1, x = 0.0, y = 0.0, z = 0.0 }}, {{ tag = 2, x = 0.0, y = 0.0, z = {L:?} }} ]
support = [ {{ node = 1, dofs = [1, 1, 1, 1, 1, 1] }} ]
element = [ {element} ]
mass = [ {{ node = 2, m = {M:?} }} ]
"#
    );
    Model::parse(&text, "cantilever.toml", false).unwrap()
}

fn t_closed(ei: f64) -> f64 {
    2.0 * std::f64::consts::PI * (M * L.powi(3) / (3.0 * ei)).sqrt()
}

#[test]
fn elastic_cantilever_periods_follow_the_local_axes() {
    // vecxz = X with the member along Z: local z = global X, so sway in X bends about
    // local y (Iy) and sway in Y about local z (Iz).
    let (e, iy, iz) = (30e9, 4.0e-4, 1.0e-4);
    let m = cantilever(
        r#"{ tag = 1, type = "elastic", E = 30e9, G = 12.5e9, A = 0.06, Iy = 4.0e-4, Iz = 1.0e-4, J = 2e-4 }"#,
        r#"{ tag = 1, type_name = "Column", group = 1, type = "elastic_beam_column", nodes = [1, 2], section = 1, transf = 1 }"#,
    );
    let v = run(&m, &["eigen", "2"]);
    let (tx, ty) = (period(&v, "X"), period(&v, "Y"));
    eprintln!(
        "elastic: TX {tx} (closed {}) TY {ty} (closed {})",
        t_closed(e * iy),
        t_closed(e * iz)
    );
    assert!((tx / t_closed(e * iy) - 1.0).abs() < 1e-6);
    assert!((ty / t_closed(e * iz) - 1.0).abs() < 1e-6);
}

#[test]
fn fiber_cantilever_periods_follow_fiber_inertia() {
    // Four fibers of area a at (±y0, ±z0): EIy = 4 E a z0², EIz = 4 E a y0².
    let (e, a, y0, z0) = (30e9, 0.01, 0.05, 0.1);
    let m = cantilever(
        r#"{ tag = 1, type = "fiber", GJ = 1e7, fibers = [[-0.05, -0.1, 0.01, 1], [0.05, -0.1, 0.01, 1], [-0.05, 0.1, 0.01, 1], [0.05, 0.1, 0.01, 1]] }"#,
        r#"{ tag = 1, type_name = "Column", group = 1, type = "beam_column", nodes = [1, 2], section = 1, transf = 1, formulation = "force", points = 3 }"#,
    );
    let v = run(&m, &["eigen", "2"]);
    let (tx, ty) = (period(&v, "X"), period(&v, "Y"));
    let (eiy, eiz) = (4.0 * e * a * z0 * z0, 4.0 * e * a * y0 * y0);
    eprintln!(
        "fiber: TX {tx} (closed {}) TY {ty} (closed {})",
        t_closed(eiy),
        t_closed(eiz)
    );
    assert!((tx / t_closed(eiy) - 1.0).abs() < 1e-6);
    assert!((ty / t_closed(eiz) - 1.0).abs() < 1e-6);
}

#[test]
fn strip_and_shell_models_export_and_sag_as_expected() {
    // A cantilever elastic strip along X (vecxz = Z: local z = vertical, so the
    // out-of-plane inertia Iy = w t³/12 resists gravity): tip sag of a tip load
    // P = m g is P L³ / (3 E Iy).
    let text = r#"name = "strip"
transformation = [ { tag = 1, type = "linear", vecxz = [0.0, 0.0, 1.0] } ]
node = [ { tag = 1, x = 0.0, y = 0.0, z = 0.0 }, { tag = 2, x = 2.0, y = 0.0, z = 0.0 } ]
support = [ { node = 1, dofs = [1, 1, 1, 1, 1, 1] } ]
element = [ { tag = 1, type_name = "Slab", group = 1, type = "elastic_strip", nodes = [1, 2], transf = 1, E = 30e9, G = 12.5e9, width = 0.5, thickness = 0.1 } ]
mass = [ { node = 2, m = 100.0 } ]
"#;
    let m = Model::parse(text, "strip.toml", false).unwrap();
    let v = run(&m, &["gravity"]);
    let uz = v["disp"]["2"][2].as_f64().unwrap();
    let want = -100.0 * 9.81 * 8.0 / (3.0 * 30e9 * 0.5 * 0.1f64.powi(3) / 12.0);
    eprintln!("strip sag {uz} closed {want}");
    assert!((uz / want - 1.0).abs() < 1e-9);

    // A square plate on four fixed corners carries its own weight; the script must run
    // and the reaction-free nodes must sag downward symmetrically.
    let text = r#"name = "plate"
section = [ { tag = 1, type = "plate", E = 30e9, nu = 0.2, h = 0.2, density = 2500.0 } ]
node = [ { tag = 1, x = 0.0, y = 0.0, z = 0.0 }, { tag = 2, x = 1.0, y = 0.0, z = 0.0 }, { tag = 3, x = 2.0, y = 0.0, z = 0.0 },
         { tag = 4, x = 0.0, y = 1.0, z = 0.0 }, { tag = 5, x = 1.0, y = 1.0, z = 0.0 }, { tag = 6, x = 2.0, y = 1.0, z = 0.0 },
         { tag = 7, x = 0.0, y = 2.0, z = 0.0 }, { tag = 8, x = 1.0, y = 2.0, z = 0.0 }, { tag = 9, x = 2.0, y = 2.0, z = 0.0 } ]
support = [ { node = 1, dofs = [1, 1, 1, 0, 0, 0] }, { node = 3, dofs = [1, 1, 1, 0, 0, 0] }, { node = 7, dofs = [1, 1, 1, 0, 0, 0] }, { node = 9, dofs = [1, 1, 1, 0, 0, 0] } ]
element = [ { tag = 1, type_name = "Slab", group = 1, type = "shell", nodes = [1, 2, 5, 4], section = 1 },
            { tag = 2, type_name = "Slab", group = 1, type = "shell", nodes = [2, 3, 6, 5], section = 1 },
            { tag = 3, type_name = "Slab", group = 1, type = "shell", nodes = [4, 5, 8, 7], section = 1 },
            { tag = 4, type_name = "Slab", group = 1, type = "shell", nodes = [5, 6, 9, 8], section = 1 } ]
"#;
    let m = Model::parse(text, "plate.toml", false).unwrap();
    assert!((m.total_mass() - 2500.0 * 0.2 * 4.0).abs() < 1e-9);
    let v = run(&m, &["gravity"]);
    let d = &v["disp"];
    let uz = |t: &str| d[t][2].as_f64().unwrap();
    eprintln!("plate: centre {} edges {} {}", uz("5"), uz("2"), uz("4"));
    assert!(uz("5") < uz("2") && uz("2") < 0.0);
    assert!((uz("2") / uz("4") - 1.0).abs() < 1e-9 && (uz("6") / uz("8") - 1.0).abs() < 1e-9);
}
