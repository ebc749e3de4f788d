//! The building model: file format (serde, TOML/JSON), validation, generator.
//!
//! Units are SI: m, kg, s, N, Pa. The format is documented in `docs/model-format.md`.
//! Load a file with [`Model::load`]; it parses, then validates (unknown references,
//! duplicate tags, zero-length elements, non-positive sizes, non-finite numbers) and
//! reports the file, line and item of the first error.
pub mod building;
pub mod element;
pub mod generate;
pub mod limits;
pub mod material;
pub mod opensees_json;
pub mod plausibility;
pub mod reference_json;
pub mod section;
mod source_map;
mod validate;

pub use element::{
    strip_properties, Element, ElementKind, Formulation, Group, Integration, TransfKind,
    Transformation,
};
pub use material::{Material, MaterialLaw};
pub use opensees_json::{import_notes, import_opensees_json, Supports};
pub use reference_json::import_reference_json;
pub use section::{Bar, ElasticEquivalent, Fiber, RcRect, Section, SectionKind, ShellLayer};
pub use validate::{Location, ModelError};

/// A value that breaks its rule, e.g. "E = -1 must be positive": the message names the
/// parameter; [`Model::validate`] adds the file, line and item ([`ModelError::Value`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct InvalidValue(pub String);

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// A node: tag and global coordinates (m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Node {
    /// Unique node tag.
    pub tag: u32,
    /// Global X (m).
    pub x: f64,
    /// Global Y (m).
    pub y: f64,
    /// Global Z (m), vertical, up.
    pub z: f64,
}

impl Node {
    /// Coordinates as an array (m).
    pub fn xyz(&self) -> [f64; 3] {
        [self.x, self.y, self.z]
    }
}

/// A support: the fixed DOFs of a node (1 = fixed, 0 = free), order ux uy uz rx ry rz.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Support {
    /// Node tag.
    pub node: u32,
    /// Fixity flags.
    pub dofs: [u8; 6],
}

/// A lumped nodal mass: `m` (kg) on the three translations, optional rotational
/// inertias (kg·m²). Several entries on one node add up.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NodalMass {
    /// Node tag.
    pub node: u32,
    /// Translational mass (kg), the same in X, Y and Z.
    pub m: f64,
    /// Rotational inertias about X, Y, Z (kg·m²); default zero.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotational: Option<[f64; 3]>,
}

/// Gravity: acceleration g (m/s²) acting in −Z on every mass (nodal masses and lumped
/// self-weight), applied in `load_steps` load-control steps and then held constant.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Gravity {
    /// Acceleration of gravity (m/s²); default 9.81.
    #[serde(default = "default_g")]
    pub g: f64,
    /// Load-control steps for applying gravity; default 10.
    #[serde(default = "default_steps")]
    pub load_steps: u32,
}

fn default_g() -> f64 {
    9.81
}
fn default_steps() -> u32 {
    10
}
fn default_scale() -> f64 {
    1.0
}

impl Default for Gravity {
    fn default() -> Self {
        Gravity {
            g: default_g(),
            load_steps: default_steps(),
        }
    }
}

/// Rayleigh damping C = a0·M + a1·K_initial, given either as damping ratio `xi` at two
/// periods `periods = [Ti, Tj]` (s) or explicitly as `a0` (1/s) and `a1` (s).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Damping {
    /// Damping ratio ξ at both anchor periods.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub xi: Option<f64>,
    /// The two anchor periods (s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub periods: Option<[f64; 2]>,
    /// Mass-proportional coefficient (1/s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub a0: Option<f64>,
    /// Initial-stiffness-proportional coefficient (s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub a1: Option<f64>,
}

