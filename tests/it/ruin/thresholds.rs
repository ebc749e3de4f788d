//! Breaking thresholds and spring stiffness of BCB's CT 22 against the worked example of
//! docs/bcb.md §3.2 (beam Formula-Assistant defaults, 400 × 400 mm contact,
//! 200 steps/s, time scale 1, L = 3 m, tol2 = 0.12), plus the scaling rules.

use fem2rbd::ruin::connection::{
    build_connections, ConnectionSpec, ConstraintClass, ConstraintRole, GroupStrength,
    RuinSettings, BCB_UNLIMITED,
};
use fem2rbd::ruin::search::find_contacts;
use fem2rbd::ruin::strength::{FormulaInputs, StrengthPerArea, StrengthSource};
use fem2rbd::ruin::BodyGeom;
use nalgebra::{Isometry3, UnitQuaternion};

fn cuboid(name: &str, group: &str, min: [f64; 3], max: [f64; 3], passive: bool) -> BodyGeom {
    BodyGeom {
        name: name.into(),
        group: group.into(),
        centre: [0, 1, 2].map(|i| 0.5 * (min[i] + max[i])),
        rotation: UnitQuaternion::identity(),
        half_extents: [0, 1, 2].map(|i| 0.5 * (max[i] - min[i])),
        passive,
    }
}

/// Two 0.4 × 0.4 × 3 m columns stacked along z: contact 400 × 400 mm, L = 3 m.
fn stacked(group_a: &str, group_b: &str, passive_a: bool) -> Vec<BodyGeom> {
    vec![
        cuboid("A", group_a, [0.0, 0.0, 0.0], [0.4, 0.4, 3.0], passive_a),
        cuboid("B", group_b, [0.0, 0.0, 3.0], [0.4, 0.4, 6.0], false),
    ]
}

fn connect(bodies: &[BodyGeom], groups: &[GroupStrength], s: &RuinSettings) -> ConnectionSpec {
    let contacts = find_contacts(bodies, &s.search).unwrap();
    assert_eq!(contacts.len(), 1);
    let poses: Vec<Isometry3<f64>> = bodies.iter().map(BodyGeom::pose).collect();
    let mut v = build_connections(bodies, groups, &contacts, &poses, s).unwrap();
    v.remove(0)
}

/// Rounds to `sig` significant figures, as the note prints them.
fn sig(x: f64, sig: i32) -> f64 {
    let e = x.abs().log10().floor() as i32;
    let m = 10f64.powi(sig - 1 - e);
    (x * m).round() / m
}

fn beam_group(name: &str) -> GroupStrength {
    GroupStrength::formula(name, FormulaInputs::default())
}

