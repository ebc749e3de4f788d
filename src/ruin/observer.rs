//! Observers of the substeps: the debug traces (`super::axial`'s axial-row trace,
//! `--trace-axial`, and `super::body_trace`'s trace of one body,
//! `--trace-body`). They read the world and change nothing in it; both are off
//! unless their option is given ([`super::settings::TraceSettings`]).

use super::axial::{axial_offset, AxialTrace};
use super::body_trace::BodyTrace;
use super::pass::two_way_axial::AxialBreak;
use super::pass::BodyState;
use super::record::StageError;
use super::world::{to_isometry, RuinWorld};
use crate::bullet::{Pose, Velocity};
use nalgebra::Isometry3;

/// The installed traces.
pub(crate) struct Observers {
    /// The axial rows' trace.
    pub(crate) axial: Option<AxialTrace>,
    /// One body's trace.
    pub(crate) body: Option<BodyTrace>,
}

/// What the body trace saw before a traced substep: every constraint's flag and the
/// body's velocity.
pub(crate) struct BeforeStep {
    enabled: Vec<bool>,
    velocity: Velocity,
}

impl Observers {
    /// Before the substep ending at `t`, s: what the body trace needs of the state before
    /// it (`None` when it does not trace that substep).
    pub(crate) fn before_step(
        &self,
        w: &RuinWorld,
        t: f64,
    ) -> Result<Option<BeforeStep>, StageError> {
        Ok(match &self.body {
            Some(tr) if tr.wants(t) => Some(BeforeStep {
                enabled: w.bullet.constraints_enabled()?,
                velocity: w.bullet.velocity(w.bodies.handles[tr.body])?,
            }),
            _ => None,
        })
    }

    /// The two-way axial rows broken in the substep ending at `t`, s.
    pub(crate) fn axial_breaks(&mut self, t: f64, breaks: &[AxialBreak]) {
        if let Some(tr) = self.axial.as_mut() {
            for b in breaks {
                tr.note_break(t, b.connection, b.impulse, b.compression_ns, b.tension_ns);
            }
        }
    }

    /// After the substep ending at `t` (s) and the passes that follow it, at the state
    /// `after`. `before`: [`Self::before_step`]'s record; `enabled`: every constraint's
    /// flag right after Bullet's step (before the connection rules); `added`: the energy
    /// the substep added beyond the ground's work, J (the ledger's balance).
    pub(crate) fn after_substep(
        &mut self,
        w: &RuinWorld,
        t: f64,
        after: &BodyState,
        before: Option<BeforeStep>,
        enabled: &[bool],
        added: f64,
    ) -> Result<(), StageError> {
        if self.axial.is_some() {
            self.trace_axial(w, t, &after.poses, &after.vels)?;
        }
        if let Some(b) = before {
            self.trace_body(w, t, &b.enabled, enabled, b.velocity, added)?;
        }
        Ok(())
    }

    /// Feeds the axial rows' trace after one substep.
    fn trace_axial(
        &mut self,
        w: &RuinWorld,
        t: f64,
        poses: &[Pose],
        vels: &[Velocity],
    ) -> Result<(), StageError> {
        let enabled = w.bullet.constraints_enabled()?;
        let iso: Vec<Isometry3<f64>> = poses.iter().map(to_isometry).collect();
        let conns = &w.connections;
        let mut axial = Vec::with_capacity(conns.specs.len());
        let mut pairs = Vec::with_capacity(conns.specs.len());
        for (i, c) in conns.specs.iter().enumerate() {
            let hs = &conns.handles[i];
            let on = hs.iter().take(2).any(|h| enabled[h.index()]);
            let x = on.then(|| {
                let f = &c.constraints[0];
                axial_offset(&iso[c.a], &iso[c.b], &f.frame_a, &f.frame_b)
            });
            axial.push(x);
            pairs.push((c.a, c.b));
        }
        let v: Vec<Option<[f64; 3]>> = vels
            .iter()
            .zip(&w.bodies.passive)
            .map(|(v, p)| (!p).then_some(v.linear))
            .collect();
        if let Some(tr) = self.axial.as_mut() {
            tr.after_substep(t, &axial, &pairs, &v);
        }
        Ok(())
    }

