//! Bad model files give an error naming the file, the line and the item.
use fem2rbd_fe::model::limits::InputFileError;
use fem2rbd_fe::model::{Model, ModelError};

const BASE: &str = r#"name = "portal"
scale = 0.25

material = [
  { tag = 1, type = "Concrete02", density = 2500.0, fpc = -30e6, epsc0 = -0.002, fpcu = -6e6, epscu = -0.004, lambda = 0.1, ft = 1.8e6, Ets = 9e8 },
  { tag = 2, type = "Steel02", Fy = 400e6, E0 = 200e9, b = 0.01, R0 = 18.0, cR1 = 0.925, cR2 = 0.15 },
  { tag = 3, type = "Elastic", E = 30e9 },
]

section = [
  { tag = 1, type = "rc_rect", b = 0.3, h = 0.3, cover = 0.03, core_material = 1, cover_material = 1, core_fibers = [4, 4], bar_material = 2, bars = [[-0.1, -0.1, 3e-4], [0.1, 0.1, 3e-4]], GJ = 1e7 },
  { tag = 2, type = "fiber", GJ = 1e7, fibers = [[0.0, -0.1, 0.01, 1], [0.0, 0.1, 0.01, 1]] },
  { tag = 3, type = "elastic", E = 30e9, G = 12e9, A = 0.09, Iy = 6.75e-4, Iz = 6.75e-4, J = 1.1e-3 },
  { tag = 4, type = "plate", E = 30e9, nu = 0.2, h = 0.12, density = 2500.0 },
]

transformation = [
  { tag = 1, type = "pdelta", vecxz = [1.0, 0.0, 0.0] },
  { tag = 2, type = "linear", vecxz = [0.0, 0.0, 1.0] },
]

node = [
  { tag = 1, x = 0.0, y = 0.0, z = 0.0 },
  { tag = 2, x = 0.0, y = 0.0, z = 3.0 },
  { tag = 3, x = 4.0, y = 0.0, z = 3.0 },
  { tag = 4, x = 4.0, y = 0.0, z = 0.0 },
  { tag = 5, x = 0.0, y = 4.0, z = 3.0 },
  { tag = 6, x = 4.0, y = 4.0, z = 3.0 },
]

support = [
  { node = 1, dofs = [1, 1, 1, 1, 1, 1] },
  { node = 4, dofs = [1, 1, 1, 1, 1, 1] },
]

element = [
  { tag = 1, type_name = "Column", group = 1, type = "beam_column", nodes = [1, 2], section = 1, transf = 1 },
  { tag = 2, type_name = "Beam", group = "C30", type = "beam_column", nodes = [2, 3], section = 2, transf = 2, formulation = "disp", points = 4 },
  { tag = 3, type_name = "Column", group = 1, type = "elastic_beam_column", nodes = [4, 3], section = 3, transf = 1 },
  { tag = 4, type_name = "Slab", group = 1, type = "elastic_strip", nodes = [2, 6], transf = 2, E = 30e9, G = 12.5e9, width = 1.0, thickness = 0.12 },
  { tag = 5, type_name = "Slab", group = 1, type = "shell", nodes = [2, 3, 6, 5], section = 4 },
]

mass = [
  { node = 2, m = 1000.0 },
  { node = 3, m = 1000.0, rotational = [0.0, 0.0, 10.0] },
]

[damping]
xi = 0.05
periods = [0.3, 0.1]
"#;

/// Parses `text` as TOML named `bad.toml`; returns the error text.
fn err(text: &str) -> String {
    match Model::parse(text, "bad.toml", false) {
        Ok(_) => panic!("expected an error"),
        Err(e) => e.to_string(),
    }
}

/// Parses `text` as TOML named `bad.toml`; returns the error itself (its kind).
fn failure(text: &str) -> ModelError {
    Model::parse(text, "bad.toml", false).expect_err("expected an error")
}

/// 1-based line of the first occurrence of `needle` in `text`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).expect(needle) + 1
}

/// Replaces `from` (must occur once) by `to`.
fn edit(from: &str, to: &str) -> String {
    assert_eq!(BASE.matches(from).count(), 1, "{from}");
    BASE.replace(from, to)
}

