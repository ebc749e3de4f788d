//! Builds the FE [`Domain`] of a [`Model`]: nodes, supports, lumped masses (nodal masses
//! plus element self-weight split to the element's nodes, as
//! [`Model::lumped_masses`] documents), gravity loads, materials, sections and
//! beam-column elements with their geometric transformations.
//!
//! The element formulation is the model's unless a [`Variant`] overrides it — the same
//! three variants the OpenSees reference runs use (`force`, `disp`, `elastic`; see
//! `tests/fixtures/opensees-frame3/run_frame3.py`). The `elastic` variant replaces
//! every nonlinear beam-column by an elastic one with its section's initial transformed
//! properties (EA, EIz, EIy, GJ from Σ E_i A_i, Σ E_i A_i y_i², Σ E_i A_i z_i²).

use crate::fe::domain::Domain;
use crate::fe::element::beam::{BeamColumnSpec, Formulation};
use crate::fe::element::elastic_beam::ElasticProps;
use crate::fe::element::force_beam::ForceBeamOptions;
use crate::fe::element::Element;
use crate::fe::material::{self, UniaxialMaterial};
use crate::fe::section::elastic::ElasticSection;
use crate::fe::section::fiber::FiberSection;
use crate::fe::section::Section;
use crate::fe::shell::element::ShellElement;
use crate::fe::shell::layers::{
    ConcreteIntegration, DamageConcreteFiber, ElasticFiber, LayeredSection, PlateFiber, RebarFiber,
};
use crate::fe::transform::TransformKind;
use crate::fe::FeError;
use crate::model::{self, ElementKind, Model, SectionKind, ShellLayer, TransfKind};
use nalgebra::Vector3;
use std::collections::BTreeMap;

/// Which element formulation to use for the model's nonlinear beam-columns.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Variant {
    /// As each element says (`formulation = "force" | "disp"`).
    #[default]
    AsModel,
    /// Every beam-column force-based (Gauss-Lobatto).
    Force,
    /// Every beam-column displacement-based (Gauss-Legendre).
    Disp,
    /// Every beam-column elastic with its section's initial properties.
    Elastic,
}

/// A name that is not an element [`Variant`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown element variant `{0}` (expected model, force, disp or elastic)")]
pub struct UnknownVariant(pub String);

impl std::str::FromStr for Variant {
    type Err = UnknownVariant;
    fn from_str(s: &str) -> std::result::Result<Self, UnknownVariant> {
        match s {
            "model" | "as-model" => Ok(Variant::AsModel),
            "force" => Ok(Variant::Force),
            "disp" => Ok(Variant::Disp),
            "elastic" => Ok(Variant::Elastic),
            other => Err(UnknownVariant(other.to_string())),
        }
    }
}

impl<'de> serde::Deserialize<'de> for Variant {
    /// The names of [`FromStr`](std::str::FromStr) (`model`, `force`, `disp`, `elastic`);
    /// an unknown name is an error naming it and the choices.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        s.parse().map_err(serde::de::Error::custom)
    }
}

/// Options of the domain builder.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BuildOptions {
    /// Formulation override.
    pub variant: Variant,
    /// Element iteration controls of force-based elements. The frame3 reference runs use
    /// `-iter 50 1e-12`.
    pub force_options: ForceBeamOptions,
    /// How the shells' `concrete` layers integrate their damage and plastic strain:
    /// OpenSees' implicit law (default) or IMPL-EX
    /// ([`crate::fe::shell::layers::ConcreteIntegration`]).
    pub concrete_integration: ConcreteIntegration,
    /// Threads for element state determination ([`Domain::set_threads`]); `None` = the
    /// machine's cores ([`crate::fe::domain::default_threads`]). The same bits for any
    /// number.
    pub threads: Option<usize>,
}

impl Default for BuildOptions {
    fn default() -> Self {
        Self {
            variant: Variant::AsModel,
            force_options: ForceBeamOptions {
                max_iter: 50,
                tol: 1e-12,
                ..ForceBeamOptions::default()
            },
            concrete_integration: ConcreteIntegration::Implicit,
            threads: None,
        }
    }
}

/// A built domain and the tag ↔ index maps of the model it came from.
#[derive(Debug)]
pub struct BuiltDomain {
    /// The FE domain, DOFs numbered, gravity loads in its reference load pattern.
    pub domain: Domain,
    /// Node tag → domain node index.
    pub node_index: BTreeMap<u32, usize>,
    /// Element tag → domain element index.
    pub element_index: BTreeMap<u32, usize>,
}

/// What building a domain returns.
type Result<T> = std::result::Result<T, FeError>;

