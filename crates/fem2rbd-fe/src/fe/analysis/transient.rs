//! Transient analysis: Newmark time integration with Newton equilibrium iterations,
//! Rayleigh damping on the initial stiffness, uniform three-component base excitation,
//! and OpenSees-style fallbacks when a step fails.
//!
//! Equation of motion in relative coordinates (OpenSees `UniformExcitation`):
//! M ü + C u̇ + F(u) = P_static − M Σ_d ι_d a_g,d(t), C = a0·M + a1·K_initial,
//! with P_static the loads held constant (gravity after `loadConst`) plus λ·P_ref.
//!
//! Newmark (Newmark 1959; OpenSees `Newmark`), displacement as unknown:
//! ü_{n+1} = (u_{n+1} − u_n)/(βΔt²) − u̇_n/(βΔt) − (1/(2β) − 1) ü_n,
//! u̇_{n+1} = u̇_n + Δt[(1 − γ) ü_n + γ ü_{n+1}],
//! effective tangent K_T + γ/(βΔt)·C + 1/(βΔt²)·M. The predictor keeps u_{n+1} = u_n
//! (OpenSees). The initial acceleration is the committed one (zero after a static
//! analysis), as in OpenSees.
//!
//! Fallbacks: if the regular algorithm fails, the step is retried with each fallback
//! algorithm at Δt/1, then in 2, 4, 8, 16 sub-steps (OpenSees-style; the reference
//! script `run_frame3.py`). Sub-steps that converged stay committed (elements keep one
//! committed state only), and the remaining interval up to the step's end time is
//! covered by the next attempt, so the time grid is kept.
//!
//! Element removal (OpenSees `remove element` after a failure criterion; MSC.Marc's
//! element deactivation in the paper's FE): if every attempt fails and an attempt failed
//! in an element's state determination (a force-based element that finds no compatible
//! section forces even after subdividing Δv, the last of those elements), that element
//! has lost its load path: it is removed ([`Domain::remove_element`]: no force, no
//! stiffness, its mass stays lumped on its nodes), the integrator is set up again for
//! the domain without it (K_initial of the damping, numbering when a node is left
//! without elements) and the step is repeated from the last converged state.
//! [`TransientResult::removed`] lists the removals. If every attempt fails without an
//! element failure (or removal is off, [`TransientSettings::remove_failed_elements`]),
//! the run stops cleanly: the domain keeps the last converged state and the result says
//! when and why.

use super::algorithm::{
    solve_step, Algorithm, ConvergenceTest, IterationFailure, StepProblem, Workspace,
};
use super::rayleigh::RayleighDamping;
use super::AnalysisError;
use crate::fe::domain::{Domain, NDF};
use crate::fe::element::{ElementDamage, ElementError};
use crate::fe::linalg::{SparsePattern, StiffnessKind};

/// Which nodal results are kept, and how often.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordSettings {
    /// Record every k-th step (k ≥ 1); the initial state, the state from which the run
    /// goes on without a removed element and the final state are always recorded.
    pub every: usize,
    /// Node indices to record; `None` = all nodes.
    pub nodes: Option<Vec<usize>>,
    /// Also record every element's [`ElementDamage`] flags at each record.
    pub element_damage: bool,
}

/// Transient analysis settings. Defaults are the frame3 reference runs.
#[derive(Debug, Clone, PartialEq)]
pub struct TransientSettings {
    /// Time step Δt (s).
    pub dt: f64,
    /// End time (s, absolute: the run starts at the domain's current time).
    pub t_end: f64,
    /// Newmark γ.
    pub gamma: f64,
    /// Newmark β.
    pub beta: f64,
    /// Regular algorithm.
    pub algorithm: Algorithm,
    /// Regular convergence test (NormDispIncr 1e-8, 50 iterations).
    pub test: ConvergenceTest,
    /// Fallback algorithms, tried in order at each subdivision.
    pub fallback_algorithms: Vec<Algorithm>,
    /// Convergence test of the fallbacks (1e-8, 200 iterations).
    pub fallback_test: ConvergenceTest,
    /// Step subdivisions tried in order (1, 2, 4, 8, 16).
    pub subdivisions: Vec<usize>,
    /// Remove an element whose state determination failed in a step that no fallback
    /// could make converge, and repeat the step (module docs); `false`: such a step
    /// ends the run ([`StopReason::Diverged`]).
    pub remove_failed_elements: bool,
    /// What to record.
    pub record: RecordSettings,
}

