//! `fem2rbd report` of an ensemble folder: a frame3 ensemble of 2 members (`fem2rbd run
//! --ensemble 2`, physics mode cut at 1 s) opened in Debian's headless Chromium by
//! tests/report/check_ensemble.mjs (as in [`super::browser`]). Asserted against the
//! members' own run folders: no JavaScript error; one mesh per member with one box per
//! row of `bodies.csv`; the world box of each member's drawn active bodies is that
//! member's ruin extent of `summary.json` to 2 mm (float32 poses, 6-decimal summary); one
//! table row per member; the debris-density map inlined; the rescue maps drawn cell for
//! cell from `rescue_map.csv` (one cell per share above 0, the same shares), the medians of
//! `rescue.json`'s distributions and its places; unticking a member hides it. A
//! member with other bodies is refused, naming its `bodies.csv`.
use super::frame3::{fem2rbd, scenario_text};
use fem2rbd::output::run_folder::RunFolder;
use serde_json::Value;
use std::process::Command;

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("{v} is not a number"))
}

#[test]
fn ensemble_report_overlays_the_members_in_headless_chromium() {
    let tmp = tempfile::tempdir().unwrap();
    let text = scenario_text()
        .replace("mode = \"hybrid\"", "mode = \"rigid\"")
        .replace("criterion = \"drift_4pct\"", "")
        .replace("time_limit_s = 3.0", "time_limit_s = 1.0");
    let sc = tmp.path().join("ens.toml");
    std::fs::write(&sc, text).unwrap();
    let dir = tmp.path().join("ens");
    fem2rbd(&[
        "run".as_ref(),
        sc.as_os_str(),
        "--out".as_ref(),
        dir.as_os_str(),
        "--ensemble".as_ref(),
        "2".as_ref(),
        "--threads".as_ref(),
        "2".as_ref(),
    ]);
    fem2rbd(&["report".as_ref(), dir.as_os_str()]);
    let html = dir.join("report.html");
    let shot = tmp.path().join("ensemble.png");
    let script =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/report/check_ensemble.mjs");
    let out = Command::new("node")
        .arg(&script)
        .arg(&html)
        .arg(&shot)
        .output()
        .unwrap_or_else(|e| {
            panic!("cannot run `node` ({e}): install Node.js >= 18, then run scripts/setup-node.sh")
        });
    assert!(
        out.status.success(),
        "check_ensemble.mjs failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let r: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(r["errors"], serde_json::json!([]), "JavaScript errors");
    assert_eq!(r["member_rows"], 2);
    assert_eq!(r["density_svgs"], 1);
    let members = r["members"].as_array().unwrap();
    assert_eq!(members.len(), 2);
    for (m, drawn) in members.iter().enumerate() {
        let run = RunFolder::load(&dir.join(format!("member-{m:03}"))).unwrap();
        assert_eq!(drawn["name"], format!("member-{m:03}"));
        assert_eq!(drawn["count"], run.bodies.len());
        let ru = &run.summary.ruins;
        let (fp, e) = (&ru.original_footprint_m, &ru.extent_beyond_footprint_m);
        let lo: Vec<f64> = drawn["min"].as_array().unwrap().iter().map(f).collect();
        let hi: Vec<f64> = drawn["max"].as_array().unwrap().iter().map(f).collect();
        // Each side: exactly the extent when debris is beyond the footprint there, else
        // within it.
        for (drawn, edge, beyond, outward) in [
            (lo[0], fp.x[0], e.x_minus, -1.0),
            (hi[0], fp.x[1], e.x_plus, 1.0),
            (lo[1], fp.y[0], e.y_minus, -1.0),
            (hi[1], fp.y[1], e.y_plus, 1.0),
        ] {
            if beyond > 0.0 {
                let want = edge + outward * beyond;
                assert!((drawn - want).abs() < 2e-3, "member {m}: {drawn} vs {want}");
            } else {
                assert!(
                    outward * (drawn - edge) < 2e-3,
                    "member {m}: {drawn} beyond {edge}"
                );
            }
        }
    }
    assert_eq!(r["visible_after_untick"], serde_json::json!([false, true]));

    // The rescue map: per column of rescue_map.csv, one drawn cell per cell with a share
    // above 0, the same shares; the distributions' medians and the places of rescue.json.
    let rescue = &r["rescue"];
    assert_eq!(rescue["none"], Value::Null);
    assert_eq!(rescue["legend"], true);
    let map = std::fs::read_to_string(dir.join("rescue_map.csv")).unwrap();
    let mut lines = map.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    for col in [
        "p_survivable",
        "p_survivable_rescuer",
        "p_survivable_camera",
        "p_void",
        "p_route_rescuer",
        "p_entry_rescuer",
    ] {
        let c = header.iter().position(|h| *h == col).unwrap();
        let ps: Vec<f64> = rows.iter().map(|r| r[c]).filter(|p| *p > 0.0).collect();
        let drawn = &rescue["maps"][col];
        assert_eq!(drawn["cells"], ps.len(), "{col}");
        let sum: f64 = ps.iter().sum();
        assert!(
            (f(&drawn["sum"]) - sum).abs() < 1e-9,
            "{col}: {drawn} vs {sum}"
        );
        eprintln!(
            "rescue map {col}: {} cells above 0, shares sum {sum}",
            ps.len()
        );
    }
    assert!(
        rescue["maps"]["p_void"]["cells"].as_u64().unwrap() > 0,
        "the members' ruins have voids"
    );
    let rj: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("rescue.json")).unwrap()).unwrap();
    for key in [
        "voids_count",
        "survivable_count",
        "survivable_volume_m3",
        "rescuer_reachable_survivable",
        "max_height_m",
        "mean_height_m",
    ] {
        assert_eq!(
            f(&rescue["medians"][key]),
            f(&rj["distributions"][key]["median"]),
            "{key}"
        );
    }
    let places: Vec<f64> = rj["places"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| f(&p["probability"]))
        .collect();
    let shown: Vec<f64> = rescue["places"].as_array().unwrap().iter().map(f).collect();
    assert_eq!(shown, places);
    let png = std::fs::read(&shot).unwrap();
    assert_eq!(&png[1..4], b"PNG");

    // A member with other bodies: its bodies.csv is named, nothing written.
    let bodies = dir.join("member-001/bodies.csv");
    let t = std::fs::read_to_string(bodies).unwrap();
    let last = t.lines().last().unwrap();
    let name = last.split(',').next().unwrap();
    // Renamed in every table the member is read from, so the member itself is consistent.
    let renamed = format!("{name}9");
    for f in ["bodies.csv", "keyframes.csv", "ruins.csv"] {
        let p = dir.join("member-001").join(f);
        let s: String = std::fs::read_to_string(&p)
            .unwrap()
            .lines()
            .map(|l| {
                let fields: Vec<&str> = l
                    .split(',')
                    .map(|x| if x == name { renamed.as_str() } else { x })
                    .collect();
                fields.join(",") + "\n"
            })
            .collect();
        assert!(s.contains(&renamed), "{f}");
        std::fs::write(&p, s).unwrap();
    }
    let out_file = dir.join("again.html");
    let out = Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
        .args([
            "report".as_ref(),
            dir.as_os_str(),
            "-o".as_ref(),
            out_file.as_os_str(),
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("member-001/bodies.csv") && err.contains("other bodies"),
        "{err}"
    );
    assert!(!out_file.exists());
}
