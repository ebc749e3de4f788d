//! The pipeline that joins the stages (paper Fig. 1): scenario → model → FE with
//! the collapse monitor → hand-off at Tc → Bullet ruin stage → outputs, on one timeline.
//!
//! * `hybrid`: the FE time history runs with the [`CollapseMonitor`] until the criterion
//!   is met at Tc (the observer returns [`StepControl::Stop`]). If a step does not
//!   converge first, the hand-off is at the last converged step (reported as
//!   `fe_diverged`); if the record ends first, the run reports `no_collapse` and stops
//!   after the FE stage. Every body's keyframe is taken from the FE state at each
//!   1/25 s up to Tc ([`Handoff::states`]: absolute poses = ground + FE relative
//!   displacement); at Tc the bodies get their instantaneous velocities (or the secant
//!   of the last keyframe and the Tc pose) and the FE damage sets each connection's
//!   start state; the ruin stage then runs with the remaining ground motion until rest or
//!   the time limit.
//! * `rigid`: the ruin stage from t = 0 on the undeformed model under the whole record
//!   ([`StageInput::rigid_only`]).
//! * `fe`: the FE stage only (no collapse monitor stop).
//!
//! **Foundation.** The FE model's base nodes are fixed to the ground; the rigid-body
//! model gets passive foundation blocks under the base columns and walls
//! ([`crate::mapping::foundation`]).
//!
//! **FE damage → connection start state**: [`ruin_start`] (FE-derived strengths and the
//! shells' lost load paths, or BCB's per-pair FE damage flags).
//!
//! The ground motion of the FE stage is the record's acceleration; the ground of the
//! mapping and of the ruin stage is its integral on the FE step with BCB-style zero-end
//! baseline ([`crate::motion::Baseline::ZeroEnd`], < 0.1 % change of the acceleration).

pub mod ensemble;
pub mod error;
pub mod preset;
pub mod ruin_stage;
pub(crate) mod ruin_start;
pub mod scenario;
pub mod strengths;
pub mod write;

use crate::bullet::{Pose, Velocity};
use crate::collapse::{CollapseEvent, CollapseMonitor, Trigger};
use crate::fe::analysis::transient::{Removal, StepControl, StopReason as FeStop};
use crate::fe::build::{BuildOptions, BuiltDomain};
use crate::fe::domain::Domain;
use crate::fe::run::{prepare, run_prepared, Prepared, RunOptions};
use crate::mapping::handoff::{GroundState, Handoff, NodeState};
use crate::mapping::{self, MapOptions};
use crate::model::Model;
use crate::motion::{Baseline, Format, GroundHistory, GroundMotion};
use crate::ruin::connection::GroupStrength;
use crate::ruin::groups::group_strengths_for;
use crate::ruin::stage::{to_isometry, to_pose, RuinResult, RuinStage, StageInput, StageSettings};
use crate::ruin::BodyGeom;
use error::Result;
pub use error::{PipelineError, ScenarioError};
use nalgebra::UnitQuaternion;
pub use ruin_stage::{ruin_stage, stage_settings, RuinStageSettings};
use ruin_start::ConnectionStart;
pub use scenario::{ConnectionModel, Mode, Scenario, VelocityHandoff};
use std::time::{Duration, Instant};

/// Keyframe rate, frames per second (BCB/Blender 25 fps).
pub(crate) const FRAME_RATE: f64 = 25.0;

pub use crate::body::Body;

/// Why the FE stage ended / what Tc is.
#[derive(Debug, Clone, PartialEq)]
pub enum TcReason {
    /// The collapse criterion was met.
    Criterion(String),
    /// A step did not converge first: hand-off at the last converged step.
    Diverged(String),
    /// The record (or `fe.duration`) ended without collapse.
    NoCollapse,
    /// Not applicable (rigid mode: Tc = 0).
    RigidOnly,
}

