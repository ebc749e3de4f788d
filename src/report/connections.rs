//! `connections.csv` read back for the report: each connection's two bodies and when it
//! became plastic and broken, so the page can colour a body by the state of its
//! connections at any time of the ruin stage.
//!
//! The file (written by `fem2rbd run` when a ruin stage ran; docs/scenario-format.md) has
//! the header [`HEADER`]; states are `intact`, `plastic` or `broken`, times are seconds
//! or empty. A connection that starts the ruin stage plastic or broken (a hybrid hand-off)
//! is so from the stage's start. Checked: the header, the field count, body names of
//! `bodies.csv`, the states, finite times, and that a connection broken at the end has a
//! time of breaking or started broken. Errors name the file and line.
use super::{inconsistent, Result};
use crate::output::run_folder::{BodyInfo, RunFolder};
use std::collections::HashMap;
use std::path::Path;

/// The header of `connections.csv`.
pub const HEADER: &str =
    "a,b,start_state,final_state,time_broken_s,time_plastic_s,first_row_lost,time_first_row_lost_s";

/// One connection as the page uses it.
#[derive(Debug, Clone, PartialEq)]
pub struct Connection {
    /// The two bodies (indices into `bodies.csv`).
    pub bodies: [usize; 2],
    /// From when it is plastic or broken, s (`None`: intact to the end).
    pub plastic_from_s: Option<f64>,
    /// From when it is broken, s (`None`: not broken at the end).
    pub broken_from_s: Option<f64>,
}

/// The connections of the run folder `dir` (`None` when it holds no `connections.csv`,
/// as after an FE-only run). `run` is the folder already read.
pub fn load(dir: &Path, run: &RunFolder) -> Result<Option<Vec<Connection>>> {
    let path = dir.join("connections.csv");
    if !path.exists() {
        if run.summary.ruin_stage.is_some() {
            return Err(inconsistent(
                &path,
                "is missing, but summary.json has a ruin stage (a run folder written by \
                 `fem2rbd run` holds connections.csv when a ruin stage ran)",
            ));
        }
        return Ok(None);
    }
    let text = crate::model::limits::read_regular_file(&path).map_err(|error| {
        super::ReportError::Read {
            path: path.clone(),
            error,
        }
    })?;
    let start_s = match &run.summary.ruin_stage {
        Some(r) => r.start_s,
        None => {
            return Err(inconsistent(
                &path,
                "exists, but summary.json has no ruin stage",
            ))
        }
    };
    parse(&text, &path, &run.bodies, start_s).map(Some)
}

