//! The bodies still moving at the end of the ruin stage.
use crate::body::Body;
use crate::output::summary::{r6, UnsettledBody};
use crate::ruin::stage::RuinResult;

/// The dynamic body with the largest instantaneous point speed at the end (`None` without
/// dynamic bodies).
pub(crate) fn instantaneous_at_end(bodies: &[Body], r: &RuinResult) -> Option<UnsettledBody> {
    r.ledger
        .final_instantaneous_speeds_mps
        .iter()
        .enumerate()
        .filter(|(i, _)| !bodies[*i].passive)
        .fold(None, |best: Option<(usize, f64)>, (i, v)| match best {
            Some((_, b)) if b >= *v => best,
            _ => Some((i, *v)),
        })
        .map(|(i, v)| UnsettledBody {
            body: bodies[i].id.name(),
            speed_mps: r6(v),
        })
}

/// The bodies not at rest at the end (name and point speed relative to the ground, m/s),
/// in body order.
pub(crate) fn unsettled(bodies: &[Body], r: &RuinResult) -> Vec<UnsettledBody> {
    r.at_rest
        .iter()
        .enumerate()
        .filter(|(_, ok)| !**ok)
        .map(|(i, _)| UnsettledBody {
            body: bodies[i].id.name(),
            speed_mps: r6(r.ledger.final_point_speeds_mps[i]),
        })
        .collect()
}
