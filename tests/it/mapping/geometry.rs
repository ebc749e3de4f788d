//! Geometry mapping: the paper's α/β rotation plus the vecxz roll equals the OpenSees local
//! frame; quads; exact box overlap volumes; bad input.
use fem2rbd::mapping::geometry::{
    member_box, opensees_frame, paper_angles, paper_rotation, quad_box,
};
use fem2rbd::mapping::overlap::overlap_volume;
use fem2rbd::mapping::{LineMember, Quad, RigidBox, Role};
use nalgebra::{UnitQuaternion, Vector3};

/// xorshift64*: a small deterministic generator for test inputs.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545F4914F6CDD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
    fn vec(&mut self, s: f64) -> [f64; 3] {
        [self.range(-s, s), self.range(-s, s), self.range(-s, s)]
    }
}

fn member(el: u32, i: [f64; 3], j: [f64; 3], vecxz: [f64; 3]) -> LineMember {
    LineMember {
        element: el,
        body_type: "Beam".into(),
        material: "1".into(),
        node_i: i,
        node_j: j,
        vecxz,
        width_m: 0.075,
        depth_m: 0.15,
        mass_kg: 21.09375,
    }
}

fn max_diff(q: &UnitQuaternion<f64>, i: [f64; 3], j: [f64; 3], v: [f64; 3]) -> f64 {
    let r = q.to_rotation_matrix().into_inner();
    let f = opensees_frame(i, j, v).unwrap();
    (r - f).abs().max()
}

#[test]
fn paper_rotation_equals_the_opensees_frame_for_random_inclined_members() {
    let mut rng = Rng(0x9E3779B97F4A7C15);
    let mut worst: f64 = 0.0;
    for _ in 0..2000 {
        let i = rng.vec(10.0);
        let j = rng.vec(10.0);
        let v = rng.vec(1.0);
        let q = paper_rotation(i, j, v).unwrap();
        worst = worst.max(max_diff(&q, i, j, v));
        // The paper's two angles alone already put the box x axis on the member.
        let d = Vector3::from(j) - Vector3::from(i);
        let (a, b) = paper_angles([d.x, d.y, d.z]);
        assert!((a - d.y.atan2(d.x)).abs() < 1e-15);
        assert!((b - (d.z / d.norm()).asin()).abs() < 1e-12);
        let r0 = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), a)
            * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -b);
        assert!((r0 * Vector3::x() - d.normalize()).norm() < 1e-12);
    }
    eprintln!("largest |R_paper − R_OpenSees| entry: {worst:.2e}");
    assert!(worst < 1e-12, "{worst}");
}

