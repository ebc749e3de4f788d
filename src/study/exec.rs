//! Running manifest entries: one entry in this process ([`run_one`]), and the local
//! scheduler ([`run_local`]) that keeps `jobs` entries running at once.
//!
//! **A run folder is written atomically**: every file goes into `runs/.tmp-<id>-<pid>/`,
//! which is renamed to `runs/<id>/` at the end (a previous incomplete or failed folder of
//! the same id is moved aside first and removed after); a file that cannot be written (a
//! full disk) removes the temporary folder. `status.json` says `ok` or
//! `failed` (with the error) and the wall time; it is the only file of a run folder that
//! differs between two executions of the same entry. The other files are the run's
//! outputs (`docs/scenario-format.md`, written without `wall_time_s`) and `entry.json`
//! (what was run: model, record files, scale factor and per-component PGA targets).
//!
//! **Failures stay local**: an error or a panic in an entry is recorded in its folder and
//! the others go on. The scheduler re-plans after every finished entry, so an IDA
//! sequence's next intensity starts as soon as its previous run is done; the order in which
//! entries finish does not change any entry's content (same id → same bytes), so the
//! results do not depend on `jobs`.
use super::error::{At, Result, StudyError};
use super::format::Study;
use super::plan::{Entry, Outcome, Store, STATUS_FILE};
use crate::pipeline::scenario::ComponentSpec;
use crate::pipeline::{self, Scenario, Silent};
use serde_json::json;
use std::cell::RefCell;
use std::collections::{BTreeMap, HashMap};
use std::path::Path;
use std::time::Instant;

/// The scale factor applied to every component of `entry`'s record: target PGA over the
/// record's reference PGA ([`super::format::ScaleBy`]).
pub fn scale_factor(study: &Study, entry: &Entry) -> f64 {
    entry.pga_g() / study.records[entry.record].reference_pga_g
}

/// The scenario of one entry: the base scenario with the entry's model, mode and record,
/// each component scaled by the entry's factor (its PGA target = factor × its recorded
/// PGA) and time-scaled by `records.time_scale`.
pub(crate) fn scenario_for(study: &Study, entry: &Entry, out: &Path) -> Scenario {
    let mut sc = study.base.clone();
    sc.model = study.models[entry.model].file.clone();
    sc.set_mode(entry.mode);
    sc.output = out.to_path_buf();
    let rec = &study.records[entry.record];
    let f = scale_factor(study, entry);
    sc.components = [0, 1, 2].map(|axis| {
        rec.files[axis].as_ref().map(|file| ComponentSpec {
            file: file.clone(),
            direction: crate::motion::Direction::ALL[axis],
            pga_g: rec.pga_g[axis].map(|p| p * f),
            time_scale: study.time_scale,
        })
    });
    sc
}

/// `entry.json`: what the entry runs (names and file names only, so the file does not
/// depend on where the study lives).
fn entry_json(study: &Study, entry: &Entry) -> serde_json::Value {
    let rec = &study.records[entry.record];
    let f = scale_factor(study, entry);
    let comps: Vec<serde_json::Value> = (0..3)
        .filter_map(|axis| {
            let file = rec.files[axis].as_ref()?;
            let pga = rec.pga_g[axis]?;
            Some(json!({
                "direction": AXES[axis],
                "file": file.file_name().map(|n| n.to_string_lossy().into_owned()),
                "recorded_pga_g": round6(pga),
                "target_pga_g": round6(pga * f),
            }))
        })
        .collect();
    let mut v = json!({
        "id": entry.id,
        "round": entry.round,
        "model": study.models[entry.model].name,
        "model_file": study.models[entry.model].file.file_name().map(|n| n.to_string_lossy().into_owned()),
        "record": rec.name,
        "mode": entry.mode.name(),
        "intensity_pga_g": round6(entry.pga_g()),
        "scale_by": match study.scale_by {
            super::format::ScaleBy::PgaX => "pga_x",
            super::format::ScaleBy::PgaGeomean => "pga_geomean",
        },
        "scale_factor": round6(f),
        "time_scale": study.time_scale,
        "components": comps,
    });
    if study.ensemble.members > 1 {
        let p = pipeline::ensemble::Perturbation::new(study.ensemble.seed, 1);
        v["ensemble"] = json!({
            "member": entry.member,
            "members": study.ensemble.members,
            "seed": study.ensemble.seed,
            "perturbation": if entry.member == 0 {
                json!("none (member 0)")
            } else if entry.mode == crate::pipeline::Mode::Rigid {
                json!({"kind": "ground_motion_scale", "relative_amplitude": p.ground_share})
            } else {
                json!({"kind": "handoff_velocity", "amplitude_mps": p.velocity_mps})
            },
        });
    }
    v
}

