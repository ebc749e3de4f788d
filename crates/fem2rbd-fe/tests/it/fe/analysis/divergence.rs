//! Non-convergence paths of the transient analysis: elements that fail on purpose
//! (an ElementError, NaN forces, a wrong tangent) drive the fallback chain; an
//! unrecoverable failure is a clean, reported stop that keeps the last converged
//! state; no NaN reaches the recorded histories.
use super::support as fe_analysis_support;

use std::f64::consts::PI;

use fe_analysis_support::{square, ElasticFrame, FailMode, Failing};
use fem2rbd_fe::fe::analysis::transient::{
    run_transient, StepControl, StepInfo, StopReason, TransientResult, TransientSettings,
};
use fem2rbd_fe::fe::domain::Domain;

const L: f64 = 2.0;
const M: f64 = 1000.0;

fn column(mode: Option<FailMode>) -> Domain {
    let mut d = Domain::new();
    d.add_node(1, [0.0, 0.0, 0.0]).unwrap();
    d.add_node(2, [0.0, 0.0, L]).unwrap();
    d.fix(0, [true; 6]).unwrap();
    d.set_mass(1, [M, M, 0.0, 0.0, 0.0, 0.0]).unwrap();
    let el = ElasticFrame::new(1, &d, 0, 1, [1.0, 0.0, 0.0], square(25e9, 0.1));
    match mode {
        None => d.add_element(Box::new(el)).unwrap(),
        Some(m) => d.add_element(Box::new(Failing::new(el, m))).unwrap(),
    };
    d
}

/// Growing harmonic base motion in X and Y: the response passes any limit at some time.
fn ground(t: f64) -> [f64; 3] {
    let a = 2.0 * t * (2.0 * PI * 2.0 * t).sin();
    [a, 0.5 * a, 0.0]
}

fn run(mode: Option<FailMode>, observed: &mut Vec<StepInfo>) -> (TransientResult, Domain) {
    let mut d = column(mode);
    // Without element removal: the failing element's step is the end of the run.
    let s = TransientSettings {
        dt: 0.01,
        t_end: 3.0,
        remove_failed_elements: false,
        ..Default::default()
    };
    let res = run_transient(&mut d, None, &ground, &s, &mut |info, _| {
        observed.push(*info);
        StepControl::Continue
    })
    .unwrap();
    (res, d)
}

fn check_clean_stop(mode: FailMode, limit: f64) {
    let (reference, _) = run(None, &mut Vec::new());
    assert_eq!(reference.stop, StopReason::Completed);
    // First recorded step at which the tip displacement (any component, incl. the
    // rotation) exceeds the limit in the unrestricted run.
    let first = reference
        .history
        .disp
        .iter()
        .position(|r| r[1].iter().any(|x| x.abs() > limit))
        .expect("reference run passes the limit");
    let t_prev = reference.history.time[first - 1];
    let t_fail = reference.history.time[first];
    let mut observed = Vec::new();
    let (res, d) = run(Some(mode), &mut observed);
    let StopReason::Diverged {
        time,
        attempted,
        reason,
    } = &res.stop
    else {
        panic!("expected a divergence stop, got {:?}", res.stop)
    };
    eprintln!("{mode:?}: stop at {time} (attempted {attempted}), reference passes the limit at {t_fail}: {reason}");
    // The stop is inside the step where the limit is crossed; sub-steps that
    // converged before the crossing are kept.
    assert!(
        *time >= t_prev - 1e-12 && *time < t_fail,
        "{time} not in [{t_prev}, {t_fail})"
    );
    assert!((attempted - t_fail).abs() < 1e-9, "{attempted}");
    assert_eq!(res.end_time, *time);
    assert_eq!(d.time(), *time);
    // Every fallback was tried: the last one is the line search.
    assert!(!reason.is_empty());
    // The last converged state is kept and is within the limit; no NaN anywhere.
    let u = d.displacement(1);
    assert!(u.iter().all(|x| x.is_finite() && x.abs() <= limit), "{u:?}");
    for rec in res
        .history
        .disp
        .iter()
        .chain(&res.history.vel)
        .chain(&res.history.acc)
    {
        assert!(rec.iter().flatten().all(|x| x.is_finite()));
    }
    assert_eq!(*res.history.time.last().unwrap(), *time);
    assert_eq!(res.history.disp.last().unwrap()[1], u);
    // Up to the step before the crossing the run is the reference run, bit for bit
    // close (same arithmetic).
    for k in 0..first {
        for c in 0..6 {
            let (a, b) = (res.history.disp[k][1][c], reference.history.disp[k][1][c]);
            assert!(
                (a - b).abs() <= 1e-12 * limit,
                "record {k} dof {c}: {a} vs {b}"
            );
        }
    }
    assert_eq!(res.steps, first - 1);
    assert_eq!(observed.len(), res.steps);
}