#[test]
fn worked_example_forces_thresholds_stiffness() {
    let bodies = stacked("beams", "beams", false);
    let c = connect(&bodies, &[beam_group("beams")], &RuinSettings::default());
    assert!((c.contact.area - 0.16).abs() < 1e-12);
    assert!((c.contact.centre_distance - 3.0).abs() < 1e-12);
    let f = &c.forces;
    // Forces: C 5.587 MN, T 0.838 MN, S_h 17.37 MN, S_w 32.17 MN, B_h 90.8 kN·m,
    // B_w 161.8 kN·m, P 272.3 kN.
    assert_eq!(sig(f.compression_n, 4), 5.587e6);
    assert_eq!(sig(f.tension_n, 3), 0.838e6);
    assert_eq!(sig(f.shear_h_n, 4), 17.37e6);
    assert_eq!(sig(f.shear_w_n, 4), 32.17e6);
    assert_eq!(sig(f.bend_h_nm, 3), 90.8e3);
    assert_eq!(sig(f.bend_w_nm, 4), 161.8e3);
    assert_eq!(sig(f.plastic_n.unwrap(), 4), 272.3e3);
    // Bullet thresholds: 61 462, 9 215, 191 090, 353 870 N·s; 680.9, 1 213 N·m·s;
    // spring 2 723 N·s.
    let bt: Vec<f64> = c.constraints.iter().map(|k| k.breaking_impulse).collect();
    assert_eq!(bt.len(), 7);
    assert_eq!(bt[0].round(), 61462.0);
    assert_eq!(bt[1].round(), 9215.0);
    assert_eq!(sig(bt[2], 5), 191090.0);
    assert_eq!(sig(bt[3], 5), 353870.0);
    assert_eq!((bt[4] * 10.0).round() / 10.0, 680.9);
    assert_eq!(bt[5].round(), 1213.0);
    assert_eq!(bt[6].round(), 2723.0);
    // Stiffness 756 300 N/m (L = 3 m, tol2 = 0.12; ×2 correction, /2 for SPRING2).
    let k = f.spring_stiffness.unwrap();
    assert_eq!(sig(k, 4), 756300.0);
    let spring = &c.constraints[6];
    // Angular axes (default `AngularSpring::Lever`): k·(0.2 m)² about x and y (the lever
    // is half the 0.4 m contact side), k·(0.4² + 0.4²)/4 about the normal z.
    let want = [k, k, k, k * 0.04, k * 0.04, k * 0.08];
    for (i, (got, want)) in spring.stiffness.iter().zip(want).enumerate() {
        assert!((got - want).abs() <= 1e-9 * want, "axis {i}");
    }
    // BCB's own rule: the same number on all six axes.
    let bcb = RuinSettings {
        angular_spring: fem2rbd::ruin::connection::AngularSpring::Bcb,
        ..RuinSettings::default()
    };
    let c_bcb = connect(&bodies, &[beam_group("beams")], &bcb);
    assert_eq!(c_bcb.constraints[6].stiffness, [k; 6]);
    assert_eq!(spring.damping, [20.0; 6]);
    assert_eq!(spring.spring, [true; 6]);
    assert!(!spring.enabled);
    assert!((0..6).all(|i| spring.is_free(i)));
    // Tolerances from the Formula Assistant: tol2D = 0.12, tol2R = atan(0.12·3/0.2).
    assert_eq!(c.tolerances.dist1, Some(0.1));
    assert_eq!(c.tolerances.rot1, Some(0.2));
    assert_eq!(c.tolerances.dist2, Some(0.12));
    let r2 = c.tolerances.rot2.unwrap();
    assert!((r2 - (0.12f64 * 3.0 / 0.2).atan()).abs() < 1e-15);
    assert!((r2 - 1.063_698).abs() < 1e-6);
}

