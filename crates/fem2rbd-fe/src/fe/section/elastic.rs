//! Elastic section (OpenSees `section Elastic` 3D with torsion): `s = diag(EA, EIz, EIy, GJ) e`.

use super::{Section, SectionDamage};
use nalgebra::{Matrix4, Vector4};

/// Linear elastic section.
#[derive(Debug, Clone)]
pub(crate) struct ElasticSection {
    k: Matrix4<f64>,
    e: Vector4<f64>,
    e_c: Vector4<f64>,
}

impl ElasticSection {
    /// Rigidities: axial `ea` (N), bending `eiz`, `eiy` (N·m²), torsion `gj` (N·m²).
    pub fn new(ea: f64, eiz: f64, eiy: f64, gj: f64) -> Self {
        Self {
            k: Matrix4::from_diagonal(&Vector4::new(ea, eiz, eiy, gj)),
            e: Vector4::zeros(),
            e_c: Vector4::zeros(),
        }
    }
}

impl Section for ElasticSection {
    fn set_trial_deformation(&mut self, e: &Vector4<f64>) {
        self.e = *e;
    }
    fn deformation(&self) -> Vector4<f64> {
        self.e
    }
    fn resultant(&self) -> Vector4<f64> {
        self.k * self.e
    }
    fn tangent(&self) -> Matrix4<f64> {
        self.k
    }
    fn initial_tangent(&self) -> Matrix4<f64> {
        self.k
    }
    fn commit_state(&mut self) {
        self.e_c = self.e;
    }
    fn revert_to_last_commit(&mut self) {
        self.e = self.e_c;
    }
    fn revert_to_start(&mut self) {
        self.e = Vector4::zeros();
        self.e_c = self.e;
    }
    fn damage(&self) -> SectionDamage {
        SectionDamage::default()
    }
    fn boxed_clone(&self) -> Box<dyn Section> {
        Box::new(self.clone())
    }
}
