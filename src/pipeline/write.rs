//! Writes a run's outputs as one folder, replaced as a whole (built beside the target,
//! then swapped in: [`crate::output::location`]):
//! `ruins.csv`, `keyframes.csv`, `history.csv`, `bodies.csv`, `connections.csv` (when a
//! ruin stage ran), `summary.json` and `collapse.glb` (formats: `docs/scenario-format.md`,
//! [`crate::output::history`]). Formatting is fixed (decimals, key order), so the
//! same input gives the same bytes; only `summary.json`'s `wall_time_s` differs between
//! runs (left out with `timing = false`).
use super::error::{PipelineError, Result};
use super::{RunRecord, TcReason};
use crate::bullet::Pose;
use crate::measure::{
    energy_summary, first_contact, floors_down, instantaneous_at_end, ruin_measures, unsettled,
};
use crate::output::csv_text::field;
use crate::output::gltf::{encode_glb, run_scene};
use crate::output::history::{bodies_csv, history_csv, BodyRow, EnergyRow, HistoryFrame};
use crate::output::keyframes::keyframes_csv;
use crate::output::location::FolderKind;
use crate::output::ruins::{ruins_csv, RuinRow};
use crate::output::run_folder::RunFolderError;
use crate::output::run_folder::{
    check_history_times, parse_bodies, parse_history, parse_keyframes,
};
use crate::output::summary::{
    r6, ConnectionCounts, FeFirstContact, FloorsDown, RemovedElementSummary, RuinMeasures,
    RuinStageSummary, RunSummary, TcKind, WallTimes,
};
use crate::output::AnimationError;
use crate::ruin::connection::ConnectionState;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The file contents of a run, in writing order (name, bytes).
pub fn contents(rec: &RunRecord, timing: bool) -> Result<Vec<(&'static str, Vec<u8>)>> {
    let mut out: Vec<(&'static str, Vec<u8>)> = Vec::new();
    let at_rest = rec.ruin.as_ref().map(|r| &r.at_rest);
    let rows: Vec<RuinRow> = rec
        .bodies
        .iter()
        .enumerate()
        .map(|(i, b)| RuinRow {
            id: &b.id,
            pose: rec.final_poses[i],
            at_rest: at_rest.map(|a| a[i]),
        })
        .collect();
    out.push(("ruins.csv", ruins_csv(&rows).into_bytes()));
    let frames = timeline(rec);
    let names: Vec<String> = rec.bodies.iter().map(|b| b.id.name()).collect();
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let keyframes_text = keyframes_csv(&names, &frames);
    let body_rows = body_rows(rec);
    let history_text = history_csv(&body_rows, &history_frames(rec, &frames));
    let bodies_text = bodies_csv(&body_rows);
    out.push(("keyframes.csv", keyframes_text.into_bytes()));
    out.push(("history.csv", history_text.into_bytes()));
    out.push(("bodies.csv", bodies_text.into_bytes()));
    if let Some(r) = &rec.ruin {
        let mut s = String::from(
            "a,b,start_state,final_state,time_broken_s,time_plastic_s,first_row_lost,time_first_row_lost_s\n",
        );
        let st = |c: ConnectionState| match c {
            ConnectionState::Elastic => "intact",
            ConnectionState::Plastic => "plastic",
            ConnectionState::Broken => "broken",
        };
        let time = |t: Option<f64>| t.map_or(String::new(), |t| format!("{t:.4}"));
        for c in &r.connections {
            let _ = writeln!(
                s,
                "{},{},{},{},{},{},{},{}",
                field(&rec.bodies[c.a].id.name()),
                field(&rec.bodies[c.b].id.name()),
                st(c.start_state),
                st(c.state),
                time(c.broke_at_s),
                time(c.plastic_at_s),
                c.first_row_lost.map_or("", |(r, _)| r.name()),
                time(c.first_row_lost.map(|(_, t)| t)),
            );
        }
        out.push(("connections.csv", s.into_bytes()));
    }
    let js = run_summary(rec, timing).to_json()?;
    out.push(("summary.json", js.into_bytes()));
    let glb_at = out.len();
    if rec.ruin.is_some() {
        let (rescue, section) =
            rescue_files(&out, rec.scale).map_err(|e| PipelineError::Rescue(Box::new(e)))?;
        let summary = out
            .iter_mut()
            .find(|f| f.0 == "summary.json")
            .expect("summary.json is written above");
        let text = std::str::from_utf8(&summary.1).expect("summary.json is UTF-8");
        let mut text = crate::rescue::report::with_summary_section(text, section)?;
        if let Some(p) = rec.preset {
            // The preset of the ruin stage's settings (`[physics] preset`, resolved).
            let mut v: serde_json::Value = serde_json::from_str(&text)?;
            if let Some(o) = v.as_object_mut() {
                o.insert("preset".into(), p.name().into());
            }
            text = serde_json::to_string_pretty(&v)? + "\n";
        }
        summary.1 = text.into_bytes();
        out.extend(rescue);
    }
    // collapse.glb last: it holds the survivable voids of voids.json.
    let text = |name: &str| {
        out.iter()
            .find(|f| f.0 == name)
            .map(|f| std::str::from_utf8(&f.1).expect("the run's own text files are UTF-8"))
    };
    let glb = glb(
        text("bodies.csv").unwrap_or(""),
        text("keyframes.csv").unwrap_or(""),
        text("history.csv").unwrap_or(""),
        text("voids.json"),
    )
    .map_err(|e| match e {
        GlbError::Tables(e) => PipelineError::OwnTables(Box::new(e)),
        GlbError::Scene(e) => PipelineError::OwnScene(Box::new(e)),
    })?;
    out.insert(glb_at, ("collapse.glb", glb));
    Ok(out)
}

/// Files by name, in writing order.
type NamedFiles = Vec<(&'static str, Vec<u8>)>;

/// The rescue analysis files (`crate::rescue`, default sizes) of a run's own tables,
/// read back from their text as `fem2rbd voids` reads them, so both give the same bytes,
/// and the `rescue` section of `summary.json` ([`crate::rescue::Analysis::summary`]).
fn rescue_files(
    files: &[(&'static str, Vec<u8>)],
    scale: f64,
) -> crate::rescue::Result<(NamedFiles, serde_json::Value)> {
    let text = |name: &str| {
        files
            .iter()
            .find(|f| f.0 == name)
            .map_or("", |f| std::str::from_utf8(&f.1).unwrap_or(""))
    };
    let ruin = crate::rescue::Ruin::from_texts(
        text("bodies.csv"),
        "bodies.csv",
        text("ruins.csv"),
        "ruins.csv",
        text("connections.csv"),
        "connections.csv",
        scale,
    )?;
    match crate::rescue::analyse(&ruin, crate::rescue::Sizes::default()) {
        Ok(a) => Ok((a.files(), a.summary())),
        // Debris thrown far makes the default grid too large: the run keeps its ruin and
        // says so in voids.json and summary.json (`fem2rbd voids --cell` analyses it with
        // larger cells).
        Err(e @ crate::rescue::RescueError::GridTooLarge { .. }) => {
            let js = serde_json::json!({ "error": e.to_string() });
            let text = serde_json::to_string_pretty(&js).expect("a JSON value") + "\n";
            Ok((
                vec![(crate::rescue::report::FILES[1], text.into_bytes())],
                js,
            ))
        }
        Err(e) => Err(e),
    }
}

/// The ruin measures of a record (`summary.json` `ruins`): its bodies at their final
/// poses, against the ground's height at the end of the timeline.
pub(crate) fn record_measures(rec: &RunRecord) -> RuinMeasures {
    let t_end = rec
        .ruin
        .as_ref()
        .map(|r| r.end_time_s)
        .or(rec.fe_end_s)
        .unwrap_or(0.0);
    let ground_z = rec.ground.ground_state_at(t_end).0[2];
    ruin_measures(&rec.bodies, &rec.final_poses, ground_z)
}

/// An FE-only run's `fe_first_contact` ([`first_contact`] over its FE keyframes); `None`
/// when a ruin stage ran.
fn fe_first_contact(rec: &RunRecord) -> Option<FeFirstContact> {
    if rec.ruin.is_some() {
        return None;
    }
    // Without a ruin stage the timeline is the FE keyframes.
    let fe = timeline(rec);
    let (k, detail) = first_contact(&rec.bodies, &fe)?;
    let (t, poses) = fe[k];
    let ground_z = rec.ground.ground_state_at(t).0[2];
    Some(FeFirstContact {
        t_s: r6(t),
        detail,
        ruins: ruin_measures(&rec.bodies, poses, ground_z),
    })
}

/// A run's `floors_down` ([`floors_down`] over its timeline).
pub(crate) fn floors_down_of(rec: &RunRecord) -> Option<FloorsDown> {
    floors_down(&rec.bodies, &timeline(rec))
}

/// The run's `summary.json` ([`RunSummary`]). `timing` = include the wall times (not
/// byte-stable).
pub fn run_summary(rec: &RunRecord, timing: bool) -> RunSummary {
    let (reason, detail) = match &rec.tc_reason {
        TcReason::Criterion(s) => (TcKind::Criterion, s.clone()),
        TcReason::Diverged(s) => (TcKind::FeDiverged, s.clone()),
        TcReason::NoCollapse => (
            TcKind::NoCollapse,
            format!(
                "the criterion was not met before the FE stage ended at t = {:.4} s",
                rec.fe_end_s.unwrap_or(0.0)
            ),
        ),
        TcReason::RigidOnly => (
            TcKind::RigidOnly,
            "no FE stage; the ruin stage starts at t = 0".into(),
        ),
    };
    let mut connections = None;
    let ruin_stage = rec.ruin.as_ref().map(|r| {
        let mut counts = [0usize; 3];
        for c in &r.connections {
            counts[match c.state {
                ConnectionState::Elastic => 0,
                ConnectionState::Plastic => 1,
                ConnectionState::Broken => 2,
            }] += 1;
        }
        connections = Some(ConnectionCounts {
            total: r.connections.len(),
            intact: counts[0],
            plastic: counts[1],
            broken: counts[2],
        });
        RuinStageSummary {
            start_s: r6(rec.tc_s.unwrap_or(0.0)),
            end_s: r6(r.end_time_s),
            stop: r.stop,
            frames: r.frames.len(),
            bodies_at_rest: r.at_rest.iter().filter(|b| **b).count(),
            first_frame_penetration_m: r6(r.first_frame_penetration_m),
            max_penetration_m: r6(r.max_penetration_m),
            energy: energy_summary(&rec.bodies, &rec.ground, r),
            unsettled_bodies: unsettled(&rec.bodies, r),
            rest_speed: Some(r.ledger.rest_speed),
            instantaneous_at_end: instantaneous_at_end(&rec.bodies, r),
        }
    });
    let wall_time_s = timing.then(|| {
        let fe = rec.fe_wall.as_secs_f64();
        let ph = rec.ruin_wall.as_secs_f64();
        let share = if ph > 0.0 {
            rec.ruin_in_bullet.as_secs_f64() / ph
        } else {
            0.0
        };
        WallTimes {
            fe,
            ruin: ph,
            ruin_in_bullet: rec.ruin_in_bullet.as_secs_f64(),
            ruin_bullet_share: share,
        }
    });
    RunSummary {
        mode: rec.mode,
        tc_s: rec.tc_s.map(r6),
        tc_reason: reason,
        tc_detail: detail,
        fe_end_s: rec.fe_end_s.map(r6),
        fe_removed_elements: rec
            .fe_removed
            .iter()
            .map(|r| RemovedElementSummary {
                element: r.element,
                t_s: r6(r.time),
                reason: r.reason.clone(),
            })
            .collect(),
        scale: Some(rec.scale),
        bodies: rec.bodies.iter().filter(|b| !b.passive).count(),
        foundation_blocks: rec.bodies.iter().filter(|b| b.passive).count(),
        keyframes_fe: rec.fe_frames.len(),
        ruin_stage,
        connections,
        ruins: record_measures(rec),
        fe_first_contact: fe_first_contact(rec),
        floors_down: floors_down_of(rec),
        wall_time_s,
        unusual_values: rec.unusual.clone(),
    }
}

/// The one timeline: FE keyframes up to Tc, then the ruin stage's frames after the last
/// FE keyframe (the record's poses, borrowed).
pub fn timeline(rec: &RunRecord) -> Vec<(f64, &[Pose])> {
    let mut frames: Vec<(f64, &[Pose])> = rec
        .fe_frames
        .iter()
        .map(|(t, p)| (*t, p.as_slice()))
        .collect();
    let last = frames.last().map_or(f64::NEG_INFINITY, |f| f.0);
    if let Some(r) = &rec.ruin {
        for f in &r.frames {
            if f.time_s > last + 1e-6 {
                frames.push((f.time_s, f.poses.as_slice()));
            }
        }
    }
    frames
}

/// The `bodies.csv` rows of a run.
fn body_rows(rec: &RunRecord) -> Vec<BodyRow<'_>> {
    rec.bodies.iter().map(BodyRow::from).collect()
}

/// The timeline's frames with their stage, connection counts and ground displacement.
fn history_frames<'a>(rec: &RunRecord, frames: &[(f64, &'a [Pose])]) -> Vec<HistoryFrame<'a>> {
    let n_fe = rec.fe_frames.len();
    // [`timeline`] appends the ruin frames after the last FE keyframe in order, skipping
    // those not later than it; the first appended one is at index `skip`.
    let start_energy = rec
        .ruin
        .as_ref()
        .and_then(|r| r.frames.first())
        .map(|f| f.energy)
        .unwrap_or_default();
    let ruin = rec.ruin.as_ref().map(|r| {
        let skip = r.frames.len() - (frames.len() - n_fe);
        &r.frames[skip..]
    });
    frames
        .iter()
        .enumerate()
        .map(|(k, (t, poses))| {
            let frame = ruin.filter(|_| k >= n_fe).map(|r| {
                let f = &r[k - n_fe];
                debug_assert!((f.time_s - t).abs() < 1e-9);
                f
            });
            let counts = frame.map(|f| (f.counts.elastic, f.counts.plastic, f.counts.broken));
            let energy = frame.map(|f| {
                let e = &f.energy;
                EnergyRow {
                    kinetic_j: e.kinetic_translational_j,
                    rotational_j: e.kinetic_rotational_j,
                    potential_j: e.potential_j,
                    ground_work_j: e.ground_work_j,
                    damping_j: e.damping_j,
                    dissipated_j: e.dissipated_j(&start_energy),
                    injected_j: e.injected_j,
                }
            });
            HistoryFrame {
                t_s: *t,
                fe: k < n_fe,
                poses,
                counts,
                ground_m: rec.ground.ground_state_at(*t).0,
                energy,
            }
        })
        .collect()
}

