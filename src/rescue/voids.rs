//! Voids: connected regions of free space under debris.
//!
//! * A cell is **solid** when the boxes cover at least [`SOLID_FRACTION`] of it, else
//!   **free**.
//! * A free cell is **covered** when a solid cell lies somewhere above it in its column
//!   (debris over it), else it is **open** to the sky.
//! * A **void** is a connected region (6-connectivity: cells sharing a face) of covered
//!   cells. It is **enclosed** when none of its cells touches an open cell or the grid's
//!   side; a void that opens to the air at its side is still a void (it is covered), only
//!   not enclosed.
//!
//! Measures of a void (m, m², m³, at the model's scale):
//!
//! * volume: cells × h³;
//! * clear height: the tallest vertical run of its cells (a free run under debris is all
//!   one void), × h;
//! * clearance of a cell: the distance from its centre to the nearest solid cell's face,
//!   `(√D − ½)·h` with `D` the squared centre distance of the exact Euclidean distance
//!   transform ([`super::distance`]), or to the ground `(k + ½)·h`, whichever is less;
//!   exact for a plane face, to within h/2 otherwise;
//! * inscribed radius: the largest clearance of its cells (the largest ball free of
//!   debris and ground centred in the void), and that cell's centre;
//! * floor area with lying / sitting clearance: the plan area of its columns whose run of
//!   void cells is at least a lying / sitting adult's height tall;
//! * lying / sitting fits: a block of the adult's size (either way round in plan, axis
//!   aligned) lies in its cells ([`super::person`]);
//! * cover depth: the least distance, over its cells, from a cell's top up to the pile
//!   surface of its column (the rubble height map);
//! * roof / floor bodies: the bodies owning the solid cells right above / below its cells
//!   (`ground` below the lowest layer), by the number of cells they cap.
//!
//! [`SOLID_FRACTION`]: super::person::SOLID_FRACTION
use super::distance::{squared_distance, FAR};
use super::grid::Grid;
use super::occupancy::Occupancy;
use super::person::{cells_for, Scaled, SOLID_FRACTION};
use std::collections::{BTreeMap, VecDeque};

/// The grid's cells classified.
#[derive(Debug, Clone)]
pub struct Field {
    /// The grid.
    pub grid: Grid,
    /// The occupancy.
    pub occupancy: Occupancy,
    /// Solid cells.
    pub solid: Vec<bool>,
    /// Per column: one past the highest solid cell (0 when the column has none); the pile
    /// surface is at `origin z + top · h`.
    pub top: Vec<usize>,
    /// Clearance of each free cell, m (0 in solid cells).
    pub clearance: Vec<f32>,
}

impl Field {
    /// Classifies the cells of `grid` from `occupancy`.
    pub fn new(grid: Grid, occupancy: Occupancy) -> Field {
        let solid: Vec<bool> = occupancy
            .fraction
            .iter()
            .map(|f| *f as f64 >= SOLID_FRACTION)
            .collect();
        let nz = grid.n[2];
        let top: Vec<usize> = (0..grid.columns())
            .map(|col| {
                let s = &solid[col * nz..(col + 1) * nz];
                s.iter().rposition(|b| *b).map_or(0, |k| k + 1)
            })
            .collect();
        let d2 = squared_distance(&grid, &solid);
        let h = grid.h;
        let clearance = d2
            .iter()
            .enumerate()
            .map(|(idx, d)| {
                if solid[idx] {
                    return 0.0;
                }
                let k = grid.ijk(idx)[2];
                let ground = (k as f64 + 0.5) * h;
                let debris = if *d == FAR {
                    f64::INFINITY
                } else {
                    ((*d as f64).sqrt() - 0.5) * h
                };
                debris.min(ground) as f32
            })
            .collect();
        Field {
            grid,
            occupancy,
            solid,
            top,
            clearance,
        }
    }

    /// Whether cell `idx` is covered free space.
    #[inline]
    pub fn covered(&self, idx: usize) -> bool {
        let nz = self.grid.n[2];
        !self.solid[idx] && idx % nz < self.top[idx / nz]
    }

    /// Whether cell `idx` is open free space (free, nothing solid above).
    #[inline]
    pub fn open(&self, idx: usize) -> bool {
        !self.solid[idx] && !self.covered(idx)
    }
}

