//! The report's poses as 16-bit integers: 14 bytes per body and frame (three `u16`
//! coordinates, four `i16` quaternion components) instead of 28 as float32, so that a
//! building of 2 700 bodies over its whole timeline fits a page a browser opens
//! comfortably. Every keyframe is kept; only the resolution of a pose is bounded.
//!
//! * **Positions** (box centres): one grid for the whole run, origin at the smallest
//!   centre coordinate of every axis over all frames and bodies, one step for all axes,
//!   `step = s / 65 535` with `s` the largest of the three spans (max − min) of the
//!   centres. A coordinate is stored as `round((x − origin) / step)` in 0…65 535 and read
//!   back as `origin + step · n`: its error is at most `step / 2` (frame3 LC5: a span of
//!   5.0 m, step 0.076 mm; the library building: 88 m, 1.3 mm).
//! * **Rotations** (unit quaternions, three.js order x, y, z, w): each component stored
//!   as `round(32 767 · q)` and read back divided by 32 767 and normalised. Each
//!   component is off by at most `1 / 65 534`, the quaternion by at most
//!   `2 / 65 534 = 3.05·10⁻⁵` (four components), so the rotation it stands for by at most
//!   twice that angle, `6.1·10⁻⁵` rad, since a unit quaternion's angle is half the
//!   rotation's: a box corner at distance `r` from the centre moves at most
//!   `6.1·10⁻⁵ · r` (0.3 mm at 5 m).
//!
//! Both are little-endian in base64 ([`super::base64`]), read by the page into
//! `Uint16Array` and `Int16Array`.

/// The largest position code: `u16::MAX` steps span the run's largest extent.
pub const POSITION_LEVELS: f64 = 65_535.0;

/// The scale of a quaternion component: `i16::MAX`, so that ±1 is representable.
pub const QUATERNION_SCALE: f64 = 32_767.0;

/// Bound on the rotation angle between a unit quaternion and its stored form, rad:
/// twice the largest change of the quaternion's direction, `2 · 2 / (2 · 32 767)`.
pub const ROTATION_ERROR_RAD: f64 = 2.0 * 2.0 / (2.0 * QUATERNION_SCALE);

/// The grid positions are stored on: `x = origin + step · n`, `n` in 0…65 535.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PositionGrid {
    /// The smallest coordinate of each axis, m.
    pub origin: [f64; 3],
    /// The step of every axis, m (1 when all points coincide).
    pub step: f64,
}

impl PositionGrid {
    /// The grid covering `points` (module docs); `origin` 0 and `step` 1 for no points.
    pub fn covering(points: impl IntoIterator<Item = [f64; 3]>) -> Self {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in points {
            for c in 0..3 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
        }
        if lo[0] > hi[0] {
            return Self {
                origin: [0.0; 3],
                step: 1.0,
            };
        }
        let span = (0..3).map(|c| hi[c] - lo[c]).fold(0.0, f64::max);
        Self {
            origin: lo,
            step: if span > 0.0 {
                span / POSITION_LEVELS
            } else {
                1.0
            },
        }
    }

    /// The codes of `p` (a point inside the grid's box; outside it the nearest code).
    pub fn encode(&self, p: [f64; 3]) -> [u16; 3] {
        std::array::from_fn(|c| {
            ((p[c] - self.origin[c]) / self.step)
                .round()
                .clamp(0.0, POSITION_LEVELS) as u16
        })
    }

    /// The point of `codes`, as the page computes it.
    pub fn decode(&self, codes: [u16; 3]) -> [f64; 3] {
        std::array::from_fn(|c| self.origin[c] + self.step * f64::from(codes[c]))
    }
}

/// The stored form of a unit quaternion (any component order).
pub fn quaternion_codes(q: [f64; 4]) -> [i16; 4] {
    q.map(|v| {
        (v * QUATERNION_SCALE)
            .round()
            .clamp(-QUATERNION_SCALE, QUATERNION_SCALE) as i16
    })
}

/// The unit quaternion of `codes`, as the page computes it (divided by the scale and
/// normalised).
pub fn quaternion_decode(codes: [i16; 4]) -> [f64; 4] {
    let q = codes.map(|c| f64::from(c) / QUATERNION_SCALE);
    let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    q.map(|v| v / n)
}

