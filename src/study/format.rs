//! The study file (`fem2rbd study … study.toml`): a base scenario and the axes it is run
//! over — models, records, intensities, modes. Documented key by key in
//! `docs/study-format.md`.
//!
//! The whole file is read and checked before anything runs: TOML syntax, unknown keys and
//! wrong types give `file:line:column`; a bad value gives `file:line` of its key where the
//! parser keeps the position (record files, intensities), else the item
//! (`study.toml: records.list[1]: ...`). Record files are read once here (their PGA fixes
//! the scale factors), so a missing or unreadable record is reported before any run.
//!
//! Paths inside the file are relative to the study file; `output` is relative to the
//! current directory (as a scenario's).
use super::error::{bail, At, Result, StudyError};
use crate::model::limits::MAX_PGA_G;
use crate::motion::{read_record, Format, G};
use crate::pipeline::{Mode, Scenario};
use serde::Deserialize;
use std::path::{Path, PathBuf};
use toml::Spanned;

/// Intensities are kept on a grid of 0.001 g (integer milli-g) so that run ids and the
/// IDA bisection are exact.
pub(crate) const MILLI_G: f64 = 0.001;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStudy {
    base: Spanned<PathBuf>,
    output: Option<PathBuf>,
    #[serde(default)]
    modes: Vec<Mode>,
    #[serde(default)]
    models: Vec<RawModel>,
    records: RawRecords,
    intensity: RawIntensity,
    #[serde(default)]
    ensemble: Option<RawEnsemble>,
    #[serde(default)]
    slurm: SlurmSpec,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawEnsemble {
    members: Spanned<i64>,
    #[serde(default = "one_u64")]
    seed: u64,
}

fn one_u64() -> u64 {
    1
}

/// Largest ensemble size of a study.
pub const MAX_MEMBERS: u32 = 1000;

/// The ensemble axis: every (model, record, mode, intensity) run `members` times, member 0
/// unperturbed, member m ≥ 1 perturbed as [`crate::pipeline::ensemble::Perturbation`]
/// of (`seed`, m).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Ensemble {
    /// Members per (model, record, mode, intensity); 1 = no ensemble.
    pub members: u32,
    /// Seed of the perturbations.
    pub seed: u64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawModel {
    name: String,
    file: Spanned<PathBuf>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRecords {
    #[serde(default = "one")]
    time_scale: f64,
    #[serde(default)]
    scale_by: ScaleBy,
    #[serde(default)]
    list: Vec<RawRecord>,
    #[serde(default)]
    folder: Vec<RawFolder>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRecord {
    name: String,
    x: Option<Spanned<PathBuf>>,
    y: Option<Spanned<PathBuf>>,
    z: Option<Spanned<PathBuf>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFolder {
    path: Spanned<PathBuf>,
    x: Option<String>,
    y: Option<String>,
    z: Option<String>,
    #[serde(default)]
    include: Vec<String>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawIntensity {
    #[serde(default)]
    pga_g: Vec<Spanned<f64>>,
    ida: Option<RawIda>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawIda {
    start_g: Spanned<f64>,
    step_g: Spanned<f64>,
    max_g: Spanned<f64>,
    tolerance_g: Spanned<f64>,
}

fn one() -> f64 {
    1.0
}

/// How a record's components share one scale factor for a target intensity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum ScaleBy {
    /// factor = target PGA / PGA of the X component (default).
    #[default]
    PgaX,
    /// factor = target PGA / √(PGA_X · PGA_Y), the geometric mean of the horizontal PGAs.
    PgaGeomean,
}

/// Slurm settings of `fem2rbd study slurm` (all can be overridden on the command line).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SlurmSpec {
    /// Stated wall-time estimate of one run, s (the time request is
    /// `shard · estimate_s · safety + 60 s`); `None`: the largest run's estimate
    /// ([`crate::estimate`], [`super::slurm::requests`]).
    pub estimate_s: Option<f64>,
    /// Safety factor on the time estimate.
    pub safety: f64,
    /// Memory request per task, MiB; `None`: the largest run's peak-memory estimate
    /// times `safety` ([`super::slurm::requests`]).
    pub mem_mb: Option<u64>,
    /// Manifest entries per array task.
    pub shard: usize,
    /// Most array tasks running at once (`--array=…%N`); 0 = no limit.
    pub throttle: usize,
    /// Partition (`--partition`); empty = the cluster's default.
    pub partition: String,
    /// Account (`--account`); empty = none.
    pub account: String,
}

impl Default for SlurmSpec {
    fn default() -> Self {
        SlurmSpec {
            estimate_s: None,
            safety: 2.0,
            mem_mb: None,
            shard: 1,
            throttle: 0,
            partition: String::new(),
            account: String::new(),
        }
    }
}

/// One model of the study.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyModel {
    /// Name used in run ids.
    pub name: String,
    /// Model file (resolved).
    pub file: PathBuf,
}

/// One record (up to three components) of the study.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyRecord {
    /// Name used in run ids.
    pub name: String,
    /// Component files, axis 0..3 = X, Y, Z (resolved).
    pub files: [Option<PathBuf>; 3],
    /// Each component's recorded PGA, g.
    pub pga_g: [Option<f64>; 3],
    /// The record's reference PGA, g, that the target intensity scales to
    /// ([`ScaleBy`]).
    pub reference_pga_g: f64,
}

/// The IDA rule: step up from `start` by `step` until collapse (or `max`), then bisect
/// between the highest intensity without collapse and the lowest with collapse until they
/// are at most `tolerance` apart. All in milli-g.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IdaRule {
    /// First intensity, milli-g.
    pub start: u32,
    /// Step of the stepping phase, milli-g.
    pub step: u32,
    /// Highest intensity tried, milli-g.
    pub max: u32,
    /// Bisection tolerance, milli-g.
    pub tolerance: u32,
}

/// The intensity axis.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Intensity {
    /// Fixed PGA targets (stripes), milli-g, ascending.
    Stripes(Vec<u32>),
    /// Incremental dynamic analysis.
    Ida(IdaRule),
}

