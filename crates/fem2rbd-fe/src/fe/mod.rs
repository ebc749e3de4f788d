//! The nonlinear finite-element solver (the paper's small-deformation stage): uniaxial
//! materials, fiber sections, beam-column elements, geometric transformations, and
//! static / modal / transient analyses on sparse linear algebra (faer).
pub mod analysis;
pub mod build;
pub mod capacity;
pub mod domain;
pub mod element;
pub mod linalg;
pub mod material;
pub mod profile;
pub mod pushover;
pub mod reactions;
pub mod run;
pub mod section;
pub mod shell;
pub mod transform;

/// A model that cannot be analysed, or an analysis that cannot be set up: the FE stage's
/// one error type ([`build::build_domain`], [`run::prepare`], [`run::run_ground_motion`],
/// [`capacity`]). A step that does not converge is not an error but a reported stop
/// ([`analysis::transient::StopReason::Diverged`], with its time and element).
/// Messages name the item (node, element, section, material) at fault.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FeError {
    /// The model holds something the FE solver cannot build (a shell element, a shell
    /// section on a beam-column, no structural element at all) or an unresolved reference.
    #[error("{0}")]
    Unsupported(String),
    /// A material that cannot be built.
    #[error("material {tag} ({name}): {error}")]
    Material {
        /// Material tag.
        tag: u32,
        /// Material name.
        name: String,
        /// What is wrong.
        error: material::MaterialError,
    },
    /// A fibre section that cannot be built.
    #[error("section {tag}: {error}")]
    Section {
        /// Section tag.
        tag: u32,
        /// What is wrong.
        error: section::fiber::SectionError,
    },
    /// A node, support, mass, load or element the domain refuses.
    #[error("{item}: {error}")]
    Domain {
        /// The item, e.g. "node 3".
        item: String,
        /// What is wrong.
        error: domain::DomainError,
    },
    /// A beam-column that cannot be built.
    #[error("element {tag}: {error}")]
    Element {
        /// Element tag.
        tag: u32,
        /// What is wrong.
        error: element::ElementError,
    },
    /// Run options out of range (time step, recording interval, duration, nodes).
    #[error("{0}")]
    Options(String),
    /// A count over its resource bound (`docs/reliability.md`).
    #[error(transparent)]
    Limit(#[from] crate::model::limits::LimitError),
    /// An analysis that failed (not a reported divergence): modal, gravity, transient set-up.
    #[error("{stage}: {error}")]
    Analysis {
        /// Which analysis: "initial modal analysis", "gravity (load control)", ….
        stage: &'static str,
        /// What failed.
        error: analysis::AnalysisError,
    },
    /// A member whose capacity cannot be computed (`capacity`).
    #[error("{item}: {message}")]
    Capacity {
        /// The member, e.g. "element 12".
        item: String,
        /// What is missing.
        message: String,
    },
    /// An error of an inner stage, e.g. the gravity analysis before a pushover.
    #[error("{stage}: {error}")]
    In {
        /// The outer stage.
        stage: &'static str,
        /// The inner error.
        error: Box<FeError>,
    },
}

impl FeError {
    /// Wraps an error of an inner stage under the name of the outer one.
    pub fn within(self, stage: &'static str) -> Self {
        FeError::In {
            stage,
            error: Box::new(self),
        }
    }
}
