//! Helpers shared by the test folders of this crate.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// The repository's top folder.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A numeric CSV table: its header and its rows.
pub fn read_csv(path: &std::path::Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let head: Vec<String> = lines
        .next()
        .expect("header")
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split(',').map(|x| x.trim().parse().unwrap()).collect())
        .collect();
    (head, rows)
}

/// Every `.rs` file under `dir`, recursively, in sorted path order (appended to `out`).
pub fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// An axis-aligned box for the ruin-stage tests: group "rc" (active) or "base" (passive),
/// centre and half extents in m.
pub fn rc_box(
    name: &str,
    centre: [f64; 3],
    he: [f64; 3],
    passive: bool,
) -> fem2rbd::ruin::BodyGeom {
    fem2rbd::ruin::BodyGeom {
        name: name.into(),
        group: if passive { "base" } else { "rc" }.into(),
        centre,
        rotation: nalgebra::UnitQuaternion::identity(),
        half_extents: he,
        passive,
    }
}
