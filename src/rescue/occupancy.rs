//! Occupancy: the fraction of every cell's volume that the debris boxes cover, exactly.
//!
//! A box (centre `c`, unit axes `n₁ n₂ n₃`, half extents `e`) is the intersection of six
//! half-spaces `±nₐ·(x − c) ≤ eₐ`. The part of a cell inside the box is the cell (a cube,
//! a convex polyhedron) clipped by those half-spaces: each face polygon is clipped by the
//! plane (Sutherland–Hodgman) and the points on the plane close the cut as a new face.
//! Its volume is the divergence theorem over the closed surface,
//! `V = ⅙ Σ_faces Σ_triangles p₀·(pᵢ × pᵢ₊₁)` (faces counter-clockwise seen from outside).
//! Planes that do not cut the cell are skipped (the cell's support along `nₐ` is
//! `h/2 · (|nₐₓ| + |nₐᵧ| + |nₐ𝑧|)`): a cell wholly inside costs nothing, one wholly outside
//! is rejected. Only the cells of each box's axis-aligned bounding box are visited.
//!
//! Overlapping boxes (the little interpenetration of a ruin) are summed and the fraction
//! capped at 1. Each cell also records the box that covers most of it (its owner), to
//! name a void's roof and floor.
use super::grid::Grid;
use super::input::RuinBox;

/// A point or vector, m.
type V = [f64; 3];

fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: V, b: V) -> V {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// A convex polyhedron as its faces' vertex lists laid end to end: face `f` is
/// `verts[starts[f]..starts[f + 1]]`, outward counter-clockwise.
#[derive(Debug, Clone, Default)]
struct Polyhedron {
    verts: Vec<V>,
    starts: Vec<usize>,
}

impl Polyhedron {
    fn clear(&mut self) {
        self.verts.clear();
        self.starts.clear();
        self.starts.push(0);
    }

    fn faces(&self) -> usize {
        self.starts.len() - 1
    }

    fn face(&self, f: usize) -> &[V] {
        &self.verts[self.starts[f]..self.starts[f + 1]]
    }

    /// Ends the face begun after the last one ended.
    fn close_face(&mut self) {
        self.starts.push(self.verts.len());
    }

    /// Drops the face begun after the last one ended.
    fn drop_open_face(&mut self) {
        self.verts
            .truncate(*self.starts.last().expect("starts holds 0"));
    }

    fn open_face_len(&self) -> usize {
        self.verts.len() - self.starts.last().expect("starts holds 0")
    }
}

/// The clip's working storage, reused from cell to cell so that clipping allocates
/// nothing once it has grown to the largest cut.
#[derive(Debug, Clone, Default)]
pub struct Clipper {
    poly: Polyhedron,
    out: Polyhedron,
    cap: Vec<V>,
    keyed: Vec<(f64, V)>,
}

impl Clipper {
    /// Sets the polyhedron to the cube `[-a, a]³`.
    fn cube(&mut self, a: f64) {
        let m = -a;
        let faces: [[V; 4]; 6] = [
            [[a, m, m], [a, a, m], [a, a, a], [a, m, a]],
            [[m, m, m], [m, m, a], [m, a, a], [m, a, m]],
            [[m, a, m], [m, a, a], [a, a, a], [a, a, m]],
            [[m, m, m], [a, m, m], [a, m, a], [m, m, a]],
            [[m, m, a], [a, m, a], [a, a, a], [m, a, a]],
            [[m, m, m], [m, a, m], [a, a, m], [a, m, m]],
        ];
        self.poly.clear();
        for f in faces {
            self.poly.verts.extend_from_slice(&f);
            self.poly.close_face();
        }
    }

    /// Clips the polyhedron to the half-space `n·x ≤ d` (`n` a unit vector); `tol` is
    /// the length below which two points are one.
    fn clip(&mut self, n: V, d: f64, tol: f64) {
        let out = &mut self.out;
        out.clear();
        let cap = &mut self.cap;
        cap.clear();
        for fi in 0..self.poly.faces() {
            let f = self.poly.face(fi);
            for i in 0..f.len() {
                let (p, q) = (f[i], f[(i + 1) % f.len()]);
                let (sp, sq) = (dot(n, p) - d, dot(n, q) - d);
                if sp <= 0.0 {
                    out.verts.push(p);
                    if sp >= -tol {
                        cap.push(p);
                    }
                }
                if (sp < 0.0 && sq > 0.0) || (sp > 0.0 && sq < 0.0) {
                    let t = sp / (sp - sq);
                    let x = [
                        p[0] + t * (q[0] - p[0]),
                        p[1] + t * (q[1] - p[1]),
                        p[2] + t * (q[2] - p[2]),
                    ];
                    out.verts.push(x);
                    cap.push(x);
                }
            }
            if out.open_face_len() >= 3 {
                out.close_face();
            } else {
                out.drop_open_face();
            }
        }
        if cap.len() >= 3 {
            // Order the cut's points counter-clockwise about +n (its outward normal).
            let m = cap
                .iter()
                .fold([0.0; 3], |s, p| [s[0] + p[0], s[1] + p[1], s[2] + p[2]]);
            let m = m.map(|v| v / cap.len() as f64);
            let helper = if n[0].abs() < 0.9 {
                [1.0, 0.0, 0.0]
            } else {
                [0.0, 1.0, 0.0]
            };
            let u = cross(n, helper);
            let un = dot(u, u).sqrt();
            let u = u.map(|c| c / un);
            let v = cross(n, u);
            let keyed = &mut self.keyed;
            keyed.clear();
            keyed.extend(cap.iter().map(|p| {
                let r = sub(*p, m);
                (dot(r, v).atan2(dot(r, u)), *p)
            }));
            keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
            let near = |p: V, q: V| dot(sub(p, q), sub(p, q)) <= tol * tol;
            let ring0 = out.verts.len();
            for &(_, p) in keyed.iter() {
                if out.verts.len() == ring0 || !near(p, out.verts[out.verts.len() - 1]) {
                    out.verts.push(p);
                }
            }
            while out.verts.len() - ring0 > 1
                && near(out.verts[ring0], out.verts[out.verts.len() - 1])
            {
                out.verts.pop();
            }
            if out.open_face_len() >= 3 {
                out.close_face();
            } else {
                out.drop_open_face();
            }
        }
        std::mem::swap(&mut self.poly, &mut self.out);
    }

    /// The volume enclosed by the polyhedron.
    fn volume(&self) -> f64 {
        let mut v = 0.0;
        for fi in 0..self.poly.faces() {
            let f = self.poly.face(fi);
            for i in 1..f.len() - 1 {
                v += dot(f[0], cross(f[i], f[i + 1]));
            }
        }
        v / 6.0
    }

    /// The volume (m³) of the intersection of the cube of edge `h` centred at the origin
    /// with the box of centre `c` (relative to the cube's centre), unit axes `axes` and
    /// half extents `e`.
    pub fn overlap(&mut self, h: f64, c: V, axes: [V; 3], e: V) -> f64 {
        let a = 0.5 * h;
        let mut cutting = [([0.0; 3], 0.0); 6];
        let mut cuts = 0;
        for (n, ea) in axes.iter().zip(e) {
            let r = a * (n[0].abs() + n[1].abs() + n[2].abs());
            let s = dot(*n, c);
            // n·x ≤ s + ea and −n·x ≤ ea − s.
            for (nn, d) in [(*n, s + ea), (n.map(|v| -v), ea - s)] {
                if d <= -r {
                    return 0.0;
                }
                if d < r {
                    cutting[cuts] = (nn, d);
                    cuts += 1;
                }
            }
        }
        if cuts == 0 {
            return h * h * h;
        }
        let tol = 1e-12 * h;
        self.cube(a);
        for &(n, d) in &cutting[..cuts] {
            self.clip(n, d, tol);
            if self.poly.faces() < 4 {
                return 0.0;
            }
        }
        self.volume().clamp(0.0, h * h * h)
    }
}

/// The volume (m³) of the intersection of the cube of edge `h` centred at the origin with
/// the box of centre `c` (relative to the cube's centre), unit axes `axes` and half extents
/// `e` ([`Clipper::overlap`] with working storage of its own).
pub fn cube_box_overlap(h: f64, c: V, axes: [V; 3], e: V) -> f64 {
    Clipper::default().overlap(h, c, axes, e)
}

/// The occupancy of a grid.
#[derive(Debug, Clone)]
pub struct Occupancy {
    /// Covered fraction of each cell, in [0, 1].
    pub fraction: Vec<f32>,
    /// The box covering most of each cell (index into the ruin's boxes), `u32::MAX` for
    /// none.
    pub owner: Vec<u32>,
}

/// The occupancy of `grid` by the active (non-passive) `boxes` at their final poses.
pub fn occupancy(grid: &Grid, boxes: &[RuinBox]) -> Occupancy {
    occupancy_rows(grid, boxes, 0..grid.n[1])
}

/// The occupancy of the cells of `grid` in the rows `rows` (`j` in that range, every `i`
/// and `k`): entry `idx − grid.index(0, rows.start, 0)` of each array is cell `idx`. Each
/// cell's value is the same as in the whole grid's [`occupancy`] (the boxes are taken in
/// the same order, the cells' centres from the same grid).
pub fn occupancy_rows(grid: &Grid, boxes: &[RuinBox], rows: std::ops::Range<usize>) -> Occupancy {
    let base = grid.index(0, rows.start, 0);
    let len = rows.len() * grid.n[0] * grid.n[2];
    let mut fraction = vec![0.0f32; len];
    let mut best = vec![0.0f32; len];
    let mut owner = vec![u32::MAX; len];
    let h = grid.h;
    let cell_volume = h * h * h;
    let mut clipper = Clipper::default();
    for (bi, b) in boxes.iter().enumerate() {
        if b.passive {
            continue;
        }
        let r = RuinBox::axes(&b.pose);
        let axes = [0, 1, 2].map(|k| [r[(0, k)], r[(1, k)], r[(2, k)]]);
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for c in b.corners_at(&b.pose) {
            for d in 0..3 {
                lo[d] = lo[d].min(c[d]);
                hi[d] = hi[d].max(c[d]);
            }
        }
        let range = |d: usize| -> Option<(usize, usize)> {
            let a = ((lo[d] - grid.origin[d]) / h).floor();
            let z = ((hi[d] - grid.origin[d]) / h).ceil();
            let a = a.max(0.0);
            let z = z.min(grid.n[d] as f64);
            (z > a).then_some((a as usize, z as usize))
        };
        let (Some((i0, i1)), Some((j0, j1)), Some((k0, k1))) = (range(0), range(1), range(2))
        else {
            continue;
        };
        for j in j0.max(rows.start)..j1.min(rows.end) {
            for i in i0..i1 {
                for k in k0..k1 {
                    let cc = grid.centre([i, j, k]);
                    let rel = sub(b.pose.position, cc);
                    let v = clipper.overlap(h, rel, axes, b.half_extents);
                    if v <= 0.0 {
                        continue;
                    }
                    let f = (v / cell_volume) as f32;
                    let idx = grid.index(i, j, k) - base;
                    fraction[idx] = (fraction[idx] + f).min(1.0);
                    if f > best[idx] {
                        best[idx] = f;
                        owner[idx] = bi as u32;
                    }
                }
            }
        }
    }
    Occupancy { fraction, owner }
}

#[cfg(test)]
mod tests {
    use super::*;

    const X: [V; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

    /// A half-space through the cube's centre halves it, tilted or not.
    #[test]
    fn a_plane_through_the_centre_halves_the_cube() {
        // A box with a huge extent on one side of a plane through the centre.
        let big = 100.0;
        for axes in [X, rotated(0.3, 0.7)] {
            let n = axes[2];
            let c = n.map(|v| -v * big);
            let v = cube_box_overlap(1.0, c, axes, [big, big, big]);
            assert!((v - 0.5).abs() < 1e-12, "{v}");
        }
    }

    /// A corner cut `x + y + z ≥ 3a − t·√3` of the cube [−a, a]³ is a tetrahedron of
    /// volume (√3 t)³ / 6 (legs of √3 t).
    #[test]
    fn a_corner_cut_is_a_tetrahedron() {
        let s = 1.0 / 3f64.sqrt();
        let n = [s, s, s];
        // Axes: n and two perpendiculars.
        let u = [
            s * 3f64.sqrt() / 2f64.sqrt(),
            -s * 3f64.sqrt() / 2f64.sqrt(),
            0.0,
        ];
        let w = cross(n, u);
        let axes = [u, w, n];
        let (a, t) = (0.5, 0.2);
        // Plane n·x = 3a/√3 − t; the box lies beyond it with half extent 50.
        let d = 3.0 * a * s - t;
        let c = n.map(|v| v * (d + 50.0));
        let v = cube_box_overlap(1.0, c, axes, [50.0, 50.0, 50.0]);
        let leg = 3f64.sqrt() * t;
        assert!((v - leg.powi(3) / 6.0).abs() < 1e-12, "{v}");
    }

    /// A box over x 0.5–2.0, y 0.5–3.5, z 0.5–1.5 m on a grid of 3 × 4 × 2 unit cells
    /// from the origin: a cell's fraction is the product of its overlaps along the axes
    /// (x 0.5, 1, 0; y 0.5, 1, 1, 0.5; z 0.5, 0.5). Rows 1–2 alone hold those cells' values
    /// at their offset from row 1, and rows 0–1 and 2–3 laid end to end are the whole grid's
    /// arrays, bit for bit.
    #[test]
    fn rows_of_the_grid_hold_the_cells_of_the_whole() {
        let grid = Grid {
            origin: [0.0; 3],
            h: 1.0,
            n: [3, 4, 2],
        };
        let pose = crate::bullet::Pose::at([1.25, 2.0, 1.0]);
        let b = RuinBox {
            id: "Slab:1:1".parse().unwrap(),
            passive: false,
            pose0: pose,
            pose,
            half_extents: [0.75, 1.5, 0.5],
        };
        let boxes = [b];
        let rows = occupancy_rows(&grid, &boxes, 1..3);
        assert_eq!(rows.fraction.len(), 12);
        let base = grid.index(0, 1, 0);
        let at = |i, j, k| grid.index(i, j, k) - base;
        for (i, j, k, want) in [
            (1, 1, 0, 0.5),
            (0, 2, 1, 0.25),
            (1, 2, 1, 0.5),
            (0, 1, 0, 0.25),
            (2, 1, 0, 0.0),
        ] {
            let f = rows.fraction[at(i, j, k)] as f64;
            assert!((f - want).abs() < 1e-6, "cell ({i}, {j}, {k}): {f}");
            let owner = if want > 0.0 { 0 } else { u32::MAX };
            assert_eq!(rows.owner[at(i, j, k)], owner);
        }
        let whole = occupancy(&grid, &boxes);
        let (a, z) = (
            occupancy_rows(&grid, &boxes, 0..2),
            occupancy_rows(&grid, &boxes, 2..4),
        );
        let bits = |v: &[f32]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
        assert_eq!(
            bits(&[a.fraction, z.fraction].concat()),
            bits(&whole.fraction)
        );
        assert_eq!([a.owner, z.owner].concat(), whole.owner);
        assert!((whole.fraction[grid.index(0, 0, 0)] as f64 - 0.125).abs() < 1e-6);
    }

    fn rotated(ax: f64, az: f64) -> [V; 3] {
        let (ca, sa, cz, sz) = (ax.cos(), ax.sin(), az.cos(), az.sin());
        // R = Rz(az) · Rx(ax); columns are the box axes.
        let r = [
            [cz, -sz * ca, sz * sa],
            [sz, cz * ca, -cz * sa],
            [0.0, sa, ca],
        ];
        [0, 1, 2].map(|k| [r[0][k], r[1][k], r[2][k]])
    }

    /// Summed over a grid, the overlaps give the box's volume to rounding, whatever its
    /// orientation.
    #[test]
    fn overlaps_sum_to_the_box_volume() {
        let axes = rotated(0.4, 1.1);
        let e = [0.37, 0.21, 0.13];
        let h = 0.05;
        let c0 = [0.013, -0.027, 0.004];
        let mut total = 0.0;
        let n = 24i32;
        for i in -n..n {
            for j in -n..n {
                for k in -n..n {
                    let cc = [i as f64 * h, j as f64 * h, k as f64 * h];
                    total += cube_box_overlap(h, sub(c0, cc), axes, e);
                }
            }
        }
        let exact = 8.0 * e[0] * e[1] * e[2];
        assert!((total - exact).abs() < 1e-12, "{total} vs {exact}");
    }
}
