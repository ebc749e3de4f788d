//! `fem2rbd plot OUT_DIR [--out DIR] [--format png|svg|both]`: the figures of a run folder
//! (`src/plot/`), of an ensemble folder (the debris-density map, `src/plot/density.rs`), or
//! of a collected study folder (`src/study/plot.rs`: IDA curves and collapse fragility),
//! written atomically into `OUT_DIR/plots` by default; the files written are listed on
//! stdout (nothing with `--quiet`).
use anyhow::Result;
use clap::Args;
use fem2rbd::plot::{self, ImageFormat, RunFolder};
use std::path::PathBuf;

/// Options of `plot`.
#[derive(Debug, Args)]
pub struct PlotArgs {
    /// Run folder written by `fem2rbd run` (bodies.csv, history.csv, keyframes.csv,
    /// ruins.csv, summary.json), or a study folder collected by `fem2rbd study collect`.
    pub run_dir: PathBuf,
    /// Folder for the figures (created). Default: RUN_DIR/plots.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Image format(s).
    #[arg(long, value_enum, default_value_t = ImageFormat::Both)]
    pub format: ImageFormat,
}

/// Runs `plot`.
pub fn run(args: &PlotArgs, quiet: bool) -> Result<()> {
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| args.run_dir.join("plots"));
    let files = if fem2rbd::study::plot::is_study_folder(&args.run_dir) {
        fem2rbd::study::plot::write_all(&args.run_dir, &out, args.format)?
    } else if args.run_dir.join("ensemble.json").is_file() {
        // An ensemble folder (`fem2rbd run --ensemble N`): the debris-density map.
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
