//! BCB's elastic → plastic → broken monitor (docs/bcb.md §4, §11.5) at the exact
//! deformation values where it must switch.
//!
//! Fixture: two 0.4 × 0.4 × 3 m columns stacked along z (centre distance d₀ = 3 m,
//! contact h = 0.4 m), beam Formula-Assistant defaults: tol1D = 0.1, tol1R = 0.2 rad,
//! tol2D = elu/100 = 0.12, tol2R = atan(0.12·3/0.2) = 1.063698 rad.

use fem2rbd::ruin::connection::{
    build_connections, ConnectionSpec, ConnectionState, GroupStrength, RuinSettings,
};
use fem2rbd::ruin::monitor::{
    start_state_from_damage, Action, AngleRule, FeDamage, Monitor, StateChange,
};
use fem2rbd::ruin::search::find_contacts;
use fem2rbd::ruin::strength::{FormulaInputs, StrengthPerArea, StrengthSource};
use fem2rbd::ruin::BodyGeom;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use std::cell::RefCell;
use std::f64::consts::{FRAC_PI_2, PI};

fn column(name: &str, z0: f64, rotation: UnitQuaternion<f64>) -> BodyGeom {
    BodyGeom {
        name: name.into(),
        group: "g".into(),
        centre: [0.2, 0.2, z0 + 1.5],
        rotation,
        half_extents: [0.2, 0.2, 1.5],
        passive: false,
    }
}

fn setup(group: GroupStrength, rot_b: UnitQuaternion<f64>) -> (Vec<BodyGeom>, Vec<ConnectionSpec>) {
    let bodies = vec![
        column("A", 0.0, UnitQuaternion::identity()),
        column("B", 3.0, rot_b),
    ];
    let s = RuinSettings::default();
    let contacts = find_contacts(&bodies, &s.search).unwrap();
    let poses: Vec<_> = bodies.iter().map(BodyGeom::pose).collect();
    let conns = build_connections(&bodies, &[group], &contacts, &poses, &s).unwrap();
    assert_eq!(conns.len(), 1);
    (bodies, conns)
}

fn beam_group() -> GroupStrength {
    GroupStrength::formula("g", FormulaInputs::default())
}

/// Poses with body B moved to centre z = `zb` and turned by `angle` about `axis` (about
/// its own centre, so the centre distance is |zb − 1.5|).
fn poses(bodies: &[BodyGeom], zb: f64, axis: Vector3<f64>, angle: f64) -> Vec<Isometry3<f64>> {
    let a = bodies[0].pose();
    let rb = UnitQuaternion::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle)
        * bodies[1].rotation;
    let b = Isometry3::from_parts(Translation3::new(0.2, 0.2, zb), rb);
    vec![a, b]
}

/// Bullet's view: enabled flags, updated by the actions (no impulse breaking here).
struct FakeBullet {
    enabled: RefCell<Vec<Vec<bool>>>,
}

impl FakeBullet {
    fn new(conns: &[ConnectionSpec]) -> Self {
        FakeBullet {
            enabled: RefCell::new(
                conns
                    .iter()
                    .map(|c| c.constraints.iter().map(|k| k.enabled).collect())
                    .collect(),
            ),
        }
    }
    fn frame(&self, m: &mut Monitor, poses: &[Isometry3<f64>]) -> Vec<Action> {
        let snapshot = self.enabled.borrow().clone();
        let actions = m.check(poses, |c, k| snapshot[c][k]).unwrap();
        for a in &actions {
            self.enabled.borrow_mut()[a.connection][a.constraint] = a.enable;
        }
        actions
    }
}

fn to_plastic_actions() -> Vec<Action> {
    let mut v: Vec<Action> = (0..6)
        .map(|k| Action {
            connection: 0,
            constraint: k,
            enable: false,
        })
        .collect();
    v.push(Action {
        connection: 0,
        constraint: 6,
        enable: true,
    });
    v
}

const D0: f64 = 3.0;
const ZA: f64 = 1.5;

