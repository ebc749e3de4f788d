//! Cross-sections: fiber sections (explicit fiber list or a rectangular RC description
//! that expands to fibers), elastic sections, elastic plate sections for shells and
//! layered shell sections (concrete and smeared-rebar layers, OpenSees `LayeredShell`).
//!
//! Section axes follow OpenSees: fiber coordinates (y, z) are in the element's local
//! y and z axes (m); areas in m².
use super::material::Material;
use super::InvalidValue;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// One fiber: local y (m), local z (m), area (m²), material tag.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Fiber(pub f64, pub f64, pub f64, pub u32);

impl Fiber {
    /// Local y coordinate (m).
    pub fn y(&self) -> f64 {
        self.0
    }
    /// Local z coordinate (m).
    pub fn z(&self) -> f64 {
        self.1
    }
    /// Area (m²).
    pub fn area(&self) -> f64 {
        self.2
    }
    /// Material tag.
    pub fn material(&self) -> u32 {
        self.3
    }
}

/// A longitudinal bar of an RC section: local y (m), local z (m), area (m²).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Bar(pub f64, pub f64, pub f64);

/// A section: tag, optional name, and its kind.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Section {
    /// Unique section tag.
    pub tag: u32,
    /// Optional human name.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub name: String,
    /// The kind and its data (`type` key).
    #[serde(flatten)]
    pub kind: SectionKind,
}

/// Section kinds (`type = "fiber" | "rc_rect" | "elastic" | "plate" | "layered_shell"`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", deny_unknown_fields, rename_all = "snake_case")]
pub enum SectionKind {
    /// Explicit fiber list plus elastic torsion GJ (OpenSees `section Fiber tag -GJ GJ`).
    Fiber {
        /// Torsional stiffness G·J (N·m²).
        #[serde(rename = "GJ")]
        gj: f64,
        /// `[y, z, area, material]` per fiber.
        fibers: Vec<Fiber>,
        /// Outline width along local y (m), for the rigid-body box; optional.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        width: Option<f64>,
        /// Outline depth along local z (m), for the rigid-body box; optional.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        depth: Option<f64>,
    },
    /// Rectangular reinforced-concrete section; expands to fibers by [`RcRect::fibers`].
    RcRect(RcRect),
    /// Elastic section: E (Pa), G (Pa), A (m²), Iy, Iz (m⁴, about local y / z), J (m⁴).
    Elastic {
        /// Young's modulus (Pa).
        #[serde(rename = "E")]
        e: f64,
        /// Shear modulus (Pa).
        #[serde(rename = "G")]
        g: f64,
        /// Area (m²).
        #[serde(rename = "A")]
        a: f64,
        /// Second moment about local y (m⁴).
        #[serde(rename = "Iy")]
        iy: f64,
        /// Second moment about local z (m⁴).
        #[serde(rename = "Iz")]
        iz: f64,
        /// Torsion constant (m⁴).
        #[serde(rename = "J")]
        j: f64,
        /// Self-weight mass per unit length (kg/m); default 0.
        #[serde(default)]
        mass_per_length: f64,
        /// Outline width along local y (m); optional.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        width: Option<f64>,
        /// Outline depth along local z (m); optional.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        depth: Option<f64>,
    },
    /// Elastic isotropic plate for shells (OpenSees `ElasticMembranePlateSection E nu h rho`).
    Plate {
        /// Young's modulus (Pa).
        #[serde(rename = "E")]
        e: f64,
        /// Poisson's ratio.
        nu: f64,
        /// Thickness h (m).
        h: f64,
        /// Density (kg/m³) for self-weight ρ·h per unit area; default 0.
        #[serde(default)]
        density: f64,
    },
    /// Layered shell section (OpenSees `section LayeredShell`, Huang & Lu): layers listed
    /// from the bottom face (local z = −h/2) to the top, each integrated at its
    /// mid-thickness with weight = its thickness; h = Σ thicknesses. At least 3 layers.
    LayeredShell {
        /// The layers, bottom to top.
        layers: Vec<ShellLayer>,
        /// Density (kg/m³) over the whole thickness for self-weight ρ·h per unit area;
        /// default 0.
        #[serde(default)]
        density: f64,
    },
}

