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
//!   for a step down). The search visits only the cells below each column's open air
//!   ([`super::flood`], which states how it chooses among routes of equal length).
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
use super::flood::{flood, Flood, NO_CELL};
pub use super::flood::{NO_SIDE, UNREACHED};
use super::grid::Grid;
use super::voids::{Field, Void};

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
pub(crate) fn boundary_code(g: &Grid, idx: usize) -> u8 {
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
/// length in covered cells, the entry side and the step that reached it
/// ([`super::flood`]).
#[derive(Debug, Clone)]
pub struct Routes {
    flood: Flood,
}

impl Routes {
    /// Covered cells along the best route to cell `idx` ([`UNREACHED`] if none).
    pub fn cost(&self, idx: usize) -> u32 {
        self.flood.cost(idx)
    }

    /// The entry side code of the best route to cell `idx`.
    pub fn side(&self, idx: usize) -> u8 {
        self.flood.side(idx)
    }

    /// The step code (`axis · 2 + (sign > 0)`) of the step into cell `idx` along its best
    /// route ([`NO_SIDE`]: a route starts there, in open air or at the grid's side);
    /// [`super::route`] follows them back.
    pub fn from(&self, idx: usize) -> u8 {
        self.flood.from(idx)
    }

    /// The cells the search stored and visited.
    pub fn searched_cells(&self) -> usize {
        self.flood.stored_cells()
    }
}

/// The routes of a body of diameter `width`, m: a cell can be entered when it is free and
/// its clearance is at least `width/2`, at cost 1 when covered, else 0. Each column's
/// open run is its cells from the top down to the first that cannot be entered or is
/// covered ([`super::flood`]).
pub fn routes(field: &Field, width: f64) -> Routes {
    let r = 0.5 * width;
    let g = &field.grid;
    let nz = g.n[2];
    let fits = |q: usize| !field.solid[q] && field.clearance[q] as f64 >= r;
    let base: Vec<u32> = (0..g.columns())
        .map(|col| {
            let top = field.top[col];
            let mut k = nz;
            while k > top && fits(col * nz + k - 1) {
                k -= 1;
            }
            k as u32
        })
        .collect();
    let flood = flood(
        g,
        base,
        |q, col, k| fits(q).then(|| u32::from(k < field.top[col])),
        false,
        true,
    );
    Routes { flood }
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
/// the side it was entered from ([`super::flood`]).
#[derive(Debug, Clone)]
pub struct BreachField {
    flood: Flood,
}

impl BreachField {
    /// Solid cells crossed on the way to cell `idx`.
    pub fn cost(&self, idx: usize) -> u32 {
        self.flood.cost(idx)
    }

    /// Entry side code of the first solid cell on the way to cell `idx`.
    pub fn side(&self, idx: usize) -> u8 {
        self.flood.side(idx)
    }

    /// The first solid cell (its index) on the way to cell `idx`; `None` when the way
    /// crosses none.
    pub fn first(&self, idx: usize) -> Option<usize> {
        let f = self.flood.first(idx);
        (f != NO_CELL).then_some(f as usize)
    }

    /// The cells the search stored and visited.
    pub fn searched_cells(&self) -> usize {
        self.flood.stored_cells()
    }
}

/// The breach field of `field`: every cell can be entered, a solid one at cost 1; each
/// column's open run is its cells above the pile surface.
pub fn breach_field(field: &Field) -> BreachField {
    let base = field.top.iter().map(|t| *t as u32).collect();
    let flood = flood(
        &field.grid,
        base,
        |q, _, _| Some(u32::from(field.solid[q])),
        true,
        false,
    );
    BreachField { flood }
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
