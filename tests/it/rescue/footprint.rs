//! The ensemble map marks the plan of a void's own cells, not its bounding box: two
//! hand-written member folders (their `voids.csv` and `voids.json` as `fem2rbd voids`
//! writes them, at scale 0.2 so that the map cell is 0.5 × 0.2 = 0.1 m, the analysis
//! cell): member 0 holds an L-shaped survivable void (0.4 × 0.2 m plus 0.2 × 0.2 m in
//! plan, the rescuer reaches it), member 1 a 0.4 × 0.4 m one with the same bounding box
//! (the rescuer does not reach it). The four map cells of the L's missing corner lie in
//! its bounding box, yet only member 1 has a void beneath them: 0.5, where a bounding-box
//! rule would give 1.
use super::ensemble::read_map;
use fem2rbd::rescue::ensemble::write_maps;
use std::path::Path;

const CSV_HEADER: &str = "void,volume_m3,survivable,rescuer_access,camera_access,pattern,\
centroid_x,centroid_y,centroid_z,min_x,min_y,min_z,max_x,max_y,max_z";

/// A member folder with one survivable void of `boxes` (cell indices, cell 0.1 m, grid
/// 6 × 6 × 5 from the origin), bounding box 0…0.4 × 0…0.4 × 0…0.3 m.
fn member(dir: &Path, boxes: &str, volume: f64, rescuer: bool) {
    std::fs::create_dir_all(dir).unwrap();
    let r = u8::from(rescuer);
    std::fs::write(
        dir.join("voids.csv"),
        format!("{CSV_HEADER}\n1,{volume},1,{r},1,pancake,0.2,0.2,0.15,0,0,0,0.4,0.4,0.3\n"),
    )
    .unwrap();
    std::fs::write(
        dir.join("voids.json"),
        format!(
            r#"{{"scale": 0.2, "grid": {{"origin_m": [0.0, 0.0, 0.0], "cell_m": 0.1, "cells": [6, 6, 5]}},
"rubble": {{"max_height_m": 0.5, "mean_height_m": 0.4}}, "voids_count": 1,
"voids": [{{"void": 1, "boxes": {boxes}}}]}}"#
        ),
    )
    .unwrap();
}

#[test]
fn an_l_shaped_void_does_not_claim_the_corner_it_does_not_cover() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // The L: x 0…0.4 at y 0…0.2, and x 0…0.2 at y 0.2…0.4 (12 columns × 3 cells).
    member(
        &dir.join("member-000"),
        "[[0, 0, 0, 4, 2, 3], [0, 2, 0, 2, 4, 3]]",
        0.036,
        true,
    );
    member(
        &dir.join("member-001"),
        "[[0, 0, 0, 4, 4, 3]]",
        0.048,
        false,
    );
    write_maps(dir).unwrap();
    let rows = read_map(&dir.join("rescue_map.csv"));
    assert_eq!(rows.len(), 36, "6 × 6 map cells of 0.1 m");
    for (i, j, x, y, p) in &rows {
        assert!(
            (x - (0.05 + 0.1 * *i as f64)).abs() < 1e-9
                && (y - (0.05 + 0.1 * *j as f64)).abs() < 1e-9
        );
        let in_l = (*i < 4 && *j < 2) || (*i < 2 && *j < 4);
        let corner = (2..4).contains(i) && (2..4).contains(j);
        // [p_void, p_survivable, p_survivable_rescuer, p_survivable_camera]
        let want = if in_l {
            [1.0, 1.0, 0.5, 1.0]
        } else if corner {
            // Inside the L's bounding box (0…0.4 both ways), outside its cells.
            assert!(*x < 0.4 && *y < 0.4);
            [0.5, 0.5, 0.0, 0.5]
        } else {
            [0.0; 4]
        };
        assert_eq!(*p, want, "cell ({i}, {j}) at ({x}, {y})");
    }
    let js: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("rescue.json")).unwrap()).unwrap();
    assert!(js["map"]["beneath"]
        .as_str()
        .unwrap()
        .contains("plan of the void's cells"));
    // A void listed without its boxes (a voids.json of an older analysis) is refused,
    // naming the file.
    let old = dir.join("member-001/voids.json");
    let text = std::fs::read_to_string(&old)
        .unwrap()
        .replace(r#", "boxes": [[0, 0, 0, 4, 4, 3]]"#, "");
    std::fs::write(&old, text).unwrap();
    let e = write_maps(dir).unwrap_err().to_string();
    assert!(
        e.contains("member-001/voids.json") && e.contains("no `boxes`"),
        "{e}"
    );
}
