//! A small IDA study run twice — locally (`fem2rbd study run --jobs 2`) and through a real
//! single-node Slurm cluster (munged, slurmctld, slurmd from Debian, started here and
//! stopped by pid; `slurm/submit.sh` submits one job array per IDA round with
//! `sbatch --wait`) — must give byte-identical results: `results/*` and every file of
//! every run folder except `status.json` (which holds the wall time).
//!
//! The cluster lives in a temporary folder (its own slurm.conf via `SLURM_CONF`, its own
//! munge socket), so nothing under /etc is changed. Needs root and the packages
//! `slurmctld slurmd slurm-client munge` (scripts/setup.sh installs them). If they are
//! missing or the cluster does not come up, the test fails: it never skips.
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

const EXE: &str = env!("CARGO_BIN_EXE_fem2rbd");

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn sh(cmd: &mut Command) -> (bool, String, String) {
    let o = cmd
        .output()
        .unwrap_or_else(|e| panic!("cannot run {cmd:?}: {e}"));
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// The daemons started by this test, stopped by pid (TERM, then KILL after 10 s).
struct Cluster {
    pidfiles: Vec<PathBuf>,
}

impl Drop for Cluster {
    fn drop(&mut self) {
        for pf in self.pidfiles.iter().rev() {
            let Some(pid) = fs::read_to_string(pf)
                .ok()
                .and_then(|s| s.trim().parse::<u32>().ok())
            else {
                continue;
            };
            let _ = Command::new("kill")
                .args(["-TERM", &pid.to_string()])
                .status();
            let t0 = Instant::now();
            while Path::new(&format!("/proc/{pid}")).exists()
                && fs::read_to_string(format!("/proc/{pid}/stat"))
                    .map(|s| !s.contains(") Z "))
                    .unwrap_or(false)
            {
                if t0.elapsed() > Duration::from_secs(10) {
                    let _ = Command::new("kill")
                        .args(["-KILL", &pid.to_string()])
                        .status();
                    break;
                }
                std::thread::sleep(Duration::from_millis(100));
            }
        }
    }
}

fn need(ok: bool, what: &str) {
    assert!(
        ok,
        "study_slurm: {what}. This test brings up a real Slurm and must not skip: run \
         scripts/setup.sh (apt: slurmctld slurmd slurm-client munge) and run the tests as root."
    );
}

/// Starts munged, slurmctld and slurmd in `dir` (docs/studies.md, "Slurm in CI").
fn start_cluster(dir: &Path) -> Cluster {
    let (ok, uid, _) = sh(Command::new("id").arg("-u"));
    need(ok && uid.trim() == "0", "not running as root");
    for b in [
        "/usr/sbin/munged",
        "/usr/sbin/slurmctld",
        "/usr/sbin/slurmd",
    ] {
        need(Path::new(b).exists(), &format!("{b} is not installed"));
    }
    need(
        Path::new("/etc/munge/munge.key").exists(),
        "/etc/munge/munge.key is missing (the munge package creates it)",
    );
    let (_, host, _) = sh(Command::new("hostname").arg("-s"));
    let host = host.trim().to_string();
    let munge = dir.join("munge");
    for d in ["state", "spool", "munge"] {
        fs::create_dir_all(dir.join(d)).unwrap();
    }
    // munged (user munge) needs to reach its socket folder; slurmd runs the jobs as root.
    sh(Command::new("chmod").args(["755"]).arg(dir));
    sh(Command::new("chown").arg("munge:munge").arg(&munge));
    sh(Command::new("chmod").arg("755").arg(&munge));
    let socket = munge.join("munge.socket");
    let d = dir.display();
    let conf = format!(
        "ClusterName=ci
SlurmctldHost={host}
AuthType=auth/munge
AuthInfo=socket={socket}
CredType=cred/munge
SlurmUser=root
SlurmctldPort=6817
SlurmdPort=6818
StateSaveLocation={d}/state
SlurmdSpoolDir={d}/spool
SlurmctldPidFile={d}/slurmctld.pid
SlurmdPidFile={d}/slurmd.pid
SlurmctldLogFile={d}/slurmctld.log
SlurmdLogFile={d}/slurmd.log
MailProg=/bin/true
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
SchedulerParameters=batch_sched_delay=0
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/filetxt
JobCompLoc={d}/jobcomp.log
MpiDefault=none
ReturnToService=2
SlurmctldTimeout=30
SlurmdTimeout=30
InactiveLimit=0
KillWait=5
MinJobAge=4
NodeName={host} NodeAddr=127.0.0.1 CPUs=2 Sockets=1 CoresPerSocket=2 ThreadsPerCore=1 RealMemory=2048 State=UNKNOWN
PartitionName=ci Nodes=ALL Default=YES MaxTime=INFINITE State=UP
",
        socket = socket.display()
    );
    let conf_path = dir.join("slurm.conf");
    fs::write(&conf_path, conf).unwrap();
    let mut cluster = Cluster {
        pidfiles: Vec::new(),
    };
    let munged_pid = munge.join("munged.pid");
    let (ok, _, err) = sh(Command::new("runuser")
        .args(["-u", "munge", "--", "/usr/sbin/munged"])
        .arg(format!("--socket={}", socket.display()))
        .arg(format!("--pid-file={}", munged_pid.display()))
        .arg(format!("--log-file={}", munge.join("munged.log").display()))
        .arg(format!("--seed-file={}", munge.join("seed").display())));
    need(ok, &format!("munged did not start: {err}"));
    cluster.pidfiles.push(munged_pid);
    let (ok, _, err) = sh(Command::new("/usr/sbin/slurmctld")
        .args(["-c", "-f"])
        .arg(&conf_path));
    need(ok, &format!("slurmctld did not start: {err}"));
    cluster.pidfiles.push(dir.join("slurmctld.pid"));
    let (ok, _, err) = sh(Command::new("/usr/sbin/slurmd").arg("-f").arg(&conf_path));
    need(ok, &format!("slurmd did not start: {err}"));
    cluster.pidfiles.push(dir.join("slurmd.pid"));
    let t0 = Instant::now();
    loop {
        let (_, state, _) = sh(Command::new("sinfo")
            .env("SLURM_CONF", &conf_path)
            .args(["-h", "-n", &host, "-o", "%T"]));
        if state.trim() == "idle" {
            break;
        }
        let log = fs::read_to_string(dir.join("slurmctld.log")).unwrap_or_default();
        need(
            t0.elapsed() < Duration::from_secs(30),
            &format!("the node is {state:?}, not idle, after 30 s; slurmctld.log:\n{log}"),
        );
        std::thread::sleep(Duration::from_millis(200));
    }
    cluster
}

/// All files under `root` (relative paths), sorted.
fn files(root: &Path) -> Vec<PathBuf> {
    fn walk(root: &Path, d: &Path, out: &mut Vec<PathBuf>) {
        for e in fs::read_dir(d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                out.push(p.strip_prefix(root).unwrap().to_path_buf());
            }
        }
    }
    let mut v = Vec::new();
    walk(root, root, &mut v);
    v.sort();
    v
}

