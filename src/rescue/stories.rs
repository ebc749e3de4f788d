//! Each story's volume loss: how much of the free space a story's ceiling sheltered in the
//! standing building it still shelters in the ruin.
//!
//! * The **stories** are numbered by their ceilings: the distinct undeformed levels of the
//!   slab panels' centres (to the millimetre), lowest first; story `n` lies under the
//!   slabs of level `n` (story 1 between the ground and the first floor).
//! * A story's **free volume** in a pose of the building is the volume of the covered free
//!   cells whose roof ([`super::voids::roofs`]: the body of the first solid cell above) is
//!   a slab panel of its ceiling: the space under that ceiling down to whatever lies
//!   below, wherever the ceiling's pieces came to rest, less the members standing in it.
//! * **Before** is the building undeformed (every box at its undeformed pose, on a grid of
//!   the same cell over it), **after** the ruin; the **loss** is `1 − after / before`
//!   (a pancaked story whose ceiling lies on its floor loses 1, a standing story 0).
//!   Space a ceiling piece shelters beyond the old footprint, once the piece slid away,
//!   still counts for the story: the loss is of volume, not of place.
use super::grid::grid_over;
use super::input::Ruin;
use super::occupancy::occupancy_rows;
use super::person::SOLID_FRACTION;
use super::voids::Field;
use super::Result;
use std::collections::BTreeMap;

/// One story's volume loss.
#[derive(Debug, Clone, PartialEq)]
pub struct StoryLoss {
    /// Story number (1 = lowest).
    pub story: usize,
    /// The undeformed level of its ceiling slabs' centres, m.
    pub ceiling_z_m: f64,
    /// Free volume under its ceiling in the standing building, m³.
    pub before_m3: f64,
    /// Free volume under its ceiling's pieces in the ruin, m³.
    pub after_m3: f64,
    /// `1 − after / before` (0 when `before` is 0).
    pub loss: f64,
}

/// The ceiling level key (mm) of every slab panel, by box index.
fn ceiling_levels(ruin: &Ruin) -> BTreeMap<usize, i64> {
    ruin.boxes
        .iter()
        .enumerate()
        .filter(|(_, b)| b.is_slab() && !b.passive)
        .map(|(i, b)| (i, (b.pose0.position[2] * 1000.0).round() as i64))
        .collect()
}

/// The number of free cells under each ceiling level (mm key) among `columns` columns of
/// `nz` cells, from each cell's solid flag and owner (index 0 the first column's lowest
/// cell).
fn sheltered_cells(
    columns: usize,
    nz: usize,
    solid: impl Fn(usize) -> bool,
    owner: &[u32],
    levels: &BTreeMap<usize, i64>,
    cells: &mut BTreeMap<i64, usize>,
) {
    for col in 0..columns {
        let mut roof: Option<i64> = None;
        for k in (0..nz).rev() {
            let idx = col * nz + k;
            if solid(idx) {
                roof = levels.get(&(owner[idx] as usize)).copied();
            } else if let Some(level) = roof {
                *cells.entry(level).or_default() += 1;
            }
        }
    }
}

/// Cell counts as volumes, m³.
fn volumes(cells: BTreeMap<i64, usize>, h: f64) -> BTreeMap<i64, f64> {
    let v = h.powi(3);
    cells.into_iter().map(|(l, n)| (l, n as f64 * v)).collect()
}

/// Rows of the standing building's grid gridded at a time (memory: their cells only).
const STANDING_ROWS: usize = 16;

/// The free volume under each ceiling level (mm key → m³) of the standing building: every
/// box of `ruin` at its undeformed pose, on a grid of cell `h` (m, at the model's scale)
/// over it (`cell_full_m` the cell as asked, for an error message). Its occupancy is made
/// [`STANDING_ROWS`] rows at a time, each cell as on the whole grid.
pub fn standing_shelter(ruin: &Ruin, h: f64, cell_full_m: f64) -> Result<BTreeMap<i64, f64>> {
    let levels = ceiling_levels(ruin);
    if levels.is_empty() {
        return Ok(BTreeMap::new());
    }
    let mut standing = ruin.clone();
    for b in &mut standing.boxes {
        b.pose = b.pose0;
    }
    let Some(g0) = grid_over(&standing, h, 0.0, cell_full_m)? else {
        return Ok(BTreeMap::new());
    };
    let mut cells = BTreeMap::new();
    let mut j = 0;
    while j < g0.n[1] {
        let rows = j..(j + STANDING_ROWS).min(g0.n[1]);
        let occ = occupancy_rows(&g0, &standing.boxes, rows.clone());
        sheltered_cells(
            rows.len() * g0.n[0],
            g0.n[2],
            |i| occ.fraction[i] as f64 >= SOLID_FRACTION,
            &occ.owner,
            &levels,
            &mut cells,
        );
        j = rows.end;
    }
    Ok(volumes(cells, g0.h))
}

/// The volume loss of every story of `ruin`, whose classified grid is `field`; the
/// standing building is gridded with the same cell (`cell_full_m` the cell as asked, for
/// an error message). Empty without slabs.
pub fn story_losses(ruin: &Ruin, field: &Field, cell_full_m: f64) -> Result<Vec<StoryLoss>> {
    let before = standing_shelter(ruin, field.grid.h, cell_full_m)?;
    Ok(story_losses_from(ruin, field, &before))
}

/// The volume loss of every story of `ruin`, whose classified grid is `field`, against
/// the standing building's free volumes `before` ([`standing_shelter`]). Empty without
/// slabs.
pub fn story_losses_from(
    ruin: &Ruin,
    field: &Field,
    before: &BTreeMap<i64, f64>,
) -> Vec<StoryLoss> {
    let levels = ceiling_levels(ruin);
    if levels.is_empty() {
        return Vec::new();
    }
    let mut cells = BTreeMap::new();
    sheltered_cells(
        field.grid.columns(),
        field.grid.n[2],
        |i| field.solid[i],
        &field.occupancy.owner,
        &levels,
        &mut cells,
    );
    let after = volumes(cells, field.grid.h);
    let mut keys: Vec<i64> = levels.values().copied().collect();
    keys.sort_unstable();
    keys.dedup();
    keys.into_iter()
        .enumerate()
        .map(|(n, key)| {
            let b = before.get(&key).copied().unwrap_or(0.0);
            let a = after.get(&key).copied().unwrap_or(0.0);
            StoryLoss {
                story: n + 1,
                ceiling_z_m: key as f64 / 1000.0,
                before_m3: b,
                after_m3: a,
                loss: if b > 0.0 { 1.0 - a / b } else { 0.0 },
            }
        })
        .collect()
}
