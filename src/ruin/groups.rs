//! Group strengths of a model's rigid bodies (BCB element groups) from the model's own
//! sections and materials, through BCB's Formula Assistant (`con_rei_beam`,
//! [`FormulaInputs`]).
//!
//! **Rule.** A rigid body's group is its element's `group` (see
//! [`crate::mapping::geometry`]). For each group the reference section is the `rc_rect`
//! section of the group's first column (`type_name = "Column"`) beam-column element, or,
//! if the group has no column, of its first beam-column element with an `rc_rect`
//! section. From it:
//!
//! * h, w (mm) = the section's `h` and `b` × 1000;
//! * c (mm) = the section's `cover` × 1000 (face to the stirrup centre line);
//! * n = the number of bars; dl (mm) = √(4·A/π) of the mean bar area A;
//! * fc (N/mm²) = |fpc| of the cover (unconfined) concrete / 10⁶ (Concrete01/02);
//! * fs (N/mm²) = Fy of the bar material / 10⁶ (Steel01/02);
//! * all other inputs (fsu, elu, stirrups s, ds, densities, k) keep BCB's defaults.
//!
//! **Wall groups.** A group without such a beam-column whose first `shell` element has a
//! `layered_shell` section (generated walls: group `W<story>`) takes BCB's wall & slab
//! assistant (`con_rei_wall`, [`FormulaKind::WallSlab`], docs/bcb.md §3.2) on a 1 m strip
//! of the wall ([`wall_inputs`]):
//!
//! * h (mm) = the section's thickness t × 1000, w = 1000 mm;
//! * c (mm) = the outer concrete layer's thickness × 1000 (face to the first bar layer);
//! * fc (N/mm²) = f′c of the first `concrete` layer / 10⁶; fs = F_y of the first rebar
//!   layer's material / 10⁶;
//! * the bars: the vertical layers (angle 90°, the bars crossing a horizontal joint)
//!   give A_s = Σ t_rebar × 1000 mm² per mm of strip; BCB's formulas take the bars only
//!   through ρ = n·π·dl²/4/(h·w) (the wall formulas' d = h/2 has no dl) and through
//!   e1 = (h − 2c − dl)/h, so dl keeps BCB's default 10 mm and n = A_s·w/(π·dl²/4)
//!   (a fractional count);
//! * all other inputs keep BCB's defaults (k = 1.9).
//!
//! For FE-derived connections (`connections = "fe"`, docs/handoff.md) the wall groups
//! get per-area strengths from the layered section by ACI 318-19 instead
//! ([`wall_per_area_aci`]); beam-column groups keep the Formula Assistant (their
//! connections take the members' fibre capacities where the members are cut).
//!
//! Passive foundation blocks get the group [`FOUNDATION_GROUP`], whose strength is never
//! used for thresholds (an active–passive connection uses the active group's strength
//! × 2, docs/bcb.md §11) but must exist; it copies the first group's inputs.

use super::connection::GroupStrength;
use super::strength::{
    FormulaInputError, FormulaInputs, FormulaKind, StrengthPerArea, StrengthSource, FA_PI,
};
use crate::model::material::MaterialLaw;
use crate::model::section::{Section, SectionKind, ShellLayer};
use crate::model::{ElementKind, Model};
use std::collections::BTreeMap;

use crate::body::BodyType;
pub use crate::body::FOUNDATION_GROUP;

