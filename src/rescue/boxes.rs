//! A void's cells as a few disjoint boxes of whole cells, the compact exact form that
//! `voids.json` carries (`boxes`), that the report draws and `collapse.glb` holds, and
//! whose plan rectangles are the void's footprint in the ensemble map.
//!
//! The merge is greedy and exact: the cells of each grid column form vertical runs
//! `[k0, k1)`; runs with the same `(j, k0, k1)` at consecutive `i` join into x-spans
//! `[i0, i1)`; spans with the same `(i0, i1, k0, k1)` at consecutive `j` join into boxes
//! `[j0, j1)`. Every cell lies in exactly one run, one span and one box, so the boxes are
//! disjoint and their union is the void's cells. A flat pancake chamber is one box, an
//! L-shaped one two.
use super::grid::Grid;
use std::collections::BTreeMap;

/// A box of whole cells: `[i0, j0, k0, i1, j1, k1]`, the lower cell indices included and
/// the upper ones excluded (the cells `i0 ≤ i < i1`, …).
pub type CellBox = [usize; 6];

/// The disjoint boxes whose union is `cells` (indices of `grid`, increasing; module
/// docs), ordered by `(k0, j0, i0)`.
pub fn cell_boxes(grid: &Grid, cells: &[usize]) -> Vec<CellBox> {
    // Vertical runs, by (j, k0, k1) → the i of each.
    let mut runs: BTreeMap<(usize, usize, usize), Vec<usize>> = BTreeMap::new();
    let mut it = cells.iter().copied().peekable();
    while let Some(first) = it.next() {
        let [i, j, k0] = grid.ijk(first);
        let mut k1 = k0 + 1;
        while k1 < grid.n[2] && it.peek() == Some(&grid.index(i, j, k1)) {
            it.next();
            k1 += 1;
        }
        runs.entry((j, k0, k1)).or_default().push(i);
    }
    // x-spans, by (i0, i1, k0, k1) → the j of each.
    let mut spans: BTreeMap<(usize, usize, usize, usize), Vec<usize>> = BTreeMap::new();
    for ((j, k0, k1), mut is) in runs {
        is.sort_unstable();
        for (i0, i1) in consecutive(&is) {
            spans.entry((i0, i1, k0, k1)).or_default().push(j);
        }
    }
    let mut boxes = Vec::new();
    for ((i0, i1, k0, k1), mut js) in spans {
        js.sort_unstable();
        for (j0, j1) in consecutive(&js) {
            boxes.push([i0, j0, k0, i1, j1, k1]);
        }
    }
    boxes.sort_unstable_by_key(|b| (b[2], b[1], b[0], b[5], b[4], b[3]));
    boxes
}

/// The maximal runs `[a, b)` of consecutive integers in sorted `v`.
fn consecutive(v: &[usize]) -> Vec<(usize, usize)> {
    let mut out: Vec<(usize, usize)> = Vec::new();
    for &x in v {
        match out.last_mut() {
            Some((_, b)) if *b == x => *b += 1,
            _ => out.push((x, x + 1)),
        }
    }
    out
}

/// The corners of `b` in metres: `[min, max]`.
pub fn box_bounds(grid: &Grid, b: &CellBox) -> [[f64; 3]; 2] {
    let at = |d: usize, n: usize| grid.origin[d] + n as f64 * grid.h;
    [
        [at(0, b[0]), at(1, b[1]), at(2, b[2])],
        [at(0, b[3]), at(1, b[4]), at(2, b[5])],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> Grid {
        Grid {
            origin: [0.0, 0.0, 0.0],
            h: 0.5,
            n: [6, 5, 4],
        }
    }

    /// The cells of `boxes`, sorted, with a panic on a cell counted twice.
    fn expand(g: &Grid, boxes: &[CellBox]) -> Vec<usize> {
        let mut out = Vec::new();
        for b in boxes {
            for i in b[0]..b[3] {
                for j in b[1]..b[4] {
                    for k in b[2]..b[5] {
                        out.push(g.index(i, j, k));
                    }
                }
            }
        }
        out.sort_unstable();
        let n = out.len();
        out.dedup();
        assert_eq!(out.len(), n, "boxes overlap");
        out
    }

    #[test]
    fn a_block_is_one_box() {
        let g = grid();
        let mut cells = Vec::new();
        for i in 1..4 {
            for j in 0..2 {
                for k in 1..3 {
                    cells.push(g.index(i, j, k));
                }
            }
        }
        cells.sort_unstable();
        assert_eq!(cell_boxes(&g, &cells), vec![[1, 0, 1, 4, 2, 3]]);
        assert_eq!(
            box_bounds(&g, &[1, 0, 1, 4, 2, 3]),
            [[0.5, 0.0, 0.5], [2.0, 1.0, 1.5]]
        );
    }

    #[test]
    fn an_l_in_plan_is_two_boxes_and_nothing_of_its_missing_corner() {
        // Plan: i 0..3 at j = 0, and i = 0 at j 1..3 (an L of 5 columns), one layer k = 0.
        let g = grid();
        let mut cells: Vec<usize> = [(0, 0), (1, 0), (2, 0), (0, 1), (0, 2)]
            .iter()
            .map(|&(i, j)| g.index(i, j, 0))
            .collect();
        cells.sort_unstable();
        let boxes = cell_boxes(&g, &cells);
        assert_eq!(boxes, vec![[0, 0, 0, 3, 1, 1], [0, 1, 0, 1, 3, 1]]);
        assert_eq!(expand(&g, &boxes), cells);
    }

    #[test]
    fn boxes_cover_an_irregular_set_exactly_once() {
        // A pseudo-random third of the cells (a fixed linear congruential sequence).
        let g = grid();
        let mut x: u64 = 12345;
        let mut cells = Vec::new();
        for idx in 0..g.len() {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            if (x >> 33) % 3 == 0 {
                cells.push(idx);
            }
        }
        let boxes = cell_boxes(&g, &cells);
        assert_eq!(expand(&g, &boxes), cells);
        assert!(boxes.len() < cells.len());
    }
}
