//! The Newton iterations' sparse solver (`SparseSolver`: LBLᵀ of the symmetric part,
//! iterative refinement, LU fallback) against nalgebra's dense LU on the pattern of a
//! 2 × 2-bay, 3-story frame (108 equations): a symmetric indefinite matrix and a slightly
//! unsymmetric one are solved on the symmetric path, a strongly unsymmetric one through
//! the LU, and a singular one is an error.
use super::support::{grid_frame, square};
use fem2rbd_fe::fe::linalg::{SolverError, SparsePattern, SparseSolver, StiffnessKind};
use nalgebra::{DMatrix, DVector};

/// The frame's pattern and its elastic stiffness (positive definite).
fn frame() -> (SparsePattern, Vec<f64>) {
    let mut d = grid_frame(2, 3, 4.0, 3.0, square(3e10, 0.4), square(3e10, 0.3), 1e4);
    let pattern = SparsePattern::new(&mut d);
    let mut k = pattern.zeros();
    pattern.add_stiffness(&d, StiffnessKind::Initial, 1.0, &mut k);
    (pattern, k)
}

/// Solves with `SparseSolver` and with a dense LU; returns the relative difference
/// ‖x − x_dense‖∞ / ‖x_dense‖∞ and the solver's stats.
fn compare(pattern: &SparsePattern, a: &[f64]) -> (f64, fem2rbd_fe::fe::linalg::SolverStats) {
    let n = pattern.dim();
    let b: Vec<f64> = (0..n).map(|i| ((i * 7 + 3) % 11) as f64 - 5.0).collect();
    let mut s = SparseSolver::new(pattern).unwrap();
    s.factor(pattern, a).unwrap();
    let mut x = b.clone();
    s.solve(pattern, &mut x).unwrap();
    let dense: DMatrix<f64> = pattern.to_dense(a);
    let xd = dense.lu().solve(&DVector::from_vec(b)).unwrap();
    let diff = x
        .iter()
        .zip(xd.iter())
        .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
    (diff / xd.amax(), s.stats())
}

/// Largest eigenvalue-sized shift: the mean diagonal entry (N/m and N·m mixed).
fn mean_diagonal(pattern: &SparsePattern, a: &[f64]) -> f64 {
    let dense = pattern.to_dense(a);
    dense.diagonal().mean()
}

#[test]
fn symmetric_indefinite_matrix_is_solved_on_the_symmetric_path() {
    let (pattern, mut a) = frame();
    // K − σ I with σ inside K's spectrum: indefinite (like the tangent of a softening
    // structure), still regular.
    let shift = 0.37 * mean_diagonal(&pattern, &a);
    let diag = vec![1.0; pattern.dim()];
    pattern.add_diagonal(&diag, -shift, &mut a);
    let eig = pattern.to_dense(&a).symmetric_eigenvalues();
    assert!(eig.min() < 0.0 && eig.max() > 0.0, "not indefinite");
    let (err, stats) = compare(&pattern, &a);
    assert!(err < 1e-9, "relative error {err:e}");
    assert_eq!(stats.lu_factorisations, 0, "{stats:?}");
    assert_eq!(stats.refined_solves, 1, "{stats:?}");
}

#[test]
fn slightly_unsymmetric_matrix_is_refined_without_the_lu() {
    let (pattern, mut a) = frame();
    // a_ij ← a_ij (1 + 1e-4 sign(i − j)): an asymmetry like the corotational geometric
    // stiffness's (relative 1e-4 ≫ the 7e-11 measured on the 7-story frame).
    let sym = pattern.symbolic();
    for c in 0..pattern.dim() {
        for p in sym.col_ptr()[c]..sym.col_ptr()[c + 1] {
            let r = sym.row_idx()[p];
            a[p] *= 1.0 + 1e-4 * (r as f64 - c as f64).signum();
        }
    }
    let (err, stats) = compare(&pattern, &a);
    assert!(err < 1e-9, "relative error {err:e}");
    assert_eq!(stats.lu_factorisations, 0, "{stats:?}");
    assert!(stats.refinement_steps >= 1, "{stats:?}");
}

#[test]
fn strongly_unsymmetric_matrix_falls_back_to_the_lu() {
    let (pattern, k) = frame();
    // A = D + N, D = diag(K) > 0, N skew (n_ij = −n_ji = 3 k_ij for i < j): regular
    // (xᵀAx = xᵀDx > 0), but its symmetric part D is far from A: refinement diverges.
    let sym = pattern.symbolic();
    let mut a = vec![0.0; k.len()];
    for c in 0..pattern.dim() {
        for p in sym.col_ptr()[c]..sym.col_ptr()[c + 1] {
            let r = sym.row_idx()[p];
            a[p] = match r.cmp(&c) {
                std::cmp::Ordering::Equal => k[p],
                std::cmp::Ordering::Less => 3.0 * k[p],
                std::cmp::Ordering::Greater => -3.0 * k[p],
            };
        }
    }
    let (err, stats) = compare(&pattern, &a);
    assert!(err < 1e-9, "relative error {err:e}");
    assert_eq!(stats.lu_factorisations, 1, "{stats:?}");
    assert_eq!(stats.refined_solves, 0, "{stats:?}");
}

#[test]
fn singular_matrix_is_an_error() {
    let (pattern, _) = frame();
    let a = pattern.zeros();
    let mut s = SparseSolver::new(&pattern).unwrap();
    let res = s
        .factor(&pattern, &a)
        .and_then(|_| s.solve(&pattern, &mut vec![1.0; pattern.dim()]));
    assert_eq!(res, Err(SolverError::Singular));
}
