//! Nothing the user owns is lost: an output folder that holds an input, or files fem2rbd
//! did not write, is refused before any work; an output file that is an input is refused;
//! no value of a study file or option can add a line or a command to a Slurm job script.
//! Each case runs the real binary and then compares every input byte for byte.
use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_fem2rbd");

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every file under `dir` (relative path → bytes).
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let rel = p.strip_prefix(dir).unwrap().display().to_string();
                out.insert(rel, fs::read(&p).unwrap());
            }
        }
    }
    out
}

/// Runs fem2rbd with `args` in `w`; returns (exit code, stderr).
fn fem2rbd(w: &Path, args: &[&str]) -> (Option<i32>, String) {
    let out = Command::new(BIN)
        .current_dir(w)
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A folder `in/` as a careless user has it: the scenario, its model and record, and an
/// old `summary.json`.
fn user_folder(w: &Path) -> PathBuf {
    let dir = w.join("in");
    fs::create_dir(&dir).unwrap();
    fs::copy(
        root().join("data/frame3/model.toml"),
        dir.join("model.toml"),
    )
    .unwrap();
    fs::copy(
        root().join("data/ground-motions/RSN6_IMPVALL.I_I-ELC180.AT2"),
        dir.join("elc180.at2"),
    )
    .unwrap();
    fs::write(
        dir.join("s.toml"),
        "model = \"model.toml\"\nmode = \"rigid\"\noutput = \"out\"\n\
         [[ground_motion]]\nfile = \"elc180.at2\"\ndirection = \"X\"\npga_g = 0.3\n\
         time_scale = 0.5\n",
    )
    .unwrap();
    fs::write(dir.join("summary.json"), "{}\n").unwrap();
    dir
}

/// Refused with exit code 1, the message holding every one of `want`, and the work folder
/// byte for byte as before.
fn refused(w: &Path, args: &[&str], want: &[&str]) {
    let before = snapshot(w);
    let (code, err) = fem2rbd(w, args);
    assert_eq!(code, Some(1), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    for s in want {
        assert!(err.contains(s), "{args:?}: stderr lacks {s:?}: {err}");
    }
    assert!(snapshot(w) == before, "{args:?}: the work folder changed");
}

#[test]
fn a_run_into_the_folder_of_its_inputs_is_refused_and_deletes_nothing() {
    let t = tempfile::tempdir().unwrap();
    let w = t.path();
    user_folder(w);
    refused(
        w,
        &["run", "in/s.toml", "--out", "in", "--quiet"],
        &["output folder in", "holds the input", "s.toml"],
    );
    // The same through another spelling of the folder, and as an ensemble.
    refused(
        w,
        &["run", "in/s.toml", "--out", "./in/../in", "--quiet"],
        &["holds the input"],
    );
    refused(
        w,
        &["run", "in/s.toml", "--out", w.to_str().unwrap(), "--quiet"],
        &["holds the input"],
    );
    refused(
        w,
        &[
            "run",
            "in/s.toml",
            "--out",
            "in",
            "--ensemble",
            "2",
            "--quiet",
        ],
        &["holds the input"],
    );
}

#[test]
fn a_folder_with_an_old_summary_and_the_user_s_files_is_not_a_run_folder() {
    let t = tempfile::tempdir().unwrap();
    let w = t.path();
    user_folder(w);
    // The model and record elsewhere; the folder holds an old summary.json and notes.
    let other = w.join("old");
    fs::create_dir(&other).unwrap();
    fs::write(other.join("summary.json"), "{}\n").unwrap();
    fs::write(other.join("ruins.csv"), "name\n").unwrap();
    fs::write(other.join("notes.txt"), "my notes\n").unwrap();
    refused(
        w,
        &["run", "in/s.toml", "--out", "old", "--quiet"],
        &["output folder old", "fem2rbd did not write it", "notes.txt"],
    );
    // A folder fem2rbd wrote, with a file of the user's added.
    fs::write(other.join(".fem2rbd"), "run\n").unwrap();
    refused(
        w,
        &["run", "in/s.toml", "--out", "old", "--quiet"],
        &["\"notes.txt\", which fem2rbd did not write there"],
    );
    // An ensemble is not written into a run folder.
    fs::remove_file(other.join("notes.txt")).unwrap();
    refused(
        w,
        &[
            "run",
            "in/s.toml",
            "--out",
            "old",
            "--ensemble",
            "2",
            "--quiet",
        ],
        &["is a fem2rbd run folder, not a ensemble folder"],
    );
}

#[test]
fn an_output_file_that_is_an_input_is_refused() {
    let t = tempfile::tempdir().unwrap();
    let w = t.path();
    let dir = user_folder(w);
    refused(
        w,
        &["map", "in/model.toml", "-o", "in/model.toml"],
        &["--output in/model.toml is the input in/model.toml"],
    );
    refused(
        w,
        &["map", "in/model.toml", "-o", "in/../in/model.toml"],
        &["is the input"],
    );
    refused(
        w,
        &["export", "opensees", "in/model.toml", "-o", "in/model.toml"],
        &["is the input"],
    );
    refused(
        w,
        &[
            "export",
            "opensees",
            "in/model.toml",
            "--gm",
            "X=in/elc180.at2",
            "-o",
            "in/elc180.at2",
        ],
        &["is the input in/elc180.at2"],
    );
    // A scene file written over by its own poses.
    fs::write(dir.join("scene.json"), "{}\n").unwrap();
    refused(
        w,
        &["scene", "in/scene.json", "--out", "in/scene.json"],
        &["--out in/scene.json is the input in/scene.json"],
    );
    // A run folder's tables are the input of `export gltf` and `export vtk`.
    let run = w.join("run");
    fs::create_dir(&run).unwrap();
    for f in ["bodies.csv", "keyframes.csv", "history.csv"] {
        fs::write(run.join(f), "x\n").unwrap();
    }
    refused(
        w,
        &["export", "gltf", "run", "-o", "run/bodies.csv"],
        &["is the input run/bodies.csv"],
    );
    refused(
        w,
        &["export", "vtk", "run", "-o", "run/history.csv"],
        &["is the input run/history.csv"],
    );
    // The frames of `-o w/run.pvd` go into `w/run/`, the run folder itself.
    refused(
        w,
        &["export", "vtk", "run", "-o", "run.pvd"],
        &["the folder of VTK frames run holds the input"],
    );
}

/// A study whose `[slurm]` would add a line or a command to the job script.
fn study(w: &Path, slurm: &str) -> PathBuf {
    let base = format!(
        "model = \"{model}\"\nmode = \"fe\"\n[[ground_motion]]\nfile = \"{elc}\"\n\
         direction = \"X\"\n[fe]\ndt = 0.01\nduration = 0.5\n",
        model = root().join("data/frame3/model.toml").display(),
        elc = root()
            .join("data/ground-motions/RSN6_IMPVALL.I_I-ELC180.AT2")
            .display(),
    );
    fs::write(w.join("base.toml"), base).unwrap();
    let text = format!(
        "base = \"base.toml\"\nmodes = [\"fe\"]\n[records]\n[[records.list]]\nname = \"elc\"\n\
         x = \"{elc}\"\n[intensity]\npga_g = [0.1]\n[slurm]\nestimate_s = 60\n\
         mem_mb = 512\n{slurm}\n",
        elc = root()
            .join("data/ground-motions/RSN6_IMPVALL.I_I-ELC180.AT2")
            .display(),
    );
    let p = w.join("study.toml");
    fs::write(&p, text).unwrap();
    p
}

#[test]
fn no_study_value_can_inject_into_the_slurm_script() {
    let t = tempfile::tempdir().unwrap();
    let w = t.path();
    let attacks = [
        (
            "partition = \"debug\\n#SBATCH --wrap=\\\"rm -rf ~\\\"\"",
            "slurm.partition",
        ),
        ("partition = \"a b\"", "slurm.partition"),
        ("account = \"lab$(rm -rf ~)\"", "slurm.account"),
        ("account = \"lab'\\\"; rm -rf ~\"", "slurm.account"),
    ];
    for (slurm, item) in attacks {
        study(w, slurm);
        refused(
            w,
            &["study", "slurm", "study.toml", "--out", "st"],
            &["study.toml", item, "would change the job script"],
        );
    }
    study(w, "partition = \"debug\"");
    refused(
        w,
        &[
            "study",
            "slurm",
            "study.toml",
            "--out",
            "st",
            "--partition",
            "gpu\n#SBATCH --wrap=id",
        ],
        &["--partition", "would change the job script"],
    );
    // Ordinary names and partition lists pass and reach the script as written.
    study(w, "partition = \"gpu,long.q\"\naccount = \"lab_1-a\"");
    let (code, err) = fem2rbd(w, &["study", "slurm", "study.toml", "--out", "st"]);
    assert_eq!(code, Some(0), "{err}");
    let script = fs::read_to_string(w.join("st/slurm/batch-000.sbatch")).unwrap();
    assert!(
        script.contains("\n#SBATCH --partition=gpu,long.q\n"),
        "{script}"
    );
    assert!(script.contains("\n#SBATCH --account=lab_1-a\n"), "{script}");
    assert!(
        script.contains("\n#SBATCH --job-name=fem2rbd-study\n"),
        "{script}"
    );
    let sbatch_lines = script.lines().filter(|l| l.starts_with("#SBATCH")).count();
    assert_eq!(sbatch_lines, 10, "{script}");
}
