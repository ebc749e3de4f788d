//! Whole-world checks of the Bullet layer against closed-form physics.
use fem2rbd::bullet::*;

const G: f64 = 9.81;

fn world() -> World {
    World::new(&WorldSettings::default()).unwrap()
}

/// Bullet integrates v ← v + g·h, x ← x + v·h (semi-implicit Euler), so after k substeps
/// z_k = z0 − g·h²·k(k+1)/2 and v_k = −g·h·k.
#[test]
fn free_fall_is_symplectic_euler_at_every_step() {
    let mut w = world();
    let h = 1.0 / 240.0;
    let z0 = 10.0;
    let b = w
        .add_box(&BoxDesc::dynamic([0.5; 3], 1.0, Pose::at([0.0, 0.0, z0])))
        .unwrap();
    let mut worst = 0.0f64;
    for k in 1..=480u32 {
        w.step(h, 1).unwrap();
        let kf = f64::from(k);
        let z_expected = z0 - G * h * h * kf * (kf + 1.0) / 2.0;
        let p = w.pose(b).unwrap();
        let v = w.velocity(b).unwrap();
        let err = (p.position[2] - z_expected).abs();
        worst = worst.max(err);
        assert!(
            err <= 1e-12,
            "step {k}: z = {} vs {z_expected}",
            p.position[2]
        );
        assert!(
            (v.linear[2] + G * h * kf).abs() <= 1e-12,
            "step {k}: vz = {}",
            v.linear[2]
        );
        assert_eq!(p.position[0], 0.0);
        assert_eq!(p.position[1], 0.0);
    }
    println!("free fall: worst |z - z_SE| over 480 steps = {worst:e} m");
    assert_eq!(w.substeps(), 480);
}

/// Sag [m] of a box of mass `m` hanging on a Spring2 constraint whose z axis is a spring
/// (k, c) and whose other five axes are locked, after `t` seconds of substeps `h`.
fn spring2_sag(m: f64, k: f64, c: f64, h: f64, t: f64) -> (f64, f64) {
    spring2_sag_limited(m, k, c, h, t, false)
}

/// As [`spring2_sag`], with Bullet's `limitIfNeeded` set to `limit`.
fn spring2_sag_limited(m: f64, k: f64, c: f64, h: f64, t: f64, limit: bool) -> (f64, f64) {
    let mut w = world();
    let anchor = w
        .add_box(&BoxDesc::fixed([0.1; 3], Pose::at([0.0, 0.0, 5.0])))
        .unwrap();
    let z0 = 3.9;
    let b = w
        .add_box(&BoxDesc::dynamic([0.1; 3], m, Pose::at([0.0, 0.0, z0])))
        .unwrap();
    let spring = Some(Spring {
        stiffness: k,
        damping: c,
        limit_if_needed: limit,
    });
    let mut d = ConstraintDesc::new(
        ConstraintKind::Spring2 {
            springs: [None, None, spring, None, None, None],
            set_equilibrium_point: true,
        },
        anchor,
        b,
        Pose::at([0.0, 0.0, -0.55]),
        Pose::at([0.0, 0.0, 0.55]),
    );
    d.limits = [
        Some((0.0, 0.0)),
        Some((0.0, 0.0)),
        Some((1.0, -1.0)), // free: lower > upper
        Some((0.0, 0.0)),
        Some((0.0, 0.0)),
        Some((0.0, 0.0)),
    ];
    d.disable_collisions_between = true;
    w.add_constraint(&d).unwrap();
    w.advance(t, h).unwrap();
    (
        z0 - w.pose(b).unwrap().position[2],
        w.velocity(b).unwrap().linear[2],
    )
}

/// A 1 kg box hangs from a static anchor on a Spring2 constraint whose z axis is a spring
/// k = 1000 N/m (damping 20 N·s/m, ζ ≈ 0.32) and whose other five axes are locked. At rest
/// the spring carries the weight: sag = m·g/k = 9.81 mm below the equilibrium point.
#[test]
fn spring2_hanging_box_sags_m_g_over_k() {
    let (m, k) = (1.0, 1000.0);
    let expected = m * G / k;
    let (sag, vz) = spring2_sag(m, k, 20.0, 1.0 / 240.0, 5.0);
    let rel = (sag - expected).abs() / expected;
    println!("spring2 sag = {sag:.12} m, m·g/k = {expected:.12} m, relative error {rel:e}");
    assert!(rel < 1e-6, "sag {sag} vs {expected}");
    assert!(vz.abs() < 1e-9);
}

