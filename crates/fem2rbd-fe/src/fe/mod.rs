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
pub mod run;
pub mod section;
pub mod shell;
pub mod transform;
