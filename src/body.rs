//! The identity of a rigid body, typed: what kind of member it is, which FE element (or
//! base node) it comes from, and its material group.
//!
//! A body of an FE element is named `Type:material:element` (paper §3.1, BCB's naming),
//! e.g. `Beam:1:234`; a foundation block under a base column is named
//! `Foundation:base:<node>` (under a wall element standing on the base:
//! `Foundation:wall:<element>`) and belongs to the group `foundation`. [`BodyId`] holds these
//! parts as data; its [`Display`](std::fmt::Display) writes the name and its
//! [`FromStr`](std::str::FromStr) reads it back, and the columns of `bodies.csv` /
//! `ruins.csv` (`name,group,type,material,element`) are [`BodyId::name`],
//! [`BodyId::group`], [`BodyId::body_type`], [`BodyId::material`] and
//! [`BodyId::element_field`] (`-` for foundations).

use std::fmt;
use std::str::FromStr;

/// The group of the passive foundation blocks (BCB's passive group).
pub const FOUNDATION_GROUP: &str = "foundation";

/// The material field of a foundation block, and its element field.
pub(crate) const NO_FIELD: &str = "-";

/// A body's member type: the element's `type_name` in the model
/// (docs/model-format.md), or the foundation block the pipeline adds.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum BodyType {
    /// `Column`.
    Column,
    /// `Beam`.
    Beam,
    /// `Slab` (slab panels and strips).
    Slab,
    /// `Wall` (shell walls).
    Wall,
    /// `Foundation`: a passive block under a base column.
    Foundation,
    /// Any other type name a model gives (non-empty, no `:`).
    Other(String),
}

impl BodyType {
    /// The type name as written in names and files.
    pub fn as_str(&self) -> &str {
        match self {
            BodyType::Column => "Column",
            BodyType::Beam => "Beam",
            BodyType::Slab => "Slab",
            BodyType::Wall => "Wall",
            BodyType::Foundation => "Foundation",
            BodyType::Other(s) => s,
        }
    }
}

impl From<&str> for BodyType {
    fn from(s: &str) -> Self {
        match s {
            "Column" => BodyType::Column,
            "Beam" => BodyType::Beam,
            "Slab" => BodyType::Slab,
            "Wall" => BodyType::Wall,
            "Foundation" => BodyType::Foundation,
            o => BodyType::Other(o.to_string()),
        }
    }
}

impl fmt::Display for BodyType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Which body: an FE element's box or a foundation block (module docs).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum BodyId {
    /// The box of one FE element; its group is its material.
    Element {
        /// Member type (the element's `type_name`).
        body_type: BodyType,
        /// Material group (the element's `group`).
        material: String,
        /// FE element tag.
        element: u32,
    },
    /// The passive foundation block under the base node `node`.
    Foundation {
        /// Base node tag.
        node: u32,
    },
    /// The passive foundation strip under the base wall element `element`, named
    /// `Foundation:wall:<element>`.
    WallFoundation {
        /// FE element tag of the wall element standing on the strip.
        element: u32,
    },
}

impl BodyId {
    /// The box of FE element `element` of type `body_type` in material group `material`.
    pub fn element(body_type: BodyType, material: impl Into<String>, element: u32) -> Self {
        BodyId::Element {
            body_type,
            material: material.into(),
            element,
        }
    }

    /// The name, `Type:material:element` or `Foundation:base:<node>`.
    pub fn name(&self) -> String {
        self.to_string()
    }

    /// The rigid-body group: the material of an element box, `foundation` for a block.
    pub fn group(&self) -> &str {
        match self {
            BodyId::Element { material, .. } => material,
            BodyId::Foundation { .. } | BodyId::WallFoundation { .. } => FOUNDATION_GROUP,
        }
    }

    /// The member type.
    pub fn body_type(&self) -> &BodyType {
        match self {
            BodyId::Element { body_type, .. } => body_type,
            BodyId::Foundation { .. } | BodyId::WallFoundation { .. } => &BodyType::Foundation,
        }
    }

    /// The type name, as [`BodyType::as_str`].
    pub fn type_name(&self) -> &str {
        self.body_type().as_str()
    }

    /// The material field (`-` for a foundation block).
    pub fn material(&self) -> &str {
        match self {
            BodyId::Element { material, .. } => material,
            BodyId::Foundation { .. } | BodyId::WallFoundation { .. } => NO_FIELD,
        }
    }

    /// The FE element tag (`None` for a foundation block).
    pub fn element_tag(&self) -> Option<u32> {
        match self {
            BodyId::Element { element, .. } => Some(*element),
            BodyId::Foundation { .. } | BodyId::WallFoundation { .. } => None,
        }
    }

    /// The element field as files hold it: the tag, or `-` for a foundation block.
    pub fn element_field(&self) -> String {
        match self {
            BodyId::Element { element, .. } => element.to_string(),
            BodyId::Foundation { .. } | BodyId::WallFoundation { .. } => NO_FIELD.to_string(),
        }
    }

