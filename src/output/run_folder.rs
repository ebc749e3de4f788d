//! Reads a run folder back: what `fem2rbd run` wrote (`bodies.csv`, `keyframes.csv`,
//! `history.csv`, `ruins.csv`, `summary.json`; formats in [`crate::output::history`],
//! [`crate::output::keyframes`], [`crate::output::ruins`] and docs/scenario-format.md
//! "Outputs"), so that a run can be plotted or re-exported without its model.
//!
//! Parsing is strict: every file's header must be the writer's header exactly, every row
//! must have the header's number of fields, numbers must be finite, quaternions of unit
//! length (|‖q‖ − 1| ≤ [`QUATERNION_NORM_TOL`]; the files hold 8 decimals), positive
//! half extents and masses ≥ 0. The body names of each `keyframes.csv` frame and of `ruins.csv`
//! must be those of `bodies.csv`, in its order; frame times must increase strictly, and
//! `history.csv` must have one row per frame with the same time. Every error names the
//! file and line (`path/keyframes.csv:12: column x: "1.2.3" is not a number`).
//!
//! Numbers come back as written: times to 4 decimals (s), lengths to 6 (m), quaternions
//! and ratios to 8.
use crate::body::BodyId;
use crate::bullet::Pose;
use crate::output::history::{BodyRow, BODIES_HEADER, HISTORY_HEADER};
use crate::output::summary::RunSummary;
use crate::output::{keyframes, ruins};
use std::path::{Path, PathBuf};

/// Largest accepted |‖q‖ − 1| of a quaternion read from a file. The writers round unit
/// quaternions to 8 decimals, which moves the norm by at most 2·10⁻⁸.
pub(crate) const QUATERNION_NORM_TOL: f64 = 1e-6;

/// The file names a run folder must hold, in the order they are read.
pub(crate) const FILES: [&str; 5] = [
    "bodies.csv",
    "keyframes.csv",
    "history.csv",
    "ruins.csv",
    "summary.json",
];

/// One row of `bodies.csv`: a body's identity, undeformed geometry and mass.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyInfo {
    /// Identity (`Type:material:element`, or `Foundation:base:<node>`).
    pub id: BodyId,
    /// Passive (kinematic foundation block, moved with the ground).
    pub passive: bool,
    /// Undeformed pose: box centre (m) and unit quaternion of the box axes.
    pub pose0: Pose,
    /// Half extents along the box axes, m (all > 0).
    pub half_extents: [f64; 3],
    /// Mass, kg (0 for passive blocks).
    pub mass_kg: f64,
}

impl BodyInfo {
    /// The row [`crate::output::history::bodies_csv`] writes for this body.
    pub fn row(&self) -> BodyRow<'_> {
        BodyRow {
            id: &self.id,
            passive: self.passive,
            pose0: self.pose0,
            half_extents: self.half_extents,
            mass_kg: self.mass_kg,
        }
    }
}

/// One row of `history.csv` (one timeline frame).
#[derive(Debug, Clone, PartialEq)]
pub struct HistoryRow {
    /// Time, s.
    pub t_s: f64,
    /// `true` for an FE keyframe (`fe`), `false` for a ruin-stage frame (`ruin`).
    pub fe: bool,
    /// Roof drift ratio (dimensionless); `None` when the run has no roof.
    pub roof_drift: Option<f64>,
    /// Largest drop of a body centre relative to the ground, m; `None` without active
    /// bodies.
    pub max_drop_m: Option<f64>,
    /// Connection counts (intact, plastic, broken); `None` in FE frames.
    pub counts: Option<(usize, usize, usize)>,
    /// Ground displacement, m.
    pub ground_m: [f64; 3],
    /// The energy ledger (ruin-stage frames; `None` in FE frames).
    pub energy: Option<crate::output::history::EnergyRow>,
}

/// A run folder, read and checked.
#[derive(Debug, Clone)]
pub struct RunFolder {
    /// The folder.
    pub dir: PathBuf,
    /// `bodies.csv`, in body order.
    pub bodies: Vec<BodyInfo>,
    /// `keyframes.csv`: (time s, one pose per body in body order), times increasing.
    pub frames: Vec<(f64, Vec<Pose>)>,
    /// `history.csv`: one row per frame, same times.
    pub history: Vec<HistoryRow>,
    /// `ruins.csv`: final pose per body.
    pub final_poses: Vec<Pose>,
    /// `ruins.csv`: at rest per body (`None`: no ruin stage ran).
    pub at_rest: Vec<Option<bool>>,
    /// `summary.json`.
    pub summary: RunSummary,
}

