//! Shell walls in the model format: `layered_shell` sections (elastic / concrete /
//! smeared-rebar layers), validation errors naming file, line and item, and the OpenSees
//! export (`LayeredShell` + `PlateRebar` + `ASDShellQ4 -local`) checked on openseespy
//! against a closed form. Needs python3 with openseespy 3.7.1.
use super::support::wall_mesh;
use fem2rbd_fe::export::{opensees_script, OpenSeesOptions};
use fem2rbd_fe::model::Model;
use serde_json::Value;
use std::process::Command;

/// A vertical wall in the XZ plane, `b` wide (2 elements) and `h` tall (`ne` elements),
/// base fixed, with the given `[[section]]` entries (tag 10) and materials.
fn wall(b: f64, h: f64, ne: usize, materials: &str, section: &str) -> String {
    wall_mesh(
        &format!("name = \"wall\"\n{materials}{section}"),
        b,
        h,
        2,
        ne,
    )
}

const STEEL: &str = "[[material]]\ntag = 1\ntype = \"Elastic\"\nE = 200e9\n";

/// Four 0.05 m elastic concrete layers (E 30 GPa, ν 0), vertical bars (90°, 2 mm smeared)
/// and horizontal bars (0°, 0.5 mm) near each face; ρ = 2500 kg/m³ over the whole
/// thickness.
const LAYERS: &str = r#"[[section]]
tag = 10
type = "layered_shell"
density = 2500.0
layers = [
  { type = "elastic", thickness = 0.05, E = 30e9, nu = 0.0 },
  { type = "rebar", thickness = 0.002, material = 1, angle = 90.0 },
  { type = "rebar", thickness = 0.0005, material = 1, angle = 0.0 },
  { type = "elastic", thickness = 0.05, E = 30e9, nu = 0.0 },
  { type = "elastic", thickness = 0.05, E = 30e9, nu = 0.0 },
  { type = "rebar", thickness = 0.0005, material = 1, angle = 0.0 },
  { type = "rebar", thickness = 0.002, material = 1, angle = 90.0 },
  { type = "elastic", thickness = 0.05, E = 30e9, nu = 0.0 },
]
"#;

fn run(model: &Model, args: &[&str]) -> (String, Value) {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("wall.py");
    let script = opensees_script(model, "wall.toml", &OpenSeesOptions::default()).unwrap();
    std::fs::write(&p, &script).unwrap();
    let v = crate::openseespy_json(Command::new("python3").arg(&p).args(args));
    (script, v)
}

/// Out-of-plane first mode of the layered cantilever wall (1 m × 6 m) against the
/// Euler–Bernoulli cantilever: ω₁ = 1.875104² √(D b / (m L⁴)), with the layered section's
/// bending stiffness per unit width by the midpoint rule of each layer (as OpenSees'
/// LayeredShell): D = Σ Eᵢ tᵢ zᵢ², only the vertical (90°) bars counting, and
/// m = ρ h b. ν = 0 makes the strip a beam. The script must write the layers in order,
/// the PlateRebar angles about the element's local x (edge 1→2, horizontal) and the mass
/// ρ h per area: each of these changes the period by more than the 1.5 % tolerance
/// (swapping the bar angles: +3.9 %; dropping the bars: +5.2 %).
#[test]
fn layered_wall_exports_to_asdshellq4_and_matches_the_cantilever_period() {
    let (b, h) = (1.0, 6.0);
    let text = wall(b, h, 12, STEEL, LAYERS);
    let model = Model::parse(&text, "wall.toml", false).unwrap();
    let thick = 4.0 * 0.05 + 2.0 * 0.002 + 2.0 * 0.0005;
    assert!((model.total_mass() - 2500.0 * thick * b * h).abs() < 1e-6);
    let (script, v) = run(&model, &["eigen", "3"]);
    for needle in [
        "ops.nDMaterial(\"PlateRebar\", 3, 1, 90.0)",
        "ops.section(\"LayeredShell\", 10, 8,",
        "ops.element(\"ASDShellQ4\", 1, 1, 2, 102, 101, 10, \"-local\", 0.5, 0.0, 0.0)",
    ] {
        assert!(script.contains(needle), "{needle} not in the script");
    }
    // Layer mid-planes, bottom to top.
    let ts = [0.05, 0.002, 0.0005, 0.05, 0.05, 0.0005, 0.002, 0.05];
    let es = [30e9, 200e9, 0.0, 30e9, 30e9, 0.0, 200e9, 30e9];
    let mut z = -thick / 2.0;
    let mut d = 0.0;
    for (t, e) in ts.iter().zip(es) {
        let zm = z + t / 2.0;
        d += e * t * zm * zm;
        z += t;
    }
    let m = 2500.0 * thick * b;
    let w = 1.875104f64.powi(2) * (d * b / (m * h.powi(4))).sqrt();
    let t_cf = 2.0 * std::f64::consts::PI / w;
    let modes = v["modes"].as_array().unwrap();
    let m1 = modes
        .iter()
        .max_by(|a, b| {
            a["Y"]
                .as_f64()
                .unwrap()
                .total_cmp(&b["Y"].as_f64().unwrap())
        })
        .unwrap();
    let t_os = m1["T"].as_f64().unwrap();
    eprintln!(
        "out-of-plane mode: OpenSees T = {t_os:.5} s, Euler-Bernoulli {t_cf:.5} s ({:+.2} %), share Y {:.3}",
        (t_os / t_cf - 1.0) * 100.0,
        m1["Y"]
    );
    assert!((t_os / t_cf - 1.0).abs() < 0.015, "{t_os} vs {t_cf}");
}