/// `collapse.glb`, built from the run's own `bodies.csv`, `keyframes.csv` and
/// `history.csv` texts read back with [`crate::output::run_folder`]'s parsers, and the
/// survivable voids of its `voids.json` ([`crate::rescue::volumes`]): the file is a
/// function of those four files alone, so `fem2rbd export gltf` on the run folder writes
/// the same bytes. (The positions therefore carry the CSVs' 6 decimals, 0.5 µm,
/// about the `f32` resolution of glTF at a few metres.)
fn glb(
    bodies: &str,
    keyframes: &str,
    history: &str,
    voids: Option<&str>,
) -> std::result::Result<Vec<u8>, GlbError> {
    let bodies = parse_bodies(bodies, "bodies.csv")?;
    let frames = parse_keyframes(keyframes, "keyframes.csv", &bodies)?;
    let history = parse_history(history, "history.csv")?;
    check_history_times(&history, &frames, "history.csv", "keyframes.csv")?;
    let ground: Vec<[f64; 3]> = history.iter().map(|h| h.ground_m).collect();
    let mut scene = run_scene(&bodies, &frames, &ground)?;
    if let Some(text) = voids {
        scene.voids = crate::rescue::volumes::survivable_volumes(text)
            .map_err(|e| AnimationError::Scene(format!("voids.json: {e}")))?;
        scene.routes = crate::rescue::volumes::route_lines(text)
            .map_err(|e| AnimationError::Scene(format!("voids.json: {e}")))?;
    }
    Ok(encode_glb(&scene)?)
}

