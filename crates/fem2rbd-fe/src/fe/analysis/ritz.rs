//! Load-dependent Ritz vectors (Wilson, Yuan & Dickens, Earthquake Eng. Struct. Dyn. 10
//! (1982) 813) as a block Krylov space of the shift-invert operator C of
//! [`super::shift_invert`] at σ = 0, started from the loads of a uniform base motion.
//!
//! With z-coordinates z = M_a^{1/2} φ_a, the load M r of an influence vector r is
//! M_a^{1/2} r_a, and the first Ritz vector K⁻¹ M r is C (M_a^{1/2} r_a); each further
//! block is C applied to the last one. So the space after j blocks is
//! span{C s, C² s, …, C^j s} for the start vectors s: a Krylov space that holds a mode
//! only in proportion to its participation factor Γ = φᵀ M r — local modes that carry
//! no mass along r are barely in it, however low their frequency.
//!
//! Each new block is orthogonalised against the whole basis twice (classical
//! Gram–Schmidt, "twice is enough") and within itself; a vector whose remainder falls
//! below 1e-10 of its norm is dropped (the space is then invariant along it: Golub &
//! Van Loan, *Matrix Computations*, 4th ed., §10.3.6). Rayleigh–Ritz on the space gives
//! H = Qᵀ C Q = S Θ Sᵀ, Ritz vectors y = Q s and residuals ‖C y − θ y‖ computed from the
//! stored images W = C Q.

// `!(x <= y)` is used on purpose: NaN counts as a failure.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use crate::fe::linalg::SolverError;

/// Relative remainder below which a new vector is dropped.
const DEFLATION: f64 = 1e-10;

/// A growing block Krylov space of a symmetric operator, with the images of its basis.
#[derive(Debug, Clone)]
pub(crate) struct KrylovSpace {
    /// Orthonormal basis vectors, expanded (their images are in `images`).
    basis: Vec<DVector<f64>>,
    /// C q for every basis vector.
    images: Vec<DVector<f64>>,
    /// The next block: orthonormal, orthogonal to `basis`, not yet expanded.
    next: Vec<DVector<f64>>,
    /// H = Qᵀ C Q over the expanded basis.
    h: DMatrix<f64>,
}

/// Ritz pairs of a [`KrylovSpace`], ordered by decreasing θ: values and the coordinates
/// of the unit Ritz vectors in the basis (vectors and residuals on demand).
#[derive(Debug, Clone)]
pub(crate) struct RitzPairs {
    /// Ritz values θ.
    pub theta: Vec<f64>,
    /// Column c: the coordinates s of Ritz vector c (y = Q s).
    pub coordinates: DMatrix<f64>,
}

/// Orthonormalises `v` against `against` and `earlier` (twice); `None` when its remainder
/// is below [`DEFLATION`] of its norm.
fn orthonormalise(
    mut v: DVector<f64>,
    against: &[DVector<f64>],
    earlier: &[DVector<f64>],
) -> Option<DVector<f64>> {
    let norm0 = v.norm();
    if !(norm0 > 0.0) || !norm0.is_finite() {
        return None;
    }
    for _ in 0..2 {
        for q in against.iter().chain(earlier) {
            let c = q.dot(&v);
            v.axpy(-c, q, 1.0);
        }
    }
    let norm = v.norm();
    (norm > DEFLATION * norm0).then(|| v / norm)
}

impl KrylovSpace {
    /// The space whose first block is C applied to `starts` (the load vectors in
    /// z-coordinates), orthonormalised; dependent starts are dropped.
    pub(crate) fn new(
        starts: &[DVector<f64>],
        mut op: impl FnMut(&[f64], &mut [f64]) -> Result<(), SolverError>,
    ) -> Result<Self, SolverError> {
        let mut next: Vec<DVector<f64>> = Vec::new();
        for s in starts {
            let mut y = DVector::zeros(s.len());
            op(s.as_slice(), y.as_mut_slice())?;
            if let Some(v) = orthonormalise(y, &[], &next) {
                next.push(v);
            }
        }
        Ok(Self {
            basis: Vec::new(),
            images: Vec::new(),
            next,
            h: DMatrix::zeros(0, 0),
        })
    }

    /// Number of expanded basis vectors.
    pub(crate) fn dim(&self) -> usize {
        self.basis.len()
    }

    /// Whether the space is invariant under C (no next block left).
    pub(crate) fn is_invariant(&self) -> bool {
        self.next.is_empty()
    }

