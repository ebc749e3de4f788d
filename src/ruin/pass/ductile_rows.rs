//! Pass (connection rule): ductile bending rows yield instead of breaking.

use crate::bullet::ConstraintHandle;
use crate::ruin::connection::{ConnectionState, BENDING_ROWS};
use crate::ruin::monitor::Monitor;
use crate::ruin::record::StageError;
use crate::ruin::world::RuinWorld;
use std::collections::BTreeMap;

/// After every substep enables again the ductile bending rows
/// ([`crate::ruin::connection::ConnectionSpec::ductile`]) of elastic connections that
/// Bullet disabled in it (their impulse reached the plastic moment's impulse): the row
/// carries its capacity and yields, as a plastic hinge. Before it is enabled the row is
/// re-locked ([`crate::ruin::stage::PlasticSettings::hinge_keeps_rotation`]): at its present
/// rotation ([`crate::bullet::World::relock_constraint`]), or by a return mapping that
/// keeps the rotation error of its first yield
/// ([`crate::ruin::stage::PlasticSettings::hinge_return_mapping`], [`Self::relock`]).
pub(crate) struct DuctileRows {
    /// Some connection is ductile (else the pass does nothing).
    any_ductile: bool,
    /// Re-lock a yielded row before enabling it.
    keeps_rotation: bool,
    /// Re-lock by the return mapping.
    return_mapping: bool,
    /// Per (connection, bending row): the rotation error at its first yield.
    first_error: BTreeMap<(usize, usize), [f64; 6]>,
}

impl DuctileRows {
    /// The rule; `any_ductile`: some connection is ductile.
    pub(crate) fn new(any_ductile: bool, keeps_rotation: bool, return_mapping: bool) -> Self {
        DuctileRows {
            any_ductile,
            keeps_rotation,
            return_mapping,
            first_error: BTreeMap::new(),
        }
    }

    /// `enabled`: every constraint's flag after the substep.
    pub(crate) fn apply(
        &mut self,
        w: &mut RuinWorld,
        monitor: &Monitor,
        enabled: &[bool],
    ) -> Result<(), StageError> {
        if !self.any_ductile {
            return Ok(());
        }
        // (connection, bending row, constraint, locked-axis mask) of every yielded row.
        let mut yielded = Vec::new();
        let conns = &w.connections;
        for (i, c) in conns.specs.iter().enumerate() {
            if !c.ductile || monitor.state(i) != ConnectionState::Elastic {
                continue;
            }
            for k in BENDING_ROWS {
                let Some(spec) = c.constraints.get(k) else {
                    continue;
                };
                if spec.no_strength {
                    continue;
                }
                if let Some(&h) = conns.handles[i].get(k) {
                    if !enabled[h.index()] {
                        let mask = (0..6)
                            .filter(|&a| spec.lower[a] == spec.upper[a])
                            .fold(0u8, |m, a| m | (1 << a));
                        yielded.push((i, k, h, mask));
                    }
                }
            }
        }
        for (i, k, h, mask) in yielded {
            if self.keeps_rotation {
                if self.return_mapping {
                    self.relock(w, i, k, h, mask)?;
                } else {
                    w.bullet.relock_constraint(h, mask)?;
                }
            }
            w.bullet.set_constraint_enabled(h, true)?;
        }
        Ok(())
    }

    /// Re-locks the locked axes `mask` of the yielded ductile row `k` of connection `i`
    /// (constraint `h`) by a return mapping: at its first yield the lock stays and the
    /// row's rotation error e₀ = θ − θ_lock per locked axis is kept; at every later yield
    /// the lock moves to θ − sign(e)·min(|e₀|, |e|) (θ when the hinge turned back,
    /// sign(e) ≠ sign(e₀): a kept error of the other sign would drive it like a motor at
    /// ERP·e/h), so the row starts the next substep with the error through which the (not
    /// fully converged) solver carried its capacity, and θ_lock follows the plastic
    /// rotation (elastic–plastic return mapping; Simo and Hughes, *Computational
    /// Inelasticity*, 1998, §1.4), rad (m on linear axes).
    fn relock(
        &mut self,
        w: &mut RuinWorld,
        i: usize,
        k: usize,
        h: ConstraintHandle,
        mask: u8,
    ) -> Result<(), StageError> {
        let axes = (0..6).filter(|a| mask & (1 << a) != 0);
        let mut err = [0.0; 6];
        let mut lock = [0.0; 6];
        for a in axes.clone() {
            let (v, lo) = w.bullet.constraint_axis_value(h, a)?;
            err[a] = v - lo;
            lock[a] = lo;
        }
        match self.first_error.get(&(i, k)) {
            None => {
                self.first_error.insert((i, k), err);
            }
            Some(e0) => {
                for a in axes {
                    let keep = if err[a] * e0[a] > 0.0 {
                        e0[a].abs().min(err[a].abs()) * err[a].signum()
                    } else {
                        0.0
                    };
                    let l = lock[a] + err[a] - keep;
                    w.bullet.set_constraint_limit(h, a, l, l)?;
                }
            }
        }
        Ok(())
    }
}
