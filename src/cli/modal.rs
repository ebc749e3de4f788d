//! `fem2rbd modal model.toml`: the building's modes on the initial stiffness — the
//! lowest with at least 1 % effective mass along X, Y or in torsion
//! (`fe::analysis::building_modes`), each an exact eigenpair with its index in the full
//! spectrum — or with `--lowest` the lowest modes whatever they carry. Per mode: period,
//! frequency, effective modal mass ratios in X, Y, Z and torsion, character (by shape);
//! with `--json`, the same at full precision (f64 round-trip) as one JSON document.
//!
//! Below the table: the effective mass ratio summed over the modes listed per direction,
//! the mode with the largest effective mass in X and in Y, and how many modes were
//! skipped below the last one listed with a bound on the mass they carry together. When
//! the sum in X or Y is under 90 % (the modal mass ASCE 7-16 §12.9.1.1 asks a
//! response-spectrum analysis to include), it says that more of the building's modes in
//! that direction lie above the last mode listed.
use anyhow::{Context, Result};
use clap::Args;
use fem2rbd::fe::analysis::building_modes::BUILDING_MODE_MASS_RATIO;
use fem2rbd::fe::analysis::modal::{modal_analysis, ModalSettings, ModeSelection};
use fem2rbd::fe::build::{build_domain, BuildOptions, Variant};
use fem2rbd::fe::run::mode_character;
use fem2rbd::model::Model;
use std::path::PathBuf;

