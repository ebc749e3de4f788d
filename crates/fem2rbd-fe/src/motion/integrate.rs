//! Integration of ground acceleration to velocity and displacement, with baseline
//! correction, for the moving ground of the ruin stage (paper §3, BCB step 3; the ground
//! after the collapse moment Tc must continue the FE-stage ground state).
//!
//! On a fixed step h, with samples a_n = a(n·h) (linear interpolation of the record):
//!
//! ```text
//! v_{n+1} = v_n + h/2 · (a_n + a_{n+1})                      (trapezoidal rule)
//! d_{n+1} = d_n + h·v_n + h²/4 · (a_n + a_{n+1})             (Newmark γ = 1/2, β = 1/4)
//! ```
//!
//! i.e. the constant-average-acceleration recurrence (Newmark 1959; Chopra, *Dynamics of
//! Structures*, §5.4), starting from rest, v_0 = d_0 = 0. Within a step the motion is the
//! one of the constant average acceleration ā = (a_n + a_{n+1})/2, so displacement and
//! velocity are continuous and v = dd/dt exactly (see [`GroundHistory::ground_state_at`]).
//!
//! Baseline correction ([`Baseline`]): a polynomial is subtracted from the **acceleration**
//! and the corrected acceleration is integrated again with the same recurrence, so the
//! three histories stay consistent with each other.

use super::GroundMotion;
use super::MotionError;
use crate::model::limits::show_number as show;

/// What integrating a motion returns.
type Result<T> = std::result::Result<T, MotionError>;

/// Baseline correction applied before integration (per component).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Baseline {
    /// No correction (BCB's import does none; displacement may drift).
    None,
    /// Least-squares fit of the velocity by v̂(t) = c₁t + c₂t² (through v(0) = 0), then
    /// a ← a − (c₁ + 2c₂t). Because the trapezoidal rule integrates a linear acceleration
    /// exactly, the corrected velocity is exactly v − v̂. Removes a velocity trend; final
    /// velocity and displacement are small but not zero.
    QuadraticVelocityFit,
    /// The smallest linear acceleration correction a ← a − (b₀ + b₁t/T), with b₀, b₁
    /// solved so that the integrated velocity and displacement are exactly zero at the
    /// last step T (to round-off). The ground then ends at rest where it started and stays
    /// there after the record. For records already processed by PEER (El Centro RSN6:
    /// raw v_end ≤ 4.4e-4 m/s, d_end ≤ 1.2e-4 m) the correction changes the acceleration
    /// by < 0.1 % of the PGA, whereas [`Baseline::QuadraticVelocityFit`] removes real
    /// long-period motion and moves d_end by up to 3.5 cm; hence this is the default.
    #[default]
    ZeroEnd,
}

/// Ground acceleration, velocity and displacement on a uniform step, from t = 0.
#[derive(Debug, Clone, PartialEq)]
pub struct GroundHistory {
    /// Step h (s).
    pub step_s: f64,
    /// a_n (m/s²), X/Y/Z, after baseline correction.
    pub acc: Vec<[f64; 3]>,
    /// v_n (m/s).
    pub vel: Vec<[f64; 3]>,
    /// d_n (m).
    pub disp: Vec<[f64; 3]>,
}

/// Integrates one acceleration series with the average-acceleration recurrence.
fn integrate_series(a: &[f64], h: f64) -> (Vec<f64>, Vec<f64>) {
    let mut v = vec![0.0; a.len()];
    let mut d = vec![0.0; a.len()];
    for n in 1..a.len() {
        let s = a[n - 1] + a[n];
        v[n] = v[n - 1] + 0.5 * h * s;
        d[n] = d[n - 1] + h * v[n - 1] + 0.25 * h * h * s;
    }
    (v, d)
}

/// Solves a 2×2 system; `None` if singular.
fn solve2(m: [[f64; 2]; 2], r: [f64; 2]) -> Option<[f64; 2]> {
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    if det.abs() < 1e-300 {
        return None;
    }
    Some([
        (r[0] * m[1][1] - m[0][1] * r[1]) / det,
        (m[0][0] * r[1] - m[1][0] * r[0]) / det,
    ])
}

fn correct_series(a: &mut [f64], h: f64, baseline: Baseline) {
    let n = a.len();
    if baseline == Baseline::None || n < 3 {
        return;
    }
    let tt = (n - 1) as f64 * h;
    if baseline == Baseline::ZeroEnd {
        zero_end(a, h, tt);
        return;
    }
    // Quadratic velocity fit in the normalised time τ = t/T (well conditioned).
    let (v, _) = integrate_series(a, h);
    let (mut s2, mut s3, mut s4, mut r1, mut r2) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (i, vi) in v.iter().enumerate() {
        let tau = i as f64 * h / tt;
        s2 += tau * tau;
        s3 += tau * tau * tau;
        s4 += tau * tau * tau * tau;
        r1 += tau * vi;
        r2 += tau * tau * vi;
    }
    if let Some([c1, c2]) = solve2([[s2, s3], [s3, s4]], [r1, r2]) {
        // v̂ = c1 τ + c2 τ² → dv̂/dt = (c1 + 2 c2 τ)/T.
        for (i, ai) in a.iter_mut().enumerate() {
            let tau = i as f64 * h / tt;
            *ai -= (c1 + 2.0 * c2 * tau) / tt;
        }
    }
}

