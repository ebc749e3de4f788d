//! `fem2rbd pushover model.toml --out DIR`: a static pushover (or, with `--cyclic`, a
//! cyclic displacement protocol) of a model after gravity
//! ([`fem2rbd::fe::pushover::run_pushover`]). Writes, as one folder replaced as a whole
//! ([`fem2rbd::output::location`]):
//!
//! * `capacity.csv` — per converged step: the control displacement and roof drift, λ (the
//!   applied lateral force), the base shear V = −ΣR along the push direction, V/W, the
//!   summed reactions, and the base shear carried by frames and by walls;
//! * `reactions.csv` — the reactions of every supported node at the last converged step;
//! * `pushover.json` — the settings, the lateral loads, W, the peak, the periods and why
//!   it ended;
//! * `capacity.svg` — the capacity curve.
//!
//! Numbers are written with 17 significant digits (round-trip). The exit code is non-zero
//! when a step does not converge before the last target (the outputs hold the curve up to
//! the last converged step).
use anyhow::{bail, Result};
use clap::Args;
use fem2rbd::fe::analysis::ConvergenceTest;
use fem2rbd::fe::build::{BuildOptions, Variant};
use fem2rbd::fe::pushover::{
    cyclic_targets, run_pushover, LoadPattern, PushoverResult, PushoverSettings, PushoverStop,
};
use fem2rbd::model::Model;
use fem2rbd::output::location::{
    check_holds_no_input, check_output_dir, check_replaceable, replace_dir, FolderKind,
};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde_json::json;
use std::fmt::Write as _;
use std::io::IsTerminal;
use std::path::PathBuf;

/// `pushover --out DIR`: an existing DIR is replaced only when `pushover` wrote it and it
/// holds nothing else.
pub const PUSHOVER_FOLDER: FolderKind = FolderKind {
    name: "pushover",
    owns: &[
        "capacity.csv",
        "reactions.csv",
        "pushover.json",
        "capacity.svg",
    ],
};

/// Options of `pushover`.
#[derive(Debug, Args)]
pub struct PushoverArgs {
    /// Model file (.toml or .json).
    pub model: PathBuf,
    /// Lateral load pattern: triangular (F ∝ m·z), uniform (F ∝ m) or first-mode
    /// (F ∝ m·φ of the mode with the largest effective mass in the push direction).
    #[arg(long, default_value = "triangular")]
    pub pattern: LoadPattern,
    /// Push direction: x or y.
    #[arg(long, default_value = "x", value_parser = parse_direction)]
    pub direction: usize,
    /// Control node tag (default: the top-level node nearest that level's mass centre).
    #[arg(long)]
    pub node: Option<u32>,
    /// Target roof drift ratio of a monotonic pushover (control displacement / control
    /// node height), e.g. 0.02 for 2 %.
    #[arg(long, default_value_t = 0.02, conflicts_with = "cyclic")]
    pub drift: f64,
    /// Cyclic protocol instead: comma-separated drift amplitudes, each run `--cycles`
    /// times as +a, −a, then back to zero (e.g. 0.0025,0.005,0.01).
    #[arg(long, value_delimiter = ',')]
    pub cyclic: Option<Vec<f64>>,
    /// Cycles per amplitude of `--cyclic`.
    #[arg(long, default_value_t = 2, requires = "cyclic")]
    pub cycles: usize,
    /// Largest control-displacement step as a drift ratio (default 1/3000 of the control
    /// node's height: 1 mm on a 3 m frame).
    #[arg(long)]
    pub step: Option<f64>,
    /// Element variant: model, force, disp or elastic.
    #[arg(long, default_value = "model")]
    pub variant: Variant,
    /// Modes of the initial modal analysis (the first-mode pattern picks among them).
    #[arg(long, default_value_t = 6)]
    pub modes: usize,
    /// Output folder (created if missing).
    #[arg(long)]
    pub out: PathBuf,
}

fn parse_direction(s: &str) -> Result<usize, String> {
    match s {
        "x" | "X" => Ok(0),
        "y" | "Y" => Ok(1),
        _ => Err(format!("unknown direction `{s}`: use x or y")),
    }
}

