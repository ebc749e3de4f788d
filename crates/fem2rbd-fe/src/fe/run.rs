//! A ground-motion time history of a [`Model`], as a library call (the CLI's `fem2rbd fe`
//! is a thin layer over it). The sequence is that of the frame3 reference runs
//! (`tests/fixtures/opensees-frame3/run_frame3.py`):
//!
//! 1. build the domain ([`build_domain`]) in the chosen element variant;
//! 2. modal analysis on the initial stiffness: the building's modes (the default
//!    [`crate::fe::analysis::modal::ModeSelection`]: local slab modes skipped), their
//!    periods, and T1, the first of them, for the default damping;
//! 3. gravity in `model.gravity.load_steps` load-control steps (NormDispIncr 1e-10, 50
//!    iterations, Newton), then `loadConst` (gravity held, λ = 0, t = 0);
//! 4. Rayleigh damping C = a0·M + a1·K_initial: the model's `[damping]` if given, else
//!    5 % at T1 and T1/3 ([`RayleighDamping::default_for_period`]);
//! 5. Newmark transient with three-component uniform base excitation from the
//!    [`GroundMotion`] (m/s²), OpenSees-style fallbacks, an observer called after every
//!    converged step (collapse criteria, progress bars) and recording every k-th step.
//!
//! A step that cannot be made to converge ends the run cleanly
//! ([`StopReason::Diverged`]); the histories end at the last converged state.

use crate::fe::analysis::modal::{modal_analysis, ModalResult, ModalSettings};
use crate::fe::analysis::rayleigh::RayleighDamping;
use crate::fe::analysis::static_analysis::{load_control, LoadControl};
use crate::fe::analysis::transient::{
    run_transient, RecordSettings, StepControl, StepInfo, StopReason, TransientResult,
    TransientSettings,
};
use crate::fe::build::{build_domain, BuildOptions, BuiltDomain};
use crate::fe::domain::Domain;
use crate::fe::FeError;
use crate::model::{limits, Model};
use crate::motion::GroundMotion;

/// What a run returns.
type Result<T> = std::result::Result<T, FeError>;

/// Options of a ground-motion run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOptions {
    /// Element variant and force-based element controls.
    pub build: BuildOptions,
    /// Time step Δt (s); the reference runs use 0.005 s.
    pub dt: f64,
    /// End time (s); `None` = the motion's duration (shortest component).
    pub duration: Option<f64>,
    /// Record every k-th step (≥ 1); the initial and final states are always recorded.
    pub every: usize,
    /// Node tags to record; `None` = all nodes (model order).
    pub record_nodes: Option<Vec<u32>>,
    /// Also record element damage flags.
    pub element_damage: bool,
    /// Number of the building's modes of the initial modal analysis (≥ 1).
    pub modes: usize,
}

impl Default for RunOptions {
    fn default() -> Self {
        Self {
            build: BuildOptions::default(),
            dt: 0.005,
            duration: None,
            every: 1,
            record_nodes: None,
            element_damage: false,
            modes: 3,
        }
    }
}

/// The model's domain after gravity: ready for a transient or a pushover.
#[derive(Debug)]
pub struct Prepared {
    /// Domain (gravity applied and held, λ = 0, t = 0) and tag maps.
    pub built: BuiltDomain,
    /// Initial-stiffness modal analysis (before gravity).
    pub modal: ModalResult,
    /// Load-control steps used for gravity.
    pub gravity_steps: usize,
}

/// Outcome of [`run_ground_motion`].
#[derive(Debug)]
pub struct RunResult {
    /// The domain in its final (last converged) state and the tag maps.
    pub built: BuiltDomain,
    /// Initial-stiffness modal analysis (before gravity).
    pub modal: ModalResult,
    /// Rayleigh damping used.
    pub damping: RayleighDamping,
    /// Histories (relative to the ground), stop reason, step counts.
    pub transient: TransientResult,
    /// Model tags of the recorded nodes, in history order.
    pub node_tags: Vec<u32>,
}

impl RunResult {
    /// Why the run ended.
    pub fn stop(&self) -> &StopReason {
        &self.transient.stop
    }
}

