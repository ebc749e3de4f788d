//! `unsafe` code is allowed only in `bullet-sys` and in `crates/fem2rbd-bullet` (the one
//! safe wrapper over it). This scans every `.rs` file of the other crates' sources and
//! fails if the keyword `unsafe` appears as a token (outside comments, strings and char
//! literals), and checks that their crate roots say `#![forbid(unsafe_code)]`.
use crate::support::rust_files;
use std::path::Path;

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

/// Source folders where `unsafe` is forbidden, and the crate roots that must say so.
const SAFE_SOURCES: [&str; 2] = ["src", "crates/fem2rbd-fe/src"];
const SAFE_ROOTS: [&str; 3] = ["src/lib.rs", "src/main.rs", "crates/fem2rbd-fe/src/lib.rs"];
const WRAPPER: &str = "crates/fem2rbd-bullet/src";

#[test]
fn unsafe_only_in_the_bullet_wrapper() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in SAFE_SOURCES {
        rust_files(&root.join(dir), &mut files);
    }
    assert!(files.len() > 50, "found too few source files: {files:?}");
    let mut bad = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        for l in unsafe_tokens(&text) {
            bad.push(format!("{}:{l}", f.strip_prefix(root).unwrap().display()));
        }
    }
    assert!(bad.is_empty(), "`unsafe` outside {WRAPPER}: {bad:?}");
    for r in SAFE_ROOTS {
        let text = std::fs::read_to_string(root.join(r)).unwrap();
        assert!(
            text.contains("#![forbid(unsafe_code)]"),
            "{r} lacks #![forbid(unsafe_code)]"
        );
    }
    // The scan is not vacuous: the wrapper itself does use unsafe.
    let mut wrapper = Vec::new();
    rust_files(&root.join(WRAPPER), &mut wrapper);
    let in_wrapper: usize = wrapper
        .iter()
        .map(|f| unsafe_tokens(&std::fs::read_to_string(f).unwrap()).len())
        .sum();
    assert!(
        in_wrapper > 0,
        "no unsafe found in {WRAPPER} — is the scanner broken?"
    );
}
