//! `anyhow` belongs to the binary's edge (ARCHITECTURE.md, "Errors"): `src/main.rs`,
//! `src/cli/` and `src/bin/`. The libraries (the `fem2rbd` library, `fem2rbd-fe`,
//! `fem2rbd-bullet`) return typed errors. This scans their sources for a use of
//! `anyhow` in code (comments are skipped) and their manifests for the dependency.
use crate::support::rust_files;
use std::path::Path;

/// Line numbers (1-based) of code (the part of a line before `//`) naming `anyhow`.
fn anyhow_lines(src: &str) -> Vec<usize> {
    src.lines()
        .enumerate()
        .filter(|(_, l)| l.split("//").next().unwrap_or("").contains("anyhow"))
        .map(|(i, _)| i + 1)
        .collect()
}

/// The binary's edge, where `anyhow` is allowed.
fn is_edge(rel: &Path) -> bool {
    rel == Path::new("src/main.rs") || rel.starts_with("src/cli") || rel.starts_with("src/bin")
}

#[test]
fn scanner_sees_code_but_not_comments() {
    let src = "//! as `anyhow` did\nuse anyhow::Result; // x\nlet x = 1; // anyhow\nanyhow::bail!(\"x\");\n";
    assert_eq!(anyhow_lines(src), vec![2, 4]);
}

#[test]
fn anyhow_only_at_the_binary_edge() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in ["src", "crates/fem2rbd-fe/src", "crates/fem2rbd-bullet/src"] {
        rust_files(&root.join(dir), &mut files);
    }
    assert!(files.len() > 50, "found too few source files: {files:?}");
    let (mut bad, mut at_edge) = (Vec::new(), 0);
    for f in &files {
        let rel = f.strip_prefix(root).unwrap();
        let hits = anyhow_lines(&std::fs::read_to_string(f).unwrap());
        if is_edge(rel) {
            at_edge += hits.len();
        } else {
            bad.extend(hits.iter().map(|l| format!("{}:{l}", rel.display())));
        }
    }
    assert!(
        bad.is_empty(),
        "`anyhow` in library code (use a thiserror enum; anyhow is for src/main.rs, \
         src/cli/, src/bin/): {bad:?}"
    );
    // Not vacuous: the binary does use anyhow.
    assert!(
        at_edge > 0,
        "no anyhow found at the edge — is the scanner broken?"
    );
    // The library crates do not depend on it (the root package keeps it for its binaries:
    // a package's binaries share its [dependencies]).
    for manifest in [
        "crates/fem2rbd-fe/Cargo.toml",
        "crates/fem2rbd-bullet/Cargo.toml",
    ] {
        let text = std::fs::read_to_string(root.join(manifest)).unwrap();
        assert!(
            !text.lines().any(|l| l.trim_start().starts_with("anyhow")),
            "{manifest} depends on anyhow"
        );
    }
}
