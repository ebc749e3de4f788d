//! Displacement-based fiber beam-column (OpenSees `dispBeamColumn` 3D): cubic Hermite
//! transverse and linear axial/torsional interpolation in the basic system, sections
//! at Gauss-Legendre points.
//!
//! Section deformations at ξ = x/L from the basic deformations v:
//! `ε0 = v0/L`, `κz = ((6ξ−4) v1 + (6ξ−2) v2)/L`, `κy = ((6ξ−4) v3 + (6ξ−2) v4)/L`,
//! `ϑ = v5/L`, i.e. `e = B(ξ) v`. Basic forces `q = Σ Bᵀ s w L`, stiffness
//! `kb = Σ Bᵀ k_s B w L`.

use super::beam::{
    damage_of, section_states, transform_error, BeamColumn, FormCache, SectionState,
};
use super::quadrature::gauss_legendre;
use super::{dmat, dvec, Element, ElementDamage, ElementError, EndDisplacements, Mat12, Prepare};
use crate::fe::section::Section;
use crate::fe::transform::{CrdTransf, DeformedFrame, Mat6};
use nalgebra::{DMatrix, DVector};
use nalgebra::{SMatrix, Vector6};

type Mat4x6 = SMatrix<f64, 4, 6>;

/// Displacement-based 3D beam-column.
#[derive(Debug)]
pub struct DispBeam3d {
    tag: i64,
    nodes: [usize; 2],
    transf: Box<dyn CrdTransf>,
    sections: Vec<Box<dyn Section>>,
    xs: Vec<f64>,
    ws: Vec<f64>,
    /// `B(ξ)` at each point.
    b: Vec<Mat4x6>,
    l: f64,
    v: Vector6<f64>,
    q: Vector6<f64>,
    kb: Mat6,
    /// Initial basic stiffness `Σ Bᵀ k_s0 B w L` (sections' initial tangents; constant).
    kb0: Mat6,
    /// Whether the transformation has a trial-geometry initial stiffness (corotational).
    trial_damping: bool,
    /// Tangent and damping stiffness of the trial state, formed once per state.
    forms: FormCache,
}

/// `B(ξ)`: section deformations from basic deformations.
fn b_matrix(xi: f64, l: f64) -> Mat4x6 {
    let mut b = Mat4x6::zeros();
    let il = 1.0 / l;
    b[(0, 0)] = il;
    b[(1, 1)] = (6.0 * xi - 4.0) * il;
    b[(1, 2)] = (6.0 * xi - 2.0) * il;
    b[(2, 3)] = (6.0 * xi - 4.0) * il;
    b[(2, 4)] = (6.0 * xi - 2.0) * il;
    b[(3, 5)] = il;
    b
}

impl DispBeam3d {
    /// New element with `n_ip ≥ 1` Gauss-Legendre points, each with a copy of `section`.
    pub fn new(
        tag: i64,
        nodes: [usize; 2],
        section: &dyn Section,
        n_ip: usize,
        transf: Box<dyn CrdTransf>,
    ) -> Result<Self, ElementError> {
        if !(1..=20).contains(&n_ip) {
            return Err(ElementError {
                element: tag,
                reason: format!("number of integration points {n_ip} must be 1..=20"),
            });
        }
        let (xs, ws) = gauss_legendre(n_ip);
        let l = transf.initial_length();
        let b = xs.iter().map(|&x| b_matrix(x, l)).collect();
        let mut s = Self {
            tag,
            nodes,
            transf,
            sections: (0..n_ip).map(|_| section.boxed_clone()).collect(),
            xs,
            ws,
            b,
            l,
            v: Vector6::zeros(),
            q: Vector6::zeros(),
            kb: Mat6::zeros(),
            kb0: Mat6::zeros(),
            trial_damping: false,
            forms: FormCache::default(),
        };
        s.trial_damping = s.transf.has_trial_initial_global_stiffness();
        s.kb0 = s.integrate_initial();
        s.state_determination();
        Ok(s)
    }

    fn state_determination(&mut self) {
        self.forms.clear();
        for (i, sec) in self.sections.iter_mut().enumerate() {
            sec.set_trial_deformation(&(self.b[i] * self.v));
        }
        self.integrate();
    }