/// A group whose strengths cannot be derived from the model: the element, section,
/// group or material is named.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum GroupError {
    /// An element refers to a section the model does not have.
    #[error("element {element}: section {section} is not in the model")]
    UnknownSection {
        /// The element's tag.
        element: u32,
        /// The missing section.
        section: u32,
    },
    /// A section lacks what the strength rule needs (a layer, bars, a material of the
    /// right law).
    #[error("{item}: {message}")]
    Section {
        /// "group G (section S)" or "section S".
        item: String,
        /// What is missing.
        message: String,
    },
    /// A wall group's section is not a layered shell.
    #[error("section {0} is not a layered_shell section")]
    NotLayered(u32),
    /// The Formula Assistant inputs of a group are unusable.
    #[error("{item}: {error}")]
    Formula {
        /// The group (and section).
        item: String,
        /// What is wrong.
        error: FormulaInputError,
    },
    /// A wall group's section cannot be read.
    #[error("group {group} (element {element}): {error}")]
    Wall {
        /// The group.
        group: String,
        /// Its first layered-shell element.
        element: u32,
        /// What is wrong.
        error: Box<GroupError>,
    },
    /// The model has no group with a strength rule.
    #[error(
        "the model has no beam-column element with an rc_rect section and no layered-shell wall"
    )]
    NoGroups,
}

/// What the group functions return.
pub type Result<T> = std::result::Result<T, GroupError>;

/// The Formula Assistant inputs of one group (module docs). Errors name the group,
/// section or material that does not fit the rule.
pub fn group_inputs(model: &Model) -> Result<BTreeMap<String, FormulaInputs>> {
    let sections = model.section_map();
    let materials = model.material_map();
    // group → (is_column, section tag) of its reference element
    let mut chosen: BTreeMap<String, (bool, u32)> = BTreeMap::new();
    for e in &model.elements {
        let sec = match &e.kind {
            ElementKind::BeamColumn { section, .. } => *section,
            _ => continue,
        };
        let Some(s) = sections.get(&sec) else {
            return Err(GroupError::UnknownSection {
                element: e.tag,
                section: sec,
            });
        };
        if !matches!(s.kind, SectionKind::RcRect(_)) {
            continue;
        }
        let is_col = BodyType::from(e.type_name.as_str()) == BodyType::Column;
        let entry = chosen.entry(e.group.0.clone()).or_insert((is_col, sec));
        if is_col && !entry.0 {
            *entry = (true, sec);
        }
    }
    let mut out = BTreeMap::new();
    for (group, (_, sec)) in chosen {
        let SectionKind::RcRect(r) = &sections[&sec].kind else {
            unreachable!("only rc_rect sections are chosen")
        };
        let item = format!("group {group} (section {sec})");
        let fpc = match materials.get(&r.cover_material).map(|m| &m.law) {
            Some(MaterialLaw::Concrete01 { fpc, .. })
            | Some(MaterialLaw::Concrete02 { fpc, .. }) => fpc.abs(),
            _ => {
                return Err(GroupError::Section {
                    item,
                    message: format!(
                        "cover material {} is not a Concrete01/02 material",
                        r.cover_material
                    ),
                })
            }
        };
        let fy = match materials.get(&r.bar_material).map(|m| &m.law) {
            Some(MaterialLaw::Steel01 { fy, .. }) | Some(MaterialLaw::Steel02 { fy, .. }) => *fy,
            _ => {
                return Err(GroupError::Section {
                    item,
                    message: format!(
                        "bar material {} is not a Steel01/02 material",
                        r.bar_material
                    ),
                })
            }
        };
        if r.bars.is_empty() {
            return Err(GroupError::Section {
                item,
                message: "the section has no bars".into(),
            });
        }
        let mean_area = r.bars.iter().map(|b| b.2).sum::<f64>() / r.bars.len() as f64;
        let inputs = FormulaInputs {
            kind: FormulaKind::BeamColumn,
            h_mm: r.h * 1000.0,
            w_mm: r.b * 1000.0,
            fc: fpc / 1e6,
            fs: fy / 1e6,
            c: r.cover * 1000.0,
            n: r.bars.len() as f64,
            dl: (4.0 * mean_area / std::f64::consts::PI).sqrt() * 1000.0,
            ..FormulaInputs::default()
        };
        if let Err(error) = inputs.validate() {
            return Err(GroupError::Formula { item, error });
        }
        out.insert(group, inputs);
    }
    Ok(out)
}

