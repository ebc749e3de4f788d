//! Pass: mass-proportional damping relative to the moving ground
//! ([`crate::ruin::stage::StageSettings::ground_damping_per_s`]).

use crate::bullet::Velocity;
use crate::ruin::record::StageError;
use crate::ruin::world::RuinWorld;

/// After every substep, v ← v_g + (v − v_g)·exp(−a₀·h) for every active body's linear
/// velocity v (v_g the ground's velocity in the substep, m/s; a₀ in 1/s): the a₀·M term of
/// the FE's Rayleigh damping C = a₀·M + a₁·K (uniform excitation: the FE damps velocities
/// relative to the ground; Chopra, *Dynamics of Structures*, §11.4), a dashpot from each
/// body to the ground. With a₀ = 0 (BCB) the pass does nothing.
pub(crate) struct GroundDamping {
    /// a₀, 1/s.
    per_s: f64,
}

impl GroundDamping {
    /// The pass with a₀ = `per_s`, 1/s.
    pub(crate) fn new(per_s: f64) -> Self {
        GroundDamping { per_s }
    }

    /// After the substep `h` (s) in which the ground moved at `vg`, m/s.
    pub(crate) fn apply(&self, w: &mut RuinWorld, vg: [f64; 3], h: f64) -> Result<(), StageError> {
        let a0 = self.per_s;
        if a0 <= 0.0 {
            return Ok(());
        }
        let f = (-a0 * h).exp();
        let vels = w.body_velocities()?;
        for (i, v) in vels.iter().enumerate() {
            // A body whose velocity is no longer finite has blown up: it is left as it is,
            // so the run ends with the error naming it, the time and the settings
            // (`pipeline::check_finite`) rather than Bullet's refusal of a NaN here.
            let finite = v.linear.iter().chain(&v.angular).all(|x| x.is_finite());
            if w.bodies.props[i].is_none() || !finite {
                continue;
            }
            let linear = [0, 1, 2].map(|k| vg[k] + (v.linear[k] - vg[k]) * f);
            w.bullet.set_velocity(
                w.bodies.handles[i],
                Velocity {
                    linear,
                    angular: v.angular,
                },
            )?;
        }
        Ok(())
    }
}
