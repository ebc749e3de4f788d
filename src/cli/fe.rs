//! `fem2rbd fe model.toml --gm X=path[,pga=G] ... --out DIR`: a nonlinear time history
//! of a model under a ground motion ([`fem2rbd::fe::run::run_ground_motion`]). Writes
//! `DIR/nodes.csv` (time and the six displacements of every node) and
//! `DIR/reactions.csv` (the summed support reactions and the base shear of frames and
//! walls at the same steps as `nodes.csv` after t = 0, [`fem2rbd::fe::reactions`]) and
//! `DIR/fe_summary.json` (periods, damping, stop reason, step counts, peaks, the elements
//! removed after they lost their load path, wall time),
//! as one folder replaced as a whole ([`fem2rbd::output::location`]). All input and the
//! output location are checked before anything runs. The exit code is non-zero when a
//! step diverges (the outputs then hold the history up to the last converged step).
use anyhow::{bail, Result};
use clap::Args;
use fem2rbd::fe::analysis::transient::{StepControl, StopReason};
use fem2rbd::fe::build::{BuildOptions, Variant};
use fem2rbd::fe::reactions::ReactionSum;
use fem2rbd::fe::run::{run_ground_motion, RunOptions, RunResult};
use fem2rbd::fe::shell::layers::ConcreteIntegration;
use fem2rbd::model::limits::{check_range, FE_DT, MAX_TIME_S};
use fem2rbd::model::Model;
use fem2rbd::motion::{Format, GroundMotion};
use fem2rbd::output::csv_text::number;
use fem2rbd::output::location::{
    check_holds_no_input, check_output_dir, check_replaceable, replace_dir, FolderKind,
};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde_json::json;
use std::fmt::Write as _;
use std::io::IsTerminal;
use std::path::PathBuf;

/// `fe --out DIR`: an existing DIR is replaced only when `fe` wrote it and it holds nothing
/// else ([`fem2rbd::output::location`]).
pub const FE_FOLDER: FolderKind = FolderKind {
    name: "fe",
    owns: &["fe_summary.json", "nodes.csv", "reactions.csv"],
};

/// Options of `fe`.
#[derive(Debug, Args)]
pub struct FeArgs {
    /// Model file (.toml or .json).
    pub model: PathBuf,
    /// Threads for element state determination (default: the machine's cores); the same
    /// bytes for any number.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Ground-motion component `DIR=PATH[,pga=G]` (DIR = X, Y or Z; PATH an AT2 or
    /// two-column file; G the target PGA in g); repeat for several components.
    #[arg(long = "gm", value_name = "DIR=PATH[,pga=G]", required = true)]
    pub gm: Vec<String>,
    /// Time-scale factor t' = f·t of the records.
    #[arg(long, default_value_t = 1.0)]
    pub time_scale: f64,
    /// Analysis time step (s).
    #[arg(long, default_value_t = 0.005)]
    pub dt: f64,
    /// Analysis duration (s); default the shortest record.
    #[arg(long)]
    pub duration: Option<f64>,
    /// Element variant: model, force, disp or elastic.
    #[arg(long, default_value = "model")]
    pub variant: Variant,
    /// Integration of the shells' concrete layers: implicit (OpenSees'
    /// PlasticDamageConcretePlaneStress) or implex (docs/shell-verification.md §10).
    #[arg(long, default_value = "implicit", value_parser = parse_integration)]
    pub concrete_integration: ConcreteIntegration,
    /// Record every k-th step.
    #[arg(long, default_value_t = 1)]
    pub every: usize,
    /// Output folder (created if missing).
    #[arg(long)]
    pub out: PathBuf,
    /// Print the time and memory estimate (docs/reliability.md) and exit without running.
    #[arg(long)]
    pub estimate: bool,
}

/// `implicit` or `implex`.
fn parse_integration(s: &str) -> Result<ConcreteIntegration, String> {
    match s {
        "implicit" => Ok(ConcreteIntegration::Implicit),
        "implex" => Ok(ConcreteIntegration::Implex),
        _ => Err(format!("expected implicit or implex, got {s:?}")),
    }
}

/// One `--gm` component (the shared syntax of [`fem2rbd::motion::spec`]).
pub type GmSpec = fem2rbd::motion::spec::ComponentArg;

/// Parses `X=path`, `X=path,pga=0.93` (or `X=path,0.93`): [`fem2rbd::motion::spec`].
pub fn parse_gm(s: &str) -> Result<GmSpec> {
    Ok(fem2rbd::motion::spec::parse_component(s)?)
}