#[test]
fn distance_switches_at_tol1_then_tol2() {
    let (bodies, conns) = setup(beam_group(), UnitQuaternion::identity());
    let mut m = Monitor::new(
        &conns,
        &bodies.iter().map(BodyGeom::pose).collect::<Vec<_>>(),
        &[ConnectionState::Elastic],
        AngleRule::RelativeRotation,
    )
    .unwrap();
    let bullet = FakeBullet::new(&conns);
    let z = Vector3::z();
    // distDif = 1 − 3/d crosses 0.1 at d = 3/0.9 = 3.3333…
    let d_switch = D0 / 0.9;
    let below = poses(&bodies, ZA + d_switch - 1e-6, z, 0.0);
    assert!(bullet.frame(&mut m, &below).is_empty());
    assert_eq!(m.state(0), ConnectionState::Elastic);
    let dd = m.deformation(0, &below);
    assert!(dd.dist_dif < 0.1 && dd.dist_dif > 0.1 - 1e-6);
    let d1 = d_switch + 1e-6;
    let above = poses(&bodies, ZA + d1, z, 0.0);
    assert_eq!(bullet.frame(&mut m, &above), to_plastic_actions());
    assert_eq!(m.state(0), ConnectionState::Plastic);
    // d₀ := d at the switch; broken when 1 − d1/d > 0.12, i.e. d > d1/0.88.
    let d_break = d1 / 0.88;
    assert!(bullet
        .frame(&mut m, &poses(&bodies, ZA + d_break - 1e-6, z, 0.0))
        .is_empty());
    assert_eq!(m.state(0), ConnectionState::Plastic);
    let acts = bullet.frame(&mut m, &poses(&bodies, ZA + d_break + 1e-6, z, 0.0));
    assert_eq!(
        acts,
        vec![Action {
            connection: 0,
            constraint: 6,
            enable: false
        }]
    );
    assert_eq!(m.state(0), ConnectionState::Broken);
    // Broken stays broken; compression counts too (|1 − d₀/d| for d < d₀).
    assert!(bullet
        .frame(&mut m, &poses(&bodies, ZA + 1.0, z, 0.0))
        .is_empty());
    let c = m.counts();
    assert_eq!((c.elastic, c.plastic, c.broken), (0, 0, 1));
}

#[test]
fn compression_also_counts() {
    let (bodies, conns) = setup(beam_group(), UnitQuaternion::identity());
    let refp: Vec<_> = bodies.iter().map(BodyGeom::pose).collect();
    let mut m = Monitor::new(
        &conns,
        &refp,
        &[ConnectionState::Elastic],
        AngleRule::default(),
    )
    .unwrap();
    let bullet = FakeBullet::new(&conns);
    // |1 − 3/d| > 0.1 for d < 3/1.1 = 2.7273.
    let d = D0 / 1.1;
    assert!(bullet
        .frame(&mut m, &poses(&bodies, ZA + d + 1e-6, Vector3::z(), 0.0))
        .is_empty());
    assert_eq!(
        bullet.frame(&mut m, &poses(&bodies, ZA + d - 1e-6, Vector3::z(), 0.0)),
        to_plastic_actions()
    );
}

#[test]
fn rotation_switches_at_tol1r_then_half_angle_at_tol2r() {
    let (bodies, conns) = setup(beam_group(), UnitQuaternion::identity());
    let refp: Vec<_> = bodies.iter().map(BodyGeom::pose).collect();
    let mut m = Monitor::new(
        &conns,
        &refp,
        &[ConnectionState::Elastic],
        AngleRule::default(),
    )
    .unwrap();
    let bullet = FakeBullet::new(&conns);
    let x = Vector3::x();
    let zb = ZA + D0;
    assert!(bullet
        .frame(&mut m, &poses(&bodies, zb, x, 0.2 - 1e-9))
        .is_empty());
    assert_eq!(
        bullet.frame(&mut m, &poses(&bodies, zb, x, 0.2 + 1e-9)),
        to_plastic_actions()
    );
    // Plastic: anglDif = asin(sin(Δ/2)) = Δ/2 against tol2R = atan(1.8).
    let tol2r = 1.8f64.atan();
    assert!((conns[0].tolerances.rot2.unwrap() - tol2r).abs() < 1e-15);
    let p = poses(&bodies, zb, x, 2.0 * tol2r - 1e-6);
    assert!(bullet.frame(&mut m, &p).is_empty());
    assert!((m.deformation(0, &p).angl_dif - (tol2r - 5e-7)).abs() < 1e-9);
    assert_eq!(
        bullet
            .frame(&mut m, &poses(&bodies, zb, x, 2.0 * tol2r + 1e-6))
            .len(),
        1
    );
    assert_eq!(m.state(0), ConnectionState::Broken);
}