const AXES: [&str; 3] = ["X", "Y", "Z"];

/// Rounds to 6 decimals for the JSON files (fixed, platform-independent text).
fn round6(v: f64) -> f64 {
    (v * 1e6).round() / 1e6
}

/// Writes `files` as the folder `runs/<id>/` atomically (module docs).
pub(crate) fn commit_folder(store: &Store, id: &str, files: &[(String, Vec<u8>)]) -> Result<()> {
    let runs = store.runs_dir();
    std::fs::create_dir_all(&runs).at(|| format!("cannot create {}", runs.display()))?;
    let pid = std::process::id();
    let tmp = runs.join(format!(".tmp-{id}-{pid}"));
    let _registered = crate::output::interrupt::temporary(&tmp);
    if tmp.exists() {
        std::fs::remove_dir_all(&tmp)?;
    }
    std::fs::create_dir(&tmp).at(|| format!("cannot create {}", tmp.display()))?;
    let written = files.iter().try_for_each(|(name, bytes)| {
        let p = tmp.join(name);
        std::fs::write(&p, bytes)
            .and_then(|()| std::fs::File::open(&p)?.sync_all())
            .at(|| format!("cannot write {}", p.display()))
    });
    if let Err(e) = written {
        // A full disk or a failing device: the partial folder goes, the old one stays.
        let _ = std::fs::remove_dir_all(&tmp);
        return Err(e);
    }
    let dest = store.run_dir(id);
    let old = runs.join(format!(".old-{id}-{pid}"));
    let moved = dest.exists();
    // Until the old folder is gone, an interrupt puts it back or removes it
    // (crate::output::interrupt); both renames run without an interrupt between them.
    let _aside = moved.then(|| crate::output::interrupt::moved_aside(&old, &dest));
    crate::output::interrupt::critical(|| -> Result<()> {
        if moved {
            std::fs::rename(&dest, &old)
                .at(|| format!("cannot move the old {} aside", dest.display()))?;
        }
        std::fs::rename(&tmp, &dest)
            .at(|| format!("cannot rename {} to {}", tmp.display(), dest.display()))?;
        Ok(())
    })?;
    if moved {
        std::fs::remove_dir_all(&old)?;
    }
    Ok(())
}

fn status_json(id: &str, error: Option<&str>, wall_s: f64) -> Vec<u8> {
    let v = match error {
        None => json!({"id": id, "status": "ok", "wall_s": round6(wall_s)}),
        Some(e) => json!({"id": id, "status": "failed", "error": e, "wall_s": round6(wall_s)}),
    };
    (serde_json::to_string_pretty(&v).expect("json") + "\n").into_bytes()
}

/// Records `entry` as failed with `error` (its folder holds `entry.json` and
/// `status.json`).
pub(crate) fn record_failure(
    study: &Study,
    store: &Store,
    entry: &Entry,
    error: &str,
) -> Result<()> {
    let files = vec![
        (
            "entry.json".to_string(),
            (serde_json::to_string_pretty(&entry_json(study, entry))? + "\n").into_bytes(),
        ),
        (
            STATUS_FILE.to_string(),
            status_json(&entry.id, Some(error), 0.0),
        ),
    ];
    commit_folder(store, &entry.id, &files)
}

