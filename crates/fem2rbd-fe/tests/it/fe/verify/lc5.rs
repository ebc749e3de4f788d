//! frame3 LC5 (El Centro at 0.93 / 1.19 / 0.57 g), displacement-based variant, against
//! OpenSees 3.7.1 (results.md §4, `tests/fixtures/opensees-frame3/LC5_disp_ts1.*`):
//! first times the roof drift passes 5 % and 10 % (corner column line: node 301 over
//! base node 1, SRSS of X and Y, over 3.0 m; OpenSees 2.39 s and 3.57 s) and the
//! collapse time Tc, the first step at which any non-base node has uz < −0.25 m
//! (OpenSees 4.735 s). Each within 5 %. The run stops at Tc through the observer (the
//! collapse criterion as a [`StepControl::Stop`]).
use super::support as fe_verify_support;

use fe_verify_support::*;
use fem2rbd_fe::fe::analysis::transient::StopReason;
use fem2rbd_fe::fe::build::Variant;

/// Runs LC5 disp to `t_end` (or Tc); returns (t5, t10, Tc).
fn lc5(t_end: f64) -> (Option<f64>, Option<f64>, Option<f64>) {
    let model = frame3();
    let gm = el_centro(LC5);
    let fixed: std::collections::BTreeSet<u32> = model.fixity().keys().copied().collect();
    // The built domain numbers nodes in model order.
    let free: Vec<usize> = model
        .nodes
        .iter()
        .enumerate()
        .filter(|(_, n)| !fixed.contains(&n.tag))
        .map(|(i, _)| i)
        .collect();
    let r = run(
        &model,
        &gm,
        Variant::Disp,
        t_end,
        &[301, 1, 312],
        &mut |d| free.iter().any(|&i| d.displacement(i)[2] < -0.25),
    );
    let h = &r.transient.history;
    let mut t5 = None;
    let mut t10 = None;
    for (k, &t) in h.time.iter().enumerate() {
        let (a, b) = (h.disp[k][0], h.disp[k][1]);
        let drift = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt() / 3.0;
        if t5.is_none() && drift > 0.05 {
            t5 = Some(t);
        }
        if t10.is_none() && drift > 0.10 {
            t10 = Some(t);
        }
    }
    // Roof-centre node 312 against the OpenSees series at a few times.
    let (_, rows) = read_csv(&fixture("LC5_disp_ts1.csv"));
    let tr: Vec<f64> = rows.iter().map(|v| v[0]).collect();
    for ts in [2.0, 2.2, 2.4, 2.7, 3.0, 3.6, 4.2, 4.7] {
        if ts > *h.time.last().unwrap() {
            break;
        }
        let ours = |j: usize| {
            at(
                &h.time,
                &h.disp.iter().map(|d| d[2][j]).collect::<Vec<_>>(),
                ts,
            )
        };
        let theirs = |j: usize| at(&tr, &rows.iter().map(|v| v[1 + j]).collect::<Vec<_>>(), ts);
        eprintln!(
            "LC5 disp t = {ts} s: node 312 ux/uy/uz = {:+.4}/{:+.4}/{:+.4} m, OpenSees {:+.4}/{:+.4}/{:+.4} m",
            ours(0), ours(1), ours(2), theirs(0), theirs(1), theirs(2)
        );
    }
    let tc = match r.transient.stop {
        StopReason::Stopped { time } => Some(time),
        _ => None,
    };
    eprintln!(
        "LC5 disp: t(5 %) = {t5:?} s (OpenSees 2.39), t(10 %) = {t10:?} s (OpenSees 3.57), Tc = {tc:?} s (OpenSees 4.735); {} steps, {} fallback steps",
        r.transient.steps, r.transient.fallback_steps
    );
    (t5, t10, tc)
}

fn within(x: Option<f64>, reference: f64, what: &str) {
    let x = x.unwrap_or_else(|| panic!("{what} not reached"));
    let rel = (x - reference) / reference;
    eprintln!(
        "{what}: {x:.3} s vs OpenSees {reference} s, diff {:+.2} %",
        rel * 100.0
    );
    assert!(rel.abs() < 0.05, "{what}: {x} s vs {reference} s");
}

/// CI: the run to 4.0 s (past the 10 % drift time).
#[test]
fn lc5_disp_times_to_5_and_10_percent_drift() {
    let (t5, t10, _) = lc5(4.0);
    within(t5, 2.39, "time to 5 % roof drift");
    within(t10, 3.57, "time to 10 % roof drift");
}

/// The collapse time (0.25 m drop; OpenSees 4.735 s). Before the displacement-based
/// corotational beams' β·K0 damping followed the trial geometry as in OpenSees
/// (`DispBeamColumn3d::getInitialStiff`; docs/fe-verification.md), the history left
/// OpenSees's at about 1.55 s and the drop was not reached by 5.5 s.
#[test]
fn lc5_disp_collapse_time() {
    let (_, _, tc) = lc5(5.5);
    within(tc, 4.735, "Tc (uz < -0.25 m)");
}

/// LC5 force-based, first 3.0 s (roof drift past 5 %; OpenSees first passes 5 % at
/// 2.26 s): node 312 ux, uy, uz every step against OpenSees
/// (`LC5_force_first4s.csv`, from `out/LC5_force_ts1.csv`), within 2 % of OpenSees's
/// peak |u| of the window, and the time to 5 % drift within 5 %. Unlike the disp
/// variant, this one stays on OpenSees's path through the large inelastic cycles.
#[test]
fn lc5_force_history_first_3s() {
    let t_end = 3.0;
    let model = frame3();
    let gm = el_centro(LC5);
    let r = run(
        &model,
        &gm,
        Variant::Force,
        t_end,
        &[312, 301, 1],
        &mut |_| false,
    );
    let h = &r.transient.history;
    let (_, rows) = read_csv(&fixture("LC5_force_first4s.csv"));
    let rows: Vec<&Vec<f64>> = rows.iter().filter(|v| v[0] <= t_end + 1e-9).collect();
    let mut t5 = None;
    for (k, &t) in h.time.iter().enumerate() {
        let (a, b) = (h.disp[k][1], h.disp[k][2]);
        let drift = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt() / 3.0;
        if t5.is_none() && drift > 0.05 {
            t5 = Some(t);
        }
    }
    for c in 0..3 {
        let peak = rows.iter().map(|v| v[1 + c].abs()).fold(0.0, f64::max);
        let ours: Vec<f64> = h.disp.iter().map(|d| d[0][c]).collect();
        let worst = rows
            .iter()
            .map(|v| (at(&h.time, &ours, v[0]) - v[1 + c]).abs())
            .fold(0.0, f64::max);
        eprintln!(
            "LC5 force 0–{t_end} s node 312 {}: max |Δ| = {:.3} mm = {:.3} % of the peak {:.1} mm",
            ["ux", "uy", "uz"][c],
            worst * 1e3,
            worst / peak * 100.0,
            peak * 1e3
        );
        assert!(worst < 0.02 * peak, "component {c}: {worst} vs peak {peak}");
    }
    within(t5, 2.26, "LC5 force: time to 5 % roof drift");
}
