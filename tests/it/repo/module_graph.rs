//! The modules of the `fem2rbd` crate import each other in one direction
//! (ARCHITECTURE.md, "Dependencies between the modules"): the graph of `crate::X` paths
//! between the top-level modules of `src/lib.rs` has no cycle, `body` and `mode` import
//! none of them, and `output` imports neither `pipeline` nor `measure` (a run folder's
//! writers do not depend on the run that produced it). Doc comments do not count.
use crate::support::{root, rust_files};
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The top-level modules declared in `src/lib.rs` (`pub mod x;`).
fn modules(root: &Path) -> Vec<String> {
    let lib = std::fs::read_to_string(root.join("src/lib.rs")).unwrap();
    lib.lines()
        .filter_map(|l| l.trim().strip_prefix("pub mod "))
        .filter_map(|rest| rest.strip_suffix(';'))
        .map(str::to_string)
        .collect()
}

/// Module → (imported module → the first `file:line` that imports it).
type Graph = BTreeMap<String, BTreeMap<String, String>>;

fn graph(root: &Path) -> Graph {
    let mods = modules(root);
    let known: BTreeSet<&str> = mods.iter().map(String::as_str).collect();
    let mut g = Graph::new();
    for m in &mods {
        let mut files = Vec::new();
        let file = root.join("src").join(format!("{m}.rs"));
        if file.is_file() {
            files.push(file);
        }
        let dir = root.join("src").join(m);
        if dir.is_dir() {
            rust_files(&dir, &mut files);
        }
        assert!(!files.is_empty(), "module {m}: no src/{m}.rs or src/{m}/");
        let edges = g.entry(m.clone()).or_default();
        for f in files {
            let rel = f.strip_prefix(root).unwrap().to_string_lossy().to_string();
            let text = std::fs::read_to_string(&f).unwrap();
            for (i, line) in text.lines().enumerate() {
                let code = line.trim_start();
                if code.starts_with("//") {
                    continue;
                }
                let code = code.split(" //").next().unwrap();
                for (at, _) in code.match_indices("crate::") {
                    let name: String = code[at + "crate::".len()..]
                        .chars()
                        .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                        .collect();
                    if name != *m && known.contains(name.as_str()) {
                        edges
                            .entry(name)
                            .or_insert_with(|| format!("{rel}:{}", i + 1));
                    }
                }
            }
        }
    }
    g
}

/// A cycle of `g` as `a → b → … → a` with the line behind each arrow, if there is one.
fn cycle(g: &Graph) -> Option<Vec<String>> {
    // Depth-first search with colours: 0 new, 1 on the stack, 2 done.
    fn visit(
        g: &Graph,
        m: &str,
        colour: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        colour.insert(m.to_string(), 1);
        stack.push(m.to_string());
        for next in g[m].keys() {
            match colour.get(next).copied().unwrap_or(0) {
                1 => {
                    let start = stack.iter().position(|s| s == next).unwrap();
                    let mut path: Vec<String> = stack[start..].to_vec();
                    path.push(next.clone());
                    return Some(
                        path.windows(2)
                            .map(|w| format!("{} → {} ({})", w[0], w[1], g[&w[0]][&w[1]]))
                            .collect(),
                    );
                }
                0 => {
                    if let Some(c) = visit(g, next, colour, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        colour.insert(m.to_string(), 2);
        None
    }
    let mut colour = BTreeMap::new();
    for m in g.keys() {
        if colour.get(m).copied().unwrap_or(0) == 0 {
            if let Some(c) = visit(g, m, &mut colour, &mut Vec::new()) {
                return Some(c);
            }
        }
    }
    None
}

#[test]
fn the_modules_import_each_other_without_a_cycle() {
    let g = graph(&root());
    assert!(g.len() >= 14, "only {} modules: is lib.rs read?", g.len());
    let edges: usize = g.values().map(BTreeMap::len).sum();
    assert!(
        edges >= 20,
        "only {edges} imports between modules: is the scan broken?"
    );
    if let Some(c) = cycle(&g) {
        panic!(
            "the modules import each other in a cycle:\n{}",
            c.join("\n")
        );
    }
    for leaf in ["body", "mode"] {
        assert!(g[leaf].is_empty(), "{leaf} imports {:?}", g[leaf]);
    }
    for banned in ["pipeline", "measure"] {
        assert!(
            !g["output"].contains_key(banned),
            "output imports {banned} ({})",
            g["output"][banned]
        );
    }
}

/// The scan finds a cycle when there is one: a hand-made graph a → b → c → a.
#[test]
fn the_cycle_search_names_a_cycle_and_its_lines() {
    let mut g = Graph::new();
    for (a, b) in [("a", "b"), ("b", "c"), ("c", "a"), ("d", "a")] {
        g.entry(a.to_string())
            .or_default()
            .insert(b.to_string(), format!("src/{a}.rs:1"));
    }
    let c = cycle(&g).expect("a cycle");
    assert_eq!(c.len(), 3, "{c:?}");
    assert!(c[0].starts_with("a → b (src/a.rs:1)"), "{c:?}");
    g.get_mut("c").unwrap().clear();
    assert_eq!(cycle(&g), None);
}
