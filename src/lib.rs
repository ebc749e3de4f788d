//! fem2rbd — hybrid finite-element + rigid-body simulation of how a reinforced-concrete
//! building collapses in an earthquake and where its ruins end up.
//!
//! Reproduces and extends Zheng, Tian, Yang & Lu, "Hybrid Framework for Simulating
//! Building Collapse and Ruin Scenarios Using Finite Element Method and Physics Engine",
//! Appl. Sci. 2020, 10, 4408. Data flows one way through the stages:
//!
//! ```text
//! scenario ─► model ─► fe (time history) ─► collapse (Tc) ─► mapping ─► ruin (Bullet) ─► output
//!                motion ───────────────────────────────────────────────► ruin (ground after Tc)
//! ```
//!
//! The structural stages (`model`, `motion`, `fe`, `collapse`, `export`) are the
//! `fem2rbd-fe` crate and the Bullet wrapper (`bullet`) is the `fem2rbd-bullet` crate;
//! both are re-exported here under their module names. Units are SI throughout
//! (m, kg, s, N, Pa). `unsafe` code lives only in `bullet-sys` and `fem2rbd-bullet`.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub use fem2rbd_bullet as bullet;
pub use fem2rbd_fe::{collapse, export, fe, model, motion};

pub mod body;
pub mod estimate;
pub mod mapping;
pub mod measure;
pub mod mode;
pub mod output;
pub mod pipeline;
pub mod plan_geometry;
pub mod plot;
pub mod report;
pub mod rescue;
pub mod ruin;
pub mod scene;
pub mod study;
