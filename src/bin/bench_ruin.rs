//! Benchmark of the ruin stage: wall time per simulated second of a scenario's ruin stage
//! under several speed settings, side by side in one process, runs alternated (A B A B …)
//! so a drift of the machine's speed hits every setting alike; plus where Bullet spends the
//! time (its `BT_PROFILE` zones) and the share of the solver rows in the largest island.
//!
//! ```text
//! cargo run --release --bin bench_ruin -- SCENARIO [--time S] [--rounds N] [--configs LIST]
//! ```
//!
//! `--time S`: simulated seconds of the ruin stage (the scenario's `time_limit_s` is set to
//! start + S and `stop_at_rest` off); default 1. `--rounds N`: runs of each setting (default
//! 3; the median is reported). `--configs`: comma-separated settings, each `tN` (N solver
//! threads) optionally followed by `+sleep` (Bullet's sleeping on) and `+bullet` (Bullet's
//! own `solveSingleIteration` instead of the shim's packed sweep, Bullet's own sweep)
//! or `+lean` (the lean sweep over Bullet's rows with a sequential joint set-up, the lean
//! sweep; docs/performance.md) or `+threads` (the packed sweep always on the threads where
//! eligible, instead of whichever of one thread and the threads measures faster) and/or
//! `+direct` (`[physics.experimental] joint_solve = "direct"`: the joints' bilateral rows solved by a
//! sparse LDLᵀ factorisation first, docs/ruin-numerics.md, "A direct solve"); default
//! `t1,t2`. CPU time per simulated second is the process's
//! CPU time (every thread) from the first to the last frame of the stage. The
//! first setting is the baseline of the ratios. Every setting's final poses are compared
//! bit for bit with the baseline's ("same bits"), which holds for thread counts and is
//! expected to fail for sleeping (a different model of rest).
//!
//! The 7-story building of docs/performance.md: `bash scripts/ruin-speed.sh`.
use anyhow::{bail, Context, Result};
use fem2rbd::bullet::{profile_read, profile_start, profile_stop, ProfileZone};
use fem2rbd::pipeline::scenario::{JointSolveSpec, Scenario, SweepSpec};
use fem2rbd::pipeline::{run, Progress};
use std::cell::Cell;

/// CPU time (user + system, every thread) of this process, s, from `/proc/self/stat`
/// (clock ticks of 10 ms; NaN where there is no procfs).
fn process_cpu_seconds() -> f64 {
    let read = || -> Option<f64> {
        let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
        let rest = &stat[stat.rfind(')')? + 2..];
        let f: Vec<&str> = rest.split_whitespace().collect();
        Some((f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?) / 100.0)
    };
    read().unwrap_or(f64::NAN)
}

/// Records the process CPU time and the simulated time at the first and the last frame of
/// the ruin stage, so the CPU time of the stepping alone (without the set-up: mapping,
/// connection search, world building) is `cpu_last - cpu_first` for `t_last - t_first`
/// simulated seconds.
#[derive(Default)]
struct CpuClock {
    first: Cell<Option<(f64, f64)>>,
    last: Cell<Option<(f64, f64)>>,
}

impl Progress for CpuClock {
    fn ruin(&self, t: f64, _t_end: f64, _counts: (usize, usize, usize)) {
        let now = (t, process_cpu_seconds());
        if self.first.get().is_none() {
            self.first.set(Some(now));
        }
        self.last.set(Some(now));
    }
}

struct Config {
    name: String,
    threads: usize,
    sleeping: bool,
    /// The solver's sweep: `bullet` (`+bullet`), `lean` (`+lean`), `threads` (`+threads`)
    /// or `packed` (default).
    sweep: &'static str,
    /// `[physics.experimental] joint_solve = "direct"` (`+direct`).
    direct: bool,
}

