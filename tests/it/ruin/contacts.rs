//! Connection search and contact geometry (docs/bcb.md §7.3, §11.3): exact face
//! contacts, dropped edge/corner contacts, rotated boxes, and a frame3-like set of boxes.

use fem2rbd::ruin::search::{
    find_contacts, Contact, ContactAreaRule, JointContacts, SearchSettings,
};
use fem2rbd::ruin::BodyGeom;
use nalgebra::{UnitQuaternion, Vector3};
use std::f64::consts::FRAC_PI_2;

fn cuboid(name: &str, group: &str, min: [f64; 3], max: [f64; 3]) -> BodyGeom {
    BodyGeom {
        name: name.into(),
        group: group.into(),
        centre: [0, 1, 2].map(|i| 0.5 * (min[i] + max[i])),
        rotation: UnitQuaternion::identity(),
        half_extents: [0, 1, 2].map(|i| 0.5 * (max[i] - min[i])),
        passive: false,
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-12
}

fn close3(a: [f64; 3], b: [f64; 3]) -> bool {
    (0..3).all(|i| close(a[i], b[i]))
}

/// A 0.3 × 0.2 slab piece resting partly on a 0.1 × 0.4 block: overlap rectangle
/// x ∈ [0.2, 0.3], y ∈ [0.0, 0.2] → h = 0.1 (x), w = 0.2 (y), a = 0.02 m², pivot
/// (0.25, 0.1, 1.0), normal +Z from the block (A) to the piece (B).
#[test]
fn face_contact_rectangle_pivot_normal() {
    let a = cuboid("block", "g", [0.2, -0.1, 0.0], [0.3, 0.3, 1.0]);
    let b = cuboid("piece", "g", [0.0, 0.0, 1.0], [0.3, 0.2, 1.05]);
    let c = find_contacts(&[a.clone(), b.clone()], &SearchSettings::default()).unwrap();
    assert_eq!(c.len(), 1);
    let c = c[0];
    assert_eq!((c.a, c.b), (0, 1));
    assert_eq!(
        (c.normal_axis, c.normal_sign, c.h_axis, c.w_axis),
        (2, 1.0, 0, 1)
    );
    assert!(close(c.h, 0.1) && close(c.w, 0.2) && close(c.area, 0.02));
    assert!(close3(c.pivot, [0.25, 0.1, 1.0]));
    assert_eq!(c.normal(), [0.0, 0.0, 1.0]);
    assert!(close(c.normal_overlap, 0.0));
    // Swapping the order swaps A and B: the normal now points down (from piece to block).
    let c2 = find_contacts(&[b, a], &SearchSettings::default()).unwrap()[0];
    assert_eq!((c2.normal_axis, c2.normal_sign), (2, -1.0));
    assert!(close3(c2.pivot, [0.25, 0.1, 1.0]) && close(c2.area, 0.02));
    // BCB's projection-sum rule agrees up to its 2e-6 m widening.
    let s = SearchSettings {
        area_rule: ContactAreaRule::ProjectionSum,
        ..SearchSettings::default()
    };
    let a = cuboid("block", "g", [0.2, -0.1, 0.0], [0.3, 0.3, 1.0]);
    let b = cuboid("piece", "g", [0.0, 0.0, 1.0], [0.3, 0.2, 1.05]);
    let p = find_contacts(&[a, b], &s).unwrap()[0];
    let w = 2e-6;
    let expect = (0.1 + w) * (0.2 + w) + (0.1 + w) * w + (0.2 + w) * w;
    assert!(close(p.area, expect));
}

/// Side-by-side boxes sharing a vertical face: normal −X when B lies at lower x.
#[test]
fn side_contact_normal_sign_from_centres() {
    let a = cuboid("right", "g", [1.0, 0.0, 0.0], [2.0, 0.5, 0.3]);
    let b = cuboid("left", "g", [0.0, 0.1, 0.1], [1.0, 0.4, 0.5]);
    let c = find_contacts(&[a, b], &SearchSettings::default()).unwrap()[0];
    // Overlaps: x 0, y 0.3, z 0.2 → normal x, h = z (0.2), w = y (0.3).
    assert_eq!(
        (c.normal_axis, c.normal_sign, c.h_axis, c.w_axis),
        (0, -1.0, 2, 1)
    );
    assert!(close(c.h, 0.2) && close(c.w, 0.3) && close(c.area, 0.06));
    assert!(close3(c.pivot, [1.0, 0.25, 0.2]));
    let d = Vector3::new(0.5 - 1.5, 0.25 - 0.25, 0.3 - 0.15).norm();
    assert!(close(c.centre_distance, d));
}

/// Boxes touching only along an edge or at a corner have a = 0 and are dropped, although
/// their enlarged AABBs overlap; so are boxes whose only overlap is a sliver below 1e-6 m².
#[test]
fn edge_and_corner_contacts_are_dropped() {
    let s = SearchSettings::default();
    let base = cuboid("base", "g", [0.0, 0.0, 0.0], [1.0, 1.0, 1.0]);
    let edge = cuboid("edge", "g", [1.0, 0.0, 1.0], [2.0, 1.0, 2.0]); // shares the edge x=1, z=1
    let corner = cuboid("corner", "g", [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]);
    let near_edge = cuboid("near", "g", [1.005, 0.0, 1.005], [2.0, 1.0, 2.0]);
    for other in [edge, corner, near_edge] {
        let c = find_contacts(&[base.clone(), other.clone()], &s).unwrap();
        assert!(c.is_empty(), "{} connected: {:?}", other.name, c);
    }
    // A face contact of 1 mm × 0.5 mm = 5e-7 m² is dropped, 1 mm × 2 mm = 2e-6 m² kept.
    let small = cuboid("small", "g", [0.999, 0.0, 1.0], [1.5, 0.0005, 1.5]);
    assert!(find_contacts(&[base.clone(), small], &s)
        .unwrap()
        .is_empty());
    let kept = cuboid("kept", "g", [0.999, 0.0, 1.0], [1.5, 0.002, 1.5]);
    let c = find_contacts(&[base, kept], &s).unwrap();
    assert_eq!(c.len(), 1);
    assert!((c[0].area - 2e-6).abs() < 1e-15);
}

/// A box turned 90° about z (a beam along y given as a rotated x-beam) has the same
/// contacts as the axis-aligned one.
#[test]
fn rotated_box_uses_its_world_aabb() {
    let col = cuboid("col", "g", [-0.05, -0.05, 0.0], [0.05, 0.05, 1.0]);
    let aligned = cuboid("beam", "g", [-0.0375, 0.05, 0.85], [0.0375, 1.45, 1.0]);
    let rotated = BodyGeom {
        half_extents: [0.7, 0.0375, 0.075],
        rotation: UnitQuaternion::from_axis_angle(&Vector3::z_axis(), FRAC_PI_2),
        ..aligned.clone()
    };
    let s = SearchSettings::default();
    let c1 = find_contacts(&[col.clone(), aligned], &s).unwrap();
    let c2 = find_contacts(&[col, rotated], &s).unwrap();
    assert_eq!(c1.len(), 1);
    assert_eq!(c2.len(), 1);
    assert!(close(c1[0].area, 0.075 * 0.15) && close(c2[0].area, c1[0].area));
    assert!(close3(c1[0].pivot, c2[0].pivot));
    assert!(close3(c1[0].pivot, [0.0, 0.05, 0.925]));
    assert_eq!((c2[0].normal_axis, c2[0].normal_sign), (1, 1.0));
}

/// A frame3-like model: 1 × 1 bay of 1.5 m, three 1 m stories, 100 × 100 mm columns split
/// at mid-height, 75 × 150 mm beams split at mid-span, one 30 mm slab per floor, and a
/// passive foundation block. Trimming rule of this fixture: a column runs from the slab
/// below (or the foundation) to its floor level z_f; beams sit between column faces with
/// their top at z_f; the slab lies on top, z_f … z_f + 0.03, over the column outlines.
fn frame3_like() -> Vec<BodyGeom> {
    let (l, hc, bw, bh, t) = (1.5, 0.05, 0.0375, 0.15, 0.03);
    let mut v = vec![BodyGeom {
        passive: true,
        ..cuboid("Foundation", "found", [-0.2, -0.2, -0.2], [1.7, 1.7, 0.0])
    }];
    for story in 0..3 {
        let zf = story as f64 * (1.0 + t) + 1.0; // floor level (top of the beams)
        let zb = zf - 1.0; // column base (top of the slab below, or 0)
        for (i, x) in [0.0, l].into_iter().enumerate() {
            for (j, y) in [0.0, l].into_iter().enumerate() {
                for (k, (z0, z1)) in [(zb, zb + 0.5), (zb + 0.5, zf)].into_iter().enumerate() {
                    v.push(cuboid(
                        &format!("Column:{story}:{i}{j}{k}"),
                        "columns",
                        [x - hc, y - hc, z0],
                        [x + hc, y + hc, z1],
                    ));
                }
            }
        }
        for (side, c) in [0.0, l].into_iter().enumerate() {
            for (half, (s0, s1)) in [(hc, l / 2.0), (l / 2.0, l - hc)].into_iter().enumerate() {
                // Beam along x at y = c, and along y at x = c.
                v.push(cuboid(
                    &format!("BeamX:{story}:{side}{half}"),
                    "beams",
                    [s0, c - bw, zf - bh],
                    [s1, c + bw, zf],
                ));
                v.push(cuboid(
                    &format!("BeamY:{story}:{side}{half}"),
                    "beams",
                    [c - bw, s0, zf - bh],
                    [c + bw, s1, zf],
                ));
            }
        }
        v.push(cuboid(
            &format!("Slab:{story}"),
            "slabs",
            [-hc, -hc, zf],
            [l + hc, l + hc, zf + t],
        ));
    }
    v
}

fn kind(name: &str) -> &str {
    name.split(':').next().unwrap()
}

#[test]
fn frame3_like_connections() {
    let bodies = frame3_like();
    assert_eq!(bodies.len(), 1 + 3 * (8 + 8 + 1));
    let contacts = find_contacts(&bodies, &SearchSettings::default()).unwrap();
    // Sorted by (a, b), a < b.
    assert!(contacts
        .windows(2)
        .all(|w| (w[0].a, w[0].b) < (w[1].a, w[1].b)));
    // Tally by kind pair and area.
    let mut tally: std::collections::BTreeMap<(String, String, i64), usize> = Default::default();
    for c in &contacts {
        let mut k = [kind(&bodies[c.a].name), kind(&bodies[c.b].name)];
        k.sort();
        let area_mm2 = (c.area * 1e6).round() as i64;
        *tally
            .entry((k[0].into(), k[1].into(), area_mm2))
            .or_default() += 1;
    }
    let expect: Vec<((&str, &str, i64), usize)> = vec![
        // Beam halves at mid-span: 75 × 150 mm.
        (("BeamX", "BeamX", 11250), 6),
        (("BeamX", "Column", 11250), 12),
        // Beam tops under the slab: 0.7 m × 75 mm.
        (("BeamX", "Slab", 52500), 12),
        (("BeamY", "BeamY", 11250), 6),
        (("BeamY", "Column", 11250), 12),
        (("BeamY", "Slab", 52500), 12),
        // Column halves at mid-height and on the foundation: 100 × 100 mm.
        (("Column", "Column", 10000), 12),
        (("Column", "Foundation", 10000), 4),
        // Column tops under their slab (12) and column bases on the slab below (8).
        (("Column", "Slab", 10000), 20),
    ];
    let got: Vec<((String, String, i64), usize)> = tally.into_iter().collect();
    let expect: Vec<((String, String, i64), usize)> = expect
        .into_iter()
        .map(|((a, b, c), n)| ((a.to_string(), b.to_string(), c), n))
        .collect();
    assert_eq!(got, expect);
    assert_eq!(contacts.len(), 96);
    // Normals: vertical for column–slab, column–column, beam–slab, foundation; horizontal
    // for beam–column and beam–beam.
    for c in &contacts {
        let k = [kind(&bodies[c.a].name), kind(&bodies[c.b].name)];
        let vertical =
            k.contains(&"Slab") || k.contains(&"Foundation") || k == ["Column", "Column"];
        assert_eq!(c.normal_axis == 2, vertical, "{:?}", k);
        // The normal points from A towards B.
        let d = bodies[c.b].centre[c.normal_axis] - bodies[c.a].centre[c.normal_axis];
        assert!(d * c.normal_sign > 0.0);
    }
    // One column–slab contact in detail: column (0,0) top of story 1 under slab 0.
    let col = bodies
        .iter()
        .position(|b| b.name == "Column:0:001")
        .unwrap();
    let slab = bodies.iter().position(|b| b.name == "Slab:0").unwrap();
    let c: &Contact = contacts.iter().find(|c| (c.a, c.b) == (col, slab)).unwrap();
    assert!(close3(c.pivot, [0.0, 0.0, 1.0]));
    assert!(close(c.h, 0.1) && close(c.w, 0.1));
    // Centres (0, 0, 0.75) and (0.75, 0.75, 1.015).
    let d = (2.0 * 0.75f64.powi(2) + 0.265f64.powi(2)).sqrt();
    assert!(close(c.centre_distance, d));
}

/// A 20 × 20 × 20 grid of unit cubes: exactly the 3·19·400 = 22 800 face contacts, each
/// 1 m², no edge or corner pair (the sweep handles 8 000 bodies quickly).
#[test]
fn cube_grid_face_contacts_only() {
    let n = 20;
    let mut bodies = Vec::new();
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let (x, y, z) = (i as f64, j as f64, k as f64);
                bodies.push(cuboid(
                    &format!("c{i}.{j}.{k}"),
                    "g",
                    [x, y, z],
                    [x + 1.0, y + 1.0, z + 1.0],
                ));
            }
        }
    }
    let c = find_contacts(&bodies, &SearchSettings::default()).unwrap();
    assert_eq!(c.len(), 3 * (n - 1) * n * n);
    assert!(c.iter().all(|c| close(c.area, 1.0)));
}

