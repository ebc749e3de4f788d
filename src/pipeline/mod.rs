//! The pipeline that joins the stages (paper Fig. 1, issue 5): scenario → model → FE with
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
//! * `physics`: the ruin stage from t = 0 on the undeformed model under the whole record
//!   ([`StageInput::physics_only`]).
//! * `fe`: the FE stage only (no collapse monitor stop).
//!
//! **Foundation.** The FE model's base nodes are fixed to the ground; the rigid-body
//! model gets one passive (kinematic) foundation block under every column that stands on
//! the base: plan 2·a × 2·a, depth a, a = the larger cross-section size of the column box,
//! top at the base level. The bottom columns connect to it with ×2 thresholds (BCB's
//! passive group rule).
//!
//! **FE damage → connection start state.** With FE-derived connections (`[physics]
//! connections = "fe"`, the hybrid default; [`strengths`], docs/handoff.md) every
//! connection starts elastic with the residual capacities at Tc and broken only where a
//! section it cuts has lost its load path. With BCB's (`"formula"`): a connection's damage
//! is the worse of the FE damage flags ([`crate::fe::element::ElementDamage`]) of the two
//! elements it joins
//! (ruptured → broken, yielded → plastic, else elastic; panels and foundations count as
//! intact) — [`crate::ruin::monitor::start_state_from_damage`].
//!
//! The ground motion of the FE stage is the record's acceleration; the ground of the
//! mapping and of the ruin stage is its integral on the FE step with BCB-style zero-end
//! baseline ([`crate::motion::Baseline::ZeroEnd`], < 0.1 % change of the acceleration).

pub mod ensemble;
pub mod scenario;
pub mod strengths;
pub mod write;

use crate::collapse::{CollapseMonitor, Trigger};
use crate::fe::analysis::transient::{StepControl, StopReason as FeStop};
use crate::fe::build::BuildOptions;
use crate::fe::run::{run_ground_motion, RunOptions};
use crate::mapping::handoff::{node_states, GroundState, Handoff, NodeState};
use crate::mapping::{self, BodyKind, MapOptions};
use crate::model::{ElementKind, Model};
use crate::motion::{Baseline, Format, GroundHistory, GroundMotion};
use crate::physics::{Pose, Velocity};
use crate::ruin::ground::GroundSpec;
use crate::ruin::groups::{group_strengths, FOUNDATION_GROUP};
use crate::ruin::monitor::FeDamage;
use crate::ruin::stage::{
    to_isometry, to_pose, RuinResult, RuinStage, StageInput, StageSettings, StopReason, StopRule,
};
use crate::ruin::BodyGeom;
use anyhow::{anyhow, Context, Result};
use nalgebra::UnitQuaternion;
pub use scenario::{ConnectionModel, Mode, Scenario, VelocityHandoff};
use std::collections::BTreeMap;
use std::time::{Duration, Instant};

/// Keyframe rate, frames per second (BCB/Blender 25 fps).
pub const FRAME_RATE: f64 = 25.0;

/// One rigid body of the run (the mapping's boxes, then the foundation blocks).
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Name, e.g. `Column:1:4`, `Foundation:base:1`.
    pub name: String,
    /// Group (element group; `foundation`).
    pub group: String,
    /// Element type (`Column`, `Beam`, `Slab`, `Foundation`).
    pub type_name: String,
    /// Material / group id of the element (`-` for foundations).
    pub material: String,
    /// FE element id (`-` for foundations, which carry the base node tag in the name).
    pub element: String,
    /// Geometric role (`None` for foundations).
    pub kind: Option<BodyKind>,
    /// Half extents, m.
    pub half_extents: [f64; 3],
    /// Undeformed pose.
    pub pose0: Pose,
    /// Mass, kg (0 for passive).
    pub mass_kg: f64,
    /// Passive (kinematic foundation).
    pub passive: bool,
}

/// Why the FE stage ended / what Tc is.
#[derive(Debug, Clone, PartialEq)]
pub enum TcReason {
    /// The collapse criterion was met.
    Criterion(String),
    /// A step did not converge first: hand-off at the last converged step.
    Diverged(String),
    /// The record (or `fe.duration`) ended without collapse.
    NoCollapse,
    /// Not applicable (physics mode: Tc = 0).
    PhysicsOnly,
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
}