impl Default for TransientSettings {
    fn default() -> Self {
        Self {
            dt: 0.005,
            t_end: 0.0,
            gamma: 0.5,
            beta: 0.25,
            algorithm: Algorithm::Newton,
            test: ConvergenceTest {
                tol: 1e-8,
                max_iter: 50,
            },
            fallback_algorithms: vec![
                Algorithm::Newton,
                Algorithm::ModifiedNewtonInitial,
                Algorithm::KrylovNewton { max_dim: 3 },
                Algorithm::NewtonLineSearch { ratio: 0.8 },
            ],
            fallback_test: ConvergenceTest {
                tol: 1e-8,
                max_iter: 200,
            },
            subdivisions: vec![1, 2, 4, 8, 16],
            remove_failed_elements: true,
            record: RecordSettings {
                every: 1,
                nodes: None,
                element_damage: false,
            },
        }
    }
}

/// Reported after each converged step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepInfo {
    /// 1-based step number.
    pub step: usize,
    /// Time reached (s).
    pub time: f64,
    /// Iterations of the last (sub)step.
    pub iterations: usize,
    /// Whether the fallbacks were needed.
    pub used_fallback: bool,
}

/// The observer's answer after a step (progress bars, collapse criteria).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepControl {
    /// Go on.
    Continue,
    /// Stop the run here (e.g. the collapse criterion is met).
    Stop,
}

/// Why the run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum StopReason {
    /// Reached `t_end`.
    Completed,
    /// A step could not be made to converge; `time` is that of the last converged
    /// state, which the domain keeps; `attempted` the end time of the failed step.
    Diverged {
        /// Time of the last converged state (s).
        time: f64,
        /// End time of the step that failed (s).
        attempted: f64,
        /// The last attempt's failure.
        reason: String,
    },
    /// The observer asked to stop.
    Stopped {
        /// Time of the stop (s).
        time: f64,
    },
}

/// An element removed during the run (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Removal {
    /// The element's tag.
    pub element: i64,
    /// Time of the last converged state, from which the step was repeated without it (s).
    pub time: f64,
    /// End time of the step that failed (s).
    pub attempted: f64,
    /// The element's failure.
    pub reason: String,
}

/// Recorded nodal histories (relative to the ground), committed states only.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct History {
    /// Recorded node indices.
    pub nodes: Vec<usize>,
    /// Recorded times (s).
    pub time: Vec<f64>,
    /// Per record, per recorded node: displacement (m, rad).
    pub disp: Vec<Vec<[f64; NDF]>>,
    /// Per record, per node: velocity (m/s, rad/s).
    pub vel: Vec<Vec<[f64; NDF]>>,
    /// Per record, per node: acceleration (m/s², rad/s²).
    pub acc: Vec<Vec<[f64; NDF]>>,
    /// Per record, per element (domain order): damage flags; empty unless
    /// [`RecordSettings::element_damage`].
    pub damage: Vec<Vec<ElementDamage>>,
    record_damage: bool,
}

impl History {
    fn push(&mut self, domain: &Domain) {
        if self.time.last() == Some(&domain.time()) && !self.time.is_empty() {
            return;
        }
        self.time.push(domain.time());
        self.disp
            .push(self.nodes.iter().map(|&n| domain.displacement(n)).collect());
        self.vel
            .push(self.nodes.iter().map(|&n| domain.velocity(n)).collect());
        self.acc
            .push(self.nodes.iter().map(|&n| domain.acceleration(n)).collect());
        if self.record_damage {
            self.damage
                .push(domain.elements().iter().map(|e| e.damage()).collect());
        }
    }
}

/// Outcome of [`run_transient`].
#[derive(Debug, Clone, PartialEq)]
pub struct TransientResult {
    /// Recorded histories.
    pub history: History,
    /// Why the run ended.
    pub stop: StopReason,
    /// Converged steps.
    pub steps: usize,
    /// Steps that needed the fallbacks.
    pub fallback_steps: usize,
    /// Time of the final (committed) state (s).
    pub end_time: f64,
    /// Elements removed, in the order of removal.
    pub removed: Vec<Removal>,
}

