//! Pass (connection rule): the first row each elastic connection loses.

use crate::ruin::axial::AxialRows;
use crate::ruin::connection::{ConnectionState, GENERIC_COUNT};
use crate::ruin::monitor::Monitor;
use crate::ruin::world::Connections;

/// After every substep records, per elastic connection, the first generic row that Bullet
/// disabled in it (its impulse reached the breaking threshold,
/// `btTypedConstraint::m_breakingImpulseThreshold`): a brittle row's break, or a ductile
/// bending row's first yield (the row is enabled again by the pass `ductile_rows`); the
/// row and the substep's end time go into
/// [`crate::ruin::record::ConnectionOutcome::first_row_lost`]. With two-way axial rows
/// the axial rows are left to the pass `two_way_axial`, which tells their breaks from
/// Bullet's sign-blind test.
pub(crate) struct LostRows {
    /// The axial rows are two-way ([`AxialRows::TwoWay`]).
    two_way: bool,
}

impl LostRows {
    /// The rule for connections with `axial_rows`.
    pub(crate) fn new(axial_rows: AxialRows) -> Self {
        LostRows {
            two_way: axial_rows == AxialRows::TwoWay,
        }
    }

    /// `enabled`: every constraint's flag after the substep; `t`: its end time, s.
    pub(crate) fn apply(
        &self,
        conns: &mut Connections,
        monitor: &Monitor,
        enabled: &[bool],
        t: f64,
    ) {
        for (i, c) in conns.specs.iter().enumerate() {
            if conns.first_lost[i].is_some() || monitor.state(i) != ConnectionState::Elastic {
                continue;
            }
            for (k, spec) in c.constraints.iter().enumerate().take(GENERIC_COUNT) {
                if !spec.enabled || spec.no_strength || (self.two_way && k < 2) {
                    continue;
                }
                if conns.handles[i].get(k).is_some_and(|h| !enabled[h.index()]) {
                    conns.first_lost[i] = Some((k, t));
                    break;
                }
            }
        }
    }
}
