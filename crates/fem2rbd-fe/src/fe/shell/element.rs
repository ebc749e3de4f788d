//! The four-node layered shell as an element of the FE domain ([`ShellElement`]):
//! OpenSees' `ASDShellQ4` (small displacements, EAS on, elastic drilling) on a layered or
//! plate section, with nonlinear layers (see [`super::layers`]).
//!
//! State determination (OpenSees 3.7.1 `ASDShellQ4::calculateAll` with `AGQIupdate`):
//! local displacements u = T u_g; the 4 enhanced-strain DOFs q are advanced once per
//! trial by one Newton step of their own equilibrium, q ← q − K_qq⁻¹ (r_q + K_qu Δu)
//! (Δu since the previous trial, K_qq, K_qu, r_q of the previous trial); at each Gauss
//! point ε = B u + B_q q, rotated into the section axes (ε_s = R_sᵀ ε), the section
//! returns σ_s and D_s (σ = R_s σ_s, D = R_s D_s R_sᵀ); then
//! f = Σ (B₁ᵀ σ + b_d k_d b_dᵀ u) dA, K = Σ (B₁ᵀ D B + k_d b_d b_dᵀ) dA,
//! r_q = Σ B_qᵀ σ dA, K_qq = Σ B_qᵀ D B_q dA, K_qu = Σ B_qᵀ D B dA, K_uq = Σ B₁ᵀ D B_q dA,
//! condensed: f ← f − K_uq K_qq⁻¹ r_q, K ← K − K_uq K_qq⁻¹ K_qu; global: Tᵀ f, Tᵀ K T.
//! With elastic layers this is the exact static condensation of [`super::asd_shell_q4_stiffness`].
//!
//! Corotational elements (`corotational = true`, OpenSees `-corotational`) run the same
//! local element on the deformational displacements of the corotated frame instead of
//! u = T u_g, and map its force and tangent back with the EICR projector and the
//! geometric stiffness (see `corotational.rs`): r = Tᵀ Pₜᵀ f,
//! K = Tᵀ (Pₜᵀ K H (Pₜ − S G) − F̃ G) T.

use nalgebra::{DMatrix, DVector, SMatrix, SVector};

use super::corotational::Corotational;
use super::layers::{LayeredSection, Vec8};
use super::{drilling_stiffness, Mat24, ShellError, ShellKinematics};
use crate::fe::element::{dmat, dvec, Element, ElementDamage, ElementError, EndDisplacements};

type Vec24 = SVector<f64, 24>;
type Vec4 = SVector<f64, 4>;
type Mat4 = SMatrix<f64, 4, 4>;
type Mat4x24 = SMatrix<f64, 4, 24>;
type Mat24x4 = SMatrix<f64, 24, 4>;

/// Enhanced-strain (AGQI) internal state.
#[derive(Debug, Clone, Copy)]
struct Eas {
    /// Internal DOFs.
    q: Vec4,
    /// Local displacements at the last update.
    u: Vec24,
    /// Residual r_q, K_qq⁻¹ and K_qu of the last state determination.
    rq: Vec4,
    kqq_inv: Mat4,
    kqu: Mat4x24,
}

/// A four-node `ASDShellQ4` shell element of the domain (24 DOFs, global axes).
#[derive(Debug)]
pub struct ShellElement {
    tag: i64,
    nodes: [usize; 4],
    kin: ShellKinematics,
    k_drill: f64,
    sections: Vec<LayeredSection>,
    /// Whether every layer is linear (then the state is K₀ u and nothing is stored).
    linear: bool,
    k0: Mat24,
    u_g: Vec24,
    f: Vec24,
    k: Mat24,
    eas: Eas,
    eas_committed: Eas,
    f_committed: Vec24,
    k_committed: Mat24,
    /// Corotational kinematics (`None`: small displacements).
    corot: Option<Box<Corotational>>,
}

