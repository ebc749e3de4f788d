//! The start-overlap depth and the ranges of `fem2rbd scene`'s plausibility check
//! (`src/scene/plausibility.rs`), against hand-computed depths.
use fem2rbd::bullet::{BodyKind, BoxDesc, Pose, Velocity};
use fem2rbd::scene::plausibility::penetration_depth;

fn boxed(position: [f64; 3], half: [f64; 3], orientation: [f64; 4]) -> BoxDesc {
    BoxDesc {
        kind: BodyKind::Dynamic,
        half_extents: half,
        margin: 0.0,
        mass: 1.0,
        pose: Pose {
            position,
            orientation,
        },
        velocity: Velocity {
            linear: [0.0; 3],
            angular: [0.0; 3],
        },
        friction: 0.5,
        rolling_friction: 0.0,
        spinning_friction: 0.0,
        restitution: 0.0,
        linear_damping: 0.0,
        angular_damping: 0.0,
        disable_deactivation: true,
    }
}

const ID: [f64; 4] = [1.0, 0.0, 0.0, 0.0];

/// Hand-computed depths: axis-aligned boxes overlap by the least of their interval
/// overlaps; a cube turned 45° about z reaches √2·h along x.
#[test]
fn penetration_depth_of_boxes() {
    let ground = boxed([0.0, 0.0, -0.5], [10.0, 10.0, 0.5], ID);
    // A unit cube (h = 0.5) centred at z = -0.4: bottom at -0.9, 0.9 m into the ground.
    let cube = boxed([0.0, 0.0, -0.4], [0.5; 3], ID);
    assert!((penetration_depth(&ground, &cube) - 0.9).abs() < 1e-12);
    // Resting exactly on it: touching, depth 0.
    let resting = boxed([3.0, 2.0, 0.5], [0.5; 3], ID);
    assert_eq!(penetration_depth(&ground, &resting), 0.0);
    // Apart.
    let above = boxed([0.0, 0.0, 2.0], [0.5; 3], ID);
    assert_eq!(penetration_depth(&ground, &above), 0.0);
    // Side by side, overlapping by 0.2 m in x (and fully in y, z).
    let a = boxed([0.0, 0.0, 0.0], [0.5; 3], ID);
    let b = boxed([0.8, 0.0, 0.0], [0.5; 3], ID);
    assert!((penetration_depth(&a, &b) - 0.2).abs() < 1e-12);
    // Turned 45° about z: its corner reaches 0.5·√2 = 0.7071 m along x, so a cube at
    // x = 1.1 overlaps it by 0.7071 + 0.5 − 1.1 = 0.1071 m.
    let half_angle = std::f64::consts::PI / 8.0;
    let turned = boxed(
        [0.0, 0.0, 0.0],
        [0.5; 3],
        [half_angle.cos(), 0.0, 0.0, half_angle.sin()],
    );
    let side = boxed([1.1, 0.0, 0.0], [0.5; 3], ID);
    let want = 0.5 * 2f64.sqrt() + 0.5 - 1.1;
    assert!((penetration_depth(&turned, &side) - want).abs() < 1e-12);
    // At x = 1.25 the corner (0.7071) stays short of the face at 0.75: apart.
    let far = boxed([1.25, 0.0, 0.0], [0.5; 3], ID);
    assert_eq!(penetration_depth(&turned, &far), 0.0);
}
