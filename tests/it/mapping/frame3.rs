//! The frame3 stand-in (reference/opensees-frame3/README.md), built by hand from its
//! dimensions: 1.5 m square bay, three 1 m stories; 100×100 mm columns (vecxz X), split in
//! two elements per story; 75×150 mm beams (vecxz Z), split in two per span; a 30 mm slab
//! per floor as 2×2 quads; concrete 2500 kg/m³ self-weight on the elements; ballast
//! 2699.75 kg per floor on the nine floor nodes by tributary area (corner 1/16, edge 1/8,
//! centre 1/4). Checks box sizes and positions, overlap removal and mass mapping.
use fem2rbd::mapping::overlap::{max_pairwise_overlap, overlap_volume};
use fem2rbd::mapping::{
    groups, map_to_boxes, LineMember, MapOptions, MappingInput, PointMass, Quad, Role,
};

const L: f64 = 1.5;
const RHO: f64 = 2500.0;
const BALLAST: f64 = 2699.75;

fn frame3() -> MappingInput {
    let mut inp = MappingInput::default();
    let mut tag = 0;
    let corners = [(0.0, 0.0), (L, 0.0), (0.0, L), (L, L)];
    for s in 1..=3 {
        let z0 = (s - 1) as f64;
        for &(x, y) in &corners {
            for k in 0..2 {
                tag += 1;
                inp.members.push(LineMember {
                    element: tag,
                    body_type: "Column".into(),
                    material: s.to_string(),
                    node_i: [x, y, z0 + 0.5 * k as f64],
                    node_j: [x, y, z0 + 0.5 * (k + 1) as f64],
                    vecxz: [1.0, 0.0, 0.0],
                    width_m: 0.1,
                    depth_m: 0.1,
                    mass_kg: RHO * 0.1 * 0.1 * 0.5,
                });
            }
        }
    }
    for f in 1..=3 {
        let z = f as f64;
        // Edges: y = 0 and y = L along X; x = 0 and x = L along Y; corner → mid → corner.
        let edges = [
            ([0.0, 0.0], [L, 0.0]),
            ([0.0, L], [L, L]),
            ([0.0, 0.0], [0.0, L]),
            ([L, 0.0], [L, L]),
        ];
        for (a, b) in edges {
            let m = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
            for (p, q) in [(a, m), (m, b)] {
                tag += 1;
                inp.members.push(LineMember {
                    element: tag,
                    body_type: "Beam".into(),
                    material: f.to_string(),
                    node_i: [p[0], p[1], z],
                    node_j: [q[0], q[1], z],
                    vecxz: [0.0, 0.0, 1.0],
                    width_m: 0.075,
                    depth_m: 0.15,
                    mass_kg: RHO * 0.075 * 0.15 * 0.75,
                });
            }
        }
    }
    for f in 1..=3 {
        let z = f as f64;
        for (i, j) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            let (x0, y0) = (0.75 * i as f64, 0.75 * j as f64);
            tag += 1;
            inp.quads.push(Quad {
                element: 1000 + tag,
                body_type: "Slab".into(),
                material: f.to_string(),
                nodes: [
                    [x0, y0, z],
                    [x0 + 0.75, y0, z],
                    [x0 + 0.75, y0 + 0.75, z],
                    [x0, y0 + 0.75, z],
                ],
                thickness_m: 0.03,
                mass_kg: RHO * 0.03 * 0.75 * 0.75,
            });
        }
        for i in 0..3 {
            for j in 0..3 {
                let w = [0.25, 0.5, 0.25][i] * [0.25, 0.5, 0.25][j];
                inp.nodal_masses.push(PointMass {
                    position: [0.75 * i as f64, 0.75 * j as f64, z],
                    mass_kg: BALLAST * w,
                });
            }
        }
    }
    inp
}

fn fe_total(inp: &MappingInput) -> f64 {
    inp.members.iter().map(|m| m.mass_kg).sum::<f64>()
        + inp.quads.iter().map(|q| q.mass_kg).sum::<f64>()
        + inp.nodal_masses.iter().map(|m| m.mass_kg).sum::<f64>()
}

