// bullet_shim.cpp — implementation of bullet_shim.h over Bullet 3.24 (double precision).
// Every extern "C" function body runs inside guard(), which turns C++ exceptions into
// BS_ERR_EXCEPTION and records a message for bs_last_error().
#include "bullet_shim.h"

// Eigen before Bullet: the direct joint solve (DirectJointSolver) factors with
// Eigen::SimplicialLDLT (Debian: libeigen3-dev, header-only).
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <btBulletDynamicsCommon.h>
#include <BulletDynamics/ConstraintSolver/btFixedConstraint.h>
#include <BulletDynamics/ConstraintSolver/btGeneric6DofSpring2Constraint.h>

#include <LinearMath/btQuickprof.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <exception>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <unordered_map>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

extern btScalar gDbvtMargin;
extern btScalar gContactBreakingThreshold;
extern btScalar gDeactivationTime;

namespace {

thread_local std::string g_last_error;

int fail(int code, const std::string &msg) {
    g_last_error = msg;
    return code;
}

template <typename F>
int guard(F &&f) noexcept {
    try {
        return f();
    } catch (const std::exception &e) {
        return fail(BS_ERR_EXCEPTION, std::string("C++ exception: ") + e.what());
    } catch (...) {
        return fail(BS_ERR_EXCEPTION, "unknown C++ exception");
    }
}

bool finite3(const double v[3]) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}
bool finite4(const double v[4]) {
    return finite3(v) && std::isfinite(v[3]);
}

btVector3 vec(const double v[3]) { return btVector3(v[0], v[1], v[2]); }
void put(const btVector3 &v, double out[3]) {
    out[0] = v.x();
    out[1] = v.y();
    out[2] = v.z();
}
// (w, x, y, z) <-> btQuaternion(x, y, z, w)
btQuaternion quat(const double q[4]) { return btQuaternion(q[1], q[2], q[3], q[0]); }
void put_quat(const btQuaternion &q, double out[4]) {
    out[0] = q.w();
    out[1] = q.x();
    out[2] = q.y();
    out[3] = q.z();
}

// A quaternion is accepted when finite and of unit length to 1e-6. It is passed on as given:
// btMatrix3x3::setRotation scales by 2/|q|², as pybullet's path does.
int check_quat(const double q[4], btQuaternion &out, const char *what) {
    if (!finite4(q)) return fail(BS_ERR_BAD_ARG, std::string(what) + " has a non-finite component");
    double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(std::fabs(n - 1.0) <= 1e-6))
        return fail(BS_ERR_BAD_ARG, std::string(what) + " is not a unit quaternion (|q| = " + std::to_string(n) + ")");
    out = quat(q);
    return BS_OK;
}

struct Body {
    std::unique_ptr<btBoxShape> shape;
    std::unique_ptr<btRigidBody> body;
    int kind = BS_DYNAMIC;
    bool has_kinematic_velocity = false;
    btVector3 kinematic_linear{0, 0, 0};
    btVector3 kinematic_angular{0, 0, 0};
};

struct Constraint {
    std::unique_ptr<btTypedConstraint> constraint;
    btJointFeedback feedback;
    int kind = BS_GENERIC6DOF;
};

void zero_feedback(btJointFeedback &fb) {
    fb.m_appliedForceBodyA.setZero();
    fb.m_appliedTorqueBodyA.setZero();
    fb.m_appliedForceBodyB.setZero();
    fb.m_appliedTorqueBodyB.setZero();
}



// ---- the iterations without Bullet's obsolete per-constraint loop ------------------------
//
// btSequentialImpulseConstraintSolver::solveSingleIteration (Bullet 3.24,
// btSequentialImpulseConstraintSolver.cpp) sweeps the joint rows, then, in every
// iteration, walks *all* constraints of the batch to call
// btTypedConstraint::solveConstraintObsolete on each enabled one (with two
// getOrInitSolverBody look-ups), then the contact and friction rows. The obsolete call is
// empty for every constraint type the shim creates (btGeneric6DofConstraint,
// btGeneric6DofSpring2Constraint, btFixedConstraint: only btConeTwistConstraint overrides
// it), but the walk reads each constraint object (about 1 kB apiece in double precision)
// and is a cache miss per constraint per iteration: measured on the library stand-in
// (63 665 constraints, docs/performance.md) it was about half of the stage's CPU time.
// LeanSolver::solveSingleIteration is Bullet's function without that walk — an altered
// version of btSequentialImpulseConstraintSolver::solveSingleIteration from Bullet Physics
// 3.24 (Copyright (c) 2003-2006 Erwin Coumans, https://bulletphysics.org; zlib licence:
// provided 'as-is', without any warranty; altered versions must be plainly marked as such):
// the same rows in the same order through the same row functions, so the same bits.
// The walk's only other effect is that getOrInitSolverBody gives a solver body to a
// kinematic or static partner of an enabled constraint that has no rows this substep (a
// locked joint exactly in place); such a solver body takes part in no row, and its
// write-back sets the body's velocity to itself.
// Runs f(begin, end) over [0, n) in chunks of `chunk` on up to `threads` threads (the
// calling thread included); the first exception of any thread is rethrown on the calling
// thread after all have stopped. f must only write what its own indices own.
template <typename F>
void parallel_chunks(int n, int threads, int chunk, F &&f) {
    if (threads <= 1 || n <= chunk) {
        f(0, n);
        return;
    }
    std::atomic<int> next{0};
    std::atomic<bool> failed{false};
    std::string error;
    std::mutex error_mutex;
    auto work = [&]() {
        for (;;) {
            int b = next.fetch_add(chunk);
            if (b >= n || failed.load()) return;
            try {
                f(b, std::min(n, b + chunk));
            } catch (const std::exception &e) {
                std::lock_guard<std::mutex> lock(error_mutex);
                error = e.what();
                failed.store(true);
            } catch (...) {
                std::lock_guard<std::mutex> lock(error_mutex);
                error = "unknown C++ exception";
                failed.store(true);
            }
        }
    };
    int extra = std::min(threads, (n + chunk - 1) / chunk) - 1;
    std::vector<std::thread> pool;
    pool.reserve(static_cast<size_t>(extra));
    for (int t = 0; t < extra; ++t) pool.emplace_back(work);
    work();
    for (auto &t : pool) t.join();
    if (failed.load()) throw std::runtime_error("solver thread: " + error);
}

// ---- the packed sweep ---------------------------------------------------------------------
//
// A btSolverConstraint is 288 bytes in double precision and a btSolverBody about 500; the
// joint-row sweep reads 24 doubles and 3 ints of each row and 15 doubles of each of its two
// bodies, so on the library stand-in (61 568 rows a substep, 17.7 MB of rows) each of the
// 100 sweeps streamed the whole pool from memory. The packed sweep copies each joint row's
// fields into a PackedRow (208 bytes, in sweep order) and each solver body's into a
// PackedBody (128 bytes, one cache line pair) once per substep, runs the iterations over
// those, and writes the applied impulses and the bodies' velocity changes back before the
// finish. The row update is Bullet 3.24's gResolveSingleConstraintRowGeneric_scalar_reference
// with btSolverBody::internalApplyImpulse (btSequentialImpulseConstraintSolver.cpp,
// btSolverBody.h; zlib licence, see LeanSolver below; altered: it reads the packed copies),
// operation for operation in the same order, so the same bits (the shim is compiled with
// -ffp-contract=off). Contact and friction rows keep Bullet's layout: the bodies' velocity
// changes are copied to Bullet's solver bodies before them and back after them in every
// iteration that has any.
struct PackedRow {
    double rhs, applied, cfm, jac;
    double n1[3], r1[3], n2[3], r2[3];  // m_contactNormal1, m_relpos1CrossNormal, ...2
    double lower, upper;
    double aA[3], aB[3];                // m_angularComponentA, m_angularComponentB
    int a, b;                           // solver body indices
    int iters;                          // m_overrideNumSolverIterations
    int orig;                           // place in Bullet's sweep order
};
struct alignas(64) PackedBody {
    double dl[3], da[3];  // m_deltaLinearVelocity, m_deltaAngularVelocity
    double im[3];         // m_invMass (per axis)
    double lf[3], af[3];  // m_linearFactor, m_angularFactor
    int active;           // m_originalBody != null
};

// A joint row's waits in the threaded sweep: segment t1 must have done q1 rows of this
// iteration (and t2 q2) before the row may run; t = -1: no wait.
struct RowDep {
    int t1 = -1, q1 = 0, t2 = -1, q2 = 0;
};
struct alignas(64) SegmentProgress {
    std::atomic<long long> done{0};  // rows done since the substep's first iteration
};
// A barrier that spins (then yields) instead of sleeping: the threaded sweep meets twice
// per iteration, far too often for a futex round trip.
class SpinBarrier {
   public:
    explicit SpinBarrier(int n) : n_(n) {}
    void wait() {
        const int g = gen_.load(std::memory_order_acquire);
        if (count_.fetch_add(1, std::memory_order_acq_rel) == n_ - 1) {
            count_.store(0, std::memory_order_relaxed);
            gen_.fetch_add(1, std::memory_order_acq_rel);
            return;
        }
        int spins = 0;
        while (gen_.load(std::memory_order_acquire) == g) {
            if (++spins < 4096) {
#if defined(__x86_64__) || defined(__i386__)
                __builtin_ia32_pause();
#endif
            } else {
                std::this_thread::yield();
            }
        }
    }

   private:
    int n_;
    alignas(64) std::atomic<int> count_{0};
    alignas(64) std::atomic<int> gen_{0};
};

// Sweep kinds (bs_world_set_sweep, bullet_shim.h).
enum {
    SWEEP_BULLET = BS_SWEEP_BULLET,
    SWEEP_LEAN = BS_SWEEP_LEAN,
    SWEEP_PACKED = BS_SWEEP_PACKED,
    SWEEP_PACKED_THREADS = BS_SWEEP_PACKED_THREADS
};

// Chooses, substep by substep, whether the joints' set-up runs on one thread (mode 0) or on
// the solver threads (mode 1), by the measured wall time per unit of work of each. Both modes give the same bits, so the choice changes only the
// speed: on a machine whose cores are busy with other work a thread that must wait for
// another is often not running, and the threaded phase can be slower than the sequential
// one (docs/performance.md). Now and then the mode not in favour is tried again: after 16
// calls, and after twice as many each time it loses again (up to 1024), so on a machine
// where the threads keep losing the trials cost little.
struct ThreadChooser {
    bool always = false;        // always mode 1 (SWEEP_PACKED_THREADS: tests, benchmarks)
    double avg[2] = {-1, -1};   // s per unit of work, exponential average (-1: none yet)
    long long calls = 0;
    long long period = 16;      // calls between trials of the mode not in favour
    long long next_trial = 16;
    int trial_of = -1;          // the mode on trial in the current call, else -1
    int pick() {
        if (always) return 1;
        ++calls;
        trial_of = -1;
        if (avg[1] < 0) return 1;
        if (avg[0] < 0) return 0;
        const int best = avg[1] < avg[0] ? 1 : 0;
        if (calls >= next_trial) {
            trial_of = 1 - best;
            return trial_of;
        }
        return best;
    }
    void record(int mode, double seconds_per_unit) {
        if (trial_of == mode) {
            // A trial replaces the mode's stale average with what it measures now.
            avg[mode] = seconds_per_unit;
            const bool won = avg[mode] < avg[1 - mode];
            period = won ? 16 : std::min<long long>(2 * period, 1024);
            next_trial = calls + period;
            trial_of = -1;
            return;
        }
        avg[mode] = avg[mode] < 0 ? seconds_per_unit : 0.75 * avg[mode] + 0.25 * seconds_per_unit;
    }
};
double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// ---- the iterations without Bullet's obsolete per-constraint loop ------------------------
//
// btSequentialImpulseConstraintSolver::solveSingleIteration (Bullet 3.24,
// btSequentialImpulseConstraintSolver.cpp) sweeps the joint rows, then, in every
// iteration, walks *all* constraints of the batch to call
// btTypedConstraint::solveConstraintObsolete on each enabled one (with two
// getOrInitSolverBody look-ups), then the contact and friction rows. The obsolete call is
// empty for every constraint type the shim creates (btGeneric6DofConstraint,
// btGeneric6DofSpring2Constraint, btFixedConstraint: only btConeTwistConstraint overrides
// it), but the walk reads each constraint object (about 1 kB apiece in double precision)
// and is a cache miss per constraint per iteration: measured on the library stand-in
// (63 665 constraints, docs/performance.md) it was about half of the stage's CPU time.
// LeanSolver::solveSingleIteration is Bullet's function without that walk — an altered
// version of btSequentialImpulseConstraintSolver::solveSingleIteration from Bullet Physics
// 3.24 (Copyright (c) 2003-2006 Erwin Coumans, https://bulletphysics.org; zlib licence:
// provided 'as-is', without any warranty; altered versions must be plainly marked as such):
// the same rows in the same order through the same row functions, so the same bits.
// The walk's only other effect is that getOrInitSolverBody gives a solver body to a
// kinematic or static partner of an enabled constraint that has no rows this substep (a
// locked joint exactly in place); such a solver body takes part in no row, and its
// write-back sets the body's velocity to itself.
//
// With sweep = SWEEP_PACKED the iterations run over packed copies of the rows (above), and
// with setup_threads > 1 the joints' set-up (convertJoints: getInfo1/getInfo2 of every
// constraint, Bullet's convertJoint) runs on that many threads: every constraint writes only
// its own members and its own rows and reads the bodies, and the solver bodies of the
// constraints' partners are assigned on the calling thread in Bullet's order, so the rows
// are the same bits for any thread count (altered version of Bullet 3.24's
// btSequentialImpulseConstraintSolver::convertJoints, same licence).
class LeanSolver : public btSequentialImpulseConstraintSolver {
   public:
    int sweep = SWEEP_PACKED;
    int setup_threads = 1;
    int sweep_threads = 1;                 // threads of the packed sweep (one batch at a time)
    long long *parallel_setups = nullptr;  // counts the joint set-ups run on threads
    long long *parallel_sweeps = nullptr;  // counts the packed sweeps run on threads
    ThreadChooser *setup_chooser = nullptr;  // null: threads whenever eligible
    bool packed() const { return sweep == SWEEP_PACKED || sweep == SWEEP_PACKED_THREADS; }

    btScalar solveSingleIteration(int iteration, btCollisionObject **bodies, int numBodies,
                                  btPersistentManifold **manifoldPtr, int numManifolds, btTypedConstraint **constraints,
                                  int numConstraints, const btContactSolverInfo &infoGlobal,
                                  btIDebugDraw *debugDrawer) override {
        if (sweep == SWEEP_BULLET || (infoGlobal.m_solverMode & SOLVER_RANDMIZE_ORDER))
            return btSequentialImpulseConstraintSolver::solveSingleIteration(
                iteration, bodies, numBodies, manifoldPtr, numManifolds, constraints, numConstraints, infoGlobal,
                debugDrawer);
        BT_PROFILE("solveSingleIteration");
        btScalar leastSquaresResidual = 0.f;
        const int numNonContactPool = m_tmpSolverNonContactConstraintPool.size();
        for (int j = 0; j < numNonContactPool; j++) {
            btSolverConstraint &constraint = m_tmpSolverNonContactConstraintPool[m_orderNonContactConstraintPool[j]];
            if (iteration < constraint.m_overrideNumSolverIterations) {
                btScalar residual = m_resolveSingleConstraintRowGeneric(m_tmpSolverBodyPool[constraint.m_solverBodyIdA],
                                                                        m_tmpSolverBodyPool[constraint.m_solverBodyIdB],
                                                                        constraint);
                leastSquaresResidual = btMax(leastSquaresResidual, residual * residual);
            }
        }
        contact_rows(iteration, infoGlobal, leastSquaresResidual);
        (void)bodies;
        (void)numBodies;
        (void)manifoldPtr;
        (void)numManifolds;
        (void)constraints;
        (void)numConstraints;
        (void)debugDrawer;
        return leastSquaresResidual;
    }

