//! The documentation says what is there: every repository path quoted in README.md,
//! ARCHITECTURE.md and `docs/*.md` (in backticks, code blocks or as a link target)
//! exists, every `fem2rbd <subcommand>` quoted names a subcommand the binary has (read
//! from the binary's own `--help`), the scenario reference `docs/scenario-format.md` lists
//! exactly the keys the scenario parser accepts, and no page dates itself by the round of work or the
//! issue that produced it ("session 7", "issue 12", "#12"): the history is in
//! CHANGELOG.md and git.
use crate::support::root;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_fem2rbd");

/// Top-level folders of the repository whose paths the pages quote.
const PREFIXES: [&str; 8] = [
    "src/",
    "tests/",
    "scripts/",
    "data/",
    "docs/",
    "crates/",
    "bullet-sys/",
    ".ci/",
];

/// The pages checked: README.md, ARCHITECTURE.md and every `docs/*.md`.
fn pages(root: &Path) -> Vec<PathBuf> {
    let mut out = vec![root.join("README.md"), root.join("ARCHITECTURE.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    out.extend(docs);
    out
}

/// The code of a Markdown page, with 1-based line numbers: every line of a fenced block
/// and every backticked span outside them.
fn code_spans(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut fenced = false;
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            out.push((i + 1, line.to_string()));
            continue;
        }
        // Outside a fence the odd-numbered pieces between backticks are code.
        for (k, piece) in line.split('`').enumerate() {
            if k % 2 == 1 && !piece.is_empty() {
                out.push((i + 1, piece.to_string()));
            }
        }
    }
    out
}

/// Targets of Markdown links, `[text](target)`, that are files of the repository (not a
/// URL, not an anchor on the same page), without their `#anchor`.
fn link_targets(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let mut rest = line;
        while let Some(at) = rest.find("](") {
            rest = &rest[at + 2..];
            let Some(end) = rest.find(')') else { break };
            let target = rest[..end].split('#').next().unwrap_or("").trim();
            if !target.is_empty() && !target.contains("://") && !target.starts_with("mailto:") {
                out.push((i + 1, target.to_string()));
            }
            rest = &rest[end..];
        }
    }
    out
}

/// Repository paths quoted in one piece of code: each word that starts with one of
/// [`PREFIXES`], cut at a Rust path (`::`), an anchor (`#`) or a line (`:12`), without
/// surrounding punctuation. Words with a placeholder or a pattern (`<name>`, `*`, `NNN`,
/// `…`, `{a,b}`, `$VAR`) are not paths and are skipped.
fn quoted_paths(code: &str) -> Vec<String> {
    let mut out = Vec::new();
    for word in code.split(|c: char| c.is_whitespace() || c == '=' || c == ',') {
        let word = word.trim_matches(|c: char| "\"'()[];,".contains(c));
        if !PREFIXES.iter().any(|p| word.starts_with(p)) {
            continue;
        }
        if word.contains(['<', '>', '*', '{', '}', '$', '…', '|']) || word.contains("NNN") {
            continue;
        }
        let word = word.split("::").next().unwrap();
        let word = word.split('#').next().unwrap();
        let word = word.split(':').next().unwrap();
        let word = word.trim_end_matches(['.', ',', ';', ')']);
        out.push(word.to_string());
    }
    out
}

/// The subcommands of `fem2rbd` and of each of them that has its own (`export opensees`,
/// `study run`, …), read from the binary's `--help`.
fn subcommands(args: &[&str]) -> BTreeSet<String> {
    let out = Command::new(BIN)
        .args(args)
        .arg("--help")
        .output()
        .expect("run fem2rbd --help");
    assert!(out.status.success(), "fem2rbd {args:?} --help failed");
    let text = String::from_utf8(out.stdout).unwrap();
    let mut names = BTreeSet::new();
    let mut in_commands = false;
    for line in text.lines() {
        if line.starts_with("Commands:") {
            in_commands = true;
        } else if in_commands {
            if line.trim().is_empty() || !line.starts_with(' ') {
                break;
            }
            let name = line.split_whitespace().next().unwrap();
            if name != "help" {
                names.insert(name.to_string());
            }
        }
    }
    names
}

