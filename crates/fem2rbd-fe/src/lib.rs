//! The structural side of fem2rbd: everything that happens while the building is still a
//! structure, with no rigid bodies and no Bullet.
//!
//! ```text
//! model (file format, validation, generator) ─► fe (nonlinear time history) ─► collapse (Tc)
//! motion (ground-motion records) ─────────────► fe
//! model ─► export (an openseespy script of the same model and analysis)
//! ```
//!
//! Units are SI throughout (m, kg, s, N, Pa). This crate builds and tests without
//! libbullet and libclang; the rigid-body side lives in the `fem2rbd` crate.
#![forbid(unsafe_code)]
#![warn(missing_docs)]
// Numerical kernels index several arrays with one loop variable (u[i], m[i], k[i][j]);
// that reads closer to the equations than zipped iterators.
#![allow(clippy::needless_range_loop)]

pub mod collapse;
pub mod export;
pub mod fe;
pub mod model;
pub mod motion;