/// A run folder that cannot be read back: it is missing, a file cannot be read, or a
/// file breaks the format (the file and line named).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RunFolderError {
    /// The run folder does not exist or is not a folder.
    #[error("run folder {} does not exist or is not a folder", .0.display())]
    NotAFolder(PathBuf),
    /// A file of the run folder cannot be read.
    #[error(
        "cannot read {} (a run folder written by `fem2rbd run` holds {}): {error}",
        path.display(),
        FILES.join(", ")
    )]
    Read {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
    /// A line of a CSV file breaks the format (header, field count, a column's value).
    #[error("{file}:{line}: {message}")]
    Line {
        /// The file, as given.
        file: String,
        /// The line (1-based; 1 is the header).
        line: usize,
        /// What is wrong, with the column.
        message: String,
    },
    /// `summary.json` does not parse as a run summary.
    #[error("{file}:{line}:{column}: {error}")]
    Summary {
        /// The file.
        file: String,
        /// Line of the error.
        line: usize,
        /// Column of the error.
        column: usize,
        /// serde_json's message.
        error: serde_json::Error,
    },
}

/// What run-folder reading returns.
pub type Result<T> = std::result::Result<T, RunFolderError>;

/// A [`RunFolderError::Line`] error.
fn at(file: &str, line: usize, message: String) -> RunFolderError {
    RunFolderError::Line {
        file: file.to_string(),
        line,
        message,
    }
}

impl RunFolder {
    /// Reads and checks the run folder `dir` (module docs).
    pub fn load(dir: &Path) -> Result<RunFolder> {
        if !dir.is_dir() {
            return Err(RunFolderError::NotAFolder(dir.to_path_buf()));
        }
        let read = |name: &str| -> Result<(String, String)> {
            let p = dir.join(name);
            let text = match crate::model::limits::read_regular_file(&p) {
                Ok(t) => t,
                Err(error) => return Err(RunFolderError::Read { path: p, error }),
            };
            Ok((p.display().to_string(), text))
        };
        let (bf, bt) = read("bodies.csv")?;
        let bodies = parse_bodies(&bt, &bf)?;
        let (kf, kt) = read("keyframes.csv")?;
        let frames = parse_keyframes(&kt, &kf, &bodies)?;
        let (hf, ht) = read("history.csv")?;
        let history = parse_history(&ht, &hf)?;
        check_history_times(&history, &frames, &hf, &kf)?;
        let (rf, rt) = read("ruins.csv")?;
        let (final_poses, at_rest) = parse_ruins(&rt, &rf, &bodies)?;
        let (sf, st) = read("summary.json")?;
        let summary: RunSummary =
            serde_json::from_str(&st).map_err(|error| RunFolderError::Summary {
                file: sf,
                line: error.line(),
                column: error.column(),
                error,
            })?;
        Ok(RunFolder {
            dir: dir.to_path_buf(),
            bodies,
            frames,
            history,
            final_poses,
            at_rest,
            summary,
        })
    }

    /// The ground displacement of each frame (m), from `history.csv`.
    pub fn ground_per_frame(&self) -> Vec<[f64; 3]> {
        self.history.iter().map(|h| h.ground_m).collect()
    }
}

/// One data row of a CSV file, with what an error message needs.
struct Row<'a> {
    file: &'a str,
    line: usize,
    header: &'static str,
    /// The row's fields (one allocation for the row, not one per field).
    fields: csv::StringRecord,
}

impl Row<'_> {
    /// The name of column `i`.
    fn column(&self, i: usize) -> &'static str {
        self.header.split(',').nth(i).unwrap_or("?")
    }

    /// An error at this row, column `i`.
    fn err(&self, i: usize, msg: impl std::fmt::Display) -> RunFolderError {
        at(
            self.file,
            self.line,
            format!("column {}: {msg}", self.column(i)),
        )
    }

    fn text(&self, i: usize) -> Result<&str> {
        let s = &self.fields[i];
        if s.is_empty() {
            return Err(self.err(i, "is empty"));
        }
        Ok(s)
    }

    fn f64(&self, i: usize) -> Result<f64> {
        let s = &self.fields[i];
        match s.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.err(i, format!("{s:?} is not a finite number"))),
        }
    }

    fn opt_f64(&self, i: usize) -> Result<Option<f64>> {
        if self.fields[i].is_empty() {
            Ok(None)
        } else {
            self.f64(i).map(Some)
        }
    }

    fn vec3(&self, i: usize) -> Result<[f64; 3]> {
        Ok([self.f64(i)?, self.f64(i + 1)?, self.f64(i + 2)?])
    }

    /// A unit quaternion (w, x, y, z) in columns `i..i + 4`.
    fn quaternion(&self, i: usize) -> Result<[f64; 4]> {
        let q = [
            self.f64(i)?,
            self.f64(i + 1)?,
            self.f64(i + 2)?,
            self.f64(i + 3)?,
        ];
        let norm = q.iter().map(|c| c * c).sum::<f64>().sqrt();
        if (norm - 1.0).abs() > QUATERNION_NORM_TOL {
            return Err(at(
                self.file,
                self.line,
                format!(
                    "columns {}..{}: quaternion {q:?} has norm {norm}, not 1",
                    self.column(i),
                    self.column(i + 3)
                ),
            ));
        }
        Ok(q)
    }

    fn pose(&self, i: usize) -> Result<Pose> {
        Ok(Pose {
            position: self.vec3(i)?,
            orientation: self.quaternion(i + 3)?,
        })
    }

    fn flag(&self, i: usize) -> Result<bool> {
        match &self.fields[i] {
            "1" => Ok(true),
            "0" => Ok(false),
            s => Err(self.err(i, format!("{s:?} must be 1 or 0"))),
        }
    }
}