    // Bullet 3.24's solveGroupCacheFriendlyIterations over the packed rows (sweep 2).
    btScalar solveGroupCacheFriendlyIterations(btCollisionObject **bodies, int numBodies,
                                               btPersistentManifold **manifoldPtr, int numManifolds,
                                               btTypedConstraint **constraints, int numConstraints,
                                               const btContactSolverInfo &infoGlobal,
                                               btIDebugDraw *debugDrawer) override {
        if (!packed() || (infoGlobal.m_solverMode & SOLVER_RANDMIZE_ORDER))
            return btSequentialImpulseConstraintSolver::solveGroupCacheFriendlyIterations(
                bodies, numBodies, manifoldPtr, numManifolds, constraints, numConstraints, infoGlobal, debugDrawer);
        BT_PROFILE("solveGroupCacheFriendlyIterations");
        solveGroupCacheFriendlySplitImpulseIterations(bodies, numBodies, manifoldPtr, numManifolds, constraints,
                                                      numConstraints, infoGlobal, debugDrawer);
        const int maxIterations = m_maxOverrideNumSolverIterations > infoGlobal.m_numIterations
                                      ? m_maxOverrideNumSolverIterations
                                      : infoGlobal.m_numIterations;
        // The sweep on the threads only when asked for (SWEEP_PACKED_THREADS): measured on a
        // shared machine, one substep of it could cost as much as hundreds of sequential
        // ones, too much for even a single trial (docs/performance.md).
        const bool threaded = sweep == SWEEP_PACKED_THREADS && sweep_threads > 1 &&
                              m_tmpSolverNonContactConstraintPool.size() >= kThreadedSweepRows;
        pack(threaded ? sweep_threads : 1);
        if (segments_ > 1) {
            if (parallel_sweeps) ++*parallel_sweeps;
            threaded_iterations(maxIterations, numBodies, bodies, numManifolds, infoGlobal);
        } else {
            for (int iteration = 0; iteration < maxIterations; iteration++) {
                m_leastSquaresResidual = packed_iteration(iteration, infoGlobal);
                if (m_leastSquaresResidual <= infoGlobal.m_leastSquaresResidualThreshold ||
                    (iteration >= (maxIterations - 1))) {
                    analytics(iteration, numBodies, bodies, numManifolds);
                    break;
                }
            }
        }
        unpack();
        return 0.f;
    }

   protected:
    void convertJoints(btTypedConstraint **constraints, int numConstraints, const btContactSolverInfo &info) override {
        if (!packed() || setup_threads <= 1 || numConstraints < 2 * kSetupChunk) {
            btSequentialImpulseConstraintSolver::convertJoints(constraints, numConstraints, info);
            return;
        }
        const int mode = setup_chooser ? setup_chooser->pick() : 1;
        const auto t0 = std::chrono::steady_clock::now();
        if (mode) {
            BT_PROFILE("convertJointsOnThreads");
            if (parallel_setups) ++*parallel_setups;
            convert_joints(constraints, numConstraints, info, setup_threads);
        } else {
            BT_PROFILE("convertJoints");
            convert_joints(constraints, numConstraints, info, 1);
        }
        if (setup_chooser) setup_chooser->record(mode, seconds_since(t0) / numConstraints);
    }

    void convert_joints(btTypedConstraint **constraints, int numConstraints, const btContactSolverInfo &info,
                        int threads) {
        m_tmpConstraintSizesPool.resizeNoInitialize(numConstraints);
        // Per constraint (its own members, its feedback and its info1 slot only): Bullet's
        // buildJacobian / internalSetAppliedImpulse loop and its getInfo1 loop.
        parallel_chunks(numConstraints, threads, kSetupChunk, [&](int begin, int end) {
            for (int i = begin; i < end; i++) {
                btTypedConstraint *constraint = constraints[i];
                constraint->buildJacobian();
                constraint->internalSetAppliedImpulse(0.0f);
                btTypedConstraint::btConstraintInfo1 &info1 = m_tmpConstraintSizesPool[i];
                btJointFeedback *fb = constraint->getJointFeedback();
                if (fb) {
                    fb->m_appliedForceBodyA.setZero();
                    fb->m_appliedTorqueBodyA.setZero();
                    fb->m_appliedForceBodyB.setZero();
                    fb->m_appliedTorqueBodyB.setZero();
                }
                if (constraint->isEnabled()) {
                    constraint->getInfo1(&info1);
                } else {
                    info1.m_numConstraintRows = 0;
                    info1.nub = 0;
                }
            }
        });
        // In Bullet's order on this thread: the rows' places, the partners' solver bodies
        // (getOrInitSolverBody appends to the pool) and the largest iteration override
        // (which convertJoint would otherwise update from every thread).
        row_start_.resize(static_cast<size_t>(numConstraints));
        body_ids_.resize(static_cast<size_t>(numConstraints));
        int totalNumRows = 0;
        for (int i = 0; i < numConstraints; i++) {
            row_start_[i] = totalNumRows;
            totalNumRows += m_tmpConstraintSizesPool[i].m_numConstraintRows;
        }
        m_tmpSolverNonContactConstraintPool.resizeNoInitialize(totalNumRows);
        for (int i = 0; i < numConstraints; i++) {
            if (!m_tmpConstraintSizesPool[i].m_numConstraintRows) continue;
            btTypedConstraint *constraint = constraints[i];
            int a = getOrInitSolverBody(constraint->getRigidBodyA(), info.m_timeStep);
            int b = getOrInitSolverBody(constraint->getRigidBodyB(), info.m_timeStep);
            body_ids_[i] = std::make_pair(a, b);
            int over = constraint->getOverrideNumSolverIterations() > 0 ? constraint->getOverrideNumSolverIterations()
                                                                         : info.m_numIterations;
            if (over > m_maxOverrideNumSolverIterations) m_maxOverrideNumSolverIterations = over;
        }
        // Bullet's convertJoint per constraint: getInfo2 into its own rows, then the rows'
        // effective masses and right-hand sides.
        parallel_chunks(numConstraints, threads, kSetupChunk, [&](int begin, int end) {
            for (int i = begin; i < end; i++) {
                const btTypedConstraint::btConstraintInfo1 &info1 = m_tmpConstraintSizesPool[i];
                if (!info1.m_numConstraintRows) continue;
                convertJoint(&m_tmpSolverNonContactConstraintPool[row_start_[i]], constraints[i], info1,
                             body_ids_[i].first, body_ids_[i].second, info);
            }
        });
    }

   private:
    static constexpr int kSetupChunk = 32;  // constraints per task
    std::vector<int> row_start_;
    std::vector<std::pair<int, int>> body_ids_;
    std::vector<PackedRow> rows_;
    std::vector<PackedBody> pbodies_;
    std::vector<int> contact_bodies_;  // solver bodies of the contact rows (sync_bodies)
    std::vector<int> body_level_, level_, level_next_;
    int levels_ = 0;
    // Threaded sweep (segments_ > 1): rows_ holds segment 0's rows, then segment 1's, ...
    static constexpr int kThreadedSweepRows = 256;  // fewer rows: one thread
    int segments_ = 1;
    std::vector<int> seg_begin_;
    std::vector<RowDep> deps_;
    std::vector<char> writes_;           // the body's velocity changes can change
    std::vector<int> owner_, row_seg_, last_seg_, last_q_;
    std::vector<double> part_;
    std::unique_ptr<SegmentProgress[]> progress_;
    int progress_size_ = 0;

    // The contact, friction and rolling-friction rows of one iteration (Bullet's order).
    void contact_rows(int iteration, const btContactSolverInfo &infoGlobal, btScalar &leastSquaresResidual) {
        // A friction row bounded by friction × its contact's impulse (Bullet's code in both
        // of its branches below).
        auto solve_friction = [&](btSolverConstraint &solveManifold, btScalar totalImpulse) {
            if (totalImpulse > btScalar(0)) {
                solveManifold.m_lowerLimit = -(solveManifold.m_friction * totalImpulse);
                solveManifold.m_upperLimit = solveManifold.m_friction * totalImpulse;
                btScalar residual = m_resolveSingleConstraintRowGeneric(
                    m_tmpSolverBodyPool[solveManifold.m_solverBodyIdA],
                    m_tmpSolverBodyPool[solveManifold.m_solverBodyIdB], solveManifold);
                leastSquaresResidual = btMax(leastSquaresResidual, residual * residual);
            }
        };
        if (iteration < infoGlobal.m_numIterations) {
            const int numPoolConstraints = m_tmpSolverContactConstraintPool.size();
            if (infoGlobal.m_solverMode & SOLVER_INTERLEAVE_CONTACT_AND_FRICTION_CONSTRAINTS) {
                int multiplier = (infoGlobal.m_solverMode & SOLVER_USE_2_FRICTION_DIRECTIONS) ? 2 : 1;
                for (int c = 0; c < numPoolConstraints; c++) {
                    btScalar totalImpulse = 0;
                    {
                        const btSolverConstraint &solveManifold = m_tmpSolverContactConstraintPool[m_orderTmpConstraintPool[c]];
                        btScalar residual = m_resolveSingleConstraintRowLowerLimit(
                            m_tmpSolverBodyPool[solveManifold.m_solverBodyIdA],
                            m_tmpSolverBodyPool[solveManifold.m_solverBodyIdB], solveManifold);
                        leastSquaresResidual = btMax(leastSquaresResidual, residual * residual);
                        totalImpulse = solveManifold.m_appliedImpulse;
                    }
                    for (int k = 0; k < multiplier; ++k) {
                        btSolverConstraint &solveManifold =
                            m_tmpSolverContactFrictionConstraintPool[m_orderFrictionConstraintPool[c * multiplier + k]];
                        solve_friction(solveManifold, totalImpulse);
                    }
                }
            } else {
                for (int j = 0; j < numPoolConstraints; j++) {
                    const btSolverConstraint &solveManifold = m_tmpSolverContactConstraintPool[m_orderTmpConstraintPool[j]];
                    btScalar residual = m_resolveSingleConstraintRowLowerLimit(
                        m_tmpSolverBodyPool[solveManifold.m_solverBodyIdA], m_tmpSolverBodyPool[solveManifold.m_solverBodyIdB],
                        solveManifold);
                    leastSquaresResidual = btMax(leastSquaresResidual, residual * residual);
                }
                const int numFrictionPoolConstraints = m_tmpSolverContactFrictionConstraintPool.size();
                for (int j = 0; j < numFrictionPoolConstraints; j++) {
                    btSolverConstraint &solveManifold = m_tmpSolverContactFrictionConstraintPool[m_orderFrictionConstraintPool[j]];
                    btScalar totalImpulse = m_tmpSolverContactConstraintPool[solveManifold.m_frictionIndex].m_appliedImpulse;
                    solve_friction(solveManifold, totalImpulse);
                }
            }
            const int numRollingFrictionPoolConstraints = m_tmpSolverContactRollingFrictionConstraintPool.size();
            for (int j = 0; j < numRollingFrictionPoolConstraints; j++) {
                btSolverConstraint &rollingFrictionConstraint = m_tmpSolverContactRollingFrictionConstraintPool[j];
                btScalar totalImpulse =
                    m_tmpSolverContactConstraintPool[rollingFrictionConstraint.m_frictionIndex].m_appliedImpulse;
                if (totalImpulse > btScalar(0)) {
                    btScalar rollingFrictionMagnitude = rollingFrictionConstraint.m_friction * totalImpulse;
                    if (rollingFrictionMagnitude > rollingFrictionConstraint.m_friction)
                        rollingFrictionMagnitude = rollingFrictionConstraint.m_friction;
                    rollingFrictionConstraint.m_lowerLimit = -rollingFrictionMagnitude;
                    rollingFrictionConstraint.m_upperLimit = rollingFrictionMagnitude;
                    btScalar residual = m_resolveSingleConstraintRowGeneric(
                        m_tmpSolverBodyPool[rollingFrictionConstraint.m_solverBodyIdA],
                        m_tmpSolverBodyPool[rollingFrictionConstraint.m_solverBodyIdB], rollingFrictionConstraint);
                    leastSquaresResidual = btMax(leastSquaresResidual, residual * residual);
                }
            }
        }
    }

    bool has_contact_rows() const {
        return m_tmpSolverContactConstraintPool.size() > 0 || m_tmpSolverContactFrictionConstraintPool.size() > 0 ||
               m_tmpSolverContactRollingFrictionConstraintPool.size() > 0;
    }

