//! The ruin stage of a scenario: its settings resolved once from the scenario's
//! `[physics]` table and its loaded inputs ([`RuinStageSettings`]), then the stage built on
//! the moving ground and run until rest or the time limit ([`ruin_stage`]). Nothing here
//! reads the scenario after [`RuinStageSettings::of`].

use super::error::Result;
use super::{scenario, time_limit, Inputs, PipelineError, Progress, Scenario};
use crate::body::Body;
use crate::bullet::Pose;
use crate::ruin::ground::GroundSpec;
use crate::ruin::stage::{RuinResult, RuinStage, StageInput, StageSettings, StopRule};
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// What the ruin stage takes of a scenario, resolved for its inputs.
#[derive(Debug, Clone)]
pub struct RuinStageSettings {
    /// The stage's settings: the scenario's `[physics]` values ([`stage_settings`]) with
    /// the ground damping of the inputs ([`Inputs::ground_damping_per_s`]).
    pub stage: StageSettings,
    /// When the stage ends: the time limit ([`time_limit`]) and, with `stop_at_rest`, the
    /// at-rest test.
    pub stop: StopRule,
    /// The scenario file, named when the stage blows up.
    pub scenario: PathBuf,
}

impl RuinStageSettings {
    /// The settings of scenario `sc` on its loaded `inputs`.
    pub fn of(sc: &Scenario, inputs: &Inputs) -> Self {
        RuinStageSettings {
            stage: StageSettings {
                ground_damping_per_s: inputs.ground_damping_per_s,
                ..stage_settings(sc)
            },
            stop: StopRule {
                max_time_s: time_limit(sc, &inputs.motion),
                rest: sc.physics.stop_at_rest.then_some(sc.physics.rest),
            },
            scenario: sc.path.clone(),
        }
    }
}

/// The ruin stage's settings of a scenario: its resolved `[physics]` values
/// ([`scenario::PhysicsTable::resolve`]) mapped onto the stage's settings, field by field
/// (the ground damping, which needs the model, is set by [`RuinStageSettings::of`]).
pub fn stage_settings(sc: &Scenario) -> StageSettings {
    let mut s = StageSettings::bcb();
    let p = &sc.physics;
    s.ruin.steps_per_second = p.steps_per_second;
    s.ruin.solver_iterations = p.solver_iterations;
    s.body.friction = p.friction;
    s.body.restitution = p.restitution;
    s.body.linear_damping = p.linear_damping;
    s.body.angular_damping = p.angular_damping;
    s.ruin.spring_correction = p.spring_correction;
    s.ruin.linear_correction = p.linear_correction;
    s.ruin.bending_correction = p.bending_correction;
    s.ruin.spring_damping = p.spring_damping;
    s.ruin.spring_limit_if_needed = p.spring_limit;
    s.ruin.angular_spring = p.angular_spring;
    s.world.solver.split_impulse = p.split_impulse;
    s.world.solver.split_impulse_penetration_threshold = p.split_impulse_threshold_m;
    s.world.solver.erp2 = (p.contact_erp * p.erp_scale()).min(1.0);
    s.world.solver.erp = (p.joint_erp * p.erp_scale()).min(1.0);
    s.body.margin = p.margin_m;
    s.body.margin_max_share = p.margin_max_share;
    s.plastic.spring_rest_at_onset = p.spring_rest_at_plastic_onset;
    s.plastic.hinge_keeps_rotation = p.hinge_keeps_rotation;
    s.plastic.hinge_return_mapping = p.hinge_return_mapping;
    s.plastic.spring_cap_per_body = p.spring_cap_per_body;
    s.plastic.spring_cap_steps_per_second = p.spring_cap_steps_per_second;
    s.monitor_every_substep = p.monitor_every_substep;
    s.touch.pairs = p.connected_pairs_touch;
    s.touch.ground_under_connected_bases = p.ground_under_connected_bases;
    s.ruin.search.search_distance = p.search_distance_m;
    s.joints.rows = match p.joint_rows {
        scenario::JointRowsSpec::Locked => crate::ruin::stage::JointRows::Locked,
        scenario::JointRowsSpec::Member => crate::ruin::stage::JointRows::Member {
            modulus_pa: p.joint_modulus_pa,
            damping_ratio: p.joint_damping_ratio,
        },
    };
    s.body.disable_deactivation = !p.sleeping;
    s.joints.warmstart = p.joint_warmstart;
    s.joints.iterations = p.joint_iterations;
    s.joints.solve = match p.joint_solve {
        scenario::JointSolveSpec::Pgs => crate::bullet::JointSolve::Pgs,
        scenario::JointSolveSpec::Direct => crate::bullet::JointSolve::Direct,
    };
    s.joints.solve_regularisation = p.joint_solve_regularisation;
    s.ruin.axial_rows = p.axial_rows;
    s.ruin.hinge_end = p.hinge_end;
    s.ruin.search.joints = p.joints;
    s.speed.sweep = p.sweep.sweep();
    if let Some(n) = sc.threads {
        s.speed.solver_threads = n;
    }
    s.traces = sc.traces.clone();
    s
}