/// Builds the domain, runs the initial modal analysis and applies gravity
/// (steps 1–3 of the module doc). Used by [`run_ground_motion`] and by pushovers.
pub fn prepare(model: &Model, build: &BuildOptions, modes: usize) -> Result<Prepared> {
    let mut built = build_domain(model, build)?;
    let modal = modal_analysis(
        &mut built.domain,
        &ModalSettings {
            modes: modes.max(1),
            ..Default::default()
        },
    )
    .map_err(|error| FeError::Analysis {
        stage: "initial modal analysis",
        error,
    })?;
    let steps = model.gravity.load_steps as usize;
    load_control(
        &mut built.domain,
        &LoadControl {
            steps,
            ..Default::default()
        },
    )
    .map_err(|error| FeError::Analysis {
        stage: "gravity (load control)",
        error,
    })?;
    built.domain.load_const();
    Ok(Prepared {
        built,
        modal,
        gravity_steps: steps,
    })
}

/// Rayleigh damping of the model: its `[damping]` if given, else 5 % at T1 and T1/3,
/// `t1` the period of the first of the building's modes.
pub(crate) fn damping_for(model: &Model, t1: f64) -> Result<RayleighDamping> {
    match model.rayleigh() {
        Some((a0, a1)) => Ok(RayleighDamping { a0, a1 }),
        None => RayleighDamping::default_for_period(t1).map_err(|error| FeError::Analysis {
            stage: "default damping (5 % at T1 and T1/3)",
            error,
        }),
    }
}

/// Runs the ground motion `motion` on `model` (module doc for the sequence).
/// `observer` is called after every converged step with the step info and the domain
/// (committed state); returning [`StepControl::Stop`] ends the run with
/// [`StopReason::Stopped`]. Errors are bad input (model, options) only; a step that
/// does not converge is a reported [`StopReason::Diverged`].
pub fn run_ground_motion(
    model: &Model,
    motion: &GroundMotion,
    options: &RunOptions,
    observer: &mut dyn FnMut(&StepInfo, &Domain) -> StepControl,
) -> Result<RunResult> {
    check_run(model, motion, options)?;
    let prepared = prepare(model, &options.build, options.modes)?;
    run_prepared(model, prepared, motion, options, observer)
}

/// The checks of a run's options and resource bounds (docs/reliability.md), before any
/// domain is built; returns the end time, s.
fn check_run(model: &Model, motion: &GroundMotion, options: &RunOptions) -> Result<f64> {
    if !(options.dt > 0.0 && options.dt.is_finite()) {
        return Err(FeError::Options(format!(
            "time step must be positive, got {}",
            options.dt
        )));
    }
    if options.every == 0 {
        return Err(FeError::Options(
            "record every k-th step needs k ≥ 1".into(),
        ));
    }
    let t_end = options.duration.unwrap_or_else(|| motion.duration_s());
    if !(t_end > 0.0 && t_end.is_finite()) {
        return Err(FeError::Options(format!(
            "duration must be positive, got {} s",
            limits::show_number(t_end)
        )));
    }
    // Resource bounds (docs/reliability.md), before the domain is built.
    let steps = limits::grid_count(
        format!(
            "analysis of {} s with Δt = {} s",
            limits::show_number(t_end),
            limits::show_number(options.dt)
        ),
        "time steps",
        t_end,
        options.dt,
        limits::MAX_FE_STEPS,
    )? as u64;
    let recorded_nodes = options
        .record_nodes
        .as_ref()
        .map_or(model.nodes.len(), Vec::len) as u64;
    limits::check(
        format!("recording every {} step(s)", options.every),
        "recorded values",
        (steps / options.every as u64 + 2).saturating_mul(6 * recorded_nodes),
        limits::MAX_RECORDED_VALUES,
    )?;
    Ok(t_end)
}