    void pack(int threads) {
        find_contact_bodies();
        const int nb = m_tmpSolverBodyPool.size();
        pbodies_.resize(static_cast<size_t>(nb));
        for (int i = 0; i < nb; i++) {
            const btSolverBody &s = m_tmpSolverBodyPool[i];
            PackedBody &p = pbodies_[i];
            for (int k = 0; k < 3; k++) {
                p.dl[k] = s.m_deltaLinearVelocity[k];
                p.da[k] = s.m_deltaAngularVelocity[k];
                p.im[k] = s.m_invMass[k];
                p.lf[k] = s.m_linearFactor[k];
                p.af[k] = s.m_angularFactor[k];
            }
            p.active = s.m_originalBody ? 1 : 0;
        }
        // The rows' levels in Bullet's sweep order j: 1 + the highest level of the earlier
        // rows on either of its bodies. Only bodies whose velocity changes can change count:
        // a body Bullet never updates (m_originalBody null) or one with zero inverse mass and
        // inverse inertia (a kinematic body: every update adds a signed zero to +0, which
        // stays +0) reads the same in any order. A body's rows have strictly increasing
        // levels, so sweeping level by level keeps every body's rows in Bullet's order and
        // each row sees exactly the velocity changes it sees in Bullet's sweep: the same bits.
        const int n = m_tmpSolverNonContactConstraintPool.size();
        writes_.assign(static_cast<size_t>(nb), 0);
        for (int i = 0; i < nb; i++) {
            const btSolverBody &sb = m_tmpSolverBodyPool[i];
            if (!sb.m_originalBody) continue;
            bool moves = !(sb.m_invMass[0] == 0 && sb.m_invMass[1] == 0 && sb.m_invMass[2] == 0);
            const btRigidBody *rb = btRigidBody::upcast(sb.m_originalBody);
            if (!rb) {
                moves = true;
            } else {
                const btMatrix3x3 &ii = rb->getInvInertiaTensorWorld();
                for (int r = 0; r < 3; r++)
                    for (int k = 0; k < 3; k++) moves = moves || ii[r][k] != 0;
            }
            writes_[i] = moves ? 1 : 0;
        }
        body_level_.assign(static_cast<size_t>(nb), 0);
        level_.resize(static_cast<size_t>(n));
        int nlev = 0;
        for (int j = 0; j < n; j++) {
            const btSolverConstraint &c = m_tmpSolverNonContactConstraintPool[m_orderNonContactConstraintPool[j]];
            const int a = c.m_solverBodyIdA, b = c.m_solverBodyIdB;
            const int la = writes_[a] ? body_level_[a] : 0;
            const int lb = writes_[b] ? body_level_[b] : 0;
            const int l = std::max(la, lb) + 1;
            level_[j] = l;
            if (writes_[a]) body_level_[a] = l;
            if (writes_[b]) body_level_[b] = l;
            nlev = std::max(nlev, l);
        }
        levels_ = nlev;
        // Segments (threaded sweep): the moving bodies cut into sweep_threads slabs along the
        // longer horizontal extent of their centres, each slab holding about as many row ends;
        // a row belongs to the segment of its body A (or B when A does not move).
        const int T = (threads > 1 && n >= kThreadedSweepRows) ? threads : 1;
        segments_ = T;
        row_seg_.assign(static_cast<size_t>(n), 0);
        if (T > 1) {
            std::vector<long long> ends(static_cast<size_t>(nb), 0);
            for (int j = 0; j < n; j++) {
                const btSolverConstraint &c = m_tmpSolverNonContactConstraintPool[m_orderNonContactConstraintPool[j]];
                if (writes_[c.m_solverBodyIdA]) ends[c.m_solverBodyIdA]++;
                if (writes_[c.m_solverBodyIdB]) ends[c.m_solverBodyIdB]++;
            }
            double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
            std::vector<int> moving;
            for (int i = 0; i < nb; i++) {
                if (!writes_[i]) continue;
                moving.push_back(i);
                const btVector3 &o = m_tmpSolverBodyPool[i].m_worldTransform.getOrigin();
                for (int k = 0; k < 2; k++) {
                    lo[k] = std::min(lo[k], double(o[k]));
                    hi[k] = std::max(hi[k], double(o[k]));
                }
            }
            const int axis = (hi[0] - lo[0] >= hi[1] - lo[1]) ? 0 : 1;
            std::stable_sort(moving.begin(), moving.end(), [&](int x, int y) {
                return m_tmpSolverBodyPool[x].m_worldTransform.getOrigin()[axis] <
                       m_tmpSolverBodyPool[y].m_worldTransform.getOrigin()[axis];
            });
            long long total = 0;
            for (int i : moving) total += ends[i];
            owner_.assign(static_cast<size_t>(nb), 0);
            long long acc = 0;
            for (int i : moving) {
                owner_[i] = total > 0 ? static_cast<int>(std::min<long long>(T - 1, (acc * T) / total)) : 0;
                acc += ends[i];
            }
            for (int j = 0; j < n; j++) {
                const btSolverConstraint &c = m_tmpSolverNonContactConstraintPool[m_orderNonContactConstraintPool[j]];
                const int a = c.m_solverBodyIdA, b = c.m_solverBodyIdB;
                row_seg_[j] = writes_[a] ? owner_[a] : (writes_[b] ? owner_[b] : 0);
            }
            if (progress_size_ < T) {
                progress_.reset(new SegmentProgress[static_cast<size_t>(T)]);
                progress_size_ = T;
            }
        }
        // Rows sorted by (segment, level, Bullet's order).
        const int buckets = T * (nlev + 1);
        level_next_.assign(static_cast<size_t>(buckets) + 1, 0);
        for (int j = 0; j < n; j++) level_next_[row_seg_[j] * (nlev + 1) + level_[j] + 1]++;
        for (int k = 1; k <= buckets; k++) level_next_[k] += level_next_[k - 1];
        seg_begin_.assign(static_cast<size_t>(T) + 1, n);
        for (int t = 0; t < T; t++) seg_begin_[t] = level_next_[t * (nlev + 1)];
        rows_.resize(static_cast<size_t>(n));
        if (T > 1) {
            deps_.assign(static_cast<size_t>(n), RowDep());
            last_seg_.assign(static_cast<size_t>(nb), -1);
            last_q_.assign(static_cast<size_t>(nb), 0);
        }
        for (int j = 0; j < n; j++) {
            const btSolverConstraint &c = m_tmpSolverNonContactConstraintPool[m_orderNonContactConstraintPool[j]];
            const int pos = level_next_[row_seg_[j] * (nlev + 1) + level_[j]]++;
            PackedRow &r = rows_[pos];
            r.rhs = c.m_rhs;
            r.applied = c.m_appliedImpulse;
            r.cfm = c.m_cfm;
            r.jac = c.m_jacDiagABInv;
            for (int k = 0; k < 3; k++) {
                r.n1[k] = c.m_contactNormal1[k];
                r.r1[k] = c.m_relpos1CrossNormal[k];
                r.n2[k] = c.m_contactNormal2[k];
                r.r2[k] = c.m_relpos2CrossNormal[k];
                r.aA[k] = c.m_angularComponentA[k];
                r.aB[k] = c.m_angularComponentB[k];
            }
            r.lower = c.m_lowerLimit;
            r.upper = c.m_upperLimit;
            r.a = c.m_solverBodyIdA;
            r.b = c.m_solverBodyIdB;
            r.iters = c.m_overrideNumSolverIterations;
            r.orig = j;
            if (T > 1) {
                // Waits: for each moving body, the previous row on it (in Bullet's order, the
                // same as level order) if another segment runs it. Every wait is for a row
                // of a lower level, and each segment runs its rows by level, so no cycle.
                const int t = row_seg_[j];
                const int q = pos - seg_begin_[t];
                RowDep &d = deps_[pos];
                const int ab[2] = {r.a, r.b};
                for (int e = 0; e < 2; e++) {
                    const int x = ab[e];
                    if (!writes_[x] || (e == 1 && r.b == r.a)) continue;
                    const int u = last_seg_[x];
                    if (u >= 0 && u != t) {
                        const int need = last_q_[x] + 1;
                        if (d.t1 < 0 || d.t1 == u) {
                            d.t1 = u;
                            d.q1 = std::max(d.q1, need);
                        } else if (d.t2 < 0 || d.t2 == u) {
                            d.t2 = u;
                            d.q2 = std::max(d.q2, need);
                        }
                    }
                    last_seg_[x] = t;
                    last_q_[x] = q;
                }
            }
        }
    }

    // Packed body velocity changes -> Bullet's solver bodies (to = true) or back.
    // The packed bodies' velocity changes -> Bullet's solver bodies (to_bullet) or back:
    // every body (all = true, before the finish) or only those the contact rows touch.
    void sync_bodies(bool to_bullet, bool all = false) {
        const int nb = all ? m_tmpSolverBodyPool.size() : static_cast<int>(contact_bodies_.size());
        for (int j = 0; j < nb; j++) {
            const int i = all ? j : contact_bodies_[j];
            btSolverBody &s = m_tmpSolverBodyPool[i];
            PackedBody &p = pbodies_[i];
            for (int k = 0; k < 3; k++) {
                if (to_bullet) {
                    s.m_deltaLinearVelocity[k] = p.dl[k];
                    s.m_deltaAngularVelocity[k] = p.da[k];
                } else {
                    p.dl[k] = s.m_deltaLinearVelocity[k];
                    p.da[k] = s.m_deltaAngularVelocity[k];
                }
            }
        }
    }

    // The solver bodies of the contact, friction and rolling-friction rows, each once.
    void find_contact_bodies() {
        const int nb = m_tmpSolverBodyPool.size();
        std::vector<char> seen(static_cast<size_t>(nb), 0);
        contact_bodies_.clear();
        auto add = [&](const btAlignedObjectArray<btSolverConstraint> &pool) {
            for (int j = 0; j < pool.size(); j++)
                for (int x : {pool[j].m_solverBodyIdA, pool[j].m_solverBodyIdB})
                    if (x >= 0 && x < nb && !seen[x]) {
                        seen[x] = 1;
                        contact_bodies_.push_back(x);
                    }
        };
        add(m_tmpSolverContactConstraintPool);
        add(m_tmpSolverContactFrictionConstraintPool);
        add(m_tmpSolverContactRollingFrictionConstraintPool);
    }

    void unpack() {
        sync_bodies(true, true);
        const int n = m_tmpSolverNonContactConstraintPool.size();
        for (int j = 0; j < n; j++)
            m_tmpSolverNonContactConstraintPool[m_orderNonContactConstraintPool[rows_[j].orig]].m_appliedImpulse =
                rows_[j].applied;
    }

    // One joint row (Bullet's row function over the packed copies, see above); returns
    // the squared residual Bullet's sweep folds into its least-squares residual.
    static inline double solve_row(PackedRow &c, PackedBody *bodies) {
        PackedBody &A = bodies[c.a];
        PackedBody &B = bodies[c.b];
        double deltaImpulse = c.rhs - c.applied * c.cfm;
        const double deltaVel1Dotn = (c.n1[0] * A.dl[0] + c.n1[1] * A.dl[1] + c.n1[2] * A.dl[2]) +
                                     (c.r1[0] * A.da[0] + c.r1[1] * A.da[1] + c.r1[2] * A.da[2]);
        const double deltaVel2Dotn = (c.n2[0] * B.dl[0] + c.n2[1] * B.dl[1] + c.n2[2] * B.dl[2]) +
                                     (c.r2[0] * B.da[0] + c.r2[1] * B.da[1] + c.r2[2] * B.da[2]);
        deltaImpulse -= deltaVel1Dotn * c.jac;
        deltaImpulse -= deltaVel2Dotn * c.jac;
        const double sum = c.applied + deltaImpulse;
        if (sum < c.lower) {
            deltaImpulse = c.lower - c.applied;
            c.applied = c.lower;
        } else if (sum > c.upper) {
            deltaImpulse = c.upper - c.applied;
            c.applied = c.upper;
        } else {
            c.applied = sum;
        }
        if (A.active) {
            for (int k = 0; k < 3; k++) {
                A.dl[k] += ((c.n1[k] * A.im[k]) * deltaImpulse) * A.lf[k];
                A.da[k] += c.aA[k] * (deltaImpulse * A.af[k]);
            }
        }
        if (B.active) {
            for (int k = 0; k < 3; k++) {
                B.dl[k] += ((c.n2[k] * B.im[k]) * deltaImpulse) * B.lf[k];
                B.da[k] += c.aB[k] * (deltaImpulse * B.af[k]);
            }
        }
        const double residual = deltaImpulse * (1. / c.jac);
        return residual * residual;
    }

    // One iteration on one thread: the joint rows through the packed copies, then the
    // contact rows through Bullet's.
    btScalar packed_iteration(int iteration, const btContactSolverInfo &infoGlobal) {
        btScalar leastSquaresResidual = 0.f;
        PackedBody *bodies = pbodies_.data();
        const size_t n = rows_.size();
        for (size_t j = 0; j < n; j++) {
            PackedRow &c = rows_[j];
            if (!(iteration < c.iters)) continue;
            leastSquaresResidual = btMax(leastSquaresResidual, solve_row(c, bodies));
        }
        if (iteration < infoGlobal.m_numIterations && has_contact_rows()) {
            sync_bodies(true);
            contact_rows(iteration, infoGlobal, leastSquaresResidual);
            sync_bodies(false);
        }
        return leastSquaresResidual;
    }

    void analytics(int iteration, int numBodies, btCollisionObject **bodies, int numManifolds) {
        m_analyticsData.m_numSolverCalls++;
        m_analyticsData.m_numIterationsUsed = iteration + 1;
        m_analyticsData.m_islandId = -2;
        if (numBodies > 0) m_analyticsData.m_islandId = bodies[0]->getCompanionId();
        m_analyticsData.m_numBodies = numBodies;
        m_analyticsData.m_numContactManifolds = numManifolds;
        m_analyticsData.m_remainingLeastSquaresResidual = m_leastSquaresResidual;
    }

    // Segment t's joint rows of one iteration (threaded sweep): before a row, wait until the
    // other segments have done the rows it depends on (deps_); after it, publish progress.
    double run_segment(int t, int iteration) {
        double ls = 0;
        PackedBody *bodies = pbodies_.data();
        const int begin = seg_begin_[t], end = seg_begin_[t + 1];
        const long long base = static_cast<long long>(iteration) * (end - begin);
        std::atomic<long long> &mine = progress_[t].done;
        for (int p = begin; p < end; p++) {
            const RowDep &d = deps_[p];
            if (d.t1 >= 0) wait_for(progress_[d.t1].done, static_cast<long long>(iteration) * seg_len(d.t1) + d.q1);
            if (d.t2 >= 0) wait_for(progress_[d.t2].done, static_cast<long long>(iteration) * seg_len(d.t2) + d.q2);
            PackedRow &c = rows_[p];
            if (iteration < c.iters) ls = btMax(ls, solve_row(c, bodies));
            mine.store(base + (p - begin) + 1, std::memory_order_release);
        }
        return ls;
    }
    int seg_len(int t) const { return seg_begin_[t + 1] - seg_begin_[t]; }

    static void wait_for(const std::atomic<long long> &a, long long target) {
        int spins = 0;
        while (a.load(std::memory_order_acquire) < target) {
            if (++spins < 4096) {
#if defined(__x86_64__) || defined(__i386__)
                __builtin_ia32_pause();
#endif
            } else {
                std::this_thread::yield();
            }
        }
    }

    // Bullet's iteration loop with the joint rows on segments_ threads: per iteration the
    // segments run concurrently (the calling thread runs segment 0), then the calling thread
    // folds their residuals (max: the same value as Bullet's fold in its order, unless a row
    // gives NaN) and runs the contact rows, then decides on the exit as Bullet does.
    int threaded_iterations(int maxIterations, int numBodies, btCollisionObject **bodies, int numManifolds,
                            const btContactSolverInfo &infoGlobal) {
        const int T = segments_;
        for (int t = 0; t < T; t++) progress_[t].done.store(0, std::memory_order_relaxed);
        part_.assign(static_cast<size_t>(T), 0.0);
        SpinBarrier barrier(T);
        std::atomic<int> go{0};  // 1 = run, 2 = abort (a thread could not be started)
        std::atomic<bool> stop{false};
        int iteration_now = 0;
        auto worker = [&](int t) {
            while (go.load(std::memory_order_acquire) == 0) std::this_thread::yield();
            if (go.load(std::memory_order_acquire) == 2) return;
            for (;;) {
                barrier.wait();  // start of an iteration (or the end)
                if (stop.load(std::memory_order_acquire)) return;
                part_[t] = run_segment(t, iteration_now);
                barrier.wait();  // the segment is done
            }
        };
        std::vector<std::thread> pool;
        pool.reserve(static_cast<size_t>(T - 1));
        try {
            for (int t = 1; t < T; t++) pool.emplace_back(worker, t);
        } catch (...) {
            go.store(2, std::memory_order_release);
            for (auto &th : pool) th.join();
            throw;
        }
        go.store(1, std::memory_order_release);
        int used = maxIterations;
        for (int iteration = 0; iteration < maxIterations; iteration++) {
            iteration_now = iteration;
            barrier.wait();
            double ls = run_segment(0, iteration);
            barrier.wait();
            for (int t = 1; t < T; t++) ls = btMax(ls, part_[t]);
            btScalar leastSquaresResidual = ls;
            if (iteration < infoGlobal.m_numIterations && has_contact_rows()) {
                sync_bodies(true);
                contact_rows(iteration, infoGlobal, leastSquaresResidual);
                sync_bodies(false);
            }
            m_leastSquaresResidual = leastSquaresResidual;
            if (m_leastSquaresResidual <= infoGlobal.m_leastSquaresResidualThreshold ||
                (iteration >= (maxIterations - 1))) {
                analytics(iteration, numBodies, bodies, numManifolds);
                used = iteration + 1;
                break;
            }
        }
        stop.store(true, std::memory_order_release);
        barrier.wait();
        for (auto &th : pool) th.join();
        return used;
    }
};

