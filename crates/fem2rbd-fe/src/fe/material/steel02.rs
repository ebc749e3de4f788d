//! Giuffré–Menegotto–Pinto steel with isotropic strain hardening, OpenSees
//! `uniaxialMaterial Steel02 $tag $Fy $E0 $b <$R0 $cR1 $cR2 <$a1 $a2 $a3 $a4 <$sigInit>>>`
//! (class `Steel02`, after Filippou, Popov & Bertero 1983).
//!
//! Each branch runs from the last reversal point (ε_r, σ_r) towards the intersection
//! (ε_0, σ_0) of the elastic line through it with the hardening asymptote of slope
//! b·E0 (Menegotto & Pinto 1973). With ε* = (ε − ε_r)/(ε_0 − ε_r):
//!
//! ```text
//! σ* = b·ε* + (1 − b)·ε* / (1 + |ε*|^R)^(1/R),      σ = σ_r + σ*·(σ_0 − σ_r)
//! E_t = (σ_0 − σ_r)/(ε_0 − ε_r) · [ b + (1 − b) / ((1 + |ε*|^R)^(1 + 1/R)) ]
//! R   = R0 · (1 − cR1·ξ/(cR2 + ξ)),   ξ = |(ε_pl − ε_0)/εy|
//! ```
//!
//! where ε_pl is the largest excursion in the direction of the previous branch, so the
//! curvature parameter R decreases with plastic excursion (Bauschinger effect).
//! Isotropic hardening (Filippou et al. 1983) shifts the asymptote at each reversal by
//! `1 + a1·((ε_max − ε_min)/(2·a2·εy))^0.8` towards compression and by
//! `1 + a3·((ε_max − ε_min)/(2·a4·εy))^0.8` towards tension. εy = Fy/E0.
//!
//! `sigInit` is an initial stress (Pa): the material works internally on ε + sigInit/E0
//! (as OpenSees); [`UniaxialMaterial::strain`] returns the strain as given, without it.
//!
//! Units: Fy, E0, sigInit and stresses in Pa; strains, b, R0, cR1, cR2, a1, a3
//! dimensionless; a2, a4 in multiples of εy.
//!
//! **fem2rbd extension (off by default):** an optional tensile rupture strain
//! `eps_rupture`. Once a trial strain reaches it the bar is ruptured: stress and tangent
//! are 0 for that trial and, after a commit, for ever. OpenSees' Steel02 has no rupture.

use super::MaterialError;
use super::{MaterialDamage, UniaxialMaterial};

/// Parameters of `Steel02` (OpenSees parameter names in code font).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Steel02Params {
    /// Yield strength `Fy` (Pa, > 0).
    pub fy: f64,
    /// Initial elastic modulus `E0` (Pa, > 0).
    pub e0: f64,
    /// Strain-hardening ratio `b` (–, 0 ≤ b < 1).
    pub b: f64,
    /// Initial curvature parameter `R0` (–, > 0; OpenSees default 15, usually 10–20).
    pub r0: f64,
    /// Curvature degradation `cR1` (–, 0 ≤ cR1 < 1; default 0.925).
    pub c_r1: f64,
    /// Curvature degradation `cR2` (–, > 0; default 0.15).
    pub c_r2: f64,
    /// Isotropic hardening in compression `a1` (–, default 0).
    pub a1: f64,
    /// Reference range for a1 in multiples of εy `a2` (> 0, default 1).
    pub a2: f64,
    /// Isotropic hardening in tension `a3` (–, default 0).
    pub a3: f64,
    /// Reference range for a3 in multiples of εy `a4` (> 0, default 1).
    pub a4: f64,
    /// Initial stress `sigInit` (Pa, default 0).
    pub sig_init: f64,
    /// Tensile rupture strain (–, > Fy/E0); `None` (default) = never ruptures.
    pub eps_rupture: Option<f64>,
}

