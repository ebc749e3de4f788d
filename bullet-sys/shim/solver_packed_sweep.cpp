// solver_packed_sweep.cpp — LeanSolver::solveGroupCacheFriendlyIterations with BS_SWEEP_PACKED
// and BS_SWEEP_PACKED_THREADS: the joint rows' sweep over packed copies, level by level, on
// one thread or (a batch with most of the rows) on several.
//
// Same bits as Bullet 3.24's btSequentialImpulseConstraintSolver::solveGroupCacheFriendlyIterations
// with gResolveSingleConstraintRowGeneric_scalar_reference: tests/it/ruin/speed.rs
// `lean_and_packed_sweeps_give_bullets_bits` (Sweep::Packed and Sweep::PackedThreads on 1-3
// threads against Sweep::Bullet; the wall asserts the sweep ran on the threads) and
// tests/it/physics/stock_bullet.rs `the_shims_solver_gives_stock_bullets_bits_on_frame3`
// (Sweep::Packed against a world of Bullet's stock classes, 3 s of frame3 under LC5).
//
// Altered versions of Bullet Physics 3.24's code (Copyright (c) 2003-2006 Erwin Coumans,
// https://bulletphysics.org; zlib licence: provided 'as-is', without any warranty; altered
// versions must be plainly marked as such): the functions below that follow Bullet's say so.
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
// btSolverBody.h; zlib licence above; altered: it reads the packed copies),
// operation for operation in the same order, so the same bits (the shim is compiled with
// -ffp-contract=off). Contact and friction rows keep Bullet's layout: the bodies' velocity
// changes are copied to Bullet's solver bodies before them and back after them in every
// iteration that has any.
#include "solvers.h"


namespace bs_shim {

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

// Bullet 3.24's solveGroupCacheFriendlyIterations over the packed rows (sweep 2).
btScalar LeanSolver::solveGroupCacheFriendlyIterations(btCollisionObject **bodies, int numBodies,
                                           btPersistentManifold **manifoldPtr, int numManifolds,
                                           btTypedConstraint **constraints, int numConstraints,
                                           const btContactSolverInfo &infoGlobal,
                                           btIDebugDraw *debugDrawer) {
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

void LeanSolver::pack(int threads) {
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

// The packed bodies' velocity changes -> Bullet's solver bodies (to_bullet) or back:
// every body (all = true, before the finish) or only those the contact rows touch.
void LeanSolver::sync_bodies(bool to_bullet, bool all) {
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
void LeanSolver::find_contact_bodies() {
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

void LeanSolver::unpack() {
    sync_bodies(true, true);
    const int n = m_tmpSolverNonContactConstraintPool.size();
    for (int j = 0; j < n; j++)
        m_tmpSolverNonContactConstraintPool[m_orderNonContactConstraintPool[rows_[j].orig]].m_appliedImpulse =
            rows_[j].applied;
}

// One joint row (Bullet's row function over the packed copies, see above); returns
// the squared residual Bullet's sweep folds into its least-squares residual.
double LeanSolver::solve_row(PackedRow &c, PackedBody *bodies) {
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
btScalar LeanSolver::packed_iteration(int iteration, const btContactSolverInfo &infoGlobal) {
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

void LeanSolver::analytics(int iteration, int numBodies, btCollisionObject **bodies, int numManifolds) {
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
double LeanSolver::run_segment(int t, int iteration) {
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

void LeanSolver::wait_for(const std::atomic<long long> &a, long long target) {
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
int LeanSolver::threaded_iterations(int maxIterations, int numBodies, btCollisionObject **bodies, int numManifolds,
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

}  // namespace bs_shim