/// At h = 1/60 s, √(k/m)·h = 0.53 > 1/4 (Bullet 3.24's test), where Bullet's `setStiffness(i, k)` (limitIfNeeded =
/// true) would silently soften the spring to m/(16·h²) = 225 N/m (sag 43.6 mm, measured in
/// docs/bullet-ffi.md §2.5). The layer passes `false`, so the sag is still m·g/k.
#[test]
fn spring2_stiffness_is_not_auto_limited_at_coarse_steps() {
    let (m, k) = (1.0, 1000.0);
    let expected = m * G / k;
    let (sag, _) = spring2_sag(m, k, 20.0, 1.0 / 60.0, 10.0);
    let rel = (sag - expected).abs() / expected;
    println!("spring2 sag at h = 1/60: {sag:.12} m (relative error {rel:e})");
    assert!(rel < 1e-6, "sag {sag} vs {expected}: stiffness was limited");
}

/// The same spring with `limit_if_needed` (Blender's and BCB's setting): at h = 1/60 s Bullet
/// caps the stiffness at m/(16·h²) = 225 N/m, so the sag is 16·g·h² = 43.6 mm (docs/bullet-ffi.md
/// §2.5); at h = 1/240 s, k·h² = 0.017 < m/16 and the spring is left alone (m·g/k).
#[test]
fn spring2_limit_if_needed_caps_stiffness_at_m_over_16_h_squared() {
    let (m, k) = (1.0, 1000.0);
    let h = 1.0 / 60.0;
    let expected = m * G / (m / (16.0 * h * h));
    let (sag, vz) = spring2_sag_limited(m, k, 20.0, h, 20.0, true);
    let rel = (sag - expected).abs() / expected;
    println!("limited spring2 sag at h = 1/60: {sag:.12} m vs 16·g·h² = {expected:.12} m");
    assert!(rel < 1e-6, "sag {sag} vs {expected}");
    assert!(vz.abs() < 1e-6);
    let (sag, _) = spring2_sag_limited(m, k, 20.0, 1.0 / 240.0, 5.0, true);
    let rel = (sag - m * G / k).abs() / (m * G / k);
    assert!(rel < 1e-6, "unlimited regime: sag {sag}");
}

/// A 2 kg box is held at its centre by a fixed constraint to a static anchor while gravity
/// grows by Δg = 0.5 m/s² per substep: g_k = k·Δg. With the pivot at the centre of mass the
/// constraint's z row carries exactly the weight, so its impulse in substep k is
/// λ_k = m·g_k·h. With threshold T = m·Δg·h·(k* − ½), λ_k < T for k < k* and λ_k ≥ T at k*:
/// the constraint must break at the end of substep k* = 40 and not before. Bullet also
/// clamps each row's impulse to ±T (btSequentialImpulseConstraintSolver::convertJoint), so
/// in substep k* the box receives only T: v_{k*} = −(g_{k*}·h − T/m) = −Δg·h/2; from
/// k*+1 it falls freely: v_{k*+1} = v_{k*} − g_{k*+1}·h.
#[test]
fn fixed_constraint_breaks_at_the_predicted_step() {
    let mut w = world();
    let (m, dg, h, k_star) = (2.0, 0.5, 1.0 / 240.0, 40u32);
    let anchor = w
        .add_box(&BoxDesc::fixed([0.1; 3], Pose::at([0.0, 0.0, 5.0])))
        .unwrap();
    let b = w
        .add_box(&BoxDesc::dynamic([0.1; 3], m, Pose::at([0.0, 0.0, 4.0])))
        .unwrap();
    let threshold = m * dg * h * (f64::from(k_star) - 0.5);
    let mut d = ConstraintDesc::new(
        ConstraintKind::Fixed,
        anchor,
        b,
        Pose::at([0.0, 0.0, -1.0]),
        Pose::IDENTITY,
    );
    d.breaking_impulse_threshold = threshold;
    d.disable_collisions_between = true;
    let c = w.add_constraint(&d).unwrap();
    assert_eq!(w.breaking_threshold(c).unwrap(), threshold);
    for k in 1..=k_star + 1 {
        let g_k = dg * f64::from(k);
        w.set_gravity([0.0, 0.0, -g_k]).unwrap();
        w.step(h, 1).unwrap();
        let enabled = w.constraint_enabled(c).unwrap();
        let vz = w.velocity(b).unwrap().linear[2];
        if k < k_star {
            assert!(enabled, "broke early, at step {k}");
            // btJointFeedback: force on B = λ/h = m·g_k upwards.
            let f = w.joint_feedback(c).unwrap();
            assert!(
                (f.force_b[2] - m * g_k).abs() <= 1e-9 * m * g_k,
                "step {k}: {f:?}"
            );
            assert!(vz.abs() < 1e-12, "step {k}: vz = {vz}");
        } else if k == k_star {
            assert!(!enabled, "did not break at step {k}");
            let expected = -(g_k * h - threshold / m);
            assert!(
                (vz - expected).abs() < 1e-12,
                "last step: vz = {vz} vs {expected}"
            );
            assert!((expected + dg * h / 2.0).abs() < 1e-15);
        } else {
            assert!(!enabled);
            let expected = -dg * h / 2.0 - g_k * h;
            assert!(
                (vz - expected).abs() < 1e-12,
                "falls freely after breaking: vz = {vz}"
            );
        }
    }
}