#[test]
fn element_error_is_a_clean_stop() {
    check_clean_stop(FailMode::ErrorBeyond(0.02), 0.02);
}

#[test]
fn nan_force_is_a_clean_stop() {
    check_clean_stop(FailMode::NanBeyond(0.02), 0.02);
}

/// A NaN tangent: Newton (regular and fallback), Krylov-Newton and the line search
/// fail at once on a non-finite matrix; the initial-stiffness modified Newton fallback
/// converges on every step; the result equals the reference run (linear problem, so
/// modified Newton with the exact initial stiffness converges like Newton).
#[test]
fn nan_tangent_is_rescued_by_fallbacks() {
    let (reference, _) = run(None, &mut Vec::new());
    let mut observed = Vec::new();
    let (res, _) = run(Some(FailMode::NanTangent), &mut observed);
    assert_eq!(res.stop, StopReason::Completed);
    assert_eq!(res.steps, reference.steps);
    eprintln!("fallback steps {} of {}", res.fallback_steps, res.steps);
    assert_eq!(res.fallback_steps, res.steps);
    assert_eq!(
        observed.iter().filter(|s| s.used_fallback).count(),
        res.fallback_steps
    );
    let peak = reference
        .history
        .disp
        .iter()
        .fold(0.0f64, |p, r| p.max(r[1][0].abs()));
    let mut diff: f64 = 0.0;
    for (a, b) in res.history.disp.iter().zip(&reference.history.disp) {
        for c in 0..6 {
            diff = diff.max((a[1][c] - b[1][c]).abs());
        }
    }
    eprintln!("max |Δu| vs reference {diff:e} m, peak {peak:e} m");
    assert!(diff < 1e-7 * peak, "{diff} vs peak {peak}");
}

/// The observer can stop the run (e.g. a collapse criterion); the stop is reported.
#[test]
fn observer_stop() {
    let mut d = column(None);
    let mut s = TransientSettings {
        dt: 0.01,
        t_end: 3.0,
        ..Default::default()
    };
    s.record.every = 7;
    s.record.element_damage = true;
    let res = run_transient(&mut d, None, &ground, &s, &mut |info, dom| {
        if dom.displacement(1)[0].abs() > 0.01 || info.step == 1000 {
            StepControl::Stop
        } else {
            StepControl::Continue
        }
    })
    .unwrap();
    let StopReason::Stopped { time } = res.stop else {
        panic!("{:?}", res.stop)
    };
    assert!(d.displacement(1)[0].abs() > 0.01);
    assert!((time - res.steps as f64 * 0.01).abs() < 1e-9 && time < 3.0);
    // Records: t = 0, every 7th step, and the final state.
    let expect = 1 + res.steps / 7 + usize::from(res.steps % 7 != 0);
    assert_eq!(res.history.time.len(), expect);
    assert_eq!(res.history.damage.len(), expect);
    assert!(res
        .history
        .damage
        .iter()
        .all(|r| r.len() == 1 && !r[0].yielded));
    assert_eq!(*res.history.time.last().unwrap(), time);
}
