//! `fem2rbd voids RUN_DIR [--cell M] [--rescuer M] [--camera M] [--timing]`: the rescue
//! analysis of a run folder's ruin (`src/rescue/`, docs/rescue.md): writes `voids.csv`,
//! `voids.json` and `rubble_height.csv` into the folder, sets `summary.json`'s
//! `rescue` section to the same analysis and rebuilds `collapse.glb` (when the folder has
//! one) with the survivable voids as nodes, each file atomically, after everything
//! succeeded; prints the files written (nothing with `--quiet`).
//!
//! Of an ensemble folder (`ensemble.json` and `member-NNN/`, `fem2rbd run --ensemble N`) it
//! analyses every member so, builds the ensemble's rescue maps (`rescue_map.csv`,
//! `rescue.json`, [`fem2rbd::rescue::ensemble`]) and the `plots/rescue_map.png` and `.svg`
//! figure from them, and writes all of these files at once, all or nothing, after every
//! member succeeded (a member whose grid would be too large fails the command, naming the
//! member and `--cell`); then it rebuilds the ensemble's `report.html` from the folder when
//! it has one.
use anyhow::{bail, Context, Result};
use clap::Args;
use fem2rbd::rescue::ensemble::{maps, member_dirs, member_from_texts, Member};
use fem2rbd::rescue::person::{DEFAULT_CAMERA_M, DEFAULT_CELL_M, DEFAULT_RESCUER_M};
use fem2rbd::rescue::report::with_summary_section;
use fem2rbd::rescue::{analyse, Ruin, Sizes};
use std::path::{Path, PathBuf};

/// Options of `voids`. Sizes are full-scale metres; the analysis multiplies them by the
/// model's scale (`summary.json` `scale`).
#[derive(Debug, Args)]
pub struct VoidsArgs {
    /// Run folder written by `fem2rbd run` (bodies.csv, ruins.csv, connections.csv,
    /// summary.json), or an ensemble folder (`fem2rbd run --ensemble N`: ensemble.json and
    /// member-NNN/), whose members are analysed and whose rescue maps are rebuilt.
    pub run_dir: PathBuf,
    /// Grid cell edge, m at full scale.
    #[arg(long, default_value_t = DEFAULT_CELL_M)]
    pub cell: f64,
    /// Width of the passage a crawling rescuer needs, m at full scale.
    #[arg(long, default_value_t = DEFAULT_RESCUER_M)]
    pub rescuer: f64,
    /// Diameter of the search camera's head, m at full scale.
    #[arg(long, default_value_t = DEFAULT_CAMERA_M)]
    pub camera: f64,
    /// Print the analysis' wall time (reading excluded).
    #[arg(long)]
    pub timing: bool,
}

