//! Elements and geometric transformations of the model file.
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// Geometric transformation (OpenSees `geomTransf Linear|PDelta|Corotational tag vecxz`).
/// Local x runs from node i to node j; local y = vecxz × x, local z = x × y.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Transformation {
    /// Unique transformation tag.
    pub tag: u32,
    /// Linear, P-Delta or corotational.
    #[serde(rename = "type")]
    pub kind: TransfKind,
    /// A vector in the local x-z plane (global components).
    pub vecxz: [f64; 3],
}

/// Kind of geometric transformation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TransfKind {
    /// Small displacements.
    Linear,
    /// P-Delta (second order, small rotations).
    Pdelta,
    /// Large displacements and rotations (Crisfield corotational).
    Corotational,
}

impl TransfKind {
    /// OpenSees' name.
    pub fn opensees_name(self) -> &'static str {
        match self {
            TransfKind::Linear => "Linear",
            TransfKind::Pdelta => "PDelta",
            TransfKind::Corotational => "Corotational",
        }
    }
}

/// Beam-column formulation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Formulation {
    /// Force-based (flexibility) element, OpenSees `forceBeamColumn`.
    #[default]
    Force,
    /// Displacement-based element, OpenSees `dispBeamColumn`.
    Disp,
}

/// Integration rule along a beam-column.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Integration {
    /// Gauss-Lobatto (end points included); OpenSees default for force-based elements.
    Lobatto,
    /// Gauss-Legendre; OpenSees default for displacement-based elements.
    Legendre,
}

/// The material group of an element: a number or a name, kept as text
/// (used in rigid-body names `Type:group:element`).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Group(pub String);

impl Serialize for Group {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self.0.parse::<i64>() {
            Ok(n) if n.to_string() == self.0 => s.serialize_i64(n),
            _ => s.serialize_str(&self.0),
        }
    }
}

impl<'de> Deserialize<'de> for Group {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Repr {
            Int(i64),
            Text(String),
        }
        Ok(match Repr::deserialize(d)? {
            Repr::Int(n) => Group(n.to_string()),
            Repr::Text(s) => Group(s),
        })
    }
}

impl std::fmt::Display for Group {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// One element: tag, naming data and the element proper.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Element {
    /// Unique element tag.
    pub tag: u32,
    /// Type name for rigid-body naming, e.g. "Column", "Beam", "Slab".
    pub type_name: String,
    /// Material group (number or name).
    pub group: Group,
    /// Whether the element becomes a rigid body in the mapping (default `true`). `false`
    /// marks an FE-only element, e.g. the elastic diagonal strips that stand in for a slab's
    /// in-plane stiffness (the slab's rigid bodies are `panel`s instead).
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub rigid_body: bool,
    /// The element kind (`type` key) and its data.
    #[serde(flatten)]
    pub kind: ElementKind,
}

fn yes() -> bool {
    true
}

fn is_true(b: &bool) -> bool {
    *b
}