/// One layer of a [`SectionKind::LayeredShell`] (`type = "elastic" | "concrete" | "rebar"`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", deny_unknown_fields, rename_all = "snake_case")]
pub enum ShellLayer {
    /// Linear elastic isotropic plate layer (OpenSees `nDMaterial ElasticIsotropic E nu`
    /// wrapped in `PlateFiber`): plane stress plus transverse shear G = E/(2(1+ν)).
    Elastic {
        /// Thickness (m).
        thickness: f64,
        /// Young's modulus (Pa).
        #[serde(rename = "E")]
        e: f64,
        /// Poisson's ratio.
        nu: f64,
    },
    /// Plane-stress concrete with cracking and crushing (OpenSees
    /// `nDMaterial PlasticDamageConcretePlaneStress E nu ft fc` with its default
    /// β, Ap, An, Bn, wrapped in `PlateFromPlaneStress` with elastic transverse shear
    /// G = E/(2(1+ν))).
    Concrete {
        /// Thickness (m).
        thickness: f64,
        /// Young's modulus (Pa).
        #[serde(rename = "E")]
        e: f64,
        /// Poisson's ratio.
        nu: f64,
        /// Compressive strength (Pa, positive).
        fc: f64,
        /// Tensile strength (Pa, positive).
        ft: f64,
    },
    /// Smeared bars (OpenSees `nDMaterial PlateRebar matTag angle`): a uniaxial material
    /// along the direction at `angle` degrees from the element's local x axis, in the
    /// plane: ε = εxx c² + εyy s² + γxy c s. Thickness = bar area per unit width
    /// (As / spacing, m).
    Rebar {
        /// Smeared thickness As/s (m).
        thickness: f64,
        /// Uniaxial material tag (e.g. Steel02).
        material: u32,
        /// Bar direction from the local x axis (degrees): 0 along x, 90 along y.
        angle: f64,
    },
}

impl ShellLayer {
    /// The layer's thickness (m).
    pub fn thickness(&self) -> f64 {
        match self {
            ShellLayer::Elastic { thickness, .. }
            | ShellLayer::Concrete { thickness, .. }
            | ShellLayer::Rebar { thickness, .. } => *thickness,
        }
    }

    /// Checks ranges; returns a message for the first violation.
    fn check(&self) -> Result<(), InvalidValue> {
        let t = self.thickness();
        if !(t.is_finite() && t > 0.0) {
            return Err(InvalidValue(format!("thickness = {t} must be positive")));
        }
        let elastic = |e: f64, nu: f64| -> Result<(), InvalidValue> {
            if !(e.is_finite() && e > 0.0) {
                return Err(InvalidValue(format!("E = {e} must be positive")));
            }
            if !(nu.is_finite() && (0.0..0.5).contains(&nu)) {
                return Err(InvalidValue(format!("nu = {nu} must be in [0, 0.5)")));
            }
            Ok(())
        };
        match self {
            ShellLayer::Elastic { e, nu, .. } => elastic(*e, *nu),
            ShellLayer::Concrete { e, nu, fc, ft, .. } => {
                elastic(*e, *nu)?;
                if !(fc.is_finite() && *fc > 0.0) {
                    return Err(InvalidValue(format!(
                        "fc = {fc} must be positive (compression positive here)"
                    )));
                }
                if !(ft.is_finite() && *ft > 0.0 && ft < fc) {
                    return Err(InvalidValue(format!(
                        "ft = {ft} must be positive and below fc = {fc}"
                    )));
                }
                Ok(())
            }
            ShellLayer::Rebar { angle, .. } => {
                if angle.is_finite() {
                    Ok(())
                } else {
                    Err(InvalidValue(format!("angle = {angle} is not finite")))
                }
            }
        }
    }
}

