//! Bilinear steel with kinematic and optional isotropic hardening, OpenSees
//! `uniaxialMaterial Steel01 $tag $Fy $E0 $b <$a1 $a2 $a3 $a4>` (class `Steel01`).
//!
//! The stress is the trial stress of an elastic predictor σ* = σ_c + E0·Δε clipped to the
//! two hardening asymptotes (Filippou, Popov & Bertero 1983, the bilinear limit of the
//! Menegotto–Pinto law):
//!
//! ```text
//! σ = max( b·E0·ε − s_n·(1−b)·Fy , min( b·E0·ε + s_p·(1−b)·Fy , σ* ) )
//! ```
//!
//! with tangent E0 while the predictor is inside the band and b·E0 on an asymptote. The
//! isotropic-hardening shifts s_p, s_n (both 1 in the virgin state) are updated at each
//! load reversal from the committed strain range [ε_min, ε_max]:
//! `s_n = 1 + a1·((ε_max − ε_min)/(2·a2·εy))^0.8` on a reversal from loading to unloading,
//! `s_p = 1 + a3·((ε_max − ε_min)/(2·a4·εy))^0.8` on a reversal from unloading to loading,
//! where εy = Fy/E0. As in OpenSees the new shift takes effect from the next step.
//!
//! Units: Fy, E0 and stresses in Pa, strains dimensionless; b, a1 and a3 dimensionless,
//! a2 and a4 in multiples of εy.
//!
//! **fem2rbd extension (off by default):** an optional rupture strain `eps_rupture` (> 0,
//! tension). Once a trial strain reaches it the bar is ruptured: stress and tangent are 0
//! for that trial and, after a commit, for ever. OpenSees' Steel01 has no rupture.

use super::MaterialError;
use super::{MaterialDamage, UniaxialMaterial};

/// Parameters of `Steel01` (OpenSees parameter names in code font).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Steel01Params {
    /// Yield strength `Fy` (Pa, > 0).
    pub fy: f64,
    /// Initial elastic modulus `E0` (Pa, > 0).
    pub e0: f64,
    /// Strain-hardening ratio `b` = E_sh/E0 (–, 0 ≤ b < 1).
    pub b: f64,
    /// Isotropic hardening, compression envelope growth `a1` (–, default 0).
    pub a1: f64,
    /// Isotropic hardening, compression reference range in εy `a2` (> 0, default 55).
    pub a2: f64,
    /// Isotropic hardening, tension envelope growth `a3` (–, default 0).
    pub a3: f64,
    /// Isotropic hardening, tension reference range in εy `a4` (> 0, default 55).
    pub a4: f64,
    /// Tensile rupture strain (–, > Fy/E0); `None` (default) = never ruptures.
    pub eps_rupture: Option<f64>,
}

impl Steel01Params {
    /// Parameters with OpenSees' defaults a1 = 0, a2 = 55, a3 = 0, a4 = 55 (no isotropic
    /// hardening) and no rupture.
    pub fn new(fy: f64, e0: f64, b: f64) -> Self {
        Self {
            fy,
            e0,
            b,
            a1: 0.0,
            a2: 55.0,
            a3: 0.0,
            a4: 55.0,
            eps_rupture: None,
        }
    }
}

/// Trial or committed state of `Steel01`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct State {
    strain: f64,
    stress: f64,
    tangent: f64,
    /// Smallest / largest strain at a reversal so far (for isotropic hardening).
    min_strain: f64,
    max_strain: f64,
    shift_p: f64,
    shift_n: f64,
    /// +1 loading (ε increasing), −1 unloading, 0 virgin.
    loading: i8,
    yielded: bool,
    ruptured: bool,
}

/// OpenSees Steel01: bilinear kinematic hardening with optional isotropic hardening.
#[derive(Debug, Clone)]
pub struct Steel01 {
    p: Steel01Params,
    trial: State,
    committed: State,
}