impl ShellElement {
    /// An element with corner nodes `nodes` (domain indices, counter-clockwise) at
    /// `coords` (m), section x axis `local_x`, and the section `section` at each of the
    /// four Gauss points (copied). `linear`: every layer is elastic. `corotational`:
    /// large displacements and rotations (OpenSees `-corotational`).
    pub fn new(
        tag: i64,
        nodes: [usize; 4],
        coords: &[[f64; 3]; 4],
        local_x: [f64; 3],
        section: &LayeredSection,
        linear: bool,
        corotational: bool,
    ) -> Result<Self, ShellError> {
        let kin = ShellKinematics::new(coords, local_x)?;
        let corot = if corotational {
            Some(Box::new(Corotational::new(coords)?))
        } else {
            None
        };
        let d0 = section.initial_tangent();
        let k_drill = drilling_stiffness(&d0);
        let sections: Vec<LayeredSection> = (0..4).map(|_| section.boxed_clone()).collect();
        let mut el = Self {
            tag,
            nodes,
            kin,
            k_drill,
            sections,
            k0: Mat24::zeros(),
            u_g: Vec24::zeros(),
            f: Vec24::zeros(),
            k: Mat24::zeros(),
            eas: Eas {
                q: Vec4::zeros(),
                u: Vec24::zeros(),
                rq: Vec4::zeros(),
                kqq_inv: Mat4::zeros(),
                kqu: Mat4x24::zeros(),
            },
            eas_committed: Eas {
                q: Vec4::zeros(),
                u: Vec24::zeros(),
                rq: Vec4::zeros(),
                kqq_inv: Mat4::zeros(),
                kqu: Mat4x24::zeros(),
            },
            f_committed: Vec24::zeros(),
            k_committed: Mat24::zeros(),
            linear: linear && corot.is_none(),
            corot,
        };
        // Initial state: zero strains, initial tangents.
        let ds = [d0; 4];
        let ss = [Vec8::zeros(); 4];
        let (fl, kl) = el.integrate(&Vec24::zeros(), &ss, &ds)?;
        let (f, k) = el.to_global(&Vec24::zeros(), &fl, &kl)?;
        el.k0 = k;
        el.k = k;
        el.f = f;
        el.k_committed = k;
        el.eas_committed = el.eas;
        Ok(el)
    }

    /// Integrates the element from section resultants `ss` and tangents `ds` (section
    /// axes) at the Gauss points and the local displacements `ul`; stores the EAS
    /// matrices and returns the local (force, tangent), condensed.
    fn integrate(
        &mut self,
        ul: &Vec24,
        ss: &[Vec8; 4],
        ds: &[super::Mat8; 4],
    ) -> Result<(Vec24, Mat24), ShellError> {
        let mut f = Vec24::zeros();
        let mut k = Mat24::zeros();
        let mut rq = Vec4::zeros();
        let mut kqq = Mat4::zeros();
        let mut kqu = Mat4x24::zeros();
        let mut kuq = Mat24x4::zeros();
        for (gp, g) in self.kin.gauss.iter().enumerate() {
            let (s, d) = match &self.kin.rs {
                Some(rs) => (rs * ss[gp], rs * ds[gp] * rs.transpose()),
                None => (ss[gp], ds[gp]),
            };
            let ed = g.bd.dot(ul);
            f += (g.b1.transpose() * s + g.bd * (self.k_drill * ed)) * g.da;
            k += g.b1.transpose() * d * g.b * g.da;
            k += g.bd * g.bd.transpose() * (self.k_drill * g.da);
            rq += g.bq.transpose() * s * g.da;
            kqq += g.bq.transpose() * d * g.bq * g.da;
            kqu += g.bq.transpose() * d * g.b * g.da;
            kuq += g.b1.transpose() * d * g.bq * g.da;
        }
        let kqq_inv = kqq
            .try_inverse()
            .ok_or_else(|| ShellError::Invalid("singular enhanced-strain stiffness".into()))?;
        let kuq_kqq_inv = kuq * kqq_inv;
        f -= kuq_kqq_inv * rq;
        k -= kuq_kqq_inv * kqu;
        self.eas.rq = rq;
        self.eas.kqq_inv = kqq_inv;
        self.eas.kqu = kqu;
        Ok((f, k))
    }