// ---- warm starting of the joints' rows ---------------------------------------------------
//
// Bullet 3.24's btSequentialImpulseConstraintSolver warm-starts contacts (setupContactConstraint:
// m_appliedImpulse = cp.m_appliedImpulse * m_warmstartingFactor, applied to both bodies before
// the first iteration) but not joints: convertJoint sets every row's m_appliedImpulse = 0, so a
// joint row's projected Gauss-Seidel solve starts from zero impulse in every substep, and what
// the iterations do not reach is left as position error (pulled back next substep by the
// Baumgarte velocity ERP*e/h). JointWarmStart keeps the impulse of every row of every
// btGeneric6DofConstraint (D6_CONSTRAINT_TYPE) at the end of a substep, and at the next
// substep's setup starts each row that is still there (same constraint, a row of the same kind
// whose axis has turned by less than ~8 degrees) from factor * that impulse, clamped to the
// row's bounds (the breaking threshold), applied to the two solver bodies exactly as Bullet
// applies a contact's warm start. factor 0 = Bullet's own behaviour.
struct WarmRow {
    btVector3 axis;    // unit linear axis (linear row) or unit angular axis (angular row)
    bool linear = true;
    btScalar impulse = 0;
};
struct WarmRecord {
    long long step = -1;  // substep counter when saved
    std::vector<WarmRow> rows;
};
struct JointWarmStart {
    double factor = 0;
    long long step = 0;  // advanced once per substep (ParallelIslandSolver::allSolved)
    std::vector<WarmRecord> records;  // indexed by btTypedConstraint::getUserConstraintId()
    long long rows_started = 0;       // rows warm-started since the last reset (diagnostics)
};

WarmRow warm_row_of(const btSolverConstraint &c) {
    WarmRow r;
    btScalar ln = c.m_contactNormal1.length();
    r.linear = ln > btScalar(0.5);
    btVector3 a = r.linear ? c.m_contactNormal1 : c.m_relpos1CrossNormal;
    btScalar n = a.length();
    r.axis = n > 0 ? a / n : btVector3(0, 0, 0);
    r.impulse = c.m_appliedImpulse;
    return r;
}

class WarmJointSolver : public LeanSolver {
   public:
    JointWarmStart *warm = nullptr;

   protected:
    void convertJoints(btTypedConstraint **constraints, int numConstraints, const btContactSolverInfo &info) override {
        LeanSolver::convertJoints(constraints, numConstraints, info);
        if (!warm || !(warm->factor > 0)) return;
        const int n = m_tmpSolverNonContactConstraintPool.size();
        int j = 0;
        while (j < n) {
            btSolverConstraint &first = m_tmpSolverNonContactConstraintPool[j];
            auto *t = static_cast<btTypedConstraint *>(first.m_originalContactPoint);
            int k = j;
            while (k < n && m_tmpSolverNonContactConstraintPool[k].m_originalContactPoint == t) ++k;
            int id = t ? t->getUserConstraintId() : -1;
            if (t && t->getConstraintType() == D6_CONSTRAINT_TYPE && id >= 0 &&
                static_cast<size_t>(id) < warm->records.size() && warm->records[id].step == warm->step - 1) {
                const WarmRecord &rec = warm->records[id];
                for (int r = j; r < k; ++r) {
                    btSolverConstraint &c = m_tmpSolverNonContactConstraintPool[r];
                    WarmRow now = warm_row_of(c);
                    // The same row index first (the usual case: the same rows as last substep),
                    // else the best-aligned row of the same kind.
                    const WarmRow *match = nullptr;
                    size_t idx = static_cast<size_t>(r - j);
                    if (idx < rec.rows.size() && rec.rows[idx].linear == now.linear &&
                        rec.rows[idx].axis.dot(now.axis) > btScalar(0.99))
                        match = &rec.rows[idx];
                    else {
                        btScalar best = btScalar(0.99);
                        for (const WarmRow &o : rec.rows) {
                            btScalar d = o.axis.dot(now.axis);
                            if (o.linear == now.linear && d > best) {
                                best = d;
                                match = &o;
                            }
                        }
                    }
                    if (!match) continue;
                    btScalar lambda = btScalar(warm->factor) * match->impulse;
                    lambda = btMax(c.m_lowerLimit, btMin(c.m_upperLimit, lambda));
                    if (lambda == 0) continue;
                    c.m_appliedImpulse = lambda;
                    btSolverBody &a = m_tmpSolverBodyPool[c.m_solverBodyIdA];
                    btSolverBody &b = m_tmpSolverBodyPool[c.m_solverBodyIdB];
                    a.internalApplyImpulse(c.m_contactNormal1 * a.internalGetInvMass(), c.m_angularComponentA, lambda);
                    b.internalApplyImpulse(c.m_contactNormal2 * b.internalGetInvMass(), c.m_angularComponentB, lambda);
                    ++warm->rows_started;
                }
            }
            j = k;
        }
    }

   public:
    // Before solveGroupCacheFriendlyFinish (which clears the pools): keep every D6 row's impulse.
    void save_joint_impulses() {
        if (!warm || !(warm->factor > 0)) return;
        const int n = m_tmpSolverNonContactConstraintPool.size();
        int j = 0;
        while (j < n) {
            auto *t = static_cast<btTypedConstraint *>(m_tmpSolverNonContactConstraintPool[j].m_originalContactPoint);
            int k = j;
            while (k < n && m_tmpSolverNonContactConstraintPool[k].m_originalContactPoint == t) ++k;
            int id = t ? t->getUserConstraintId() : -1;
            if (t && t->getConstraintType() == D6_CONSTRAINT_TYPE && id >= 0) {
                if (static_cast<size_t>(id) >= warm->records.size()) warm->records.resize(static_cast<size_t>(id) + 1);
                WarmRecord &rec = warm->records[id];
                rec.step = warm->step;
                rec.rows.clear();
                for (int r = j; r < k; ++r) rec.rows.push_back(warm_row_of(m_tmpSolverNonContactConstraintPool[r]));
            }
            j = k;
        }
    }
};

// ---- direct solve of the joints' bilateral rows -----------------------------------------
//
// Bullet 3.24's projected Gauss-Seidel row update (btSequentialImpulseConstraintSolver.cpp,
// gResolveSingleConstraintRowGeneric_scalar_reference) is, for a row i between solver bodies
// a and b with D_i = m_jacDiagABInv, C_i = m_cfm (convertJoint keeps the joint's own CFM, not
// multiplied by D_i, unlike a contact's) and the bodies' velocity changes dv so far:
//   dlambda_i = m_rhs_i - lambda_i C_i - D_i (J_i . dv),   J_i = (n1, r1 x n1 | n2, r2 x n2)
// (m_contactNormal1, m_relpos1CrossNormal, m_contactNormal2, m_relpos2CrossNormal), clamped so
// that lambda_i stays in [m_lowerLimit, m_upperLimit], then applied to both bodies by
// btSolverBody::internalApplyImpulse: dv_lin += n * invMass * dlambda * linearFactor and
// dv_ang += m_angularComponent * dlambda * angularFactor, where invMass = 1/m * linearFactor
// (initSolverBody) and m_angularComponentA = I_A^-1 (r1 x n1) * angularFactor_A (convertJoint).
// Its fixed point for the rows that are bilateral (m_lowerLimit < 0 < m_upperLimit) and not
// clamped is the linear system
//   (A + diag(C_i / D_i)) lambda = m_rhs_i / D_i - J_i . dv0,
//   A_ij = sum over the bodies rows i and j share of J_i^b . u_j^b,
//   u_j^b = (n_j^b * invMass_b * linearFactor_b, m_angularComponent_j^b * angularFactor_b),
// the response of body b's velocity to a unit impulse of row j (dynamic bodies only: a static
// or kinematic body has invMass 0 and zero inverse inertia). With uniform angular factors
// (the shim never sets any) A = J M^-1 J^T is symmetric positive semi-definite. The solver
// below assembles it sparse (rows couple only through shared bodies), adds eps * A_ii to its
// diagonal (redundant locked rows in closed frame loops make A singular when C = 0), factors
// it with Eigen's SimplicialLDLT and solves for the increment over the rows' present impulses
// (0 or a warm start) in residual form,
//   (A + diag(C_i/D_i) + eps diag(A_ii)) delta = (m_rhs_i - lambda_i C_i)/D_i - J_i . dv,
// so the result replaces a warm start rather than adding to it. A row whose impulse would
// leave its bounds (its breaking threshold) is held at the bound and the others solved
// again with it (an active set, at most kActivePasses re-solves: the box-constrained
// solution the projected iterations converge to). eps * A_ii on the diagonal is a relative
// CFM of eps on every row (Bullet's joint convention, C_i/D_i with D_i = 1/A_ii): it bounds
// the impulses a geometrically inconsistent right-hand side on redundant rows would
// otherwise drive to ~1/eps (measured on frame3: eps <= 3e-6 breaks the building under
// gravity, 1e-5 and 1e-4 inject energy into the LC5 debris; 1e-3, the default, neither;
// docs/ruin-numerics.md §11.1). Each new impulse is stored as m_appliedImpulse
// and the change applied to both solver bodies as the row update does; Bullet's iterations then run as
// usual from there (contacts, one-sided limit rows, and the clamped rows). If the
// factorisation fails or a result is not finite the substep stays with PGS (a fallback).
// Runs in the batch's set-up on the calling thread; all scratch state is the solver's own.
struct JointDirectSolve {
    int mode = 0;                   // BS_JOINT_SOLVE_PGS or BS_JOINT_SOLVE_DIRECT
    double regularisation = 1e-3;   // eps
    long long solves = 0;           // batches solved directly
    long long fallbacks = 0;        // batches left to PGS (factorisation failed, non-finite)
    long long rows = 0;             // rows solved directly (diagnostics)
};

class DirectJointSolver : public WarmJointSolver {
   public:
    JointDirectSolve *direct = nullptr;

   protected:
    void convertJoints(btTypedConstraint **constraints, int numConstraints, const btContactSolverInfo &info) override {
        WarmJointSolver::convertJoints(constraints, numConstraints, info);
        if (direct && direct->mode == BS_JOINT_SOLVE_DIRECT) direct_solve();
    }

   private:
    struct Side {
        int body = -1;  // solver body, -1: no response (static, kinematic)
        btVector3 jl, ja, ul, ua;
    };
    std::vector<int> rows_;                  // pool index of each bilateral row
    std::vector<Side> sides_;                // 2 per row (A, B)
    std::vector<std::vector<int>> touching_; // per solver body: 2 * local row + side
    std::vector<Eigen::Triplet<double>> trip_;
    Eigen::SparseMatrix<double> m_;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt_;
    Eigen::VectorXd rhs_, delta_, rhs2_;
    std::vector<Eigen::Triplet<double>> trip2_;
    std::vector<char> fixed_;
    std::vector<double> dfix_;
    static constexpr int kActivePasses = 8;
    int pattern_n_ = -1;  // the pattern ldlt_'s analysis belongs to
    std::vector<int> pattern_outer_, pattern_inner_;

    bool responds(const btSolverBody &b) const {
        return b.m_originalBody && b.m_originalBody->getInvMass() > 0;
    }

