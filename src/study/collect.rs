//! `fem2rbd study collect`: checks that every run of the plan is complete and aggregates
//! the run folders into `<study>/results/`:
//!
//! * `runs.csv` — one row per run in manifest order: `id, round, model, record, mode,
//!   pga_g, status, collapse, tc_s, tc_reason, peak_roof_drift, fe_end_s, ruin_stop,
//!   connections_broken, extent_max_m, debris_area_m2, debris_height_m, min_slab_overlap,
//!   error`. `peak_roof_drift` is the largest |roof drift| of `history.csv`'s FE frames up
//!   to Tc (the whole FE stage without collapse): horizontal roof-centroid displacement
//!   relative to the ground over the roof height (`src/output/history.rs`), sampled at
//!   25 fps. Ruin measures come from `summary.json` (`docs/scenario-format.md`) and are
//!   empty without a ruin stage; `error` is the failure message on one line.
//! * `ida.csv` — the IDA curves: ok runs sorted by (model, mode, record, pga_g) with
//!   `peak_roof_drift` and `collapse`.
//! * `study.json` — counts, each IDA sequence's result (collapse bracket or censoring) and
//!   the collapse fragility per (model, mode) ([`super::fragility`]).
//!
//! Only inputs of the runs enter these files (no wall times, no paths), with fixed
//! decimals, so a study collected after a local run and after a Slurm run gives the same
//! bytes. Written atomically.
use super::format::{Intensity, Study, MILLI_G};
use super::fragility::{fit_ida, fit_stripes};
use super::plan::{read_summary, Outcome, Plan, SequenceState, Store};
use crate::output::run_folder::parse_history;
use crate::output::write_atomic;
use anyhow::{bail, Context, Result};
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::PathBuf;

/// One run's row.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRow {
    /// Run id.
    pub id: String,
    /// IDA round.
    pub round: u32,
    /// Model name.
    pub model: String,
    /// Record name.
    pub record: String,
    /// Mode name.
    pub mode: &'static str,
    /// Intensity, g.
    pub pga_g: f64,
    /// Ok (else failed; the message).
    pub error: Option<String>,
    /// Collapse (Tc exists).
    pub collapse: bool,
    /// Tc, s.
    pub tc_s: Option<f64>,
    /// `tc_reason`.
    pub tc_reason: String,
    /// Peak |roof drift| over the FE frames up to Tc.
    pub peak_roof_drift: Option<f64>,
    /// FE end, s.
    pub fe_end_s: Option<f64>,
    /// Ruin stage stop reason.
    pub ruin_stop: Option<String>,
    /// Broken connections at the end.
    pub broken: Option<u64>,
    /// Debris extent beyond the footprint, m.
    pub extent_max_m: Option<f64>,
    /// Debris plan area, m².
    pub debris_area_m2: Option<f64>,
    /// Debris height, m.
    pub debris_height_m: Option<f64>,
    /// Smallest slab overlap ratio.
    pub min_slab_overlap: Option<f64>,
}

fn opt(v: Option<f64>, d: usize) -> String {
    v.map_or(String::new(), |v| format!("{v:.d$}"))
}

/// Reads one run folder into its row.
fn row(study: &Study, store: &Store, e: &super::plan::Entry, o: &Outcome) -> Result<RunRow> {
    let mut r = RunRow {
        id: e.id.clone(),
        round: e.round,
        model: study.models[e.model].name.clone(),
        record: study.records[e.record].name.clone(),
        mode: e.mode.name(),
        pga_g: e.pga_g(),
        error: None,
        collapse: false,
        tc_s: None,
        tc_reason: String::new(),
        peak_roof_drift: None,
        fe_end_s: None,
        ruin_stop: None,
        broken: None,
        extent_max_m: None,
        debris_area_m2: None,
        debris_height_m: None,
        min_slab_overlap: None,
    };
    if let Outcome::Failed(msg) = o {
        r.error = Some(msg.clone());
        return Ok(r);
    }
    let dir = store.run_dir(&e.id);
    let s = read_summary(&dir.join("summary.json"))?;
    r.tc_s = s.tc_s;
    r.collapse = r.tc_s.is_some();
    r.tc_reason = s.tc_reason.name().to_string();
    r.fe_end_s = s.fe_end_s;
    let hp = dir.join("history.csv");
    let text =
        std::fs::read_to_string(&hp).with_context(|| format!("cannot read {}", hp.display()))?;
    let hist = parse_history(&text, &hp.display().to_string())?;
    let until = r.tc_s.unwrap_or(f64::INFINITY) + 1e-9;
    r.peak_roof_drift = hist
        .iter()
        .filter(|h| h.fe && h.t_s <= until)
        .filter_map(|h| h.roof_drift)
        .map(f64::abs)
        .reduce(f64::max);
    if let Some(stage) = &s.ruin_stage {
        let finite = |x: f64| Some(x).filter(|x| x.is_finite());
        r.ruin_stop = Some(stage.stop.name().to_owned());
        r.broken = s.connections.map(|c| c.broken as u64);
        r.extent_max_m = finite(s.ruins.extent_beyond_footprint_m.max);
        r.debris_area_m2 = finite(s.ruins.debris_footprint_area_m2);
        r.debris_height_m = finite(s.ruins.max_debris_height_m);
        r.min_slab_overlap = s
            .ruins
            .slab_overlap
            .iter()
            .map(|o| o.overlap_ratio)
            .reduce(f64::min);
    }
    Ok(r)
}

