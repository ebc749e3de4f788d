//! `fem2rbd run [scenario.toml] [--mode hybrid|rigid|fe] [--out DIR]`: the whole
//! pipeline ([`fem2rbd::pipeline`]). Without a scenario it runs the shipped frame3 LC5
//! example `data/frame3/lc5.toml`. The scenario is read and checked completely before
//! anything runs; the outputs are written at the end, each atomically, then the run's HTML
//! report `report.html` from the written folder (unless `--no-report`).
use anyhow::{bail, Context, Result};
use clap::Args;
use fem2rbd::pipeline::{self, Mode, Progress, Scenario};
use fem2rbd::ruin::stage::{AxialTraceSettings, BodyTraceSettings, TraceSettings};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::cell::{Cell, RefCell};
use std::io::IsTerminal;
use std::path::PathBuf;

/// The shipped example scenario (frame3, LC5).
pub const DEFAULT_SCENARIO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/frame3/lc5.toml");

/// Options of `run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Scenario file (TOML); default the shipped frame3 LC5 example.
    pub scenario: Option<PathBuf>,
    /// Override the scenario's mode: hybrid, rigid or fe.
    #[arg(long, value_parser = Mode::from_arg)]
    pub mode: Option<Mode>,
    /// Override the scenario's output folder.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Run an ensemble of N members (member 0 unperturbed; docs/ruin-numerics.md):
    /// OUT/member-NNN/ and OUT/ensemble.json.
    #[arg(long, value_name = "N")]
    pub ensemble: Option<usize>,
    /// Ensemble seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Threads (default: the machine's cores): a single run's FE and ruin-stage solver
    /// threads; an ensemble's members run this many at once, each on one thread. The
    /// same bytes for any number.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Write the ruin stage's axial-row trace to FILE (sign changes of the connections'
    /// axial offsets and the kicks after them; src/ruin/axial.rs).
    #[arg(
        long,
        value_name = "FILE",
        help_heading = "Diagnostics: ruin-stage traces"
    )]
    pub trace_axial: Option<PathBuf>,
    /// A kick in the axial trace: a body's centre velocity changing by more than this in
    /// one substep, m/s.
    #[arg(
        long,
        value_name = "MPS",
        default_value_t = 0.1,
        requires = "trace_axial",
        help_heading = "Diagnostics: ruin-stage traces"
    )]
    pub trace_axial_kick: f64,
    /// Trace the substeps of the body NAME (`bodies.csv` name, e.g. Column:3:34) into
    /// --trace-body-file (src/ruin/body_trace.rs).
    #[arg(
        long,
        value_name = "NAME",
        requires = "trace_body_file",
        help_heading = "Diagnostics: ruin-stage traces"
    )]
    pub trace_body: Option<String>,
    /// The file of --trace-body.
    #[arg(
        long,
        value_name = "FILE",
        requires = "trace_body",
        help_heading = "Diagnostics: ruin-stage traces"
    )]
    pub trace_body_file: Option<PathBuf>,
    /// The traces start at this time, s.
    #[arg(
        long,
        value_name = "S",
        default_value_t = 0.0,
        help_heading = "Diagnostics: ruin-stage traces"
    )]
    pub trace_from: f64,
    /// The body trace ends at this time, s (default: the end of the run).
    #[arg(
        long,
        value_name = "S",
        help_heading = "Diagnostics: ruin-stage traces"
    )]
    pub trace_to: Option<f64>,
    /// Print the time and memory estimate of one run (docs/reliability.md) and exit
    /// without running.
    #[arg(long)]
    pub estimate: bool,
    /// Do not write report.html (the run's HTML report, `fem2rbd report`) into the run
    /// folder.
    #[arg(long)]
    pub no_report: bool,
}

/// A progress bar on stderr per stage (hidden when quiet or not on a terminal).
struct Bars {
    visible: bool,
    bar: RefCell<Option<ProgressBar>>,
    /// The current stage's simulated time span, s.
    span: Cell<(f64, f64)>,
}

