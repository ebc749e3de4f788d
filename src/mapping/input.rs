//! The mapping's own plain input: geometry and mass of each FE element, independent of
//! the model file format (a converter from the model builds these). SI units.

use crate::body::BodyType;

/// A line element (beam-column, elastic strip): one box per FE element.
#[derive(Debug, Clone, PartialEq)]
pub struct LineMember {
    /// FE element tag (used in the body name and in messages).
    pub element: u32,
    /// Member type for the body name, e.g. `Beam`, `Column`.
    pub body_type: BodyType,
    /// Material (group) id; one rigid-body group per material.
    pub material: String,
    /// End node i (m).
    pub node_i: [f64; 3],
    /// End node j (m).
    pub node_j: [f64; 3],
    /// OpenSees `vecxz`: a vector in the local x–z plane; local y = vecxz × x,
    /// local z = x × y.
    pub vecxz: [f64; 3],
    /// Section size along local y (m).
    pub width_m: f64,
    /// Section size along local z (m).
    pub depth_m: f64,
    /// Element self-weight mass (kg), ≥ 0.
    pub mass_kg: f64,
}

/// A quadrilateral shell / slab / wall element: one box of its thickness per FE element.
#[derive(Debug, Clone, PartialEq)]
pub struct Quad {
    /// FE element tag.
    pub element: u32,
    /// Member type, e.g. `Slab`, `Wall`.
    pub body_type: BodyType,
    /// Material (group) id.
    pub material: String,
    /// The four corner nodes in cyclic order (m).
    pub nodes: [[f64; 3]; 4],
    /// Thickness (m), along the quad's normal.
    pub thickness_m: f64,
    /// Element self-weight mass (kg), ≥ 0.
    pub mass_kg: f64,
}

/// A lumped (translational) mass at an FE node, e.g. ballast.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointMass {
    /// Node position (m).
    pub position: [f64; 3],
    /// Mass (kg), ≥ 0.
    pub mass_kg: f64,
}

/// Everything the mapping needs.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MappingInput {
    /// Line elements.
    pub members: Vec<LineMember>,
    /// Quadrilateral elements.
    pub quads: Vec<Quad>,
    /// Nodal masses.
    pub nodal_masses: Vec<PointMass>,
}
