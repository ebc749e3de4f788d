//! The ruin a rescue analysis reads: every box's final pose (`ruins.csv`), its undeformed
//! pose, size and identity (`bodies.csv`), the connections with their final states
//! (`connections.csv`) and the model's geometric scale (`summary.json` `scale`).
use super::{RescueError, Result};
use crate::body::{BodyId, BodyType};
use crate::bullet::Pose;
use crate::output::run_folder::{parse_bodies, parse_ruins, RunFolderError};
use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use std::collections::HashMap;
use std::path::Path;

/// `connections.csv` header (the run writer's, `crate::pipeline::write`).
pub const CONNECTIONS_HEADER: &str =
    "a,b,start_state,final_state,time_broken_s,time_plastic_s,first_row_lost,time_first_row_lost_s";

/// One box of the ruin.
#[derive(Debug, Clone, PartialEq)]
pub struct RuinBox {
    /// Identity (`Type:material:element`).
    pub id: BodyId,
    /// A passive foundation block (moved with the ground, not debris).
    pub passive: bool,
    /// Undeformed pose (centre m, unit quaternion).
    pub pose0: Pose,
    /// Final pose.
    pub pose: Pose,
    /// Half extents along the box axes, m.
    pub half_extents: [f64; 3],
}

impl RuinBox {
    /// The box's axes at `pose` as the columns of a rotation matrix.
    pub fn axes(pose: &Pose) -> Matrix3<f64> {
        let [w, x, y, z] = pose.orientation;
        UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z))
            .to_rotation_matrix()
            .into_inner()
    }

    /// The 8 corners at `pose`, m.
    pub fn corners_at(&self, pose: &Pose) -> [[f64; 3]; 8] {
        let r = Self::axes(pose);
        let c = Vector3::from(pose.position);
        let h = self.half_extents;
        let mut out = [[0.0; 3]; 8];
        for (k, o) in out.iter_mut().enumerate() {
            let s = [
                if k & 1 == 0 { -1.0 } else { 1.0 },
                if k & 2 == 0 { -1.0 } else { 1.0 },
                if k & 4 == 0 { -1.0 } else { 1.0 },
            ];
            let p = c + r * Vector3::new(s[0] * h[0], s[1] * h[1], s[2] * h[2]);
            *o = [p.x, p.y, p.z];
        }
        out
    }

    /// The Euclidean distance (m) from point `p` to the box at its final pose (0 inside).
    pub fn distance_to(&self, p: [f64; 3]) -> f64 {
        let r = Self::axes(&self.pose);
        let d = r.transpose() * (Vector3::from(p) - Vector3::from(self.pose.position));
        (0..3)
            .map(|k| (d[k].abs() - self.half_extents[k]).max(0.0).powi(2))
            .sum::<f64>()
            .sqrt()
    }

    /// Whether this is a slab panel.
    pub fn is_slab(&self) -> bool {
        *self.id.body_type() == BodyType::Slab
    }
}

/// A connection between two boxes (indices into [`Ruin::boxes`]) and whether it still
/// holds at the end (`intact` or `plastic` in `connections.csv`, not `broken`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Connection {
    /// First box.
    pub a: usize,
    /// Second box.
    pub b: usize,
    /// Not broken at the end of the ruin stage.
    pub holds: bool,
}

/// A ruin: its boxes, connections and scale.
#[derive(Debug, Clone, PartialEq)]
pub struct Ruin {
    /// The boxes, in `bodies.csv` order.
    pub boxes: Vec<RuinBox>,
    /// The connections, in `connections.csv` order.
    pub connections: Vec<Connection>,
    /// Geometric scale of the model against its prototype (frame3: 0.25).
    pub scale: f64,
}

impl Ruin {
    /// Reads the ruin of the run folder `dir` (`bodies.csv`, `ruins.csv`,
    /// `connections.csv`, the `scale` of `summary.json`); every error names the file.
    pub fn load(dir: &Path) -> Result<Ruin> {
        if !dir.is_dir() {
            return Err(RunFolderError::NotAFolder(dir.to_path_buf()).into());
        }
        let read = |name: &str| -> Result<(String, String)> {
            let p = dir.join(name);
            match crate::model::limits::read_regular_file(&p) {
                Ok(t) => Ok((p.display().to_string(), t)),
                Err(error) => Err(RunFolderError::Read { path: p, error }.into()),
            }
        };
        let (bf, bt) = read("bodies.csv")?;
        let (rf, rt) = read("ruins.csv")?;
        let (cf, ct) = read("connections.csv")?;
        let (sf, st) = read("summary.json")?;
        let scale = summary_scale(&st, &sf)?;
        Ruin::from_texts(&bt, &bf, &rt, &rf, &ct, &cf, scale)
    }