impl Bars {
    /// Position of simulated time `t` in the stage's span, ‰.
    fn permille(&self, t: f64) -> u64 {
        let (a, b) = self.span.get();
        if b > a {
            ((t - a) / (b - a) * 1000.0).clamp(0.0, 1000.0) as u64
        } else {
            1000
        }
    }
}

impl Progress for Bars {
    fn stage(&self, name: &str, from: f64, to: f64) {
        if !self.visible {
            return;
        }
        // Both stages: a bar over the simulated time span (the ruin stage may stop
        // earlier, when the debris is at rest).
        let b = ProgressBar::with_draw_target(Some(1000), ProgressDrawTarget::stderr());
        b.set_style(
            ProgressStyle::with_template("{prefix:>13} {bar:40} {msg} [{elapsed_precise}]")
                .expect("valid template"),
        );
        b.set_message(format!("t = {from:.2} / {to:.2} s"));
        b.set_prefix(format!("{name} stage"));
        self.span.set((from, to));
        *self.bar.borrow_mut() = Some(b);
    }
    fn plan(&self, fe_steps: u64, substeps: u64) {
        if self.visible {
            eprintln!(
                "work: {fe_steps} FE steps, at most {substeps} ruin-stage substeps (bounds: docs/reliability.md)"
            );
        }
    }
    fn fe(&self, t: f64, t_end: f64) {
        if let Some(b) = self.bar.borrow().as_ref() {
            b.set_position(self.permille(t));
            b.set_message(format!("t = {t:.3} / {t_end:.3} s"));
        }
    }
    fn ruin(&self, t: f64, t_end: f64, (intact, plastic, broken): (usize, usize, usize)) {
        if let Some(b) = self.bar.borrow().as_ref() {
            b.set_position(self.permille(t));
            b.set_message(format!(
                "t = {t:.2} / ≤ {t_end:.2} s, connections {intact} intact / {plastic} plastic / {broken} broken"
            ));
        }
    }
    fn done(&self) {
        if let Some(b) = self.bar.borrow_mut().take() {
            b.finish_and_clear();
        }
    }
}

