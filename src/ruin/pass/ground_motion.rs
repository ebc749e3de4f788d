//! Pass: the moving ground (BCB step 3, docs/bcb.md §6 and §11.6; `crate::ruin::ground`).

use crate::ruin::record::StageError;
use crate::ruin::world::{shifted, to_pose, RuinWorld};

/// Before every substep [t, t + h] places the ground box at its rest pose + d(t + h), d
/// the record's absolute ground displacement, and every passive body (foundation block) at
/// its start pose + d(t + h) − d(t_start), as kinematic targets. Bullet's
/// `saveKinematicState` then gives them the secant velocity v_g = (d(t + h) − d(t))/h
/// during that substep's solve, so a body resting on the ground is carried by exactly the
/// record's displacement increment. Without a ground motion nothing moves (v_g = 0).
pub(crate) struct GroundMotion {
    /// Whether the ground has a motion history.
    moving: bool,
    /// d(t_start), m.
    d_start: [f64; 3],
}

impl GroundMotion {
    /// The pass for `world`'s ground from the start time `t_start`, s.
    pub(crate) fn new(world: &RuinWorld, t_start: f64) -> Self {
        GroundMotion {
            moving: world.ground.spec.history.is_some(),
            d_start: world.ground.spec.displacement_at(t_start),
        }
    }

    /// Moves the ground and the passive bodies for the substep from `t_cur` to `t_next`
    /// (`h` = t_next − t_cur, s); returns the ground's secant velocity v_g, m/s.
    pub(crate) fn apply(
        &self,
        w: &mut RuinWorld,
        t_cur: f64,
        t_next: f64,
        h: f64,
    ) -> Result<[f64; 3], StageError> {
        let mut vg = [0.0; 3];
        if !self.moving {
            return Ok(vg);
        }
        let spec = &w.ground.spec;
        let d = spec.displacement_at(t_next);
        let d_prev = spec.displacement_at(t_cur);
        vg = [
            (d[0] - d_prev[0]) / h,
            (d[1] - d_prev[1]) / h,
            (d[2] - d_prev[2]) / h,
        ];
        w.bullet
            .set_kinematic_target(w.ground.handle, shifted(&w.ground.rest, d), None)?;
        let d_start = self.d_start;
        let dd = [d[0] - d_start[0], d[1] - d_start[1], d[2] - d_start[2]];
        let b = &w.bodies;
        for i in 0..b.handles.len() {
            if b.passive[i] {
                let p = shifted(&to_pose(&b.start_poses[i]), dd);
                w.bullet.set_kinematic_target(b.handles[i], p, None)?;
            }
        }
        Ok(vg)
    }
}
