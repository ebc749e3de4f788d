//! Static pushover and cyclic analyses of a [`Model`] after gravity: a lateral load
//! pattern whose factor λ is found by displacement control of one node (OpenSees
//! `integrator DisplacementControl`), driven to a list of control displacements — one
//! target for a monotonic pushover, a series of ± amplitudes for a cyclic test.
//!
//! Sequence: [`prepare`] (build, initial modal analysis, gravity in load control,
//! `loadConst`), then the lateral pattern P_ref in the reference load pattern, then per
//! step [`displacement_increment`] (Newton, initial-stiffness fallback, the increment
//! split into 2, 4, 8 sub-steps when it fails). Every converged step gives a point of
//! the capacity curve: the control displacement, λ, and the support reactions
//! ([`Domain::reactions`]).
//!
//! With the pattern normalised to ΣF = 1 N, λ is the total applied lateral force (N), and
//! static equilibrium makes the base shear V = −ΣR_d equal to it; both are reported, and
//! their difference is the equilibrium residual of the converged step.
//!
//! Load patterns (ASCE/SEI 41-17 §7.4.3.2.3 and ASCE/SEI 7-16 eq. 12.8-12 with k = 1):
//! * uniform: F_i ∝ m_i (the lumped mass of node i in the push direction);
//! * triangular: F_i ∝ m_i (z_i − z_base) (an inverted triangle weighted by mass);
//! * first mode: F_i ∝ m_i φ_i,d of the mode with the largest effective-mass ratio in
//!   the push direction d among the building's modes computed (the initial modal
//!   analysis's default selection, which skips local slab modes), signed so that the
//!   control node moves forward.
//!
//! Units SI: m, N, kg.
use std::collections::BTreeMap;

use crate::fe::analysis::modal::ModalResult;
use crate::fe::analysis::static_analysis::displacement_increment;
use crate::fe::analysis::ConvergenceTest;
use crate::fe::build::BuildOptions;
use crate::fe::domain::{Domain, NDF};
use crate::fe::reactions::ReactionSum;
use crate::fe::run::prepare;
use crate::fe::FeError;
use crate::model::Model;

/// The lateral load pattern's distribution over the storeys (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LoadPattern {
    /// F_i ∝ m_i.
    Uniform,
    /// F_i ∝ m_i (z_i − z_base).
    Triangular,
    /// F_i ∝ m_i φ_i of the dominant mode in the push direction.
    FirstMode,
}

impl LoadPattern {
    /// The name used on the command line and in outputs.
    pub fn name(self) -> &'static str {
        match self {
            LoadPattern::Uniform => "uniform",
            LoadPattern::Triangular => "triangular",
            LoadPattern::FirstMode => "first-mode",
        }
    }
}

impl std::str::FromStr for LoadPattern {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "uniform" => Ok(LoadPattern::Uniform),
            "triangular" => Ok(LoadPattern::Triangular),
            "first-mode" => Ok(LoadPattern::FirstMode),
            _ => Err(format!(
                "unknown load pattern `{s}`: use uniform, triangular or first-mode"
            )),
        }
    }
}

/// What a static lateral analysis does.
#[derive(Debug, Clone, PartialEq)]
pub struct PushoverSettings {
    /// Element variant and force-based element controls.
    pub build: BuildOptions,
    /// Lateral load pattern.
    pub pattern: LoadPattern,
    /// Push direction: 0 = X, 1 = Y.
    pub direction: usize,
    /// Control node tag; `None` = the top-level node nearest the mass centre of that
    /// level in plan ([`default_control_node`]).
    pub control_node: Option<u32>,
    /// Control displacements to reach in turn (m, along the push direction): one for a
    /// monotonic pushover, `+a, −a, …, 0` for a cyclic protocol ([`cyclic_targets`]).
    pub targets: Vec<f64>,
    /// Largest control-displacement increment of a step (m).
    pub increment: f64,
    /// Modes of the initial modal analysis (the first-mode pattern picks among them).
    pub modes: usize,
    /// Newton's convergence test of a step (OpenSees `NormDispIncr`).
    pub test: ConvergenceTest,
}