/// A generic 6-DoF constraint with a breaking threshold above the load never breaks, and
/// one disabled by hand lets the body fall; re-enabling it is reported.
#[test]
fn generic6dof_enable_disable_and_applied_impulse() {
    let mut w = world();
    let h = 1.0 / 240.0;
    let anchor = w
        .add_box(&BoxDesc::fixed([0.1; 3], Pose::at([0.0, 0.0, 5.0])))
        .unwrap();
    let b = w
        .add_box(&BoxDesc::dynamic([0.1; 3], 3.0, Pose::at([0.0, 0.0, 4.0])))
        .unwrap();
    let mut d = ConstraintDesc::new(
        ConstraintKind::Generic6Dof {
            use_linear_reference_frame_a: true,
        },
        anchor,
        b,
        Pose::at([0.0, 0.0, -1.0]),
        Pose::IDENTITY,
    );
    d.limits = [Some((0.0, 0.0)); 6];
    d.breaking_impulse_threshold = 1.0;
    d.disable_collisions_between = true;
    let c = w.add_constraint(&d).unwrap();
    w.step(h, 240).unwrap();
    assert!(w.constraint_enabled(c).unwrap());
    let z = w.pose(b).unwrap().position[2];
    assert!((z - 4.0).abs() < 1e-9, "held: z = {z}");
    // Total vertical force on the body equals its weight m·g.
    let f = w.joint_feedback(c).unwrap();
    assert!((f.force_b[2] - 3.0 * G).abs() < 1e-6, "{f:?}");
    assert!(w.applied_impulse(c).unwrap().is_finite());
    w.set_constraint_enabled(c, false).unwrap();
    assert!(!w.constraint_enabled(c).unwrap());
    w.step(h, 1).unwrap();
    assert!((w.velocity(b).unwrap().linear[2] + G * h).abs() < 1e-12);
}

/// A box resting on a static ground reports one contact pair with four points, a normal
/// impulse per substep equal to m·g·h, and a penetration of the order of the slop.
#[test]
fn contact_query_on_a_resting_box() {
    let mut w = world();
    let h = 1.0 / 240.0;
    let ground = w
        .add_box(&BoxDesc::fixed([5.0, 5.0, 0.5], Pose::at([0.0, 0.0, -0.5])))
        .unwrap();
    let b = w
        .add_box(&BoxDesc::dynamic([0.5; 3], 4.0, Pose::at([0.0, 0.0, 0.5])))
        .unwrap();
    let other = w
        .add_box(&BoxDesc::dynamic([0.5; 3], 1.0, Pose::at([3.0, 3.0, 3.0])))
        .unwrap();
    w.step(h, 240).unwrap();
    let c = w.contact(b, ground).unwrap();
    assert_eq!(c.num_points, 4);
    assert!(c.min_distance <= 0.0 && c.min_distance > -1e-3, "{c:?}");
    let rel = (c.total_normal_impulse - 4.0 * G * h).abs() / (4.0 * G * h);
    assert!(
        rel < 1e-3,
        "normal impulse {} vs m·g·h {}",
        c.total_normal_impulse,
        4.0 * G * h
    );
    assert_eq!(w.contact(ground, b).unwrap(), c);
    assert_eq!(w.contact(b, other).unwrap(), ContactSummary::NONE);
}

/// A kinematic ground moved by set_kinematic_target carries a resting box along (friction)
/// and reports the velocity Bullet derived from the pose change.
#[test]
fn kinematic_body_moves_with_its_targets() {
    let mut w = world();
    let h = 1.0 / 240.0;
    let ground = w
        .add_box(&BoxDesc::kinematic(
            [5.0, 5.0, 0.5],
            Pose::at([0.0, 0.0, -0.5]),
        ))
        .unwrap();
    assert!(w.set_pose(ground, Pose::IDENTITY).is_err());
    let speed = 0.3;
    for k in 1..=240 {
        let x = speed * h * f64::from(k);
        w.set_kinematic_target(ground, Pose::at([x, 0.0, -0.5]), None)
            .unwrap();
        w.step(h, 1).unwrap();
    }
    let p = w.pose(ground).unwrap();
    assert!((p.position[0] - speed).abs() < 1e-12);
    let v = w.velocity(ground).unwrap();
    assert!((v.linear[0] - speed).abs() < 1e-9, "{v:?}");
    // An explicit velocity overrides the derived one during the substep.
    w.set_kinematic_target(
        ground,
        Pose::at([speed, 0.0, -0.5]),
        Some(Velocity {
            linear: [1.5, 0.0, 0.0],
            angular: [0.0; 3],
        }),
    )
    .unwrap();
    w.step(h, 1).unwrap();
    assert_eq!(w.velocity(ground).unwrap().linear[0], 1.5);
}

