//! The flood of an access search: a 0/1 breadth-first search from open air, confined to
//! the cells near debris.
//!
//! A search ([`super::access`]) gives every cell a class: blocked, or the cost of
//! entering it (0 or 1). From open air at the grid's sides and top it finds, for every
//! cell, the least total cost of a 6-connected path to it, the side the path entered the
//! first cell of cost 1 from, the step into the cell along that path and, for the breach,
//! the first cell of cost 1 on it.
//!
//! **Where it runs.** Most of the grid is the open air around the pile. Every column's
//! cells from the top face down to its lowest cell with only cells of cost 0 above it
//! (its **open run**, `base..nz`) are reached at cost 0 straight down from the top face,
//! which lies wholly in open air (the grid reaches a margin above the debris). Those
//! cells are settled at cost 0 without being visited: no entry side, no step (a route
//! starts there), no first cell. The search stores and visits only the cells below each
//! column's open run (column by column, `k` upward): the pile, the air under and
//! between its pieces, and the thin layer above it where a body does not fit.
//!
//! **Why the costs are those of a search over the whole grid.** A cell of an open run
//! costs 0, the least cost there is, and a whole-grid search gives it 0 too. Any path
//! from open air to a stored cell, after the last open-run cell it passes, runs through
//! stored cells only; the confined search starts from every open-run cell at cost 0 and
//! from the stored cells on the grid's sides and top at their own cost (as the whole-grid
//! search does), so it finds the same least cost for every cell. Only the choice among
//! paths of equal cost (the entry side, the route's cells, the breach's first cell) can
//! differ from a whole-grid search, which settles the cells in another order.
//!
//! **Ties, deterministically.** The search starts from the stored cells, in cell index
//! order (column by column, `k` upward), that can be entered at no more than their own
//! cost: a cell on the grid's sides or top (its entry side that face, the top before the
//! sides, as [`super::access::boundary_code`]; no step), else a cell next to an open run
//! (its entry side and step the first such neighbour's step in the order of the step
//! codes: `x+` (a step towards −x), `x−`, `y+`, `y−`, `top` (a step down)). Cells of
//! cost 0 form the first level, cells of cost 1 the next, and so on (Dial's buckets);
//! within a level the cells are settled first in, first out, and each settled cell offers
//! its neighbours in the step order −x, +x, −y, +y, −z, +z. A cell keeps the first of
//! its least-cost offers. The same classes give the same result whatever the thread
//! count.
use super::grid::Grid;

/// No path reaches the cell.
pub const UNREACHED: u32 = u32::MAX;
/// No entry side or step (a path wholly in open air, or one that starts at the cell).
pub const NO_SIDE: u8 = u8::MAX;
/// No cell of cost 1 on the path.
pub const NO_CELL: u32 = u32::MAX;

/// A cell a search cannot enter.
const BLOCKED: u8 = 2;

/// What a flood found: for every stored cell its least cost, entry side, step (when
/// traced) and first cell of cost 1 (when marked); open-run cells read as cost 0.
#[derive(Debug, Clone)]
pub struct Flood {
    grid: Grid,
    /// Per column: the lowest cell of its open run.
    base: Vec<u32>,
    /// Per column: where its stored cells (`0..base`) begin; `columns + 1` entries.
    start: Vec<u32>,
    cost: Vec<u32>,
    side: Vec<u8>,
    from: Vec<u8>,
    first: Vec<u32>,
}

impl Flood {
    /// Where cell `idx` is stored (`None`: it lies in its column's open run).
    #[inline]
    fn stored(&self, idx: usize) -> Option<usize> {
        let nz = self.grid.n[2];
        let (col, k) = (idx / nz, idx % nz);
        (k < self.base[col] as usize).then(|| self.start[col] as usize + k)
    }

    /// The least cost to cell `idx` ([`UNREACHED`] if none).
    pub fn cost(&self, idx: usize) -> u32 {
        self.stored(idx).map_or(0, |l| self.cost[l])
    }