/// The frame3-like model through `build_connections`: column bases on the passive
/// foundation get doubled thresholds; a column–foundation connection checked by hand.
#[test]
fn frame3_like_connection_thresholds() {
    use fem2rbd::ruin::connection::{build_connections, GroupStrength, RuinSettings};
    use fem2rbd::ruin::strength::{FormulaInputs, FormulaKind};
    let bodies = frame3_like();
    let s = RuinSettings::default();
    let contacts = find_contacts(&bodies, &s.search).unwrap();
    // Sections "0 = contact dims" for columns and beams, walls/slabs formula for slabs;
    // the foundation group needs no strengths (passive).
    let sym = FormulaInputs {
        h_mm: 0.0,
        w_mm: 0.0,
        ..FormulaInputs::default()
    };
    let groups = [
        GroupStrength::formula("columns", sym),
        GroupStrength::formula("beams", sym),
        GroupStrength::formula(
            "slabs",
            FormulaInputs {
                kind: FormulaKind::WallSlab,
                ..sym
            },
        ),
    ];
    let poses: Vec<_> = bodies.iter().map(BodyGeom::pose).collect();
    let conns = build_connections(&bodies, &groups, &contacts, &poses, &s).unwrap();
    assert_eq!(conns.len(), 96);
    let found: Vec<_> = conns.iter().filter(|c| bodies[c.a].passive).collect();
    assert_eq!(found.len(), 4);
    // By hand: 100 × 100 mm contact, ρ = 5·3.1416·25/10⁴ = 0.03927;
    // (BCB's π = 3.1416) C = (30(1 − ρ) + 500ρ)·10⁴ N, ×2 to the foundation, ×2.2/200.
    let rho = 5.0 * fem2rbd::ruin::strength::FA_PI * 25.0 / 1.0e4;
    let c_n = (30.0 * (1.0 - rho) + 500.0 * rho) * 1.0e4 * 2.0;
    for c in &found {
        assert_eq!(c.group, "columns");
        assert!((c.forces.compression_n - c_n).abs() < 1e-6 * c_n);
        assert!((c.constraints[0].breaking_impulse - c_n * 2.2 / 200.0).abs() < 1e-6);
        // Square contact: no distinct 90° values; bending B·h/w = B on both rows.
        assert!((c.forces.bend_h_nm - c.forces.bend_w_nm).abs() < 1e-9 * c.forces.bend_w_nm);
    }
    assert!((c_n * 2.2 / 200.0 - 10660.6).abs() < 0.1);
    // A column–column mid-height joint has exactly half the foundation's values.
    let mid = conns
        .iter()
        .find(|c| kind(&bodies[c.a].name) == "Column" && kind(&bodies[c.b].name) == "Column")
        .unwrap();
    assert!((2.0 * mid.forces.compression_n - c_n).abs() < 1e-6 * c_n);
    // Column–slab: the weaker group per value (slab shear 0.15·k·(100ρfc)^(1/3) is far
    // below the beam formula's), the column group (A, lower index) governs tolerances.
    let cs = conns
        .iter()
        .find(|c| kind(&bodies[c.a].name) == "Column" && kind(&bodies[c.b].name) == "Slab")
        .unwrap();
    assert_eq!(cs.group, "columns");
    let v_slab = 0.15 * 1.9 * (100.0 * rho * 30.0f64).powf(1.0 / 3.0) * 1.0e4;
    assert!((cs.forces.shear_h_n - v_slab).abs() < 1e-6 * v_slab);
    // Every constraint frame pair coincides in the start pose.
    for c in &conns {
        for k in &c.constraints {
            let wa = poses[c.a] * k.frame_a;
            let wb = poses[c.b] * k.frame_b;
            assert!((wa.translation.vector - wb.translation.vector).norm() < 1e-12);
        }
    }
}

