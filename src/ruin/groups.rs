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
//! Passive foundation blocks get the group [`FOUNDATION_GROUP`], whose strength is never
//! used for thresholds (an active–passive connection uses the active group's strength
//! × 2, docs/bcb.md §11) but must exist; it copies the first group's inputs.

use super::connection::GroupStrength;
use super::strength::{FormulaInputs, FormulaKind};
use crate::model::material::MaterialLaw;
use crate::model::section::SectionKind;
use crate::model::{ElementKind, Model};
use anyhow::{anyhow, bail, Result};
use std::collections::BTreeMap;

use crate::body::BodyType;
pub use crate::body::FOUNDATION_GROUP;

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
            bail!("element {}: section {sec} is not in the model", e.tag);
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
            _ => bail!(
                "{item}: cover material {} is not a Concrete01/02 material",
                r.cover_material
            ),
        };
        let fy = match materials.get(&r.bar_material).map(|m| &m.law) {
            Some(MaterialLaw::Steel01 { fy, .. }) | Some(MaterialLaw::Steel02 { fy, .. }) => *fy,
            _ => bail!(
                "{item}: bar material {} is not a Steel01/02 material",
                r.bar_material
            ),
        };
        if r.bars.is_empty() {
            bail!("{item}: the section has no bars");
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
        inputs.validate().map_err(|m| anyhow!("{item}: {m}"))?;
        out.insert(group, inputs);
    }
    Ok(out)
}

/// The [`GroupStrength`] of every group of `model` plus [`FOUNDATION_GROUP`].
pub fn group_strengths(model: &Model) -> Result<Vec<GroupStrength>> {
    let inputs = group_inputs(model)?;
    let first = *inputs
        .values()
        .next()
        .ok_or_else(|| anyhow!("the model has no beam-column element with an rc_rect section"))?;
    let mut out: Vec<GroupStrength> = inputs
        .iter()
        .map(|(name, i)| GroupStrength::formula(name, *i))
        .collect();
    out.push(GroupStrength::formula(FOUNDATION_GROUP, first));
    Ok(out)
}