/// Targets of a cyclic protocol: each amplitude (m) `cycles` times as `+a, −a`, then back
/// to zero (FEMA 461 / ACI 374.2R-style series of increasing amplitudes).
pub fn cyclic_targets(amplitudes: &[f64], cycles: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity(2 * amplitudes.len() * cycles + 1);
    for &a in amplitudes {
        for _ in 0..cycles {
            out.push(a);
            out.push(-a);
        }
    }
    out.push(0.0);
    out
}

/// Steps of a leg of length `leg` with steps of at most `increment` (both m):
/// ⌈|leg| / increment − 10⁻⁹⌉, at least 1, so that a leg that is a whole number of steps
/// up to rounding (0.006 / 0.001 = 6.000000000000001) takes that number.
pub fn steps_of(leg: f64, increment: f64) -> usize {
    (leg.abs() / increment - 1e-9).ceil().max(1.0) as usize
}

/// One converged step of the capacity curve.
#[derive(Debug, Clone, PartialEq)]
pub struct CurvePoint {
    /// Step number (0 = after gravity).
    pub step: usize,
    /// Control node displacement along the push direction (m).
    pub control_displacement: f64,
    /// Load factor λ = total applied lateral force (N).
    pub load_factor: f64,
    /// Sum of the support reactions `[Rx, Ry, Rz, Mx, My, Mz]` (N, N·m; moments about
    /// the origin are not formed: the moment components are the sums of the nodal
    /// reaction moments).
    pub reaction_sum: [f64; NDF],
    /// Base shear along the push direction carried by the beam-columns (N).
    pub base_shear_frame: f64,
    /// Base shear along the push direction carried by the shells (N).
    pub base_shear_wall: f64,
}

impl CurvePoint {
    /// Base shear V = −ΣR along the push direction (N).
    pub fn base_shear(&self, direction: usize) -> f64 {
        -self.reaction_sum[direction]
    }
}

/// Why the analysis ended.
#[derive(Debug, Clone, PartialEq)]
pub enum PushoverStop {
    /// Every target was reached.
    Completed,
    /// A step failed even in 8 sub-steps: the curve ends at the last converged state.
    NotConverged {
        /// Control displacement of the last converged state (m).
        at: f64,
        /// The target being approached (m).
        target: f64,
    },
}

/// Result of [`run_pushover`].
#[derive(Debug)]
pub struct PushoverResult {
    /// The control node's tag.
    pub control_node: u32,
    /// Height of the control node above the lowest support (m).
    pub control_height: f64,
    /// The normalised lateral loads `(node tag, F)` (ΣF = 1 N) in the push direction.
    pub pattern_loads: Vec<(u32, f64)>,
    /// The mode whose shape the first-mode pattern follows, by its index in the whole
    /// spectrum (1 = the longest period), if used.
    pub pattern_mode: Option<usize>,
    /// Total gravity load W = Σ|F_z| of the gravity loads (N).
    pub weight: f64,
    /// Initial-stiffness modal analysis.
    pub modal: ModalResult,
    /// The capacity curve, step 0 first.
    pub curve: Vec<CurvePoint>,
    /// Final reactions per supported node `(tag, [Rx, Ry, Rz, Mx, My, Mz])`.
    pub reactions: Vec<(u32, [f64; NDF])>,
    /// Why it ended.
    pub stop: PushoverStop,
    /// The domain in its last converged state.
    pub domain: Domain,
    /// Domain node index → model tag.
    pub node_tags: Vec<u32>,
}

