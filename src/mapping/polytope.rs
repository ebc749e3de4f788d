//! Exact intersection of oriented boxes as a convex polyhedron (face-list clipping,
//! Sutherland–Hodgman per face plus a cap polygon on each cutting plane), and its volume
//! by decomposition into tetrahedra from the vertex centroid (valid for convex sets).

use nalgebra::{Matrix3, Vector3};

/// A convex polyhedron as a list of planar polygon faces (vertices in cyclic order).
#[derive(Debug, Clone, Default)]
pub(crate) struct Polytope {
    faces: Vec<Vec<Vector3<f64>>>,
}

/// An oriented box: centre, axes (matrix columns), half sizes.
#[derive(Debug, Clone, Copy)]
pub struct Obb {
    /// Centre (m).
    pub centre: Vector3<f64>,
    /// Columns = local x, y, z unit axes.
    pub axes: Matrix3<f64>,
    /// Half sizes (m).
    pub half: Vector3<f64>,
}

impl Obb {
    /// Corner `(±, ±, ±)`, bits of `i` choosing the signs.
    fn corner(&self, i: usize) -> Vector3<f64> {
        let s = |b: usize| if i >> b & 1 == 1 { 1.0 } else { -1.0 };
        self.centre
            + self.axes.column(0) * (s(0) * self.half.x)
            + self.axes.column(1) * (s(1) * self.half.y)
            + self.axes.column(2) * (s(2) * self.half.z)
    }

    /// Axis-aligned bounds (min, max) (m).
    pub fn aabb(&self) -> ([f64; 3], [f64; 3]) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for i in 0..8 {
            let c = self.corner(i);
            for k in 0..3 {
                lo[k] = lo[k].min(c[k]);
                hi[k] = hi[k].max(c[k]);
            }
        }
        (lo, hi)
    }

    /// The six bounding planes as (outward unit normal n, offset d): inside is n·p ≤ d.
    fn planes(&self) -> [(Vector3<f64>, f64); 6] {
        let mut out = [(Vector3::zeros(), 0.0); 6];
        for k in 0..3 {
            let n = self.axes.column(k).into_owned();
            let c = n.dot(&self.centre);
            out[2 * k] = (n, c + self.half[k]);
            out[2 * k + 1] = (-n, -c + self.half[k]);
        }
        out
    }
}

impl Polytope {
    /// The box as six quadrilateral faces.
    pub fn from_obb(b: &Obb) -> Self {
        // Corner index bits: 0 → x, 1 → y, 2 → z. Faces listed with consistent winding.
        const F: [[usize; 4]; 6] = [
            [1, 3, 7, 5], // +x
            [0, 4, 6, 2], // −x
            [2, 6, 7, 3], // +y
            [0, 1, 5, 4], // −y
            [4, 5, 7, 6], // +z
            [0, 2, 3, 1], // −z
        ];
        let c: Vec<Vector3<f64>> = (0..8).map(|i| b.corner(i)).collect();
        Self {
            faces: F
                .iter()
                .map(|f| f.iter().map(|&i| c[i]).collect())
                .collect(),
        }
    }

    /// All vertices (with repeats across faces).
    pub fn vertices(&self) -> impl Iterator<Item = &Vector3<f64>> {
        self.faces.iter().flatten()
    }

    /// True when nothing is left.
    pub fn is_empty(&self) -> bool {
        self.faces.is_empty()
    }

