//! Thick-restart block Lanczos with full reorthogonalisation for the eigenvalues of
//! largest magnitude of a symmetric operator `C` (dimension n), given only `y = C x`.
//!
//! The modal analysis applies it to the shift-invert operator (see
//! [`super::modal`]), whose largest eigenvalues θ = 1/(λ − σ) are the eigenvalues λ
//! nearest the shift σ.
//!
//! Method (Golub & Van Loan, *Matrix Computations*, 4th ed., §10.3.6 block Lanczos and
//! §10.1.5 / Wu & Simon's thick restart; Stewart's Krylov–Schur reduces to it for
//! symmetric C):
//! - a basis Q = [q₁ … q_j] with orthonormal columns grows by blocks of b vectors:
//!   W = C P for the newest block P, W is orthogonalised against *all* of Q twice
//!   (classical Gram–Schmidt, "twice is enough"), the coefficients fill the projected
//!   matrix H = Qᵀ C Q, and a rank-revealing QR of the remainder gives the next block
//!   and the coupling R (C P = Q H_{:,P} + P_next R);
//! - a block size b ≥ the multiplicity of an eigenvalue finds all its copies (one
//!   vector per copy in the start block); a start block of deterministic pseudo-random
//!   numbers makes the run reproducible bit for bit;
//! - when the expanded part reaches the basis size, Rayleigh–Ritz: H_ee = S Θ Sᵀ, Ritz
//!   vectors Y = Q_e S, residuals ‖C y_i − θ_i y_i‖ = ‖E s_i‖ where E is the coupling of
//!   the unexpanded block to the expanded basis;
//! - converged when the wanted Ritz pairs have ‖E s_i‖ ≤ tol · |θ_i|; otherwise restart
//!   with the best k Ritz vectors plus the unexpanded block (an "arrowhead" H), which
//!   keeps the Krylov relation exact, and expand again;
//! - a block that loses rank (an invariant subspace was found) is completed with
//!   pseudo-random vectors orthogonal to Q, with zero coupling.

use nalgebra::{DMatrix, SymmetricEigen};

/// Settings of [`block_lanczos`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LanczosOptions {
    /// Block size b (≥ the largest multiplicity expected among the wanted eigenvalues).
    pub block: usize,
    /// Number of expanded basis vectors before a restart (rounded up to a multiple of b).
    pub basis: usize,
    /// Relative residual tolerance ‖C y − θ y‖ ≤ tol·|θ| of each wanted pair.
    pub tol: f64,
    /// Maximum number of restarts.
    pub max_restarts: usize,
}

/// Failure of [`block_lanczos`].
#[derive(Debug, Clone, thiserror::Error, PartialEq)]
pub(crate) enum LanczosError {
    /// Bad sizes (more wanted pairs than the basis can hold, etc.).
    #[error("block Lanczos: {0}")]
    Input(String),
    /// The operator failed (e.g. a singular factorisation).
    #[error("block Lanczos: operator failed: {0}")]
    Operator(String),
    /// Not converged within the restart limit; the worst relative residual.
    #[error(
        "block Lanczos did not converge in {restarts} restarts (worst relative residual {residual:.3e})"
    )]
    NotConverged {
        /// Restarts done.
        restarts: usize,
        /// Worst relative residual among the wanted pairs.
        residual: f64,
    },
}

/// Deterministic pseudo-random numbers in [−½, ½) (a 64-bit LCG, Knuth's MMIX constants).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

