//! Transient analysis (Newmark average acceleration + Newton) against closed forms:
//! SDOF free vibration (exact discrete solution with the Newmark period elongation),
//! SDOF under harmonic base acceleration (scalar Newmark recurrence and the exact
//! steady state), Rayleigh damping measured by the logarithmic decrement at both
//! anchor periods, and the non-convergence paths.
use super::support as fe_analysis_support;

use std::f64::consts::PI;

use fe_analysis_support::{square, ElasticFrame, FailMode, Failing, Props};
use fem2rbd_fe::fe::analysis::modal::{modal_analysis, EigenMethod, ModalSettings, ModeSelection};
use fem2rbd_fe::fe::analysis::rayleigh::RayleighDamping;
use fem2rbd_fe::fe::analysis::transient::{
    run_transient, RecordSettings, StepControl, StopReason, TransientResult, TransientSettings,
};
use fem2rbd_fe::fe::domain::Domain;
use fem2rbd_fe::fe::linalg::StiffnessKind;

const L: f64 = 2.0;
const M: f64 = 1000.0;

fn props() -> Props {
    square(25e9, 0.1)
}

/// Lateral stiffness of the cantilever column, k = 3EI/L³ (N/m).
fn k_col() -> f64 {
    3.0 * 25e9 * props().iy / L.powi(3)
}

