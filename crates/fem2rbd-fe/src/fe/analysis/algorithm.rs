//! Solution algorithms for one load or time step (OpenSees `algorithm`), with the
//! displacement-increment convergence test (OpenSees `NormDispIncr`: ‖Δu‖₂ ≤ tol, over
//! all free DOFs, m and rad mixed).
//!
//! A step is a nonlinear problem R(u) = 0 in the equation unknowns u; `StepProblem`
//! supplies the residual, the effective tangent and the update. Every failure — element
//! error, singular or non-finite matrix, NaN in a residual, no convergence — is an
//! [`IterationFailure`], never a panic.

use crate::fe::domain::Domain;
use crate::fe::element::ElementError;
use crate::fe::linalg::{SolverError, SparsePattern, SparseSolver, StiffnessKind};
use crate::fe::profile::{self, Phase};

/// Equilibrium-iteration algorithm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Algorithm {
    /// Newton-Raphson, tangent re-formed every iteration (OpenSees `Newton`).
    Newton,
    /// Modified Newton with the initial stiffness (OpenSees `ModifiedNewton -initial`).
    ModifiedNewtonInitial,
    /// Krylov-subspace accelerated modified Newton (Carlson & Miller 1998, Scott &
    /// Fenves 2003; OpenSees `KrylovNewton`): tangent formed at the start of the step,
    /// corrections accelerated by a least-squares fit over the previous corrections;
    /// when more than `max_dim` are held the subspace restarts with a new tangent.
    KrylovNewton {
        /// Subspace dimension before restart (OpenSees default 3).
        max_dim: usize,
    },
    /// Newton with an initial-interpolated line search (OpenSees `NewtonLineSearch`,
    /// `InitialInterpolated`): accept η when |s(η)/s(0)| ≤ `ratio`, s(η) = Δu·R(u+ηΔu).
    NewtonLineSearch {
        /// Tolerance on |s(η)/s(0)| (0.8 in the reference runs).
        ratio: f64,
    },
}

/// `NormDispIncr` convergence test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConvergenceTest {
    /// Tolerance on ‖Δu‖₂ (m, rad mixed).
    pub tol: f64,
    /// Maximum iterations.
    pub max_iter: usize,
}

/// Why a step failed.
#[derive(Debug, Clone, thiserror::Error, PartialEq)]
pub enum IterationFailure {
    /// An element's state determination failed.
    #[error("element {element}: {reason}")]
    Element {
        /// The element's tag.
        element: i64,
        /// What went wrong.
        reason: String,
    },
    /// A displacement-control step cannot move its control DOF.
    #[error("{0}")]
    Control(String),
    /// The linear solve failed.
    #[error("linear solver: {0}")]
    Solver(#[from] SolverError),
    /// NaN or infinity in the residual.
    #[error("non-finite residual")]
    NonFiniteResidual,
    /// The test was not met within the iteration limit.
    #[error("no convergence in {iterations} iterations (last ‖Δu‖ = {norm:.3e})")]
    NotConverged {
        /// Iterations done.
        iterations: usize,
        /// Last ‖Δu‖₂.
        norm: f64,
    },
}

impl From<ElementError> for IterationFailure {
    fn from(e: ElementError) -> Self {
        IterationFailure::Element {
            element: e.element,
            reason: e.reason,
        }
    }
}

/// One step's nonlinear problem.
pub(crate) trait StepProblem {
    /// Effective residual R at the current trial state (N, N·m).
    fn residual(&mut self, domain: &Domain, out: &mut [f64]);
    /// Effective tangent −∂R/∂u using the element `kind` stiffness, into `values`.
    /// `values` is zeroed on entry and laid out on `pattern`.
    fn tangent(
        &mut self,
        domain: &Domain,
        pattern: &SparsePattern,
        kind: StiffnessKind,
        values: &mut [f64],
    );
    /// Adds `du` to the trial unknowns and updates the domain (elements included).
    fn apply(&mut self, domain: &mut Domain, du: &[f64]) -> Result<(), ElementError>;
}

/// Matrices and vectors reused across iterations and steps.
#[derive(Debug)]
pub(crate) struct Workspace {
    pub pattern: SparsePattern,
    pub lu: SparseSolver,
    pub values: Vec<f64>,
    pub r: Vec<f64>,
    pub du: Vec<f64>,
}

impl Workspace {
    pub fn new(domain: &mut Domain) -> Result<Self, SolverError> {
        let pattern = SparsePattern::new(domain);
        let lu = SparseSolver::new(&pattern)?;
        let n = pattern.dim();
        Ok(Self {
            values: pattern.zeros(),
            lu,
            pattern,
            r: vec![0.0; n],
            du: vec![0.0; n],
        })
    }

    pub(crate) fn factor(
        &mut self,
        problem: &mut dyn StepProblem,
        domain: &Domain,
        kind: StiffnessKind,
    ) -> Result<(), SolverError> {
        profile::timed(Phase::Assembly, || {
            self.values.iter_mut().for_each(|v| *v = 0.0);
            problem.tangent(domain, &self.pattern, kind, &mut self.values);
        });
        profile::timed(Phase::Factor, || {
            self.lu.factor(&self.pattern, &self.values)
        })
    }
}

fn norm(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

fn dot(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).map(|(a, b)| a * b).sum()
}

fn residual_checked(
    problem: &mut dyn StepProblem,
    domain: &Domain,
    r: &mut [f64],
) -> Result<(), IterationFailure> {
    profile::timed(Phase::Residual, || problem.residual(domain, r));
    if r.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(IterationFailure::NonFiniteResidual)
    }
}

