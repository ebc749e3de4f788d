//! `fem2rbd export`: `opensees` writes an openseespy script of a model and its analysis;
//! `gltf` and `vtk` turn a run folder (what `fem2rbd run` wrote) into an animated glTF
//! binary or a ParaView time series, without the model.
use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use fem2rbd::export::{opensees_script, GroundMotionInput, OpenSeesOptions, Variant};
use fem2rbd::model::Model;
use fem2rbd::output::gltf::{encode_glb, run_scene, AnimatedScene};
use fem2rbd::output::location::{check_not_an_input, check_output_file};
use fem2rbd::output::run_folder::RunFolder;
use std::path::{Path, PathBuf};

/// Export targets.
#[derive(Debug, Subcommand)]
pub enum ExportCommand {
    /// A self-contained openseespy script (`python3 out.py eigen|gravity|th`).
    Opensees(OpenSeesArgs),
    /// An animated glTF 2.0 binary of a run folder's whole timeline (the run's own
    /// collapse.glb, rebuilt from bodies.csv, keyframes.csv and history.csv, with the
    /// survivable voids of voids.json).
    Gltf(GltfArgs),
    /// A ParaView time series (.pvd + one .vtu per frame) of a run folder's timeline.
    Vtk(VtkArgs),
}

/// Options of `export gltf`.
#[derive(Debug, Args)]
pub struct GltfArgs {
    /// Run folder written by `fem2rbd run`.
    pub run_dir: PathBuf,
    /// Output file; default RUN_DIR/collapse.glb.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

/// Options of `export vtk`.
#[derive(Debug, Args)]
pub struct VtkArgs {
    /// Run folder written by `fem2rbd run`.
    pub run_dir: PathBuf,
    /// Output .pvd file; the .vtu files go into the folder beside it named after its
    /// stem. Default RUN_DIR/vtk/collapse.pvd (frames in RUN_DIR/vtk/collapse/).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

/// The animated scene of the run folder `dir` ([`run_scene`] of its tables).
pub fn run_folder_scene(dir: &Path) -> Result<AnimatedScene> {
    let rf = RunFolder::load(dir)?;
    run_scene(&rf.bodies, &rf.frames, &rf.ground_per_frame())
        .with_context(|| format!("cannot build the scene of run folder {}", dir.display()))
}

/// The files of the run folder `dir` that `export gltf` and `export vtk` read (and so must
/// not write).
fn run_folder_inputs(dir: &Path) -> Vec<PathBuf> {
    ["bodies.csv", "keyframes.csv", "history.csv"]
        .iter()
        .map(|f| dir.join(f))
        .collect()
}

/// The bytes of the glTF binary of the run folder `dir`: the same as the run's own
/// `collapse.glb` (with the survivable voids of its `voids.json`, when it has one).
pub fn run_folder_glb(dir: &Path) -> Result<Vec<u8>> {
    let path = dir.join("voids.json");
    let voids = fem2rbd::model::limits::read_optional_regular_file(&path)
        .with_context(|| format!("cannot read {}", path.display()))?;
    run_folder_glb_with(dir, voids.as_deref())
}

/// The glTF binary of the run folder `dir` with the survivable voids of the `voids.json`
/// text `voids` (none: no void nodes).
pub fn run_folder_glb_with(dir: &Path, voids: Option<&str>) -> Result<Vec<u8>> {
    let mut scene = run_folder_scene(dir)?;
    if let Some(text) = voids {
        scene.voids = fem2rbd::rescue::volumes::survivable_volumes(text)
            .map_err(anyhow::Error::msg)
            .with_context(|| format!("{}", dir.join("voids.json").display()))?;
        scene.routes = fem2rbd::rescue::volumes::route_lines(text)
            .map_err(anyhow::Error::msg)
            .with_context(|| format!("{}", dir.join("voids.json").display()))?;
    }
    encode_glb(&scene)
        .with_context(|| format!("cannot encode the glTF of run folder {}", dir.display()))
}

/// Options of `export opensees`.
#[derive(Debug, Args)]
pub struct OpenSeesArgs {
    /// Model file (.toml or .json).
    pub model: PathBuf,
    /// Ground-motion component `DIR=PATH[,pga=G]` (DIR = X, Y or Z; PATH an AT2 file; G
    /// the target PGA in g, default as recorded), the syntax of `fem2rbd fe`; repeat for
    /// several components.
    #[arg(long = "gm", value_name = "DIR=PATH[,pga=G]")]
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

/// Parses one `--gm` value: the syntax shared with `fem2rbd fe`
/// ([`fem2rbd::motion::spec`]), `DIR=PATH[,pga=G]`.
pub fn parse_gm(s: &str) -> Result<GroundMotionInput> {
    let c = fem2rbd::motion::spec::parse_component(s)?;
    Ok(GroundMotionInput {
        direction: c.axis as u8 + 1,
        path: c.path,
        pga_g: c.pga_g,
    })
}

/// Runs `export`.
pub fn run(cmd: &ExportCommand, allow_unusual: bool) -> Result<()> {
    match cmd {
        ExportCommand::Opensees(a) => {
            check_output_file(&a.output, "--output")?;
            let gms: Vec<GroundMotionInput> =
                a.gm.iter().map(|g| parse_gm(g)).collect::<Result<_>>()?;
            let mut inputs = vec![a.model.as_path()];
            inputs.extend(gms.iter().map(|g| g.path.as_path()));
            check_not_an_input(&a.output, &inputs, "--output")?;
            let model = Model::load(&a.model)?;
            super::plausible(&model, &a.model, allow_unusual)?;
            let variant = match a.variant.as_deref() {
                None => Variant::AsModel,
                Some("force") => Variant::Force,
                Some("disp") => Variant::Disp,
                Some("elastic") => Variant::Elastic,
                Some(o) => bail!("--variant {o:?}: use force, disp or elastic"),
            };
            let opts = OpenSeesOptions {
                ground_motions: gms,
                time_scale: a.time_scale,
                dt: a.dt,
                duration: a.duration,
                variant,
                stop_uz: a.stop_uz,
            };
            let text = opensees_script(&model, &a.model.display().to_string(), &opts)?;
            fem2rbd::output::write_atomic(&a.output, text.as_bytes())
                .with_context(|| format!("cannot write {}", a.output.display()))
        }
        ExportCommand::Gltf(a) => {
            let out = a
                .output
                .clone()
                .unwrap_or_else(|| a.run_dir.join("collapse.glb"));
            check_output_file(&out, "--output")?;
            check_not_an_input(&out, &run_folder_inputs(&a.run_dir), "--output")?;
            let bytes = run_folder_glb(&a.run_dir)?;
            fem2rbd::output::write_atomic(&out, &bytes)
                .with_context(|| format!("cannot write {}", out.display()))
        }
        ExportCommand::Vtk(a) => {
            let out = a
                .output
                .clone()
                .unwrap_or_else(|| a.run_dir.join("vtk").join("collapse.pvd"));
            // The .pvd and the folder of frames beside it (named after its stem).
            let inputs = run_folder_inputs(&a.run_dir);
            check_not_an_input(&out, &inputs, "--output")?;
            if let Some(stem) = out.file_stem() {
                fem2rbd::output::location::check_holds_no_input(
                    &out.with_file_name(stem),
                    &inputs,
                    "the folder of VTK frames",
                )?;
            }
            let scene = run_folder_scene(&a.run_dir)?;
            fem2rbd::output::vtk::write_pvd(&scene, &out)
                .with_context(|| format!("cannot write {}", out.display()))?;
            Ok(())
        }
    }
}
