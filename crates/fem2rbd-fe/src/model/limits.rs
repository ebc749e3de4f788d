//! Resource bounds: the most one input may make fem2rbd allocate or compute before it
//! says no. Every count that sizes an allocation or a loop and comes from an input file
//! or an option (elements, fibres, load steps, ground-motion samples, FE steps, recorded
//! values, physics substeps) is checked against one of these ceilings **before** any
//! work is done, with an error naming the item, the value and the bound
//! ([`LimitError`]). The values are documented in `docs/reliability.md`.
//!
//! The ceilings are set two to three orders of magnitude above the largest model and
//! record the project runs (frame3, `data/frame3/model.toml`: 67 nodes, 96 elements, 80
//! and 112 fibres per section, 5 points per member, 10 gravity steps; El Centro RSN6:
//! 5 372 samples at 0.01 s; LC5 time-compressed by 0.5: 5 345 FE steps of 5 ms and at
//! most 6 345 physics substeps), and low enough that what they admit fits in the memory
//! of a workstation (the largest allocation each admits is listed with it).
//!
//! Counts are computed in `f64` or `u64` and compared before any cast to `usize`, so a
//! time step of 1e-300 s or a time scale of 1e300 gives an error, not an overflow.

/// Largest number of nodes of a model.
pub(crate) const MAX_NODES: usize = 200_000;
/// Largest number of elements of a model.
pub(crate) const MAX_ELEMENTS: usize = 200_000;
/// Largest number of fibres of one section (an RC section's core, cover and bars).
pub(crate) const MAX_FIBERS_PER_SECTION: u64 = 10_000;
/// Largest number of fibre states of a model: Σ over beam-column elements of
/// integration points × fibres of the section (≈ 200 bytes of material state each,
/// so at most ≈ 1 GB).
pub(crate) const MAX_FIBER_STATES: u64 = 5_000_000;
/// Largest number of load-control steps of gravity (`[gravity] load_steps`).
pub(crate) const MAX_LOAD_STEPS: u32 = 100_000;
/// Largest number of samples of one ground-motion record (AT2 `NPTS`, rows of a text
/// record) and of the integrated ground history (72 bytes per sample: at most 360 MB).
pub const MAX_SAMPLES: u64 = 5_000_000;
/// Largest number of FE time steps of one analysis (duration / Δt).
pub const MAX_FE_STEPS: u64 = 5_000_000;
/// Largest number of numbers an FE analysis may record (recorded steps × recorded
/// nodes × 6 DOFs; 8 bytes each: at most 2 GB).
pub(crate) const MAX_RECORDED_VALUES: u64 = 250_000_000;
/// Largest number of physics substeps of a ruin stage (time span × steps per second).
pub const MAX_PHYSICS_SUBSTEPS: u64 = 20_000_000;

// ---- physical ranges shared by every front end (scenario, `fe`, `export opensees`)

/// Largest target PGA, g: above the largest ground accelerations ever recorded (about 4 g);
/// the shipped LC5 scenario asks for 1.19 g.
pub const MAX_PGA_G: f64 = 5.0;
/// Range of a record's time-scale factor t' = f·t (dimensionless): similitude of models
/// from 1/10 000 to 10 000 times full size (f = √λ).
pub const TIME_SCALE: (f64, f64) = (0.01, 100.0);
/// Range of the FE time step Δt, s: below 1 µs a record of a few seconds needs millions
/// of steps; above 0.1 s the shaking is not resolved (records are sampled at 0.005 to
/// 0.02 s).
pub const FE_DT: (f64, f64) = (1e-6, 0.1);
/// Largest simulated time of a stage (FE duration, physics time limit, settle time), s.
pub const MAX_TIME_S: f64 = 3600.0;

/// A count over its ceiling (or not a finite count at all).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{item}: {what} {} exceeds the limit of {max} (docs/reliability.md, resource bounds)", show_count(*.count))]
pub struct LimitError {
    /// The item at fault, e.g. `fe.dt` or `gravity.load_steps`.
    pub item: String,
    /// What is counted, e.g. "ground-motion samples".
    pub what: &'static str,
    /// The count (may be infinite or NaN when it comes from floats).
    pub count: f64,
    /// The ceiling.
    pub max: u64,
}

impl LimitError {
    /// The message without the item (for errors that name the item themselves).
    pub fn short(&self) -> String {
        format!(
            "{} {} exceeds the limit of {} (docs/reliability.md, resource bounds)",
            self.what,
            show_count(self.count),
            self.max
        )
    }
}

/// Largest input file read (model, scenario, scene, ground-motion record), bytes:
/// 256 MiB, room for [`MAX_SAMPLES`] record samples of ≈ 50 characters.
pub(crate) const MAX_INPUT_BYTES: u64 = 256 << 20;

