//! The exact Euclidean distance transform of a grid: for every cell, the squared distance
//! (in cells², between cell centres) to the nearest feature cell.
//!
//! Felzenszwalb & Huttenlocher, "Distance transforms of sampled functions", Theory of
//! Computing 8 (2012) 415–428: the squared distance is separable,
//! `D(x, y, z) = min_z' (min_y' (min_x' f + (x − x')²) + (y − y')²) + (z − z')²`, and each
//! 1-D pass is the lower envelope of the parabolas `f(q) + (p − q)²`, found in linear time
//! (their Algorithm 1). Three passes: O(cells). Feature cells have `f = 0`, others `+∞`
//! (left out of the envelope); a line without features stays `+∞`.
use super::grid::Grid;

/// The squared distance of a cell that no feature reaches.
pub const FAR: f32 = f32::INFINITY;

/// The 1-D squared distance transform of `f` (`+∞` for no feature) into `d`; `v` and
/// `z` are work buffers of `f.len()` and `f.len() + 1`.
fn transform_line(f: &[f64], d: &mut [f64], v: &mut [usize], z: &mut [f64]) {
    let n = f.len();
    let mut k: isize = -1;
    for q in 0..n {
        if !f[q].is_finite() {
            continue;
        }
        let fq = f[q] + (q * q) as f64;
        let mut s = f64::NEG_INFINITY;
        while k >= 0 {
            let p = v[k as usize];
            s = (fq - (f[p] + (p * p) as f64)) / (2.0 * (q as f64 - p as f64));
            if s <= z[k as usize] {
                k -= 1;
            } else {
                break;
            }
        }
        if k < 0 {
            s = f64::NEG_INFINITY;
        }
        k += 1;
        v[k as usize] = q;
        z[k as usize] = s;
        z[k as usize + 1] = f64::INFINITY;
    }
    if k < 0 {
        d.fill(f64::INFINITY);
        return;
    }
    let mut j = 0usize;
    for (q, dq) in d.iter_mut().enumerate() {
        while z[j + 1] < q as f64 {
            j += 1;
        }
        let p = v[j];
        let dx = q as f64 - p as f64;
        *dq = dx * dx + f[p];
    }
}

/// The squared distance (cells²) from every cell of `grid` to the nearest cell with
/// `feature` set.
///
/// The passes along x and y take their lines a plane at a time: the lines of a plane
/// (all `k` for one `j`, or for one `i`) lie side by side in memory, so they are copied
/// out and back together, a run of `nz` cells at each step along the line, instead of
/// one cell a memory line apart at a time. Each line's transform is the same.
pub fn squared_distance(grid: &Grid, feature: &[bool]) -> Vec<f32> {
    let [nx, ny, nz] = grid.n;
    let mut out: Vec<f32> = feature.iter().map(|&s| if s { 0.0 } else { FAR }).collect();
    let m = nx.max(ny).max(nz);
    let (mut f, mut d) = (vec![0.0f64; m], vec![0.0f64; m]);
    let (mut v, mut z) = (vec![0usize; m], vec![0.0f64; m + 1]);
    // Along z (contiguous). A column without features stays +∞, and so does a plane of
    // lines along x (a row of columns, one `j`) none of whose columns has one: their
    // transforms are skipped.
    let mut row_has = vec![false; ny];
    for (c, col) in out.chunks_mut(nz).enumerate() {
        if col.iter().all(|o| *o == FAR) {
            continue;
        }
        row_has[c / nx] = true;
        for (ft, o) in f.iter_mut().zip(col.iter()) {
            *ft = *o as f64;
        }
        transform_line(&f[..nz], &mut d[..nz], &mut v[..nz], &mut z[..nz + 1]);
        for (o, dt) in col.iter_mut().zip(d.iter()) {
            *o = *dt as f32;
        }
    }
    // Along x, then y: a plane of `nz` lines at a time, `block[k · n + t]` the cell `t`
    // of line `k`.
    let mut block = vec![0.0f32; nz * m];
    for axis in [0usize, 1] {
        let n = grid.n[axis];
        let planes = if axis == 0 { ny } else { nx };
        for p in (0..planes).filter(|&p| axis == 1 || row_has[p]) {
            let at = |t: usize| {
                if axis == 0 {
                    grid.index(t, p, 0)
                } else {
                    grid.index(p, t, 0)
                }
            };
            for t in 0..n {
                let run = &out[at(t)..at(t) + nz];
                for (k, o) in run.iter().enumerate() {
                    block[k * n + t] = *o;
                }
            }
            for k in 0..nz {
                let line = &mut block[k * n..(k + 1) * n];
                for (ft, o) in f.iter_mut().zip(line.iter()) {
                    *ft = *o as f64;
                }
                transform_line(&f[..n], &mut d[..n], &mut v[..n], &mut z[..n + 1]);
                for (o, dt) in line.iter_mut().zip(d.iter()) {
                    *o = *dt as f32;
                }
            }
            for t in 0..n {
                let a = at(t);
                for (k, o) in out[a..a + nz].iter_mut().enumerate() {
                    *o = block[k * n + t];
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against brute force on a random-ish pattern.
    #[test]
    #[allow(clippy::needless_range_loop)]
    fn equals_brute_force() {
        let grid = Grid {
            origin: [0.0; 3],
            h: 1.0,
            n: [7, 5, 6],
        };
        let mut feature = vec![false; grid.len()];
        let mut state = 12345u64;
        for f in feature.iter_mut() {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            *f = (state >> 33) % 11 == 0;
        }
        let d = squared_distance(&grid, &feature);
        for a in 0..grid.len() {
            let ca = grid.ijk(a);
            let mut best = f64::INFINITY;
            for b in 0..grid.len() {
                if feature[b] {
                    let cb = grid.ijk(b);
                    let s: f64 = (0..3).map(|k| (ca[k] as f64 - cb[k] as f64).powi(2)).sum();
                    best = best.min(s);
                }
            }
            assert_eq!(d[a] as f64, best, "cell {ca:?}");
        }
    }

    /// One feature cell (1, 2, 1) on a 5 × 4 × 3 grid: the rows and columns without
    /// features (their passes skipped) get their distances through the other passes,
    /// (i − 1)² + (j − 2)² + (k − 1)² everywhere.
    #[test]
    fn one_feature_reaches_the_rows_without_one() {
        let grid = Grid {
            origin: [0.0; 3],
            h: 1.0,
            n: [5, 4, 3],
        };
        let mut feature = vec![false; grid.len()];
        feature[grid.index(1, 2, 1)] = true;
        let d = squared_distance(&grid, &feature);
        for (idx, v) in d.iter().enumerate() {
            let [i, j, k] = grid.ijk(idx).map(|c| c as f32);
            let want = (i - 1.0).powi(2) + (j - 2.0).powi(2) + (k - 1.0).powi(2);
            assert_eq!(*v, want, "cell {:?}", grid.ijk(idx));
        }
    }

    #[test]
    fn no_feature_is_far() {
        let grid = Grid {
            origin: [0.0; 3],
            h: 1.0,
            n: [3, 2, 4],
        };
        let d = squared_distance(&grid, &vec![false; grid.len()]);
        assert!(d.iter().all(|v| *v == FAR));
    }
}