/// As [`run_ground_motion`] on a domain the caller prepared ([`prepare`]: built, modal,
/// gravity applied and held), so that one domain serves the gravity-state queries (e.g.
/// the section capacities at the gravity loads) and the time history. `options.build`
/// and `options.modes` are those of `prepared` and not used here.
pub fn run_prepared(
    model: &Model,
    prepared: Prepared,
    motion: &GroundMotion,
    options: &RunOptions,
    observer: &mut dyn FnMut(&StepInfo, &Domain) -> StepControl,
) -> Result<RunResult> {
    let t_end = check_run(model, motion, options)?;
    let Prepared {
        mut built, modal, ..
    } = prepared;
    let damping = damping_for(model, modal.periods[0])?;
    let (nodes, node_tags) = match &options.record_nodes {
        Some(tags) => {
            let mut idx = Vec::with_capacity(tags.len());
            for t in tags {
                idx.push(*built.node_index.get(t).ok_or_else(|| {
                    FeError::Options(format!("recorded node {t} is not in the model"))
                })?);
            }
            (Some(idx), tags.clone())
        }
        None => (None, model.nodes.iter().map(|n| n.tag).collect()),
    };
    let settings = TransientSettings {
        dt: options.dt,
        t_end,
        record: RecordSettings {
            every: options.every,
            nodes,
            element_damage: options.element_damage,
        },
        ..Default::default()
    };
    let ground = |t: f64| motion.accel_at(t);
    let transient = run_transient(
        &mut built.domain,
        Some(damping),
        &ground,
        &settings,
        observer,
    )
    .map_err(|error| FeError::Analysis {
        stage: "transient analysis",
        error,
    })?;
    Ok(RunResult {
        built,
        modal,
        damping,
        transient,
        node_tags,
    })
}

/// What a mode shape mainly does, for reports (`fem2rbd modal`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModeCharacter {
    /// Translation along X.
    X,
    /// Translation along Y.
    Y,
    /// Rotation about the vertical axis.
    Torsion,
    /// Vertical motion (e.g. slab modes).
    Vertical,
}

impl std::fmt::Display for ModeCharacter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ModeCharacter::X => "X",
            ModeCharacter::Y => "Y",
            ModeCharacter::Torsion => "torsion",
            ModeCharacter::Vertical => "vertical",
        })
    }
}

/// Classifies mode `mode` of `modal` by the kinetic-energy shares of its shape φ with the
/// lumped translational masses m of `domain`. The massed nodes are grouped by level
/// (equal z, to 1 mm); on each level the horizontal motion is projected on the rigid
/// plan motions: translation X, E_x = (Σ m φx)²/Σ m; translation Y, E_y = (Σ m φy)²/Σ m;
/// rotation about the level's mass centre, E_θ = (Σ m (x′φy − y′φx))²/Σ m r². The
/// vertical share is E_z = Σ m φz² over all nodes. The largest of the level sums of
/// E_x, E_y, E_θ and E_z names the mode. Identifying modes by shape, not by order,
/// matters for frame3, whose slab modes lie next to its torsion mode.
pub fn mode_character(domain: &Domain, modal: &ModalResult, mode: usize) -> ModeCharacter {
    use std::collections::BTreeMap;
    let shape = &modal.shapes[mode];
    let mut levels: BTreeMap<i64, Vec<(usize, f64)>> = BTreeMap::new();
    let mut e_z = 0.0;
    for (i, node) in domain.nodes().iter().enumerate() {
        let m = domain.mass(i);
        if m[0] <= 0.0 && m[1] <= 0.0 && m[2] <= 0.0 {
            continue;
        }
        e_z += m[2] * shape[i][2] * shape[i][2];
        let key = (node.coords[2] * 1000.0).round() as i64;
        levels.entry(key).or_default().push((i, m[0].max(m[1])));
    }
    let (mut e_x, mut e_y, mut e_t) = (0.0, 0.0, 0.0);
    for list in levels.values() {
        let mt: f64 = list.iter().map(|(_, m)| m).sum();
        if mt <= 0.0 {
            continue;
        }
        let c = |k: usize| {
            list.iter()
                .map(|&(i, m)| m * domain.nodes()[i].coords[k])
                .sum::<f64>()
                / mt
        };
        let (xc, yc) = (c(0), c(1));
        let (mut px, mut py, mut pt, mut j) = (0.0, 0.0, 0.0, 0.0);
        for &(i, m) in list {
            let (x, y) = (
                domain.nodes()[i].coords[0] - xc,
                domain.nodes()[i].coords[1] - yc,
            );
            let (ux, uy) = (shape[i][0], shape[i][1]);
            px += m * ux;
            py += m * uy;
            pt += m * (x * uy - y * ux);
            j += m * (x * x + y * y);
        }
        e_x += px * px / mt;
        e_y += py * py / mt;
        if j > 0.0 {
            e_t += pt * pt / j;
        }
    }
    let shares = [
        (e_x, ModeCharacter::X),
        (e_y, ModeCharacter::Y),
        (e_t, ModeCharacter::Torsion),
        (e_z, ModeCharacter::Vertical),
    ];
    shares
        .iter()
        .fold(shares[0], |best, &s| if s.0 > best.0 { s } else { best })
        .1
}