/// A checked study.
#[derive(Debug, Clone)]
pub struct Study {
    /// The study file.
    pub path: PathBuf,
    /// Its name (file stem).
    pub name: String,
    /// The base scenario (its ground motions are replaced by the records).
    pub base: Scenario,
    /// Study folder.
    pub output: PathBuf,
    /// Modes, in file order.
    pub modes: Vec<Mode>,
    /// Models, in file order.
    pub models: Vec<StudyModel>,
    /// Records: the explicit list in file order, then each folder's records sorted by name.
    pub records: Vec<StudyRecord>,
    /// Time-scale factor of every component.
    pub time_scale: f64,
    /// How components share the scale factor.
    pub scale_by: ScaleBy,
    /// The intensity axis.
    pub intensity: Intensity,
    /// Slurm settings.
    pub slurm: SlurmSpec,
    /// The ensemble axis (`members = 1` without an `[ensemble]` table).
    pub ensemble: Ensemble,
}

/// 1-based line of byte offset `at` in `text`.
pub(crate) fn line_of(text: &str, at: usize) -> usize {
    text[..at.min(text.len())].matches('\n').count() + 1
}

/// A name usable in run ids and file names: `[A-Za-z0-9._-]`, not empty, no `__`, not
/// starting with `.`.
fn check_name(name: &str) -> Result<()> {
    if name.is_empty()
        || name.starts_with('.')
        || name.contains("__")
        || !name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-'))
    {
        bail!("name {name:?} must be letters, digits, '.', '_' or '-' (no \"__\", not starting with '.')");
    }
    Ok(())
}

