//! What the three beam-column elements share: the hand-off interface [`BeamColumn`],
//! section state reports, and the one-call builder [`BeamColumnSpec::build`] the domain
//! uses to create an element from the model.

use super::{
    DispBeam3d, ElasticBeam3d, ElasticProps, Element, ElementDamage, ElementError, ForceBeam3d,
    ForceBeamOptions,
};
use crate::fe::section::{Section, SectionDamage};
use crate::fe::transform::{new_transform, DeformedFrame, TransformError, TransformKind};
use nalgebra::{Vector3, Vector6};
use std::sync::OnceLock;

use super::Mat12;

/// The global matrices of a two-node beam-column's trial state, formed on first use and
/// kept until the state changes ([`FormCache::clear`] on every `set_trial` and revert).
/// The tangent is read by the assembly and the trial-geometry damping stiffness by both
/// the residual (`D v`) and the tangent of the same Newton iteration, so each is formed
/// once per state instead of once per read, and can be formed on the domain's threads
/// ([`Element::prepare`]); a cached matrix is the same bits as a freshly formed one.
#[derive(Debug, Clone, Default)]
pub(crate) struct FormCache {
    tangent: OnceLock<Mat12>,
    damping: OnceLock<Option<Mat12>>,
}

impl FormCache {
    /// Forgets the matrices (the trial state changed).
    pub fn clear(&mut self) {
        self.tangent.take();
        self.damping.take();
    }
    /// The tangent, formed by `form` if not yet formed for this state.
    pub fn tangent(&self, form: impl FnOnce() -> Mat12) -> &Mat12 {
        self.tangent.get_or_init(form)
    }
    /// The damping stiffness, formed by `form` if not yet formed for this state.
    pub fn damping(&self, form: impl FnOnce() -> Option<Mat12>) -> Option<&Mat12> {
        self.damping.get_or_init(form).as_ref()
    }
}

/// State of one integration point (section), for outputs and collapse criteria.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionState {
    /// Position along the element, ξ = x/L ∈ [0, 1].
    pub xi: f64,
    /// Integration weight (fraction of L).
    pub weight: f64,
    /// Section deformations `[ε0, κz, κy, ϑ]`.
    pub deformation: [f64; 4],
    /// Section forces `[N, Mz, My, T]` (N, N·m).
    pub resultant: [f64; 4],
    /// Damage flags and extreme fiber strains.
    pub damage: SectionDamage,
}

/// A 3D beam-column: an [`Element`] that also reports its basic forces, sections and
/// deformed placement (for the hand-off to rigid bodies).
pub trait BeamColumn: Element {
    /// Basic forces `[N, Mz_i, Mz_j, My_i, My_j, T]` of the trial state (N, N·m).
    fn basic_forces(&self) -> Vector6<f64>;
    /// Basic deformations `[Δl, θz_i, θz_j, θy_i, θy_j, φ]` of the trial state.
    fn basic_deformations(&self) -> Vector6<f64>;
    /// Section states at the integration points (empty for the elastic element).
    fn section_states(&self) -> Vec<SectionState>;
    /// Current node positions and local axes ([`DeformedFrame::centroid`] gives the
    /// centroid, `axes` the rotation matrix whose columns are local x, y, z).
    fn deformed_frame(&self) -> DeformedFrame;
    /// The same element as a plain [`Element`] (for a domain that stores `Box<dyn Element>`).
    fn into_element(self: Box<Self>) -> Box<dyn Element>;
}

/// Element damage from section damages.
pub(crate) fn damage_of(sections: &[Box<dyn Section>]) -> ElementDamage {
    let mut d = ElementDamage::default();
    for s in sections {
        let sd = s.damage();
        d.yielded |= sd.yielded;
        d.ruptured |= sd.ruptured;
    }
    d
}

pub(crate) fn section_states(
    sections: &[Box<dyn Section>],
    xs: &[f64],
    ws: &[f64],
) -> Vec<SectionState> {
    sections
        .iter()
        .zip(xs.iter().zip(ws))
        .map(|(s, (&xi, &weight))| SectionState {
            xi,
            weight,
            deformation: s.deformation().into(),
            resultant: s.resultant().into(),
            damage: s.damage(),
        })
        .collect()
}

pub(crate) fn transform_error(tag: i64, e: TransformError) -> ElementError {
    ElementError {
        element: tag,
        reason: format!("geometric transformation: {e}"),
    }
}

/// How the element integrates its sections.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Formulation {
    /// `elasticBeamColumn` with the given properties (no section needed).
    Elastic(ElasticProps),
    /// `dispBeamColumn`, Gauss-Legendre with `n_ip` points.
    DispBased {
        /// Number of integration points (≥ 1).
        n_ip: usize,
    },
    /// `forceBeamColumn`, Gauss-Lobatto with `n_ip` points.
    ForceBased {
        /// Number of integration points (≥ 2).
        n_ip: usize,
        /// Element iteration controls.
        options: ForceBeamOptions,
    },
}

/// Everything needed to create one beam-column element.
#[derive(Debug)]
pub struct BeamColumnSpec {
    /// Element tag (model id).
    pub tag: i64,
    /// Indices of nodes i and j in the domain's node arrays.
    pub nodes: [usize; 2],
    /// Undeformed coordinates of node i (m).
    pub xi: Vector3<f64>,
    /// Undeformed coordinates of node j (m).
    pub xj: Vector3<f64>,
    /// Geometric transformation.
    pub transform: TransformKind,
    /// Vector in the local x-z plane (OpenSees `vecxz`).
    pub vecxz: Vector3<f64>,
    /// Formulation and integration.
    pub formulation: Formulation,
    /// Section prototype (copied to every integration point); `None` for `Elastic`.
    pub section: Option<Box<dyn Section>>,
}

impl BeamColumnSpec {
    /// Creates the element. Errors name the element tag.
    pub fn build(self) -> Result<Box<dyn BeamColumn>, ElementError> {
        let tag = self.tag;
        let transf = new_transform(self.transform, self.xi, self.xj, self.vecxz)
            .map_err(|e| transform_error(tag, e))?;
        let need_section = || {
            self.section.as_ref().ok_or_else(|| ElementError {
                element: tag,
                reason: "a fiber/section element needs a section".into(),
            })
        };
        Ok(match self.formulation {
            Formulation::Elastic(p) => Box::new(ElasticBeam3d::new(tag, self.nodes, p, transf)?),
            Formulation::DispBased { n_ip } => Box::new(DispBeam3d::new(
                tag,
                self.nodes,
                need_section()?.as_ref(),
                n_ip,
                transf,
            )?),
            Formulation::ForceBased { n_ip, options } => Box::new(ForceBeam3d::new(
                tag,
                self.nodes,
                need_section()?.as_ref(),
                n_ip,
                transf,
                options,
            )?),
        })
    }
}