/// Progress reporting hooks (the CLI passes indicatif bars; tests pass nothing).
pub trait Progress {
    /// FE stage: simulated time `t` of `t_end` s.
    fn fe(&self, _t: f64, _t_end: f64) {}
    /// Physics stage: frame at simulated time `t` of at most `t_end` s, with the
    /// connection counts (intact, plastic, broken) after it.
    fn physics(&self, _t: f64, _t_end: f64, _counts: (usize, usize, usize)) {}
    /// A stage begins (`"fe"`, `"physics"`), with its simulated time span.
    fn stage(&self, _name: &str, _from_s: f64, _to_s: f64) {}
    /// The work ahead, once checked against the resource bounds ([`check_budget`]):
    /// FE steps and physics substeps (at most; the physics stage may stop at rest).
    fn plan(&self, _fe_steps: u64, _physics_substeps: u64) {}
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
        .with_context(|| format!("{}: ground_motion {}", sc.path.display(), c.direction))?;
        let mut rec = one.components[axis]
            .clone()
            .ok_or_else(|| anyhow!("{}: no record read", c.file.display()))?;
        if let Some(g) = c.pga_g {
            rec.scale_to_pga(g)
                .with_context(|| format!("{}: scaling to {g} g", c.file.display()))?;
        }
        if c.time_scale != 1.0 {
            rec.time_scale(c.time_scale)?;
        }
        gm.components[axis] = Some(rec);
    }
    Ok(gm)
}

/// The model's bodies: mapped boxes then foundation blocks (module docs).
pub fn bodies_of(model: &Model, mapping: &mapping::Mapping) -> Vec<Body> {
    let mut out: Vec<Body> = mapping
        .bodies
        .iter()
        .map(|b| Body {
            name: b.name.clone(),
            group: b.group.clone(),
            type_name: b.type_name.clone(),
            material: b.material.clone(),
            element: b.element.to_string(),
            kind: Some(b.kind),
            half_extents: b.half_extents,
            pose0: to_pose(&BodyGeom::pose(&geom_of_box(b))),
            mass_kg: b.mass_kg,
            passive: false,
        })
        .collect();
    let zmin = model
        .nodes
        .iter()
        .map(|n| n.xyz()[2])
        .fold(f64::INFINITY, f64::min);
    let mut feet = Vec::new();
    for b in &mapping.bodies {
        if b.kind != BodyKind::Column {
            continue;
        }
        let Some(base) = b.nodes.iter().find(|n| (n[2] - zmin).abs() < 1e-9) else {
            continue;
        };
        let a = b.half_extents[1].max(b.half_extents[2]) * 2.0;
        let tag = model
            .nodes
            .iter()
            .find(|n| n.xyz() == *base)
            .map_or(0, |n| n.tag);
        feet.push(Body {
            name: format!("Foundation:base:{tag}"),
            group: FOUNDATION_GROUP.into(),
            type_name: "Foundation".into(),
            material: "-".into(),
            element: "-".into(),
            kind: None,
            half_extents: [a, a, a / 2.0],
            pose0: Pose::at([base[0], base[1], zmin - a / 2.0]),
            mass_kg: 0.0,
            passive: true,
        });
    }
    out.extend(feet);
    out
}

fn geom_of_box(b: &mapping::RigidBox) -> BodyGeom {
    BodyGeom {
        name: b.name.clone(),
        group: b.group.clone(),
        centre: b.centre,
        rotation: b.rotation,
        half_extents: b.half_extents,
        passive: false,
    }
}

/// The ruin stage's view of the bodies.
pub fn geoms(bodies: &[Body]) -> Vec<BodyGeom> {
    bodies
        .iter()
        .map(|b| {
            let iso = to_isometry(&b.pose0);
            BodyGeom {
                name: b.name.clone(),
                group: b.group.clone(),
                centre: [iso.translation.x, iso.translation.y, iso.translation.z],
                rotation: iso.rotation,
                half_extents: b.half_extents,
                passive: b.passive,
            }
        })
        .collect()
}

