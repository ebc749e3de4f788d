//! Plan geometry of box bodies: their corners, their projections on the ground plane and
//! the areas of unions and intersections of projections (the ruin measures of
//! `summary.json`, the figures of `fem2rbd plot`).
//!
//! * a body's **plan projection** is the convex hull of its 8 box corners projected on
//!   the ground plane (x, y);
//! * areas of unions and intersections of projections are counted on a square raster
//!   (cell = the smallest plan-AABB side of the measured projections / [`CELLS_PER_SIDE`];
//!   a cell counts when its centre lies inside), exact to about one cell along the edges.
use crate::bullet::Pose;
use crate::ruin::stage::to_isometry;
use nalgebra::{Point3, Vector3};

/// Raster resolution of the area measures: cells across the smallest projection side.
pub(crate) const CELLS_PER_SIDE: f64 = 20.0;

/// The 8 corners of a box of half extents `he` at `pose`, m.
pub fn corners(pose: &Pose, he: [f64; 3]) -> Vec<[f64; 3]> {
    let iso = to_isometry(pose);
    let mut out = Vec::with_capacity(8);
    for sx in [-1.0, 1.0] {
        for sy in [-1.0, 1.0] {
            for sz in [-1.0, 1.0] {
                let p = iso * Point3::from(Vector3::new(sx * he[0], sy * he[1], sz * he[2]));
                out.push([p.x, p.y, p.z]);
            }
        }
    }
    out
}

/// Convex hull (counter-clockwise, Andrew's monotone chain) of plan points.
pub fn hull(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut p: Vec<[f64; 2]> = points.to_vec();
    p.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut lower: Vec<[f64; 2]> = Vec::new();
    for &q in &p {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], q) <= 0.0 {
            lower.pop();
        }
        lower.push(q);
    }
    let mut upper: Vec<[f64; 2]> = Vec::new();
    for &q in p.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], q) <= 0.0 {
            upper.pop();
        }
        upper.push(q);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

/// Whether (`x`, `y`) lies inside or on the convex polygon `poly` (counter-clockwise, at
/// least 3 points): on the left of or on every edge.
pub fn inside(poly: &[[f64; 2]], x: f64, y: f64) -> bool {
    if poly.len() < 3 {
        return false;
    }
    (0..poly.len()).all(|i| {
        let a = poly[i];
        let b = poly[(i + 1) % poly.len()];
        (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]) >= 0.0
    })
}

/// Plan projection of a box.
pub fn projection(pose: &Pose, he: [f64; 3]) -> Vec<[f64; 2]> {
    let c: Vec<[f64; 2]> = corners(pose, he).iter().map(|c| [c[0], c[1]]).collect();
    hull(&c)
}

/// The raster cell of a set of projections, m: 1/[`CELLS_PER_SIDE`] of the smallest
/// plan-AABB side among them (so every body is resolved, however far the debris spreads).
fn cell_of(polys: &[&Vec<[f64; 2]>]) -> f64 {
    let mut side = f64::INFINITY;
    for p in polys {
        let (lo, hi) = bbox(p);
        side = side.min((hi[0] - lo[0]).min(hi[1] - lo[1]));
    }
    (side.max(1e-4)) / CELLS_PER_SIDE
}