/// Everything a run produced, before it is written.
#[derive(Debug, Clone)]
pub struct RunRecord {
    /// The scenario's mode.
    pub mode: Mode,
    /// Model scale.
    pub scale: f64,
    /// The bodies.
    pub bodies: Vec<Body>,
    /// Tc, s (end of the FE stage).
    pub tc_s: Option<f64>,
    /// Why.
    pub tc_reason: TcReason,
    /// FE keyframes (t, poses), 25 fps up to Tc.
    pub fe_frames: Vec<(f64, Vec<Pose>)>,
    /// The ruin stage's result.
    pub ruin: Option<RuinResult>,
    /// The preset the ruin stage's settings started from (`summary.json` `preset`;
    /// `None` when no ruin stage ran).
    pub preset: Option<preset::Preset>,
    /// Final poses (ruin stage, else the FE's last state).
    pub final_poses: Vec<Pose>,
    /// Ground displacement history (for the glTF ground and the debris height).
    pub ground: GroundHistory,
    /// FE stage wall time.
    pub fe_wall: Duration,
    /// Ruin stage wall time (build + run) and the part inside Bullet's step.
    pub ruin_wall: Duration,
    /// Wall time inside Bullet.
    pub ruin_in_bullet: Duration,
    /// FE end time reached, s.
    pub fe_end_s: Option<f64>,
    /// Elements the FE removed after they lost their load path, in the order of removal
    /// (`summary.json` `fe_removed_elements`).
    pub fe_removed: Vec<Removal>,
    /// The model's values outside their plausible ranges that the user accepted
    /// (`--allow-unusual`; [`crate::model::plausibility`]); `summary.json` lists them.
    pub unusual: Vec<String>,
}

/// Progress reporting hooks (the CLI passes indicatif bars; tests pass nothing).
pub trait Progress {
    /// FE stage: simulated time `t` of `t_end` s.
    fn fe(&self, _t: f64, _t_end: f64) {}
    /// Ruin stage: frame at simulated time `t` of at most `t_end` s, with the
    /// connection counts (intact, plastic, broken) after it.
    fn ruin(&self, _t: f64, _t_end: f64, _counts: (usize, usize, usize)) {}
    /// A stage begins (`"fe"`, `"ruin"`), with its simulated time span.
    fn stage(&self, _name: &str, _from_s: f64, _to_s: f64) {}
    /// The work ahead, once checked against the resource bounds ([`check_budget`]):
    /// FE steps and ruin-stage substeps (at most; the ruin stage may stop at rest).
    fn plan(&self, _fe_steps: u64, _ruin_substeps: u64) {}
    /// A stage ends.
    fn done(&self) {}
}

/// No progress output.
pub struct Silent;
impl Progress for Silent {}

/// Reads the scenario's ground motion: each component from its file, scaled to its PGA
/// and time-scaled by its own factor.
pub fn ground_motion(sc: &Scenario) -> Result<GroundMotion> {
    let mut gm = GroundMotion::default();
    for (axis, c) in sc.components.iter().enumerate() {
        let Some(c) = c else { continue };
        let one = GroundMotion::from_files(
            {
                let mut p: [Option<&std::path::Path>; 3] = [None; 3];
                p[axis] = Some(c.file.as_path());
                p
            },
            Format::Auto,
        )
        .map_err(|error| PipelineError::Record {
            scenario: sc.path.clone(),
            direction: c.direction,
            error: Box::new(error),
        })?;
        let mut rec = one.components[axis]
            .clone()
            .ok_or_else(|| PipelineError::NoRecord(c.file.clone()))?;
        if let Some(g) = c.pga_g {
            rec.scale_to_pga(g).map_err(|error| PipelineError::Scale {
                file: c.file.clone(),
                pga_g: g,
                error: Box::new(error),
            })?;
        }
        if c.time_scale != 1.0 {
            rec.time_scale(c.time_scale)
                .map_err(|error| PipelineError::Motion {
                    what: "time scaling",
                    error: Box::new(error),
                })?;
        }
        gm.components[axis] = Some(rec);
    }
    Ok(gm)
}

/// The ruin stage's view of the bodies.
pub fn geoms(bodies: &[Body]) -> Vec<BodyGeom> {
    bodies
        .iter()
        .map(|b| {
            let iso = to_isometry(&b.pose0);
            BodyGeom {
                name: b.id.name(),
                group: b.id.group().to_string(),
                centre: [iso.translation.x, iso.translation.y, iso.translation.z],
                rotation: iso.rotation,
                half_extents: b.half_extents,
                passive: b.passive,
            }
        })
        .collect()
}