/// Options of `modal`.
#[derive(Debug, Args)]
pub struct ModalArgs {
    /// Model file (.toml or .json).
    pub model: PathBuf,
    /// Number of modes.
    #[arg(long, default_value_t = 6)]
    pub modes: usize,
    /// The lowest modes, whatever they carry (local slab modes too), instead of the
    /// building's (the lowest with at least 1 % effective mass along X, Y or in torsion).
    #[arg(long)]
    pub lowest: bool,
    /// Element variant: model, force, disp or elastic.
    #[arg(long, default_value = "model")]
    pub variant: Variant,
    /// Print JSON (periods and ratios at full precision) instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// The report printed by `modal`: a table with one line per mode, or with `json` one JSON
/// document `{"selection", "modes": [{"mode", "index", "period_s", "frequency_hz",
/// "effective_mass_ratio": [x, y, z], "torsion_mass_ratio", "residual", "character"},
/// …],
/// "effective_mass_ratio_sum", "torsion_mass_ratio_sum", "largest_effective_mass_mode",
/// "skipped": {"count", "ranges": [[first, last], …], "mass_ratio_bound": [x, y,
/// torsion]}}` whose numbers round-trip.
pub fn report(
    model: &Model,
    modes: usize,
    selection: ModeSelection,
    variant: Variant,
    json: bool,
) -> Result<String> {
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
            selection,
            ..Default::default()
        },
    )
    .context("modal analysis")?;
    let n = modal.periods.len();
    let sum: [f64; 3] =
        std::array::from_fn(|d| modal.effective_mass_ratio.iter().map(|r| r[d]).sum());
    let sum_torsion: f64 = modal.torsion_mass_ratio.iter().sum();
    // The mode with the largest effective mass ratio in X (d = 0) and in Y (d = 1).
    let dominant = |d: usize| {
        (0..n).max_by(|&a, &b| {
            modal.effective_mass_ratio[a][d].total_cmp(&modal.effective_mass_ratio[b][d])
        })
    };
    let skipped = modal.skipped;
    if json {
        let list: Vec<serde_json::Value> = (0..n)
            .map(|k| {
                serde_json::json!({
                    "mode": k + 1,
                    "index": modal.index[k],
                    "period_s": modal.periods[k],
                    "frequency_hz": 1.0 / modal.periods[k],
                    "effective_mass_ratio": modal.effective_mass_ratio[k],
                    "torsion_mass_ratio": modal.torsion_mass_ratio[k],
                    "residual": modal.residual[k],
                    "character": mode_character(&built.domain, &modal, k).to_string(),
                })
            })
            .collect();
        let doc = serde_json::json!({
            "selection": modal.selection.to_string(),
            "building_mode_mass_ratio": BUILDING_MODE_MASS_RATIO,
            "modes": list,
            "effective_mass_ratio_sum": sum,
            "torsion_mass_ratio_sum": sum_torsion,
            "largest_effective_mass_mode": {
                "X": dominant(0).map(|k| k + 1),
                "Y": dominant(1).map(|k| k + 1),
            },
            "skipped": {
                "count": skipped.count,
                "ranges": skipped_ranges(&modal.index)
                    .iter()
                    .map(|&(a, z, _)| [a, z])
                    .collect::<Vec<_>>(),
                "mass_ratio_bound": skipped.mass_ratio_bound,
            },
        });
        return Ok(serde_json::to_string_pretty(&doc)? + "\n");
    }
    let mut out =
        String::from("mode  index  T (s)     f (Hz)    MX     MY     MZ     MRZ    character\n");
    for k in 0..n {
        let t = modal.periods[k];
        let r = modal.effective_mass_ratio[k];
        out.push_str(&format!(
            "{:>4}  {:>5}  {:.5}  {:>8.4}  {:.3}  {:.3}  {:.3}  {:.3}  {}\n",
            k + 1,
            modal.index[k],
            t,
            1.0 / t,
            r[0],
            r[1],
            r[2],
            modal.torsion_mass_ratio[k],
            mode_character(&built.domain, &modal, k)
        ));
    }
    let last = modal.index.last().copied().unwrap_or(0);
    out.push_str(&format!(
        "\neffective mass of the {n} modes: X {:.3}, Y {:.3}, Z {:.3}, torsion {:.3}\n",
        sum[0], sum[1], sum[2], sum_torsion
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
                "under 90 % in {name}: more of the building's modes in {name} lie above \
                 index {last} (ask for more with --modes)\n"
            ));
        }
    }
    match modal.selection {
        ModeSelection::Lowest => out.push_str(&format!("the {n} lowest modes\n")),
        ModeSelection::Building => {
            let pct = BUILDING_MODE_MASS_RATIO * 100.0;
            out.push_str(&format!(
                "the building's modes: the {n} lowest with at least {pct} % effective mass \
                 along X, Y or in torsion{} (--lowest: every mode)\n",
                if n < modes {
                    format!(" (asked for {modes}, found {n})")
                } else {
                    String::new()
                }
            ));
            let b = skipped.mass_ratio_bound;
            let ranges = skipped_ranges(&modal.index);
            let where_: Vec<String> = ranges
                .iter()
                .map(|&(a, z, k)| {
                    let span = if a == z {
                        format!("{a}")
                    } else {
                        format!("{a}–{z}")
                    };
                    // k: the listed mode right above the range; the one below, if any.
                    let upper = format!("{:.5} s", modal.periods[k]);
                    if k == 0 {
                        format!("{span} (T > {upper})")
                    } else {
                        format!("{span} ({upper} < T < {:.5} s)", modal.periods[k - 1])
                    }
                })
                .collect();
            out.push_str(&format!(
                "skipped: {} modes{}{}\n",
                skipped.count,
                if where_.is_empty() {
                    String::new()
                } else {
                    format!(", index {}", where_.join(", "))
                },
                if skipped.count == 0 {
                    String::new()
                } else {
                    format!(
                        "; together at most X {:.4}, Y {:.4}, torsion {:.4} of the effective \
                         mass{}",
                        b[0],
                        b[1],
                        b[2],
                        if b.iter().all(|&x| x < BUILDING_MODE_MASS_RATIO) {
                            " (none of them can be a building mode)"
                        } else {
                            ": a building mode among them is not excluded"
                        }
                    )
                }
            ));
        }
    }
    Ok(out)
}

/// The index ranges the listing skips: `(first, last, k)` with `k` the listed mode right
/// above the range, from the listed modes' indices (ascending).
fn skipped_ranges(index: &[usize]) -> Vec<(usize, usize, usize)> {
    let mut out = Vec::new();
    let mut next = 1;
    for (k, &i) in index.iter().enumerate() {
        if i > next {
            out.push((next, i - 1, k));
        }
        next = i + 1;
    }
    out
}

/// Runs `modal`.
pub fn run(args: &ModalArgs, allow_unusual: bool) -> Result<()> {
    let model = Model::load(&args.model)?;
    // No analysis of a model with nodes nothing holds can run: named before any work.
    fem2rbd::fe::build::check_unused_nodes(&model)
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.model.display()))?;
    super::plausible(&model, &args.model, allow_unusual)?;
    let selection = if args.lowest {
        ModeSelection::Lowest
    } else {
        ModeSelection::default()
    };
    print!(
        "{}",
        report(&model, args.modes, selection, args.variant, args.json)?
    );
    Ok(())
}