fn wall_sum(root: &Path) -> (usize, f64) {
    let mut n = 0;
    let mut s = 0.0;
    for f in files(&root.join("runs")) {
        if f.file_name().unwrap() == "status.json" {
            let v: serde_json::Value =
                serde_json::from_str(&fs::read_to_string(root.join("runs").join(f)).unwrap())
                    .unwrap();
            n += 1;
            s += v["wall_s"].as_f64().unwrap();
        }
    }
    (n, s)
}

/// Asserts that the study folders `local` and `remote` (without `slurm/`) hold the same
/// files with the same bytes, `status.json` aside; returns the number compared.
fn same_bytes(local: &Path, remote: &Path) -> usize {
    let a = files(local);
    let b: Vec<PathBuf> = files(remote)
        .into_iter()
        .filter(|p| !p.starts_with("slurm"))
        .collect();
    assert_eq!(
        a, b,
        "the local and the Slurm study folders differ in their files"
    );
    let mut compared = 0;
    for f in &a {
        if f.file_name().unwrap() == "status.json" {
            continue;
        }
        let (x, y) = (
            fs::read(local.join(f)).unwrap(),
            fs::read(remote.join(f)).unwrap(),
        );
        assert!(
            x == y,
            "{} differs between the local and the Slurm run",
            f.display()
        );
        compared += 1;
    }
    compared
}