fn shifted(p: &Pose, d: [f64; 3]) -> Pose {
    Pose {
        position: [
            p.position[0] + d[0],
            p.position[1] + d[1],
            p.position[2] + d[2],
        ],
        orientation: p.orientation,
    }
}

fn poses_from_states(
    handoff: &Handoff,
    bodies: &[Body],
    nodes: &[NodeState],
    ground: &GroundState,
) -> Result<(Vec<Pose>, Vec<Velocity>)> {
    let states = handoff
        .states(nodes, ground)
        .map_err(|e| PipelineError::HandOff(Box::new(e)))?;
    let mut poses = Vec::with_capacity(bodies.len());
    let mut vels = Vec::with_capacity(bodies.len());
    for s in &states {
        poses.push(to_pose(&nalgebra::Isometry3::from_parts(
            nalgebra::Translation3::from(nalgebra::Vector3::from(s.centre)),
            s.rotation,
        )));
        vels.push(Velocity {
            linear: s.linear_velocity,
            angular: s.angular_velocity,
        });
    }
    for b in &bodies[states.len()..] {
        poses.push(shifted(&b.pose0, ground.displacement));
        vels.push(Velocity {
            linear: ground.velocity,
            angular: [0.0; 3],
        });
    }
    Ok((poses, vels))
}

fn ground_at(h: &GroundHistory, t: f64) -> GroundState {
    let (d, v, _) = h.ground_state_at(t);
    GroundState {
        displacement: d,
        velocity: v,
    }
}

/// The end of the timeline: `physics.time_limit_s`, else the record's end + settle time.
pub(crate) fn time_limit(sc: &Scenario, gm: &GroundMotion) -> f64 {
    sc.physics
        .time_limit_s
        .unwrap_or(gm.duration_s() + sc.physics.settle_s)
}

/// The work a scenario asks for, checked against the resource bounds
/// ([`crate::model::limits`]) once the records are read and before anything runs:
/// FE steps (duration / Δt), ground-history samples (record / Δt) and physics substeps
/// (timeline × steps per second). Returns (FE steps, physics substeps).
pub(crate) fn check_budget(sc: &Scenario, gm: &GroundMotion) -> Result<(u64, u64)> {
    use crate::model::limits::{
        grid_count, show_number, MAX_FE_STEPS, MAX_PHYSICS_SUBSTEPS, MAX_SAMPLES,
    };
    let p = sc.path.display();
    let fe_end = sc.duration.unwrap_or_else(|| gm.duration_s());
    grid_count(
        format!(
            "{p}: ground motion of {} s with fe.dt = {} s",
            show_number(gm.duration_s()),
            show_number(sc.dt)
        ),
        "ground-history samples",
        gm.duration_s(),
        sc.dt,
        MAX_SAMPLES,
    )?;
    let fe = if sc.mode == Mode::Rigid {
        0
    } else {
        grid_count(
            format!(
                "{p}: FE stage of {} s with fe.dt = {} s",
                show_number(fe_end),
                show_number(sc.dt)
            ),
            "time steps",
            fe_end,
            sc.dt,
            MAX_FE_STEPS,
        )? as u64
    };
    let limit = time_limit(sc, gm);
    let physics = if sc.mode == Mode::Fe {
        0
    } else {
        grid_count(
            format!(
                "{p}: ruin stage of up to {} s at physics.steps_per_second = {}",
                show_number(limit),
                show_number(sc.physics.steps_per_second)
            ),
            "ruin-stage substeps",
            limit,
            1.0 / sc.physics.steps_per_second,
            MAX_PHYSICS_SUBSTEPS,
        )? as u64
    };
    Ok((fe, physics))
}

/// Runs a scenario and returns the record (nothing is written).
pub fn run(sc: &Scenario, progress: &dyn Progress) -> Result<RunRecord> {
    run_perturbed(sc, progress, None)
}