/// Intensity in g → milli-g, which must be on the 0.001 g grid and in (0,
/// [`MAX_PGA_G`]] g, the range of a target PGA in every front end (docs/reliability.md).
fn milli(v: f64) -> Result<u32> {
    if !(v.is_finite() && v > 0.0 && v <= MAX_PGA_G) {
        bail!(
            "{} g is outside the target PGA range (0, {MAX_PGA_G}] g (above the largest \
             recorded ground accelerations, about 4 g)",
            crate::model::limits::show_number(v)
        );
    }
    let m = (v / MILLI_G).round();
    if ((m * MILLI_G) - v).abs() > 1e-9 {
        bail!("{v} g is not a multiple of 0.001 g");
    }
    Ok(m as u32)
}

/// Recorded PGA of a file in g.
fn record_pga(file: &Path) -> Result<f64> {
    let recs = read_record(file, Format::Auto)?;
    let [rec] = recs.as_slice() else {
        bail!(
            "{}: holds {} components; a study takes one component per file (AT2 or two-column)",
            file.display(),
            recs.len()
        );
    };
    let (pga, _) = rec.pga();
    if pga == 0.0 {
        bail!("{}: all samples are zero", file.display());
    }
    Ok(pga / G)
}

impl Study {
    /// Reads and checks a study file (module docs). Nothing is written.
    pub fn load(path: impl AsRef<Path>) -> Result<Study> {
        let path = path.as_ref();
        let text = crate::model::limits::read_regular_file(path)
            .at(|| format!("cannot read study file {}", path.display()))?;
        Self::parse(&text, path)
    }

