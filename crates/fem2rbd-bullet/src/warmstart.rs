//! Warm starting of the joints' rows (`bs_world_set_joint_warmstart`).
//!
//! Bullet 3.24's `btSequentialImpulseConstraintSolver` warm-starts contact rows
//! (`setupContactConstraint`: the first guess of a contact's impulse is
//! `m_warmstartingFactor` × its impulse of the last substep) but not joint rows:
//! `convertJoint` sets every row's `m_appliedImpulse = 0`, so each substep's projected
//! Gauss–Seidel solve of a joint starts from zero, and whatever the iterations leave
//! unsolved stays as position error, pulled back in the next substep by the Baumgarte
//! velocity ERP·e/h. With a factor f > 0 the shim's solver starts every row of every
//! `btGeneric6DofConstraint` from f × its impulse of the last substep (the same row: same
//! constraint, same kind, axis turned by less than about 8°; clamped to the row's bounds,
//! i.e. its breaking threshold) and applies that impulse to both bodies before the first
//! iteration, as Bullet does for contacts. The iterations then correct the guess instead of
//! building the whole impulse again, so a joint carrying a steady load (a column under its
//! slab) converges in a few iterations. f = 0 is Bullet's own behaviour.
use super::types::PhysicsError;
use super::world::{check, World};
use bullet_sys as sys;

impl World {
    /// Sets the warm-start factor of the generic (6-dof) constraints' rows, 0..=1
    /// (module docs; 0 = Bullet's behaviour, every joint row starts from zero impulse).
    pub fn set_joint_warmstart(&mut self, factor: f64) -> Result<(), PhysicsError> {
        if !(factor.is_finite() && (0.0..=1.0).contains(&factor)) {
            return Err(PhysicsError::Invalid(format!(
                "joint warm-start factor {factor} must be in [0, 1]"
            )));
        }
        // SAFETY: live world; the shim validates the factor again.
        check("set_joint_warmstart", unsafe {
            sys::bs_world_set_joint_warmstart(self.raw_ptr(), factor)
        })
    }

    /// The warm-start factor and the number of joint rows warm-started so far.
    pub fn joint_warmstart(&self) -> Result<(f64, u64), PhysicsError> {
        let (mut f, mut n) = (0.0, 0i64);
        // SAFETY: live world; two writable outputs.
        check("get_joint_warmstart", unsafe {
            sys::bs_world_get_joint_warmstart(self.raw_ptr(), &mut f, &mut n)
        })?;
        Ok((f, n.max(0) as u64))
    }
}