/// What every stage reads, loaded and checked once before any work: the model, the
/// ground motion (perturbed for a rigid-only ensemble member), its integral on the FE
/// step, the mapped bodies and the BCB group strengths.
pub struct Inputs {
    /// The model.
    pub model: Model,
    /// The ground motion (accelerations), as the FE stage uses it.
    pub motion: GroundMotion,
    /// Its integral on the FE step (displacement, velocity), the ground of the mapping
    /// and the ruin stage.
    pub ground: GroundHistory,
    /// The mapping of the FE elements to boxes.
    pub mapping: mapping::Mapping,
    /// The run's bodies: mapped boxes, then foundation blocks
    /// ([`mapping::foundation::bodies_of`]).
    pub bodies: Vec<Body>,
    /// BCB's Formula-Assistant strengths per group.
    pub groups: Vec<GroupStrength>,
    /// The work ahead ([`check_budget`]): FE steps and physics substeps.
    pub budget: (u64, u64),
    /// The ruin stage's mass-proportional damping relative to the ground, 1/s
    /// (`[physics] ground_damping`: 0, or the model's Rayleigh a₀).
    pub ground_damping_per_s: f64,
}

/// Loads and checks the scenario's inputs (module docs of [`Inputs`]). In the rigid
/// mode an ensemble member's ground motion is scaled by its perturbation.
pub(crate) fn load_inputs(
    sc: &Scenario,
    perturbation: Option<&ensemble::Perturbation>,
) -> Result<Inputs> {
    let model = Model::load(&sc.model).map_err(|error| PipelineError::Model {
        path: sc.model.clone(),
        error: Box::new(error),
    })?;
    let mut motion = ground_motion(sc)?;
    if let (Some(p), Mode::Rigid) = (perturbation, sc.mode) {
        for (k, c) in motion.components.iter_mut().enumerate() {
            if let Some(rec) = c {
                rec.scale(1.0 + p.ground_share * p.uniform(1, k as u64));
            }
        }
    }
    let budget = check_budget(sc, &motion)?;
    let ground = motion
        .integrate(sc.dt, Baseline::default())
        .map_err(|error| PipelineError::Motion {
            what: "integrating the ground motion",
            error: Box::new(error),
        })?;
    let mapping = mapping::from_model(&model)
        .and_then(|input| mapping::map_to_boxes(&input, &MapOptions::default()))
        .map_err(|error| PipelineError::Mapping {
            path: sc.model.clone(),
            error: Box::new(error),
        })?;
    let bodies = mapping::foundation::bodies_of(&model, &mapping);
    // Wall groups take ACI 318 per-area strengths when the connections are FE-derived
    // (docs/handoff.md §2.5), BCB's con_rei_wall otherwise.
    let fe_strengths = ConnectionStart::of(sc).fe_strengths;
    let groups =
        group_strengths_for(&model, fe_strengths).map_err(|error| PipelineError::Groups {
            path: sc.model.clone(),
            error: Box::new(error),
        })?;
    let ground_damping_per_s = match sc.physics.ground_damping {
        scenario::GroundDamping::None => 0.0,
        scenario::GroundDamping::Fe => match model.rayleigh() {
            Some((a0, _)) => a0,
            None => {
                return Err(PipelineError::Scenario(ScenarioError::Invalid {
                    file: sc.path.display().to_string(),
                    message: format!(
                        "physics.ground_damping = \"fe\" needs the model's [damping] \
                         (its Rayleigh a0); {} has none",
                        sc.model.display()
                    ),
                }))
            }
        },
    };
    Ok(Inputs {
        model,
        motion,
        ground,
        mapping,
        bodies,
        groups,
        budget,
        ground_damping_per_s,
    })
}

/// The FE domain of a scenario, built once ([`crate::fe::run::prepare`]: the element
/// variant, the initial modal analysis, gravity applied and held). The FE-derived
/// connection strengths read its gravity state; the FE stage then runs the time history
/// on it.
pub(crate) fn fe_domain(settings: &FeStageSettings, model: &Model) -> Result<Prepared> {
    prepare(model, &settings.build, RunOptions::default().modes).map_err(|error| {
        PipelineError::Fe {
            stage: "building the FE domain",
            error: Box::new(error),
        }
    })
}