    /// Local displacements of the global ones `ug`: T u_g, or the corotational
    /// deformational displacements (after compounding the nodal rotations when `update`).
    fn local_displacements(&mut self, ug: &Vec24, update: bool) -> Result<Vec24, ShellError> {
        match &mut self.corot {
            None => Ok(self.kin.t * ug),
            Some(co) => {
                if update {
                    co.update_rotations(ug);
                }
                let fr = co.frame(ug)?;
                Ok(co.local_displacements(&fr, ug))
            }
        }
    }

    /// The global (force, tangent) of the local ones at the global displacements `ug`.
    fn to_global(&self, ug: &Vec24, fl: &Vec24, kl: &Mat24) -> Result<(Vec24, Mat24), ShellError> {
        match &self.corot {
            None => {
                let t = &self.kin.t;
                Ok((t.transpose() * fl, t.transpose() * kl * t))
            }
            Some(co) => {
                let fr = co.frame(ug)?;
                let ul = co.local_displacements(&fr, ug);
                Ok(co.to_global(&fr, &ul, fl, kl))
            }
        }
    }

    fn fail(&self, reason: String) -> ElementError {
        ElementError {
            element: self.tag,
            reason,
        }
    }
}

impl Element for ShellElement {
    fn tag(&self) -> i64 {
        self.tag
    }
    fn nodes(&self) -> &[usize] {
        &self.nodes
    }
    fn set_trial(&mut self, disp: &EndDisplacements<'_>) -> Result<(), ElementError> {
        self.u_g = Vec24::from_column_slice(disp.total);
        if self.linear {
            return Ok(());
        }
        let ug = self.u_g;
        let ul = self
            .local_displacements(&ug, true)
            .map_err(|e| self.fail(e.to_string()))?;
        // One Newton step on the internal DOFs (OpenSees `AGQIupdate`).
        let du = ul - self.eas.u;
        self.eas.u = ul;
        self.eas.q -= self.eas.kqq_inv * (self.eas.rq + self.eas.kqu * du);
        let mut ss = [Vec8::zeros(); 4];
        let mut ds = [super::Mat8::zeros(); 4];
        for (gp, g) in self.kin.gauss.iter().enumerate() {
            let e = g.b * ul + g.bq * self.eas.q;
            let es = match &self.kin.rs {
                Some(rs) => rs.transpose() * e,
                None => e,
            };
            let sec = &mut self.sections[gp];
            sec.set_trial(&es);
            ss[gp] = sec.stress();
            ds[gp] = sec.tangent();
        }
        let (f, k) = self
            .integrate(&ul, &ss, &ds)
            .and_then(|(fl, kl)| self.to_global(&ug, &fl, &kl))
            .map_err(|e| self.fail(e.to_string()))?;
        if f.iter().any(|x| !x.is_finite()) || k.iter().any(|x| !x.is_finite()) {
            return Err(self.fail("non-finite shell forces".into()));
        }
        self.f = f;
        self.k = k;
        Ok(())
    }
    fn resisting_force(&self) -> DVector<f64> {
        if self.linear {
            dvec(&(self.k0 * self.u_g))
        } else {
            dvec(&self.f)
        }
    }
    fn tangent_stiffness(&self) -> DMatrix<f64> {
        if self.linear {
            dmat(&self.k0)
        } else {
            dmat(&self.k)
        }
    }
    fn initial_stiffness(&self) -> DMatrix<f64> {
        dmat(&self.k0)
    }
    fn set_time_increment(&mut self, dt: f64) {
        if self.linear {
            return;
        }
        for s in &mut self.sections {
            s.set_time_increment(dt);
        }
    }
    fn commit_state(&mut self) {
        if self.linear {
            return;
        }
        for s in &mut self.sections {
            s.commit_state();
        }
        self.eas_committed = self.eas;
        self.f_committed = self.f;
        self.k_committed = self.k;
        if let Some(co) = &mut self.corot {
            co.commit();
        }
    }
    fn revert_to_last_commit(&mut self) {
        if self.linear {
            return;
        }
        for s in &mut self.sections {
            s.revert_to_last_commit();
        }
        self.eas = self.eas_committed;
        self.f = self.f_committed;
        self.k = self.k_committed;
        if let Some(co) = &mut self.corot {
            co.revert();
        }
    }
    /// `yielded`: a bar layer yielded or a concrete layer damaged in compression at some
    /// Gauss point; `ruptured`: the section at some Gauss point has lost its load path
    /// ([`LayeredSection::load_path_lost`]: a bar layer ruptured or the concrete crushed
    /// through the thickness; cracking and cover crushing never count) — the wall rule of
    /// the hand-off (docs/handoff.md §3).
    fn damage(&self) -> ElementDamage {
        let yielded = self.sections.iter().any(|s| s.damage().0);
        let ruptured = self.sections.iter().any(|s| s.load_path_lost());
        ElementDamage { yielded, ruptured }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::shell::layers::{ElasticFiber, PlateFiber};
    use nalgebra::{UnitQuaternion, Vector3};

    /// The corotational tangent is the derivative of the residual: central differences
    /// of the forces (rotation DOFs perturbed as the solver increments them, i.e. spins
    /// compounded onto the nodal rotations) against the analytic tangent, on a warped,
    /// distorted element with elastic layers in a large rigid rotation plus a deformation.
    #[test]
    fn corotational_tangent_matches_finite_differences_of_the_residual() {
        let coords = [
            [0.0, 0.0, 0.0],
            [1.1, 0.1, 0.02],
            [1.0, 0.9, -0.01],
            [-0.1, 1.0, 0.015],
        ];
        let layers: Vec<(f64, Box<dyn PlateFiber>)> = (0..3)
            .map(|_| {
                (
                    0.05,
                    Box::new(ElasticFiber::new(30e9, 0.2)) as Box<dyn PlateFiber>,
                )
            })
            .collect();
        let sec = LayeredSection::new(layers);
        let mut el =
            ShellElement::new(1, [0, 1, 2, 3], &coords, [1.0, 0.0, 0.0], &sec, true, true).unwrap();
        let rot = UnitQuaternion::from_scaled_axis(Vector3::new(0.4, -0.9, 0.6));
        let mut u = vec![0.0; 24];
        for i in 0..4 {
            let x = Vector3::from(coords[i]);
            let y = rot * x + Vector3::new(0.3, -0.2, 0.1);
            let def = Vector3::new(
                0.004 * i as f64,
                -0.003 * (i % 2) as f64,
                0.01 * (i % 3) as f64,
            );
            for k in 0..3 {
                u[6 * i + k] = y[k] - x[k] + def[k];
            }
            let th = rot.scaled_axis() + Vector3::new(0.02, -0.015 * i as f64, 0.01);
            for k in 0..3 {
                u[6 * i + 3 + k] = th[k];
            }
        }
        let set = |el: &mut ShellElement, u: &[f64]| {
            el.set_trial(&EndDisplacements {
                total: u,
                delta: &[0.0; 24],
            })
            .unwrap();
        };
        set(&mut el, &u);
        let k = el.tangent_stiffness();
        let f0 = el.resisting_force();
        let h = 1e-7;
        let (mut worst, mut kmax) = (0.0f64, 0.0f64);
        for j in 0..24 {
            let mut up = u.clone();
            up[j] += h;
            set(&mut el, &up);
            let fp = el.resisting_force();
            let mut um = u.clone();
            um[j] -= h;
            set(&mut el, &um);
            let fm = el.resisting_force();
            set(&mut el, &u);
            for i in 0..24 {
                let fd = (fp[i] - fm[i]) / (2.0 * h);
                worst = worst.max((fd - k[(i, j)]).abs());
                kmax = kmax.max(k[(i, j)].abs());
            }
        }
        eprintln!(
            "corotational tangent vs central differences: {:.2e} of max |K|",
            worst / kmax
        );
        // Back at u, the state is the same (rotations compounded and undone exactly).
        let f1 = el.resisting_force();
        assert!((f1 - &f0).amax() <= 1e-6 * f0.amax().max(1.0));
        assert!(
            worst < 1e-6 * kmax,
            "tangent vs finite differences: {:e} of {kmax:e}",
            worst / kmax
        );
    }
}
