//! `fem2rbd study plan|run|run-one|slurm|collect STUDY.toml`: batch studies
//! ([`fem2rbd::study`], `docs/study-format.md`, `docs/studies.md`). Thin: options, the
//! study progress bar and the child-process runner; the logic is in the library.
use anyhow::{anyhow, bail, Context, Result};
use clap::{Args, Subcommand};
use fem2rbd::study::exec::{run_local, run_one};
use fem2rbd::study::slurm::{submit_script, write_batch, SlurmOptions};
use fem2rbd::study::{collect, Outcome, Store, Study};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::Command;

/// The study subcommands.
#[derive(Debug, Subcommand)]
pub enum StudyCommand {
    /// Print the manifest: one line per run (id, round, model, record, mode, pga_g).
    Plan(Common),
    /// Run every pending run on this machine, `--jobs` at a time, then collect.
    Run(StudyRunArgs),
    /// Run one manifest entry by id (what each Slurm task calls).
    RunOne(RunOneArgs),
    /// Write the next sbatch job-array script (prints its path; nothing when no run is
    /// pending) and slurm/submit.sh.
    Slurm(SlurmArgs),
    /// Check that every run is complete and aggregate into results/.
    Collect(CollectArgs),
}

/// Options every study subcommand takes.
#[derive(Debug, Args)]
pub struct Common {
    /// Study file (TOML, docs/study-format.md).
    pub study: PathBuf,
    /// Override the study folder (the file's `output`).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Options of `study run`.
#[derive(Debug, Args)]
pub struct StudyRunArgs {
    #[command(flatten)]
    pub common: Common,
    /// Runs at once (child processes).
    #[arg(long, short, default_value_t = 1)]
    pub jobs: usize,
    /// Run failed runs again (their folders are removed first).
    #[arg(long)]
    pub retry_failed: bool,
}

/// Options of `study run-one`.
#[derive(Debug, Args)]
pub struct RunOneArgs {
    /// Study file.
    pub study: PathBuf,
    /// Run id (a manifest line's first field).
    pub id: String,
    /// Override the study folder.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Options of `study slurm` (override the study's `[slurm]`).
#[derive(Debug, Args)]
pub struct SlurmArgs {
    #[command(flatten)]
    pub common: Common,
    /// fem2rbd executable the tasks run (default: this one).
    #[arg(long)]
    pub exe: Option<PathBuf>,
    /// Runs per array task.
    #[arg(long)]
    pub shard: Option<usize>,
    /// Most tasks at once (`--array=…%N`; 0 = no limit).
    #[arg(long)]
    pub throttle: Option<usize>,
    /// Stated wall time of one run, s (default: the study's `slurm.estimate_s`, else the
    /// estimate of its largest run).
    #[arg(long)]
    pub estimate_s: Option<f64>,
    /// Memory per task, MiB (default: the study's `slurm.mem_mb`, else the largest run's
    /// estimate × safety).
    #[arg(long)]
    pub mem_mb: Option<u64>,
    /// Partition.
    #[arg(long)]
    pub partition: Option<String>,
}

/// Options of `study collect`.
#[derive(Debug, Args)]
pub struct CollectArgs {
    #[command(flatten)]
    pub common: Common,
    /// Aggregate what is complete instead of failing on pending runs.
    #[arg(long)]
    pub partial: bool,
}

fn load(study: &PathBuf, out: &Option<PathBuf>) -> Result<(Study, Store)> {
    let mut s = Study::load(study)?;
    if let Some(o) = out {
        s.output = o.clone();
    }
    if s.output.exists() && !s.output.is_dir() {
        bail!(
            "study folder {} exists and is not a folder",
            s.output.display()
        );
    }
    let store = Store::new(s.output.clone());
    Ok((s, store))
}

/// Refuses a study whose models hold values outside their plausible ranges, unless
/// `allow` ([`super::plausible`]); checked by the commands that start runs.
fn plausible_models(study: &Study, allow: bool) -> Result<()> {
    for m in &study.models {
        // A model that does not load fails its runs, which record the error.
        if let Ok(model) = fem2rbd::model::Model::load(&m.file) {
            super::plausible(&model, &m.file, allow)?;
        }
    }
    Ok(())
}

/// Runs a study subcommand.
pub fn run(cmd: &StudyCommand, quiet: bool, allow_unusual: bool) -> Result<()> {
    match cmd {
        StudyCommand::Plan(c) => {
            let (study, store) = load(&c.study, &c.out)?;
            let plan = store.plan(&study);
            print!("{}", plan.manifest(&study));
            if !quiet {
                let pending = plan.pending().count();
                match fem2rbd::study::slurm::largest_run(&study) {
                    Ok((run, e)) => eprintln!(
                        "estimate: the largest run ({run}) {e}; an IDA sequence takes at most {} runs (docs/reliability.md)",
                        fem2rbd::study::slurm::max_runs_per_sequence(&study)
                    ),
                    Err(e) => eprintln!("estimate: not available ({e:#})"),
                }
                eprintln!(
                    "study {}: {} run(s) planned, {} complete, {pending} pending{}",
                    study.name,
                    plan.entries.len(),
                    plan.entries.len() - pending,
                    if plan.sequences.is_empty() {
                        String::new()
                    } else {
                        format!(
                            "; IDA: {} of {} sequences finished (more rounds are planned as runs complete)",
                            plan.sequences
                                .iter()
                                .filter(|s| s.state != fem2rbd::study::plan::SequenceState::Running)
                                .count(),
                            plan.sequences.len()
                        )
                    }
                );
            }
            Ok(())
        }
        StudyCommand::RunOne(a) => {
            let (study, store) = load(&a.study, &a.out)?;
            let plan = store.plan(&study);
            let Some(entry) = plan.entries.iter().find(|e| e.id == a.id) else {
                bail!(
                    "{}: run id {:?} is not in the plan (`fem2rbd study plan` lists the runs known so far)",
                    study.path.display(),
                    a.id
                );
            };
            if let Some(Outcome::Ok { .. }) = store.outcome(&entry.id) {
                if !quiet {
                    eprintln!("{}: complete, skipped", entry.id);
                }
                return Ok(());
            }
            match run_one(&study, &store, entry)? {
                Outcome::Ok { collapse } => {
                    if !quiet {
                        eprintln!("{}: ok (collapse: {collapse})", entry.id);
                    }
                    Ok(())
                }
                Outcome::Failed(e) => Err(anyhow!("{}: failed (recorded): {e}", entry.id)),
            }
        }
        StudyCommand::Run(a) => {
            let (study, store) = load(&a.common.study, &a.common.out)?;
            plausible_models(&study, allow_unusual)?;
            // Held until the runs end; a second `study run` of the folder is refused.
            let _lock = fem2rbd::study::lock::StudyLock::acquire(&store.dir)?;
            if a.retry_failed {
                let plan = store.plan(&study);
                for (e, o) in plan.entries.iter().zip(&plan.outcomes) {
                    if let Some(Outcome::Failed(_)) = o {
                        std::fs::remove_dir_all(store.run_dir(&e.id))?;
                    }
                }
            }
            let exe = std::env::current_exe().context("cannot find the fem2rbd executable")?;
            let study_path = study.path.clone();
            let out = store.dir.clone();
            let runner = |e: &fem2rbd::study::Entry| -> Result<()> {
                let o = Command::new(&exe)
                    .arg("--quiet")
                    .args(["study", "run-one"])
                    .arg(&study_path)
                    .arg(&e.id)
                    .arg("--out")
                    .arg(&out)
                    .output()
                    .with_context(|| format!("cannot start {}", exe.display()))?;
                if o.status.success() {
                    Ok(())
                } else {
                    let err = String::from_utf8_lossy(&o.stderr);
                    let tail: Vec<&str> = err.lines().rev().take(5).collect();
                    let tail: Vec<&str> = tail.into_iter().rev().collect();
                    Err(anyhow!("{} ({})", tail.join(" | "), o.status))
                }
            };
            let bar = if !quiet && std::io::stderr().is_terminal() {
                let b = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::stderr());
                b.set_style(
                    ProgressStyle::with_template(
                        "study {prefix} {bar:40} {pos}/{len} runs [{elapsed_precise}, eta {eta}]",
                    )
                    .expect("valid template"),
                );
                b.set_prefix(study.name.clone());
                Some(b)
            } else {
                None
            };
            let progress = |done: usize, total: usize| {
                if let Some(b) = &bar {
                    b.set_length(total as u64);
                    b.set_position(done as u64);
                }
            };
            if let (Some(_), Ok((run, e))) = (&bar, fem2rbd::study::slurm::largest_run(&study)) {
                let plan = store.plan(&study);
                let pending = plan.pending().count() as u64;
                let (runs, what) = if plan.sequences.is_empty() {
                    (pending, format!("{pending} run(s) pending"))
                } else {
                    let per = fem2rbd::study::slurm::max_runs_per_sequence(&study);
                    let open = plan
                        .sequences
                        .iter()
                        .filter(|s| s.state == fem2rbd::study::plan::SequenceState::Running)
                        .count() as u64;
                    (
                        open * per,
                        format!("{open} IDA sequence(s) open, at most {per} runs each"),
                    )
                };
                let jobs = a.jobs.max(1) as f64;
                eprintln!(
                    "estimate: {what}; the largest run ({run}) {e}; at most {} on {} job(s), {} peak memory (docs/reliability.md)",
                    fem2rbd::estimate::show_seconds(runs as f64 * e.seconds / jobs),
                    a.jobs.max(1),
                    fem2rbd::estimate::show_bytes(e.peak_bytes * jobs)
                );
            }
            let t0 = std::time::Instant::now();
            let s = run_local(&study, &store, a.jobs, &runner, &progress)?;
            if let Some(b) = &bar {
                b.finish_and_clear();
            }
            let files = collect::collect(&study, &store, false)?;
            if !quiet {
                eprintln!(
                    "study {}: {} run(s) ok, {} failed, {} already complete; {:.1} s; results in {}",
                    study.name,
                    s.ok,
                    s.failed,
                    s.skipped,
                    t0.elapsed().as_secs_f64(),
                    files[0].parent().map_or(String::new(), |p| p.display().to_string())
                );
            }
            let failed = store
                .plan(&study)
                .outcomes
                .iter()
                .filter(|o| matches!(o, Some(Outcome::Failed(_))))
                .count();
            if failed > 0 {
                bail!(
                    "{failed} run(s) failed (errors in runs/<id>/status.json and results/runs.csv; `--retry-failed` runs them again)"
                );
            }
            Ok(())
        }
        StudyCommand::Slurm(a) => {
            // Checked before the study folder is touched: it goes into the job script.
            if let Some(v) = &a.partition {
                fem2rbd::study::slurm::check_slurm_name(v, "--partition")?;
            }
            let (study, store) = load(&a.common.study, &a.common.out)?;
            plausible_models(&study, allow_unusual)?;
            let mut spec = study.slurm.clone();
            let mut extra = String::new();
            if let Some(v) = a.shard {
                spec.shard = v;
                extra += &format!(" --shard {v}");
            }
            if let Some(v) = a.throttle {
                spec.throttle = v;
                extra += &format!(" --throttle {v}");
            }
            if let Some(v) = a.estimate_s {
                spec.estimate_s = Some(v);
                extra += &format!(" --estimate-s {v}");
            }
            if let Some(v) = a.mem_mb {
                spec.mem_mb = Some(v);
                extra += &format!(" --mem-mb {v}");
            }
            if let Some(v) = &a.partition {
                extra += &format!(" --partition '{}'", v.replace('\'', r"'\''"));
                spec.partition = v.clone();
            }
            if spec.shard == 0
                || spec.estimate_s.is_some_and(|e| !(e.is_finite() && e > 0.0))
                || spec.mem_mb == Some(0)
            {
                bail!("--shard, --estimate-s and --mem-mb must be positive");
            }
            let exe = match &a.exe {
                Some(e) => std::path::absolute(e)?,
                None => std::env::current_exe().context("cannot find the fem2rbd executable")?,
            };
            let opt = SlurmOptions { spec, exe };
            let batch = write_batch(&study, &store, &opt)?;
            let submit = submit_script(&study, &store, &opt, &extra)?;
            if let Some(p) = batch {
                println!("{}", p.display());
                if !quiet {
                    eprintln!(
                        "submit with: sbatch {}   (or run {} to go through every IDA round and collect)",
                        p.display(),
                        submit.display()
                    );
                }
            } else if !quiet {
                eprintln!(
                    "study {}: nothing pending; collect with `fem2rbd study collect`",
                    study.name
                );
            }
            Ok(())
        }
        StudyCommand::Collect(a) => {
            let (study, store) = load(&a.common.study, &a.common.out)?;
            let files = collect::collect(&study, &store, a.partial)?;
            if !quiet {
                for f in files {
                    println!("{}", f.display());
                }
            }
            Ok(())
        }
    }
}