impl Steel02Params {
    /// Parameters with OpenSees' defaults R0 = 15, cR1 = 0.925, cR2 = 0.15, a1 = a3 = 0,
    /// a2 = a4 = 1, sigInit = 0, and no rupture.
    pub fn new(fy: f64, e0: f64, b: f64) -> Self {
        Self {
            fy,
            e0,
            b,
            r0: 15.0,
            c_r1: 0.925,
            c_r2: 0.15,
            a1: 0.0,
            a2: 1.0,
            a3: 0.0,
            a4: 1.0,
            sig_init: 0.0,
            eps_rupture: None,
        }
    }
}

/// Which branch the material is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Branch {
    /// No strain change yet from the initial state.
    Virgin,
    /// Strain increasing (towards the tension asymptote).
    Up,
    /// Strain decreasing (towards the compression asymptote).
    Down,
}

/// Trial or committed state of `Steel02`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct State {
    /// Strain as given by the caller (–).
    strain: f64,
    /// Internal strain ε = strain + sigInit/E0 (–).
    eps: f64,
    sig: f64,
    e: f64,
    eps_max: f64,
    eps_min: f64,
    /// Largest excursion in the direction of the previous branch (ε_pl).
    eps_pl: f64,
    /// Asymptote intersection point (ε_0, σ_0) of the current branch.
    eps_0: f64,
    sig_0: f64,
    /// Last reversal point (ε_r, σ_r).
    eps_r: f64,
    sig_r: f64,
    branch: Branch,
    yielded: bool,
    ruptured: bool,
}

/// OpenSees Steel02 (Giuffré–Menegotto–Pinto with isotropic hardening).
#[derive(Debug, Clone)]
pub struct Steel02 {
    p: Steel02Params,
    trial: State,
    committed: State,
}