fn expect(text: &str, line_marker: &str, item: &str, msg: &str) {
    let e = err(text);
    let line = line_of(text, line_marker);
    let want = format!("bad.toml:{line}: {item}: ");
    assert!(
        e.starts_with(&want),
        "error {e:?} should start with {want:?}"
    );
    assert!(e.contains(msg), "error {e:?} should mention {msg:?}");
}

#[test]
fn base_model_is_valid_and_derived_quantities_are_right() {
    let m = Model::parse(BASE, "base.toml", false).unwrap();
    assert_eq!(m.elements[1].group.0, "C30");
    assert_eq!(m.elements[0].body_name(), "Column:1:1");
    // self-weight: column 2500*0.09*3 (rc fibers: concrete only, steel density 0)
    let col = m.element_mass(&m.elements[0]);
    assert!((col - 2500.0 * 0.09 * 3.0).abs() < 1e-9, "{col}");
    let shell = m.element_mass(&m.elements[4]);
    assert!((shell - 2500.0 * 0.12 * 16.0).abs() < 1e-9, "{shell}");
    let total = m.total_mass();
    let want = 2500.0 * 0.09 * 3.0 + 2500.0 * 0.02 * 4.0 + 2500.0 * 0.12 * 16.0 + 2000.0;
    assert!((total - want).abs() < 1e-9 * want, "{total} vs {want}");
    // gravity loads skip fully fixed nodes and equal -m g
    let loads = m.gravity_loads();
    assert!(loads.iter().all(|(t, _)| *t != 1 && *t != 4));
    let l2 = loads.iter().find(|(t, _)| *t == 2).unwrap().1;
    let m2 = m.lumped_masses()[&2][2];
    assert!((l2 + m2 * 9.81).abs() < 1e-9);
    // Rayleigh: a0 = 2 xi wi wj/(wi+wj), a1 = 2 xi/(wi+wj)
    let (a0, a1) = m.rayleigh().unwrap();
    let (wi, wj) = (
        2.0 * std::f64::consts::PI / 0.3,
        2.0 * std::f64::consts::PI / 0.1,
    );
    assert!((a0 - 0.1 * wi * wj / (wi + wj)).abs() < 1e-12);
    assert!((a1 - 0.1 / (wi + wj)).abs() < 1e-15);
    // the same model as JSON loads equal
    let js = serde_json::to_string_pretty(&m).unwrap();
    assert_eq!(Model::parse(&js, "m.json", true).unwrap(), m);
}

#[test]
fn toml_syntax_error_names_file_and_line() {
    let t = edit("{ tag = 3, x = 4.0,", "{ tag = 3, x = 4.0 y,");
    let e = err(&t);
    let line = line_of(&t, "x = 4.0 y");
    assert!(e.starts_with(&format!("bad.toml:{line}:")), "{e}");
    assert!(matches!(failure(&t), ModelError::Syntax { at, .. } if at.line == Some(line)));
}

#[test]
fn missing_field_names_line_and_item() {
    let t = edit(
        "{ tag = 2, x = 0.0, y = 0.0, z = 3.0 }",
        "{ tag = 2, x = 0.0, y = 0.0 }",
    );
    let e = err(&t);
    let line = line_of(&t, "{ tag = 2, x = 0.0, y = 0.0 }");
    assert!(
        e.starts_with(&format!("bad.toml:{line}: node item 2: ")),
        "{e}"
    );
    assert!(e.contains("missing field `z`"), "{e}");
    assert!(matches!(
        failure(&t),
        ModelError::Syntax { at, .. } if at.item.as_deref() == Some("node item 2")
    ));
}

#[test]
fn unknown_node_in_element() {
    let t = edit(
        "nodes = [2, 3], section = 2",
        "nodes = [2, 33], section = 2",
    );
    expect(&t, "nodes = [2, 33]", "element 2", "unknown node 33");
    assert!(matches!(failure(&t), ModelError::UnknownReference { .. }));
}

#[test]
fn unknown_section_in_element() {
    let t = edit("nodes = [1, 2], section = 1", "nodes = [1, 2], section = 9");
    expect(&t, "section = 9", "element 1", "unknown section 9");
    assert!(matches!(failure(&t), ModelError::UnknownReference { .. }));
}

#[test]
fn unknown_transformation_in_element() {
    let t = edit("section = 3, transf = 1", "section = 3, transf = 7");
    expect(&t, "transf = 7", "element 3", "unknown transformation 7");
    assert!(matches!(failure(&t), ModelError::UnknownReference { .. }));
}