/// Reads, scales and time-scales the ground motion of the `--gm` components.
pub fn ground_motion(specs: &[GmSpec], time_scale: f64) -> Result<GroundMotion> {
    Ok(fem2rbd::motion::spec::read_components(
        specs,
        time_scale,
        Format::Auto,
    )?)
}

/// `nodes.csv`: `t,ux_<tag>,uy_<tag>,uz_<tag>,rx_<tag>,ry_<tag>,rz_<tag>,...`, times (s)
/// and displacements (m, rad) with 17 significant digits
/// ([`fem2rbd::output::csv_text::number`]).
pub fn nodes_csv(result: &RunResult) -> String {
    let h = &result.transient.history;
    let mut s = String::from("t");
    for tag in &result.node_tags {
        for c in ["ux", "uy", "uz", "rx", "ry", "rz"] {
            let _ = write!(s, ",{c}_{tag}");
        }
    }
    s.push('\n');
    for (k, t) in h.time.iter().enumerate() {
        s.push_str(&number(*t));
        for d in &h.disp[k] {
            for v in d {
                let _ = write!(s, ",{}", number(*v));
            }
        }
        s.push('\n');
    }
    s
}

/// `reactions.csv`: per recorded step after t = 0, `t` (s), the summed support reactions
/// `rx_n, ry_n, rz_n, mx_nm, my_nm, mz_nm` and the base shear along x and y carried by the
/// beam-columns and by the shells (`vx_frame_n, vx_wall_n, vy_frame_n, vy_wall_n`), times
/// and forces with 17 significant digits ([`fem2rbd::output::csv_text::number`]). Reactions are static (R = F_int − P at the fixed DOFs, OpenSees
/// `reactions` without `-dynamic`): they leave out the damping forces at the supports.
pub fn reactions_csv(rows: &[(f64, ReactionSum)]) -> String {
    let mut s = String::from(
        "t,rx_n,ry_n,rz_n,mx_nm,my_nm,mz_nm,vx_frame_n,vx_wall_n,vy_frame_n,vy_wall_n\n",
    );
    for (t, r) in rows {
        s.push_str(&number(*t));
        for v in r
            .total
            .iter()
            .chain(&[r.frame[0], r.wall[0], r.frame[1], r.wall[1]])
        {
            let _ = write!(s, ",{}", number(*v));
        }
        s.push('\n');
    }
    s
}

/// `fe_summary.json` content.
pub fn summary(result: &RunResult, wall_s: f64) -> serde_json::Value {
    let tr = &result.transient;
    let stop = match &tr.stop {
        StopReason::Completed => json!({"reason": "completed", "time": tr.end_time}),
        StopReason::Stopped { time } => json!({"reason": "stopped", "time": time}),
        StopReason::Diverged {
            time,
            attempted,
            reason,
        } => json!({"reason": "diverged", "time": time, "attempted": attempted, "message": reason}),
    };
    // Peak |u| per component over all recorded nodes and times.
    let h = &tr.history;
    let names = ["ux", "uy", "uz", "rx", "ry", "rz"];
    let mut peaks = serde_json::Map::new();
    for (c, name) in names.iter().enumerate() {
        let mut best = (0.0f64, 0u32, 0.0f64);
        for (k, t) in h.time.iter().enumerate() {
            for (n, d) in h.disp[k].iter().enumerate() {
                if d[c].abs() > best.0.abs() {
                    best = (d[c], result.node_tags[n], *t);
                }
            }
        }
        peaks.insert(
            (*name).to_string(),
            json!({"value": best.0, "node": best.1, "time": best.2}),
        );
    }
    let mut summary = json!({
        "periods_s": result.modal.periods,
        "rayleigh": {"a0": result.damping.a0, "a1": result.damping.a1},
        "stop": stop,
        "end_time_s": tr.end_time,
        "steps": tr.steps,
        "fallback_steps": tr.fallback_steps,
        "records": h.time.len(),
        "peaks": peaks,
        "wall_time_s": wall_s,
    });
    // Elements removed after they lost their load path (absent when none was).
    if !tr.removed.is_empty() {
        summary["removed_elements"] = tr
            .removed
            .iter()
            .map(|r| json!({"element": r.element, "time": r.time, "attempted": r.attempted, "message": r.reason}))
            .collect();
    }
    summary
}

