//! `fem2rbd study` on this machine: the manifest, errors before any work, a failing run
//! that does not stop the others, resuming, and results that do not depend on `--jobs`.
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

const EXE: &str = env!("CARGO_BIN_EXE_fem2rbd");

fn repo(p: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(p)
        .display()
        .to_string()
}

fn fem2rbd(args: &[&str]) -> (bool, String, String) {
    let o = Command::new(EXE).args(args).output().unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// A stripe study: frame3 and a model file that is not a model ("broken": every run of
/// it fails in the FE stage's model reader), El Centro at 0.4 and 1.2 g, FE only for
/// 0.5 s.
fn write_study(dir: &Path) -> PathBuf {
    fs::write(
        dir.join("base.toml"),
        format!(
            "model = \"{}\"\nmode = \"fe\"\n[[ground_motion]]\nfile = \"{}\"\ndirection = \"X\"\n[fe]\ndt = 0.01\nduration = 0.5\n",
            repo("data/frame3/model.toml"),
            repo("data/ground-motions/RSN6_IMPVALL.I_I-ELC180.AT2")
        ),
    )
    .unwrap();
    fs::write(dir.join("broken.toml"), "this is = not a model\n").unwrap();
    let p = dir.join("study.toml");
    fs::write(
        &p,
        format!(
            r#"base = "base.toml"
[[models]]
name = "frame3"
file = "{model}"
[[models]]
name = "broken"
file = "broken.toml"
[records]
time_scale = 0.5
[[records.list]]
name = "elcentro"
x = "{gm}/RSN6_IMPVALL.I_I-ELC180.AT2"
y = "{gm}/RSN6_IMPVALL.I_I-ELC270.AT2"
[intensity]
pga_g = [1.2, 0.4]
"#,
            model = repo("data/frame3/model.toml"),
            gm = repo("data/ground-motions"),
        ),
    )
    .unwrap();
    p
}

fn tree(root: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    fn walk(root: &Path, d: &Path, out: &mut Vec<(PathBuf, Vec<u8>)>) {
        for e in fs::read_dir(d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(root, &p, out);
            } else if p.file_name().unwrap() != "status.json" {
                out.push((
                    p.strip_prefix(root).unwrap().to_path_buf(),
                    fs::read(&p).unwrap(),
                ));
            }
        }
    }
    let mut v = Vec::new();
    walk(root, root, &mut v);
    v.sort();
    v
}