/// Limits and locked axes of the six generics (docs/bcb.md §2.1, §11.4) for a +Z normal with
/// a 400 × 200 mm contact whose h (0.2 m) lies along world y.
#[test]
fn generic_rows_lock_the_right_axes() {
    let bodies = vec![
        cuboid("A", "g", [0.0, 0.0, 0.0], [0.4, 0.2, 3.0], false),
        cuboid("B", "g", [0.0, 0.0, 3.0], [0.4, 0.2, 6.0], false),
    ];
    let c = connect(&bodies, &[beam_group("g")], &RuinSettings::default());
    assert_eq!(
        (c.contact.normal_axis, c.contact.h_axis, c.contact.w_axis),
        (2, 1, 0)
    );
    // +Z normal: local (X, Y, Z) = world (Z, Y, −X): h (world y) is local Y = 1, w is Z = 2.
    let roles: Vec<ConstraintRole> = c.constraints.iter().map(|k| k.role).collect();
    use ConstraintRole::*;
    assert_eq!(
        roles,
        vec![
            Compression,
            Tension,
            ShearH,
            ShearW,
            BendH,
            BendW,
            PlasticSpring
        ]
    );
    let free =
        |k: usize| -> Vec<usize> { (0..6).filter(|&i| !c.constraints[k].is_free(i)).collect() };
    assert_eq!(free(0), vec![0]);
    assert_eq!(
        (c.constraints[0].lower[0], c.constraints[0].upper[0]),
        (0.0, BCB_UNLIMITED)
    );
    assert_eq!(free(1), vec![0]);
    assert_eq!(
        (c.constraints[1].lower[0], c.constraints[1].upper[0]),
        (-BCB_UNLIMITED, 0.0)
    );
    assert_eq!(free(2), vec![1]);
    assert_eq!(free(3), vec![2]);
    assert_eq!(free(4), vec![3, 5]); // torsion + rotation about the w-axis (local Z)
    assert_eq!(free(5), vec![3, 4]); // torsion + rotation about the h-axis (local Y)
    for k in 0..6 {
        assert_eq!(c.constraints[k].kind, ConstraintClass::Generic6Dof);
        assert!(c.constraints[k].enabled);
        for i in 0..6 {
            if !c.constraints[k].is_free(i) && k > 1 {
                assert_eq!(
                    (c.constraints[k].lower[i], c.constraints[k].upper[i]),
                    (0.0, 0.0)
                );
            }
        }
    }
    assert_eq!(c.constraints[6].kind, ConstraintClass::Spring2);
    // Frames: the pivot (0.2, 0.1, 3.0) in each body, local X on +Z.
    let pa = bodies[0].pose() * c.constraints[0].frame_a;
    let pb = bodies[1].pose() * c.constraints[0].frame_b;
    for p in [pa, pb] {
        assert!((p.translation.vector - nalgebra::Vector3::new(0.2, 0.1, 3.0)).norm() < 1e-12);
        assert!((p.rotation * nalgebra::Vector3::x() - nalgebra::Vector3::z()).norm() < 1e-12);
    }
    // The spring frame is world-aligned.
    let ps = bodies[0].pose() * c.constraints[6].frame_a;
    assert!(ps.rotation.angle() < 1e-12);
    // Shear along h gets the smaller capacity, bending about the w-axis the smaller one.
    assert!(c.forces.shear_h_n < c.forces.shear_w_n);
    assert!(c.forces.bend_h_nm < c.forces.bend_w_nm);
}

/// Thresholds scale with time_scale / steps_per_second; stiffness does not.
#[test]
fn thresholds_scale_with_inverse_step_rate() {
    let bodies = stacked("beams", "beams", false);
    let groups = [beam_group("beams")];
    let base = connect(&bodies, &groups, &RuinSettings::default());
    for (sps, ts) in [(100.0, 1.0), (300.0, 1.0), (200.0, 0.5)] {
        let s = RuinSettings {
            steps_per_second: sps,
            time_scale: ts,
            ..RuinSettings::default()
        };
        let c = connect(&bodies, &groups, &s);
        let factor = (ts / sps) / (1.0 / 200.0);
        for (k, b) in c.constraints.iter().zip(&base.constraints) {
            assert!(
                (k.breaking_impulse - b.breaking_impulse * factor).abs()
                    <= 1e-9 * b.breaking_impulse
            );
        }
        assert_eq!(c.forces.spring_stiffness, base.forces.spring_stiffness);
    }
    // 300 steps/s (the 2020 setting): compression 5.587 MN · 2.2 / 300 = 40 975 N·s.
    let s = RuinSettings {
        steps_per_second: 300.0,
        ..RuinSettings::default()
    };
    let c = connect(&bodies, &groups, &s);
    assert_eq!(c.constraints[0].breaking_impulse.round(), 40975.0);
}

/// ×2 towards a passive (foundation) body; the active group governs.
#[test]
fn passive_partner_doubles_thresholds() {
    let groups = [beam_group("beams"), beam_group("found")];
    let base = connect(
        &stacked("beams", "beams", false),
        &groups,
        &RuinSettings::default(),
    );
    let fnd = connect(
        &stacked("found", "beams", true),
        &groups,
        &RuinSettings::default(),
    );
    assert_eq!(fnd.group, "beams");
    for (k, b) in fnd.constraints.iter().zip(&base.constraints) {
        assert!((k.breaking_impulse - 2.0 * b.breaking_impulse).abs() <= 1e-9 * b.breaking_impulse);
    }
    // The stiffness follows the doubled plastic capacity.
    let (kf, kb) = (
        fnd.forces.spring_stiffness.unwrap(),
        base.forces.spring_stiffness.unwrap(),
    );
    assert!((kf - 2.0 * kb).abs() < 1e-6 * kb);
    // Two passive bodies are never connected.
    let mut two = stacked("found", "found", true);
    two[1].passive = true;
    let contacts = find_contacts(&two, &RuinSettings::default().search).unwrap();
    assert!(contacts.is_empty());
}

