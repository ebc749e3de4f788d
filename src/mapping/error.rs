//! The error of the mapping stage ([`MappingError`]): the element, body or nodal mass
//! that cannot be mapped or handed off, named.
use crate::body::{BodyId, BodyType};

/// An FE element, nodal mass or body that cannot be mapped to a rigid box or posed at
/// the hand-off. Every variant names its item (element tag, body name, nodal mass).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MappingError {
    /// An element refers to something the model does not have (node, transformation,
    /// section) or has no box outline.
    #[error("element {element}{}: {message}", body.as_ref().map(|b| format!(" ({b})")).unwrap_or_default())]
    Element {
        /// The element's tag.
        element: u32,
        /// Its body name or type, when known.
        body: Option<String>,
        /// What is wrong.
        message: String,
    },
    /// No element of the model becomes a rigid body: nothing to map.
    #[error(
        "no element becomes a rigid body ({elements} element(s), {fe_only} of them \
         rigid_body = false, which stay FE-only): nothing to map; give the members \
         rigid_body = true (the default)"
    )]
    NoBodies {
        /// Elements of the model.
        elements: usize,
        /// Of them, elements with `rigid_body = false`.
        fe_only: usize,
    },
    /// A line element's local frame is undefined (zero length, `vecxz` along the axis).
    #[error("{0}")]
    Frame(String),
    /// Two elements give the same body name.
    #[error("two elements map to the same body name {0}")]
    DuplicateBody(BodyId),
    /// A mapping option is out of range.
    #[error("{0}")]
    Options(String),
    /// Overlap removal needs more than 1000 cuts of one body.
    #[error("overlap removal: body {0} needs more than 1000 cuts")]
    TooManyCuts(BodyId),
    /// Overlap removal would remove a body lying within another.
    #[error(
        "overlap removal: body {body} lies within body {within}; it would vanish \
         (fix the model's geometry)"
    )]
    Vanishes {
        /// The body that would vanish.
        body: BodyId,
        /// The body it lies within.
        within: BodyId,
    },
    /// A nodal mass of the model is at no node.
    #[error("mass at unknown node {0}")]
    UnknownMassNode(u32),
    /// A nodal mass is not finite or negative, or is at no element node.
    #[error("nodal mass {index} {message}")]
    NodalMass {
        /// Its index in the mapping input.
        index: usize,
        /// What is wrong, with its position.
        message: String,
    },
    /// A mapped body cannot be handed off (its element is missing or of the wrong kind).
    #[error("body {body}: {message}")]
    Body {
        /// The body's name.
        body: BodyId,
        /// What is wrong.
        message: String,
    },
    /// The FE nodal state does not match the model.
    #[error("hand-off: {given} node states given for a model of {nodes} nodes")]
    NodeCount {
        /// States given.
        given: usize,
        /// Nodes of the model.
        nodes: usize,
    },
    /// A body's element degenerated at the hand-off (zero chord, collinear quad).
    #[error("hand-off: body {body}: {what}")]
    Degenerate {
        /// The body.
        body: BodyId,
        /// How it degenerated.
        what: &'static str,
    },
    /// The secant velocity's keyframes or interval do not fit.
    #[error("{0}")]
    Secant(String),
}

impl MappingError {
    /// An [`MappingError::Element`] error of element `element` of type `body`.
    pub(crate) fn element(element: u32, message: impl Into<String>) -> Self {
        MappingError::Element {
            element,
            body: None,
            message: message.into(),
        }
    }

    /// An [`MappingError::Element`] error of element `element` of type `body`.
    pub(crate) fn typed(element: u32, body: &BodyType, message: impl Into<String>) -> Self {
        MappingError::Element {
            element,
            body: Some(body.to_string()),
            message: message.into(),
        }
    }
}

/// What mapping functions return.
pub type Result<T> = std::result::Result<T, MappingError>;
