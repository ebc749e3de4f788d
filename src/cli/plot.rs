//! `fem2rbd plot OUT_DIR [--out DIR] [--format png|svg|both]`: the figures of a run folder
//! (`src/plot/`), written atomically into `OUT_DIR/plots` by default; the files written
//! are listed on stdout (nothing with `--quiet`).
use anyhow::Result;
use clap::Args;
use fem2rbd::plot::{self, Format, RunFolder};
use std::path::PathBuf;

/// Options of `plot`.
#[derive(Debug, Args)]
pub struct PlotArgs {
    /// Run folder written by `fem2rbd run` (bodies.csv, history.csv, keyframes.csv,
    /// ruins.csv, summary.json).
    pub run_dir: PathBuf,
    /// Folder for the figures (created). Default: RUN_DIR/plots.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Image format(s).
    #[arg(long, value_enum, default_value_t = Format::Both)]
    pub format: Format,
}

/// Runs `plot`.
pub fn run(args: &PlotArgs, quiet: bool) -> Result<()> {
    let run = RunFolder::load(&args.run_dir)?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| args.run_dir.join("plots"));
    let files = plot::write_all(&run, &out, args.format)?;
    if !quiet {
        for f in files {
            println!("{}", f.display());
        }
    }
    Ok(())
}