/// CSV field: quoted if it has a comma, quote or newline.
fn field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// `runs.csv` text.
pub fn runs_csv(rows: &[RunRow]) -> String {
    let mut s = String::from("id,round,model,record,mode,pga_g,status,collapse,tc_s,tc_reason,peak_roof_drift,fe_end_s,ruin_stop,connections_broken,extent_max_m,debris_area_m2,debris_height_m,min_slab_overlap,error\n");
    for r in rows {
        let ok = r.error.is_none();
        let _ = writeln!(
            s,
            "{},{},{},{},{},{:.3},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.id,
            r.round,
            r.model,
            r.record,
            r.mode,
            r.pga_g,
            if ok { "ok" } else { "failed" },
            if ok {
                if r.collapse {
                    "1"
                } else {
                    "0"
                }
            } else {
                ""
            },
            opt(r.tc_s, 4),
            r.tc_reason,
            opt(r.peak_roof_drift, 6),
            opt(r.fe_end_s, 4),
            r.ruin_stop.clone().unwrap_or_default(),
            r.broken.map_or(String::new(), |b| b.to_string()),
            opt(r.extent_max_m, 4),
            opt(r.debris_area_m2, 4),
            opt(r.debris_height_m, 4),
            opt(r.min_slab_overlap, 4),
            field(&r.error.as_deref().unwrap_or("").replace('\n', " ")),
        );
    }
    s
}

/// `ida.csv` text: ok runs by (model, mode, record, pga).
pub fn ida_csv(rows: &[RunRow]) -> String {
    let mut ok: Vec<&RunRow> = rows.iter().filter(|r| r.error.is_none()).collect();
    ok.sort_by(|a, b| {
        (&a.model, a.mode, &a.record)
            .cmp(&(&b.model, b.mode, &b.record))
            .then(a.pga_g.total_cmp(&b.pga_g))
    });
    let mut s = String::from("model,mode,record,pga_g,peak_roof_drift,collapse\n");
    for r in ok {
        let _ = writeln!(
            s,
            "{},{},{},{:.3},{},{}",
            r.model,
            r.mode,
            r.record,
            r.pga_g,
            opt(r.peak_roof_drift, 6),
            u8::from(r.collapse)
        );
    }
    s
}

fn r6(v: f64) -> Value {
    json!((v * 1e6).round() / 1e6)
}

