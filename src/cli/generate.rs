//! `fem2rbd generate frame`: write a regular RC frame model (defaults = frame3);
//! `fem2rbd generate building`: the frame plus shear walls of layered shells.
use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use fem2rbd::model::building::{building, BuildingParams, WallSpec};
use fem2rbd::model::generate::{frame, FrameParams};
use fem2rbd::model::{Formulation, TransfKind};
use std::path::PathBuf;

/// What to generate.
#[derive(Debug, Subcommand)]
pub enum GenerateCommand {
    /// A regular RC frame: bays in X and Y, stories, fiber columns and beams, slab as mass
    /// plus diagonal elastic strips. The defaults reproduce the reference frame3.
    Frame(Box<FrameArgs>),
    /// A frame–shear-wall building: the frame's options plus walls placed by column line,
    /// bay and story, meshed into layered shells (docs/model-format.md, docs/case2.md).
    Building(Box<BuildingArgs>),
}

/// Options of `generate building`: every `generate frame` option plus the walls.
#[derive(Debug, Args)]
pub struct BuildingArgs {
    /// The frame.
    #[command(flatten)]
    pub frame: FrameArgs,
    /// A wall segment LINE:BAY:STORIES[:open=A0-A1/U0-U1], repeatable: x0:2:1-7 = along
    /// X on column line 0 (y index), bay 2 (1-based), stories 1 to 7; y3:1:2 = along Y on
    /// column line 3, bay 1, story 2; open= leaves mesh cells A0..A1 along, U0..U1 up out.
    #[arg(long = "wall")]
    pub walls: Vec<String>,
    /// Wall thickness (m), one value or one per story.
    #[arg(long, default_value = "0.2")]
    pub wall_thickness: String,
    /// Vertical reinforcement ratio of the walls (both faces).
    #[arg(long, default_value_t = 0.0025)]
    pub wall_rho_vertical: f64,
    /// Horizontal reinforcement ratio of the walls (both faces).
    #[arg(long, default_value_t = 0.0025)]
    pub wall_rho_horizontal: f64,
    /// Cover concrete layer per wall face (m).
    #[arg(long, default_value_t = 0.02)]
    pub wall_cover: f64,
    /// Core concrete layers of the wall section.
    #[arg(long, default_value_t = 4)]
    pub wall_core_layers: u32,
    /// Wall mesh per bay and story, ALONGxUP (multiples of 2·beam_elements and
    /// column_elements); default the frame's nodes.
    #[arg(long)]
    pub wall_mesh: Option<String>,
    /// Leave the beams over and under walls out (the wall carries the floor).
    #[arg(long)]
    pub no_beams_over_walls: bool,
}

impl BuildingArgs {
    /// Converts the options to generator parameters.
    pub fn params(&self) -> Result<BuildingParams> {
        Ok(BuildingParams {
            frame: self.frame.params()?,
            walls: self
                .walls
                .iter()
                .map(|w| WallSpec::parse(w).context("--wall"))
                .collect::<Result<_>>()?,
            wall_thickness: list(&self.wall_thickness).context("--wall-thickness")?,
            wall_rho_vertical: self.wall_rho_vertical,
            wall_rho_horizontal: self.wall_rho_horizontal,
            wall_cover: self.wall_cover,
            wall_core_layers: self.wall_core_layers,
            wall_mesh: self
                .wall_mesh
                .as_deref()
                .map(pair)
                .transpose()
                .context("--wall-mesh")?,
            beams_over_walls: !self.no_beams_over_walls,
        })
    }
}

/// frame3's concrete E per story (Pa), the default of `--ec`.
const DEFAULT_EC: &str = "25e9,27e9,23e9";
/// frame3's concrete f'c per story (Pa), the default of `--fc`.
const DEFAULT_FC: &str = "22.5e6,23.9e6,15.6e6";
/// frame3's added mass per floor (kg), the default of `--added-mass`.
const DEFAULT_ADDED_MASS: &str = "2699.75";

fn list(s: &str) -> Result<Vec<f64>> {
    s.split(',')
        .map(|x| {
            x.trim()
                .parse::<f64>()
                .with_context(|| format!("{x:?} is not a number"))
        })
        .collect()
}

fn pair<T: std::str::FromStr>(s: &str) -> Result<[T; 2]> {
    let v: Vec<&str> = s.split('x').collect();
    if v.len() != 2 {
        bail!("{s:?}: expected AxB");
    }
    let p = |x: &str| {
        x.trim()
            .parse::<T>()
            .ok()
            .with_context(|| format!("{x:?} is not a number"))
    };
    Ok([p(v[0])?, p(v[1])?])
}