/// Iterates one step to convergence. Returns the number of iterations. On failure the
/// domain holds a trial state the caller must revert.
pub(crate) fn solve_step(
    problem: &mut dyn StepProblem,
    domain: &mut Domain,
    ws: &mut Workspace,
    algorithm: Algorithm,
    test: ConvergenceTest,
) -> Result<usize, IterationFailure> {
    let mut last = f64::INFINITY;
    // Krylov subspace: corrections V and their images AV ≈ K0⁻¹ K V.
    let mut v_sub: Vec<Vec<f64>> = Vec::new();
    let mut av_sub: Vec<Vec<f64>> = Vec::new();
    match algorithm {
        Algorithm::ModifiedNewtonInitial => ws.factor(problem, domain, StiffnessKind::Initial)?,
        Algorithm::KrylovNewton { .. } => ws.factor(problem, domain, StiffnessKind::Tangent)?,
        _ => {}
    }
    for it in 1..=test.max_iter {
        residual_checked(problem, domain, &mut ws.r)?;
        if matches!(
            algorithm,
            Algorithm::Newton | Algorithm::NewtonLineSearch { .. }
        ) {
            ws.factor(problem, domain, StiffnessKind::Tangent)?;
        }
        if let Algorithm::KrylovNewton { max_dim } = algorithm {
            // Restart (OpenSees): when the subspace exceeds its dimension, clear it and
            // re-form the tangent at the current state.
            if v_sub.len() > max_dim {
                v_sub.clear();
                av_sub.clear();
                ws.factor(problem, domain, StiffnessKind::Tangent)?;
            }
        }
        ws.du.copy_from_slice(&ws.r);
        profile::timed(Phase::Solve, || ws.lu.solve(&ws.pattern, &mut ws.du))?;
        let step_norm = match algorithm {
            Algorithm::Newton | Algorithm::ModifiedNewtonInitial => {
                problem.apply(domain, &ws.du)?;
                norm(&ws.du)
            }
            Algorithm::KrylovNewton { .. } => {
                let y = ws.du.clone();
                if let Some(last_av) = av_sub.last_mut() {
                    last_av.iter_mut().zip(&y).for_each(|(a, b)| *a -= b);
                }
                let v = krylov_correction(&v_sub, &av_sub, &y);
                problem.apply(domain, &v)?;
                let n = norm(&v);
                v_sub.push(v);
                av_sub.push(y);
                n
            }
            Algorithm::NewtonLineSearch { ratio } => line_search(problem, domain, ws, ratio)?,
        };
        last = step_norm;
        if !step_norm.is_finite() {
            return Err(IterationFailure::NonFiniteResidual);
        }
        if step_norm <= test.tol {
            residual_checked(problem, domain, &mut ws.r)?;
            return Ok(it);
        }
    }
    Err(IterationFailure::NotConverged {
        iterations: test.max_iter,
        norm: last,
    })
}

/// Krylov acceleration: c = argmin ‖y − AV c‖₂ (normal equations, Cholesky), correction
/// v = V c + (y − AV c). Falls back to v = y if the small system is singular.
fn krylov_correction(v_sub: &[Vec<f64>], av_sub: &[Vec<f64>], y: &[f64]) -> Vec<f64> {
    let m = v_sub.len();
    if m == 0 {
        return y.to_vec();
    }
    let mut g = nalgebra::DMatrix::<f64>::zeros(m, m);
    let mut b = nalgebra::DVector::<f64>::zeros(m);
    for i in 0..m {
        b[i] = dot(&av_sub[i], y);
        for j in 0..m {
            g[(i, j)] = dot(&av_sub[i], &av_sub[j]);
        }
    }
    let Some(c) = g.cholesky().map(|ch| ch.solve(&b)) else {
        return y.to_vec();
    };
    if c.iter().any(|x| !x.is_finite()) {
        return y.to_vec();
    }
    let mut v = y.to_vec();
    for i in 0..m {
        for k in 0..v.len() {
            v[k] += c[i] * (v_sub[i][k] - av_sub[i][k]);
        }
    }
    v
}

/// Initial-interpolated line search along Newton direction `ws.du`, residual `ws.r` at
/// η = 0. Applies η·Δu and returns ‖η·Δu‖₂. η bounded to [0.1, 10], at most 10 trials.
fn line_search(
    problem: &mut dyn StepProblem,
    domain: &mut Domain,
    ws: &mut Workspace,
    ratio: f64,
) -> Result<f64, IterationFailure> {
    let s0 = dot(&ws.du, &ws.r);
    problem.apply(domain, &ws.du)?;
    let mut eta = 1.0;
    if s0.abs() <= f64::MIN_POSITIVE {
        return Ok(norm(&ws.du));
    }
    residual_checked(problem, domain, &mut ws.r)?;
    let mut s = dot(&ws.du, &ws.r);
    let mut count = 0;
    while (s / s0).abs() > ratio && count < 10 {
        count += 1;
        let denom = s0 - s;
        let mut next = if denom.abs() > f64::MIN_POSITIVE {
            eta * s0 / denom
        } else {
            10.0
        };
        next = next.clamp(0.1, 10.0);
        let change: Vec<f64> = ws.du.iter().map(|d| (next - eta) * d).collect();
        problem.apply(domain, &change)?;
        eta = next;
        residual_checked(problem, domain, &mut ws.r)?;
        s = dot(&ws.du, &ws.r);
    }
    Ok(eta.abs() * norm(&ws.du))
}