/// A void's measures (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Void {
    /// Its cells (indices, increasing).
    pub cells: Vec<usize>,
    /// Volume, m³.
    pub volume_m3: f64,
    /// Clear height, m.
    pub clear_height_m: f64,
    /// Inscribed radius, m.
    pub inscribed_radius_m: f64,
    /// The cell at the inscribed ball's centre.
    pub widest_cell: usize,
    /// Floor area with a lying adult's height, m².
    pub floor_area_lying_m2: f64,
    /// Floor area with a sitting adult's height, m².
    pub floor_area_sitting_m2: f64,
    /// A lying adult fits.
    pub lying_fits: bool,
    /// A sitting adult fits.
    pub sitting_fits: bool,
    /// No cell touches open air or the grid's side.
    pub enclosed: bool,
    /// Centroid, m.
    pub centroid_m: [f64; 3],
    /// Bounding box (min, max corners), m.
    pub bounds_m: [[f64; 3]; 2],
    /// Cover depth, m.
    pub cover_depth_m: f64,
    /// Roof bodies (box index, cells capped), most first.
    pub roof: Vec<(usize, usize)>,
    /// Floor bodies (box index, cells), most first; the ground's cells as `usize::MAX`.
    pub floor: Vec<(usize, usize)>,
}

impl Void {
    /// Survivable: a lying or a sitting adult fits.
    pub fn survivable(&self) -> bool {
        self.lying_fits || self.sitting_fits
    }
}

/// The voids of `field`, largest first (ties: by first cell), and the label of every cell
/// (`u32::MAX` outside voids; else the void's index in the returned list).
pub fn find_voids(field: &Field, sizes: &Scaled) -> (Vec<Void>, Vec<u32>) {
    let grid = &field.grid;
    let mut label = vec![u32::MAX; grid.len()];
    let mut regions: Vec<(Vec<usize>, bool)> = Vec::new();
    let mut queue = VecDeque::new();
    for start in 0..grid.len() {
        if label[start] != u32::MAX || !field.covered(start) {
            continue;
        }
        let id = regions.len() as u32;
        label[start] = id;
        queue.push_back(start);
        let mut cells = Vec::new();
        let mut enclosed = true;
        while let Some(c) = queue.pop_front() {
            cells.push(c);
            let [i, j, _] = grid.ijk(c);
            if i == 0 || j == 0 || i + 1 == grid.n[0] || j + 1 == grid.n[1] {
                enclosed = false;
            }
            for (q, _, _) in grid.neighbours(c) {
                if field.covered(q) {
                    if label[q] == u32::MAX {
                        label[q] = id;
                        queue.push_back(q);
                    }
                } else if !field.solid[q] {
                    enclosed = false;
                }
            }
        }
        cells.sort_unstable();
        regions.push((cells, enclosed));
    }
    let mut voids: Vec<Void> = regions
        .into_iter()
        .map(|(cells, enclosed)| measure(field, sizes, cells, enclosed))
        .collect();
    voids.sort_by(|a, b| {
        b.cells
            .len()
            .cmp(&a.cells.len())
            .then(a.cells[0].cmp(&b.cells[0]))
    });
    for (n, v) in voids.iter().enumerate() {
        for &c in &v.cells {
            label[c] = n as u32;
        }
    }
    (voids, label)
}

/// Whether the 0/1 plan `mask` (`w` × `d`, row-major by y) holds an `a` × `b` rectangle of
/// ones, by a summed-area table.
fn holds_rectangle(mask: &[bool], w: usize, d: usize, a: usize, b: usize) -> bool {
    if a > w || b > d {
        return false;
    }
    let mut sat = vec![0u32; (w + 1) * (d + 1)];
    for y in 0..d {
        for x in 0..w {
            sat[(y + 1) * (w + 1) + x + 1] =
                mask[y * w + x] as u32 + sat[y * (w + 1) + x + 1] + sat[(y + 1) * (w + 1) + x]
                    - sat[y * (w + 1) + x];
        }
    }
    let full = (a * b) as u32;
    for y in 0..=d - b {
        for x in 0..=w - a {
            let s = sat[(y + b) * (w + 1) + x + a] + sat[y * (w + 1) + x]
                - sat[y * (w + 1) + x + a]
                - sat[(y + b) * (w + 1) + x];
            if s == full {
                return true;
            }
        }
    }
    false
}

