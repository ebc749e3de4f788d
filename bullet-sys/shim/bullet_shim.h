/*
 * bullet_shim.h — a small C API over Bullet 3.24 (double precision) for Rust.
 *
 * Design: one opaque world handle owns every Bullet object (collision configuration,
 * dispatcher, Dbvt broadphase, sequential-impulse solver, discrete dynamics world, box
 * shapes, rigid bodies, constraints and their joint feedback). Bodies and constraints are
 * addressed by dense indices (0, 1, 2, ... in creation order) and are never removed before
 * the world is freed. Every entry point catches all C++ exceptions and returns a status code
 * (BS_OK = 0, negative = error); bs_last_error() gives a message for the last failure on the
 * calling thread. All reals are double (btScalar must be double: see bs_abi_self_check).
 * Quaternions are (w, x, y, z). Units are SI.
 */
#ifndef BULLET_SHIM_H
#define BULLET_SHIM_H

#ifdef __cplusplus
extern "C" {
#endif

typedef struct bs_world bs_world;

enum bs_status {
    BS_OK = 0,
    BS_ERR_EXCEPTION = -1,  /* a C++ exception was caught */
    BS_ERR_NULL = -2,       /* a null pointer argument */
    BS_ERR_BAD_INDEX = -3,  /* body or constraint index out of range */
    BS_ERR_BAD_ARG = -4,    /* an argument out of its domain (NaN, negative mass, ...) */
    BS_ERR_ABI = -5,        /* the linked libBullet disagrees with our btScalar */
    BS_ERR_WRONG_KIND = -6, /* operation not valid for this body / constraint kind */
    BS_ERR_STOCK = -7       /* a solver feature of the shim asked of a stock world (bs_world_new_stock) */
};

enum bs_body_kind { BS_STATIC = 0, BS_KINEMATIC = 1, BS_DYNAMIC = 2 };

/* BS_POINT2POINT: btPoint2PointConstraint(A, B, pivotInA, pivotInB), the pivots the frames'
 * positions; the frames' orientations must be the identity and no limit may be given. */
enum bs_constraint_kind { BS_GENERIC6DOF = 0, BS_SPRING2 = 1, BS_FIXED = 2, BS_POINT2POINT = 3 };

/* Solver and world settings: btContactSolverInfo fields (names follow Bullet's m_*). */
typedef struct bs_solver_params {
    int num_iterations;                         /* m_numIterations */
    double erp;                                 /* m_erp: joint error reduction */
    double erp2;                                /* m_erp2: contact error reduction */
    double friction_erp;                        /* m_frictionERP */
    double global_cfm;                          /* m_globalCfm */
    double linear_slop;                         /* m_linearSlop [m] */
    int split_impulse;                          /* m_splitImpulse (0/1) */
    double split_impulse_penetration_threshold; /* m_splitImpulsePenetrationThreshold [m] */
    double split_impulse_turn_erp;              /* m_splitImpulseTurnErp */
    int solver_mode;                            /* m_solverMode (btSolverMode flags) */
    double warmstarting_factor;                 /* m_warmstartingFactor */
    double least_squares_residual_threshold;    /* m_leastSquaresResidualThreshold */
    int minimum_solver_batch_size;              /* m_minimumSolverBatchSize (island size) */
    double restitution_velocity_threshold;      /* m_restitutionVelocityThreshold [m/s] */
    double max_error_reduction;                 /* m_maxErrorReduction [m/s] */
    double sor;                                 /* m_sor */
    double damping;                             /* m_damping (non-contact constraints) */
} bs_solver_params;

typedef struct bs_body_desc {
    int kind;                    /* bs_body_kind */
    double half_extents[3];      /* outer half extents [m] (margin included) */
    double margin;               /* collision margin [m], 0 <= margin <= min half extent */
    double mass;                 /* [kg]; must be 0 for static/kinematic, > 0 for dynamic */
    double position[3];          /* centre [m] */
    double orientation[4];       /* unit quaternion (w, x, y, z) */
    double linear_velocity[3];   /* [m/s] */
    double angular_velocity[3];  /* [rad/s], world frame */
    double friction;
    double rolling_friction;
    double spinning_friction;
    double restitution;
    double linear_damping;       /* btRigidBody::setDamping, [0, 1] */
    double angular_damping;
    int disable_deactivation;    /* 1: DISABLE_DEACTIVATION, 0: ACTIVE_TAG (may sleep) */
} bs_body_desc;

typedef struct bs_constraint_desc {
    int kind;                    /* bs_constraint_kind */
    int body_a, body_b;          /* body indices (must differ) */
    double frame_a_position[3];  /* joint frame in body A's local frame */
    double frame_a_orientation[4];
    double frame_b_position[3];  /* joint frame in body B's local frame */
    double frame_b_orientation[4];
    int use_linear_reference_frame_a; /* generic6dof only */
    int has_limit[6];            /* 1: setLimit(i, lower[i], upper[i]); 0: leave the default */
    double lower[6], upper[6];   /* axes 0..2 linear [m], 3..5 angular [rad] */
    int spring_enabled[6];       /* spring2 only: enableSpring(i, true) */
    double stiffness[6];         /* spring2: setStiffness(i, k, limit[i]) [N/m, N·m/rad] */
    double damping[6];           /* spring2: setDamping(i, d, limit[i]) [N·s/m, N·m·s/rad] */
    int limit_if_needed[6];      /* spring2: Bullet's limitIfNeeded (stiffness to m/(16 h²), damping to m/h) */
    int set_equilibrium_point;   /* spring2: setEquilibriumPoint() after creation */
    double breaking_impulse_threshold; /* [N·s] per substep per row; +inf = unbreakable */
    int disable_collisions_between;    /* addConstraint(c, disable) */
    int enabled;                 /* initial setEnabled */
    int override_solver_iterations;    /* < 0: use the world's */
} bs_constraint_desc;

/* One persistent manifold (a pair of bodies in contact or near contact). */
typedef struct bs_contact_pair {
    int body_a, body_b;          /* body indices, body_a < body_b */
    int num_points;              /* manifold points (distance <= contact breaking threshold) */
    double min_distance;         /* most negative distance [m] (penetration < 0) */
    double total_normal_impulse; /* sum of the points' applied normal impulses [N·s] */
} bs_contact_pair;

/* ---- library facts ---------------------------------------------------------------- */
int bs_sizeof_scalar(void);         /* sizeof(btScalar) as compiled into the shim */
int bs_bullet_version(void);        /* btGetVersion() */
int bs_abi_self_check(void);        /* 1 if libBullet agrees with our btScalar, else 0 */
const char *bs_last_error(void);    /* message of the last failure on this thread */

/* ---- process-global Bullet variables (shared by every world in the process) -------- */
int bs_set_global_dbvt_margin(double margin);               /* gDbvtMargin */
double bs_get_global_dbvt_margin(void);
int bs_set_global_contact_breaking_threshold(double value); /* gContactBreakingThreshold */
double bs_get_global_contact_breaking_threshold(void);

/* ---- world --------------------------------------------------------------------------- */
int bs_world_new(const double gravity[3], bs_world **out);
/* A world of Bullet's stock classes only: btDefaultCollisionConfiguration,
 * btCollisionDispatcher, btDbvtBroadphase, btSequentialImpulseConstraintSolver and
 * btDiscreteDynamicsWorld, none of the shim's solver subclasses (the reference the shim's
 * solver is checked against). Everything else behind this API is the same: the bodies,
 * constraints, their feedback and the kinematic velocities set before each substep. The
 * shim's solver features are refused with BS_ERR_STOCK unless they ask for what stock
 * Bullet does: one solver thread, the sweep BS_SWEEP_BULLET, joint warm start 0, the
 * joint solve BS_JOINT_SOLVE_PGS; island statistics and parallel counts are not kept. */
int bs_world_new_stock(const double gravity[3], bs_world **out);
/* 1 if w was made by bs_world_new_stock, else 0 (-2 for a null world). */
int bs_world_is_stock(const bs_world *w);
void bs_world_free(bs_world *w);
int bs_world_set_gravity(bs_world *w, const double gravity[3]);
int bs_world_get_gravity(const bs_world *w, double gravity[3]);
int bs_world_default_solver_params(bs_solver_params *out); /* Bullet 3.24's own defaults */
int bs_world_set_solver_params(bs_world *w, const bs_solver_params *p);
int bs_world_get_solver_params(const bs_world *w, bs_solver_params *out);
/* Runs `count` steps of stepSimulation(h, 0): each advances exactly h seconds. */
int bs_world_step(bs_world *w, double h, int count);
int bs_world_num_bodies(const bs_world *w);
int bs_world_num_constraints(const bs_world *w);
/* Fills up to `capacity` pairs in manifold order; *total receives the number available. */
int bs_world_contact_pairs(const bs_world *w, bs_contact_pair *out, int capacity, int *total);

/* Bulk reads: `n` must equal the number of bodies / constraints; arrays hold n entries of
 * 3 (positions, velocities) or 4 (quaternions) doubles, or n ints. */
int bs_world_get_poses(const bs_world *w, int n, double *positions, double *orientations);
int bs_world_get_velocities(const bs_world *w, int n, double *linear, double *angular);
int bs_world_get_enabled(const bs_world *w, int n, int *enabled);

/* ---- bodies -------------------------------------------------------------------------- */
int bs_body_add_box(bs_world *w, const bs_body_desc *d, int *out_index);
int bs_body_get_pose(const bs_world *w, int body, double position[3], double orientation[4]);
/* Dynamic/static: teleports (world and interpolation transform). Kinematic: sets the
 * target for the next substep; Bullet derives the body's velocity from the change. */
int bs_body_set_pose(bs_world *w, int body, const double position[3], const double orientation[4]);
int bs_body_get_velocity(const bs_world *w, int body, double linear[3], double angular[3]);
int bs_body_set_velocity(bs_world *w, int body, const double linear[3], const double angular[3]);
/* Kinematic only: velocity imposed during the next substep instead of the derived one. */
int bs_body_set_kinematic_velocity(bs_world *w, int body, const double linear[3], const double angular[3]);
int bs_body_apply_central_impulse(bs_world *w, int body, const double impulse[3]);
int bs_body_set_activation_state(bs_world *w, int body, int state); /* Bullet's 1..5 */
int bs_body_get_activation_state(const bs_world *w, int body, int *state);
int bs_body_get_mass_inertia(const bs_world *w, int body, double *mass, double inertia[3]);

/* ---- constraints --------------------------------------------------------------------- */
int bs_constraint_add(bs_world *w, const bs_constraint_desc *d, int *out_index);
int bs_constraint_set_enabled(bs_world *w, int c, int enabled);
int bs_constraint_is_enabled(const bs_world *w, int c, int *enabled);
int bs_constraint_applied_impulse(const bs_world *w, int c, double *impulse); /* last row */
int bs_constraint_set_breaking_threshold(bs_world *w, int c, double threshold);
int bs_constraint_get_breaking_threshold(const bs_world *w, int c, double *threshold);
/* btJointFeedback, zeroed before every substep: forces [N] and torques [N·m] on A and B. */
int bs_constraint_feedback(const bs_world *w, int c, double force_a[3], double torque_a[3],
                           double force_b[3], double torque_b[3]);
/* spring2/fixed: setEquilibriumPoint() at the current relative pose. */
int bs_constraint_set_equilibrium_point(bs_world *w, int c);
/* btTypedConstraint::setParam(num, value, axis) of a generic6dof or spring2 constraint:
 * num 2 = BT_CONSTRAINT_STOP_ERP (the limit rows' error reduction, default the world's m_erp),
 * 4 = BT_CONSTRAINT_STOP_CFM (the limit rows' constraint force mixing, default m_globalCfm);
 * axis 0..5. value finite and >= 0. */
int bs_constraint_set_param(bs_world *w, int c, int num, double value, int axis);
/* Generic6dof: every axis i with bit i of `mask` set whose limits are locked (lower == upper)
 * is locked again at its current value (calculateTransforms(); linear axes
 * getRelativePivotPosition(i), angular axes getAngle(i - 3)): the joint keeps its present
 * deformation instead of driving back to the old lock. */
int bs_constraint_relock(bs_world *w, int c, int mask);
int bs_constraint_set_limit(bs_world *w, int c, int axis, double lo, double hi);
/* Axis `axis` of a generic6dof: its current value (relative pivot position or angle) and
 * its lower limit. */
int bs_constraint_axis_value(bs_world *w, int c, int axis, double *value, double *lo);

/* Warm starting of joint rows (Bullet 3.24 warm-starts contacts only): every row of every
 * btGeneric6DofConstraint starts the next substep's Gauss-Seidel iterations from factor times
 * its impulse of the last substep (matched by row kind and axis, clamped to the row's bounds),
 * applied to both bodies before the first iteration, as Bullet does for contacts.
 * factor in [0, 1]; 0 (the default) = Bullet's behaviour (every joint row starts from 0). */
int bs_world_set_joint_warmstart(bs_world *w, double factor);
/* The factor and the number of rows warm-started so far. */
int bs_world_get_joint_warmstart(const bs_world *w, double *factor, long long *rows_started);

/* Direct solve of the joints' bilateral rows (Bullet 3.24 solves them by projected
 * Gauss-Seidel only). With BS_JOINT_SOLVE_DIRECT, at every substep's set-up of every batch
 * (after the rows are built and any joint warm start applied) the rows of the joint pool
 * that are bilateral now (lower < 0 < upper) get the impulses of the linear system their
 * Gauss-Seidel iterations converge to, (A + diag(cfm/D) + eps diag(A)) lambda = rhs/D - J dv,
 * A = J M^-1 J^T, solved by a sparse LDL^T factorisation (Eigen's SimplicialLDLT), rows that
 * would leave their bounds held at them and the rest solved again (an active set), then
 * applied to both bodies; the usual iterations then follow (contacts,
 * one-sided limits, clamped rows). A failed factorisation or a non-finite result leaves that
 * batch's substep to Gauss-Seidel (counted as a fallback). regularisation = eps in [0, 1]
 * (default 1e-3: eps * A_ii on the diagonal is a relative CFM of eps on every row). */
#define BS_JOINT_SOLVE_PGS 0
#define BS_JOINT_SOLVE_DIRECT 1
int bs_world_set_joint_solve(bs_world *w, int mode, double regularisation);
/* The mode, eps, and the batches solved directly, the fallbacks and the rows solved so far. */
int bs_world_get_joint_solve(const bs_world *w, int *mode, double *regularisation, long long *solves,
                             long long *fallbacks, long long *rows);

/* ---- speed: island-parallel solving, sleeping, phase timing --------------------------- */
/* Solver threads of this world (>= 1; 1 = Bullet's own sequential path). With n > 1 every
 * batch of islands that btDiscreteDynamicsWorld hands the solver is set up in order on the
 * calling thread, its Gauss-Seidel iterations run on up to n threads (one batch per thread
 * at a time; batches share no dynamic body), and the batches are finished in order. Each
 * batch does exactly the arithmetic of the sequential solver, so the results are the same
 * bytes for every n. Split impulse on: always sequential (Bullet counts its recoveries in a
 * global). */
int bs_world_set_solver_threads(bs_world *w, int n);
int bs_world_get_solver_threads(const bs_world *w, int *n);

/* The solver's sweep (the Gauss-Seidel iterations) and joint set-up:
 * BS_SWEEP_BULLET: Bullet's own solveSingleIteration (for benchmarks);
 * BS_SWEEP_LEAN: Bullet's sweep without its per-iteration walk over every constraint for
 *   btTypedConstraint::solveConstraintObsolete, which is empty for every constraint type the
 *   shim creates: the same rows in the same order through Bullet's row functions;
 * BS_SWEEP_PACKED (the default): the lean sweep over packed copies of the joint rows (208
 *   instead of 288 bytes a row, 128 bytes a solver body) in dependency-level order (every
 *   body's rows keep Bullet's order), the same arithmetic; with solver threads n > 1 the
 *   joints' set-up (getInfo1/getInfo2 and Bullet's convertJoint of every constraint) runs on
 *   one or n threads, whichever has measured faster (the bits are the same);
 * BS_SWEEP_PACKED_THREADS: as packed, the set-up always on the n threads, and the sweep of a
 *   batch holding most of the substep's rows on n threads too (slabs of bodies, one per
 *   thread, a row waiting for the rows before it on its bodies).
 * All give the same bits, for any number of solver threads. */
enum bs_sweep { BS_SWEEP_BULLET = 0, BS_SWEEP_LEAN = 1, BS_SWEEP_PACKED = 2, BS_SWEEP_PACKED_THREADS = 3 };
int bs_world_set_sweep(bs_world *w, int sweep);
/* Joint set-ups and packed sweeps (one each per solver batch and substep) run on the solver
 * threads so far. */
int bs_world_parallel_counts(const bs_world *w, long long *setups, long long *sweeps);

/* Island statistics of the last substep's solve: the number of solver batches (island
 * groups passed to solveGroup), the solver rows of the largest batch and of all batches
 * together (contact + joint rows after setup), summed since the last reset. */
typedef struct bs_island_stats {
    long long substeps;          /* substeps counted */
    long long batches;           /* solveGroup calls */
    long long rows_total;        /* solver rows over all batches */
    long long rows_largest;      /* sum over substeps of the largest batch's rows */
    long long bodies_awake;      /* sum over substeps of the dynamic bodies solved */
} bs_island_stats;
int bs_world_island_stats(const bs_world *w, bs_island_stats *out);
int bs_world_reset_island_stats(bs_world *w);

/* Sleeping: Bullet's per-body thresholds (btRigidBody::setSleepingThresholds, [m/s], [rad/s])
 * and the process-global gDeactivationTime [s] (how long a body must stay below both before
 * its island may sleep). */
int bs_body_set_sleeping_thresholds(bs_world *w, int body, double linear, double angular);
int bs_set_global_deactivation_time(double seconds);
double bs_get_global_deactivation_time(void);
/* Number of dynamic bodies whose activation state is ISLAND_SLEEPING (2). */
int bs_world_num_sleeping(const bs_world *w, int *count);

/* Contact between bodies a and b (btCollisionObject::setIgnoreCollisionCheck, on both).
 * collide = 0 puts each body on the other's ignore list (once) and drops the pair's
 * cached contact manifold; collide = 1 removes every entry, including the one per
 * constraint that addConstraint(c, true) added (btRigidBody::addConstraintRef; Bullet
 * keeps it while the constraint is in the world, enabled or broken). Takes effect at the
 * next step's narrow phase (btCollisionDispatcher::needsCollision). */
int bs_body_set_collision_with(bs_world *w, int a, int b, int collide);
/* 1 if the narrow phase would process the pair (neither ignores the other), else 0. */
int bs_body_collides_with(const bs_world *w, int a, int b, int *collides);

/* Phase timing through Bullet's BT_PROFILE zones (btSetCustomEnterProfileZoneFunc): per
 * zone name the inclusive wall time and the number of entries, recorded for the calling
 * thread only (other threads' zones are ignored). */
typedef struct bs_profile_entry {
    char name[64];
    double seconds;
    long long calls;
    int depth;                   /* nesting depth at the first entry (0 = outermost) */
} bs_profile_entry;
int bs_profile_start(void);      /* installs the hooks (once) and clears this thread's record */
int bs_profile_stop(void);       /* stops recording on this thread */
int bs_profile_read(bs_profile_entry *out, int capacity, int *total);

#ifdef __cplusplus
}
#endif
#endif /* BULLET_SHIM_H */
