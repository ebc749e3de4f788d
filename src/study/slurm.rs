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
//!   `--array=0-(T-1)%throttle`, one CPU, `--mem` from `slurm.mem_mb`, and
//!   `--time` = shard × `slurm.estimate_s` × `slurm.safety` + 60 s, rounded up to a
//!   minute; logs per task `slurm/logs/batch-NNN-<jobid>_<task>.out`; `--chdir` the
//!   current folder, all paths absolute.
//!
//! [`submit_script`] writes `slurm/submit.sh`, a loop for a login node that submits the
//! next batch with `sbatch --wait` until nothing is pending (one batch for stripes, one
//! per IDA round), then runs `fem2rbd study collect`.
use super::format::{SlurmSpec, Study};
use super::plan::Store;
use crate::output::write_atomic;
use anyhow::{bail, Context, Result};
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

/// `--time` of a task running `shard` entries: shard × estimate × safety + 60 s, rounded
/// up to whole minutes, as `D-HH:MM:SS`.
pub(crate) fn time_request(spec: &SlurmSpec) -> String {
    let s = spec.shard as f64 * spec.estimate_s * spec.safety + 60.0;
    let min = (s / 60.0).ceil() as u64;
    let (d, h, m) = (min / 1440, (min / 60) % 24, min % 60);
    format!("{d}-{h:02}:{m:02}:00")
}

fn abs(p: &Path) -> Result<PathBuf> {
    std::path::absolute(p).with_context(|| format!("cannot make {} absolute", p.display()))
}

/// Single-quotes a path for bash.
fn sh(p: &Path) -> String {
    format!("'{}'", p.display().to_string().replace('\'', r"'\''"))
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
    let dir = abs(&store.dir.join("slurm"))?;
    std::fs::create_dir_all(dir.join("logs"))
        .with_context(|| format!("cannot create {}", dir.display()))?;
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
        "# Written by `fem2rbd study slurm`; time request = {} x {} s x {} + 60 s.",
        spec.shard, spec.estimate_s, spec.safety
    );
    let _ = writeln!(s, "#SBATCH --job-name=fem2rbd-{}", study.name);
    let throttle = if spec.throttle > 0 {
        format!("%{}", spec.throttle)
    } else {
        String::new()
    };
    let _ = writeln!(s, "#SBATCH --array=0-{}{throttle}", tasks - 1);
    let _ = writeln!(s, "#SBATCH --ntasks=1");
    let _ = writeln!(s, "#SBATCH --cpus-per-task=1");
    let _ = writeln!(s, "#SBATCH --time={}", time_request(spec));
    let _ = writeln!(s, "#SBATCH --mem={}M", spec.mem_mb);
    let _ = writeln!(s, "#SBATCH --chdir={}", abs(Path::new("."))?.display());
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
    let dir = abs(&store.dir.join("slurm"))?;
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
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
            estimate_s: 600.0,
            safety: 2.0,
            shard: 3,
            ..Default::default()
        };
        // 3 × 600 × 2 + 60 = 3660 s = 61 min.
        assert_eq!(time_request(&spec), "0-01:01:00");
        let big = SlurmSpec {
            estimate_s: 3600.0,
            safety: 1.5,
            shard: 20,
            ..Default::default()
        };
        // 20 × 3600 × 1.5 + 60 = 108060 s = 1801 min = 1 d 06:01.
        assert_eq!(time_request(&big), "1-06:01:00");
    }
}
