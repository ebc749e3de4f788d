//! Overlap removal beyond the regular frame: inclined braces through joints, random
//! inclined members meeting at a node, and a body that would vanish.
use fem2rbd::mapping::overlap::max_pairwise_overlap;
use fem2rbd::mapping::{
    map_to_boxes, LineMember, MapOptions, MappingError, MappingInput, Quad, Role,
};

fn member(el: u32, ty: &str, i: [f64; 3], j: [f64; 3], v: [f64; 3], w: f64, d: f64) -> LineMember {
    LineMember {
        element: el,
        body_type: ty.into(),
        material: "1".into(),
        node_i: i,
        node_j: j,
        vecxz: v,
        width_m: w,
        depth_m: d,
        mass_kg: 10.0,
    }
}

/// One story, one bay, two columns, a beam, and a diagonal brace from the foot of one
/// column to the top of the other.
#[test]
fn brace_through_two_joints() {
    let col = |el, x: f64| {
        member(
            el,
            "Column",
            [x, 0.0, 0.0],
            [x, 0.0, 1.0],
            [1.0, 0.0, 0.0],
            0.1,
            0.1,
        )
    };
    let inp = MappingInput {
        members: vec![
            col(1, 0.0),
            col(2, 1.5),
            member(
                3,
                "Beam",
                [0.0, 0.0, 1.0],
                [1.5, 0.0, 1.0],
                [0.0, 0.0, 1.0],
                0.075,
                0.15,
            ),
            member(
                4,
                "Brace",
                [0.0, 0.0, 0.0],
                [1.5, 0.0, 1.0],
                [0.0, 1.0, 0.0],
                0.06,
                0.06,
            ),
        ],
        ..Default::default()
    };
    let before = map_to_boxes(
        &inp,
        &MapOptions {
            remove_overlaps: false,
            ..Default::default()
        },
    )
    .unwrap();
    let (v0, _) = max_pairwise_overlap(&before.bodies);
    let m = map_to_boxes(&inp, &MapOptions::default()).unwrap();
    let (v1, pair) = max_pairwise_overlap(&m.bodies);
    let brace = &m.bodies[3];
    eprintln!(
        "brace: overlap before {v0:.3e} m³, after {v1:.3e} m³ ({pair:?}); length {:.4} → {:.4} m",
        2.0 * brace.untrimmed_half_extents[0],
        2.0 * brace.half_extents[0]
    );
    assert!(v0 > 1e-5);
    assert!(v1 <= 1e-9);
    assert_eq!(brace.kind, Role::Beam);
    // The brace keeps its section and is shortened only along its axis, by at least the
    // part inside the two column halves (0.05 m horizontally each → 0.05/cos θ).
    assert_eq!(brace.half_extents[1..], brace.untrimmed_half_extents[1..]);
    let len0 = 2.0 * brace.untrimmed_half_extents[0];
    let cos = 1.5 / len0;
    assert!(2.0 * brace.half_extents[0] < len0 - 2.0 * 0.05 / cos + 1e-12);
    assert!(2.0 * brace.half_extents[0] > 0.7 * len0);
    // Columns untouched.
    for c in &m.bodies[..2] {
        assert_eq!(c.half_extents, c.untrimmed_half_extents);
    }
}