/// Linear acceleration correction making v and d zero at the last step (see [`Baseline::ZeroEnd`]).
fn zero_end(a: &mut [f64], h: f64, tt: f64) {
    let n = a.len();
    {
        let (v, d) = integrate_series(a, h);
        let ones = vec![1.0; n];
        let ramp: Vec<f64> = (0..n).map(|i| i as f64 * h / tt).collect();
        let (v1, d1) = integrate_series(&ones, h);
        let (v2, d2) = integrate_series(&ramp, h);
        let m = [[v1[n - 1], v2[n - 1]], [d1[n - 1], d2[n - 1]]];
        if let Some([b0, b1]) = solve2(m, [v[n - 1], d[n - 1]]) {
            for (ai, r) in a.iter_mut().zip(&ramp) {
                *ai -= b0 + b1 * r;
            }
        }
    }
}

impl GroundMotion {
    /// Samples the motion at t_n = n·h for n = 0..=⌊duration/h⌋ and integrates each
    /// component to velocity and displacement (module docs), after the chosen baseline
    /// correction. Absent components give zeros.
    pub fn integrate(&self, step_s: f64, baseline: Baseline) -> Result<GroundHistory> {
        if !(step_s.is_finite() && step_s > 0.0) {
            return Err(MotionError::Options(format!(
                "integration step must be positive, got {} s",
                show(step_s)
            )));
        }
        let dur = self.duration_s();
        // n = ⌊T/h⌋ + 1, bounded before the cast (a step of 1e-300 s or a record
        // time-scaled by 1e300 is an error here, not an overflow).
        let n = crate::model::limits::grid_count(
            format!(
                "ground motion of {} s on a step of {} s",
                show(dur),
                show(step_s)
            ),
            "integration samples",
            dur,
            step_s,
            crate::model::limits::MAX_SAMPLES,
        )?;
        let mut acc = vec![[0.0; 3]; n];
        let mut vel = vec![[0.0; 3]; n];
        let mut disp = vec![[0.0; 3]; n];
        for k in 0..3 {
            if self.components[k].is_none() {
                continue;
            }
            let mut a: Vec<f64> = (0..n)
                .map(|i| self.accel_at(i as f64 * step_s)[k])
                .collect();
            correct_series(&mut a, step_s, baseline);
            let (v, d) = integrate_series(&a, step_s);
            for i in 0..n {
                acc[i][k] = a[i];
                vel[i][k] = v[i];
                disp[i][k] = d[i];
            }
        }
        Ok(GroundHistory {
            step_s,
            acc,
            vel,
            disp,
        })
    }
}

impl GroundHistory {
    /// Time of the last step (s).
    pub fn end_time_s(&self) -> f64 {
        (self.acc.len() - 1) as f64 * self.step_s
    }

    /// Ground (displacement m, velocity m/s, acceleration m/s²) at time `t` (s).
    ///
    /// - t ≤ 0: at rest at the origin.
    /// - Inside step n: the constant-average-acceleration motion, ā = (a_n + a_{n+1})/2,
    ///   v = v_n + ā·τ, d = d_n + v_n·τ + ā·τ²/2 (τ = t − t_n), which meets the recurrence at
    ///   both ends, so d and v are continuous; the acceleration returned is the linear
    ///   interpolation of a_n, a_{n+1}.
    /// - After the last step T: a = 0, v = v_T, d = d_T + v_T·(t − T) (continuous d and v;
    ///   with [`super::Baseline::ZeroEnd`] v_T = d_T = 0: the ground rests).
    pub fn ground_state_at(&self, t: f64) -> ([f64; 3], [f64; 3], [f64; 3]) {
        let last = self.acc.len() - 1;
        if !(t > 0.0) {
            return ([0.0; 3], [0.0; 3], [0.0; 3]);
        }
        let tend = self.end_time_s();
        if t >= tend {
            let dt = t - tend;
            let (d, v) = (self.disp[last], self.vel[last]);
            return (
                [d[0] + v[0] * dt, d[1] + v[1] * dt, d[2] + v[2] * dt],
                v,
                if dt == 0.0 { self.acc[last] } else { [0.0; 3] },
            );
        }
        let n = ((t / self.step_s).floor() as usize).min(last - 1);
        let tau = t - n as f64 * self.step_s;
        let w = tau / self.step_s;
        let mut out = ([0.0; 3], [0.0; 3], [0.0; 3]);
        for k in 0..3 {
            let (a0, a1) = (self.acc[n][k], self.acc[n + 1][k]);
            let abar = 0.5 * (a0 + a1);
            out.0[k] = self.disp[n][k] + self.vel[n][k] * tau + 0.5 * abar * tau * tau;
            out.1[k] = self.vel[n][k] + abar * tau;
            out.2[k] = a0 * (1.0 - w) + a1 * w;
        }
        out
    }
}
