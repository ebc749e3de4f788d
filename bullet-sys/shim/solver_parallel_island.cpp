// solver_parallel_island.cpp — ParallelIslandSolver: the batches of islands Bullet hands the
// solver in a substep, solved on threads (bs_world_set_solver_threads; one thread is
// Bullet's own solveGroup sequence).
//
// Same bits as Bullet 3.24's btSequentialImpulseConstraintSolver::solveGroup, batch by batch:
// tests/it/ruin/speed.rs `island_parallel_solver_gives_the_same_bits_for_any_thread_count`
// (1, 2 and 3 threads, every island its own batch and Bullet's batching) and
// tests/it/physics/stock_bullet.rs `the_shims_solver_gives_stock_bullets_bits_on_frame3`
// (2 threads against a world of Bullet's stock classes).
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
#include "solvers.h"


namespace bs_shim {

void ParallelIslandSolver::prepareSolve(int a, int b) {
    btSequentialImpulseConstraintSolver::prepareSolve(a, b);
    njobs_ = 0;
    largest_ = 0;
}

btScalar ParallelIslandSolver::solveGroup(btCollisionObject **bodies, int numBodies, btPersistentManifold **manifolds, int numManifolds,
                    btTypedConstraint **constraints, int numConstraints, const btContactSolverInfo &info,
                    btIDebugDraw *dd, btDispatcher *dispatcher) {
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

void ParallelIslandSolver::allSolved(const btContactSolverInfo &info, btIDebugDraw *dd) {
    if (njobs_ > 0) run_jobs(info, dd);
    stats.substeps += 1;
    if (warm) warm->step += 1;
    stats.rows_largest += largest_;
    stats.bodies_awake += awake_;
    awake_ = 0;
    btSequentialImpulseConstraintSolver::allSolved(info, dd);
}

void ParallelIslandSolver::run_jobs(const btContactSolverInfo &info, btIDebugDraw *dd) {
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

}  // namespace bs_shim