/// Runs one entry in this process and writes its folder; an error or panic of the run is
/// recorded as a failure (returned as [`Outcome::Failed`]); `Err` only when the folder
/// cannot be written.
pub fn run_one(study: &Study, store: &Store, entry: &Entry) -> Result<Outcome> {
    let t0 = Instant::now();
    let out = store.run_dir(&entry.id);
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let sc = scenario_for(study, entry, &out);
        // Ensemble member m ≥ 1: the ruin stage's start perturbed as `run --ensemble`
        // (pipeline::ensemble); member 0 is the plain run.
        let p = (entry.member > 0).then(|| {
            pipeline::ensemble::Perturbation::new(study.ensemble.seed, u64::from(entry.member))
        });
        let rec = pipeline::run_perturbed(&sc, &Silent, p.as_ref())?;
        let files = pipeline::write::contents(&rec, false)?;
        Ok::<_, crate::pipeline::PipelineError>((files, rec.tc_s.is_some()))
    }));
    let error = match &result {
        Ok(Ok(_)) => None,
        Ok(Err(e)) => Some(format!("{e:#}")),
        Err(p) => Some(format!(
            "panic: {}",
            p.downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| p.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "?".into())
        )),
    };
    let mut files: Vec<(String, Vec<u8>)> = Vec::new();
    let mut outcome = Outcome::Failed(error.clone().unwrap_or_default());
    if let Ok(Ok((outs, collapse))) = result {
        files.extend(outs.into_iter().map(|(n, b)| (n.to_string(), b)));
        outcome = Outcome::Ok { collapse };
    }
    files.push((
        "entry.json".into(),
        (serde_json::to_string_pretty(&entry_json(study, entry))? + "\n").into_bytes(),
    ));
    files.push((
        STATUS_FILE.into(),
        status_json(&entry.id, error.as_deref(), t0.elapsed().as_secs_f64()),
    ));
    commit_folder(store, &entry.id, &files)?;
    Ok(outcome)
}

/// Counts of a local execution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LocalSummary {
    /// Entries complete before this execution (skipped).
    pub skipped: usize,
    /// Entries run now that ended ok.
    pub ok: usize,
    /// Entries run now that failed.
    pub failed: usize,
}

/// Runs every pending entry of `study`, `jobs` at a time, re-planning after each one (IDA
/// sequences continue until they finish). `runner(entry)` runs one entry, with the
/// caller's own error type (the CLI starts `fem2rbd study run-one` in a child process);
/// if it returns an error and the entry's folder records no outcome, the failure is
/// recorded here (its `{:#}` text). `progress(done, total)` is
/// called whenever the counts change.
pub fn run_local<E: std::fmt::Display + Send>(
    study: &Study,
    store: &Store,
    jobs: usize,
    runner: &(dyn Fn(&Entry) -> std::result::Result<(), E> + Sync),
    progress: &dyn Fn(usize, usize),
) -> Result<LocalSummary> {
    let jobs = jobs.max(1);
    let cache: RefCell<HashMap<String, Outcome>> = RefCell::new(HashMap::new());
    let outcome = |id: &str| -> Option<Outcome> {
        if let Some(o) = cache.borrow().get(id) {
            return Some(o.clone());
        }
        let o = store.outcome(id)?;
        cache.borrow_mut().insert(id.to_string(), o.clone());
        Some(o)
    };
    let first = super::plan::plan(study, &outcome);
    let mut summary = LocalSummary {
        skipped: first.outcomes.iter().filter(|o| o.is_some()).count(),
        ..Default::default()
    };
    std::thread::scope(|scope| -> Result<()> {
        let (tx, rx) = std::sync::mpsc::channel::<(String, std::result::Result<(), E>)>();
        let mut running: BTreeMap<String, Entry> = BTreeMap::new();
        loop {
            let plan = super::plan::plan(study, &outcome);
            let done = plan.outcomes.iter().filter(|o| o.is_some()).count();
            progress(done, plan.entries.len());
            for e in plan.pending() {
                if running.len() >= jobs {
                    break;
                }
                if running.contains_key(&e.id) {
                    continue;
                }
                running.insert(e.id.clone(), e.clone());
                let tx = tx.clone();
                let e = e.clone();
                scope.spawn(move || {
                    let r = runner(&e);
                    let _ = tx.send((e.id.clone(), r));
                });
            }
            if running.is_empty() {
                return Ok(());
            }
            let (id, r) = rx.recv().map_err(|_| {
                StudyError::Invalid("a study worker thread ended without reporting".into())
            })?;
            let e = running.remove(&id).expect("a running entry");
            let o = match (store.outcome(&id), r) {
                (Some(o), _) => o,
                (None, Err(err)) => {
                    let msg = format!("{err:#}");
                    record_failure(study, store, &e, &msg)?;
                    Outcome::Failed(msg)
                }
                (None, Ok(())) => {
                    let msg = "the run ended without writing its folder".to_string();
                    record_failure(study, store, &e, &msg)?;
                    Outcome::Failed(msg)
                }
            };
            match &o {
                Outcome::Ok { .. } => summary.ok += 1,
                Outcome::Failed(_) => summary.failed += 1,
            }
            cache.borrow_mut().insert(id, o);
        }
    })?;
    Ok(summary)
}
