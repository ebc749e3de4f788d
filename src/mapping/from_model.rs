//! Model file → mapping input: the converter [`from_model`] that feeds
//! [`super::map_to_boxes`] from a [`Model`].
//!
//! Rules:
//! - Only elements with `rigid_body = true` (the default) become bodies; FE-only elements
//!   (`rigid_body = false`, e.g. frame3's diagonal slab strips) do not.
//! - Beam-columns and elastic beam-columns → [`LineMember`]: the box's width (local y) and
//!   depth (local z) from [`crate::model::Section::outline`] (an error names the element
//!   when its section has no outline), `vecxz` from its transformation, mass = its
//!   self-weight ([`Model::element_mass`]). A rigid elastic strip maps with its own width
//!   × thickness.
//! - Shells (thickness = the plate's h) and panels → [`Quad`], mass = self-weight.
//! - Nodal masses → [`PointMass`] (translational `m` only: a rigid box's inertia is its
//!   own uniform-box inertia, nodal rotational inertias are not carried over).
//! - The self-weight of an FE-only element is not lost: half (line) or a quarter (quad)
//!   goes to each of its nodes as a nodal mass, then follows the nodal-mass rule of
//!   [`super::mass`].
//! - Nothing is dropped, supports included: the mapped bodies carry exactly
//!   [`Model::total_mass`] (the lower halves of the base columns included, whose mass the
//!   FE lumps onto the fixed base nodes).

use super::error::{MappingError, Result};
use super::input::{LineMember, MappingInput, PointMass, Quad};
use crate::model::{ElementKind, Model};

/// Builds the mapping input of a model (module docs). Errors name the element; a model
/// none of whose elements becomes a body is refused ([`MappingError::NoBodies`]).
pub fn from_model(model: &Model) -> Result<MappingInput> {
    let nodes = model.node_map();
    let secs = model.section_map();
    let transfs = model.transformation_map();
    let pos = |tag: &u32, e: u32| -> Result<[f64; 3]> {
        nodes
            .get(tag)
            .map(|n| n.xyz())
            .ok_or_else(|| MappingError::element(e, format!("unknown node {tag}")))
    };
    let mut input = MappingInput::default();
    for (e, mass_kg) in model.elements.iter().zip(model.element_masses()) {
        if !e.rigid_body {
            let share = mass_kg / e.nodes().len() as f64;
            if share > 0.0 {
                for n in e.nodes() {
                    input.nodal_masses.push(PointMass {
                        position: pos(n, e.tag)?,
                        mass_kg: share,
                    });
                }
            }
            continue;
        }
        let line = |width_m: f64, depth_m: f64| -> Result<LineMember> {
            let [i, j] = e.nodes() else {
                unreachable!("line elements have two nodes")
            };
            let tt = e.transf().expect("line elements have a transformation");
            let t = transfs.get(&tt).ok_or_else(|| {
                MappingError::element(e.tag, format!("unknown transformation {tt}"))
            })?;
            Ok(LineMember {
                element: e.tag,
                body_type: e.type_name.as_str().into(),
                material: e.group.0.clone(),
                node_i: pos(i, e.tag)?,
                node_j: pos(j, e.tag)?,
                vecxz: t.vecxz,
                width_m,
                depth_m,
                mass_kg,
            })
        };
        let quad = |thickness_m: f64| -> Result<Quad> {
            let n = e.nodes();
            Ok(Quad {
                element: e.tag,
                body_type: e.type_name.as_str().into(),
                material: e.group.0.clone(),
                nodes: [
                    pos(&n[0], e.tag)?,
                    pos(&n[1], e.tag)?,
                    pos(&n[2], e.tag)?,
                    pos(&n[3], e.tag)?,
                ],
                thickness_m,
                mass_kg,
            })
        };
        match &e.kind {
            ElementKind::BeamColumn { section, .. }
            | ElementKind::ElasticBeamColumn { section, .. } => {
                let sec = secs.get(section).ok_or_else(|| {
                    MappingError::element(e.tag, format!("unknown section {section}"))
                })?;
                let (w, d) = sec.outline().ok_or_else(|| MappingError::Element {
                    element: e.tag,
                    body: Some(e.body_name()),
                    message: format!(
                        "section {section} has no outline (width × depth); \
                         give the section's width and depth, or mark the element \
                         rigid_body = false"
                    ),
                })?;
                input.members.push(line(w, d)?);
            }
            ElementKind::ElasticStrip {
                width, thickness, ..
            } => input.members.push(line(*width, *thickness)?),
            ElementKind::Shell { section, .. } => {
                let Some(h) = secs.get(section).and_then(|s| s.shell_thickness()) else {
                    return Err(MappingError::element(
                        e.tag,
                        format!("section {section} is not a shell section"),
                    ));
                };
                input.quads.push(quad(h)?);
            }
            ElementKind::Panel { thickness, .. } => input.quads.push(quad(*thickness)?),
        }
    }
    if input.members.is_empty() && input.quads.is_empty() {
        return Err(MappingError::NoBodies {
            elements: model.elements.len(),
            fe_only: model.elements.iter().filter(|e| !e.rigid_body).count(),
        });
    }
    for m in &model.masses {
        input.nodal_masses.push(PointMass {
            position: pos(&m.node, 0).map_err(|_| MappingError::UnknownMassNode(m.node))?,
            mass_kg: m.m,
        });
    }
    Ok(input)
}
