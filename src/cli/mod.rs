//! Command-line interface (clap). Each subcommand lives in its own file and only calls
//! into the library; only subcommands that work are listed.
use clap::{Parser, Subcommand};

pub mod export;
pub mod fe;
pub mod generate;
pub mod import;
pub mod interrupt;
pub mod map;
pub mod modal;
pub mod plot;
pub mod pushover;
pub mod report;
pub mod run;
pub mod scene;
pub mod study;
pub mod voids;

/// `fem2rbd --version`: the crate version and the Bullet library linked.
fn long_version() -> &'static str {
    static TEXT: std::sync::LazyLock<String> = std::sync::LazyLock::new(|| {
        format!(
            "{} (Bullet {}, double precision, Debian libbullet)",
            env!("CARGO_PKG_VERSION"),
            fem2rbd::bullet::LINKED_BULLET_PKG_VERSION
        )
    });
    &TEXT
}

/// Hybrid FE + rigid-body simulation of RC building collapse and ruin scenarios.
#[derive(Debug, Parser)]
#[command(name = "fem2rbd", version, long_version = long_version(), about, long_about = None)]
pub struct Cli {
    /// Print nothing but errors (no progress bars).
    #[arg(long, global = true)]
    pub quiet: bool,
    /// Accept a model or scene whose values lie outside their plausible ranges (a 3 000 m
    /// column, E = 30 Pa, 500 % damping, restitution 2, bodies that start inside each
    /// other: docs/reliability.md); a run's summary.json lists them.
    #[arg(long, global = true)]
    pub allow_unusual: bool,
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a JSON rigid-body scene in Bullet and write body poses as CSV.
    Scene(scene::SceneArgs),
    /// Write a building model file (e.g. a regular RC frame).
    #[command(subcommand)]
    Generate(generate::GenerateCommand),
    /// Export a model (openseespy script) or a run folder (animated glTF, ParaView VTK).
    #[command(subcommand)]
    Export(export::ExportCommand),
    /// Import a model from another program (OpenSees' `print -JSON`).
    #[command(subcommand)]
    Import(import::ImportCommand),
    /// Map a model's elements to rigid boxes and write the rigid-body table (CSV).
    Map(map::MapArgs),
    /// Eigen periods, effective masses and mode characters of a model.
    Modal(modal::ModalArgs),
    /// Nonlinear FE time history of a model under a ground motion.
    Fe(fe::FeArgs),
    /// Static pushover or cyclic displacement protocol of a model after gravity: the
    /// capacity curve and the reactions.
    Pushover(pushover::PushoverArgs),
    /// Run a scenario: FE until collapse, then the Bullet ruin stage (or one of them).
    Run(run::RunArgs),
    /// Figures of a run folder: ruin plan and elevations, drift/drop and connection histories.
    Plot(plot::PlotArgs),
    /// A self-contained HTML report of a run folder: the collapse in 3-D, the ruin, the key figures.
    Report(report::ReportArgs),
    /// Batch studies: plan, run locally or on Slurm, collect (IDA, fragility, libraries).
    #[command(subcommand)]
    Study(study::StudyCommand),
    /// Rescue analysis of a run folder: voids, access routes, rubble height map.
    Voids(voids::VoidsArgs),
}

/// Refuses a model with values outside their plausible ranges
/// ([`fem2rbd::model::plausibility`]) before any work, listing each with its range and
/// the unit slip it looks like; with `allow` (`--allow-unusual`) it accepts them and
/// returns them (a run records them in its summary).
pub fn plausible(
    model: &fem2rbd::model::Model,
    file: &std::path::Path,
    allow: bool,
) -> anyhow::Result<Vec<String>> {
    let found: Vec<String> = fem2rbd::model::plausibility::unusual(model)
        .iter()
        .map(ToString::to_string)
        .collect();
    if found.is_empty() || allow {
        return Ok(found);
    }
    let shown: Vec<String> = found.iter().take(10).map(|u| format!("  {u}")).collect();
    let more = match found.len() {
        n if n > 10 => format!("\n  … and {} more", n - 10),
        _ => String::new(),
    };
    anyhow::bail!(
        "{}: {} value(s) outside their plausible ranges (docs/reliability.md):\n{}{more}\n\
         If they are meant, run again with --allow-unusual (a run's summary.json records them).",
        file.display(),
        found.len(),
        shown.join("\n")
    )
}

/// Parses the process arguments and runs the chosen subcommand.
pub fn main() -> anyhow::Result<()> {
    let cli = Cli::parse();
    interrupt::install();
    run(cli)
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Scene(args) => scene::run(args, cli.quiet, cli.allow_unusual),
        Command::Generate(cmd) => generate::run(&cmd),
        Command::Export(cmd) => export::run(&cmd, cli.allow_unusual),
        Command::Import(cmd) => import::run(&cmd, cli.quiet, cli.allow_unusual),
        Command::Map(args) => map::run(&args, cli.quiet, cli.allow_unusual),
        Command::Modal(args) => modal::run(&args, cli.allow_unusual),
        Command::Fe(args) => fe::run(&args, cli.quiet, cli.allow_unusual),
        Command::Pushover(args) => pushover::run(&args, cli.quiet, cli.allow_unusual),
        Command::Run(args) => run::run(&args, cli.quiet, cli.allow_unusual),
        Command::Plot(args) => plot::run(&args, cli.quiet),
        Command::Report(args) => report::run(&args, cli.quiet),
        Command::Study(cmd) => study::run(&cmd, cli.quiet, cli.allow_unusual),
        Command::Voids(args) => voids::run(&args, cli.quiet),
    }
}
