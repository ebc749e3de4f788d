//! Covered space split into chambers under one roof each, and the throats between them
//! (`src/rescue/voids.rs`, docs/rescue.md §2).
use super::scene::*;

/// `boxes` without connections, full scale, analysed at cell `cell`.
fn analysed_plain(boxes: &[SceneBox], cell: f64) -> fem2rbd::rescue::Analysis {
    analysed(boxes, &[], 1.0, cell)
}
use fem2rbd::rescue::pattern::Pattern;

/// Two tables meeting over a wall: one chamber under each slab, 11.32 m³ each (exact on
/// the aligned 0.1 m grid), joined by a throat over the wall: the 0.4 m gap's 80 faces
/// (0.8 m²) and clearance 0.4/2 − h/2 = 0.15 m (the distance transform's half-cell).
#[test]
fn two_tables_over_a_low_wall_are_two_chambers_and_a_throat() {
    let a = analysed_plain(&two_tables(), 0.1);
    assert_eq!(a.voids.len(), 2, "{}", a.voids_csv());
    let roofs: Vec<&str> = a
        .voids
        .iter()
        .map(|r| a.names[r.void.roof[0].0].as_str())
        .collect();
    assert_eq!(roofs, ["Slab:1:1", "Slab:1:2"]);
    for r in &a.voids {
        close(r.void.volume_m3, 11.32, 1e-9, "chamber volume");
        assert_eq!(r.void.roof.len(), 1);
        close(r.void.clear_height_m, 2.0, 1e-9, "clear height");
        assert_eq!(r.void.region, 0);
        assert_eq!(r.pattern.pattern, Pattern::Pancake);
    }
    assert_eq!(a.throats.len(), 1);
    let t = &a.throats[0];
    assert_eq!((t.a, t.b, t.faces), (0, 1, 80));
    close(t.area_m2, 0.8, 1e-9, "throat area");
    close(t.clearance_m, 0.15, 1e-6, "throat clearance");
    let csv = a.voids_csv();
    let row: Vec<&str> = csv.lines().nth(1).unwrap().split(',').collect();
    assert_eq!(row[row.len() - 2..], ["1", "2:0.150000"]);
    let js = a.json();
    assert_eq!(js["regions_count"], 1);
    assert_eq!(js["voids"][1]["neighbours"][0]["void"], 1);
    assert_eq!(js["voids"][1]["neighbours"][0]["throat_area_m2"], 0.8);
}

/// A lean-to resting on a pancake's edge: two chambers, the pancake's 13.824 m³ (exact)
/// and the 40° wedge's 6.0 / tan 40° m³ to within half a cell along its slanted face, a
/// pancake and a supported lean-to held by the flat slab, joined through the whole
/// 2.4 × 1.8 m opening between them.
#[test]
fn a_lean_to_beside_a_pancake_is_two_chambers_with_their_patterns() {
    let h = 0.05;
    let a = analysed_plain(&lean_to_beside_pancake(40.0), h);
    let find = |roof: &str| {
        a.voids
            .iter()
            .position(|r| a.names[r.void.roof[0].0] == roof)
            .unwrap_or_else(|| panic!("no chamber under {roof}: {}", a.voids_csv()))
    };
    let (p, l) = (find("Slab:1:5"), find("Slab:1:2"));
    let (rp, rl) = (&a.voids[p], &a.voids[l]);
    close(rp.void.volume_m3, 13.824, 1e-9, "pancake chamber");
    assert_eq!(rp.pattern.pattern, Pattern::Pancake);
    let (la, lb) = (2.0f64, 2.0 / 40f64.to_radians().tan());
    close(
        rl.void.volume_m3,
        3.0 * la * lb / 2.0,
        la.hypot(lb) * 3.0 * h / 2.0,
        "wedge chamber",
    );
    assert_eq!(rl.pattern.pattern, Pattern::SupportedLeanTo);
    assert_eq!(rl.pattern.held_by, "debris Slab:1:5");
    close(rl.pattern.roof_tilt_deg.unwrap(), 40.0, 1e-6, "tilt");
    let t = a
        .throats
        .iter()
        .find(|t| (t.a, t.b) == (p.min(l), p.max(l)))
        .expect("a throat between them");
    close(t.area_m2, 2.4 * 1.8, 1e-9, "opening");
    assert_eq!(rp.void.region, rl.void.region);
}

/// A fragment joins its neighbour: a 0.2 m cube stuck under the table's slab caps a part
/// of 2 × 2 × 18 = 72 cells, fewer than a sitting adult's 5 × 5 × 9 = 225, so it joins
/// the chamber under the slab: one chamber of 11.28 − 0.008 m³ (exact) whose roof is the
/// slab and the cube, and no throat.
#[test]
fn a_fragment_under_a_small_roof_joins_its_neighbour() {
    let (mut boxes, _) = table();
    boxes.push(beam(9, [0.0, 0.0, 1.9], [0.1, 0.1, 0.1]));
    let a = analysed_plain(&boxes, 0.1);
    assert_eq!(a.voids.len(), 1, "{}", a.voids_csv());
    let v = &a.voids[0].void;
    close(v.volume_m3, 11.28 - 0.008, 1e-9, "chamber volume");
    let roof: Vec<(&str, usize)> = v
        .roof
        .iter()
        .map(|(b, n)| (a.names[*b].as_str(), *n))
        .collect();
    assert_eq!(roof, [("Slab:1:1", 564 - 4), ("Beam:1:9", 4)]);
    assert!(a.throats.is_empty());
    assert_eq!(
        fem2rbd::rescue::voids::fragment_cells(&a.scaled, 0.1),
        5 * 5 * 9
    );
}
