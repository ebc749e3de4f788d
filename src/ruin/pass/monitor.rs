//! Pass: the connection monitor (BCB's per-frame elastic → plastic → broken check,
//! `crate::ruin::monitor`).

use crate::bullet::Pose;
use crate::ruin::connection::ConstraintClass;
use crate::ruin::monitor::{Monitor, StateChange};
use crate::ruin::record::StageError;
use crate::ruin::world::{to_isometry, RuinWorld};

/// Once per frame (1/frame_rate s, BCB: 25 Hz), or after every substep
/// ([`crate::ruin::stage::StageSettings::monitor_every_substep`]), checks every connection
/// at the bodies' poses and Bullet's enabled flags ([`Monitor::check`]: its deformation
/// against BCB's tolerances, docs/bcb.md §7.3) and applies its actions before the next
/// substep: constraints enabled or disabled, and with
/// [`crate::ruin::stage::PlasticSettings::spring_rest_at_onset`] a plastic spring's
/// rest pose set to the present relative pose. The state changes are kept with their
/// times until the frame is recorded.
pub(crate) struct MonitorPass {
    /// The state machine.
    monitor: Monitor,
    /// Check after every substep instead of once per frame.
    every_substep: bool,
    /// Set a spring's rest pose when it is switched on.
    spring_rest_at_onset: bool,
    /// State changes not yet recorded, with their times, s.
    pending: Vec<(StateChange, f64)>,
}

impl MonitorPass {
    /// The pass over `monitor`.
    pub(crate) fn new(monitor: Monitor, every_substep: bool, spring_rest_at_onset: bool) -> Self {
        MonitorPass {
            monitor,
            every_substep,
            spring_rest_at_onset,
            pending: Vec::new(),
        }
    }

    /// The state machine.
    pub(crate) fn monitor(&self) -> &Monitor {
        &self.monitor
    }

    /// Whether it checks after every substep.
    pub(crate) fn every_substep(&self) -> bool {
        self.every_substep
    }

    /// Checks the connections at the bodies' `poses` (read after the last substep) and
    /// applies the actions. Returns the state changes (connection, from, to).
    pub(crate) fn apply(
        &mut self,
        w: &mut RuinWorld,
        poses: &[Pose],
    ) -> Result<Vec<StateChange>, StageError> {
        let poses: Vec<_> = poses.iter().map(to_isometry).collect();
        let enabled = w.bullet.constraints_enabled()?;
        let conns = &w.connections;
        let actions = self
            .monitor
            .check(&poses, |c, k| conns.is_on(&enabled, c, k))?;
        for a in actions {
            let h = conns.handles[a.connection][a.constraint];
            w.bullet.set_constraint_enabled(h, a.enable)?;
            let spring = conns.specs[a.connection].constraints[a.constraint].kind
                == ConstraintClass::Spring2;
            if a.enable && spring && self.spring_rest_at_onset {
                w.bullet.set_equilibrium_point(h)?;
            }
        }
        Ok(self.monitor.last_changes().to_vec())
    }

    /// Keeps `changes` found at time `t`, s, until the frame is recorded.
    pub(crate) fn hold(&mut self, changes: Vec<StateChange>, t: f64) {
        for ch in changes {
            self.pending.push((ch, t));
        }
    }

    /// The state changes since the last frame, with their times, s.
    pub(crate) fn take_changes(&mut self) -> Vec<(StateChange, f64)> {
        std::mem::take(&mut self.pending)
    }
}