/// Two active groups: each value is the weaker one; 90° values survive only if both have them.
#[test]
fn weaker_of_two_groups() {
    let strong = beam_group("strong");
    let weak = GroupStrength {
        name: "weak".into(),
        strength: StrengthSource::PerArea(StrengthPerArea {
            c: 10.0,
            t: 20.0,
            s: 0.5,
            s90: None,
            b: 0.1,
            b90: None,
            p: Some(5.0),
        }),
        ..beam_group("weak")
    };
    let groups = [strong, weak];
    let c = connect(
        &stacked("strong", "weak", false),
        &groups,
        &RuinSettings::default(),
    );
    let a = 160000.0; // mm²
    let beam = FormulaInputs::default().per_area(0.0, 0.0);
    assert!((c.forces.compression_n - 10.0 * a).abs() < 1e-6);
    assert!((c.forces.tension_n - beam.t * a).abs() < 1e-6);
    assert!((c.forces.shear_h_n - 0.5 * a).abs() < 1e-6);
    assert!((c.forces.shear_w_n - 0.5 * a).abs() < 1e-6);
    // No 90° values on either side after combining: BCB's btRatio = h/w = 1 here.
    assert!((c.forces.bend_h_nm - 0.1 * a).abs() < 1e-6);
    assert!((c.forces.plastic_n.unwrap() - beam.p.unwrap() * a).abs() < 1e-6);
    // A's group ("strong", a formula) governs the tolerances.
    assert_eq!(c.group, "strong");
    assert_eq!(c.tolerances.dist2, Some(0.12));
    // With the weaker group first, its preset tolerances (0.2 / 0.8) govern.
    let c2 = connect(
        &stacked("weak", "strong", false),
        &groups,
        &RuinSettings::default(),
    );
    assert_eq!(c2.group, "weak");
    assert_eq!(c2.tolerances.dist2, Some(0.2));
    assert_eq!(c2.tolerances.rot2, Some(0.8));
    assert_eq!(c2.forces.compression_n, c.forces.compression_n);
}

/// BCB's btRatio: without any 90° value, bending rows get B·h/w and B·w/h.
#[test]
fn bending_ratio_without_90_degree_values() {
    let g = GroupStrength {
        name: "preset".into(),
        strength: StrengthSource::PerArea(StrengthPerArea::bcb_default_preset()),
        ..beam_group("preset")
    };
    let bodies = vec![
        cuboid("A", "preset", [0.0, 0.0, 0.0], [0.4, 0.2, 3.0], false),
        cuboid("B", "preset", [0.0, 0.0, 3.0], [0.4, 0.2, 6.0], false),
    ];
    let c = connect(&bodies, &[g], &RuinSettings::default());
    let a = 80000.0;
    assert!((c.forces.bend_h_nm - 1.0 * a * 0.5).abs() < 1e-6);
    assert!((c.forces.bend_w_nm - 1.0 * a * 2.0).abs() < 1e-6);
    assert!((c.forces.shear_h_n - 155.0 * a).abs() < 1e-6);
    assert!((c.forces.shear_w_n - 155.0 * a).abs() < 1e-6);
    // Spring: k = P·a/(L·0.2) (preset tol2 without a formula).
    let k = 1.3 * a / (3.0 * 0.2);
    assert!((c.forces.spring_stiffness.unwrap() - k).abs() < 1e-6 * k);
}

