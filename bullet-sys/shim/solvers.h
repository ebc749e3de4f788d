// solvers.h — the shim's private header: the solver classes that extend Bullet 3.24's
// btSequentialImpulseConstraintSolver, declared here and defined one extension per file:
//   solver_lean.cpp            LeanSolver's iterations without the obsolete per-constraint walk
//   solver_joint_setup.cpp     LeanSolver's joint set-up (convertJoints) on threads
//   solver_packed_sweep.cpp    LeanSolver's sweep over packed row copies, on one or more threads
//   solver_warm_joint.cpp      WarmJointSolver: the joint rows' warm start
//   solver_direct_joint.cpp    DirectJointSolver: the direct solve of the joints' bilateral rows
//   solver_parallel_island.cpp ParallelIslandSolver: batches of islands solved on threads
// Each file's header says whether it gives the same bits as Bullet's own function (and the
// test that shows it) or changes the iterates (and what validates it). bullet_shim.cpp, the
// C API, creates a ParallelIslandSolver per world. Not part of the C API (bullet_shim.h).
#ifndef BULLET_SHIM_SOLVERS_H
#define BULLET_SHIM_SOLVERS_H

#include "bullet_shim.h"

// Eigen before Bullet: the direct joint solve (DirectJointSolver) factors with
// Eigen::SimplicialLDLT (Debian: libeigen3-dev, header-only).
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <atomic>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace bs_shim {

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

// One joint row and one solver body as the packed sweep reads them
// (solver_packed_sweep.cpp).
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

// Bullet's solver with the lean iterations (solver_lean.cpp), the joint set-up on threads
// (solver_joint_setup.cpp) and the packed sweep (solver_packed_sweep.cpp); sweep ==
// SWEEP_BULLET is Bullet's own solveSingleIteration and convertJoints.
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
                                  btIDebugDraw *debugDrawer) override;

    // Bullet 3.24's solveGroupCacheFriendlyIterations over the packed rows (sweep 2).
    btScalar solveGroupCacheFriendlyIterations(btCollisionObject **bodies, int numBodies,
                                               btPersistentManifold **manifoldPtr, int numManifolds,
                                               btTypedConstraint **constraints, int numConstraints,
                                               const btContactSolverInfo &infoGlobal,
                                               btIDebugDraw *debugDrawer) override;

   protected:
    void convertJoints(btTypedConstraint **constraints, int numConstraints, const btContactSolverInfo &info) override;
    void convert_joints(btTypedConstraint **constraints, int numConstraints, const btContactSolverInfo &info,
                        int threads);

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
    void contact_rows(int iteration, const btContactSolverInfo &infoGlobal, btScalar &leastSquaresResidual);
    bool has_contact_rows() const {
        return m_tmpSolverContactConstraintPool.size() > 0 || m_tmpSolverContactFrictionConstraintPool.size() > 0 ||
               m_tmpSolverContactRollingFrictionConstraintPool.size() > 0;
    }
    void pack(int threads);
    // The packed bodies' velocity changes -> Bullet's solver bodies (to_bullet) or back:
    // every body (all = true, before the finish) or only those the contact rows touch.
    void sync_bodies(bool to_bullet, bool all = false);
    void find_contact_bodies();
    void unpack();
    static double solve_row(PackedRow &c, PackedBody *bodies);
    btScalar packed_iteration(int iteration, const btContactSolverInfo &infoGlobal);
    void analytics(int iteration, int numBodies, btCollisionObject **bodies, int numManifolds);
    double run_segment(int t, int iteration);
    int seg_len(int t) const { return seg_begin_[t + 1] - seg_begin_[t]; }
    static void wait_for(const std::atomic<long long> &a, long long target);
    int threaded_iterations(int maxIterations, int numBodies, btCollisionObject **bodies, int numManifolds,
                            const btContactSolverInfo &infoGlobal);
};

// The joint rows' warm start (solver_warm_joint.cpp): each D6 constraint's row impulses
// at the end of a substep, indexed by btTypedConstraint::getUserConstraintId().
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

class WarmJointSolver : public LeanSolver {
   public:
    JointWarmStart *warm = nullptr;
    // Before solveGroupCacheFriendlyFinish (which clears the pools): keep every D6 row's impulse.
    void save_joint_impulses();

   protected:
    void convertJoints(btTypedConstraint **constraints, int numConstraints, const btContactSolverInfo &info) override;
};

// The direct solve of the joints' bilateral rows (solver_direct_joint.cpp): its settings
// and counters.
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
    void convertJoints(btTypedConstraint **constraints, int numConstraints, const btContactSolverInfo &info) override;

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

    void direct_solve();
};

// Batches of islands solved on threads (solver_parallel_island.cpp).
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

    void prepareSolve(int a, int b) override;
    btScalar solveGroup(btCollisionObject **bodies, int numBodies, btPersistentManifold **manifolds, int numManifolds,
                        btTypedConstraint **constraints, int numConstraints, const btContactSolverInfo &info,
                        btIDebugDraw *dd, btDispatcher *dispatcher) override;
    void allSolved(const btContactSolverInfo &info, btIDebugDraw *dd) override;

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

    void run_jobs(const btContactSolverInfo &info, btIDebugDraw *dd);
};

}  // namespace bs_shim

#endif
