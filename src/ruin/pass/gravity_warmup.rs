//! Pass: gravity warm-up ([`crate::ruin::stage::StageSettings::warmup_s`]).

use crate::bullet::World;
use crate::ruin::record::StageError;

/// Grows gravity from 0 to its full value g over the warm-up time T after the start: in
/// the substep ending at t the world's gravity is g·s(τ) with the smoothstep
/// s(τ) = 3τ² − 2τ³, τ = min((t − t_start)/T, 1) (BCB's warm-up period: 20 frames = 0.8 s,
/// a Bezier ease ≈ smoothstep, docs/bcb.md §4). With T = 0 (the default) gravity is full
/// from the start and this pass does nothing.
pub(crate) struct GravityWarmup {
    /// The warm-up time T, s (0: off).
    warmup_s: f64,
    /// The full gravity g, m/s².
    full: [f64; 3],
}

impl GravityWarmup {
    /// Warm-up over `warmup_s` to the gravity `full`, m/s².
    pub(crate) fn new(warmup_s: f64, full: [f64; 3]) -> Self {
        GravityWarmup { warmup_s, full }
    }

    /// Sets the gravity of substep `done` + 1 (`done` substeps of `h` s taken) while in the
    /// warm-up; returns the gravity of that substep, m/s².
    pub(crate) fn apply(
        &self,
        world: &mut World,
        done: u64,
        h: f64,
    ) -> Result<[f64; 3], StageError> {
        let g_full = self.full;
        let mut g = g_full;
        if self.warmup_s > 0.0 && (done as f64) * h < self.warmup_s {
            let tau = ((done + 1) as f64 * h / self.warmup_s).min(1.0);
            let f = tau * tau * (3.0 - 2.0 * tau);
            g = [g_full[0] * f, g_full[1] * f, g_full[2] * f];
            world.set_gravity(g)?;
        }
        Ok(g)
    }
}