    /// Basic forces and stiffness from the sections' current states.
    fn integrate(&mut self) {
        let mut q = Vector6::zeros();
        let mut kb = Mat6::zeros();
        for (i, sec) in self.sections.iter().enumerate() {
            let b = &self.b[i];
            let wl = self.ws[i] * self.l;
            q += b.transpose() * sec.resultant() * wl;
            kb += b.transpose() * sec.tangent() * b * wl;
        }
        self.q = q;
        self.kb = kb;
    }

    /// `K = Tᵀ kb T + K_g` of the trial state (cached).
    fn tangent12(&self) -> &Mat12 {
        self.forms
            .tangent(|| self.transf.global_stiffness(&self.kb, &self.q))
    }

    /// `Tbᵀ kb0 Tb` with the trial geometry (cached), `None` for linear and P-Δ.
    fn damping12(&self) -> Option<&Mat12> {
        if !self.trial_damping {
            return None;
        }
        self.forms
            .damping(|| self.transf.trial_initial_global_stiffness(&self.kb0))
    }

    fn integrate_initial(&self) -> Mat6 {
        let mut kb = Mat6::zeros();
        for (i, sec) in self.sections.iter().enumerate() {
            let b = &self.b[i];
            kb += b.transpose() * sec.initial_tangent() * b * (self.ws[i] * self.l);
        }
        kb
    }
}

impl Element for DispBeam3d {
    fn tag(&self) -> i64 {
        self.tag
    }
    fn nodes(&self) -> &[usize] {
        &self.nodes
    }
    fn set_trial(&mut self, disp: &EndDisplacements<'_>) -> Result<(), ElementError> {
        self.transf
            .update(&disp.total12())
            .map_err(|e| transform_error(self.tag, e))?;
        self.v = self.transf.basic_deformations();
        self.state_determination();
        if self.q.iter().any(|x| !x.is_finite()) {
            return Err(ElementError {
                element: self.tag,
                reason: "non-finite section forces".into(),
            });
        }
        Ok(())
    }
    fn resisting_force(&self) -> DVector<f64> {
        dvec(&self.transf.global_resisting_force(&self.q))
    }
    fn tangent_stiffness(&self) -> DMatrix<f64> {
        dmat(self.tangent12())
    }
    fn initial_stiffness(&self) -> DMatrix<f64> {
        dmat(&self.transf.initial_global_stiffness(&self.kb0))
    }
    fn damping_stiffness(&self) -> Option<DMatrix<f64>> {
        self.damping12().map(dmat)
    }
    fn resisting_force_into(&self, out: &mut [f64]) {
        out.copy_from_slice(self.transf.global_resisting_force(&self.q).as_slice());
    }
    fn tangent_stiffness_into(&self, out: &mut [f64]) {
        out.copy_from_slice(self.tangent12().as_slice());
    }
    fn damping_stiffness_into(&self, out: &mut [f64]) -> bool {
        self.damping12()
            .map(|k| out.copy_from_slice(k.as_slice()))
            .is_some()
    }
    fn has_trial_damping_stiffness(&self) -> bool {
        self.trial_damping
    }
    fn prepare(&self, what: Prepare) {
        match what {
            Prepare::Tangent => {
                self.tangent12();
            }
            Prepare::Damping => {
                self.damping12();
            }
        }
    }
    fn commit_state(&mut self) {
        self.transf.commit();
        for s in &mut self.sections {
            s.commit_state();
        }
    }
    fn revert_to_last_commit(&mut self) {
        self.transf.revert();
        for s in &mut self.sections {
            s.revert_to_last_commit();
        }
        self.v = self.transf.basic_deformations();
        self.forms.clear();
        self.integrate();
    }
    fn damage(&self) -> ElementDamage {
        damage_of(&self.sections)
    }
    fn sections(&self) -> Vec<(f64, &dyn Section)> {
        self.xs
            .iter()
            .zip(&self.sections)
            .map(|(&xi, s)| (xi, s.as_ref()))
            .collect()
    }
}

impl BeamColumn for DispBeam3d {
    fn basic_forces(&self) -> Vector6<f64> {
        self.q
    }
    fn basic_deformations(&self) -> Vector6<f64> {
        self.v
    }
    fn section_states(&self) -> Vec<SectionState> {
        section_states(&self.sections, &self.xs, &self.ws)
    }
    fn deformed_frame(&self) -> DeformedFrame {
        self.transf.deformed_frame()
    }
    fn into_element(self: Box<Self>) -> Box<dyn Element> {
        self
    }
}