fn pile_final_bits() -> Vec<u64> {
    let mut w = World::new(&WorldSettings::default()).unwrap();
    w.add_box(&BoxDesc::fixed(
        [10.0, 10.0, 0.5],
        Pose::at([0.0, 0.0, -0.5]),
    ))
    .unwrap();
    let mut bodies = Vec::new();
    for i in 0..12 {
        let fi = f64::from(i);
        let mut d = BoxDesc::dynamic(
            [0.3, 0.2, 0.1],
            1.0 + fi * 0.1,
            Pose {
                position: [0.05 * (fi % 3.0), 0.03 * (fi % 2.0), 0.3 + 0.25 * fi],
                orientation: [0.9950041652780258, 0.0, 0.0, 0.09983341664682815],
            },
        );
        d.velocity.angular = [0.0, 0.0, 0.5 * fi];
        bodies.push(w.add_box(&d).unwrap());
    }
    w.advance(1.5, 1.0 / 240.0).unwrap();
    bodies
        .iter()
        .flat_map(|&b| {
            let p = w.pose(b).unwrap();
            p.position
                .into_iter()
                .chain(p.orientation)
                .map(f64::to_bits)
        })
        .collect()
}

#[test]
fn bulk_reads_equal_single_reads() {
    let mut w = world();
    let h = 1.0 / 240.0;
    let anchor = w
        .add_box(&BoxDesc::fixed([0.1; 3], Pose::at([0.0, 0.0, 5.0])))
        .unwrap();
    let mut bodies = vec![anchor];
    for i in 0..4 {
        let mut d = BoxDesc::dynamic([0.2; 3], 1.0, Pose::at([f64::from(i), 0.0, 4.0]));
        d.velocity.angular = [0.1 * f64::from(i), 0.2, 0.0];
        bodies.push(w.add_box(&d).unwrap());
    }
    let mut d = ConstraintDesc::new(
        ConstraintKind::Fixed,
        anchor,
        bodies[1],
        Pose::at([0.0, 0.0, -1.0]),
        Pose::IDENTITY,
    );
    d.breaking_impulse_threshold = 1e-3; // breaks in the first substep
    let c0 = w.add_constraint(&d).unwrap();
    d.body_b = bodies[2];
    d.frame_a = Pose::at([1.0, 0.0, -1.0]);
    d.breaking_impulse_threshold = f64::INFINITY;
    let c1 = w.add_constraint(&d).unwrap();
    w.step(h, 10).unwrap();
    let poses = w.poses().unwrap();
    let vels = w.velocities().unwrap();
    for (i, &b) in bodies.iter().enumerate() {
        assert_eq!(poses[i], w.pose(b).unwrap());
        assert_eq!(vels[i], w.velocity(b).unwrap());
    }
    assert_eq!(w.constraints_enabled().unwrap(), vec![false, true]);
    assert!(!w.constraint_enabled(c0).unwrap() && w.constraint_enabled(c1).unwrap());
}

#[test]
fn two_runs_give_identical_bits() {
    assert_eq!(pile_final_bits(), pile_final_bits());
}

/// A box resting on a kinematic platform that starts moving at v = 0.3 m/s along x is
/// dragged by Coulomb friction: it accelerates at μ·g (μ = 0.5·0.5 = 0.25, Bullet's product
/// rule) until it moves with the platform, after v/(μ·g) = 0.122 s. One second after the
/// start it has travelled v·t − v²/(2μg) = 0.28165 m and moves at v. So the velocity Bullet
/// derives for a kinematic body from its targets is what its contacts see.
#[test]
fn kinematic_platform_drags_a_box_by_friction() {
    let mut w = world();
    let h = 1.0 / 240.0;
    let platform = w
        .add_box(&BoxDesc::kinematic(
            [5.0, 5.0, 0.5],
            Pose::at([0.0, 0.0, -0.5]),
        ))
        .unwrap();
    let b = w
        .add_box(&BoxDesc::dynamic([0.5; 3], 1.0, Pose::at([0.0, 0.0, 0.5])))
        .unwrap();
    w.step(h, 120).unwrap(); // settle
    let x0 = w.pose(b).unwrap().position[0];
    let v = 0.3;
    for k in 1..=240 {
        let x = v * h * f64::from(k);
        w.set_kinematic_target(platform, Pose::at([x, 0.0, -0.5]), None)
            .unwrap();
        w.step(h, 1).unwrap();
    }
    let mu_g = 0.25 * G;
    let expected = v * 1.0 - v * v / (2.0 * mu_g);
    let x = w.pose(b).unwrap().position[0] - x0;
    let vx = w.velocity(b).unwrap().linear[0];
    println!("dragged box: x = {x:.6} m (Coulomb {expected:.6} m), vx = {vx:.9} m/s");
    assert!((x - expected).abs() < 2e-3, "x = {x} vs {expected}");
    // Friction ERP leaves a residual of a few µm/s (measured 2.5e-6 m/s).
    assert!((vx - v).abs() < 1e-5, "vx = {vx}");
}