    /// The step code (`axis · 2 + (sign > 0)`) of the step into the first cell of cost 1
    /// on the least-cost path to `idx` ([`NO_SIDE`]: none).
    pub fn side(&self, idx: usize) -> u8 {
        self.stored(idx).map_or(NO_SIDE, |l| self.side[l])
    }

    /// The step code of the step into cell `idx` along its least-cost path ([`NO_SIDE`]:
    /// the path starts there). Only for a traced flood.
    pub fn from(&self, idx: usize) -> u8 {
        self.stored(idx).map_or(NO_SIDE, |l| self.from[l])
    }

    /// The first cell of cost 1 (its index) on the least-cost path to `idx` ([`NO_CELL`]:
    /// none). Only for a marked flood.
    pub fn first(&self, idx: usize) -> u32 {
        self.stored(idx).map_or(NO_CELL, |l| self.first[l])
    }

    /// The cells the flood stored and searched (those below the open runs).
    pub fn stored_cells(&self) -> usize {
        self.cost.len()
    }
}

/// Floods `grid` (module docs). `class(idx, col, k)` is the cost of entering cell `idx`
/// (column `col`, layer `k`): `Some(0)`, `Some(1)` or `None` for blocked. `base[col]` is
/// the lowest cell of each column's open run: every cell from it up must cost 0 (and no
/// cell below it need). `mark` keeps the first cell of cost 1 of every path, `trace`
/// the step into every cell.
pub fn flood(
    grid: &Grid,
    base: Vec<u32>,
    class: impl Fn(usize, usize, usize) -> Option<u32>,
    mark: bool,
    trace: bool,
) -> Flood {
    let [nx, ny, nz] = grid.n;
    let columns = grid.columns();
    debug_assert_eq!(base.len(), columns);
    let mut start = Vec::with_capacity(columns + 1);
    let mut total = 0u64;
    for b in &base {
        start.push(total as u32);
        total += u64::from(*b);
    }
    start.push(total as u32);
    let stored = total as usize;
    // The class of each stored cell, and the grid's side faces of each column (bits in
    // the step order −x, +x, −y, +y: the neighbour that way lies outside).
    let mut cls = vec![BLOCKED; stored];
    let mut col_faces = vec![0u8; columns];
    for j in 0..ny {
        for i in 0..nx {
            let col = grid.column(i, j);
            col_faces[col] = u8::from(i == 0)
                | u8::from(i + 1 == nx) << 1
                | u8::from(j == 0) << 2
                | u8::from(j + 1 == ny) << 3;
            let s = start[col] as usize;
            for k in 0..base[col] as usize {
                cls[s + k] = class(col * nz + k, col, k).map_or(BLOCKED, |c| c as u8);
            }
        }
    }
    let mut cost = vec![UNREACHED; stored];
    let mut side = vec![NO_SIDE; stored];
    let mut from = if trace {
        vec![NO_SIDE; stored]
    } else {
        Vec::new()
    };
    let mut first = if mark {
        vec![NO_CELL; stored]
    } else {
        Vec::new()
    };
    // Whether (col, k) lies in its column's open run.
    let open = |col: usize, k: usize| k >= base[col] as usize;
    // A queue entry: column << 32 | k.
    let entry = |col: usize, k: usize| ((col as u64) << 32) | k as u64;
    let mut level: Vec<u64> = Vec::new();
    let mut next: Vec<u64> = Vec::new();
    // The starts, in cell index order (module docs).
    for col in 0..columns {
        let faces = col_faces[col];
        let s = start[col] as usize;
        let b = base[col] as usize;
        for k in 0..b {
            let l = s + k;
            let c = cls[l];
            if c == BLOCKED {
                continue;
            }
            let boundary = faces != 0 || k + 1 == nz;
            let entered = if boundary {
                Some((super::access::boundary_code(grid, col * nz + k), NO_SIDE))
            } else {
                // The open-run neighbours in the order of the step into this cell:
                // from +x (a step towards −x), −x, +y, −y, above.
                [
                    (0u8, open(col + 1, k)),
                    (1, open(col - 1, k)),
                    (2, open(col + nx, k)),
                    (3, open(col - nx, k)),
                    (4, k + 1 == b),
                ]
                .into_iter()
                .find(|(_, o)| *o)
                .map(|(code, _)| (code, code))
            };
            let Some((code, step)) = entered else {
                continue;
            };
            cost[l] = u32::from(c);
            if c > 0 {
                side[l] = code;
                if mark {
                    first[l] = (col * nz + k) as u32;
                }
            }
            if trace {
                from[l] = step;
            }
            if c > 0 {
                next.push(entry(col, k));
            } else {
                level.push(entry(col, k));
            }
        }
    }
    // Cells are settled in order of cost, `at` the cost of the level; a cell may be
    // queued once per cost it was given, and an entry whose cell has since been given a
    // lower cost (and settled at it) is skipped.
    let mut at = 0u32;
    let mut head = 0usize;
    loop {
        let Some(&e) = level.get(head) else {
            if next.is_empty() {
                break;
            }
            std::mem::swap(&mut level, &mut next);
            next.clear();
            head = 0;
            at += 1;
            continue;
        };
        head += 1;
        let (col, k) = ((e >> 32) as usize, (e & 0xffff_ffff) as usize);
        let l = start[col] as usize + k;
        if cost[l] < at {
            continue;
        }
        let faces = col_faces[col];
        for s in 0..6u8 {
            let (qc, qk) = match s {
                0..=3 => {
                    if faces & (1 << s) != 0 {
                        continue;
                    }
                    let qc = match s {
                        0 => col - 1,
                        1 => col + 1,
                        2 => col - nx,
                        _ => col + nx,
                    };
                    (qc, k)
                }
                4 => {
                    if k == 0 {
                        continue;
                    }
                    (col, k - 1)
                }
                _ => (col, k + 1),
            };
            if open(qc, qk) {
                continue;
            }
            let q = start[qc] as usize + qk;
            let enter = cls[q];
            if enter == BLOCKED {
                continue;
            }
            let nc = at + u32::from(enter);
            if nc < cost[q] {
                cost[q] = nc;
                side[q] = if enter > 0 && side[l] == NO_SIDE {
                    s
                } else {
                    side[l]
                };
                if mark {
                    first[q] = if first[l] == NO_CELL && enter > 0 {
                        (qc * nz + qk) as u32
                    } else {
                        first[l]
                    };
                }
                if trace {
                    from[q] = s;
                }
                if enter == 0 {
                    level.push(entry(qc, qk));
                } else {
                    next.push(entry(qc, qk));
                }
            }
        }
    }
    Flood {
        grid: *grid,
        base,
        start,
        cost,
        side,
        from,
        first,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::VecDeque;

    fn grid(n: [usize; 3]) -> Grid {
        Grid {
            origin: [0.0; 3],
            h: 1.0,
            n,
        }
    }

    /// The least costs over the whole grid, from every enterable cell on its sides and
    /// top at its own cost (a plain 0/1 breadth-first search with a double-ended queue,
    /// no open runs).
    fn whole_grid(g: &Grid, class: &[Option<u32>]) -> Vec<u32> {
        let mut cost = vec![UNREACHED; g.len()];
        let mut queue = VecDeque::new();
        for idx in 0..g.len() {
            if let (Some(c), true) = (class[idx], g.on_open_boundary(idx)) {
                cost[idx] = c;
                if c == 0 {
                    queue.push_front(idx);
                } else {
                    queue.push_back(idx);
                }
            }
        }
        while let Some(c) = queue.pop_front() {
            for (q, _, _) in g.neighbours(c) {
                let Some(enter) = class[q] else { continue };
                if cost[c] + enter < cost[q] {
                    cost[q] = cost[c] + enter;
                    if enter == 0 {
                        queue.push_front(q);
                    } else {
                        queue.push_back(q);
                    }
                }
            }
        }
        cost
    }

    /// Each column's open run by the rule the access searches use: its cells from the
    /// top down while they cost 0.
    fn open_runs(g: &Grid, class: &[Option<u32>]) -> Vec<u32> {
        let nz = g.n[2];
        (0..g.columns())
            .map(|col| {
                let mut k = nz;
                while k > 0 && class[col * nz + k - 1] == Some(0) {
                    k -= 1;
                }
                k as u32
            })
            .collect()
    }

    fn run(g: &Grid, class: &[Option<u32>], mark: bool, trace: bool) -> Flood {
        flood(g, open_runs(g, class), |q, _, _| class[q], mark, trace)
    }

    /// Cell classes with `solid` cells costing 1 and every other cell 0, or blocked where
    /// `blocked`; a free cell under a solid one costs 1 too when `covered_costs`.
    fn classes(
        g: &Grid,
        solid: &[[usize; 3]],
        blocked: &[[usize; 3]],
        covered_costs: bool,
    ) -> Vec<Option<u32>> {
        let mut class = vec![Some(0); g.len()];
        for c in blocked {
            class[g.index(c[0], c[1], c[2])] = None;
        }
        for c in solid {
            class[g.index(c[0], c[1], c[2])] = if covered_costs { None } else { Some(1) };
        }
        if covered_costs {
            let nz = g.n[2];
            for col in 0..g.columns() {
                let top = (0..nz).rev().find(|k| {
                    solid
                        .iter()
                        .any(|c| g.index(c[0], c[1], c[2]) == col * nz + k)
                });
                if let Some(top) = top {
                    for k in 0..top {
                        if class[col * nz + k] == Some(0) {
                            class[col * nz + k] = Some(1);
                        }
                    }
                }
            }
        }
        class
    }

    /// A covered corridor along x at j = 2, k = 0, under a slab (k = 1) between walls
    /// (j = 1 and 3, k = 0..1), from i = 2 to 6 on an 8 × 5 × 3 grid, with two cells of
    /// open air blocked at its −x end above (1, 2, 0), so that the corridor is entered at
    /// its −x end through an open cell under them. A route's cost is the covered cells it
    /// crosses: min(i − 1, 7 − i) for the corridor's cell i, by hand, and the same over
    /// the whole grid. The middle cell (4, 2, 0), 3 from either end, is reached from x+:
    /// the +x end's cell is a start of the second level, ahead of the −x end's, which the
    /// first level finds (through the open cell under the blocked ones); its steps lead
    /// back to the open run of column (7, 2).
    #[test]
    fn a_covered_corridor_is_reached_from_its_nearer_end() {
        let g = grid([8, 5, 3]);
        let mut solid = Vec::new();
        for i in 2..=6 {
            solid.extend([[i, 1, 0], [i, 1, 1], [i, 3, 0], [i, 3, 1], [i, 2, 1]]);
        }
        let class = classes(&g, &solid, &[[1, 2, 1], [1, 2, 2]], true);
        let f = run(&g, &class, false, true);
        let want = [1, 2, 3, 2, 1];
        for (i, w) in (2..=6).zip(want) {
            assert_eq!(f.cost(g.index(i, 2, 0)), w, "corridor cell {i}");
        }
        assert_eq!(
            whole_grid(&g, &class),
            (0..g.len()).map(|q| f.cost(q)).collect::<Vec<_>>()
        );
        // The open cell under the blocked ones costs 0 and is entered from x−.
        let under = g.index(1, 2, 0);
        assert_eq!(
            (f.cost(under), f.side(under), f.from(under)),
            (0, NO_SIDE, 1)
        );
        // The corridor's −x end is entered from x− through that cell.
        assert_eq!(f.side(g.index(2, 2, 0)), 1, "x-");
        let mid = g.index(4, 2, 0);
        assert_eq!(f.side(mid), 0, "entered from x+");
        let mut path = vec![mid];
        let mut c = mid;
        while f.from(c) != NO_SIDE {
            assert_eq!(f.from(c), 0, "every step towards -x");
            c += g.n[2];
            path.push(c);
        }
        let cells: Vec<[usize; 3]> = path.iter().rev().map(|&q| g.ijk(q)).collect();
        assert_eq!(cells, [[7, 2, 0], [6, 2, 0], [5, 2, 0], [4, 2, 0]]);
        // Stored: the 3 cells of column (1, 2) and the 2 below each of the 15 solid
        // columns' surface (k = 0, 1).
        assert_eq!(f.stored_cells(), 3 + 15 * 2);
    }

    /// A free cell (2, 2, 0) walled in by four solid cells around it and two above it, on
    /// a 5 × 5 × 4 grid: the least breach crosses one solid cell (a wall), not two (the
    /// roof). Of the walls, (2, 1, 0) enters the second level first (cell index order)
    /// and is entered from x+ (the first of its open neighbours in step-code order).
    #[test]
    fn a_walled_cell_is_breached_through_one_wall() {
        let g = grid([5, 5, 4]);
        let solid = [
            [1, 2, 0],
            [3, 2, 0],
            [2, 1, 0],
            [2, 3, 0],
            [2, 2, 1],
            [2, 2, 2],
        ];
        let class = classes(&g, &solid, &[], false);
        let f = run(&g, &class, true, false);
        let void = g.index(2, 2, 0);
        assert_eq!(f.cost(void), 1);
        assert_eq!(f.first(void), g.index(2, 1, 0) as u32);
        assert_eq!(f.side(void), 0, "x+");
        assert_eq!(f.cost(g.index(2, 2, 2)), 1);
        assert_eq!(f.cost(g.index(2, 2, 3)), 0);
        assert_eq!(f.first(g.index(2, 2, 3)), NO_CELL);
        assert_eq!(
            whole_grid(&g, &class),
            (0..g.len()).map(|q| f.cost(q)).collect::<Vec<_>>()
        );
    }

    /// On random classes (a quarter of the cells cost 1, a tenth blocked, nothing on the
    /// top face), the confined flood's costs equal the whole grid's for every cell, and
    /// each traced step leads to a cell whose cost is this cell's less its own.
    #[test]
    fn random_classes_give_the_whole_grid_costs() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        for n in [[9, 7, 6], [4, 11, 5], [1, 1, 3]] {
            let g = grid(n);
            let class: Vec<Option<u32>> = (0..g.len())
                .map(|q| {
                    seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
                    let r = (seed >> 33) % 20;
                    if g.ijk(q)[2] + 1 == g.n[2] {
                        Some(0)
                    } else if r < 2 {
                        None
                    } else if r < 7 {
                        Some(1)
                    } else {
                        Some(0)
                    }
                })
                .collect();
            let f = run(&g, &class, true, true);
            let want = whole_grid(&g, &class);
            for q in 0..g.len() {
                assert_eq!(f.cost(q), want[q], "grid {n:?}, cell {:?}", g.ijk(q));
                let step = f.from(q);
                if step != NO_SIDE {
                    let (axis, plus) = (usize::from(step / 2), step % 2 == 1);
                    let mut p = g.ijk(q);
                    if plus {
                        p[axis] -= 1;
                    } else {
                        p[axis] += 1;
                    }
                    let p = g.index(p[0], p[1], p[2]);
                    assert_eq!(f.cost(p) + class[q].unwrap(), f.cost(q));
                }
            }
            assert!(f.stored_cells() < g.len() || g.len() == 3);
        }
    }
}
