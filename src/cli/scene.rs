//! `fem2rbd scene`: run a JSON scene in Bullet and write body poses as CSV.
use clap::Args;
use std::path::PathBuf;

/// Run a JSON rigid-body scene in Bullet and write the bodies' poses as CSV.
#[derive(Debug, Args)]
pub struct SceneArgs {
    /// The scene file (JSON; format in the `fem2rbd::scene` docs, examples in data/scenes/).
    pub scene: PathBuf,
    /// Output CSV (written atomically).
    #[arg(long)]
    pub out: PathBuf,
    /// Also write poses every N substeps (and at substep 0), not only the final ones.
    #[arg(long, value_name = "N")]
    pub frames: Option<u64>,
}

/// Runs the subcommand.
pub fn run(args: SceneArgs) -> anyhow::Result<()> {
    fem2rbd::scene::run_scene_file(&args.scene, &args.out, args.frames)
}