#[test]
fn unknown_material_in_fiber_section() {
    let t = edit("[0.0, 0.1, 0.01, 1]", "[0.0, 0.1, 0.01, 5]");
    expect(&t, "[0.0, 0.1, 0.01, 5]", "section 2", "unknown material 5");
    assert!(matches!(failure(&t), ModelError::UnknownReference { .. }));
}

#[test]
fn unknown_node_in_mass_and_support() {
    let t = edit("{ node = 2, m = 1000.0 }", "{ node = 12, m = 1000.0 }");
    expect(&t, "node = 12", "mass 1 (node 12)", "unknown node 12");
    let t = edit("{ node = 4, dofs", "{ node = 40, dofs");
    expect(&t, "node = 40", "support of node 40", "unknown node 40");
    assert!(matches!(failure(&t), ModelError::UnknownReference { .. }));
}

#[test]
fn duplicate_tags() {
    let t = edit("{ tag = 5, x = 0.0", "{ tag = 4, x = 0.0");
    expect(&t, "{ tag = 4, x = 0.0", "node 4", "duplicate node tag");
    let t = edit(
        "{ tag = 4, type_name = \"Slab\"",
        "{ tag = 3, type_name = \"Slab\"",
    );
    expect(
        &t,
        "{ tag = 3, type_name = \"Slab\"",
        "element 3",
        "duplicate element tag",
    );
    let t = edit(
        "{ tag = 3, type = \"Elastic\"",
        "{ tag = 2, type = \"Elastic\"",
    );
    expect(
        &t,
        "{ tag = 2, type = \"Elastic\"",
        "material 2",
        "duplicate material tag",
    );
    assert!(matches!(failure(&t), ModelError::Duplicate { .. }));
}

#[test]
fn zero_length_element() {
    let t = edit("nodes = [2, 6], transf = 2", "nodes = [2, 7], transf = 2").replace(
        "  { tag = 6, x = 4.0,",
        "  { tag = 7, x = 0.0, y = 0.0, z = 3.0 },\n  { tag = 6, x = 4.0,",
    );
    expect(&t, "nodes = [2, 7]", "element 4", "zero length");
    assert!(matches!(failure(&t), ModelError::Geometry { .. }));
}

#[test]
fn vecxz_parallel_to_axis() {
    let t = edit(
        "nodes = [1, 2], section = 1, transf = 1",
        "nodes = [1, 2], section = 1, transf = 2",
    );
    expect(
        &t,
        "nodes = [1, 2]",
        "element 1",
        "parallel to the element axis",
    );
    assert!(matches!(failure(&t), ModelError::Geometry { .. }));
}

#[test]
fn non_positive_sizes_and_areas() {
    let t = edit("b = 0.3, h = 0.3", "b = 0.0, h = 0.3");
    expect(
        &t,
        "b = 0.0, h = 0.3",
        "section 1",
        "b = 0 must be positive",
    );
    let t = edit("[0.0, -0.1, 0.01, 1]", "[0.0, -0.1, -0.01, 1]");
    expect(
        &t,
        "[0.0, -0.1, -0.01, 1]",
        "section 2",
        "fiber 1 area = -0.01 must be positive",
    );
    let t = edit(
        "width = 1.0, thickness = 0.12",
        "width = 1.0, thickness = 0.0",
    );
    expect(
        &t,
        "thickness = 0.0",
        "element 4",
        "thickness = 0 must be positive",
    );
    let t = edit("A = 0.09", "A = -0.09");
    expect(&t, "A = -0.09", "section 3", "A = -0.09 must be positive");
    let t = edit("{ node = 3, m = 1000.0", "{ node = 3, m = -1000.0");
    expect(&t, "m = -1000.0", "mass 2 (node 3)", "must not be negative");
    let t = edit("E = 30e9 }", "E = 0.0 }");
    expect(&t, "E = 0.0 }", "material 3", "E = 0 must be positive");
    let t = edit("cover = 0.03", "cover = 0.2");
    expect(&t, "cover = 0.2", "section 1", "leaves no core");
}

#[test]
fn nan_and_infinity() {
    let t = edit("{ tag = 3, x = 4.0,", "{ tag = 3, x = nan,");
    expect(&t, "x = nan", "node 3", "x is not finite");
    let t = edit("fpc = -30e6", "fpc = -inf");
    expect(&t, "fpc = -inf", "material 1", "fpc is not finite");
    let t = edit("Iy = 6.75e-4", "Iy = inf");
    expect(&t, "Iy = inf", "section 3", "Iy is not finite");
}

