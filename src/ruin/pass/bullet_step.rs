//! Pass: Bullet's step.

use crate::bullet::World;
use crate::ruin::record::StageError;
use std::time::{Duration, Instant};

/// One substep h of Bullet's world ([`World::step`]: velocity damping, gravity, the
/// sequential-impulse solve of contacts and constraint rows — a constraint whose impulse
/// reaches its breaking threshold is disabled —, integration; `crate::ruin::energy`
/// module docs), with the wall time spent inside it
/// ([`crate::ruin::record::WallTime::in_bullet`]).
#[derive(Default)]
pub(crate) struct BulletStep {
    /// Wall time inside `World::step` so far.
    in_bullet: Duration,
}

impl BulletStep {
    /// Steps `world` by `h` s.
    pub(crate) fn apply(&mut self, world: &mut World, h: f64) -> Result<(), StageError> {
        let t = Instant::now();
        world.step(h, 1)?;
        self.in_bullet += t.elapsed();
        Ok(())
    }

    /// Wall time inside Bullet so far.
    pub(crate) fn in_bullet(&self) -> Duration {
        self.in_bullet
    }
}