/// The plan bounding box (lower, upper corner) of the points `p`, m.
pub fn bbox(p: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for q in p {
        for k in 0..2 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    (lo, hi)
}

/// The cells of side `cell` whose centres lie in the union of `polys`, as row runs: for
/// every row j, sorted and merged inclusive column ranges `(j, i_first, i_last)`, in
/// increasing (j, i) order.
///
/// A convex polygon meets a row of cell centres in one run of cells; the run's ends come
/// from the polygon's edges crossing the row's centre line y = (j + ½)·cell and are then
/// settled with the same inside test a cell-by-cell count uses, so the runs hold exactly
/// the cells such a count would (this is the raster of the module docs). Memory and time
/// grow with the rows the polygons span, not with their cells: the debris of a
/// seven-story building at centimetre cells would otherwise be 10⁸ cells.
fn row_runs(polys: &[&Vec<[f64; 2]>], cell: f64) -> Vec<(i64, i64, i64)> {
    let mut runs: Vec<(i64, i64, i64)> = Vec::new();
    for p in polys {
        if p.len() < 3 {
            continue;
        }
        let (lo, hi) = bbox(p);
        let (i0, i1) = ((lo[0] / cell).floor() as i64, (hi[0] / cell).ceil() as i64);
        let (j0, j1) = ((lo[1] / cell).floor() as i64, (hi[1] / cell).ceil() as i64);
        for j in j0..=j1 {
            let y = (j as f64 + 0.5) * cell;
            let Some((xa, xb)) = chord(p, y) else {
                continue;
            };
            let centre = |i: i64| (i as f64 + 0.5) * cell;
            let inside_i = |i: i64| inside(p, centre(i), y);
            // First guess from the chord, clamped to the bounding box's columns.
            let mut a = ((xa / cell - 0.5).ceil() as i64).clamp(i0, i1);
            let mut b = ((xb / cell - 0.5).floor() as i64).clamp(i0, i1);
            // Settle both ends with the inside test itself.
            while a > i0 && inside_i(a - 1) {
                a -= 1;
            }
            while a <= i1 && !inside_i(a) {
                a += 1;
            }
            if a > i1 {
                continue;
            }
            b = b.max(a);
            while b < i1 && inside_i(b + 1) {
                b += 1;
            }
            while b > a && !inside_i(b) {
                b -= 1;
            }
            runs.push((j, a, b));
        }
    }
    runs.sort_unstable();
    let mut merged: Vec<(i64, i64, i64)> = Vec::with_capacity(runs.len());
    for (j, a, b) in runs {
        match merged.last_mut() {
            Some(last) if last.0 == j && a <= last.2 + 1 => last.2 = last.2.max(b),
            _ => merged.push((j, a, b)),
        }
    }
    merged
}

/// The x-extent of the convex polygon `p` (counter-clockwise) on the line y = `y`, or
/// `None` if the line misses it: the intersection of the edges' half-planes, each edge
/// a→b bounding x through (b_x − a_x)(y − a_y) − (b_y − a_y)(x − a_x) ≥ 0.
fn chord(p: &[[f64; 2]], y: f64) -> Option<(f64, f64)> {
    let (mut xa, mut xb) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..p.len() {
        let a = p[k];
        let b = p[(k + 1) % p.len()];
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let c = dx * (y - a[1]);
        if dy > 0.0 {
            xb = xb.min(a[0] + c / dy);
        } else if dy < 0.0 {
            xa = xa.max(a[0] + c / dy);
        } else if c < 0.0 {
            return None;
        }
    }
    (xa <= xb).then_some((xa, xb))
}

/// Number of cells in row runs.
fn run_cells(runs: &[(i64, i64, i64)]) -> usize {
    runs.iter().map(|&(_, a, b)| (b - a + 1) as usize).sum()
}

/// Plan area of the union of `polys`, m².
pub fn union_area(polys: &[&Vec<[f64; 2]>]) -> f64 {
    if polys.is_empty() {
        return 0.0;
    }
    let cell = cell_of(polys);
    run_cells(&row_runs(polys, cell)) as f64 * cell * cell
}

/// Area of (∪ a) ∩ (∪ b), m².
pub fn intersection_area(a: &[&Vec<[f64; 2]>], b: &[&Vec<[f64; 2]>]) -> f64 {
    if a.is_empty() || b.is_empty() {
        return 0.0;
    }
    let all: Vec<&Vec<[f64; 2]>> = a.iter().chain(b.iter()).copied().collect();
    let cell = cell_of(&all);
    let (ra, rb) = (row_runs(a, cell), row_runs(b, cell));
    // Both lists are sorted by (row, first column) and disjoint within a row: walk them
    // together, counting the overlap of every pair of runs of the same row.
    let (mut i, mut k, mut n) = (0, 0, 0usize);
    while i < ra.len() && k < rb.len() {
        let ((ja, a0, a1), (jb, b0, b1)) = (ra[i], rb[k]);
        if ja != jb {
            if ja < jb {
                i += 1;
            } else {
                k += 1;
            }
            continue;
        }
        let (lo, hi) = (a0.max(b0), a1.min(b1));
        if lo <= hi {
            n += (hi - lo + 1) as usize;
        }
        if a1 < b1 {
            i += 1;
        } else {
            k += 1;
        }
    }
    n as f64 * cell * cell
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cell-by-cell count the row runs replace: every cell of every polygon's bounding
    /// box whose centre passes the inside test, deduplicated.
    fn brute_force_cells(polys: &[&Vec<[f64; 2]>], cell: f64) -> Vec<(i64, i64)> {
        let mut out = Vec::new();
        for p in polys {
            if p.len() < 3 {
                continue;
            }
            let (lo, hi) = bbox(p);
            let (i0, i1) = ((lo[0] / cell).floor() as i64, (hi[0] / cell).ceil() as i64);
            let (j0, j1) = ((lo[1] / cell).floor() as i64, (hi[1] / cell).ceil() as i64);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    if inside(p, (i as f64 + 0.5) * cell, (j as f64 + 0.5) * cell) {
                        out.push((i, j));
                    }
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Rotated, overlapping boxes (a fixed linear congruential sequence), some touching
    /// cell centres exactly (axis-aligned on the grid): the row runs hold exactly the
    /// cells of the cell-by-cell count, for unions and intersections.
    #[test]
    fn row_runs_count_the_same_cells_as_the_cell_by_cell_raster() {
        let mut seed = 12345u64;
        let mut next = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut polys: Vec<Vec<[f64; 2]>> = Vec::new();
        for k in 0..60 {
            let he = [0.05 + 2.0 * next(), 0.05 + 0.5 * next(), 0.2];
            let angle = if k % 5 == 0 {
                0.0
            } else {
                std::f64::consts::TAU * next()
            };
            let pose = Pose {
                position: [10.0 * next() - 5.0, 10.0 * next() - 5.0, 0.0],
                orientation: [(angle / 2.0).cos(), 0.0, 0.0, (angle / 2.0).sin()],
            };
            polys.push(projection(&pose, he));
        }
        // Grid-aligned squares whose edges pass through cell centres.
        polys.push(vec![
            [0.025, 0.025],
            [1.025, 0.025],
            [1.025, 1.025],
            [0.025, 1.025],
        ]);
        polys.push(vec![
            [0.525, 0.025],
            [2.025, 0.025],
            [2.025, 0.525],
            [0.525, 0.525],
        ]);
        let all: Vec<&Vec<[f64; 2]>> = polys.iter().collect();
        let (a, b) = all.split_at(30);
        for cell in [0.05, 0.0137, cell_of(&all)] {
            let brute = brute_force_cells(&all, cell);
            let runs = row_runs(&all, cell);
            assert_eq!(run_cells(&runs), brute.len(), "cell {cell}");
            let expanded: Vec<(i64, i64)> = runs
                .iter()
                .flat_map(|&(j, a, b)| (a..=b).map(move |i| (i, j)))
                .collect();
            let mut sorted = expanded.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, brute, "cell {cell}");
            let (ba, bb) = (brute_force_cells(a, cell), brute_force_cells(b, cell));
            let n_int = ba.iter().filter(|c| bb.binary_search(c).is_ok()).count();
            let (ra, rb) = (row_runs(a, cell), row_runs(b, cell));
            let mut n = 0usize;
            for &(j, a0, a1) in &ra {
                for &(jb, b0, b1) in &rb {
                    if j == jb && a0.max(b0) <= a1.min(b1) {
                        n += (a1.min(b1) - a0.max(b0) + 1) as usize;
                    }
                }
            }
            assert_eq!(n, n_int, "cell {cell}");
            assert!(
                n_int > 0 && brute.len() > 1000,
                "the case must exercise overlaps"
            );
        }
        let cell = cell_of(&all);
        let n_int = {
            let (ba, bb) = (brute_force_cells(a, cell), brute_force_cells(b, cell));
            ba.iter().filter(|c| bb.binary_search(c).is_ok()).count()
        };
        assert_eq!(intersection_area(a, b), n_int as f64 * cell * cell);
    }
}
