//! Pass (connection rule): two-way axial rows broken in the sense they push
//! (`crate::ruin::axial`, docs/handoff.md §4.1).

use crate::ruin::axial::{two_way_breaks, AxialLeft, AxialRows, COMPRESSION_SIGN};
use crate::ruin::connection::{ConnectionSpec, ConnectionState, BCB_UNLIMITED};
use crate::ruin::monitor::Monitor;
use crate::ruin::record::StageError;
use crate::ruin::world::RuinWorld;

/// With [`AxialRows::TwoWay`], after every substep, for each elastic connection: a
/// two-way row whose impulse λ in the substep reached the breaking impulse of the sense
/// it pushed in (it breaks in compression when λ·s_c ≥ C·κ·h, in tension when
/// −λ·s_c ≥ T·κ·h; [`two_way_breaks`]) becomes BCB's one-way row of the other sense with
/// that sense's breaking impulse (BCB's rows break one at a time); when that row is gone
/// too, the connection's tension constraint (which has no rows) is disabled with it. A row
/// Bullet disabled below its sense's breaking impulse is enabled again; the Bullet
/// threshold (and clamp) of the next substep is the breaking impulse of the sense the row
/// pushed in (the smaller one after a substep without impulse). With BCB's rows
/// ([`AxialRows::Bcb`]) the pass does nothing.
pub(crate) struct TwoWayAxial {
    /// The rows are two-way.
    on: bool,
    /// κ·h: BCB's linear correction times the substep, s.
    kappa_h: f64,
    /// Per connection, which senses its axial row still holds.
    left: Vec<AxialLeft>,
    /// Per connection, the Bullet threshold of its axial row now, N·s.
    threshold: Vec<f64>,
}

/// A two-way row broken in a substep (for the axial trace, `crate::ruin::observer`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct AxialBreak {
    /// The connection.
    pub(crate) connection: usize,
    /// The row's impulse λ, N·s.
    pub(crate) impulse: f64,
    /// C·κ·h, N·s.
    pub(crate) compression_ns: f64,
    /// T·κ·h, N·s.
    pub(crate) tension_ns: f64,
}

impl TwoWayAxial {
    /// The rule for `connections` built with `axial_rows`, with BCB's linear correction
    /// `linear_correction` (κ) at the substep `h`, s. A connection whose constraint 0 is
    /// locked at [0, 0] on the normal has a two-way row; one built with BCB's rows (a sense
    /// without strength) is left to Bullet.
    pub(crate) fn new(
        connections: &[ConnectionSpec],
        axial_rows: AxialRows,
        linear_correction: f64,
        h: f64,
    ) -> Self {
        let on = axial_rows == AxialRows::TwoWay;
        TwoWayAxial {
            on,
            kappa_h: linear_correction * h,
            left: connections
                .iter()
                .map(|c| match c.constraints.first() {
                    Some(k) if on && k.lower[0] == k.upper[0] => AxialLeft::Both,
                    _ => AxialLeft::None,
                })
                .collect(),
            threshold: connections
                .iter()
                .map(|c| c.constraints.first().map_or(0.0, |k| k.breaking_impulse))
                .collect(),
        }
    }

    /// Per connection, which senses its axial row still holds.
    pub(crate) fn left(&self) -> &[AxialLeft] {
        &self.left
    }

    /// `enabled`: every constraint's flag right after the substep; `t`: its end time, s.
    /// Returns the rows broken in it.
    pub(crate) fn apply(
        &mut self,
        w: &mut RuinWorld,
        monitor: &Monitor,
        enabled: &[bool],
        t: f64,
    ) -> Result<Vec<AxialBreak>, StageError> {
        let mut breaks = Vec::new();
        if !self.on {
            return Ok(breaks);
        }
        let kappa_h = self.kappa_h;
        let conns = &mut w.connections;
        for (i, c) in conns.specs.iter().enumerate() {
            if monitor.state(i) != ConnectionState::Elastic {
                continue;
            }
            let hs = &conns.handles[i];
            let (Some(&h0), Some(&h1)) = (hs.first(), hs.get(1)) else {
                continue;
            };
            let (c_ns, t_ns) = (
                c.forces.compression_n * kappa_h,
                c.forces.tension_n * kappa_h,
            );
            match self.left[i] {
                AxialLeft::Both => {
                    let lambda = w.bullet.applied_impulse(h0)?;
                    let pushing = lambda * COMPRESSION_SIGN;
                    if two_way_breaks(lambda, c_ns, t_ns) {
                        breaks.push(AxialBreak {
                            connection: i,
                            impulse: lambda,
                            compression_ns: c_ns,
                            tension_ns: t_ns,
                        });
                        let role = if pushing > 0.0 { 0 } else { 1 };
                        conns.first_lost[i].get_or_insert((role, t));
                        let (lo, hi, t, left) = if pushing > 0.0 {
                            (-BCB_UNLIMITED, 0.0, t_ns, AxialLeft::Tension)
                        } else {
                            (0.0, BCB_UNLIMITED, c_ns, AxialLeft::Compression)
                        };
                        w.bullet.set_constraint_limit(h0, 0, lo, hi)?;
                        w.bullet.set_breaking_threshold(h0, t)?;
                        w.bullet.set_constraint_enabled(h0, true)?;
                        self.left[i] = left;
                    } else {
                        if !enabled[h0.index()] {
                            // Bullet's sign-blind test at the other sense's threshold: not
                            // a break of this sense (the impulse was clamped there).
                            w.bullet.set_constraint_enabled(h0, true)?;
                        }
                        // Next substep: the threshold of the sense the row pushed in.
                        let next = if pushing > 0.0 {
                            c_ns
                        } else if pushing < 0.0 {
                            t_ns
                        } else {
                            c_ns.min(t_ns)
                        };
                        if next != self.threshold[i] {
                            w.bullet.set_breaking_threshold(h0, next)?;
                            self.threshold[i] = next;
                        }
                    }
                }
                AxialLeft::Compression | AxialLeft::Tension => {
                    if !enabled[h0.index()] {
                        let role = if self.left[i] == AxialLeft::Compression {
                            0
                        } else {
                            1
                        };
                        conns.first_lost[i].get_or_insert((role, t));
                        self.left[i] = AxialLeft::None;
                        if enabled[h1.index()] {
                            w.bullet.set_constraint_enabled(h1, false)?;
                        }
                    }
                }
                AxialLeft::None => {}
            }
        }
        Ok(breaks)
    }
}
