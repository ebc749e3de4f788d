//! Builds a ruin stage (docs/bcb.md §1, §6, §7.1, §11; docs/ruin-model.md): checks the
//! input and the settings, makes Bullet's world, then
//!
//! 1. **Ground** ([`ground`]): a large box, friction 1, top at the model's base
//!    ([`GroundSpec`]); kinematic when a ground motion is given, static otherwise. It is
//!    body 0 of the world.
//! 2. **Bodies** ([`bodies`]): every [`super::BodyGeom`] as a box at its start pose with its
//!    start velocity (linear and angular, world frame), in input order (world body i + 1).
//!    Active bodies are dynamic, with BCB's body settings ([`BodySettings`]: friction 1,
//!    restitution 0, damping 0.04 / 0.1, never deactivated, margin 0.04). Passive bodies
//!    (foundation blocks) are kinematic and ride on the ground.
//! 3. **Remaining ground motion**: not built but stepped — before every substep the ground
//!    (and the passive bodies) are placed by the record's absolute displacement at the
//!    substep's end (the pass `ground_motion`). With `start_time_s` = Tc this continues the
//!    FE stage's ground in position and velocity.
//! 4. **Connections** (BCB's steps 4 and 5, [`connections`]): the contacts of the
//!    undeformed bodies, BCB's connections with frames from the start poses (nothing fires
//!    at the start), then each connection's starting state (of the FE damage given per
//!    body pair): broken → no constraint enabled; plastic → spring on (its equilibrium is
//!    the start pose), generics off. The seven Bullet constraints of each connection are
//!    created in spec order with `addConstraint(c, disable_collisions)`.
//!
//! Then the passes (`super::pass`) with their starting state, the observers, and the
//! separations that hold from the start.

mod bodies;
pub(crate) mod connections;
mod ground;

use super::ground::GroundSpec;
use super::monitor::Monitor;
use super::observer::Observers;
use super::pass::{
    bullet_step::BulletStep, ductile_rows::DuctileRows, energy::EnergyLedger,
    gravity_warmup::GravityWarmup, ground_damping::GroundDamping, ground_motion::GroundMotion,
    lost_rows::LostRows, monitor::MonitorPass, separation::Separations, sleep::KinematicSleep,
    speed_bound::SpeedBound, two_way_axial::TwoWayAxial, BodyState, Passes,
};
use super::record::StageError;
use super::separation::Separation;
use super::settings::{StageInput, StageSettings};
use super::stage::{bad, Clock, RuinStage};
use super::world::{to_pose, RuinWorld};
use super::RuinError;
use crate::bullet::{Velocity, World};

/// Builds the stage (module docs). Errors name the body, group or setting at fault.
pub(crate) fn build(
    input: &StageInput,
    ground_spec: GroundSpec,
    settings: &StageSettings,
) -> Result<RuinStage, StageError> {
    check_input(input)?;
    let (h, substeps_per_frame) = check_rates(settings)?;
    if !input.start_time_s.is_finite() || input.start_time_s < 0.0 {
        return Err(bad(
            "start_time_s",
            format!("{} must be finite and >= 0", input.start_time_s),
        ));
    }
    ground::check(&ground_spec)?;
    let mut bullet = new_world(settings)?;
    let t0 = input.start_time_s;

    // 1. Ground.
    let extent = ground::Extent::of(input.bodies);
    let ground = ground::add(&mut bullet, &extent, ground_spec, &settings.body, t0)?;
    // 2. Bodies.
    let bodies = bodies::add(
        &mut bullet,
        input,
        ground.spec.friction,
        &settings.body,
        &extent,
    )?;
    // 4. + 5. Connections.
    let connections = connections::add(&mut bullet, input, &bodies.handles, settings, h)?;

    let monitor = Monitor::new(
        &connections.specs,
        &input.start_poses,
        &connections.start_states,
        settings.angle_rule,
    )?;
    let separation = Separation::new(
        connections
            .specs
            .iter()
            .map(|c| (c.a, c.b, c.disable_collisions)),
        &bodies.passive,
        settings.touch.pairs,
        settings.touch.ground_under_connected_bases,
    );
    for i in separation.ground_exempt() {
        bullet.set_collision_with(bodies.handles[i], ground.handle, false)?;
    }
    let world = RuinWorld {
        bullet,
        ground,
        bodies,
        connections,
    };
    let passes = passes(&world, input, settings, monitor, separation, h);
    let names: Vec<String> = input.bodies.iter().map(|b| b.name.clone()).collect();
    let body_trace = match &settings.traces.body {
        Some(t) => {
            Some(super::body_trace::BodyTrace::new(t, &names).map_err(|m| bad("--trace-body", m))?)
        }
        None => None,
    };
    let observers = Observers {
        axial: settings
            .traces
            .axial
            .as_ref()
            .map(|t| super::axial::AxialTrace::new(t, names, world.connections.specs.len())),
        body: body_trace,
    };
    let mut stage = RuinStage {
        world,
        passes,
        observers,
        settings: settings.clone(),
        clock: Clock {
            start_time_s: t0,
            substep_s: h,
            substeps_per_frame,
            substeps_done: 0,
        },
    };
    let (w, p) = (&mut stage.world, &mut stage.passes);
    let enabled = w.bullet.constraints_enabled()?;
    p.separation.apply(w, &enabled, p.two_way_axial.left())?;
    Ok(stage)
}

