//! Element removal in the transient analysis: an element whose state determination fails
//! in a step no fallback can make converge is removed (no force, no stiffness, its mass
//! kept on the nodes) and the step is repeated. Checked against closed forms: the period
//! and base shear of a portal frame before and after one column is removed, the free
//! flight of a node left without elements, and the vertical-drop criterion reached where
//! the run without removal stops at the failure.
use super::support as fe_analysis_support;

use std::f64::consts::PI;

use fe_analysis_support::{ElasticFrame, FailMode, Failing, Props};
use fem2rbd_fe::fe::analysis::transient::{
    run_transient, StepControl, StopReason, TransientResult, TransientSettings,
};
use fem2rbd_fe::fe::domain::{Domain, DomainError};
use serde_json::json;

/// Column height, bay width (m), floor mass per top node (kg), E (Pa).
const H: f64 = 3.0;
const BAY: f64 = 4.0;
const M: f64 = 10_000.0;
const E: f64 = 30e9;
const G: f64 = 9.81;

/// 0.4 m square column's bending properties with a cross-section area 1 000 times the real
/// one: the members are axially rigid (EA/L ≥ 10⁵ × the lateral stiffness), as the closed
/// forms assume.
fn props() -> Props {
    let b: f64 = 0.4;
    let i = b.powi(4) / 12.0;
    Props {
        e: E,
        g: E / 2.4,
        a: 1000.0 * b * b,
        iy: i,
        iz: i,
        j: 0.1406 * b.powi(4),
    }
}

/// A one-bay portal in the X–Z plane: columns 1 (nodes 1–3, x = 0) and 2 (nodes 2–4,
/// x = BAY), beam 3 (nodes 3–4) with the columns' section; bases fixed; each top node
/// carries M in X and Y (no vertical or rotational mass). Column 1 fails beyond `limit`.
fn portal(limit: Option<f64>) -> Domain {
    let mut d = Domain::new();
    for (tag, c) in [
        (1, [0.0, 0.0, 0.0]),
        (2, [BAY, 0.0, 0.0]),
        (3, [0.0, 0.0, H]),
        (4, [BAY, 0.0, H]),
    ] {
        d.add_node(tag, c).unwrap();
    }
    d.fix(0, [true; 6]).unwrap();
    d.fix(1, [true; 6]).unwrap();
    for n in [2, 3] {
        d.set_mass(n, [M, M, 0.0, 0.0, 0.0, 0.0]).unwrap();
    }
    let p = props();
    let col1 = ElasticFrame::new(1, &d, 0, 2, [1.0, 0.0, 0.0], p);
    match limit {
        Some(l) => d
            .add_element(Box::new(Failing::new(col1, FailMode::ErrorBeyond(l))))
            .unwrap(),
        None => d.add_element(Box::new(col1)).unwrap(),
    };
    d.add_element(Box::new(ElasticFrame::new(2, &d, 1, 3, [1.0, 0.0, 0.0], p)))
        .unwrap();
    d.add_element(Box::new(ElasticFrame::new(3, &d, 2, 3, [0.0, 0.0, 1.0], p)))
        .unwrap();
    d
}

/// A half-sine ground pulse in X (0.1 s, 10 m/s²), then still ground: free vibration.
fn pulse(t: f64) -> [f64; 3] {
    let a = if t < 0.1 {
        10.0 * (PI * t / 0.1).sin()
    } else {
        0.0
    };
    [a, 0.0, 0.0]
}

fn run(d: &mut Domain, ground: &dyn Fn(f64) -> [f64; 3], dt: f64, t_end: f64) -> TransientResult {
    let s = TransientSettings {
        dt,
        t_end,
        ..Default::default()
    };
    run_transient(d, None, ground, &s, &mut |_, _| StepControl::Continue).unwrap()
}

