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
//! * `rescue/<model>__<mode>__<pga>g.csv` and `.json` — the rescue maps of each intensity
//!   over its runs ([`super::rescue`]); each run's `rescue.*` numbers join its ruin
//!   measures (and so `ensemble.csv`).
//!
//! Only inputs of the runs enter these files (no wall times, no paths), with fixed
//! decimals, so a study collected after a local run and after a Slurm run gives the same
//! bytes. Written atomically.
use super::error::{bail, At, Result};
use super::format::{Intensity, Study, MILLI_G};
use super::fragility::{fit_ida, fit_stripes};
use super::plan::{read_summary, Outcome, Plan, SequenceState, Store};
use crate::output::run_folder::{parse_history, RunFolder};
use crate::output::write_atomic;
use crate::pipeline::ensemble::stats_json;
use crate::plot::density::DensityGrid;
use serde_json::{json, Value};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::PathBuf;

/// One run's row.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RunRow {
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
    /// Ensemble member (0 without an ensemble).
    pub member: u32,
    /// Every ruin measure of the run by name ([`ruin_measures`]); empty without a ruin
    /// stage.
    pub measures: BTreeMap<String, f64>,
}

/// The ruin measures of a run's `summary.json` that the ensemble statistics aggregate,
/// flattened to `name → value`: every number of `ruins` (`ruins.debris_footprint_area_m2`,
/// `ruins.extent_beyond_footprint_m.max`, `ruins.floors[0].horizontal_offset_m`, …) and of
/// `connections` (`connections.broken`, …), `ruin_stage.end_s`,
/// `ruin_stage.max_speed_mps` (`ruin_stage.energy.speed.max_mps`),
/// `ruin_stage.unsettled_bodies` (their count), `tc_s`, and `floors_down.t_s` and
/// `floors_down.stories_above_whole` (1 or 0) where the run has them. Empty without a
/// ruin stage.
pub fn ruin_measures(summary: &Value) -> BTreeMap<String, f64> {
    use crate::pipeline::ensemble::flatten;
    let mut m = BTreeMap::new();
    if summary["ruin_stage"].is_null() {
        return m;
    }
    flatten("ruins", &summary["ruins"], &mut m);
    flatten("connections", &summary["connections"], &mut m);
    let rs = &summary["ruin_stage"];
    if let Some(v) = rs["end_s"].as_f64() {
        m.insert("ruin_stage.end_s".into(), v);
    }
    if let Some(v) = rs["energy"]["speed"]["max_mps"].as_f64() {
        m.insert("ruin_stage.max_speed_mps".into(), v);
    }
    if let Some(a) = rs["unsettled_bodies"].as_array() {
        m.insert("ruin_stage.unsettled_bodies".into(), a.len() as f64);
    }
    if let Some(v) = summary["tc_s"].as_f64() {
        m.insert("tc_s".into(), v);
    }
    let fd = &summary["floors_down"];
    if let (Some(t), Some(w)) = (fd["t_s"].as_f64(), fd["stories_above_whole"].as_bool()) {
        m.insert("floors_down.t_s".into(), t);
        m.insert(
            "floors_down.stories_above_whole".into(),
            f64::from(u8::from(w)),
        );
    }
    m
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
        member: e.member,
        measures: BTreeMap::new(),
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
    let text = crate::model::limits::read_regular_file(&hp)
        .at(|| format!("cannot read {}", hp.display()))?;
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
        r.measures = ruin_measures(&super::plan::read_json(&dir.join("summary.json"))?);
        r.measures.extend(super::rescue::run_measures(&dir)?);
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

/// `runs.csv` text; `ensemble`: with a `member` column after `pga_g`.
pub(crate) fn runs_csv(rows: &[RunRow], ensemble: bool) -> String {
    let mut s = format!("id,round,model,record,mode,pga_g,{}status,collapse,tc_s,tc_reason,peak_roof_drift,fe_end_s,ruin_stop,connections_broken,extent_max_m,debris_area_m2,debris_height_m,min_slab_overlap,error\n", if ensemble { "member," } else { "" });
    for r in rows {
        let ok = r.error.is_none();
        let _ = writeln!(
            s,
            "{},{},{},{},{},{:.3},{}{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.id,
            r.round,
            r.model,
            r.record,
            r.mode,
            r.pga_g,
            if ensemble {
                format!("{},", r.member)
            } else {
                String::new()
            },
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
pub(crate) fn ida_csv(rows: &[RunRow]) -> String {
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
pub(crate) fn study_json(study: &Study, plan: &Plan, rows: &[RunRow]) -> Value {
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
            // One observation per (model, record, mode, intensity): collapse is the FE
            // stage's outcome (`tc_s`), which an ensemble's members share (they perturb
            // the hand-off state or, rigid-only, have no Tc), so counting every member
            // would multiply the binomial counts without adding information. The first
            // member without an error stands for its run.
            let mut counted: BTreeSet<(usize, usize, usize, u32)> = BTreeSet::new();
            let mut by: BTreeMap<(usize, usize), BTreeMap<u32, (usize, usize)>> = BTreeMap::new();
            for (e, r) in plan.entries.iter().zip(rows) {
                if r.error.is_some()
                    || !counted.insert((e.model, e.record, mode_index(e.mode), e.milli_g))
                {
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
        rows.push(row(study, store, e, o).at(|| format!("run {}", e.id))?);
        done.entries.push(e.clone());
        done.outcomes.push(Some(o.clone()));
    }
    let dir = store.dir.join("results");
    std::fs::create_dir_all(&dir).at(|| format!("cannot create {}", dir.display()))?;
    let js = serde_json::to_string_pretty(&study_json(study, &done, &rows))? + "\n";
    let ensemble = study.ensemble.members > 1;
    let mut files = vec![
        ("runs.csv".to_string(), runs_csv(&rows, ensemble)),
        ("ida.csv".to_string(), ida_csv(&rows)),
        ("study.json".to_string(), js),
        ("manifest.tsv".to_string(), plan.manifest(study)),
    ];
    if ensemble {
        let (j, c) = ensemble_stats(study, &done, &rows);
        files.push((
            "ensemble.json".into(),
            serde_json::to_string_pretty(&j)? + "\n",
        ));
        files.push(("ensemble.csv".into(), c));
    }
    for (stem, grid) in density_grids(study, store, &done, &rows)? {
        let (j, c) = density_files(&grid);
        // Compact: one cell per array, thousands of cells.
        files.push((
            format!("density/{stem}.json"),
            serde_json::to_string(&j)? + "\n",
        ));
        files.push((format!("density/{stem}.csv"), c));
    }
    for (stem, maps) in super::rescue::rescue_maps(study, store, &done, &rows)? {
        let [(_, c), (_, j)] = <[_; 2]>::try_from(maps.files()).expect("two files");
        files.push((
            format!("rescue/{stem}.csv"),
            String::from_utf8(c).expect("UTF-8"),
        ));
        files.push((
            format!("rescue/{stem}.json"),
            String::from_utf8(j).expect("UTF-8"),
        ));
    }
    // Density and rescue files of an earlier collect that no longer has runs are removed.
    for sub in ["density", "rescue"] {
        let ddir = dir.join(sub);
        if ddir.is_dir() {
            for e in std::fs::read_dir(&ddir)?.flatten() {
                let name = format!("{sub}/{}", e.file_name().to_string_lossy());
                if !files.iter().any(|(n, _)| *n == name) {
                    std::fs::remove_file(e.path())?;
                }
            }
        }
    }
    let mut out = Vec::new();
    for (name, text) in files {
        let p = dir.join(&name);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).at(|| format!("cannot create {}", parent.display()))?;
        }
        write_atomic(&p, text.as_bytes())?;
        out.push(p);
    }
    Ok(out)
}

/// Per (model, record, mode, intensity) the statistics ([`stats_json`]) of every ruin
/// measure ([`ruin_measures`]) over its ok ensemble members: `ensemble.json` and
/// `ensemble.csv` (`model,record,mode,pga_g,measure,members,mean,std,min,max`, one row
/// per group and measure, groups in manifest order and measures by name).
pub(crate) fn ensemble_stats(study: &Study, plan: &Plan, rows: &[RunRow]) -> (Value, String) {
    type Key = (usize, usize, usize, u32);
    /// The members of a group and each ruin measure's values over them.
    type Group = (Vec<u32>, BTreeMap<String, Vec<f64>>);
    let mode_index =
        |m: crate::pipeline::Mode| study.modes.iter().position(|x| *x == m).unwrap_or(0);
    let mut groups: BTreeMap<Key, Group> = BTreeMap::new();
    for (e, r) in plan.entries.iter().zip(rows) {
        let g = groups
            .entry((e.model, e.record, mode_index(e.mode), e.milli_g))
            .or_default();
        if r.error.is_some() {
            continue;
        }
        g.0.push(e.member);
        for (k, v) in &r.measures {
            g.1.entry(k.clone()).or_default().push(*v);
        }
    }
    let mut csv = String::from("model,record,mode,pga_g,measure,members,mean,std,min,max\n");
    let mut out = Vec::new();
    for ((mi, ri, modi, g), (members, measures)) in &groups {
        let (model, record, mode) = (
            &study.models[*mi].name,
            &study.records[*ri].name,
            study.modes[*modi].name(),
        );
        let pga = *g as f64 * MILLI_G;
        let mut ms = serde_json::Map::new();
        for (k, v) in measures {
            let st = stats_json(v);
            let _ = writeln!(
                csv,
                "{model},{record},{mode},{pga:.3},{k},{},{:.6},{:.6},{:.6},{:.6}",
                v.len(),
                st["mean"].as_f64().unwrap_or(f64::NAN),
                st["std"].as_f64().unwrap_or(f64::NAN),
                st["min"].as_f64().unwrap_or(f64::NAN),
                st["max"].as_f64().unwrap_or(f64::NAN),
            );
            ms.insert(k.clone(), st);
        }
        out.push(json!({
            "model": model, "record": record, "mode": mode, "pga_g": r6(pga),
            "members_ok": members.len(),
            "measures": Value::Object(ms),
        }));
    }
    let p = crate::pipeline::ensemble::Perturbation::new(study.ensemble.seed, 1);
    (
        json!({
            "study": study.name,
            "members": study.ensemble.members,
            "seed": study.ensemble.seed,
            "member_0": "unperturbed",
            "perturbation": {
                "hybrid": {"kind": "handoff_velocity", "amplitude_mps": p.velocity_mps},
                "rigid": {"kind": "ground_motion_scale", "relative_amplitude": p.ground_share},
            },
            "groups": out,
        }),
        csv,
    )
}

/// The ok runs of a study (no error, and `keep`) grouped by (model index, the mode's
/// index in the study, intensity in milli-g), each group in plan order: the groups over
/// which the density grids and the rescue maps are formed.
pub(crate) fn intensity_groups<'a>(
    study: &Study,
    plan: &'a Plan,
    rows: &[RunRow],
    keep: impl Fn(&super::plan::Entry, &RunRow) -> bool,
) -> BTreeMap<(usize, usize, u32), Vec<&'a super::plan::Entry>> {
    let mode_index =
        |m: crate::pipeline::Mode| study.modes.iter().position(|x| *x == m).unwrap_or(0);
    let mut groups: BTreeMap<(usize, usize, u32), Vec<&super::plan::Entry>> = BTreeMap::new();
    for (e, r) in plan.entries.iter().zip(rows) {
        if r.error.is_some() || !keep(e, r) {
            continue;
        }
        groups
            .entry((e.model, mode_index(e.mode), e.milli_g))
            .or_default()
            .push(e);
    }
    groups
}

/// A density grid of one (model, mode, intensity): file stem
/// `<model>__<mode>__<pga>g` and the grid over every ok run of that intensity (all
/// records and members). Modes with a ruin stage only (not `fe`).
pub(crate) fn density_grids(
    study: &Study,
    store: &Store,
    plan: &Plan,
    rows: &[RunRow],
) -> Result<Vec<(String, StudyDensity)>> {
    let groups = intensity_groups(study, plan, rows, |e, _| {
        e.mode != crate::pipeline::Mode::Fe
    });
    let mut out = Vec::new();
    for ((mi, modi, g), entries) in groups {
        let mut grid: Option<DensityGrid> = None;
        let mut ids = Vec::new();
        for e in entries {
            let run = RunFolder::load(&store.run_dir(&e.id)).at(|| format!("run {}", e.id))?;
            grid.get_or_insert_with(|| DensityGrid::for_run(&run))
                .add(&run);
            ids.push(e.id.clone());
        }
        let Some(grid) = grid else { continue };
        let (model, mode) = (&study.models[mi].name, study.modes[modi].name());
        let stem = format!("{model}__{mode}__{}.{:03}g", g / 1000, g % 1000);
        out.push((
            stem,
            StudyDensity {
                study: study.name.clone(),
                model: model.clone(),
                mode,
                pga_g: g as f64 * MILLI_G,
                run_ids: ids,
                grid,
            },
        ));
    }
    Ok(out)
}

/// A density grid of a study intensity level with what it is over.
#[derive(Debug, Clone)]
pub struct StudyDensity {
    /// Study name.
    pub study: String,
    /// Model name.
    pub model: String,
    /// Mode.
    pub mode: &'static str,
    /// Intensity, g.
    pub pga_g: f64,
    /// The runs, manifest order.
    pub run_ids: Vec<String>,
    /// The grid.
    pub grid: DensityGrid,
}

/// `density/<stem>.json` and `.csv` of a grid: the JSON holds the grid's header (runs,
/// bodies per run, cell side, footprint, run ids) and every non-empty cell as
/// `[i, j, covered, centres]`; the CSV one row per non-empty cell
/// (`i,j,x_m,y_m,runs_covered,share,body_centres,bodies_per_m2`: the cell's lower-left
/// corner, the runs with debris over its centre and their share, the body final centres
/// in it over all runs, and those per run per m²).
pub fn density_files(d: &StudyDensity) -> (Value, String) {
    let g = &d.grid;
    let keys: std::collections::BTreeSet<(i64, i64)> =
        g.covered.keys().chain(g.centres.keys()).copied().collect();
    let c = g.cell_m;
    let mut csv = String::from("i,j,x_m,y_m,runs_covered,share,body_centres,bodies_per_m2\n");
    let mut cells = Vec::new();
    for (i, j) in keys {
        let cov = g.covered.get(&(i, j)).copied().unwrap_or(0);
        let cen = g.centres.get(&(i, j)).copied().unwrap_or(0);
        let _ = writeln!(
            csv,
            "{i},{j},{:.6},{:.6},{cov},{:.6},{cen},{:.6}",
            i as f64 * c,
            j as f64 * c,
            cov as f64 / g.runs as f64,
            cen as f64 / (g.runs as f64 * c * c)
        );
        cells.push(json!([i, j, cov, cen]));
    }
    (
        json!({
            "study": d.study,
            "model": d.model,
            "mode": d.mode,
            "pga_g": r6(d.pga_g),
            "runs": g.runs,
            "bodies_per_run": g.bodies,
            "cell_m": r6(c),
            "footprint_m": {"x": [r6(g.footprint.0[0]), r6(g.footprint.0[1])],
                            "y": [r6(g.footprint.1[0]), r6(g.footprint.1[1])]},
            "run_ids": d.run_ids,
            "cells_ijcn": "[i, j, runs with debris over the cell centre, body final centres in the cell]",
            "cells": cells,
        }),
        csv,
    )
}
