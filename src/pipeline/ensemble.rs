//! Ensembles (docs/ruin-numerics.md): N runs of one scenario whose ruin stage starts from
//! a hand-off perturbed by a stated, physically negligible amount, run in parallel, and
//! the spread of their ruin measures.
//!
//! * **Member 0** is the unperturbed run (the same bytes as `fem2rbd run`).
//! * **Member m ≥ 1**, hybrid mode: every active body's hand-off velocity at Tc gets
//!   δv = ε_v·(u₁, u₂, u₃), uᵢ uniform in [−1, 1), ε_v = [`Perturbation::velocity_mps`]
//!   (default 1e-4 m/s = 0.1 mm/s, 10⁻⁴ of frame3's hand-off speeds of about 1 m/s, far
//!   below what the FE stage resolves). Rigid-only mode (no hand-off): every component
//!   of the ground acceleration is scaled by 1 + ε_g·u, ε_g = [`Perturbation::ground_share`]
//!   (default 1e-4, i.e. 0.01 % of the record's amplitude).
//! * The uᵢ come from SplitMix64 (Steele et al. 2014) seeded with (seed, member, stream,
//!   index): the same seed gives the same ensemble, on any number of threads.
//! * Members run on `threads` worker threads (`std::thread::scope`); each member is a
//!   complete, independent pipeline run (its own FE stage and Bullet world), so the
//!   results do not depend on the thread count (tested in `tests/it/pipeline/ensemble.rs`).
use super::error::{PipelineError, Result};
use super::{run_perturbed, RunRecord, Scenario, Silent};
use crate::output::location::FolderKind;
use serde_json::{json, Map, Value};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// How one member's start is perturbed (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Perturbation {
    /// Ensemble seed.
    pub seed: u64,
    /// Member number (≥ 1; member 0 is not perturbed).
    pub member: u64,
    /// ε_v, m/s: amplitude of the hand-off velocity perturbation (hybrid).
    pub velocity_mps: f64,
    /// ε_g: relative amplitude of the ground-motion scaling (rigid-only).
    pub ground_share: f64,
}

impl Perturbation {
    /// The defaults of the module docs for `member` of ensemble `seed`.
    pub fn new(seed: u64, member: u64) -> Self {
        Perturbation {
            seed,
            member,
            velocity_mps: 1e-4,
            ground_share: 1e-4,
        }
    }

