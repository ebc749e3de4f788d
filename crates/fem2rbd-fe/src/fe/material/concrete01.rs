//! Kent–Scott–Park concrete without tensile strength, OpenSees
//! `uniaxialMaterial Concrete01 $tag $fpc $epsc0 $fpcu $epscU` (class `Concrete01`).
//!
//! Compression envelope (Kent & Park 1971, as modified by Scott, Park & Priestley 1982),
//! compression negative, η = ε/ε_c0:
//!
//! ```text
//! ε ≥ ε_c0 :        σ = f'c·(2η − η²)                      (parabola, E_c0 = 2 f'c/ε_c0)
//! ε_cu < ε < ε_c0 : σ = f'c + (f'c − f'cu)/(ε_c0 − ε_cu)·(ε − ε_c0)  (linear descent)
//! ε ≤ ε_cu :        σ = f'cu                                (residual plateau)
//! ```
//!
//! Unloading from the largest compressive strain ε_min follows a straight line to the
//! plastic strain ε_p given by Karsan & Jirsa (1969): with η_m = max(ε_min, ε_cu)/ε_c0,
//! ε_p/ε_c0 = 0.145·η_m² + 0.13·η_m for η_m < 2 and 0.707·(η_m − 2) + 0.834 otherwise;
//! the unloading slope is never taken stiffer than E_c0 (then ε_p moves accordingly).
//! Reloading retraces the same line; there is no tensile strength (σ = 0 for ε > ε_p and
//! for every ε > 0). This follows OpenSees' implementation (Filippou / Scott).
//!
//! Units: f'c, f'cu and stresses in Pa; strains dimensionless. Compression negative.

use super::MaterialError;
use super::{MaterialDamage, UniaxialMaterial};

/// Trial or committed state of `Concrete01`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct State {
    strain: f64,
    stress: f64,
    tangent: f64,
    /// Largest compressive strain so far (≤ 0).
    min_strain: f64,
    /// Strain at zero stress of the current unloading line.
    end_strain: f64,
    /// Slope of the current unloading/reloading line (Pa).
    unload_slope: f64,
}

/// OpenSees Concrete01 (Kent–Scott–Park, no tension, Karsan–Jirsa unloading).
#[derive(Debug, Clone)]
pub struct Concrete01 {
    fpc: f64,
    epsc0: f64,
    fpcu: f64,
    epscu: f64,
    trial: State,
    committed: State,
}

impl Concrete01 {
    /// Concrete with compressive strength `fpc` (Pa, < 0), strain at strength `epsc0`
    /// (< 0), residual (crushing) strength `fpcu` (Pa, ≤ 0) reached at strain `epscu`
    /// (≤ epsc0). OpenSees silently flips positive values; this constructor rejects them.
    pub fn new(fpc: f64, epsc0: f64, fpcu: f64, epscu: f64) -> Result<Self, MaterialError> {
        check_compression_envelope("Concrete01", fpc, epsc0, fpcu, epscu)?;
        let mut m = Self {
            fpc,
            epsc0,
            fpcu,
            epscu,
            trial: State {
                strain: 0.0,
                stress: 0.0,
                tangent: 0.0,
                min_strain: 0.0,
                end_strain: 0.0,
                unload_slope: 0.0,
            },
            committed: State {
                strain: 0.0,
                stress: 0.0,
                tangent: 0.0,
                min_strain: 0.0,
                end_strain: 0.0,
                unload_slope: 0.0,
            },
        };
        m.revert_to_start();
        Ok(m)
    }

    /// Initial modulus E_c0 = 2 f'c/ε_c0 (Pa).
    pub fn ec0(&self) -> f64 {
        2.0 * self.fpc / self.epsc0
    }

    /// Compressive strength f'c (Pa, negative).
    pub fn fpc(&self) -> f64 {
        self.fpc
    }

