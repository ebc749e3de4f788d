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
    /// Print the time and memory estimate (docs/reliability.md) and exit without running.
    #[arg(long)]
    pub estimate: bool,
}

/// Runs the subcommand; a progress bar over the substeps on a terminal (not with
/// `--quiet`).
pub fn run(args: SceneArgs, quiet: bool, allow_unusual: bool) -> anyhow::Result<()> {
    use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
    use std::io::IsTerminal;
    let bar = if quiet || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        let b = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
        b.set_style(
            ProgressStyle::with_template("scene {bar:40} {pos}/{len} substeps [{elapsed_precise}]")
                .expect("valid template"),
        );
        b
    };
    if args.estimate {
        let scene = fem2rbd::scene::Scene::load(&args.scene)?;
        let (size, work, e) = fem2rbd::estimate::for_scene(&scene, args.frames);
        println!("{}", fem2rbd::estimate::report(&size, &work, &e));
        return Ok(());
    }
    if !quiet && std::io::stderr().is_terminal() {
        // Read once more for the estimate (milliseconds); errors are reported by the run.
        if let Ok(scene) = fem2rbd::scene::Scene::load(&args.scene) {
            let (_, _, e) = fem2rbd::estimate::for_scene(&scene, args.frames);
            eprintln!("estimate: {e} (docs/reliability.md)");
        }
    }
    let r = fem2rbd::scene::run::run_scene_file_with(
        &args.scene,
        &args.out,
        args.frames,
        allow_unusual,
        &mut |d, n| {
            bar.set_length(n);
            bar.set_position(d);
        },
    );
    bar.finish_and_clear();
    Ok(r?)
}
