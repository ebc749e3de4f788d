//! `fem2rbd plot OUT_DIR [--out DIR] [--format png|svg|both]`: the figures of a run folder
//! (`src/plot/`; for an ensemble folder the debris-density map), written atomically into `OUT_DIR/plots` by default; the files written
//! are listed on stdout (nothing with `--quiet`).
use crate::plot::{self, Format, RunFolder};
use anyhow::Result;
use clap::Args;
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
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| args.run_dir.join("plots"));
    // An ensemble folder (`fem2rbd run --ensemble N`): the debris-density map.
    let files = if args.run_dir.join("ensemble.json").is_file() {
        plot::write_ensemble(&args.run_dir, &out, args.format)?
    } else {
        plot::write_all(&RunFolder::load(&args.run_dir)?, &out, args.format)?
    };
    if !quiet {
        for f in files {
            println!("{}", f.display());
        }
    }
    Ok(())
}