/// Random inclined members meeting at one node, and a slab around it: after trimming no
/// pair overlaps by more than the tolerance, whatever the tolerance.
#[test]
fn random_members_at_a_joint() {
    let mut s: u64 = 12345;
    let mut rnd = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut ok, mut vanished, mut cuts) = (0, 0, 0);
    for trial in 0..20 {
        let node = [1.0, 1.0, 1.0];
        let mut members = Vec::new();
        for k in 0..5 {
            let th = rnd() * std::f64::consts::TAU;
            let ph = (rnd() - 0.5) * 2.8;
            let len = 0.6 + rnd();
            let far = [
                node[0] + len * ph.cos() * th.cos(),
                node[1] + len * ph.cos() * th.sin(),
                node[2] + len * ph.sin(),
            ];
            let v = [rnd() - 0.5, rnd() - 0.5, rnd() - 0.5];
            members.push(member(
                k + 1,
                "M",
                node,
                far,
                v,
                0.05 + 0.1 * rnd(),
                0.05 + 0.1 * rnd(),
            ));
        }
        let quads = vec![Quad {
            element: 99,
            body_type: "Slab".into(),
            material: "1".into(),
            nodes: [
                [0.4, 0.4, 1.0],
                [1.6, 0.4, 1.0],
                [1.6, 1.6, 1.0],
                [0.4, 1.6, 1.0],
            ],
            thickness_m: 0.04,
            mass_kg: 50.0,
        }];
        let inp = MappingInput {
            members,
            quads,
            ..Default::default()
        };
        for tol in [1e-9, 1e-6, 1e-4] {
            let m = match map_to_boxes(
                &inp,
                &MapOptions {
                    remove_overlaps: true,
                    overlap_tolerance_m3: tol,
                },
            ) {
                Ok(m) => m,
                // A member lying inside another is a legitimate error; it must name both.
                Err(e) => {
                    assert!(matches!(e, MappingError::Vanishes { .. }), "{e}");
                    vanished += 1;
                    continue;
                }
            };
            ok += 1;
            cuts += m.trim.cuts;
            let (v, _) = max_pairwise_overlap(&m.bodies);
            assert!(
                v <= tol * (1.0 + 1e-9) + 1e-15,
                "trial {trial} tol {tol}: {v}"
            );
            // Trimming only shrinks, along one axis at a time.
            for b in &m.bodies {
                for k in 0..3 {
                    assert!(b.half_extents[k] <= b.untrimmed_half_extents[k] + 1e-15);
                    assert!(b.half_extents[k] > 0.0);
                }
            }
        }
    }
    eprintln!(
        "random joints: {ok} trimmed ({cuts} cuts), {vanished} refused (a member inside another)"
    );
    assert!(ok >= 40 && cuts >= 100, "{ok} {cuts}");
}

#[test]
fn a_body_inside_another_is_an_error() {
    let inp = MappingInput {
        members: vec![member(
            1,
            "Column",
            [0.0; 3],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 0.0],
            0.4,
            0.4,
        )],
        quads: vec![Quad {
            element: 7,
            body_type: "Slab".into(),
            material: "2".into(),
            nodes: [
                [-0.1, -0.1, 0.5],
                [0.1, -0.1, 0.5],
                [0.1, 0.1, 0.5],
                [-0.1, 0.1, 0.5],
            ],
            thickness_m: 0.03,
            mass_kg: 1.0,
        }],
        ..Default::default()
    };
    let e = map_to_boxes(&inp, &MapOptions::default()).unwrap_err();
    assert_eq!(
        e.to_string(),
        "overlap removal: body Slab:2:7 lies within body Column:1:1; it would vanish (fix the \
         model's geometry)"
    );
    // Duplicate names are refused too.
    let dup = MappingInput {
        members: vec![
            member(
                5,
                "Beam",
                [0.0; 3],
                [1.0, 0.0, 0.0],
                [0.0, 0.0, 1.0],
                0.1,
                0.1,
            ),
            member(
                5,
                "Beam",
                [0.0, 2.0, 0.0],
                [1.0, 2.0, 0.0],
                [0.0, 0.0, 1.0],
                0.1,
                0.1,
            ),
        ],
        ..Default::default()
    };
    assert_eq!(
        map_to_boxes(&dup, &MapOptions::default())
            .unwrap_err()
            .to_string(),
        "two elements map to the same body name Beam:1:5"
    );
}

