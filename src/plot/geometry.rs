//! What the ruin figures draw, in metres: box projections, drawing order, stories, the
//! original footprint, the ground level and equal-aspect axis ranges.
//!
//! * A body's **projection** on a view plane is the convex hull of its 8 box corners
//!   projected on that plane ([`crate::plan_geometry::corners`], `hull`).
//! * **Drawing order** (back to front, so nearer bodies cover farther ones): plan — by the
//!   final centre height z, ascending (upper bodies drawn over lower ones); elevation x–z
//!   (seen from −y) — by y descending; elevation y–z (seen from +x) — by x ascending.
//!   Ties by body index, so the order and the figure bytes are reproducible.
//! * **Stories**: the floor levels are the distinct undeformed centre heights (to the mm)
//!   of the active `Slab` bodies (of the `Beam` bodies when there are no slabs). A body
//!   whose undeformed centre z lies at or below level k (1 mm tolerance) and above level
//!   k − 1 belongs to story k (1 = lowest): a story is its columns and the floor on top
//!   of them. Bodies above the top level belong to the top story.
//! * **Original footprint**: the AABB of the undeformed active bodies' corners in the
//!   view's two axes (in plan, as `summary.json`'s footprint).
//! * **Ground level**: the top of the passive foundations (the base; else the lowest
//!   active corner) plus the ground's final vertical displacement (`history.csv`).
use super::{BodyInfo, RunFolder};
use crate::bullet::Pose;
use crate::plan_geometry::{corners, hull};
use std::collections::BTreeSet;

/// A projection plane of the ruin figures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum View {
    /// x to the right, y up (seen from above).
    Plan,
    /// x to the right, z up (seen from −y).
    ElevationXz,
    /// y to the right, z up (seen from +x).
    ElevationYz,
}

impl View {
    /// The world axes (0 = x, 1 = y, 2 = z) drawn horizontally and vertically.
    pub fn axes(self) -> (usize, usize) {
        match self {
            View::Plan => (0, 1),
            View::ElevationXz => (0, 2),
            View::ElevationYz => (1, 2),
        }
    }

    /// Axis names for the labels.
    pub fn axis_names(self) -> (&'static str, &'static str) {
        match self {
            View::Plan => ("x (m)", "y (m)"),
            View::ElevationXz => ("x (m)", "z (m)"),
            View::ElevationYz => ("y (m)", "z (m)"),
        }
    }

    /// Sort key of a body centre: smaller keys are farther from the viewer, drawn first.
    pub fn depth_key(self, centre: [f64; 3]) -> f64 {
        match self {
            View::Plan => centre[2],
            View::ElevationXz => -centre[1],
            View::ElevationYz => centre[0],
        }
    }
}

/// Projection of the box `half_extents` at `pose` on the view plane: convex hull of the
/// 8 projected corners, counter-clockwise, m.
pub fn project(pose: &Pose, half_extents: [f64; 3], view: View) -> Vec<[f64; 2]> {
    let (a, b) = view.axes();
    let pts: Vec<[f64; 2]> = corners(pose, half_extents)
        .iter()
        .map(|c| [c[a], c[b]])
        .collect();
    hull(&pts)
}

/// The indices `ids` in drawing order for `view` (back to front; ties by index).
pub(crate) fn draw_order(poses: &[Pose], ids: &[usize], view: View) -> Vec<usize> {
    let mut out = ids.to_vec();
    out.sort_by(|&i, &j| {
        view.depth_key(poses[i].position)
            .total_cmp(&view.depth_key(poses[j].position))
            .then(i.cmp(&j))
    });
    out
}

/// Floor levels of the undeformed building (module docs), m, ascending.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Stories {
    /// Floor levels, m.
    pub levels: Vec<f64>,
}

impl Stories {
    /// The floor levels of `bodies`.
    pub fn from_bodies(bodies: &[BodyInfo]) -> Stories {
        let levels_of = |ty: &str| -> BTreeSet<i64> {
            bodies
                .iter()
                .filter(|b| !b.passive && b.id.type_name() == ty)
                .map(|b| (b.pose0.position[2] * 1000.0).round() as i64)
                .collect()
        };
        let mut mm = levels_of("Slab");
        if mm.is_empty() {
            mm = levels_of("Beam");
        }
        Stories {
            levels: mm.into_iter().map(|v| v as f64 / 1000.0).collect(),
        }
    }

    /// Number of stories (at least 1).
    pub fn count(&self) -> usize {
        self.levels.len().max(1)
    }

