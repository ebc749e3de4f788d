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
//! Units are SI throughout (m, kg, s, N, Pa). `unsafe` code lives only in the
//! `bullet-sys` crate and in [`physics`], the one safe wrapper over it.
#![deny(unsafe_code)]

pub mod cli;
pub mod collapse;
pub mod export;
pub mod fe;
pub mod mapping;
pub mod model;
pub mod motion;
pub mod output;
#[allow(unsafe_code)]
pub mod physics;
pub mod pipeline;
pub mod plot;
pub mod ruin;
pub mod scene;
pub mod study;