/// Parses `text` (the file `path`) against `bodies` (`bodies.csv`); `start_s` is the
/// ruin stage's start.
pub fn parse(
    text: &str,
    path: &Path,
    bodies: &[BodyInfo],
    start_s: f64,
) -> Result<Vec<Connection>> {
    let index: HashMap<String, usize> = bodies
        .iter()
        .enumerate()
        .map(|(i, b)| (b.id.name(), i))
        .collect();
    let at = |line: usize, msg: String| inconsistent(format!("{}:{line}", path.display()), msg);
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(text.as_bytes());
    let mut records = reader.records();
    let header = match records.next() {
        Some(Ok(h)) => h,
        _ => return Err(at(1, format!("the header must be {HEADER}"))),
    };
    if header.iter().collect::<Vec<_>>().join(",") != HEADER {
        return Err(at(1, format!("the header must be {HEADER}")));
    }
    let mut out = Vec::new();
    for record in records {
        let line = out.len() + 2;
        let r = record.map_err(|e| at(line, e.to_string()))?;
        let line = r.position().map_or(line, |p| p.line() as usize);
        if r.len() != 8 {
            return Err(at(line, format!("{} fields, the header has 8", r.len())));
        }
        let body = |k: usize| -> Result<usize> {
            index.get(&r[k]).copied().ok_or_else(|| {
                at(
                    line,
                    format!(
                        "column {}: body {:?} is not in bodies.csv",
                        ["a", "b"][k],
                        &r[k]
                    ),
                )
            })
        };
        let state = |k: usize, col: &str| -> Result<u8> {
            match &r[k] {
                "intact" => Ok(0),
                "plastic" => Ok(1),
                "broken" => Ok(2),
                s => Err(at(
                    line,
                    format!("column {col}: {s:?} must be intact, plastic or broken"),
                )),
            }
        };
        let time = |k: usize, col: &str| -> Result<Option<f64>> {
            let s = &r[k];
            if s.is_empty() {
                return Ok(None);
            }
            match s.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(Some(v)),
                _ => Err(at(
                    line,
                    format!("column {col}: {s:?} is not a finite number"),
                )),
            }
        };
        let bodies = [body(0)?, body(1)?];
        let start = state(2, "start_state")?;
        let end = state(3, "final_state")?;
        let broken = time(4, "time_broken_s")?;
        let plastic = time(5, "time_plastic_s")?;
        time(7, "time_first_row_lost_s")?;
        let broken_from_s = if start == 2 { Some(start_s) } else { broken };
        if (end == 2) != broken_from_s.is_some() {
            return Err(at(
                line,
                format!(
                    "final_state {} disagrees with time_broken_s {:?}",
                    &r[3], &r[4]
                ),
            ));
        }
        let plastic_from_s = if start >= 1 {
            Some(start_s)
        } else {
            match (plastic, broken) {
                (Some(p), Some(b)) => Some(p.min(b)),
                (p, b) => p.or(b),
            }
        };
        if (end >= 1) != plastic_from_s.is_some() {
            return Err(at(
                line,
                format!(
                    "final_state {} disagrees with time_plastic_s {:?} and time_broken_s {:?}",
                    &r[3], &r[5], &r[4]
                ),
            ));
        }
        out.push(Connection {
            bodies,
            plastic_from_s,
            broken_from_s,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bullet::Pose;

    fn bodies() -> Vec<BodyInfo> {
        ["Column:1:1", "Beam:1:2", "Slab:1:3"]
            .iter()
            .map(|n| BodyInfo {
                id: n.parse().unwrap(),
                passive: false,
                pose0: Pose::at([0.0, 0.0, 1.0]),
                half_extents: [0.1, 0.1, 0.5],
                mass_kg: 1.0,
            })
            .collect()
    }

    fn parse_rows(rows: &str) -> Result<Vec<Connection>> {
        parse(
            &format!("{HEADER}\n{rows}"),
            Path::new("c.csv"),
            &bodies(),
            1.5,
        )
    }

    #[test]
    fn times_of_plastic_and_broken_from_the_rows_and_the_start_state() {
        let c = parse_rows(
            "Column:1:1,Beam:1:2,intact,intact,,,,\n\
             Column:1:1,Slab:1:3,intact,plastic,,2.0400,bend_h,2.0400\n\
             Beam:1:2,Slab:1:3,intact,broken,3.1000,2.5000,,\n\
             Beam:1:2,Column:1:1,intact,broken,2.2000,,,\n\
             Slab:1:3,Column:1:1,plastic,broken,4.0000,,,\n\
             Slab:1:3,Beam:1:2,broken,broken,,,,\n",
        )
        .unwrap();
        let got: Vec<_> = c
            .iter()
            .map(|c| (c.bodies, c.plastic_from_s, c.broken_from_s))
            .collect();
        assert_eq!(
            got,
            [
                ([0, 1], None, None),
                ([0, 2], Some(2.04), None),
                ([1, 2], Some(2.5), Some(3.1)),
                // broken without a plastic phase: damaged from the break
                ([1, 0], Some(2.2), Some(2.2)),
                // plastic at the hand-off: from the ruin stage's start (1.5 s)
                ([2, 0], Some(1.5), Some(4.0)),
                ([2, 1], Some(1.5), Some(1.5)),
            ]
        );
    }

    #[test]
    fn bad_rows_are_named_by_line() {
        let e = parse_rows(
            "Column:1:1,Beam:1:2,intact,intact,,,,\nColumn:1:1,Beam:1:9,intact,intact,,,,\n",
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("c.csv:3: column b") && e.contains("Beam:1:9"),
            "{e}"
        );
        let e = parse_rows("Column:1:1,Beam:1:2,intact,snapped,,,,\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("c.csv:2: column final_state"), "{e}");
        let e = parse_rows("Column:1:1,Beam:1:2,intact,broken,,,,\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("c.csv:2:") && e.contains("time_broken_s"),
            "{e}"
        );
        let e = parse_rows("Column:1:1,Beam:1:2,intact,intact,x,,,\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("column time_broken_s"), "{e}");
        let e = parse("a,b\n", Path::new("c.csv"), &bodies(), 0.0)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("c.csv:1: the header must be"), "{e}");
    }
}