/// The rows of `text` after checking that its first line is `header`, one at a time (a
/// run's keyframes are frames × bodies rows: they are parsed as they are read, never held
/// as text fields all at once). `file` names the file in errors.
fn rows<'a>(
    text: &'a str,
    file: &'a str,
    header: &'static str,
) -> Result<impl Iterator<Item = Result<Row<'a>>> + 'a> {
    let n_columns = header.split(',').count();
    match text.lines().next() {
        None => {
            return Err(at(
                file,
                1,
                format!("the file is empty; expected the header {header:?}"),
            ))
        }
        Some(h) if h != header => {
            return Err(at(
                file,
                1,
                format!("header {h:?} is not the expected {header:?}"),
            ))
        }
        Some(_) => {}
    }
    // RFC 4180 records (quoted fields may hold commas, quotes and newlines:
    // crate::output::csv_text), read with the `csv` crate; errors name the line where
    // the record starts.
    let reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .flexible(true)
        .from_reader(text.as_bytes());
    Ok(reader.into_records().map(move |rec| {
        let rec = rec.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line());
            at(file, line as usize, format!("not a CSV row: {e}"))
        })?;
        let n = rec.position().map_or(0, |p| p.line() as usize);
        if rec.len() != n_columns {
            return Err(at(
                file,
                n,
                format!("{} fields, expected {n_columns} ({header})", rec.len()),
            ));
        }
        Ok(Row {
            file,
            line: n,
            header,
            fields: rec,
        })
    }))
}

/// Parses `bodies.csv` (header [`BODIES_HEADER`]); `file` names it in errors.
pub fn parse_bodies(text: &str, file: &str) -> Result<Vec<BodyInfo>> {
    let mut out: Vec<BodyInfo> = Vec::new();
    // Body → its index, to refuse a repeated body in one lookup (the library building
    // has thousands of bodies; a scan per row would be quadratic).
    let mut seen: std::collections::HashMap<BodyId, usize> = std::collections::HashMap::new();
    for r in rows(text, file, BODIES_HEADER)? {
        let r = r?;
        let half_extents = r.vec3(13)?;
        for (d, h) in half_extents.iter().enumerate() {
            if *h <= 0.0 {
                return Err(r.err(13 + d, format!("half extent {h} m must be > 0")));
            }
        }
        let mass_kg = r.f64(16)?;
        if mass_kg < 0.0 {
            return Err(r.err(16, format!("mass {mass_kg} kg must be >= 0")));
        }
        let name = r.text(0)?.to_string();
        r.text(2)?;
        let id = BodyId::from_columns(
            &name,
            &r.fields[1],
            &r.fields[2],
            &r.fields[3],
            &r.fields[4],
        )
        .map_err(|e| {
            let c = ["name", "group", "type", "material", "element"]
                .iter()
                .position(|c| *c == e.column)
                .unwrap_or(0);
            r.err(c, e.message)
        })?;
        if let Some(k) = seen.insert(id.clone(), out.len()) {
            return Err(r.err(0, format!("body {name:?} is already on line {}", k + 2)));
        }
        out.push(BodyInfo {
            id,
            passive: r.flag(5)?,
            pose0: r.pose(6)?,
            half_extents,
            mass_kg,
        });
    }
    Ok(out)
}