/// A regular 5 × 5-bay, 7-story frame (3 m spans, 3 m stories; 300 × 300 mm columns,
/// 200 × 400 mm beams, 100 mm slab as 2 × 2 quads per bay; members split in two): 2044
/// bodies. Every beam element stops at its column face, every slab quad keeps the clear
/// area with one column-corner strip, no pair overlaps, and the mass is conserved.
#[test]
fn seven_story_frame_scales() {
    let (nb, ns, span, h) = (5usize, 7usize, 3.0, 3.0);
    let mut inp = MappingInput::default();
    let mut tag = 0;
    let mut next = || {
        tag += 1;
        tag
    };
    for s in 0..ns {
        for i in 0..=nb {
            for j in 0..=nb {
                let (x, y, z) = (i as f64 * span, j as f64 * span, s as f64 * h);
                for k in 0..2 {
                    let mut m = member(
                        next(),
                        "Column",
                        [x, y, z + 0.5 * h * k as f64],
                        [x, y, z + 0.5 * h * (k + 1) as f64],
                        [1.0, 0.0, 0.0],
                        0.3,
                        0.3,
                    );
                    m.mass_kg = 2500.0 * 0.09 * 1.5;
                    inp.members.push(m);
                }
            }
        }
        let z = (s + 1) as f64 * h;
        for line in 0..=nb {
            for bay in 0..nb {
                for k in 0..2 {
                    let a = bay as f64 * span + 0.5 * span * k as f64;
                    let b = a + 0.5 * span;
                    let c = line as f64 * span;
                    for (p, q) in [([a, c, z], [b, c, z]), ([c, a, z], [c, b, z])] {
                        let mut m = member(next(), "Beam", p, q, [0.0, 0.0, 1.0], 0.2, 0.4);
                        m.mass_kg = 2500.0 * 0.08 * 1.5;
                        inp.members.push(m);
                    }
                }
            }
        }
        for i in 0..2 * nb {
            for j in 0..2 * nb {
                let (x0, y0) = (i as f64 * 0.5 * span, j as f64 * 0.5 * span);
                let d = 0.5 * span;
                inp.quads.push(Quad {
                    element: next(),
                    body_type: "Slab".into(),
                    material: "1".into(),
                    nodes: [
                        [x0, y0, z],
                        [x0 + d, y0, z],
                        [x0 + d, y0 + d, z],
                        [x0, y0 + d, z],
                    ],
                    thickness_m: 0.1,
                    mass_kg: 2500.0 * 0.1 * d * d,
                });
                inp.nodal_masses.push(fem2rbd::mapping::PointMass {
                    position: [x0, y0, z],
                    mass_kg: 500.0,
                });
            }
        }
    }
    let n = inp.members.len() + inp.quads.len();
    assert_eq!(n, 2044);
    let m = map_to_boxes(&inp, &MapOptions::default()).unwrap();
    let (v, pair) = max_pairwise_overlap(&m.bodies);
    assert!(v <= 1e-9, "{v} {pair:?}");
    for b in &m.bodies {
        match b.kind {
            Role::Column => assert_eq!(b.half_extents, b.untrimmed_half_extents),
            Role::Beam => assert!(
                (2.0 * b.half_extents[0] - 1.35).abs() < 1e-12,
                "{}",
                b.id.name()
            ),
            Role::Slab => {
                let mut s = [2.0 * b.half_extents[0], 2.0 * b.half_extents[1]];
                s.sort_by(f64::total_cmp);
                assert!(
                    (s[0] - 1.35).abs() < 1e-12 && (s[1] - 1.4).abs() < 1e-12,
                    "{}: {s:?}",
                    b.id.name()
                );
            }
            Role::Wall => unreachable!(),
        }
    }
    let fe: f64 = inp.members.iter().map(|m| m.mass_kg).sum::<f64>()
        + inp.quads.iter().map(|q| q.mass_kg).sum::<f64>()
        + inp.nodal_masses.iter().map(|m| m.mass_kg).sum::<f64>();
    let rb: f64 = m.bodies.iter().map(|b| b.mass_kg).sum();
    assert!(((rb - fe) / fe).abs() < 1e-9);
    eprintln!(
        "7-story frame: {n} bodies, {} cuts, FE mass {fe} kg",
        m.trim.cuts
    );
}