/// Period from the upward zero crossings of a recorded series after `from` (linear
/// interpolation between records): mean spacing of the first and last crossing.
fn period(times: &[f64], u: &[f64], from: f64) -> f64 {
    let mut crossings = Vec::new();
    for k in 1..u.len() {
        if times[k - 1] >= from && u[k - 1] < 0.0 && u[k] >= 0.0 {
            let s = u[k - 1] / (u[k - 1] - u[k]);
            crossings.push(times[k - 1] + s * (times[k] - times[k - 1]));
        }
    }
    assert!(crossings.len() >= 4, "{} crossings", crossings.len());
    (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64
}

/// The period Newmark's average acceleration gives a linear oscillator of period `t` at
/// step `dt`: ω̄Δt = 2·atan(ωΔt/2) (Hughes, The Finite Element Method, §9.3).
fn newmark_period(t: f64, dt: f64) -> f64 {
    let w = 2.0 * PI / t;
    2.0 * PI * dt / (2.0 * (w * dt / 2.0).atan())
}

/// Lateral stiffness of the portal (slope deflection, axially rigid members, equal
/// joint rotations in sway): k = (24 EI_c/h³)·(c + 6b)/(4c + 6b), c = EI_c/h, b = EI_b/L
/// (Chopra, Dynamics of Structures, Eq. 1.3.5, with ρ = b/(2c)). Of a fixed-base
/// column with a free top rotation (a cantilever): k = 3EI/h³.
fn stiffness_portal() -> f64 {
    let ei = E * props().iz;
    let (c, b) = (ei / H, ei / BAY);
    24.0 * ei / H.powi(3) * (c + 6.0 * b) / (4.0 * c + 6.0 * b)
}
fn stiffness_cantilever() -> f64 {
    3.0 * E * props().iy / H.powi(3)
}

/// Column 1 fails when the sway passes 6 mm; it is removed at the step where the
/// unfailing portal first passes 6 mm, and the frame goes on as one cantilever column
/// carrying both floor masses (the beam turns freely at the removed column's top: no
/// vertical or rotational mass there). Before: T = 2π√(2M/k_portal) = 0.1465 s; after:
/// T = 2π√(2M h³/3EI) = 0.3332 s, each as Newmark's average acceleration lengthens it at
/// Δt = 1 ms (by 1.5·10⁻⁴ and 3·10⁻⁵). The remaining column's base shear is 3EI/h³ times its top's sway, the
/// removed column's base carries nothing, and the mass is where it was.
#[test]
fn portal_column_removed_leaves_a_cantilever() {
    let (dt, t_end, limit) = (0.001, 3.0, 0.006);
    let mut reference = portal(None);
    let r0 = run(&mut reference, &pulse, dt, t_end);
    assert_eq!(r0.stop, StopReason::Completed);
    assert!(r0.removed.is_empty());
    let ux = |r: &TransientResult, node: usize| -> Vec<f64> {
        r.history.disp.iter().map(|d| d[node][0]).collect()
    };
    let t0 = period(&r0.history.time, &ux(&r0, 3), 0.1);
    let t0_closed = newmark_period(2.0 * PI * (2.0 * M / stiffness_portal()).sqrt(), dt);
    eprintln!("portal: T = {t0:.7} s, closed form (Newmark) {t0_closed:.7} s");
    assert!((t0 / t0_closed - 1.0).abs() < 1e-5, "{t0} vs {t0_closed}");

    // Where the unfailing portal first passes the limit (any DOF of column 1's nodes).
    let first = r0
        .history
        .disp
        .iter()
        .position(|d| d[2].iter().any(|x| x.abs() > limit))
        .expect("the pulse passes the limit");
    let (t_prev, t_fail) = (r0.history.time[first - 1], r0.history.time[first]);

    let mut d = portal(Some(limit));
    let mass_before: Vec<[f64; 6]> = (0..4).map(|n| d.mass(n)).collect();
    let r1 = run(&mut d, &pulse, dt, t_end);
    assert_eq!(r1.stop, StopReason::Completed);
    assert_eq!(r1.removed.len(), 1);
    let removal = &r1.removed[0];
    eprintln!("removed {removal:?}; the reference passes the limit at {t_fail} s");
    assert_eq!(removal.element, 1);
    assert!((removal.attempted - t_fail).abs() < 1e-9);
    assert!(removal.time >= t_prev - 1e-12 && removal.time < t_fail);
    assert!(removal.reason.contains("limit"), "{}", removal.reason);
    let col1 = &d.elements()[0];
    assert_eq!(col1.removed_at(), Some(removal.time));
    assert!(col1.damage().ruptured);
    // Up to the removal the run is the reference run.
    for k in 0..first {
        assert_eq!(r1.history.disp[k], r0.history.disp[k], "record {k}");
    }

    // Mass: every nodal mass as before, the same total translational mass in the
    // equations (2M in X), no DOF held (every node still has an element or is fixed).
    for (n, m) in mass_before.iter().enumerate() {
        assert_eq!(d.mass(n), *m);
        assert_eq!(d.held(n), [false; 6]);
    }
    let iota = d.influence_vector(0);
    let mx: f64 = d
        .mass_diagonal()
        .iter()
        .zip(&iota)
        .map(|(m, i)| m * i)
        .sum();
    assert_eq!(mx, 2.0 * M);

    let t1 = period(&r1.history.time, &ux(&r1, 3), removal.attempted + 0.05);
    let t1_closed = newmark_period(2.0 * PI * (2.0 * M / stiffness_cantilever()).sqrt(), dt);
    eprintln!("one column: T = {t1:.7} s, closed form (Newmark) {t1_closed:.7} s");
    assert!((t1 / t1_closed - 1.0).abs() < 1e-5, "{t1} vs {t1_closed}");

    // Forces at the end: the remaining column is a cantilever, V = 3EI/h³ · Δ.
    let reactions = d.reactions();
    let base = |node: usize| reactions.iter().find(|(n, _)| *n == node).unwrap().1;
    let (r_removed, r_kept) = (base(0), base(1));
    assert!(r_removed.iter().all(|&x| x == 0.0), "{r_removed:?}");
    let sway = d.displacement(3)[0];
    let v = -r_kept[0];
    eprintln!(
        "base shear {v:.3} N at sway {sway:.6} m: k = {:.6e}",
        v / sway
    );
    assert!((v / (stiffness_cantilever() * sway) - 1.0).abs() < 1e-4);
    // Base moment of the cantilever: V·h (about −Y for a sway in +X).
    assert!((-r_kept[4] / (v * H) - 1.0).abs() < 1e-4, "{}", r_kept[4]);
}

const L_COL: f64 = 2.0;

/// A single column (node 1 fixed at the base, node 2 on top with mass M in X, Y and Z and
/// its weight M·g held constant) that fails beyond `limit`.
fn column(limit: f64) -> Domain {
    let mut d = Domain::new();
    d.add_node(1, [0.0, 0.0, 0.0]).unwrap();
    d.add_node(2, [0.0, 0.0, L_COL]).unwrap();
    d.fix(0, [true; 6]).unwrap();
    d.set_mass(1, [M, M, M, 0.0, 0.0, 0.0]).unwrap();
    d.add_nodal_load(1, [0.0, 0.0, -M * G, 0.0, 0.0, 0.0])
        .unwrap();
    d.set_load_factor(1.0);
    d.load_const();
    let el = ElasticFrame::new(1, &d, 0, 1, [1.0, 0.0, 0.0], props());
    d.add_element(Box::new(Failing::new(el, FailMode::ErrorBeyond(limit))))
        .unwrap();
    d
}

/// Growing harmonic ground motion in X and Y.
fn shaking(t: f64) -> [f64; 3] {
    let a = 4.0 * t * (2.0 * PI * 2.0 * t).sin();
    [a, 0.5 * a, 0.0]
}

/// The column's removal leaves its top node without elements: its rotations (no mass)
/// are held where they were and leave the equations; its translations keep their mass
/// and fly freely: relative acceleration −a_g in X and Y and −g in Z, which Newmark's
/// average acceleration integrates exactly.
#[test]
fn a_node_without_elements_flies_freely() {
    let mut d = column(0.001);
    let neq = {
        d.number_dofs();
        d.num_equations()
    };
    assert_eq!(neq, 6);
    let r = run(&mut d, &shaking, 0.005, 2.0);
    assert_eq!(r.stop, StopReason::Completed);
    assert_eq!(r.removed.len(), 1);
    let t_r = r.removed[0].time;
    assert_eq!(d.held(1), [false, false, false, true, true, true]);
    assert_eq!(d.num_equations(), 3);
    assert_eq!(d.mass(1), [M, M, M, 0.0, 0.0, 0.0]);
    // The state at the removal is recorded.
    let k_r = r
        .history
        .time
        .iter()
        .position(|&t| t == t_r)
        .expect("the removal state is recorded");
    let rot_at_removal = &r.history.disp[k_r][1][3..];
    let mut checked = 0;
    for k in k_r + 1..r.history.time.len() {
        let t = r.history.time[k];
        let ag = shaking(t);
        let a = r.history.acc[k][1];
        assert!(
            (a[0] + ag[0]).abs() < 1e-9,
            "t = {t}: {} vs {}",
            a[0],
            -ag[0]
        );
        assert!(
            (a[1] + ag[1]).abs() < 1e-9,
            "t = {t}: {} vs {}",
            a[1],
            -ag[1]
        );
        assert!((a[2] + G).abs() < 1e-9, "t = {t}: {}", a[2]);
        assert_eq!(&r.history.disp[k][1][3..], rot_at_removal);
        checked += 1;
    }
    assert!(checked > 100, "{checked}");
    // Free fall from the state one step after the removal (from there on ü = −g at both
    // ends of every step): uz(τ) = uz1 + vz1 τ − g τ²/2.
    let (uz0, vz0) = (r.history.disp[k_r + 1][1][2], r.history.vel[k_r + 1][1][2]);
    let t_last = *r.history.time.last().unwrap();
    let tau = t_last - r.history.time[k_r + 1];
    let uz = uz0 + vz0 * tau - 0.5 * G * tau * tau;
    assert!((d.displacement(1)[2] - uz).abs() < 1e-9 * uz.abs());
}

/// The vertical-drop criterion (a node 1 m down) observed after every step: without
/// removal the run ends at the column's failure (`Diverged`); with it the top node falls
/// and the criterion stops the run at the first step at which the free fall from the
/// removal state has passed 1 m.
#[test]
fn removal_reaches_the_drop_criterion_where_the_run_diverged() {
    let drop_m = 1.0;
    let go = |remove: bool| {
        let mut d = column(0.001);
        let s = TransientSettings {
            dt: 0.005,
            t_end: 5.0,
            remove_failed_elements: remove,
            ..Default::default()
        };
        let r = run_transient(&mut d, None, &shaking, &s, &mut |_, dom| {
            if -dom.displacement(1)[2] >= drop_m {
                StepControl::Stop
            } else {
                StepControl::Continue
            }
        })
        .unwrap();
        (r, d)
    };
    let (diverged, _) = go(false);
    let StopReason::Diverged { time: t_div, .. } = diverged.stop else {
        panic!("{:?}", diverged.stop)
    };
    let (r, d) = go(true);
    let StopReason::Stopped { time: t_stop } = r.stop else {
        panic!("{:?}", r.stop)
    };
    assert_eq!(r.removed.len(), 1);
    let t_r = r.removed[0].time;
    assert_eq!(t_r, t_div);
    // The state at the removal is the diverged run's last state.
    let k_r = r.history.time.iter().position(|&t| t == t_r).unwrap();
    assert_eq!(
        r.history.disp[k_r][1],
        diverged.history.disp.last().unwrap()[1]
    );
    // Free fall from one step after the removal (ü = −g at both ends of every step from
    // there): τ at which uz1 + vz1 τ − g τ²/2 = −1 m, then the first step end at or after.
    let t1 = r.history.time[k_r + 1];
    let (uz1, vz1) = (r.history.disp[k_r + 1][1][2], r.history.vel[k_r + 1][1][2]);
    let tau = (vz1 + (vz1 * vz1 + 2.0 * G * (uz1 + drop_m)).sqrt()) / G;
    let grid = |t: f64| (t / 0.005 - 1e-9).ceil() * 0.005;
    eprintln!("removed at {t_r} s; falls 1 m {tau:.4} s after {t1} s; stopped at {t_stop} s");
    assert!(
        (t_stop - grid(t1 + tau)).abs() < 1e-9,
        "{t_stop} vs {}",
        grid(t1 + tau)
    );
    assert!(t_stop > t_div + 0.4);
    assert!(-d.displacement(1)[2] >= drop_m);
}

/// Removal errors name the element: a second removal, an index out of range.
#[test]
fn removing_twice_or_out_of_range_is_an_error() {
    let mut d = portal(None);
    // Column 2's base (index 1) is left without elements; it is fixed, nothing is held.
    assert_eq!(d.remove_element(1), Ok(vec![1]));
    assert_eq!(d.held(1), [false; 6]);
    assert_eq!(d.remove_element(1), Err(DomainError::AlreadyRemoved(2)));
    assert_eq!(d.remove_element(7), Err(DomainError::ElementIndex(7)));
    // Removing the beam too leaves node 4 (index 3) without elements.
    assert_eq!(d.remove_element(2), Ok(vec![3]));
    assert_eq!(d.held(3), [false, false, true, true, true, true]);
}

/// The portal with column 1 removed after step 50 (t = 0.05 s, OpenSees' `remove element`
/// between two `analyze` calls) against openseespy 3.7.1 on the same model, pulse and
/// steps (`tests/opensees/portal_removal.py`): the sway of both top nodes over 1 s agrees
/// to 10⁻⁹ of its peak, before and after the removal.
#[test]
fn portal_removal_agrees_with_opensees() {
    let (dt, steps, remove_after) = (0.001, 1000, 50);
    let mut d = portal(None);
    let s = |t_end: f64| TransientSettings {
        dt,
        t_end,
        ..Default::default()
    };
    let before = run_transient(
        &mut d,
        None,
        &pulse,
        &s(remove_after as f64 * dt),
        &mut |_, _| StepControl::Continue,
    )
    .unwrap();
    d.remove_element(0).unwrap();
    let after = run_transient(&mut d, None, &pulse, &s(steps as f64 * dt), &mut |_, _| {
        StepControl::Continue
    })
    .unwrap();
    assert_eq!(after.stop, StopReason::Completed);
    let ours: Vec<(f64, [f64; 2])> = before
        .history
        .time
        .iter()
        .zip(&before.history.disp)
        .chain(after.history.time.iter().zip(&after.history.disp).skip(1))
        .map(|(t, u)| (*t, [u[2][0], u[3][0]]))
        .collect();
    assert_eq!(ours.len(), steps + 1);

    let p = props();
    let pr = json!({"A": p.a, "E": p.e, "G": p.g, "J": p.j, "Iy": p.iy, "Iz": p.iz});
    let case = json!({
        "nodes": [[0.0, 0.0, 0.0], [BAY, 0.0, 0.0], [0.0, 0.0, H], [BAY, 0.0, H]],
        "masses": [[3, [M, M, 0.0, 0.0, 0.0, 0.0]], [4, [M, M, 0.0, 0.0, 0.0, 0.0]]],
        "elements": [
            {"tag": 1, "nodes": [1, 3], "vecxz": [1.0, 0.0, 0.0], "props": pr},
            {"tag": 2, "nodes": [2, 4], "vecxz": [1.0, 0.0, 0.0], "props": pr},
            {"tag": 3, "nodes": [3, 4], "vecxz": [0.0, 0.0, 1.0], "props": pr},
        ],
        "dt": dt,
        "ag": (0..=steps).map(|k| pulse(k as f64 * dt)[0]).collect::<Vec<_>>(),
        "steps": steps,
        "remove_after": remove_after,
        "remove": 1,
    });
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("portal.json");
    std::fs::write(&path, case.to_string()).unwrap();
    let v = crate::openseespy_json(
        std::process::Command::new("python3")
            .arg(crate::repo_root().join("tests/opensees/portal_removal.py"))
            .arg(&path),
    );
    let t_ops: Vec<f64> = serde_json::from_value(v["t"].clone()).unwrap();
    let u_ops: Vec<[f64; 2]> = serde_json::from_value(v["ux"].clone()).unwrap();
    assert_eq!(t_ops.len(), ours.len());
    let peak = u_ops.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut worst: f64 = 0.0;
    for ((t, u), (to, uo)) in ours.iter().zip(t_ops.iter().zip(&u_ops)) {
        assert!((t - to).abs() < 1e-9, "{t} vs {to}");
        for c in 0..2 {
            worst = worst.max((u[c] - uo[c]).abs());
        }
    }
    eprintln!("peak sway {peak:.6e} m, largest difference {worst:.3e} m");
    assert!(peak > 0.01);
    assert!(worst < 1e-9 * peak, "{worst} vs peak {peak}");
}