    void direct_solve() {
        const int n = m_tmpSolverNonContactConstraintPool.size();
        const int nb = m_tmpSolverBodyPool.size();
        rows_.clear();
        for (int r = 0; r < n; ++r) {
            const btSolverConstraint &c = m_tmpSolverNonContactConstraintPool[r];
            if (!(c.m_lowerLimit < 0 && c.m_upperLimit > 0)) continue;  // one-sided: PGS
            if (!(std::isfinite(c.m_jacDiagABInv) && c.m_jacDiagABInv > 0)) continue;
            if (!responds(m_tmpSolverBodyPool[c.m_solverBodyIdA]) && !responds(m_tmpSolverBodyPool[c.m_solverBodyIdB]))
                continue;
            rows_.push_back(r);
        }
        const int m = static_cast<int>(rows_.size());
        if (m == 0) return;
        if (static_cast<int>(touching_.size()) < nb) touching_.resize(static_cast<size_t>(nb));
        for (int b = 0; b < nb; ++b) touching_[b].clear();
        sides_.assign(static_cast<size_t>(2 * m), Side());
        for (int p = 0; p < m; ++p) {
            const btSolverConstraint &c = m_tmpSolverNonContactConstraintPool[rows_[p]];
            for (int s = 0; s < 2; ++s) {
                const int id = s == 0 ? c.m_solverBodyIdA : c.m_solverBodyIdB;
                const btSolverBody &b = m_tmpSolverBodyPool[id];
                if (!responds(b)) continue;
                // internalApplyImpulse multiplies the angular response by the body's angular
                // factor elementwise: A stays symmetric only for a uniform factor.
                if (!(b.m_angularFactor.x() == b.m_angularFactor.y() && b.m_angularFactor.y() == b.m_angularFactor.z())) {
                    direct->fallbacks += 1;
                    return;
                }
                Side &sd = sides_[static_cast<size_t>(2 * p + s)];
                sd.body = id;
                sd.jl = s == 0 ? c.m_contactNormal1 : c.m_contactNormal2;
                sd.ja = s == 0 ? c.m_relpos1CrossNormal : c.m_relpos2CrossNormal;
                sd.ul = sd.jl * b.internalGetInvMass() * b.m_linearFactor;
                sd.ua = (s == 0 ? c.m_angularComponentA : c.m_angularComponentB) * b.m_angularFactor;
                touching_[id].push_back(2 * p + s);
            }
        }
        // Lower triangle, in row order then side order (A, B) of the later row, so the sums
        // do not depend on the solver bodies' numbering.
        trip_.clear();
        rhs_.resize(m);
        const double eps = direct->regularisation;
        for (int p = 0; p < m; ++p) {
            const btSolverConstraint &c = m_tmpSolverNonContactConstraintPool[rows_[p]];
            double diag = 0;
            for (int s = 0; s < 2; ++s) {
                const Side &sp = sides_[static_cast<size_t>(2 * p + s)];
                if (sp.body < 0) continue;
                for (int e : touching_[sp.body]) {
                    const int q = e / 2;
                    if (q > p) break;  // touching_ lists are in row order
                    const Side &sq = sides_[static_cast<size_t>(e)];
                    const double v = sp.jl.dot(sq.ul) + sp.ja.dot(sq.ua);
                    trip_.emplace_back(p, q, v);
                    if (q == p && e == 2 * p + s) diag += v;
                }
            }
            const double d = c.m_jacDiagABInv;
            trip_.emplace_back(p, p, c.m_cfm / d + eps * diag);
            const btSolverBody &a = m_tmpSolverBodyPool[c.m_solverBodyIdA];
            const btSolverBody &b = m_tmpSolverBodyPool[c.m_solverBodyIdB];
            const double jdv = c.m_contactNormal1.dot(a.m_deltaLinearVelocity) +
                               c.m_relpos1CrossNormal.dot(a.m_deltaAngularVelocity) +
                               c.m_contactNormal2.dot(b.m_deltaLinearVelocity) +
                               c.m_relpos2CrossNormal.dot(b.m_deltaAngularVelocity);
            rhs_[p] = (c.m_rhs - c.m_appliedImpulse * c.m_cfm) / d - jdv;
        }
        m_.resize(m, m);
        m_.setFromTriplets(trip_.begin(), trip_.end());
        // The fill-reducing ordering and the symbolic factorisation depend on the pattern
        // only: kept while the rows' pattern is that of the last substep's first solve.
        const int nnz = static_cast<int>(m_.nonZeros());
        const bool same = m == pattern_n_ && pattern_outer_.size() == static_cast<size_t>(m + 1) &&
                          std::equal(pattern_outer_.begin(), pattern_outer_.end(), m_.outerIndexPtr()) &&
                          pattern_inner_.size() == static_cast<size_t>(nnz) &&
                          std::equal(pattern_inner_.begin(), pattern_inner_.end(), m_.innerIndexPtr());
        if (!same) {
            ldlt_.analyzePattern(m_);
            pattern_n_ = m;
            pattern_outer_.assign(m_.outerIndexPtr(), m_.outerIndexPtr() + m + 1);
            pattern_inner_.assign(m_.innerIndexPtr(), m_.innerIndexPtr() + nnz);
        }
        ldlt_.factorize(m_);
        if (ldlt_.info() != Eigen::Success) {
            direct->fallbacks += 1;
            return;
        }
        delta_ = ldlt_.solve(rhs_);
        if (ldlt_.info() != Eigen::Success) {
            direct->fallbacks += 1;
            return;
        }
        // Active set: a row whose new impulse would leave its bounds is held at the bound
        // and the other rows are solved again with it (the box-constrained solution the
        // projected iterations converge to), at most kActivePasses times.
        fixed_.assign(static_cast<size_t>(m), 0);
        dfix_.assign(static_cast<size_t>(m), 0.0);
        for (int pass = 0; pass < kActivePasses; ++pass) {
            for (int p = 0; p < m; ++p)
                if (!std::isfinite(delta_[p])) {
                    direct->fallbacks += 1;
                    return;
                }
            int added = 0;
            for (int p = 0; p < m; ++p) {
                if (fixed_[p]) continue;
                const btSolverConstraint &c = m_tmpSolverNonContactConstraintPool[rows_[p]];
                const double t = c.m_appliedImpulse + delta_[p];
                if (t < c.m_lowerLimit || t > c.m_upperLimit) {
                    fixed_[p] = 1;
                    dfix_[p] = (t < c.m_lowerLimit ? c.m_lowerLimit : c.m_upperLimit) - c.m_appliedImpulse;
                    ++added;
                }
            }
            if (added == 0) break;
            // The reduced system: the held rows' known increments move to the right-hand
            // side (each stored entry (p, q), p >= q, stands for (p, q) and (q, p)); a held
            // row's own equation becomes delta_p = its increment to the bound.
            trip2_.clear();
            rhs2_ = rhs_;
            for (const auto &t : trip_) {
                const int p = t.row(), q = t.col();
                const bool fp = fixed_[p], fq = fixed_[q];
                if (!fp && !fq)
                    trip2_.push_back(t);
                else {
                    // An explicit zero keeps the pattern, hence the kept analysis.
                    trip2_.emplace_back(p, q, 0.0);
                    if (p != q) {
                        if (!fp) rhs2_[p] -= t.value() * dfix_[q];
                        if (!fq) rhs2_[q] -= t.value() * dfix_[p];
                    }
                }
            }
            for (int p = 0; p < m; ++p)
                if (fixed_[p]) {
                    trip2_.emplace_back(p, p, 1.0);
                    rhs2_[p] = dfix_[p];
                }
            m_.setFromTriplets(trip2_.begin(), trip2_.end());
            ldlt_.factorize(m_);
            if (ldlt_.info() != Eigen::Success) {
                direct->fallbacks += 1;
                return;
            }
            delta_ = ldlt_.solve(rhs2_);
        }
        for (int p = 0; p < m; ++p)
            if (!std::isfinite(delta_[p])) {
                direct->fallbacks += 1;
                return;
            }
        for (int p = 0; p < m; ++p) {
            btSolverConstraint &c = m_tmpSolverNonContactConstraintPool[rows_[p]];
            const btScalar old = c.m_appliedImpulse;
            const btScalar lambda = btMax(c.m_lowerLimit, btMin(c.m_upperLimit, old + btScalar(delta_[p])));
            const btScalar dl = lambda - old;
            c.m_appliedImpulse = lambda;
            if (dl == 0) continue;
            btSolverBody &a = m_tmpSolverBodyPool[c.m_solverBodyIdA];
            btSolverBody &b = m_tmpSolverBodyPool[c.m_solverBodyIdB];
            a.internalApplyImpulse(c.m_contactNormal1 * a.internalGetInvMass(), c.m_angularComponentA, dl);
            b.internalApplyImpulse(c.m_contactNormal2 * b.internalGetInvMass(), c.m_angularComponentB, dl);
        }
        direct->solves += 1;
        direct->rows += m;
    }
};

// ---- island-parallel solving -------------------------------------------------------------
//
// btDiscreteDynamicsWorld::solveConstraints hands the solver one batch of islands at a time
// (solveGroup: islands merged until they hold more than m_minimumSolverBatchSize constraints
// and manifolds), between prepareSolve() and allSolved(). Batches share no dynamic body, no
// manifold and no constraint; they share only static and kinematic bodies, which the solver
// reads but never changes (infinite mass: their solver bodies take no impulse).
//
// In Debian's build (no BT_THREADSAFE) a kinematic body gets its solver-body index through
// btCollisionObject::setCompanionId, which solveSingleIteration reads back on every iteration
// (getOrInitSolverBody for each enabled joint). To give every batch the same index for the
// same kinematic body, each batch's body list starts with all kinematic bodies of the world,
// in world order: they become solver bodies 0..K-1 in every batch, and the companion id any
// thread reads is the same number. The arithmetic is unchanged (a solver body's index enters
// no sum; each row's impulses are computed in the same order).
//
// Phase order: setup of every batch (in batch order, calling thread), the iterations of the
// batches on up to n threads (a batch is one task; the assignment does not matter, the
// batches are independent), then the finish of every batch in batch order (write-back of
// velocities, contact and joint impulses, joint feedback, breaking).
class JobSolver : public DirectJointSolver {
   public:
    btScalar setup(btCollisionObject **b, int nb, btPersistentManifold **m, int nm, btTypedConstraint **c, int nc,
                   const btContactSolverInfo &info, btIDebugDraw *dd) {
        return solveGroupCacheFriendlySetup(b, nb, m, nm, c, nc, info, dd);
    }
    btScalar iterate(btCollisionObject **b, int nb, btPersistentManifold **m, int nm, btTypedConstraint **c, int nc,
                     const btContactSolverInfo &info, btIDebugDraw *dd) {
        return solveGroupCacheFriendlyIterations(b, nb, m, nm, c, nc, info, dd);
    }
    btScalar finish(btCollisionObject **b, int nb, const btContactSolverInfo &info) {
        return solveGroupCacheFriendlyFinish(b, nb, info);
    }
    long long rows() const {
        return static_cast<long long>(m_tmpSolverContactConstraintPool.size()) +
               m_tmpSolverNonContactConstraintPool.size() + m_tmpSolverContactFrictionConstraintPool.size() +
               m_tmpSolverContactRollingFrictionConstraintPool.size();
    }
};

struct SolverJob {
    std::vector<btCollisionObject *> bodies;
    std::vector<btPersistentManifold *> manifolds;
    std::vector<btTypedConstraint *> constraints;
    long long rows = 0;
};

class ParallelIslandSolver : public DirectJointSolver {
   public:
    int threads = 1;
    std::vector<btCollisionObject *> kinematic;  // set by the world before each step
    bs_island_stats stats{};
    long long parallel_setups = 0;  // joint set-ups of batches run on the solver threads
    long long parallel_sweeps = 0;  // packed sweeps of batches run on the solver threads
    ThreadChooser setup_chooser;  // shared by the batches' solvers

    void prepareSolve(int a, int b) override {
        btSequentialImpulseConstraintSolver::prepareSolve(a, b);
        njobs_ = 0;
        largest_ = 0;
    }

    btScalar solveGroup(btCollisionObject **bodies, int numBodies, btPersistentManifold **manifolds, int numManifolds,
                        btTypedConstraint **constraints, int numConstraints, const btContactSolverInfo &info,
                        btIDebugDraw *dd, btDispatcher *dispatcher) override {
        if (threads <= 1 || info.m_splitImpulse) {
            // Bullet's own sequential path (btSequentialImpulseConstraintSolver::solveGroup).
            BT_PROFILE("solveGroup");
            solveGroupCacheFriendlySetup(bodies, numBodies, manifolds, numManifolds, constraints, numConstraints, info, dd);
            long long rows = static_cast<long long>(m_tmpSolverContactConstraintPool.size()) +
                             m_tmpSolverNonContactConstraintPool.size() +
                             m_tmpSolverContactFrictionConstraintPool.size() +
                             m_tmpSolverContactRollingFrictionConstraintPool.size();
            count(rows, numBodies);
            solveGroupCacheFriendlyIterations(bodies, numBodies, manifolds, numManifolds, constraints, numConstraints, info, dd);
            save_joint_impulses();
            solveGroupCacheFriendlyFinish(bodies, numBodies, info);
            (void)dispatcher;
            return 0;
        }
        if (jobs_.size() <= njobs_) jobs_.emplace_back();
        SolverJob &j = jobs_[njobs_++];
        j.bodies.assign(kinematic.begin(), kinematic.end());
        j.bodies.insert(j.bodies.end(), bodies, bodies + numBodies);
        j.manifolds.assign(manifolds, manifolds + numManifolds);
        j.constraints.assign(constraints, constraints + numConstraints);
        awake_ += numBodies;
        return 0;
    }

    void allSolved(const btContactSolverInfo &info, btIDebugDraw *dd) override {
        if (njobs_ > 0) run_jobs(info, dd);
        stats.substeps += 1;
        if (warm) warm->step += 1;
        stats.rows_largest += largest_;
        stats.bodies_awake += awake_;
        awake_ = 0;
        btSequentialImpulseConstraintSolver::allSolved(info, dd);
    }

   private:
    std::vector<SolverJob> jobs_;
    std::vector<std::unique_ptr<JobSolver>> solvers_;
    size_t njobs_ = 0;
    long long largest_ = 0;
    long long awake_ = 0;

    void count(long long rows, int bodies) {
        stats.batches += 1;
        stats.rows_total += rows;
        largest_ = std::max(largest_, rows);
        awake_ += bodies;
    }

    static btCollisionObject **ptr(std::vector<btCollisionObject *> &v) { return v.empty() ? nullptr : v.data(); }
    static btPersistentManifold **ptr(std::vector<btPersistentManifold *> &v) { return v.empty() ? nullptr : v.data(); }
    static btTypedConstraint **ptr(std::vector<btTypedConstraint *> &v) { return v.empty() ? nullptr : v.data(); }

    void run_jobs(const btContactSolverInfo &info, btIDebugDraw *dd) {
        const size_t n = njobs_;
        while (solvers_.size() < n) solvers_.emplace_back(new JobSolver());
        for (size_t i = 0; i < n; ++i) {
            solvers_[i]->sweep = sweep;
            solvers_[i]->setup_threads = threads;
            solvers_[i]->parallel_setups = &parallel_setups;
            setup_chooser.always = sweep == SWEEP_PACKED_THREADS;
            solvers_[i]->setup_chooser = &setup_chooser;
        }
        {
            BT_PROFILE("parallelSolverSetup");
            for (size_t i = 0; i < n; ++i) {
                SolverJob &j = jobs_[i];
                solvers_[i]->warm = warm;
                solvers_[i]->direct = direct;
                solvers_[i]->setup(ptr(j.bodies), static_cast<int>(j.bodies.size()), ptr(j.manifolds),
                                   static_cast<int>(j.manifolds.size()), ptr(j.constraints),
                                   static_cast<int>(j.constraints.size()), info, dd);
                j.rows = solvers_[i]->rows();
                stats.batches += 1;
                stats.rows_total += j.rows;
                largest_ = std::max(largest_, j.rows);
            }
            // A batch with most of the substep's rows (an intact building is one island)
            // runs its own sweep on the threads; the others take one thread each.
            long long total = 0;
            for (size_t i = 0; i < n; ++i) total += jobs_[i].rows;
            for (size_t i = 0; i < n; ++i) {
                solvers_[i]->sweep_threads = 2 * jobs_[i].rows > total ? threads : 1;
                solvers_[i]->parallel_sweeps = &parallel_sweeps;
            }
        }
        {
            BT_PROFILE("parallelSolverIterations");
            // Largest batches first (longest-processing-time order); any order gives the same
            // bytes.
            std::vector<size_t> order(n);
            for (size_t i = 0; i < n; ++i) order[i] = i;
            std::stable_sort(order.begin(), order.end(),
                             [&](size_t a, size_t b) { return jobs_[a].rows > jobs_[b].rows; });
            // One batch per work item, handed out in that order (parallel_chunks: the
            // first exception of any thread is rethrown here after all have stopped).
            parallel_chunks(static_cast<int>(n), threads, 1, [&](int b, int e) {
                for (int k = b; k < e; ++k) {
                    SolverJob &j = jobs_[order[k]];
                    solvers_[order[k]]->iterate(ptr(j.bodies), static_cast<int>(j.bodies.size()), ptr(j.manifolds),
                                                static_cast<int>(j.manifolds.size()), ptr(j.constraints),
                                                static_cast<int>(j.constraints.size()), info, dd);
                }
            });
        }
        {
            BT_PROFILE("parallelSolverFinish");
            for (size_t i = 0; i < n; ++i) {
                SolverJob &j = jobs_[i];
                solvers_[i]->save_joint_impulses();
                solvers_[i]->finish(ptr(j.bodies), static_cast<int>(j.bodies.size()), info);
            }
        }
        njobs_ = 0;
    }
};

// ---- phase timing through BT_PROFILE -----------------------------------------------------
struct ZoneStat {
    double seconds = 0;
    long long calls = 0;
    int depth = 0;
    size_t first = 0;  // order of first appearance
};
struct ProfileRecord {
    bool on = false;
    std::vector<std::pair<const char *, std::chrono::steady_clock::time_point>> stack;
    std::unordered_map<const char *, ZoneStat> zones;
};
thread_local ProfileRecord t_profile;

