//! Voids: connected regions of free space under debris.
//!
//! * A cell is **solid** when the boxes cover at least [`SOLID_FRACTION`] of it, else
//!   **free**.
//! * A free cell is **covered** when a solid cell lies somewhere above it in its column
//!   (debris over it), else it is **open** to the sky.
//! * A **void** is a **chamber**: free space under one roof. The **roof** of a covered
//!   cell is the body owning the first solid cell above it in its column. Covered cells
//!   with the same roof body that share a face form a part; a part smaller than a sitting
//!   adult's block in cells ([`fragment_cells`]) joins the adjoining part it shares the
//!   most faces with (smallest first; ties: the lower part number), and what remains are
//!   the chambers. A chamber is **enclosed** when none of its cells touches an open cell
//!   or the grid's side; a chamber that opens to the air at its side is still a void (it
//!   is covered), only not enclosed.
//! * Chambers that share faces adjoin through a **throat**: its area (shared faces × h²)
//!   and its clearance, the largest over the shared face pairs of the lesser clearance of
//!   the two cells (a body of diameter `w` passes when it is at least `w/2`, as in
//!   [`super::access`]). Chambers joined through throats form a **region**: the connected
//!   covered space (6-connectivity) that held them all.
//!
//! Why roofs: a rescuer names a void by what lies over it (the slab of a pancake, the
//! leaning slab of a lean-to), and the collapse patterns ([`super::pattern`]) are read
//! from the roof. Under a pile whose floors came down on each other the covered space is
//! one connected region running under every slab; cut by roof, each slab panel or beam
//! that caps free space gets its own chamber, and the passages between them are the
//! throats (docs/rescue.md §2).
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
        // The squared distances become the clearances in place.
        let mut clearance = squared_distance(&grid, &solid);
        let h = grid.h;
        for (s, d) in solid.chunks(nz).zip(clearance.chunks_mut(nz)) {
            for (k, (s, d)) in s.iter().zip(d).enumerate() {
                *d = if *s {
                    0.0
                } else {
                    let ground = (k as f64 + 0.5) * h;
                    let debris = if *d == FAR {
                        f64::INFINITY
                    } else {
                        ((*d as f64).sqrt() - 0.5) * h
                    };
                    debris.min(ground) as f32
                };
            }
        }
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
    /// The covered region it belongs to (chambers joined through throats), numbered from
    /// 0 in the order of their largest chamber.
    pub region: usize,
}

impl Void {
    /// Survivable: a lying or a sitting adult fits.
    pub fn survivable(&self) -> bool {
        self.lying_fits || self.sitting_fits
    }
}

/// Where two chambers meet: the cells faces they share and the widest point of the
/// passage (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Throat {
    /// The two chambers (indices in the void list, `a < b`).
    pub a: usize,
    /// The second chamber.
    pub b: usize,
    /// Cell faces shared.
    pub faces: usize,
    /// Area of the shared faces, m².
    pub area_m2: f64,
    /// Largest clearance along the shared faces, m: the largest of `min(clearance of the
    /// two cells)` over the face pairs. A body of diameter `w` passes when it is at least
    /// `w/2`.
    pub clearance_m: f64,
}

/// The roof of every covered cell: the body owning the first solid cell above it in its
/// column (`u32::MAX` for cells that are not covered, or whose roof cell has no owner).
pub fn roofs(field: &Field) -> Vec<u32> {
    let grid = &field.grid;
    let nz = grid.n[2];
    let mut roof = vec![u32::MAX; grid.len()];
    for col in 0..grid.columns() {
        let mut above = u32::MAX;
        for k in (0..field.top[col]).rev() {
            let idx = col * nz + k;
            if field.solid[idx] {
                above = field.occupancy.owner[idx];
            } else {
                roof[idx] = above;
            }
        }
    }
    roof
}

/// The smallest chamber that stands on its own, in cells: the cells of a sitting adult's
/// block (a smaller chamber cannot hold a person by its volume alone and joins its
/// neighbour).
pub fn fragment_cells(sizes: &Scaled, h: f64) -> usize {
    sizes.sitting.iter().map(|l| cells_for(*l, h)).product()
}

