//! Integration of ground acceleration: closed-form check, baseline correction on El Centro,
//! continuity of the ground state used after the collapse moment.
use fem2rbd_fe::motion::{read_record, Baseline, Format, GroundMotion, Record, G};
use std::path::Path;

fn el_centro() -> GroundMotion {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("data/ground-motions");
    let rd = |f: &str| read_record(&dir.join(f), Format::Auto).unwrap().pop();
    GroundMotion::new(
        rd("RSN6_IMPVALL.I_I-ELC180.AT2"),
        rd("RSN6_IMPVALL.I_I-ELC270.AT2"),
        rd("RSN6_IMPVALL.I_I-ELC-UP.AT2"),
    )
}

/// a(t) = A sin ωt from rest: v = A/ω (1 − cos ωt), d = A t/ω − A sin(ωt)/ω².
#[test]
fn sine_acceleration_integrates_to_the_closed_form() {
    let (amp, w, dt, tt): (f64, f64, f64, f64) =
        (2.0, 2.0 * std::f64::consts::PI * 1.3, 0.001, 5.0);
    let n = (tt / dt).round() as usize + 1;
    let a: Vec<f64> = (0..n).map(|i| amp * (w * i as f64 * dt).sin()).collect();
    let gm = GroundMotion::new(None, Some(Record::new("sine", dt, 0.0, a).unwrap()), None);
    for step in [0.001, 0.0025] {
        let h = gm.integrate(step, Baseline::None).unwrap();
        let (mut ev, mut ed) = (0.0f64, 0.0f64);
        for (i, (v, d)) in h.vel.iter().zip(&h.disp).enumerate() {
            let t = i as f64 * step;
            let v_exact = amp / w * (1.0 - (w * t).cos());
            let d_exact = amp * t / w - amp * (w * t).sin() / (w * w);
            ev = ev.max((v[1] - v_exact).abs());
            ed = ed.max((d[1] - d_exact).abs());
            assert_eq!(v[0], 0.0);
            assert_eq!(d[2], 0.0);
        }
        // Peak |v| = 2A/ω = 0.245 m/s, final d = A T/ω = 1.22 m. The trapezoidal
        // velocity error is h²/12·(a'(t) − a'(0)) ≤ h²·2Aω/12 = 2.72·h² (m/s); the
        // displacement error its integral, ≤ 13.6·h² here. Measured: 2.72e-6 / 6.81e-6
        // at h = 1 ms; 1.91e-5 / 4.77e-5 at h = 2.5 ms (record sampled at 1 ms,
        // interpolated).
        let (vmax, dmax) = (2.0 * amp / w, amp * tt / w);
        eprintln!("step {step}: max |v err| {ev:.3e} m/s, max |d err| {ed:.3e} m");
        assert!(ev < 3.5 * step * step, "velocity error {ev}");
        assert!(ed < 10.0 * step * step, "displacement error {ed}");
        // Between steps the state follows the constant-average-acceleration motion,
        // which adds a local velocity error up to |a'|·h²/4 = Aω·h²/4 = 4.1·h².
        let t = 1.2345;
        let (d, v, _) = h.ground_state_at(t);
        assert!((v[1] - amp / w * (1.0 - (w * t).cos())).abs() < 8.0 * step * step);
        assert!((d[1] - (amp * t / w - amp * (w * t).sin() / (w * w))).abs() < 10.0 * step * step);
        assert!(vmax > 0.24 && dmax > 1.2);
    }
}

