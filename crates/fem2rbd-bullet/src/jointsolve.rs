//! Direct (sparse LDLᵀ) solve of the joints' bilateral rows (`bs_world_set_joint_solve`).
//!
//! Bullet 3.24 solves joint rows by projected Gauss–Seidel (PGS) only, with a fixed number
//! of sweeps per substep: on a long stiff chain (columns of a frame carrying slabs) the
//! sweeps do not converge and the residual is left as position error
//! (docs/ruin-numerics.md §11). Bullet's row update
//! (`btSequentialImpulseConstraintSolver.cpp`, `gResolveSingleConstraintRowGeneric_scalar_reference`)
//! is Δλᵢ = rhsᵢ − λᵢ·Cᵢ − Dᵢ·(Jᵢ·Δv), with `m_rhs` rhsᵢ \[N·s\], the joint's CFM Cᵢ
//! (`convertJoint` keeps it unscaled, relative to the row's effective mass), Dᵢ =
//! `m_jacDiagABInv` = 1/(Jᵢ M⁻¹ Jᵢᵀ) \[kg or kg·m²\] and Δv the bodies' velocity changes so far.
//! Its fixed point for the rows that are bilateral (lower bound < 0 < upper bound) is
//!
//! (A + diag(Cᵢ/Dᵢ)) λ = rhsᵢ/Dᵢ − Jᵢ·Δv₀,  A = J M⁻¹ Jᵀ,
//!
//! A coupling two rows only through a dynamic body they share (Aᵢⱼ = Σ_b Jᵢᵇ·uⱼᵇ with uⱼᵇ
//! the change of body b's velocity per unit impulse of row j, as
//! `btSolverBody::internalApplyImpulse` applies it). With [`JointSolve::Direct`] the shim
//! assembles that sparse system at every substep's set-up (after `convertJoints` and any
//! joint warm start), adds ε·Aᵢᵢ to the diagonal (redundant locked rows in closed frame
//! loops make A singular when C = 0; an inconsistent right-hand side on such rows gives
//! impulses ∝ 1/ε; ε·Aᵢᵢ is a relative CFM of ε on every row in Bullet's joint convention),
//! factors it with Eigen's `SimplicialLDLT`, solves for the increment over the rows' present
//! impulses (so a warm start is replaced, not added to), holds every row whose impulse would
//! leave its bounds (its breaking threshold) at the bound and solves the others again (an
//! active set, at most 8 passes: the box-constrained solution the projected iterations
//! converge to), and applies the impulses to both bodies.
//! Bullet's usual sweeps then run from there (contacts, one-sided limit rows, clamped rows).
//! A failed factorisation or a non-finite impulse leaves that substep to PGS (counted as a
//! fallback). The result is the same bits for any number of solver threads.
//!
//! ε (docs/ruin-numerics.md §11.1): frame3 under gravity with locked rows stands with
//! ε ≥ 1e-5 (sag 0.27 mm at 1e-5, 3.3 mm at 1e-3) and breaks up with ε ≤ 3e-6 (the
//! redundant rows' impulses reach the breaking thresholds); in the LC5 debris ε = 1e-5 and
//! 1e-4 inject energy (a body at 210 m/s at 1e-5), 1e-3 does not. Default 1e-3. ε acts on
//! the increment over the warm start, so it is a compliance of the joints: a locked row
//! carrying λ gives way by about ε·λ·Aᵢᵢ·h/ERP per substep's correction.
use super::types::PhysicsError;
use super::world::{check, World};
use bullet_sys as sys;

/// The default regularisation ε (module docs: the smallest value measured safe on frame3
/// under gravity and in the LC5 debris; the shim's own default is the same).
pub const DEFAULT_REGULARISATION: f64 = 1e-3;

/// How the joints' bilateral rows are solved at each substep (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum JointSolve {
    /// Bullet's projected Gauss–Seidel only (the default).
    #[default]
    Pgs,
    /// A sparse LDLᵀ solve of the bilateral rows' linear system first, then PGS.
    Direct,
}

/// The state of the direct joint solve ([`World::joint_solve`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointSolveStats {
    /// The mode.
    pub mode: JointSolve,
    /// The regularisation ε (dimensionless; ε·Aᵢᵢ is added to each diagonal entry).
    pub regularisation: f64,
    /// Batches of islands solved directly so far (one per batch per substep).
    pub solves: u64,
    /// Batches left to PGS because the factorisation failed or an impulse was not finite.
    pub fallbacks: u64,
    /// Rows solved directly so far (summed over substeps).
    pub rows: u64,
}

impl World {
    /// Selects how the joints' bilateral rows are solved (module docs); `regularisation` ε
    /// in \[0, 1\] (the shim's default 1e-3; unused with [`JointSolve::Pgs`]).
    pub fn set_joint_solve(
        &mut self,
        mode: JointSolve,
        regularisation: f64,
    ) -> Result<(), PhysicsError> {
        if !(regularisation.is_finite() && (0.0..=1.0).contains(&regularisation)) {
            return Err(PhysicsError::Invalid(format!(
                "joint solve regularisation {regularisation} must be in [0, 1]"
            )));
        }
        let m = match mode {
            JointSolve::Pgs => sys::BS_JOINT_SOLVE_PGS,
            JointSolve::Direct => sys::BS_JOINT_SOLVE_DIRECT,
        } as i32;
        // SAFETY: live world; the shim validates the arguments again.
        check("set_joint_solve", unsafe {
            sys::bs_world_set_joint_solve(self.raw_ptr(), m, regularisation)
        })
    }

    /// The mode, ε and the counts of direct solves, fallbacks and rows so far.
    pub fn joint_solve(&self) -> Result<JointSolveStats, PhysicsError> {
        let (mut m, mut eps, mut solves, mut fallbacks, mut rows) = (0i32, 0.0, 0i64, 0i64, 0i64);
        // SAFETY: live world; five writable outputs.
        check("get_joint_solve", unsafe {
            sys::bs_world_get_joint_solve(
                self.raw_ptr(),
                &mut m,
                &mut eps,
                &mut solves,
                &mut fallbacks,
                &mut rows,
            )
        })?;
        Ok(JointSolveStats {
            mode: if m == sys::BS_JOINT_SOLVE_DIRECT as i32 {
                JointSolve::Direct
            } else {
                JointSolve::Pgs
            },
            regularisation: eps,
            solves: solves.max(0) as u64,
            fallbacks: fallbacks.max(0) as u64,
            rows: rows.max(0) as u64,
        })
    }
}
