//! Pass: connected bodies start touching once nothing holds them
//! (`crate::ruin::separation`, docs/ruin-numerics.md §16).

use crate::ruin::axial::AxialLeft;
use crate::ruin::connection::GENERIC_COUNT;
use crate::ruin::record::StageError;
use crate::ruin::separation::{Other, Separation, Until};
use crate::ruin::world::RuinWorld;

/// Lets a pair of bodies that a connection held together touch again (Bullet's collision
/// exemption is lifted, [`crate::bullet::World::set_collision_with`]) once the
/// connections that justify the exemption no longer hold: every constraint disabled
/// ([`Until::Broken`]), every rigid (generic) row disabled ([`Until::Yielded`]), or for a
/// piece on a foundation block and the ground, its axial row no longer carrying
/// compression ([`Until::CompressionLost`]). Run at the build, after every substep's
/// connection rules while an exemption is left, and after every monitor check that
/// changed a state.
pub(crate) struct Separations {
    /// Which bodies may not touch yet, and when they may.
    separation: Separation,
}

impl Separations {
    /// The pass over `separation`'s exemptions.
    pub(crate) fn new(separation: Separation) -> Self {
        Separations { separation }
    }

    /// Some exemption is left.
    pub(crate) fn pending(&self) -> bool {
        self.separation.pending()
    }

    /// Lifts the exemptions whose connections no longer hold. `enabled`: every
    /// constraint's flag now; `axial_left`: per connection, the senses its two-way axial
    /// row still holds (constraint 0 is the axial row: BCB's compression row, or the
    /// two-way row, which may have broken in compression and carry tension only).
    pub(crate) fn apply(
        &mut self,
        w: &mut RuinWorld,
        enabled: &[bool],
        axial_left: &[AxialLeft],
    ) -> Result<(), StageError> {
        let conns = &w.connections;
        let lifted = self.separation.lift(|c, until| {
            let on = |k: usize| conns.is_on(enabled, c, k);
            match until {
                Until::Broken => (0..conns.handles[c].len()).any(on),
                Until::Yielded => (0..GENERIC_COUNT).any(on),
                Until::CompressionLost => on(0) && axial_left.get(c) != Some(&AxialLeft::Tension),
            }
        });
        for (i, other) in lifted {
            let o = match other {
                Other::Body(j) => w.bodies.handles[j],
                Other::Ground => w.ground.handle,
            };
            w.bullet.set_collision_with(w.bodies.handles[i], o, true)?;
        }
        Ok(())
    }
}
