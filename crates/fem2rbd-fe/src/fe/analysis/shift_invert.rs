//! The spectral transformation of K φ = λ M φ with a lumped mass matrix M that is zero
//! on some DOFs (the massless rotations): with the massed DOFs `a`, the massless `b` and
//! K_σ = K − σM, the operator on the massed DOFs only
//!
//!   C = M_a^{1/2} [K_σ⁻¹]_aa M_a^{1/2}
//!
//! is symmetric, with eigenvalues θ = 1/(λ − σ) and eigenvectors z = M_a^{1/2} φ_a,
//! because [K_σ⁻¹]_aa is the inverse of the statically condensed K̂ − σM_a (Ericsson &
//! Ruhe, Math. Comp. 35 (1980) 1251; Nour-Omid, Parlett, Ericsson & Jensen, Math. Comp.
//! 48 (1987) 663, for singular M). The eigenvalues nearest σ are the largest |θ|. A mode
//! shape with its massless DOFs is φ = K_σ⁻¹ (M^{1/2} z) / θ (exact statics for them):
//! its massed part is M_a^{-1/2} z and (K − σM) φ = M φ / θ.
//!
//! The Euclidean inner product on z is the M-inner product on φ: a unit z is a
//! mass-normalised φ, and the participation factor of φ for an influence vector r is
//! Γ = φᵀ M r = zᵀ (M_a^{1/2} r_a).
//!
//! The factorisation also gives the Sturm sequence count: the inertia of K − σM (its
//! LBLᵀ's block diagonal) has as many negative eigenvalues as the pencil has below σ
//! when K_bb, the stiffness of the massless DOFs, is positive definite (Haynsworth's
//! inertia additivity: In(K − σM) = In(K_bb) + In(K̂ − σM_a); Bathe, *Finite Element
//! Procedures*, §11.4.3).

use nalgebra::DVector;

use super::AnalysisError;
use crate::fe::linalg::{SolverError, SparsePattern, SparseSolver};

/// The operator C of the module docs for one shift σ, on one factorisation of K − σM.
pub(crate) struct ShiftInvert<'a> {
    pattern: &'a SparsePattern,
    /// Equations with mass (`a`), in equation order.
    massed: &'a [usize],
    /// M_a^{1/2}, per massed equation (kg^½).
    sqrt_m: Vec<f64>,
    solver: SparseSolver,
    sigma: f64,
    full: Vec<f64>,
    /// Whether each solve must meet [`SparseSolver::solve`]'s backward error (with the
    /// LU as the fallback) rather than [`SparseSolver::solve_unchecked`]'s.
    checked: bool,
}

/// The equations with a positive mass, in equation order.
pub(crate) fn massed_equations(m: &[f64]) -> Vec<usize> {
    (0..m.len()).filter(|&i| m[i] > 0.0).collect()
}

impl<'a> ShiftInvert<'a> {
    /// Factors K − σM (`k` on `pattern`, the lumped mass diagonal `m` (kg), σ in
    /// rad²/s²); `massed` is [`massed_equations`] of `m`.
    pub(crate) fn new(
        pattern: &'a SparsePattern,
        k: &[f64],
        m: &[f64],
        massed: &'a [usize],
        sigma: f64,
    ) -> Result<Self, AnalysisError> {
        let mut op = Self {
            pattern,
            massed,
            sqrt_m: massed.iter().map(|&i| m[i].sqrt()).collect(),
            solver: SparseSolver::new(pattern)?,
            sigma,
            full: vec![0.0; pattern.dim()],
            checked: false,
        };
        op.shift(k, m, sigma)?;
        Ok(op)
    }

    /// Each solve to [`SparseSolver::solve`]'s backward error, with its LU fallback (the
    /// lowest modes' Lanczos at σ = 0, as it always solved).
    pub(crate) fn checked(mut self) -> Self {
        self.checked = true;
        self
    }

    /// Factors K − σM for a new shift σ, reusing the symbolic analysis.
    pub(crate) fn shift(&mut self, k: &[f64], m: &[f64], sigma: f64) -> Result<(), AnalysisError> {
        self.sigma = sigma;
        if sigma == 0.0 {
            self.solver.factor(self.pattern, k)?;
        } else {
            let mut ks = k.to_vec();
            self.pattern.add_diagonal(m, -sigma, &mut ks);
            self.solver.factor(self.pattern, &ks)?;
        }
        Ok(())
    }

    /// The pattern of K.
    pub(crate) fn pattern(&self) -> &'a SparsePattern {
        self.pattern
    }

    /// The shift σ (rad²/s²).
    pub(crate) fn sigma(&self) -> f64 {
        self.sigma
    }

    /// Dimension of C: the number of massed DOFs.
    pub(crate) fn dim(&self) -> usize {
        self.massed.len()
    }

    /// M_a^{1/2} (kg^½), per massed DOF.
    pub(crate) fn sqrt_mass(&self) -> &[f64] {
        &self.sqrt_m
    }

    /// `full` = K_σ⁻¹ (M^{1/2} z lifted to all equations).
    fn lift_solve(&mut self, z: &[f64]) -> Result<(), SolverError> {
        self.full.iter_mut().for_each(|v| *v = 0.0);
        for (i, &e) in self.massed.iter().enumerate() {
            self.full[e] = self.sqrt_m[i] * z[i];
        }
        if self.checked {
            self.solver.solve(self.pattern, &mut self.full)
        } else {
            // The iterations check their pairs themselves: near an eigenvalue K − σM is
            // nearly singular and the refinement may stall short of the LU's accuracy.
            self.solver.solve_unchecked(self.pattern, &mut self.full)
        }
    }

    /// y = C z.
    pub(crate) fn apply(&mut self, z: &[f64], y: &mut [f64]) -> Result<(), SolverError> {
        self.lift_solve(z)?;
        for (i, &e) in self.massed.iter().enumerate() {
            y[i] = self.sqrt_m[i] * self.full[e];
        }
        Ok(())
    }

    /// The mode shape on all equations of an eigenvector z of C with eigenvalue θ:
    /// φ = K_σ⁻¹ (M^{1/2} z) / θ.
    pub(crate) fn shape(&mut self, z: &[f64], theta: f64) -> Result<DVector<f64>, SolverError> {
        self.lift_solve(z)?;
        Ok(DVector::from_iterator(
            self.full.len(),
            self.full.iter().map(|v| v / theta),
        ))
    }

    /// The number of eigenvalues of the pencil below σ (module docs), `None` when the
    /// factorisation gives no inertia.
    pub(crate) fn count_below(&self) -> Option<usize> {
        self.solver.inertia().map(|i| i.negative)
    }
}