/// The files of one run folder's analysis (name, bytes), in writing order, and the
/// timing line.
struct Analysed {
    files: Vec<(&'static str, Vec<u8>)>,
    timing: String,
}

impl Analysed {
    fn text(&self, name: &str) -> &str {
        self.files
            .iter()
            .find(|f| f.0 == name)
            .map_or("", |f| std::str::from_utf8(&f.1).expect("UTF-8 text"))
    }
}

/// Analyses the run folder `dir` with `sizes`: the rescue files, `summary.json` with its
/// `rescue` section and, when the folder has one, `collapse.glb`, none written yet.
fn analysed(dir: &Path, sizes: Sizes) -> Result<Analysed> {
    let ruin = Ruin::load(dir)?;
    let t0 = std::time::Instant::now();
    let analysis = analyse(&ruin, sizes)?;
    let mut files: Vec<(&str, Vec<u8>)> = analysis.files();
    let elapsed = t0.elapsed().as_secs_f64();
    // summary.json's `rescue` section follows the new analysis, so that it never
    // disagrees with voids.json.
    let summary_path = dir.join("summary.json");
    let summary = fem2rbd::model::limits::read_regular_file(&summary_path)
        .with_context(|| format!("{}: cannot read", summary_path.display()))?;
    let summary = with_summary_section(&summary, analysis.summary())
        .with_context(|| format!("{}: not a JSON object", summary_path.display()))?;
    files.push(("summary.json", summary.into_bytes()));
    // collapse.glb holds the survivable voids: rebuilt with the new voids.json.
    if dir.join("collapse.glb").is_file() {
        let voids = files
            .iter()
            .find(|f| f.0 == "voids.json")
            .map(|f| std::str::from_utf8(&f.1).expect("voids.json is UTF-8"));
        let glb = super::export::run_folder_glb_with(dir, voids)?;
        files.push(("collapse.glb", glb));
    }
    let cells = analysis.field.as_ref().map_or(0, |f| f.grid.len());
    let timing = format!(
        "rescue analysis: {} bodies, {cells} cells, {} voids in {elapsed:.3} s",
        ruin.boxes.len(),
        analysis.voids.len()
    );
    Ok(Analysed { files, timing })
}

/// Runs `voids`.
pub fn run(args: &VoidsArgs, quiet: bool) -> Result<()> {
    let sizes = Sizes {
        cell_m: args.cell,
        rescuer_m: args.rescuer,
        camera_m: args.camera,
    };
    // Sizes first (before reading), then the folder.
    sizes.scaled(1.0)?;
    if args.run_dir.join("ensemble.json").is_file() {
        return run_ensemble(args, sizes, quiet);
    }
    let a = analysed(&args.run_dir, sizes)?;
    for (name, bytes) in &a.files {
        fem2rbd::output::write_atomic(args.run_dir.join(name), bytes)?;
    }
    if args.timing {
        println!("{}", a.timing);
    }
    if !quiet {
        for (name, _) in &a.files {
            println!("{}", args.run_dir.join(name).display());
        }
    }
    Ok(())
}

/// `voids ENSEMBLE_DIR` (module docs).
fn run_ensemble(args: &VoidsArgs, sizes: Sizes, quiet: bool) -> Result<()> {
    let dir = &args.run_dir;
    let found = member_dirs(dir)?;
    if found.is_empty() {
        bail!(
            "{}: an ensemble folder (it has ensemble.json) without member-NNN folders",
            dir.display()
        );
    }
    let mut writes: Vec<(PathBuf, Vec<u8>)> = Vec::new();
    let mut members = Vec::with_capacity(found.len());
    for (name, mdir) in found {
        let a =
            analysed(&mdir, sizes).with_context(|| format!("{}: member {name}", dir.display()))?;
        if args.timing {
            println!("{name}: {}", a.timing);
        }
        members.push(Member {
            rescue: member_from_texts(&mdir, a.text("voids.json"), a.text("voids.csv"))?,
            name,
        });
        writes.extend(a.files.into_iter().map(|(n, b)| (mdir.join(n), b)));
    }
    let maps = maps(members, dir)?;
    let files = maps.files();
    let text = |k: usize| std::str::from_utf8(&files[k].1).expect("UTF-8 text");
    let fig = fem2rbd::plot::voids::RescueMapFigure::from_texts(dir, text(0), text(1))?;
    let plots = dir.join("plots");
    std::fs::create_dir_all(&plots)
        .with_context(|| format!("{}: cannot create the plot folder", plots.display()))?;
    let figures = [
        (
            plots.join("rescue_map.png"),
            fem2rbd::plot::png_bytes(&fig)?,
        ),
        (
            plots.join("rescue_map.svg"),
            fem2rbd::plot::svg_string(&fig)?.into_bytes(),
        ),
    ];
    writes.extend(files.into_iter().map(|(n, b)| (dir.join(n), b)));
    writes.extend(figures);
    fem2rbd::output::write_all_atomic(&writes)?;
    let mut written: Vec<PathBuf> = writes.into_iter().map(|(p, _)| p).collect();
    let report = dir.join("report.html");
    if report.is_file() {
        super::report::write(dir, &report).with_context(|| {
            format!(
                "the members' analyses and the rescue maps of {} are written; its report",
                dir.display()
            )
        })?;
        written.push(report);
    }
    if !quiet {
        for p in written {
            println!("{}", p.display());
        }
    }
    Ok(())
}