    /// Feeds the trace of one body after the substep ending at `t` (`en0`, `en1`: every
    /// constraint's flag before and right after it, before the connection rules; `v0`:
    /// the body's velocity before it; `added`: the energy the substep added beyond the
    /// ground's work, J).
    fn trace_body(
        &mut self,
        w: &RuinWorld,
        t: f64,
        en0: &[bool],
        en1: &[bool],
        v0: Velocity,
        added: f64,
    ) -> Result<(), StageError> {
        let Some(tr) = self.body.as_ref() else {
            return Ok(());
        };
        let (world, handles) = (&w.bullet, &w.bodies.handles);
        let i = tr.body;
        let me = handles[i];
        let v1 = world.velocity(me)?;
        let p = world.pose(me)?;
        let mut lines = vec![format!(
            "t {t:.5} pos {:.4} {:.4} {:.4} v0 {:.3} {:.3} {:.3} v1 {:.3} {:.3} {:.3} w1 {:.2} {:.2} {:.2} added_j {added:.2}",
            p.position[0], p.position[1], p.position[2],
            v0.linear[0], v0.linear[1], v0.linear[2],
            v1.linear[0], v1.linear[1], v1.linear[2],
            v1.angular[0], v1.angular[1], v1.angular[2]
        )];
        for (ci, c) in w.connections.specs.iter().enumerate() {
            if c.a != i && c.b != i {
                continue;
            }
            let other = if c.a == i { c.b } else { c.a };
            if let Some(f) = c.constraints.first() {
                let pa = to_isometry(&world.pose(handles[c.a])?) * f.frame_a;
                let pb = to_isometry(&world.pose(handles[c.b])?) * f.frame_b;
                let d = pa.rotation.inverse() * (pb.translation.vector - pa.translation.vector);
                let r = (pa.rotation.inverse() * pb.rotation).to_rotation_matrix();
                let m = r.matrix();
                // XYZ Euler angles (R = Rx·Ry·Rz): y = asin(m02), gimbal lock at ±π/2.
                let y = m[(0, 2)].clamp(-1.0, 1.0).asin();
                let x = (-m[(1, 2)]).atan2(m[(2, 2)]);
                let z = (-m[(0, 1)]).atan2(m[(0, 0)]);
                lines.push(format!(
                    "  frame {ci} {} d {:.4} {:.4} {:.4} xyz {x:.3} {y:.3} {z:.3}",
                    tr.names[other], d.x, d.y, d.z
                ));
            }
            for (k, &h) in w.connections.handles[ci].iter().enumerate() {
                let (e0, e1) = (en0[h.index()], en1[h.index()]);
                if !e0 && !e1 {
                    continue;
                }
                let lambda = world.applied_impulse(h)?;
                let fb = world.joint_feedback(h)?;
                let f = if c.a == i { fb.force_a } else { fb.force_b };
                let fm = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
                lines.push(format!(
                    "  conn {ci} {} k{k} on {e0}->{e1} lambda {lambda:.4} thr {:.4} F {:.0} {:.0} {:.0} |F| {fm:.0}",
                    tr.names[other],
                    world.breaking_threshold(h)?,
                    f[0], f[1], f[2]
                ));
            }
        }
        for pair in world.contact_pairs()? {
            let (a, b) = (pair.body_a, pair.body_b);
            let other = if a == me {
                b
            } else if b == me {
                a
            } else {
                continue;
            };
            let name = handles
                .iter()
                .position(|&x| x == other)
                .map_or("ground".to_string(), |j| tr.names[j].clone());
            lines.push(format!(
                "  contact {name} n {} d {:.4} J {:.4}",
                pair.contact.num_points,
                pair.contact.min_distance,
                pair.contact.total_normal_impulse
            ));
        }
        if let Some(tr) = self.body.as_mut() {
            for l in lines {
                tr.push(l);
            }
        }
        Ok(())
    }

    /// The body trace's file and text, for the caller to write.
    pub(crate) fn body_report(&self) -> Option<(std::path::PathBuf, String)> {
        self.body.as_ref().map(|t| t.report())
    }

    /// The axial trace's file and text for the connections' body `pairs`, for the caller
    /// to write.
    pub(crate) fn axial_report(
        &self,
        pairs: &[(usize, usize)],
    ) -> Option<(std::path::PathBuf, String)> {
        self.axial.as_ref().map(|t| t.report(pairs))
    }
}
