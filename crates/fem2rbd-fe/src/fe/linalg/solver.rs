//! Sparse solvers (faer), symbolic analyses computed once per pattern and reused for
//! every numeric factorisation: [`SparseLu`], LU with partial pivoting (COLAMD ordering,
//! supernodal), and [`SparseSolver`], the Newton iterations' solver: a symmetric
//! indefinite LBLᵀ of the matrix's symmetric part (AMD ordering) with iterative
//! refinement, falling back to [`SparseLu`]. Singular or non-finite systems are errors,
//! not panics.

// `!(x <= y)` is used on purpose: NaN counts as a failure.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::supernodal::SupernodalIntranodeLbltRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, IntranodeLbltRef, SymbolicCholesky,
    SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::lu::{
    factorize_symbolic_lu, LuRef, LuSymbolicParams, NumericLu, SymbolicLu,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::{Conj, MatMut, Par, Side};

use super::pattern::SparsePattern;

/// Failure of a factorisation or solve.
#[derive(Debug, Clone, thiserror::Error, PartialEq)]
pub enum SolverError {
    /// The matrix holds NaN or infinite entries.
    #[error("matrix has non-finite entries")]
    NonFiniteMatrix,
    /// The matrix is (numerically) singular: zero pivot, or a non-finite solution.
    #[error("matrix is singular (zero pivot or non-finite solution)")]
    Singular,
    /// Symbolic analysis or memory failure inside faer.
    #[error("sparse factorisation failed: {0}")]
    Faer(String),
    /// `solve` called before a successful `factor`.
    #[error("solve before factorisation")]
    NotFactored,
}

/// Sparse LU solver bound to one [`SparsePattern`].
pub struct SparseLu {
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    factored: bool,
    factor_mem: MemBuffer,
    solve_mem: MemBuffer,
    n: usize,
}

impl std::fmt::Debug for SparseLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseLu")
            .field("n", &self.n)
            .field("factored", &self.factored)
            .finish()
    }
}

impl SparseLu {
    /// Symbolic analysis of the pattern (once).
    pub fn new(pattern: &SparsePattern) -> Result<Self, SolverError> {
        // Supernodal: its numeric factorisation reuses the symbolic structure; faer's
        // simplicial LU re-runs a depth-first search per column at every factorisation
        // (measured 7× slower on frame3's 234 equations).
        let params = LuSymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        let symbolic = factorize_symbolic_lu(pattern.symbolic(), params)
            .map_err(|e| SolverError::Faer(format!("{e:?}")))?;
        let factor_mem = MemBuffer::try_new(
            symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()),
        )
        .map_err(|e| SolverError::Faer(format!("{e:?}")))?;
        let solve_mem = MemBuffer::try_new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq))
            .map_err(|e| SolverError::Faer(format!("{e:?}")))?;
        Ok(Self {
            symbolic,
            numeric: NumericLu::new(),
            factored: false,
            factor_mem,
            solve_mem,
            n: pattern.dim(),
        })
    }

    /// Numeric factorisation of `values` (on the pattern given to [`SparseLu::new`]).
    pub fn factor(&mut self, pattern: &SparsePattern, values: &[f64]) -> Result<(), SolverError> {
        self.factored = false;
        if values.iter().any(|x| !x.is_finite()) {
            return Err(SolverError::NonFiniteMatrix);
        }
        if self.n == 0 {
            self.factored = true;
            return Ok(());
        }
        let res = self.symbolic.factorize_numeric_lu(
            &mut self.numeric,
            pattern.as_mat(values),
            Par::Seq,
            MemStack::new(&mut self.factor_mem),
            Default::default(),
        );
        match res {
            Ok(_) => {
                self.factored = true;
                Ok(())
            }
            Err(faer::sparse::linalg::LuError::SymbolicSingular { .. }) => {
                Err(SolverError::Singular)
            }
            Err(e) => Err(SolverError::Faer(format!("{e:?}"))),
        }
    }

    /// Solves `A x = b` in place (`rhs` holds b on entry, x on exit).
    pub fn solve(&mut self, rhs: &mut [f64]) -> Result<(), SolverError> {
        if !self.factored {
            return Err(SolverError::NotFactored);
        }
        if self.n == 0 {
            return Ok(());
        }
        let lu = LuRef::new_unchecked(&self.symbolic, &self.numeric);
        let n = rhs.len();
        lu.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            Par::Seq,
            MemStack::new(&mut self.solve_mem),
        );
        if rhs.iter().any(|x| !x.is_finite()) {
            return Err(SolverError::Singular);
        }
        Ok(())
    }
}

