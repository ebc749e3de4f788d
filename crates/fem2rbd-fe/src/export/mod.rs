//! Exports of the model to other programs (openseespy). (Issue 3.)
pub mod opensees;

pub use opensees::{opensees_script, GroundMotionInput, OpenSeesOptions, Variant};