/// A hybrid ensemble study (frame3, El Centro at 1.5 g, 2 members, FE 1.5 s, ruin stage to
/// 1.8 s; no stated Slurm requests: they come from the estimate of its run).
fn ensemble_study(t: &Path) -> PathBuf {
    fs::write(
        t.join("ens-base.toml"),
        format!(
            "model = \"{}\"\nmode = \"hybrid\"\n[[ground_motion]]\nfile = \"{}\"\ndirection = \"X\"\n[fe]\ndt = 0.01\nduration = 1.5\n[collapse]\ncriterion = \"drift_4pct\"\n[physics]\ntime_limit_s = 1.8\n",
            repo("data/frame3/model.toml").display(),
            repo("data/ground-motions/RSN6_IMPVALL.I_I-ELC180.AT2").display()
        ),
    )
    .unwrap();
    let p = t.join("ens.toml");
    fs::write(
        &p,
        format!(
            "base = \"ens-base.toml\"\n[records]\ntime_scale = 0.5\n[[records.list]]\nname = \"elcentro\"\nx = \"{gm}/RSN6_IMPVALL.I_I-ELC180.AT2\"\ny = \"{gm}/RSN6_IMPVALL.I_I-ELC270.AT2\"\n[intensity]\npga_g = [1.5]\n[ensemble]\nmembers = 2\nseed = 3\n",
            gm = repo("data/ground-motions").display()
        ),
    )
    .unwrap();
    p
}

