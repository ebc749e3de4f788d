//! The energy ledger's summary (docs/ruin-numerics.md): start and end energies, the
//! settle phase's largest energy rise and the fastest body against their bounds.
use crate::body::Body;
use crate::motion::GroundHistory;
use crate::output::summary::{r6, EndEnergy, EnergySummary, SettlePhase, SpeedCheck, StartEnergy};
use crate::ruin::stage::RuinResult;

/// Settle-phase energy rises larger than this share of the initial potential energy fail
/// the check of docs/ruin-numerics.md.
pub(crate) const SETTLE_RISE_LIMIT: f64 = 1e-3;

/// The energy ledger's summary (docs/ruin-numerics.md): start and end energies, ground
/// work, damping, dissipated (J); the settle phase's largest rise of the mechanical energy
/// between two frames (t ≥ the record's end, ground still) against
/// [`SETTLE_RISE_LIMIT`] × the undeformed building's potential energy; the fastest body
/// against √(v_Tc,max² + 2·g·H) + the record's peak ground speed (m/s). `None` without
/// frames.
pub(crate) fn energy_summary(
    bodies: &[Body],
    ground: &GroundHistory,
    r: &RuinResult,
) -> Option<EnergySummary> {
    let l = &r.ledger;
    let (first, last) = (r.frames.first()?, r.frames.last()?);
    let (e0, e1) = (&first.energy, &last.energy);
    let motion_end = ground.end_time_s();
    let mut rise = (0.0_f64, None::<f64>);
    let mut settle_frames = 0usize;
    for w in r.frames.windows(2) {
        if w[0].time_s < motion_end - 1e-9 {
            continue;
        }
        settle_frames += 1;
        let d = w[1].energy.mechanical_j() - w[0].energy.mechanical_j();
        if d > rise.0 {
            rise = (d, Some(w[1].time_s));
        }
    }
    let peak_ground = ground
        .vel
        .iter()
        .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
        .fold(0.0, f64::max);
    let bound = (l.start_max_speed_mps.powi(2) + 2.0 * l.gravity_mps2 * l.model_height_m).sqrt()
        + peak_ground;
    let ratio = if l.initial_potential_j > 0.0 {
        rise.0 / l.initial_potential_j
    } else {
        0.0
    };
    Some(EnergySummary {
        initial_potential_j: r6(l.initial_potential_j),
        start: StartEnergy {
            kinetic_j: r6(e0.kinetic_translational_j + e0.kinetic_rotational_j),
            potential_j: r6(e0.potential_j),
        },
        end: EndEnergy {
            kinetic_j: r6(e1.kinetic_translational_j + e1.kinetic_rotational_j),
            potential_j: r6(e1.potential_j),
            ground_work_j: r6(e1.ground_work_j),
            damping_j: r6(e1.damping_j),
            dissipated_j: r6(e1.dissipated_j(e0)),
        },
        injected_j: r6(l.injected_j),
        max_substep_injection_j: r6(l.max_injection.0),
        max_substep_injection_at_s: r6(l.max_injection.1),
        settle_phase: SettlePhase {
            from_s: r6(motion_end),
            frames: settle_frames,
            max_rise_j: r6(rise.0),
            max_rise_at_s: rise.1.map(r6),
            max_rise_ratio: r6(ratio),
            limit_ratio: SETTLE_RISE_LIMIT,
            ok: ratio <= SETTLE_RISE_LIMIT,
        },
        speed: SpeedCheck {
            max_mps: r6(l.max_speed_mps),
            max_body: l.max_speed_at.map(|(i, _)| bodies[i].id.name()),
            max_at_s: l.max_speed_at.map(|(_, t)| r6(t)),
            start_max_mps: r6(l.start_max_speed_mps),
            peak_ground_mps: r6(peak_ground),
            bound_mps: r6(bound),
            ok: l.max_speed_mps <= bound,
        },
    })
}
