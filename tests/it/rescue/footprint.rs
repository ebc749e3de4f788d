//! The ensemble map marks the plan of a void's own cells, not its bounding box: two
//! hand-written member folders (their `voids.csv` and `voids.json` as `fem2rbd voids`
//! writes them, at scale 0.2 so that the map cell is 0.5 × 0.2 = 0.1 m, the analysis
//! cell): member 0 holds an L-shaped survivable void (0.4 × 0.2 m plus 0.2 × 0.2 m in
//! plan, the rescuer reaches it), member 1 a 0.4 × 0.4 m one with the same bounding box
//! (the rescuer does not reach it). The four map cells of the L's missing corner lie in
//! its bounding box, yet only member 1 has a void beneath them: 0.5, where a bounding-box
//! rule would give 1. Their routes, written by hand, pass over the map cells by the
//! closed-square rule: member 0's (the rescuer's and the camera's) along y = 0.05 m from
//! x = 0.55 to 0.35 m, member 1's (the camera's) along the cell edge x = 0.1 m from
//! y = 0.55 to 0.35 m, over the cells on both sides of it.
use super::ensemble::{read_map, read_route_map};
use fem2rbd::rescue::ensemble::write_maps;
use std::path::Path;

const CSV_HEADER: &str = "void,volume_m3,survivable,rescuer_access,camera_access,pattern,\
centroid_x,centroid_y,centroid_z,min_x,min_y,min_z,max_x,max_y,max_z";

/// A member folder with one survivable void of `boxes` (cell indices, cell 0.1 m, grid
/// 6 × 6 × 5 from the origin), bounding box 0…0.4 × 0…0.4 × 0…0.3 m, reached by the
/// camera along `path` (`path_m`) and by the rescuer along it too when `rescuer`.
fn member(dir: &Path, boxes: &str, volume: f64, rescuer: bool, path: &str) {
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
"voids": [{{"void": 1, "boxes": {boxes}, "rescuer": {rescuer_access},
"camera": {{"reached": true, "path_m": {path}}}}}]}}"#,
            rescuer_access = if rescuer {
                format!(r#"{{"reached": true, "path_m": {path}}}"#)
            } else {
                r#"{"reached": false}"#.to_string()
            }
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
        "[[0.55, 0.05, 0.15], [0.35, 0.05, 0.15]]",
    );
    member(
        &dir.join("member-001"),
        "[[0, 0, 0, 4, 4, 3]]",
        0.048,
        false,
        "[[0.1, 0.55, 0.15], [0.1, 0.35, 0.15]]",
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
    // [p_route_rescuer, p_route_camera, p_entry_rescuer, p_entry_camera]: member 0's
    // routes over cells 3, 4, 5 of row 0 (x 0.3…0.6), leaving open air in cell 5; member
    // 1's camera over the cells 0 and 1 of rows 3, 4, 5 (y 0.3…0.6; the edge x = 0.1 is
    // theirs both), leaving open air in cells 0 and 1 of row 5.
    for (i, j, x, y, q) in read_route_map(&dir.join("rescue_map.csv")) {
        let m0 = j == 0 && (3..=5).contains(&i);
        let m1 = i <= 1 && (3..=5).contains(&j);
        let half = |on: bool| if on { 0.5 } else { 0.0 };
        let want = [
            half(m0),
            half(m0 || m1),
            half(m0 && i == 5),
            half((m0 && i == 5) || (m1 && j == 5)),
        ];
        assert_eq!(q, want, "route cell ({i}, {j}) at ({x}, {y})");
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