    /// Story (1-based) of a body whose undeformed centre is at height `z0`, m.
    pub fn of(&self, z0: f64) -> usize {
        let below = self.levels.iter().filter(|&&l| l < z0 - 1e-3).count();
        (below + 1).min(self.count())
    }
}

/// An axis-aligned rectangle in a view plane, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// Horizontal range.
    pub x: [f64; 2],
    /// Vertical range.
    pub y: [f64; 2],
}

impl Bounds {
    /// The bounds of `points` (None when empty or not finite).
    pub fn of(points: impl IntoIterator<Item = [f64; 2]>) -> Option<Bounds> {
        let mut b: Option<Bounds> = None;
        for p in points {
            if !(p[0].is_finite() && p[1].is_finite()) {
                continue;
            }
            let q = Bounds {
                x: [p[0], p[0]],
                y: [p[1], p[1]],
            };
            b = Some(b.map_or(q, |b| b.union(&q)));
        }
        b
    }

    /// Smallest rectangle holding both.
    pub fn union(&self, o: &Bounds) -> Bounds {
        Bounds {
            x: [self.x[0].min(o.x[0]), self.x[1].max(o.x[1])],
            y: [self.y[0].min(o.y[0]), self.y[1].max(o.y[1])],
        }
    }

    /// Widened by `frac` of the larger side on every side (at least `min_m`).
    pub fn padded(&self, frac: f64, min_m: f64) -> Bounds {
        let side = (self.x[1] - self.x[0]).max(self.y[1] - self.y[0]);
        let p = (frac * side).max(min_m);
        Bounds {
            x: [self.x[0] - p, self.x[1] + p],
            y: [self.y[0] - p, self.y[1] + p],
        }
    }

    /// Widened so that one metre spans the same number of pixels on both axes of a
    /// `px_w` × `px_h` plotting area (equal aspect): horizontally about the centre,
    /// vertically about the centre or, with `keep_bottom`, upwards only (elevations: the
    /// ground stays near the bottom).
    pub fn equal_aspect(&self, px_w: u32, px_h: u32, keep_bottom: bool) -> Bounds {
        let (w, h) = (self.x[1] - self.x[0], self.y[1] - self.y[0]);
        let (pw, ph) = (f64::from(px_w.max(1)), f64::from(px_h.max(1)));
        // metres per pixel: the larger of the two fits both
        let m = (w / pw).max(h / ph);
        let (cx, cy) = (0.5 * (self.x[0] + self.x[1]), 0.5 * (self.y[0] + self.y[1]));
        let (hw, hh) = (0.5 * m * pw, 0.5 * m * ph);
        let y = if keep_bottom {
            [self.y[0], self.y[0] + 2.0 * hh]
        } else {
            [cy - hh, cy + hh]
        };
        Bounds {
            x: [cx - hw, cx + hw],
            y,
        }
    }
}

/// The original footprint in `view` (module docs); None without active bodies.
pub(crate) fn original_outline(bodies: &[BodyInfo], view: View) -> Option<Bounds> {
    Bounds::of(
        bodies
            .iter()
            .filter(|b| !b.passive)
            .flat_map(|b| project(&b.pose0, b.half_extents, view)),
    )
}

/// The base level: top of the passive foundations, else the lowest active corner, m.
pub(crate) fn base_level(bodies: &[BodyInfo]) -> Option<f64> {
    let top = |passive: bool, f: fn(f64, f64) -> f64, init: f64| {
        bodies
            .iter()
            .filter(|b| b.passive == passive)
            .flat_map(|b| corners(&b.pose0, b.half_extents))
            .map(|c| c[2])
            .fold(init, f)
    };
    let passive_top = top(true, f64::max, f64::NEG_INFINITY);
    if passive_top.is_finite() {
        return Some(passive_top);
    }
    let lowest = top(false, f64::min, f64::INFINITY);
    lowest.is_finite().then_some(lowest)
}

