//! Access: how a rescuer or a search camera reaches a void from open air, or, where
//! neither can, the least debris to breach.
//!
//! * A body of diameter `w` can stand with its centre in a free cell whose clearance
//!   ([`super::voids`]) is at least `w/2`: the free space eroded by the radius, through
//!   the exact distance transform. Starting from such cells on the grid's sides and top
//!   (open air), a breadth-first search with 0/1 costs (0 through open cells, 1 per
//!   covered cell) finds, for every cell, the least length of crawl under debris
//!   (6-connected steps × h) and where the route left open air: the **entry side** is the
//!   side of the covered region it entered through (`x-` for a step towards +x, …, `top`
//!   for a step down).
//! * A void is **reached** when the search gets to one of its cells; the route is the one
//!   to its reached cell with the largest clearance (the most room; ties by the shorter
//!   route, then by cell order).
//! * The route itself, as a line, is traced back along the steps the search took
//!   ([`super::route`]).
//! * **Breach**: a 0/1 search from the grid's sides and top where entering a solid cell
//!   costs 1 and a free cell 0 gives the least number of solid cells between open air and
//!   each void (× h: the least debris thickness along a 6-connected path; 0 for a void
//!   open to the air) and the first solid cell of that path (where to start) with the side
//!   it was entered from.
use super::grid::Grid;
use super::voids::{Field, Void};

/// No route.
pub const UNREACHED: u32 = u32::MAX;
/// No entry side (a route wholly in open air).
pub const NO_SIDE: u8 = u8::MAX;

/// The name of a step code (`axis · 2 + (sign > 0)`) as the side of the region it enters.
pub fn side_name(code: u8) -> &'static str {
    match code {
        0 => "x+",
        1 => "x-",
        2 => "y+",
        3 => "y-",
        4 => "top",
        5 => "below",
        _ => "",
    }
}

fn step_code(axis: usize, sign: i8) -> u8 {
    (axis * 2) as u8 + u8::from(sign > 0)
}

/// The step code of entering the grid at boundary cell `idx` from outside (the side it
/// lies on; the top before the sides).
pub(crate) fn boundary_code(field: &Field, idx: usize) -> u8 {
    let g = &field.grid;
    let [i, j, k] = g.ijk(idx);
    if k + 1 == g.n[2] {
        step_code(2, -1)
    } else if i == 0 {
        step_code(0, 1)
    } else if i + 1 == g.n[0] {
        step_code(0, -1)
    } else if j == 0 {
        step_code(1, 1)
    } else {
        step_code(1, -1)
    }
}

/// Routes of a body of diameter `width` (m, at the model's scale): per cell the crawl
/// length in covered cells, the entry side and the step that reached it. Held in the
/// search's layered order ([`Grid::layered`](super::grid::Grid::layered)); read them by
/// cell index.
#[derive(Debug, Clone)]
pub struct Routes {
    grid: Grid,
    cost: Vec<u32>,
    side: Vec<u8>,
    from: Vec<u8>,
}

impl Routes {
    /// Covered cells along the best route to cell `idx` ([`UNREACHED`] if none).
    pub fn cost(&self, idx: usize) -> u32 {
        self.cost[self.grid.layered(idx)]
    }

    /// The entry side code of the best route to cell `idx`.
    pub fn side(&self, idx: usize) -> u8 {
        self.side[self.grid.layered(idx)]
    }

    /// The step code (`axis · 2 + (sign > 0)`) of the step into cell `idx` along its best
    /// route ([`NO_SIDE`]: a route starts there); [`super::route`] follows them back.
    pub fn from(&self, idx: usize) -> u8 {
        self.from[self.grid.layered(idx)]
    }
}

/// What a search found, per cell in layered order: its cost, entry side, the step into it
/// (empty unless traced) and the first marked cell of its route (its layered index; empty
/// unless marking).
struct Found {
    cost: Vec<u32>,
    side: Vec<u8>,
    from: Vec<u8>,
    first: Vec<u32>,
}

/// A cell a search cannot enter (its step cost in the low bits of a [`classes`] entry is
/// 0 or 1 otherwise).
const BLOCKED: u8 = 2;
/// The low bits of a [`classes`] entry: the cost of entering the cell, or [`BLOCKED`].
const COST_BITS: u8 = 3;

