//! Readers for ground-acceleration files. Every error names `file:line`.
//!
//! - **PEER AT2** (NGA-West2): three header lines, then a line with either
//!   `NPTS=   5372, DT=   .0100 SEC,` or `5372    0.0100    NPTS, DT`, then the samples in g,
//!   any number per line (Fortran `E15.7`, e.g. `-.8338791E-03`; a `D` exponent is accepted).
//!   The number of samples must equal NPTS.
//! - **Two-column** `t a`: one sample per line, separated by whitespace, `,` or `;`;
//!   a in m/s² (or in g with `Format::TwoColumn { in_g: true }`).
//! - **BCB CSV** `t, ax, ay, az` (Bullet Constraints Builder, `docs/bcb.md` §6): in s and
//!   m/s², separators `,` `;` tab or space; lines starting with `#` or `/` are skipped.
//!
//! Text formats need a uniform time step: each time must lie within 1e-3·dt of
//! `t0 + i·dt`, with dt = (t_last − t0)/(n − 1). (BCB sorts rows by time and allows any
//! spacing; here an unsorted or uneven file is an error naming the first bad line.)

use super::MotionError;
use super::{Record, G};
use crate::model::limits::show_number;

/// What reading a record returns.
type Result<T> = std::result::Result<T, MotionError>;

/// An error at a line of a record file.
fn at(file: &str, line: usize, message: String) -> MotionError {
    MotionError::Syntax {
        file: file.to_string(),
        line,
        message,
    }
}
use std::path::Path;

/// File format for [`read_record`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Format {
    /// `.at2` → AT2, `.csv` → BCB CSV; otherwise by content: a line mentioning `NPTS` in
    /// the first 10 lines → AT2, four numeric columns → CSV, two → two-column in m/s².
    #[default]
    Auto,
    /// PEER AT2 (values in g).
    At2,
    /// Two columns `t a`; `in_g` says the accelerations are in g instead of m/s².
    TwoColumn {
        /// Accelerations in g (converted with [`G`]).
        in_g: bool,
    },
    /// BCB-style `t, ax, ay, az` in m/s².
    Csv,
}

/// Reads a ground-acceleration file.
///
/// Returns one [`Record`] (named after the file stem) for AT2 and two-column files, and
/// three records `stem:x`, `stem:y`, `stem:z` for a BCB CSV file.
pub fn read_record(path: &Path, format: Format) -> Result<Vec<Record>> {
    let text = crate::model::limits::read_input_file(path, "ground-motion file")?;
    let file = path.display().to_string();
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| file.clone());
    let format = match format {
        Format::Auto => detect(path, &text),
        f => f,
    };
    match format {
        Format::At2 => Ok(vec![parse_at2(&text, &file, &stem)?]),
        Format::TwoColumn { in_g } => {
            let (t0, dt, cols) = parse_columns(&text, &file, 2)?;
            let f = if in_g { G } else { 1.0 };
            let a = cols[0].iter().map(|v| v * f).collect();
            Ok(vec![
                Record::new(stem, dt, t0, a).map_err(|e| e.in_file(&file))?
            ])
        }
        Format::Csv => {
            let (t0, dt, cols) = parse_columns(&text, &file, 4)?;
            cols.into_iter()
                .zip(["x", "y", "z"])
                .map(|(a, ax)| {
                    Record::new(format!("{stem}:{ax}"), dt, t0, a).map_err(|e| e.in_file(&file))
                })
                .collect()
        }
        Format::Auto => unreachable!("resolved above"),
    }
}

/// Largest time step of a record (s). Strong-motion records are sampled at 0.001 to
/// 0.04 s; one sample per second would already be no earthquake record.
pub(crate) const MAX_RECORD_DT: f64 = 1.0;