/// A vertical cantilever column (1 element, vecxz = X) with a tip mass M in X only:
/// an SDOF in X, massless in the other DOFs. `mode` makes the element fail on purpose.
fn column(mode: Option<FailMode>) -> Domain {
    let mut d = Domain::new();
    d.add_node(1, [0.0, 0.0, 0.0]).unwrap();
    d.add_node(2, [0.0, 0.0, L]).unwrap();
    d.fix(0, [true; 6]).unwrap();
    d.set_mass(1, [M, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
    let el = ElasticFrame::new(1, &d, 0, 1, [1.0, 0.0, 0.0], props());
    match mode {
        None => d.add_element(Box::new(el)).unwrap(),
        Some(m) => d.add_element(Box::new(Failing::new(el, m))).unwrap(),
    };
    d.number_dofs();
    d
}

fn settings(dt: f64, t_end: f64) -> TransientSettings {
    TransientSettings {
        dt,
        t_end,
        ..Default::default()
    }
}

fn run(
    d: &mut Domain,
    damping: Option<RayleighDamping>,
    ground: &dyn Fn(f64) -> [f64; 3],
    s: &TransientSettings,
) -> TransientResult {
    run_transient(d, damping, ground, s, &mut |_, _| StepControl::Continue).unwrap()
}

/// Free vibration from u₀ with consistent ü₀ = −ω²u₀: the average-acceleration
/// solution is exactly u_n = u₀ cos(n θ), tan(θ/2) = ωΔt/2 (period elongation
/// T̄/T = ωΔt / θ; Hughes, *The Finite Element Method*, §9.3).
#[test]
fn sdof_free_vibration_period_elongation() {
    let mut d = column(None);
    let w = (k_col() / M).sqrt();
    let t = 2.0 * PI / w;
    let dt = t / 12.0; // coarse on purpose: elongation ≈ 2.3 %
    let n = d.num_equations();
    let ex = d.equation(1, 0).unwrap();
    let u0 = 0.01;
    // Static shape of a tip displacement: rotation θ = 3u/(2L) about +Y.
    let (mut u, v, mut a) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    u[ex] = u0;
    u[d.equation(1, 4).unwrap()] = 1.5 * u0 / L;
    a[ex] = -w * w * u0;
    d.set_initial_state(&u, &v, &a).unwrap();
    let res = run(&mut d, None, &|_| [0.0; 3], &settings(dt, 3.0 * t));
    assert_eq!(res.stop, StopReason::Completed);
    assert_eq!(res.steps, 36);
    let theta = 2.0 * (w * dt / 2.0).atan();
    let mut max_exact_diff: f64 = 0.0;
    for (k, (tk, rec)) in res.history.time.iter().zip(&res.history.disp).enumerate() {
        assert!((tk - k as f64 * dt).abs() < 1e-12);
        let ux = rec[1][0];
        let expect = u0 * (k as f64 * theta).cos();
        assert!(
            (ux - expect).abs() < 1e-9 * u0,
            "step {k}: {ux} vs {expect}"
        );
        max_exact_diff = max_exact_diff.max((ux - u0 * (w * tk).cos()).abs());
    }
    // The elongation is visible: after 3 periods the exact solution differs by > 10 %.
    assert!(max_exact_diff > 0.1 * u0, "{max_exact_diff}");
}

/// Scalar Newmark (γ = 1/2, β = 1/4) for m ü + c u̇ + k u = −m a_g(t): the reference
/// recurrence written independently of the library.
fn scalar_newmark(m: f64, c: f64, k: f64, dt: f64, n: usize, ag: &dyn Fn(f64) -> f64) -> Vec<f64> {
    let (g, b) = (0.5, 0.25);
    let (mut u, mut v, mut a) = (0.0, 0.0, 0.0);
    let keff = k + g / (b * dt) * c + m / (b * dt * dt);
    let mut out = vec![u];
    for i in 1..=n {
        let p = -m * ag(i as f64 * dt);
        let rhs = p
            + m * (u / (b * dt * dt) + v / (b * dt) + (0.5 / b - 1.0) * a)
            + c * (g / (b * dt) * u + (g / b - 1.0) * v + dt * (g / (2.0 * b) - 1.0) * a);
        let un = rhs / keff;
        let an = (un - u) / (b * dt * dt) - v / (b * dt) - (0.5 / b - 1.0) * a;
        let vn = v + dt * ((1.0 - g) * a + g * an);
        u = un;
        v = vn;
        a = an;
        out.push(u);
    }
    out
}

/// Harmonic base acceleration a_g = A sin(Ω t) in X with 5 % Rayleigh damping: the
/// FE run equals the scalar Newmark recurrence (c = a0 m + a1 k, exact because the
/// massless DOFs follow statically), and the late-time amplitude equals the exact
/// steady state |u| = A / √((ω² − Ω²)² + (2ξωΩ)²) within 0.2 % (Δt = T/100;
/// measured 0.08 %, the Newmark period error).
#[test]
fn sdof_harmonic_base_acceleration() {
    let mut d = column(None);
    let w = (k_col() / M).sqrt();
    let t = 2.0 * PI / w;
    let damping = RayleighDamping::from_periods(0.05, t, t / 3.0).unwrap();
    let (amp, wg) = (0.5, 0.8 * w);
    let ground = move |tt: f64| [amp * (wg * tt).sin(), 0.3, -0.2];
    // Y and Z components act on massless DOFs only (no mass in Y, Z): no effect.
    let dt = t / 100.0;
    let nsteps = 4000;
    let mut s = settings(dt, nsteps as f64 * dt);
    s.record = RecordSettings {
        every: 1,
        nodes: Some(vec![1]),
        element_damage: false,
    };
    let res = run(&mut d, Some(damping), &ground, &s);
    assert_eq!(res.stop, StopReason::Completed);
    let c = damping.a0 * M + damping.a1 * k_col();
    let reference = scalar_newmark(M, c, k_col(), dt, nsteps, &|tt| amp * (wg * tt).sin());
    let peak = reference.iter().fold(0.0f64, |p, x| p.max(x.abs()));
    for (k, rec) in res.history.disp.iter().enumerate() {
        assert!((rec[0][0] - reference[k]).abs() < 1e-9 * peak, "step {k}");
        assert!(rec[0][1].abs() < 1e-15 && rec[0][2].abs() < 1e-15);
    }
    // Steady state over the last 10 forcing periods (transient decayed: e^{-ξωt} < 1e-5).
    let xi = damping.ratio(w);
    let exact = amp / ((w * w - wg * wg).powi(2) + (2.0 * xi * w * wg).powi(2)).sqrt();
    let last = (10.0 * 2.0 * PI / wg / dt) as usize;
    let measured = res.history.disp[nsteps - last..]
        .iter()
        .fold(0.0f64, |p, r| p.max(r[0][0].abs()));
    eprintln!("steady state: measured {measured:.6e} m, exact {exact:.6e} m");
    assert!(
        ((measured - exact) / exact).abs() < 0.01,
        "{measured} vs {exact}"
    );
}

/// Rayleigh damping, 5 % at both periods of a two-story model: free vibration in
/// each mode; the logarithmic decrement over 5 cycles gives ξ = δ/√(4π² + δ²) = 5 %.
#[test]
fn rayleigh_log_decrement_at_anchor_periods() {
    let build = || {
        let mut d = Domain::new();
        for f in 0..3 {
            d.add_node(f, [0.0, 0.0, 3.0 * f as f64]).unwrap();
        }
        d.fix(0, [true; 6]).unwrap();
        for f in 1..3 {
            d.fix(f, [false, false, false, true, true, true]).unwrap();
            d.set_mass(f, [2000.0, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
        }
        for f in 0..2usize {
            let el = ElasticFrame::new(f as i64, &d, f, f + 1, [1.0, 0.0, 0.0], square(30e9, 0.3));
            d.add_element(Box::new(el)).unwrap();
        }
        d
    };
    let mut d = build();
    let modal = modal_analysis(
        &mut d,
        &ModalSettings {
            selection: ModeSelection::Lowest,
            modes: 2,
            stiffness: StiffnessKind::Initial,
            method: EigenMethod::DenseCondensed,
        },
    )
    .unwrap();
    let (t1, t2) = (modal.periods[0], modal.periods[1]);
    let damping = RayleighDamping::from_periods(0.05, t1, t2).unwrap();
    for mode in 0..2 {
        let mut d = build();
        d.number_dofs();
        let n = d.num_equations();
        let w2 = modal.omega_squared[mode];
        let (mut u, v, mut a) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for node in 0..3 {
            for k in 0..6 {
                if let Some(e) = d.equation(node, k) {
                    u[e] = 0.01 * modal.shapes[mode][node][k];
                    a[e] = -w2 * u[e];
                }
            }
        }
        d.set_initial_state(&u, &v, &a).unwrap();
        let tp = modal.periods[mode];
        let dt = tp / 400.0;
        let mut s = settings(dt, 5.2 * tp);
        s.record.nodes = Some(vec![2]);
        let res = run(&mut d, Some(damping), &|_| [0.0; 3], &s);
        // Positive peaks by parabolic interpolation.
        let x: Vec<f64> = res.history.disp.iter().map(|r| r[0][0]).collect();
        let mut peaks = Vec::new();
        for i in 1..x.len() - 1 {
            if x[i] > x[i - 1] && x[i] >= x[i + 1] && x[i] > 0.0 {
                let (y0, y1, y2) = (x[i - 1], x[i], x[i + 1]);
                let den = y0 - 2.0 * y1 + y2;
                let p = 0.5 * (y0 - y2) / den;
                peaks.push(y1 - 0.25 * (y0 - y2) * p);
            }
        }
        assert!(peaks.len() >= 5, "{} peaks", peaks.len());
        let cycles = (peaks.len() - 1) as f64;
        let delta = (peaks[0].abs() / peaks[peaks.len() - 1].abs()).ln() / cycles;
        let xi = delta / (4.0 * PI * PI + delta * delta).sqrt();
        eprintln!("mode {mode}: T = {tp:.5} s, measured ξ = {xi:.6}");
        assert!((xi - 0.05).abs() < 0.0005, "mode {mode}: ξ = {xi}");
    }
}
