//! The access routes on an ensemble's rescue map (`rescue_map.csv` `p_route_rescuer`,
//! `p_route_camera`, `p_entry_rescuer`, `p_entry_camera`): two members holding the room
//! down a corridor (`routes.rs`), the second shifted 0.5 m along x, give the shares of
//! the cells their routes pass over and leave open air in, counted by hand; every cell
//! agrees with a brute-force recount of the members' `voids.json`; a member whose
//! `voids.json` has no routes is refused naming it, with nothing written.
use super::ensemble::{
    assert_map_agrees_with_members, assert_maps_written_again_are_the_same, member, read_route_map,
};
use super::scene::*;
use fem2rbd::rescue::ensemble::{write_maps, FILES};
use serde_json::Value;
use std::path::Path;

/// Writes the two members: the room down a corridor (member 0) and the same 0.5 m along
/// x (member 1), each analysed by `fem2rbd voids`.
pub fn corridor_ensemble(dir: &Path) {
    member(&dir.join("member-000"), &room_down_a_corridor(), &[]);
    member(
        &dir.join("member-001"),
        &shifted(&room_down_a_corridor(), [0.5, 0.0, 0.0]),
        &[],
    );
}

fn json(file: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap()
}

/// The room down a corridor spans x −3.0 … 1.0 m, y −1.0 … 1.0 m; its analysis grid
/// is widened by the rescuer's 0.6 m and two 0.1 m cells: origin (−3.8, −1.8) m, to
/// (1.8, 1.8) m, and member 1's to (2.3, 1.8) m. The map's 0.5 m cells from (−3.8, −1.8)
/// are 13 × 8; row j = 3 spans y −0.3 … 0.2 m.
///
/// Both survivable voids (the room and the corridor) are reached along the corridor's
/// axis (y = ±0.05 m, inside row 3), from where the route leaves open air before the
/// corridor's mouth: member 0's routes run over x −3.05 … −0.15 m (the room's; the
/// corridor's is a part of it), cells i = 1 (−3.3 … −2.8) to 7 (−0.3 … 0.2); member 1's
/// over −2.55 … 0.35 m, cells 2 to 8. No point lies on a cell's edge. Shares: 1 in cells
/// 2–7 of row 3, 0.5 in cells 1 and 8, 0 elsewhere; the routes leave open air in cell 1
/// (member 0, x = −3.05) and cell 2 (member 1, x = −2.55): 0.5 each. The camera takes the
/// same lines.
#[test]
fn the_routes_down_a_corridor_give_their_shares_per_cell() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    corridor_ensemble(dir);
    // The premises: each member's routes start at x = −3.05 (+0.5) and the room's ends
    // at −0.15 (+0.5), all at y = ±0.05.
    for (m, dx) in [(0, 0.0), (1, 0.5)] {
        let js = json(&dir.join(format!("member-{m:03}/voids.json")));
        let voids = js["voids"].as_array().unwrap();
        assert_eq!(voids.len(), 2);
        for v in voids {
            assert_eq!(v["survivable"], true);
            for kind in ["rescuer", "camera"] {
                let p = v[kind]["path_m"].as_array().unwrap();
                let x = |k: usize| p[k][0].as_f64().unwrap();
                assert!(
                    (x(0) - (-3.05 + dx)).abs() < 1e-9,
                    "member {m} {kind}: {p:?}"
                );
                assert!(p
                    .iter()
                    .all(|q| (q[1].as_f64().unwrap().abs() - 0.05).abs() < 1e-9));
                let last = x(p.len() - 1);
                assert!(last > x(0) && last <= -0.15 + dx + 1e-9, "{p:?}");
            }
        }
        let room = &voids[0]["rescuer"]["path_m"];
        let end = room[room.as_array().unwrap().len() - 1][0]
            .as_f64()
            .unwrap();
        assert!(
            (end - (-0.15 + dx)).abs() < 1e-9,
            "the room's route ends at {end}"
        );
    }

    write_maps(dir).unwrap();
    let rj = json(&dir.join("rescue.json"));
    assert_eq!(rj["map"]["origin_m"], serde_json::json!([-3.8, -1.8]));
    assert_eq!(rj["map"]["cells"], serde_json::json!([13, 8]));
    let rows = read_route_map(&dir.join("rescue_map.csv"));
    assert_eq!(rows.len(), 13 * 8);
    for (i, j, x, y, q) in &rows {
        let over = if *j != 3 {
            0.0
        } else {
            match i {
                2..=7 => 1.0,
                1 | 8 => 0.5,
                _ => 0.0,
            }
        };
        let entry = if *j == 3 && (*i == 1 || *i == 2) {
            0.5
        } else {
            0.0
        };
        assert_eq!(
            *q,
            [over, over, entry, entry],
            "cell ({i}, {j}) at ({x}, {y})"
        );
    }
    assert_map_agrees_with_members(dir);

    // The same folder gives the same bytes.
    assert_maps_written_again_are_the_same(dir);
}

/// A member whose `voids.json` lacks a reached void's route (an older analysis) is
/// refused naming the file, the void and `rescuer.path_m`; no map is written.
#[test]
fn a_member_without_routes_is_refused_naming_its_file() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    corridor_ensemble(dir);
    let jf = dir.join("member-001/voids.json");
    let mut js = json(&jf);
    for v in js["voids"].as_array_mut().unwrap() {
        for kind in ["rescuer", "camera"] {
            v[kind].as_object_mut().unwrap().remove("path_m");
        }
    }
    std::fs::write(&jf, serde_json::to_string_pretty(&js).unwrap()).unwrap();
    let e = write_maps(dir).unwrap_err().to_string();
    assert!(
        e.contains("member-001/voids.json")
            && e.contains("void 1 has no `rescuer.path_m`")
            && e.contains("fem2rbd voids"),
        "{e}"
    );
    for f in FILES {
        assert!(!dir.join(f).exists(), "{f} written");
    }
}