/// A number of the tables: [`fem2rbd::output::csv_text::number`], 17 significant digits.
fn num(x: f64) -> String {
    fem2rbd::output::csv_text::number(x)
}

/// The step increment used when `--step` is not given, as a drift ratio.
pub const DEFAULT_STEP_DRIFT: f64 = 1.0 / 3000.0;

fn check_drift(option: &str, value: f64) -> Result<()> {
    if !(value.is_finite() && value > 0.0 && value <= 0.5) {
        bail!("{option} = {value}: a drift ratio must lie in (0, 0.5] (0.02 is 2 %)");
    }
    Ok(())
}

/// `capacity.csv` of a result.
pub fn capacity_csv(r: &PushoverResult, direction: usize) -> String {
    let mut s = String::from(
        "step,control_displacement_m,roof_drift,load_factor_n,base_shear_n,base_shear_over_weight,\
         reaction_x_n,reaction_y_n,reaction_z_n,base_shear_frame_n,base_shear_wall_n\n",
    );
    for p in &r.curve {
        let v = p.base_shear(direction);
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{}",
            p.step,
            num(p.control_displacement),
            num(p.control_displacement / r.control_height),
            num(p.load_factor),
            num(v),
            num(v / r.weight),
            num(p.reaction_sum[0]),
            num(p.reaction_sum[1]),
            num(p.reaction_sum[2]),
            num(p.base_shear_frame),
            num(p.base_shear_wall),
        );
    }
    s
}

/// `reactions.csv`: the last converged step's reactions per supported node.
pub fn reactions_csv(r: &PushoverResult) -> String {
    let mut s = String::from("node,fx_n,fy_n,fz_n,mx_nm,my_nm,mz_nm\n");
    for (tag, f) in &r.reactions {
        let cols: Vec<String> = f.iter().map(|&x| num(x)).collect();
        let _ = writeln!(s, "{tag},{}", cols.join(","));
    }
    s
}

/// `pushover.json` of a result.
pub fn summary(
    r: &PushoverResult,
    args: &PushoverArgs,
    targets: &[f64],
    increment: f64,
) -> serde_json::Value {
    let d = args.direction;
    let direction = ["x", "y"][d];
    let peak = r
        .curve
        .iter()
        .max_by(|a, b| a.base_shear(d).total_cmp(&b.base_shear(d)))
        .expect("the curve has the gravity point");
    let stop = match &r.stop {
        PushoverStop::Completed => json!({"kind": "completed"}),
        PushoverStop::NotConverged { at, target } => json!({
            "kind": "not_converged",
            "control_displacement_m": at,
            "target_m": target,
        }),
    };
    json!({
        "model": args.model.display().to_string(),
        "variant": format!("{:?}", args.variant).to_lowercase(),
        "pattern": args.pattern.name(),
        "pattern_mode": r.pattern_mode,
        "direction": direction,
        "control_node": r.control_node,
        "control_height_m": r.control_height,
        "targets_m": targets,
        "step_m": increment,
        "weight_n": r.weight,
        "steps": r.curve.len() - 1,
        "peak": {
            "base_shear_n": peak.base_shear(d),
            "base_shear_over_weight": peak.base_shear(d) / r.weight,
            "control_displacement_m": peak.control_displacement,
            "roof_drift": peak.control_displacement / r.control_height,
        },
        "periods_s": r.modal.periods,
        "lateral_loads": r.pattern_loads.iter().map(|(t, f)| json!([t, f])).collect::<Vec<_>>(),
        "stop": stop,
    })
}