impl Steel01 {
    /// Validates the parameters and returns the material in its virgin state.
    pub fn new(p: Steel01Params) -> Result<Self, MaterialError> {
        let fin = |v: f64| v.is_finite();
        if !(fin(p.fy) && p.fy > 0.0) {
            return Err(MaterialError::Parameter(format!(
                "Steel01: Fy must be > 0 (Pa), got {}",
                p.fy
            )));
        }
        if !(fin(p.e0) && p.e0 > 0.0) {
            return Err(MaterialError::Parameter(format!(
                "Steel01: E0 must be > 0 (Pa), got {}",
                p.e0
            )));
        }
        if !(fin(p.b) && (0.0..1.0).contains(&p.b)) {
            return Err(MaterialError::Parameter(format!(
                "Steel01: b must be in [0, 1), got {}",
                p.b
            )));
        }
        if !(fin(p.a1) && fin(p.a3)) {
            return Err(MaterialError::Parameter(format!(
                "Steel01: a1 and a3 must be finite, got {} and {}",
                p.a1, p.a3
            )));
        }
        if !(fin(p.a2) && p.a2 > 0.0 && fin(p.a4) && p.a4 > 0.0) {
            return Err(MaterialError::Parameter(format!(
                "Steel01: a2 and a4 must be > 0, got {} and {}",
                p.a2, p.a4
            )));
        }
        if let Some(er) = p.eps_rupture {
            if !(fin(er) && er > p.fy / p.e0) {
                return Err(MaterialError::Parameter(format!(
                    "Steel01: eps_rupture must exceed the yield strain Fy/E0 = {}, got {er}",
                    p.fy / p.e0
                )));
            }
        }
        let s = Self::virgin(&p);
        Ok(Self {
            p,
            trial: s,
            committed: s,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &Steel01Params {
        &self.p
    }

    fn virgin(p: &Steel01Params) -> State {
        State {
            strain: 0.0,
            stress: 0.0,
            tangent: p.e0,
            min_strain: 0.0,
            max_strain: 0.0,
            shift_p: 1.0,
            shift_n: 1.0,
            loading: 0,
            yielded: false,
            ruptured: false,
        }
    }

    /// The elastic-predictor / asymptote law and reversal bookkeeping for a strain
    /// change `d` from the committed state `c` into trial state `t`.
    fn trial_state(&self, c: &State, t: &mut State, d: f64) {
        let p = &self.p;
        let esh = p.b * p.e0;
        let eps_y = p.fy / p.e0;
        let band = p.fy * (1.0 - p.b);
        let on_hardening = esh * t.strain;
        let predictor = c.stress + p.e0 * d;
        let upper = on_hardening + t.shift_p * band;
        let lower = on_hardening - t.shift_n * band;
        t.stress = predictor.min(upper).max(lower);
        t.tangent = if (t.stress - predictor).abs() < f64::EPSILON {
            p.e0
        } else {
            esh
        };

        if t.loading == 0 && d != 0.0 {
            t.loading = if d > 0.0 { 1 } else { -1 };
        }
        if t.loading == 1 && d < 0.0 {
            t.loading = -1;
            t.max_strain = t.max_strain.max(c.strain);
            let range = (t.max_strain - t.min_strain) / (2.0 * p.a2 * eps_y);
            t.shift_n = 1.0 + p.a1 * range.powf(0.8);
        }
        if t.loading == -1 && d > 0.0 {
            t.loading = 1;
            t.min_strain = t.min_strain.min(c.strain);
            let range = (t.max_strain - t.min_strain) / (2.0 * p.a4 * eps_y);
            t.shift_p = 1.0 + p.a3 * range.powf(0.8);
        }
    }
}

impl UniaxialMaterial for Steel01 {
    fn set_trial_strain(&mut self, strain: f64) {
        let c = self.committed;
        let mut t = c;
        if c.ruptured {
            t.strain = strain;
            self.trial = t;
            return;
        }
        let d = strain - c.strain;
        // OpenSees keeps the committed state for a change below machine epsilon.
        if d.abs() > f64::EPSILON {
            t.strain = strain;
            self.trial_state(&c, &mut t, d);
        }
        t.yielded |= t.strain.abs() > self.p.fy / self.p.e0;
        if let Some(er) = self.p.eps_rupture {
            if t.strain >= er {
                t.ruptured = true;
                t.stress = 0.0;
                t.tangent = 0.0;
            }
        }
        self.trial = t;
    }
    fn strain(&self) -> f64 {
        self.trial.strain
    }
    fn stress(&self) -> f64 {
        self.trial.stress
    }
    fn tangent(&self) -> f64 {
        self.trial.tangent
    }
    fn initial_tangent(&self) -> f64 {
        self.p.e0
    }
    fn commit_state(&mut self) {
        self.committed = self.trial;
    }
    fn revert_to_last_commit(&mut self) {
        self.trial = self.committed;
    }
    fn revert_to_start(&mut self) {
        self.committed = Self::virgin(&self.p);
        self.trial = self.committed;
    }
    fn boxed_clone(&self) -> Box<dyn UniaxialMaterial> {
        Box::new(self.clone())
    }
    /// Yielded: |ε| > Fy/E0 at a commit. Ruptured: the optional rupture strain was reached.
    fn damage(&self) -> MaterialDamage {
        MaterialDamage {
            yielded: self.committed.yielded,
            ruptured: self.committed.ruptured,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bar() -> Steel01 {
        Steel01::new(Steel01Params::new(400e6, 200e9, 0.02)).unwrap()
    }

    fn step(m: &mut Steel01, eps: f64) -> (f64, f64) {
        m.set_trial_strain(eps);
        m.commit_state();
        (m.stress(), m.tangent())
    }

    #[test]
    fn bilinear_yield_and_hardening_slope() {
        let mut m = bar();
        let eps_y = 400e6 / 200e9;
        let (s, e) = step(&mut m, 0.5 * eps_y);
        assert!((s - 200e6).abs() < 1e-6 && e == 200e9);
        assert!(!m.damage().yielded);
        // Past yield: σ = Fy + b·E0·(ε − εy).
        let eps = 5.0 * eps_y;
        let (s, e) = step(&mut m, eps);
        let expect = 400e6 + 0.02 * 200e9 * (eps - eps_y);
        assert!((s - expect).abs() < 1e-6 * 400e6, "{s} vs {expect}");
        assert_eq!(e, 0.02 * 200e9);
        assert!(m.damage().yielded);
        // Elastic unloading by 2εy (inside the 2Fy band minus hardening), slope E0.
        let (s2, e2) = step(&mut m, eps - 1.5 * eps_y);
        assert!((s2 - (s - 200e9 * 1.5 * eps_y)).abs() < 1e-6 * 400e6);
        assert_eq!(e2, 200e9);
        // Far in compression: lower asymptote σ = b·E0·ε − (1−b)·Fy.
        let (s3, _) = step(&mut m, -10.0 * eps_y);
        let expect3 = 0.02 * 200e9 * (-10.0 * eps_y) - 0.98 * 400e6;
        assert!((s3 - expect3).abs() < 1e-6 * 400e6);
    }

    #[test]
    fn trial_twice_and_revert() {
        let mut a = bar();
        let mut b = bar();
        step(&mut a, 0.004);
        step(&mut b, 0.004);
        a.set_trial_strain(-0.003);
        a.set_trial_strain(0.001);
        b.set_trial_strain(0.001);
        assert_eq!(a.stress(), b.stress());
        assert_eq!(a.tangent(), b.tangent());
        a.commit_state();
        b.commit_state();
        let committed = (a.stress(), a.tangent(), a.strain());
        a.set_trial_strain(-0.01);
        a.revert_to_last_commit();
        assert_eq!(committed, (a.stress(), a.tangent(), a.strain()));
        a.set_trial_strain(-0.002);
        b.set_trial_strain(-0.002);
        assert_eq!(a.stress(), b.stress());
    }

    #[test]
    fn rupture_extension() {
        let mut p = Steel01Params::new(400e6, 200e9, 0.02);
        p.eps_rupture = Some(0.05);
        let mut m = Steel01::new(p).unwrap();
        step(&mut m, 0.04);
        assert!(m.stress() > 400e6 && !m.damage().ruptured);
        step(&mut m, 0.051);
        assert_eq!((m.stress(), m.tangent()), (0.0, 0.0));
        assert!(m.damage().ruptured);
        step(&mut m, -0.01);
        assert_eq!(m.stress(), 0.0);
    }

    #[test]
    fn rejects_bad_parameters() {
        assert!(Steel01::new(Steel01Params::new(-1.0, 200e9, 0.01))
            .unwrap_err()
            .to_string()
            .contains("Fy"));
        assert!(Steel01::new(Steel01Params::new(400e6, 0.0, 0.01))
            .unwrap_err()
            .to_string()
            .contains("E0"));
        assert!(Steel01::new(Steel01Params::new(400e6, 2e11, 1.0))
            .unwrap_err()
            .to_string()
            .contains("b must"));
    }
}