/// The ground level at the end of the run: base level + final ground z displacement, m.
pub(crate) fn final_ground_level(run: &RunFolder) -> Option<f64> {
    let gz = run.history.last().map_or(0.0, |h| h.ground_m[2]);
    base_level(&run.bodies).map(|b| b + gz)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::BodyId;

    fn body(ty: &str, z: f64, passive: bool) -> BodyInfo {
        BodyInfo {
            id: BodyId::element(ty.into(), "1", (z * 1e4).round().abs() as u32),
            passive,
            pose0: Pose::at([0.0, 0.0, z]),
            half_extents: [0.5, 0.25, 0.1],
            mass_kg: 1.0,
        }
    }

    #[test]
    fn stories_from_slab_levels() {
        let b = vec![
            body("Foundation", -0.2, true),
            body("Column", 1.5, false),
            body("Beam", 2.8, false),
            body("Slab", 3.0, false),
            body("Column", 4.5, false),
            body("Slab", 6.0, false),
            body("Slab", 6.0004, false),
        ];
        let s = Stories::from_bodies(&b);
        assert_eq!(s.levels, vec![3.0, 6.0]);
        assert_eq!(s.count(), 2);
        assert_eq!(s.of(1.5), 1);
        assert_eq!(s.of(2.8), 1);
        assert_eq!(s.of(3.0), 1);
        assert_eq!(s.of(4.5), 2);
        assert_eq!(s.of(6.0004), 2);
        assert_eq!(s.of(7.0), 2);
        // no slabs: beams give the levels; neither: one story
        assert_eq!(Stories::from_bodies(&b[..3]).levels, vec![2.8]);
        assert_eq!(Stories::from_bodies(&b[..2]).count(), 1);
    }

    #[test]
    fn projection_of_a_turned_box() {
        // 90° about z: the 1.0 × 0.5 box becomes 0.5 × 1.0 in plan
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let pose = Pose {
            position: [2.0, 3.0, 1.0],
            orientation: [h, 0.0, 0.0, h],
        };
        let p = project(&pose, [0.5, 0.25, 0.1], View::Plan);
        let b = Bounds::of(p.iter().copied()).unwrap();
        assert!((b.x[0] - 1.75).abs() < 1e-12 && (b.x[1] - 2.25).abs() < 1e-12);
        assert!((b.y[0] - 2.5).abs() < 1e-12 && (b.y[1] - 3.5).abs() < 1e-12);
        assert_eq!(p.len(), 4);
        let e = project(&pose, [0.5, 0.25, 0.1], View::ElevationYz);
        let b = Bounds::of(e.iter().copied()).unwrap();
        assert!((b.x[0] - 2.5).abs() < 1e-12 && (b.y[1] - 1.1).abs() < 1e-12);
    }

    #[test]
    fn order_back_to_front() {
        let poses = vec![
            Pose::at([0.0, 5.0, 3.0]),
            Pose::at([1.0, 0.0, 1.0]),
            Pose::at([-1.0, 2.0, 3.0]),
        ];
        let ids = [0, 1, 2];
        assert_eq!(draw_order(&poses, &ids, View::Plan), vec![1, 0, 2]);
        assert_eq!(draw_order(&poses, &ids, View::ElevationXz), vec![0, 2, 1]);
        assert_eq!(draw_order(&poses, &ids, View::ElevationYz), vec![2, 0, 1]);
    }

    #[test]
    fn equal_aspect_keeps_metres_per_pixel() {
        let b = Bounds {
            x: [0.0, 10.0],
            y: [0.0, 2.0],
        };
        let e = b.equal_aspect(500, 400, false);
        let mx = (e.x[1] - e.x[0]) / 500.0;
        let my = (e.y[1] - e.y[0]) / 400.0;
        assert!((mx - my).abs() < 1e-12);
        assert!((mx - 0.02).abs() < 1e-12);
        assert!((e.y[0] + 3.0).abs() < 1e-12 && (e.y[1] - 5.0).abs() < 1e-12);
        let e = b.equal_aspect(500, 400, true);
        assert!(e.y[0].abs() < 1e-12 && (e.y[1] - 8.0).abs() < 1e-12);
        // a tall box widens horizontally about its centre
        let t = Bounds {
            x: [0.0, 1.0],
            y: [0.0, 8.0],
        }
        .equal_aspect(500, 400, true);
        assert!((t.x[0] + 4.5).abs() < 1e-12 && (t.x[1] - 5.5).abs() < 1e-12);
        assert!(t.y[0].abs() < 1e-12 && (t.y[1] - 8.0).abs() < 1e-12);
    }

    #[test]
    fn base_is_top_of_foundations() {
        let b = vec![body("Foundation", -0.2, true), body("Column", 1.5, false)];
        assert!((base_level(&b).unwrap() + 0.1).abs() < 1e-12);
        assert!((base_level(&b[1..]).unwrap() - 1.4).abs() < 1e-12);
    }
}