/// distDif > tol1D + anglDif/π: with 0.15 rad of rotation the distance limit is
/// 0.1 + 0.15/π = 0.147746.
#[test]
fn combined_distance_and_angle_rule() {
    let (bodies, conns) = setup(beam_group(), UnitQuaternion::identity());
    let refp: Vec<_> = bodies.iter().map(BodyGeom::pose).collect();
    let lim = 0.1 + 0.15 / PI;
    for (dist_dif, expect) in [
        (lim - 1e-7, ConnectionState::Elastic),
        (lim + 1e-7, ConnectionState::Plastic),
    ] {
        let mut m = Monitor::new(
            &conns,
            &refp,
            &[ConnectionState::Elastic],
            AngleRule::default(),
        )
        .unwrap();
        let bullet = FakeBullet::new(&conns);
        let d = D0 / (1.0 - dist_dif);
        bullet.frame(&mut m, &poses(&bodies, ZA + d, Vector3::y(), 0.15));
        assert_eq!(m.state(0), expect, "distDif {dist_dif}");
    }
}

/// Bullet breaking: all six generics broken → broken (no actions); a broken spring while
/// plastic → broken. Some generics broken: the tolerance switch still disables the rest.
#[test]
fn impulse_breaking_feedback() {
    let (bodies, conns) = setup(beam_group(), UnitQuaternion::identity());
    let refp: Vec<_> = bodies.iter().map(BodyGeom::pose).collect();
    let still = poses(&bodies, ZA + D0, Vector3::z(), 0.0);
    let mut m = Monitor::new(
        &conns,
        &refp,
        &[ConnectionState::Elastic],
        AngleRule::default(),
    )
    .unwrap();
    assert!(m.check(&still, |_, _| false).unwrap().is_empty());
    assert_eq!(m.state(0), ConnectionState::Broken);

    let mut m = Monitor::new(
        &conns,
        &refp,
        &[ConnectionState::Elastic],
        AngleRule::default(),
    )
    .unwrap();
    // Tension (1) and shear-h (2) already broke; then the distance tolerance trips.
    let pulled = poses(&bodies, ZA + D0 / 0.85, Vector3::z(), 0.0);
    let acts = m
        .check(&pulled, |_, k| !(k == 1 || k == 2 || k == 6))
        .unwrap();
    let disabled: Vec<usize> = acts
        .iter()
        .filter(|a| !a.enable)
        .map(|a| a.constraint)
        .collect();
    assert_eq!(disabled, vec![0, 3, 4, 5]);
    assert!(acts.contains(&Action {
        connection: 0,
        constraint: 6,
        enable: true
    }));
    assert_eq!(
        m.last_changes(),
        &[StateChange {
            connection: 0,
            from: ConnectionState::Elastic,
            to: ConnectionState::Plastic
        }]
    );
    // Spring broken by impulse next frame: no action, but a recorded change.
    assert!(m.check(&pulled, |_, _| false).unwrap().is_empty());
    assert_eq!(m.state(0), ConnectionState::Broken);
    assert_eq!(
        m.last_changes(),
        &[StateChange {
            connection: 0,
            from: ConnectionState::Plastic,
            to: ConnectionState::Broken
        }]
    );
    assert!(m.check(&pulled, |_, _| false).unwrap().is_empty());
    assert!(m.last_changes().is_empty());
}

/// Hand-off: FE damage at Tc sets the starting state; the reference is the pose at Tc.
#[test]
fn starting_state_from_fe_damage() {
    assert_eq!(
        start_state_from_damage(FeDamage::Intact),
        ConnectionState::Elastic
    );
    assert_eq!(
        start_state_from_damage(FeDamage::Yielded),
        ConnectionState::Plastic
    );
    assert_eq!(
        start_state_from_damage(FeDamage::Ruptured),
        ConnectionState::Broken
    );

    let (bodies, mut conns) = setup(beam_group(), UnitQuaternion::identity());
    let mut c2 = conns[0].clone();
    conns[0].set_state(ConnectionState::Plastic);
    let flags: Vec<bool> = conns[0].constraints.iter().map(|k| k.enabled).collect();
    assert_eq!(flags, vec![false, false, false, false, false, false, true]);
    c2.set_state(ConnectionState::Broken);
    assert!(c2.constraints.iter().all(|k| !k.enabled));

    // Reference at a "Tc" pose with B already 0.2 m higher: d₀ = 3.2.
    let tc = poses(&bodies, ZA + 3.2, Vector3::z(), 0.0);
    let mut m = Monitor::new(
        &conns,
        &tc,
        &[ConnectionState::Plastic],
        AngleRule::default(),
    )
    .unwrap();
    let bullet = FakeBullet::new(&conns);
    let d_break = 3.2 / 0.88;
    assert!(bullet
        .frame(
            &mut m,
            &poses(&bodies, ZA + d_break - 1e-6, Vector3::z(), 0.0)
        )
        .is_empty());
    assert_eq!(
        bullet
            .frame(
                &mut m,
                &poses(&bodies, ZA + d_break + 1e-6, Vector3::z(), 0.0)
            )
            .len(),
        1
    );

    let mut m = Monitor::new(&[c2], &tc, &[ConnectionState::Broken], AngleRule::default()).unwrap();
    assert!(m.check(&tc, |_, _| false).unwrap().is_empty());
    assert_eq!(m.counts().broken, 1);
}