#[test]
fn untrimmed_boxes_names_and_groups() {
    let inp = frame3();
    let m = map_to_boxes(
        &inp,
        &MapOptions {
            remove_overlaps: false,
            ..Default::default()
        },
    )
    .unwrap();
    let b = &m.bodies;
    assert_eq!(b.len(), 24 + 24 + 12);
    assert_eq!(b[0].id.name(), "Column:1:1");
    assert_eq!(b[24].id.name(), "Beam:1:25");
    assert_eq!(b[48].id.name(), "Slab:1:1049");
    assert_eq!(b[59].id.name(), "Slab:3:1060");
    let g = groups(b);
    assert_eq!(g.keys().collect::<Vec<_>>(), ["1", "2", "3"]);
    for (mat, idx) in &g {
        assert_eq!(idx.len(), 8 + 8 + 4, "group {mat}");
        assert!(idx
            .iter()
            .all(|&i| b[i].id.material() == *mat && b[i].id.name().contains(mat)));
    }
    // Column 1: base (0, 0, 0) → (0, 0, 0.5).
    assert_eq!(b[0].kind, Role::Column);
    assert_eq!(b[0].centre, [0.0, 0.0, 0.25]);
    assert_eq!(b[0].half_extents, [0.25, 0.05, 0.05]);
    // Beam 25: (0, 0, 1) → (0.75, 0, 1), depth vertical.
    assert_eq!(b[24].kind, Role::Beam);
    assert_eq!(b[24].centre, [0.375, 0.0, 1.0]);
    assert_eq!(b[24].half_extents, [0.375, 0.0375, 0.075]);
    assert!((b[24].matrix()[2][2] - 1.0).abs() < 1e-15);
    // Slab 1049: (0..0.75)² at z = 1.
    assert_eq!(b[48].kind, Role::Slab);
    assert_eq!(b[48].centre, [0.375, 0.375, 1.0]);
    assert_eq!(b[48].half_extents, [0.375, 0.375, 0.015]);
    // Before trimming, a beam end sits inside the column: 0.05 × 0.075 × 0.075 m³ with the
    // lower column half of the joint (the column element ends at the floor node).
    let v = overlap_volume(&b[1], &b[24]);
    assert!((v - 0.05 * 0.075 * 0.075).abs() < 1e-15, "{v}");
    let (worst, _) = max_pairwise_overlap(b);
    eprintln!("largest overlap before trimming: {worst:.3e} m³");
    assert!(worst > 1e-4);
}