/// The ruin stage: the Bullet world of `input` (start poses, velocities, connection
/// states) on the moving ground, stepped until rest or the time limit. A blown-up stage
/// (a non-finite pose) is an error naming the body.
pub fn ruin_stage(
    settings: &RuinStageSettings,
    inputs: &Inputs,
    input: &StageInput,
    progress: &dyn Progress,
) -> Result<(RuinResult, Duration)> {
    let limit = settings.stop.max_time_s;
    let t0 = Instant::now();
    progress.stage("ruin", input.start_time_s, limit);
    let mut stage = build_stage(settings, inputs, input, &|_| ())?;
    let result = stage
        .run_with(&settings.stop, &mut |f| {
            let c = f.counts;
            progress.ruin(f.time_s, limit, (c.elastic, c.plastic, c.broken));
        })
        .map_err(|error| PipelineError::Ruin {
            stage: "running the ruin stage",
            error: Box::new(error),
        })?;
    progress.done();
    for (path, text) in [stage.axial_trace_report(), stage.body_trace_report()]
        .into_iter()
        .flatten()
    {
        crate::output::write_atomic(&path, text.as_bytes())?;
    }
    check_finite(&result, &inputs.bodies, settings)?;
    Ok((result, t0.elapsed()))
}

/// The ruin stage of `input` on the moving ground of `inputs` (its top at the foundation
/// blocks' tops) with `settings`, `adjust` applied last to a copy of them.
pub(crate) fn build_stage(
    settings: &RuinStageSettings,
    inputs: &Inputs,
    input: &StageInput,
    adjust: &dyn Fn(&mut StageSettings),
) -> Result<RuinStage> {
    let base_z = inputs
        .bodies
        .iter()
        .filter(|b| b.passive)
        .map(|b| b.pose0.position[2] + b.half_extents[2])
        .reduce(f64::max);
    let mut stage = settings.stage.clone();
    adjust(&mut stage);
    RuinStage::build(
        input,
        GroundSpec {
            top_z: base_z,
            ..GroundSpec::moving(inputs.ground.clone())
        },
        &stage,
    )
    .map_err(|error| PipelineError::Ruin {
        stage: "building the ruin stage",
        error: Box::new(error),
    })
}

/// A ruin stage that blew up (a non-finite pose) is an error naming the first body, the
/// time and the settings that bear on it, instead of a NaN found later in the written
/// tables ("cannot build collapse.glb: keyframes.csv:26: column x: NaN").
fn check_finite(result: &RuinResult, bodies: &[Body], settings: &RuinStageSettings) -> Result<()> {
    let s = &settings.stage.ruin;
    let bad = |p: &Pose| {
        !(p.position.iter().all(|v| v.is_finite()) && p.orientation.iter().all(|v| v.is_finite()))
    };
    for f in &result.frames {
        if let Some(i) = f.poses.iter().position(bad) {
            return Err(PipelineError::BlewUp {
                scenario: settings.scenario.clone(),
                message: format!(
                    "body {} has a non-finite pose at t = {:.4} s \
                     (physics.steps_per_second = {}, physics.experimental.spring_correction = {}, \
                     spring_damping = {}; a higher substep rate or spring_limit = true \
                     may help)",
                    bodies[i].id,
                    f.time_s,
                    s.steps_per_second,
                    s.spring_correction,
                    s.spring_damping
                ),
            });
        }
    }
    if let Some(i) = result.final_poses.iter().position(bad) {
        return Err(PipelineError::BlewUp {
            scenario: settings.scenario.clone(),
            message: format!("body {} has a non-finite final pose", bodies[i].id),
        });
    }
    Ok(())
}
