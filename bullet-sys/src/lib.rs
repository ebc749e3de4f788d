//! placeholder: owned by the physics helper