/// The top-level node (largest z) nearest, in plan, to the mass centre of the nodes at
/// that level; ties go to the smaller tag.
pub fn default_control_node(model: &Model) -> Option<u32> {
    let z_top = model
        .nodes
        .iter()
        .map(|n| n.z)
        .fold(f64::NEG_INFINITY, f64::max);
    let tol = 1e-6 * (1.0 + z_top.abs());
    let top: Vec<_> = model
        .nodes
        .iter()
        .filter(|n| (n.z - z_top).abs() <= tol)
        .collect();
    let masses = model.lumped_masses();
    let (mut sm, mut sx, mut sy) = (0.0, 0.0, 0.0);
    for n in &top {
        let m = masses.get(&n.tag).map_or(0.0, |m| m[0]);
        sm += m;
        sx += m * n.x;
        sy += m * n.y;
    }
    let (cx, cy) = if sm > 0.0 {
        (sx / sm, sy / sm)
    } else {
        let k = top.len().max(1) as f64;
        (
            top.iter().map(|n| n.x).sum::<f64>() / k,
            top.iter().map(|n| n.y).sum::<f64>() / k,
        )
    };
    top.iter()
        .min_by(|a, b| {
            let da = (a.x - cx).hypot(a.y - cy);
            let db = (b.x - cx).hypot(b.y - cy);
            da.total_cmp(&db).then(a.tag.cmp(&b.tag))
        })
        .map(|n| n.tag)
}

fn input(message: String) -> FeError {
    FeError::Options(message)
}

/// Loads `(node tag, F)` along the push direction (N).
type NodeLoads = Vec<(u32, f64)>;

/// The lateral pattern's loads before normalisation, per massed free node.
fn raw_pattern(
    model: &Model,
    pattern: LoadPattern,
    d: usize,
    modal: &ModalResult,
    node_index: &BTreeMap<u32, usize>,
    control: usize,
) -> Result<(NodeLoads, Option<usize>), FeError> {
    let fixity = model.fixity();
    let nodes = model.node_map();
    let z_base = fixity
        .keys()
        .filter_map(|t| nodes.get(t).map(|n| n.z))
        .fold(f64::INFINITY, f64::min);
    let mode = match pattern {
        LoadPattern::FirstMode => {
            let k = (0..modal.periods.len())
                .max_by(|&a, &b| {
                    modal.effective_mass_ratio[a][d]
                        .total_cmp(&modal.effective_mass_ratio[b][d])
                        .then(b.cmp(&a))
                })
                .ok_or_else(|| input("the first-mode pattern needs a mode".into()))?;
            Some(k)
        }
        _ => None,
    };
    let sign = mode.map_or(1.0, |k| {
        if modal.shapes[k][control][d] < 0.0 {
            -1.0
        } else {
            1.0
        }
    });
    let mut out = Vec::new();
    for (tag, m) in model.lumped_masses() {
        let fixed = fixity.get(&tag).is_some_and(|f| f[d] != 0);
        if fixed || m[d] <= 0.0 {
            continue;
        }
        let f = match pattern {
            LoadPattern::Uniform => m[d],
            LoadPattern::Triangular => m[d] * (nodes[&tag].z - z_base),
            LoadPattern::FirstMode => {
                let k = mode.expect("mode chosen above");
                m[d] * sign * modal.shapes[k][node_index[&tag]][d]
            }
        };
        if f != 0.0 {
            out.push((tag, f));
        }
    }
    Ok((out, mode.map(|k| modal.index[k])))
}

fn point(domain: &Domain, step: usize, control: usize, d: usize) -> CurvePoint {
    let sum = ReactionSum::of(domain);
    CurvePoint {
        step,
        control_displacement: domain.displacement(control)[d],
        load_factor: domain.load_factor(),
        reaction_sum: sum.total,
        base_shear_frame: sum.frame[d],
        base_shear_wall: sum.wall[d],
    }
}