/// A rectangular RC section of width `b` (along local y) and depth `h` (along local z).
///
/// Fiber layout (the same as `rect_fibers` of the reference `gen_frame3.py`):
/// the core is the rectangle `cover` (m) inside every face, divided into
/// `core_fibers = [ny, nz]` equal fibers (loop y outer, z inner); the bottom and top cover
/// strips span the full width, divided into `ny + 2` fibers across and `cover_layers`
/// through their thickness; the left and right strips span the core height with
/// `cover_layers` × `nz` fibers. Bars are added as point fibers (their area is not
/// subtracted from the concrete, as in OpenSees fiber sections).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RcRect {
    /// Width along local y (m).
    pub b: f64,
    /// Depth along local z (m).
    pub h: f64,
    /// Distance from each face to the core boundary (stirrup centre line) (m).
    pub cover: f64,
    /// Core material tag (confined concrete).
    pub core_material: u32,
    /// Cover material tag (unconfined concrete).
    pub cover_material: u32,
    /// Core subdivision `[ny, nz]`.
    pub core_fibers: [u32; 2],
    /// Fibers through the cover thickness; default 1.
    #[serde(default = "one")]
    pub cover_layers: u32,
    /// Bar material tag.
    pub bar_material: u32,
    /// Bars `[y, z, area]`.
    pub bars: Vec<Bar>,
    /// Torsional stiffness G·J (N·m²).
    #[serde(rename = "GJ")]
    pub gj: f64,
}

fn one() -> u32 {
    1
}

impl RcRect {
    /// Expands to the explicit fiber list `[y, z, area, material]`.
    pub fn fibers(&self) -> Vec<Fiber> {
        let mut out = Vec::new();
        let (y0, y1) = (-self.b / 2.0, self.b / 2.0);
        let (z0, z1) = (-self.h / 2.0, self.h / 2.0);
        let (cy0, cy1) = (y0 + self.cover, y1 - self.cover);
        let (cz0, cz1) = (z0 + self.cover, z1 - self.cover);
        let [ny, nz] = self.core_fibers;
        let nt = self.cover_layers;
        let mut patch = |ya: f64, yb: f64, za: f64, zb: f64, ny: u32, nz: u32, mat: u32| {
            let dy = (yb - ya) / ny as f64;
            let dz = (zb - za) / nz as f64;
            for a in 0..ny {
                for c in 0..nz {
                    out.push(Fiber(
                        ya + (a as f64 + 0.5) * dy,
                        za + (c as f64 + 0.5) * dz,
                        dy * dz,
                        mat,
                    ));
                }
            }
        };
        patch(cy0, cy1, cz0, cz1, ny, nz, self.core_material);
        patch(y0, y1, z0, cz0, ny + 2, nt, self.cover_material);
        patch(y0, y1, cz1, z1, ny + 2, nt, self.cover_material);
        patch(y0, cy0, cz0, cz1, nt, nz, self.cover_material);
        patch(cy1, y1, cz0, cz1, nt, nz, self.cover_material);
        for bar in &self.bars {
            out.push(Fiber(bar.0, bar.1, bar.2, self.bar_material));
        }
        out
    }
}

/// Initial (transformed) elastic stiffnesses of a section about its origin:
/// EA = Σ E_i A_i, EIz = Σ E_i A_i y_i², EIy = Σ E_i A_i z_i² (N, N·m²), GJ (N·m²).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ElasticEquivalent {
    /// Axial stiffness (N).
    #[serde(rename = "EA")]
    pub ea: f64,
    /// Bending stiffness about local z (N·m²).
    #[serde(rename = "EIz")]
    pub eiz: f64,
    /// Bending stiffness about local y (N·m²).
    #[serde(rename = "EIy")]
    pub eiy: f64,
    /// Torsional stiffness (N·m²).
    #[serde(rename = "GJ")]
    pub gj: f64,
}

impl Section {
    /// The fibers of a fiber or RC section (expanded); `None` for elastic/plate sections.
    pub fn fibers(&self) -> Option<Vec<Fiber>> {
        match &self.kind {
            SectionKind::Fiber { fibers, .. } => Some(fibers.clone()),
            SectionKind::RcRect(rc) => Some(rc.fibers()),
            _ => None,
        }
    }