/// Largest componentwise backward error accepted from the symmetric path of
/// [`SparseSolver`]: 64 ε (ε = 2.2e-16, f64), i.e. the solution solves a system whose
/// entries differ from `A`'s and `b`'s by at most 1.4e-14 of their size — what a
/// backward-stable LU gives (its error is a small multiple of ε times the growth factor).
const BERR_ACCEPT: f64 = 64.0 * f64::EPSILON;
/// Refinement steps before the symmetric path gives up for this matrix.
const MAX_REFINE: usize = 8;

/// Inertia of a symmetric matrix: how many of its eigenvalues are negative, zero and
/// positive (Sylvester's law of inertia: those of the block-diagonal B of any
/// congruence A = P L B Lᵀ Pᵀ).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Inertia {
    /// Negative eigenvalues.
    pub negative: usize,
    /// Zero eigenvalues (exactly zero pivots).
    pub zero: usize,
    /// Positive eigenvalues.
    pub positive: usize,
}

/// What [`SparseSolver`] did so far.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SolverStats {
    /// Numeric factorisations of the symmetric part (LBLᵀ).
    pub symmetric_factorisations: u64,
    /// Solves that the symmetric path with refinement met ([`BERR_ACCEPT`]).
    pub refined_solves: u64,
    /// Refinement steps over all solves (one residual and one LBLᵀ solve each).
    pub refinement_steps: u64,
    /// Numeric LU factorisations (the fallback; see [`SparseSolver`]).
    pub lu_factorisations: u64,
}

/// Linear solver of the Newton iterations: a symmetric factorisation of the matrix's
/// symmetric part, iterative refinement on the matrix itself, and the LU of
/// [`SparseLu`] only for matrices where that does not reach LU accuracy.
///
/// The effective tangents are symmetric for linear and P-Delta transformations and
/// nearly so with the corotational one (its geometric stiffness K_g ≈ ∂Tᵀ/∂u·p is not
/// symmetric; measured max |a_ij − a_ji| / max |a| = 7e-11 on the 7-story frame of
/// docs/performance.md). A sparse LU with partial pivoting on COLAMD's column order
/// fills in far more than a symmetric factorisation on AMD's order: on that frame's
/// 6 384 equations faer's LU took 170 ms, the supernodal LBLᵀ 16 ms. So:
///
/// 1. `factor`: S = (A + Aᵀ)/2, S = P L B Lᵀ Pᵀ (faer's supernodal Cholesky structure on
///    AMD's order, computed once per pattern; Bunch-Kaufman 1×1/2×2 pivots inside each
///    supernode, so indefinite tangents of a softening structure factor too).
/// 2. `solve`: x₀ = S⁻¹b, then x_{k+1} = x_k + S⁻¹(b − A x_k) (iterative refinement;
///    converges when ‖S⁻¹(A − S)‖ < 1, in one or two steps for these tangents) until the
///    componentwise backward error ω = max_i |b − A x|_i / (|A||x| + |b|)_i (Oettli &
///    Prager 1964; LAPACK's `dgerfs` criterion) is ≤ 64 ε, at most 8 steps or while ω
///    halves.
/// 3. If ω is not met (strong asymmetry, or a pivot the intranode pivoting cannot
///    handle), the matrix is factored by [`SparseLu`] and solved as before; that LU is
///    kept for further solves with the same matrix.
///
/// Everything runs on one thread in a fixed order: the same bits on every run and for
/// any `FEM2RBD_THREADS`.
pub struct SparseSolver {
    n: usize,
    symbolic: Option<SymbolicCholesky<usize>>,
    /// Value position of the transposed entry, per stored entry.
    transpose: Vec<usize>,
    a: Vec<f64>,
    sym: Vec<f64>,
    l: Vec<f64>,
    subdiag: Vec<f64>,
    perm_fwd: Vec<usize>,
    perm_inv: Vec<usize>,
    factor_mem: MemBuffer,
    solve_mem: MemBuffer,
    /// Whether the symmetric factors are finite (else the LU is used directly).
    symmetric_ok: bool,
    /// Made on the first fallback: its symbolic analysis and scratch are large.
    lu: Option<SparseLu>,
    /// Whether `lu` holds the factors of the current matrix.
    lu_current: bool,
    factored: bool,
    stats: SolverStats,
    r: Vec<f64>,
    d: Vec<f64>,
    ax: Vec<f64>,
}