void profile_enter(const char *name) {
    ProfileRecord &p = t_profile;
    if (!p.on) return;
    p.stack.emplace_back(name, std::chrono::steady_clock::now());
}
void profile_leave() {
    ProfileRecord &p = t_profile;
    if (!p.on || p.stack.empty()) return;
    auto top = p.stack.back();
    p.stack.pop_back();
    double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - top.second).count();
    auto it = p.zones.find(top.first);
    if (it == p.zones.end()) {
        ZoneStat z;
        z.depth = static_cast<int>(p.stack.size());
        z.first = p.zones.size();
        it = p.zones.emplace(top.first, z).first;
    }
    it->second.seconds += dt;
    it->second.calls += 1;
}

}  // namespace

struct bs_world {
    // Declaration order = construction order; destruction runs in reverse, but the
    // destructor below removes constraints and bodies from the world explicitly first.
    std::unique_ptr<btDefaultCollisionConfiguration> config;
    std::unique_ptr<btCollisionDispatcher> dispatcher;
    std::unique_ptr<btDbvtBroadphase> broadphase;
    std::unique_ptr<ParallelIslandSolver> solver;          // null in a stock world
    std::unique_ptr<btSequentialImpulseConstraintSolver> stock_solver;  // only in a stock world
    std::unique_ptr<btDiscreteDynamicsWorld> world;
    JointWarmStart warm;
    JointDirectSolve direct;
    std::vector<Body> bodies;
    std::vector<std::unique_ptr<Constraint>> constraints;  // stable addresses for feedback

    ~bs_world() {
        if (world) {
            for (auto it = constraints.rbegin(); it != constraints.rend(); ++it)
                world->removeConstraint((*it)->constraint.get());
            for (auto it = bodies.rbegin(); it != bodies.rend(); ++it)
                world->removeRigidBody(it->body.get());
        }
        constraints.clear();
        bodies.clear();
        world.reset();
        solver.reset();
        stock_solver.reset();
        broadphase.reset();
        dispatcher.reset();
        config.reset();
    }
};

namespace {

// Runs before every substep's solve (after Bullet has derived kinematic velocities).
void pre_tick(btDynamicsWorld *dw, btScalar) {
    auto *w = static_cast<bs_world *>(dw->getWorldUserInfo());
    for (auto &c : w->constraints) zero_feedback(c->feedback);
    for (auto &b : w->bodies) {
        if (b.kind == BS_KINEMATIC && b.has_kinematic_velocity) {
            b.body->setLinearVelocity(b.kinematic_linear);
            b.body->setAngularVelocity(b.kinematic_angular);
            b.has_kinematic_velocity = false;
        }
    }
}

int check_world(const bs_world *w) {
    if (!w) return fail(BS_ERR_NULL, "null world");
    return BS_OK;
}
int check_body(const bs_world *w, int i) {
    if (!w) return fail(BS_ERR_NULL, "null world");
    if (i < 0 || static_cast<size_t>(i) >= w->bodies.size())
        return fail(BS_ERR_BAD_INDEX, "body index " + std::to_string(i) + " out of range");
    return BS_OK;
}
// The shim's solver (ParallelIslandSolver) of w, or BS_ERR_STOCK naming `what` for a stock world.
int check_shim_solver(const bs_world *w, const char *what) {
    if (!w) return fail(BS_ERR_NULL, "null world");
    if (!w->solver) return fail(BS_ERR_STOCK, std::string(what) + " is a feature of the shim's solver; a stock world has none");
    return BS_OK;
}

int check_constraint(const bs_world *w, int i) {
    if (!w) return fail(BS_ERR_NULL, "null world");
    if (i < 0 || static_cast<size_t>(i) >= w->constraints.size())
        return fail(BS_ERR_BAD_INDEX, "constraint index " + std::to_string(i) + " out of range");
    return BS_OK;
}

void params_from_info(const btContactSolverInfo &s, bs_solver_params *p) {
    p->num_iterations = s.m_numIterations;
    p->erp = s.m_erp;
    p->erp2 = s.m_erp2;
    p->friction_erp = s.m_frictionERP;
    p->global_cfm = s.m_globalCfm;
    p->linear_slop = s.m_linearSlop;
    p->split_impulse = s.m_splitImpulse;
    p->split_impulse_penetration_threshold = s.m_splitImpulsePenetrationThreshold;
    p->split_impulse_turn_erp = s.m_splitImpulseTurnErp;
    p->solver_mode = s.m_solverMode;
    p->warmstarting_factor = s.m_warmstartingFactor;
    p->least_squares_residual_threshold = s.m_leastSquaresResidualThreshold;
    p->minimum_solver_batch_size = s.m_minimumSolverBatchSize;
    p->restitution_velocity_threshold = s.m_restitutionVelocityThreshold;
    p->max_error_reduction = s.m_maxErrorReduction;
    p->sor = s.m_sor;
    p->damping = s.m_damping;
}

}  // namespace

extern "C" {

int bs_sizeof_scalar(void) { return static_cast<int>(sizeof(btScalar)); }

int bs_bullet_version(void) { return btGetVersion(); }

// The btBoxShape constructor and setMargin run inside libBulletCollision; the getters are
// inline and read the fields with *our* btScalar layout. If the library was built with a
// different btScalar, the values read back are wrong (measured: 0 with float libraries).
int bs_abi_self_check(void) {
    try {
        btBoxShape s(btVector3(1, 2, 3));
        btVector3 he = s.getHalfExtentsWithMargin();
        bool ok = s.getMargin() == btScalar(0.04) && he.x() == 1 && he.y() == 2 && he.z() == 3;
        s.setMargin(btScalar(0.25));
        btVector3 inner = s.getHalfExtentsWithoutMargin();
        ok = ok && s.getMargin() == btScalar(0.25) && inner.x() == 0.75 && inner.y() == 1.75 &&
             inner.z() == 2.75;
        btVector3 inertia;
        s.calculateLocalInertia(btScalar(12), inertia);  // m/12 (4 hy² + 4 hz²) etc.
        ok = ok && inertia.x() == 4 * (4 + 9) && inertia.y() == 4 * (1 + 9) && inertia.z() == 4 * (1 + 4);
        return (ok && sizeof(btScalar) == 8) ? 1 : 0;
    } catch (...) {
        return 0;
    }
}

const char *bs_last_error(void) { return g_last_error.c_str(); }

int bs_set_global_dbvt_margin(double margin) {
    if (!(std::isfinite(margin) && margin >= 0)) return fail(BS_ERR_BAD_ARG, "dbvt margin must be finite and >= 0");
    gDbvtMargin = margin;
    return BS_OK;
}
double bs_get_global_dbvt_margin(void) { return gDbvtMargin; }
int bs_set_global_contact_breaking_threshold(double value) {
    if (!(std::isfinite(value) && value > 0))
        return fail(BS_ERR_BAD_ARG, "contact breaking threshold must be finite and > 0");
    gContactBreakingThreshold = value;
    return BS_OK;
}
double bs_get_global_contact_breaking_threshold(void) { return gContactBreakingThreshold; }

namespace {
// Creates the world with the shim's solver (stock = false) or with Bullet's stock
// btSequentialImpulseConstraintSolver (stock = true).
int world_new(const double gravity[3], bs_world **out, bool stock) {
    return guard([&]() -> int {
        if (!gravity || !out) return fail(BS_ERR_NULL, "null argument to bs_world_new");
        *out = nullptr;
        if (!finite3(gravity)) return fail(BS_ERR_BAD_ARG, "gravity has a non-finite component");
        if (!bs_abi_self_check())
            return fail(BS_ERR_ABI, "Bullet ABI self-check failed: libBullet was built with a different btScalar than the shim (use bullet-float64)");
        std::unique_ptr<bs_world> w(new bs_world());
        w->config.reset(new btDefaultCollisionConfiguration());
        w->dispatcher.reset(new btCollisionDispatcher(w->config.get()));
        w->broadphase.reset(new btDbvtBroadphase());
        btConstraintSolver *solver = nullptr;
        if (stock) {
            w->stock_solver.reset(new btSequentialImpulseConstraintSolver());
            solver = w->stock_solver.get();
        } else {
            w->solver.reset(new ParallelIslandSolver());
            w->solver->warm = &w->warm;
            w->solver->direct = &w->direct;
            solver = w->solver.get();
        }
        w->world.reset(new btDiscreteDynamicsWorld(w->dispatcher.get(), w->broadphase.get(), solver, w->config.get()));
        w->world->setGravity(vec(gravity));
        w->world->setInternalTickCallback(pre_tick, w.get(), true);
        *out = w.release();
        return BS_OK;
    });
}
}  // namespace

int bs_world_new(const double gravity[3], bs_world **out) { return world_new(gravity, out, false); }

int bs_world_new_stock(const double gravity[3], bs_world **out) { return world_new(gravity, out, true); }

int bs_world_is_stock(const bs_world *w) {
    if (!w) return BS_ERR_NULL;
    return w->solver ? 0 : 1;
}

void bs_world_free(bs_world *w) {
    try {
        delete w;
    } catch (...) {
        // Nothing sensible to do; never let an exception cross the C boundary.
    }
}

int bs_world_set_gravity(bs_world *w, const double gravity[3]) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (!gravity) return fail(BS_ERR_NULL, "null gravity");
        if (!finite3(gravity)) return fail(BS_ERR_BAD_ARG, "gravity has a non-finite component");
        w->world->setGravity(vec(gravity));
        return BS_OK;
    });
}

int bs_world_get_gravity(const bs_world *w, double gravity[3]) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (!gravity) return fail(BS_ERR_NULL, "null gravity");
        put(w->world->getGravity(), gravity);
        return BS_OK;
    });
}

int bs_world_default_solver_params(bs_solver_params *out) {
    return guard([&]() -> int {
        if (!out) return fail(BS_ERR_NULL, "null params");
        btContactSolverInfo info;
        params_from_info(info, out);
        return BS_OK;
    });
}

int bs_world_set_solver_params(bs_world *w, const bs_solver_params *p) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (!p) return fail(BS_ERR_NULL, "null params");
        const double reals[] = {p->erp, p->erp2, p->friction_erp, p->global_cfm, p->linear_slop,
                                p->split_impulse_penetration_threshold, p->split_impulse_turn_erp,
                                p->warmstarting_factor, p->least_squares_residual_threshold,
                                p->restitution_velocity_threshold, p->max_error_reduction, p->sor, p->damping};
        for (double r : reals)
            if (!std::isfinite(r)) return fail(BS_ERR_BAD_ARG, "a solver parameter is not finite");
        if (p->num_iterations < 1) return fail(BS_ERR_BAD_ARG, "num_iterations must be >= 1");
        if (p->minimum_solver_batch_size < 0) return fail(BS_ERR_BAD_ARG, "minimum_solver_batch_size must be >= 0");
        btContactSolverInfo &s = w->world->getSolverInfo();
        s.m_numIterations = p->num_iterations;
        s.m_erp = p->erp;
        s.m_erp2 = p->erp2;
        s.m_frictionERP = p->friction_erp;
        s.m_globalCfm = p->global_cfm;
        s.m_linearSlop = p->linear_slop;
        s.m_splitImpulse = p->split_impulse;
        s.m_splitImpulsePenetrationThreshold = p->split_impulse_penetration_threshold;
        s.m_splitImpulseTurnErp = p->split_impulse_turn_erp;
        s.m_solverMode = p->solver_mode;
        s.m_warmstartingFactor = p->warmstarting_factor;
        s.m_leastSquaresResidualThreshold = p->least_squares_residual_threshold;
        s.m_minimumSolverBatchSize = p->minimum_solver_batch_size;
        s.m_restitutionVelocityThreshold = p->restitution_velocity_threshold;
        s.m_maxErrorReduction = p->max_error_reduction;
        s.m_sor = p->sor;
        s.m_damping = p->damping;
        return BS_OK;
    });
}

int bs_world_get_solver_params(const bs_world *w, bs_solver_params *out) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (!out) return fail(BS_ERR_NULL, "null params");
        params_from_info(w->world->getSolverInfo(), out);
        return BS_OK;
    });
}

int bs_world_step(bs_world *w, double h, int count) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (!(std::isfinite(h) && h > 1e-12)) return fail(BS_ERR_BAD_ARG, "substep must be finite and > 1e-12 s");
        if (count < 0) return fail(BS_ERR_BAD_ARG, "negative step count");
        for (int i = 0; i < count; ++i) {
            // maxSubSteps = 0: Bullet's variable-step mode runs exactly one step of h.
            int n = w->world->stepSimulation(h, 0);
            if (n != 1) return fail(BS_ERR_EXCEPTION, "stepSimulation did not run exactly one substep");
        }
        return BS_OK;
    });
}

int bs_world_num_bodies(const bs_world *w) { return w ? static_cast<int>(w->bodies.size()) : 0; }
int bs_world_num_constraints(const bs_world *w) { return w ? static_cast<int>(w->constraints.size()) : 0; }

int bs_world_contact_pairs(const bs_world *w, bs_contact_pair *out, int capacity, int *total) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (!total || (capacity > 0 && !out)) return fail(BS_ERR_NULL, "null output");
        btDispatcher *d = w->world->getDispatcher();
        int n = d->getNumManifolds();
        int count = 0;
        for (int i = 0; i < n; ++i) {
            const btPersistentManifold *m = d->getManifoldByIndexInternal(i);
            int np = m->getNumContacts();
            if (np == 0) continue;
            int a = m->getBody0()->getUserIndex();
            int b = m->getBody1()->getUserIndex();
            if (a > b) std::swap(a, b);
            double dmin = INFINITY, imp = 0;
            for (int k = 0; k < np; ++k) {
                const btManifoldPoint &pt = m->getContactPoint(k);
                if (pt.getDistance() < dmin) dmin = pt.getDistance();
                imp += pt.getAppliedImpulse();
            }
            if (count < capacity) out[count] = bs_contact_pair{a, b, np, dmin, imp};
            ++count;
        }
        *total = count;
        return BS_OK;
    });
}

int bs_world_get_poses(const bs_world *w, int n, double *positions, double *orientations) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (n != static_cast<int>(w->bodies.size()))
            return fail(BS_ERR_BAD_ARG, "bulk pose read: n = " + std::to_string(n) + " but the world has " + std::to_string(w->bodies.size()) + " bodies");
        if (n > 0 && (!positions || !orientations)) return fail(BS_ERR_NULL, "null output");
        for (int i = 0; i < n; ++i) {
            const btTransform &t = w->bodies[i].body->getWorldTransform();
            put(t.getOrigin(), positions + 3 * i);
            put_quat(t.getRotation(), orientations + 4 * i);
        }
        return BS_OK;
    });
}

int bs_world_get_velocities(const bs_world *w, int n, double *linear, double *angular) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (n != static_cast<int>(w->bodies.size()))
            return fail(BS_ERR_BAD_ARG, "bulk velocity read: n = " + std::to_string(n) + " but the world has " + std::to_string(w->bodies.size()) + " bodies");
        if (n > 0 && (!linear || !angular)) return fail(BS_ERR_NULL, "null output");
        for (int i = 0; i < n; ++i) {
            put(w->bodies[i].body->getLinearVelocity(), linear + 3 * i);
            put(w->bodies[i].body->getAngularVelocity(), angular + 3 * i);
        }
        return BS_OK;
    });
}

