//! The ruin stage in Bullet: a world ([`super::world`]: the ground box, the members'
//! boxes, the connections' constraints) built by [`RuinStage::build`] (`super::build`:
//! ground, bodies, connections), then stepped by an ordered list of substep passes
//! (`super::pass`), each in its own file, in the one function [`RuinStage::substep`],
//! with the monitor and the at-rest test once per frame ([`RuinStage::run`]).
//!
//! Run: substeps of h = time_scale / steps_per_second; every 1/frame_rate s the monitor
//! ([`super::monitor::Monitor::check`]) reads the poses and Bullet's enabled flags and its
//! actions are applied before the next substep; each frame is recorded ([`Frame`]). The
//! run ends at [`StopRule::max_time_s`] or when the debris is at rest
//! ([`super::rest::RestTest`]).
//!
//! **Bullet's locked rows** (measured in `tests/it/ruin/stage_statics.rs`): a
//! `btGeneric6DofConstraint` axis with lo = hi only produces a solver row while its error
//! is strictly outside the limit; a joint that starts exactly in place (frames from the
//! start poses) carries nothing in its first substep, and under load the row now and then
//! drops out for a substep, after which it needs about twice the static impulse. So a
//! CT 22 generic breaks between 1/2 and 1 times the force or moment its threshold stands
//! for (BCB runs the same Bullet code; its empirical corrections 2.2/1.5 include this).
//! A load switched on at once (no warm-up) is the worst case. Static joint forces, once
//! settled, equal the closed-form ones to 0.25 % (column test).
//!
//! **Wall time**: [`RuinResult::wall`] splits the run's wall time into the time inside
//! `World::step` and the rest (monitor, pose reads, ground updates). Measured (debug
//! profile): 98–99 % inside Bullet for a 5-body portal frame under ground motion, 99.7 %
//! for 30 debris boxes.
//!
//! **Rigid-only mode** (BCB alone): [`StageInput::rigid_only`] — undeformed start poses,
//! zero velocities, all connections elastic, start at t = 0 under the whole record.

pub use super::record::{
    ConnectionOutcome, Frame, LedgerSummary, RuinResult, RuinStop, StageError, WallTime,
};
pub use super::settings::{
    member_row_erp_cfm, AxialTraceSettings, BodySettings, BodyTraceSettings, JointRows,
    JointSettings, PlasticSettings, SpeedSettings, StageInput, StageSettings, StopRule,
    TouchSettings, TraceSettings, MEMBER_ROW_MAX_CFM,
};
pub use super::world::{to_isometry, to_pose};

use super::connection::{ConnectionSpec, ConnectionState};
use super::energy::EnergyFrame;
use super::ground::GroundSpec;
use super::monitor::{Monitor, StateChange};
use super::observer::Observers;
use super::pass::rest::{last_frame_mean_speeds, motion_measures, RestCheck};
use super::pass::{BodyState, Passes};
use super::rest::RestSpeed;
use super::world::RuinWorld;
use super::RuinError;
use crate::bullet::{BodyHandle, ConstraintHandle, Pose, Velocity, World};
use std::time::Instant;

/// A built ruin stage: the world, the passes that step it, the observers and the clock.
pub struct RuinStage {
    pub(super) world: RuinWorld,
    pub(super) passes: Passes,
    pub(super) observers: Observers,
    pub(super) settings: StageSettings,
    pub(super) clock: Clock,
}

/// Where a stage is in time.
pub(super) struct Clock {
    /// Start time, s.
    pub(super) start_time_s: f64,
    /// The substep h, s.
    pub(super) substep_s: f64,
    /// Substeps per monitor frame.
    pub(super) substeps_per_frame: u64,
    /// Substeps taken.
    pub(super) substeps_done: u64,
}

impl Clock {
    /// Absolute time after `done` substeps, s.
    fn after(&self, done: u64) -> f64 {
        self.start_time_s + done as f64 * self.substep_s
    }
}

pub(super) fn bad(item: &str, message: String) -> StageError {
    StageError::Ruin(RuinError::BadSetting {
        item: item.into(),
        message,
    })
}

impl RuinStage {
    /// Builds the Bullet world of a ruin stage (`super::build`). Errors name the body,
    /// group or setting at fault.
    pub fn build(
        input: &StageInput,
        ground: GroundSpec,
        settings: &StageSettings,
    ) -> Result<RuinStage, StageError> {
        super::build::build(input, ground, settings)
    }

