//! `fem2rbd export opensees`: write an openseespy script of a model and its analysis.
use crate::export::{opensees_script, GroundMotionInput, OpenSeesOptions, Variant};
use crate::model::Model;
use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use std::path::PathBuf;

/// Export targets.
#[derive(Debug, Subcommand)]
pub enum ExportCommand {
    /// A self-contained openseespy script (`python3 out.py eigen|gravity|th`).
    Opensees(OpenSeesArgs),
}

/// Options of `export opensees`.
#[derive(Debug, Args)]
pub struct OpenSeesArgs {
    /// Model file (.toml or .json).
    pub model: PathBuf,
    /// Ground-motion component DIR=path,pga_g (DIR = X, Y or Z; AT2 file; PGA in g);
    /// repeat for several components.
    #[arg(long = "gm", value_name = "DIR=PATH,PGA_G")]
    pub gm: Vec<String>,
    /// Time-scale factor on the records' time step.
    #[arg(long, default_value_t = 1.0)]
    pub time_scale: f64,
    /// Analysis time step (s).
    #[arg(long, default_value_t = 0.005)]
    pub dt: f64,
    /// Analysis duration (s); default the shortest record.
    #[arg(long)]
    pub duration: Option<f64>,
    /// Element variant: force, disp or elastic (default: as the model says).
    #[arg(long)]
    pub variant: Option<String>,
    /// Stop the time history when a free node sinks below -STOP_UZ (m);
    /// default 1 m x model scale.
    #[arg(long)]
    pub stop_uz: Option<f64>,
    /// Output script.
    #[arg(short, long)]
    pub output: PathBuf,
}

/// Parses `X=path,0.3`.
pub fn parse_gm(s: &str) -> Result<GroundMotionInput> {
    let (dir, rest) = s
        .split_once('=')
        .with_context(|| format!("--gm {s:?}: expected DIR=PATH,PGA_G"))?;
    let direction = match dir.trim().to_ascii_uppercase().as_str() {
        "X" => 1,
        "Y" => 2,
        "Z" => 3,
        o => bail!("--gm {s:?}: direction {o:?} must be X, Y or Z"),
    };
    let (path, pga) = rest
        .rsplit_once(',')
        .with_context(|| format!("--gm {s:?}: expected DIR=PATH,PGA_G"))?;
    let pga_g: f64 = pga
        .trim()
        .parse()
        .with_context(|| format!("--gm {s:?}: PGA {pga:?} is not a number"))?;
    Ok(GroundMotionInput {
        direction,
        path: PathBuf::from(path),
        pga_g,
    })
}

/// Runs `export`.
pub fn run(cmd: &ExportCommand) -> Result<()> {
    match cmd {
        ExportCommand::Opensees(a) => {
            let model = Model::load(&a.model)?;
            let variant = match a.variant.as_deref() {
                None => None,
                Some("force") => Some(Variant::Force),
                Some("disp") => Some(Variant::Disp),
                Some("elastic") => Some(Variant::Elastic),
                Some(o) => bail!("--variant {o:?}: use force, disp or elastic"),
            };
            let opts = OpenSeesOptions {
                ground_motions: a.gm.iter().map(|g| parse_gm(g)).collect::<Result<_>>()?,
                time_scale: a.time_scale,
                dt: a.dt,
                duration: a.duration,
                variant,
                stop_uz: a.stop_uz,
            };
            let text = opensees_script(&model, &a.model.display().to_string(), &opts)?;
            crate::output::write_atomic(&a.output, text.as_bytes())
                .with_context(|| format!("cannot write {}", a.output.display()))
        }
    }
}