#[test]
fn baseline_correction_on_el_centro() {
    let gm = el_centro();
    let raw = gm.integrate(0.01, Baseline::None).unwrap();
    let fit = gm.integrate(0.01, Baseline::QuadraticVelocityFit).unwrap();
    let zero = gm.integrate(0.01, Baseline::default()).unwrap();
    assert_eq!(raw.acc.len(), 5346);
    let last = raw.acc.len() - 1;
    let pgv = |h: &fem2rbd_fe::motion::GroundHistory, k: usize| {
        h.vel.iter().map(|v| v[k].abs()).fold(0.0, f64::max)
    };
    for k in 0..3 {
        eprintln!(
            "axis {k}: raw v_end {:+.4e} d_end {:+.4e} | fit v_end {:+.4e} d_end {:+.4e} | \
             zero-end v_end {:+.3e} d_end {:+.3e} | PGV raw {:.4} fit {:.4} zero {:.4}",
            raw.vel[last][k],
            raw.disp[last][k],
            fit.vel[last][k],
            fit.disp[last][k],
            zero.vel[last][k],
            zero.disp[last][k],
            pgv(&raw, k),
            pgv(&fit, k),
            pgv(&zero, k)
        );
        assert!(
            zero.vel[last][k].abs() < 1e-12,
            "v_end {}",
            zero.vel[last][k]
        );
        assert!(
            zero.disp[last][k].abs() < 1e-12,
            "d_end {}",
            zero.disp[last][k]
        );
        assert!(
            fit.vel[last][k].abs() < 0.01,
            "fit v_end {}",
            fit.vel[last][k]
        );
        assert!(
            fit.disp[last][k].abs() < 0.05,
            "fit d_end {}",
            fit.disp[last][k]
        );
        // The correction is tiny next to the record: < 0.1 % of the PGA.
        let pga = gm.components[k].as_ref().unwrap().pga().0;
        for (a, b) in zero.acc.iter().zip(&raw.acc) {
            assert!((a[k] - b[k]).abs() < 1e-3 * pga);
        }
    }
    // PGV against the shared README (30.9 / 31.3 / 8.6 cm/s, computed there with
    // g = 9.80665 and no correction): within 3 %.
    for (k, readme) in [0.309, 0.313, 0.086].into_iter().enumerate() {
        let p = pgv(&zero, k) * 9.80665 / G;
        assert!((p / readme - 1.0).abs() < 0.03, "axis {k}: PGV {p}");
    }
}

#[test]
fn ground_state_is_continuous_and_consistent() {
    let mut gm = el_centro();
    gm.scale_to_pga([Some(0.93), Some(1.19), Some(0.57)])
        .unwrap();
    let h = gm.integrate(0.005, Baseline::default()).unwrap();
    // v = dd/dt inside a step (central difference of the quadratic is exact).
    for &t in &[0.0123, 3.881, 17.3337, 50.0001] {
        let e = 1e-6;
        let (dp, ..) = h.ground_state_at(t + e);
        let (dm, ..) = h.ground_state_at(t - e);
        let (_, v, _) = h.ground_state_at(t);
        for k in 0..3 {
            let fd = (dp[k] - dm[k]) / (2.0 * e);
            assert!((fd - v[k]).abs() < 1e-6, "t {t} axis {k}: {fd} vs {v:?}");
        }
    }
    // Continuity across a step boundary and across the end of the record.
    let tend = h.end_time_s();
    assert!((tend - 53.45).abs() < 1e-9);
    for &t in &[3.88, 20.0, tend] {
        let e = 1e-9;
        let (d0, v0, _) = h.ground_state_at(t - e);
        let (d1, v1, _) = h.ground_state_at(t + e);
        for k in 0..3 {
            assert!((d0[k] - d1[k]).abs() < 1e-9);
            assert!((v0[k] - v1[k]).abs() < 1e-6);
        }
    }
    // After the record the ground rests where it ended (zero-end baseline: at the origin).
    let (d, v, a) = h.ground_state_at(tend + 10.0);
    for k in 0..3 {
        assert!(d[k].abs() < 1e-12 && v[k].abs() < 1e-12 && a[k] == 0.0);
    }
    // At a sample time the state is the recurrence's.
    let (d, v, a) = h.ground_state_at(776.0 * 0.005);
    assert!((d[0] - h.disp[776][0]).abs() < 1e-12);
    assert!((v[0] - h.vel[776][0]).abs() < 1e-12);
    assert!((a[0] - h.acc[776][0]).abs() < 1e-9);
}