    /// The Bullet world (read access, e.g. for contacts).
    pub fn world(&self) -> &World {
        &self.world.bullet
    }

    /// The ground's handle.
    pub fn ground(&self) -> BodyHandle {
        self.world.ground.handle
    }

    /// The ground's pose with zero displacement.
    pub fn ground_rest_pose(&self) -> Pose {
        self.world.ground.rest
    }

    /// The ground box's half extents, m.
    pub fn ground_half_extents(&self) -> [f64; 3] {
        self.world.ground.half_extents
    }

    /// The settings the stage was built with.
    pub fn settings(&self) -> &StageSettings {
        &self.settings
    }

    /// The world handle of input body `i`.
    pub fn body(&self, i: usize) -> BodyHandle {
        self.world.bodies.handles[i]
    }

    /// The connections (specs as created, with their starting `enabled` flags).
    pub fn connections(&self) -> &[ConnectionSpec] {
        &self.world.connections.specs
    }

    /// The Bullet handles of connection `i`'s constraints, in spec order.
    pub fn constraint_handles(&self, i: usize) -> &[ConstraintHandle] {
        &self.world.connections.handles[i]
    }

    /// The monitor.
    pub fn monitor(&self) -> &Monitor {
        self.passes.monitor.monitor()
    }

    /// Current absolute time, s.
    pub fn time_s(&self) -> f64 {
        self.clock.after(self.clock.substeps_done)
    }

    /// The substep h, s.
    pub fn substep_s(&self) -> f64 {
        self.clock.substep_s
    }

    /// Substeps per monitor frame.
    pub fn substeps_per_frame(&self) -> u64 {
        self.clock.substeps_per_frame
    }

    /// Runs `count` substeps ([`Self::substep`]; the monitor only when it checks after
    /// every substep: [`RuinStage::run`] calls this once per frame and then the monitor).
    pub fn substeps(&mut self, count: u64) -> Result<(), StageError> {
        let mut before = BodyState {
            poses: self.world.body_poses()?,
            vels: self.world.body_velocities()?,
        };
        self.passes.energy.open(&self.world, &before);
        for _ in 0..count {
            before = self.substep(&before)?;
        }
        Ok(())
    }

    /// One substep h from the bodies' state `before`: every pass in its order, each
    /// documented in its file under `super::pass`. Returns the state after it.
    fn substep(&mut self, before: &BodyState) -> Result<BodyState, StageError> {
        let RuinStage {
            world: w,
            passes: p,
            observers: obs,
            clock,
            ..
        } = self;
        let h = clock.substep_s;
        let done = clock.substeps_done;
        let (t_cur, t_next) = (clock.after(done), clock.after(done + 1));
        // 1. Gravity warm-up: g·s(τ) over the first warmup_s (off by default).
        let g = p.gravity.apply(&mut w.bullet, done, h)?;
        // 2. The ground and the foundations to their place at t_next; v_g their velocity.
        let vg = p.ground_motion.apply(w, t_cur, t_next, h)?;
        // 3. Once the motion has ended, the ground and the foundations sleep (sleeping on).
        p.sleep.apply(w, t_cur, h)?;
        let traced = obs.before_step(w, t_next)?;
        // 4. Bullet's step: contacts, constraint rows, breaking thresholds, integration.
        p.bullet_step.apply(&mut w.bullet, h)?;
        clock.substeps_done += 1;
        let enabled = w.bullet.constraints_enabled()?;
        let monitor = p.monitor.monitor();
        // 5. Connection rule: the first row each elastic connection lost (the record).
        p.lost_rows
            .apply(&mut w.connections, monitor, &enabled, t_next);
        // 6. Connection rule: ductile bending rows that reached their capacity yield.
        p.ductile_rows.apply(w, monitor, &enabled)?;
        // 7. Connection rule: two-way axial rows break in the sense they pushed.
        let breaks = p.two_way_axial.apply(w, monitor, &enabled, t_next)?;
        obs.axial_breaks(t_next, &breaks);
        // 8. Pairs that nothing holds any more touch again.
        if p.separation.pending() {
            let now = w.bullet.constraints_enabled()?;
            p.separation.apply(w, &now, p.two_way_axial.left())?;
        }
        // 9. Damping relative to the ground, exp(−a₀·h) (off by default).
        p.ground_damping.apply(w, vg, h)?;
        let after = BodyState {
            vels: w.body_velocities()?,
            poses: w.body_poses()?,
        };
        // 10. The energy ledger: ground work, damping loss, the solver's injection.
        let added = p.energy.apply(w, before, &after, h, g, vg, t_next);
        // 11. The largest body speed.
        p.speed_bound.apply(w, &after, t_next);
        obs.after_substep(w, t_next, &after, traced, &enabled, added)?;
        // 12. The connection monitor, when it checks after every substep (else per frame).
        if p.monitor.every_substep() {
            let changes = check_connections(w, p, &after.poses)?;
            p.monitor.hold(changes, t_next);
        }
        Ok(after)
    }