/// The passes with their starting state.
fn passes(
    w: &RuinWorld,
    input: &StageInput,
    settings: &StageSettings,
    monitor: Monitor,
    separation: Separation,
    h: f64,
) -> Passes {
    let specs = &w.connections.specs;
    let r = &settings.ruin;
    let undeformed = BodyState {
        poses: input.bodies.iter().map(|b| to_pose(&b.pose())).collect(),
        vels: vec![Velocity::default(); input.bodies.len()],
    };
    let b = &settings.body;
    Passes {
        gravity: GravityWarmup::new(settings.warmup_s, settings.world.gravity),
        ground_motion: GroundMotion::new(w, input.start_time_s),
        sleep: KinematicSleep::new(!b.disable_deactivation),
        bullet_step: BulletStep::default(),
        lost_rows: LostRows::new(r.axial_rows),
        ductile_rows: DuctileRows::new(
            specs.iter().any(|c| c.ductile),
            settings.plastic.hinge_keeps_rotation,
            settings.plastic.hinge_return_mapping,
        ),
        two_way_axial: TwoWayAxial::new(specs, r.axial_rows, r.linear_correction, h),
        separation: Separations::new(separation),
        ground_damping: GroundDamping::new(settings.ground_damping_per_s),
        energy: EnergyLedger::new(
            w,
            settings.world.gravity,
            (b.linear_damping, b.angular_damping),
            &undeformed,
            input.start_time_s,
        ),
        speed_bound: SpeedBound::new(w, &input.start_velocities),
        monitor: MonitorPass::new(
            monitor,
            settings.monitor_every_substep,
            settings.plastic.spring_rest_at_onset,
        ),
    }
}

fn check_len(what: &str, expected: usize, got: usize) -> Result<(), StageError> {
    if expected != got {
        return Err(StageError::Ruin(RuinError::LengthMismatch {
            what: what.into(),
            expected,
            got,
        }));
    }
    Ok(())
}

/// One entry per body in every per-body slice; every body usable, with a finite mass > 0
/// when it is active and a finite start velocity.
fn check_input(input: &StageInput) -> Result<(), StageError> {
    let n = input.bodies.len();
    check_len("body masses", n, input.masses_kg.len())?;
    check_len("start poses", n, input.start_poses.len())?;
    check_len("start velocities", n, input.start_velocities.len())?;
    for (i, b) in input.bodies.iter().enumerate() {
        b.validate(i)?;
        let m = input.masses_kg[i];
        let usable = m.is_finite() && m > 0.0;
        if !b.passive && !usable {
            return Err(StageError::Ruin(RuinError::BadBody {
                index: i,
                name: b.name.clone(),
                message: format!("mass {m} kg must be finite and > 0"),
            }));
        }
        let v = &input.start_velocities[i];
        if v.linear.iter().chain(&v.angular).any(|x| !x.is_finite()) {
            return Err(StageError::Ruin(RuinError::BadBody {
                index: i,
                name: b.name.clone(),
                message: "start velocity is not finite".into(),
            }));
        }
    }
    Ok(())
}

/// The stepping rates and the warm-up: returns the substep h (s) and the substeps per
/// frame, a whole number.
fn check_rates(settings: &StageSettings) -> Result<(f64, u64), StageError> {
    let r = &settings.ruin;
    let positive = |v: f64| v.is_finite() && v > 0.0;
    if [r.steps_per_second, r.frame_rate, r.time_scale]
        .iter()
        .any(|v| !positive(*v))
    {
        return Err(bad(
            "ruin settings",
            "steps_per_second, frame_rate and time_scale must be finite and > 0".into(),
        ));
    }
    let h = r.substep();
    let frame_sim = r.time_scale / r.frame_rate;
    let spf = (frame_sim / h).round();
    if spf < 1.0 || (frame_sim / h - spf).abs() > 1e-9 * spf {
        return Err(bad(
            "steps_per_second",
            format!(
                "{} substeps/s is not a whole multiple of the frame rate {} frames/s at \
                 time scale {}: a keyframe is written every {} s of simulated time, and \
                 the world is stepped a whole number of substeps between two keyframes, \
                 so that every keyframe is a state Bullet computed; give a multiple of {} \
                 substeps/s, e.g. {}",
                r.steps_per_second,
                r.frame_rate,
                r.time_scale,
                frame_sim,
                r.frame_rate / r.time_scale,
                ((r.steps_per_second * frame_sim).ceil().max(1.0) / frame_sim).round()
            ),
        ));
    }
    if !(settings.warmup_s.is_finite() && settings.warmup_s >= 0.0) {
        return Err(bad(
            "warmup_s",
            format!("{} must be finite and >= 0", settings.warmup_s),
        ));
    }
    Ok((h, spf as u64))
}

/// Bullet's world with the stage's solver settings (the iteration count of
/// `ruin.solver_iterations`, no gravity while it warms up, the solver threads, the joint
/// rows' warm start, solve and the sweep).
fn new_world(settings: &StageSettings) -> Result<World, StageError> {
    let mut ws = settings.world.clone();
    ws.solver.num_iterations = settings.ruin.solver_iterations;
    if settings.warmup_s > 0.0 {
        ws.gravity = [0.0; 3];
    }
    let mut world = World::new(&ws)?;
    world.set_solver_threads(settings.speed.solver_threads.max(1))?;
    if !(settings.joints.warmstart.is_finite() && (0.0..=1.0).contains(&settings.joints.warmstart))
    {
        return Err(bad(
            "joint_warmstart",
            format!("{} must be in [0, 1]", settings.joints.warmstart),
        ));
    }
    if settings.joints.iterations == Some(0) {
        return Err(bad("joint_iterations", "must be >= 1".into()));
    }
    world.set_joint_warmstart(settings.joints.warmstart)?;
    // ε is checked by the wrapper (and by the scenario, with its file and line).
    world.set_joint_solve(settings.joints.solve, settings.joints.solve_regularisation)?;
    world.set_sweep(settings.speed.sweep)?;
    Ok(world)
}