/// A box hangs on a slider: the joint's z axis (axis 2) is limited to [−0.3, 0.2] m and the
/// other five axes are locked. Gravity pulls it down until the lower limit holds it, 0.3 m
/// below where it started, for both 6-DoF classes; the locked axes keep x, y and the
/// orientation. (Axis order 0..5 = x, y, z, rx, ry, rz of the joint frame.)
#[test]
fn six_dof_linear_limit_stops_the_fall_at_the_limit() {
    let kinds = [
        ConstraintKind::Generic6Dof {
            use_linear_reference_frame_a: true,
        },
        ConstraintKind::Spring2 {
            springs: [None; 6],
            set_equilibrium_point: false,
        },
    ];
    for kind in kinds {
        let mut w = world();
        let anchor = w
            .add_box(&BoxDesc::fixed([0.1; 3], Pose::at([0.0, 0.0, 5.0])))
            .unwrap();
        let b = w
            .add_box(&BoxDesc::dynamic([0.1; 3], 2.0, Pose::at([0.0, 0.0, 4.0])))
            .unwrap();
        let mut d =
            ConstraintDesc::new(kind, anchor, b, Pose::at([0.0, 0.0, -1.0]), Pose::IDENTITY);
        d.limits = [
            Some((0.0, 0.0)),
            Some((0.0, 0.0)),
            Some((-0.3, 0.2)),
            Some((0.0, 0.0)),
            Some((0.0, 0.0)),
            Some((0.0, 0.0)),
        ];
        d.disable_collisions_between = true;
        w.add_constraint(&d).unwrap();
        w.advance(2.0, 1.0 / 240.0).unwrap();
        let p = w.pose(b).unwrap();
        println!("{kind:?}: z = {:.9}", p.position[2]);
        assert!(
            (p.position[2] - 3.7).abs() < 1e-6,
            "{kind:?}: z = {}",
            p.position[2]
        );
        assert!(p.position[0].abs() < 1e-9 && p.position[1].abs() < 1e-9);
        assert!((p.orientation[0] - 1.0).abs() < 1e-9, "{:?}", p.orientation);
    }
}

/// A Generic6Dof constraint with all six axes locked, `b` hanging 1 m below `anchor`.
fn locked_hanger(w: &mut World, anchor: BodyHandle, b: BodyHandle) -> ConstraintHandle {
    crate::support::locked_joint(w, anchor, b, [0.0, 0.0, -1.0], [0.0; 3])
}

/// A box of mass `m` hanging 1 m below a static anchor on [`locked_hanger`], its vertical
/// row given `erp` and `cfm`: (world, box, constraint).
fn member_hanger(m: f64, erp: f64, cfm: f64) -> (World, BodyHandle, ConstraintHandle) {
    let mut w = world();
    let anchor = w
        .add_box(&BoxDesc::fixed([0.1; 3], Pose::at([0.0, 0.0, 5.0])))
        .unwrap();
    let b = w
        .add_box(&BoxDesc::dynamic([0.1; 3], m, Pose::at([0.0, 0.0, 4.0])))
        .unwrap();
    let c = locked_hanger(&mut w, anchor, b);
    w.set_constraint_param(c, ConstraintParam::StopErp, 2, erp)
        .unwrap();
    w.set_constraint_param(c, ConstraintParam::StopCfm, 2, cfm)
        .unwrap();
    (w, b, c)
}

