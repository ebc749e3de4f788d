//! Integration rules on [0, 1] for beam-column sections: Gauss-Legendre (interior
//! points; `dispBeamColumn` default) and Gauss-Lobatto (includes both ends, where
//! plasticity concentrates; `forceBeamColumn` default). Weights sum to 1 (multiply by L).
//!
//! Points are the roots of the Legendre polynomial `P_n` (Legendre) or the ends plus the
//! roots of `P'_{n−1}` (Lobatto), found by Newton iteration from Chebyshev-like guesses;
//! weights `2 / ((1 − x²) P_n'(x)²)` and `2 / (n (n−1) P_{n−1}(x)²)` on [−1, 1]
//! (Abramowitz & Stegun 25.4.29, 25.4.32), mapped to [0, 1].

/// `(P_n(x), P_n'(x))` by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    let nf = n as f64;
    // P_n'(x) = n (x P_n − P_{n−1}) / (x² − 1), valid off the ends.
    let dp = nf * (x * p1 - p0) / (x * x - 1.0);
    (p1, dp)
}

/// Gauss-Legendre rule with `n ≥ 1` points on [0, 1]: `(points, weights)`.
pub(crate) fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    assert!(n >= 1, "Gauss-Legendre needs at least one point");
    let mut xs = Vec::with_capacity(n);
    let mut ws = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = -(std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        for _ in 0..100 {
            let (p, dp) = legendre(n, x);
            let dx = p / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        let (_, dp) = legendre(n, x);
        xs.push(0.5 * (x + 1.0));
        ws.push(0.5 * 2.0 / ((1.0 - x * x) * dp * dp));
    }
    (xs, ws)
}

/// Gauss-Lobatto rule with `n ≥ 2` points on [0, 1] (ends included): `(points, weights)`.
pub(crate) fn gauss_lobatto(n: usize) -> (Vec<f64>, Vec<f64>) {
    assert!(n >= 2, "Gauss-Lobatto needs at least two points");
    let m = n - 1;
    let nf = n as f64;
    let mut xs = vec![-1.0];
    let mut ws = vec![2.0 / (nf * (nf - 1.0))];
    for i in 1..m {
        // Roots of P_m'; start from the Chebyshev-Gauss-Lobatto points.
        let mut x = -(std::f64::consts::PI * i as f64 / m as f64).cos();
        for _ in 0..100 {
            // f = P_m'(x); f' = P_m''(x) = (2x P_m' − m(m+1) P_m) / (1 − x²).
            let (p, dp) = legendre(m, x);
            let mf = m as f64;
            let ddp = (2.0 * x * dp - mf * (mf + 1.0) * p) / (1.0 - x * x);
            let dx = dp / ddp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        let (p, _) = legendre(m, x);
        xs.push(x);
        ws.push(2.0 / (nf * (nf - 1.0) * p * p));
    }
    xs.push(1.0);
    ws.push(2.0 / (nf * (nf - 1.0)));
    (
        xs.iter().map(|x| 0.5 * (x + 1.0)).collect(),
        ws.iter().map(|w| 0.5 * w).collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lobatto_five_points_match_closed_form() {
        let (x, w) = gauss_lobatto(5);
        let a = (3.0f64 / 7.0).sqrt();
        let xe = [0.0, 0.5 * (1.0 - a), 0.5, 0.5 * (1.0 + a), 1.0];
        let we = [0.05, 49.0 / 180.0, 32.0 / 90.0, 49.0 / 180.0, 0.05];
        for i in 0..5 {
            assert!((x[i] - xe[i]).abs() < 1e-14, "{x:?}");
            assert!((w[i] - we[i]).abs() < 1e-14, "{w:?}");
        }
    }

    #[test]
    fn legendre_three_points_match_closed_form() {
        let (x, w) = gauss_legendre(3);
        let a = 0.5 * (0.6f64).sqrt();
        assert!((x[0] - (0.5 - a)).abs() < 1e-15 && (x[2] - (0.5 + a)).abs() < 1e-15);
        assert!((w[1] - 4.0 / 9.0).abs() < 1e-15 && (w[0] - 5.0 / 18.0).abs() < 1e-15);
    }

    #[test]
    fn rules_integrate_polynomials_exactly() {
        for n in 1..=10 {
            let (x, w) = gauss_legendre(n);
            for p in 0..(2 * n) {
                let s: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(p as i32)).sum();
                assert!((s - 1.0 / (p as f64 + 1.0)).abs() < 1e-13, "GL n={n} p={p}");
            }
        }
        for n in 2..=10 {
            let (x, w) = gauss_lobatto(n);
            for p in 0..(2 * n - 2) {
                let s: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(p as i32)).sum();
                assert!(
                    (s - 1.0 / (p as f64 + 1.0)).abs() < 1e-13,
                    "GLL n={n} p={p}"
                );
            }
        }
    }
}
