//! `fem2rbd run [scenario.toml] [--mode hybrid|physics|fe] [--out DIR]`: the whole
//! pipeline ([`crate::pipeline`]). Without a scenario it runs the shipped frame3 LC5
//! example `data/frame3/lc5.toml`. The scenario is read and checked completely before
//! anything runs; the outputs are written at the end, each atomically.
use crate::pipeline::{self, Mode, Progress, Scenario};
use anyhow::Result;
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::cell::RefCell;
use std::io::IsTerminal;
use std::path::PathBuf;

/// The shipped example scenario (frame3, LC5).
pub const DEFAULT_SCENARIO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/frame3/lc5.toml");

/// Options of `run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Scenario file (TOML); default the shipped frame3 LC5 example.
    pub scenario: Option<PathBuf>,
    /// Override the scenario's mode.
    #[arg(long, value_enum)]
    pub mode: Option<Mode>,
    /// Override the scenario's output folder.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// A progress bar on stderr per stage (hidden when quiet or not on a terminal).
struct Bars {
    visible: bool,
    bar: RefCell<Option<ProgressBar>>,
}

impl Progress for Bars {
    fn stage(&self, name: &str, from: f64, to: f64) {
        if !self.visible {
            return;
        }
        let b = if name == "fe" {
            let b = ProgressBar::with_draw_target(Some(1000), ProgressDrawTarget::stderr());
            b.set_style(
                ProgressStyle::with_template("{prefix} {bar:40} {msg} [{elapsed_precise}]")
                    .expect("valid template"),
            );
            b
        } else {
            let b = ProgressBar::new_spinner();
            b.set_style(
                ProgressStyle::with_template("{prefix} {spinner} {msg} [{elapsed_precise}]")
                    .expect("valid template"),
            );
            b.set_message(format!("t = {from:.2} → ≤ {to:.2} s"));
            b.enable_steady_tick(std::time::Duration::from_millis(200));
            b
        };
        b.set_prefix(format!("{name} stage"));
        *self.bar.borrow_mut() = Some(b);
    }
    fn fe(&self, t: f64, t_end: f64) {
        if let Some(b) = self.bar.borrow().as_ref() {
            b.set_position((t / t_end * 1000.0) as u64);
            b.set_message(format!("t = {t:.3} / {t_end:.3} s"));
        }
    }
    fn done(&self) {
        if let Some(b) = self.bar.borrow_mut().take() {
            b.finish_and_clear();
        }
    }
}

/// Runs `run`.
pub fn run(args: &RunArgs, quiet: bool) -> Result<()> {
    let path = args
        .scenario
        .clone()
        .unwrap_or_else(|| PathBuf::from(DEFAULT_SCENARIO));
    let mut sc = Scenario::load(&path)?;
    if let Some(m) = args.mode {
        sc.mode = m;
    }
    if let Some(o) = &args.out {
        sc.output = o.clone();
    }
    if sc.output.exists() && !sc.output.is_dir() {
        anyhow::bail!("output {} exists and is not a folder", sc.output.display());
    }
    let bars = Bars {
        visible: !quiet && std::io::stderr().is_terminal(),
        bar: RefCell::new(None),
    };
    let rec = pipeline::run(&sc, &bars)?;
    let written = pipeline::write::write(&rec, &sc.output, true)?;
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
