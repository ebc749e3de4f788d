//! The rubble pile as a whole.
//!
//! * **Height map**: per plan column of the grid, the height of the pile surface above the
//!   ground (the top of the column's highest solid cell; 0 without debris).
//! * **Pile height**: its maximum, and its mean over the columns that hold debris.
//! * **Debris extent** per side: how far the debris (the exact corners of the boxes at
//!   their final poses) lies beyond the building's original footprint (the plan bounding
//!   box of the undeformed boxes), and each against the building's height (the highest
//!   undeformed corner above the ground). Planning practice takes the debris' reach as
//!   2/3 of the height for buildings under 24 m (docs/rescue.md §3), so the ratio is
//!   reported with that rule beside it.
//! * **Porosity**: 1 − (volume of the boxes inside the pile's envelope) / (the envelope's
//!   volume), the envelope being the height map's columns: the share of the pile that is
//!   air. The boxes' volume is the exact occupancy (fractions, not solid cells).
//!
//! Each story's volume loss: [`super::stories`].
use super::input::Ruin;
use super::voids::Field;

/// The planning rule's debris reach over height for buildings under 24 m.
pub const PLANNING_REACH_OVER_HEIGHT: f64 = 2.0 / 3.0;

/// The rubble measures.
#[derive(Debug, Clone, PartialEq)]
pub struct Rubble {
    /// Highest point of the pile above the ground, m.
    pub max_height_m: f64,
    /// Mean pile height over the columns with debris, m.
    pub mean_height_m: f64,
    /// Plan area of the columns with debris, m².
    pub footprint_area_m2: f64,
    /// The building's height above the ground, m.
    pub building_height_m: f64,
    /// Debris beyond the original footprint: x−, x+, y−, y+, m (0 when inside).
    pub extent_m: [f64; 4],
    /// Each extent over the building height.
    pub extent_over_height: [f64; 4],
    /// Share of the pile's envelope that is air.
    pub porosity: f64,
    /// Volume of the boxes in the pile, m³.
    pub debris_volume_m3: f64,
    /// Volume of the pile's envelope, m³.
    pub envelope_volume_m3: f64,
}

/// The pile surface height of every column (m above the ground), in column order.
pub fn height_map(field: &Field) -> Vec<f64> {
    field.top.iter().map(|t| *t as f64 * field.grid.h).collect()
}

/// The rubble measures of `ruin` on `field`; `ground_z` is the ground level, m.
pub fn rubble(ruin: &Ruin, field: &Field, ground_z: f64) -> Rubble {
    let h = field.grid.h;
    let heights = height_map(field);
    let with: Vec<f64> = heights.iter().copied().filter(|v| *v > 0.0).collect();
    let max_height_m = with.iter().copied().fold(0.0, f64::max);
    let mean_height_m = if with.is_empty() {
        0.0
    } else {
        with.iter().sum::<f64>() / with.len() as f64
    };
    let nz = field.grid.n[2];
    let mut debris = 0.0f64;
    let mut envelope = 0usize;
    for (col, &t) in field.top.iter().enumerate() {
        envelope += t;
        for k in 0..t {
            debris += field.occupancy.fraction[col * nz + k] as f64;
        }
    }
    let cell = h * h * h;
    let (debris_volume_m3, envelope_volume_m3) = (debris * cell, envelope as f64 * cell);
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    let mut top0 = f64::NEG_INFINITY;
    let mut beyond = [0.0f64; 4];
    let active: Vec<_> = ruin.boxes.iter().filter(|b| !b.passive).collect();
    for b in &active {
        for c in b.corners_at(&b.pose0) {
            for d in 0..2 {
                lo[d] = lo[d].min(c[d]);
                hi[d] = hi[d].max(c[d]);
            }
            top0 = top0.max(c[2]);
        }
    }
    for b in &active {
        for c in b.corners_at(&b.pose) {
            beyond[0] = beyond[0].max(lo[0] - c[0]);
            beyond[1] = beyond[1].max(c[0] - hi[0]);
            beyond[2] = beyond[2].max(lo[1] - c[1]);
            beyond[3] = beyond[3].max(c[1] - hi[1]);
        }
    }
    let building_height_m = (top0 - ground_z).max(0.0);
    Rubble {
        max_height_m,
        mean_height_m,
        footprint_area_m2: with.len() as f64 * h * h,
        building_height_m,
        extent_m: beyond,
        extent_over_height: beyond.map(|e| {
            if building_height_m > 0.0 {
                e / building_height_m
            } else {
                0.0
            }
        }),
        porosity: if envelope > 0 {
            1.0 - debris_volume_m3 / envelope_volume_m3
        } else {
            0.0
        },
        debris_volume_m3,
        envelope_volume_m3,
    }
}