fn uniaxial(m: &model::Material) -> Result<Box<dyn UniaxialMaterial>> {
    let params: BTreeMap<String, f64> = m
        .parameters()
        .into_iter()
        .filter(|(k, _)| *k != "density")
        .map(|(k, v)| (k.to_string(), v))
        .collect();
    material::build(m.type_name(), &params).map_err(|error| FeError::Material {
        tag: m.tag,
        name: m.name.clone(),
        error,
    })
}

fn section_prototype(
    s: &model::Section,
    mats: &BTreeMap<u32, &model::Material>,
) -> Result<Box<dyn Section>> {
    match &s.kind {
        SectionKind::Elastic {
            e, g, a, iy, iz, j, ..
        } => Ok(Box::new(ElasticSection::new(e * a, e * iz, e * iy, g * j))),
        SectionKind::Plate { .. } | SectionKind::LayeredShell { .. } => {
            Err(FeError::Unsupported(format!(
                "section {} is a shell section; beam-columns need a fiber, rc_rect or elastic section",
                s.tag
            )))
        }
        _ => {
            let fibers = s.fibers().expect("fiber or rc_rect section has fibers");
            let gj = s.gj().expect("beam section has GJ");
            let mut list = Vec::with_capacity(fibers.len());
            for f in &fibers {
                let m = mats.get(&f.material()).ok_or_else(|| {
                    FeError::Unsupported(format!(
                        "section {}: unknown material {}",
                        s.tag,
                        f.material()
                    ))
                })?;
                list.push((f.y(), f.z(), f.area(), uniaxial(m)?));
            }
            Ok(Box::new(
                FiberSection::new(list, gj)
                    .map_err(|error| FeError::Section { tag: s.tag, error })?,
            ))
        }
    }
}

/// Initial transformed elastic properties of a beam section, as an elastic element with
/// E = 1 (so A, Iz, Iy, J carry EA, EIz, EIy, GJ), the `elastic` variant of the
/// reference runs.
fn elastic_equivalent(
    s: &model::Section,
    mats: &BTreeMap<u32, &model::Material>,
) -> Result<ElasticProps> {
    if let SectionKind::Elastic {
        e, g, a, iy, iz, j, ..
    } = &s.kind
    {
        return Ok(ElasticProps {
            e: *e,
            g: *g,
            a: *a,
            iy: *iy,
            iz: *iz,
            j: *j,
        });
    }
    let fibers = s
        .fibers()
        .ok_or_else(|| FeError::Unsupported(format!("section {} has no fibers", s.tag)))?;
    let (mut ea, mut eiz, mut eiy) = (0.0, 0.0, 0.0);
    for f in &fibers {
        let m = mats.get(&f.material()).ok_or_else(|| {
            FeError::Unsupported(format!(
                "section {}: unknown material {}",
                s.tag,
                f.material()
            ))
        })?;
        let e = m.initial_tangent();
        ea += e * f.area();
        eiz += e * f.area() * f.y() * f.y();
        eiy += e * f.area() * f.z() * f.z();
    }
    Ok(ElasticProps {
        e: 1.0,
        g: 1.0,
        a: ea,
        iy: eiy,
        iz: eiz,
        j: s.gj().unwrap_or(0.0),
    })
}

fn transform_kind(k: TransfKind) -> TransformKind {
    match k {
        TransfKind::Linear => TransformKind::Linear,
        TransfKind::Pdelta => TransformKind::PDelta,
        TransfKind::Corotational => TransformKind::Corotational,
    }
}

/// The layered section of a shell element for the domain, and whether all its layers are
/// linear (elastic layers, bars of an `Elastic` material).
fn shell_section(
    tag: u32,
    s: &model::Section,
    mats: &BTreeMap<u32, &model::Material>,
    integration: ConcreteIntegration,
) -> Result<(LayeredSection, bool)> {
    let SectionKind::LayeredShell { layers, .. } = &s.kind else {
        return Err(FeError::Unsupported(format!(
            "element {tag}: section {} is a `plate` section; the FE solver's shell \
             (ASDShellQ4) takes a `layered_shell` section (write the plate as elastic layers)",
            s.tag
        )));
    };
    let mut linear = true;
    let mut list: Vec<(f64, Box<dyn PlateFiber>)> = Vec::with_capacity(layers.len());
    for l in layers {
        let fiber: Box<dyn PlateFiber> = match l {
            ShellLayer::Elastic { e, nu, .. } => Box::new(ElasticFiber::new(*e, *nu)),
            ShellLayer::Concrete { e, nu, fc, ft, .. } => {
                linear = false;
                Box::new(DamageConcreteFiber::new(*e, *nu, *ft, *fc).with_integration(integration))
            }
            ShellLayer::Rebar {
                material, angle, ..
            } => {
                let m = mats.get(material).ok_or_else(|| {
                    FeError::Unsupported(format!(
                        "element {tag}: section {}: unknown material {material}",
                        s.tag
                    ))
                })?;
                if m.type_name() != "Elastic" {
                    linear = false;
                }
                Box::new(RebarFiber::new(uniaxial(m)?, *angle))
            }
        };
        list.push((l.thickness(), fiber));
    }
    Ok((LayeredSection::new(list), linear))
}