    /// The ruin from the texts of `bodies.csv`, `ruins.csv` and `connections.csv` (file
    /// names for errors) and the model's scale.
    #[allow(clippy::too_many_arguments)]
    pub fn from_texts(
        bodies: &str,
        bodies_file: &str,
        ruins: &str,
        ruins_file: &str,
        connections: &str,
        connections_file: &str,
        scale: f64,
    ) -> Result<Ruin> {
        let infos = parse_bodies(bodies, bodies_file)?;
        let (poses, _) = parse_ruins(ruins, ruins_file, &infos)?;
        let boxes: Vec<RuinBox> = infos
            .into_iter()
            .zip(poses)
            .map(|(b, pose)| RuinBox {
                id: b.id,
                passive: b.passive,
                pose0: b.pose0,
                pose,
                half_extents: b.half_extents,
            })
            .collect();
        let connections = parse_connections(connections, connections_file, &boxes)?;
        Ok(Ruin {
            boxes,
            connections,
            scale,
        })
    }
}

/// The `scale` of a `summary.json` text (`file` names it in errors).
pub fn summary_scale(text: &str, file: &str) -> Result<f64> {
    let v: serde_json::Value =
        serde_json::from_str(text).map_err(|error| RunFolderError::Summary {
            file: file.to_string(),
            line: error.line(),
            column: error.column(),
            error,
        })?;
    match v.get("scale").and_then(serde_json::Value::as_f64) {
        Some(s) if s.is_finite() && s > 0.0 => Ok(s),
        Some(s) => Err(RescueError::Inconsistent {
            file: file.to_string(),
            line: 1,
            message: format!("scale {s} must be a positive number"),
        }),
        None => Err(RescueError::Inconsistent {
            file: file.to_string(),
            line: 1,
            message: "no number `scale` (the model's geometric scale; `fem2rbd run` writes it): \
                      run the scenario again"
                .into(),
        }),
    }
}

/// Parses `connections.csv` against the boxes (names of `bodies.csv`).
fn parse_connections(text: &str, file: &str, boxes: &[RuinBox]) -> Result<Vec<Connection>> {
    let bad = |line: usize, message: String| RescueError::Inconsistent {
        file: file.to_string(),
        line,
        message,
    };
    match text.lines().next() {
        None => {
            return Err(bad(
                1,
                format!("the file is empty; expected the header {CONNECTIONS_HEADER:?}"),
            ))
        }
        Some(h) if h != CONNECTIONS_HEADER => {
            return Err(bad(
                1,
                format!("header {h:?} is not the expected {CONNECTIONS_HEADER:?}"),
            ))
        }
        Some(_) => {}
    }
    let index: HashMap<String, usize> = boxes
        .iter()
        .enumerate()
        .map(|(i, b)| (b.id.name(), i))
        .collect();
    let n_columns = CONNECTIONS_HEADER.split(',').count();
    let reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .flexible(true)
        .from_reader(text.as_bytes());
    let mut out = Vec::new();
    for rec in reader.into_records() {
        let rec = rec.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line() as usize);
            bad(line, format!("not a CSV row: {e}"))
        })?;
        let line = rec.position().map_or(0, |p| p.line() as usize);
        if rec.len() != n_columns {
            return Err(bad(
                line,
                format!(
                    "{} fields, expected {n_columns} ({CONNECTIONS_HEADER})",
                    rec.len()
                ),
            ));
        }
        let body = |k: usize, col: &str| -> Result<usize> {
            index.get(&rec[k]).copied().ok_or_else(|| {
                bad(
                    line,
                    format!("column {col}: body {:?} is not in bodies.csv", &rec[k]),
                )
            })
        };
        let a = body(0, "a")?;
        let b = body(1, "b")?;
        if a == b {
            return Err(bad(line, format!("body {:?} connected to itself", &rec[0])));
        }
        for (k, col) in [(2, "start_state"), (3, "final_state")] {
            if !matches!(&rec[k], "intact" | "plastic" | "broken") {
                return Err(bad(
                    line,
                    format!(
                        "column {col}: {:?} must be intact, plastic or broken",
                        &rec[k]
                    ),
                ));
            }
        }
        out.push(Connection {
            a,
            b,
            holds: &rec[3] != "broken",
        });
    }
    Ok(out)
}