/// `N` (top and bottom) or `TOP,BOTTOM` bar counts.
fn beam_bars(s: &str) -> Result<[u32; 2]> {
    let v: Vec<u32> = s
        .split(',')
        .map(|x| {
            x.trim()
                .parse::<u32>()
                .with_context(|| format!("{x:?} is not a bar count"))
        })
        .collect::<Result<_>>()?;
    match v[..] {
        [n] => Ok([n, n]),
        [t, b] => Ok([t, b]),
        _ => bail!("{s:?}: give N or TOP,BOTTOM"),
    }
}

/// Options of `generate frame` (SI units; lists are comma-separated).
#[derive(Debug, Args)]
pub struct FrameArgs {
    /// Output model file (.toml, or .json).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Model name.
    #[arg(long, default_value = "frame3-quarter-scale-stand-in")]
    pub name: String,
    /// Bay spans in X (m), e.g. 1.5,1.5.
    #[arg(long, default_value = "1.5")]
    pub spans_x: String,
    /// Bay spans in Y (m).
    #[arg(long, default_value = "1.5")]
    pub spans_y: String,
    /// Story heights bottom up (m).
    #[arg(long, default_value = "1.0,1.0,1.0")]
    pub stories: String,
    /// Column section b x h (m).
    #[arg(long, default_value = "0.1x0.1")]
    pub column: String,
    /// Beam section b x h (m).
    #[arg(long, default_value = "0.075x0.15")]
    pub beam: String,
    /// Slab thickness (m).
    #[arg(long, default_value_t = 0.03)]
    pub slab_thickness: f64,
    /// Face to core boundary (m).
    #[arg(long, default_value_t = 0.012)]
    pub cover: f64,
    /// Face to bar centre (m).
    #[arg(long, default_value_t = 0.013)]
    pub bar_offset: f64,
    /// Longitudinal bar diameter of columns and beams (m).
    #[arg(long, default_value_t = 0.0035)]
    pub bar_diameter: f64,
    /// Column bar diameter (m); default --bar-diameter.
    #[arg(long)]
    pub column_bar_diameter: Option<f64>,
    /// Beam bar diameter (m); default --bar-diameter.
    #[arg(long)]
    pub beam_bar_diameter: Option<f64>,
    /// Column bars per face.
    #[arg(long, default_value_t = 3)]
    pub column_bars_per_face: u32,
    /// Beam bars per layer: one count for top and bottom, or TOP,BOTTOM.
    #[arg(long, default_value = "3")]
    pub beam_bars: String,
    /// Concrete E per story (Pa), one value or one per story.
    #[arg(long, default_value = DEFAULT_EC)]
    pub ec: String,
    /// Concrete f'c per story (Pa, positive), one value or one per story.
    #[arg(long, default_value = DEFAULT_FC)]
    pub fc: String,
    /// Core confinement factor.
    #[arg(long, default_value_t = 1.1)]
    pub confinement: f64,
    /// Cover concrete strain at the residual stress (negative).
    #[arg(long, default_value_t = -0.004, allow_negative_numbers = true)]
    pub cover_epscu: f64,
    /// Core concrete strain at the residual stress (negative).
    #[arg(long, default_value_t = -0.012, allow_negative_numbers = true)]
    pub core_epscu: f64,
    /// Concrete residual stress as a share of the peak (0..1).
    #[arg(long, default_value_t = 0.2, allow_negative_numbers = true)]
    pub residual: f64,
    /// Bar yield strength (Pa).
    #[arg(long, default_value_t = 457.7e6)]
    pub fy: f64,
    /// Bar Young's modulus (Pa).
    #[arg(long, default_value_t = 200e9)]
    pub es: f64,
    /// Concrete density (kg/m3).
    #[arg(long, default_value_t = 2500.0)]
    pub concrete_density: f64,
    /// Bar density (kg/m3); 0 leaves bar mass out, as frame3.
    #[arg(long, default_value_t = 0.0)]
    pub steel_density: f64,
    /// Added mass per floor (kg), one value or one per floor.
    #[arg(long, default_value = DEFAULT_ADDED_MASS)]
    pub added_mass: String,
    /// Share of the added mass put on the bay-centre nodes (0..1); the rest is spread
    /// like the slab.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub ballast_centre: f64,
    /// Elements per column per story.
    #[arg(long, default_value_t = 2)]
    pub column_elements: u32,
    /// Elements per half beam span.
    #[arg(long, default_value_t = 1)]
    pub beam_elements: u32,
    /// Column core fibers ny x nz.
    #[arg(long, default_value = "8x8")]
    pub column_fibers: String,
    /// Beam core fibers ny x nz.
    #[arg(long, default_value = "4x10")]
    pub beam_fibers: String,
    /// Geometric transformation: linear, pdelta or corotational.
    #[arg(long, default_value = "corotational")]
    pub transformation: String,
    /// Beam-column formulation: force or disp.
    #[arg(long, default_value = "force")]
    pub formulation: String,
    /// Integration points per beam-column.
    #[arg(long, default_value_t = 5)]
    pub points: u32,
    /// Model scale (collapse threshold scale).
    #[arg(long, default_value_t = 0.25)]
    pub scale: f64,
    /// Rayleigh damping ratio.
    #[arg(long, default_value_t = 0.05)]
    pub xi: f64,
    /// First Rayleigh anchor period (s); the second is T1/3.
    #[arg(long, default_value_t = 0.316)]
    pub t1: f64,
}