/// Refuses nodes with a free DOF that no structural element uses: no stiffness holds
/// those DOFs, so the stiffness matrix is singular (and the modal analysis would
/// condense thousands of them in a dense matrix). Names the first ten and the count.
/// The command line checks every model with it before any work; [`build_domain`] does
/// not, so that a program can build a domain and add stiffness of its own.
pub fn check_unused_nodes(model: &Model) -> Result<()> {
    let mut used = std::collections::BTreeSet::new();
    for e in &model.elements {
        if !matches!(e.kind, ElementKind::Panel { .. }) {
            used.extend(e.nodes().iter().copied());
        }
    }
    let fixity = model.fixity();
    let unused: Vec<u32> = model
        .nodes
        .iter()
        .map(|n| n.tag)
        .filter(|t| !used.contains(t) && fixity.get(t).is_none_or(|d| d.contains(&0)))
        .collect();
    if unused.is_empty() {
        return Ok(());
    }
    let shown: Vec<String> = unused.iter().take(10).map(u32::to_string).collect();
    let more = if unused.len() > 10 { ", …" } else { "" };
    Err(FeError::Unsupported(format!(
        "{} node(s) used by no structural element (node {}{more}): nothing holds their \
         free DOFs, so the stiffness matrix is singular; remove them, connect them to an \
         element, or fix all six DOFs",
        unused.len(),
        shown.join(", ")
    )))
}