/// What the FE stage takes of a scenario, resolved for its model and record.
pub(crate) struct FeStageSettings {
    /// The domain's element variant, concrete integration and threads.
    pub build: BuildOptions,
    /// Time step, s.
    pub dt: f64,
    /// End of the time history, s: the scenario's `duration`, or the record's.
    pub end_s: f64,
    /// The collapse criterion at the model's scale.
    pub criterion: crate::collapse::Criterion,
    /// Whether the time history stops when the criterion is met (the hybrid mode).
    pub stop_at_tc: bool,
}

impl FeStageSettings {
    /// The settings of scenario `sc` on its loaded `inputs`.
    pub(crate) fn of(sc: &Scenario, inputs: &Inputs) -> Self {
        FeStageSettings {
            build: BuildOptions {
                variant: sc.variant,
                concrete_integration: sc.concrete_integration,
                threads: sc.threads,
                ..Default::default()
            },
            dt: sc.dt,
            end_s: sc.duration.unwrap_or_else(|| inputs.motion.duration_s()),
            criterion: sc.criterion.resolve(inputs.model.scale),
            stop_at_tc: sc.mode == Mode::Hybrid,
        }
    }
}

/// What the FE stage produced.
pub(crate) struct FeStageOutput {
    /// The domain in its last converged state.
    pub built: BuiltDomain,
    /// Why the time history ended.
    pub stop: FeStop,
    /// Elements removed during the time history.
    pub removed: Vec<Removal>,
    /// The collapse criterion's event, if it was met.
    pub event: Option<CollapseEvent>,
    /// The FE nodal state (model node order) every 1/[`FRAME_RATE`] s from t = 0.
    pub frames: Vec<(f64, Vec<NodeState>)>,
    /// The nodal state at the end (model node order).
    pub end_state: Vec<NodeState>,
    /// End time reached, s.
    pub end_s: f64,
    /// Wall time.
    pub wall: Duration,
}

/// The FE stage: the time history on the prepared domain `prepared` under the scenario's
/// ground motion, the collapse monitor observing every converged step; in the hybrid mode
/// it stops when the criterion is met. Keyframes of the nodal state every 1/25 s.
pub(crate) fn fe_stage(
    settings: &FeStageSettings,
    inputs: &Inputs,
    prepared: Prepared,
    progress: &dyn Progress,
) -> Result<FeStageOutput> {
    let model = &inputs.model;
    let gm = &inputs.motion;
    let mut monitor = CollapseMonitor::new(model, settings.criterion)?;
    let node_index = |t: &u32| -> Result<usize> {
        prepared
            .built
            .node_index
            .get(t)
            .copied()
            .ok_or(PipelineError::MissingNode { at: "", node: *t })
    };
    let index: Vec<usize> = monitor
        .structure()
        .node_tags
        .iter()
        .map(node_index)
        .collect::<Result<_>>()?;
    let model_index: Vec<usize> = model
        .nodes
        .iter()
        .map(|n| node_index(&n.tag))
        .collect::<Result<_>>()?;
    let t_end = settings.end_s;
    let options = RunOptions {
        build: settings.build,
        dt: settings.dt,
        duration: Some(t_end),
        every: usize::MAX,
        ..Default::default()
    };
    let stop_at_tc = settings.stop_at_tc;
    let mut frames: Vec<(f64, Vec<NodeState>)> = Vec::new();
    let mut next_frame = 1u64;
    progress.stage("fe", 0.0, t_end);
    let t0 = Instant::now();
    frames.push((0.0, vec![NodeState::default(); model.nodes.len()]));
    let result = run_prepared(model, prepared, gm, &options, &mut |info, domain| {
        progress.fe(info.time, t_end);
        let frame_t = next_frame as f64 / FRAME_RATE;
        if info.time >= frame_t - 1e-9 {
            frames.push((frame_t, states_at(domain, &model_index)));
            while next_frame as f64 / FRAME_RATE <= info.time + 1e-9 {
                next_frame += 1;
            }
        }
        let u: Vec<[f64; 3]> = index
            .iter()
            .map(|&k| {
                let d = domain.displacement(k);
                [d[0], d[1], d[2]]
            })
            .collect();
        if monitor.observe(info.step, info.time, &u).is_some() && stop_at_tc {
            StepControl::Stop
        } else {
            StepControl::Continue
        }
    })
    .map_err(|e| PipelineError::FeRun(Box::new(e)))?;
    progress.done();
    let wall = t0.elapsed();
    let end_state = states_at(&result.built.domain, &model_index);
    Ok(FeStageOutput {
        end_s: result.built.domain.time(),
        stop: result.transient.stop,
        removed: result.transient.removed,
        built: result.built,
        event: monitor.event().copied(),
        frames,
        end_state,
        wall,
    })
}