    /// The number of fibres of a fiber or RC section without expanding it (so a huge
    /// `core_fibers` is counted, not allocated); 0 for elastic/plate sections. RC: core
    /// ny·nz, cover strips 2·(ny + 2)·layers + 2·layers·nz, plus the bars ([`RcRect`]).
    pub fn fiber_count(&self) -> u64 {
        match &self.kind {
            SectionKind::Fiber { fibers, .. } => fibers.len() as u64,
            SectionKind::RcRect(rc) => {
                let [ny, nz] = rc.core_fibers.map(u64::from);
                let nt = u64::from(rc.cover_layers);
                ny * nz + 2 * (ny + 2) * nt + 2 * nt * nz + rc.bars.len() as u64
            }
            _ => 0,
        }
    }

    /// Torsional stiffness GJ (N·m²) of a beam section; `None` for plates.
    pub fn gj(&self) -> Option<f64> {
        match &self.kind {
            SectionKind::Fiber { gj, .. } => Some(*gj),
            SectionKind::RcRect(rc) => Some(rc.gj),
            SectionKind::Elastic { g, j, .. } => Some(g * j),
            SectionKind::Plate { .. } | SectionKind::LayeredShell { .. } => None,
        }
    }

    /// Whether this section can serve a line (beam-column) element.
    pub fn is_beam_section(&self) -> bool {
        !self.is_shell_section()
    }

    /// Whether this section serves shell elements (`plate` or `layered_shell`).
    pub fn is_shell_section(&self) -> bool {
        matches!(
            self.kind,
            SectionKind::Plate { .. } | SectionKind::LayeredShell { .. }
        )
    }

    /// Thickness h (m) of a shell section (Σ layer thicknesses for a layered one);
    /// `None` for beam sections.
    pub fn shell_thickness(&self) -> Option<f64> {
        match &self.kind {
            SectionKind::Plate { h, .. } => Some(*h),
            SectionKind::LayeredShell { layers, .. } => {
                Some(layers.iter().map(ShellLayer::thickness).sum())
            }
            _ => None,
        }
    }

    /// Self-weight mass per unit area (kg/m²) of a shell section, ρ·h; `None` for beam
    /// sections.
    pub fn mass_per_area(&self) -> Option<f64> {
        match &self.kind {
            SectionKind::Plate { h, density, .. } => Some(density * h),
            SectionKind::LayeredShell { density, .. } => {
                Some(density * self.shell_thickness().unwrap_or(0.0))
            }
            _ => None,
        }
    }

    /// Outline `(width along local y, depth along local z)` in m, if known: b × h of an
    /// RC section, the given width/depth of fiber and elastic sections.
    pub fn outline(&self) -> Option<(f64, f64)> {
        match &self.kind {
            SectionKind::RcRect(rc) => Some((rc.b, rc.h)),
            SectionKind::Fiber { width, depth, .. } | SectionKind::Elastic { width, depth, .. } => {
                Some(((*width)?, (*depth)?))
            }
            SectionKind::Plate { .. } | SectionKind::LayeredShell { .. } => None,
        }
    }

    /// Self-weight mass per unit length (kg/m) of a beam section: Σ ρ_i A_i over fibers
    /// (ρ from each fiber's material), or `mass_per_length` of an elastic section.
    pub fn mass_per_length(&self, materials: &BTreeMap<u32, &Material>) -> f64 {
        match &self.kind {
            SectionKind::Elastic {
                mass_per_length, ..
            } => *mass_per_length,
            SectionKind::Plate { .. } | SectionKind::LayeredShell { .. } => 0.0,
            _ => self
                .fibers()
                .unwrap_or_default()
                .iter()
                .map(|f| f.area() * materials.get(&f.material()).map_or(0.0, |m| m.density))
                .sum(),
        }
    }