#[test]
fn wrong_material_sign_and_section_kind() {
    let t = edit("fpc = -30e6", "fpc = 30e6");
    expect(&t, "fpc = 30e6", "material 1", "must be negative");
    let t = edit(
        "type = \"shell\", nodes = [2, 3, 6, 5], section = 4",
        "type = \"shell\", nodes = [2, 3, 6, 5], section = 3",
    );
    expect(&t, "section = 3 }", "element 5", "wrong kind");
}

#[test]
fn incomplete_damping() {
    let t = edit("periods = [0.3, 0.1]\n", "");
    let e = err(&t);
    let line = line_of(&t, "[damping]");
    assert!(e.starts_with(&format!("bad.toml:{line}: damping: ")), "{e}");
    assert!(e.contains("give either xi and periods"), "{e}");
}

#[test]
fn json_errors_carry_lines_too() {
    let m = Model::parse(BASE, "base.toml", false).unwrap();
    let js = serde_json::to_string_pretty(&m).unwrap();
    // syntax error
    let bad = js.replacen("\"tag\": 3,", "\"tag\": 3,,", 1);
    let e = Model::parse(&bad, "bad.json", true)
        .unwrap_err()
        .to_string();
    let line = line_of(&bad, "\"tag\": 3,,");
    assert!(e.starts_with(&format!("bad.json:{line}:")), "{e}");
    // semantic error: unknown node in element 2
    let mut v: serde_json::Value = serde_json::from_str(&js).unwrap();
    v["element"][1]["nodes"][1] = 99.into();
    let text = serde_json::to_string_pretty(&v).unwrap();
    let e = Model::parse(&text, "bad.json", true)
        .unwrap_err()
        .to_string();
    let line = text.lines().position(|l| l.contains("99")).unwrap() + 1;
    assert!(
        e.starts_with("bad.json:") && e.contains(": element 2: unknown node 99"),
        "{e}"
    );
    let got: usize = e.split(':').nth(1).unwrap().parse().unwrap();
    assert!(
        got < line && line - got < 15,
        "line {got} should be the start of element 2 (node at {line})"
    );
}

#[test]
fn load_reports_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("m.toml");
    std::fs::write(
        &p,
        edit(
            "nodes = [2, 3], section = 2",
            "nodes = [2, 33], section = 2",
        ),
    )
    .unwrap();
    let e = format!("{:#}", Model::load(&p).unwrap_err());
    assert!(e.starts_with(&p.display().to_string()), "{e}");
    let e = Model::load(dir.path().join("none.toml")).unwrap_err();
    assert!(
        matches!(e, ModelError::File(InputFileError::Missing { .. })),
        "{e}"
    );
    let e = e.to_string();
    assert!(e.contains("cannot read model file"), "{e}");
}

#[test]
fn unknown_top_level_key_is_an_error() {
    let t = BASE.replace("scale = 0.25", "scale = 0.25\nscal = 2.0");
    let e = err(&t);
    assert!(e.contains("unknown field `scal`"), "{e}");
    assert!(
        e.starts_with(&format!("bad.toml:{}:", line_of(&t, "scal ="))),
        "{e}"
    );
}

/// A misspelt key inside a material, a section or an element (flattened `type` data) is
/// an error naming the line, the item and the key — not silently ignored.
#[test]
fn unknown_key_inside_material_section_element_is_an_error() {
    let cases = [
        (
            "ft = 1.8e6, Ets",
            "ft = 1.8e6, ftt = 2.0, Ets",
            "material item 1",
            "unknown field `ftt`",
        ),
        (
            "cover = 0.03, core_material",
            "cover = 0.03, cvr = 0.04, core_material",
            "section item 1",
            "unknown field `cvr`",
        ),
        (
            "formulation = \"disp\", points = 4",
            "formulation = \"disp\", point = 4",
            "element item 2",
            "unknown field `point`",
        ),
    ];
    for (from, to, item, msg) in cases {
        let t = edit(from, to);
        let e = err(&t);
        let line = line_of(&t, to);
        assert!(e.starts_with(&format!("bad.toml:{line}:")), "{e}");
        assert!(e.contains(item) && e.contains(msg), "{e}");
    }
}