/// Orthogonalises the columns `from..to` of `q` against columns `0..from` (twice,
/// classical Gram–Schmidt) and then among themselves (modified Gram–Schmidt, twice).
/// Returns the coefficients: `c` ((from) × (to−from)) on the old columns, and the upper
/// triangular `r` ((to−from) × (to−from)) of the block QR. A column whose remainder is
/// below 1e-10 of its norm on entry is replaced by a pseudo-random vector orthogonal to
/// all others, with a zero diagonal in `r` (an error if ten tries fail: no room left).
fn orthonormalise_block(
    q: &mut DMatrix<f64>,
    from: usize,
    to: usize,
    rng: &mut Lcg,
) -> Result<(DMatrix<f64>, DMatrix<f64>), LanczosError> {
    let n = q.nrows();
    let b = to - from;
    let mut c = DMatrix::<f64>::zeros(from, b);
    let mut r = DMatrix::<f64>::zeros(b, b);
    let norms0: Vec<f64> = (from..to).map(|j| q.column(j).norm()).collect();
    if from > 0 {
        for _ in 0..2 {
            let (old, mut new) = q.columns_range_pair_mut(0..from, from..to);
            let coef = old.transpose() * &new;
            new.gemm(-1.0, &old, &coef, 1.0);
            c += coef;
        }
    }
    for (jj, j) in (from..to).enumerate() {
        let mut random_tries = 0;
        loop {
            for _ in 0..2 {
                for i in from..j {
                    let d = q.column(i).dot(&q.column(j));
                    if random_tries == 0 {
                        r[(i - from, jj)] += d;
                    }
                    let qi = q.column(i).clone_owned();
                    q.column_mut(j).axpy(-d, &qi, 1.0);
                }
            }
            let nrm = q.column(j).norm();
            let reference = if random_tries == 0 { norms0[jj] } else { 1.0 };
            if nrm > 1e-10 * reference && nrm > 0.0 {
                if random_tries == 0 {
                    r[(jj, jj)] = nrm;
                }
                q.column_mut(j).scale_mut(1.0 / nrm);
                break;
            }
            // Rank loss: a fresh pseudo-random direction, orthogonal to all columns.
            random_tries += 1;
            if random_tries >= 10 {
                return Err(LanczosError::Input(format!(
                    "cannot complete a Lanczos block of {b} vectors in dimension {n}"
                )));
            }
            if random_tries == 1 {
                // The remainder is numerically zero: its coupling is zero.
                for i in from..j {
                    r[(i - from, jj)] = 0.0;
                }
                r[(jj, jj)] = 0.0;
            }
            for k in 0..n {
                q[(k, j)] = rng.next();
            }
            for _ in 0..2 {
                let (old, mut new) = q.columns_range_pair_mut(0..j, j..j + 1);
                let coef = old.transpose() * &new;
                new.gemm(-1.0, &old, &coef, 1.0);
            }
        }
    }
    Ok((c, r))
}