/// `fem2rbd WORD [WORD]` in one piece of code: the words after the binary's name (the
/// binary as a word of its own or at the end of a path, `target/release/fem2rbd`), each
/// split at `|` (`export gltf|vtk`). Options, placeholders (`<cmd>`, `CMD`), a bare
/// name and shell comments (`# fem2rbd vs OpenSees`) are not subcommands.
fn invocations(code: &str) -> Vec<Vec<Vec<String>>> {
    // A shell comment in a code block is prose.
    if code.trim_start().starts_with('#') {
        return Vec::new();
    }
    let words: Vec<&str> = code.split_whitespace().collect();
    let mut out = Vec::new();
    for (i, w) in words.iter().enumerate() {
        if *w != "fem2rbd" && !w.ends_with("/fem2rbd") {
            continue;
        }
        let mut call = Vec::new();
        for next in words.iter().skip(i + 1).take(2) {
            let next = next.trim_end_matches(['.', ',', ';', ')', ':']);
            let plain = !next.is_empty()
                && next
                    .chars()
                    .all(|c| c.is_ascii_lowercase() || c == '-' || c == '|')
                && !next.starts_with('-');
            if !plain {
                break;
            }
            call.push(next.split('|').map(str::to_string).collect());
        }
        if !call.is_empty() {
            out.push(call);
        }
    }
    out
}

/// Work-log labels in a page: "session 7", "sessions 1–4", "session-4", "issue 12",
/// "issue #12", "#12" (an issue reference). Returns each label as written (lower case).
fn work_log_labels(text: &str) -> Vec<String> {
    let chars: Vec<char> = text.to_lowercase().chars().collect();
    // The end of the digits that follow `from` after spaces, hyphens or a `#`, if any.
    let digits_end = |from: usize| -> Option<usize> {
        let mut k = from;
        while k < chars.len() && matches!(chars[k], ' ' | '-' | '#') {
            k += 1;
        }
        let start = k;
        while k < chars.len() && chars[k].is_ascii_digit() {
            k += 1;
        }
        (k > start).then_some(k)
    };
    let word_at = |at: usize, word: &str| -> bool {
        let w: Vec<char> = word.chars().collect();
        at + w.len() <= chars.len()
            && chars[at..at + w.len()] == w[..]
            && (at == 0 || !chars[at - 1].is_alphanumeric())
    };
    let mut found = Vec::new();
    for at in 0..chars.len() {
        for word in ["sessions", "session", "issues", "issue"] {
            if word_at(at, word) {
                if let Some(end) = digits_end(at + word.chars().count()) {
                    found.push(chars[at..end].iter().collect());
                    break;
                }
            }
        }
        // "#12" after a space or an opening bracket; Markdown headings are "# …".
        if chars[at] == '#' && (at == 0 || chars[at - 1] == ' ' || chars[at - 1] == '(') {
            if let Some(end) =
                digits_end(at + 1).filter(|_| chars.get(at + 1).is_some_and(|c| c.is_ascii_digit()))
            {
                found.push(chars[at..end].iter().collect());
            }
        }
    }
    found
}

#[test]
fn docs_scanners_find_paths_commands_and_labels() {
    let page =
        "Run `fem2rbd run data/frame3/lc5.toml --out OUT` (see `src/ruin/rest.rs::tests`).\n\
                ```\n\
                python3 scripts/handoff-continuity.py --out D\n\
                ./target/release/fem2rbd export gltf|vtk RUN\n\
                # fem2rbd vs OpenSees\n\
                ```\n\
                Links: [rescue](rescue.md#voids), [web](https://example.org), `docs/<name>.md`.\n\
                Measured in session 7 for issue 12 (#35); ACI §22.9 stays.\n";
    let spans = code_spans(page);
    let paths: Vec<String> = spans.iter().flat_map(|(_, c)| quoted_paths(c)).collect();
    assert_eq!(
        paths,
        [
            "data/frame3/lc5.toml",
            "src/ruin/rest.rs",
            "scripts/handoff-continuity.py"
        ]
    );
    let calls: Vec<Vec<Vec<String>>> = spans.iter().flat_map(|(_, c)| invocations(c)).collect();
    assert_eq!(
        calls,
        vec![
            vec![vec!["run".to_string()]],
            vec![
                vec!["export".to_string()],
                vec!["gltf".to_string(), "vtk".to_string()]
            ],
        ]
    );
    assert_eq!(link_targets(page), vec![(7, "rescue.md".to_string())]);
    assert_eq!(work_log_labels(page), ["session 7", "issue 12", "#35"]);
    assert!(work_log_labels("## 5. Convergence\n§3.2.6, sessions of a study").is_empty());
}

