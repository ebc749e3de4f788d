//! `unsafe` code is allowed only in `bullet-sys` and in `src/physics/` (the one safe
//! wrapper over it). This scans every `.rs` file under `src/` and fails if the keyword
//! `unsafe` appears as a token (outside comments, strings and char literals) anywhere else.
use std::path::{Path, PathBuf};

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
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

/// Line numbers (1-based) where `unsafe` occurs as a code token.
fn unsafe_tokens(src: &str) -> Vec<usize> {
    let b = src.as_bytes();
    let (mut i, mut line, mut hits) = (0usize, 1usize, Vec::new());
    let is_ident = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    while i < b.len() {
        let c = b[i];
        if c == b'\n' {
            line += 1;
            i += 1;
        } else if b[i..].starts_with(b"//") {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if b[i..].starts_with(b"/*") {
            let mut depth = 0;
            while i < b.len() {
                if b[i..].starts_with(b"/*") {
                    depth += 1;
                    i += 2;
                } else if b[i..].starts_with(b"*/") {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    if b[i] == b'\n' {
                        line += 1;
                    }
                    i += 1;
                }
            }
        } else if c == b'r'
            && i + 1 < b.len()
            && (b[i + 1] == b'"' || b[i + 1] == b'#')
            && (i == 0 || !is_ident(b[i - 1]))
        {
            // Raw string r#*"..."#*.
            let mut j = i + 1;
            let mut hashes = 0;
            while j < b.len() && b[j] == b'#' {
                hashes += 1;
                j += 1;
            }
            if j < b.len() && b[j] == b'"' {
                let close: Vec<u8> = std::iter::once(b'"')
                    .chain(std::iter::repeat_n(b'#', hashes))
                    .collect();
                j += 1;
                while j < b.len() && !b[j..].starts_with(&close) {
                    if b[j] == b'\n' {
                        line += 1;
                    }
                    j += 1;
                }
                i = j + close.len();
            } else {
                i += 1;
            }
        } else if c == b'"' {
            i += 1;
            while i < b.len() && b[i] != b'"' {
                if b[i] == b'\\' {
                    i += 1;
                }
                if i < b.len() && b[i] == b'\n' {
                    line += 1;
                }
                i += 1;
            }
            i += 1;
        } else if c == b'\'' {
            // Char literal ('x', '\n', '\'') or a lifetime ('a): skip only literals.
            if i + 2 < b.len() && b[i + 1] == b'\\' {
                i += 2;
                while i < b.len() && b[i] != b'\'' {
                    i += 1;
                }
                i += 1;
            } else if i + 2 < b.len() && b[i + 2] == b'\'' {
                i += 3;
            } else {
                i += 1;
            }
        } else if is_ident(c) {
            let start = i;
            while i < b.len() && is_ident(b[i]) {
                i += 1;
            }
            if &b[start..i] == b"unsafe" {
                hits.push(line);
            }
        } else {
            i += 1;
        }
    }
    hits
}

#[test]
fn scanner_sees_code_but_not_comments_or_strings() {
    let src = "// unsafe\n/* unsafe /* nested */ unsafe */\nlet s = \"unsafe\";\nlet r = r#\"unsafe\"#;\n#![deny(unsafe_code)]\nfn f<'a>(c: char) { let q = '\"'; unsafe { g() } }\n";
    assert_eq!(unsafe_tokens(src), vec![6]);
}

#[test]
fn unsafe_only_in_src_physics() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    assert!(files.len() > 5, "found too few source files: {files:?}");
    let allowed = root.join("src").join("physics");
    let mut bad = Vec::new();
    let mut in_physics = 0;
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        let hits = unsafe_tokens(&text);
        if f.starts_with(&allowed) {
            in_physics += hits.len();
        } else {
            for l in hits {
                bad.push(format!("{}:{l}", f.strip_prefix(root).unwrap().display()));
            }
        }
    }
    assert!(bad.is_empty(), "`unsafe` outside src/physics/: {bad:?}");
    // The scan is not vacuous: the wrapper itself does use unsafe.
    assert!(
        in_physics > 0,
        "no unsafe found in src/physics/ — is the scanner broken?"
    );
}