/// A Generic6Dof row given ERP and CFM from a target stiffness k and damping ratio ζ
/// ([`fem2rbd::ruin::stage::member_row_erp_cfm`], Bullet's joint CFM being relative to the
/// row's effective mass 1/K): a 10 kg box hanging from a static anchor on such a vertical
/// row (the other five locked as usual) settles at sag = m·g/k, the static deflection of
/// an implicit spring k — here x = √(k/m)·h = 2 at h = 1/200 s (k = 1.6·10⁶ N/m,
/// m·g/k = 61.3 µm; ERP 0.5, CFM 0.125), critically damped.
#[test]
fn generic6dof_member_row_sags_m_g_over_k() {
    let (m, h, zeta) = (10.0, 1.0 / 200.0, 1.0);
    let k = m * (2.0 / h) * (2.0 / h);
    let (erp, cfm) = fem2rbd::ruin::stage::member_row_erp_cfm(k, 1.0 / m, h, zeta);
    assert!((erp - 0.5).abs() < 1e-12 && (cfm - 0.125).abs() < 1e-12);
    let (mut w, b, c) = member_hanger(m, erp, cfm);
    let expected = m * G / k;
    let mut peak: f64 = 0.0;
    for _ in 0..400 {
        w.step(h, 1).unwrap();
        peak = peak.max(4.0 - w.pose(b).unwrap().position[2]);
    }
    let sag = 4.0 - w.pose(b).unwrap().position[2];
    println!("member row: sag {sag:.4e} m, m·g/k {expected:.4e} m, peak {peak:.4e} m");
    assert!(
        (sag - expected).abs() < 0.01 * expected,
        "sag {sag} vs m·g/k {expected}"
    );
    // The peak is the first substep's free fall g·h² (symplectic Euler): a locked row
    // exactly at its limit produces no solver row (src/ruin/stage.rs, "Bullet's locked
    // rows"); from then on the row pulls the box back to m·g/k without overshoot.
    assert!(
        (peak - G * h * h).abs() < 1e-3 * G * h * h,
        "peak {peak} vs g·h² {}",
        G * h * h
    );
    // Rejected values name the parameter.
    assert!(w
        .set_constraint_param(c, ConstraintParam::StopCfm, 6, 0.1)
        .is_err());
    assert!(w
        .set_constraint_param(c, ConstraintParam::StopErp, 0, f64::NAN)
        .is_err());
}

/// A member row softer than Bullet's joint update allows: x = √(k/m)·h = 0.3 gives
/// CFM = 1/(x(x + 2)) = 1.45, and Bullet's row update λ ← rhs − CFM·λ (per sweep) then
/// diverges — the box is thrown to a non-finite or far-off pose within a second.
/// [`fem2rbd::ruin::stage::member_row_erp_cfm`] stiffens such a row to CFM = 0.5
/// (x = √3 − 1): the box then settles at m·g/k' with k' = m·(x/h)², the stiffened row's
/// static deflection (g·h²/(√3 − 1)² = 0.457 mm at h = 1/200 s).
#[test]
fn generic6dof_member_row_softer_than_the_sweeps_allow_is_stiffened() {
    let (m, h, zeta) = (10.0, 1.0 / 200.0, 1.0);
    let k = m * (0.3 / h) * (0.3 / h);
    let hang = |erp: f64, cfm: f64| {
        let (mut w, b, _) = member_hanger(m, erp, cfm);
        for _ in 0..200 {
            if w.step(h, 1).is_err() {
                return f64::NAN;
            }
        }
        4.0 - w.pose(b).unwrap().position[2]
    };
    let x: f64 = 0.3;
    let raw = hang(x / (x + 2.0), 1.0 / (x * (x + 2.0)));
    let (erp, cfm) = fem2rbd::ruin::stage::member_row_erp_cfm(k, 1.0 / m, h, zeta);
    let x_min = 3f64.sqrt() - 1.0;
    assert!((cfm - 0.5).abs() < 1e-12 && (erp - x_min / (x_min + 2.0)).abs() < 1e-12);
    let capped = hang(erp, cfm);
    let expected = G * h * h / (x_min * x_min);
    println!("soft member row: raw CFM 1.45 sag {raw:e} m; capped sag {capped:.4e} m (expected {expected:.4e})");
    assert!(
        raw.is_nan() || raw.abs() >= 1.0,
        "CFM 1.45 must diverge, sag {raw}"
    );
    assert!(
        (capped - expected).abs() < 0.01 * expected,
        "capped sag {capped} vs {expected}"
    );
}

/// `relock_constraint`: a body that starts 0.1 rad turned about z against its locked
/// Generic6Dof frames (no gravity) is driven back to 0 by Bullet's velocity bias ERP·θ/h;
/// re-locked first, the row holds it at 0.1 rad.
#[test]
fn generic6dof_relock_holds_the_present_angle() {
    let angle_after = |relock: bool| {
        let mut w = World::new(&WorldSettings {
            gravity: [0.0; 3],
            ..WorldSettings::default()
        })
        .unwrap();
        let anchor = w
            .add_box(&BoxDesc::fixed([0.1; 3], Pose::at([0.0, 0.0, 5.0])))
            .unwrap();
        let half = 0.05_f64;
        let q = [half.cos(), 0.0, 0.0, half.sin()]; // 0.1 rad about z
        let b = w
            .add_box(&BoxDesc::dynamic(
                [0.1; 3],
                1.0,
                Pose {
                    position: [0.0, 0.0, 4.0],
                    orientation: q,
                },
            ))
            .unwrap();
        let c = locked_hanger(&mut w, anchor, b);
        if relock {
            w.relock_constraint(c, 0b111_000).unwrap();
        }
        w.step(1.0 / 200.0, 200).unwrap();
        let o = w.pose(b).unwrap().orientation;
        2.0 * o[3].atan2(o[0])
    };
    let (free, held) = (angle_after(false), angle_after(true));
    println!("after 1 s: {free:.3e} rad (old lock), {held:.6} rad (relocked)");
    assert!(free.abs() < 1e-3, "old lock drives back to 0: {free}");
    assert!(
        (held - 0.1).abs() < 1e-6,
        "relocked row holds 0.1 rad: {held}"
    );
}

