//! FE-derived connection strengths of a run's bodies (docs/handoff.md): the
//! FE capacity analysis ([`crate::fe::capacity`]) turned into the plain numbers the ruin
//! stage takes ([`BodyStrength`]).
//!
//! Per body that is a beam-column element with an `rc_rect` section: its local axes, and
//! per end (node i, node j) the section's compression, tension, shear and bending
//! capacities and whether it has lost its load path ([`BodyCapacity::Member`]). The
//! boxes of `panel` elements (slab panels: rigid bodies only, the FE carries the slab as
//! lumped mass on elastic strips) are [`BodyCapacity::Elastic`] with `elastic_panels`
//! (`[physics] panel_connections = "elastic"`, docs/handoff.md §2.6): they never limit a
//! connection. Every other body (walls, foundation blocks, panels with `"group"`) is
//! [`BodyCapacity::Group`] and keeps its group strength.
//!
//! The remaining rotation capacity of each end ([`EndCapacity::rotation_left`]) becomes
//! the connection's 1st rotation tolerance: its bending rows hold the moment capacity as
//! a rigid–plastic hinge until the rotation since Tc exceeds it
//! ([`crate::ruin::connection::ConnectionSpec::ductile`]).

use super::Body;
use crate::fe::capacity::{EndCapacity, MemberCapacity};
use crate::model::{ElementKind, Model};
use crate::ruin::connection::{BodyCapacity, BodyStrength, EndStrength};
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

/// One entry per body (module docs). `elastic_panels`: panel bodies are
/// [`BodyCapacity::Elastic`] (else [`BodyCapacity::Group`]).
pub fn body_strengths(
    model: &Model,
    bodies: &[Body],
    caps: &BTreeMap<u32, MemberCapacity>,
    elastic_panels: bool,
) -> Vec<BodyCapacity> {
    let kinds: BTreeMap<u32, &ElementKind> =
        model.elements.iter().map(|e| (e.tag, &e.kind)).collect();
    bodies
        .iter()
        .map(|b| {
            let Some(tag) = b.id.element_tag() else {
                return BodyCapacity::Group;
            };
            if let Some(m) = caps.get(&tag) {
                return BodyCapacity::Member(Box::new(BodyStrength {
                    axes: m.axes,
                    ends: [
                        (m.nodes[0], end_strength(&m.ends[0])),
                        (m.nodes[1], end_strength(&m.ends[1])),
                    ],
                }));
            }
            match kinds.get(&tag) {
                Some(ElementKind::Panel { .. }) if elastic_panels => BodyCapacity::Elastic,
                _ => BodyCapacity::Group,
            }
        })
        .collect()
}