fn detect(path: &Path, text: &str) -> Format {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    match ext.as_str() {
        "at2" => return Format::At2,
        "csv" => return Format::Csv,
        _ => {}
    }
    if text
        .lines()
        .take(10)
        .any(|l| l.to_ascii_uppercase().contains("NPTS"))
    {
        return Format::At2;
    }
    let first = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#') && !l.starts_with('/'));
    match first.map(|l| split_fields(l).len()) {
        Some(4) => Format::Csv,
        _ => Format::TwoColumn { in_g: false },
    }
}

/// Parses a Fortran-style real: accepts `.5`, `-.8338791E-03`, `1.0D+00`.
fn parse_real(tok: &str) -> Option<f64> {
    let v: f64 = if tok.contains(['d', 'D']) {
        tok.replace(['d', 'D'], "E").parse().ok()?
    } else {
        tok.parse().ok()?
    };
    v.is_finite().then_some(v)
}

/// Reads the AT2 header line: `NPTS= n, DT= dt SEC` or `n dt NPTS, DT`.
fn parse_at2_header(line: &str) -> Option<(usize, f64)> {
    let up = line.to_ascii_uppercase();
    if let Some(p) = up.find("NPTS=") {
        let rest = &up[p + 5..];
        let npts_tok = rest.split(',').next()?.trim();
        let d = up.find("DT=")?;
        let dt_tok = up[d + 3..]
            .split(|c: char| c == ',' || c.is_whitespace())
            .find(|s| !s.is_empty())?;
        return Some((npts_tok.parse().ok()?, parse_real(dt_tok)?));
    }
    let mut toks = up.split_whitespace();
    let npts = toks.next()?.parse().ok()?;
    let dt = parse_real(toks.next()?.trim_end_matches(','))?;
    let tail: String = toks.collect::<Vec<_>>().join(" ");
    (tail.starts_with("NPTS")).then_some((npts, dt))
}

fn parse_at2(text: &str, file: &str, stem: &str) -> Result<Record> {
    let lines: Vec<&str> = text.lines().collect();
    // The NPTS line is line 4 in both NGA forms; look at the first 10 lines in case of
    // extra header lines.
    let Some(hdr) = lines
        .iter()
        .take(10)
        .position(|l| l.to_ascii_uppercase().contains("NPTS"))
    else {
        return Err(at(
            file,
            4,
            "AT2 header line not found: expected `NPTS= <n>, DT= <dt> SEC` or \
             `<n> <dt> NPTS, DT` within the first 10 lines"
                .into(),
        ));
    };
    for (i, l) in lines[..hdr].iter().enumerate() {
        let up = l.to_ascii_uppercase();
        if up.contains("VELOCITY") || up.contains("DISPLACEMENT") {
            return Err(at(
                file,
                i + 1,
                format!("not an acceleration record: {}", l.trim()),
            ));
        }
        if let Some(u) = up.find("UNITS OF") {
            let unit = up[u + 8..].split_whitespace().next().unwrap_or("");
            if unit != "G" {
                return Err(at(
                    file,
                    i + 1,
                    format!("AT2 values must be in g, the header says `{}`", l.trim()),
                ));
            }
        }
    }
    let (npts, dt) = parse_at2_header(lines[hdr]).ok_or_else(|| {
        at(
            file,
            hdr + 1,
            format!(
                "bad AT2 header line `{}`: expected `NPTS= <n>, DT= <dt> SEC` or \
                 `<n> <dt> NPTS, DT`",
                lines[hdr].trim()
            ),
        )
    })?;
    if npts == 0 || !(dt > 0.0) {
        return Err(at(
            file,
            hdr + 1,
            format!(
                "AT2 header needs NPTS > 0 and DT > 0, got NPTS={npts}, DT={}",
                show_number(dt)
            ),
        ));
    }
    crate::model::limits::check(
        format!("{file}:{}: AT2 header", hdr + 1),
        "NPTS",
        npts as u64,
        crate::model::limits::MAX_SAMPLES,
    )?;
    crate::model::limits::check_range(
        format!("{file}:{}: AT2 header DT", hdr + 1),
        dt,
        0.0,
        true,
        MAX_RECORD_DT,
        "s",
    )?;
    let mut a = Vec::with_capacity(npts.min(1 << 16));
    let mut last_line = hdr + 1;
    for (i, l) in lines.iter().enumerate().skip(hdr + 1) {
        for tok in l.split_whitespace() {
            let v = parse_real(tok)
                .ok_or_else(|| at(file, i + 1, format!("`{tok}` is not a number")))?;
            if a.len() == npts {
                return Err(at(
                    file,
                    i + 1,
                    format!("more samples than NPTS = {npts} (line {})", hdr + 1),
                ));
            }
            a.push(v * G);
        }
        if !l.trim().is_empty() {
            last_line = i + 1;
        }
    }
    if a.len() != npts {
        return Err(at(
            file,
            last_line,
            format!(
                "{} samples read but NPTS = {npts} (line {})",
                a.len(),
                hdr + 1
            ),
        ));
    }
    Record::new(stem, dt, 0.0, a).map_err(|e| e.in_file(file))
}

