//! Elastic 3D beam-column (OpenSees `elasticBeamColumn` 3D, Euler-Bernoulli, no shear
//! deformation). Basic stiffness (L = initial length):
//!
//! `N = EA/L Δl`, `[Mz_i Mz_j] = EIz/L [4 2; 2 4] [θz_i θz_j]`, same with EIy for My,
//! `T = GJ/L φ`.

use super::beam::{transform_error, BeamColumn, FormCache, SectionState};
use super::{dmat, dvec, Element, ElementError, EndDisplacements, Mat12, Prepare};
use crate::fe::transform::{CrdTransf, DeformedFrame, Mat6};
use nalgebra::Vector6;
use nalgebra::{DMatrix, DVector};

/// Properties of an elastic beam-column (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElasticProps {
    /// Young's modulus E (Pa).
    pub e: f64,
    /// Shear modulus G (Pa).
    pub g: f64,
    /// Area A (m²).
    pub a: f64,
    /// Second moment about local y, Iy (m⁴).
    pub iy: f64,
    /// Second moment about local z, Iz (m⁴).
    pub iz: f64,
    /// Torsion constant J (m⁴).
    pub j: f64,
}

/// Elastic 3D beam-column.
#[derive(Debug)]
pub struct ElasticBeam3d {
    tag: i64,
    nodes: [usize; 2],
    props: ElasticProps,
    transf: Box<dyn CrdTransf>,
    kb: Mat6,
    v: Vector6<f64>,
    /// Tangent of the trial state, formed once per state.
    forms: FormCache,
}

impl ElasticBeam3d {
    /// New element; every property must be positive and finite.
    pub fn new(
        tag: i64,
        nodes: [usize; 2],
        props: ElasticProps,
        transf: Box<dyn CrdTransf>,
    ) -> Result<Self, ElementError> {
        let p = props;
        for (name, x) in [
            ("E", p.e),
            ("G", p.g),
            ("A", p.a),
            ("Iy", p.iy),
            ("Iz", p.iz),
            ("J", p.j),
        ] {
            if !(x > 0.0 && x.is_finite()) {
                return Err(ElementError {
                    element: tag,
                    reason: format!("elastic property {name} = {x} must be positive and finite"),
                });
            }
        }
        let l = transf.initial_length();
        let mut kb = Mat6::zeros();
        kb[(0, 0)] = p.e * p.a / l;
        let (z, y) = (p.e * p.iz / l, p.e * p.iy / l);
        kb[(1, 1)] = 4.0 * z;
        kb[(2, 2)] = 4.0 * z;
        kb[(1, 2)] = 2.0 * z;
        kb[(2, 1)] = 2.0 * z;
        kb[(3, 3)] = 4.0 * y;
        kb[(4, 4)] = 4.0 * y;
        kb[(3, 4)] = 2.0 * y;
        kb[(4, 3)] = 2.0 * y;
        kb[(5, 5)] = p.g * p.j / l;
        Ok(Self {
            tag,
            nodes,
            props,
            transf,
            kb,
            v: Vector6::zeros(),
            forms: FormCache::default(),
        })
    }

    /// The element's properties.
    pub fn props(&self) -> ElasticProps {
        self.props
    }

    /// `K = Tᵀ kb T + K_g` of the trial state (cached).
    fn tangent12(&self) -> &Mat12 {
        self.forms
            .tangent(|| self.transf.global_stiffness(&self.kb, &(self.kb * self.v)))
    }
}

impl Element for ElasticBeam3d {
    fn tag(&self) -> i64 {
        self.tag
    }
    fn nodes(&self) -> &[usize] {
        &self.nodes
    }
    fn set_trial(&mut self, disp: &EndDisplacements<'_>) -> Result<(), ElementError> {
        self.forms.clear();
        self.transf
            .update(&disp.total12())
            .map_err(|e| transform_error(self.tag, e))?;
        self.v = self.transf.basic_deformations();
        Ok(())
    }
    fn resisting_force(&self) -> DVector<f64> {
        dvec(&self.transf.global_resisting_force(&(self.kb * self.v)))
    }
    fn tangent_stiffness(&self) -> DMatrix<f64> {
        dmat(self.tangent12())
    }
    fn resisting_force_into(&self, out: &mut [f64]) {
        out.copy_from_slice(
            self.transf
                .global_resisting_force(&(self.kb * self.v))
                .as_slice(),
        );
    }
    fn tangent_stiffness_into(&self, out: &mut [f64]) {
        out.copy_from_slice(self.tangent12().as_slice());
    }
    fn has_trial_damping_stiffness(&self) -> bool {
        false
    }
    fn prepare(&self, what: Prepare) {
        if what == Prepare::Tangent {
            self.tangent12();
        }
    }
    fn initial_stiffness(&self) -> DMatrix<f64> {
        dmat(&self.transf.initial_global_stiffness(&self.kb))
    }
    fn commit_state(&mut self) {
        self.transf.commit();
    }
    fn revert_to_last_commit(&mut self) {
        self.transf.revert();
        self.v = self.transf.basic_deformations();
        self.forms.clear();
    }
}

impl BeamColumn for ElasticBeam3d {
    fn basic_forces(&self) -> Vector6<f64> {
        self.kb * self.v
    }
    fn basic_deformations(&self) -> Vector6<f64> {
        self.v
    }
    fn section_states(&self) -> Vec<SectionState> {
        Vec::new()
    }
    fn deformed_frame(&self) -> DeformedFrame {
        self.transf.deformed_frame()
    }
    fn into_element(self: Box<Self>) -> Box<dyn Element> {
        self
    }
}
