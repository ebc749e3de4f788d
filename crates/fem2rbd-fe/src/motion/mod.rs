//! Ground motions: PEER AT2 / two-column / BCB CSV readers, scaling, time scaling,
//! interpolation and integration to ground velocity and displacement.
//!
//! Units: time in s, acceleration in m/s² inside the program. Records given in g are
//! converted with [`G`] = 9.81 m/s², the value the reference OpenSees runs of frame3 use
//! (`frame3.json`: `gravity = 9.81`), so that a PGA target in g means the same here and there.
//!
//! - [`read_record`] reads one file ([`Format`]) into one or three [`Record`]s.
//! - [`GroundMotion`] holds the X, Y and Z components (each optional), scales them to a
//!   target PGA, scales time (scale-model similitude) and interpolates `accel_at(t)`.
//! - [`GroundMotion::integrate`] gives a [`GroundHistory`]: acceleration, velocity and
//!   displacement on a fixed step with a documented baseline correction, queried with
//!   [`GroundHistory::ground_state_at`] for the moving ground after the collapse moment.

// `!(x > 0.0)` is used on purpose: it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod integrate;
mod read;
pub mod spec;

pub use integrate::{Baseline, GroundHistory};
pub use read::{read_record, Format};

/// A ground motion that cannot be read, built or scaled. Messages name the file and line
/// (record files), the record, or the component.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MotionError {
    /// The record file cannot be read (missing, not a file, too large, unreadable).
    #[error(transparent)]
    File(#[from] crate::model::limits::InputFileError),
    /// A line of a record file that is not what its format says.
    #[error("{file}:{line}: {message}")]
    Syntax {
        /// File name as given.
        file: String,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A record file as a whole (too few samples, several components where one is wanted).
    #[error("{file}: {message}")]
    Content {
        /// File name as given.
        file: String,
        /// What is wrong.
        message: String,
    },
    /// A record's values (time step, start time, samples, scaling).
    #[error("record {name}: {message}")]
    Record {
        /// Record name.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// A target PGA for a component the motion does not have.
    #[error("no {axis} component to scale")]
    NoComponent {
        /// "X", "Y" or "Z".
        axis: &'static str,
    },
    /// A value outside its physical range.
    #[error(transparent)]
    Range(#[from] crate::model::limits::RangeError),
    /// A count over its resource bound (`docs/reliability.md`).
    #[error(transparent)]
    Limit(#[from] crate::model::limits::LimitError),
    /// A `--gm DIR=PATH[,pga=G]` argument that does not parse.
    #[error(transparent)]
    Arg(#[from] spec::GmArgError),
    /// Command-line options of the ground motion: a direction given twice, a motion of
    /// zero length, a bad integration step.
    #[error("{0}")]
    Options(String),
    /// An error inside a file, under the file's name.
    #[error("{file}: {error}")]
    InFile {
        /// File name as given.
        file: String,
        /// The error.
        error: Box<MotionError>,
    },
}

impl MotionError {
    /// The same error under the name of the file it came from.
    pub fn in_file(self, file: &str) -> Self {
        MotionError::InFile {
            file: file.to_string(),
            error: Box::new(self),
        }
    }
}

/// What building or scaling a motion returns.
type Result<T> = std::result::Result<T, MotionError>;

/// A record error.
fn record_error(name: &str, message: String) -> MotionError {
    MotionError::Record {
        name: name.to_string(),
        message,
    }
}

/// Standard gravity used to convert records in g to m/s² (m/s²). Equal to the `gravity`
/// of the reference OpenSees model `frame3.json` (not 9.80665), so PGA targets agree.
pub const G: f64 = 9.81;

/// One component of a ground acceleration record on a uniform time grid.
///
/// Sample `i` is at time `t0_s + i·dt_s`.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// Name of the component (file stem, or `stem:x` for one column of a CSV file).
    pub name: String,
    /// Time step (s), > 0.
    pub dt_s: f64,
    /// Time of the first sample (s), ≥ 0; 0 for AT2 files.
    pub t0_s: f64,
    /// Accelerations (m/s²).
    pub accel_mps2: Vec<f64>,
}

impl Record {
    /// Builds a record, checking `dt > 0`, `t0 ≥ 0`, at least one sample, all finite.
    pub fn new(
        name: impl Into<String>,
        dt_s: f64,
        t0_s: f64,
        accel_mps2: Vec<f64>,
    ) -> Result<Self> {
        let name = name.into();
        if !(dt_s.is_finite() && dt_s > 0.0) {
            return Err(record_error(
                &name,
                format!("time step must be positive, got {dt_s}"),
            ));
        }
        if !(t0_s.is_finite() && t0_s >= 0.0) {
            return Err(record_error(
                &name,
                format!("start time must be finite and non-negative, got {t0_s}"),
            ));
        }
        if accel_mps2.is_empty() {
            return Err(record_error(&name, "no samples".into()));
        }
        if let Some(i) = accel_mps2.iter().position(|a| !a.is_finite()) {
            return Err(record_error(&name, format!("sample {i} is not finite")));
        }
        Ok(Self {
            name,
            dt_s,
            t0_s,
            accel_mps2,
        })
    }

    /// Time of the last sample (s): `t0 + (n − 1)·dt`. For El Centro 270 this is 53.45 s.
    pub fn end_time_s(&self) -> f64 {
        self.t0_s + (self.accel_mps2.len() - 1) as f64 * self.dt_s
    }

    /// Peak ground acceleration: the largest |a| (m/s², positive) and the time of that
    /// sample (s). The first sample wins on a tie.
    pub fn pga(&self) -> (f64, f64) {
        let mut best = (0.0, self.t0_s);
        for (i, a) in self.accel_mps2.iter().enumerate() {
            if a.abs() > best.0 {
                best = (a.abs(), self.t0_s + i as f64 * self.dt_s);
            }
        }
        best
    }

    /// Multiplies every sample by `factor`.
    pub fn scale(&mut self, factor: f64) {
        for a in &mut self.accel_mps2 {
            *a *= factor;
        }
    }

    /// Scales the record so that its PGA becomes `target_g · G` (m/s²). Errors if the
    /// record is all zeros or the target is negative / not finite.
    pub fn scale_to_pga(&mut self, target_g: f64) -> Result<()> {
        if !(target_g.is_finite() && target_g >= 0.0) {
            return Err(record_error(
                &self.name,
                format!("target PGA must be ≥ 0 g, got {target_g}"),
            ));
        }
        let (pga, _) = self.pga();
        if pga == 0.0 {
            return Err(record_error(
                &self.name,
                "all samples are zero, cannot scale to a PGA".into(),
            ));
        }
        let target = target_g * G;
        for a in &mut self.accel_mps2 {
            // Divide then multiply so that the peak sample becomes exactly ±target.
            *a = *a / pga * target;
        }
        Ok(())
    }

    /// Scale-model similitude in time: t' = f·t (dt and t0 multiplied by `f`). Only time
    /// is scaled; scale accelerations separately (e.g. with [`Record::scale_to_pga`]).
    pub fn time_scale(&mut self, f: f64) -> Result<()> {
        if !(f.is_finite() && f > 0.0) {
            return Err(record_error(
                &self.name,
                format!("time-scale factor must be positive, got {f}"),
            ));
        }
        self.dt_s *= f;
        self.t0_s *= f;
        Ok(())
    }

    /// Acceleration at time `t` (m/s²) by linear interpolation between samples; 0 before
    /// `t0` and after the last sample.
    pub fn accel_at(&self, t: f64) -> f64 {
        let s = (t - self.t0_s) / self.dt_s;
        let n = self.accel_mps2.len();
        if !(s >= 0.0) || s > (n - 1) as f64 {
            return 0.0;
        }
        let i = (s.floor() as usize).min(n - 1);
        if i == n - 1 {
            return self.accel_mps2[i];
        }
        let w = s - i as f64;
        self.accel_mps2[i] * (1.0 - w) + self.accel_mps2[i + 1] * w
    }
}

/// A three-component ground motion: X, Y (horizontal) and Z (vertical), each optional.
///
/// Its length is that of the **shortest** present component (as in the reference OpenSees
/// runs, where El Centro is cut to the 270 component's 53.45 s); [`GroundMotion::accel_at`]
/// is zero outside `[0, duration]`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GroundMotion {
    /// Components X, Y, Z.
    pub components: [Option<Record>; 3],
}

impl GroundMotion {
    /// A ground motion from its X, Y, Z components.
    pub fn new(x: Option<Record>, y: Option<Record>, z: Option<Record>) -> Self {
        Self {
            components: [x, y, z],
        }
    }

    /// Reads X, Y, Z from one file each (`None`: no such component), each file holding
    /// one component (AT2 or two-column; see [`read_record`]).
    pub fn from_files(paths: [Option<&std::path::Path>; 3], format: Format) -> Result<Self> {
        let mut gm = Self::default();
        for (k, p) in paths.iter().enumerate() {
            if let Some(p) = p {
                let mut v = read_record(p, format)?;
                if v.len() != 1 {
                    return Err(MotionError::Content {
                        file: p.display().to_string(),
                        message: format!(
                            "holds {} components; give it as a three-component CSV instead",
                            v.len()
                        ),
                    });
                }
                gm.components[k] = v.pop();
            }
        }
        Ok(gm)
    }

    /// Reads a BCB-style `t, ax, ay, az` CSV (m/s²) as the X, Y, Z components.
    pub fn from_csv(path: &std::path::Path) -> Result<Self> {
        let v = read_record(path, Format::Csv)?;
        let mut it = v.into_iter();
        Ok(Self::new(it.next(), it.next(), it.next()))
    }

    /// Duration (s): the smallest end time of the present components; 0 if none.
    pub fn duration_s(&self) -> f64 {
        self.components
            .iter()
            .flatten()
            .map(Record::end_time_s)
            .reduce(f64::min)
            .unwrap_or(0.0)
    }

    /// Scales each present component to its own target PGA in g (`None` leaves it as is).
    /// A target given for an absent component is an error.
    pub fn scale_to_pga(&mut self, targets_g: [Option<f64>; 3]) -> Result<()> {
        for (axis, (c, t)) in self.components.iter_mut().zip(targets_g).enumerate() {
            match (c, t) {
                (Some(r), Some(t)) => r.scale_to_pga(t)?,
                (None, Some(_)) => return Err(MotionError::NoComponent { axis: AXES[axis] }),
                _ => {}
            }
        }
        Ok(())
    }

    /// Time-scales every component: t' = f·t.
    pub fn time_scale(&mut self, f: f64) -> Result<()> {
        for r in self.components.iter_mut().flatten() {
            r.time_scale(f)?;
        }
        Ok(())
    }

    /// Ground acceleration (m/s²) along X, Y, Z at time `t` (s): linear interpolation of
    /// each component; zero for an absent component, for `t < 0` and for `t` beyond
    /// [`GroundMotion::duration_s`] (the ground stops shaking at the end of the record).
    pub fn accel_at(&self, t: f64) -> [f64; 3] {
        let mut a = [0.0; 3];
        if !(t >= 0.0) || t > self.duration_s() {
            return a;
        }
        for (k, c) in self.components.iter().enumerate() {
            if let Some(r) = c {
                a[k] = r.accel_at(t);
            }
        }
        a
    }
}

/// Axis names for messages.
pub(crate) const AXES: [&str; 3] = ["X", "Y", "Z"];

/// A ground-motion direction: global X, Y or Z (files and `--gm` write `X`, `Y`, `Z`,
/// in either case).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Direction {
    /// Global X (index 0).
    X,
    /// Global Y (index 1).
    Y,
    /// Global Z, vertical (index 2).
    Z,
}

impl Direction {
    /// The three directions in axis order.
    pub const ALL: [Direction; 3] = [Direction::X, Direction::Y, Direction::Z];

    /// Axis index: 0 = X, 1 = Y, 2 = Z.
    pub fn index(self) -> usize {
        self as usize
    }
}

impl std::fmt::Display for Direction {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(AXES[self.index()])
    }
}

/// A name that is not a [`Direction`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("direction {0:?} is not X, Y or Z")]
pub struct UnknownDirection(pub String);

impl std::str::FromStr for Direction {
    type Err = UnknownDirection;
    /// `X`, `Y` or `Z`, in either case, surrounding blanks ignored.
    fn from_str(s: &str) -> std::result::Result<Self, UnknownDirection> {
        match s.trim().to_ascii_uppercase().as_str() {
            "X" => Ok(Direction::X),
            "Y" => Ok(Direction::Y),
            "Z" => Ok(Direction::Z),
            _ => Err(UnknownDirection(s.trim().to_string())),
        }
    }
}

impl<'de> serde::Deserialize<'de> for Direction {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        s.parse().map_err(serde::de::Error::custom)
    }
}