impl Steel02 {
    /// Validates the parameters and returns the material in its virgin state.
    pub fn new(p: Steel02Params) -> Result<Self, MaterialError> {
        let fin = |v: f64| v.is_finite();
        if !(fin(p.fy) && p.fy > 0.0) {
            return Err(MaterialError::Parameter(format!(
                "Steel02: Fy must be > 0 (Pa), got {}",
                p.fy
            )));
        }
        if !(fin(p.e0) && p.e0 > 0.0) {
            return Err(MaterialError::Parameter(format!(
                "Steel02: E0 must be > 0 (Pa), got {}",
                p.e0
            )));
        }
        if !(fin(p.b) && (0.0..1.0).contains(&p.b)) {
            return Err(MaterialError::Parameter(format!(
                "Steel02: b must be in [0, 1), got {}",
                p.b
            )));
        }
        if !(fin(p.r0) && p.r0 > 0.0) {
            return Err(MaterialError::Parameter(format!(
                "Steel02: R0 must be > 0, got {}",
                p.r0
            )));
        }
        if !(fin(p.c_r1) && (0.0..1.0).contains(&p.c_r1)) {
            return Err(MaterialError::Parameter(format!(
                "Steel02: cR1 must be in [0, 1), got {}",
                p.c_r1
            )));
        }
        if !(fin(p.c_r2) && p.c_r2 > 0.0) {
            return Err(MaterialError::Parameter(format!(
                "Steel02: cR2 must be > 0, got {}",
                p.c_r2
            )));
        }
        if !(fin(p.a1) && fin(p.a3)) {
            return Err(MaterialError::Parameter(format!(
                "Steel02: a1 and a3 must be finite, got {} and {}",
                p.a1, p.a3
            )));
        }
        if !(fin(p.a2) && p.a2 > 0.0 && fin(p.a4) && p.a4 > 0.0) {
            return Err(MaterialError::Parameter(format!(
                "Steel02: a2 and a4 must be > 0, got {} and {}",
                p.a2, p.a4
            )));
        }
        if !fin(p.sig_init) {
            return Err(MaterialError::Parameter(format!(
                "Steel02: sigInit must be finite, got {}",
                p.sig_init
            )));
        }
        if let Some(er) = p.eps_rupture {
            if !(fin(er) && er > p.fy / p.e0) {
                return Err(MaterialError::Parameter(format!(
                    "Steel02: eps_rupture must exceed the yield strain Fy/E0 = {}, got {er}",
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
    pub fn params(&self) -> &Steel02Params {
        &self.p
    }

    fn virgin(p: &Steel02Params) -> State {
        let eps_y = p.fy / p.e0;
        State {
            strain: 0.0,
            eps: if p.sig_init != 0.0 {
                p.sig_init / p.e0
            } else {
                0.0
            },
            sig: p.sig_init,
            e: p.e0,
            eps_max: eps_y,
            eps_min: -eps_y,
            eps_pl: 0.0,
            eps_0: 0.0,
            sig_0: 0.0,
            eps_r: 0.0,
            sig_r: 0.0,
            branch: Branch::Virgin,
            yielded: false,
            ruptured: false,
        }
    }

    /// Menegotto–Pinto state determination from committed `c` into `t` (t.eps set).
    fn menegotto_pinto(&self, c: &State, t: &mut State) {
        let p = &self.p;
        let esh = p.b * p.e0;
        let eps_y = p.fy / p.e0;
        let deps = t.eps - c.eps;

        if t.branch == Branch::Virgin {
            if deps.abs() < 10.0 * f64::EPSILON {
                t.e = p.e0;
                t.sig = p.sig_init;
                return;
            }
            t.eps_max = eps_y;
            t.eps_min = -eps_y;
            if deps < 0.0 {
                t.branch = Branch::Down;
                t.eps_0 = t.eps_min;
                t.sig_0 = -p.fy;
                t.eps_pl = t.eps_min;
            } else {
                t.branch = Branch::Up;
                t.eps_0 = t.eps_max;
                t.sig_0 = p.fy;
                t.eps_pl = t.eps_max;
            }
        }

        if t.branch == Branch::Down && deps > 0.0 {
            // Reversal from a descending to an ascending branch at the committed point.
            t.branch = Branch::Up;
            t.eps_r = c.eps;
            t.sig_r = c.sig;
            t.eps_min = t.eps_min.min(c.eps);
            let range = (t.eps_max - t.eps_min) / (2.0 * (p.a4 * eps_y));
            let shift = 1.0 + p.a3 * range.powf(0.8);
            t.eps_0 =
                (p.fy * shift - esh * eps_y * shift - t.sig_r + p.e0 * t.eps_r) / (p.e0 - esh);
            t.sig_0 = p.fy * shift + esh * (t.eps_0 - eps_y * shift);
            t.eps_pl = t.eps_max;
        } else if t.branch == Branch::Up && deps < 0.0 {
            // Reversal from an ascending to a descending branch.
            t.branch = Branch::Down;
            t.eps_r = c.eps;
            t.sig_r = c.sig;
            t.eps_max = t.eps_max.max(c.eps);
            let range = (t.eps_max - t.eps_min) / (2.0 * (p.a2 * eps_y));
            let shift = 1.0 + p.a1 * range.powf(0.8);
            t.eps_0 =
                (-p.fy * shift + esh * eps_y * shift - t.sig_r + p.e0 * t.eps_r) / (p.e0 - esh);
            t.sig_0 = -p.fy * shift + esh * (t.eps_0 + eps_y * shift);
            t.eps_pl = t.eps_min;
        }

        let xi = ((t.eps_pl - t.eps_0) / eps_y).abs();
        let r = p.r0 * (1.0 - (p.c_r1 * xi) / (p.c_r2 + xi));
        let eps_star = (t.eps - t.eps_r) / (t.eps_0 - t.eps_r);
        let d1 = 1.0 + eps_star.abs().powf(r);
        let d2 = d1.powf(1.0 / r);
        let sig_star = p.b * eps_star + (1.0 - p.b) * eps_star / d2;
        t.sig = sig_star * (t.sig_0 - t.sig_r) + t.sig_r;
        let e_star = p.b + (1.0 - p.b) / (d1 * d2);
        t.e = e_star * (t.sig_0 - t.sig_r) / (t.eps_0 - t.eps_r);
    }
}

impl UniaxialMaterial for Steel02 {
    fn set_trial_strain(&mut self, strain: f64) {
        let c = self.committed;
        let mut t = c;
        t.strain = strain;
        t.eps = if self.p.sig_init != 0.0 {
            strain + self.p.sig_init / self.p.e0
        } else {
            strain
        };
        if c.ruptured {
            self.trial = t;
            return;
        }
        self.menegotto_pinto(&c, &mut t);
        t.yielded |= t.eps.abs() > self.p.fy / self.p.e0;
        if let Some(er) = self.p.eps_rupture {
            if t.strain >= er {
                t.ruptured = true;
                t.sig = 0.0;
                t.e = 0.0;
            }
        }
        self.trial = t;
    }
    fn strain(&self) -> f64 {
        self.trial.strain
    }
    fn stress(&self) -> f64 {
        self.trial.sig
    }
    fn tangent(&self) -> f64 {
        self.trial.e
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

    fn bar() -> Steel02 {
        Steel02::new(Steel02Params {
            r0: 18.0,
            ..Steel02Params::new(457.7e6, 200e9, 0.01)
        })
        .unwrap()
    }

    fn step(m: &mut Steel02, eps: f64) -> f64 {
        m.set_trial_strain(eps);
        m.commit_state();
        m.stress()
    }

    #[test]
    fn elastic_start_and_asymptote() {
        let mut m = bar();
        let eps_y = 457.7e6 / 200e9;
        // Far below yield the curve is E0·ε to within the Menegotto-Pinto smoothing.
        let s = step(&mut m, 0.2 * eps_y);
        assert!((s - 200e9 * 0.2 * eps_y).abs() < 1e-6 * 457.7e6);
        assert!(!m.damage().yielded);
        // Far past yield it approaches the asymptote Fy + b·E0·(ε − εy).
        let eps = 20.0 * eps_y;
        let s = step(&mut m, eps);
        let asymptote = 457.7e6 + 0.01 * 200e9 * (eps - eps_y);
        assert!((s - asymptote).abs() < 1e-6 * 457.7e6, "{s} vs {asymptote}");
        assert!(m.damage().yielded);
    }

    #[test]
    fn trial_twice_and_revert() {
        let mut a = bar();
        let mut b = bar();
        for m in [&mut a, &mut b] {
            step(m, 0.01);
            step(m, -0.004);
        }
        a.set_trial_strain(0.02);
        a.set_trial_strain(-0.006);
        b.set_trial_strain(-0.006);
        assert_eq!((a.stress(), a.tangent()), (b.stress(), b.tangent()));
        a.revert_to_last_commit();
        assert_eq!(a.strain(), -0.004);
        a.set_trial_strain(-0.006);
        assert_eq!(a.stress(), b.stress());
    }

    #[test]
    fn sig_init_is_the_stress_at_zero_strain() {
        let mut m = Steel02::new(Steel02Params {
            sig_init: 100e6,
            ..Steel02Params::new(400e6, 200e9, 0.01)
        })
        .unwrap();
        m.set_trial_strain(0.0);
        assert_eq!(m.stress(), 100e6);
    }

    #[test]
    fn rejects_bad_parameters() {
        let p = Steel02Params::new(400e6, 200e9, 0.01);
        assert!(Steel02::new(Steel02Params { fy: 0.0, ..p })
            .unwrap_err()
            .to_string()
            .contains("Fy"));
        assert!(Steel02::new(Steel02Params { c_r2: 0.0, ..p })
            .unwrap_err()
            .to_string()
            .contains("cR2"));
        assert!(Steel02::new(Steel02Params {
            eps_rupture: Some(1e-3),
            ..p
        })
        .unwrap_err()
        .to_string()
        .contains("eps_rupture"));
    }
}
