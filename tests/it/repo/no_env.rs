//! Environment variables are read only at the binary's edge: no `.rs` file under `src/`
//! or `crates/` reads one (`std::env::var`, `var_os`, `vars`) except the binary's entry
//! (`src/main.rs`, `src/cli/`) and build scripts (`build.rs`, which Cargo talks to through
//! the environment). Threads, traces and the solver's sweep reach the library as values.
use crate::support::{root, rust_files};

#[test]
fn library_code_reads_no_environment_variable() {
    let root = root();
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    rust_files(&root.join("crates"), &mut files);
    let mut reads = Vec::new();
    let mut checked = 0;
    for f in &files {
        let rel = f
            .strip_prefix(&root)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        if rel == "src/main.rs" || rel.starts_with("src/cli/") || rel.ends_with("/build.rs") {
            continue;
        }
        checked += 1;
        let text = std::fs::read_to_string(f).unwrap();
        for (i, line) in text.lines().enumerate() {
            if line.contains("env::var") {
                reads.push(format!("{rel}:{}: {}", i + 1, line.trim()));
            }
        }
    }
    assert!(checked > 100, "only {checked} files: is the walk broken?");
    assert!(
        reads.is_empty(),
        "environment variables read outside the binary's edge:\n{}",
        reads.join("\n")
    );
}
