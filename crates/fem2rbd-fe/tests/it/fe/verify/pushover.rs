//! frame3 pushover in +X after gravity through [`run_pushover`], force-based (as
//! `pushover.py` of the OpenSees reference): the triangular pattern F = m·z at every
//! massed node above the base (z_base = 0), displacement control of the roof-centre node
//! 312 in X in 1 mm steps (NormDispIncr 1e-8, 100 iterations; initial-stiffness fallback,
//! the step split into 2, 4, 8 when it fails). W = g × total mass above the base
//! (9386.75 kg, 92.08 kN). OpenSees: peak V/W = 0.174 at 0.63 % roof drift
//! (`tests/fixtures/opensees-frame3/pushover_X_force.csv`). CI runs to 1.0 % roof drift
//! (30 steps). At 0.80 % Newton and modified Newton fail in both programs; fem2rbd's
//! fallbacks carry the curve on, as OpenSees's carry its. Up to 0.77 % the curve agrees
//! with OpenSees to 0.05 % of the peak (measured: to the reference's last digit); from
//! 0.80 % on the two settle on different equilibria of the softening frame (4.9 % of the
//! peak at 0.80 %, at most 1.7 % after, equal again at 0.97 %), asserted within 6 %.
//! The base shear compared is −ΣR_x of the support reactions, not λ: a wrong reaction
//! fails it.
use super::support as fe_verify_support;

use fe_verify_support::*;
use fem2rbd_fe::fe::analysis::ConvergenceTest;
use fem2rbd_fe::fe::build::{BuildOptions, Variant};
use fem2rbd_fe::fe::pushover::{
    cyclic_targets, run_pushover, LoadPattern, PushoverSettings, PushoverStop,
};

fn settings(variant: Variant, pattern: LoadPattern, targets: Vec<f64>) -> PushoverSettings {
    PushoverSettings {
        build: BuildOptions {
            variant,
            ..Default::default()
        },
        pattern,
        direction: 0,
        control_node: None,
        targets,
        increment: 0.001,
        modes: 3,
        test: ConvergenceTest {
            tol: 1e-8,
            max_iter: 100,
        },
    }
}