    /// The debug trace of one body (`super::body_trace`, on only with
    /// [`super::settings::TraceSettings::body`]): its file and text, for the caller to write.
    pub fn body_trace_report(&self) -> Option<(std::path::PathBuf, String)> {
        self.observers.body_report()
    }

    /// The debug trace of the axial rows (`super::axial`, on only with
    /// [`super::settings::TraceSettings::axial`]): its file and text, for the caller to write.
    pub fn axial_trace_report(&self) -> Option<(std::path::PathBuf, String)> {
        let pairs: Vec<(usize, usize)> = self.connections().iter().map(|c| (c.a, c.b)).collect();
        self.observers.axial_report(&pairs)
    }

    /// The energy ledger now ([`super::energy`]).
    pub fn energy(&self) -> Result<EnergyFrame, StageError> {
        self.passes.energy.frame(&self.world)
    }

    /// The poses of the input bodies, input order.
    pub fn body_poses(&self) -> Result<Vec<Pose>, StageError> {
        self.world.body_poses()
    }

    /// The velocities of the input bodies, input order.
    pub fn body_velocities(&self) -> Result<Vec<Velocity>, StageError> {
        self.world.body_velocities()
    }

    /// One monitor frame: check the connections at the current poses, apply the actions.
    /// Returns the state changes (connection, from, to).
    pub fn monitor_frame(&mut self) -> Result<Vec<StateChange>, StageError> {
        let poses = self.world.body_poses()?;
        check_connections(&mut self.world, &mut self.passes, &poses)
    }

    /// Kinetic energy of the dynamic bodies relative to the ground (J), the largest point
    /// speed (m/s) and each body's point speed (passive: 0) — see [`super::rest`].
    pub fn motion_measures(&self) -> Result<(f64, f64, Vec<f64>), StageError> {
        motion_measures(&self.world, self.time_s())
    }

    /// The deepest penetration between any two bodies after the last substep, m (≥ 0).
    pub fn deepest_penetration(&self) -> Result<f64, StageError> {
        self.world.deepest_penetration()
    }

    /// Runs frame by frame until `stop` (module docs) and returns the record.
    pub fn run(&mut self, stop: &StopRule) -> Result<RuinResult, StageError> {
        self.run_with(stop, &mut |_| {})
    }