#[test]
fn docs_quote_only_paths_that_exist() {
    let root = root();
    let mut dead = Vec::new();
    let mut checked = 0;
    for page in pages(&root) {
        let text = std::fs::read_to_string(&page).unwrap();
        let rel = page.strip_prefix(&root).unwrap().display().to_string();
        for (line, code) in code_spans(&text) {
            for path in quoted_paths(&code) {
                checked += 1;
                if !root.join(&path).exists() {
                    dead.push(format!("{rel}:{line}: `{path}`"));
                }
            }
        }
        let dir = page.parent().unwrap();
        for (line, target) in link_targets(&text) {
            checked += 1;
            if !dir.join(&target).exists() {
                dead.push(format!("{rel}:{line}: link ({target})"));
            }
        }
    }
    eprintln!("{checked} quoted paths and links checked");
    assert!(
        checked > 100,
        "only {checked} paths found: is the scanner broken?"
    );
    assert!(
        dead.is_empty(),
        "paths quoted in the docs that do not exist ({}):\n{}",
        dead.len(),
        dead.join("\n")
    );
}

#[test]
fn docs_quote_only_subcommands_the_binary_has() {
    let root = root();
    let top = subcommands(&[]);
    assert!(
        top.contains("run") && top.contains("study"),
        "fem2rbd --help lists {top:?}"
    );
    let nested: BTreeMap<String, BTreeSet<String>> = top
        .iter()
        .map(|c| (c.clone(), subcommands(&[c.as_str()])))
        .collect();
    let mut wrong = Vec::new();
    let mut checked = 0;
    for page in pages(&root) {
        let text = std::fs::read_to_string(&page).unwrap();
        let rel = page.strip_prefix(&root).unwrap().display().to_string();
        for (line, code) in code_spans(&text) {
            for call in invocations(&code) {
                checked += 1;
                for name in &call[0] {
                    if !top.contains(name) {
                        wrong.push(format!("{rel}:{line}: `fem2rbd {name}`"));
                    }
                }
                let (Some(second), [first]) = (call.get(1), call[0].as_slice()) else {
                    continue;
                };
                let Some(subs) = nested.get(first).filter(|s| !s.is_empty()) else {
                    continue;
                };
                for name in second {
                    if !subs.contains(name) {
                        wrong.push(format!("{rel}:{line}: `fem2rbd {first} {name}`"));
                    }
                }
            }
        }
    }
    eprintln!("{checked} quoted commands checked");
    assert!(
        checked > 20,
        "only {checked} commands found: is the scanner broken?"
    );
    assert!(
        wrong.is_empty(),
        "commands quoted in the docs that the binary does not have (fem2rbd --help: \
         {top:?}):\n{}",
        wrong.join("\n")
    );
}

#[test]
fn docs_carry_no_work_log_labels() {
    let root = root();
    let mut found = Vec::new();
    for page in pages(&root) {
        let text = std::fs::read_to_string(&page).unwrap();
        let rel = page.strip_prefix(&root).unwrap().display().to_string();
        for (i, line) in text.lines().enumerate() {
            for label in work_log_labels(line) {
                found.push(format!("{rel}:{}: {label:?}", i + 1));
            }
        }
    }
    assert!(
        found.is_empty(),
        "work-log labels in the docs (the history belongs in CHANGELOG.md; name a \
         section by its title) ({}):\n{}",
        found.len(),
        found.join("\n")
    );
}