/// Builds the domain of `model` (which must have passed validation, as
/// [`Model::load`] guarantees). Shells are `ASDShellQ4` elements
/// ([`crate::fe::shell::element::ShellElement`]) on `layered_shell` sections, small-
/// displacement or corotational; `plate` sections are refused, naming the element.
pub fn build_domain(model: &Model, options: &BuildOptions) -> Result<BuiltDomain> {
    if !model
        .elements
        .iter()
        .any(|e| !matches!(e.kind, crate::model::ElementKind::Panel { .. }))
    {
        return Err(FeError::Unsupported(format!(
            "model {:?} has no structural elements ({} nodes, {} elements, panels are \
             rigid-body only): nothing to analyse",
            model.name,
            model.nodes.len(),
            model.elements.len()
        )));
    }
    let mut domain = Domain::new();
    if let Some(n) = options.threads {
        domain.set_threads(n);
    }
    let mut node_index = BTreeMap::new();
    for n in &model.nodes {
        let i = domain
            .add_node(i64::from(n.tag), n.xyz())
            .map_err(|error| FeError::Domain {
                item: format!("node {}", n.tag),
                error,
            })?;
        node_index.insert(n.tag, i);
    }
    let idx = |tag: u32| -> Result<usize> {
        node_index
            .get(&tag)
            .copied()
            .ok_or_else(|| FeError::Unsupported(format!("unknown node {tag}")))
    };
    let at_node = |tag: u32| {
        move |error| FeError::Domain {
            item: format!("node {tag}"),
            error,
        }
    };
    for (tag, dofs) in model.fixity() {
        domain
            .fix(idx(tag)?, dofs.map(|d| d != 0))
            .map_err(at_node(tag))?;
    }
    for (tag, m) in model.lumped_masses() {
        if let Some(bad) = m.iter().find(|v| !v.is_finite()) {
            return Err(FeError::Unsupported(format!(
                "node {tag}: its lumped mass {bad} kg is not finite: the self-weight of the \
                 elements at it overflows (check their node coordinates, lengths and \
                 densities: docs/reliability.md)"
            )));
        }
        domain.set_mass(idx(tag)?, m).map_err(at_node(tag))?;
    }
    for (tag, fz) in model.gravity_loads() {
        domain
            .add_nodal_load(idx(tag)?, [0.0, 0.0, fz, 0.0, 0.0, 0.0])
            .map_err(at_node(tag))?;
    }

    let mats = model.material_map();
    let secs = model.section_map();
    let transfs = model.transformation_map();
    let mut element_index = BTreeMap::new();
    let node_map = model.node_map();
    for e in &model.elements {
        let tag = i64::from(e.tag);
        let (nodes, transf) = match &e.kind {
            ElementKind::BeamColumn { nodes, transf, .. }
            | ElementKind::ElasticBeamColumn { nodes, transf, .. }
            | ElementKind::ElasticStrip { nodes, transf, .. } => (*nodes, *transf),
            ElementKind::Panel { .. } => continue, // rigid-body model only
            ElementKind::Shell {
                nodes,
                section,
                local_x,
                corotational,
            } => {
                let s = secs.get(section).ok_or_else(|| {
                    FeError::Unsupported(format!("element {}: unknown section {section}", e.tag))
                })?;
                let (sec, linear) = shell_section(e.tag, s, &mats, options.concrete_integration)?;
                let mut coords = [[0.0; 3]; 4];
                let mut idxs = [0; 4];
                for ((c, i), n) in coords.iter_mut().zip(&mut idxs).zip(nodes) {
                    *c = node_map
                        .get(n)
                        .ok_or_else(|| {
                            FeError::Unsupported(format!("element {}: unknown node {n}", e.tag))
                        })?
                        .xyz();
                    *i = idx(*n)?;
                }
                let lx = local_x.unwrap_or([
                    coords[1][0] - coords[0][0],
                    coords[1][1] - coords[0][1],
                    coords[1][2] - coords[0][2],
                ]);
                let el = ShellElement::new(tag, idxs, &coords, lx, &sec, linear, *corotational)
                    .map_err(|err| FeError::Unsupported(format!("element {}: {err}", e.tag)))?;
                let i = domain
                    .add_element(Box::new(el))
                    .map_err(|error| FeError::Domain {
                        item: format!("element {}", e.tag),
                        error,
                    })?;
                element_index.insert(e.tag, i);
                continue;
            }
        };
        let t = transfs.get(&transf).ok_or_else(|| {
            FeError::Unsupported(format!(
                "element {}: unknown transformation {transf}",
                e.tag
            ))
        })?;
        let [ni, nj] = nodes;
        let xi = Vector3::from(node_map[&ni].xyz());
        let xj = Vector3::from(node_map[&nj].xyz());
        let (formulation, section) = match &e.kind {
            ElementKind::BeamColumn {
                section,
                formulation,
                points,
                ..
            } => {
                let s = secs.get(section).ok_or_else(|| {
                    FeError::Unsupported(format!("element {}: unknown section {section}", e.tag))
                })?;
                let n_ip = *points as usize;
                let chosen = match options.variant {
                    Variant::AsModel => match formulation {
                        model::Formulation::Force => Variant::Force,
                        model::Formulation::Disp => Variant::Disp,
                    },
                    v => v,
                };
                match chosen {
                    Variant::Elastic => (Formulation::Elastic(elastic_equivalent(s, &mats)?), None),
                    Variant::Disp => (
                        Formulation::DispBased { n_ip },
                        Some(section_prototype(s, &mats)?),
                    ),
                    _ => (
                        Formulation::ForceBased {
                            n_ip,
                            options: options.force_options,
                        },
                        Some(section_prototype(s, &mats)?),
                    ),
                }
            }
            ElementKind::ElasticBeamColumn { section, .. } => {
                let s = secs.get(section).ok_or_else(|| {
                    FeError::Unsupported(format!("element {}: unknown section {section}", e.tag))
                })?;
                (Formulation::Elastic(elastic_equivalent(s, &mats)?), None)
            }
            ElementKind::ElasticStrip {
                e: young,
                g,
                width,
                thickness,
                ..
            } => {
                let (a, iy, iz, j) = model::element::strip_properties(*width, *thickness);
                (
                    Formulation::Elastic(ElasticProps {
                        e: *young,
                        g: *g,
                        a,
                        iy,
                        iz,
                        j,
                    }),
                    None,
                )
            }
            ElementKind::Shell { .. } | ElementKind::Panel { .. } => unreachable!("refused above"),
        };
        let spec = BeamColumnSpec {
            tag,
            nodes: [idx(ni)?, idx(nj)?],
            xi,
            xj,
            transform: transform_kind(t.kind),
            vecxz: Vector3::from(t.vecxz),
            formulation,
            section,
        };
        let element: Box<dyn Element> = spec
            .build()
            .map_err(|error| FeError::Element { tag: e.tag, error })?;
        let i = domain
            .add_element(element)
            .map_err(|error| FeError::Domain {
                item: format!("element {}", e.tag),
                error,
            })?;
        element_index.insert(e.tag, i);
    }
    domain.number_dofs();
    Ok(BuiltDomain {
        domain,
        node_index,
        element_index,
    })
}