#[test]
fn pushover_force_peak_base_shear_within_5_percent() {
    let model = frame3();
    let h = 3.0;
    let r = run_pushover(
        &model,
        &settings(Variant::Force, LoadPattern::Triangular, vec![0.01 * h]),
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(r.control_node, 312, "the roof-centre node is the default");
    assert!((r.control_height - h).abs() < 1e-12);
    assert!(
        (r.weight - 9386.75 * model.gravity.g).abs() < 0.01 * model.gravity.g,
        "W = {}",
        r.weight
    );
    let curve: Vec<(f64, f64)> = r
        .curve
        .iter()
        .map(|p| (p.control_displacement / h, p.base_shear(0) / r.weight))
        .collect();
    let stopped_at = match r.stop {
        PushoverStop::Completed => None,
        PushoverStop::NotConverged { at, .. } => Some(at / h),
    };
    eprintln!(
        "pushover stopped at {stopped_at:?} (roof drift), {} points",
        curve.len()
    );
    let last_drift = curve.last().unwrap().0;
    assert!(
        last_drift > 0.0095,
        "pushover must pass the peak (0.63 %) and the Newton failure at 0.80 %, ended at \
         {last_drift}"
    );
    let (_, rows) = read_csv(&fixture("pushover_X_force.csv"));
    let dr: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    let vw: Vec<f64> = rows.iter().map(|r| r[1]).collect();
    // Up to 0.77 % Newton converges in both programs and they find the same equilibria:
    // the curves agree to 0.05 % of the peak. At 0.80 % Newton and modified Newton fail in
    // both; the fallbacks (fem2rbd: Krylov–Newton, line search, sub-steps; OpenSees: its
    // own ladder) settle there on equilibria of the softening frame that differ by 4.9 %
    // of the peak, and the paths stay apart by up to 1.7 % until they meet at 0.97 %.
    let mut max_diff = 0.0f64;
    let mut off = Vec::new();
    for &(x, v) in &curve[1..] {
        let v_ref = at(&dr, &vw, x);
        let d = (v - v_ref).abs();
        max_diff = max_diff.max(d);
        if x < 0.0079 && d > 0.0005 * 0.1737 {
            off.push((x, d / 0.1737 * 100.0));
        }
    }
    let peak = curve
        .iter()
        .cloned()
        .fold((0.0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
    let peak_ref =
        rows.iter()
            .map(|r| (r[0], r[1]))
            .fold((0.0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
    eprintln!(
        "pushover force: peak V/W = {:.4} at {:.2} % drift (OpenSees {:.4} at {:.2} %), diff {:+.2} %; curve up to its end: max |Δ(V/W)| = {:.4} ({:.2} % of peak)",
        peak.1,
        peak.0 * 100.0,
        peak_ref.1,
        peak_ref.0 * 100.0,
        (peak.1 - peak_ref.1) / peak_ref.1 * 100.0,
        max_diff,
        max_diff / peak_ref.1 * 100.0
    );
    eprintln!("points below 0.79 % off by more than 0.05 % of the peak: {off:?}");
    assert!((peak.1 - 0.174).abs() < 0.05 * 0.174, "peak V/W {}", peak.1);
    assert!(off.is_empty(), "points off: {off:?}");
    assert!(max_diff < 0.06 * peak_ref.1, "curve differs by {max_diff}");
}

/// Static equilibrium of every converged step: the support reactions balance the applied
/// loads, ΣR_x = −λ (the pattern sums to 1 N), ΣR_y = 0 and ΣR_z = W (gravity held), to
/// the Newton tolerance; the base shear of the frame group is all of it (frame3 has no
/// walls).
#[test]
fn pushover_reactions_balance_the_applied_loads() {
    let model = frame3();
    let r = run_pushover(
        &model,
        &settings(Variant::Force, LoadPattern::Uniform, vec![0.006]),
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(r.stop, PushoverStop::Completed);
    assert_eq!(r.curve.len(), 7, "6 steps of 1 mm and the gravity point");
    let sum: f64 = r.pattern_loads.iter().map(|(_, f)| f).sum();
    assert!((sum - 1.0).abs() < 1e-12, "pattern sums to {sum}");
    for p in &r.curve {
        let scale = 1.0 + p.load_factor.abs();
        assert!(
            (p.reaction_sum[0] + p.load_factor).abs() < 1e-6 * scale,
            "step {}: ΣRx = {} against λ = {}",
            p.step,
            p.reaction_sum[0],
            p.load_factor
        );
        assert!(
            p.reaction_sum[1].abs() < 1e-6 * scale,
            "ΣRy {}",
            p.reaction_sum[1]
        );
        assert!(
            (p.reaction_sum[2] - r.weight).abs() < 1e-8 * r.weight,
            "ΣRz = {} against W = {}",
            p.reaction_sum[2],
            r.weight
        );
        assert!((p.base_shear_frame - p.base_shear(0)).abs() < 1e-9 * scale);
        assert_eq!(p.base_shear_wall, 0.0);
    }
    // Uniform: every massed node's load is its mass share.
    let masses = model.lumped_masses();
    let fixity = model.fixity();
    let total: f64 = masses
        .iter()
        .filter(|(t, _)| !fixity.contains_key(t))
        .map(|(_, m)| m[0])
        .sum();
    for (tag, f) in &r.pattern_loads {
        assert!((f - masses[tag][0] / total).abs() < 1e-15);
    }
    assert!(r.curve[6].base_shear(0) > 0.0);
}

/// A cyclic protocol on the elastic frame: the path returns to zero displacement with zero
/// base shear (no hysteresis), and the base shear at +a and −a is equal and opposite up to
/// the P-Δ asymmetry of gravity (none: the frame is symmetric), to 1e-6 of the peak.
/// The force-based frame pushed past yield to 0.6 % and back to zero displacement must be
/// pulled there: its base shear at zero is negative (more than 5 % of the peak).
#[test]
fn cyclic_protocol_elastic_returns_and_force_based_dissipates() {
    let model = frame3();
    let a = 0.003 * 3.0;
    let targets = cyclic_targets(&[a], 1);
    assert_eq!(targets, vec![a, -a, 0.0]);
    let r = run_pushover(
        &model,
        &settings(Variant::Elastic, LoadPattern::Triangular, targets),
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(r.stop, PushoverStop::Completed);
    let at = |u: f64| {
        r.curve
            .iter()
            .find(|p| (p.control_displacement - u).abs() < 1e-9)
            .unwrap_or_else(|| panic!("no point at {u}"))
    };
    let vp = at(a).base_shear(0);
    let vm = at(-a).base_shear(0);
    let v0 = r.curve.last().unwrap().base_shear(0);
    assert!(vp > 0.0 && vm < 0.0);
    assert!((vp + vm).abs() < 1e-6 * vp, "V(+a) = {vp}, V(−a) = {vm}");
    assert!(v0.abs() < 1e-6 * vp, "V back at zero: {v0}");
    // 9 + 18 + 9 = 36 steps of 1 mm (a = 9 mm) and the gravity point.
    assert_eq!(r.curve.len(), 37);

    let a = 0.006 * 3.0;
    let r = run_pushover(
        &model,
        &settings(Variant::Force, LoadPattern::Triangular, vec![a, 0.0]),
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(r.stop, PushoverStop::Completed);
    let peak = r.curve.iter().map(|p| p.base_shear(0)).fold(0.0, f64::max);
    let last = r.curve.last().unwrap();
    eprintln!(
        "force-based, to 0.6 % and back: peak V = {peak:.1} N, V at zero = {:.1} N",
        last.base_shear(0)
    );
    assert!(
        last.base_shear(0) < -0.05 * peak,
        "unloading to zero after yield leaves a negative base shear, got {} (peak {peak})",
        last.base_shear(0)
    );
}