    /// Parses study text; `path` names the file in errors and anchors relative paths.
    pub fn parse(text: &str, path: &Path) -> Result<Study> {
        let p = path.display();
        let raw: RawStudy = toml::from_str(text).map_err(|e| {
            let (line, col) = e
                .span()
                .map(|s| {
                    let before = &text[..s.start.min(text.len())];
                    let col = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
                    (line_of(text, s.start), col)
                })
                .unwrap_or((0, 0));
            StudyError::Invalid(format!("{p}:{line}: column {col}: {}", e.message()))
        })?;
        Mode::warn_former_names(text, &p.to_string());
        let at = |s: std::ops::Range<usize>| format!("{p}:{}", line_of(text, s.start));
        let base_dir = path.parent().unwrap_or(Path::new("."));
        let base_path = base_dir.join(raw.base.get_ref());
        let base =
            Scenario::load(&base_path).at(|| format!("{}: base scenario", at(raw.base.span())))?;
        let modes = if raw.modes.is_empty() {
            vec![base.mode]
        } else {
            let mut seen = Vec::new();
            for m in &raw.modes {
                if seen.contains(m) {
                    bail!("{p}: modes: {} given twice", m.name());
                }
                seen.push(*m);
            }
            seen
        };
        let mut models = Vec::new();
        for (i, m) in raw.models.iter().enumerate() {
            check_name(&m.name).at(|| format!("{p}: models[{i}]"))?;
            if models.iter().any(|o: &StudyModel| o.name == m.name) {
                bail!("{p}: models[{i}]: name {:?} given twice", m.name);
            }
            let file = base_dir.join(m.file.get_ref());
            if !file.is_file() {
                bail!(
                    "{}: models[{i}]: file {} does not exist",
                    at(m.file.span()),
                    file.display()
                );
            }
            models.push(StudyModel {
                name: m.name.clone(),
                file,
            });
        }
        if models.is_empty() {
            models.push(StudyModel {
                name: "base".into(),
                file: base.model.clone(),
            });
        }
        let rr = &raw.records;
        if !(rr.time_scale.is_finite() && rr.time_scale > 0.0) {
            bail!(
                "{p}: records.time_scale must be positive, got {}",
                rr.time_scale
            );
        }
        let mut records: Vec<StudyRecord> = Vec::new();
        let mut add =
            |name: String, files: [Option<(PathBuf, String)>; 3], item: String| -> Result<()> {
                check_name(&name).at(|| item.clone())?;
                if records.iter().any(|r| r.name == name) {
                    bail!("{item}: record name {name:?} given twice");
                }
                let mut pga = [None; 3];
                let mut paths: [Option<PathBuf>; 3] = [None, None, None];
                for (axis, f) in files.into_iter().enumerate() {
                    let Some((file, loc)) = f else { continue };
                    if !file.is_file() {
                        bail!("{loc}: record file {} does not exist", file.display());
                    }
                    pga[axis] = Some(record_pga(&file).at(|| loc.clone())?);
                    paths[axis] = Some(file);
                }
                let Some(px) = pga[0] else {
                    bail!("{item}: an X component is needed (the intensity scales to it)");
                };
                let reference = match rr.scale_by {
                    ScaleBy::PgaX => px,
                    ScaleBy::PgaGeomean => {
                        let Some(py) = pga[1] else {
                            bail!("{item}: scale_by = \"pga_geomean\" needs a Y component");
                        };
                        (px * py).sqrt()
                    }
                };
                records.push(StudyRecord {
                    name,
                    files: paths,
                    pga_g: pga,
                    reference_pga_g: reference,
                });
                Ok(())
            };
        for (i, r) in rr.list.iter().enumerate() {
            let files = [&r.x, &r.y, &r.z].map(|f| {
                f.as_ref()
                    .map(|s| (base_dir.join(s.get_ref()), at(s.span())))
            });
            add(r.name.clone(), files, format!("{p}: records.list[{i}]"))?;
        }
        for (i, f) in rr.folder.iter().enumerate() {
            let item = format!("{p}: records.folder[{i}]");
            let dir = base_dir.join(f.path.get_ref());
            let loc = at(f.path.span());
            if !dir.is_dir() {
                bail!(
                    "{loc}: records.folder[{i}]: {} is not a folder",
                    dir.display()
                );
            }
            let suffix = [&f.x, &f.y, &f.z];
            let Some(sx) = &f.x else {
                bail!("{item}: x (the file-name suffix of the X component) is needed");
            };
            let mut stems: Vec<String> = std::fs::read_dir(&dir)
                .at(|| format!("{loc}: cannot list {}", dir.display()))?
                .filter_map(|e| e.ok())
                .filter_map(|e| e.file_name().to_str().map(str::to_owned))
                .filter_map(|n| n.strip_suffix(sx.as_str()).map(str::to_owned))
                .filter(|s| !s.is_empty())
                .collect();
            stems.sort();
            if !f.include.is_empty() {
                for inc in &f.include {
                    if !stems.contains(inc) {
                        bail!(
                            "{item}: include: no record {inc:?} ({}{sx}) in {}",
                            inc,
                            dir.display()
                        );
                    }
                }
                stems.retain(|s| f.include.contains(s));
            }
            if stems.is_empty() {
                bail!("{item}: no file ending in {sx:?} in {}", dir.display());
            }
            for stem in stems {
                let files = suffix.map(|s| {
                    s.as_ref()
                        .map(|s| (dir.join(format!("{stem}{s}")), format!("{item}: {stem}")))
                });
                add(stem.clone(), files, format!("{item}: {stem}"))?;
            }
        }
        if records.is_empty() {
            bail!("{p}: records: at least one record (records.list or records.folder) is needed");
        }
        let ri = &raw.intensity;
        let intensity = match (&ri.pga_g[..], &ri.ida) {
            ([], None) => bail!("{p}: intensity: give pga_g = [...] or [intensity.ida]"),
            ([_, ..], Some(_)) => {
                bail!("{p}: intensity: give pga_g or [intensity.ida], not both")
            }
            (list, None) => {
                let mut v = Vec::new();
                for s in list {
                    let m =
                        milli(*s.get_ref()).at(|| format!("{}: intensity.pga_g", at(s.span())))?;
                    if v.contains(&m) {
                        bail!(
                            "{}: intensity.pga_g: {} g given twice",
                            at(s.span()),
                            s.get_ref()
                        );
                    }
                    v.push(m);
                }
                v.sort_unstable();
                Intensity::Stripes(v)
            }
            ([], Some(ida)) => {
                let g = |s: &Spanned<f64>, k: &str| {
                    milli(*s.get_ref()).at(|| format!("{}: intensity.ida.{k}", at(s.span())))
                };
                let rule = IdaRule {
                    start: g(&ida.start_g, "start_g")?,
                    step: g(&ida.step_g, "step_g")?,
                    max: g(&ida.max_g, "max_g")?,
                    tolerance: g(&ida.tolerance_g, "tolerance_g")?,
                };
                if rule.max < rule.start {
                    bail!(
                        "{}: intensity.ida.max_g is below start_g",
                        at(ida.max_g.span())
                    );
                }
                if rule.tolerance > rule.step {
                    bail!(
                        "{}: intensity.ida.tolerance_g must not exceed step_g",
                        at(ida.tolerance_g.span())
                    );
                }
                if modes.contains(&Mode::Rigid) {
                    bail!("{p}: intensity.ida needs modes fe or hybrid: rigid mode has no collapse moment");
                }
                Intensity::Ida(rule)
            }
        };
        let ensemble = match &raw.ensemble {
            None => Ensemble {
                members: 1,
                seed: 1,
            },
            Some(e) => {
                let n = *e.members.get_ref();
                if !(1..=i64::from(MAX_MEMBERS)).contains(&n) {
                    bail!(
                        "{}: ensemble.members must be 1 to {MAX_MEMBERS}, got {n}",
                        at(e.members.span())
                    );
                }
                if n > 1 && modes.contains(&Mode::Fe) {
                    bail!(
                        "{}: ensemble.members: members perturb the ruin stage only, so fe-mode members would be identical copies; use modes hybrid or rigid",
                        at(e.members.span())
                    );
                }
                Ensemble {
                    members: n as u32,
                    seed: e.seed,
                }
            }
        };
        let s = &raw.slurm;
        if s.estimate_s.is_some_and(|e| !(e.is_finite() && e > 0.0)) {
            bail!("{p}: slurm.estimate_s must be positive");
        }
        if !(s.safety.is_finite() && s.safety >= 1.0) {
            bail!("{p}: slurm.safety must be at least 1");
        }
        if s.shard == 0 || s.mem_mb == Some(0) {
            bail!("{p}: slurm.shard and slurm.mem_mb must be at least 1");
        }
        super::slurm::check_slurm_name(&s.partition, &format!("{p}: slurm.partition"))?;
        super::slurm::check_slurm_name(&s.account, &format!("{p}: slurm.account"))?;
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "study".into());
        if raw
            .output
            .as_ref()
            .is_some_and(|o| o.as_os_str().is_empty())
        {
            bail!(
                "{p}: output is empty: give a folder name, or leave it out for out/studies/{name}"
            );
        }
        let output = raw
            .output
            .clone()
            .unwrap_or_else(|| PathBuf::from("out/studies").join(&name));
        Ok(Study {
            path: path.to_path_buf(),
            name,
            base,
            output,
            modes,
            models,
            records,
            time_scale: rr.time_scale,
            scale_by: rr.scale_by,
            intensity,
            slurm: raw.slurm.clone(),
            ensemble,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intensities_are_on_the_milli_g_grid() {
        assert_eq!(milli(0.35).unwrap(), 350);
        assert_eq!(milli(1.2).unwrap(), 1200);
        assert!(milli(0.3505).is_err());
        assert!(milli(-0.1).is_err());
    }

    #[test]
    fn names_are_file_safe() {
        assert!(check_name("FF01").is_ok());
        assert!(check_name("el-centro.1940").is_ok());
        assert!(check_name("a__b").is_err());
        assert!(check_name("a/b").is_err());
        assert!(check_name(".x").is_err());
    }
}
