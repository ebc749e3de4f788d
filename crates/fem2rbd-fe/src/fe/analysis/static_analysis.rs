//! Static analysis: load control (OpenSees `integrator LoadControl`, e.g. gravity in
//! N steps followed by [`crate::fe::domain::Domain::load_const`]) and displacement
//! control (OpenSees `integrator DisplacementControl`, for pushover).
//!
//! Residual: R(u) = P_const + λ·P_ref − F_int(u).

use super::algorithm::{solve_step, Algorithm, ConvergenceTest, StepProblem, Workspace};
use super::{AnalysisError, IterationFailure};
use crate::fe::domain::Domain;
use crate::fe::element::ElementError;
use crate::fe::linalg::{SparsePattern, StiffnessKind};

/// Settings of a load-control run.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadControl {
    /// Number of equal steps Δλ = 1/steps from the current λ (λ ends at λ₀ + 1).
    pub steps: usize,
    /// Convergence test (the reference gravity uses 1e-10 / 50).
    pub test: ConvergenceTest,
    /// Algorithms tried in order on each step (first = regular, rest = fallbacks).
    pub algorithms: Vec<Algorithm>,
}

impl Default for LoadControl {
    fn default() -> Self {
        Self {
            steps: 10,
            test: ConvergenceTest {
                tol: 1e-10,
                max_iter: 50,
            },
            algorithms: vec![Algorithm::Newton],
        }
    }
}

/// Per-step outcome of a static run.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticStep {
    /// λ after the step.
    pub load_factor: f64,
    /// Iterations used (by the algorithm that succeeded).
    pub iterations: usize,
}

struct StaticProblem {
    u: Vec<f64>,
    p: Vec<f64>,
    f: Vec<f64>,
}

impl StaticProblem {
    fn new(domain: &Domain) -> Self {
        let n = domain.num_equations();
        let mut u = vec![0.0; n];
        domain.trial_displacement_eq(&mut u);
        Self {
            u,
            p: vec![0.0; n],
            f: vec![0.0; n],
        }
    }
}

impl StepProblem for StaticProblem {
    fn residual(&mut self, domain: &Domain, out: &mut [f64]) {
        domain.external_load(&mut self.p);
        domain.resisting_force(&mut self.f);
        for ((o, p), f) in out.iter_mut().zip(&self.p).zip(&self.f) {
            *o = p - f;
        }
    }
    fn tangent(
        &mut self,
        domain: &Domain,
        pattern: &SparsePattern,
        kind: StiffnessKind,
        values: &mut [f64],
    ) {
        pattern.add_stiffness(domain, kind, 1.0, values);
    }
    fn apply(&mut self, domain: &mut Domain, du: &[f64]) -> Result<(), ElementError> {
        self.u.iter_mut().zip(du).for_each(|(u, d)| *u += d);
        domain.set_trial_eq(&self.u, None, None)
    }
}

/// Tries the algorithms in order; reverts the domain between attempts.
fn step_with_fallbacks(
    problem_at_start: &dyn Fn(&Domain) -> StaticProblem,
    domain: &mut Domain,
    ws: &mut Workspace,
    algorithms: &[Algorithm],
    test: ConvergenceTest,
) -> Result<usize, IterationFailure> {
    let mut last = IterationFailure::NotConverged {
        iterations: 0,
        norm: f64::NAN,
    };
    for alg in algorithms {
        let mut problem = problem_at_start(domain);
        match solve_step(&mut problem, domain, ws, *alg, test) {
            Ok(it) => return Ok(it),
            Err(e) => {
                domain.revert_to_last_commit();
                last = e;
            }
        }
    }
    Err(last)
}

/// Load control: λ += 1/steps per step, each step iterated to equilibrium and committed;
/// the pseudo-time follows λ (OpenSees). On failure the domain keeps the last converged
/// step and the error names the failed step.
pub fn load_control(
    domain: &mut Domain,
    settings: &LoadControl,
) -> Result<Vec<StaticStep>, AnalysisError> {
    if settings.steps == 0 || settings.algorithms.is_empty() {
        return Err(AnalysisError::Input(
            "load control needs steps ≥ 1 and an algorithm".into(),
        ));
    }
    let mut ws = Workspace::new(domain)?;
    let dl = 1.0 / settings.steps as f64;
    let mut out = Vec::with_capacity(settings.steps);
    for step in 1..=settings.steps {
        let lambda0 = domain.load_factor();
        let t0 = domain.time();
        let lambda = lambda0 + dl;
        domain.set_load_factor(lambda);
        let res = step_with_fallbacks(
            &StaticProblem::new,
            domain,
            &mut ws,
            &settings.algorithms,
            settings.test,
        );
        match res {
            Ok(iterations) => {
                domain.set_time(t0 + dl);
                domain.commit();
                out.push(StaticStep {
                    load_factor: lambda,
                    iterations,
                });
            }
            Err(reason) => {
                domain.set_load_factor(lambda0);
                return Err(AnalysisError::StaticStepFailed {
                    step,
                    load_factor: lambda,
                    reason,
                });
            }
        }
    }
    Ok(out)
}