    /// Initial elastic stiffnesses; fibers use each material's initial tangent.
    pub fn elastic_equivalent(&self, materials: &BTreeMap<u32, &Material>) -> ElasticEquivalent {
        match &self.kind {
            SectionKind::Elastic {
                e, g, a, iy, iz, j, ..
            } => ElasticEquivalent {
                ea: e * a,
                eiz: e * iz,
                eiy: e * iy,
                gj: g * j,
            },
            SectionKind::Plate { .. } | SectionKind::LayeredShell { .. } => ElasticEquivalent {
                ea: 0.0,
                eiz: 0.0,
                eiy: 0.0,
                gj: 0.0,
            },
            _ => {
                let fibers = self.fibers().unwrap_or_default();
                let e = |f: &Fiber| {
                    materials
                        .get(&f.material())
                        .map_or(0.0, |m| m.initial_tangent())
                };
                ElasticEquivalent {
                    ea: fibers.iter().map(|f| e(f) * f.area()).sum(),
                    eiz: fibers.iter().map(|f| e(f) * f.area() * f.y() * f.y()).sum(),
                    eiy: fibers.iter().map(|f| e(f) * f.area() * f.z() * f.z()).sum(),
                    gj: self.gj().unwrap_or(0.0),
                }
            }
        }
    }

    /// Material tags this section refers to.
    pub fn material_refs(&self) -> Vec<u32> {
        match &self.kind {
            SectionKind::Fiber { fibers, .. } => fibers.iter().map(|f| f.material()).collect(),
            SectionKind::RcRect(rc) => vec![rc.core_material, rc.cover_material, rc.bar_material],
            SectionKind::LayeredShell { layers, .. } => layers
                .iter()
                .filter_map(|l| match l {
                    ShellLayer::Rebar { material, .. } => Some(*material),
                    _ => None,
                })
                .collect(),
            _ => Vec::new(),
        }
    }

    /// Checks sizes and finiteness; returns a message for the first violation.
    pub fn check(&self) -> Result<(), InvalidValue> {
        let pos = |name: &str, v: f64| -> Result<(), InvalidValue> {
            if !v.is_finite() {
                Err(InvalidValue(format!("{name} is not finite ({v})")))
            } else if v > 0.0 {
                Ok(())
            } else {
                Err(InvalidValue(format!("{name} = {v} must be positive")))
            }
        };
        let opt = |name: &str, v: &Option<f64>| -> Result<(), InvalidValue> {
            match v {
                Some(v) => pos(name, *v),
                None => Ok(()),
            }
        };
        match &self.kind {
            SectionKind::Fiber {
                gj,
                fibers,
                width,
                depth,
            } => {
                pos("GJ", *gj)?;
                opt("width", width)?;
                opt("depth", depth)?;
                if fibers.is_empty() {
                    return Err(InvalidValue("has no fibers".into()));
                }
                for (k, f) in fibers.iter().enumerate() {
                    if !f.y().is_finite() || !f.z().is_finite() {
                        return Err(InvalidValue(format!(
                            "fiber {} has a non-finite coordinate",
                            k + 1
                        )));
                    }
                    pos(&format!("fiber {} area", k + 1), f.area())?;
                }
            }
            SectionKind::RcRect(rc) => {
                pos("b", rc.b)?;
                pos("h", rc.h)?;
                pos("cover", rc.cover)?;
                pos("GJ", rc.gj)?;
                if 2.0 * rc.cover >= rc.b.min(rc.h) {
                    return Err(InvalidValue(format!(
                        "cover {} m leaves no core in a {} x {} m section",
                        rc.cover, rc.b, rc.h
                    )));
                }
                if rc.core_fibers[0] == 0 || rc.core_fibers[1] == 0 || rc.cover_layers == 0 {
                    return Err(InvalidValue(
                        "fiber subdivision counts must be at least 1".into(),
                    ));
                }
                for (k, bar) in rc.bars.iter().enumerate() {
                    if !bar.0.is_finite() || !bar.1.is_finite() {
                        return Err(InvalidValue(format!(
                            "bar {} has a non-finite coordinate",
                            k + 1
                        )));
                    }
                    pos(&format!("bar {} area", k + 1), bar.2)?;
                    if bar.0.abs() > rc.b / 2.0 || bar.1.abs() > rc.h / 2.0 {
                        return Err(InvalidValue(format!(
                            "bar {} at ({}, {}) lies outside the {} x {} m section",
                            k + 1,
                            bar.0,
                            bar.1,
                            rc.b,
                            rc.h
                        )));
                    }
                }
            }
            SectionKind::Elastic {
                e,
                g,
                a,
                iy,
                iz,
                j,
                mass_per_length,
                width,
                depth,
            } => {
                pos("E", *e)?;
                pos("G", *g)?;
                pos("A", *a)?;
                pos("Iy", *iy)?;
                pos("Iz", *iz)?;
                pos("J", *j)?;
                opt("width", width)?;
                opt("depth", depth)?;
                if !mass_per_length.is_finite() || *mass_per_length < 0.0 {
                    return Err(InvalidValue(format!(
                        "mass_per_length = {mass_per_length} must be finite and >= 0"
                    )));
                }
            }
            SectionKind::Plate { e, nu, h, density } => {
                pos("E", *e)?;
                pos("h", *h)?;
                if !nu.is_finite() || !(-1.0..0.5).contains(nu) {
                    return Err(InvalidValue(format!("nu = {nu} must be in (-1, 0.5)")));
                }
                if !density.is_finite() || *density < 0.0 {
                    return Err(InvalidValue(format!(
                        "density = {density} must be finite and >= 0"
                    )));
                }
            }
            SectionKind::LayeredShell { layers, density } => {
                if layers.len() < 3 {
                    return Err(InvalidValue(format!(
                        "has {} layers; a layered shell needs at least 3 (OpenSees LayeredShell)",
                        layers.len()
                    )));
                }
                for (k, l) in layers.iter().enumerate() {
                    l.check()
                        .map_err(|e| InvalidValue(format!("layer {}: {e}", k + 1)))?;
                }
                if !density.is_finite() || *density < 0.0 {
                    return Err(InvalidValue(format!(
                        "density = {density} must be finite and >= 0"
                    )));
                }
            }
        }
        Ok(())
    }
}