impl Damping {
    /// (a0, a1). From ξ and ωi = 2π/Ti, ωj = 2π/Tj (Chopra, Dynamics of Structures,
    /// eq. 11.4.9 with ξi = ξj): a0 = 2ξ ωi ωj/(ωi+ωj), a1 = 2ξ/(ωi+ωj).
    pub fn coefficients(&self) -> Option<(f64, f64)> {
        match (self.xi, self.periods, self.a0, self.a1) {
            (Some(xi), Some([ti, tj]), None, None) => {
                let wi = 2.0 * std::f64::consts::PI / ti;
                let wj = 2.0 * std::f64::consts::PI / tj;
                Some((2.0 * xi * wi * wj / (wi + wj), 2.0 * xi / (wi + wj)))
            }
            (None, None, Some(a0), Some(a1)) => Some((a0, a1)),
            _ => None,
        }
    }
}

/// The whole model. File keys are singular (`[[node]]`, `[[element]]`, ...).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Model {
    /// Model name.
    #[serde(default)]
    pub name: String,
    /// Free text.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub description: String,
    /// Geometric scale of the model relative to the prototype (e.g. 0.25 for a 1/4-scale
    /// shaking-table model); scales the collapse threshold. Default 1.
    #[serde(default = "default_scale")]
    pub scale: f64,
    /// Gravity.
    #[serde(default)]
    pub gravity: Gravity,
    /// Rayleigh damping (none if absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<Damping>,
    /// Uniaxial materials.
    #[serde(rename = "material", default)]
    pub materials: Vec<Material>,
    /// Sections.
    #[serde(rename = "section", default)]
    pub sections: Vec<Section>,
    /// Geometric transformations.
    #[serde(rename = "transformation", default)]
    pub transformations: Vec<Transformation>,
    /// Nodes.
    #[serde(rename = "node", default)]
    pub nodes: Vec<Node>,
    /// Supports.
    #[serde(rename = "support", default)]
    pub supports: Vec<Support>,
    /// Elements.
    #[serde(rename = "element", default)]
    pub elements: Vec<Element>,
    /// Lumped nodal masses (besides element self-weight).
    #[serde(rename = "mass", default)]
    pub masses: Vec<NodalMass>,
}

impl Model {
    /// Reads, parses and validates a model file (`.json` → JSON, anything else → TOML).
    /// A `.json` file in the reference layout of `frame3.json` (it has a top-level
    /// `uniaxial_materials` key) goes through [`import_reference_json`]; OpenSees'
    /// `print -JSON` output is refused with the command that imports it
    /// ([`import_opensees_json`]).
    pub fn load(path: impl AsRef<Path>) -> Result<Model, ModelError> {
        let path = path.as_ref();
        let text = limits::read_input_file(path, "model file")?;
        let is_json = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"));
        if is_json && reference_json::is_reference_layout(&text) {
            return import_reference_json(path);
        }
        if is_json && opensees_json::is_print_layout(&text) {
            return Err(ModelError::Import {
                at: Location {
                    file: path.display().to_string(),
                    line: None,
                    item: None,
                },
                message: "this is OpenSees' `print -JSON` output, which has no supports: \
                          convert it with `fem2rbd import opensees-json FILE [--fix-lowest] \
                          -o model.toml`"
                    .into(),
            });
        }
        Self::parse(&text, &path.display().to_string(), is_json)
    }

    /// Parses and validates model text; `file` names the source in error messages.
    pub fn parse(text: &str, file: &str, is_json: bool) -> Result<Model, ModelError> {
        validate::parse_and_validate(text, file, is_json)
    }

    /// Validates a model built in memory (errors carry no line numbers).
    pub fn validate(&self) -> Result<(), ModelError> {
        validate::validate(self, "<memory>", &source_map::SourceMap::default())
    }

    /// Writes the model as TOML text (deterministic).
    pub fn to_toml(&self) -> Result<String, toml::ser::Error> {
        toml::to_string(self)
    }

    /// Node tag → node.
    pub fn node_map(&self) -> BTreeMap<u32, &Node> {
        self.nodes.iter().map(|n| (n.tag, n)).collect()
    }
    /// Material tag → material.
    pub fn material_map(&self) -> BTreeMap<u32, &Material> {
        self.materials.iter().map(|m| (m.tag, m)).collect()
    }
    /// Section tag → section.
    pub fn section_map(&self) -> BTreeMap<u32, &Section> {
        self.sections.iter().map(|s| (s.tag, s)).collect()
    }
    /// Transformation tag → transformation.
    pub fn transformation_map(&self) -> BTreeMap<u32, &Transformation> {
        self.transformations.iter().map(|t| (t.tag, t)).collect()
    }