/// Runs `fe`.
pub fn run(args: &FeArgs, quiet: bool, allow_unusual: bool) -> Result<()> {
    let specs: Vec<GmSpec> = args.gm.iter().map(|g| parse_gm(g)).collect::<Result<_>>()?;
    let mut inputs = vec![args.model.as_path()];
    inputs.extend(specs.iter().map(|s| s.path.as_path()));
    check_holds_no_input(&args.out, &inputs, "--out")?;
    check_output_dir(&args.out, "--out")?;
    check_replaceable(&args.out, &FE_FOLDER, "--out")?;
    let model = Model::load(&args.model)?;
    // No analysis of a model with nodes nothing holds can run: named before any work.
    fem2rbd::fe::build::check_unused_nodes(&model)
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.model.display()))?;
    super::plausible(&model, &args.model, allow_unusual)?;
    let gm = ground_motion(&specs, args.time_scale)?;
    check_range("--dt", args.dt, FE_DT.0, false, FE_DT.1, "s")?;
    if args.every == 0 {
        bail!("--every must be at least 1");
    }
    if args.threads == Some(0) {
        bail!("--threads 0: give at least 1 thread");
    }
    if let Some(d) = args.duration {
        check_range("--duration", d, 0.0, true, MAX_TIME_S, "s")?;
    }
    let t_end = args.duration.unwrap_or_else(|| gm.duration_s());
    let options = RunOptions {
        build: BuildOptions {
            variant: args.variant,
            concrete_integration: args.concrete_integration,
            threads: args.threads,
            ..Default::default()
        },
        dt: args.dt,
        duration: Some(t_end),
        every: args.every,
        ..Default::default()
    };
    let total = (t_end / args.dt).ceil() as u64;
    let bar = if quiet || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        let b = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
        b.set_style(
            ProgressStyle::with_template("{bar:40} {msg} [{elapsed_precise}, eta {eta}]")
                .expect("valid template"),
        );
        b
    };
    let size = fem2rbd::estimate::Size::of_model(&model);
    let work = fem2rbd::estimate::Work {
        fe_steps: total,
        fe_recorded_steps: total / args.every as u64 + 1,
        ground_samples: (gm.duration_s() / args.dt).ceil() as u64,
        ..Default::default()
    };
    let e = fem2rbd::estimate::estimate(&size, &work);
    if args.estimate {
        println!("{}", fem2rbd::estimate::report(&size, &work, &e));
        return Ok(());
    }
    if !quiet && std::io::stderr().is_terminal() {
        eprintln!("estimate: {e} (docs/reliability.md)");
    }
    let start = std::time::Instant::now();
    let mut reactions = Vec::new();
    let mut last = None;
    let every = args.every;
    let result = run_ground_motion(&model, &gm, &options, &mut |info, domain| {
        let r = (info.time, ReactionSum::of(domain));
        if info.step % every == 0 {
            reactions.push(r);
            last = None;
        } else {
            last = Some(r);
        }
        bar.set_position(info.step as u64);
        bar.set_message(format!("t = {:.3} / {t_end:.3} s", info.time));
        StepControl::Continue
    })?;
    bar.finish_and_clear();
    // The final state is recorded whatever `--every` says, as in nodes.csv.
    reactions.extend(last);
    let wall = start.elapsed().as_secs_f64();
    let text = serde_json::to_string_pretty(&summary(&result, wall))? + "\n";
    replace_dir(
        &args.out,
        &FE_FOLDER,
        &[
            ("nodes.csv", nodes_csv(&result).as_bytes()),
            ("reactions.csv", reactions_csv(&reactions).as_bytes()),
            ("fe_summary.json", text.as_bytes()),
        ],
    )?;
    if !quiet {
        match &result.transient.stop {
            // Reported as the error below.
            StopReason::Diverged { .. } => {}
            _ => eprintln!(
                "fe: t = {:.3} s in {} steps ({} with fallbacks), {wall:.1} s",
                result.transient.end_time, result.transient.steps, result.transient.fallback_steps
            ),
        }
        for r in &result.transient.removed {
            eprintln!(
                "fe: element {} removed at t = {:.4} s ({})",
                r.element, r.time, r.reason
            );
        }
    }
    if let StopReason::Diverged { time, reason, .. } = &result.transient.stop {
        // The outputs hold the history up to the last converged step; the exit code
        // says the analysis did not reach its end.
        bail!(
            "the analysis diverged at t = {time:.4} s ({reason}); {} and {} hold the \
             history up to the last converged step",
            args.out.join("nodes.csv").display(),
            args.out.join("fe_summary.json").display()
        );
    }
    Ok(())
}