/// The committed FE state of every model node (model order) of a built domain:
/// displacement/rotation and velocity/rotational velocity, relative to the ground (the
/// hand-off's plain input, [`NodeState`]). Errors name a model node missing from the
/// domain.
pub fn node_states(model: &Model, built: &BuiltDomain) -> Result<Vec<NodeState>> {
    let index = model
        .nodes
        .iter()
        .map(|n| {
            built
                .node_index
                .get(&n.tag)
                .copied()
                .ok_or(PipelineError::MissingNode {
                    at: "hand-off: ",
                    node: n.tag,
                })
        })
        .collect::<Result<Vec<usize>>>()?;
    Ok(states_at(&built.domain, &index))
}

/// The committed state (displacement/rotation, velocity/rotational velocity, relative
/// to the ground) of the domain nodes `index`.
fn states_at(domain: &Domain, index: &[usize]) -> Vec<NodeState> {
    index
        .iter()
        .map(|&k| {
            let (d, v) = (domain.displacement(k), domain.velocity(k));
            NodeState {
                u: [d[0], d[1], d[2]],
                theta: [d[3], d[4], d[5]],
                v: [v[0], v[1], v[2]],
                omega: [v[3], v[4], v[5]],
            }
        })
        .collect()
}

/// The collapse decision: Tc and why.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct CollapseDecision {
    /// Tc, s: the criterion's time, or the last converged step when the FE diverged;
    /// `None` without collapse.
    pub tc_s: Option<f64>,
    /// Why.
    pub reason: TcReason,
}

/// Decides Tc from the FE stage: a step that did not converge first means a hand-off at
/// the last converged step; else the criterion's event (in the `fe` mode the FE runs on
/// past it, Tc is still the event's time); else no collapse.
pub(crate) fn collapse_decision(fe: &FeStageOutput) -> CollapseDecision {
    let tc = fe.end_s;
    let reason = match (&fe.stop, &fe.event) {
        (
            FeStop::Diverged {
                attempted, reason, ..
            },
            _,
        ) => TcReason::Diverged(format!(
            "the step to t = {attempted:.4} s did not converge ({reason}); hand-off at the last converged step t = {tc:.4} s"
        )),
        (_, Some(ev)) => TcReason::Criterion(match ev.trigger {
            Trigger::VerticalDrop { node, drop_m, threshold_m } => format!(
                "vertical drop of node {node}: {drop_m:.4} m >= {threshold_m:.4} m"
            ),
            Trigger::StoryDrift { story, ratio, limit, .. } => format!(
                "story {story} drift ratio {ratio:.5} >= {limit:.5}"
            ),
        }),
        _ => TcReason::NoCollapse,
    };
    let tc_s = match reason {
        TcReason::Criterion(_) => fe.event.as_ref().map(|e| e.time_s),
        TcReason::Diverged(_) => Some(tc),
        _ => None,
    };
    CollapseDecision { tc_s, reason }
}

/// The hand-off's result: the bodies' keyframes up to the end of the FE stage and their
/// poses and velocities there.
#[derive(Debug, Clone)]
pub(crate) struct HandoffOutput {
    /// Keyframes (t, one pose per body), every 1/25 s from 0.
    pub frames: Vec<(f64, Vec<Pose>)>,
    /// Poses at the end of the FE stage (Tc).
    pub poses: Vec<Pose>,
    /// Velocities there (instantaneous or secant, [`VelocityHandoff`]).
    pub velocities: Vec<Velocity>,
}

