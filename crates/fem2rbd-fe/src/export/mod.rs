//! Exports of the model to other programs (openseespy).
pub mod opensees;

pub use opensees::{opensees_script, GroundMotionInput, OpenSeesOptions, Variant};
