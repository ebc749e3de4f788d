//! Concrete with linear tension softening, OpenSees
//! `uniaxialMaterial Concrete02 $tag $fpc $epsc0 $fpcu $epscU <$lambda $ft $Ets>`
//! (class `Concrete02`; Yassin 1994).
//!
//! Compression envelope (Kent & Park 1971 modified by Scott, Park & Priestley 1982),
//! compression negative, η = ε/ε_c0, E_c0 = 2 f'c/ε_c0 (so the initial tangent is
//! **2·fpc/epsc0**, not an independent modulus):
//!
//! ```text
//! ε ≥ ε_c0 :        σ = f'c·η·(2 − η)
//! ε_cu < ε < ε_c0 : σ = f'c + (f'cu − f'c)·(ε − ε_c0)/(ε_cu − ε_c0)
//! ε ≤ ε_cu :        σ = f'cu   (tangent 1e-10 Pa, as OpenSees)
//! ```
//!
//! Tension envelope: linear E_c0·ε up to f_t at ε_t = f_t/E_c0, then linear softening
//! σ = f_t − E_ts·(ε − ε_t) to zero at ε_t + f_t/E_ts, zero beyond (tangent 1e-10 Pa).
//!
//! Cyclic rules (Yassin 1994; Filippou, Popov & Bertero 1983, EERC 83/19 §2): all
//! unloading and reloading lines in compression aim at a common point R,
//! ε_R = (f'cu − λ·E_c0·ε_cu)/(E_c0·(1 − λ)), σ_R = E_c0·ε_R. From the largest
//! compressive strain ε_min (envelope stress σ_m) the reloading slope is
//! E_r = (σ_m − σ_R)/(ε_min − ε_R), and it crosses zero stress at ε_pt = ε_min − σ_m/E_r.
//! Below ε_pt the stress follows an elastic predictor of slope E_c0 bounded by the
//! reloading line σ_m + E_r·(ε − ε_min) (below) and the unloading line ½E_r·(ε − ε_pt)
//! (above). Above ε_pt the material is in tension, shifted by ε_pt: it reloads linearly
//! to the largest tensile excursion so far and then follows the shifted tension envelope.
//! λ is the ratio of the unloading slope at ε_cu to E_c0.
//!
//! Units: f'c, f'cu, f_t and stresses in Pa; E_ts in Pa; strains and λ dimensionless.

use super::concrete01::check_compression_envelope;
use super::MaterialError;
use super::{MaterialDamage, UniaxialMaterial};

/// Parameters of `Concrete02` (OpenSees parameter names in code font).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Concrete02Params {
    /// Compressive strength `fpc` (Pa, < 0).
    pub fpc: f64,
    /// Strain at compressive strength `epsc0` (–, < 0).
    pub epsc0: f64,
    /// Crushing (residual) strength `fpcu` (Pa, ≤ 0).
    pub fpcu: f64,
    /// Strain at crushing strength `epscU` (–, ≤ epsc0).
    pub epscu: f64,
    /// Ratio of unloading slope at epscu to the initial slope `lambda` (–, 0 ≤ λ < 1).
    pub lambda: f64,
    /// Tensile strength `ft` (Pa, ≥ 0).
    pub ft: f64,
    /// Tension softening stiffness `Ets` (Pa, > 0; the magnitude of the slope).
    pub ets: f64,
}

impl Concrete02Params {
    /// The four compression parameters with OpenSees' defaults for the rest:
    /// λ = 0.1, f_t = 0.1·|f'c|, E_ts = 0.1·f'c/ε_c0.
    pub fn new(fpc: f64, epsc0: f64, fpcu: f64, epscu: f64) -> Self {
        Self {
            fpc,
            epsc0,
            fpcu,
            epscu,
            lambda: 0.1,
            ft: (0.1 * fpc).abs(),
            ets: 0.1 * fpc / epsc0,
        }
    }
}

