//! World and solver settings, with Bullet 3.24's own defaults and the pybullet 3.2.7 preset.
use serde::{Deserialize, Serialize};

/// `btSolverMode::SOLVER_USE_WARMSTARTING`.
pub const SOLVER_USE_WARMSTARTING: i32 = 4;
/// `btSolverMode::SOLVER_USE_2_FRICTION_DIRECTIONS`: a second friction row per contact.
/// pybullet always sets it (its `btMultiBodyDynamicsWorld` constructor does), see
/// `docs/bullet-ffi.md` §3.3.
pub const SOLVER_USE_2_FRICTION_DIRECTIONS: i32 = 16;
/// `btSolverMode::SOLVER_SIMD` (no effect in the double-precision build, kept for parity).
pub const SOLVER_SIMD: i32 = 256;

/// The sequential-impulse solver's settings (`btContactSolverInfo`; field names follow
/// Bullet's `m_*` members). Dimensionless unless a unit is given.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SolverSettings {
    /// `m_numIterations`: Gauss–Seidel sweeps per substep.
    pub num_iterations: u32,
    /// `m_erp`: error reduction parameter of joints (non-contact constraints).
    pub erp: f64,
    /// `m_erp2`: error reduction parameter of contacts ("contact ERP").
    pub erp2: f64,
    /// `m_frictionERP`.
    pub friction_erp: f64,
    /// `m_globalCfm`: constraint force mixing.
    pub global_cfm: f64,
    /// `m_linearSlop` \[m\]: penetration allowed before the contact pushes back.
    pub linear_slop: f64,
    /// `m_splitImpulse`: position correction of deep contacts through pseudo-velocities.
    pub split_impulse: bool,
    /// `m_splitImpulsePenetrationThreshold` \[m\] (negative): deeper contacts use split impulse.
    pub split_impulse_penetration_threshold: f64,
    /// `m_splitImpulseTurnErp`.
    pub split_impulse_turn_erp: f64,
    /// `m_solverMode`: `btSolverMode` flags (260 = warm starting | SIMD; pybullet 276).
    pub solver_mode: i32,
    /// `m_warmstartingFactor`: fraction of last substep's contact impulse applied first.
    pub warmstarting_factor: f64,
    /// `m_leastSquaresResidualThreshold`: early exit of the iterations.
    pub least_squares_residual_threshold: f64,
    /// `m_minimumSolverBatchSize` (pybullet's "minimumSolverIslandSize").
    pub minimum_solver_batch_size: u32,
    /// `m_restitutionVelocityThreshold` [m/s]: slower impacts get no restitution.
    pub restitution_velocity_threshold: f64,
    /// `m_maxErrorReduction` [m/s].
    pub max_error_reduction: f64,
    /// `m_sor`: successive over-relaxation.
    pub sor: f64,
    /// `m_damping`: damping of non-contact constraints.
    pub damping: f64,
}

impl Default for SolverSettings {
    /// Bullet 3.24's `btContactSolverInfo` defaults (also what `bs_world_default_solver_params`
    /// reports; a unit test checks the two agree). Three of them are `float` literals in
    /// Bullet's source (`-0.04f`, `0.1f`, `0.2f`), hence the `f32` values here.
    fn default() -> Self {
        Self {
            num_iterations: 10,
            erp: 0.2,
            erp2: 0.2,
            friction_erp: 0.2,
            global_cfm: 0.0,
            linear_slop: 0.0,
            split_impulse: true,
            split_impulse_penetration_threshold: -0.04_f32 as f64,
            split_impulse_turn_erp: 0.1_f32 as f64,
            solver_mode: SOLVER_USE_WARMSTARTING | SOLVER_SIMD,
            warmstarting_factor: 0.85,
            least_squares_residual_threshold: 0.0,
            minimum_solver_batch_size: 128,
            restitution_velocity_threshold: 0.2_f32 as f64,
            max_error_reduction: 20.0,
            sor: 1.0,
            damping: 1.0,
        }
    }
}

impl SolverSettings {
    /// pybullet 3.2.7's effective settings for plain rigid bodies (docs/bullet-ffi.md §3.3/§3.4):
    /// 50 iterations, contact ERP 0.08, slop 1e-5, warm starting 0.1, residual threshold
    /// 1e-7, batch size 0, and solver mode 276 (adds two friction directions).
    pub fn pybullet() -> Self {
        Self {
            num_iterations: 50,
            erp2: 0.08,
            linear_slop: 1e-5,
            warmstarting_factor: 0.1,
            least_squares_residual_threshold: 1e-7,
            minimum_solver_batch_size: 0,
            solver_mode: SOLVER_USE_WARMSTARTING | SOLVER_SIMD | SOLVER_USE_2_FRICTION_DIRECTIONS,
            ..Self::default()
        }
    }
}

/// Everything a [`crate::World`] is created with.
#[derive(Clone, Debug, PartialEq)]
pub struct WorldSettings {
    /// Gravity [m/s²], world frame (z up in this project: (0, 0, −9.81)).
    pub gravity: [f64; 3],
    /// Solver settings.
    pub solver: SolverSettings,
    /// `gDbvtMargin` \[m\] (Bullet default 0.05, pybullet 0). **Process-global**: it is a
    /// variable in libBulletCollision shared by every world in the process; `None` leaves it.
    pub dbvt_margin: Option<f64>,
    /// `gContactBreakingThreshold` \[m\] (default 0.02 in both). **Process-global**, like
    /// `dbvt_margin`; it is read when a contact manifold is created.
    pub contact_breaking_threshold: Option<f64>,
    /// Build the world from Bullet's stock classes only (`bs_world_new_stock`: Bullet 3.24's
    /// `btSequentialImpulseConstraintSolver`, none of the shim's solver subclasses), the
    /// reference the shim's solver is checked against. Such a world runs one solver thread,
    /// Bullet's sweep ([`crate::Sweep::Bullet`]), no joint warm start and the projected
    /// Gauss–Seidel joint solve; asking it for anything else is an error. `false` (default):
    /// the shim's solver.
    pub stock_solver: bool,
}

impl Default for WorldSettings {
    /// Bullet's defaults with gravity (0, 0, −9.81) m/s²; globals left as they are.
    fn default() -> Self {
        Self {
            gravity: [0.0, 0.0, -9.81],
            solver: SolverSettings::default(),
            dbvt_margin: None,
            contact_breaking_threshold: None,
            stock_solver: false,
        }
    }
}

impl WorldSettings {
    /// pybullet 3.2.7's settings (docs/bullet-ffi.md §3.3), gravity (0, 0, −9.81), gDbvtMargin 0.
    pub fn pybullet() -> Self {
        Self {
            gravity: [0.0, 0.0, -9.81],
            solver: SolverSettings::pybullet(),
            dbvt_margin: Some(0.0),
            contact_breaking_threshold: Some(0.02),
            stock_solver: false,
        }
    }
}