/// The layered-shell data a wall group's strengths need (module docs), in SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallSection {
    /// Thickness t, m.
    pub t: f64,
    /// Outer concrete layer (face to the first bar layer), m.
    pub cover: f64,
    /// Concrete compressive strength f′c, Pa.
    pub fc: f64,
    /// Bar yield strength f_y, Pa.
    pub fy: f64,
    /// Vertical reinforcement ratio ρ_v = Σ t_rebar(90°)/t.
    pub rho_v: f64,
    /// Horizontal reinforcement ratio ρ_h = Σ t_rebar(0°)/t.
    pub rho_h: f64,
}

/// Reads a layered-shell section as a wall section; errors name what is missing.
pub fn wall_section(model: &Model, sec: &Section) -> Result<WallSection> {
    let missing = |message: &str| GroupError::Section {
        item: format!("section {}", sec.tag),
        message: message.into(),
    };
    let SectionKind::LayeredShell { layers, .. } = &sec.kind else {
        return Err(GroupError::NotLayered(sec.tag));
    };
    let t: f64 = layers.iter().map(ShellLayer::thickness).sum();
    let fc = layers
        .iter()
        .find_map(|l| match l {
            ShellLayer::Concrete { fc, .. } => Some(*fc),
            _ => None,
        })
        .ok_or_else(|| missing("no concrete layer (BCB's wall formula needs f'c)"))?;
    let cover = layers
        .first()
        .filter(|l| matches!(l, ShellLayer::Concrete { .. }))
        .map(ShellLayer::thickness)
        .ok_or_else(|| missing("the first layer is not concrete (no cover)"))?;
    let materials = model.material_map();
    let mut fy = None;
    let (mut tv, mut th) = (0.0, 0.0);
    for l in layers {
        if let ShellLayer::Rebar {
            thickness,
            material,
            angle,
        } = l
        {
            let f = match materials.get(material).map(|m| &m.law) {
                Some(MaterialLaw::Steel01 { fy, .. }) | Some(MaterialLaw::Steel02 { fy, .. }) => {
                    *fy
                }
                _ => {
                    return Err(missing(&format!(
                        "rebar material {material} is not a Steel01/02 material"
                    )))
                }
            };
            fy.get_or_insert(f);
            let a = angle.to_radians();
            tv += thickness * a.sin().powi(2);
            th += thickness * a.cos().powi(2);
        }
    }
    let fy = fy.ok_or_else(|| missing("no rebar layer"))?;
    Ok(WallSection {
        t,
        cover,
        fc,
        fy,
        rho_v: tv / t,
        rho_h: th / t,
    })
}

/// BCB's wall & slab Formula Assistant inputs of a wall section (module docs).
pub fn wall_inputs(w: &WallSection) -> FormulaInputs {
    let d = FormulaInputs::default();
    let (h, width) = (w.t * 1000.0, 1000.0);
    let a_s = w.rho_v * h * width;
    FormulaInputs {
        kind: FormulaKind::WallSlab,
        h_mm: h,
        w_mm: width,
        fc: w.fc / 1e6,
        fs: w.fy / 1e6,
        c: w.cover * 1000.0,
        n: a_s / (FA_PI * d.dl * d.dl / 4.0),
        ..d
    }
}

