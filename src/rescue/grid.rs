//! The regular grid a ruin is measured on: cubic cells of edge `h` from the ground up.
//!
//! Plan extent: the debris (active boxes at their final poses) and the building's original
//! footprint (active boxes at their undeformed poses), widened on every side by a margin
//! of open air as wide as the rescuer plus two cells, so that a rescuer can walk round the
//! pile. Height: from the ground level to the top of the debris plus the same margin.
//! The ground level is the top of the foundation blocks at their final poses (the highest
//! foundation corner; the blocks stand on the ground), or, without foundation blocks, the
//! lowest corner of the debris. Debris below the ground level is not gridded.
//!
//! Cell `(i, j, k)` spans `origin + [i, i+1] × [j, j+1] × [k, k+1] · h`; cells are stored
//! column by column (`k` fastest), so vertical scans are contiguous.
use super::input::Ruin;
use super::{RescueError, Result};

/// Peak memory of the analysis per cell, bytes: the occupancy (fraction f32, owner u32,
/// the best overlap f32 while it is built), the solid flag, the clearance (f32) and the
/// squared distance (f32) it is made from, the chamber label and roof (u32 each), and
/// the access searches, two at a time (the rescuer's then the camera's on one thread,
/// the breach field on the other), each over at most every cell (they store only the
/// cells below each column's open air, [`super::flood`], which is every cell in the worst
/// case): its cell classes (u8), cost (u32), side and step (u8 each) or first cell (u32),
/// and its queues of u64 entries. The standing building for the story losses is gridded
/// a few rows at a time. Measured peak resident memory: 23 bytes per cell on the library
/// ruin, 51 on the standing library building before the searches were confined
/// (docs/rescue.md §5b); the bound keeps the worst case.
pub const BYTES_PER_CELL: u64 = 64;
/// The most memory a grid may take whatever the machine has: 16 GiB.
pub const MAX_BYTES: u64 = 16 << 30;

/// The memory the machine can give now (`MemAvailable` of `/proc/meminfo`), bytes;
/// `None` where that file is missing or unreadable.
pub fn memory_available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// The largest grid accepted, cells: [`MAX_BYTES`], or the memory available now if less,
/// over [`BYTES_PER_CELL`].
pub fn max_cells() -> u64 {
    MAX_BYTES.min(memory_available().unwrap_or(MAX_BYTES)) / BYTES_PER_CELL
}

/// A regular grid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    /// Corner of cell (0, 0, 0), m.
    pub origin: [f64; 3],
    /// Cell edge, m.
    pub h: f64,
    /// Cells along x, y, z.
    pub n: [usize; 3],
}

impl Grid {
    /// Cell count.
    pub fn len(&self) -> usize {
        self.n[0] * self.n[1] * self.n[2]
    }

    /// Whether the grid has no cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Plan columns (nx · ny).
    pub fn columns(&self) -> usize {
        self.n[0] * self.n[1]
    }

    /// The index of cell (i, j, k).
    #[inline]
    pub fn index(&self, i: usize, j: usize, k: usize) -> usize {
        (j * self.n[0] + i) * self.n[2] + k
    }

    /// The column of plan cell (i, j).
    #[inline]
    pub fn column(&self, i: usize, j: usize) -> usize {
        j * self.n[0] + i
    }

    /// The (i, j, k) of an index.
    #[inline]
    pub fn ijk(&self, idx: usize) -> [usize; 3] {
        let k = idx % self.n[2];
        let col = idx / self.n[2];
        [col % self.n[0], col / self.n[0], k]
    }

    /// The centre of cell (i, j, k), m.
    pub fn centre(&self, c: [usize; 3]) -> [f64; 3] {
        [0, 1, 2].map(|d| self.origin[d] + (c[d] as f64 + 0.5) * self.h)
    }

    /// The 6 face neighbours of `idx` that lie in the grid, with the axis (0, 1, 2) and
    /// sign (−1 or +1) of the step.
    pub fn neighbours(&self, idx: usize) -> impl Iterator<Item = (usize, usize, i8)> + '_ {
        let c = self.ijk(idx);
        (0..6).filter_map(move |s| {
            let (d, sign) = (s / 2, if s % 2 == 0 { -1i8 } else { 1 });
            let mut q = c;
            if sign < 0 {
                if q[d] == 0 {
                    return None;
                }
                q[d] -= 1;
            } else {
                q[d] += 1;
                if q[d] >= self.n[d] {
                    return None;
                }
            }
            Some((self.index(q[0], q[1], q[2]), d, sign))
        })
    }

    /// Whether cell `idx` lies on a side face or the top face of the grid (where open air
    /// goes on).
    pub fn on_open_boundary(&self, idx: usize) -> bool {
        let [i, j, k] = self.ijk(idx);
        i == 0 || j == 0 || i + 1 == self.n[0] || j + 1 == self.n[1] || k + 1 == self.n[2]
    }
}

/// The ground level of a ruin (module docs), m; `None` without boxes.
pub fn ground_level(ruin: &Ruin) -> Option<f64> {
    let top_of_blocks = ruin
        .boxes
        .iter()
        .filter(|b| b.passive)
        .flat_map(|b| b.corners_at(&b.pose))
        .map(|c| c[2])
        .fold(f64::NAN, f64::max);
    if !top_of_blocks.is_nan() {
        return Some(top_of_blocks);
    }
    let low = ruin
        .boxes
        .iter()
        .flat_map(|b| b.corners_at(&b.pose))
        .map(|c| c[2])
        .fold(f64::INFINITY, f64::min);
    low.is_finite().then_some(low)
}

/// The grid over a ruin (module docs) with cell `h` and an open-air `margin` (m), both
/// at the model's scale; `None` when the ruin has no debris. `cell_full_m` is the cell as
/// asked (full scale), for the error message.
pub fn grid_over(ruin: &Ruin, h: f64, margin: f64, cell_full_m: f64) -> Result<Option<Grid>> {
    let Some(z0) = ground_level(ruin) else {
        return Ok(None);
    };
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    let mut any = false;
    for b in ruin.boxes.iter().filter(|b| !b.passive) {
        any = true;
        for (pose, vertical) in [(&b.pose, true), (&b.pose0, false)] {
            for c in b.corners_at(pose) {
                for d in 0..2 {
                    lo[d] = lo[d].min(c[d]);
                    hi[d] = hi[d].max(c[d]);
                }
                if vertical {
                    hi[2] = hi[2].max(c[2]);
                }
            }
        }
    }
    if !any || hi[2] <= z0 {
        return Ok(None);
    }
    let pad = margin + 2.0 * h;
    let origin = [lo[0] - pad, lo[1] - pad, z0];
    let span = [
        hi[0] - lo[0] + 2.0 * pad,
        hi[1] - lo[1] + 2.0 * pad,
        hi[2] - z0 + pad,
    ];
    let n64 = span.map(|s| (s / h).ceil().max(1.0) as u64);
    let cells = n64[0].saturating_mul(n64[1]).saturating_mul(n64[2]);
    let max = max_cells();
    if cells > max {
        return Err(RescueError::GridTooLarge {
            cell_m: cell_full_m,
            model_cell_m: h,
            nx: n64[0],
            ny: n64[1],
            nz: n64[2],
            cells,
            extent: format!("{:.3} x {:.3} x {:.3} m", span[0], span[1], span[2]),
            max,
            bytes_per_cell: BYTES_PER_CELL,
        });
    }
    Ok(Some(Grid {
        origin,
        h,
        n: n64.map(|v| v as usize),
    }))
}