    /// Length (m) of a line element, or `None` for shells / unknown nodes.
    pub fn element_length(&self, e: &Element) -> Option<f64> {
        length_in(&self.node_map(), e)
    }

    /// The lookups that one element's mass needs, built once for many elements
    /// (building them per element made reading a model of n elements cost n² log n).
    fn lookups(&self) -> Lookups<'_> {
        Lookups {
            nodes: self.node_map(),
            mats: self.material_map(),
            secs: self.section_map(),
        }
    }

    /// Local axes `[x, y, z]` (unit vectors, global components) of a line element, by the
    /// OpenSees `geomTransf` convention: x from node i to node j, y = vecxz × x / |…|,
    /// z = x × y. `None` for shells, unknown nodes/transformations or a degenerate axis.
    pub fn local_axes(&self, e: &Element) -> Option<[[f64; 3]; 3]> {
        Self::local_axes_in(&self.node_map(), &self.transformation_map(), e)
    }

    /// [`Model::local_axes`] with the node and transformation lookups built once by the
    /// caller ([`Model::node_map`], [`Model::transformation_map`]): for many elements,
    /// building them per element would cost n² log n.
    pub fn local_axes_in(
        nodes: &BTreeMap<u32, &Node>,
        transfs: &BTreeMap<u32, &Transformation>,
        e: &Element,
    ) -> Option<[[f64; 3]; 3]> {
        let [i, j] = e.nodes() else { return None };
        let (a, b) = (nodes.get(i)?.xyz(), nodes.get(j)?.xyz());
        let v = transfs.get(&e.transf()?)?.vecxz;
        let cross = |p: [f64; 3], q: [f64; 3]| {
            [
                p[1] * q[2] - p[2] * q[1],
                p[2] * q[0] - p[0] * q[2],
                p[0] * q[1] - p[1] * q[0],
            ]
        };
        let unit = |p: [f64; 3]| {
            let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            (n > 0.0).then(|| [p[0] / n, p[1] / n, p[2] / n])
        };
        let x = unit([b[0] - a[0], b[1] - a[1], b[2] - a[2]])?;
        let y = unit(cross(v, x))?;
        let z = cross(x, y);
        Some([x, y, z])
    }

    /// Area (m²) of a shell's quadrilateral (half the norm of the diagonals' cross product).
    pub fn shell_area(&self, e: &Element) -> Option<f64> {
        area_in(&self.node_map(), e)
    }

    /// Self-weight mass (kg) of one element: mass per length × length for line elements
    /// (section Σ ρA, strip ρ·w·t), ρ·h·area for shells.
    pub fn element_mass(&self, e: &Element) -> f64 {
        mass_in(&self.lookups(), e)
    }

    /// [`Model::element_mass`] of every element, in model order (the lookups built once).
    pub fn element_masses(&self) -> Vec<f64> {
        let l = self.lookups();
        self.elements.iter().map(|e| mass_in(&l, e)).collect()
    }

    /// Total lumped mass per node `[mx, my, mz, Ixx, Iyy, Izz]` (kg, kg·m²): the nodal
    /// masses plus each element's self-weight split equally among its nodes (half to each
    /// end of a line element, a quarter to each shell corner), translations only.
    /// Includes nodes at supports. Sorted by node tag.
    pub fn lumped_masses(&self) -> BTreeMap<u32, [f64; 6]> {
        let mut out: BTreeMap<u32, [f64; 6]> = BTreeMap::new();
        for (e, m) in self.elements.iter().zip(self.element_masses()) {
            if m == 0.0 {
                continue;
            }
            let share = m / e.nodes().len() as f64;
            for n in e.nodes() {
                let v = out.entry(*n).or_default();
                for k in 0..3 {
                    v[k] += share;
                }
            }
        }
        for nm in &self.masses {
            let v = out.entry(nm.node).or_default();
            for k in 0..3 {
                v[k] += nm.m;
            }
            if let Some(r) = nm.rotational {
                for k in 0..3 {
                    v[3 + k] += r[k];
                }
            }
        }
        out
    }

    /// Total translational mass (kg), supports included.
    pub fn total_mass(&self) -> f64 {
        self.lumped_masses().values().map(|m| m[2]).sum()
    }

    /// Fixity flags per node (nodes without a support are absent).
    pub fn fixity(&self) -> BTreeMap<u32, [u8; 6]> {
        let mut out = BTreeMap::new();
        for s in &self.supports {
            out.insert(s.node, s.dofs);
        }
        out
    }

    /// Gravity loads: Fz = −m_z·g (N) at every node with mass, sorted by tag. Nodes whose
    /// six DOFs are all fixed are left out (the load would go straight to the support).
    pub fn gravity_loads(&self) -> Vec<(u32, f64)> {
        let fix = self.fixity();
        self.lumped_masses()
            .into_iter()
            .filter(|(t, m)| m[2] > 0.0 && fix.get(t) != Some(&[1; 6]))
            .map(|(t, m)| (t, -m[2] * self.gravity.g))
            .collect()
    }

    /// Rayleigh coefficients (a0, a1), if damping is given.
    pub fn rayleigh(&self) -> Option<(f64, f64)> {
        self.damping.as_ref().and_then(|d| d.coefficients())
    }
}