/// The `study.json` value.
pub fn study_json(study: &Study, plan: &Plan, rows: &[RunRow]) -> Value {
    let failed = rows.iter().filter(|r| r.error.is_some()).count();
    let mut groups: BTreeMap<(usize, usize), Vec<Value>> = BTreeMap::new();
    let mut fits = Vec::new();
    let mode_index =
        |m: crate::pipeline::Mode| study.modes.iter().position(|x| *x == m).unwrap_or(0);
    match &study.intensity {
        Intensity::Ida(_) => {
            for sq in &plan.sequences {
                let (state, lo, hi) = match sq.state {
                    SequenceState::Collapse { lo, hi } => ("collapse", Some(lo), Some(hi)),
                    SequenceState::NoCollapse { max } => ("no_collapse", Some(max), None),
                    SequenceState::Failed => ("failed", None, None),
                    SequenceState::Running => ("running", None, None),
                };
                let g = |m: Option<u32>| m.map_or(Value::Null, |m| r6(m as f64 * MILLI_G));
                groups
                    .entry((sq.model, mode_index(sq.mode)))
                    .or_default()
                    .push(json!({
                        "record": study.records[sq.record].name,
                        "state": state,
                        "collapse_g": if state == "collapse" { g(hi) } else { Value::Null },
                        "highest_without_collapse_g": if state == "collapse" { g(lo) } else { Value::Null },
                        "censored_at_g": if state == "no_collapse" { g(lo) } else { Value::Null },
                    }));
            }
            for ((mi, modi), seqs) in &groups {
                let collapse: Vec<f64> = seqs
                    .iter()
                    .filter_map(|s| s["collapse_g"].as_f64())
                    .collect();
                let censored: Vec<f64> = seqs
                    .iter()
                    .filter_map(|s| s["censored_at_g"].as_f64())
                    .collect();
                let fit = fit_ida(&collapse, &censored);
                fits.push(fit_json(
                    study,
                    *mi,
                    *modi,
                    "ida_lognormal_mle_censored",
                    collapse.len(),
                    censored.len(),
                    fit,
                    seqs.clone(),
                ));
            }
        }
        Intensity::Stripes(_) => {
            let mut by: BTreeMap<(usize, usize), BTreeMap<u32, (usize, usize)>> = BTreeMap::new();
            for (e, r) in plan.entries.iter().zip(rows) {
                if r.error.is_some() {
                    continue;
                }
                let c = by
                    .entry((e.model, mode_index(e.mode)))
                    .or_default()
                    .entry(e.milli_g)
                    .or_default();
                c.0 += 1;
                c.1 += usize::from(r.collapse);
            }
            for ((mi, modi), st) in &by {
                let data: Vec<(f64, usize, usize)> = st
                    .iter()
                    .map(|(m, (n, z))| (*m as f64 * MILLI_G, *n, *z))
                    .collect();
                let stripes: Vec<Value> = data
                    .iter()
                    .map(|(x, n, z)| json!({"pga_g": r6(*x), "runs": n, "collapses": z}))
                    .collect();
                let n: usize = data.iter().map(|d| d.1).sum();
                let z: usize = data.iter().map(|d| d.2).sum();
                fits.push(fit_json(
                    study,
                    *mi,
                    *modi,
                    "stripes_lognormal_mle_binomial",
                    z,
                    n - z,
                    fit_stripes(&data),
                    stripes,
                ));
            }
        }
    }
    json!({
        "study": study.name,
        "intensity_measure": match study.scale_by {
            super::format::ScaleBy::PgaX => "pga_x",
            super::format::ScaleBy::PgaGeomean => "pga_geomean",
        },
        "runs": rows.len(),
        "failed": failed,
        "fragility": fits,
    })
}

#[allow(clippy::too_many_arguments)]
fn fit_json(
    study: &Study,
    model: usize,
    mode: usize,
    method: &str,
    collapses: usize,
    others: usize,
    fit: Result<super::fragility::Fit>,
    data: Vec<Value>,
) -> Value {
    let (fit, err) = match fit {
        Ok(f) => (
            json!({"median_g": r6(f.median_g), "beta": r6(f.beta), "log_likelihood": r6(f.log_likelihood)}),
            Value::Null,
        ),
        Err(e) => (Value::Null, json!(format!("{e:#}"))),
    };
    json!({
        "model": study.models[model].name,
        "mode": study.modes[mode].name(),
        "method": method,
        "collapses": collapses,
        "non_collapses": others,
        "fit": fit,
        "fit_error": err,
        "data": data,
    })
}

/// Collects (module docs); with `partial`, pending runs are left out instead of being an
/// error. Returns the files written.
pub fn collect(study: &Study, store: &Store, partial: bool) -> Result<Vec<PathBuf>> {
    let plan = store.plan(study);
    let pending: Vec<&str> = plan.pending().map(|e| e.id.as_str()).collect();
    if !pending.is_empty() && !partial {
        let more = if pending.len() > 10 {
            format!(" and {} more", pending.len() - 10)
        } else {
            String::new()
        };
        bail!(
            "{}: the study is not complete: {} run(s) pending: {}{more} (run them, or collect with --partial)",
            store.dir.display(),
            pending.len(),
            pending[..pending.len().min(10)].join(", ")
        );
    }
    let mut rows = Vec::new();
    let mut done = plan.clone();
    done.entries.clear();
    done.outcomes.clear();
    for (e, o) in plan.entries.iter().zip(&plan.outcomes) {
        let Some(o) = o else { continue };
        rows.push(row(study, store, e, o).with_context(|| format!("run {}", e.id))?);
        done.entries.push(e.clone());
        done.outcomes.push(Some(o.clone()));
    }
    let dir = store.dir.join("results");
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let js = serde_json::to_string_pretty(&study_json(study, &done, &rows))? + "\n";
    let files = [
        ("runs.csv", runs_csv(&rows)),
        ("ida.csv", ida_csv(&rows)),
        ("study.json", js),
        ("manifest.tsv", plan.manifest(study)),
    ];
    let mut out = Vec::new();
    for (name, text) in files {
        let p = dir.join(name);
        write_atomic(&p, text.as_bytes())?;
        out.push(p);
    }
    Ok(out)
}
