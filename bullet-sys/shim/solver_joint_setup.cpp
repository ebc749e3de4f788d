// solver_joint_setup.cpp — LeanSolver::convertJoints: the joints' set-up (getInfo1/getInfo2
// of every constraint, Bullet's convertJoint) on the solver threads.
//
// Same bits as Bullet 3.24's btSequentialImpulseConstraintSolver::convertJoints:
// tests/it/ruin/speed.rs `lean_and_packed_sweeps_give_bullets_bits` (Sweep::PackedThreads on
// 2 and 3 threads, which asserts that the set-up ran on the threads, against Sweep::Bullet)
// and tests/it/physics/stock_bullet.rs `the_shims_solver_gives_stock_bullets_bits_on_frame3`
// (Sweep::Packed on 2 threads against a world of Bullet's stock classes).
//
// Altered versions of Bullet Physics 3.24's code (Copyright (c) 2003-2006 Erwin Coumans,
// https://bulletphysics.org; zlib licence: provided 'as-is', without any warranty; altered
// versions must be plainly marked as such): the functions below that follow Bullet's say so.
//
// With a packed sweep (SWEEP_PACKED, SWEEP_PACKED_THREADS) and setup_threads > 1 the
// joints' set-up (convertJoints: getInfo1/getInfo2 of every constraint, Bullet's
// convertJoint) runs on that many threads: every constraint writes only
// its own members and its own rows and reads the bodies, and the solver bodies of the
// constraints' partners are assigned on the calling thread in Bullet's order, so the rows
// are the same bits for any thread count (altered version of Bullet 3.24's
// btSequentialImpulseConstraintSolver::convertJoints, same licence).
// Which of the two runs is chosen substep by substep by a ThreadChooser (solvers.h), on the
// measured time per constraint: both give the same bits, so the choice changes only the speed.
#include "solvers.h"

#include <chrono>

namespace bs_shim {

static double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void LeanSolver::convertJoints(btTypedConstraint **constraints, int numConstraints, const btContactSolverInfo &info) {
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

void LeanSolver::convert_joints(btTypedConstraint **constraints, int numConstraints, const btContactSolverInfo &info,
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

}  // namespace bs_shim