/// Runs `run`.
pub fn run(args: &RunArgs, quiet: bool, allow_unusual: bool) -> Result<()> {
    let path = args
        .scenario
        .clone()
        .unwrap_or_else(|| PathBuf::from(DEFAULT_SCENARIO));
    let mut sc = Scenario::load(&path)?;
    if let Some(m) = args.mode {
        sc.set_mode(m);
    }
    if let Some(o) = &args.out {
        sc.output = o.clone();
    }
    // The ensemble's options are checked before any work.
    if let Some(n) = args.ensemble {
        if n == 0 || n > pipeline::ensemble::MAX_MEMBERS {
            bail!(
                "--ensemble {n}: give 1 to {} members (docs/reliability.md, resource bounds)",
                pipeline::ensemble::MAX_MEMBERS
            );
        }
        if sc.mode == Mode::Fe {
            bail!(
                "--ensemble with the fe mode: its members would be identical (an ensemble \
                 perturbs the hand-off velocity, or the ground motion of a rigid-only run); \
                 run it with --mode hybrid or --mode rigid"
            );
        }
    }
    if args.threads == Some(0) {
        bail!("--threads 0: give at least 1 thread");
    }
    sc.threads = if args.ensemble.is_some() {
        // The members are the parallel unit.
        Some(1)
    } else {
        args.threads
    };
    for (option, t) in [
        ("--trace-from", Some(args.trace_from)),
        ("--trace-to", args.trace_to),
    ] {
        if t.is_some_and(|t| !t.is_finite()) {
            bail!("{option}: give a time in s");
        }
    }
    if !(args.trace_axial_kick.is_finite() && args.trace_axial_kick > 0.0) {
        bail!("--trace-axial-kick: give a speed > 0 in m/s");
    }
    sc.traces = TraceSettings {
        axial: args.trace_axial.clone().map(|path| AxialTraceSettings {
            path,
            from_s: args.trace_from,
            kick_mps: args.trace_axial_kick,
        }),
        body: args
            .trace_body
            .clone()
            .zip(args.trace_body_file.clone())
            .map(|(body, path)| BodyTraceSettings {
                path,
                body,
                from_s: args.trace_from,
                to_s: args.trace_to.unwrap_or(f64::INFINITY),
            }),
    };
    // The output location and the work are checked before anything runs: the folder is
    // replaced as a whole, so it must hold none of the inputs and nothing but an earlier
    // output of the same kind.
    use fem2rbd::output::location::{check_holds_no_input, check_output_dir, check_replaceable};
    check_holds_no_input(&sc.output, &sc.inputs(), "output folder")?;
    check_output_dir(&sc.output, "output folder")?;
    let kind = if args.ensemble.is_some() {
        &pipeline::ensemble::ENSEMBLE_FOLDER
    } else {
        &pipeline::write::RUN_FOLDER
    };
    check_replaceable(&sc.output, kind, "output folder")?;
    let model = fem2rbd::model::Model::load(&sc.model)?;
    let unusual = super::plausible(&model, &sc.model, allow_unusual)?;
    drop(model);
    if args.estimate {
        let (size, work, e) = fem2rbd::estimate::for_scenario(&sc)?;
        println!("{}", fem2rbd::estimate::report(&size, &work, &e));
        return Ok(());
    }
    let visible = !quiet && std::io::stderr().is_terminal();
    if let Some(n) = args.ensemble {
        let threads = args.threads.unwrap_or_else(|| {
            std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
        });
        if visible {
            let (_, _, e) = fem2rbd::estimate::for_scenario(&sc)?;
            let rounds = n.div_ceil(threads.clamp(1, n.max(1))) as f64;
            eprintln!(
                "estimate: {n} members, {} each; about {} on {threads} threads, {} peak memory (docs/reliability.md)",
                fem2rbd::estimate::show_seconds(e.seconds),
                fem2rbd::estimate::show_seconds(e.seconds * rounds),
                fem2rbd::estimate::show_bytes(e.peak_bytes * threads.min(n) as f64)
            );
        }
        let mut recs = pipeline::ensemble::run_ensemble(&sc, n, args.seed, threads)?;
        for r in &mut recs {
            r.unusual.clone_from(&unusual);
        }
        let written = pipeline::ensemble::write_ensemble(&sc, &recs, args.seed, &sc.output)?;
        if !quiet {
            eprintln!(
                "ensemble ({}): {n} members on {threads} threads; {} files in {}",
                sc.mode.name(),
                written.len(),
                sc.output.display()
            );
        }
        return Ok(());
    }
    if visible {
        let (_, _, e) = fem2rbd::estimate::for_scenario(&sc)?;
        eprintln!("estimate: {e} (docs/reliability.md)");
    }
    let bars = Bars {
        visible,
        bar: RefCell::new(None),
        span: Cell::new((0.0, 0.0)),
    };
    let mut rec = pipeline::run(&sc, &bars)?;
    rec.unusual = unusual;
    let mut written = pipeline::write::write(&rec, &sc.output, true)?;
    if !args.no_report {
        // Written after the run folder, from its files alone (as `fem2rbd report` would).
        let out = sc.output.join("report.html");
        super::report::write(&sc.output, &out).with_context(|| {
            format!(
                "the run folder {} is written; its report",
                sc.output.display()
            )
        })?;
        written.push(out);
    }
    if !quiet {
        let tc = match rec.tc_s {
            Some(t) => format!("Tc = {t:.3} s"),
            None => "no Tc".into(),
        };
        eprintln!(
            "run ({}): {tc} ({:?}); {} files in {}",
            sc.mode.name(),
            rec.tc_reason,
            written.len(),
            sc.output.display()
        );
    }
    Ok(())
}