/// The chambers of `field` (module docs), largest first (ties: by first cell), the label
/// of every cell (`u32::MAX` outside chambers; else the chamber's index in the returned
/// list) and the throats between adjoining chambers (by `a`, then `b`).
pub fn find_voids(field: &Field, sizes: &Scaled) -> (Vec<Void>, Vec<u32>, Vec<Throat>) {
    let grid = &field.grid;
    let roof = roofs(field);
    // 1. Connected parts of covered cells under the same roof body.
    let mut label = vec![u32::MAX; grid.len()];
    let mut size: Vec<usize> = Vec::new();
    let mut first: Vec<usize> = Vec::new();
    let mut queue = VecDeque::new();
    // Covered cells lie below their column's pile surface: in index order, the cells
    // `0..top` of each column.
    let nz = grid.n[2];
    let below_top = || (0..grid.columns()).flat_map(move |col| col * nz..col * nz + field.top[col]);
    for start in below_top() {
        if label[start] != u32::MAX || !field.covered(start) {
            continue;
        }
        let id = size.len() as u32;
        label[start] = id;
        queue.push_back(start);
        let mut n = 0usize;
        while let Some(c) = queue.pop_front() {
            n += 1;
            for (q, _, _) in grid.neighbours(c) {
                if label[q] == u32::MAX && field.covered(q) && roof[q] == roof[start] {
                    label[q] = id;
                    queue.push_back(q);
                }
            }
        }
        size.push(n);
        first.push(start);
    }
    // 2. Shared faces between parts (each face once: steps towards +x, +y, +z).
    let parts = size.len();
    let mut faces: Vec<BTreeMap<u32, usize>> = vec![BTreeMap::new(); parts];
    for_each_shared_face(field, &label, |_, _, a, b| {
        *faces[a as usize].entry(b).or_default() += 1;
        *faces[b as usize].entry(a).or_default() += 1;
    });
    // 3. Fragments join the neighbour they share the most faces with, smallest first.
    let min_cells = fragment_cells(sizes, grid.h);
    let mut parent: Vec<u32> = (0..parts as u32).collect();
    let mut order: std::collections::BTreeSet<(usize, usize, u32)> =
        (0..parts).map(|p| (size[p], first[p], p as u32)).collect();
    while let Some((n, f, p)) = order.pop_first() {
        if n >= min_cells {
            break;
        }
        let Some((&into, _)) = faces[p as usize]
            .iter()
            .max_by(|x, y| x.1.cmp(y.1).then(y.0.cmp(x.0)))
        else {
            continue;
        };
        let mine = std::mem::take(&mut faces[p as usize]);
        for (other, count) in mine {
            faces[other as usize].remove(&p);
            if other != into {
                *faces[other as usize].entry(into).or_default() += count;
                *faces[into as usize].entry(other).or_default() += count;
            }
        }
        let i = into as usize;
        order.remove(&(size[i], first[i], into));
        size[i] += n;
        first[i] = first[i].min(f);
        parent[p as usize] = into;
        order.insert((size[i], first[i], into));
    }
    let root = |mut p: u32| {
        while parent[p as usize] != p {
            p = parent[p as usize];
        }
        p
    };
    // 4. The chambers' cells and whether each touches open air or the grid's side.
    let mut cells_of: BTreeMap<u32, (Vec<usize>, bool)> = BTreeMap::new();
    for c in below_top() {
        let l = &mut label[c];
        if *l == u32::MAX {
            continue;
        }
        let r = root(*l);
        *l = r;
        let entry = cells_of.entry(r).or_insert_with(|| (Vec::new(), true));
        entry.0.push(c);
        let [i, j, _] = grid.ijk(c);
        if i == 0 || j == 0 || i + 1 == grid.n[0] || j + 1 == grid.n[1] {
            entry.1 = false;
        }
        if grid.neighbours(c).any(|(q, _, _)| field.open(q)) {
            entry.1 = false;
        }
    }
    let mut voids: Vec<(u32, Void)> = cells_of
        .into_iter()
        .map(|(r, (cells, enclosed))| (r, measure(field, sizes, cells, enclosed)))
        .collect();
    voids.sort_by(|a, b| {
        b.1.cells
            .len()
            .cmp(&a.1.cells.len())
            .then(a.1.cells[0].cmp(&b.1.cells[0]))
    });
    let mut index = BTreeMap::new();
    for (n, (r, _)) in voids.iter().enumerate() {
        index.insert(*r, n as u32);
    }
    for c in below_top() {
        let l = &mut label[c];
        if *l != u32::MAX {
            *l = index[&*l];
        }
    }
    // 5. Throats between the final chambers.
    let mut throat: BTreeMap<(u32, u32), (usize, f32)> = BTreeMap::new();
    for_each_shared_face(field, &label, |c, q, a, b| {
        let e = throat.entry((a.min(b), a.max(b))).or_insert((0, 0.0));
        e.0 += 1;
        e.1 = e.1.max(field.clearance[c].min(field.clearance[q]));
    });
    let h = grid.h;
    let throats: Vec<Throat> = throat
        .into_iter()
        .map(|((a, b), (n, cl))| Throat {
            a: a as usize,
            b: b as usize,
            faces: n,
            area_m2: n as f64 * h * h,
            clearance_m: cl as f64,
        })
        .collect();
    let mut voids: Vec<Void> = voids.into_iter().map(|(_, v)| v).collect();
    // Regions: chambers joined through throats, numbered by their largest chamber.
    let mut region: Vec<usize> = (0..voids.len()).collect();
    loop {
        let mut changed = false;
        for t in throat_pairs(&throats) {
            let m = region[t.0].min(region[t.1]);
            if region[t.0] != m || region[t.1] != m {
                region[t.0] = m;
                region[t.1] = m;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    let mut numbers = BTreeMap::new();
    for (v, r) in voids.iter_mut().zip(region) {
        let next = numbers.len();
        v.region = *numbers.entry(r).or_insert(next);
    }
    (voids, label, throats)
}

fn throat_pairs(throats: &[Throat]) -> impl Iterator<Item = (usize, usize)> + '_ {
    throats.iter().map(|t| (t.a, t.b))
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
        region: 0,
        cells,
    }
}

/// Calls `f(c, q, a, b)` once for every face between two labelled cells `c` and `q` (the
/// step from `c` to `q` towards +x, +y or +z) whose labels `a` = `label[c]` and
/// `b` = `label[q]` differ; `u32::MAX` marks an unlabelled cell, as every cell at or above
/// its column's pile surface is. Cells in index order.
fn for_each_shared_face(field: &Field, label: &[u32], mut f: impl FnMut(usize, usize, u32, u32)) {
    let grid = &field.grid;
    let nz = grid.n[2];
    let cells = (0..grid.columns()).flat_map(|col| col * nz..col * nz + field.top[col]);
    for c in cells {
        let a = label[c];
        if a == u32::MAX {
            continue;
        }
        for (q, _, sign) in grid.neighbours(c) {
            let b = label[q];
            if sign > 0 && b != u32::MAX && b != a {
                f(c, q, a, b);
            }
        }
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