/// A step that no attempt could make converge.
#[derive(Debug, Clone, PartialEq)]
pub struct StepFailure {
    /// The last attempt's failure.
    pub last: IterationFailure,
    /// The element whose state determination failed in the latest attempt that failed
    /// that way (tag and reason), if any did.
    pub element: Option<(i64, String)>,
}

/// Newmark integrator state bound to one domain (matrices reused across steps).
#[derive(Debug)]
pub struct Newmark {
    ws: Workspace,
    /// Copy of the workspace's pattern, for K_initial·v in the damping force.
    pattern: SparsePattern,
    kinit: Vec<f64>,
    /// Σ K0_e of the elements whose damping stiffness is constant (all but
    /// displacement-based corotational beams, whose `D_e` follows the trial geometry).
    kdamp_const: Vec<f64>,
    mass: Vec<f64>,
    iota: [Vec<f64>; 3],
    damping: RayleighDamping,
    gamma: f64,
    beta: f64,
}

struct NewmarkProblem<'a> {
    pattern_kinit: &'a [f64],
    pattern_kdamp_const: &'a [f64],
    mass: &'a [f64],
    iota: &'a [Vec<f64>; 3],
    damping: RayleighDamping,
    h: f64,
    gamma: f64,
    beta: f64,
    ag: [f64; 3],
    un: Vec<f64>,
    vn: Vec<f64>,
    an: Vec<f64>,
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    p: Vec<f64>,
    f: Vec<f64>,
    kv: Vec<f64>,
    pattern: &'a SparsePattern,
}

impl NewmarkProblem<'_> {
    fn kinematics(&mut self) {
        let (h, g, b) = (self.h, self.gamma, self.beta);
        for i in 0..self.u.len() {
            let a = (self.u[i] - self.un[i]) / (b * h * h)
                - self.vn[i] / (b * h)
                - (0.5 / b - 1.0) * self.an[i];
            self.a[i] = a;
            self.v[i] = self.vn[i] + h * ((1.0 - g) * self.an[i] + g * a);
        }
    }
}

impl StepProblem for NewmarkProblem<'_> {
    fn residual(&mut self, domain: &Domain, out: &mut [f64]) {
        domain.external_load(&mut self.p);
        domain.resisting_force(&mut self.f);
        // Stiffness-proportional damping force D·v, D = Σ K0_e; per element as OpenSees
        // forms it (Element::getRayleighDampingForces), with the trial geometry where the
        // element asks for it (Element::damping_stiffness).
        self.pattern
            .mul_vec(self.pattern_kdamp_const, &self.v, &mut self.kv);
        self.pattern
            .add_trial_damping_product(domain, &self.v, &mut self.kv);
        let RayleighDamping { a0, a1 } = self.damping;
        for i in 0..out.len() {
            let ag = self.iota[0][i] * self.ag[0]
                + self.iota[1][i] * self.ag[1]
                + self.iota[2][i] * self.ag[2];
            out[i] = self.p[i]
                - self.mass[i] * (self.a[i] + ag)
                - a0 * self.mass[i] * self.v[i]
                - a1 * self.kv[i]
                - self.f[i];
        }
    }

    fn tangent(
        &mut self,
        domain: &Domain,
        pattern: &SparsePattern,
        kind: StiffnessKind,
        values: &mut [f64],
    ) {
        let c1 = 1.0 / (self.beta * self.h * self.h);
        let c2 = self.gamma / (self.beta * self.h);
        let RayleighDamping { a0, a1 } = self.damping;
        match kind {
            StiffnessKind::Initial => {
                let kfac = 1.0 + c2 * a1;
                values
                    .iter_mut()
                    .zip(self.pattern_kinit)
                    .for_each(|(v, k)| *v += kfac * k);
            }
            StiffnessKind::Tangent => {
                // K_t + c2·a1·D with the damping stiffness of the residual (trial
                // geometry where the element asks for it), as OpenSees's Newmark forms it.
                pattern.add_stiffness(domain, StiffnessKind::Tangent, 1.0, values);
                let kfac = c2 * a1;
                if kfac != 0.0 {
                    values
                        .iter_mut()
                        .zip(self.pattern_kdamp_const)
                        .for_each(|(v, k)| *v += kfac * k);
                    pattern.add_trial_damping_stiffness(domain, kfac, values);
                }
            }
        }
        pattern.add_diagonal(self.mass, c1 + c2 * a0, values);
    }

    fn apply(&mut self, domain: &mut Domain, du: &[f64]) -> Result<(), ElementError> {
        self.u.iter_mut().zip(du).for_each(|(u, d)| *u += d);
        self.kinematics();
        domain.set_trial_eq(&self.u, Some(&self.v), Some(&self.a))
    }
}

