//! `fem2rbd modal model.toml`: eigen periods of a model on its initial stiffness, with
//! frequencies, effective modal mass ratios and each mode's character (by shape); with
//! `--json`, the same at full precision (f64 round-trip) as one JSON document.
//!
//! Below the table, the building's modes among those computed: the effective mass ratio
//! summed over them per direction, and the mode with the largest effective mass in X and
//! in Y. When the sum in X or Y is under 90 % (the modal mass ASCE 7-16 §12.9.1.1 asks a
//! response-spectrum analysis to include), it says that the building's modes in that
//! direction may lie above the last mode computed: a model with many slab nodes has
//! hundreds of local vertical slab modes below its first translation.
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
    let n = modal.periods.len();
    let sum: [f64; 3] =
        std::array::from_fn(|d| modal.effective_mass_ratio.iter().map(|r| r[d]).sum());
    // The mode with the largest effective mass ratio in X (d = 0) and in Y (d = 1).
    let dominant = |d: usize| {
        (0..n).max_by(|&a, &b| {
            modal.effective_mass_ratio[a][d].total_cmp(&modal.effective_mass_ratio[b][d])
        })
    };
    if json {
        let list: Vec<serde_json::Value> = (0..n)
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
        let doc = serde_json::json!({
            "modes": list,
            "effective_mass_ratio_sum": sum,
            "largest_effective_mass_mode": {
                "X": dominant(0).map(|k| k + 1),
                "Y": dominant(1).map(|k| k + 1),
            },
        });
        return Ok(serde_json::to_string_pretty(&doc)? + "\n");
    }
    let mut out = String::from("mode  T (s)     f (Hz)    MX     MY     MZ     character\n");
    for k in 0..n {
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
    out.push_str(&format!(
        "\neffective mass of the {n} modes: X {:.3}, Y {:.3}, Z {:.3}\n",
        sum[0], sum[1], sum[2]
    ));
    for (d, name) in [(0, "X"), (1, "Y")] {
        if let Some(k) = dominant(d).filter(|&k| modal.effective_mass_ratio[k][d] > 0.0) {
            out.push_str(&format!(
                "largest in {name}: mode {}, T = {:.5} s, effective mass {:.3}\n",
                k + 1,
                modal.periods[k],
                modal.effective_mass_ratio[k][d]
            ));
        }
        if sum[d] < 0.9 {
            out.push_str(&format!(
                "under 90 % in {name}: the building's modes in {name} may lie above mode {n} \
                 (ask for more with --modes)\n"
            ));
        }
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
