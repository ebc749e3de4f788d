//! Mass mapping: the rigid bodies carry the FE model's whole mass.
//!
//! Rule:
//! 1. Each body keeps its own element's self-weight (already set by [`super::geometry`]);
//!    trimming does not change it (the FE mass is what must be conserved, not the
//!    trimmed box volume × density).
//! 2. Each nodal mass is split **equally** among the bodies whose FE element has that node,
//!    preferring, in this order, slabs, then beams, then all attached bodies (columns,
//!    walls). Floor masses (ballast, finishes, lumped slab weight) belong to the floor
//!    system and move with it when the ruins form; putting them on columns would make the
//!    columns the heaviest bodies and shift the floor's mass to the column lines. Node
//!    masses between floors (e.g. at column mid-height nodes) have only columns attached
//!    and go to them.
//! 3. A node matches an element node when their coordinates round to the same micrometre.
//!    A non-zero nodal mass at a node of no element is an error.
//!
//! The mass moves from the node to the body's centre; with a symmetric floor (frame3) the
//! floor's centre of mass stays where it was in plan (tests measure the shift).
//! Inertia ([`super::RigidBox::principal_inertia_kgm2`]) treats each body as a uniform box.

use super::error::{MappingError, Result};
use super::geometry::RigidBox;
use super::input::PointMass;
use crate::body::Role;
use std::collections::BTreeMap;

type Key = [i64; 3];

fn key(p: [f64; 3]) -> Key {
    p.map(|x| (x * 1e6).round() as i64)
}

/// Adds the nodal masses to the bodies (module docs). Returns, per nodal mass, the body
/// indices that received a share.
pub(crate) fn distribute_nodal_masses(
    boxes: &mut [RigidBox],
    masses: &[PointMass],
) -> Result<Vec<Vec<usize>>> {
    let mut at: BTreeMap<Key, Vec<usize>> = BTreeMap::new();
    for (i, b) in boxes.iter().enumerate() {
        for n in &b.nodes {
            let v = at.entry(key(*n)).or_default();
            if !v.contains(&i) {
                v.push(i);
            }
        }
    }
    let mut shares = Vec::with_capacity(masses.len());
    for (k, m) in masses.iter().enumerate() {
        let p = m.position;
        let valid = m.mass_kg >= 0.0 && m.mass_kg.is_finite() && p.iter().all(|x| x.is_finite());
        if !valid {
            return Err(MappingError::NodalMass {
                index: k,
                message: format!(
                    "at ({}, {}, {}): mass must be finite and ≥ 0 kg, got {}",
                    p[0], p[1], p[2], m.mass_kg
                ),
            });
        }
        if m.mass_kg == 0.0 {
            shares.push(Vec::new());
            continue;
        }
        let Some(attached) = at.get(&key(p)) else {
            return Err(MappingError::NodalMass {
                index: k,
                message: format!(
                    "of {} kg at ({}, {}, {}) is at no element node",
                    m.mass_kg, p[0], p[1], p[2]
                ),
            });
        };
        let pick = |kind: Role| -> Vec<usize> {
            attached
                .iter()
                .copied()
                .filter(|&i| boxes[i].kind == kind)
                .collect()
        };
        let mut to = pick(Role::Slab);
        if to.is_empty() {
            to = pick(Role::Beam);
        }
        if to.is_empty() {
            to = attached.clone();
        }
        let share = m.mass_kg / to.len() as f64;
        for &i in &to {
            boxes[i].mass_kg += share;
        }
        shares.push(to);
    }
    Ok(shares)
}