/// The rotation angle between two unit quaternions, rad: `2 acos |q₁ · q₂|`.
pub fn rotation_angle(a: [f64; 4], b: [f64; 4]) -> f64 {
    let dot: f64 = (0..4).map(|k| a[k] * b[k]).sum();
    2.0 * dot.abs().min(1.0).acos()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_by_hand() {
        // Span 65.535 m along x → step 1 mm; 1.2344 m from the origin is code 1234.
        let g = PositionGrid::covering([[10.0, -2.0, 0.5], [75.535, 3.0, 0.5]]);
        assert_eq!(g.origin, [10.0, -2.0, 0.5]);
        assert!((g.step - 0.001).abs() < 1e-15, "{}", g.step);
        assert_eq!(g.encode([11.2344, -2.0, 0.5]), [1234, 0, 0]);
        assert_eq!(g.encode([75.535, 3.0, 0.5]), [65_535, 5000, 0]);
        let back = g.decode([1234, 5000, 7]);
        assert!((back[0] - 11.234).abs() < 1e-12, "{back:?}");
        assert!((back[1] - 3.0).abs() < 1e-12, "{back:?}");
        assert!((back[2] - 0.507).abs() < 1e-12, "{back:?}");
    }

    #[test]
    fn position_error_is_at_most_half_a_step() {
        // A spiral of points: every coordinate comes back within step / 2.
        let pts: Vec<[f64; 3]> = (0..5000)
            .map(|k| {
                let t = f64::from(k) * 0.013;
                [40.0 * t.cos(), 25.0 * t.sin() - 3.0, 0.004 * f64::from(k)]
            })
            .collect();
        let g = PositionGrid::covering(pts.iter().copied());
        // x spans 80 m (the largest): step = 80 / 65 535.
        assert!(
            (g.step - 80.0 / 65_535.0).abs() < 1e-6 * g.step,
            "{}",
            g.step
        );
        let mut worst: f64 = 0.0;
        for p in &pts {
            let b = g.decode(g.encode(*p));
            for c in 0..3 {
                worst = worst.max((b[c] - p[c]).abs());
            }
        }
        assert!(
            worst <= 0.5 * g.step * (1.0 + 1e-9),
            "{worst} vs {}",
            g.step
        );
        // …and uses the grid: at least a quarter step somewhere.
        assert!(worst > 0.25 * g.step, "{worst}");
    }

    #[test]
    fn coincident_points_and_no_points() {
        let g = PositionGrid::covering([[1.0, 2.0, 3.0], [1.0, 2.0, 3.0]]);
        assert_eq!(g.step, 1.0);
        assert_eq!(g.decode(g.encode([1.0, 2.0, 3.0])), [1.0, 2.0, 3.0]);
        let g = PositionGrid::covering(std::iter::empty());
        assert_eq!((g.origin, g.step), ([0.0; 3], 1.0));
    }

    #[test]
    fn quaternions_by_hand() {
        // A quarter turn about y: (0, 0.70710678, 0, 0.70710678) → 0.70710678 · 32 767 =
        // 23 169.77 → 23 170.
        let h = std::f64::consts::FRAC_1_SQRT_2;
        assert_eq!(quaternion_codes([0.0, h, 0.0, h]), [0, 23_170, 0, 23_170]);
        assert_eq!(quaternion_codes([0.0, 0.0, 0.0, 1.0]), [0, 0, 0, 32_767]);
        assert_eq!(quaternion_codes([-1.0, 0.0, 0.0, 0.0]), [-32_767, 0, 0, 0]);
        let d = quaternion_decode([0, 23_170, 0, 23_170]);
        assert!(
            (d[1] - h).abs() < 1e-15 && (d[3] - h).abs() < 1e-15,
            "{d:?}"
        );
    }

    #[test]
    fn rotation_error_is_within_the_bound() {
        // Quaternions over the whole sphere (a deterministic sweep of axes and angles):
        // the stored rotation is within ROTATION_ERROR_RAD of the true one.
        assert!(
            (ROTATION_ERROR_RAD - 6.1037e-5).abs() < 1e-9,
            "{ROTATION_ERROR_RAD}"
        );
        let mut worst: f64 = 0.0;
        for i in 0..60 {
            for j in 0..60 {
                for k in 0..12 {
                    let th = std::f64::consts::PI * (f64::from(i) + 0.37) / 60.0;
                    let ph = 2.0 * std::f64::consts::PI * (f64::from(j) + 0.11) / 60.0;
                    let ang = 2.0 * std::f64::consts::PI * (f64::from(k) + 0.5) / 12.0;
                    let axis = [th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()];
                    let s = (0.5 * ang).sin();
                    let q = [axis[0] * s, axis[1] * s, axis[2] * s, (0.5 * ang).cos()];
                    let e = rotation_angle(q, quaternion_decode(quaternion_codes(q)));
                    worst = worst.max(e);
                }
            }
        }
        assert!(worst <= ROTATION_ERROR_RAD, "{worst}");
        assert!(worst > 0.1 * ROTATION_ERROR_RAD, "{worst}");
    }
}