#[test]
fn vertical_members_are_handled() {
    let mut rng = Rng(42);
    for k in 0..200 {
        let base = rng.vec(5.0);
        let h = rng.range(0.2, 4.0) * if k % 2 == 0 { 1.0 } else { -1.0 };
        let top = [base[0], base[1], base[2] + h];
        let mut v = rng.vec(1.0);
        v[2] = 0.0; // a horizontal vecxz, as for columns
        if k % 3 == 0 {
            v[2] = 0.7; // and some inclined ones
        }
        let q = paper_rotation(base, top, v).unwrap();
        assert!(max_diff(&q, base, top, v) < 1e-12);
        let (a, b) = paper_angles([0.0, 0.0, h]);
        assert_eq!(a, 0.0);
        assert!((b.abs() - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    }
    // The frame3 column: vecxz = (1, 0, 0) → local y = (0, 1, 0), local z = (−1, 0, 0)...
    // by OpenSees y = vecxz × x = (1,0,0) × (0,0,1) = (0,−1,0), z = x × y = (1,0,0).
    let q = paper_rotation([0.0, 0.0, 0.0], [0.0, 0.0, 0.5], [1.0, 0.0, 0.0]).unwrap();
    let m = q.to_rotation_matrix().into_inner();
    assert!((m.column(0) - Vector3::new(0.0, 0.0, 1.0)).norm() < 1e-15);
    assert!((m.column(1) - Vector3::new(0.0, -1.0, 0.0)).norm() < 1e-15);
    assert!((m.column(2) - Vector3::new(1.0, 0.0, 0.0)).norm() < 1e-15);
}

#[test]
fn member_box_name_size_and_position() {
    let m = LineMember {
        element: 234,
        ..member(0, [0.0, 0.75, 1.0], [0.0, 1.5, 1.0], [0.0, 0.0, 1.0])
    };
    let b = member_box(&m).unwrap();
    assert_eq!(b.id.name(), "Beam:1:234");
    assert_eq!(b.id.group(), "1");
    assert_eq!(b.kind, Role::Beam);
    assert_eq!(b.half_extents, [0.375, 0.0375, 0.075]);
    assert_eq!(b.centre, [0.0, 1.125, 1.0]);
    assert_eq!(b.mass_kg, 21.09375);
    // Beam along +Y with vecxz Z: y = Z × Y = −X, z = x × y = +Z (depth vertical).
    let r = b.matrix();
    assert!((r[0][1] + 1.0).abs() < 1e-15 && (r[2][2] - 1.0).abs() < 1e-15);
    let q = b.quaternion_wxyz();
    assert!((q.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-15);
    // Uniform box inertia: I_x = m(b² + c²)/3 with half sizes.
    let i = b.principal_inertia_kgm2();
    assert!((i[0] - 21.09375 * (0.0375f64.powi(2) + 0.075f64.powi(2)) / 3.0).abs() < 1e-15);
    // Inclined: a 45° brace is a beam; a 60° one is a column.
    let brace = member_box(&member(7, [0.0; 3], [1.0, 1.0, 1.0], [0.0, 0.0, 1.0])).unwrap();
    assert_eq!(brace.kind, Role::Beam);
    let steep = member_box(&member(8, [0.0; 3], [0.0, 1.0, 1.8], [1.0, 0.0, 0.0])).unwrap();
    assert_eq!(steep.kind, Role::Column);
}

fn quad(nodes: [[f64; 3]; 4]) -> Quad {
    Quad {
        element: 501,
        body_type: "Slab".into(),
        material: "2".into(),
        nodes,
        thickness_m: 0.03,
        mass_kg: 42.1875,
    }
}

#[test]
fn quad_boxes() {
    // Rectangle 0.75 × 0.5 at z = 2, either winding.
    for nodes in [
        [
            [0.0, 0.0, 2.0],
            [0.75, 0.0, 2.0],
            [0.75, 0.5, 2.0],
            [0.0, 0.5, 2.0],
        ],
        [
            [0.0, 0.0, 2.0],
            [0.0, 0.5, 2.0],
            [0.75, 0.5, 2.0],
            [0.75, 0.0, 2.0],
        ],
    ] {
        let b = quad_box(&quad(nodes)).unwrap();
        assert_eq!(b.id.name(), "Slab:2:501");
        assert_eq!(b.kind, Role::Slab);
        assert_eq!(b.centre, [0.375, 0.25, 2.0]);
        let mut h = b.half_extents;
        h[..2].sort_by(f64::total_cmp);
        assert!((h[0] - 0.25).abs() < 1e-15 && (h[1] - 0.375).abs() < 1e-15);
        assert_eq!(h[2], 0.015);
        assert!((b.matrix()[2][2].abs() - 1.0).abs() < 1e-15);
    }
    // A vertical wall panel in the XZ plane is a wall.
    let w = quad_box(&quad([
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 0.0, 3.0],
        [0.0, 0.0, 3.0],
    ]))
    .unwrap();
    assert_eq!(w.kind, Role::Wall);
    assert!((w.volume_m3() - 2.0 * 3.0 * 0.03).abs() < 1e-15);
    // Parallelogram (base 1, height 0.6, shear 0.3) and trapezoid (bases 1, 0.5, height
    // 0.4): the box keeps the quad's area.
    let p = quad_box(&quad([
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.3, 0.6, 0.0],
        [0.3, 0.6, 0.0],
    ]))
    .unwrap();
    assert!((4.0 * p.half_extents[0] * p.half_extents[1] - 0.6).abs() < 1e-14);
    let t = quad_box(&quad([
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.75, 0.4, 0.0],
        [0.25, 0.4, 0.0],
    ]))
    .unwrap();
    assert!((4.0 * t.half_extents[0] * t.half_extents[1] - 0.3).abs() < 1e-14);
    // Inclined roof panel: sizes along its own plane.
    let s = 0.5f64.sqrt();
    let r = quad_box(&quad([
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, s, s],
        [0.0, s, s],
    ]))
    .unwrap();
    assert!((r.half_extents[0] - 0.5).abs() < 1e-15 && (r.half_extents[1] - 0.5).abs() < 1e-15);
}

#[test]
fn bad_elements_are_named() {
    let err = |m: LineMember| format!("{:#}", member_box(&m).unwrap_err());
    assert_eq!(
        err(member(12, [1.0; 3], [1.0; 3], [0.0, 0.0, 1.0])),
        "element 12 (Beam): zero-length element"
    );
    assert_eq!(
        err(member(13, [0.0; 3], [0.0, 0.0, 1.0], [0.0, 0.0, 2.0])),
        "element 13 (Beam): vecxz [0.0, 0.0, 2.0] is parallel to the element axis"
    );
    assert_eq!(
        err(LineMember {
            width_m: 0.0,
            ..member(14, [0.0; 3], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0])
        }),
        "element 14 (Beam): section width and depth must be positive, got 0 × 0.15 m"
    );
    assert_eq!(
        err(member(
            15,
            [f64::NAN, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0]
        )),
        "element 15 (Beam): node coordinates and vecxz must be finite"
    );
    let qerr = |q: Quad| format!("{:#}", quad_box(&q).unwrap_err());
    assert_eq!(
        qerr(quad([
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [3.0, 0.0, 0.0]
        ])),
        "element 501 (Slab): degenerate quadrilateral (zero area)"
    );
    // A bow-tie (nodes 1 and 2 swapped).
    assert_eq!(
        qerr(quad([
            [0.0; 3],
            [1.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.5, 0.0]
        ])),
        "element 501 (Slab): nodes are not in cyclic order around a convex quad (corner 1)"
    );
    assert_eq!(
        qerr(Quad {
            thickness_m: -0.03,
            ..quad([[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]])
        }),
        "element 501 (Slab): thickness must be positive, got -0.03 m"
    );
}