/// The hand-off: every FE keyframe and the end state posed as rigid bodies (absolute:
/// the ground's displacement plus the FE's relative state; foundations move with the
/// ground), with the instantaneous velocities at the end, or (`velocity`) the paper's
/// secant through the last keyframe before it.
pub(crate) fn hand_off(
    velocity: VelocityHandoff,
    inputs: &Inputs,
    handoff: &Handoff,
    fe: &FeStageOutput,
) -> Result<HandoffOutput> {
    let bodies = &inputs.bodies;
    let mut frames = Vec::with_capacity(fe.frames.len());
    for (t, nodes) in &fe.frames {
        let (poses, _) = poses_from_states(handoff, bodies, nodes, &ground_at(&inputs.ground, *t))?;
        frames.push((*t, poses));
    }
    let tc = fe.end_s;
    let (poses, mut velocities) = poses_from_states(
        handoff,
        bodies,
        &fe.end_state,
        &ground_at(&inputs.ground, tc),
    )?;
    if velocity == VelocityHandoff::Secant {
        let (t_prev, prev) = frames
            .iter()
            .rev()
            .find(|(t, _)| *t < tc - 1e-9)
            .cloned()
            .ok_or(PipelineError::NoKeyframe { tc_s: tc })?;
        let q = |p: &Pose| {
            UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                p.orientation[0],
                p.orientation[1],
                p.orientation[2],
                p.orientation[3],
            ))
        };
        for (i, v) in velocities
            .iter_mut()
            .enumerate()
            .take(inputs.mapping.bodies.len())
        {
            let (lin, ang) = mapping::handoff::secant_velocity(
                &[
                    (prev[i].position, q(&prev[i])),
                    (poses[i].position, q(&poses[i])),
                ],
                tc - t_prev,
                1,
            )
            .map_err(|e| PipelineError::HandOff(Box::new(e)))?;
            *v = Velocity {
                linear: lin,
                angular: ang,
            };
        }
    }
    Ok(HandoffOutput {
        frames,
        poses,
        velocities,
    })
}

/// The rigid-only ruin stage of `sc` exactly as [`run`] builds it (BCB's Formula-Assistant
/// connections, every body at its start pose at t = 0, the scenario's moving ground), with
/// `adjust` applied to its settings, not yet run: for checks that drive the same stage in
/// two ways (e.g. the shim's solver against Bullet's stock one,
/// [`crate::bullet::WorldSettings::stock_solver`]). The scenario must be rigid-only with
/// `connections = "formula"` (the default of that mode).
pub fn rigid_only_stage(sc: &Scenario, adjust: &dyn Fn(&mut StageSettings)) -> Result<RuinStage> {
    if sc.mode != Mode::Rigid || sc.physics.connections != ConnectionModel::Formula {
        return Err(PipelineError::Scenario(ScenarioError::Invalid {
            file: sc.path.display().to_string(),
            message: "a rigid-only stage needs mode = \"rigid\" with connections = \"formula\""
                .into(),
        }));
    }
    let inputs = load_inputs(sc, None)?;
    let geoms = geoms(&inputs.bodies);
    let masses: Vec<f64> = inputs.bodies.iter().map(|b| b.mass_kg).collect();
    let start = StageInput::rigid_only(&geoms, &masses, &inputs.groups);
    ruin_stage::build_stage(&RuinStageSettings::of(sc, &inputs), &inputs, &start, adjust)
}

