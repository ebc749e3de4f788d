//! `fem2rbd report RUN_DIR [-o report.html]`: the self-contained HTML report of a run
//! folder ([`fem2rbd::report`]): the collapse and the ruin in 3-D over the whole timeline,
//! the key figures of `summary.json` and the run's figures; of an ensemble folder, the
//! members' ruins overlaid, the debris-density and rescue maps; of a collected study
//! folder, the fragilities, IDA and fragility figures and per intensity the debris-density
//! and rescue maps. Written atomically, by default
//! to `RUN_DIR/report.html`; the file written is printed on stdout (nothing with
//! `--quiet`).
use anyhow::Result;
use clap::Args;
use fem2rbd::output::location::check_output_file;
use std::path::{Path, PathBuf};

/// Options of `report`.
#[derive(Debug, Args)]
pub struct ReportArgs {
    /// Run folder written by `fem2rbd run` (bodies.csv, keyframes.csv, history.csv,
    /// ruins.csv, summary.json; connections.csv and plots/*.svg when present), or an
    /// ensemble folder (`fem2rbd run --ensemble N`: ensemble.json and member-NNN/), or a
    /// study folder collected by `fem2rbd study collect` (results/study.json).
    pub run_dir: PathBuf,
    /// Output file. Default: RUN_DIR/report.html.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

/// Writes the report of `run_dir` to `out` (checked first); returns its size in bytes.
pub fn write(run_dir: &Path, out: &Path) -> Result<usize> {
    check_output_file(out, "--output")?;
    Ok(fem2rbd::report::write_report(run_dir, out)?)
}

/// Runs `report`.
pub fn run(args: &ReportArgs, quiet: bool) -> Result<()> {
    let out = args
        .output
        .clone()
        .unwrap_or_else(|| args.run_dir.join("report.html"));
    write(&args.run_dir, &out)?;
    if !quiet {
        println!("{}", out.display());
    }
    Ok(())
}