/// The joint rule (docs/handoff.md §2.7) on frame3's own joint geometry (1/4 scale): two
/// 0.25 m column pieces stacked at the floor (z = 1.0), a beam half centred on the floor
/// (0.15 m deep) and a slab quarter panel (30 mm) framing into their side, and a roof
/// joint with no piece above. BCB connects the beam and the panel to both pieces; with
/// `ColumnAbove` only to the upper one, and the roof joint keeps its beam.
#[test]
fn joints_attach_to_the_column_piece_above_the_floor() {
    let bodies = vec![
        cuboid("lower", "c", [-0.05, -0.05, 0.75], [0.05, 0.05, 1.0]),
        cuboid("upper", "c", [-0.05, -0.05, 1.0], [0.05, 0.05, 1.25]),
        cuboid("beam", "b", [0.05, -0.0375, 0.925], [0.75, 0.0375, 1.075]),
        cuboid("panel", "s", [0.0375, 0.05, 0.985], [0.75, 0.75, 1.015]),
        cuboid("roof column", "c", [2.95, -0.05, 0.75], [3.05, 0.05, 1.0]),
        cuboid(
            "roof beam",
            "b",
            [3.05, -0.0375, 0.925],
            [3.75, 0.0375, 1.075],
        ),
    ];
    let pairs = |joints| -> Vec<(String, String)> {
        let s = SearchSettings {
            joints,
            ..SearchSettings::default()
        };
        find_contacts(&bodies, &s)
            .unwrap()
            .iter()
            .map(|c| (bodies[c.a].name.clone(), bodies[c.b].name.clone()))
            .collect()
    };
    let names = |v: &[(&str, &str)]| -> Vec<(String, String)> {
        v.iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect()
    };
    assert_eq!(
        pairs(JointContacts::Faces),
        names(&[
            ("lower", "upper"),
            ("lower", "beam"),
            ("lower", "panel"),
            ("upper", "beam"),
            ("upper", "panel"),
            ("beam", "panel"),
            ("roof column", "roof beam"),
        ])
    );
    assert_eq!(
        pairs(JointContacts::ColumnAbove),
        names(&[
            ("lower", "upper"),
            ("upper", "beam"),
            ("upper", "panel"),
            ("beam", "panel"),
            ("roof column", "roof beam"),
        ])
    );
}