impl std::fmt::Debug for SparseSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseSolver")
            .field("n", &self.n)
            .field("factored", &self.factored)
            .field("stats", &self.stats)
            .finish()
    }
}

impl SparseSolver {
    /// Symbolic analyses of the pattern (once): AMD order and supernodal structure of the
    /// symmetric factorisation, and the LU's (for the fallback).
    pub fn new(pattern: &SparsePattern) -> Result<Self, SolverError> {
        let faer_err = |e: &dyn std::fmt::Debug| SolverError::Faer(format!("{e:?}"));
        let n = pattern.dim();
        let sym_pat = pattern.symbolic();
        let (cp, ri) = (sym_pat.col_ptr(), sym_pat.row_idx());
        let mut transpose = vec![0; pattern.nnz()];
        for c in 0..n {
            for p in cp[c]..cp[c + 1] {
                let r = ri[p];
                let rows = &ri[cp[r]..cp[r + 1]];
                // The pattern is structurally symmetric (SparsePattern::new).
                transpose[p] = cp[r] + rows.binary_search(&c).map_err(|e| faer_err(&e))?;
            }
        }
        let (symbolic, factor_mem, solve_mem) = if n == 0 {
            (
                None,
                MemBuffer::new(StackReq::EMPTY),
                MemBuffer::new(StackReq::EMPTY),
            )
        } else {
            let symbolic = factorize_symbolic_cholesky(
                sym_pat,
                Side::Lower,
                SymmetricOrdering::Amd,
                CholeskySymbolicParams {
                    supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                    ..Default::default()
                },
            )
            .map_err(|e| faer_err(&e))?;
            let factor_mem = MemBuffer::try_new(
                symbolic
                    .factorize_numeric_intranode_lblt_scratch::<f64>(Par::Seq, Default::default()),
            )
            .map_err(|e| faer_err(&e))?;
            let solve_mem = MemBuffer::try_new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq))
                .map_err(|e| faer_err(&e))?;
            (Some(symbolic), factor_mem, solve_mem)
        };
        let len_l = symbolic.as_ref().map_or(0, |s| s.len_val());
        Ok(Self {
            n,
            symbolic,
            transpose,
            a: pattern.zeros(),
            sym: pattern.zeros(),
            l: vec![0.0; len_l],
            subdiag: vec![0.0; n],
            perm_fwd: (0..n).collect(),
            perm_inv: (0..n).collect(),
            factor_mem,
            solve_mem,
            symmetric_ok: false,
            lu: None,
            lu_current: false,
            factored: false,
            stats: SolverStats::default(),
            r: vec![0.0; n],
            d: vec![0.0; n],
            ax: vec![0.0; n],
        })
    }

    /// What the solver did so far.
    pub fn stats(&self) -> SolverStats {
        self.stats
    }

    /// Numeric factorisation of `values` (on the pattern given to [`SparseSolver::new`]):
    /// the LBLᵀ of its symmetric part; the LU only if that is not finite.
    pub fn factor(&mut self, pattern: &SparsePattern, values: &[f64]) -> Result<(), SolverError> {
        self.factored = false;
        self.lu_current = false;
        if values.iter().any(|x| !x.is_finite()) {
            return Err(SolverError::NonFiniteMatrix);
        }
        self.a.copy_from_slice(values);
        let Some(symbolic) = &self.symbolic else {
            self.factored = true;
            return Ok(());
        };
        for (p, s) in self.sym.iter_mut().enumerate() {
            *s = 0.5 * (values[p] + values[self.transpose[p]]);
        }
        symbolic.factorize_numeric_intranode_lblt(
            &mut self.l,
            &mut self.subdiag,
            &mut self.perm_fwd,
            &mut self.perm_inv,
            pattern.as_mat(&self.sym),
            Side::Lower,
            Par::Seq,
            MemStack::new(&mut self.factor_mem),
            Default::default(),
        );
        self.stats.symmetric_factorisations += 1;
        self.symmetric_ok = self.l.iter().chain(&self.subdiag).all(|x| x.is_finite());
        if !self.symmetric_ok {
            self.factor_lu(pattern)?;
        }
        self.factored = true;
        Ok(())
    }

    /// Inertia of the symmetric part S = (A + Aᵀ)/2 of the last factored matrix, read
    /// from its LBLᵀ's block diagonal B: a 1 × 1 pivot d counts by its sign; a 2 × 2 pivot
    /// [[a, s], [s, b]] has one negative and one positive eigenvalue when ab − s² < 0,
    /// else two of a's sign. `None` when nothing is factored or the symmetric factors are
    /// not finite. Applied to K − σM this is the Sturm sequence count of the eigenvalues
    /// below σ (Bathe, *Finite Element Procedures*, §11.4.3).
    pub fn inertia(&self) -> Option<Inertia> {
        if !self.factored || !self.symmetric_ok {
            return None;
        }
        let Some(symbolic) = &self.symbolic else {
            return Some(Inertia::default());
        };
        let SymbolicCholeskyRaw::Supernodal(supernodal) = symbolic.raw() else {
            return None;
        };
        let perm = PermRef::new_checked(&self.perm_fwd, &self.perm_inv, self.n);
        let factors = SupernodalIntranodeLbltRef::new(supernodal, &self.l, &self.subdiag, perm);
        let mut inertia = Inertia::default();
        let mut count = |v: f64| match v.partial_cmp(&0.0) {
            Some(std::cmp::Ordering::Less) => inertia.negative += 1,
            Some(std::cmp::Ordering::Greater) => inertia.positive += 1,
            _ => inertia.zero += 1,
        };
        for s in 0..supernodal.n_supernodes() {
            let node = factors.supernode(s);
            let start = node.start();
            let b = node.val();
            let size = b.ncols();
            let mut j = 0;
            while j < size {
                let off = self.subdiag[start + j];
                if off == 0.0 {
                    count(b[(j, j)]);
                    j += 1;
                } else {
                    let (a, d) = (b[(j, j)], b[(j + 1, j + 1)]);
                    let det = a * d - off * off;
                    if det < 0.0 {
                        count(-1.0);
                        count(1.0);
                    } else if det > 0.0 {
                        count(a);
                        count(a);
                    } else {
                        count(0.0);
                        count(a + d);
                    }
                    j += 2;
                }
            }
        }
        Some(inertia)
    }

    fn factor_lu(&mut self, pattern: &SparsePattern) -> Result<(), SolverError> {
        self.stats.lu_factorisations += 1;
        if self.lu.is_none() {
            self.lu = Some(SparseLu::new(pattern)?);
        }
        self.lu
            .as_mut()
            .expect("made above")
            .factor(pattern, &self.a)?;
        self.lu_current = true;
        Ok(())
    }

    fn symmetric_solve(&mut self, x: &mut [f64]) {
        let Some(symbolic) = &self.symbolic else {
            return;
        };
        let perm = PermRef::new_checked(&self.perm_fwd, &self.perm_inv, self.n);
        IntranodeLbltRef::new(symbolic, &self.l, &self.subdiag, perm).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(x, self.n, 1),
            Par::Seq,
            MemStack::new(&mut self.solve_mem),
        );
    }

    /// r = b − A x and the componentwise backward error max_i |r_i| / (|A||x| + |b|)_i.
    fn residual(&mut self, pattern: &SparsePattern, b: &[f64], x: &[f64]) -> f64 {
        let sym = pattern.symbolic();
        let (cp, ri) = (sym.col_ptr(), sym.row_idx());
        self.r.copy_from_slice(b);
        self.ax.iter_mut().zip(b).for_each(|(s, b)| *s = b.abs());
        for c in 0..self.n {
            let xc = x[c];
            for p in cp[c]..cp[c + 1] {
                let v = self.a[p] * xc;
                self.r[ri[p]] -= v;
                self.ax[ri[p]] += v.abs();
            }
        }
        let mut omega = 0.0f64;
        for (r, s) in self.r.iter().zip(&self.ax) {
            let e = if *s > 0.0 {
                r.abs() / s
            } else if *r == 0.0 {
                0.0
            } else {
                f64::INFINITY
            };
            if e.is_nan() {
                return f64::INFINITY;
            }
            omega = omega.max(e);
        }
        omega
    }

    /// The symmetric solve of `b` with iterative refinement (step 2 of the type docs):
    /// `x` holds the best solution on exit; returns its backward error ω.
    fn refined(&mut self, pattern: &SparsePattern, b: &[f64], x: &mut [f64]) -> f64 {
        x.copy_from_slice(b);
        self.symmetric_solve(x);
        let mut omega = self.residual(pattern, b, x);
        let mut steps = 0;
        while omega.is_finite() && omega > BERR_ACCEPT && steps < MAX_REFINE {
            let mut d = std::mem::take(&mut self.d);
            d.copy_from_slice(&self.r);
            self.symmetric_solve(&mut d);
            let mut next = x.to_vec();
            next.iter_mut().zip(&d).for_each(|(x, d)| *x += d);
            self.d = d;
            steps += 1;
            let w = self.residual(pattern, b, &next);
            if w.is_nan() || w >= omega {
                break;
            }
            x.copy_from_slice(&next);
            let halved = w <= 0.5 * omega;
            omega = w;
            if !halved {
                break;
            }
        }
        self.stats.refinement_steps += steps as u64;
        omega
    }

    /// Solves `A x = b` in place (`rhs` holds b on entry, x on exit) for the matrix of the
    /// last [`SparseSolver::factor`].
    pub fn solve(&mut self, pattern: &SparsePattern, rhs: &mut [f64]) -> Result<(), SolverError> {
        self.solve_accepting(pattern, rhs, Acceptance::BackwardError)
    }

    /// As [`SparseSolver::solve`] for an iteration that checks its own accuracy (the
    /// eigen solvers' shift-invert steps): the symmetric solve with iterative
    /// refinement is kept even when its backward error stays above 64 ε. Near an
    /// eigenvalue K − σM is nearly singular and refinement stalls; the LU fallback would
    /// buy nothing such an iteration needs, at a cost (over 9 GB on a 130 000-equation
    /// frame). A solution that is not finite is [`SolverError::Singular`].
    pub fn solve_unchecked(
        &mut self,
        pattern: &SparsePattern,
        rhs: &mut [f64],
    ) -> Result<(), SolverError> {
        self.solve_accepting(pattern, rhs, Acceptance::Finite)
    }

    /// The symmetric solve with iterative refinement, its result judged by `acceptance`;
    /// the LU when the symmetric factors are unusable or already replaced.
    fn solve_accepting(
        &mut self,
        pattern: &SparsePattern,
        rhs: &mut [f64],
        acceptance: Acceptance,
    ) -> Result<(), SolverError> {
        if !self.factored {
            return Err(SolverError::NotFactored);
        }
        if self.n == 0 {
            return Ok(());
        }
        if self.symmetric_ok && !self.lu_current {
            let b = rhs.to_vec();
            let omega = self.refined(pattern, &b, rhs);
            match acceptance {
                Acceptance::BackwardError if omega <= BERR_ACCEPT => {
                    self.stats.refined_solves += 1;
                    return Ok(());
                }
                Acceptance::BackwardError => {
                    rhs.copy_from_slice(&b);
                    self.factor_lu(pattern)?;
                }
                Acceptance::Finite if rhs.iter().all(|x| x.is_finite()) => return Ok(()),
                Acceptance::Finite => return Err(SolverError::Singular),
            }
        }
        self.lu.as_mut().expect("factored by factor_lu").solve(rhs)
    }
}

/// When [`SparseSolver`] accepts the refined symmetric solution.
#[derive(Clone, Copy, Debug)]
enum Acceptance {
    /// Its componentwise backward error is at most 64 ε; otherwise the LU solves.
    BackwardError,
    /// It is finite (the caller checks its own accuracy).
    Finite,
}