/// The elastic sections of an imported model: OpenSees gives an `elasticBeamColumn` its
/// properties on the element line, fem2rbd keeps them in a section, so each distinct set
/// becomes one section, tagged from `first_tag` on in order of first use and named
/// `elastic_1`, `elastic_2`, ….
///
/// A property set is `[E (Pa), G (Pa), A (m²), Iy (m⁴), Iz (m⁴), J (m⁴), mass per length (kg/m)]`.
#[derive(Debug)]
pub(crate) struct ImportedElasticSections {
    first_tag: u32,
    sets: Vec<[f64; 7]>,
}

impl ImportedElasticSections {
    /// No sets yet; the first one gets `first_tag`.
    pub(crate) fn new(first_tag: u32) -> Self {
        Self {
            first_tag,
            sets: Vec::new(),
        }
    }

    /// The tag of the section holding `set`, added if it is new (equal bit for bit).
    pub(crate) fn tag_of(&mut self, set: [f64; 7]) -> u32 {
        let k = match self.sets.iter().position(|q| *q == set) {
            Some(k) => k,
            None => {
                self.sets.push(set);
                self.sets.len() - 1
            }
        };
        self.first_tag + k as u32
    }

    /// The sections, in tag order.
    pub(crate) fn into_sections(self) -> impl Iterator<Item = Section> {
        let first_tag = self.first_tag;
        self.sets
            .into_iter()
            .enumerate()
            .map(move |(k, p)| Section {
                tag: first_tag + k as u32,
                name: format!("elastic_{}", k + 1),
                kind: SectionKind::Elastic {
                    e: p[0],
                    g: p[1],
                    a: p[2],
                    iy: p[3],
                    iz: p[4],
                    j: p[5],
                    mass_per_length: p[6],
                    width: None,
                    depth: None,
                },
            })
    }
}