#[test]
fn overlap_removal_on_frame3() {
    let inp = frame3();
    let m = map_to_boxes(&inp, &MapOptions::default()).unwrap();
    let b = &m.bodies;
    let (worst, pair) = max_pairwise_overlap(b);
    eprintln!(
        "after trimming: largest overlap {worst:.3e} m³ ({:?}); {} cuts on {} bodies, {:.6} m³ removed",
        pair.map(|(i, j)| (b[i].id.name(), b[j].id.name())),
        m.trim.cuts,
        m.trim.trimmed_boxes,
        m.trim.removed_volume_m3
    );
    assert!(worst <= 1e-9, "{worst}");
    // Columns run through the joints: untouched.
    for c in b.iter().filter(|b| b.kind == Role::Column) {
        assert_eq!(c.centre, c.untrimmed_centre, "{}", c.id.name());
        assert_eq!(c.half_extents, c.untrimmed_half_extents, "{}", c.id.name());
    }
    // Beams stop at the column faces: every beam element loses 0.05 m at its corner end,
    // keeps its section, and is 0.70 m long.
    for be in b.iter().filter(|b| b.kind == Role::Beam) {
        assert!(
            (2.0 * be.half_extents[0] - 0.70).abs() < 1e-12,
            "{}",
            be.id.name()
        );
        assert_eq!(be.half_extents[1..], [0.0375, 0.075]);
        // Its centre moved 0.025 m away from the corner, towards the mid-span node.
        let shift: f64 = (0..3)
            .map(|k| (be.centre[k] - be.untrimmed_centre[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!((shift - 0.025).abs() < 1e-12, "{}", be.id.name());
        let mid_dist = |c: [f64; 3]| ((c[0] - 0.75).abs()).min((c[1] - 0.75).abs());
        assert!(mid_dist(be.centre) < mid_dist(be.untrimmed_centre));
    }
    // Beam 25 runs from the corner (0, 0, 1) to mid-span: cut at its node-i end, so its
    // centre moved +0.025 m along its own axis.
    let b25 = b.iter().find(|x| x.id.name() == "Beam:1:25").unwrap();
    let off = b25.trim_offset_local();
    assert!((off[0] - 0.025).abs() < 1e-12 && off[1].abs() < 1e-12 && off[2].abs() < 1e-12);
    // Slabs: reduced to the clear area inside the beams' faces (0.0375 m strip along each
    // edge on a beam line), plus the column corner: one in-plane side is cut back to the
    // column face (0.05 m) instead. Each quad keeps 0.7125 × 0.70 × 0.03 m.
    for s in b.iter().filter(|b| b.kind == Role::Slab) {
        let mut h = [2.0 * s.half_extents[0], 2.0 * s.half_extents[1]];
        h.sort_by(f64::total_cmp);
        assert!(
            (h[0] - 0.70).abs() < 1e-12 && (h[1] - 0.7125).abs() < 1e-12,
            "{}: {h:?}",
            s.id.name()
        );
        assert_eq!(s.half_extents[2], 0.015);
        assert!((s.volume_m3() - 0.7125 * 0.70 * 0.03).abs() < 1e-15);
        // The sides on the interior lines (x = 0.75 or y = 0.75) are not cut.
        let lo = [
            s.centre[0] - s.half_extents[0],
            s.centre[1] - s.half_extents[1],
        ];
        let hi = [
            s.centre[0] + s.half_extents[0],
            s.centre[1] + s.half_extents[1],
        ];
        for k in 0..2 {
            let interior = if s.untrimmed_centre[k] < 0.75 {
                hi[k]
            } else {
                lo[k]
            };
            assert!((interior - 0.75).abs() < 1e-12, "{}", s.id.name());
        }
    }
    // Removed volume: 24 beams × 0.05 × 0.075 × 0.15 + 12 slabs × (0.5625 − 0.49875) × 0.03.
    let expect = 24.0 * 0.05 * 0.075 * 0.15 + 12.0 * (0.5625 - 0.7125 * 0.70) * 0.03;
    assert!((m.trim.removed_volume_m3 - expect).abs() < 1e-12);
    assert_eq!(m.trim.trimmed_boxes, 24 + 12);
    // Same input, same result.
    assert_eq!(map_to_boxes(&inp, &MapOptions::default()).unwrap(), m);
}

#[test]
fn mass_mapping_on_frame3() {
    let inp = frame3();
    let m = map_to_boxes(&inp, &MapOptions::default()).unwrap();
    let b = &m.bodies;
    let total: f64 = b.iter().map(|b| b.mass_kg).sum();
    let fe = fe_total(&inp);
    eprintln!("FE mass {fe} kg, rigid bodies {total} kg");
    assert!(((total - fe) / fe).abs() < 1e-9);
    // 24 × 12.5 + 24 × 21.09375 + 12 × 42.1875 + 3 × 2699.75.
    assert!((fe - (300.0 + 506.25 + 506.25 + 8099.25)).abs() < 1e-9);
    // Per-body: columns and beams keep their self-weight (the ballast goes to the slabs,
    // preferred at every floor node); each slab quad gets 1/4 of its floor's ballast:
    // corner 1/16 + two edge halves 2 × 1/16 + a quarter of the centre 1/16.
    for x in b {
        let expect = match x.kind {
            Role::Column => 12.5,
            Role::Beam => RHO * 0.075 * 0.15 * 0.75,
            Role::Slab => RHO * 0.03 * 0.5625 + BALLAST / 4.0,
            Role::Wall => unreachable!(),
        };
        assert!(
            (x.mass_kg - expect).abs() < 1e-9,
            "{}: {}",
            x.id.name(),
            x.mass_kg
        );
    }
    // Per floor (slabs + beams of that floor, z = 1, 2, 3) the centre of mass stays at the
    // plan centre (0.75, 0.75) within 1 mm despite the asymmetric corner cuts.
    for f in 1..=3 {
        let z = f as f64;
        let on_floor: Vec<_> = b
            .iter()
            .filter(|x| x.kind != Role::Column && (x.centre[2] - z).abs() < 1e-9)
            .collect();
        let mass: f64 = on_floor.iter().map(|x| x.mass_kg).sum();
        let cx = on_floor
            .iter()
            .map(|x| x.mass_kg * x.centre[0])
            .sum::<f64>()
            / mass;
        let cy = on_floor
            .iter()
            .map(|x| x.mass_kg * x.centre[1])
            .sum::<f64>()
            / mass;
        eprintln!("floor {f}: mass {mass:.4} kg, centre ({cx:.6}, {cy:.6})");
        assert!((cx - 0.75).abs() < 1e-3 && (cy - 0.75).abs() < 1e-3);
    }
    // The rule's preference: without slabs, floor ballast goes to the beams at the node
    // (corner: the two beam elements meeting there; mid-edge: the two halves), and the
    // centre node's ballast has no element: an error naming it.
    let mut no_slab = inp.clone();
    no_slab.quads.clear();
    let e = map_to_boxes(&no_slab, &MapOptions::default()).unwrap_err();
    assert_eq!(
        e.to_string(),
        "nodal mass 4 of 674.9375 kg at (0.75, 0.75, 1) is at no element node"
    );
    no_slab
        .nodal_masses
        .retain(|n| n.position[0] != 0.75 || n.position[1] != 0.75);
    let m2 = map_to_boxes(&no_slab, &MapOptions::default()).unwrap();
    let beam = m2
        .bodies
        .iter()
        .find(|x| x.id.name() == "Beam:1:25")
        .unwrap();
    // Node (0,0,1): corner ballast 1/16 shared by beams 25 and 29; node (0.75,0,1): edge
    // ballast 1/8 shared by beams 25 and 26.
    let expect = RHO * 0.075 * 0.15 * 0.75 + BALLAST / 32.0 + BALLAST / 16.0;
    assert!((beam.mass_kg - expect).abs() < 1e-9, "{}", beam.mass_kg);
    let col = m2
        .bodies
        .iter()
        .find(|x| x.id.name() == "Column:1:2")
        .unwrap();
    assert_eq!(col.mass_kg, 12.5);
}

#[test]
fn body_table() {
    use fem2rbd::mapping::table::{bodies_csv, HEADER};
    let m = map_to_boxes(&frame3(), &MapOptions::default()).unwrap();
    let csv = bodies_csv(&m.bodies);
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 61);
    assert_eq!(lines[0], HEADER);
    assert!(
        lines[1].starts_with("Column:1:1,1,Column,1,1,Column,0,0,0.25,"),
        "{}",
        lines[1]
    );
    // Every row parses back to the body's numbers; the quaternion is a unit one.
    for (line, b) in lines[1..].iter().zip(&m.bodies) {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(f.len(), 20);
        assert_eq!(f[0], b.id.name().as_str());
        let x: Vec<f64> = f[6..].iter().map(|s| s.parse().unwrap()).collect();
        assert_eq!(x[..3], b.centre);
        assert!((x[3..7].iter().map(|q| q * q).sum::<f64>() - 1.0).abs() < 1e-15);
        assert_eq!(x[7..10], b.half_extents);
        assert_eq!(x[10], b.mass_kg);
    }
    assert_eq!(bodies_csv(&m.bodies), csv);
}

#[test]
fn bad_nodal_mass_is_named() {
    let mut inp = frame3();
    inp.nodal_masses[2].mass_kg = f64::NAN;
    assert_eq!(
        map_to_boxes(&inp, &MapOptions::default())
            .unwrap_err()
            .to_string(),
        "nodal mass 2 at (0, 1.5, 1): mass must be finite and ≥ 0 kg, got NaN"
    );
    let mut inp = frame3();
    inp.nodal_masses[0].position = [0.3, 0.0, 1.0];
    assert_eq!(
        map_to_boxes(&inp, &MapOptions::default())
            .unwrap_err()
            .to_string(),
        "nodal mass 0 of 168.734375 kg at (0.3, 0, 1) is at no element node"
    );
}