/// The `nev` eigenpairs of largest |θ| of the symmetric operator `op` (y = C x, both of
/// length `n`): eigenvalues ordered by decreasing |θ|, orthonormal eigenvectors as the
/// columns of the returned matrix (n × nev).
pub(crate) fn block_lanczos<E: std::fmt::Display>(
    n: usize,
    nev: usize,
    mut op: impl FnMut(&[f64], &mut [f64]) -> Result<(), E>,
    opts: &LanczosOptions,
) -> Result<(Vec<f64>, DMatrix<f64>), LanczosError> {
    let b = opts.block.max(1);
    let basis = opts.basis.max(nev + b).div_ceil(b) * b;
    if nev == 0 || basis + b > n {
        return Err(LanczosError::Input(format!(
            "{nev} eigenpairs with basis {basis} + block {b} need an operator larger than n = {n}"
        )));
    }
    let cap = basis + b;
    let mut q = DMatrix::<f64>::zeros(n, cap);
    let mut h = DMatrix::<f64>::zeros(cap, cap);
    let mut rng = Lcg(0x2545_f491_4f6c_dd1d);
    let mut x = vec![0.0; n];
    let mut y = vec![0.0; n];
    let mut apply = |src: &[f64], dst: &mut [f64]| -> Result<(), LanczosError> {
        op(src, dst).map_err(|e| LanczosError::Operator(e.to_string()))?;
        if dst.iter().any(|v| !v.is_finite()) {
            return Err(LanczosError::Operator("non-finite result".into()));
        }
        Ok(())
    };
    // Start block: pseudo-random vectors mapped once through C (so that they lie in its
    // range), then orthonormalised.
    for j in 0..b {
        for v in x.iter_mut() {
            *v = rng.next();
        }
        apply(&x, &mut y)?;
        q.column_mut(j).copy_from_slice(&y);
    }
    orthonormalise_block(&mut q, 0, b, &mut rng)?;
    let mut expanded = 0; // columns whose images C q are in H
    let mut len = b; // columns of Q in use; the block expanded..len is unexpanded
    let mut restarts = 0;
    loop {
        // Expand the newest block P = Q[:, expanded..len].
        while expanded + b <= basis {
            debug_assert_eq!(len, expanded + b);
            for j in 0..b {
                x.copy_from_slice(q.column(expanded + j).as_slice());
                apply(&x, &mut y)?;
                q.column_mut(len + j).copy_from_slice(&y);
            }
            let (c, r) = orthonormalise_block(&mut q, len, len + b, &mut rng)?;
            // H[0..len, P] = c (projection of C P on the basis), symmetric copy.
            for jj in 0..b {
                let col = expanded + jj;
                for i in 0..len {
                    h[(i, col)] = c[(i, jj)];
                    h[(col, i)] = c[(i, jj)];
                }
                for i in 0..b {
                    h[(len + i, col)] = r[(i, jj)];
                    h[(col, len + i)] = r[(i, jj)];
                }
            }
            // The diagonal block P×P: symmetric part.
            for i in 0..b {
                for j in 0..i {
                    let s =
                        0.5 * (h[(expanded + i, expanded + j)] + h[(expanded + j, expanded + i)]);
                    h[(expanded + i, expanded + j)] = s;
                    h[(expanded + j, expanded + i)] = s;
                }
            }
            expanded += b;
            len += b;
        }
        // Rayleigh–Ritz on the expanded part.
        let hee = h.view((0, 0), (expanded, expanded)).clone_owned();
        let hee = (&hee + hee.transpose()) * 0.5;
        let eig = SymmetricEigen::new(hee);
        let mut idx: Vec<usize> = (0..expanded).collect();
        idx.sort_by(|&i, &j| {
            eig.eigenvalues[j]
                .abs()
                .total_cmp(&eig.eigenvalues[i].abs())
                .then(i.cmp(&j))
        });
        let s = DMatrix::from_fn(expanded, expanded, |r, c| eig.eigenvectors[(r, idx[c])]);
        let theta: Vec<f64> = idx.iter().map(|&i| eig.eigenvalues[i]).collect();
        let e = h.view((expanded, 0), (b, expanded)).clone_owned();
        let es = &e * &s; // b × expanded: coupling of the Ritz vectors to the next block
        let resid: Vec<f64> = (0..expanded)
            .map(|i| es.column(i).norm() / theta[i].abs().max(f64::MIN_POSITIVE))
            .collect();
        let worst = resid[..nev].iter().cloned().fold(0.0, f64::max);
        if worst <= opts.tol {
            let vectors = q.columns(0, expanded) * s.columns(0, nev);
            return Ok((theta[..nev].to_vec(), vectors));
        }
        if restarts >= opts.max_restarts {
            return Err(LanczosError::NotConverged {
                restarts,
                residual: worst,
            });
        }
        restarts += 1;
        // Thick restart: the k best Ritz vectors and the unexpanded block.
        let k = (nev + (expanded - nev) / 2).min(expanded - b).max(nev);
        let ritz = q.columns(0, expanded) * s.columns(0, k);
        let next = q.columns(expanded, b).clone_owned();
        q.fill(0.0);
        q.columns_mut(0, k).copy_from(&ritz);
        q.columns_mut(k, b).copy_from(&next);
        h.fill(0.0);
        for i in 0..k {
            h[(i, i)] = theta[i];
            for j in 0..b {
                h[(k + j, i)] = es[(j, i)];
                h[(i, k + j)] = es[(j, i)];
            }
        }
        expanded = k;
        len = k + b;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A diagonal operator with a triple, a double and a close pair at the top of the
    /// spectrum: all copies are found, to the tolerance.
    #[test]
    fn repeated_and_close_eigenvalues_of_a_diagonal_operator() {
        let n = 400;
        let mut d: Vec<f64> = (0..n).map(|i| 1.0 / (10.0 + i as f64)).collect();
        d[7] = 1.0;
        d[100] = 1.0;
        d[300] = 1.0;
        d[50] = 0.5;
        d[51] = 0.5;
        d[200] = 0.3;
        d[201] = 0.3 * (1.0 + 1e-7);
        let op = |x: &[f64], y: &mut [f64]| -> Result<(), std::convert::Infallible> {
            for i in 0..n {
                y[i] = d[i] * x[i];
            }
            Ok(())
        };
        let opts = LanczosOptions {
            block: 4,
            basis: 24,
            tol: 1e-12,
            max_restarts: 200,
        };
        let (theta, v) = block_lanczos(n, 7, op, &opts).unwrap();
        let want = [1.0, 1.0, 1.0, 0.5, 0.5, 0.3 * (1.0 + 1e-7), 0.3];
        for (t, w) in theta.iter().zip(want) {
            assert!((t - w).abs() < 1e-12, "{theta:?}");
        }
        // Orthonormal eigenvectors spanning the triple's coordinates.
        let g = v.transpose() * &v;
        assert!((g - DMatrix::identity(7, 7)).norm() < 1e-10);
        let span: f64 = (0..3)
            .map(|c| v[(7, c)].powi(2) + v[(100, c)].powi(2) + v[(300, c)].powi(2))
            .sum();
        assert!((span - 3.0).abs() < 1e-10, "{span}");
        // Same input, same bytes.
        let (theta2, v2) = block_lanczos(n, 7, op, &opts).unwrap();
        assert_eq!(theta, theta2);
        assert_eq!(v, v2);
    }
}
