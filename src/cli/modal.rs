//! `fem2rbd modal model.toml`: eigen periods of a model on its initial stiffness, with
//! frequencies, effective modal mass ratios and each mode's character (by shape); with
//! `--json`, the same at full precision (f64 round-trip) as one JSON document.
use anyhow::{Context, Result};
use clap::Args;
use fem2rbd::fe::analysis::modal::{modal_analysis, ModalSettings};
use fem2rbd::fe::build::{build_domain, BuildOptions, Variant};
use fem2rbd::fe::run::mode_character;
use fem2rbd::model::Model;
use std::path::PathBuf;

/// Options of `modal`.
#[derive(Debug, Args)]
pub struct ModalArgs {
    /// Model file (.toml or .json).
    pub model: PathBuf,
    /// Number of modes (lowest first).
    #[arg(long, default_value_t = 6)]
    pub modes: usize,
    /// Element variant: model, force, disp or elastic.
    #[arg(long, default_value = "model")]
    pub variant: Variant,
    /// Print JSON (periods and ratios at full precision) instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// The report printed by `modal`: a table with one line per mode, or with `json` one JSON
/// document `{"modes": [{"mode", "period_s", "frequency_hz", "effective_mass_ratio":
/// [x, y, z], "character"}, …]}` whose numbers round-trip.
pub fn report(model: &Model, modes: usize, variant: Variant, json: bool) -> Result<String> {
    let mut built = build_domain(
        model,
        &BuildOptions {
            variant,
            ..Default::default()
        },
    )?;
    let modal = modal_analysis(
        &mut built.domain,
        &ModalSettings {
            modes,
            ..Default::default()
        },
    )
    .context("modal analysis")?;
    if json {
        let list: Vec<serde_json::Value> = (0..modal.periods.len())
            .map(|k| {
                serde_json::json!({
                    "mode": k + 1,
                    "period_s": modal.periods[k],
                    "frequency_hz": 1.0 / modal.periods[k],
                    "effective_mass_ratio": modal.effective_mass_ratio[k],
                    "character": mode_character(&built.domain, &modal, k).to_string(),
                })
            })
            .collect();
        return Ok(serde_json::to_string_pretty(&serde_json::json!({ "modes": list }))? + "\n");
    }
    let mut out = String::from("mode  T (s)     f (Hz)    MX     MY     MZ     character\n");
    for k in 0..modal.periods.len() {
        let t = modal.periods[k];
        let r = modal.effective_mass_ratio[k];
        out.push_str(&format!(
            "{:>4}  {:.5}  {:>8.4}  {:.3}  {:.3}  {:.3}  {}\n",
            k + 1,
            t,
            1.0 / t,
            r[0],
            r[1],
            r[2],
            mode_character(&built.domain, &modal, k)
        ));
    }
    Ok(out)
}

/// Runs `modal`.
pub fn run(args: &ModalArgs, allow_unusual: bool) -> Result<()> {
    let model = Model::load(&args.model)?;
    // No analysis of a model with nodes nothing holds can run: named before any work.
    fem2rbd::fe::build::check_unused_nodes(&model)
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.model.display()))?;
    super::plausible(&model, &args.model, allow_unusual)?;
    print!("{}", report(&model, args.modes, args.variant, args.json)?);
    Ok(())
}