/// Parses `keyframes.csv` (header [`keyframes::HEADER`]) against the bodies of
/// `bodies.csv`: each frame lists every body once, in body order, at one time; times
/// increase strictly. `file` names it in errors.
pub fn parse_keyframes(
    text: &str,
    file: &str,
    bodies: &[BodyInfo],
) -> Result<Vec<(f64, Vec<Pose>)>> {
    let rows = rows(text, file, keyframes::HEADER)?;
    let n = bodies.len();
    let mut frames: Vec<(f64, Vec<Pose>)> = Vec::new();
    let names: Vec<String> = bodies.iter().map(|b| b.id.name()).collect();
    // The number of rows read and the line of the last one.
    let (mut count, mut last_line) = (0usize, 0usize);
    for (k, r) in rows.enumerate() {
        let r = r?;
        (count, last_line) = (k + 1, r.line);
        if n == 0 {
            return Err(at(
                file,
                r.line,
                "a frame row, but bodies.csv lists no bodies".into(),
            ));
        }
        let i = k % n;
        let t = r.f64(0)?;
        let name = &r.fields[1];
        if name != names[i] {
            return Err(r.err(
                1,
                format!(
                    "body {name:?} where bodies.csv has {:?} (body #{i}; each frame lists \
                     every body in bodies.csv order)",
                    names[i]
                ),
            ));
        }
        if i == 0 {
            if let Some((prev, _)) = frames.last() {
                if t <= *prev {
                    return Err(r.err(
                        0,
                        format!("frame time {t} s does not follow the previous {prev} s"),
                    ));
                }
            }
            if t < 0.0 {
                return Err(r.err(0, format!("frame time {t} s is negative")));
            }
            frames.push((t, Vec::with_capacity(n)));
        } else {
            let t0 = frames.last().expect("a frame was started").0;
            if t != t0 {
                return Err(r.err(
                    0,
                    format!("time {t} s within the frame at {t0} s (expected {t0})"),
                ));
            }
        }
        frames.last_mut().expect("a frame").1.push(r.pose(2)?);
    }
    if n > 0 && count % n != 0 {
        return Err(at(
            file,
            last_line,
            format!(
                "the last frame (t = {} s) lists {} of the {n} bodies",
                frames.last().expect("a frame").0,
                count % n
            ),
        ));
    }
    Ok(frames)
}

/// Parses `history.csv` (header [`HISTORY_HEADER`]); `file` names it in errors.
pub(crate) fn parse_history(text: &str, file: &str) -> Result<Vec<HistoryRow>> {
    let mut out = Vec::new();
    for r in rows(text, file, HISTORY_HEADER)? {
        let r = r?;
        let fe = match &r.fields[1] {
            "fe" => true,
            // `physics`: the ruin stage's former name, in run folders written before.
            "ruin" | "physics" => false,
            s => return Err(r.err(1, format!("stage {s:?} must be fe or ruin"))),
        };
        let counts = if (4..7).all(|k| r.fields[k].is_empty()) {
            None
        } else {
            let mut c = [0usize; 3];
            for (d, cd) in c.iter_mut().enumerate() {
                let s = &r.fields[4 + d];
                *cd = s
                    .parse()
                    .map_err(|_| r.err(4 + d, format!("{s:?} is not a count")))?;
            }
            Some((c[0], c[1], c[2]))
        };
        out.push(HistoryRow {
            t_s: r.f64(0)?,
            fe,
            roof_drift: r.opt_f64(2)?,
            max_drop_m: r.opt_f64(3)?,
            counts,
            ground_m: r.vec3(7)?,
            energy: if (10..17).all(|k| r.fields[k].is_empty()) {
                None
            } else {
                Some(crate::output::history::EnergyRow {
                    kinetic_j: r.f64(10)?,
                    rotational_j: r.f64(11)?,
                    potential_j: r.f64(12)?,
                    ground_work_j: r.f64(13)?,
                    damping_j: r.f64(14)?,
                    dissipated_j: r.f64(15)?,
                    injected_j: r.f64(16)?,
                })
            },
        });
    }
    Ok(out)
}

/// Checks that `history` has one row per frame of `frames`, at the same times.
/// `hist_file` and `kf_file` name the files in errors.
pub(crate) fn check_history_times(
    history: &[HistoryRow],
    frames: &[(f64, Vec<Pose>)],
    hist_file: &str,
    kf_file: &str,
) -> Result<()> {
    for (k, (h, (t, _))) in history.iter().zip(frames).enumerate() {
        if h.t_s != *t {
            return Err(at(
                hist_file,
                k + 2,
                format!(
                    "column t: {} s, but frame {k} of {kf_file} is at {t} s \
                     (one history row per frame)",
                    h.t_s
                ),
            ));
        }
    }
    if history.len() != frames.len() {
        return Err(at(
            hist_file,
            history.len().min(frames.len()) + 2,
            format!(
                "{} rows, but {kf_file} has {} frames (one history row per frame)",
                history.len(),
                frames.len()
            ),
        ));
    }
    Ok(())
}

