//! FE-derived connection strengths of a run's bodies (issue 11, docs/handoff.md): the
//! FE capacity analysis ([`crate::fe::capacity`]) turned into the plain numbers the ruin
//! stage takes ([`BodyStrength`]).
//!
//! Per body that is a beam-column element with an `rc_rect` section: its local axes, and
//! per end (node i, node j) the section's compression, tension, shear and bending
//! capacities and whether it has lost its load path. Other bodies (slab panels,
//! foundation blocks) get `None` and keep their group strengths.
//!
//! The remaining rotation capacity of each end ([`EndCapacity::rotation_left`]) becomes
//! the connection's 1st rotation tolerance: its bending rows hold the moment capacity as
//! a rigid–plastic hinge until the rotation since Tc exceeds it
//! ([`crate::ruin::connection::ConnectionSpec::ductile`]).

use super::Body;
use crate::fe::capacity::{EndCapacity, MemberCapacity};
use crate::ruin::connection::{BodyStrength, EndStrength};
use std::collections::BTreeMap;

fn end_strength(e: &EndCapacity) -> EndStrength {
    EndStrength {
        compression_n: e.section.compression_n,
        tension_n: e.section.tension_n,
        shear_n: e.shear_n,
        moment_nm: e.section.moment_nm,
        rotation_left: Some(e.rotation_left),
        lost: e.lost,
    }
}

/// One entry per body (module docs).
pub fn body_strengths(
    bodies: &[Body],
    caps: &BTreeMap<u32, MemberCapacity>,
) -> Vec<Option<BodyStrength>> {
    bodies
        .iter()
        .map(|b| {
            let tag = b.id.element_tag()?;
            let m = caps.get(&tag)?;
            Some(BodyStrength {
                axes: m.axes,
                ends: [
                    (m.nodes[0], end_strength(&m.ends[0])),
                    (m.nodes[1], end_strength(&m.ends[1])),
                ],
            })
        })
        .collect()
}

/// Counts of member ends: (total, lost) — for reports.
pub fn lost_ends(caps: &BTreeMap<u32, MemberCapacity>) -> (usize, usize) {
    let total = caps.len() * 2;
    let lost = caps
        .values()
        .flat_map(|m| m.ends.iter())
        .filter(|e| e.lost)
        .count();
    (total, lost)
}