    /// Keeps the part with n·p ≤ d. `eps` (m) is the on-plane tolerance.
    pub fn clip(&self, n: &Vector3<f64>, d: f64, eps: f64) -> Self {
        // Nothing beyond the plane: unchanged (no cap, which would duplicate a coplanar face).
        if self.vertices().all(|p| n.dot(p) - d <= eps) {
            return self.clone();
        }
        let mut faces = Vec::with_capacity(self.faces.len() + 1);
        let mut cap: Vec<Vector3<f64>> = Vec::new();
        for face in &self.faces {
            let s: Vec<f64> = face.iter().map(|p| n.dot(p) - d).collect();
            if s.iter().all(|&x| x <= eps) {
                for (p, &sp) in face.iter().zip(&s) {
                    if sp.abs() <= eps {
                        cap.push(*p);
                    }
                }
                faces.push(face.clone());
                continue;
            }
            let mut out = Vec::with_capacity(face.len() + 2);
            for i in 0..face.len() {
                let j = (i + 1) % face.len();
                let (p, q, sp, sq) = (face[i], face[j], s[i], s[j]);
                if sp <= eps {
                    out.push(p);
                    if sp.abs() <= eps {
                        cap.push(p);
                    }
                }
                if (sp < -eps && sq > eps) || (sp > eps && sq < -eps) {
                    let x = p + (q - p) * (sp / (sp - sq));
                    out.push(x);
                    cap.push(x);
                }
            }
            if out.len() >= 3 {
                faces.push(out);
            }
        }
        if faces.is_empty() {
            return Self::default();
        }
        if let Some(poly) = cap_polygon(&cap, n, eps) {
            faces.push(poly);
        }
        Self { faces }
    }

    /// Volume (m³): Σ over faces and fan triangles of |det(p0 − c, pi − c, pi+1 − c)|/6,
    /// c the vertex mean (inside a convex polyhedron, so every tetrahedron is positive).
    pub fn volume(&self) -> f64 {
        let (mut c, mut k) = (Vector3::zeros(), 0usize);
        for p in self.vertices() {
            c += p;
            k += 1;
        }
        if k == 0 {
            return 0.0;
        }
        c /= k as f64;
        let mut v = 0.0;
        for f in &self.faces {
            let a = f[0] - c;
            for w in f[1..].windows(2) {
                v += a.dot(&(w[0] - c).cross(&(w[1] - c))).abs();
            }
        }
        v / 6.0
    }
}

/// Orders the points on a cutting plane into a convex polygon (deduplicated); `None` if
/// fewer than three distinct points.
fn cap_polygon(pts: &[Vector3<f64>], n: &Vector3<f64>, eps: f64) -> Option<Vec<Vector3<f64>>> {
    let mut uniq: Vec<Vector3<f64>> = Vec::new();
    for p in pts {
        if !uniq.iter().any(|q| (q - p).norm() <= 10.0 * eps) {
            uniq.push(*p);
        }
    }
    if uniq.len() < 3 {
        return None;
    }
    let c = uniq.iter().sum::<Vector3<f64>>() / uniq.len() as f64;
    let u = {
        let t = if n.x.abs() < 0.9 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        n.cross(&t).normalize()
    };
    let w = n.cross(&u);
    let mut ang: Vec<(f64, Vector3<f64>)> = uniq
        .into_iter()
        .map(|p| ((p - c).dot(&w).atan2((p - c).dot(&u)), p))
        .collect();
    ang.sort_by(|a, b| a.0.total_cmp(&b.0));
    Some(ang.into_iter().map(|(_, p)| p).collect())
}

/// The intersection of two boxes (empty polytope if disjoint).
pub(crate) fn intersect(a: &Obb, b: &Obb) -> Polytope {
    let scale = a.half.max().max(b.half.max()).max(1e-3);
    let eps = 1e-12 * scale;
    let mut p = Polytope::from_obb(b);
    for (n, d) in a.planes() {
        p = p.clip(&n, d, eps);
        if p.is_empty() {
            break;
        }
    }
    p
}

/// Exact overlap volume of two oriented boxes (m³).
pub fn overlap_volume(a: &Obb, b: &Obb) -> f64 {
    let (alo, ahi) = a.aabb();
    let (blo, bhi) = b.aabb();
    if (0..3).any(|k| alo[k] >= bhi[k] || blo[k] >= ahi[k]) {
        return 0.0;
    }
    intersect(a, b).volume()
}