/// A group without a plastic value has no spring: the first tolerance breaks it outright.
#[test]
fn no_spring_breaks_at_first_tolerance() {
    let g = GroupStrength {
        name: "g".into(),
        strength: StrengthSource::PerArea(StrengthPerArea {
            p: None,
            ..StrengthPerArea::bcb_default_preset()
        }),
        ..beam_group()
    };
    let (bodies, conns) = setup(g, UnitQuaternion::identity());
    assert_eq!(conns[0].constraints.len(), 6);
    let refp: Vec<_> = bodies.iter().map(BodyGeom::pose).collect();
    let mut m = Monitor::new(
        &conns,
        &refp,
        &[ConnectionState::Elastic],
        AngleRule::default(),
    )
    .unwrap();
    let acts = m
        .check(
            &poses(&bodies, ZA + D0 / 0.85, Vector3::z(), 0.0),
            |_, _| true,
        )
        .unwrap();
    assert_eq!(acts.len(), 6);
    assert!(acts.iter().all(|a| !a.enable));
    assert_eq!(m.state(0), ConnectionState::Broken);
}

/// BCB's own angle measure (z-axis angle) vs the relative-rotation default: a body turned
/// 90° about z from the start looks deformed to BCB's rule, and twist about z is unseen.
#[test]
fn bcb_z_axis_rule_quirks() {
    let turned = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), FRAC_PI_2);
    let (bodies, conns) = setup(beam_group(), turned);
    let refp: Vec<_> = bodies.iter().map(BodyGeom::pose).collect();
    let mut rel = Monitor::new(
        &conns,
        &refp,
        &[ConnectionState::Elastic],
        AngleRule::RelativeRotation,
    )
    .unwrap();
    let mut bcb = Monitor::new(
        &conns,
        &refp,
        &[ConnectionState::Elastic],
        AngleRule::BcbZAxis,
    )
    .unwrap();
    assert!(rel.check(&refp, |_, _| true).unwrap().is_empty());
    assert!((bcb.deformation(0, &refp).angl_dif - FRAC_PI_2).abs() < 1e-12);
    assert_eq!(bcb.check(&refp, |_, _| true).unwrap().len(), 7);

    let (bodies, conns) = setup(beam_group(), UnitQuaternion::identity());
    let refp: Vec<_> = bodies.iter().map(BodyGeom::pose).collect();
    let twist = poses(&bodies, ZA + D0, Vector3::z(), 0.3);
    let mut rel = Monitor::new(
        &conns,
        &refp,
        &[ConnectionState::Elastic],
        AngleRule::RelativeRotation,
    )
    .unwrap();
    let mut bcb = Monitor::new(
        &conns,
        &refp,
        &[ConnectionState::Elastic],
        AngleRule::BcbZAxis,
    )
    .unwrap();
    assert_eq!(rel.check(&twist, |_, _| true).unwrap().len(), 7);
    assert!(bcb.check(&twist, |_, _| true).unwrap().is_empty());
    // Bending about x is seen by both at the same angle (fresh, elastic monitors).
    let rel = Monitor::new(
        &conns,
        &refp,
        &[ConnectionState::Elastic],
        AngleRule::RelativeRotation,
    )
    .unwrap();
    let bcb = Monitor::new(
        &conns,
        &refp,
        &[ConnectionState::Elastic],
        AngleRule::BcbZAxis,
    )
    .unwrap();
    let bend = poses(&bodies, ZA + D0, Vector3::x(), 0.25);
    assert!((bcb.deformation(0, &bend).angl_dif - 0.25).abs() < 1e-12);
    assert!((rel.deformation(0, &bend).angl_dif - 0.25).abs() < 1e-12);
}

#[test]
fn length_mismatch_is_an_error() {
    let (bodies, conns) = setup(beam_group(), UnitQuaternion::identity());
    let refp: Vec<_> = bodies.iter().map(BodyGeom::pose).collect();
    let err = Monitor::new(&conns, &refp, &[], AngleRule::default()).unwrap_err();
    assert_eq!(
        err.to_string(),
        "monitor starting states: expected 1 entries, got 0"
    );
    let mut m = Monitor::new(
        &conns,
        &refp,
        &[ConnectionState::Elastic],
        AngleRule::default(),
    )
    .unwrap();
    assert!(m.check(&refp[..1], |_, _| true).is_err());
}