    /// As [`RuinStage::run`], calling `on_frame` after every recorded frame (progress).
    /// Each frame: the substeps ([`Self::substeps`]), the connection monitor (pass 12,
    /// once per frame unless it checks after every substep), the frame's record, the
    /// penetration, and the at-rest test (`super::pass::rest`).
    pub fn run_with(
        &mut self,
        stop: &StopRule,
        on_frame: &mut dyn FnMut(&Frame),
    ) -> Result<RuinResult, StageError> {
        let start = Instant::now();
        let bullet_before = self.passes.bullet_step.in_bullet();
        if !self.world.bullet.is_stock() {
            self.world.bullet.reset_island_stats()?;
        }
        if !stop.max_time_s.is_finite() {
            return Err(bad(
                "max_time_s",
                format!("{} must be finite", stop.max_time_s),
            ));
        }
        let g = {
            let g = self.settings.world.gravity;
            (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt()
        };
        let rest = stop.rest;
        let frame_dt = self.clock.substeps_per_frame as f64 * self.clock.substep_s;
        let mut rest_check = rest.map(|r| RestCheck::new(&self.world, r, g, frame_dt));

        let conns = &self.world.connections;
        let mut outcomes: Vec<ConnectionOutcome> = (0..conns.specs.len())
            .map(|i| ConnectionOutcome {
                a: conns.specs[i].a,
                b: conns.specs[i].b,
                start_state: conns.start_states[i],
                state: self.passes.monitor.monitor().state(i),
                broke_at_s: None,
                plastic_at_s: None,
                first_row_lost: None,
            })
            .collect();
        let mut frames = vec![self.frame()?];
        let mut reason = RuinStop::TimeLimit;
        let mut first_pen: Option<f64> = None;
        let mut max_pen = 0.0_f64;
        while self.time_s() < stop.max_time_s - 1e-9 * frame_dt {
            self.substeps(self.clock.substeps_per_frame)?;
            let t = self.time_s();
            // 12. The connection monitor, once per frame (BCB).
            if !self.passes.monitor.every_substep() {
                let changes = self.monitor_frame()?;
                self.passes.monitor.hold(changes, t);
            }
            for (ch, t) in self.passes.monitor.take_changes() {
                let o = &mut outcomes[ch.connection];
                if ch.to == ConnectionState::Broken && o.broke_at_s.is_none() {
                    o.broke_at_s = Some(t);
                }
                if ch.to == ConnectionState::Plastic && o.plastic_at_s.is_none() {
                    o.plastic_at_s = Some(t);
                }
            }
            frames.push(self.frame()?);
            on_frame(frames.last().expect("just pushed"));
            let pen = self.world.deepest_penetration()?;
            first_pen.get_or_insert(pen);
            max_pen = max_pen.max(pen);
            // The at-rest test.
            if let Some(rc) = rest_check.as_mut() {
                if rc.apply(&self.world, &frames, t)? {
                    reason = RuinStop::AtRest;
                    break;
                }
            }
        }
        let conns = &self.world.connections;
        for (i, o) in outcomes.iter_mut().enumerate() {
            o.state = self.passes.monitor.monitor().state(i);
            o.first_row_lost = conns.first_lost[i]
                .and_then(|(k, t)| conns.specs[i].constraints.get(k).map(|c| (c.role, t)));
        }
        let (_, _, instantaneous) = self.motion_measures()?;
        let speed_measure = rest.unwrap_or_default().speed;
        let speeds = match speed_measure {
            RestSpeed::FrameMean => last_frame_mean_speeds(&self.world, &frames),
            RestSpeed::Instantaneous => None,
        }
        .unwrap_or_else(|| instantaneous.clone());
        let vtol = rest.unwrap_or_default().max_speed_mps;
        let at_rest: Vec<bool> = speeds
            .iter()
            .zip(&self.world.bodies.passive)
            .map(|(s, p)| *p || *s < vtol)
            .collect();
        let wall = WallTime {
            in_bullet: self.passes.bullet_step.in_bullet() - bullet_before,
            total: start.elapsed(),
        };
        let (energy, speed) = (&self.passes.energy, &self.passes.speed_bound);
        let bullet = &self.world.bullet;
        Ok(RuinResult {
            frames,
            final_poses: self.world.body_poses()?,
            final_velocities: self.world.body_velocities()?,
            at_rest,
            connections: outcomes,
            first_frame_penetration_m: first_pen.unwrap_or(0.0),
            max_penetration_m: max_pen,
            stop: reason,
            end_time_s: self.time_s(),
            wall,
            ledger: LedgerSummary {
                initial_potential_j: energy.initial_potential_j(),
                model_height_m: self.world.bodies.model_height_m,
                gravity_mps2: g,
                start_max_speed_mps: speed.start_max_mps(),
                max_speed_mps: speed.max().0,
                max_speed_at: speed.max().1,
                final_point_speeds_mps: speeds,
                final_instantaneous_speeds_mps: instantaneous,
                rest_speed: speed_measure,
                injected_j: energy.injected_j(),
                max_injection: energy.max_injection(),
            },
            islands: if bullet.is_stock() {
                None
            } else {
                Some(bullet.island_stats()?)
            },
            sleeping_at_end: bullet.num_sleeping()?,
            joint_solve: bullet.joint_solve()?,
        })
    }

    /// The frame record now.
    fn frame(&self) -> Result<Frame, StageError> {
        Ok(Frame {
            time_s: self.time_s(),
            poses: self.world.body_poses()?,
            counts: self.passes.monitor.monitor().counts(),
            energy: self.energy()?,
        })
    }
}

/// The connection monitor (pass 12) at the bodies' `poses`, then the separations it
/// allows (pass 8) when it changed a state. Returns the state changes.
fn check_connections(
    w: &mut RuinWorld,
    p: &mut Passes,
    poses: &[Pose],
) -> Result<Vec<StateChange>, StageError> {
    let changes = p.monitor.apply(w, poses)?;
    if p.separation.pending() && !changes.is_empty() {
        let enabled = w.bullet.constraints_enabled()?;
        p.separation.apply(w, &enabled, p.two_way_axial.left())?;
    }
    Ok(changes)
}