impl Newmark {
    /// Prepares the integrator: numbering, sparse pattern and symbolic LU (once),
    /// K_initial, the lumped mass and the influence vectors.
    pub fn new(
        domain: &mut Domain,
        damping: Option<RayleighDamping>,
        gamma: f64,
        beta: f64,
    ) -> Result<Self, AnalysisError> {
        if !(gamma > 0.0 && beta > 0.0 && gamma.is_finite() && beta.is_finite()) {
            return Err(AnalysisError::Input(format!(
                "Newmark γ = {gamma}, β = {beta}"
            )));
        }
        let damping = damping.unwrap_or(RayleighDamping { a0: 0.0, a1: 0.0 });
        if !(damping.a0.is_finite() && damping.a1.is_finite()) {
            return Err(AnalysisError::Input(format!("Rayleigh {damping:?}")));
        }
        let ws = Workspace::new(domain)?;
        let mut kinit = ws.pattern.zeros();
        ws.pattern
            .add_stiffness(domain, StiffnessKind::Initial, 1.0, &mut kinit);
        let mut kdamp_const = ws.pattern.zeros();
        ws.pattern
            .add_constant_damping_stiffness(domain, 1.0, &mut kdamp_const);
        let mass = domain.mass_diagonal();
        let iota = [0, 1, 2].map(|d| domain.influence_vector(d));
        Ok(Self {
            pattern: ws.pattern.clone(),
            ws,
            kinit,
            kdamp_const,
            mass,
            iota,
            damping,
            gamma,
            beta,
        })
    }

    /// One attempt: from the committed state to `t0 + h` with one algorithm. On
    /// success the state is committed and the domain time set; on failure reverted.
    fn attempt(
        &mut self,
        domain: &mut Domain,
        h: f64,
        ground: &dyn Fn(f64) -> [f64; 3],
        algorithm: Algorithm,
        test: ConvergenceTest,
    ) -> Result<usize, IterationFailure> {
        let n = self.mass.len();
        let t1 = domain.time() + h;
        let ag = ground(t1);
        if ag.iter().any(|x| !x.is_finite()) {
            return Err(IterationFailure::NonFiniteResidual);
        }
        domain.set_time_increment(h);
        let mut un = vec![0.0; n];
        let mut vn = vec![0.0; n];
        let mut an = vec![0.0; n];
        domain.committed_eq(&mut un, &mut vn, &mut an);
        let mut problem = NewmarkProblem {
            pattern_kinit: &self.kinit,
            pattern_kdamp_const: &self.kdamp_const,
            mass: &self.mass,
            iota: &self.iota,
            damping: self.damping,
            h,
            gamma: self.gamma,
            beta: self.beta,
            ag,
            u: un.clone(),
            un,
            vn,
            an,
            v: vec![0.0; n],
            a: vec![0.0; n],
            p: vec![0.0; n],
            f: vec![0.0; n],
            kv: vec![0.0; n],
            pattern: &self.pattern,
        };
        problem.kinematics();
        let res = solve_step(&mut problem, domain, &mut self.ws, algorithm, test);
        match res {
            Ok(it) => {
                domain.set_time(t1);
                domain.commit();
                Ok(it)
            }
            Err(e) => {
                domain.revert_to_last_commit();
                Err(e)
            }
        }
    }