/// Parses `ruins.csv` (header [`ruins::HEADER`]) against the bodies of `bodies.csv`
/// (same names, groups, types, materials and elements, same order): final poses and
/// at-rest flags. `file` names it in errors.
pub(crate) fn parse_ruins(
    text: &str,
    file: &str,
    bodies: &[BodyInfo],
) -> Result<(Vec<Pose>, Vec<Option<bool>>)> {
    let rows = rows(text, file, ruins::HEADER)?.collect::<Result<Vec<Row>>>()?;
    let mut poses = Vec::with_capacity(rows.len());
    let mut at_rest = Vec::with_capacity(rows.len());
    for (i, r) in rows.iter().enumerate() {
        let Some(b) = bodies.get(i) else {
            return Err(at(
                file,
                r.line,
                format!(
                    "a row for body #{i}, but bodies.csv lists {} bodies",
                    bodies.len()
                ),
            ));
        };
        let want = [
            b.id.name(),
            b.id.group().to_string(),
            b.id.body_type().to_string(),
            b.id.material().to_string(),
            b.id.element_field(),
        ];
        for (c, w) in want.iter().enumerate() {
            if r.fields[c] != *w {
                return Err(r.err(
                    c,
                    format!(
                        "{:?} where bodies.csv has {w:?} for body #{i} (rows in bodies.csv order)",
                        &r.fields[c]
                    ),
                ));
            }
        }
        poses.push(r.pose(5)?);
        at_rest.push(match &r.fields[12] {
            "1" => Some(true),
            "0" => Some(false),
            "-" => None,
            s => return Err(r.err(12, format!("{s:?} must be 1, 0 or -"))),
        });
    }
    if rows.len() != bodies.len() {
        return Err(at(
            file,
            rows.len() + 2,
            format!(
                "{} body rows, but bodies.csv lists {} bodies",
                rows.len(),
                bodies.len()
            ),
        ));
    }
    Ok((poses, at_rest))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::history::{bodies_csv, history_csv, HistoryFrame};
    use crate::output::keyframes::keyframes_csv;
    use crate::output::ruins::{ruins_csv, RuinRow};

    /// Three bodies (a passive block and two tilted boxes) with awkward numbers.
    fn bodies() -> Vec<BodyInfo> {
        let q = |a: f64, axis: [f64; 3]| {
            let n = axis.iter().map(|c| c * c).sum::<f64>().sqrt();
            let s = (a / 2.0).sin() / n;
            [(a / 2.0).cos(), s * axis[0], s * axis[1], s * axis[2]]
        };
        let b = |name: &str, _t: &str, passive, p: [f64; 3], o, h, m| BodyInfo {
            id: name.parse().unwrap(),
            passive,
            pose0: Pose {
                position: p,
                orientation: o,
            },
            half_extents: h,
            mass_kg: m,
        };
        vec![
            b(
                "Foundation:base:1",
                "Foundation",
                true,
                [0.0, 0.0, -0.1],
                [1.0, 0.0, 0.0, 0.0],
                [0.2, 0.2, 0.1],
                0.0,
            ),
            b(
                "Column:mat1:7",
                "Column",
                false,
                [0.1234567891, -2.0 / 3.0, 1.5],
                q(0.3, [1.0, 2.0, 3.0]),
                [0.1, 0.15, 0.75],
                123.456789,
            ),
            b(
                "Beam:mat1:9",
                "Beam",
                false,
                [1.0 / 7.0, 2.5, 3.0000004],
                q(-1.1, [0.0, 1.0, -1.0]),
                [1.25, 0.1, 0.125],
                77.0,
            ),
        ]
    }

    /// Poses of frame `k`: each body moved and rotated a little.
    fn poses(bodies: &[BodyInfo], k: usize) -> Vec<Pose> {
        let t = k as f64 * 0.04;
        bodies
            .iter()
            .enumerate()
            .map(|(i, b)| {
                let a = 0.7 * t * (i as f64 + 1.0);
                let (c, s) = ((a / 2.0).cos(), (a / 2.0).sin());
                let q0 = b.pose0.orientation;
                // q = q0 · (c, 0, 0, s): a turn about the body's own z.
                let q = [
                    q0[0] * c - q0[3] * s,
                    q0[1] * c + q0[2] * s,
                    q0[2] * c - q0[1] * s,
                    q0[3] * c + q0[0] * s,
                ];
                let p = b.pose0.position;
                Pose {
                    position: [p[0] + 0.1 * t.sin(), p[1] - t / 3.0, p[2] - 0.5 * t * t],
                    orientation: q,
                }
            })
            .collect()
    }

    struct Written {
        bodies: String,
        keyframes: String,
        history: String,
        ruins: String,
        frames: Vec<(f64, Vec<Pose>)>,
        ground: Vec<[f64; 3]>,
    }

    fn written() -> Written {
        let bs = bodies();
        let rows: Vec<BodyRow> = bs.iter().map(BodyInfo::row).collect();
        let frames: Vec<(f64, Vec<Pose>)> = (0..6)
            .map(|k| (k as f64 * 0.04 + 1e-7, poses(&bs, k)))
            .collect();
        let ground: Vec<[f64; 3]> = frames
            .iter()
            .map(|(t, _)| [0.01 * (9.0 * t).sin(), -0.003 * t, 1e-4 / 3.0])
            .collect();
        let names: Vec<String> = bs.iter().map(|b| b.id.name()).collect();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        let fr: Vec<(f64, &[Pose])> = frames.iter().map(|(t, p)| (*t, p.as_slice())).collect();
        let hf: Vec<HistoryFrame> = frames
            .iter()
            .zip(&ground)
            .enumerate()
            .map(|(k, ((t, p), g))| HistoryFrame {
                t_s: *t,
                fe: k < 3,
                poses: p,
                counts: (k >= 3).then_some((10 - k, k, 2 * k)),
                ground_m: *g,
                energy: None,
            })
            .collect();
        let last = &frames.last().unwrap().1;
        let ruin_rows: Vec<RuinRow> = bs
            .iter()
            .zip(last)
            .enumerate()
            .map(|(i, (b, p))| RuinRow {
                id: &b.id,
                pose: *p,
                at_rest: [None, Some(true), Some(false)][i],
            })
            .collect();
        Written {
            bodies: bodies_csv(&rows),
            keyframes: keyframes_csv(&names, &fr),
            history: history_csv(&rows, &hf),
            ruins: ruins_csv(&ruin_rows),
            frames,
            ground,
        }
    }

    fn write_folder(dir: &Path, w: &Written) {
        std::fs::write(dir.join("bodies.csv"), &w.bodies).unwrap();
        std::fs::write(dir.join("keyframes.csv"), &w.keyframes).unwrap();
        std::fs::write(dir.join("history.csv"), &w.history).unwrap();
        std::fs::write(dir.join("ruins.csv"), &w.ruins).unwrap();
        std::fs::write(dir.join("summary.json"), "{\"mode\": \"hybrid\", \"tc_s\": 1.0, \"tc_reason\": \"criterion\", \"tc_detail\": \"d\", \"fe_end_s\": 1.0, \"bodies\": 2, \"foundation_blocks\": 1, \"keyframes_fe\": 3, \"ruins\": {\"original_footprint_m\": {\"x\": [0, 1], \"y\": [0, 1]}, \"extent_beyond_footprint_m\": {\"x_minus\": 0, \"x_plus\": 0, \"y_minus\": 0, \"y_plus\": 0, \"max\": 0}, \"debris_footprint_area_m2\": 1, \"original_footprint_area_m2\": 1, \"max_debris_height_m\": 1, \"floors\": [], \"slab_overlap\": []}}\n").unwrap();
    }

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    fn assert_pose(got: &Pose, want: &Pose, what: &str) {
        for d in 0..3 {
            assert!(
                close(got.position[d], want.position[d], 5e-7),
                "{what}: position {:?} vs {:?}",
                got.position,
                want.position
            );
        }
        for d in 0..4 {
            assert!(
                close(got.orientation[d], want.orientation[d], 5e-9),
                "{what}: quaternion {:?} vs {:?}",
                got.orientation,
                want.orientation
            );
        }
    }

    /// Everything written comes back to the written precision (half a unit in the last
    /// decimal: 5e-5 s, 5e-7 m, 5e-9 for quaternions and ratios), and writing the parsed
    /// values again gives the same bytes.
    #[test]
    fn round_trip_with_the_writers() {
        let w = written();
        let dir = tempfile::tempdir().unwrap();
        write_folder(dir.path(), &w);
        let rf = RunFolder::load(dir.path()).unwrap();
        let bs = bodies();
        assert_eq!(rf.bodies.len(), 3);
        for (got, want) in rf.bodies.iter().zip(&bs) {
            assert_eq!(got.id, want.id);
            assert_eq!(got.passive, want.passive);
            assert_pose(&got.pose0, &want.pose0, &want.id.name());
            for d in 0..3 {
                assert!(close(got.half_extents[d], want.half_extents[d], 5e-7));
            }
            assert!(close(got.mass_kg, want.mass_kg, 5e-7), "{}", got.mass_kg);
        }
        assert_eq!(rf.frames.len(), w.frames.len());
        for ((t, p), (wt, wp)) in rf.frames.iter().zip(&w.frames) {
            assert!(close(*t, *wt, 5e-5), "{t} vs {wt}");
            assert_eq!(*t, format!("{wt:.4}").parse::<f64>().unwrap());
            for (a, b) in p.iter().zip(wp) {
                assert_pose(a, b, &format!("t = {t}"));
            }
        }
        assert_eq!(rf.history.len(), w.frames.len());
        for (k, h) in rf.history.iter().enumerate() {
            assert_eq!(h.t_s, rf.frames[k].0);
            assert_eq!(h.fe, k < 3);
            assert_eq!(h.counts, (k >= 3).then_some((10 - k, k, 2 * k)));
            for d in 0..3 {
                assert!(close(h.ground_m[d], w.ground[k][d], 5e-7));
            }
            assert!(h.roof_drift.unwrap() >= 0.0);
        }
        // Frame 0: the bodies have not moved relative to the ground but the ground's z
        // offset 1e-4/3 m (rounded 0.000033): max drop = that offset.
        assert!(close(rf.history[0].max_drop_m.unwrap(), 1e-4 / 3.0, 5e-7));
        // Frame 5 (t = 0.2 s): the beam fell 0.5 t² = 0.02 m, plus the ground offset.
        assert!(close(
            rf.history[5].max_drop_m.unwrap(),
            0.5 * 0.2f64.powi(2) + 1e-4 / 3.0,
            2e-6
        ));
        assert_eq!(rf.at_rest, vec![None, Some(true), Some(false)]);
        for (a, b) in rf.final_poses.iter().zip(&w.frames.last().unwrap().1) {
            assert_pose(a, b, "ruins");
        }
        assert_eq!(rf.summary.mode, crate::mode::Mode::Hybrid);
        assert_eq!(rf.ground_per_frame().len(), 6);

        // Writing what was read gives the same text.
        let rows: Vec<BodyRow> = rf.bodies.iter().map(BodyInfo::row).collect();
        assert_eq!(bodies_csv(&rows), w.bodies);
        let names: Vec<String> = rf.bodies.iter().map(|b| b.id.name()).collect();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        let fr: Vec<(f64, &[Pose])> = rf.frames.iter().map(|(t, p)| (*t, p.as_slice())).collect();
        assert_eq!(keyframes_csv(&names, &fr), w.keyframes);
    }

    /// Writes `w` with `file` replaced by `text`, loads, returns the error text.
    fn load_error(file: &str, text: &str) -> String {
        let dir = tempfile::tempdir().unwrap();
        write_folder(dir.path(), &written());
        std::fs::write(dir.path().join(file), text).unwrap();
        let e = RunFolder::load(dir.path()).unwrap_err();
        let s = format!("{e:#}");
        let path = dir.path().join(file).display().to_string();
        assert!(s.contains(&path), "error names the file {path}: {s}");
        s
    }

    /// `text` with field `col` (0-based) of line `line` (1-based) set to `value`.
    fn set(text: &str, line: usize, col: usize, value: &str) -> String {
        text.lines()
            .enumerate()
            .map(|(k, l)| {
                if k + 1 == line {
                    let mut f: Vec<&str> = l.split(',').collect();
                    f[col] = value;
                    f.join(",")
                } else {
                    l.to_string()
                }
            })
            .collect::<Vec<_>>()
            .join("\n")
            + "\n"
    }

    /// The first `n` lines of `text`.
    fn head(text: &str, n: usize) -> String {
        text.lines().take(n).map(|l| format!("{l}\n")).collect()
    }

    #[test]
    fn bad_inputs_name_file_line_and_column() {
        let w = written();
        // bodies.csv: line 2 the foundation, 3 the column, 4 the beam.
        let e = load_error("bodies.csv", &w.bodies.replacen("cx", "x", 1));
        assert!(e.contains("bodies.csv:1: header"), "{e}");
        let e = load_error("bodies.csv", &set(&w.bodies, 3, 13, "abc"));
        assert!(e.contains("bodies.csv:3: column hx: \"abc\""), "{e}");
        let e = load_error("bodies.csv", &set(&w.bodies, 3, 8, "inf"));
        assert!(e.contains("bodies.csv:3: column cz: \"inf\""), "{e}");
        let e = load_error("bodies.csv", &set(&w.bodies, 4, 15, "0.000000"));
        assert!(
            e.contains("bodies.csv:4: column hz") && e.contains("> 0"),
            "{e}"
        );
        let e = load_error("bodies.csv", &set(&w.bodies, 4, 16, "-1.0"));
        assert!(e.contains("bodies.csv:4: column mass_kg"), "{e}");
        let e = load_error("bodies.csv", &set(&w.bodies, 2, 5, "yes"));
        assert!(e.contains("bodies.csv:2: column passive"), "{e}");
        let e = load_error("bodies.csv", &set(&w.bodies, 2, 0, ""));
        assert!(e.contains("bodies.csv:2: column name: is empty"), "{e}");
        // A second body with line 3's identity (name, type and element all agree).
        let dup = set(
            &set(&set(&w.bodies, 4, 0, "Column:mat1:7"), 4, 2, "Column"),
            4,
            4,
            "7",
        );
        let e = load_error("bodies.csv", &dup);
        assert!(
            e.contains("bodies.csv:4: column name") && e.contains("already on line 3"),
            "{e}"
        );
        let e = load_error("bodies.csv", &set(&w.bodies, 2, 15, "0.1,7"));
        assert!(e.contains("bodies.csv:2: 18 fields, expected 17"), "{e}");
        let e = load_error("bodies.csv", &set(&w.bodies, 2, 9, "0.90000000"));
        assert!(
            e.contains("bodies.csv:2: columns qw..qz") && e.contains("norm"),
            "{e}"
        );
        let e = load_error("bodies.csv", "");
        assert!(e.contains("bodies.csv:1: the file is empty"), "{e}");
        // keyframes.csv: line 2 + 3k + i holds body i of frame k (t = 0.04 k).
        let e = load_error("keyframes.csv", &set(&w.keyframes, 6, 1, "Column:mat1:8"));
        assert!(
            e.contains("keyframes.csv:6: column name: body \"Column:mat1:8\"")
                && e.contains("\"Column:mat1:7\""),
            "{e}"
        );
        let e = load_error("keyframes.csv", &set(&w.keyframes, 9, 0, "0.1600"));
        assert!(
            e.contains("keyframes.csv:9: column t") && e.contains("within the frame"),
            "{e}"
        );
        // Frame 3 (lines 11-13) given frame 1's time: not increasing.
        let bad = (11..=13).fold(w.keyframes.clone(), |s, l| set(&s, l, 0, "0.0400"));
        let e = load_error("keyframes.csv", &bad);
        assert!(
            e.contains("keyframes.csv:11: column t") && e.contains("does not follow"),
            "{e}"
        );
        let e = load_error("keyframes.csv", &set(&w.keyframes, 7, 4, "1.0,"));
        assert!(e.contains("keyframes.csv:7: 10 fields"), "{e}");
        let e = load_error("keyframes.csv", &set(&w.keyframes, 8, 2, "NaN"));
        assert!(e.contains("keyframes.csv:8: column x: \"NaN\""), "{e}");
        let e = load_error("keyframes.csv", &head(&w.keyframes, 18));
        assert!(
            e.contains("keyframes.csv:18: the last frame") && e.contains("2 of the 3"),
            "{e}"
        );
        // history.csv: line 2 + k holds frame k.
        let e = load_error("history.csv", &set(&w.history, 3, 1, "FE"));
        assert!(e.contains("history.csv:3: column stage"), "{e}");
        let e = load_error("history.csv", &set(&w.history, 6, 2, "x"));
        assert!(e.contains("history.csv:6: column roof_drift"), "{e}");
        let e = load_error("history.csv", &set(&w.history, 7, 5, "-2"));
        assert!(e.contains("history.csv:7: column plastic"), "{e}");
        let e = load_error("history.csv", &set(&w.history, 5, 9, ""));
        assert!(e.contains("history.csv:5: column ground_z"), "{e}");
        let e = load_error("history.csv", &set(&w.history, 4, 0, "0.0801"));
        assert!(
            e.contains("history.csv:4: column t") && e.contains("frame 2"),
            "{e}"
        );
        let e = load_error("history.csv", &head(&w.history, 6));
        assert!(
            e.contains("history.csv:7: 5 rows") && e.contains("6 frames"),
            "{e}"
        );
        // ruins.csv
        let e = load_error("ruins.csv", &set(&w.ruins, 3, 1, "other"));
        assert!(e.contains("ruins.csv:3: column group"), "{e}");
        let e = load_error("ruins.csv", &set(&w.ruins, 4, 12, "maybe"));
        assert!(e.contains("ruins.csv:4: column at_rest"), "{e}");
        let e = load_error("ruins.csv", &head(&w.ruins, 3));
        assert!(e.contains("ruins.csv:4: 2 body rows"), "{e}");
        // summary.json
        let e = load_error("summary.json", "{\n  \"mode\": hybrid\n}\n");
        assert!(e.contains("summary.json:2:"), "{e}");
    }

    #[test]
    fn missing_folder_or_file_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let none = dir.path().join("nothing-here");
        let e = format!("{:#}", RunFolder::load(&none).unwrap_err());
        assert!(
            e.contains("nothing-here") && e.contains("does not exist"),
            "{e}"
        );
        write_folder(dir.path(), &written());
        std::fs::remove_file(dir.path().join("history.csv")).unwrap();
        let e = format!("{:#}", RunFolder::load(dir.path()).unwrap_err());
        assert!(
            e.contains(&dir.path().join("history.csv").display().to_string()),
            "{e}"
        );
    }
}