/// Joint warm start (`World::set_joint_warmstart`, the shim's `JointWarmStart`): a 100 kg
/// box hangs from a static anchor through a 1 kg box, both links locked Generic6Dof
/// constraints, solved with 4 Gauss–Seidel iterations at h = 1/200 s. Bullet starts every
/// joint row from zero impulse in every substep (`convertJoint`), so the solve falls short
/// of the heavy box's weight and the chain settles where the Baumgarte bias ERP·e/h makes
/// up the rest: a static sag e0. Started from f times its last impulse, the slowly
/// converging mode keeps almost all of that guess (its iteration factor t^N ≈ 1), so the
/// share the bias must make up, hence the sag, scales with 1 − f: e(f) ≈ (1 − f)·e0. At
/// f = 1 that mode's impulse is carried over unchanged, an integrator acting with a
/// one-substep lag: the chain oscillates with growing amplitude (docs/ruin-numerics.md, "The
/// joint warm start").
#[test]
fn generic6dof_warm_start_scales_the_unconverged_sag() {
    let h = 1.0 / 200.0;
    let sag_after = |factor: f64| {
        let mut s = WorldSettings::default();
        s.solver.num_iterations = 4;
        let mut w = World::new(&s).unwrap();
        w.set_joint_warmstart(factor).unwrap();
        let (_, heavy, _) = crate::support::hanging_chain(&mut w, 0.0);
        w.step(h, 400).unwrap();
        let v = w.velocity(heavy).unwrap().linear[2].abs();
        let (f, started) = w.joint_warmstart().unwrap();
        assert_eq!(f, factor);
        assert_eq!(started > 0, factor > 0.0, "rows warm-started: {started}");
        (3.0 - w.pose(heavy).unwrap().position[2], v)
    };
    let (cold, v_cold) = sag_after(0.0);
    let (quarter, _) = sag_after(0.25);
    let (half, v_half) = sag_after(0.5);
    let (full, v_full) = sag_after(1.0);
    println!(
        "sag: f = 0 {cold:.4e} m, 0.25 {quarter:.4e} m, 0.5 {half:.4e} m, 1 {full:.4e} m; \
         speeds {v_cold:.1e}, {v_half:.1e}, {v_full:.1e} m/s"
    );
    assert!(
        cold > 1e-2,
        "the cold-started solve leaves a sag, got {cold}"
    );
    for (f, e) in [(0.25, quarter), (0.5, half)] {
        let expected = (1.0 - f) * cold;
        assert!(
            (e - expected).abs() < 0.02 * cold,
            "f = {f}: sag {e} vs (1 - f)·e0 = {expected}"
        );
    }
    assert!(
        v_cold < 1e-3 && v_half < 1e-3,
        "at rest: {v_cold}, {v_half}"
    );
    assert!(v_full > 1.0, "f = 1 should be unstable, speed {v_full}");
    assert!(World::new(&WorldSettings::default())
        .unwrap()
        .set_joint_warmstart(1.5)
        .is_err());
}