    /// Advances the committed state to `target` (s): the regular algorithm, then the
    /// fallbacks. Returns the iterations of the last sub-step and whether fallbacks were
    /// used; on failure the domain holds the last converged (sub)step.
    pub fn advance(
        &mut self,
        domain: &mut Domain,
        target: f64,
        ground: &dyn Fn(f64) -> [f64; 3],
        settings: &TransientSettings,
    ) -> Result<(usize, bool), StepFailure> {
        let h = target - domain.time();
        let mut element = None;
        let mut note = |e: IterationFailure| {
            if let IterationFailure::Element {
                element: tag,
                reason,
            } = &e
            {
                element = Some((*tag, reason.clone()));
            }
            e
        };
        let mut last = match self.attempt(domain, h, ground, settings.algorithm, settings.test) {
            Ok(it) => return Ok((it, false)),
            Err(e) => note(e),
        };
        let eps = 1e-9 * h.abs().max(1e-300);
        for &sub in &settings.subdivisions {
            let hs = h / sub.max(1) as f64;
            for &alg in &settings.fallback_algorithms {
                let mut ok = None;
                while domain.time() < target - eps {
                    let remaining = target - domain.time();
                    let step = if remaining < hs * (1.0 + 1e-9) {
                        remaining
                    } else {
                        hs
                    };
                    match self.attempt(domain, step, ground, alg, settings.fallback_test) {
                        Ok(it) => ok = Some(it),
                        Err(e) => {
                            last = note(e);
                            ok = None;
                            break;
                        }
                    }
                }
                if domain.time() >= target - eps {
                    domain.set_time(target);
                    return Ok((ok.unwrap_or(0), true));
                }
            }
        }
        Err(StepFailure { last, element })
    }
}

/// Runs a transient analysis from the domain's current (committed) state and time to
/// `settings.t_end`, calling `observer` after every converged step. Non-convergence is
/// a reported stop ([`StopReason::Diverged`]), not an error; errors are only for bad
/// settings or a solver that cannot be set up.
pub fn run_transient(
    domain: &mut Domain,
    damping: Option<RayleighDamping>,
    ground: &dyn Fn(f64) -> [f64; 3],
    settings: &TransientSettings,
    observer: &mut dyn FnMut(&StepInfo, &Domain) -> StepControl,
) -> Result<TransientResult, AnalysisError> {
    if !(settings.dt > 0.0 && settings.dt.is_finite() && settings.t_end.is_finite()) {
        return Err(AnalysisError::Input(format!(
            "transient Δt = {}",
            settings.dt
        )));
    }
    if settings.record.every == 0 {
        return Err(AnalysisError::Input("record every 0 steps".into()));
    }
    let nodes = match &settings.record.nodes {
        Some(list) => {
            if let Some(bad) = list.iter().find(|&&n| n >= domain.nodes().len()) {
                return Err(AnalysisError::Input(format!(
                    "recorded node index {bad} out of range"
                )));
            }
            list.clone()
        }
        None => (0..domain.nodes().len()).collect(),
    };
    let mut integrator = Newmark::new(domain, damping, settings.gamma, settings.beta)?;
    let mut removed = Vec::new();
    let mut history = History {
        nodes,
        record_damage: settings.record.element_damage,
        ..Default::default()
    };
    history.push(domain);
    let t_start = domain.time();
    let mut steps = 0;
    let mut fallback_steps = 0;
    let mut stop = StopReason::Completed;
    let eps = 1e-9 * settings.dt;
    while domain.time() < settings.t_end - eps {
        let target = (t_start + (steps + 1) as f64 * settings.dt).min(settings.t_end);
        match integrator.advance(domain, target, ground, settings) {
            Ok((iterations, used_fallback)) => {
                steps += 1;
                if used_fallback {
                    fallback_steps += 1;
                }
                if steps % settings.record.every == 0 {
                    history.push(domain);
                }
                let info = StepInfo {
                    step: steps,
                    time: domain.time(),
                    iterations,
                    used_fallback,
                };
                if observer(&info, domain) == StepControl::Stop {
                    stop = StopReason::Stopped {
                        time: domain.time(),
                    };
                    break;
                }
            }
            Err(StepFailure {
                element: Some((tag, reason)),
                ..
            }) if settings.remove_failed_elements => {
                let index = domain.element_index(tag).ok_or_else(|| {
                    AnalysisError::Input(format!("failed element {tag} is not in the domain"))
                })?;
                domain
                    .remove_element(index)
                    .map_err(|e| AnalysisError::Input(format!("removing a failed element: {e}")))?;
                history.push(domain);
                removed.push(Removal {
                    element: tag,
                    time: domain.time(),
                    attempted: target,
                    reason,
                });
                integrator = Newmark::new(domain, damping, settings.gamma, settings.beta)?;
            }
            Err(e) => {
                stop = StopReason::Diverged {
                    time: domain.time(),
                    attempted: target,
                    reason: e.last.to_string(),
                };
                break;
            }
        }
    }
    history.push(domain);
    Ok(TransientResult {
        history,
        stop,
        steps,
        fallback_steps,
        end_time: domain.time(),
        removed,
    })
}