/// The ruin stage's settings from the scenario.
pub fn stage_settings(sc: &Scenario) -> StageSettings {
    let mut s = StageSettings::default();
    let p = &sc.physics;
    s.ruin.steps_per_second = p.steps_per_second;
    s.ruin.solver_iterations = p.solver_iterations;
    s.body.friction = p.friction;
    s.body.restitution = p.restitution;
    s.body.linear_damping = p.linear_damping;
    s.body.angular_damping = p.angular_damping;
    s.ruin.spring_correction = p.spring_correction;
    s.ruin.spring_damping = p.spring_damping;
    s.ruin.spring_limit_if_needed = p.spring_limit;
    s.ruin.angular_spring = p.angular_spring;
    s.world.solver.split_impulse = p.split_impulse;
    s.world.solver.split_impulse_penetration_threshold = p.split_impulse_threshold_m;
    s.world.solver.erp2 = p.contact_erp;
    s.world.solver.erp = p.joint_erp;
    s.body.margin = p.margin_m;
    s.body.margin_max_share = p.margin_max_share;
    s.spring_rest_at_plastic_onset = p.spring_rest_at_plastic_onset;
    s.body.disable_deactivation = !p.sleeping;
    s
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
    let states = handoff.states(nodes, ground)?;
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
pub fn time_limit(sc: &Scenario, gm: &GroundMotion) -> f64 {
    sc.physics
        .time_limit_s
        .unwrap_or(gm.duration_s() + sc.physics.settle_s)
}

/// The work a scenario asks for, checked against the resource bounds
/// ([`crate::model::limits`]) once the records are read and before anything runs:
/// FE steps (duration / Δt), ground-history samples (record / Δt) and physics substeps
/// (timeline × steps per second). Returns (FE steps, physics substeps).
pub fn check_budget(sc: &Scenario, gm: &GroundMotion) -> Result<(u64, u64)> {
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
    let fe = if sc.mode == Mode::Physics {
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
                "{p}: physics stage of up to {} s at physics.steps_per_second = {}",
                show_number(limit),
                show_number(sc.physics.steps_per_second)
            ),
            "physics substeps",
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

/// As [`run`], with the start of the ruin stage perturbed as an ensemble member
/// ([`ensemble`]): hybrid, the hand-off velocities; physics-only, the ground motion.
pub fn run_perturbed(
    sc: &Scenario,
    progress: &dyn Progress,
    perturbation: Option<&ensemble::Perturbation>,
) -> Result<RunRecord> {
    let model = Model::load(&sc.model).with_context(|| format!("model {}", sc.model.display()))?;
    let mut gm = ground_motion(sc)?;
    if let (Some(p), Mode::Physics) = (perturbation, sc.mode) {
        for (k, c) in gm.components.iter_mut().enumerate() {
            if let Some(rec) = c {
                rec.scale(1.0 + p.ground_share * p.uniform(1, k as u64));
            }
        }
    }
    let (fe_steps, substeps) = check_budget(sc, &gm)?;
    progress.plan(fe_steps, substeps);
    let ground = gm
        .integrate(sc.dt, Baseline::default())
        .context("integrating the ground motion")?;
    let map = mapping::map_to_boxes(&mapping::from_model(&model)?, &MapOptions::default())
        .with_context(|| format!("mapping {}", sc.model.display()))?;
    let bodies = bodies_of(&model, &map);
    let geoms = geoms(&bodies);
    let masses: Vec<f64> = bodies.iter().map(|b| b.mass_kg).collect();
    let groups = group_strengths(&model).with_context(|| format!("{}", sc.model.display()))?;
    let settings = stage_settings(sc);
    let limit = time_limit(sc, &gm);
    let stop = StopRule {
        max_time_s: limit,
        rest: sc.physics.stop_at_rest.then_some(sc.physics.rest),
    };
    let mut rec = RunRecord {
        mode: sc.mode,
        scale: model.scale,
        bodies: bodies.clone(),
        tc_s: None,
        tc_reason: TcReason::PhysicsOnly,
        fe_frames: Vec::new(),
        ruin: None,
        final_poses: bodies.iter().map(|b| b.pose0).collect(),
        ground,
        fe_wall: Duration::ZERO,
        ruin_wall: Duration::ZERO,
        ruin_in_bullet: Duration::ZERO,
        fe_end_s: None,
    };
    let mut start_input = StageInput::physics_only(&geoms, &masses, &groups);
    // FE-derived connection strengths (docs/handoff.md): the gravity axial loads, and in
    // the physics mode the undamaged capacities at them.
    let fe_strengths =
        sc.mode != Mode::Fe && sc.physics.connection_model(sc.mode) == ConnectionModel::Fe;
    let push = crate::fe::capacity::PushSettings::default();
    let mut gravity_n = BTreeMap::new();
    let mut gravity_caps = BTreeMap::new();
    if fe_strengths {
        let build = BuildOptions {
            variant: sc.variant,
            ..Default::default()
        };
        let (loads, caps) = crate::fe::capacity::gravity_capacities(&model, &build, &push)
            .context("FE-derived connection strengths")?;
        gravity_n = loads;
        start_input.body_strengths = strengths::body_strengths(&bodies, &caps);
        gravity_caps = caps;
    }
    if sc.mode != Mode::Physics {
        let handoff = Handoff::new(&model, &map)?;
        let criterion = sc.criterion.resolve(model.scale);
        let mut monitor = CollapseMonitor::new(&model, criterion)?;
        let index: Vec<usize> = {
            let built = crate::fe::build::build_domain(
                &model,
                &BuildOptions {
                    variant: sc.variant,
                    ..Default::default()
                },
            )?;
            monitor
                .structure()
                .node_tags
                .iter()
                .map(|t| built.node_index[t])
                .collect()
        };
        let model_index: Vec<usize> = {
            let built = crate::fe::build::build_domain(&model, &BuildOptions::default())?;
            model
                .nodes
                .iter()
                .map(|n| built.node_index[&n.tag])
                .collect()
        };
        let t_end = sc.duration.unwrap_or_else(|| gm.duration_s());
        let options = RunOptions {
            build: BuildOptions {
                variant: sc.variant,
                ..Default::default()
            },
            dt: sc.dt,
            duration: Some(t_end),
            every: usize::MAX,
            ..Default::default()
        };
        let stop_at_tc = sc.mode == Mode::Hybrid;
        let mut frames_nodes: Vec<(f64, Vec<NodeState>)> = Vec::new();
        let mut next_frame = 1u64;
        progress.stage("fe", 0.0, t_end);
        let t0 = Instant::now();
        frames_nodes.push((0.0, vec![NodeState::default(); model.nodes.len()]));
        let result = run_ground_motion(&model, &gm, &options, &mut |info, domain| {
            progress.fe(info.time, t_end);
            let frame_t = next_frame as f64 / FRAME_RATE;
            if info.time >= frame_t - 1e-9 {
                let nodes = model_index
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
                    .collect();
                frames_nodes.push((frame_t, nodes));
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
        })?;
        progress.done();
        rec.fe_wall = t0.elapsed();
        let tc = result.built.domain.time();
        rec.fe_end_s = Some(tc);
        rec.tc_reason = match (&result.transient.stop, monitor.event()) {
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
        rec.tc_s = match rec.tc_reason {
            // In `fe` mode the FE runs on past the criterion: Tc is the event's time.
            TcReason::Criterion(_) => monitor.event().map(|e| e.time_s),
            TcReason::Diverged(_) => Some(tc),
            _ => None,
        };
        for (t, nodes) in &frames_nodes {
            let (poses, _) =
                poses_from_states(&handoff, &bodies, nodes, &ground_at(&rec.ground, *t))?;
            rec.fe_frames.push((*t, poses));
        }
        let at_tc = node_states(&model, &result.built)?;
        let (poses, mut vels) =
            poses_from_states(&handoff, &bodies, &at_tc, &ground_at(&rec.ground, tc))?;
        if sc.velocity == VelocityHandoff::Secant {
            let (t_prev, prev) = rec
                .fe_frames
                .iter()
                .rev()
                .find(|(t, _)| *t < tc - 1e-9)
                .cloned()
                .ok_or_else(|| anyhow!("secant velocity: no keyframe before Tc = {tc} s"))?;
            for (i, v) in vels.iter_mut().enumerate().take(map.bodies.len()) {
                let q = |p: &Pose| {
                    UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                        p.orientation[0],
                        p.orientation[1],
                        p.orientation[2],
                        p.orientation[3],
                    ))
                };
                let (lin, ang) = mapping::handoff::secant_velocity(
                    &[
                        (prev[i].position, q(&prev[i])),
                        (poses[i].position, q(&poses[i])),
                    ],
                    tc - t_prev,
                    1,
                )?;
                *v = Velocity {
                    linear: lin,
                    angular: ang,
                };
            }
        }
        rec.final_poses = poses.clone();
        if sc.mode == Mode::Fe || rec.tc_s.is_none() {
            return Ok(rec);
        }
        if fe_strengths {
            // Residual capacities at Tc; broken only where the load path is lost.
            let caps = crate::fe::capacity::member_capacities_against(
                &model,
                &result.built,
                &gravity_n,
                &push,
                Some(&gravity_caps),
            )
            .context("FE-derived connection strengths at Tc")?;
            start_input.body_strengths = strengths::body_strengths(&bodies, &caps);
        }
        // FE damage per body → per connected pair (BCB's Formula-Assistant connections).
        let damage = if fe_strengths {
            BTreeMap::new()
        } else {
            element_damage(&model, &result.built)
        };
        let body_damage: Vec<FeDamage> = bodies
            .iter()
            .map(|b| {
                b.element
                    .parse::<u32>()
                    .ok()
                    .and_then(|e| damage.get(&e).copied())
                    .unwrap_or(FeDamage::Intact)
            })
            .collect();
        let mut start_damage = BTreeMap::new();
        for a in 0..bodies.len() {
            for b in a + 1..bodies.len() {
                let d = body_damage[a].max(body_damage[b]);
                if d != FeDamage::Intact {
                    start_damage.insert((a, b), d);
                }
            }
        }
        if let Some(p) = perturbation {
            for (i, v) in vels.iter_mut().enumerate().take(map.bodies.len()) {
                for (d, x) in v.linear.iter_mut().enumerate() {
                    *x += p.velocity_mps * p.uniform(2, (3 * i + d) as u64);
                }
            }
        }
        start_input.start_poses = poses.iter().map(to_isometry).collect();
        start_input.start_velocities = vels;
        start_input.start_time_s = tc;
        start_input.start_damage = start_damage;
    }
    let t0 = Instant::now();
    progress.stage("physics", start_input.start_time_s, limit);
    let base_z = bodies
        .iter()
        .filter(|b| b.passive)
        .map(|b| b.pose0.position[2] + b.half_extents[2])
        .reduce(f64::max);
    let mut stage = RuinStage::build(
        &start_input,
        GroundSpec {
            top_z: base_z,
            ..GroundSpec::moving(rec.ground.clone())
        },
        &settings,
    )
    .context("building the ruin stage")?;
    let result = stage
        .run_with(&stop, &mut |f| {
            let c = f.counts;
            progress.physics(f.time_s, limit, (c.elastic, c.plastic, c.broken));
        })
        .context("running the ruin stage")?;
    progress.done();
    check_finite(&result, &bodies, sc)?;
    rec.ruin_wall = t0.elapsed();
    rec.ruin_in_bullet = result.wall.in_bullet;
    rec.final_poses = result.final_poses.clone();
    rec.ruin = Some(result);
    Ok(rec)
}

/// A ruin stage that blew up (a non-finite pose) is an error naming the first body, the
/// time and the settings that bear on it, instead of a NaN found later in the written
/// tables ("cannot build collapse.glb: keyframes.csv:26: column x: NaN").
fn check_finite(result: &RuinResult, bodies: &[Body], sc: &Scenario) -> Result<()> {
    let bad = |p: &Pose| {
        !(p.position.iter().all(|v| v.is_finite()) && p.orientation.iter().all(|v| v.is_finite()))
    };
    for f in &result.frames {
        if let Some(i) = f.poses.iter().position(bad) {
            anyhow::bail!(
                "{}: the ruin stage blew up: body {} has a non-finite pose at t = {:.4} s \
                 (physics.steps_per_second = {}, spring_correction = {}, spring_damping = {}; \
                 a higher substep rate or spring_limit = true may help)",
                sc.path.display(),
                bodies[i].name,
                f.time_s,
                sc.physics.steps_per_second,
                sc.physics.spring_correction,
                sc.physics.spring_damping
            );
        }
    }
    if let Some(i) = result.final_poses.iter().position(bad) {
        anyhow::bail!(
            "{}: the ruin stage blew up: body {} has a non-finite final pose",
            sc.path.display(),
            bodies[i].name
        );
    }
    Ok(())
}

/// FE damage of every beam-column element (model tag → flag) in a built domain.
fn element_damage(model: &Model, built: &crate::fe::build::BuiltDomain) -> BTreeMap<u32, FeDamage> {
    let mut out = BTreeMap::new();
    for e in &model.elements {
        if !matches!(e.kind, ElementKind::BeamColumn { .. }) {
            continue;
        }
        if let Some(&i) = built.element_index.get(&e.tag) {
            let d = built.domain.elements()[i].damage();
            let f = if d.ruptured {
                FeDamage::Ruptured
            } else if d.yielded {
                FeDamage::Yielded
            } else {
                FeDamage::Intact
            };
            out.insert(e.tag, f);
        }
    }
    out
}

/// Why the ruin stage stopped, as written in the summary.
pub fn ruin_stop_name(s: StopReason) -> &'static str {
    match s {
        StopReason::AtRest => "at_rest",
        StopReason::TimeLimit => "time_limit",
    }
}