struct Sample {
    wall_s: f64,
    /// CPU s per simulated s of the stepping (first to last frame), every thread.
    cpu_per_sim: f64,
    sim_s: f64,
    bullet_s: f64,
    largest_share: f64,
    rows_per_substep: f64,
    sleeping: usize,
    /// Direct joint solves and fallbacks to PGS over the run.
    direct: (u64, u64),
    bits: Vec<u64>,
    profile: Vec<ProfileZone>,
}

fn parse_configs(s: &str) -> Result<Vec<Config>> {
    s.split(',')
        .map(|c| {
            let c = c.trim();
            let mut parts = c.split('+');
            let t = parts.next().unwrap_or("");
            let threads: usize = t
                .strip_prefix('t')
                .and_then(|n| n.parse().ok())
                .filter(|&n| n >= 1)
                .with_context(|| {
                    format!("--configs: '{c}' must be tN[+sleep][+bullet|+lean|+threads][+direct]")
                })?;
            let mut cfg = Config {
                name: c.to_string(),
                threads,
                sleeping: false,
                sweep: "packed",
                direct: false,
            };
            for o in parts {
                match o {
                    "sleep" => cfg.sleeping = true,
                    "bullet" => cfg.sweep = "bullet",
                    "lean" => cfg.sweep = "lean",
                    "threads" => cfg.sweep = "threads",
                    "direct" => cfg.direct = true,
                    _ => bail!(
                        "--configs: '{c}': unknown option '{o}' (+sleep, +bullet, +lean, +threads, +direct)"
                    ),
                }
            }
            Ok(cfg)
        })
        .collect()
}

