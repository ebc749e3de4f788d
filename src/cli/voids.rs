//! `fem2rbd voids RUN_DIR [--cell M] [--rescuer M] [--camera M] [--timing]`: the rescue
//! analysis of a run folder's ruin (`src/rescue/`, docs/rescue.md): writes `voids.csv`,
//! `voids.json` and `rubble_height.csv` into the folder, sets `summary.json`'s
//! `rescue` section to the same analysis and rebuilds `collapse.glb` (when the folder has
//! one) with the survivable voids as nodes, each file atomically, after everything
//! succeeded; prints the files written (nothing with `--quiet`).
use anyhow::{Context, Result};
use clap::Args;
use fem2rbd::rescue::person::{DEFAULT_CAMERA_M, DEFAULT_CELL_M, DEFAULT_RESCUER_M};
use fem2rbd::rescue::report::with_summary_section;
use fem2rbd::rescue::{analyse, Ruin, Sizes};
use std::path::PathBuf;

/// Options of `voids`. Sizes are full-scale metres; the analysis multiplies them by the
/// model's scale (`summary.json` `scale`).
#[derive(Debug, Args)]
pub struct VoidsArgs {
    /// Run folder written by `fem2rbd run` (bodies.csv, ruins.csv, connections.csv,
    /// summary.json).
    pub run_dir: PathBuf,
    /// Grid cell edge, m at full scale.
    #[arg(long, default_value_t = DEFAULT_CELL_M)]
    pub cell: f64,
    /// Width of the passage a crawling rescuer needs, m at full scale.
    #[arg(long, default_value_t = DEFAULT_RESCUER_M)]
    pub rescuer: f64,
    /// Diameter of the search camera's head, m at full scale.
    #[arg(long, default_value_t = DEFAULT_CAMERA_M)]
    pub camera: f64,
    /// Print the analysis' wall time (reading excluded).
    #[arg(long)]
    pub timing: bool,
}

/// Runs `voids`.
pub fn run(args: &VoidsArgs, quiet: bool) -> Result<()> {
    let sizes = Sizes {
        cell_m: args.cell,
        rescuer_m: args.rescuer,
        camera_m: args.camera,
    };
    // Sizes first (before reading), then the folder.
    sizes.scaled(1.0)?;
    let ruin = Ruin::load(&args.run_dir)?;
    let t0 = std::time::Instant::now();
    let analysis = analyse(&ruin, sizes)?;
    let mut files: Vec<(&str, Vec<u8>)> = analysis.files();
    let elapsed = t0.elapsed().as_secs_f64();
    // summary.json's `rescue` section follows the new analysis, so that it never
    // disagrees with voids.json.
    let summary_path = args.run_dir.join("summary.json");
    let summary = fem2rbd::model::limits::read_regular_file(&summary_path)
        .with_context(|| format!("{}: cannot read", summary_path.display()))?;
    let summary = with_summary_section(&summary, analysis.summary())
        .with_context(|| format!("{}: not a JSON object", summary_path.display()))?;
    files.push(("summary.json", summary.into_bytes()));
    // collapse.glb holds the survivable voids: rebuilt with the new voids.json.
    if args.run_dir.join("collapse.glb").is_file() {
        let voids = files
            .iter()
            .find(|f| f.0 == "voids.json")
            .map(|f| std::str::from_utf8(&f.1).expect("voids.json is UTF-8"));
        let glb = super::export::run_folder_glb_with(&args.run_dir, voids)?;
        files.push(("collapse.glb", glb));
    }
    for (name, bytes) in &files {
        fem2rbd::output::write_atomic(args.run_dir.join(name), bytes)?;
    }
    if args.timing {
        let cells = analysis.field.as_ref().map_or(0, |f| f.grid.len());
        println!(
            "rescue analysis: {} bodies, {cells} cells, {} voids in {elapsed:.3} s",
            ruin.boxes.len(),
            analysis.voids.len()
        );
    }
    if !quiet {
        for (name, _) in &files {
            println!("{}", args.run_dir.join(name).display());
        }
    }
    Ok(())
}