/// Settings of a displacement-control run (OpenSees `integrator DisplacementControl`):
/// the load factor λ of the reference pattern is an unknown, found so that one DOF
/// moves by a prescribed increment per step. Passes limit points (softening), as a
/// pushover needs.
#[derive(Debug, Clone, PartialEq)]
pub struct DisplacementControl {
    /// Control node index.
    pub node: usize,
    /// Control DOF (0..6).
    pub dof: usize,
    /// Increment of the control DOF per step (m or rad).
    pub increment: f64,
    /// Number of steps.
    pub steps: usize,
    /// Convergence test.
    pub test: ConvergenceTest,
    /// When Newton fails: modified Newton with the initial stiffness, then Krylov–Newton,
    /// then Newton with line search ([`CONTROL_FALLBACKS`]).
    pub fallbacks: bool,
}

/// Newton iteration with the arc constraint "control DOF moves by `target`"
/// (Batoz & Dhatt 1979): per iteration solve K δu_R = R and K δu_P = P_ref, then
/// δλ = (target_remaining − δu_R[c]) / δu_P[c], δu = δu_R + δλ δu_P.
fn displacement_step(
    domain: &mut Domain,
    ws: &mut Workspace,
    c: usize,
    increment: f64,
    kind: StiffnessKind,
    test: ConvergenceTest,
) -> Result<usize, IterationFailure> {
    let n = ws.pattern.dim();
    let mut problem = StaticProblem::new(domain);
    let mut p_ref = vec![0.0; n];
    domain.reference_load(&mut p_ref);
    let mut du_p = vec![0.0; n];
    let mut remaining = increment;
    let mut last = f64::INFINITY;
    let mut factored = false;
    for it in 1..=test.max_iter {
        problem.residual(domain, &mut ws.r);
        if ws.r.iter().any(|x| !x.is_finite()) {
            return Err(IterationFailure::NonFiniteResidual);
        }
        if kind == StiffnessKind::Tangent || !factored {
            ws.values.iter_mut().for_each(|v| *v = 0.0);
            problem.tangent(domain, &ws.pattern, kind, &mut ws.values);
            ws.lu.factor(&ws.pattern, &ws.values)?;
            factored = true;
        }
        ws.du.copy_from_slice(&ws.r);
        ws.lu.solve(&ws.pattern, &mut ws.du)?;
        du_p.copy_from_slice(&p_ref);
        ws.lu.solve(&ws.pattern, &mut du_p)?;
        if du_p[c].abs() < f64::MIN_POSITIVE {
            return Err(IterationFailure::Control(
                "displacement control: the reference load does not move the control DOF".into(),
            ));
        }
        let dlambda = (remaining - ws.du[c]) / du_p[c];
        for (d, p) in ws.du.iter_mut().zip(&du_p) {
            *d += dlambda * p;
        }
        remaining = 0.0;
        domain.set_load_factor(domain.load_factor() + dlambda);
        problem.apply(domain, &ws.du)?;
        last = ws.du.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !last.is_finite() {
            return Err(IterationFailure::NonFiniteResidual);
        }
        if last <= test.tol {
            problem.residual(domain, &mut ws.r);
            if ws.r.iter().any(|x| !x.is_finite()) {
                return Err(IterationFailure::NonFiniteResidual);
            }
            return Ok(it);
        }
    }
    Err(IterationFailure::NotConverged {
        iterations: test.max_iter,
        norm: last,
    })
}

/// The displacement-control step as a [`StepProblem`], so that the general algorithms
/// (Krylov–Newton, Newton with line search) can iterate it as OpenSees' algorithms
/// iterate its `DisplacementControl` integrator: each correction δu_R the algorithm makes
/// is projected onto the constraint "the control DOF has moved by the increment" with
/// δλ = (remaining − δu_R[c]) / δu_P[c], δu = δu_R + δλ δu_P (Batoz & Dhatt 1979), where
/// δu_P = K⁻¹ P_ref is solved once with the tangent at the start of the step.
struct ControlledProblem {
    base: StaticProblem,
    c: usize,
    du_p: Vec<f64>,
    remaining: f64,
}

impl StepProblem for ControlledProblem {
    fn residual(&mut self, domain: &Domain, out: &mut [f64]) {
        self.base.residual(domain, out)
    }
    fn tangent(
        &mut self,
        domain: &Domain,
        pattern: &SparsePattern,
        kind: StiffnessKind,
        values: &mut [f64],
    ) {
        self.base.tangent(domain, pattern, kind, values)
    }
    fn apply(&mut self, domain: &mut Domain, du: &[f64]) -> Result<(), ElementError> {
        let dlambda = (self.remaining - du[self.c]) / self.du_p[self.c];
        self.remaining = 0.0;
        let full: Vec<f64> = du
            .iter()
            .zip(&self.du_p)
            .map(|(d, p)| d + dlambda * p)
            .collect();
        domain.set_load_factor(domain.load_factor() + dlambda);
        self.base.apply(domain, &full)
    }
}

