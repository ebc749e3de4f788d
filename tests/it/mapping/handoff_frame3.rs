//! Hand-off of frame3's rigid bodies from closed-form FE node fields.
use fem2rbd::mapping::handoff::{secant_velocity, BodyState, GroundState, Handoff, NodeState};
use fem2rbd::mapping::{self, MapOptions, Mapping};
use fem2rbd::model::Model;
use nalgebra::{Rotation3, UnitQuaternion, Vector3};

const TOML: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/data/frame3-standin/model.toml"
);

fn setup() -> (Model, Mapping, Handoff) {
    let model = Model::load(TOML).unwrap();
    let m = mapping::map_to_boxes(
        &mapping::from_model(&model).unwrap(),
        &MapOptions::default(),
    )
    .unwrap();
    let h = Handoff::new(&model, &m).unwrap();
    (model, m, h)
}

fn v3(a: [f64; 3]) -> Vector3<f64> {
    Vector3::from(a)
}

fn close(a: Vector3<f64>, b: Vector3<f64>, tol: f64, what: &str) {
    assert!(
        (a - b).norm() <= tol,
        "{what}: {a:?} vs {b:?} (|d| = {:e})",
        (a - b).norm()
    );
}

fn rot_close(a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>, tol: f64, what: &str) {
    let d = a.angle_to(b);
    assert!(d <= tol, "{what}: rotations differ by {d:e} rad");
}

/// Every body moved by x ↦ o + R(x − o) + t, velocity v0 + ω × (x − o_now).
fn check_rigid(
    rot: Rotation3<f64>,
    t: Vector3<f64>,
    v0: Vector3<f64>,
    w: Vector3<f64>,
    g: GroundState,
) {
    let (model, m, h) = setup();
    let o = Vector3::new(0.75, 0.75, 0.0);
    let theta = rot.scaled_axis();
    let ug = v3(g.displacement);
    let nodes: Vec<NodeState> = model
        .nodes
        .iter()
        .map(|n| {
            let x = v3(n.xyz());
            let moved = o + rot * (x - o) + t;
            NodeState {
                u: (moved - x).into(),
                theta: theta.into(),
                v: (v0 + w.cross(&(moved - o - t))).into(),
                omega: w.into(),
            }
        })
        .collect();
    let states: Vec<BodyState> = h.states(&nodes, &g).unwrap();
    assert_eq!(states.len(), 60);
    let uq = UnitQuaternion::from_rotation_matrix(&rot);
    for (s, b) in states.iter().zip(&m.bodies) {
        assert_eq!(s.id.name(), b.id.name());
        let c = o + rot * (v3(b.centre) - o) + t + ug;
        close(v3(s.centre), c, 1e-12, &format!("{} centre", b.id.name()));
        rot_close(&s.rotation, &(uq * b.rotation), 1e-12, &b.id.name());
        let want_v = v3(g.velocity) + v0 + w.cross(&(c - ug - o - t));
        close(
            v3(s.linear_velocity),
            want_v,
            1e-12,
            &format!("{} velocity", b.id.name()),
        );
        close(
            v3(s.angular_velocity),
            w,
            1e-12,
            &format!("{} angular velocity", b.id.name()),
        );
    }
}

#[test]
fn undeformed_state_reproduces_the_mapping() {
    let (model, m, h) = setup();
    let states = h
        .states(
            &vec![NodeState::default(); model.nodes.len()],
            &GroundState::default(),
        )
        .unwrap();
    for (s, b) in states.iter().zip(&m.bodies) {
        close(v3(s.centre), v3(b.centre), 1e-15, &b.id.name());
        rot_close(&s.rotation, &b.rotation, 1e-15, &b.id.name());
        assert_eq!(s.linear_velocity, [0.0; 3]);
        assert_eq!(s.angular_velocity, [0.0; 3]);
    }
    // the wrong number of node states is an error
    let e = h.states(&[], &GroundState::default()).unwrap_err();
    assert!(
        matches!(e, mapping::MappingError::NodeCount { given: 0, nodes } if nodes == model.nodes.len()),
        "{e}"
    );
}

#[test]
fn rigid_translation_with_ground_motion_moves_every_body_by_it() {
    check_rigid(
        Rotation3::identity(),
        Vector3::new(0.12, -0.05, 0.03),
        Vector3::new(0.4, 0.1, -0.2),
        Vector3::zeros(),
        GroundState {
            displacement: [0.07, 0.02, 0.0],
            velocity: [0.3, -0.1, 0.0],
        },
    );
}

#[test]
fn small_rigid_rotation_moves_every_body_by_it() {
    check_rigid(
        Rotation3::new(Vector3::new(1e-3, -2e-3, 0.5e-3)),
        Vector3::new(0.01, 0.0, 0.0),
        Vector3::new(0.1, 0.0, 0.0),
        Vector3::new(0.02, -0.01, 0.03),
        GroundState::default(),
    );
}

#[test]
fn finite_rigid_rotation_moves_every_body_by_it() {
    check_rigid(
        Rotation3::new(Vector3::new(0.3, 0.5, -0.7)),
        Vector3::new(-0.2, 0.4, 0.1),
        Vector3::new(0.5, -0.3, 0.2),
        Vector3::new(0.8, -0.4, 1.1),
        GroundState {
            displacement: [0.05, -0.02, 0.0],
            velocity: [0.2, 0.1, 0.0],
        },
    );
}