#[test]
fn study_through_slurm_matches_local_run() {
    let tmp = tempfile::Builder::new()
        .prefix("fem2rbd-study-slurm")
        .tempdir_in("/tmp")
        .unwrap();
    let t = tmp.path();
    // A small IDA: frame3 (FE only, first 1.5 s of the time-compressed record, 0.01 s
    // steps, FEMA 356 4 % drift) under El Centro and FF02.
    let base = format!(
        r#"model = "{model}"
mode = "fe"
[[ground_motion]]
file = "{elc}"
direction = "X"
[fe]
dt = 0.01
duration = 1.5
[collapse]
criterion = "drift_4pct"
"#,
        model = repo("data/frame3/model.toml").display(),
        elc = repo("data/ground-motions/RSN6_IMPVALL.I_I-ELC180.AT2").display(),
    );
    fs::write(t.join("base.toml"), base).unwrap();
    let study = format!(
        r#"base = "base.toml"
modes = ["fe"]
[[models]]
name = "frame3"
file = "{model}"
[records]
time_scale = 0.5
[[records.list]]
name = "elcentro"
x = "{gm}/RSN6_IMPVALL.I_I-ELC180.AT2"
y = "{gm}/RSN6_IMPVALL.I_I-ELC270.AT2"
[[records.folder]]
path = "{gm}/fema-p695-far-field"
x = "-H1.AT2"
y = "-H2.AT2"
include = ["FF02"]
[intensity.ida]
start_g = 1.0
step_g = 0.5
max_g = 2.0
tolerance_g = 0.25
[slurm]
estimate_s = 60
mem_mb = 512
throttle = 2
"#,
        model = repo("data/frame3/model.toml").display(),
        gm = repo("data/ground-motions").display(),
    );
    let study_path = t.join("study.toml");
    fs::write(&study_path, study).unwrap();

    // Local run.
    let local = t.join("local");
    let t0 = Instant::now();
    let (ok, _, err) = sh(Command::new(EXE)
        .args(["--quiet", "study", "run"])
        .arg(&study_path)
        .arg("--out")
        .arg(&local)
        .args(["--jobs", "2"]));
    assert!(ok, "local study run failed: {err}");
    let local_wall = t0.elapsed().as_secs_f64();
    let ens = ensemble_study(t);
    let ens_local = t.join("ens-local");
    let (ok, _, err) = sh(Command::new(EXE)
        .args(["--quiet", "study", "run"])
        .arg(&ens)
        .arg("--out")
        .arg(&ens_local)
        .args(["--jobs", "2"]));
    assert!(ok, "local ensemble study run failed: {err}");

    // Slurm run.
    let cluster_dir = t.join("cluster");
    let cluster = start_cluster(&cluster_dir);
    let conf = cluster_dir.join("slurm.conf");
    let remote = t.join("slurm");
    let (ok, script, err) = sh(Command::new(EXE)
        .args(["--quiet", "study", "slurm"])
        .arg(&study_path)
        .arg("--out")
        .arg(&remote));
    assert!(ok, "study slurm failed: {err}");
    let script = PathBuf::from(script.trim());
    let text = fs::read_to_string(&script).unwrap();
    // Two sequences → a first batch of two tasks, at most 2 at once, 60 s × 2 + 60 s.
    assert!(text.contains("#SBATCH --array=0-1%2\n"), "{text}");
    assert!(text.contains("#SBATCH --time=0-00:03:00\n"), "{text}");
    assert!(text.contains("#SBATCH --mem=512M\n"), "{text}");
    let t1 = Instant::now();
    let (ok, out, err) = sh(Command::new("timeout")
        .arg("900")
        .arg("bash")
        .arg(remote.join("slurm/submit.sh"))
        .env("SLURM_CONF", &conf));
    let slurm_wall = t1.elapsed().as_secs_f64();
    assert!(
        ok,
        "submit.sh failed: {out}\n{err}\njobcomp.log:\n{}",
        fs::read_to_string(cluster_dir.join("jobcomp.log")).unwrap_or_default()
    );
    // The ensemble study: its requests come from the estimate of its run.
    let ens_remote = t.join("ens-slurm");
    let (ok, script, err) = sh(Command::new(EXE)
        .args(["--quiet", "study", "slurm"])
        .arg(&ens)
        .arg("--out")
        .arg(&ens_remote));
    assert!(ok, "study slurm (ensemble) failed: {err}");
    let text = fs::read_to_string(script.trim()).unwrap();
    let ens_study = fem2rbd::study::Study::load(&ens).unwrap();
    let (_, e) = fem2rbd::study::slurm::largest_run(&ens_study).unwrap();
    let time = fem2rbd::study::slurm::time_request(&ens_study.slurm, e.seconds);
    let mem = (e.peak_bytes * 2.0 / 1048576.0).ceil() as u64;
    assert!(text.contains(&format!("#SBATCH --time={time}\n")), "{text}");
    assert!(text.contains(&format!("#SBATCH --mem={mem}M\n")), "{text}");
    assert!(
        text.contains("estimate of the largest run (base/elcentro/hybrid)"),
        "{text}"
    );
    assert!(text.contains("#SBATCH --array=0-1\n"), "{text}");
    let (ok, out2, err2) = sh(Command::new("timeout")
        .arg("600")
        .arg("bash")
        .arg(ens_remote.join("slurm/submit.sh"))
        .env("SLURM_CONF", &conf));
    let jobcomp = fs::read_to_string(cluster_dir.join("jobcomp.log")).unwrap_or_default();
    drop(cluster);
    assert!(
        ok,
        "submit.sh (ensemble) failed: {out2}\n{err2}\njobcomp.log:\n{jobcomp}"
    );
    let ens_compared = same_bytes(&ens_local, &ens_remote);
    assert!(ens_local.join("results/ensemble.csv").is_file());
    assert!(ens_local
        .join("results/density/base__hybrid__1.500g.csv")
        .is_file());
    let batches = fs::read_dir(remote.join("slurm"))
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .ends_with(".sbatch")
        })
        .count();
    let tasks = jobcomp.matches("JobState=COMPLETED").count();

    // Same files, same bytes (status.json holds wall times).
    let compared = same_bytes(&local, &remote);
    // The IDA went through several rounds and found El Centro's collapse.
    let runs = fs::read_to_string(local.join("results/runs.csv")).unwrap();
    let n_runs = runs.lines().count() - 1;
    assert!(n_runs >= 5, "{runs}");
    assert!(batches >= 3, "{batches} batches");
    assert_eq!(
        tasks,
        n_runs + 2,
        "every run one completed array task (+2 of the ensemble):\n{jobcomp}"
    );
    let sj: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(local.join("results/study.json")).unwrap())
            .unwrap();
    let seqs = sj["fragility"][0]["data"].as_array().unwrap();
    assert_eq!(seqs.len(), 2);
    assert_eq!(seqs[0]["record"], "elcentro");
    assert_eq!(seqs[0]["state"], "collapse", "{sj:#}");
    let (n_l, w_l) = wall_sum(&local);
    let (n_s, w_s) = wall_sum(&remote);
    assert_eq!((n_l, n_s), (n_runs, n_runs));
    eprintln!(
        "study_slurm: {n_runs} runs in {batches} Slurm batches, {compared} files identical \
         (ensemble: {ens_compared}); \
         local --jobs 2: {local_wall:.1} s wall, runs {w_l:.1} s in total, overhead per run \
         {:.2} s; Slurm: {slurm_wall:.1} s wall, runs {w_s:.1} s in total, overhead per run \
         {:.2} s (wall × 2 slots − run time, per run)",
        (local_wall * 2.0 - w_l) / n_runs as f64,
        (slurm_wall * 2.0 - w_s) / n_runs as f64,
    );
}