/// Trial or committed state of `Concrete02`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct State {
    eps: f64,
    sig: f64,
    e: f64,
    /// Largest compressive strain so far (≤ 0).
    ecmin: f64,
    /// Largest tensile excursion beyond the zero-stress strain ε_pt so far.
    dept: f64,
}

/// OpenSees Concrete02 (Kent–Scott–Park compression, linear tension softening).
#[derive(Debug, Clone)]
pub struct Concrete02 {
    p: Concrete02Params,
    /// Constants of the law, formed once from `p` (the same expressions, hence bits, as
    /// forming them on every trial).
    k: Derived,
    trial: State,
    committed: State,
}

/// Constants derived from the parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Derived {
    /// E_c0 = 2 f'c / ε_c0.
    ec0: f64,
    /// Slope of the descending branch, (f'cu − f'c)/(ε_cu − ε_c0).
    slope: f64,
    /// ε_R of the common point R.
    eps_r: f64,
    /// σ_R = E_c0 ε_R.
    sig_r: f64,
    /// ε_t = f_t / E_c0.
    eps_t: f64,
    /// Strain where the tension envelope reaches zero, f_t (1/E_ts + 1/E_c0).
    eps_zero: f64,
}

impl Derived {
    fn new(p: &Concrete02Params) -> Self {
        let ec0 = 2.0 * p.fpc / p.epsc0;
        let eps_r = (p.fpcu - p.lambda * ec0 * p.epscu) / (ec0 * (1.0 - p.lambda));
        Self {
            ec0,
            slope: (p.fpcu - p.fpc) / (p.epscu - p.epsc0),
            eps_r,
            sig_r: ec0 * eps_r,
            eps_t: p.ft / ec0,
            eps_zero: p.ft * (1.0 / p.ets + 1.0 / ec0),
        }
    }
}

