//! A full disk, for real: the output goes to a small tmpfs mounted in an unprivileged user
//! and mount namespace (`unshare --user --map-root-user --mount`), the command runs inside
//! it, and the tmpfs's content is listed before the namespace ends. Where the kernel or
//! its policy refuses such namespaces (e.g. Ubuntu's AppArmor restriction on unprivileged
//! user namespaces), each test prints the reason and returns without asserting.
//!
//! * `a_full_disk_during_a_study_leaves_no_temporary_run_folder`: a study whose run folder
//!   does not fit records the run as failed, naming the file and "No space left on
//!   device", exits 1, and leaves no `runs/.tmp-*` folder (nor any other temporary);
//! * `a_full_disk_while_plotting_a_study_writes_no_figure`: the figures of a study folder,
//!   of which some would fit, are written all or nothing: none, and no temporary.
use std::path::Path;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_fem2rbd");

/// What the command left on the tmpfs and how it ended.
struct Inside {
    /// Exit code of the command.
    code: i32,
    /// Its stderr.
    stderr: String,
    /// Every path under the tmpfs, relative, sorted.
    listing: Vec<String>,
    /// The `status.json` files of a study's runs on the tmpfs.
    status: String,
}

/// Runs `fem2rbd ARGS` in `cwd` with a tmpfs of `kib` KiB mounted on `mnt`; `None` (with
/// the reason printed) when the namespace or the mount is refused.
fn on_small_tmpfs(cwd: &Path, mnt: &Path, kib: u32, args: &[&str]) -> Option<Inside> {
    // The script: mount, run, then print the exit code and the listing on stdout.
    let script = r#"mnt="$1"; size="$2"; shift 2
mount -t tmpfs -o "size=${size}k" none "$mnt" || { echo "mount refused" >&2; exit 97; }
"$@" 2>"$mnt.stderr"
echo "code=$?"
cd "$mnt" && find . -mindepth 1 | sort && find . -name status.json -exec cat {} +"#;
    let out = Command::new("unshare")
        .args([
            "--user",
            "--map-root-user",
            "--mount",
            "sh",
            "-c",
            script,
            "sh",
        ])
        .arg(mnt)
        .arg(kib.to_string())
        .arg(BIN)
        .args(args)
        .current_dir(cwd)
        .output();
    let out = match out {
        Ok(o) => o,
        Err(e) => {
            eprintln!("SKIPPED: cannot start unshare: {e}");
            return None;
        }
    };
    let stdout = String::from_utf8_lossy(&out.stdout);
    let Some(code) = stdout
        .lines()
        .find_map(|l| l.strip_prefix("code="))
        .and_then(|c| c.parse().ok())
    else {
        eprintln!(
            "SKIPPED: this machine refuses an unprivileged user and mount namespace with a \
             tmpfs (exit {:?}): {}",
            out.status.code(),
            String::from_utf8_lossy(&out.stderr).trim()
        );
        return None;
    };
    let stderr = std::fs::read_to_string(mnt.with_extension("stderr")).unwrap_or_default();
    let listing = stdout
        .lines()
        .filter(|l| l.starts_with("./"))
        .map(|l| l[2..].to_string())
        .collect();
    let status = stdout
        .lines()
        .filter(|l| !l.starts_with("./") && !l.starts_with("code="))
        .collect::<Vec<_>>()
        .join("\n");
    Some(Inside {
        code,
        stderr,
        listing,
        status,
    })
}

fn copy_inputs(w: &Path) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    std::fs::copy(root.join("data/frame3/model.toml"), w.join("model.toml")).unwrap();
    std::fs::copy(
        root.join("data/ground-motions/RSN6_IMPVALL.I_I-ELC180.AT2"),
        w.join("elc180.at2"),
    )
    .unwrap();
}