/// A rigid landing passes its whole impulse in one substep (docs/ruin-numerics.md, "Landings"): a
/// 1000 kg block carrying a 500 kg block on a fixed joint falls 0.5 m onto the ground
/// (v = √(2·g·0.5) = 3.13 m/s). Bullet's contact stops the pair within one substep, so the
/// joint passes the upper block's momentum m_B·v = 1566 N·s in that substep: its peak
/// force is about m_B·v/h, doubling with every halving of h (measured 359 / 732 / 1276 /
/// 2842 kN at 200 / 400 / 800 / 1600 substeps/s; the impulse is 1.02–1.17 × m_B·v). Any
/// connection of finite strength therefore breaks at a landing once h is small enough: a
/// ruin that depends on whether a story survives a landing is not converged in h.
#[test]
fn a_rigid_landing_passes_its_impulse_through_a_joint_in_one_substep() {
    let (m_b, drop) = (500.0, 0.5f64);
    let v = (2.0 * 9.81 * drop).sqrt();
    let mut peaks = Vec::new();
    for sps in [200.0, 400.0, 800.0, 1600.0] {
        let h = 1.0 / sps;
        let mut ws = WorldSettings::default();
        ws.solver.num_iterations = 100;
        let mut w = World::new(&ws).unwrap();
        w.add_box(&BoxDesc::fixed([5.0, 5.0, 0.5], Pose::at([0.0, 0.0, -0.5])))
            .unwrap();
        let mut da = BoxDesc::dynamic([0.25, 0.25, 0.1], 1000.0, Pose::at([0.0, 0.0, 0.1 + drop]));
        da.margin = 0.0;
        let a = w.add_box(&da).unwrap();
        let mut db = BoxDesc::dynamic([0.25, 0.25, 0.1], m_b, Pose::at([0.0, 0.0, 0.3 + drop]));
        db.margin = 0.0;
        let b = w.add_box(&db).unwrap();
        let mut d = ConstraintDesc::new(
            ConstraintKind::Fixed,
            a,
            b,
            Pose::at([0.0, 0.0, 0.1]),
            Pose::at([0.0, 0.0, -0.1]),
        );
        d.disable_collisions_between = true;
        let c = w.add_constraint(&d).unwrap();
        let mut peak: f64 = 0.0;
        for _ in 0..(0.5 * sps) as usize {
            w.step(h, 1).unwrap();
            peak = peak.max(w.applied_impulse(c).unwrap().abs());
        }
        println!(
            "{sps} substeps/s: peak joint impulse {peak:.1} N·s ({:.3} × m_B·v), force {:.0} kN",
            peak / (m_b * v),
            peak / h / 1e3
        );
        assert!(
            (1.0..=1.25).contains(&(peak / (m_b * v))),
            "{sps}: {peak} N·s against m_B·v = {}",
            m_b * v
        );
        peaks.push(peak / h);
    }
    // The peak force grows like 1/h: ×8 from 200 to 1600 substeps/s (±25 %).
    let ratio = peaks[3] / peaks[0];
    assert!((6.0..=10.0).contains(&ratio), "force ratio {ratio}");
}

/// A locked joint's error decays by the factor (1 − ERP) per substep: Bullet's row asks
/// for the bias velocity −ERP·e/h (Baumgarte). A free 1 kg box (no gravity) starts 10 mm
/// off its joint with a fixed anchor; after n substeps its offset is 10 mm·(1 − ERP)ⁿ.
/// With ERP 0.2 per substep at any rate (Bullet, BCB) the 0.05 s decay depends on the
/// substep: 0.8¹⁰, 0.8²⁰, 0.8⁴⁰ at 200 / 400 / 800 substeps/s (10.7 %, 1.2 %, 0.01 % left).
/// With the ERP given per time (`[physics.experimental] erp_steps_per_second = 200`, the default:
/// ERP = 0.2·200/rate) it is 0.8¹⁰, 0.9²⁰, 0.95⁴⁰ and converges, at first order in h, to
/// exp(−0.2·200/s·0.05 s) = exp(−2) = 13.5 % (docs/ruin-numerics.md, "The error reduction per
/// second").
#[test]
fn a_joint_error_decays_by_one_minus_erp_per_substep() {
    let offset_after = |sps: u32, erp: f64| {
        let s = WorldSettings {
            gravity: [0.0; 3],
            solver: SolverSettings {
                erp,
                ..SolverSettings::default()
            },
            ..WorldSettings::default()
        };
        let mut w = World::new(&s).unwrap();
        let anchor = w
            .add_box(&BoxDesc::fixed([0.1; 3], Pose::at([0.0; 3])))
            .unwrap();
        let b = w
            .add_box(&BoxDesc::dynamic([0.1; 3], 1.0, Pose::at([0.01, 0.0, 0.0])))
            .unwrap();
        crate::support::locked_joint(&mut w, anchor, b, [0.0; 3], [0.0; 3]);
        let n = sps / 20;
        w.step(1.0 / f64::from(sps), n).unwrap();
        (w.pose(b).unwrap().position[0], n)
    };
    let exact = 0.01 * (-2.0f64).exp();
    let mut last_gap = f64::INFINITY;
    for sps in [200u32, 400, 800] {
        let per_time = 0.2 * 200.0 / f64::from(sps);
        for erp in [0.2, per_time] {
            let (x, n) = offset_after(sps, erp);
            let want = 0.01 * (1.0 - erp).powi(n as i32);
            println!(
                "{sps} substeps/s, ERP {erp}: offset {x:.6e} m, 10 mm·(1 − ERP)^{n} = {want:.6e}"
            );
            assert!(
                (x - want).abs() <= 1e-9 * 0.01,
                "{sps}/s ERP {erp}: {x} vs {want}"
            );
        }
        let gap = (offset_after(sps, per_time).0 - exact).abs();
        assert!(
            gap < 0.6 * last_gap,
            "{sps}/s: {gap} against {last_gap} at half the rate"
        );
        last_gap = gap;
    }
    assert!(
        last_gap < 0.07 * exact,
        "800/s: {last_gap} m from exp(-2)·10 mm"
    );
}
