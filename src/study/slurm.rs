//! Slurm job arrays for a study (`fem2rbd study slurm`).
//!
//! [`write_batch`] takes the pending entries of the current plan (all runs of a stripe
//! study; the frontier of an IDA — [`super::plan`]) and writes, in `<study>/slurm/`:
//!
//! * `batch-NNN.ids` — the entries' ids, one a line (when they are the same as the last
//!   batch's, that batch is written again under its own number: calling `study slurm`
//!   twice before submitting gives one batch);
//! * `batch-NNN.sbatch` — an sbatch script for a job array of `ceil(n / shard)` tasks:
//!   task k runs lines `k·shard + 1 … (k+1)·shard` of the ids file, each with
//!   `fem2rbd --quiet study run-one STUDY ID --out DIR`, and exits with the last non-zero
//!   status (a failed run is recorded in its own folder either way). Requests:
//!   `--array=0-(T-1)%throttle`, one CPU, `--mem` and `--time` from [`requests`]:
//!   `--time` = shard × estimate × `slurm.safety` + 60 s, rounded up to a minute, and
//!   `--mem` = the memory estimate × `slurm.safety`, where the estimate is the study's
//!   `slurm.estimate_s` / `slurm.mem_mb` when stated, else that of the largest run
//!   ([`largest_run`], [`crate::estimate`]); logs per task `slurm/logs/batch-NNN-<jobid>_<task>.out`; `--chdir` the
//!   current folder, all paths absolute.
//!
//! [`submit_script`] writes `slurm/submit.sh`, a loop for a login node that submits the
//! next batch with `sbatch --wait` until nothing is pending (one batch for stripes, one
//! per IDA round), then runs `fem2rbd study collect`.
use super::error::{bail, At, Result, StudyError};
use super::exec::scenario_for;
use super::format::{Intensity, SlurmSpec, Study};
use super::plan::{Entry, Store};
use crate::estimate::{self, Estimate};
use crate::output::write_atomic;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Settings of the scripts (the study's `[slurm]` with command-line overrides).
#[derive(Debug, Clone)]
pub struct SlurmOptions {
    /// Requests.
    pub spec: SlurmSpec,
    /// The fem2rbd executable the tasks call (absolute).
    pub exe: PathBuf,
}

/// `--time` of a task running `shard` entries of `estimate_s` each: shard × estimate ×
/// safety + 60 s, rounded up to whole minutes, as `D-HH:MM:SS`.
pub fn time_request(spec: &SlurmSpec, estimate_s: f64) -> String {
    let s = spec.shard as f64 * estimate_s * spec.safety + 60.0;
    let min = (s / 60.0).ceil() as u64;
    let (d, h, m) = (min / 1440, (min / 60) % 24, min % 60);
    format!("{d}-{h:02}:{m:02}:00")
}

/// The largest estimate ([`crate::estimate::for_scenario`]) over the study's (model,
/// record, mode) combinations — the intensity does not change the work — and the run it
/// is for (`model/record/mode`). Reads every model and record once more (milliseconds
/// each). Combinations whose estimate fails (a model that does not load: its runs will
/// fail and be recorded) are left out; an error only if every one fails.
pub fn largest_run(study: &Study) -> Result<(String, Estimate)> {
    let milli_g = match &study.intensity {
        Intensity::Stripes(v) => v[0],
        Intensity::Ida(r) => r.start,
    };
    let mut best: Option<(String, Estimate)> = None;
    let mut first_error: Option<StudyError> = None;
    for (mi, m) in study.models.iter().enumerate() {
        for (ri, r) in study.records.iter().enumerate() {
            for &mode in &study.modes {
                let e = Entry {
                    id: String::new(),
                    round: 0,
                    model: mi,
                    record: ri,
                    mode,
                    milli_g,
                    member: 0,
                };
                let sc = scenario_for(study, &e, Path::new("."));
                match estimate::for_scenario(&sc) {
                    Ok((_, _, est)) => {
                        if best.as_ref().is_none_or(|b| est.seconds > b.1.seconds) {
                            best = Some((format!("{}/{}/{}", m.name, r.name, mode.name()), est));
                        }
                    }
                    Err(err) => {
                        first_error.get_or_insert_with(|| StudyError::At {
                            item: format!("estimating {}/{}/{}", m.name, r.name, mode.name()),
                            error: Box::new(err.into()),
                        });
                    }
                }
            }
        }
    }
    match (best, first_error) {
        (Some(b), _) => Ok(b),
        (None, Some(e)) => Err(e),
        (None, None) => Err(StudyError::Invalid(format!(
            "{}: the study has no runs",
            study.path.display()
        ))),
    }
}
/// The most runs an IDA sequence can take: the steps from `start_g` to `max_g`, then a
/// bisection of the widest bracket (a step, or 0 … `start_g`) down to `tolerance_g`.
pub fn max_runs_per_sequence(study: &Study) -> u64 {
    match &study.intensity {
        Intensity::Stripes(v) => v.len() as u64,
        Intensity::Ida(r) => {
            let steps = u64::from((r.max - r.start).div_ceil(r.step)) + 1;
            let width = r.step.max(r.start) as f64 / r.tolerance as f64;
            steps + width.log2().ceil().max(0.0) as u64
        }
    }
}

/// What a task asks Slurm for: wall time of one run (s) and memory (MiB), and where the
/// numbers come from.
#[derive(Debug, Clone, PartialEq)]
pub struct Requests {
    /// Wall time of one run, s (before shard × safety).
    pub estimate_s: f64,
    /// Memory per task, MiB.
    pub mem_mb: u64,
    /// Where they come from, for the script's comment.
    pub source: String,
}

/// The requests of `spec` (module docs): stated values win; what is not stated comes from
/// the estimate of the study's largest run (time as estimated; memory × `safety`).
pub fn requests(study: &Study, spec: &SlurmSpec) -> Result<Requests> {
    if let (Some(t), Some(m)) = (spec.estimate_s, spec.mem_mb) {
        return Ok(Requests {
            estimate_s: t,
            mem_mb: m,
            source: format!("stated: {t} s and {m} MiB per run"),
        });
    }
    let (run, e) = largest_run(study)?;
    let mem = spec
        .mem_mb
        .unwrap_or_else(|| (e.peak_bytes * spec.safety / (1024.0 * 1024.0)).ceil() as u64);
    let t = spec.estimate_s.unwrap_or(e.seconds);
    Ok(Requests {
        estimate_s: t,
        mem_mb: mem,
        source: format!(
            "estimate of the largest run ({run}): {:.1} s, {} (fem2rbd::estimate, docs/reliability.md){}",
            e.seconds,
            estimate::show_bytes(e.peak_bytes),
            match (spec.estimate_s, spec.mem_mb) {
                (Some(_), _) => "; time stated",
                (_, Some(_)) => "; memory stated",
                _ => "",
            }
        ),
    })
}

fn abs(p: &Path) -> Result<PathBuf> {
    std::path::absolute(p).at(|| format!("cannot make {} absolute", p.display()))
}

/// Single-quotes a path for bash.
fn sh(p: &Path) -> String {
    format!("'{}'", p.display().to_string().replace('\'', r"'\''"))
}

/// Checks a Slurm partition or account before it goes into an `#SBATCH` line: Slurm's
/// names are letters, digits, `_`, `-` and `.`, and a partition may be a list of them
/// separated by commas. Anything else (a newline, a space, quotes, `$(…)`) would change
/// the job script, so it is refused, naming `item`.
pub fn check_slurm_name(value: &str, item: &str) -> Result<()> {
    let ok = value.split(',').all(|n| {
        !n.is_empty()
            && n.chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
    });
    if !value.is_empty() && !ok {
        bail!(
            "{item} {value:?}: a Slurm partition or account is letters, digits, '_', '-' and \
             '.' (a partition list separated by commas); this value would change the job script"
        );
    }
    Ok(())
}

/// Checks a path before it goes into an `#SBATCH` line, where sbatch splits options at
/// white space, takes no shell quoting and expands `%` patterns: such a path is refused,
/// naming `item`.
fn check_sbatch_path(p: &Path, item: &str) -> Result<()> {
    let s = p.display().to_string();
    if let Some(c) = s
        .chars()
        .find(|c| c.is_control() || c.is_whitespace() || matches!(c, '"' | '\'' | '\\' | '%'))
    {
        bail!(
            "{item} {s:?} holds {c:?}, which an #SBATCH line cannot carry; run the study from, \
             and write it to, a folder whose path has no white space, quotes, backslashes or '%'"
        );
    }
    Ok(())
}

/// Checks the study's name (its file's stem) before it goes into the scripts' comment
/// lines and the job name: no control characters (a newline would start a new line of
/// the script).
fn check_study_name(study: &Study) -> Result<()> {
    if study.name.chars().any(char::is_control) {
        bail!(
            "study file {}: its name holds a control character, which would change the job \
             script; rename the file",
            study.path.display()
        );
    }
    Ok(())
}

/// The job name: `fem2rbd-` and the study's name with every character other than a
/// letter, digit, `_`, `-` or `.` replaced by `_`.
fn job_name(study: &Study) -> String {
    let name: String = study
        .name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("fem2rbd-{name}")
}

/// Writes the next batch (module docs) and returns its sbatch script, or `None` when
/// nothing is pending.
pub fn write_batch(study: &Study, store: &Store, opt: &SlurmOptions) -> Result<Option<PathBuf>> {
    let plan = store.plan(study);
    let ids: Vec<&str> = plan.pending().map(|e| e.id.as_str()).collect();
    if ids.is_empty() {
        return Ok(None);
    }
    let spec = &opt.spec;
    if spec.shard == 0 {
        bail!("shard must be at least 1");
    }
    // Every value that goes into the script is checked before anything is written.
    check_slurm_name(&spec.partition, "slurm.partition")?;
    check_slurm_name(&spec.account, "slurm.account")?;
    check_study_name(study)?;
    let dir = abs(&store.dir.join("slurm"))?;
    let cwd = abs(Path::new("."))?;
    check_sbatch_path(&cwd, "the current folder (--chdir)")?;
    check_sbatch_path(&dir, "the study's slurm folder (--output)")?;
    let req = requests(study, spec)?;
    std::fs::create_dir_all(dir.join("logs")).at(|| format!("cannot create {}", dir.display()))?;
    let mut k = 0;
    while dir.join(format!("batch-{k:03}.sbatch")).exists() {
        k += 1;
    }
    let ids_text = ids.join("\n") + "\n";
    // The same pending set as the last batch: that batch again (idempotent).
    if k > 0 {
        let last = format!("batch-{:03}", k - 1);
        if std::fs::read_to_string(dir.join(format!("{last}.ids")))
            .ok()
            .as_deref()
            == Some(ids_text.as_str())
        {
            k -= 1;
        }
    }
    let stem = format!("batch-{k:03}");
    let ids_file = dir.join(format!("{stem}.ids"));
    let script = dir.join(format!("{stem}.sbatch"));
    write_atomic(&ids_file, ids_text.as_bytes())?;
    let tasks = ids.len().div_ceil(spec.shard);
    let mut s = String::new();
    let _ = writeln!(s, "#!/bin/bash");
    let _ = writeln!(
        s,
        "# fem2rbd study {}: {} run(s) in {} array task(s), {} per task.",
        study.name,
        ids.len(),
        tasks,
        spec.shard
    );
    let _ = writeln!(
        s,
        "# Written by `fem2rbd study slurm`. Per run: {}.",
        req.source
    );
    let _ = writeln!(
        s,
        "# time request = {} x {:.1} s x {} + 60 s; memory = {} MiB.",
        spec.shard, req.estimate_s, spec.safety, req.mem_mb
    );
    let _ = writeln!(s, "#SBATCH --job-name={}", job_name(study));
    let throttle = if spec.throttle > 0 {
        format!("%{}", spec.throttle)
    } else {
        String::new()
    };
    let _ = writeln!(s, "#SBATCH --array=0-{}{throttle}", tasks - 1);
    let _ = writeln!(s, "#SBATCH --ntasks=1");
    let _ = writeln!(s, "#SBATCH --cpus-per-task=1");
    let _ = writeln!(s, "#SBATCH --time={}", time_request(spec, req.estimate_s));
    let _ = writeln!(s, "#SBATCH --mem={}M", req.mem_mb);
    let _ = writeln!(s, "#SBATCH --chdir={}", cwd.display());
    let _ = writeln!(
        s,
        "#SBATCH --output={}",
        dir.join("logs").join(format!("{stem}-%A_%a.out")).display()
    );
    if !spec.partition.is_empty() {
        let _ = writeln!(s, "#SBATCH --partition={}", spec.partition);
    }
    if !spec.account.is_empty() {
        let _ = writeln!(s, "#SBATCH --account={}", spec.account);
    }
    let _ = writeln!(s, "set -u");
    let _ = writeln!(s, "EXE={}", sh(&opt.exe));
    let _ = writeln!(s, "STUDY={}", sh(&abs(&study.path)?));
    let _ = writeln!(s, "OUT={}", sh(&abs(&store.dir)?));
    let _ = writeln!(s, "IDS={}", sh(&ids_file));
    let _ = writeln!(s, "SHARD={}", spec.shard);
    s.push_str(
        r#"first=$(( SLURM_ARRAY_TASK_ID * SHARD + 1 ))
last=$(( first + SHARD - 1 ))
status=0
for id in $(sed -n "${first},${last}p" "$IDS"); do
    echo "fem2rbd run $id: start $(date -u +%FT%T.%NZ) on $(hostname)"
    "$EXE" --quiet study run-one "$STUDY" "$id" --out "$OUT" || status=$?
    echo "fem2rbd run $id: end $(date -u +%FT%T.%NZ) status $status"
done
exit $status
"#,
    );
    write_atomic(&script, s.as_bytes())?;
    Ok(Some(script))
}

/// Writes `slurm/submit.sh` (module docs); `extra` are the `study slurm` options to pass
/// on (already shell-quoted).
pub fn submit_script(
    study: &Study,
    store: &Store,
    opt: &SlurmOptions,
    extra: &str,
) -> Result<PathBuf> {
    check_study_name(study)?;
    let dir = abs(&store.dir.join("slurm"))?;
    std::fs::create_dir_all(&dir).at(|| format!("cannot create {}", dir.display()))?;
    let p = dir.join("submit.sh");
    let s = format!(
        r#"#!/bin/bash
# Runs fem2rbd study {name} on Slurm from a login node: submits the pending runs as a job
# array and waits (sbatch --wait), again until nothing is pending (one batch for a stripe
# study, one per IDA round), then collects. Written by `fem2rbd study slurm`.
set -u
cd {cwd}
EXE={exe}
STUDY={study}
OUT={out}
while :; do
    script=$("$EXE" --quiet study slurm "$STUDY" --out "$OUT" --exe "$EXE"{extra}) || exit 1
    [ -n "$script" ] || break
    sbatch --parsable --wait "$script" || echo "submit.sh: some runs of $script failed (recorded in their folders)" >&2
done
exec "$EXE" study collect "$STUDY" --out "$OUT"
"#,
        name = study.name,
        cwd = sh(&abs(Path::new("."))?),
        exe = sh(&opt.exe),
        study = sh(&abs(&study.path)?),
        out = sh(&abs(&store.dir)?),
    );
    write_atomic(&p, s.as_bytes())?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o755))?;
    }
    Ok(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_request_rounds_up_to_minutes() {
        let spec = SlurmSpec {
            safety: 2.0,
            shard: 3,
            ..Default::default()
        };
        // 3 × 600 × 2 + 60 = 3660 s = 61 min.
        assert_eq!(time_request(&spec, 600.0), "0-01:01:00");
        let big = SlurmSpec {
            safety: 1.5,
            shard: 20,
            ..Default::default()
        };
        // 20 × 3600 × 1.5 + 60 = 108060 s = 1801 min = 1 d 06:01.
        assert_eq!(time_request(&big, 3600.0), "1-06:01:00");
    }
}
