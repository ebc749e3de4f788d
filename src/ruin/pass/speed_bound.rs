//! Pass: the largest body speed (the speed bound of docs/ruin-numerics.md).

use super::BodyState;
use crate::bullet::Velocity;
use crate::ruin::world::RuinWorld;

/// After every substep, the largest centre speed |v| of any dynamic body so far (m/s),
/// with the body and the substep's end time: checked against the bound of
/// docs/ruin-numerics.md (v_Tc,max + √(2·g·H), H the model's height) by the summary.
pub(crate) struct SpeedBound {
    /// Largest centre speed of a dynamic body at the start, m/s.
    start_max_mps: f64,
    /// Largest centre speed so far, m/s, and its body and time, s.
    max: (f64, Option<(usize, f64)>),
}

impl SpeedBound {
    /// The pass from the bodies' velocities at the start (input order).
    pub(crate) fn new(w: &RuinWorld, start: &[Velocity]) -> Self {
        let start_max_mps = (0..start.len())
            .filter(|&i| w.bodies.props[i].is_some())
            .map(|i| {
                let l = start[i].linear;
                (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt()
            })
            .fold(0.0, f64::max);
        SpeedBound {
            start_max_mps,
            max: (start_max_mps, None),
        }
    }

    /// After the substep ending at `t` (s), at the state `after`.
    pub(crate) fn apply(&mut self, w: &RuinWorld, after: &BodyState, t: f64) {
        for (i, v) in after.vels.iter().enumerate() {
            if w.bodies.props[i].is_some() {
                let l = v.linear;
                let s = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
                if s > self.max.0 {
                    self.max = (s, Some((i, t)));
                }
            }
        }
    }

    /// Largest centre speed of a dynamic body at the start, m/s.
    pub(crate) fn start_max_mps(&self) -> f64 {
        self.start_max_mps
    }

    /// Largest centre speed so far, m/s, and its body and time, s.
    pub(crate) fn max(&self) -> (f64, Option<(usize, f64)>) {
        self.max
    }
}
