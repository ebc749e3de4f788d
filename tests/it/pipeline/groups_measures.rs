//! The pipeline's building blocks against closed-form values: group strengths read from
//! frame3's sections and materials; plan projections, union and intersection areas of the
//! summary's ruin measures.
use fem2rbd::bullet::Pose;
use fem2rbd::model::Model;
use fem2rbd::plan_geometry::{hull, intersection_area, projection, union_area};
use fem2rbd::ruin::groups::{group_inputs, group_strengths, FOUNDATION_GROUP};

#[test]
fn frame3_group_strengths_come_from_its_column_sections() {
    let model = Model::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/frame3-standin/model.toml"
    ))
    .unwrap();
    let g = group_inputs(&model).unwrap();
    assert_eq!(g.keys().collect::<Vec<_>>(), ["1", "2", "3"]);
    let f = g["1"];
    // column_S1: b = h = 0.1 m, cover 0.012 m, 8 bars of 9.621e-6 m² (d = 3.5 mm),
    // cover_F1 fpc = -22.5 MPa, Steel02 Fy = 457.7 MPa.
    assert!((f.h_mm - 100.0).abs() < 1e-9 && (f.w_mm - 100.0).abs() < 1e-9);
    assert!((f.c - 12.0).abs() < 1e-9);
    assert_eq!(f.n, 8.0);
    assert!((f.dl - 3.5).abs() < 1e-6, "dl = {}", f.dl);
    assert!((f.fc - 22.5).abs() < 1e-9);
    assert!((f.fs - 457.7).abs() < 1e-9);
    assert!((g["2"].fc - 23.9).abs() < 1e-9, "group 2 uses cover_F2");
    let s = group_strengths(&model).unwrap();
    assert_eq!(s.len(), 4);
    assert_eq!(s[3].name, FOUNDATION_GROUP);
}

#[test]
fn plan_areas_match_closed_form() {
    // A 2 × 1 box rotated 90° about z: projection is 1 × 2.
    let q = nalgebra::UnitQuaternion::from_axis_angle(
        &nalgebra::Vector3::z_axis(),
        std::f64::consts::FRAC_PI_2,
    );
    let pose = Pose {
        position: [0.0, 0.0, 5.0],
        orientation: [q.w, q.i, q.j, q.k],
    };
    let p = projection(&pose, [1.0, 0.5, 0.2]);
    assert_eq!(p.len(), 4);
    let a = union_area(&[&p]);
    assert!((a - 2.0).abs() < 6.0 * 1.0 / 20.0 * 0.1, "area {a}");
    // Two unit squares offset by 0.5 in x: union 1.5, intersection 0.5.
    let s1 = hull(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
    let s2 = hull(&[[0.5, 0.0], [1.5, 0.0], [1.5, 1.0], [0.5, 1.0]]);
    let cell = 1.0 / 20.0;
    let u = union_area(&[&s1, &s2]);
    let i = intersection_area(&[&s1], &[&s2]);
    assert!((u - 1.5).abs() < 4.0 * cell, "union {u}");
    assert!((i - 0.5).abs() < 4.0 * cell, "intersection {i}");
    // Disjoint: no overlap.
    let s3 = hull(&[[3.0, 3.0], [4.0, 3.0], [4.0, 4.0], [3.0, 4.0]]);
    assert_eq!(intersection_area(&[&s1], &[&s3]), 0.0);
}
