//! A frame3 run folder for the report tests, made once per test process by the real
//! binary: `fem2rbd run` (which writes `report.html` by default) on the shipped frame3
//! model under LC5 in CI size — the FEMA 356 drift criterion (4 %, Tc ≈ 1.53 s, as in
//! tests/it/pipeline/run_frame3.rs) and the ruin stage cut at 3 s — then
//! `fem2rbd plot --format svg`, then `fem2rbd report` again so the page inlines the
//! figures. The folder is `CARGO_TARGET_TMPDIR/report-frame3/run`.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// The CI-sized hybrid LC5 scenario of frame3 (FEMA 356's 4 % drift criterion, 3 s).
pub fn scenario_text() -> String {
    crate::support::frame3_lc5(
        "hybrid",
        "criterion = \"drift_4pct\"",
        "",
        "time_limit_s = 3.0",
    )
}

/// Runs the binary with `args`; panics with its stderr when it fails.
pub fn fem2rbd(args: &[&std::ffi::OsStr]) -> std::process::Output {
    let out = Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
        .arg("--quiet")
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "fem2rbd {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// The run folder (made on first use).
pub fn run_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let base = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report-frame3");
        let _ = std::fs::remove_dir_all(&base);
        std::fs::create_dir_all(&base).unwrap();
        let sc = base.join("hybrid.toml");
        std::fs::write(&sc, scenario_text()).unwrap();
        let run = base.join("run");
        fem2rbd(&[
            "run".as_ref(),
            sc.as_os_str(),
            "--out".as_ref(),
            run.as_os_str(),
        ]);
        assert!(
            run.join("report.html").is_file(),
            "`fem2rbd run` writes report.html by default"
        );
        fem2rbd(&[
            "plot".as_ref(),
            run.as_os_str(),
            "--format".as_ref(),
            "svg".as_ref(),
        ]);
        fem2rbd(&["report".as_ref(), run.as_os_str()]);
        run
    })
}