/// The keys the scenario parser accepts in `table` (`""` = the top level), read from its
/// error for an unknown key: serde names the fields it expected.
fn parser_keys(table: &str) -> BTreeSet<String> {
    let text = match table {
        "" => "zzz_unknown = 1\n".to_string(),
        "ground_motion" => "model = \"m.toml\"\n[[ground_motion]]\nzzz_unknown = 1\n".into(),
        t => format!("model = \"m.toml\"\n[{t}]\nzzz_unknown = 1\n"),
    };
    let err = fem2rbd::pipeline::Scenario::parse(&text, Path::new("s.toml"))
        .unwrap_err()
        .to_string();
    let expected = err
        .split_once("expected")
        .unwrap_or_else(|| panic!("[{table}]: no list of keys in {err:?}"))
        .1;
    expected
        .split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

/// The scenario keys the reference `docs/scenario-format.md` documents, by table: the
/// first cell of each row of its "Format" table (`` `[physics] friction`, `restitution` ``),
/// and for `[[ground_motion]]` and `[physics.rest]` the keys their row names.
fn documented_keys(text: &str) -> BTreeMap<String, BTreeSet<String>> {
    let mut out: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let section = text
        .split("## Format (TOML)")
        .nth(1)
        .expect("a Format section")
        .split("\n## ")
        .next()
        .unwrap();
    let is_key = |w: &str| !w.is_empty() && w.chars().all(|c| c.is_ascii_lowercase() || c == '_');
    for row in section.lines().filter(|l| l.starts_with("| `")) {
        let cells: Vec<&str> = row.split(" | ").collect();
        let spans: Vec<&str> = cells[0].split('`').skip(1).step_by(2).collect();
        let first = spans[0];
        let (table, keys): (String, Vec<String>) = if let Some(t) = first
            .strip_prefix("[[")
            .and_then(|r| r.strip_suffix("]]"))
            .or_else(|| first.strip_prefix('[').and_then(|r| r.strip_suffix(']')))
        {
            // A table whose keys are listed in the row's other cells.
            let keys = cells[1..]
                .iter()
                .flat_map(|c| c.split('`').skip(1).step_by(2))
                .filter_map(|s| s.split(' ').next())
                .filter(|w| is_key(w))
                .map(str::to_string)
                .collect();
            (t.to_string(), keys)
        } else if let Some((t, k)) = first.strip_prefix('[').and_then(|r| r.split_once("] ")) {
            let mut keys = vec![k.to_string()];
            keys.extend(spans[1..].iter().map(|s| s.to_string()));
            (t.to_string(), keys)
        } else {
            (String::new(), vec![first.to_string()])
        };
        out.entry(table).or_default().extend(keys);
    }
    out
}

/// Every scenario key in the reference is one the parser accepts, in the table the
/// reference puts it, and every key the parser accepts is in the reference (the old
/// spellings in `[physics]` of the keys that moved to `[physics.experimental]`, which
/// the parser refuses by name, excepted).
#[test]
fn scenario_reference_lists_exactly_the_keys_the_parser_accepts() {
    let text = std::fs::read_to_string(root().join("docs/scenario-format.md")).unwrap();
    let documented = documented_keys(&text);
    let tables = [
        "",
        "ground_motion",
        "fe",
        "collapse",
        "physics",
        "physics.experimental",
        "physics.rest",
    ];
    assert_eq!(
        documented
            .keys()
            .map(String::as_str)
            .collect::<BTreeSet<_>>(),
        tables.into_iter().collect::<BTreeSet<_>>(),
        "the reference's tables"
    );
    let experimental = parser_keys("physics.experimental");
    for table in tables {
        let mut accepted = parser_keys(table);
        match table {
            // Sub-tables are documented as rows of their own.
            "" => {
                for t in ["ground_motion", "fe", "collapse", "physics"] {
                    assert!(accepted.remove(t), "top level: {t}");
                }
            }
            "physics" => {
                accepted.retain(|k| !experimental.contains(k));
                assert!(accepted.remove("rest") && accepted.remove("experimental"));
            }
            _ => {}
        }
        assert_eq!(
            documented[table], accepted,
            "[{table}]: keys in docs/scenario-format.md (left) against the parser's (right)"
        );
    }
    assert!(experimental.contains("axial_rows") && experimental.len() > 20);
}
