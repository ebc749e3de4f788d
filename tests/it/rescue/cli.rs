//! `fem2rbd voids RUN_DIR`: the files it writes, their agreement with the library, and
//! bad input refused with the file or option named and nothing written.
use super::scene::*;
use std::path::Path;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_fem2rbd");

fn voids(dir: &Path, extra: &[&str]) -> std::process::Output {
    Command::new(BIN)
        .arg("voids")
        .arg(dir)
        .args(extra)
        .output()
        .unwrap()
}

fn written(dir: &Path) -> Vec<&'static str> {
    fem2rbd::rescue::report::FILES
        .into_iter()
        .filter(|f| dir.join(f).exists())
        .collect()
}

/// The table's folder gets the three files; `voids.csv` lists its one void (11.28 m³,
/// survivable, pancake, rescuer access), the height map one row per grid column, and a
/// second run writes the same bytes.
#[test]
fn writes_the_three_files_into_the_run_folder() {
    let dir = tempfile::tempdir().unwrap();
    let (boxes, cons) = table();
    write_run(dir.path(), &boxes, &cons, 1.0);
    let out = voids(dir.path(), &["--timing"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("rescue analysis: 5 bodies"), "{stdout}");
    assert_eq!(written(dir.path()), fem2rbd::rescue::report::FILES);
    let csv = std::fs::read_to_string(dir.path().join("voids.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 2, "{csv}");
    let head: Vec<&str> = lines[0].split(',').collect();
    let row: Vec<&str> = lines[1].split(',').collect();
    let col = |name: &str| row[head.iter().position(|h| *h == name).unwrap()];
    assert_eq!(col("volume_m3"), "11.280000");
    assert_eq!(col("survivable"), "1");
    assert_eq!(col("pattern"), "pancake");
    assert_eq!(col("rescuer_access"), "1");
    assert_eq!(col("roof_bodies"), "Slab:1:1");
    let js: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("voids.json")).unwrap())
            .unwrap();
    assert_eq!(js["voids_count"], 1);
    assert_eq!(js["survivable_count"], 1);
    let g = &js["grid"]["cells"];
    let columns = g[0].as_u64().unwrap() * g[1].as_u64().unwrap();
    let hm = std::fs::read_to_string(dir.path().join("rubble_height.csv")).unwrap();
    assert_eq!(hm.lines().count() as u64, columns + 1);
    let before: Vec<Vec<u8>> = fem2rbd::rescue::report::FILES
        .iter()
        .map(|f| std::fs::read(dir.path().join(f)).unwrap())
        .collect();
    assert!(voids(dir.path(), &[]).status.success());
    for (f, b) in fem2rbd::rescue::report::FILES.iter().zip(before) {
        assert_eq!(std::fs::read(dir.path().join(f)).unwrap(), b, "{f}");
    }
    // summary.json keeps its keys and gets the `rescue` section of the same analysis.
    let read = |f: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(dir.path().join(f)).unwrap()).unwrap()
    };
    let summary = read("summary.json");
    assert_eq!(summary["mode"], "rigid");
    assert_eq!(summary["scale"], 1.0);
    let rescue = &summary["rescue"];
    assert_eq!(rescue["voids_count"], 1);
    assert_eq!(rescue["survivable_count"], 1);
    assert_eq!(rescue["survivable_volume_m3"], 11.28);
    assert_eq!(rescue["largest_survivable"]["void"], 1);
    assert_eq!(rescue["largest_survivable"]["volume_m3"], 11.28);
    assert_eq!(rescue["largest_survivable"]["pattern"], "pancake");
    assert_eq!(rescue["largest_survivable"]["rescuer_access"], true);
    assert_eq!(rescue["pile_max_height_m"], 2.2);
    assert_eq!(rescue["extent_m"]["x_minus"], 0.0);
    // Re-analysed with another cell, the section follows voids.json.
    assert!(voids(dir.path(), &["--cell", "0.2"]).status.success());
    let (summary, js) = (read("summary.json"), read("voids.json"));
    assert_eq!(summary["rescue"]["sizes_full_scale_m"]["cell"], 0.2);
    assert_eq!(
        summary["rescue"]["survivable_volume_m3"],
        js["survivable_volume_m3"]
    );
    assert_eq!(summary["rescue"]["voids_count"], js["voids_count"]);
}

/// Runs `voids` on a table folder changed by `spoil`; returns stderr after checking that
/// it failed and wrote nothing.
fn refused(spoil: impl Fn(&Path), extra: &[&str]) -> String {
    let dir = tempfile::tempdir().unwrap();
    let (boxes, cons) = table();
    write_run(dir.path(), &boxes, &cons, 1.0);
    spoil(dir.path());
    let out = voids(dir.path(), extra);
    assert!(!out.status.success());
    assert!(written(dir.path()).is_empty(), "nothing written");
    String::from_utf8_lossy(&out.stderr).to_string()
}

#[test]
fn bad_input_is_named_and_nothing_is_written() {
    let e = refused(|_| {}, &["--cell", "0"]);
    assert!(e.contains("--cell = 0"), "{e}");
    let e = refused(|_| {}, &["--rescuer=-0.6"]);
    assert!(e.contains("--rescuer = -0.6"), "{e}");
    let e = refused(|_| {}, &["--camera", "nan"]);
    assert!(e.contains("--camera"), "{e}");
    let e = refused(|_| {}, &["--cell", "0.001"]);
    assert!(
        e.contains("--cell 0.001") && e.contains("more than the bound"),
        "{e}"
    );
    let e = refused(
        |d| std::fs::remove_file(d.join("connections.csv")).unwrap(),
        &[],
    );
    assert!(e.contains("connections.csv"), "{e}");
    let e = refused(
        |d| {
            let p = d.join("connections.csv");
            let t = std::fs::read_to_string(&p)
                .unwrap()
                .replace("Column:1:3", "Column:1:99");
            std::fs::write(p, t).unwrap();
        },
        &[],
    );
    assert!(
        e.contains("connections.csv:3: column b: body \"Column:1:99\" is not in bodies.csv"),
        "{e}"
    );
    let e = refused(
        |d| std::fs::write(d.join("summary.json"), "{\"mode\": \"rigid\"}\n").unwrap(),
        &[],
    );
    assert!(e.contains("summary.json") && e.contains("scale"), "{e}");
    let e = refused(
        |d| {
            let p = d.join("ruins.csv");
            let t = std::fs::read_to_string(&p).unwrap();
            let t: String = t.lines().take(3).map(|l| format!("{l}\n")).collect();
            std::fs::write(p, t).unwrap();
        },
        &[],
    );
    assert!(e.contains("ruins.csv"), "{e}");
}