#[test]
fn a_full_disk_during_a_study_leaves_no_temporary_run_folder() {
    let tmp = tempfile::tempdir().unwrap();
    let w = tmp.path();
    copy_inputs(w);
    std::fs::write(
        w.join("base.toml"),
        "model = \"model.toml\"\nmode = \"fe\"\n[[ground_motion]]\nfile = \"elc180.at2\"\n\
         direction = \"X\"\ntime_scale = 0.5\n[fe]\nduration = 0.05\n",
    )
    .unwrap();
    std::fs::write(
        w.join("st.toml"),
        "base = \"base.toml\"\n[records]\ntime_scale = 0.5\n[[records.list]]\nname = \"e\"\n\
         x = \"elc180.at2\"\n[intensity]\npga_g = [0.5]\n",
    )
    .unwrap();
    let mnt = w.join("mnt");
    std::fs::create_dir(&mnt).unwrap();
    let study = mnt.join("study");
    // 64 KiB: the study folder and its lock fit, the run's folder (≈ 100 KiB) does not.
    let Some(r) = on_small_tmpfs(
        w,
        &mnt,
        64,
        &["study", "run", "st.toml", "--out", study.to_str().unwrap()],
    ) else {
        return;
    };
    // The run is recorded as failed, with the reason, and the study exits 1.
    assert_eq!(r.code, 1, "{}", r.stderr);
    assert!(r.stderr.contains("1 run(s) failed"), "{}", r.stderr);
    assert!(
        r.listing
            .contains(&"study/runs/base__e__fe__0.500g/status.json".to_string()),
        "{:?}",
        r.listing
    );
    assert!(
        r.status.contains("\"status\": \"failed\"")
            && r.status.contains("cannot write")
            && r.status.contains("No space left on device"),
        "{}",
        r.status
    );
    let leftovers: Vec<_> = r
        .listing
        .iter()
        .filter(|p| p.contains(".tmp-") || p.contains(".old-") || p.ends_with(".lock"))
        .collect();
    assert!(leftovers.is_empty(), "left behind: {leftovers:?}");
}

#[test]
fn a_full_disk_while_plotting_a_study_writes_no_figure() {
    let tmp = tempfile::tempdir().unwrap();
    let w = tmp.path();
    // A collected study folder as `study collect` writes it: the IDA curves of two
    // models, no fragility (four figures in PNG and SVG).
    let results = w.join("study/results");
    std::fs::create_dir_all(&results).unwrap();
    std::fs::write(
        results.join("study.json"),
        "{\"study\": \"disk\", \"fragility\": []}\n",
    )
    .unwrap();
    let mut ida = String::from("model,mode,record,pga_g,peak_roof_drift,collapse\n");
    for model in ["a", "b"] {
        for (k, g) in [0.5, 1.0, 1.5, 2.0].iter().enumerate() {
            ida.push_str(&format!(
                "{model},fe,r1,{g},{},{}\n",
                0.004 * (k + 1) as f64,
                u8::from(k == 3)
            ));
        }
    }
    std::fs::write(results.join("ida.csv"), ida).unwrap();
    // Plotted on a roomy disk, the set is larger than the small tmpfs below.
    let roomy = w.join("roomy");
    let out = Command::new(BIN)
        .args(["plot", "study", "--out"])
        .arg(&roomy)
        .current_dir(w)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let sizes: Vec<u64> = std::fs::read_dir(&roomy)
        .unwrap()
        .map(|e| e.unwrap().metadata().unwrap().len())
        .collect();
    let total: u64 = sizes.iter().sum();
    let largest = *sizes.iter().max().unwrap();
    assert!(sizes.len() >= 4, "{sizes:?}");
    // Room for the largest figure and more, not for all of them.
    let kib = ((largest + total) / 2 / 1024) as u32;
    assert!(u64::from(kib) * 1024 > largest && u64::from(kib) * 1024 < total);
    let mnt = w.join("mnt");
    std::fs::create_dir(&mnt).unwrap();
    let figs = mnt.join("figs");
    let Some(r) = on_small_tmpfs(
        w,
        &mnt,
        kib,
        &["plot", "study", "--out", figs.to_str().unwrap()],
    ) else {
        return;
    };
    assert_eq!(r.code, 1, "{}", r.stderr);
    assert!(r.stderr.contains("No space left on device"), "{}", r.stderr);
    let files: Vec<_> = r.listing.iter().filter(|p| *p != "figs").collect();
    assert!(
        files.is_empty(),
        "a partial figure set or a temporary is left: {files:?} ({kib} KiB for {total} bytes)"
    );
}
