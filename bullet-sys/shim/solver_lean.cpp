// solver_lean.cpp — LeanSolver::solveSingleIteration (BS_SWEEP_LEAN and the contact rows of
// every packed sweep): Bullet's iterations without its obsolete per-constraint walk.
//
// Same bits as Bullet 3.24's btSequentialImpulseConstraintSolver::solveSingleIteration:
// tests/it/ruin/speed.rs `lean_and_packed_sweeps_give_bullets_bits` (Sweep::Lean against
// Sweep::Bullet on separate towers and one wall: joint rows, contacts, friction, breaking).
//
// Altered versions of Bullet Physics 3.24's code (Copyright (c) 2003-2006 Erwin Coumans,
// https://bulletphysics.org; zlib licence: provided 'as-is', without any warranty; altered
// versions must be plainly marked as such): the functions below that follow Bullet's say so.
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
#include "solvers.h"


namespace bs_shim {

btScalar LeanSolver::solveSingleIteration(int iteration, btCollisionObject **bodies, int numBodies,
                              btPersistentManifold **manifoldPtr, int numManifolds, btTypedConstraint **constraints,
                              int numConstraints, const btContactSolverInfo &infoGlobal,
                              btIDebugDraw *debugDrawer) {
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

// The contact, friction and rolling-friction rows of one iteration (Bullet's order).
void LeanSolver::contact_rows(int iteration, const btContactSolverInfo &infoGlobal, btScalar &leastSquaresResidual) {
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

}  // namespace bs_shim