/// Runs gravity, then the lateral pattern in displacement control through
/// `settings.targets` (module doc). `observer` is called after every converged step.
/// Errors are bad input (model, settings) and a failed gravity analysis; a lateral step
/// that does not converge ends the curve ([`PushoverStop::NotConverged`]).
pub fn run_pushover(
    model: &Model,
    settings: &PushoverSettings,
    observer: &mut dyn FnMut(&CurvePoint),
) -> Result<PushoverResult, FeError> {
    let d = settings.direction;
    if d > 1 {
        return Err(input(format!("push direction {d}: use 0 (X) or 1 (Y)")));
    }
    if !(settings.increment > 0.0 && settings.increment.is_finite()) {
        return Err(input(format!(
            "the control increment must be positive, got {} m",
            settings.increment
        )));
    }
    if settings.targets.is_empty() || settings.targets.iter().any(|t| !t.is_finite()) {
        return Err(input(
            "the control targets must be finite and not empty".into(),
        ));
    }
    let control_tag = match settings.control_node {
        Some(t) => t,
        None => {
            default_control_node(model).ok_or_else(|| input("the model has no nodes".into()))?
        }
    };
    let nodes = model.node_map();
    let Some(control_model_node) = nodes.get(&control_tag) else {
        return Err(input(format!(
            "control node {control_tag} is not in the model"
        )));
    };
    if model.fixity().get(&control_tag).is_some_and(|f| f[d] != 0) {
        return Err(input(format!(
            "control node {control_tag} is fixed in the push direction"
        )));
    }
    let z_base = model
        .fixity()
        .keys()
        .filter_map(|t| nodes.get(t).map(|n| n.z))
        .fold(f64::INFINITY, f64::min);
    let control_height = control_model_node.z - z_base;
    let mut prepared = prepare(model, &settings.build, settings.modes.max(1))?;
    let node_index = prepared.built.node_index.clone();
    let control = node_index[&control_tag];
    let (raw, pattern_mode) = raw_pattern(
        model,
        settings.pattern,
        d,
        &prepared.modal,
        &node_index,
        control,
    )?;
    let total: f64 = raw.iter().map(|(_, f)| f).sum();
    if !(total.abs() > 0.0 && total.is_finite()) {
        return Err(input(format!(
            "the {} pattern has no resultant in the push direction (no mass above the \
             supports?)",
            settings.pattern.name()
        )));
    }
    let pattern_loads: Vec<(u32, f64)> = raw.iter().map(|&(t, f)| (t, f / total)).collect();
    let domain = &mut prepared.built.domain;
    for &(tag, f) in &pattern_loads {
        let mut load = [0.0; NDF];
        load[d] = f;
        domain
            .add_nodal_load(node_index[&tag], load)
            .map_err(|e| input(format!("lateral load at node {tag}: {e}")))?;
    }
    let weight: f64 = model.gravity_loads().iter().map(|(_, fz)| fz.abs()).sum();
    let first = point(domain, 0, control, d);
    observer(&first);
    let mut curve = vec![first];
    let mut stop = PushoverStop::Completed;
    let tol = 1e-12 * (1.0 + settings.increment);
    'targets: for &target in &settings.targets {
        let start = domain.displacement(control)[d];
        let leg = target - start;
        if leg.abs() <= tol {
            continue;
        }
        let n = steps_of(leg, settings.increment);
        for k in 1..=n {
            // Aim at start + k/n of the leg, so rounding does not accumulate.
            let aim = start + leg * k as f64 / n as f64;
            let now = domain.displacement(control)[d];
            if !displacement_increment(domain, control, d, aim - now, settings.test) {
                stop = PushoverStop::NotConverged {
                    at: domain.displacement(control)[d],
                    target,
                };
                break 'targets;
            }
            let p = point(domain, curve.len(), control, d);
            observer(&p);
            curve.push(p);
        }
    }
    let mut node_tags = vec![0; node_index.len()];
    for (&tag, &i) in &node_index {
        node_tags[i] = tag;
    }
    let reactions = domain
        .reactions()
        .into_iter()
        .map(|(i, r)| (node_tags[i], r))
        .collect();
    Ok(PushoverResult {
        control_node: control_tag,
        control_height,
        pattern_loads,
        pattern_mode,
        weight,
        modal: prepared.modal,
        curve,
        reactions,
        stop,
        domain: prepared.built.domain,
        node_tags,
    })
}