/// Why [`glb`] failed: reading the tables back, or the scene (with the voids).
#[derive(Debug, thiserror::Error)]
enum GlbError {
    /// A table cannot be read back.
    #[error(transparent)]
    Tables(#[from] RunFolderError),
    /// The scene cannot be built or encoded, or `voids.json` cannot be read.
    #[error(transparent)]
    Scene(#[from] AnimationError),
}

/// A run folder: the files [`contents`] writes, and what other commands add to it
/// (`plot`'s `plots/`, `export vtk`'s `vtk/`). An existing folder is replaced only when it
/// is such a folder and holds nothing else ([`crate::output::location::check_replaceable`]).
pub const RUN_FOLDER: FolderKind = FolderKind {
    name: "run",
    owns: &[
        "ruins.csv",
        "keyframes.csv",
        "history.csv",
        "bodies.csv",
        "connections.csv",
        "summary.json",
        "collapse.glb",
        "voids.csv",
        "voids.json",
        "rubble_height.csv",
        "report.html",
        "plots",
        "vtk",
    ],
};

/// Writes the outputs as the whole content of `dir`: built beside it and swapped in, so
/// the folder holds this run's files and nothing of an earlier run
/// ([`crate::output::location::replace_dir`]); returns the paths written.
pub fn write(rec: &RunRecord, dir: &Path, timing: bool) -> Result<Vec<PathBuf>> {
    let files = contents(rec, timing)?;
    let refs: Vec<(&str, &[u8])> = files.iter().map(|(n, b)| (*n, b.as_slice())).collect();
    crate::output::location::replace_dir(dir, &RUN_FOLDER, &refs).map_err(|error| {
        PipelineError::RunFolder {
            path: dir.to_path_buf(),
            error: Box::new(error),
        }
    })
}