/// Node, material and section lookups by tag.
struct Lookups<'a> {
    nodes: BTreeMap<u32, &'a Node>,
    mats: BTreeMap<u32, &'a Material>,
    secs: BTreeMap<u32, &'a Section>,
}

/// Length (m) of a line element with its nodes looked up in `nodes`.
fn length_in(nodes: &BTreeMap<u32, &Node>, e: &Element) -> Option<f64> {
    match e.nodes() {
        [i, j] => {
            let (a, b) = (nodes.get(i)?, nodes.get(j)?);
            Some(((b.x - a.x).powi(2) + (b.y - a.y).powi(2) + (b.z - a.z).powi(2)).sqrt())
        }
        _ => None,
    }
}

/// Area (m²) of a quadrilateral element with its nodes looked up in `nodes`.
pub(crate) fn area_in(nodes: &BTreeMap<u32, &Node>, e: &Element) -> Option<f64> {
    match e.nodes() {
        [a, b, c, d] => {
            let p = |t: &u32| nodes.get(t).map(|n| n.xyz());
            let (a, b, c, d) = (p(a)?, p(b)?, p(c)?, p(d)?);
            let d1 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let d2 = [d[0] - b[0], d[1] - b[1], d[2] - b[2]];
            let x = [
                d1[1] * d2[2] - d1[2] * d2[1],
                d1[2] * d2[0] - d1[0] * d2[2],
                d1[0] * d2[1] - d1[1] * d2[0],
            ];
            Some(0.5 * (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt())
        }
        _ => None,
    }
}

/// Self-weight mass (kg) of one element ([`Model::element_mass`]).
fn mass_in(l: &Lookups<'_>, e: &Element) -> f64 {
    match &e.kind {
        ElementKind::BeamColumn { section, .. }
        | ElementKind::ElasticBeamColumn { section, .. } => {
            let mpl = l
                .secs
                .get(section)
                .map_or(0.0, |s| s.mass_per_length(&l.mats));
            mpl * length_in(&l.nodes, e).unwrap_or(0.0)
        }
        ElementKind::ElasticStrip {
            width,
            thickness,
            density,
            ..
        } => density * width * thickness * length_in(&l.nodes, e).unwrap_or(0.0),
        ElementKind::Shell { section, .. } => {
            l.secs
                .get(section)
                .and_then(|s| s.mass_per_area())
                .unwrap_or(0.0)
                * area_in(&l.nodes, e).unwrap_or(0.0)
        }
        ElementKind::Panel {
            thickness, density, ..
        } => density * thickness * area_in(&l.nodes, e).unwrap_or(0.0),
    }
}
