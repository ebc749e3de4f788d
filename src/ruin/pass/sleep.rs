//! Pass: the ground and the foundations go to sleep once the ground motion has ended
//! ([`crate::ruin::stage::BodySettings::disable_deactivation`] false).

use crate::ruin::record::StageError;
use crate::ruin::world::{RuinWorld, ISLAND_SLEEPING};

/// With sleeping on, in the first substep that starts at t ≥ t_end + h (t_end the end of
/// the ground motion, so the ground's velocity from the last substep is 0) puts the ground
/// and the passive bodies to sleep (Bullet's `ISLAND_SLEEPING`): a moving kinematic body
/// keeps everything it touches awake, a resting one need not. Without sleeping (BCB) this
/// pass does nothing.
pub(crate) struct KinematicSleep {
    /// Sleeping is on.
    on: bool,
    /// The ground and the foundations sleep already.
    asleep: bool,
}

impl KinematicSleep {
    /// The pass; `on` when Bullet may deactivate bodies.
    pub(crate) fn new(on: bool) -> Self {
        KinematicSleep { on, asleep: false }
    }

    /// Before the substep starting at `t_cur` (substep `h`), s.
    pub(crate) fn apply(
        &mut self,
        w: &mut RuinWorld,
        t_cur: f64,
        h: f64,
    ) -> Result<(), StageError> {
        if !(self.on && !self.asleep && t_cur >= w.ground.spec.motion_end_s() + h) {
            return Ok(());
        }
        w.bullet
            .set_activation_state(w.ground.handle, ISLAND_SLEEPING)?;
        let b = &w.bodies;
        for i in 0..b.handles.len() {
            if b.passive[i] {
                w.bullet
                    .set_activation_state(b.handles[i], ISLAND_SLEEPING)?;
            }
        }
        self.asleep = true;
        Ok(())
    }
}
