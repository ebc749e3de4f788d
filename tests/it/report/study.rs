//! The report of a collected study folder (`fem2rbd report STUDY_DIR`,
//! `src/report/study.rs`) in Debian's headless Chromium, driven by
//! tests/report/check_study.mjs; asserted against the study's own files:
//!
//! * the page raised no JavaScript error, logged none and made no network request; its
//!   element ids are unique; the same folder gives the same bytes;
//! * one fragility row per fit of `study.json`, with its model, mode and median;
//! * the IDA and fragility figures of `fem2rbd plot STUDY_DIR`, in its order, each an
//!   inline SVG drawn with a size;
//! * one section per intensity of `results/rescue/` and `results/density/`, each with its
//!   debris-density figure and the four rescue maps, whose cells with a share above 0 are
//!   those of the intensity's `rescue_map.csv`, share for share; the medians of the
//!   distributions are those of its `rescue.json`.
//!
//! The study itself is run by `tests/it/study/local.rs`
//! (`hybrid_runs_fill_the_ruin_columns_and_the_study_plots`), which calls
//! [`check_study_report`]. Fails (does not skip) when node, playwright-core or chromium is
//! missing.
use serde_json::Value;
use std::path::Path;
use std::process::Command;

fn fem2rbd_report(dir: &Path) -> Vec<u8> {
    let out = Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
        .args(["--quiet", "report"])
        .arg(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::read(dir.join("report.html")).unwrap()
}

/// Checks the report of the collected study folder `dir` (module docs).
pub fn check_study_report(dir: &Path) {
    let first = fem2rbd_report(dir);
    assert_eq!(
        fem2rbd_report(dir),
        first,
        "the same folder, the same bytes"
    );
    let shots = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report-study");
    std::fs::create_dir_all(&shots).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/report/check_study.mjs");
    let out = Command::new("node")
        .arg(&script)
        .arg(dir.join("report.html"))
        .arg(shots.join("study.png"))
        .output()
        .unwrap_or_else(|e| {
            panic!("cannot run `node` ({e}): install Node.js >= 18, then run scripts/setup-node.sh")
        });
    assert!(
        out.status.success(),
        "check_study.mjs failed (chromium: `apt-get install chromium`; playwright-core: \
         scripts/setup-node.sh): {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let r: Value = serde_json::from_slice(&out.stdout).expect("check_study.mjs prints JSON");
    assert_eq!(r["errors"], serde_json::json!([]), "JavaScript errors");
    let ids: Vec<&str> = r["ids"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    let unique: std::collections::BTreeSet<&&str> = ids.iter().collect();
    assert_eq!(unique.len(), ids.len(), "element ids repeat: {ids:?}");

    let sj: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("results/study.json")).unwrap())
            .unwrap();
    let fits = sj["fragility"].as_array().unwrap();
    let rows = r["fragility"].as_array().unwrap();
    assert_eq!(rows.len(), fits.len());
    for (row, fit) in rows.iter().zip(fits) {
        assert_eq!(row["model"], fit["model"]);
        assert_eq!(row["mode"], fit["mode"]);
        assert_eq!(
            row["median"].as_str().unwrap(),
            fit["fit"]["median_g"].to_string()
        );
    }
    let figs = fem2rbd::study::plot::figures(dir).unwrap();
    let want: Vec<&str> = figs
        .iter()
        .map(|(s, _)| s.as_str())
        .filter(|s| !s.starts_with("density_"))
        .collect();
    let drawn = r["figures"].as_array().unwrap();
    let got: Vec<&str> = drawn.iter().map(|f| f["plot"].as_str().unwrap()).collect();
    assert_eq!(got, want);
    for f in drawn {
        assert!(f["svg"]["width"].as_f64().unwrap() > 100.0, "{f}");
    }

    let stems: Vec<String> = {
        let mut v: Vec<String> = std::fs::read_dir(dir.join("results/rescue"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "json"))
            .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    assert!(!stems.is_empty(), "the study has rescue maps");
    let sections = r["intensities"].as_array().unwrap();
    assert_eq!(sections.len(), stems.len());
    for (s, stem) in sections.iter().zip(&stems) {
        assert_eq!(s["stem"], stem.as_str());
        let density = s["density"].as_array().unwrap();
        assert_eq!(density.len(), 1, "{s}");
        assert_eq!(
            density[0]["plot"],
            format!("density_{}", stem.replace("__", "_"))
        );
        let maps = s["maps"].as_array().unwrap();
        let cols: Vec<&str> = maps.iter().map(|m| m["map"].as_str().unwrap()).collect();
        assert_eq!(
            cols,
            [
                "p_survivable",
                "p_survivable_rescuer",
                "p_survivable_camera",
                "p_void",
                "p_route_rescuer",
                "p_entry_rescuer"
            ]
        );
        let csv = std::fs::read_to_string(dir.join(format!("results/rescue/{stem}.csv"))).unwrap();
        let mut lines = csv.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let table: Vec<Vec<f64>> = lines
            .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
            .collect();
        for m in maps {
            let k = header
                .iter()
                .position(|h| *h == m["map"].as_str().unwrap())
                .unwrap();
            let mut want: Vec<f64> = table
                .iter()
                .map(|row| row[k])
                .filter(|p| *p > 0.0)
                .collect();
            let mut shown: Vec<f64> = m["shares"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_f64().unwrap())
                .collect();
            want.sort_by(f64::total_cmp);
            shown.sort_by(f64::total_cmp);
            assert_eq!(shown, want, "{stem} {}", m["map"]);
        }
        assert!(maps[3]["cells"].as_u64().unwrap() > 0, "{stem}: some void");
        let rj: Value = serde_json::from_str(
            &std::fs::read_to_string(dir.join(format!("results/rescue/{stem}.json"))).unwrap(),
        )
        .unwrap();
        assert_eq!(
            s["medians"]["voids_count"].as_f64().unwrap(),
            rj["distributions"]["voids_count"]["median"]
                .as_f64()
                .unwrap()
        );
        assert_eq!(
            s["places"].as_array().unwrap().len(),
            rj["places"].as_array().unwrap().len()
        );
    }
}