fn measure(field: &Field, sizes: &Scaled, cells: Vec<usize>, enclosed: bool) -> Void {
    let grid = &field.grid;
    let h = grid.h;
    let nz = grid.n[2];
    let (mut lo, mut hi) = ([usize::MAX; 3], [0usize; 3]);
    let mut sum = [0.0f64; 3];
    let mut widest = (f32::NEG_INFINITY, 0usize);
    let mut cover = f64::INFINITY;
    let mut roof: BTreeMap<usize, usize> = BTreeMap::new();
    let mut floor: BTreeMap<usize, usize> = BTreeMap::new();
    for &c in &cells {
        let ijk = grid.ijk(c);
        for d in 0..3 {
            lo[d] = lo[d].min(ijk[d]);
            hi[d] = hi[d].max(ijk[d]);
        }
        let p = grid.centre(ijk);
        for d in 0..3 {
            sum[d] += p[d];
        }
        if field.clearance[c] > widest.0 {
            widest = (field.clearance[c], c);
        }
        let k = ijk[2];
        let surface = field.top[c / nz];
        cover = cover.min((surface as f64 - (k + 1) as f64) * h);
        if k + 1 < nz && field.solid[c + 1] {
            let o = field.occupancy.owner[c + 1];
            if o != u32::MAX {
                *roof.entry(o as usize).or_default() += 1;
            }
        }
        if k == 0 {
            *floor.entry(usize::MAX).or_default() += 1;
        } else if field.solid[c - 1] {
            let o = field.occupancy.owner[c - 1];
            if o != u32::MAX {
                *floor.entry(o as usize).or_default() += 1;
            }
        }
    }
    // Runs of void cells upward within the bounding box: up[x, y, z] = cells of this void
    // from z up without a gap.
    let w = [hi[0] - lo[0] + 1, hi[1] - lo[1] + 1, hi[2] - lo[2] + 1];
    let local =
        |i: usize, j: usize, k: usize| ((j - lo[1]) * w[0] + (i - lo[0])) * w[2] + (k - lo[2]);
    let mut inside = vec![false; w[0] * w[1] * w[2]];
    for &c in &cells {
        let [i, j, k] = grid.ijk(c);
        inside[local(i, j, k)] = true;
    }
    let mut up = vec![0u32; inside.len()];
    let mut tallest = 0u32;
    let mut col_run = vec![0u32; w[0] * w[1]];
    for (col, best) in col_run.iter_mut().enumerate() {
        let mut run = 0u32;
        for k in (0..w[2]).rev() {
            let at = col * w[2] + k;
            run = if inside[at] { run + 1 } else { 0 };
            up[at] = run;
            *best = (*best).max(run);
        }
        tallest = tallest.max(*best);
    }
    let area = |height: f64| -> f64 {
        let need = cells_for(height, h) as u32;
        col_run.iter().filter(|r| **r >= need).count() as f64 * h * h
    };
    let fits = |body: [f64; 3]| -> bool {
        let need = cells_for(body[2], h) as u32;
        let (a, b) = (cells_for(body[0], h), cells_for(body[1], h));
        let mut mask = vec![false; w[0] * w[1]];
        for k in 0..w[2] {
            let mut any = false;
            for (col, m) in mask.iter_mut().enumerate() {
                *m = up[col * w[2] + k] >= need;
                any |= *m;
            }
            if any
                && (holds_rectangle(&mask, w[0], w[1], a, b)
                    || holds_rectangle(&mask, w[0], w[1], b, a))
            {
                return true;
            }
        }
        false
    };
    let n = cells.len() as f64;
    let by_count = |m: BTreeMap<usize, usize>| {
        let mut v: Vec<(usize, usize)> = m.into_iter().collect();
        v.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        v
    };
    Void {
        volume_m3: n * h * h * h,
        clear_height_m: tallest as f64 * h,
        inscribed_radius_m: widest.0 as f64,
        widest_cell: widest.1,
        floor_area_lying_m2: area(sizes.lying[2]),
        floor_area_sitting_m2: area(sizes.sitting[2]),
        lying_fits: fits(sizes.lying),
        sitting_fits: fits(sizes.sitting),
        enclosed,
        centroid_m: sum.map(|s| s / n),
        bounds_m: [
            [0, 1, 2].map(|d| grid.origin[d] + lo[d] as f64 * h),
            [0, 1, 2].map(|d| grid.origin[d] + (hi[d] + 1) as f64 * h),
        ],
        cover_depth_m: cover,
        roof: by_count(roof),
        floor: by_count(floor),
        cells,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rectangles_in_a_mask() {
        // 5 × 3 mask with a 4 × 2 block of ones at x 1..5, y 1..3.
        let mut m = vec![false; 15];
        for y in 1..3 {
            for x in 1..5 {
                m[y * 5 + x] = true;
            }
        }
        assert!(holds_rectangle(&m, 5, 3, 4, 2));
        assert!(!holds_rectangle(&m, 5, 3, 2, 4));
        assert!(!holds_rectangle(&m, 5, 3, 5, 1));
        assert!(holds_rectangle(&m, 5, 3, 1, 1));
    }
}