    /// The identity from the five identity columns of `bodies.csv` / `ruins.csv`
    /// (`name,group,type,material,element`); an error says which column disagrees.
    pub fn from_columns(
        name: &str,
        group: &str,
        type_name: &str,
        material: &str,
        element: &str,
    ) -> Result<BodyId, BodyIdError> {
        let id = if element == NO_FIELD {
            let tag = |prefix: &str| {
                name.strip_prefix(prefix)
                    .and_then(|n| n.parse::<u32>().ok())
            };
            if let Some(node) = tag("Foundation:base:") {
                BodyId::Foundation { node }
            } else if let Some(element) = tag("Foundation:wall:") {
                BodyId::WallFoundation { element }
            } else {
                return Err(BodyIdError {
                    column: "name",
                    message: format!(
                        "{name:?} is not Foundation:base:<node> or Foundation:wall:<element> \
                         although element is -"
                    ),
                });
            }
        } else {
            let element: u32 = element.parse().map_err(|_| BodyIdError {
                column: "element",
                message: format!("{element:?} is not an element tag or -"),
            })?;
            if type_name.is_empty() || type_name.contains(':') {
                return Err(BodyIdError {
                    column: "type",
                    message: format!("{type_name:?} must be non-empty and contain no ':'"),
                });
            }
            BodyId::element(type_name.into(), material, element)
        };
        for (column, have, want) in [
            ("name", name.to_string(), id.name()),
            ("group", group.to_string(), id.group().to_string()),
            ("type", type_name.to_string(), id.body_type().to_string()),
            ("material", material.to_string(), id.material().to_string()),
        ] {
            if have != want {
                return Err(BodyIdError {
                    column,
                    message: format!("{have:?} where the body's identity gives {want:?}"),
                });
            }
        }
        Ok(id)
    }
}

impl fmt::Display for BodyId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BodyId::Element {
                body_type,
                material,
                element,
            } => write!(f, "{body_type}:{material}:{element}"),
            BodyId::Foundation { node } => write!(f, "Foundation:base:{node}"),
            BodyId::WallFoundation { element } => write!(f, "Foundation:wall:{element}"),
        }
    }
}

/// A body name or identity columns that do not make a [`BodyId`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("column {column}: {message}")]
pub struct BodyIdError {
    /// The column (or `name`) at fault.
    pub column: &'static str,
    /// What is wrong.
    pub message: String,
}

impl FromStr for BodyId {
    type Err = BodyIdError;

    /// Reads `Type:material:element` (element a tag) or `Foundation:base:<node>`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = |m: &str| BodyIdError {
            column: "name",
            message: format!("{s:?} {m}"),
        };
        let mut parts = s.split(':');
        let (Some(t), Some(m), Some(e), None) =
            (parts.next(), parts.next(), parts.next(), parts.next())
        else {
            return Err(bad("is not Type:material:element"));
        };
        let tag: u32 = e
            .parse()
            .map_err(|_| bad("does not end in a numeric element tag"))?;
        if t.is_empty() || m.is_empty() {
            return Err(bad("has an empty type or material"));
        }
        if t == "Foundation" && m == "base" {
            return Ok(BodyId::Foundation { node: tag });
        }
        if t == "Foundation" && m == "wall" {
            return Ok(BodyId::WallFoundation { element: tag });
        }
        Ok(BodyId::element(t.into(), m, tag))
    }
}

/// What a body is, for the mapping's overlap rule (`mapping::overlap`): decided from
/// geometry.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Role {
    /// Line element within 45° of vertical.
    Column,
    /// Quad whose normal is within 45° of horizontal.
    Wall,
    /// Other line element.
    Beam,
    /// Quad whose normal is within 45° of vertical.
    Slab,
}

/// One rigid body of the run (the mapping's boxes, then the foundation blocks).
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Identity, named e.g. `Column:1:4`, `Foundation:base:1`.
    pub id: BodyId,
    /// Geometric role (`None` for foundations).
    pub kind: Option<Role>,
    /// Half extents, m.
    pub half_extents: [f64; 3],
    /// Undeformed pose.
    pub pose0: crate::bullet::Pose,
    /// Mass, kg (0 for passive).
    pub mass_kg: f64,
    /// Passive (kinematic foundation).
    pub passive: bool,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_columns() {
        let c = BodyId::element(BodyType::Column, "1", 4);
        assert_eq!(c.to_string(), "Column:1:4");
        assert_eq!(c.group(), "1");
        assert_eq!(c.element_field(), "4");
        assert_eq!("Column:1:4".parse::<BodyId>().unwrap(), c);
        let f = BodyId::Foundation { node: 17 };
        assert_eq!(f.to_string(), "Foundation:base:17");
        assert_eq!(
            (f.group(), f.material(), f.element_field().as_str()),
            ("foundation", "-", "-")
        );
        assert_eq!("Foundation:base:17".parse::<BodyId>().unwrap(), f);
        let o = BodyId::element("Brace".into(), "steel", 9);
        assert_eq!(o.body_type(), &BodyType::Other("Brace".into()));
        assert_eq!("Brace:steel:9".parse::<BodyId>().unwrap(), o);
        assert!("Beam:1".parse::<BodyId>().is_err());
        assert!("Beam:1:x".parse::<BodyId>().is_err());
        assert_eq!(
            BodyId::from_columns("Column:1:4", "1", "Column", "1", "4").unwrap(),
            c
        );
        assert_eq!(
            BodyId::from_columns("Foundation:base:17", "foundation", "Foundation", "-", "-")
                .unwrap(),
            f
        );
        let e = BodyId::from_columns("Column:1:4", "2", "Column", "1", "4").unwrap_err();
        assert_eq!(e.column, "group");
        let e = BodyId::from_columns("Column:1:4", "1", "Column", "1", "x").unwrap_err();
        assert_eq!(e.column, "element");
    }
}