    /// Envelope stress and tangent at strain `eps`.
    fn envelope(&self, eps: f64) -> (f64, f64) {
        if eps > self.epsc0 {
            let eta = eps / self.epsc0;
            (self.fpc * (2.0 * eta - eta * eta), self.ec0() * (1.0 - eta))
        } else if eps > self.epscu {
            let slope = (self.fpc - self.fpcu) / (self.epsc0 - self.epscu);
            (self.fpc + slope * (eps - self.epsc0), slope)
        } else {
            (self.fpcu, 0.0)
        }
    }

    /// Karsan–Jirsa unloading line from the envelope point (t.min_strain, t.stress).
    fn set_unloading_line(&self, t: &mut State) {
        let eta = t.min_strain.max(self.epscu) / self.epsc0;
        let ratio = if eta < 2.0 {
            0.145 * eta * eta + 0.13 * eta
        } else {
            0.707 * (eta - 2.0) + 0.834
        };
        t.end_strain = ratio * self.epsc0;
        let ec0 = self.ec0();
        let span = t.min_strain - t.end_strain;
        let elastic_span = t.stress / ec0;
        if span > -f64::EPSILON {
            t.unload_slope = ec0;
        } else if span <= elastic_span {
            t.end_strain = t.min_strain - span;
            t.unload_slope = t.stress / span;
        } else {
            // The Karsan-Jirsa line would be stiffer than E_c0: unload with E_c0.
            t.end_strain = t.min_strain - elastic_span;
            t.unload_slope = ec0;
        }
    }

    /// Loading further into compression: envelope if past the previous minimum, else
    /// back along the unloading line, else zero (open crack).
    fn reload(&self, t: &mut State) {
        if t.strain <= t.min_strain {
            t.min_strain = t.strain;
            let (s, e) = self.envelope(t.strain);
            t.stress = s;
            t.tangent = e;
            self.set_unloading_line(t);
        } else if t.strain <= t.end_strain {
            t.tangent = t.unload_slope;
            t.stress = t.tangent * (t.strain - t.end_strain);
        } else {
            t.stress = 0.0;
            t.tangent = 0.0;
        }
    }
}

/// Shared parameter checks of the Kent–Scott–Park compression envelope.
pub(crate) fn check_compression_envelope(
    kind: &str,
    fpc: f64,
    epsc0: f64,
    fpcu: f64,
    epscu: f64,
) -> Result<(), MaterialError> {
    if !(fpc.is_finite() && fpc < 0.0) {
        return Err(MaterialError::Parameter(format!(
            "{kind}: fpc must be < 0 (compressive strength in Pa, compression negative), got {fpc}"
        )));
    }
    if !(epsc0.is_finite() && epsc0 < 0.0) {
        return Err(MaterialError::Parameter(format!(
            "{kind}: epsc0 must be < 0 (strain at fpc), got {epsc0}"
        )));
    }
    if !(fpcu.is_finite() && fpcu <= 0.0) {
        return Err(MaterialError::Parameter(format!(
            "{kind}: fpcu must be ≤ 0 (residual strength in Pa), got {fpcu}"
        )));
    }
    if !(epscu.is_finite() && epscu <= epsc0) {
        return Err(MaterialError::Parameter(format!(
            "{kind}: epscu must be ≤ epsc0 = {epsc0} (crushing strain, compression negative), got {epscu}"
        )));
    }
    Ok(())
}

