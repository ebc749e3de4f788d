//! With `autotests = false`, Cargo ignores a test file that no `mod` line reaches, silently.
//! This walks both integration-test crates (`tests/it/`, `crates/fem2rbd-fe/tests/it/`)
//! from their `main.rs` along the `mod` declarations and fails on any `.rs` file under
//! `tests/` (outside the Node/Python helper folders) that is not reached.
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn rs_files(dir: &Path, out: &mut BTreeSet<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().to_string();
        if p.is_dir() {
            if name != "node_modules" && name != "snapshots" {
                rs_files(&p, out);
            }
        } else if name.ends_with(".rs") {
            out.insert(p);
        }
    }
}

/// Module files reached from `file` (a module whose children live in `dir`), recursively.
/// Understands `mod a;` and inline `mod a { mod b; }` blocks; nesting is read from the
/// indentation (the tree is rustfmt-formatted, which CI checks).
fn reached(file: &Path, dir: &Path, out: &mut BTreeSet<PathBuf>) {
    let text = std::fs::read_to_string(file).unwrap();
    // Open inline modules: (indentation, name).
    let mut inline: Vec<(usize, String)> = Vec::new();
    for line in text.lines() {
        let indent = line.len() - line.trim_start().len();
        let t = line.trim();
        let t = t
            .strip_prefix("pub(crate) ")
            .or_else(|| t.strip_prefix("pub "))
            .unwrap_or(t);
        let Some(rest) = t.strip_prefix("mod ") else {
            continue;
        };
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        inline.retain(|(i, _)| *i < indent);
        let mut here = dir.to_path_buf();
        for (_, m) in &inline {
            here.push(m);
        }
        if rest.trim_end().ends_with('{') {
            inline.push((indent, name));
        } else if rest.trim_end().ends_with(';') {
            let flat = here.join(format!("{name}.rs"));
            let child = if flat.exists() {
                flat
            } else {
                here.join(&name).join("mod.rs")
            };
            assert!(
                child.exists(),
                "{}: `mod {name};` has no file",
                file.display()
            );
            out.insert(child.clone());
            reached(&child, &here.join(&name), out);
        }
    }
}

#[test]
fn every_test_file_is_part_of_a_test_crate() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = BTreeSet::new();
    let mut seen = BTreeSet::new();
    for tests in [root.join("tests"), root.join("crates/fem2rbd-fe/tests")] {
        rs_files(&tests, &mut files);
        let main = tests.join("it/main.rs");
        seen.insert(main.clone());
        reached(&main, &tests.join("it"), &mut seen);
    }
    // Helper sources of the Node/Python checks are not Rust test modules.
    files.retain(|f| !f.starts_with(root.join("tests/gltf")));
    let orphans: Vec<_> = files.difference(&seen).collect();
    assert!(
        orphans.is_empty(),
        "test files no `mod` line reaches (Cargo ignores them): {orphans:?}"
    );
    assert!(seen.len() > 60, "walked too few modules: {}", seen.len());
}