/// An input file that cannot be used: missing, unreadable, not a regular file, too large.
/// `what` names the kind of file ("model file"), `path` the file as given.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum InputFileError {
    /// The file does not exist.
    #[error("cannot read {what}: {} does not exist", path.display())]
    Missing {
        /// Kind of file, e.g. "model file".
        what: &'static str,
        /// The path as given.
        path: std::path::PathBuf,
    },
    /// The file exists but cannot be inspected or read.
    #[error("cannot read {what} {}: {error}", path.display())]
    Io {
        /// Kind of file.
        what: &'static str,
        /// The path as given.
        path: std::path::PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
    /// A folder, device or pipe (which could be endless: `/dev/zero`).
    #[error("{what} {} is not a regular file (a folder, device or pipe)", path.display())]
    NotAFile {
        /// Kind of file.
        what: &'static str,
        /// The path as given.
        path: std::path::PathBuf,
    },
    /// Longer than [`MAX_INPUT_BYTES`].
    #[error(
        "{what} {}: {bytes} bytes exceeds the limit of {MAX_INPUT_BYTES} bytes \
         (docs/reliability.md, resource bounds)",
        path.display()
    )]
    TooLarge {
        /// Kind of file.
        what: &'static str,
        /// The path as given.
        path: std::path::PathBuf,
        /// Its length, bytes.
        bytes: u64,
    },
}

/// An input file must exist, be a regular file (not a folder, device or pipe, which could
/// be endless: `/dev/zero`) and be at most [`MAX_INPUT_BYTES`] long. `what` names it
/// ("model file").
pub fn check_input_file(path: &std::path::Path, what: &'static str) -> Result<(), InputFileError> {
    let meta = std::fs::metadata(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => InputFileError::Missing {
            what,
            path: path.to_path_buf(),
        },
        _ => InputFileError::Io {
            what,
            path: path.to_path_buf(),
            error: e,
        },
    })?;
    if !meta.is_file() {
        return Err(InputFileError::NotAFile {
            what,
            path: path.to_path_buf(),
        });
    }
    if meta.len() > MAX_INPUT_BYTES {
        return Err(InputFileError::TooLarge {
            what,
            path: path.to_path_buf(),
            bytes: meta.len(),
        });
    }
    Ok(())
}

/// [`check_input_file`], then the file's text (UTF-8).
pub fn read_input_file(
    path: &std::path::Path,
    what: &'static str,
) -> Result<String, InputFileError> {
    check_input_file(path, what)?;
    std::fs::read_to_string(path).map_err(|e| InputFileError::Io {
        what,
        path: path.to_path_buf(),
        error: e,
    })
}

/// Reads a text input (a run folder's table, a study file) with the rules of
/// [`check_input_file`] — a regular file (a pipe or a device could be endless) of at most
/// [`MAX_INPUT_BYTES`] — as an I/O error whose message says which rule it breaks, for
/// readers whose errors carry the path themselves.
pub fn read_regular_file(path: &std::path::Path) -> std::io::Result<String> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a regular file (a folder, pipe or device is refused: it could be endless)",
        ));
    }
    if meta.len() > MAX_INPUT_BYTES {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!(
                "{} bytes exceed the limit of {MAX_INPUT_BYTES} (docs/reliability.md, resource bounds)",
                meta.len()
            ),
        ));
    }
    std::fs::read_to_string(path)
}

/// [`read_regular_file`] of a file a reader may do without: `None` when nothing is at
/// `path`; anything else that is there must be a regular file (a pipe named like the file
/// is refused, never waited on, and never taken for a missing file).
pub fn read_optional_regular_file(path: &std::path::Path) -> std::io::Result<Option<String>> {
    match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(e),
        Ok(_) => read_regular_file(path).map(Some),
    }
}

/// A count for a message: integers in full up to 10¹², else in scientific notation
/// (a count from a 300-digit input is not printed in full).
pub(crate) fn show_count(c: f64) -> String {
    if c.is_finite() && c.abs() < 1e12 && c.fract() == 0.0 {
        format!("{c:.0}")
    } else {
        format!("{c:.3e}")
    }
}

/// A number for a message: its shortest round-trip form when short (`0.005`, `1e300`),
/// else 4 significant digits in scientific notation (a 300-digit input is not printed
/// in full).
pub fn show_number(v: f64) -> String {
    let s = format!("{v}");
    let plain = v == 0.0 || !v.is_finite() || (1e-4..1e6).contains(&v.abs());
    if plain && s.len() <= 12 {
        return s;
    }
    let e = format!("{v:e}");
    if e.len() <= 12 {
        e
    } else {
        format!("{v:.3e}")
    }
}

