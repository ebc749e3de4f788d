//! Frame pass: the at-rest test that ends a run (`crate::ruin::rest`,
//! docs/ruin-numerics.md §3, §17).

use crate::ruin::record::{Frame, StageError};
use crate::ruin::rest::{body_energy_speed, frame_mean_speed, RestSpeed, RestTest};
use crate::ruin::world::RuinWorld;

/// After every recorded frame, once the ground motion has ended: the debris is quiet when
/// its kinetic energy relative to the ground E_k < ε·M·g·L_ref and the largest point speed
/// is below v_tol (measured as [`RestSpeed`] says); at rest when it has been quiet for
/// [`RestTest::hold_s`] (a whole number of frames, at least one).
pub(crate) struct RestCheck {
    /// The test.
    test: RestTest,
    /// ε·M·g·L_ref, J.
    energy_bound_j: f64,
    /// Frames in a row the test must hold.
    hold_frames: u64,
    /// End of the ground motion, s.
    motion_end_s: f64,
    /// Quiet frames in a row so far.
    quiet: u64,
}

impl RestCheck {
    /// The check of `test` on `w` under gravity |g| = `g` (m/s²), with frames of
    /// `frame_dt` s.
    pub(crate) fn new(w: &RuinWorld, test: RestTest, g: f64, frame_dt: f64) -> Self {
        let l = test
            .reference_length_m
            .unwrap_or(w.bodies.model_height_m.max(1.0));
        RestCheck {
            test,
            energy_bound_j: test.energy_ratio * w.bodies.total_mass_kg * g * l,
            hold_frames: (test.hold_s / frame_dt - 1e-9).ceil().max(1.0) as u64,
            motion_end_s: w.ground.spec.motion_end_s(),
            quiet: 0,
        }
    }

    /// After the frame at `t` (s), the last of `frames`: whether the debris is at rest.
    pub(crate) fn apply(
        &mut self,
        w: &RuinWorld,
        frames: &[Frame],
        t: f64,
    ) -> Result<bool, StageError> {
        let (e, vmax, _) = motion_measures(w, t)?;
        let vmax = match self.test.speed {
            RestSpeed::Instantaneous => vmax,
            // Frame 0 is pushed before the loop, so there is a last frame.
            RestSpeed::FrameMean => {
                last_frame_mean_speeds(w, frames).map_or(0.0, |v| v.into_iter().fold(0.0, f64::max))
            }
        };
        if t >= self.motion_end_s - 1e-12
            && e < self.energy_bound_j
            && vmax < self.test.max_speed_mps
        {
            self.quiet += 1;
        } else {
            self.quiet = 0;
        }
        Ok(self.quiet >= self.hold_frames)
    }
}

/// Kinetic energy of the dynamic bodies relative to the ground (J), the largest point
/// speed (m/s) and each body's point speed (passive: 0) at time `t`, s, from their
/// velocities — see [`crate::ruin::rest`].
pub(crate) fn motion_measures(w: &RuinWorld, t: f64) -> Result<(f64, f64, Vec<f64>), StageError> {
    let poses = w.body_poses()?;
    let vels = w.body_velocities()?;
    let vg = w.ground.spec.velocity_at(t);
    let n = w.bodies.handles.len();
    let mut e = 0.0;
    let mut vmax: f64 = 0.0;
    let mut speeds = vec![0.0; n];
    for i in 0..n {
        if let Some(rb) = &w.bodies.rest[i] {
            let (ei, si) = body_energy_speed(
                rb,
                poses[i].orientation,
                vels[i].linear,
                vels[i].angular,
                vg,
            );
            e += ei;
            vmax = vmax.max(si);
            speeds[i] = si;
        }
    }
    Ok((e, vmax, speeds))
}

/// Each body's frame-mean point speed relative to the ground over the last of `frames`
/// (m/s; passive: 0) — [`frame_mean_speed`]; `None` before a frame has ended.
pub(crate) fn last_frame_mean_speeds(w: &RuinWorld, frames: &[Frame]) -> Option<Vec<f64>> {
    let [.., f0, f1] = frames else {
        return None;
    };
    let (t0, t1, p0, p1) = (f0.time_s, f1.time_s, &f0.poses, &f1.poses);
    let spec = &w.ground.spec;
    let (g0, g1) = (spec.displacement_at(t0), spec.displacement_at(t1));
    let shift = [g1[0] - g0[0], g1[1] - g0[1], g1[2] - g0[2]];
    Some(
        (0..w.bodies.handles.len())
            .map(|i| match &w.bodies.rest[i] {
                Some(rb) => frame_mean_speed(
                    rb,
                    (p0[i].position, p0[i].orientation),
                    (p1[i].position, p1[i].orientation),
                    shift,
                    t1 - t0,
                ),
                None => 0.0,
            })
            .collect(),
    )
}
