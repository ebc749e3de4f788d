//! The reference-JSON importer reads every top-level key or refuses the file naming it:
//! shells, ties and loads it does not import are never dropped, and the keys it can check
//! (dimensions, units, total mass, gravity loads) must agree with the imported model.
use fem2rbd_fe::model::Model;
use serde_json::{json, Value};

const REF: &str = concat!(
    concat!(env!("CARGO_MANIFEST_DIR"), "/../.."),
    "/data/frame3-standin/reference-frame3.json"
);

fn reference() -> Value {
    serde_json::from_str(&std::fs::read_to_string(REF).unwrap()).unwrap()
}

/// Imports `v` written to a temporary file; the error message, or "" when it imports.
fn import(v: &Value) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("model.json");
    std::fs::write(&path, v.to_string()).unwrap();
    match Model::load(&path) {
        Ok(_) => String::new(),
        Err(e) => e.to_string(),
    }
}

#[test]
fn the_shipped_reference_imports_with_every_key_accounted_for() {
    assert_eq!(import(&reference()), "");
}

#[test]
fn content_the_importer_does_not_read_is_refused_by_name() {
    for (key, value, says) in [
        (
            "shell_elements",
            json!([{"tag": 1}, {"tag": 2}]),
            "`shell_elements` (2 items) not imported",
        ),
        (
            "equal_dofs",
            json!([{"retained": 1}]),
            "`equal_dofs` (1 items) not imported",
        ),
        ("loads", json!([]), "`loads` (0 items) not imported"),
        (
            "nd_materials",
            json!([{"tag": 9}]),
            "`nd_materials` (1 items) not imported",
        ),
    ] {
        let mut v = reference();
        v[key] = value;
        let err = import(&v);
        assert!(err.contains(says), "{key}: {err}");
        assert!(err.contains("docs/model-format.md"), "{err}");
    }
}

#[test]
fn a_layered_shell_section_is_refused_by_type() {
    let mut v = reference();
    v["sections"][0]["type"] = json!("LayeredShell");
    let err = import(&v);
    let tag = v["sections"][0]["tag"].as_u64().unwrap();
    assert!(
        err.contains(&format!(
            "section {tag}: type \"LayeredShell\" is not imported"
        )),
        "{err}"
    );
}

#[test]
fn checked_keys_must_agree_with_the_imported_model() {
    let mut v = reference();
    v["units"]["length"] = json!("mm");
    let err = import(&v);
    assert!(
        err.contains("`units.length` = \"mm\": the model is read in SI (length in m)"),
        "{err}"
    );

    let mut v = reference();
    v["ndf"] = json!(3);
    assert!(import(&v).contains("`ndf` = 3"), "{}", import(&v));

    let mut v = reference();
    v["total_mass_kg"] = json!(9000.0);
    let err = import(&v);
    assert!(err.contains("`total_mass_kg` = 9000 kg"), "{err}");
    assert!(err.contains("add up to 9386.75"), "{err}");

    let mut v = reference();
    let node = v["gravity_loads"]["loads"][0]["tag"].as_u64().unwrap();
    v["gravity_loads"]["loads"][0]["Fz"] = json!(-1.0);
    let err = import(&v);
    assert!(
        err.contains(&format!(
            "`gravity_loads`: node {node} Fz = -1 N, the imported masses give"
        )),
        "{err}"
    );
}