#[test]
fn bent_and_twisted_column_follows_its_chord_and_mean_twist() {
    let (model, m, h) = setup();
    // Column:1:1 from base node 1 (0,0,0) to node 51 (0,0,0.5): tip pushed by d along X,
    // rotated by a bending angle about Y and twisted by tw about Z
    let (d, bend, tw) = (0.05, 0.15, 0.2);
    let k51 = model.nodes.iter().position(|n| n.tag == 51).unwrap();
    let mut nodes = vec![NodeState::default(); model.nodes.len()];
    nodes[k51].u = [d, 0.0, 0.0];
    nodes[k51].theta = [0.0, bend, tw];
    nodes[k51].v = [1.0, 0.0, 0.0];
    let s = &h.states(&nodes, &GroundState::default()).unwrap()[0];
    assert_eq!(s.id.name(), "Column:1:1");
    let b = &m.bodies[0];
    let r = s.rotation.to_rotation_matrix();
    let x: Vector3<f64> = r.matrix().column(0).into();
    let chord = Vector3::new(d, 0.0, 0.5).normalize();
    close(x, chord, 1e-15, "box axis along the deformed chord");
    // roll: y0 = -Y; the tip triad's y is R(θ)·(-Y); the mean with the base's -Y,
    // projected off the chord, gives the box y
    let y0 = Vector3::new(0.0, -1.0, 0.0);
    let yj = Rotation3::new(Vector3::new(0.0, bend, tw)) * y0;
    let ym = (y0 + yj) * 0.5;
    let y = (ym - chord * ym.dot(&chord)).normalize();
    close(r.matrix().column(1).into(), y, 1e-12, "box y");
    // untrimmed column box: centre at the chord midpoint (+ trim offset, zero for it)
    assert_eq!(b.trim_offset_local(), [0.0; 3]);
    close(
        v3(s.centre),
        Vector3::new(d / 2.0, 0.0, 0.25),
        1e-15,
        "centre",
    );
    // velocity: tip moves at 1 m/s along X: centre at 0.5 m/s (no offset from the chord),
    // angular velocity x × (v_j - v_i)/L about Y
    close(
        v3(s.linear_velocity),
        Vector3::new(0.5, 0.0, 0.0),
        1e-12,
        "centre velocity",
    );
    let l = (d * d + 0.25f64).sqrt();
    let w = chord.cross(&Vector3::new(1.0, 0.0, 0.0)) / l;
    close(v3(s.angular_velocity), w, 1e-15, "angular velocity");
    assert!(w.y > 0.0);
}

#[test]
fn secant_velocity_over_keyframes() {
    let dt = 0.04;
    let w = Vector3::new(0.0, 0.0, 0.5);
    let v = Vector3::new(1.0, -2.0, 0.5);
    let poses: Vec<([f64; 3], UnitQuaternion<f64>)> = (0..5)
        .map(|k| {
            let t = k as f64 * dt;
            ((v * t).into(), UnitQuaternion::from_scaled_axis(w * t))
        })
        .collect();
    let (lin, ang) = secant_velocity(&poses, dt, 3).unwrap();
    close(v3(lin), v, 1e-12, "secant linear");
    close(v3(ang), w, 1e-12, "secant angular");
    assert!(secant_velocity(&poses, dt, 5).is_err());
    assert!(secant_velocity(&poses, 0.0, 1).is_err());
}

#[test]
fn in_plane_stretch_of_a_floor_gives_panels_their_mean_velocity_and_no_spin() {
    let (model, m, h) = setup();
    // floor-1 nodes (z = 1) move at v = eps (x - c), c the bay centre: a pure stretch
    let (eps, c) = (0.4, Vector3::new(0.75, 0.75, 1.0));
    let nodes: Vec<NodeState> = model
        .nodes
        .iter()
        .map(|n| {
            let x = v3(n.xyz());
            let v = if n.z == 1.0 {
                (x - c) * eps
            } else {
                Vector3::zeros()
            };
            NodeState {
                v: v.into(),
                ..NodeState::default()
            }
        })
        .collect();
    let states = h.states(&nodes, &GroundState::default()).unwrap();
    let mut seen = 0;
    for (s, b) in states.iter().zip(&m.bodies) {
        if b.id.name().starts_with("Slab:1:") {
            // least-squares rigid fit: mean node velocity, no spin (Σ r × εr = 0)
            let mean = b
                .nodes
                .iter()
                .map(|p| (v3(*p) - c) * eps)
                .sum::<Vector3<f64>>()
                / 4.0;
            close(
                v3(s.angular_velocity),
                Vector3::zeros(),
                1e-15,
                &b.id.name(),
            );
            // the trimmed centre moves with the fitted rigid motion: v̄ + 0 × r
            close(v3(s.linear_velocity), mean, 1e-15, &b.id.name());
            assert!(mean.norm() > 0.1);
            seen += 1;
        }
    }
    assert_eq!(seen, 4);
}
