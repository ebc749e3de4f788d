//! `fem2rbd report` and the `report.html` of `fem2rbd run` on the frame3 run folder
//! ([`super::frame3`]): the page holds the run's numbers (one body-table row per body,
//! Tc, every keyframe's poses), the same folder gives the same bytes, bad run folders are
//! refused with the file named and nothing written, and `run --no-report` writes none.
use super::frame3::{fem2rbd, run_dir, scenario_text};
use fem2rbd::output::run_folder::RunFolder;
use std::path::Path;
use std::process::Command;

/// A copy of the frame3 run folder in a temporary folder.
fn copy_run() -> tempfile::TempDir {
    let tmp = tempfile::tempdir().unwrap();
    let to = tmp.path().join("run");
    std::fs::create_dir(&to).unwrap();
    for e in std::fs::read_dir(run_dir()).unwrap() {
        let p = e.unwrap().path();
        if p.is_file() {
            std::fs::copy(&p, to.join(p.file_name().unwrap())).unwrap();
        }
    }
    std::fs::create_dir(to.join("plots")).unwrap();
    for e in std::fs::read_dir(run_dir().join("plots")).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, to.join("plots").join(p.file_name().unwrap())).unwrap();
    }
    tmp
}

/// `fem2rbd report DIR -o OUT`: its stderr when it fails (and OUT must not exist then).
fn report_error(dir: &Path) -> String {
    let out_file = dir.join("r.html");
    let out = Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
        .args([
            "report".as_ref(),
            dir.as_os_str(),
            "-o".as_ref(),
            out_file.as_os_str(),
        ])
        .output()
        .unwrap();
    assert!(
        !out.status.success(),
        "report of a bad run folder succeeded"
    );
    assert!(
        !out_file.exists(),
        "nothing may be written on a bad run folder"
    );
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The page's data (the JSON of `report-data`).
fn page_data(html: &str) -> serde_json::Value {
    let start = html
        .find(r#"<script type="application/json" id="report-data">"#)
        .unwrap();
    let json = &html[start..];
    let json = &json[json.find('>').unwrap() + 1..json.find("</script>").unwrap()];
    serde_json::from_str(json).unwrap()
}

/// The bytes of base64 `text`, decoded here independently of the writer (RFC 4648
/// alphabet).
fn base64_bytes(text: &str) -> Vec<u8> {
    let alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut bits = 0u32;
    let mut nbits = 0;
    let mut bytes = Vec::new();
    for c in text.chars().filter(|&c| c != '=') {
        bits = (bits << 6) | alphabet.find(c).unwrap() as u32;
        nbits += 6;
        if nbits >= 8 {
            nbits -= 8;
            bytes.push((bits >> nbits) as u8);
            bits &= (1 << nbits) - 1;
        }
    }
    bytes
}

#[test]
fn the_page_holds_the_runs_numbers_and_is_byte_stable() {
    let dir = run_dir();
    let run = RunFolder::load(dir).unwrap();
    let html = std::fs::read_to_string(dir.join("report.html")).unwrap();
    // One body-table row per body, named as in bodies.csv.
    for (i, b) in run.bodies.iter().enumerate() {
        assert!(
            html.contains(&format!(
                r#"<tr id="body-{i}" data-body="{i}"><td>{i}</td><td>{}</td>"#,
                b.id.name()
            )),
            "row of {}",
            b.id.name()
        );
    }
    assert!(!html.contains(&format!(r#"id="body-{}""#, run.bodies.len())));
    // Tc in the key figures, as summary.json has it.
    let tc = run.summary.tc_s.unwrap();
    assert!(html.contains(&format!(
        r#"<tr data-key="tc_s"><th>Collapse moment Tc</th><td data-value="{tc}">{tc} s</td></tr>"#
    )));
    // Every keyframe's poses as 16-bit codes: the centres on one grid whose step is the
    // largest span of the centres over 65 535 (each coordinate within half a step), the
    // quaternions (x, y, z, w) as 32 767 · q (each component within half a code).
    let data = page_data(&html);
    let position = &data["position"];
    let step = position["step"].as_f64().unwrap();
    let origin: Vec<f64> = (0..3)
        .map(|c| position["origin"][c].as_f64().unwrap())
        .collect();
    let centres = || {
        run.frames
            .iter()
            .flat_map(|f| f.1.iter().map(|p| p.position))
    };
    let span = (0..3)
        .map(|c| {
            let hi = centres().map(|p| p[c]).fold(f64::NEG_INFINITY, f64::max);
            let lo = centres().map(|p| p[c]).fold(f64::INFINITY, f64::min);
            assert_eq!(lo, origin[c], "origin along axis {c}");
            hi - lo
        })
        .fold(0.0, f64::max);
    assert!(
        (step - span / 65_535.0).abs() <= 1e-15 * span,
        "{step} vs {span}"
    );
    let pos: Vec<u16> = base64_bytes(position["u16"].as_str().unwrap())
        .chunks(2)
        .map(|b| u16::from_le_bytes([b[0], b[1]]))
        .collect();
    assert_eq!(data["rotation"]["scale"].as_f64(), Some(32_767.0));
    let rot: Vec<i16> = base64_bytes(data["rotation"]["i16"].as_str().unwrap())
        .chunks(2)
        .map(|b| i16::from_le_bytes([b[0], b[1]]))
        .collect();
    let n = run.bodies.len();
    assert_eq!(pos.len(), run.frames.len() * n * 3);
    assert_eq!(rot.len(), run.frames.len() * n * 4);
    let mut worst_position: f64 = 0.0;
    for (k, (_, poses)) in run.frames.iter().enumerate() {
        for (i, p) in poses.iter().enumerate() {
            for c in 0..3 {
                let v = origin[c] + step * f64::from(pos[(k * n + i) * 3 + c]);
                let e = (v - p.position[c]).abs();
                assert!(
                    e <= 0.5 * step * (1.0 + 1e-9),
                    "{e} > step/2 = {}",
                    step / 2.0
                );
                worst_position = worst_position.max(e);
            }
            let [w, x, y, z] = p.orientation;
            for (c, q) in [x, y, z, w].into_iter().enumerate() {
                let code = f64::from(rot[(k * n + i) * 4 + c]);
                assert!((code - 32_767.0 * q).abs() <= 0.5 + 1e-9, "{code} for {q}");
            }
        }
    }
    // The grid is used: the largest error is more than a quarter step.
    assert!(worst_position > 0.25 * step, "{worst_position} vs {step}");
    // Nothing loaded from outside the page: no external script, style sheet or frame.
    for needle in ["<script src", "<link", "<iframe", "<img"] {
        assert!(!html.contains(needle), "{needle}");
    }
    // The same folder, the same bytes.
    let tmp = tempfile::tempdir().unwrap();
    let a = tmp.path().join("a.html");
    let b = tmp.path().join("b.html");
    fem2rbd(&[
        "report".as_ref(),
        dir.as_os_str(),
        "-o".as_ref(),
        a.as_os_str(),
    ]);
    fem2rbd(&[
        "report".as_ref(),
        dir.as_os_str(),
        "-o".as_ref(),
        b.as_os_str(),
    ]);
    let (a, b) = (std::fs::read(a).unwrap(), std::fs::read(b).unwrap());
    assert!(a == b, "two reports of one run folder differ");
    assert_eq!(
        a,
        html.as_bytes(),
        "report.html is the report of its folder"
    );
    eprintln!("frame3 CI report: {} bytes", a.len());
}

#[test]
fn bad_run_folders_are_named_and_nothing_is_written() {
    // A missing table.
    let t = copy_run();
    let d = t.path().join("run");
    std::fs::remove_file(d.join("keyframes.csv")).unwrap();
    let e = report_error(&d);
    assert!(e.contains("keyframes.csv"), "{e}");

    // summary.json disagreeing with bodies.csv.
    let t = copy_run();
    let d = t.path().join("run");
    let p = d.join("summary.json");
    let s = std::fs::read_to_string(&p).unwrap();
    std::fs::write(&p, s.replace("\"bodies\": 84", "\"bodies\": 85")).unwrap();
    let e = report_error(&d);
    assert!(
        e.contains("summary.json") && e.contains("bodies = 85"),
        "{e}"
    );

    // A connection naming a body that bodies.csv does not have: file and line.
    let t = copy_run();
    let d = t.path().join("run");
    let p = d.join("connections.csv");
    let s = std::fs::read_to_string(&p).unwrap();
    let second = s.lines().nth(1).unwrap();
    let a = second.split(',').next().unwrap();
    std::fs::write(
        &p,
        s.replacen(second, &second.replacen(a, "Column:9:999", 1), 1),
    )
    .unwrap();
    let e = report_error(&d);
    assert!(
        e.contains("connections.csv:2") && e.contains("Column:9:999"),
        "{e}"
    );

    // A ruin stage without connections.csv.
    std::fs::remove_file(&p).unwrap();
    let e = report_error(&d);
    assert!(
        e.contains("connections.csv") && e.contains("missing"),
        "{e}"
    );

    // A figure that is not an SVG.
    let t = copy_run();
    let d = t.path().join("run");
    std::fs::write(d.join("plots/zz.svg"), "<html></html>").unwrap();
    let e = report_error(&d);
    assert!(e.contains("zz.svg") && e.contains("not an SVG"), "{e}");

    // Not a run folder at all.
    let t = tempfile::tempdir().unwrap();
    let e = report_error(t.path());
    assert!(e.contains("bodies.csv"), "{e}");
}

#[test]
fn run_without_collapse_reports_and_no_report_writes_none() {
    // The FE stage alone until 0.5 s (no collapse, no ruin stage, no connections.csv).
    let tmp = tempfile::tempdir().unwrap();
    let text = scenario_text()
        .replace("dt = 0.005", "dt = 0.005\nduration = 0.5")
        .replace("criterion = \"drift_4pct\"", "");
    let sc = tmp.path().join("nc.toml");
    std::fs::write(&sc, text).unwrap();
    let with = tmp.path().join("with");
    let without = tmp.path().join("without");
    fem2rbd(&[
        "run".as_ref(),
        sc.as_os_str(),
        "--out".as_ref(),
        with.as_os_str(),
    ]);
    fem2rbd(&[
        "run".as_ref(),
        sc.as_os_str(),
        "--out".as_ref(),
        without.as_os_str(),
        "--no-report".as_ref(),
    ]);
    assert!(!without.join("report.html").exists());
    let html = std::fs::read_to_string(with.join("report.html")).unwrap();
    // 13 FE keyframes 0 … 0.48 s; no Tc, no connection colouring, no ruin stage.
    let run = RunFolder::load(&with).unwrap();
    assert_eq!(run.frames.len(), 13);
    assert!(html.contains(r#"min="0" max="0.48""#), "slider range");
    assert!(html.contains(r#"<td>none</td>"#));
    assert!(!html.contains(r#"<option value="connection">"#));
    assert!(!html.contains(r#"id="goto-tc""#));
    // The other files are the same with and without the report.
    for f in [
        "bodies.csv",
        "keyframes.csv",
        "history.csv",
        "ruins.csv",
        "collapse.glb",
    ] {
        assert_eq!(
            std::fs::read(with.join(f)).unwrap(),
            std::fs::read(without.join(f)).unwrap(),
            "{f}"
        );
    }
}