/// Per-mm² strengths of a wall cut (a joint through the wall) by ACI 318-19, for
/// FE-derived connections (N/mm², B in N·m/mm²; f′c, f_y in MPa, ρ = ρ_v the bars
/// crossing a horizontal joint, t in mm, per 1 mm of joint length):
///
/// * C = 0.85·f′c·(1 − ρ) + f_y·ρ — nominal axial strength P₀ = 0.85·f′c·(A_g − A_st)
///   + f_y·A_st per area (§22.4.2.2);
/// * T = f_y·ρ — P_nt = f_y·A_st (§22.4.3.1);
/// * S = S90 = min(μ·ρ_min·f_y, 0.2·f′c, 3.3 + 0.08·f′c, 11) — shear friction
///   V_n = μ·A_vf·f_y across the joint with μ = 1.4 (monolithic concrete, λ = 1;
///   §22.9.4.2, Table 22.9.4.2) and its upper limits (§22.9.4.4); A_vf the weaker of
///   the two bar directions (a joint is crossed by the vertical bars when horizontal, by
///   the horizontal bars when vertical), no axial-load term (N_u = 0, conservative);
/// * B = M_n/(t·1) — out-of-plane flexure of the joint with one face's bars in tension:
///   A_s1 = ρ·t/2 per mm, d = t − c, a = A_s1·f_y/(0.85·f′c) (§22.2.2.4.1, Whitney
///   block), M_n = A_s1·f_y·(d − a/2) (N·mm per mm), divided by t and by 1000 for N·m;
/// * P = f_su·ρ/4 — BCB's plastic value with its f_su = 650 N/mm² (docs/bcb.md §3.2).
pub fn wall_per_area_aci(w: &WallSection) -> StrengthPerArea {
    let (fc, fy, t, c) = (w.fc / 1e6, w.fy / 1e6, w.t * 1000.0, w.cover * 1000.0);
    let rho = w.rho_v;
    let shear = (1.4 * w.rho_v.min(w.rho_h) * fy)
        .min(0.2 * fc)
        .min(3.3 + 0.08 * fc)
        .min(11.0);
    let a_s1 = rho * t / 2.0;
    let a = a_s1 * fy / (0.85 * fc);
    let m_n = a_s1 * fy * ((t - c) - a / 2.0);
    StrengthPerArea {
        c: 0.85 * fc * (1.0 - rho) + fy * rho,
        t: fy * rho,
        s: shear,
        s90: None,
        b: m_n / t / 1000.0,
        b90: None,
        p: Some(FormulaInputs::default().fsu * rho / 4.0),
    }
}

/// The wall groups of `model` (module docs): group → its first layered-shell section,
/// for groups without a beam-column with an `rc_rect` section.
pub fn wall_groups(model: &Model) -> Result<BTreeMap<String, WallSection>> {
    let beam_groups = group_inputs(model)?;
    let sections = model.section_map();
    let mut out = BTreeMap::new();
    for e in &model.elements {
        let ElementKind::Shell { section, .. } = &e.kind else {
            continue;
        };
        if beam_groups.contains_key(&e.group.0) || out.contains_key(&e.group.0) {
            continue;
        }
        let Some(s) = sections.get(section) else {
            return Err(GroupError::UnknownSection {
                element: e.tag,
                section: *section,
            });
        };
        if !matches!(s.kind, SectionKind::LayeredShell { .. }) {
            continue;
        }
        let w = wall_section(model, s).map_err(|error| GroupError::Wall {
            group: e.group.0.clone(),
            element: e.tag,
            error: Box::new(error),
        })?;
        out.insert(e.group.0.clone(), w);
    }
    Ok(out)
}

/// The [`GroupStrength`] of every group of `model` plus [`FOUNDATION_GROUP`]:
/// beam-column groups by `con_rei_beam`, wall groups by `con_rei_wall` (module docs).
pub fn group_strengths(model: &Model) -> Result<Vec<GroupStrength>> {
    group_strengths_for(model, false)
}