impl UniaxialMaterial for Concrete01 {
    fn set_trial_strain(&mut self, strain: f64) {
        let c = self.committed;
        let mut t = c;
        if (strain - c.strain).abs() < f64::EPSILON {
            self.trial = t;
            return;
        }
        t.strain = strain;
        if strain > 0.0 {
            t.stress = 0.0;
            t.tangent = 0.0;
        } else {
            let along_unloading = c.stress + c.unload_slope * strain - c.unload_slope * c.strain;
            if strain < c.strain {
                self.reload(&mut t);
                if along_unloading > t.stress {
                    t.stress = along_unloading;
                    t.tangent = t.unload_slope;
                }
            } else if along_unloading <= 0.0 {
                t.stress = along_unloading;
                t.tangent = c.unload_slope;
            } else {
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
        self.ec0()
    }
    fn commit_state(&mut self) {
        self.committed = self.trial;
    }
    fn revert_to_last_commit(&mut self) {
        self.trial = self.committed;
    }
    fn revert_to_start(&mut self) {
        let ec0 = self.ec0();
        self.committed = State {
            strain: 0.0,
            stress: 0.0,
            tangent: ec0,
            min_strain: 0.0,
            end_strain: 0.0,
            unload_slope: ec0,
        };
        self.trial = self.committed;
    }
    fn boxed_clone(&self) -> Box<dyn UniaxialMaterial> {
        Box::new(self.clone())
    }
    /// Yielded: the committed compressive strain has reached epsc0 (peak strength passed).
    /// Ruptured: it has reached epscu (crushed to the residual strength).
    fn damage(&self) -> MaterialDamage {
        MaterialDamage {
            yielded: self.committed.min_strain <= self.epsc0,
            ruptured: self.committed.min_strain <= self.epscu,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn concrete() -> Concrete01 {
        Concrete01::new(-30e6, -0.002, -6e6, -0.006).unwrap()
    }

    fn step(m: &mut Concrete01, eps: f64) -> (f64, f64) {
        m.set_trial_strain(eps);
        m.commit_state();
        (m.stress(), m.tangent())
    }

    #[test]
    fn peak_descent_and_residual() {
        let mut m = concrete();
        assert_eq!(m.initial_tangent(), 2.0 * 30e6 / 0.002);
        let (s, _) = step(&mut m, -0.001);
        assert!((s - (-30e6 * 0.75)).abs() < 1e-6);
        // At ε_c0 exactly OpenSees is already on the descending line (stress f'c).
        let (s, _) = step(&mut m, -0.002);
        assert!((s + 30e6).abs() < 1e-6);
        assert!(m.damage().yielded && !m.damage().ruptured);
        let (s, e) = step(&mut m, -0.004);
        assert!((s + 18e6).abs() < 1e-6, "{s}");
        assert!((e - (-24e6 / 0.004)).abs() < 1e-3, "{e}");
        let (s, e) = step(&mut m, -0.008);
        assert_eq!((s, e), (-6e6, 0.0));
        assert!(m.damage().ruptured);
        // No tension.
        let (s, e) = step(&mut m, 0.001);
        assert_eq!((s, e), (0.0, 0.0));
    }

    #[test]
    fn karsan_jirsa_plastic_strain() {
        let mut m = concrete();
        step(&mut m, -0.003); // η = 1.5: ε_p = (0.145·2.25 + 0.13·1.5)·ε_c0
        let ep = (0.145 * 2.25 + 0.13 * 1.5) * -0.002;
        let (s, _) = step(&mut m, ep + 1e-9);
        assert!(s.abs() < 30e6 * 1e-5, "{s}");
        let (s, _) = step(&mut m, ep - 1e-4);
        assert!(s < 0.0);
    }

    #[test]
    fn trial_twice_and_revert() {
        let mut a = concrete();
        let mut b = concrete();
        step(&mut a, -0.0025);
        step(&mut b, -0.0025);
        a.set_trial_strain(-0.005);
        a.set_trial_strain(-0.001);
        b.set_trial_strain(-0.001);
        assert_eq!((a.stress(), a.tangent()), (b.stress(), b.tangent()));
        a.revert_to_last_commit();
        assert_eq!(a.strain(), -0.0025);
        a.set_trial_strain(-0.005);
        b.revert_to_last_commit();
        b.set_trial_strain(-0.005);
        assert_eq!(a.stress(), b.stress());
    }

    #[test]
    fn rejects_bad_parameters() {
        assert!(Concrete01::new(30e6, -0.002, -6e6, -0.006)
            .unwrap_err()
            .to_string()
            .contains("fpc"));
        assert!(Concrete01::new(-30e6, 0.002, -6e6, -0.006)
            .unwrap_err()
            .to_string()
            .contains("epsc0"));
        assert!(Concrete01::new(-30e6, -0.002, -6e6, -0.001)
            .unwrap_err()
            .to_string()
            .contains("epscu"));
    }
}
