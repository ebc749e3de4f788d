//! `fem2rbd import`: `opensees-json` turns the model OpenSees writes with `print -JSON`
//! (openseespy `printModel('-JSON', '-file', f)`) into a model file.
use anyhow::{Context, Result};
use clap::{Args, Subcommand};
use fem2rbd::model::{import_notes, import_opensees_json, Supports};
use fem2rbd::output::location::{check_not_an_input, check_output_file};
use std::path::PathBuf;

/// Import sources.
#[derive(Debug, Subcommand)]
pub enum ImportCommand {
    /// The model of OpenSees' `print -JSON` (nodes and masses, materials, sections,
    /// transformations, elements; docs/model-format.md). The print has no supports:
    /// --fix-lowest fixes the nodes at the lowest z, or add `[[support]]` entries to the
    /// model file written.
    OpenseesJson(OpenSeesJsonArgs),
}

/// Options of `import opensees-json`.
#[derive(Debug, Args)]
pub struct OpenSeesJsonArgs {
    /// The JSON file OpenSees wrote.
    pub file: PathBuf,
    /// Fix all six DOFs of every node at the lowest z of the model.
    #[arg(long)]
    pub fix_lowest: bool,
    /// Output model file (.toml, or .json for the model format's JSON).
    #[arg(short, long)]
    pub output: PathBuf,
}

/// Runs `import`.
pub fn run(cmd: &ImportCommand, quiet: bool, allow_unusual: bool) -> Result<()> {
    match cmd {
        ImportCommand::OpenseesJson(a) => {
            check_output_file(&a.output, "--output")?;
            check_not_an_input(&a.output, &[a.file.as_path()], "--output")?;
            let supports = if a.fix_lowest {
                Supports::FixLowest
            } else {
                Supports::None
            };
            let model = import_opensees_json(&a.file, supports)?;
            super::plausible(&model, &a.file, allow_unusual)?;
            let is_json = a
                .output
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("json"));
            let text = if is_json {
                serde_json::to_string_pretty(&model)? + "\n"
            } else {
                model.to_toml()?
            };
            fem2rbd::output::write_atomic(&a.output, text.as_bytes())
                .with_context(|| format!("cannot write {}", a.output.display()))?;
            if !quiet {
                for note in import_notes(&model, supports) {
                    eprintln!("import: {note}");
                }
            }
            Ok(())
        }
    }
}