fn split_fields(line: &str) -> Vec<&str> {
    line.split([',', ';', '\t', ' '])
        .filter(|s| !s.is_empty())
        .collect()
}

/// Parses `ncol` numeric columns (time first) into (t0, dt, value columns).
fn parse_columns(text: &str, file: &str, ncol: usize) -> Result<(f64, f64, Vec<Vec<f64>>)> {
    let mut t = Vec::new();
    let mut line_no = Vec::new();
    let mut cols = vec![Vec::new(); ncol - 1];
    for (i, raw) in text.lines().enumerate() {
        let l = raw.trim();
        if l.is_empty() || l.starts_with('#') || l.starts_with('/') {
            continue;
        }
        let f = split_fields(l);
        if f.len() != ncol {
            return Err(at(
                file,
                i + 1,
                format!(
                    "expected {ncol} columns ({}), found {}",
                    if ncol == 2 { "t a" } else { "t, ax, ay, az" },
                    f.len()
                ),
            ));
        }
        let mut vals = Vec::with_capacity(ncol);
        for tok in f {
            vals.push(
                parse_real(tok)
                    .ok_or_else(|| at(file, i + 1, format!("`{tok}` is not a number")))?,
            );
        }
        if t.len() as u64 >= crate::model::limits::MAX_SAMPLES {
            crate::model::limits::check(
                format!("{file}:{}", i + 1),
                "rows",
                t.len() as u64 + 1,
                crate::model::limits::MAX_SAMPLES,
            )?;
        }
        t.push(vals[0]);
        line_no.push(i + 1);
        for (c, v) in cols.iter_mut().zip(&vals[1..]) {
            c.push(*v);
        }
    }
    if t.len() < 2 {
        return Err(MotionError::Content {
            file: file.to_string(),
            message: format!("need at least two samples, found {}", t.len()),
        });
    }
    let n = t.len();
    for k in 1..n {
        if !(t[k] > t[k - 1]) {
            return Err(at(
                file,
                line_no[k],
                format!("time {} does not increase (previous {})", t[k], t[k - 1]),
            ));
        }
    }
    let t0 = t[0];
    let dt = (t[n - 1] - t0) / (n - 1) as f64;
    for k in 1..n {
        let expect = t0 + k as f64 * dt;
        if (t[k] - expect).abs() > 1e-3 * dt {
            return Err(at(
                file,
                line_no[k],
                format!(
                    "time {} is off the uniform step {dt} s (expected {expect})",
                    t[k]
                ),
            ));
        }
    }
    if t0 < 0.0 {
        return Err(at(file, line_no[0], format!("negative start time {t0}")));
    }
    crate::model::limits::check_range(
        format!("{file}:{}: time step of the rows", line_no[1]),
        dt,
        0.0,
        true,
        MAX_RECORD_DT,
        "s",
    )?;
    crate::model::limits::check_range(
        format!("{file}:{}: start time", line_no[0]),
        t0,
        0.0,
        false,
        1e4,
        "s",
    )?;
    Ok((t0, dt, cols))
}
