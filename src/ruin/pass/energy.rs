//! Pass: the energy ledger (`crate::ruin::energy`, docs/ruin-numerics.md).

use super::BodyState;
use crate::ruin::energy::{mechanical, substep_balance, EnergyFrame};
use crate::ruin::record::StageError;
use crate::ruin::world::RuinWorld;

/// After every substep h adds its ground work ΔW_g = v_g·Σ_i J_i, with
/// J_i = m_i·(v_i⁺ − (1 − d_lin)^h·v_i⁻ − g·h) the impulse body i received from contacts
/// and joints, and its damping loss ½·m·|v⁻|²·(1 − λ_lin²) + T_r⁻·(1 − λ_ang²),
/// λ = (1 − d)^h ([`crate::ruin::energy`] module docs, Bullet 3.24's substep); and the
/// energy the solver injected, the positive part of ΔE − ΔW_g + ΔD with E = T_t + T_r + V
/// the mechanical energy (J).
pub(crate) struct EnergyLedger {
    /// The full gravity, m/s².
    gravity: [f64; 3],
    /// Bullet's linear and angular damping of the bodies, per second.
    damping: (f64, f64),
    /// Potential energy of the undeformed building relative to the ground's top, J.
    initial_potential_j: f64,
    /// W_g so far, J.
    ground_work_j: f64,
    /// D so far, J.
    damping_j: f64,
    /// Energy the solver added so far, J.
    injected_j: f64,
    /// The largest single-substep injection, J, and the end time of its substep, s.
    max_injection: (f64, f64),
    /// E after the last substep, J (`None` before the first).
    last_mechanical_j: Option<f64>,
}

impl EnergyLedger {
    /// The ledger of `w` under `gravity` (m/s²) with the bodies' linear and angular
    /// `damping`, from the start time `t_start`, s; `undeformed`: the bodies at their
    /// undeformed poses, at rest (the scale V(0) of the settle-phase check).
    pub(crate) fn new(
        w: &RuinWorld,
        gravity: [f64; 3],
        damping: (f64, f64),
        undeformed: &BodyState,
        t_start: f64,
    ) -> Self {
        let (_, _, initial_potential_j) = mechanical(
            &w.bodies.props,
            &undeformed.poses,
            &undeformed.vels,
            gravity,
            w.ground.reference,
        );
        EnergyLedger {
            gravity,
            damping,
            initial_potential_j,
            ground_work_j: 0.0,
            damping_j: 0.0,
            injected_j: 0.0,
            max_injection: (0.0, t_start),
            last_mechanical_j: None,
        }
    }

    /// Before the first substep: E of the state `now`.
    pub(crate) fn open(&mut self, w: &RuinWorld, now: &BodyState) {
        if self.last_mechanical_j.is_none() {
            let (a, b, c) = mechanical(
                &w.bodies.props,
                &now.poses,
                &now.vels,
                self.gravity,
                w.ground.reference,
            );
            self.last_mechanical_j = Some(a + b + c);
        }
    }

    /// After the substep `h` (s) ending at `t` (s) from `before` to `after`, under the
    /// gravity `g` (m/s²) with the ground moving at `vg` (m/s). Returns the energy the
    /// substep added beyond the ground's work, J.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn apply(
        &mut self,
        w: &RuinWorld,
        before: &BodyState,
        after: &BodyState,
        h: f64,
        g: [f64; 3],
        vg: [f64; 3],
        t: f64,
    ) -> f64 {
        let (ld, ad) = self.damping;
        let props = &w.bodies.props;
        let b = substep_balance(
            props,
            &before.poses,
            &before.vels,
            &after.vels,
            h,
            g,
            vg,
            ld,
            ad,
        );
        self.ground_work_j += b.ground_work_j;
        self.damping_j += b.damping_j;
        let gref = w.ground.reference;
        let (t1, r1, v1) = mechanical(props, &after.poses, &after.vels, self.gravity, gref);
        let e1 = t1 + r1 + v1;
        let mut added = 0.0;
        if let Some(e0) = self.last_mechanical_j {
            // Energy the substep added beyond the ground's work (the balance's
            // negative part; damping is a loss, so it is added back).
            added = e1 - e0 - b.ground_work_j + b.damping_j;
            if added > 0.0 {
                self.injected_j += added;
                if added > self.max_injection.0 {
                    self.max_injection = (added, t);
                }
            }
        }
        self.last_mechanical_j = Some(e1);
        added
    }

    /// The ledger now.
    pub(crate) fn frame(&self, w: &RuinWorld) -> Result<EnergyFrame, StageError> {
        let (tt, tr, v) = mechanical(
            &w.bodies.props,
            &w.body_poses()?,
            &w.body_velocities()?,
            self.gravity,
            w.ground.reference,
        );
        Ok(EnergyFrame {
            kinetic_translational_j: tt,
            kinetic_rotational_j: tr,
            potential_j: v,
            ground_work_j: self.ground_work_j,
            damping_j: self.damping_j,
            injected_j: self.injected_j,
        })
    }

    /// Potential energy of the undeformed building relative to the ground's top, J.
    pub(crate) fn initial_potential_j(&self) -> f64 {
        self.initial_potential_j
    }

    /// Energy the solver added over the run, J.
    pub(crate) fn injected_j(&self) -> f64 {
        self.injected_j
    }

    /// The largest single-substep injection, J, and the end time of its substep, s.
    pub(crate) fn max_injection(&self) -> (f64, f64) {
        self.max_injection
    }
}