/// As [`run`], with the start of the ruin stage perturbed as an ensemble member
/// ([`ensemble`]): hybrid, the hand-off velocities; rigid-only, the ground motion.
/// The stages in order: [`load_inputs`], [`fe_domain`] (once), [`fe_stage`],
/// [`collapse_decision`], [`hand_off`], the ruin stage's start state, [`ruin_stage`].
pub(crate) fn run_perturbed(
    sc: &Scenario,
    progress: &dyn Progress,
    perturbation: Option<&ensemble::Perturbation>,
) -> Result<RunRecord> {
    let inputs = load_inputs(sc, perturbation)?;
    progress.plan(inputs.budget.0, inputs.budget.1);
    let bodies = &inputs.bodies;
    let mut rec = RunRecord {
        mode: sc.mode,
        scale: inputs.model.scale,
        bodies: bodies.clone(),
        tc_s: None,
        tc_reason: TcReason::RigidOnly,
        fe_frames: Vec::new(),
        ruin: None,
        preset: None,
        final_poses: bodies.iter().map(|b| b.pose0).collect(),
        ground: inputs.ground.clone(),
        fe_wall: Duration::ZERO,
        ruin_wall: Duration::ZERO,
        ruin_in_bullet: Duration::ZERO,
        fe_end_s: None,
        fe_removed: Vec::new(),
        unusual: Vec::new(),
    };
    let geoms = geoms(bodies);
    let masses: Vec<f64> = bodies.iter().map(|b| b.mass_kg).collect();
    let mut start = StageInput::rigid_only(&geoms, &masses, &inputs.groups);
    let connection_start = ConnectionStart::of(sc);
    let fe_settings = FeStageSettings::of(sc, &inputs);
    let domain = if sc.mode != Mode::Rigid || connection_start.fe_strengths {
        Some(fe_domain(&fe_settings, &inputs.model)?)
    } else {
        None
    };
    let gravity = match &domain {
        Some(d) => ruin_start::gravity_strengths(
            connection_start,
            &inputs.model,
            &d.built,
            bodies,
            &mut start,
        )?,
        None => None,
    };
    if sc.mode != Mode::Rigid {
        let handoff = Handoff::new(&inputs.model, &inputs.mapping)
            .map_err(|e| PipelineError::HandOff(Box::new(e)))?;
        let prepared = domain.expect("the FE modes build the domain");
        let fe = fe_stage(&fe_settings, &inputs, prepared, progress)?;
        rec.fe_wall = fe.wall;
        rec.fe_end_s = Some(fe.end_s);
        rec.fe_removed.clone_from(&fe.removed);
        let decision = collapse_decision(&fe);
        rec.tc_s = decision.tc_s;
        rec.tc_reason = decision.reason;
        let HandoffOutput {
            frames,
            poses,
            mut velocities,
        } = hand_off(sc.velocity, &inputs, &handoff, &fe)?;
        rec.fe_frames = frames;
        rec.final_poses = poses.clone();
        if sc.mode == Mode::Fe || rec.tc_s.is_none() {
            return Ok(rec);
        }
        ruin_start::damage_at_tc(connection_start, &inputs, &fe, gravity.as_ref(), &mut start)?;
        if let Some(p) = perturbation {
            ruin_start::perturb_velocities(p, &mut velocities, inputs.mapping.bodies.len());
        }
        start.start_poses = poses.iter().map(to_isometry).collect();
        start.start_velocities = velocities;
        start.start_time_s = fe.end_s;
    }
    let (result, wall) = ruin_stage(
        &RuinStageSettings::of(sc, &inputs),
        &inputs,
        &start,
        progress,
    )?;
    rec.ruin_wall = wall;
    rec.ruin_in_bullet = result.wall.in_bullet;
    rec.final_poses = result.final_poses.clone();
    rec.ruin = Some(result);
    rec.preset = Some(sc.physics.preset);
    Ok(rec)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// The ERPs handed to Bullet: BCB's 0.2 at 200 substeps/s whatever
    /// `erp_steps_per_second` says; 0.05 at 800 when given per time (the default),
    /// 0.2 at 800 with `erp_steps_per_second = 0` (per substep, Bullet's and BCB's);
    /// capped at 1 below the reference rate.
    #[test]
    fn erps_given_per_time_scale_with_the_substep() {
        let erps = |physics: &str| {
            // The shipped frame3 LC5 scenario (its [physics] table comes last).
            let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/frame3/lc5.toml");
            let text = std::fs::read_to_string(&path).unwrap() + "\n" + physics + "\n";
            let sc = Scenario::parse(&text, &path).unwrap();
            let s = stage_settings(&sc);
            (s.world.solver.erp2, s.world.solver.erp)
        };
        assert_eq!(erps(""), (0.2, 0.2));
        assert_eq!(erps("steps_per_second = 800"), (0.05, 0.05));
        assert_eq!(
            erps("steps_per_second = 800\nexperimental.contact_erp = 0.4\nexperimental.joint_erp = 0.1"),
            (0.1, 0.025)
        );
        assert_eq!(
            erps("steps_per_second = 800\nexperimental.erp_steps_per_second = 0"),
            (0.2, 0.2)
        );
        assert_eq!(
            erps("steps_per_second = 50\nexperimental.joint_erp = 0.5"),
            (0.8, 1.0)
        );
    }
}