int bs_world_get_enabled(const bs_world *w, int n, int *enabled) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (n != static_cast<int>(w->constraints.size()))
            return fail(BS_ERR_BAD_ARG, "bulk enabled read: n = " + std::to_string(n) + " but the world has " + std::to_string(w->constraints.size()) + " constraints");
        if (n > 0 && !enabled) return fail(BS_ERR_NULL, "null output");
        for (int i = 0; i < n; ++i) enabled[i] = w->constraints[i]->constraint->isEnabled() ? 1 : 0;
        return BS_OK;
    });
}

int bs_body_add_box(bs_world *w, const bs_body_desc *d, int *out_index) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (!d || !out_index) return fail(BS_ERR_NULL, "null argument to bs_body_add_box");
        if (d->kind != BS_STATIC && d->kind != BS_KINEMATIC && d->kind != BS_DYNAMIC)
            return fail(BS_ERR_BAD_ARG, "unknown body kind " + std::to_string(d->kind));
        if (!finite3(d->half_extents) || !(d->half_extents[0] > 0 && d->half_extents[1] > 0 && d->half_extents[2] > 0))
            return fail(BS_ERR_BAD_ARG, "half extents must be finite and > 0");
        double hmin = std::min(d->half_extents[0], std::min(d->half_extents[1], d->half_extents[2]));
        if (!(std::isfinite(d->margin) && d->margin >= 0 && d->margin <= hmin))
            return fail(BS_ERR_BAD_ARG, "margin must be finite, >= 0 and <= the smallest half extent");
        if (!std::isfinite(d->mass)) return fail(BS_ERR_BAD_ARG, "mass is not finite");
        if (d->kind == BS_DYNAMIC && !(d->mass > 0)) return fail(BS_ERR_BAD_ARG, "a dynamic body needs mass > 0");
        if (d->kind != BS_DYNAMIC && d->mass != 0) return fail(BS_ERR_BAD_ARG, "a static or kinematic body needs mass 0");
        if (!finite3(d->position) || !finite3(d->linear_velocity) || !finite3(d->angular_velocity))
            return fail(BS_ERR_BAD_ARG, "position or velocity has a non-finite component");
        const double props[] = {d->friction, d->rolling_friction, d->spinning_friction, d->restitution,
                                d->linear_damping, d->angular_damping};
        for (double p : props)
            if (!(std::isfinite(p) && p >= 0)) return fail(BS_ERR_BAD_ARG, "friction, restitution and damping must be finite and >= 0");
        if (d->linear_damping > 1 || d->angular_damping > 1) return fail(BS_ERR_BAD_ARG, "damping must be <= 1");
        btQuaternion q;
        if (int e = check_quat(d->orientation, q, "orientation")) return e;

        Body b;
        b.kind = d->kind;
        b.shape.reset(new btBoxShape(vec(d->half_extents)));
        b.shape->setMargin(d->margin);  // keeps the outer half extents
        btVector3 inertia(0, 0, 0);
        if (d->kind == BS_DYNAMIC) b.shape->calculateLocalInertia(d->mass, inertia);
        btRigidBody::btRigidBodyConstructionInfo info(d->mass, nullptr, b.shape.get(), inertia);
        info.m_startWorldTransform = btTransform(q, vec(d->position));
        info.m_friction = d->friction;
        info.m_rollingFriction = d->rolling_friction;
        info.m_spinningFriction = d->spinning_friction;
        info.m_restitution = d->restitution;
        info.m_linearDamping = d->linear_damping;
        info.m_angularDamping = d->angular_damping;
        b.body.reset(new btRigidBody(info));
        int index = static_cast<int>(w->bodies.size());
        b.body->setUserIndex(index);
        if (d->kind == BS_KINEMATIC) {
            b.body->setCollisionFlags(b.body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
            b.body->setActivationState(DISABLE_DEACTIVATION);
        } else if (d->kind == BS_DYNAMIC) {
            b.body->setLinearVelocity(vec(d->linear_velocity));
            b.body->setAngularVelocity(vec(d->angular_velocity));
            if (d->disable_deactivation) b.body->setActivationState(DISABLE_DEACTIVATION);
        }
        w->bodies.push_back(std::move(b));
        try {
            w->world->addRigidBody(w->bodies.back().body.get());
        } catch (...) {
            w->bodies.pop_back();
            throw;
        }
        if (d->kind == BS_KINEMATIC && w->solver) w->solver->kinematic.push_back(w->bodies.back().body.get());
        *out_index = index;
        return BS_OK;
    });
}

int bs_body_get_pose(const bs_world *w, int body, double position[3], double orientation[4]) {
    return guard([&]() -> int {
        if (int e = check_body(w, body)) return e;
        if (!position || !orientation) return fail(BS_ERR_NULL, "null output");
        const btTransform &t = w->bodies[body].body->getWorldTransform();
        put(t.getOrigin(), position);
        put_quat(t.getRotation(), orientation);
        return BS_OK;
    });
}

int bs_body_set_pose(bs_world *w, int body, const double position[3], const double orientation[4]) {
    return guard([&]() -> int {
        if (int e = check_body(w, body)) return e;
        if (!position || !orientation) return fail(BS_ERR_NULL, "null input");
        if (!finite3(position)) return fail(BS_ERR_BAD_ARG, "position has a non-finite component");
        btQuaternion q;
        if (int e = check_quat(orientation, q, "orientation")) return e;
        Body &b = w->bodies[body];
        btTransform t(q, vec(position));
        b.body->setWorldTransform(t);
        if (b.kind != BS_KINEMATIC) {
            b.body->setInterpolationWorldTransform(t);
            if (b.kind == BS_DYNAMIC) b.body->activate(true);
        }
        return BS_OK;
    });
}

int bs_body_get_velocity(const bs_world *w, int body, double linear[3], double angular[3]) {
    return guard([&]() -> int {
        if (int e = check_body(w, body)) return e;
        if (!linear || !angular) return fail(BS_ERR_NULL, "null output");
        put(w->bodies[body].body->getLinearVelocity(), linear);
        put(w->bodies[body].body->getAngularVelocity(), angular);
        return BS_OK;
    });
}

int bs_body_set_velocity(bs_world *w, int body, const double linear[3], const double angular[3]) {
    return guard([&]() -> int {
        if (int e = check_body(w, body)) return e;
        if (!linear || !angular) return fail(BS_ERR_NULL, "null input");
        if (!finite3(linear) || !finite3(angular)) return fail(BS_ERR_BAD_ARG, "velocity has a non-finite component");
        Body &b = w->bodies[body];
        if (b.kind != BS_DYNAMIC) return fail(BS_ERR_WRONG_KIND, "set_velocity needs a dynamic body (use the kinematic velocity for kinematic bodies)");
        b.body->setLinearVelocity(vec(linear));
        b.body->setAngularVelocity(vec(angular));
        b.body->activate(true);
        return BS_OK;
    });
}

int bs_body_set_kinematic_velocity(bs_world *w, int body, const double linear[3], const double angular[3]) {
    return guard([&]() -> int {
        if (int e = check_body(w, body)) return e;
        if (!linear || !angular) return fail(BS_ERR_NULL, "null input");
        if (!finite3(linear) || !finite3(angular)) return fail(BS_ERR_BAD_ARG, "velocity has a non-finite component");
        Body &b = w->bodies[body];
        if (b.kind != BS_KINEMATIC) return fail(BS_ERR_WRONG_KIND, "set_kinematic_velocity needs a kinematic body");
        b.has_kinematic_velocity = true;
        b.kinematic_linear = vec(linear);
        b.kinematic_angular = vec(angular);
        return BS_OK;
    });
}

int bs_body_apply_central_impulse(bs_world *w, int body, const double impulse[3]) {
    return guard([&]() -> int {
        if (int e = check_body(w, body)) return e;
        if (!impulse) return fail(BS_ERR_NULL, "null impulse");
        if (!finite3(impulse)) return fail(BS_ERR_BAD_ARG, "impulse has a non-finite component");
        Body &b = w->bodies[body];
        if (b.kind != BS_DYNAMIC) return fail(BS_ERR_WRONG_KIND, "apply_central_impulse needs a dynamic body");
        b.body->applyCentralImpulse(vec(impulse));
        b.body->activate(true);
        return BS_OK;
    });
}

int bs_body_set_activation_state(bs_world *w, int body, int state) {
    return guard([&]() -> int {
        if (int e = check_body(w, body)) return e;
        if (state < ACTIVE_TAG || state > DISABLE_SIMULATION)
            return fail(BS_ERR_BAD_ARG, "activation state must be 1..5");
        w->bodies[body].body->forceActivationState(state);
        return BS_OK;
    });
}

int bs_body_get_activation_state(const bs_world *w, int body, int *state) {
    return guard([&]() -> int {
        if (int e = check_body(w, body)) return e;
        if (!state) return fail(BS_ERR_NULL, "null output");
        *state = w->bodies[body].body->getActivationState();
        return BS_OK;
    });
}

int bs_body_get_mass_inertia(const bs_world *w, int body, double *mass, double inertia[3]) {
    return guard([&]() -> int {
        if (int e = check_body(w, body)) return e;
        if (!mass || !inertia) return fail(BS_ERR_NULL, "null output");
        const btRigidBody *b = w->bodies[body].body.get();
        double inv = b->getInvMass();
        *mass = inv > 0 ? 1.0 / inv : 0.0;
        btVector3 ii = b->getLocalInertia();
        put(ii, inertia);
        return BS_OK;
    });
}

int bs_constraint_add(bs_world *w, const bs_constraint_desc *d, int *out_index) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (!d || !out_index) return fail(BS_ERR_NULL, "null argument to bs_constraint_add");
        if (int e = check_body(w, d->body_a)) return e;
        if (int e = check_body(w, d->body_b)) return e;
        if (d->body_a == d->body_b) return fail(BS_ERR_BAD_ARG, "a constraint needs two different bodies");
        if (!finite3(d->frame_a_position) || !finite3(d->frame_b_position))
            return fail(BS_ERR_BAD_ARG, "a frame position has a non-finite component");
        btQuaternion qa, qb;
        if (int e = check_quat(d->frame_a_orientation, qa, "frame A orientation")) return e;
        if (int e = check_quat(d->frame_b_orientation, qb, "frame B orientation")) return e;
        if (std::isnan(d->breaking_impulse_threshold) || !(d->breaking_impulse_threshold > 0))
            return fail(BS_ERR_BAD_ARG, "breaking impulse threshold must be > 0 (+inf = unbreakable)");
        for (int i = 0; i < 6; ++i) {
            if (d->has_limit[i] && (std::isnan(d->lower[i]) || std::isnan(d->upper[i])))
                return fail(BS_ERR_BAD_ARG, "limit of axis " + std::to_string(i) + " is NaN");
            if (d->spring_enabled[i] && !(std::isfinite(d->stiffness[i]) && d->stiffness[i] >= 0 &&
                                          std::isfinite(d->damping[i]) && d->damping[i] >= 0))
                return fail(BS_ERR_BAD_ARG, "spring of axis " + std::to_string(i) + " needs finite stiffness and damping >= 0");
        }
        btRigidBody &ra = *w->bodies[d->body_a].body;
        btRigidBody &rb = *w->bodies[d->body_b].body;
        btTransform fa(qa, vec(d->frame_a_position)), fb(qb, vec(d->frame_b_position));

        std::unique_ptr<Constraint> c(new Constraint());
        c->kind = d->kind;
        zero_feedback(c->feedback);
        switch (d->kind) {
            case BS_GENERIC6DOF: {
                auto *g = new btGeneric6DofConstraint(ra, rb, fa, fb, d->use_linear_reference_frame_a != 0);
                c->constraint.reset(g);
                for (int i = 0; i < 6; ++i)
                    if (d->has_limit[i]) g->setLimit(i, d->lower[i], d->upper[i]);
                break;
            }
            case BS_SPRING2: {
                auto *g = new btGeneric6DofSpring2Constraint(ra, rb, fa, fb, RO_XYZ);
                c->constraint.reset(g);
                for (int i = 0; i < 6; ++i) {
                    if (d->has_limit[i]) g->setLimit(i, d->lower[i], d->upper[i]);
                    if (d->spring_enabled[i]) {
                        g->enableSpring(i, true);
                        g->setStiffness(i, d->stiffness[i], d->limit_if_needed[i] != 0);
                        g->setDamping(i, d->damping[i], d->limit_if_needed[i] != 0);
                    }
                }
                if (d->set_equilibrium_point) g->setEquilibriumPoint();
                break;
            }
            case BS_FIXED:
                c->constraint.reset(new btFixedConstraint(ra, rb, fa, fb));
                break;
            case BS_POINT2POINT: {
                for (int i = 0; i < 6; ++i)
                    if (d->has_limit[i] || d->spring_enabled[i])
                        return fail(BS_ERR_BAD_ARG, "a point-to-point constraint takes no limit and no spring");
                if (qa != btQuaternion::getIdentity() || qb != btQuaternion::getIdentity())
                    return fail(BS_ERR_BAD_ARG, "a point-to-point constraint takes pivots only: frame orientations must be the identity");
                c->constraint.reset(new btPoint2PointConstraint(ra, rb, fa.getOrigin(), fb.getOrigin()));
                break;
            }
            default:
                return fail(BS_ERR_BAD_ARG, "unknown constraint kind " + std::to_string(d->kind));
        }
        btTypedConstraint *t = c->constraint.get();
        t->setBreakingImpulseThreshold(d->breaking_impulse_threshold);
        t->setJointFeedback(&c->feedback);
        t->setEnabled(d->enabled != 0);
        if (d->override_solver_iterations >= 0) t->setOverrideNumSolverIterations(d->override_solver_iterations);
        int index = static_cast<int>(w->constraints.size());
        t->setUserConstraintId(index);
        w->constraints.push_back(std::move(c));
        try {
            w->world->addConstraint(t, d->disable_collisions_between != 0);
        } catch (...) {
            w->constraints.pop_back();
            throw;
        }
        *out_index = index;
        return BS_OK;
    });
}

int bs_constraint_set_enabled(bs_world *w, int c, int enabled) {
    return guard([&]() -> int {
        if (int e = check_constraint(w, c)) return e;
        w->constraints[c]->constraint->setEnabled(enabled != 0);
        return BS_OK;
    });
}

int bs_constraint_is_enabled(const bs_world *w, int c, int *enabled) {
    return guard([&]() -> int {
        if (int e = check_constraint(w, c)) return e;
        if (!enabled) return fail(BS_ERR_NULL, "null output");
        *enabled = w->constraints[c]->constraint->isEnabled() ? 1 : 0;
        return BS_OK;
    });
}

int bs_constraint_applied_impulse(const bs_world *w, int c, double *impulse) {
    return guard([&]() -> int {
        if (int e = check_constraint(w, c)) return e;
        if (!impulse) return fail(BS_ERR_NULL, "null output");
        *impulse = w->constraints[c]->constraint->getAppliedImpulse();
        return BS_OK;
    });
}

int bs_constraint_set_breaking_threshold(bs_world *w, int c, double threshold) {
    return guard([&]() -> int {
        if (int e = check_constraint(w, c)) return e;
        if (std::isnan(threshold) || !(threshold > 0))
            return fail(BS_ERR_BAD_ARG, "breaking impulse threshold must be > 0 (+inf = unbreakable)");
        w->constraints[c]->constraint->setBreakingImpulseThreshold(threshold);
        return BS_OK;
    });
}