#[test]
fn plan_lists_every_run_with_stable_ids() {
    let t = tempfile::tempdir().unwrap();
    let study = write_study(t.path());
    let out = t.path().join("out");
    let (ok, stdout, err) = fem2rbd(&[
        "--quiet",
        "study",
        "plan",
        study.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert_eq!(
        stdout,
        "id\tround\tmodel\trecord\tmode\tpga_g\n\
         frame3__elcentro__fe__0.400g\t0\tframe3\telcentro\tfe\t0.400\n\
         frame3__elcentro__fe__1.200g\t0\tframe3\telcentro\tfe\t1.200\n\
         broken__elcentro__fe__0.400g\t0\tbroken\telcentro\tfe\t0.400\n\
         broken__elcentro__fe__1.200g\t0\tbroken\telcentro\tfe\t1.200\n"
    );
    assert!(!out.exists(), "plan writes nothing");
}

#[test]
fn bad_study_files_name_file_and_line_and_write_nothing() {
    let t = tempfile::tempdir().unwrap();
    let study = write_study(t.path());
    let text = fs::read_to_string(&study).unwrap();
    let out = t.path().join("out");
    let cases = [
        (
            text.replace("[intensity]\n", "[intensity]\nstep = 1\n"),
            "study.toml:15: column 1: unknown field `step`",
        ),
        (
            text.replace("ELC270.AT2", "ELC999.AT2"),
            "study.toml:13: record file",
        ),
        (
            text.replace("[1.2, 0.4]", "[1.2, 0.4005]"),
            "study.toml:15: intensity.pga_g: 0.4005 g is not a multiple of 0.001 g",
        ),
        (
            text.replace("name = \"broken\"", "name = \"frame3\""),
            "models[1]: name \"frame3\" given twice",
        ),
        (
            text.replace(
                "[intensity]\npga_g = [1.2, 0.4]",
                "[intensity.ida]\nstart_g = 0.5\nstep_g = 0.1\nmax_g = 1.0\ntolerance_g = 0.2",
            ),
            "study.toml:18: intensity.ida.tolerance_g must not exceed step_g",
        ),
    ];
    for (bad, want) in cases {
        fs::write(&study, &bad).unwrap();
        let (ok, _, err) = fem2rbd(&[
            "--quiet",
            "study",
            "run",
            study.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(!ok);
        assert!(err.contains(want), "wanted {want:?} in:\n{err}");
        assert!(!out.exists(), "nothing written on {want:?}");
    }
}

#[test]
fn failing_runs_are_recorded_resume_skips_and_jobs_do_not_change_the_bytes() {
    let t = tempfile::tempdir().unwrap();
    let study = write_study(t.path());
    let s = study.to_str().unwrap();
    let (a, b) = (t.path().join("a"), t.path().join("b"));
    // The study has no `modes`: the base scenario's (fe).
    let (ok, _, err) = fem2rbd(&[
        "--quiet",
        "study",
        "run",
        s,
        "--out",
        a.to_str().unwrap(),
        "--jobs",
        "1",
    ]);
    assert!(!ok, "two runs fail, so the study run reports failure");
    assert!(err.contains("2 run(s) failed"), "{err}");
    let runs = fs::read_to_string(a.join("results/runs.csv")).unwrap();
    let lines: Vec<&str> = runs.lines().collect();
    assert_eq!(lines.len(), 5, "{runs}");
    for l in &lines[1..3] {
        assert!(l.starts_with("frame3__elcentro__fe__"), "{l}");
        assert!(l.contains(",fe,") && l.contains(",ok,"), "{l}");
    }
    for l in &lines[3..5] {
        assert!(
            l.starts_with("broken__elcentro__fe__") && l.contains(",failed,"),
            "{l}"
        );
        assert!(
            l.contains("broken.toml"),
            "the error names the model file: {l}"
        );
    }
    let status: serde_json::Value = serde_json::from_str(
        &fs::read_to_string(a.join("runs/broken__elcentro__fe__0.400g/status.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(status["status"], "failed");
    // The ok runs are complete run folders.
    let ok_dir = a.join("runs/frame3__elcentro__fe__1.200g");
    for f in [
        "summary.json",
        "history.csv",
        "ruins.csv",
        "entry.json",
        "status.json",
    ] {
        assert!(ok_dir.join(f).is_file(), "{f}");
    }
    // The X component is scaled to the target, Y by the same factor.
    let entry: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(ok_dir.join("entry.json")).unwrap()).unwrap();
    let c = &entry["components"];
    assert_eq!(c[0]["target_pga_g"], 1.2);
    let f = entry["scale_factor"].as_f64().unwrap();
    assert!((c[0]["recorded_pga_g"].as_f64().unwrap() * f - 1.2).abs() < 1e-5);
    assert!(
        (c[1]["target_pga_g"].as_f64().unwrap() - c[1]["recorded_pga_g"].as_f64().unwrap() * f)
            .abs()
            < 2e-6
    );
    // Resume: nothing runs again.
    let before = fs::read(ok_dir.join("status.json")).unwrap();
    let (_, _, err) = fem2rbd(&[
        "study",
        "run",
        s,
        "--out",
        a.to_str().unwrap(),
        "--jobs",
        "2",
    ]);
    assert!(
        err.contains("0 run(s) ok, 0 failed, 4 already complete"),
        "{err}"
    );
    assert_eq!(fs::read(ok_dir.join("status.json")).unwrap(), before);
    // A run folder removed is run again, alone.
    fs::remove_dir_all(a.join("runs/frame3__elcentro__fe__0.400g")).unwrap();
    let (_, _, err) = fem2rbd(&["study", "run", s, "--out", a.to_str().unwrap()]);
    assert!(
        err.contains("1 run(s) ok, 0 failed, 3 already complete"),
        "{err}"
    );
    // --jobs 2 from scratch: the same bytes.
    let _ = fem2rbd(&[
        "--quiet",
        "study",
        "run",
        s,
        "--out",
        b.to_str().unwrap(),
        "--jobs",
        "2",
    ]);
    let (ta, tb) = (tree(&a), tree(&b));
    assert_eq!(
        ta.iter().map(|x| &x.0).collect::<Vec<_>>(),
        tb.iter().map(|x| &x.0).collect::<Vec<_>>()
    );
    for ((p, x), (_, y)) in ta.iter().zip(&tb) {
        assert!(
            x == y,
            "{} differs between --jobs 1 and --jobs 2",
            p.display()
        );
    }
    // No temporary folders are left.
    for e in fs::read_dir(a.join("runs")).unwrap() {
        let n = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!n.starts_with('.'), "{n} left behind");
    }
}

/// A hybrid run through a study: the ruin columns of `runs.csv` are those of the run's
/// `summary.json`, `fem2rbd plot` draws the study's figures, the same bytes twice, and
/// `fem2rbd report` makes its page (checked in the browser by `tests/it/report/study.rs`).
#[test]
fn hybrid_runs_fill_the_ruin_columns_and_the_study_plots() {
    let t = tempfile::tempdir().unwrap();
    // BCB's axial rows, no joint warm start and BCB's 100 iterations (BCB's solve with
    // FE-derived connections): with them connections break within the 1 s of ruin stage
    // this test runs, which the broken-connections column below needs; with the two-way
    // row (docs/handoff.md §4.1) or the hybrid default's 400 iterations the frame handed
    // over at 4 % drift holds longer.
    fs::write(
        t.path().join("base.toml"),
        format!(
            "model = \"{}\"\nmode = \"hybrid\"\n[[ground_motion]]\nfile = \"{}\"\ndirection = \"X\"\n[fe]\ndt = 0.01\nduration = 2.0\n[collapse]\ncriterion = \"drift_4pct\"\n[physics]\ntime_limit_s = 2.5\nsolver_iterations = 100\n[physics.experimental]\naxial_rows = \"bcb\"\njoint_warmstart = 0.0\n",
            repo("data/frame3/model.toml"),
            repo("data/ground-motions/RSN6_IMPVALL.I_I-ELC180.AT2")
        ),
    )
    .unwrap();
    let study = t.path().join("study.toml");
    fs::write(
        &study,
        format!(
            "base = \"base.toml\"\n[records]\ntime_scale = 0.5\n[[records.list]]\nname = \"elcentro\"\nx = \"{gm}/RSN6_IMPVALL.I_I-ELC180.AT2\"\ny = \"{gm}/RSN6_IMPVALL.I_I-ELC270.AT2\"\n[intensity]\npga_g = [1.5]\n",
            gm = repo("data/ground-motions")
        ),
    )
    .unwrap();
    let out = t.path().join("out");
    let (ok, _, err) = fem2rbd(&[
        "--quiet",
        "study",
        "run",
        study.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let runs = fs::read_to_string(out.join("results/runs.csv")).unwrap();
    let row: Vec<&str> = runs.lines().nth(1).unwrap().split(',').collect();
    let s: serde_json::Value = serde_json::from_str(
        &fs::read_to_string(out.join("runs/base__elcentro__hybrid__1.500g/summary.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(row[0], "base__elcentro__hybrid__1.500g");
    assert_eq!(row[7], "1", "collapse: {runs}");
    assert_eq!(row[8], format!("{:.4}", s["tc_s"].as_f64().unwrap()));
    assert_eq!(row[9], "criterion");
    assert_eq!(row[12], s["ruin_stage"]["stop"].as_str().unwrap());
    assert_eq!(
        row[13],
        s["connections"]["broken"].as_u64().unwrap().to_string()
    );
    let r = &s["ruins"];
    assert_eq!(
        row[14],
        format!(
            "{:.4}",
            r["extent_beyond_footprint_m"]["max"].as_f64().unwrap()
        )
    );
    assert_eq!(
        row[15],
        format!("{:.4}", r["debris_footprint_area_m2"].as_f64().unwrap())
    );
    assert_eq!(
        row[16],
        format!("{:.4}", r["max_debris_height_m"].as_f64().unwrap())
    );
    let min_overlap = r["slab_overlap"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| o["overlap_ratio"].as_f64().unwrap())
        .fold(f64::INFINITY, f64::min);
    assert_eq!(row[17], format!("{min_overlap:.4}"));
    assert!(s["connections"]["broken"].as_u64().unwrap() > 0);
    // Peak roof drift up to Tc from history.csv: the largest |roof_drift| of FE rows.
    let hist =
        fs::read_to_string(out.join("runs/base__elcentro__hybrid__1.500g/history.csv")).unwrap();
    let tc = s["tc_s"].as_f64().unwrap();
    let peak = hist
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|f| f[1] == "fe" && f[0].parse::<f64>().unwrap() <= tc + 1e-9)
        .map(|f| f[2].parse::<f64>().unwrap().abs())
        .fold(0.0, f64::max);
    assert_eq!(row[10], format!("{peak:.6}"));
    assert!(peak > 0.01, "{peak}");
    // Study figures, twice: the same bytes.
    let mut first = Vec::new();
    for k in 0..2 {
        let (ok, stdout, err) = fem2rbd(&["plot", out.to_str().unwrap(), "--format", "png"]);
        assert!(ok, "{err}");
        let files: Vec<&str> = stdout.lines().collect();
        assert_eq!(files.len(), 3, "{stdout}");
        assert!(
            files[0].ends_with("ida_base_hybrid.png")
                && files[1].ends_with("fragility_base_hybrid.png")
                && files[2].ends_with("density_base_hybrid_1.500g.png")
        );
        let bytes: Vec<Vec<u8>> = files.iter().map(|f| fs::read(f).unwrap()).collect();
        assert!(bytes.iter().all(|b| b.starts_with(b"\x89PNG")));
        if k == 0 {
            first = bytes;
        } else {
            assert_eq!(first, bytes);
        }
    }
    // The study's report in the browser (tests/it/report/study.rs).
    crate::report::study::check_study_report(&out);
}

/// A study folder whose lock is held by a process that runs is refused naming that
/// process's id, before any run; a lock left by a process that has ended is taken over,
/// and the lock is removed when the study run ends.
#[test]
fn a_locked_study_folder_is_refused_and_a_stale_lock_is_taken_over() {
    let t = tempfile::tempdir().unwrap();
    let study = write_study(t.path());
    let s = study.to_str().unwrap();
    let out = t.path().join("out");
    fs::create_dir_all(&out).unwrap();
    let lock = out.join(".lock");
    // A second process holds the folder.
    let mut holder = Command::new("sleep").arg("600").spawn().unwrap();
    let pid = holder.id();
    fs::write(&lock, format!("{pid}\n")).unwrap();
    let (ok, _, err) = fem2rbd(&["--quiet", "study", "run", s, "--out", out.to_str().unwrap()]);
    holder.kill().unwrap();
    holder.wait().unwrap();
    assert!(!ok);
    assert!(
        err.contains(&format!(
            "is in use by another `study run` (process {pid}, lock file {})",
            lock.display()
        )),
        "{err}"
    );
    assert!(!out.join("runs").exists(), "no run started");
    assert_eq!(fs::read_to_string(&lock).unwrap(), format!("{pid}\n"));
    // The holder has ended: its lock is stale and taken over; the runs go ahead.
    let (_, _, err) = fem2rbd(&["--quiet", "study", "run", s, "--out", out.to_str().unwrap()]);
    assert!(!err.contains("in use"), "{err}");
    assert!(err.contains("2 run(s) failed"), "{err}");
    assert!(out.join("runs").is_dir(), "the runs went ahead");
    assert!(!lock.exists(), "the lock is removed at the end");
}
