//! The route of an access as a line: the cells a rescuer or a camera passes from open air
//! to the void, as a polyline of cell centres simplified to within one cell.
//!
//! * The access search ([`super::access`]) records for every cell the step that first
//!   reached it at its least cost; following those steps back from the void's reached
//!   cell gives one least-cost route to it, back to where it started in open air.
//! * The route is drawn from where it **leaves open air**: the last cell that is not under
//!   debris before its first covered cell (the open air before that is free to walk and
//!   its cells carry no meaning). A route whose first cell is already covered (at the
//!   grid's side) starts one cell outside the grid.
//! * The cell centres are simplified by Douglas–Peucker (Douglas & Peucker 1973, "Algorithms
//!   for the reduction of the number of points required to represent a digitized line or
//!   its caricature", The Canadian Cartographer 10(2) 112–122) with the tolerance
//!   [`TOLERANCE_CELLS`] × h: every cell centre of the route lies within one cell edge of the
//!   polyline, whose points are cell centres of the route, first and last kept. A straight
//!   corridor is two points, a staircase of steps along a diagonal one segment, a bend its
//!   corner. The line may cut a corner of debris by up to that tolerance; it stands for the
//!   route, the cells are the route.
use super::access::{Routes, NO_SIDE};
use super::voids::Field;

/// The simplification tolerance in cell edges (m = this × h).
pub const TOLERANCE_CELLS: f64 = 1.0;

/// The cells of the least-cost route to `cell` along `routes`, from its first cell (on the
/// grid's side or top) to `cell`.
pub fn cells(field: &Field, routes: &Routes, cell: usize) -> Vec<usize> {
    let g = &field.grid;
    let mut path = vec![cell];
    let mut c = cell;
    while routes.from(c) != NO_SIDE {
        let code = routes.from(c);
        let axis = usize::from(code / 2);
        let mut q = g.ijk(c);
        // The step went towards + for odd codes: the cell before lies at −1.
        if code % 2 == 1 {
            q[axis] -= 1;
        } else {
            q[axis] += 1;
        }
        c = g.index(q[0], q[1], q[2]);
        path.push(c);
        assert!(path.len() <= g.len(), "a route has no cycle");
    }
    path.reverse();
    path
}

/// The route to `cell` as a polyline, m: from where it leaves open air (module docs) to
/// the centre of `cell`, simplified to within [`TOLERANCE_CELLS`] × h.
pub fn polyline(field: &Field, routes: &Routes, cell: usize) -> Vec<[f64; 3]> {
    let g = &field.grid;
    let path = cells(field, routes, cell);
    let first_covered = path
        .iter()
        .position(|&c| field.covered(c))
        .unwrap_or(path.len() - 1);
    let mut points: Vec<[f64; 3]> = Vec::with_capacity(path.len() + 1);
    if first_covered == 0 {
        // Entered from outside the grid: one cell beyond its side (or top).
        let c = g.ijk(path[0]);
        let mut p = g.centre(c);
        let code = super::access::boundary_code(g, path[0]);
        let axis = usize::from(code / 2);
        p[axis] += if code % 2 == 1 { -g.h } else { g.h };
        points.push(p);
    }
    let start = first_covered.saturating_sub(1);
    points.extend(path[start..].iter().map(|&c| g.centre(g.ijk(c))));
    simplify(&points, TOLERANCE_CELLS * g.h)
}

/// Distance from `p` to the segment `a`–`b`, m.
pub fn segment_distance(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = [0, 1, 2].map(|k| b[k] - a[k]);
    let ap = [0, 1, 2].map(|k| p[k] - a[k]);
    let len2: f64 = ab.iter().map(|x| x * x).sum();
    let t = if len2 > 0.0 {
        (ab.iter().zip(&ap).map(|(x, y)| x * y).sum::<f64>() / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (0..3)
        .map(|k| (ap[k] - t * ab[k]).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// Douglas–Peucker: the points of `points` to keep so that every point lies within `tol`
/// of the polyline through them (first and last always kept; of equally far points the
/// first is kept).
pub fn simplify(points: &[[f64; 3]], tol: f64) -> Vec<[f64; 3]> {
    if points.len() <= 2 {
        return points.to_vec();
    }
    let mut keep = vec![false; points.len()];
    keep[0] = true;
    keep[points.len() - 1] = true;
    let mut stack = vec![(0, points.len() - 1)];
    while let Some((a, b)) = stack.pop() {
        let mut far = (0.0, a);
        for (i, p) in points.iter().enumerate().take(b).skip(a + 1) {
            let d = segment_distance(*p, points[a], points[b]);
            if d > far.0 {
                far = (d, i);
            }
        }
        if far.0 > tol {
            keep[far.1] = true;
            stack.push((a, far.1));
            stack.push((far.1, b));
        }
    }
    points
        .iter()
        .zip(&keep)
        .filter(|(_, k)| **k)
        .map(|(p, _)| *p)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn max_off(points: &[[f64; 3]], line: &[[f64; 3]]) -> f64 {
        points
            .iter()
            .map(|p| {
                line.windows(2)
                    .map(|s| segment_distance(*p, s[0], s[1]))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn a_straight_run_of_cells_is_one_segment() {
        let pts: Vec<[f64; 3]> = (0..10).map(|i| [i as f64, 2.0, 3.0]).collect();
        assert_eq!(simplify(&pts, 1.0), vec![[0.0, 2.0, 3.0], [9.0, 2.0, 3.0]]);
    }

    /// An L of cell steps keeps its corner; a staircase along the diagonal (steps x, y,
    /// x, y, …) lies within 1/√2 of the diagonal and simplifies to it.
    #[test]
    fn an_l_keeps_its_corner_and_a_staircase_is_its_diagonal() {
        let mut l: Vec<[f64; 3]> = (0..=5).map(|i| [i as f64, 0.0, 0.0]).collect();
        l.extend((1..=5).map(|j| [5.0, j as f64, 0.0]));
        let s = simplify(&l, 1.0);
        assert_eq!(s, vec![[0.0, 0.0, 0.0], [5.0, 0.0, 0.0], [5.0, 5.0, 0.0]]);
        let mut st = vec![[0.0, 0.0, 0.0]];
        for n in 0..6 {
            let p = *st.last().unwrap();
            st.push(if n % 2 == 0 {
                [p[0] + 1.0, p[1], 0.0]
            } else {
                [p[0], p[1] + 1.0, 0.0]
            });
        }
        let s = simplify(&st, 1.0);
        assert_eq!(s, vec![[0.0, 0.0, 0.0], [3.0, 3.0, 0.0]]);
        assert!((max_off(&st, &s) - 0.5f64.sqrt()).abs() < 1e-12);
    }

    /// On a random walk every point lies within the tolerance of the simplified line, and
    /// its points are the walk's own, in order.
    #[test]
    fn every_cell_lies_within_the_tolerance() {
        let mut seed = 12345u64;
        let mut pts = vec![[0.0f64; 3]];
        for _ in 0..400 {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
            let r = (seed >> 33) % 6;
            let mut p = *pts.last().unwrap();
            p[(r / 2) as usize] += if r % 2 == 0 { 1.0 } else { -1.0 };
            pts.push(p);
        }
        for tol in [0.5, 1.0, 3.0] {
            let s = simplify(&pts, tol);
            assert!(max_off(&pts, &s) <= tol + 1e-12, "tolerance {tol}");
            let mut at = 0;
            for p in &s {
                at += pts[at..].iter().position(|q| q == p).expect("a walk point");
            }
            assert!(s.len() < pts.len());
        }
    }
}
