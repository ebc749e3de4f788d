//! Geometry mapping (paper §3.1, Module 1): FE elements → rigid boxes,
//! overlap removal (BCB step 2) and mass mapping.
//!
//! The mapping reads its own plain input ([`MappingInput`]: [`LineMember`], [`Quad`],
//! [`PointMass`]), not the model file: a converter from the model builds it. Then
//! [`map_to_boxes`] runs three steps:
//! 1. [`geometry`]: one box per FE element, named `Type:material:element`, one group per
//!    material;
//! 2. [`overlap`]: boxes at joints are shortened so no pair overlaps by more than the
//!    tolerance;
//! 3. [`mass`]: element self-weight plus nodal masses onto the boxes.
//!
//! [`from_model()`] builds the input from a [`crate::model::Model`] (rigid-body elements
//! only; FE-only elements' weight goes to their nodes). [`handoff`] poses the mapped
//! bodies from an FE nodal state (keyframes up to Tc, instantaneous velocities at Tc).

// `!(x > 0.0)` is used on purpose: it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod error;
pub mod foundation;
pub mod from_model;
pub mod geometry;
pub mod handoff;
pub mod input;
pub mod mass;
pub mod overlap;
pub mod polytope;
pub mod table;

pub use crate::body::Role;
pub use error::MappingError;
pub use from_model::from_model;
pub use geometry::RigidBox;
pub use input::{LineMember, MappingInput, PointMass, Quad};
pub use overlap::TrimReport;

use error::Result;
use std::collections::BTreeMap;

/// Options of [`map_to_boxes`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapOptions {
    /// Remove overlaps (BCB's "Intersection removal", on by default).
    pub remove_overlaps: bool,
    /// Largest overlap volume left between any two boxes (m³). BCB's pair threshold is
    /// 1e-4 m³; the default 1e-9 m³ removes every overlap but round-off.
    pub overlap_tolerance_m3: f64,
}

impl Default for MapOptions {
    fn default() -> Self {
        Self {
            remove_overlaps: true,
            overlap_tolerance_m3: 1e-9,
        }
    }
}

/// The mapped bodies and what overlap removal did.
#[derive(Debug, Clone, PartialEq)]
pub struct Mapping {
    /// Bodies: line members first, then quads, each in input order.
    pub bodies: Vec<RigidBox>,
    /// Overlap-removal summary.
    pub trim: TrimReport,
}

/// Maps FE elements to rigid boxes (module docs). Errors name the element.
pub fn map_to_boxes(input: &MappingInput, opts: &MapOptions) -> Result<Mapping> {
    let mut bodies = Vec::with_capacity(input.members.len() + input.quads.len());
    for m in &input.members {
        bodies.push(geometry::member_box(m)?);
    }
    for q in &input.quads {
        bodies.push(geometry::quad_box(q)?);
    }
    let mut seen = BTreeMap::new();
    for b in &bodies {
        if seen.insert(b.id.clone(), ()).is_some() {
            return Err(MappingError::DuplicateBody(b.id.clone()));
        }
    }
    let trim = if opts.remove_overlaps {
        overlap::trim_overlaps(&mut bodies, opts.overlap_tolerance_m3)?
    } else {
        TrimReport::default()
    };
    mass::distribute_nodal_masses(&mut bodies, &input.nodal_masses)?;
    Ok(Mapping { bodies, trim })
}

/// The rigid-body groups: material → indices of its bodies (ordered by material name).
pub fn groups(bodies: &[RigidBox]) -> BTreeMap<String, Vec<usize>> {
    let mut g: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for (i, b) in bodies.iter().enumerate() {
        g.entry(b.id.group().to_string()).or_default().push(i);
    }
    g
}