impl Concrete02 {
    /// Validates the parameters and returns the material in its virgin state.
    /// OpenSees silently flips positive compression values; this constructor rejects them.
    pub fn new(p: Concrete02Params) -> Result<Self, MaterialError> {
        check_compression_envelope("Concrete02", p.fpc, p.epsc0, p.fpcu, p.epscu)?;
        if !(p.lambda.is_finite() && (0.0..1.0).contains(&p.lambda)) {
            return Err(MaterialError::Parameter(format!(
                "Concrete02: lambda must be in [0, 1), got {}",
                p.lambda
            )));
        }
        if !(p.ft.is_finite() && p.ft >= 0.0) {
            return Err(MaterialError::Parameter(format!(
                "Concrete02: ft must be ≥ 0 (Pa), got {}",
                p.ft
            )));
        }
        if !(p.ets.is_finite() && p.ets > 0.0) {
            return Err(MaterialError::Parameter(format!(
                "Concrete02: Ets must be > 0 (Pa), got {}",
                p.ets
            )));
        }
        if p.fpcu == 0.0 && p.lambda == 0.0 {
            return Err(MaterialError::Parameter(
                "Concrete02: fpcu = 0 together with lambda = 0 puts the common \
                        reloading point R at the origin (undefined reloading slope); \
                        give fpcu < 0 or lambda > 0"
                    .to_string(),
            ));
        }
        let s = Self::virgin(&p);
        Ok(Self {
            p,
            k: Derived::new(&p),
            trial: s,
            committed: s,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &Concrete02Params {
        &self.p
    }

    /// Initial modulus E_c0 = 2 f'c/ε_c0 (Pa).
    pub fn ec0(&self) -> f64 {
        self.k.ec0
    }

    fn virgin(p: &Concrete02Params) -> State {
        State {
            eps: 0.0,
            sig: 0.0,
            e: 2.0 * p.fpc / p.epsc0,
            ecmin: 0.0,
            dept: 0.0,
        }
    }

    /// Compression envelope: stress and tangent at strain `eps`.
    fn compression_envelope(&self, eps: f64) -> (f64, f64) {
        let p = &self.p;
        let ec0 = self.k.ec0;
        let eta = eps / p.epsc0;
        if eps >= p.epsc0 {
            (p.fpc * eta * (2.0 - eta), ec0 * (1.0 - eta))
        } else if eps > p.epscu {
            let slope = self.k.slope;
            (
                (p.fpcu - p.fpc) * (eps - p.epsc0) / (p.epscu - p.epsc0) + p.fpc,
                slope,
            )
        } else {
            (p.fpcu, 1.0e-10)
        }
    }

    /// Tension envelope: stress and tangent at strain `eps` (measured from zero stress).
    fn tension_envelope(&self, eps: f64) -> (f64, f64) {
        let p = &self.p;
        let ec0 = self.k.ec0;
        let (eps_t, eps_zero) = (self.k.eps_t, self.k.eps_zero);
        if eps <= eps_t {
            (eps * ec0, ec0)
        } else if eps <= eps_zero {
            (p.ft - p.ets * (eps - eps_t), -p.ets)
        } else {
            (0.0, 1.0e-10)
        }
    }
}

impl UniaxialMaterial for Concrete02 {
    fn set_trial_strain(&mut self, strain: f64) {
        let c = self.committed;
        let mut t = c;
        t.eps = strain;
        let deps = strain - c.eps;
        // OpenSees returns early here leaving the previous *trial* stress; keeping the
        // committed one is the same in a commit-every-step history and makes repeated
        // trials independent of each other.
        if deps.abs() < f64::EPSILON {
            self.trial = t;
            return;
        }
        let ec0 = self.ec0();
        if strain < c.ecmin {
            let (s, e) = self.compression_envelope(strain);
            t.sig = s;
            t.e = e;
            t.ecmin = strain;
        } else {
            let (eps_r, sig_r) = (self.k.eps_r, self.k.sig_r);
            let (sig_m, _) = self.compression_envelope(c.ecmin);
            let e_r = (sig_m - sig_r) / (c.ecmin - eps_r);
            let ept = c.ecmin - sig_m / e_r;
            if strain <= ept {
                let sig_min = sig_m + e_r * (strain - c.ecmin);
                let sig_max = e_r * 0.5 * (strain - ept);
                t.sig = c.sig + ec0 * deps;
                t.e = ec0;
                if t.sig <= sig_min {
                    t.sig = sig_min;
                    t.e = e_r;
                }
                if t.sig >= sig_max {
                    t.sig = sig_max;
                    t.e = 0.5 * e_r;
                }
            } else if strain <= ept + c.dept {
                // Linear reloading towards the largest tensile excursion so far.
                let (sig_n, _) = self.tension_envelope(c.dept);
                t.e = if c.dept != 0.0 { sig_n / c.dept } else { ec0 };
                t.sig = t.e * (strain - ept);
            } else {
                let (s, e) = self.tension_envelope(strain - ept);
                t.sig = s;
                t.e = e;
                t.dept = strain - ept;
            }
        }
        self.trial = t;
    }
    fn strain(&self) -> f64 {
        self.trial.eps
    }
    fn stress(&self) -> f64 {
        self.trial.sig
    }
    fn tangent(&self) -> f64 {
        self.trial.e
    }
    fn initial_tangent(&self) -> f64 {
        self.ec0()
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
    /// Yielded: the committed compressive strain has reached epsc0 (peak strength passed).
    /// Ruptured: it has reached epscu (crushed to the residual strength).
    fn damage(&self) -> MaterialDamage {
        MaterialDamage {
            yielded: self.committed.ecmin <= self.p.epsc0,
            ruptured: self.committed.ecmin <= self.p.epscu,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// frame3's cover concrete (cover_F1).
    fn cover() -> Concrete02 {
        Concrete02::new(Concrete02Params {
            fpc: -22.5e6,
            epsc0: -0.0018,
            fpcu: -4.5e6,
            epscu: -0.004,
            lambda: 0.1,
            ft: 1.5653274417833479e6,
            ets: 782663720.8916739,
        })
        .unwrap()
    }

    fn step(m: &mut Concrete02, eps: f64) -> (f64, f64) {
        m.set_trial_strain(eps);
        m.commit_state();
        (m.stress(), m.tangent())
    }

    #[test]
    fn initial_tangent_peak_and_residual() {
        let mut m = cover();
        assert_eq!(m.initial_tangent(), 2.0 * -22.5e6 / -0.0018);
        assert!((m.initial_tangent() - 25e9).abs() < 1.0);
        let mut e_prev = f64::INFINITY;
        for i in 1..=18 {
            let eps = if i == 18 { -0.0018 } else { -0.0001 * i as f64 };
            let (s, e) = step(&mut m, eps);
            assert!(e < e_prev && s < 0.0);
            e_prev = e;
        }
        assert!(
            (m.stress() + 22.5e6).abs() < 1e-6 * 22.5e6,
            "{}",
            m.stress()
        );
        assert!(m.tangent().abs() < 1e-3);
        assert!(m.damage().yielded && !m.damage().ruptured);
        let (s, _) = step(&mut m, -0.003);
        assert!((s - (-22.5e6 + 18e6 * 0.0012 / 0.0022)).abs() < 1e-6 * 22.5e6);
        let (s, _) = step(&mut m, -0.006);
        assert_eq!(s, -4.5e6);
        assert!(m.damage().ruptured);
    }

    #[test]
    fn tension_softening_to_zero() {
        let mut m = cover();
        let ec0 = 25e9;
        let ft = 1.5653274417833479e6;
        let ets = 782663720.8916739;
        let eps_t = ft / ec0;
        let (s, e) = step(&mut m, 0.5 * eps_t);
        assert!((s - 0.5 * ft).abs() < 1e-6 * ft && (e - ec0).abs() < 1e-3);
        step(&mut m, eps_t);
        assert!((m.stress() - ft).abs() < 1e-6 * ft);
        let eps = eps_t + 0.5 * ft / ets;
        let (s, e) = step(&mut m, eps);
        assert!((s - 0.5 * ft).abs() < 1e-6 * ft, "{s}");
        assert_eq!(e, -ets);
        let (s, _) = step(&mut m, eps_t + ft / ets + 1e-5);
        assert_eq!(s, 0.0);
        // Back to zero strain: the crack stays open with no stress until ε_pt = 0.
        let (s, _) = step(&mut m, 1e-5);
        assert_eq!(s, 0.0);
    }

    #[test]
    fn trial_twice_and_revert() {
        let mut a = cover();
        let mut b = cover();
        for m in [&mut a, &mut b] {
            step(m, -0.0025);
            step(m, -0.001);
        }
        a.set_trial_strain(0.001);
        a.set_trial_strain(-0.0012);
        b.set_trial_strain(-0.0012);
        assert_eq!((a.stress(), a.tangent()), (b.stress(), b.tangent()));
        // Setting the committed strain again returns the committed stress.
        a.set_trial_strain(-0.001);
        b.revert_to_last_commit();
        assert_eq!((a.stress(), a.tangent()), (b.stress(), b.tangent()));
        a.set_trial_strain(-0.01);
        a.revert_to_last_commit();
        assert_eq!(a.strain(), -0.001);
        assert_eq!(a.stress(), b.stress());
    }

    #[test]
    fn rejects_bad_parameters() {
        let p = Concrete02Params::new(-30e6, -0.002, -6e6, -0.006);
        assert!(Concrete02::new(Concrete02Params { ets: 0.0, ..p })
            .unwrap_err()
            .to_string()
            .contains("Ets"));
        assert!(Concrete02::new(Concrete02Params { lambda: 1.0, ..p })
            .unwrap_err()
            .to_string()
            .contains("lambda"));
        assert!(Concrete02::new(Concrete02Params { fpc: 30e6, ..p })
            .unwrap_err()
            .to_string()
            .contains("fpc"));
    }
}