/// Checks `count ≤ max`.
pub fn check(
    item: impl Into<String>,
    what: &'static str,
    count: u64,
    max: u64,
) -> Result<(), LimitError> {
    if count <= max {
        Ok(())
    } else {
        Err(LimitError {
            item: item.into(),
            what,
            count: count as f64,
            max,
        })
    }
}

/// The number of samples n = ⌊span/step⌋ + 1 of a uniform grid over `[0, span]`, checked
/// against `max` before it is turned into a `usize`. `span ≥ 0` and `step > 0` finite are
/// the caller's checks; a NaN or infinite count is an error here too.
pub fn grid_count(
    item: impl Into<String>,
    what: &'static str,
    span: f64,
    step: f64,
    max: u64,
) -> Result<usize, LimitError> {
    let n = (span / step + 1e-9).floor() + 1.0;
    if n.is_finite() && n >= 1.0 && n <= max as f64 {
        Ok(n as usize)
    } else {
        Err(LimitError {
            item: item.into(),
            what,
            count: n,
            max,
        })
    }
}

/// A value outside its physical range ([`check_range`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub struct RangeError {
    /// The item at fault, e.g. `physics.restitution`.
    pub item: String,
    /// The value given.
    pub value: f64,
    /// Lower bound.
    pub lo: f64,
    /// `true` if the lower bound itself is excluded (a positive quantity).
    pub lo_open: bool,
    /// Upper bound (included).
    pub hi: f64,
    /// Unit (SI), empty for a dimensionless value.
    pub unit: &'static str,
}

impl std::fmt::Display for RangeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let u = |s: &str| {
            if s.is_empty() {
                String::new()
            } else {
                format!(" {s}")
            }
        };
        write!(
            f,
            "{} = {}{}: must be in {}{}, {}]{}",
            self.item,
            show_number(self.value),
            u(self.unit),
            if self.lo_open { "(" } else { "[" },
            show_number(self.lo),
            show_number(self.hi),
            u(self.unit)
        )
    }
}

/// Checks `lo ≤ v ≤ hi` (or `lo < v ≤ hi` with `lo_open`); NaN and infinities fail.
pub fn check_range(
    item: impl Into<String>,
    v: f64,
    lo: f64,
    lo_open: bool,
    hi: f64,
    unit: &'static str,
) -> Result<(), RangeError> {
    let above = if lo_open { v > lo } else { v >= lo };
    if v.is_finite() && above && v <= hi {
        Ok(())
    } else {
        Err(RangeError {
            item: item.into(),
            value: v,
            lo,
            lo_open,
            hi,
            unit,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_count_bounds_before_the_cast() {
        assert_eq!(grid_count("x", "samples", 1.0, 0.25, 10).unwrap(), 5);
        assert_eq!(grid_count("x", "samples", 0.0, 0.25, 10).unwrap(), 1);
        // 11 samples > 10.
        let e = grid_count("fe.dt", "samples", 1.0, 0.1, 10).unwrap_err();
        assert_eq!(e.count, 11.0);
        assert!(e
            .to_string()
            .starts_with("fe.dt: samples 11 exceeds the limit of 10"));
        for (span, step) in [(53.45, 1e-300), (1e300, 0.005), (f64::INFINITY, 1.0)] {
            let e = grid_count("x", "samples", span, step, MAX_SAMPLES).unwrap_err();
            assert!(e.to_string().contains("e"), "{e}");
        }
        assert!(grid_count("x", "samples", f64::NAN, 1.0, 10).is_err());
    }

    #[test]
    fn numbers_are_shortened() {
        assert_eq!(show_count(5e6), "5000000");
        assert_eq!(show_count(1e300), "1.000e300");
        assert_eq!(show_number(0.005), "0.005");
        assert_eq!(show_number(1e300), "1e300");
        assert_eq!(show_number(1.0 / 3.0), "3.333e-1");
        assert_eq!(show_number(1e-6), "1e-6");
        assert_eq!(show_number(2e11), "2e11");
        assert_eq!(show_number(2699.75), "2699.75");
    }

    #[test]
    fn ranges_name_item_value_bounds_and_unit() {
        assert!(check_range("r", 0.5, 0.0, false, 1.0, "").is_ok());
        assert!(check_range("r", 0.0, 0.0, false, 1.0, "").is_ok());
        assert!(check_range("dt", 0.0, 0.0, true, 1.0, "s").is_err());
        assert!(check_range("r", f64::NAN, 0.0, false, 1.0, "").is_err());
        let e = check_range("physics.restitution", 5.0, 0.0, false, 1.0, "").unwrap_err();
        assert_eq!(e.to_string(), "physics.restitution = 5: must be in [0, 1]");
        let e = check_range("fe.dt", 1e300, 0.0, true, 0.1, "s").unwrap_err();
        assert_eq!(e.to_string(), "fe.dt = 1e300 s: must be in (0, 0.1] s");
    }
}