    /// Expands the next block: its images join the space, and their parts orthogonal to
    /// the whole basis form the following block.
    pub(crate) fn expand(
        &mut self,
        mut op: impl FnMut(&[f64], &mut [f64]) -> Result<(), SolverError>,
    ) -> Result<(), SolverError> {
        let block = std::mem::take(&mut self.next);
        let mut images = Vec::with_capacity(block.len());
        for q in &block {
            let mut w = DVector::zeros(q.len());
            op(q.as_slice(), w.as_mut_slice())?;
            images.push(w);
        }
        self.basis.extend(block);
        let mut next: Vec<DVector<f64>> = Vec::new();
        for w in &images {
            if let Some(v) = orthonormalise(w.clone(), &self.basis, &next) {
                next.push(v);
            }
        }
        let (old, d) = (self.images.len(), self.basis.len());
        self.images.extend(images);
        self.next = next;
        let mut h = std::mem::replace(&mut self.h, DMatrix::zeros(0, 0)).resize(d, d, 0.0);
        for j in old..d {
            for i in 0..=j {
                let v =
                    0.5 * (self.basis[i].dot(&self.images[j]) + self.basis[j].dot(&self.images[i]));
                h[(i, j)] = v;
                h[(j, i)] = v;
            }
        }
        self.h = h;
        Ok(())
    }

    /// Basis coordinates `Qᵀ v` of a vector.
    pub(crate) fn project(&self, v: &DVector<f64>) -> DVector<f64> {
        DVector::from_iterator(self.dim(), self.basis.iter().map(|q| q.dot(v)))
    }

    /// The Ritz vector y = Q s and its residual ‖C y − θ y‖ (from W = C Q).
    pub(crate) fn vector(&self, s: &[f64], theta: f64) -> (DVector<f64>, f64) {
        let n = self.basis.first().map_or(0, |q| q.len());
        let mut y = DVector::zeros(n);
        let mut cy = DVector::zeros(n);
        for ((q, w), &c) in self.basis.iter().zip(&self.images).zip(s) {
            y.axpy(c, q, 1.0);
            cy.axpy(c, w, 1.0);
        }
        cy.axpy(-theta, &y, 1.0);
        let r = cy.norm();
        (y, r)
    }

    /// Rayleigh–Ritz on the expanded basis (module docs).
    pub(crate) fn ritz(&self) -> RitzPairs {
        let d = self.dim();
        let eig = SymmetricEigen::new(self.h.clone());
        let mut order: Vec<usize> = (0..d).collect();
        order.sort_by(|&i, &j| {
            eig.eigenvalues[j]
                .total_cmp(&eig.eigenvalues[i])
                .then(i.cmp(&j))
        });
        RitzPairs {
            theta: order.iter().map(|&c| eig.eigenvalues[c]).collect(),
            coordinates: DMatrix::from_fn(d, d, |r, c| eig.eigenvectors[(r, order[c])]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A diagonal operator and a start vector that holds only some of its eigenvectors:
    /// the space becomes invariant after as many vectors as the start vector has
    /// eigen-components, and its Ritz pairs are then exact; the components the start
    /// vector lacks are never found.
    #[test]
    fn a_start_vector_reaches_only_its_own_eigenvectors() {
        let d = [5.0, 4.0, 3.0, 2.0, 1.0, 0.5];
        let op = |x: &[f64], y: &mut [f64]| -> Result<(), SolverError> {
            for i in 0..d.len() {
                y[i] = d[i] * x[i];
            }
            Ok(())
        };
        // Components on eigenvectors 1, 3 and 5 only (θ = 4, 2, 0.5).
        let s = DVector::from_vec(vec![0.0, 1.0, 0.0, 2.0, 0.0, 3.0]);
        let mut space = KrylovSpace::new(&[s], op).unwrap();
        while !space.is_invariant() {
            space.expand(op).unwrap();
        }
        assert_eq!(space.dim(), 3);
        let pairs = space.ritz();
        for (t, want) in pairs.theta.iter().zip([4.0, 2.0, 0.5]) {
            assert!((t - want).abs() < 1e-12, "{:?}", pairs.theta);
        }
        for c in 0..3 {
            let (y, r) = space.vector(pairs.coordinates.column(c).as_slice(), pairs.theta[c]);
            assert!(r < 1e-12, "{r}");
            assert!(y[0].abs() + y[2].abs() + y[4].abs() < 1e-12);
        }
    }
}