    /// A number uniform in [−1, 1) for (stream, index): SplitMix64 of the mixed key.
    pub fn uniform(&self, stream: u64, index: u64) -> f64 {
        let mut z = self
            .seed
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add(self.member.wrapping_mul(0xBF58_476D_1CE4_E5B9))
            .wrapping_add(stream.wrapping_mul(0x94D0_49BB_1331_11EB))
            .wrapping_add(index);
        z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// Runs `n` members of `sc` (member 0 unperturbed) on `threads` threads; records in
/// member order.
pub fn run_ensemble(sc: &Scenario, n: usize, seed: u64, threads: usize) -> Result<Vec<RunRecord>> {
    if n == 0 {
        return Err(PipelineError::NoMembers);
    }
    if n > MAX_MEMBERS {
        return Err(PipelineError::TooManyMembers(n));
    }
    let next = AtomicUsize::new(0);
    let slots: Mutex<Vec<Option<Result<RunRecord>>>> = Mutex::new((0..n).map(|_| None).collect());
    std::thread::scope(|s| {
        for _ in 0..threads.clamp(1, n) {
            s.spawn(|| loop {
                let m = next.fetch_add(1, Ordering::SeqCst);
                if m >= n {
                    break;
                }
                let p = (m > 0).then(|| Perturbation::new(seed, m as u64));
                let r = run_perturbed(sc, &Silent, p.as_ref());
                slots.lock().expect("no poisoned lock")[m] = Some(r);
            });
        }
    });
    slots
        .into_inner()
        .expect("no poisoned lock")
        .into_iter()
        .enumerate()
        .map(|(m, r)| {
            r.unwrap_or(Err(PipelineError::NotRun(m)))
                .map_err(|e| PipelineError::Member {
                    member: m,
                    error: Box::new(e),
                })
        })
        .collect()
}

/// Percentiles (nearest rank) 50 / 90 / 100 of the horizontal distance of the active
/// bodies' final centres beyond the original footprint (0 inside), m.
pub(crate) fn distance_percentiles(rec: &RunRecord) -> [f64; 3] {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for b in rec.bodies.iter().filter(|b| !b.passive) {
        for c in crate::plan_geometry::corners(&b.pose0, b.half_extents) {
            for k in 0..2 {
                lo[k] = lo[k].min(c[k]);
                hi[k] = hi[k].max(c[k]);
            }
        }
    }
    let mut d: Vec<f64> = rec
        .bodies
        .iter()
        .zip(&rec.final_poses)
        .filter(|(b, _)| !b.passive)
        .map(|(_, p)| {
            let dx = (lo[0] - p.position[0]).max(p.position[0] - hi[0]).max(0.0);
            let dy = (lo[1] - p.position[1]).max(p.position[1] - hi[1]).max(0.0);
            dx.hypot(dy)
        })
        .collect();
    if d.is_empty() {
        return [0.0; 3];
    }
    d.sort_by(f64::total_cmp);
    let rank = |p: f64| d[((p * d.len() as f64).ceil() as usize).clamp(1, d.len()) - 1];
    [rank(0.5), rank(0.9), rank(1.0)]
}

/// Every number of a JSON value by its path (`a.b[2].c`), into `out`.
pub fn flatten(prefix: &str, v: &Value, out: &mut BTreeMap<String, f64>) {
    match v {
        Value::Number(x) => {
            if let Some(f) = x.as_f64() {
                out.insert(prefix.to_string(), f);
            }
        }
        Value::Object(m) => {
            for (k, x) in m {
                let p = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                flatten(&p, x, out);
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                flatten(&format!("{prefix}[{i}]"), x, out);
            }
        }
        _ => {}
    }
}

/// The ruin measures of one member, flattened (`ruins` of `summary.json` plus the
/// distance percentiles and the ruin stage's end time and fastest body).
pub fn member_measures(rec: &RunRecord) -> BTreeMap<String, f64> {
    let mut m = BTreeMap::new();
    let measures = serde_json::to_value(super::write::record_measures(rec)).unwrap_or_default();
    flatten("", &measures, &mut m);
    let [p50, p90, p100] = distance_percentiles(rec);
    m.insert("distance_beyond_footprint_m.p50".into(), p50);
    m.insert("distance_beyond_footprint_m.p90".into(), p90);
    m.insert("distance_beyond_footprint_m.p100".into(), p100);
    if let Some(f) = super::write::floors_down_of(rec) {
        m.insert("floors_down.t_s".into(), f.t_s);
        m.insert(
            "floors_down.stories_above_whole".into(),
            f64::from(u8::from(f.stories_above_whole)),
        );
    }
    if let Some(r) = &rec.ruin {
        m.insert("ruin_stage.end_s".into(), r.end_time_s);
        m.insert("ruin_stage.max_speed_mps".into(), r.ledger.max_speed_mps);
        m.insert(
            "ruin_stage.unsettled_bodies".into(),
            r.at_rest.iter().filter(|a| !**a).count() as f64,
        );
    }
    m
}

fn r6(x: f64) -> f64 {
    (x * 1e6).round() / 1e6 + 0.0
}

/// Mean, sample standard deviation (n − 1; 0 for one value), min and max of `v`, to 6
/// decimals, and the count as `members`.
pub fn stats_json(v: &[f64]) -> Value {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = if v.len() > 1 {
        v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)
    } else {
        0.0
    };
    json!({
        "mean": r6(mean), "std": r6(var.sqrt()),
        "min": r6(v.iter().copied().fold(f64::INFINITY, f64::min)),
        "max": r6(v.iter().copied().fold(f64::NEG_INFINITY, f64::max)),
        "members": v.len(),
    })
}

/// `ensemble.json`: per measure the mean, sample standard deviation, min and max over the
/// members (measures missing in a member are left out of that member).
pub fn ensemble_summary(sc: &Scenario, recs: &[RunRecord], seed: u64) -> Value {
    let mut all: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    for r in recs {
        for (k, v) in member_measures(r) {
            all.entry(k).or_default().push(v);
        }
    }
    let mut stats = Map::new();
    for (k, v) in all {
        stats.insert(k, stats_json(&v));
    }
    let p = Perturbation::new(seed, 1);
    json!({
        "mode": sc.mode.name(),
        "members": recs.len(),
        "seed": seed,
        "perturbation": if sc.mode == super::Mode::Rigid {
            json!({"kind": "ground_motion_scale", "relative_amplitude": p.ground_share})
        } else {
            json!({"kind": "handoff_velocity", "amplitude_mps": p.velocity_mps})
        },
        "member_0": "unperturbed",
        "measures": Value::Object(stats),
    })
}

/// Most members of one ensemble: every member is a whole run (frame3 LC5 about 10 s in a
/// release build, the library building about 20 min), and each keeps its records in
/// memory until the ensemble is written.
pub const MAX_MEMBERS: usize = 1000;

/// An ensemble folder: its members' run folders, `ensemble.json` and `plot`'s `plots/`.
/// An existing folder is written into only when it is such a folder and holds nothing else
/// ([`crate::output::location::check_replaceable`]).
pub const ENSEMBLE_FOLDER: FolderKind = FolderKind {
    name: "ensemble",
    owns: &[
        "member-*",
        "ensemble.json",
        "rescue_map.csv",
        "rescue.json",
        "plots",
    ],
};

/// Writes every member into `dir/member-NNN/` (without wall times, so the bytes depend
/// only on the input), `dir/ensemble.json` and, when every member has a ruin, the rescue
/// maps `dir/rescue_map.csv` and `dir/rescue.json` (`crate::rescue::ensemble`), and removes the member folders of an
/// earlier, larger ensemble in `dir`; returns the paths written.
pub fn write_ensemble(
    sc: &Scenario,
    recs: &[RunRecord],
    seed: u64,
    dir: &Path,
) -> Result<Vec<PathBuf>> {
    use crate::output::location::{check_replaceable, MARKER};
    use crate::output::OutputError;
    check_replaceable(dir, &ENSEMBLE_FOLDER, "output folder")?;
    std::fs::create_dir_all(dir).map_err(OutputError::io("cannot create", dir))?;
    crate::output::write_atomic(dir.join(MARKER), ENSEMBLE_FOLDER.marker_text().as_bytes())?;
    let mut out = Vec::new();
    for (m, r) in recs.iter().enumerate() {
        out.extend(super::write::write(
            r,
            &dir.join(format!("member-{m:03}")),
            false,
        )?);
    }
    // Members of an earlier, larger ensemble would be read as members of this one.
    if let Ok(entries) = std::fs::read_dir(dir) {
        for e in entries.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            let stale = name
                .strip_prefix("member-")
                .and_then(|k| k.parse::<usize>().ok())
                .is_some_and(|k| k >= recs.len());
            if stale {
                let p = e.path();
                std::fs::remove_dir_all(&p).map_err(OutputError::io("cannot remove", &p))?;
            }
        }
    }
    let p = dir.join("ensemble.json");
    let text = serde_json::to_string_pretty(&ensemble_summary(sc, recs, seed))? + "\n";
    crate::output::write_atomic(&p, text.as_bytes())?;
    out.push(p);
    // The rescue maps over the members' own rescue files (crate::rescue::ensemble).
    if recs.iter().all(|r| r.ruin.is_some()) {
        let maps = crate::rescue::ensemble::write_maps(dir)
            .map_err(|e| PipelineError::Rescue(Box::new(e)))?;
        out.extend(maps);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_numbers_are_in_range_and_depend_on_every_key() {
        let p = Perturbation::new(7, 3);
        let xs: Vec<f64> = (0..10_000).map(|i| p.uniform(1, i)).collect();
        assert!(xs.iter().all(|x| (-1.0..1.0).contains(x)));
        let mean = xs.iter().sum::<f64>() / xs.len() as f64;
        assert!(mean.abs() < 0.03, "{mean}");
        assert_ne!(p.uniform(1, 0), Perturbation::new(8, 3).uniform(1, 0));
        assert_ne!(p.uniform(1, 0), Perturbation::new(7, 4).uniform(1, 0));
        assert_ne!(p.uniform(1, 0), p.uniform(2, 0));
        assert_eq!(p.uniform(1, 5), Perturbation::new(7, 3).uniform(1, 5));
    }
}