fn run_once(base: &Scenario, cfg: &Config, time_s: f64) -> Result<Sample> {
    let mut sc = base.clone();
    sc.physics.sleeping = cfg.sleeping;
    if cfg.direct {
        sc.physics.joint_solve = JointSolveSpec::Direct;
    }
    sc.physics.stop_at_rest = false;
    sc.physics.time_limit_s = Some(time_s);
    sc.threads = Some(cfg.threads);
    sc.physics.sweep = match cfg.sweep {
        "bullet" => SweepSpec::Bullet,
        "lean" => SweepSpec::Lean,
        "threads" => SweepSpec::Threads,
        _ => SweepSpec::Packed,
    };
    profile_start()?;
    let clock = CpuClock::default();
    let rec = run(&sc, &clock)?;
    profile_stop();
    let profile = profile_read()?;
    let r = rec.ruin.context("the scenario ran no ruin stage")?;
    let sim_s = r.end_time_s - r.frames.first().map_or(0.0, |f| f.time_s);
    let mut bits = Vec::new();
    for p in &r.final_poses {
        bits.extend(p.position.iter().chain(&p.orientation).map(|x| x.to_bits()));
    }
    let st = r
        .islands
        .context("the ruin stage ran on a stock Bullet world, which keeps no island statistics")?;
    let cpu_per_sim = match (clock.first.get(), clock.last.get()) {
        (Some((t0, c0)), Some((t1, c1))) if t1 > t0 => (c1 - c0) / (t1 - t0),
        _ => f64::NAN,
    };
    Ok(Sample {
        wall_s: r.wall.total.as_secs_f64(),
        cpu_per_sim,
        sim_s,
        bullet_s: r.wall.in_bullet.as_secs_f64(),
        largest_share: st.largest_share(),
        rows_per_substep: st.rows_total as f64 / st.substeps.max(1) as f64,
        sleeping: r.sleeping_at_end,
        direct: (r.joint_solve.solves, r.joint_solve.fallbacks),
        bits,
        profile,
    })
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut path = None;
    let mut time_s: f64 = 1.0;
    let mut rounds = 3usize;
    let mut configs = "t1,t2".to_string();
    let mut i = 0;
    while i < args.len() {
        let value = |i: usize| {
            args.get(i + 1)
                .cloned()
                .with_context(|| format!("{} needs a value", args[i]))
        };
        match args[i].as_str() {
            "--time" => {
                time_s = value(i)?.parse().context("--time")?;
                i += 1;
            }
            "--rounds" => {
                rounds = value(i)?.parse().context("--rounds")?;
                i += 1;
            }
            "--configs" => {
                configs = value(i)?;
                i += 1;
            }
            a if a.starts_with("--") => bail!("unknown option {a}"),
            a => path = Some(a.to_string()),
        }
        i += 1;
    }
    let path = path
        .context("usage: bench_ruin SCENARIO [--time S] [--rounds N] [--configs t1,t2,t2+sleep]")?;
    if !(time_s.is_finite() && time_s > 0.0) || rounds == 0 {
        bail!("--time must be > 0 and --rounds >= 1");
    }
    let configs = parse_configs(&configs)?;
    let sc = Scenario::load(&path).with_context(|| format!("scenario {path}"))?;
    let start = match sc.mode {
        fem2rbd::pipeline::scenario::Mode::Rigid => 0.0,
        _ => bail!("{path}: bench_ruin needs a rigid-only scenario (mode = \"physics\")"),
    };
    let end = start + time_s;
    println!(
        "{path}: ruin stage 0 → {end} s simulated, {rounds} round(s), settings {}",
        configs
            .iter()
            .map(|c| c.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let mut samples: Vec<Vec<Sample>> = configs.iter().map(|_| Vec::new()).collect();
    for round in 0..rounds {
        for (k, cfg) in configs.iter().enumerate() {
            let s = run_once(&sc, cfg, end)?;
            println!(
                "round {} {:>10}: {:8.2} s wall, {:6.3} s simulated, {:7.2} wall s/s, {:7.2} CPU s/s",
                round + 1,
                cfg.name,
                s.wall_s,
                s.sim_s,
                s.wall_s / s.sim_s,
                s.cpu_per_sim
            );
            samples[k].push(s);
        }
    }
    println!();
    println!("| setting | CPU s per simulated s (median) | CPU ratio to {0} (median of rounds) | wall s per simulated s (median) | wall ratio to {0} | in Bullet | largest island's share of rows | rows per substep | asleep at end | same bits as {0} | direct solves / fallbacks |", configs[0].name);
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for (k, cfg) in configs.iter().enumerate() {
        let per = median(samples[k].iter().map(|s| s.wall_s / s.sim_s).collect());
        let ratio = median(
            (0..rounds)
                .map(|r| samples[k][r].wall_s / samples[0][r].wall_s)
                .collect(),
        );
        let share = median(samples[k].iter().map(|s| s.bullet_s / s.wall_s).collect());
        let cpu = median(samples[k].iter().map(|s| s.cpu_per_sim).collect());
        let cpu_ratio = median(
            (0..rounds)
                .map(|r| samples[k][r].cpu_per_sim / samples[0][r].cpu_per_sim)
                .collect(),
        );
        let s0 = &samples[k][0];
        let same = samples[k].iter().all(|s| s.bits == samples[0][0].bits);
        println!(
            "| {} | {cpu:.2} | {cpu_ratio:.3} | {per:.2} | {ratio:.3} | {:.1} % | {:.3} | {:.0} | {} | {} | {} / {} |",
            cfg.name,
            100.0 * share,
            s0.largest_share,
            s0.rows_per_substep,
            s0.sleeping,
            if same { "yes" } else { "no" },
            s0.direct.0,
            s0.direct.1
        );
    }
    for (k, cfg) in configs.iter().enumerate() {
        let s = &samples[k][0];
        let total = s
            .profile
            .iter()
            .find(|z| z.name == "stepSimulation")
            .map_or(s.bullet_s, |z| z.seconds);
        println!();
        println!(
            "Bullet's zones, {} (round 1; share of stepSimulation):",
            cfg.name
        );
        println!("| zone | s | share | calls |");
        println!("|---|---|---|---|");
        for z in &s.profile {
            println!(
                "| {}{} | {:.2} | {:.1} % | {} |",
                "  ".repeat(z.depth as usize),
                z.name,
                z.seconds,
                100.0 * z.seconds / total,
                z.calls
            );
        }
    }
    Ok(())
}