/// Each cell's class for a search, in layered order ([`Grid::layered`]): the cost of
/// entering it (`cost_of(index, column, k)`: 0, 1, or `None` for [`BLOCKED`]) in the low
/// two bits, and above them the grid faces it lies on ([`Grid::faces`] shifted by 2), so
/// that a search steps to its neighbours without dividing an index into (i, j, k).
///
/// Why layers: a search floods the open air from the grid's top face down, a whole layer
/// of columns at a time; cells stored column by column would put each cell of such a
/// layer on a memory line of its own, cells stored layer by layer put them side by side.
fn classes(field: &Field, cost_of: impl Fn(usize, usize, usize) -> Option<u32>) -> Vec<u8> {
    let g = &field.grid;
    let [nx, ny, nz] = g.n;
    let columns = g.columns();
    let mut class = vec![BLOCKED; g.len()];
    for j in 0..ny {
        for i in 0..nx {
            let col = g.column(i, j);
            for k in 0..nz {
                let cost = match cost_of(col * nz + k, col, k) {
                    Some(c) => c as u8,
                    None => BLOCKED,
                };
                class[k * columns + col] = cost | (g.faces(i, j, k) << 2);
            }
        }
    }
    class
}

/// 0/1 breadth-first search over cells classed by [`classes`] (all in layered order),
/// starting from the cells on the grid's sides and top (in cell index order); `mark` (breach: the cells of cost 1, the solid ones) keeps
/// the first such cell along each route; `trace` keeps the step into each cell.
fn search(field: &Field, class: &[u8], mark: bool, trace: bool) -> Found {
    let g = &field.grid;
    let [nx, ny, nz] = g.n;
    let columns = g.columns();
    let mut cost = vec![UNREACHED; g.len()];
    let mut side = vec![NO_SIDE; g.len()];
    let mut from = if trace {
        vec![NO_SIDE; g.len()]
    } else {
        Vec::new()
    };
    // The first marked cell of the route (breach: the first solid cell).
    let mut first = if mark {
        vec![u32::MAX; g.len()]
    } else {
        Vec::new()
    };
    // Two first-in-first-out queues, one per cost level (Dial's buckets for costs 0 and
    // 1): the cells of the level being settled, and those of the next. Within a level the
    // cells are settled breadth first, so a route through free cells (cost 0) takes the
    // fewest steps from where the level was entered, not a meander. Each queue is a list
    // read from its head.
    let mut level: Vec<u32> = Vec::new();
    let mut next: Vec<u32> = Vec::new();
    // The cells on the sides and the top, in index order.
    for j in 0..ny {
        for i in 0..nx {
            let side_column = i == 0 || j == 0 || i + 1 == nx || j + 1 == ny;
            let col = g.column(i, j);
            let ks = if side_column { 0 } else { nz - 1 };
            for k in ks..nz {
                let l = k * columns + col;
                let c = class[l] & COST_BITS;
                if c == BLOCKED {
                    continue;
                }
                cost[l] = u32::from(c);
                if c > 0 {
                    side[l] = boundary_code(field, col * nz + k);
                    if mark {
                        first[l] = l as u32;
                    }
                    next.push(l as u32);
                } else {
                    level.push(l as u32);
                }
            }
        }
    }
    let step = g.layered_steps();
    // Cells are settled in order of cost, `at` the cost of the level; a cell may be
    // queued once per cost it was given, and an entry whose cell has since been given a
    // lower cost (and settled at it) is skipped.
    let mut at = 0u32;
    let mut head = 0usize;
    loop {
        let Some(&c) = level.get(head) else {
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
        let c = c as usize;
        if cost[c] < at {
            continue;
        }
        let faces = class[c] >> 2;
        for (s, offset) in step.iter().enumerate() {
            if faces & (1 << s) != 0 {
                continue;
            }
            let q = c.wrapping_add_signed(*offset);
            let enter = class[q] & COST_BITS;
            if enter == BLOCKED {
                continue;
            }
            let nc = at + u32::from(enter);
            if nc < cost[q] {
                cost[q] = nc;
                side[q] = if enter > 0 && side[c] == NO_SIDE {
                    s as u8
                } else {
                    side[c]
                };
                if mark {
                    first[q] = if first[c] == u32::MAX && enter > 0 {
                        q as u32
                    } else {
                        first[c]
                    };
                }
                if trace {
                    from[q] = s as u8;
                }
                if enter == 0 {
                    level.push(q as u32);
                } else {
                    next.push(q as u32);
                }
            }
        }
    }
    Found {
        cost,
        side,
        from,
        first,
    }
}

/// The routes of a body of diameter `width`, m.
pub fn routes(field: &Field, width: f64) -> Routes {
    let r = 0.5 * width;
    let class = classes(field, |q, col, k| {
        let free = !field.solid[q] && field.clearance[q] as f64 >= r;
        free.then(|| u32::from(k < field.top[col]))
    });
    let found = search(field, &class, false, true);
    Routes {
        grid: field.grid,
        cost: found.cost,
        side: found.side,
        from: found.from,
    }
}

/// A void's access for one body size.
#[derive(Debug, Clone, PartialEq)]
pub struct Access {
    /// Crawl length under debris to the void's most spacious reached cell, m.
    pub route_m: f64,
    /// Side the route entered the debris through (`x-`, `x+`, `y-`, `y+`, `top`, `below`;
    /// empty when the route never passes under debris).
    pub entry: &'static str,
    /// The cell reached.
    pub cell: usize,
    /// The route as a line from where it leaves open air to the reached cell's centre, m
    /// ([`super::route::polyline`]).
    pub path_m: Vec<[f64; 3]>,
}

/// The access to `void` along `routes` (`None`: not reached).
pub fn access(field: &Field, routes: &Routes, void: &Void) -> Option<Access> {
    let mut best: Option<(f32, u32, usize)> = None;
    for &c in &void.cells {
        let cost = routes.cost(c);
        if cost == UNREACHED {
            continue;
        }
        let key = (field.clearance[c], cost, c);
        let better = match best {
            None => true,
            Some((cl, co, _)) => key.0 > cl || (key.0 == cl && key.1 < co),
        };
        if better {
            best = Some(key);
        }
    }
    best.map(|(_, cost, c)| Access {
        route_m: cost as f64 * field.grid.h,
        entry: side_name(routes.side(c)),
        cell: c,
        path_m: super::route::polyline(field, routes, c),
    })
}

/// The breach field: per cell the least solid cells from open air, the first of them and
/// the side it was entered from (held in layered order, read by cell index).
#[derive(Debug, Clone)]
pub struct BreachField {
    grid: Grid,
    cost: Vec<u32>,
    side: Vec<u8>,
    first: Vec<u32>,
}

impl BreachField {
    /// Solid cells crossed on the way to cell `idx`.
    pub fn cost(&self, idx: usize) -> u32 {
        self.cost[self.grid.layered(idx)]
    }

    /// Entry side code of the first solid cell on the way to cell `idx`.
    pub fn side(&self, idx: usize) -> u8 {
        self.side[self.grid.layered(idx)]
    }

    /// The first solid cell (its index) on the way to cell `idx`; `None` when the way
    /// crosses none.
    pub fn first(&self, idx: usize) -> Option<usize> {
        let l = self.first[self.grid.layered(idx)];
        (l != u32::MAX).then(|| self.grid.unlayered(l as usize))
    }
}

/// The breach field of `field`.
pub fn breach_field(field: &Field) -> BreachField {
    let class = classes(field, |q, _, _| Some(u32::from(field.solid[q])));
    let found = search(field, &class, true, false);
    BreachField {
        grid: field.grid,
        cost: found.cost,
        side: found.side,
        first: found.first,
    }
}

/// The least breach into a void.
#[derive(Debug, Clone, PartialEq)]
pub struct Breach {
    /// Debris thickness to cut, m (0: open to the air).
    pub thickness_m: f64,
    /// Centre of the first solid cell to cut (`None` when nothing is cut), m.
    pub at_m: Option<[f64; 3]>,
    /// The side it is entered from.
    pub side: &'static str,
}

/// The least breach into `void`.
pub fn breach(field: &Field, b: &BreachField, void: &Void) -> Breach {
    let c = void
        .cells
        .iter()
        .copied()
        .min_by_key(|&c| (b.cost(c), c))
        .expect("a void has cells");
    let first = b.first(c);
    Breach {
        thickness_m: b.cost(c) as f64 * field.grid.h,
        at_m: first.map(|f| field.grid.centre(field.grid.ijk(f))),
        side: if first.is_some() {
            side_name(b.side(c))
        } else {
            ""
        },
    }
}