impl FrameArgs {
    /// Converts the options to generator parameters.
    pub fn params(&self) -> Result<FrameParams> {
        let story_heights = list(&self.stories).context("--stories")?;
        let per_story = |option: &str, text: &str, default: &str| -> Result<Vec<f64>> {
            let v = list(text).with_context(|| option.to_string())?;
            let n = story_heights.len();
            if v.len() != 1 && v.len() != n {
                let given = if text == default {
                    format!("its default {default} has")
                } else {
                    "it has".to_string()
                };
                bail!(
                    "{option}: {given} {} values for {n} stories (--stories): give one \
                     value for every story, or one per story",
                    v.len()
                );
            }
            Ok(v)
        };
        Ok(FrameParams {
            name: self.name.clone(),
            spans_x: list(&self.spans_x).context("--spans-x")?,
            spans_y: list(&self.spans_y).context("--spans-y")?,
            story_heights: story_heights.clone(),
            column: pair(&self.column).context("--column")?,
            beam: pair(&self.beam).context("--beam")?,
            slab_thickness: self.slab_thickness,
            cover: self.cover,
            bar_offset: self.bar_offset,
            column_bar_diameter: self.column_bar_diameter.unwrap_or(self.bar_diameter),
            beam_bar_diameter: self.beam_bar_diameter.unwrap_or(self.bar_diameter),
            column_bars_per_face: self.column_bars_per_face,
            beam_bars: beam_bars(&self.beam_bars).context("--beam-bars")?,
            ec: per_story("--ec", &self.ec, DEFAULT_EC)?,
            fc: per_story("--fc", &self.fc, DEFAULT_FC)?,
            confinement: self.confinement,
            cover_epscu: self.cover_epscu,
            core_epscu: self.core_epscu,
            residual: self.residual,
            nu: 0.2,
            fy: self.fy,
            es: self.es,
            concrete_density: self.concrete_density,
            steel_density: self.steel_density,
            added_mass: per_story("--added-mass", &self.added_mass, DEFAULT_ADDED_MASS)?,
            ballast_centre: self.ballast_centre,
            column_elements: self.column_elements,
            beam_elements: self.beam_elements,
            column_fibers: pair(&self.column_fibers).context("--column-fibers")?,
            beam_fibers: pair(&self.beam_fibers).context("--beam-fibers")?,
            transformation: match self.transformation.as_str() {
                "linear" => TransfKind::Linear,
                "pdelta" => TransfKind::Pdelta,
                "corotational" => TransfKind::Corotational,
                o => bail!("--transformation {o:?}: use linear, pdelta or corotational"),
            },
            formulation: match self.formulation.as_str() {
                "force" => Formulation::Force,
                "disp" => Formulation::Disp,
                o => bail!("--formulation {o:?}: use force or disp"),
            },
            points: self.points,
            scale: self.scale,
            g: 9.81,
            xi: self.xi,
            t1: self.t1,
        })
    }
}

/// Runs `generate`.
pub fn run(cmd: &GenerateCommand) -> Result<()> {
    let (output, model) = match cmd {
        GenerateCommand::Frame(args) => {
            fem2rbd::output::location::check_output_file(&args.output, "--output")?;
            (&args.output, frame(&args.params()?)?)
        }
        GenerateCommand::Building(args) => {
            fem2rbd::output::location::check_output_file(&args.frame.output, "--output")?;
            (&args.frame.output, building(&args.params()?)?)
        }
    };
    let is_json = output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    let text = if is_json {
        serde_json::to_string_pretty(&model)? + "\n"
    } else {
        model.to_toml()?
    };
    fem2rbd::output::write_atomic(output, text.as_bytes())
        .with_context(|| format!("cannot write {}", output.display()))
}
