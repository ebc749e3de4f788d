//! Writes a run's outputs into its folder, each file atomically (temp name, then rename):
//! `ruins.csv`, `keyframes.csv`, `history.csv`, `bodies.csv`, `connections.csv` (when a
//! ruin stage ran), `summary.json` and `collapse.glb` (formats: `docs/scenario-format.md`,
//! [`crate::output::history`]). Formatting is fixed (decimals, key order), so the
//! same input gives the same bytes; only `summary.json`'s `wall_time_s` differs between
//! runs (left out with `timing = false`).
use super::RunRecord;
use crate::output::gltf::{encode_glb, AnimBody, AnimatedScene, GroundBox};
use crate::output::history::{bodies_csv, history_csv, BodyRow, HistoryFrame};
use crate::output::keyframes::keyframes_csv;
use crate::output::ruins::{ruins_csv, RuinRow};
use crate::output::summary::summary;
use crate::output::write_atomic;
use crate::physics::Pose;
use crate::ruin::connection::ConnectionState;
use anyhow::{Context, Result};
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
            name: &b.name,
            group: &b.group,
            type_name: &b.type_name,
            material: &b.material,
            element: &b.element,
            pose: rec.final_poses[i],
            at_rest: at_rest.map(|a| a[i]),
        })
        .collect();
    out.push(("ruins.csv", ruins_csv(&rows).into_bytes()));
    let frames = timeline(rec);
    let names: Vec<&str> = rec.bodies.iter().map(|b| b.name.as_str()).collect();
    let fr: Vec<(f64, &[Pose])> = frames.iter().map(|(t, p)| (*t, p.as_slice())).collect();
    out.push(("keyframes.csv", keyframes_csv(&names, &fr).into_bytes()));
    let body_rows = body_rows(rec);
    out.push((
        "history.csv",
        history_csv(&body_rows, &history_frames(rec, &frames)).into_bytes(),
    ));
    out.push(("bodies.csv", bodies_csv(&body_rows).into_bytes()));
    if let Some(r) = &rec.ruin {
        let mut s = String::from("a,b,start_state,final_state,time_broken_s\n");
        let st = |c: ConnectionState| match c {
            ConnectionState::Elastic => "intact",
            ConnectionState::Plastic => "plastic",
            ConnectionState::Broken => "broken",
        };
        for c in &r.connections {
            let _ = writeln!(
                s,
                "{},{},{},{},{}",
                rec.bodies[c.a].name,
                rec.bodies[c.b].name,
                st(c.start_state),
                st(c.state),
                c.broke_at_s.map_or(String::new(), |t| format!("{t:.4}"))
            );
        }
        out.push(("connections.csv", s.into_bytes()));
    }
    let js = serde_json::to_string_pretty(&summary(rec, timing))? + "\n";
    out.push(("summary.json", js.into_bytes()));
    out.push(("collapse.glb", glb(rec, &frames)?));
    Ok(out)
}

/// The one timeline: FE keyframes up to Tc, then the ruin stage's frames after the last
/// FE keyframe.
pub fn timeline(rec: &RunRecord) -> Vec<(f64, Vec<Pose>)> {
    let mut frames: Vec<(f64, Vec<Pose>)> = rec.fe_frames.clone();
    let last = frames.last().map_or(f64::NEG_INFINITY, |f| f.0);
    if let Some(r) = &rec.ruin {
        for f in &r.frames {
            if f.time_s > last + 1e-6 {
                frames.push((f.time_s, f.poses.clone()));
            }
        }
    }
    frames
}

/// The `bodies.csv` rows of a run.
fn body_rows(rec: &RunRecord) -> Vec<BodyRow<'_>> {
    rec.bodies
        .iter()
        .map(|b| BodyRow {
            name: &b.name,
            group: &b.group,
            type_name: &b.type_name,
            material: &b.material,
            element: &b.element,
            passive: b.passive,
            pose0: b.pose0,
            half_extents: b.half_extents,
            mass_kg: b.mass_kg,
        })
        .collect()
}

/// The timeline's frames with their stage, connection counts and ground displacement.
fn history_frames<'a>(rec: &RunRecord, frames: &'a [(f64, Vec<Pose>)]) -> Vec<HistoryFrame<'a>> {
    let n_fe = rec.fe_frames.len();
    let ruin = rec.ruin.as_ref();
    frames
        .iter()
        .enumerate()
        .map(|(k, (t, poses))| {
            let counts = if k < n_fe {
                None
            } else {
                ruin.and_then(|r| {
                    r.frames
                        .iter()
                        .find(|f| (f.time_s - t).abs() < 1e-9)
                        .map(|f| (f.counts.elastic, f.counts.plastic, f.counts.broken))
                })
            };
            HistoryFrame {
                t_s: *t,
                fe: k < n_fe,
                poses,
                counts,
                ground_m: rec.ground.ground_state_at(*t).0,
            }
        })
        .collect()
}

fn glb(rec: &RunRecord, frames: &[(f64, Vec<Pose>)]) -> Result<Vec<u8>> {
    let mut times: Vec<f64> = Vec::new();
    let mut keep: Vec<usize> = Vec::new();
    for (k, (t, _)) in frames.iter().enumerate() {
        if times.last().is_none_or(|p| (*t as f32) > (*p as f32)) {
            times.push(*t);
            keep.push(k);
        }
    }
    let bodies = rec
        .bodies
        .iter()
        .enumerate()
        .map(|(i, b)| AnimBody {
            name: b.name.clone(),
            type_name: b.type_name.clone(),
            half_extents: b.half_extents,
            poses: keep
                .iter()
                .map(|&k| (frames[k].1[i].position, frames[k].1[i].orientation))
                .collect(),
        })
        .collect();
    // A ground slab under the footprint with 2 m margin, moved by the record.
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for b in &rec.bodies {
        for k in 0..3 {
            lo[k] =
                lo[k].min(b.pose0.position[k] - b.half_extents.iter().copied().fold(0.0, f64::max));
            hi[k] =
                hi[k].max(b.pose0.position[k] + b.half_extents.iter().copied().fold(0.0, f64::max));
        }
    }
    let he = [
        (hi[0] - lo[0]) / 2.0 + 2.0,
        (hi[1] - lo[1]) / 2.0 + 2.0,
        0.05,
    ];
    let base_z = rec
        .bodies
        .iter()
        .filter(|b| b.passive)
        .map(|b| b.pose0.position[2] + b.half_extents[2])
        .fold(lo[2], f64::max);
    let c = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0, base_z - 0.05];
    let ground = GroundBox {
        half_extents: he,
        poses: times
            .iter()
            .map(|t| {
                let d = rec.ground.ground_state_at(*t).0;
                (
                    [c[0] + d[0], c[1] + d[1], c[2] + d[2]],
                    [1.0, 0.0, 0.0, 0.0],
                )
            })
            .collect(),
    };
    encode_glb(&AnimatedScene {
        bodies,
        ground: Some(ground),
        times_s: times,
    })
}

/// Writes the outputs into `dir` (created if missing); returns the paths written.
pub fn write(rec: &RunRecord, dir: &Path, timing: bool) -> Result<Vec<PathBuf>> {
    let files = contents(rec, timing)?;
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let mut out = Vec::new();
    for (name, bytes) in files {
        let p = dir.join(name);
        write_atomic(&p, &bytes).with_context(|| format!("cannot write {}", p.display()))?;
        out.push(p);
    }
    Ok(out)
}