fn err(text: &str) -> String {
    Model::parse(text, "wall.toml", false)
        .unwrap_err()
        .to_string()
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).unwrap() + 1
}

#[test]
fn bad_layered_sections_and_shells_are_refused_with_file_line_and_item() {
    let good = wall(1.0, 2.0, 2, STEEL, LAYERS);
    Model::parse(&good, "wall.toml", false).unwrap();
    let expect = |text: &str, needle: &str, item: &str, msg: &str| {
        let e = err(text);
        let line = line_of(text, needle);
        assert!(
            e.starts_with(&format!("wall.toml:{line}: {item}: ")),
            "{e} (want line {line})"
        );
        assert!(e.contains(msg), "{e}");
    };
    // A layer with zero thickness.
    let t = good.replacen(
        "{ type = \"rebar\", thickness = 0.002, material = 1, angle = 90.0 }",
        "{ type = \"rebar\", thickness = 0.0, material = 1, angle = 90.0 }",
        1,
    );
    expect(
        &t,
        "[[section]]",
        "section 10",
        "layer 2: thickness = 0 must be positive",
    );
    // A rebar layer naming an unknown material.
    let t = good.replacen("material = 1, angle = 0.0", "material = 7, angle = 0.0", 1);
    expect(&t, "[[section]]", "section 10", "unknown material 7");
    // Concrete with ft above fc, and too few layers.
    let t = wall(
        1.0,
        2.0,
        2,
        STEEL,
        "[[section]]\ntag = 10\ntype = \"layered_shell\"\nlayers = [\n  { type = \"concrete\", thickness = 0.1, E = 30e9, nu = 0.2, fc = 30e6, ft = 40e6 },\n  { type = \"elastic\", thickness = 0.1, E = 30e9, nu = 0.2 },\n  { type = \"elastic\", thickness = 0.1, E = 30e9, nu = 0.6 },\n]\n",
    );
    expect(
        &t,
        "[[section]]",
        "section 10",
        "layer 1: ft = 40000000 must be positive and below fc",
    );
    let t = wall(
        1.0,
        2.0,
        2,
        STEEL,
        "[[section]]\ntag = 10\ntype = \"layered_shell\"\nlayers = [\n  { type = \"elastic\", thickness = 0.1, E = 30e9, nu = 0.2 },\n  { type = \"elastic\", thickness = 0.1, E = 30e9, nu = 0.2 },\n]\n",
    );
    expect(
        &t,
        "[[section]]",
        "section 10",
        "has 2 layers; a layered shell needs at least 3",
    );
    // An unknown layer type is a parse error on its line.
    let t = good.replacen(
        "type = \"elastic\", thickness = 0.05",
        "type = \"plastic\", thickness = 0.05",
        1,
    );
    let e = err(&t);
    assert!(e.starts_with("wall.toml:"), "{e}");
    assert!(e.contains("plastic"), "{e}");
    // local_x normal to the wall's plane (the wall is in XZ: normal ±Y).
    let t = good.replacen(
        "section = 10\n",
        "section = 10\nlocal_x = [0.0, 1.0, 0.0]\n",
        1,
    );
    expect(
        &t,
        "[[element]]",
        "element 1",
        "normal to the shell's plane",
    );
    // A layered section on a beam-column.
    let t = format!(
        "{good}[[transformation]]\ntag = 1\ntype = \"linear\"\nvecxz = [0.0, 1.0, 0.0]\n[[element]]\ntag = 99\ntype_name = \"Column\"\ngroup = 1\ntype = \"beam_column\"\nnodes = [1, 101]\nsection = 10\ntransf = 1\n"
    );
    let e = err(&t);
    let line = t.lines().count() - 7; // the last [[element]] header
    assert_eq!(t.lines().nth(line - 1), Some("[[element]]"));
    assert!(
        e.starts_with(&format!("wall.toml:{line}: element 99: ")),
        "{e}"
    );
    assert!(e.contains("wrong kind"), "{e}");
}