fn cube(c: [f64; 3], half: [f64; 3], q: UnitQuaternion<f64>) -> RigidBox {
    let mut b = member_box(&member(1, [0.0; 3], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0])).unwrap();
    b.centre = c;
    b.half_extents = half;
    b.rotation = q;
    b
}

#[test]
fn exact_overlap_volumes() {
    let id = UnitQuaternion::identity();
    // Axis-aligned: overlap 0.3 × 0.5 × 1 of two unit cubes shifted by (0.7, 0.5, 0).
    let a = cube([0.0; 3], [0.5; 3], id);
    let b = cube([0.7, 0.5, 0.0], [0.5; 3], id);
    let v = overlap_volume(&a, &b);
    assert!((v - 0.15).abs() < 1e-14, "{v}");
    // Face contact and separation: zero.
    assert!(overlap_volume(&a, &cube([1.0, 0.0, 0.0], [0.5; 3], id)).abs() < 1e-15);
    assert_eq!(
        overlap_volume(&a, &cube([1.5, 0.0, 0.0], [0.5; 3], id)),
        0.0
    );
    // A unit cube and itself turned 45° about z: a regular octagon prism of area
    // 2(√2 − 1) = 0.828427.
    let r45 = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_4);
    let v = overlap_volume(&a, &cube([0.0; 3], [0.5; 3], r45));
    assert!((v - 2.0 * (2f64.sqrt() - 1.0)).abs() < 1e-13, "{v}");
    // Contained box: its own volume, whatever the orientation.
    let q = UnitQuaternion::from_euler_angles(0.3, -0.7, 1.1);
    let small = cube([0.05, -0.02, 0.01], [0.1, 0.05, 0.2], q);
    assert!((overlap_volume(&a, &small) - 0.008).abs() < 1e-15);
    assert!((overlap_volume(&small, &a) - 0.008).abs() < 1e-15);
    // Half-space check: a big box rotated about x cutting the unit cube along a diagonal
    // plane y + z ≥ 0 keeps exactly half the cube.
    let rx = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_4);
    let s = 0.5f64.sqrt();
    let half_space = cube([0.0, 5.0 * s, 5.0 * s], [10.0, 5.0, 10.0], rx); // local y = (0, s, s)
    assert!((overlap_volume(&half_space, &a) - 0.5).abs() < 1e-12);
}

/// The exact overlap against a Monte Carlo estimate for random oriented box pairs.
#[test]
fn overlap_volume_matches_monte_carlo() {
    let mut rng = Rng(7);
    let mut checked = 0;
    for _ in 0..40 {
        let qa = UnitQuaternion::from_euler_angles(
            rng.range(-3.0, 3.0),
            rng.range(-3.0, 3.0),
            rng.range(-3.0, 3.0),
        );
        let qb = UnitQuaternion::from_euler_angles(
            rng.range(-3.0, 3.0),
            rng.range(-3.0, 3.0),
            rng.range(-3.0, 3.0),
        );
        let a = cube(
            rng.vec(0.3),
            [
                rng.range(0.1, 0.6),
                rng.range(0.1, 0.6),
                rng.range(0.1, 0.6),
            ],
            qa,
        );
        let b = cube(
            rng.vec(0.3),
            [
                rng.range(0.1, 0.6),
                rng.range(0.1, 0.6),
                rng.range(0.1, 0.6),
            ],
            qb,
        );
        let exact = overlap_volume(&a, &b);
        assert!((exact - overlap_volume(&b, &a)).abs() < 1e-12);
        // Sample B uniformly, count points inside A.
        let n = 100_000;
        let (ra, rb) = (
            a.rotation.to_rotation_matrix(),
            b.rotation.to_rotation_matrix(),
        );
        let mut inside = 0usize;
        for _ in 0..n {
            let s = Vector3::new(
                rng.range(-1.0, 1.0) * b.half_extents[0],
                rng.range(-1.0, 1.0) * b.half_extents[1],
                rng.range(-1.0, 1.0) * b.half_extents[2],
            );
            let p = rb * s + Vector3::from(b.centre) - Vector3::from(a.centre);
            let l = ra.inverse() * p;
            if (0..3).all(|k| l[k].abs() <= a.half_extents[k]) {
                inside += 1;
            }
        }
        let frac = inside as f64 / n as f64;
        let est = b.volume_m3() * frac;
        let sigma = b.volume_m3() * (frac * (1.0 - frac) / n as f64).sqrt();
        assert!(
            (exact - est).abs() <= 4.0 * sigma + 1e-12,
            "exact {exact} vs MC {est} ± {sigma}"
        );
        if exact > 0.0 {
            checked += 1;
        }
    }
    assert!(checked > 20, "{checked}");
}