/// As [`group_strengths`]; with `fe_walls` the wall groups take the ACI 318 per-area
/// strengths of their layered section ([`wall_per_area_aci`]) instead of BCB's wall
/// formula (FE-derived connections).
pub fn group_strengths_for(model: &Model, fe_walls: bool) -> Result<Vec<GroupStrength>> {
    let mut inputs = group_inputs(model)?;
    let mut per_area = BTreeMap::new();
    for (name, w) in wall_groups(model)? {
        let i = wall_inputs(&w);
        if let Err(error) = i.validate() {
            return Err(GroupError::Formula {
                item: format!("group {name}"),
                error,
            });
        }
        if fe_walls {
            per_area.insert(name, wall_per_area_aci(&w));
        } else {
            inputs.insert(name, i);
        }
    }
    let mut out: Vec<GroupStrength> = inputs
        .iter()
        .map(|(name, i)| GroupStrength::formula(name, *i))
        .collect();
    for (name, p) in per_area {
        out.push(GroupStrength {
            strength: StrengthSource::PerArea(p),
            ..GroupStrength::formula(&name, FormulaInputs::default())
        });
    }
    out.sort_by(|a, b| a.name.cmp(&b.name));
    let Some(first) = inputs.values().next().copied() else {
        return Err(GroupError::NoGroups);
    };
    out.push(GroupStrength::formula(FOUNDATION_GROUP, first));
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The generator's default wall: t = 0.2 m, cover 20 mm, ρ_v = ρ_h = 0.25 %,
    /// f′c = 26.8 MPa, f_y = 400 MPa (docs/bcb.md §8 worked numbers).
    fn wall() -> WallSection {
        WallSection {
            t: 0.2,
            cover: 0.02,
            fc: 26.8e6,
            fy: 400e6,
            rho_v: 0.0025,
            rho_h: 0.0025,
        }
    }

    #[test]
    fn wall_formula_inputs_and_strengths() {
        let i = wall_inputs(&wall());
        assert_eq!(i.kind, FormulaKind::WallSlab);
        assert!((i.rho(i.h_mm, i.w_mm) - 0.0025).abs() < 1e-15);
        assert!((i.n - 500.0 / (FA_PI * 25.0)).abs() < 1e-12);
        let p = i.per_area(0.0, 0.0);
        let close = |a: f64, b: f64| (a - b).abs() < 1e-9 * b.abs().max(1.0);
        assert!(close(p.c, 26.8 * 0.9975 + 400.0 * 0.0025), "{}", p.c);
        assert!(close(p.t, 1.0));
        assert!(close(p.s, 0.15 * 1.9 * 6.7f64.cbrt()), "{}", p.s);
        let b = (26.8 * 0.9975 + 4.5 * 400.0 * 0.0025 * 0.75) * 200.0 / 12.0 / 1000.0;
        assert!(close(p.b, b), "{} vs {b}", p.b);
        assert!(close(p.p.unwrap(), 650.0 * 0.0025 / 4.0));
        // docs/bcb.md §8 rounds these to 27.73 / 0.537 / 0.502 / 0.406.
        assert!((p.c - 27.73).abs() < 0.005 && (p.s - 0.537).abs() < 0.0005);
        assert!((p.b - 0.502).abs() < 0.0005);
    }

    /// ACI 318-19 values (docs/handoff.md §2.5): C = 0.85·26.8·0.9975 + 400·0.0025 =
    /// 23.72 N/mm², T = 1.0, S = min(1.4·0.0025·400 = 1.4, 0.2·26.8 = 5.36, 5.444, 11) =
    /// 1.4, a = 0.25·400/(0.85·26.8) = 4.390 mm, M_n = 0.25·400·(180 − 2.195) =
    /// 17 780.5 N·mm per mm, B = 17 780.5/200/1000 = 0.0889 N·m/mm².
    #[test]
    fn wall_aci_strengths() {
        let p = wall_per_area_aci(&wall());
        let close = |a: f64, b: f64| (a - b).abs() < 1e-9 * b.abs().max(1.0);
        assert!(close(p.c, 0.85 * 26.8 * 0.9975 + 1.0));
        assert!(close(p.t, 1.0));
        assert!(close(p.s, 1.4), "{}", p.s);
        let a = 0.25 * 400.0 / (0.85 * 26.8);
        assert!(close(
            p.b,
            0.25 * 400.0 * (180.0 - a / 2.0) / 200.0 / 1000.0
        ));
        assert!((p.b - 0.0889).abs() < 5e-5, "{}", p.b);
        // The shear-friction caps govern a heavily reinforced joint: 3 % → 0.2·f′c.
        let heavy = wall_per_area_aci(&WallSection {
            rho_v: 0.03,
            rho_h: 0.03,
            ..wall()
        });
        assert!(close(heavy.s, 0.2 * 26.8));
    }
}
