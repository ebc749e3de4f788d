//! `[fe] concrete_integration` of a scenario (docs/scenario-format.md): the shells'
//! concrete layers integrated by OpenSees' implicit law (default) or IMPL-EX
//! (docs/shell-verification.md §10). The library scenarios ask for IMPL-EX; a value that
//! is neither is refused naming the file, line and key before anything runs.
use crate::support::root;
use fem2rbd::fe::shell::layers::ConcreteIntegration;
use fem2rbd::pipeline::Scenario;

#[test]
fn library_scenarios_use_implex_others_default_to_implicit_and_bad_values_are_refused() {
    for f in ["elcentro-4g.toml", "elcentro-4g-fe.toml"] {
        let sc = Scenario::load(root().join("data/library").join(f)).unwrap();
        assert_eq!(sc.concrete_integration, ConcreteIntegration::Implex, "{f}");
    }
    let sc = Scenario::load(root().join("data/frame3/lc5.toml")).unwrap();
    assert_eq!(sc.concrete_integration, ConcreteIntegration::Implicit);

    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(root().join("data/library/elcentro-4g-fe.toml"))
        .unwrap()
        .replace(
            "model = \"model.toml\"",
            &format!(
                "model = \"{}\"",
                root().join("data/library/model.toml").display()
            ),
        )
        .replace(
            "../ground-motions",
            &root().join("data/ground-motions").display().to_string(),
        )
        .replace(
            "concrete_integration = \"implex\"",
            "concrete_integration = \"explicit\"",
        );
    let p = dir.path().join("bad.toml");
    std::fs::write(&p, &text).unwrap();
    let err = Scenario::load(&p).unwrap_err().to_string();
    let line = text
        .lines()
        .position(|l| l.starts_with("concrete_integration"))
        .unwrap()
        + 1;
    assert!(err.contains("bad.toml"), "{err}");
    assert!(err.contains(&line.to_string()), "line {line}: {err}");
    assert!(err.contains("explicit") && err.contains("implex"), "{err}");
}