#[test]
fn unknown_group_is_an_error_naming_the_body() {
    let bodies = stacked("beams", "nope", false);
    let s = RuinSettings::default();
    let contacts = find_contacts(&bodies, &s.search).unwrap();
    let poses: Vec<Isometry3<f64>> = bodies.iter().map(BodyGeom::pose).collect();
    let err =
        build_connections(&bodies, &[beam_group("beams")], &contacts, &poses, &s).unwrap_err();
    assert_eq!(
        err.to_string(),
        "rigid body 1 ('B') is in group 'nope', which has no strength definition"
    );
    let err =
        build_connections(&bodies, &[beam_group("beams")], &contacts, &poses[..1], &s).unwrap_err();
    assert!(
        err.to_string().contains("expected 2 entries, got 1"),
        "{err}"
    );
}

/// Frames from deformed start poses (the hand-off at Tc): every constraint's two frames
/// coincide in the world at Tc, the generics' X axis follows the bodies, and the spring's
/// frame is the world-aligned one carried along.
#[test]
fn frames_from_start_poses_coincide() {
    use nalgebra::{Translation3, Vector3};
    let bodies = stacked("beams", "beams", false);
    let s = RuinSettings::default();
    let contacts = find_contacts(&bodies, &s.search).unwrap();
    // Tc: the whole pair tilted by 0.3 rad about y and shifted; B slightly more tilted.
    let tilt = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), 0.3);
    let extra = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.02);
    let shift = Translation3::new(0.5, -0.1, 0.05);
    let a_tc = Isometry3::from_parts(shift, tilt) * bodies[0].pose();
    let b_tc = Isometry3::from_parts(shift, tilt) * bodies[1].pose();
    let b_tc = Isometry3::from_parts(b_tc.translation, extra * b_tc.rotation);
    let poses = vec![a_tc, b_tc];
    let c = build_connections(&bodies, &[beam_group("beams")], &contacts, &poses, &s)
        .unwrap()
        .remove(0);
    for k in &c.constraints {
        let wa = a_tc * k.frame_a;
        let wb = b_tc * k.frame_b;
        assert!((wa.translation.vector - wb.translation.vector).norm() < 1e-12);
        assert!(wa.rotation.angle_to(&wb.rotation) < 1e-12);
    }
    // Generic X ≈ the tilted normal (+Z turned by 0.3 about y, half of B's extra turn).
    let x = (a_tc * c.constraints[0].frame_a).rotation * Vector3::x();
    let expect = tilt * Vector3::z();
    assert!((x - expect).norm() < 0.011, "{x:?} vs {expect:?}");
    // Spring frame: identity carried by the tilt.
    let r = (a_tc * c.constraints[6].frame_a).rotation;
    assert!((r.angle_to(&tilt) - 0.01).abs() < 1e-3);
}

/// Group strengths read from TOML as a scenario would give them; partial formula inputs
/// take BCB's defaults.
#[test]
fn group_strength_from_toml() {
    let g: GroupStrength = toml::from_str(
        r#"
name = "columns"
plastic_length = 0.0
[strength.formula]
kind = "beam_column"
h_mm = 100.0
w_mm = 100.0
fc = 22.5
[tolerances]
rot1 = 0.4
"#,
    )
    .unwrap();
    assert_eq!(g.threshold_multiplier, 1.0);
    assert_eq!(g.tolerances.dist1, 0.1);
    assert_eq!(g.tolerances.rot1, 0.4);
    match g.strength {
        StrengthSource::Formula(f) => {
            assert_eq!(
                (f.h_mm, f.w_mm, f.fc, f.fs, f.n),
                (100.0, 100.0, 22.5, 500.0, 5.0)
            );
        }
        _ => panic!("expected a formula"),
    }
    let bad: Result<GroupStrength, _> =
        toml::from_str("name = \"x\"\n[strength.formula]\nfcc = 3.0\n");
    assert!(bad.unwrap_err().to_string().contains("fcc"));
}