/// One displacement-control step iterated by `algorithm` ([`ControlledProblem`]).
fn controlled_step(
    domain: &mut Domain,
    ws: &mut Workspace,
    c: usize,
    increment: f64,
    algorithm: Algorithm,
    test: ConvergenceTest,
) -> Result<usize, IterationFailure> {
    let n = ws.pattern.dim();
    let mut problem = ControlledProblem {
        base: StaticProblem::new(domain),
        c,
        du_p: vec![0.0; n],
        remaining: increment,
    };
    ws.factor(&mut problem, domain, StiffnessKind::Tangent)?;
    domain.reference_load(&mut problem.du_p);
    ws.lu.solve(&ws.pattern, &mut problem.du_p)?;
    if problem.du_p[c].abs() < f64::MIN_POSITIVE {
        return Err(IterationFailure::Control(
            "displacement control: the reference load does not move the control DOF".into(),
        ));
    }
    solve_step(&mut problem, domain, ws, algorithm, test)
}

/// The algorithms a displacement-control step falls back to when Newton and modified
/// Newton on the initial stiffness fail, in the order of OpenSees' pushover scripts:
/// Krylov–Newton (subspace 3), then Newton with line search (ratio 0.8).
const CONTROL_FALLBACKS: [Algorithm; 2] = [
    Algorithm::KrylovNewton { max_dim: 3 },
    Algorithm::NewtonLineSearch { ratio: 0.8 },
];

/// One pushover increment: moves the control DOF (`node`, `dof`) by `increment` with
/// Newton (tolerance `test`, the fallbacks of [`DisplacementControl::fallbacks`]); if that
/// fails, retries what is
/// left in 2, then 4, then 8 equal sub-steps. Returns whether the increment was reached;
/// on `false` the domain keeps its last converged state (past a pushover's peak the
/// curve ends there). OpenSees's pushover scripts fall back to other algorithms instead.
pub fn displacement_increment(
    domain: &mut Domain,
    node: usize,
    dof: usize,
    increment: f64,
    test: ConvergenceTest,
) -> bool {
    let target = domain.displacement(node)[dof] + increment;
    [1usize, 2, 4, 8].into_iter().any(|n| {
        let left = target - domain.displacement(node)[dof];
        let ctl = DisplacementControl {
            node,
            dof,
            increment: left / n as f64,
            steps: n,
            test,
            fallbacks: true,
        };
        displacement_control(domain, &ctl).is_ok()
    })
}

/// Displacement control: each step moves the control DOF by `increment` and finds λ.
/// Returns per step λ and iterations. On failure the domain keeps the last converged
/// step and the error names the failed step.
pub fn displacement_control(
    domain: &mut Domain,
    settings: &DisplacementControl,
) -> Result<Vec<StaticStep>, AnalysisError> {
    if !domain.is_numbered() {
        domain.number_dofs();
    }
    let c = domain
        .equation(settings.node, settings.dof)
        .ok_or_else(|| {
            AnalysisError::Input(format!(
                "displacement control: node index {} DOF {} is not a free DOF",
                settings.node, settings.dof
            ))
        })?;
    if settings.steps == 0 || !(settings.increment.is_finite() && settings.increment != 0.0) {
        return Err(AnalysisError::Input(
            "displacement control: steps ≥ 1, increment ≠ 0".into(),
        ));
    }
    let mut ws = Workspace::new(domain)?;
    let mut kinds = vec![StiffnessKind::Tangent];
    if settings.fallbacks {
        kinds.push(StiffnessKind::Initial);
    }
    let mut out = Vec::with_capacity(settings.steps);
    for step in 1..=settings.steps {
        let lambda0 = domain.load_factor();
        let t0 = domain.time();
        let mut result = Err(IterationFailure::NotConverged {
            iterations: 0,
            norm: f64::NAN,
        });
        for &kind in &kinds {
            result = displacement_step(domain, &mut ws, c, settings.increment, kind, settings.test);
            if result.is_ok() {
                break;
            }
            domain.revert_to_last_commit();
            domain.set_load_factor(lambda0);
        }
        if result.is_err() && settings.fallbacks {
            for algorithm in CONTROL_FALLBACKS {
                result = controlled_step(
                    domain,
                    &mut ws,
                    c,
                    settings.increment,
                    algorithm,
                    settings.test,
                );
                if result.is_ok() {
                    break;
                }
                domain.revert_to_last_commit();
                domain.set_load_factor(lambda0);
            }
        }
        match result {
            Ok(iterations) => {
                domain.set_time(t0 + 1.0);
                domain.commit();
                out.push(StaticStep {
                    load_factor: domain.load_factor(),
                    iterations,
                });
            }
            Err(reason) => {
                return Err(AnalysisError::StaticStepFailed {
                    step,
                    load_factor: lambda0,
                    reason,
                });
            }
        }
    }
    Ok(out)
}