/// Element kinds (`type = "beam_column" | "elastic_beam_column" | "elastic_strip" | "shell" |
/// "panel"`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", deny_unknown_fields, rename_all = "snake_case")]
pub enum ElementKind {
    /// Nonlinear beam-column with a fiber, RC or elastic section.
    BeamColumn {
        /// End nodes i, j.
        nodes: [u32; 2],
        /// Section tag.
        section: u32,
        /// Transformation tag.
        transf: u32,
        /// `force` (default) or `disp`.
        #[serde(default)]
        formulation: Formulation,
        /// Integration points (default 5).
        #[serde(default = "five")]
        points: u32,
        /// Rule; default Lobatto for `force`, Legendre for `disp`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        integration: Option<Integration>,
    },
    /// Linear elastic beam-column with an elastic section.
    ElasticBeamColumn {
        /// End nodes i, j.
        nodes: [u32; 2],
        /// Elastic section tag.
        section: u32,
        /// Transformation tag.
        transf: u32,
    },
    /// Elastic strip of slab: a beam of rectangular cross-section `width` (local y) ×
    /// `thickness` (local z) with A = w t, Iy = w t³/12, Iz = t w³/12, J = w t³/3.
    ElasticStrip {
        /// End nodes i, j.
        nodes: [u32; 2],
        /// Transformation tag.
        transf: u32,
        /// Young's modulus (Pa).
        #[serde(rename = "E")]
        e: f64,
        /// Shear modulus (Pa).
        #[serde(rename = "G")]
        g: f64,
        /// Strip width (m, local y).
        width: f64,
        /// Strip thickness (m, local z).
        thickness: f64,
        /// Density for self-weight ρ·w·t per length (kg/m³); default 0.
        #[serde(default)]
        density: f64,
    },
    /// Four-node quadrilateral shell/slab (nodes counter-clockwise) with a `plate` or a
    /// `layered_shell` section.
    Shell {
        /// Corner nodes.
        nodes: [u32; 4],
        /// Plate or layered-shell section tag.
        section: u32,
        /// Direction of the element's local x axis (projected on its plane), from which
        /// rebar-layer angles are measured; default the edge node 1 → node 2.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        local_x: Option<[f64; 3]>,
        /// Large displacements and rotations (corotational, OpenSees
        /// `ASDShellQ4 -corotational`); default false (small displacements).
        #[serde(default, skip_serializing_if = "std::ops::Not::not")]
        corotational: bool,
    },
    /// Slab panel for the rigid-body model only: four corner nodes (cyclic order) and a
    /// thickness; no FE stiffness (the FE solver and the OpenSees export skip it). Its
    /// self-weight is ρ·t·area when a `density` is given, else zero (frame3 lumps the
    /// slab's weight as nodal masses). Its rigid-body pose follows its four nodes.
    Panel {
        /// Corner nodes, cyclic order.
        nodes: [u32; 4],
        /// Thickness (m).
        thickness: f64,
        /// Density for self-weight (kg/m³); default 0.
        #[serde(default)]
        density: f64,
    },
}

fn five() -> u32 {
    5
}

/// Properties of an elastic strip: (A, Iy, Iz, J) in m², m⁴.
pub fn strip_properties(width: f64, thickness: f64) -> (f64, f64, f64, f64) {
    let (w, t) = (width, thickness);
    (
        w * t,
        w * t.powi(3) / 12.0,
        t * w.powi(3) / 12.0,
        w * t.powi(3) / 3.0,
    )
}

impl Element {
    /// The element's nodes (2 for line elements, 4 for shells).
    pub fn nodes(&self) -> &[u32] {
        match &self.kind {
            ElementKind::BeamColumn { nodes, .. }
            | ElementKind::ElasticBeamColumn { nodes, .. }
            | ElementKind::ElasticStrip { nodes, .. } => nodes,
            ElementKind::Shell { nodes, .. } | ElementKind::Panel { nodes, .. } => nodes,
        }
    }

    /// Section tag, if the element has one.
    pub fn section(&self) -> Option<u32> {
        match &self.kind {
            ElementKind::BeamColumn { section, .. }
            | ElementKind::ElasticBeamColumn { section, .. }
            | ElementKind::Shell { section, .. } => Some(*section),
            ElementKind::ElasticStrip { .. } | ElementKind::Panel { .. } => None,
        }
    }

    /// Transformation tag of a line element.
    pub fn transf(&self) -> Option<u32> {
        match &self.kind {
            ElementKind::BeamColumn { transf, .. }
            | ElementKind::ElasticBeamColumn { transf, .. }
            | ElementKind::ElasticStrip { transf, .. } => Some(*transf),
            ElementKind::Shell { .. } | ElementKind::Panel { .. } => None,
        }
    }

    /// The file's name of the kind.
    pub fn kind_name(&self) -> &'static str {
        match self.kind {
            ElementKind::BeamColumn { .. } => "beam_column",
            ElementKind::ElasticBeamColumn { .. } => "elastic_beam_column",
            ElementKind::ElasticStrip { .. } => "elastic_strip",
            ElementKind::Shell { .. } => "shell",
            ElementKind::Panel { .. } => "panel",
        }
    }

    /// Whether the FE solver models the element (everything but `panel`).
    pub fn in_fe(&self) -> bool {
        !matches!(self.kind, ElementKind::Panel { .. })
    }

    /// Rigid-body name `Type:group:tag`, e.g. `Beam:1:234` (paper §3.1, BCB naming).
    pub fn body_name(&self) -> String {
        format!("{}:{}:{}", self.type_name, self.group, self.tag)
    }
}