/// Runs `pushover`.
pub fn run(args: &PushoverArgs, quiet: bool, allow_unusual: bool) -> Result<()> {
    check_holds_no_input(&args.out, &[args.model.as_path()], "--out")?;
    check_output_dir(&args.out, "--out")?;
    check_replaceable(&args.out, &PUSHOVER_FOLDER, "--out")?;
    let model = Model::load(&args.model)?;
    // No analysis of a model with nodes nothing holds can run: named before any work.
    fem2rbd::fe::build::check_unused_nodes(&model)
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.model.display()))?;
    super::plausible(&model, &args.model, allow_unusual)?;
    match &args.cyclic {
        Some(amps) => {
            if amps.is_empty() {
                bail!("--cyclic needs at least one amplitude");
            }
            for &a in amps {
                check_drift("--cyclic", a)?;
            }
            if !(1..=100).contains(&args.cycles) {
                bail!("--cycles = {}: give 1 to 100", args.cycles);
            }
        }
        None => check_drift("--drift", args.drift)?,
    }
    if let Some(s) = args.step {
        check_drift("--step", s)?;
    }
    if !(1..=1000).contains(&args.modes) {
        bail!("--modes = {}: give 1 to 1000", args.modes);
    }
    let control = match args.node {
        Some(t) => t,
        None => fem2rbd::fe::pushover::default_control_node(&model)
            .ok_or_else(|| anyhow::anyhow!("{}: the model has no nodes", args.model.display()))?,
    };
    let nodes = model.node_map();
    let Some(cn) = nodes.get(&control) else {
        bail!("--node {control}: no such node in {}", args.model.display());
    };
    let z_base = model
        .fixity()
        .keys()
        .filter_map(|t| nodes.get(t).map(|n| n.z))
        .fold(f64::INFINITY, f64::min);
    let height = cn.z - z_base;
    if height.is_nan() || height <= 0.0 {
        bail!(
            "--node {control}: it lies {height} m above the lowest support; a drift needs a \
             node above the base"
        );
    }
    let targets: Vec<f64> = match &args.cyclic {
        Some(amps) => {
            let m: Vec<f64> = amps.iter().map(|a| a * height).collect();
            cyclic_targets(&m, args.cycles)
        }
        None => vec![args.drift * height],
    };
    let increment = args.step.unwrap_or(DEFAULT_STEP_DRIFT) * height;
    let total_steps: f64 = {
        let mut at = 0.0;
        let mut n = 0.0;
        for &t in &targets {
            n += fem2rbd::fe::pushover::steps_of(t - at, increment) as f64;
            at = t;
        }
        n
    };
    if total_steps > 1e6 {
        bail!(
            "the protocol needs {total_steps} steps of {increment} m: give a larger --step \
             (at most 1 000 000 steps)"
        );
    }
    let settings = PushoverSettings {
        build: BuildOptions {
            variant: args.variant,
            ..Default::default()
        },
        pattern: args.pattern,
        direction: args.direction,
        control_node: Some(control),
        targets: targets.clone(),
        increment,
        modes: args.modes,
        test: ConvergenceTest {
            tol: 1e-8,
            max_iter: 100,
        },
    };
    let bar = if quiet || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        let b =
            ProgressBar::with_draw_target(Some(total_steps as u64), ProgressDrawTarget::stderr());
        b.set_style(
            ProgressStyle::with_template("{bar:40} {msg} [{elapsed_precise}, eta {eta}]")
                .expect("valid template"),
        );
        b
    };
    let d = args.direction;
    let result = run_pushover(&model, &settings, &mut |p| {
        bar.set_position(p.step as u64);
        bar.set_message(format!(
            "drift {:.3} %, V = {:.4e} N",
            100.0 * p.control_displacement / height,
            p.base_shear(d)
        ));
    })?;
    bar.finish_and_clear();
    let text = serde_json::to_string_pretty(&summary(&result, args, &targets, increment))? + "\n";
    let svg = fem2rbd::plot::capacity::svg(&result, d)?;
    replace_dir(
        &args.out,
        &PUSHOVER_FOLDER,
        &[
            ("capacity.csv", capacity_csv(&result, d).as_bytes()),
            ("reactions.csv", reactions_csv(&result).as_bytes()),
            ("pushover.json", text.as_bytes()),
            ("capacity.svg", svg.as_bytes()),
        ],
    )?;
    if let PushoverStop::NotConverged { at, target } = result.stop {
        bail!(
            "a step did not converge at a control displacement of {at} m on the way to \
             {target} m; {} holds the curve up to the last converged step",
            args.out.join("capacity.csv").display()
        );
    }
    if !quiet {
        eprintln!(
            "pushover: {} steps to {} m at node {control}",
            result.curve.len() - 1,
            targets.last().copied().unwrap_or(0.0)
        );
    }
    Ok(())
}
