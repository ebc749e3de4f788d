//! `fem2rbd voids ENSEMBLE_DIR`: every member re-analysed, the ensemble's rescue maps,
//! their figure and its report rebuilt from them, all or nothing.
use super::ensemble::{assert_map_agrees_with_members, at, map_rows, table_at};
use super::scene::*;
use serde_json::Value;
use std::path::Path;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_fem2rbd");

fn voids(dir: &Path, args: &[&str]) -> std::process::Output {
    Command::new(BIN)
        .arg("--quiet")
        .arg("voids")
        .arg(dir)
        .args(args)
        .output()
        .unwrap()
}

fn json(p: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// Three members written as run folders with no analysis yet (the table; the table 0.5 m
/// along x; the table and a second one 6 m along x) and an `ensemble.json`: `fem2rbd voids
/// DIR` analyses each member (its `voids.csv`, `voids.json`, `rubble_height.csv`, the
/// `rescue` section of `summary.json`), writes `rescue_map.csv` and `rescue.json` equal
/// byte for byte to what the maps of the written members give
/// (`rescue::ensemble::write_maps`), and the `plots/rescue_map` figure equal to `fem2rbd
/// plot`'s; under the table's middle all three members have a survivable void the rescuer
/// reaches (1), under the far table one of three. Again with a 2.5 m rescuer (taller than
/// the table's 2.0 m clearance): every member is re-analysed and no cell has a survivable
/// void the rescuer reaches, while the camera still reaches them. The same folder gives
/// the same bytes twice.
#[test]
fn voids_of_an_ensemble_folder_rebuilds_its_maps_from_reanalysed_members() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("ens");
    let (t, c) = table_at([0.0; 3], 0);
    write_run(&dir.join("member-000"), &t, &c, 1.0);
    let (t1, c1) = table_at([0.5, 0.0, 0.0], 0);
    write_run(&dir.join("member-001"), &t1, &c1, 1.0);
    let (mut two, mut c2) = table_at([0.0; 3], 0);
    let (far, cf) = table_at([6.0, 0.0, 0.0], two.len());
    two.extend(far);
    c2.extend(cf);
    write_run(&dir.join("member-002"), &two, &c2, 1.0);
    std::fs::write(dir.join("ensemble.json"), "{}\n").unwrap();

    let out = voids(&dir, &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for m in 0..3 {
        let md = dir.join(format!("member-{m:03}"));
        for f in ["voids.csv", "voids.json", "rubble_height.csv"] {
            assert!(md.join(f).is_file(), "member {m}: {f}");
        }
        assert_eq!(
            json(&md.join("summary.json"))["rescue"]["survivable_count"],
            if m == 2 { 2 } else { 1 }
        );
    }
    let js = json(&dir.join("rescue.json"));
    assert_eq!(js["members_analysed"], 3);
    assert_map_agrees_with_members(&dir);
    let rows = map_rows(&dir);
    let h = js["map"]["cell_m"].as_f64().unwrap();
    assert_eq!(at(&rows, 0.25, 0.0, h), [1.0, 1.0, 1.0, 1.0]);
    let far = at(&rows, 6.0, 0.0, h);
    assert!((far[2] - 1.0 / 3.0).abs() < 1e-6, "{far:?}");
    // The maps are those of the written members; the figure is `fem2rbd plot`'s.
    let ours: Vec<Vec<u8>> = [
        "rescue_map.csv",
        "rescue.json",
        "plots/rescue_map.svg",
        "plots/rescue_map.png",
    ]
    .iter()
    .map(|f| std::fs::read(dir.join(f)).unwrap())
    .collect();
    fem2rbd::rescue::ensemble::write_maps(&dir).unwrap();
    assert_eq!(std::fs::read(dir.join("rescue_map.csv")).unwrap(), ours[0]);
    assert_eq!(std::fs::read(dir.join("rescue.json")).unwrap(), ours[1]);
    let fig = fem2rbd::plot::voids::RescueMapFigure::load(&dir)
        .unwrap()
        .unwrap();
    assert_eq!(
        fem2rbd::plot::svg_string(&fig).unwrap().into_bytes(),
        ours[2]
    );
    assert_eq!(fem2rbd::plot::png_bytes(&fig).unwrap(), ours[3]);
    // The same folder, the same bytes.
    let out = voids(&dir, &[]);
    assert!(out.status.success());
    assert_eq!(std::fs::read(dir.join("rescue.json")).unwrap(), ours[1]);
    assert_eq!(
        std::fs::read(dir.join("plots/rescue_map.png")).unwrap(),
        ours[3]
    );

    let out = voids(&dir, &["--rescuer", "2.5"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for m in 0..3 {
        let v = json(&dir.join(format!("member-{m:03}/voids.json")));
        assert_eq!(v["sizes_full_scale_m"]["rescuer"], 2.5);
        assert_eq!(v["rescuer_reachable_survivable"], 0);
    }
    assert_map_agrees_with_members(&dir);
    let rows = map_rows(&dir);
    assert!(rows.iter().all(|r| r.4[2] == 0.0));
    assert_eq!(at(&rows, 0.25, 0.0, h), [1.0, 1.0, 0.0, 1.0]);
}

/// A member without `connections.csv`: the command fails naming the member and the file,
/// and nothing is written — no member's analysis, no map, no figure.
#[test]
fn voids_of_an_ensemble_with_a_broken_member_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("ens");
    let (t, c) = table_at([0.0; 3], 0);
    write_run(&dir.join("member-000"), &t, &c, 1.0);
    write_run(&dir.join("member-001"), &t, &c, 1.0);
    std::fs::remove_file(dir.join("member-001/connections.csv")).unwrap();
    std::fs::write(dir.join("ensemble.json"), "{}\n").unwrap();
    let out = voids(&dir, &[]);
    assert!(!out.status.success());
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(
        e.contains("member-001") && e.contains("connections.csv"),
        "{e}"
    );
    assert!(!dir.join("member-000/voids.csv").exists());
    assert!(!dir.join("rescue_map.csv").exists() && !dir.join("rescue.json").exists());
    assert!(!dir.join("plots/rescue_map.png").exists());
    let left: Vec<_> = std::fs::read_dir(dir.join("member-000"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    // An ensemble folder without members.
    let empty = tmp.path().join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    std::fs::write(empty.join("ensemble.json"), "{}\n").unwrap();
    let out = voids(&empty, &[]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("without member-NNN folders"));
}