int bs_constraint_get_breaking_threshold(const bs_world *w, int c, double *threshold) {
    return guard([&]() -> int {
        if (int e = check_constraint(w, c)) return e;
        if (!threshold) return fail(BS_ERR_NULL, "null output");
        *threshold = w->constraints[c]->constraint->getBreakingImpulseThreshold();
        return BS_OK;
    });
}

int bs_constraint_feedback(const bs_world *w, int c, double force_a[3], double torque_a[3],
                           double force_b[3], double torque_b[3]) {
    return guard([&]() -> int {
        if (int e = check_constraint(w, c)) return e;
        if (!force_a || !torque_a || !force_b || !torque_b) return fail(BS_ERR_NULL, "null output");
        const btJointFeedback &fb = w->constraints[c]->feedback;
        put(fb.m_appliedForceBodyA, force_a);
        put(fb.m_appliedTorqueBodyA, torque_a);
        put(fb.m_appliedForceBodyB, force_b);
        put(fb.m_appliedTorqueBodyB, torque_b);
        return BS_OK;
    });
}

int bs_constraint_set_equilibrium_point(bs_world *w, int c) {
    return guard([&]() -> int {
        if (int e = check_constraint(w, c)) return e;
        Constraint &k = *w->constraints[c];
        if (k.kind != BS_SPRING2 && k.kind != BS_FIXED)
            return fail(BS_ERR_WRONG_KIND, "set_equilibrium_point needs a spring2 or fixed constraint");
        static_cast<btGeneric6DofSpring2Constraint *>(k.constraint.get())->setEquilibriumPoint();
        return BS_OK;
    });
}

int bs_constraint_set_param(bs_world *w, int c, int num, double value, int axis) {
    return guard([&]() -> int {
        if (int e = check_constraint(w, c)) return e;
        Constraint &k = *w->constraints[c];
        if (k.kind != BS_GENERIC6DOF && k.kind != BS_SPRING2)
            return fail(BS_ERR_WRONG_KIND, "set_param needs a generic6dof or spring2 constraint");
        if (num != BT_CONSTRAINT_STOP_ERP && num != BT_CONSTRAINT_STOP_CFM)
            return fail(BS_ERR_BAD_ARG, "set_param: num must be 2 (STOP_ERP) or 4 (STOP_CFM), got " + std::to_string(num));
        if (axis < 0 || axis > 5)
            return fail(BS_ERR_BAD_ARG, "set_param: axis must be 0..5, got " + std::to_string(axis));
        if (!(std::isfinite(value) && value >= 0))
            return fail(BS_ERR_BAD_ARG, "set_param: value must be finite and >= 0");
        k.constraint->setParam(num, value, axis);
        return BS_OK;
    });
}

int bs_constraint_relock(bs_world *w, int c, int mask) {
    return guard([&]() -> int {
        if (int e = check_constraint(w, c)) return e;
        Constraint &k = *w->constraints[c];
        if (k.kind != BS_GENERIC6DOF)
            return fail(BS_ERR_WRONG_KIND, "relock needs a generic6dof constraint");
        auto *g = static_cast<btGeneric6DofConstraint *>(k.constraint.get());
        g->calculateTransforms();
        btVector3 llo, lhi, alo, ahi;
        g->getLinearLowerLimit(llo);
        g->getLinearUpperLimit(lhi);
        g->getAngularLowerLimit(alo);
        g->getAngularUpperLimit(ahi);
        for (int i = 0; i < 6; ++i) {
            if (!(mask & (1 << i))) continue;
            if (i < 3) {
                if (llo[i] != lhi[i]) continue;
                btScalar v = g->getRelativePivotPosition(i);
                g->setLimit(i, v, v);
            } else {
                if (alo[i - 3] != ahi[i - 3]) continue;
                btScalar v = g->getAngle(i - 3);
                g->setLimit(i, v, v);
            }
        }
        return BS_OK;
    });
}

// fem2rbd (ductile hinges' return mapping, src/ruin/stage.rs): one axis's current value
// (relative pivot position or angle, as calculateTransforms() leaves them) and lower limit.
int bs_constraint_axis_value(bs_world *w, int c, int axis, double *value, double *lo) {
    return guard([&]() -> int {
        if (int e = check_constraint(w, c)) return e;
        Constraint &k = *w->constraints[c];
        if (k.kind != BS_GENERIC6DOF)
            return fail(BS_ERR_WRONG_KIND, "axis_value needs a generic6dof constraint");
        if (axis < 0 || axis > 5) return fail(BS_ERR_BAD_ARG, "axis must be 0..5");
        if (!value || !lo) return fail(BS_ERR_NULL, "null output");
        auto *g = static_cast<btGeneric6DofConstraint *>(k.constraint.get());
        g->calculateTransforms();
        btVector3 v;
        if (axis < 3) {
            g->getLinearLowerLimit(v);
            *lo = v[axis];
            *value = g->getRelativePivotPosition(axis);
        } else {
            g->getAngularLowerLimit(v);
            *lo = v[axis - 3];
            *value = g->getAngle(axis - 3);
        }
        return BS_OK;
    });
}

// fem2rbd (axial rows, src/ruin/axial.rs): sets one axis's limits of a generic6dof
// constraint (btGeneric6DofConstraint::setLimit; lo > hi frees the axis).
int bs_constraint_set_limit(bs_world *w, int c, int axis, double lo, double hi) {
    return guard([&]() -> int {
        if (int e = check_constraint(w, c)) return e;
        Constraint &k = *w->constraints[c];
        if (k.kind != BS_GENERIC6DOF)
            return fail(BS_ERR_WRONG_KIND, "set_limit needs a generic6dof constraint");
        if (axis < 0 || axis > 5) return fail(BS_ERR_BAD_ARG, "axis must be 0..5");
        if (!std::isfinite(lo) || !std::isfinite(hi)) return fail(BS_ERR_BAD_ARG, "limits must be finite");
        auto *g = static_cast<btGeneric6DofConstraint *>(k.constraint.get());
        g->setLimit(axis, lo, hi);
        return BS_OK;
    });
}

int bs_world_set_joint_warmstart(bs_world *w, double factor) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (!(std::isfinite(factor) && factor >= 0 && factor <= 1))
            return fail(BS_ERR_BAD_ARG, "joint warm-start factor must be in [0, 1], got " + std::to_string(factor));
        if (factor != 0)
            if (int e = check_shim_solver(w, "the joint warm start")) return e;
        w->warm.factor = factor;
        return BS_OK;
    });
}

int bs_world_get_joint_warmstart(const bs_world *w, double *factor, long long *rows_started) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (!factor || !rows_started) return fail(BS_ERR_NULL, "null output");
        *factor = w->warm.factor;
        *rows_started = w->warm.rows_started;
        return BS_OK;
    });
}

int bs_world_set_joint_solve(bs_world *w, int mode, double regularisation) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (mode != BS_JOINT_SOLVE_PGS && mode != BS_JOINT_SOLVE_DIRECT)
            return fail(BS_ERR_BAD_ARG, "joint solve mode must be 0 (pgs) or 1 (direct), got " + std::to_string(mode));
        if (!(std::isfinite(regularisation) && regularisation >= 0 && regularisation <= 1))
            return fail(BS_ERR_BAD_ARG, "joint solve regularisation must be in [0, 1], got " + std::to_string(regularisation));
        if (mode != BS_JOINT_SOLVE_PGS)
            if (int e = check_shim_solver(w, "the direct joint solve")) return e;
        w->direct.mode = mode;
        w->direct.regularisation = regularisation;
        return BS_OK;
    });
}

int bs_world_get_joint_solve(const bs_world *w, int *mode, double *regularisation, long long *solves,
                             long long *fallbacks, long long *rows) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (!mode || !regularisation || !solves || !fallbacks || !rows) return fail(BS_ERR_NULL, "null output");
        *mode = w->direct.mode;
        *regularisation = w->direct.regularisation;
        *solves = w->direct.solves;
        *fallbacks = w->direct.fallbacks;
        *rows = w->direct.rows;
        return BS_OK;
    });
}

int bs_world_set_solver_threads(bs_world *w, int n) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (n < 1 || n > 256) return fail(BS_ERR_BAD_ARG, "solver threads must be 1..256, got " + std::to_string(n));
        if (!w->solver && n == 1) return BS_OK;
        if (int e = check_shim_solver(w, "more than one solver thread")) return e;
        w->solver->threads = n;
        return BS_OK;
    });
}

int bs_world_set_sweep(bs_world *w, int on) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (on < 0 || on > 3) return fail(BS_ERR_BAD_ARG, "sweep must be 0..3, got " + std::to_string(on));
        if (!w->solver && on == BS_SWEEP_BULLET) return BS_OK;
        if (int e = check_shim_solver(w, "a sweep other than Bullet's")) return e;
        w->solver->sweep = on;
        return BS_OK;
    });
}

int bs_world_parallel_counts(const bs_world *w, long long *setups, long long *sweeps) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (!setups || !sweeps) return fail(BS_ERR_NULL, "null output");
        if (int e = check_shim_solver(w, "the parallel counts")) return e;
        *setups = w->solver->parallel_setups;
        *sweeps = w->solver->parallel_sweeps;
        return BS_OK;
    });
}

int bs_world_get_solver_threads(const bs_world *w, int *n) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (!n) return fail(BS_ERR_NULL, "null output");
        *n = w->solver ? w->solver->threads : 1;
        return BS_OK;
    });
}

int bs_world_island_stats(const bs_world *w, bs_island_stats *out) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (!out) return fail(BS_ERR_NULL, "null output");
        if (int e = check_shim_solver(w, "the island statistics")) return e;
        *out = w->solver->stats;
        return BS_OK;
    });
}

int bs_world_reset_island_stats(bs_world *w) {
    return guard([&]() -> int {
        if (int e = check_shim_solver(w, "the island statistics")) return e;
        w->solver->stats = bs_island_stats{};
        return BS_OK;
    });
}

int bs_body_set_sleeping_thresholds(bs_world *w, int body, double linear, double angular) {
    return guard([&]() -> int {
        if (int e = check_body(w, body)) return e;
        if (!(std::isfinite(linear) && linear >= 0 && std::isfinite(angular) && angular >= 0))
            return fail(BS_ERR_BAD_ARG, "sleeping thresholds must be finite and >= 0");
        w->bodies[body].body->setSleepingThresholds(linear, angular);
        return BS_OK;
    });
}

int bs_set_global_deactivation_time(double seconds) {
    if (!(std::isfinite(seconds) && seconds >= 0)) return fail(BS_ERR_BAD_ARG, "deactivation time must be finite and >= 0");
    gDeactivationTime = seconds;
    return BS_OK;
}
double bs_get_global_deactivation_time(void) { return gDeactivationTime; }

int bs_body_set_collision_with(bs_world *w, int a, int b, int collide) {
    return guard([&]() -> int {
        if (int e = check_body(w, a)) return e;
        if (int e = check_body(w, b)) return e;
        if (a == b) return fail(BS_ERR_BAD_ARG, "a body's contact with itself cannot be set");
        btRigidBody *ra = w->bodies[a].body.get();
        btRigidBody *rb = w->bodies[b].body.get();
        if (collide) {
            // setIgnoreCollisionCheck(.., false) removes one entry; addConstraintRef adds one
            // per constraint, so remove until none is left.
            while (!ra->checkCollideWithOverride(rb)) ra->setIgnoreCollisionCheck(rb, false);
            while (!rb->checkCollideWithOverride(ra)) rb->setIgnoreCollisionCheck(ra, false);
        } else {
            if (ra->checkCollideWithOverride(rb)) ra->setIgnoreCollisionCheck(rb, true);
            if (rb->checkCollideWithOverride(ra)) rb->setIgnoreCollisionCheck(ra, true);
            btBroadphaseProxy *pa = ra->getBroadphaseHandle();
            btBroadphaseProxy *pb = rb->getBroadphaseHandle();
            if (pa && pb) {
                btOverlappingPairCache *cache = w->world->getBroadphase()->getOverlappingPairCache();
                if (btBroadphasePair *pair = cache->findPair(pa, pb))
                    cache->cleanOverlappingPair(*pair, w->world->getDispatcher());
            }
        }
        return BS_OK;
    });
}

int bs_body_collides_with(const bs_world *w, int a, int b, int *collides) {
    return guard([&]() -> int {
        if (int e = check_body(w, a)) return e;
        if (int e = check_body(w, b)) return e;
        if (!collides) return fail(BS_ERR_NULL, "null output");
        const btRigidBody *ra = w->bodies[a].body.get();
        const btRigidBody *rb = w->bodies[b].body.get();
        *collides = (ra->checkCollideWith(rb) && rb->checkCollideWith(ra)) ? 1 : 0;
        return BS_OK;
    });
}

int bs_world_num_sleeping(const bs_world *w, int *count) {
    return guard([&]() -> int {
        if (int e = check_world(w)) return e;
        if (!count) return fail(BS_ERR_NULL, "null output");
        int c = 0;
        for (const Body &b : w->bodies)
            if (b.kind == BS_DYNAMIC && b.body->getActivationState() == ISLAND_SLEEPING) ++c;
        *count = c;
        return BS_OK;
    });
}

int bs_profile_start(void) {
    return guard([&]() -> int {
        static std::once_flag hooks;
        std::call_once(hooks, [] {
            btSetCustomEnterProfileZoneFunc(profile_enter);
            btSetCustomLeaveProfileZoneFunc(profile_leave);
        });
        t_profile.stack.clear();
        t_profile.zones.clear();
        t_profile.on = true;
        return BS_OK;
    });
}

int bs_profile_stop(void) {
    t_profile.on = false;
    t_profile.stack.clear();
    return BS_OK;
}

int bs_profile_read(bs_profile_entry *out, int capacity, int *total) {
    return guard([&]() -> int {
        if (!total || (capacity > 0 && !out)) return fail(BS_ERR_NULL, "null output");
        // Merge zones of the same name (a literal may have several addresses), first-seen order.
        std::map<std::string, ZoneStat> by_name;
        for (const auto &kv : t_profile.zones) {
            ZoneStat &z = by_name[kv.first];
            if (z.calls == 0) {
                z.depth = kv.second.depth;
                z.first = kv.second.first;
            } else {
                z.first = std::min(z.first, kv.second.first);
                z.depth = std::min(z.depth, kv.second.depth);
            }
            z.seconds += kv.second.seconds;
            z.calls += kv.second.calls;
        }
        std::vector<std::pair<std::string, ZoneStat>> v(by_name.begin(), by_name.end());
        std::stable_sort(v.begin(), v.end(), [](const std::pair<std::string, ZoneStat> &a, const std::pair<std::string, ZoneStat> &b) {
            return a.second.first < b.second.first;
        });
        int n = static_cast<int>(v.size());
        for (int i = 0; i < n && i < capacity; ++i) {
            bs_profile_entry &e = out[i];
            std::memset(e.name, 0, sizeof e.name);
            std::strncpy(e.name, v[i].first.c_str(), sizeof e.name - 1);
            e.seconds = v[i].second.seconds;
            e.calls = v[i].second.calls;
            e.depth = v[i].second.depth;
        }
        *total = n;
        return BS_OK;
    });
}

}  // extern "C"
