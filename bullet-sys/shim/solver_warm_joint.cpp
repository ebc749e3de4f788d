// solver_warm_joint.cpp — WarmJointSolver: the joint rows' warm start
// (bs_world_set_joint_warmstart; factor 0, the physics-only default, is Bullet's behaviour).
//
// Changes the iterates: validated by tests/it/physics/world.rs
// `generic6dof_warm_start_scales_the_unconverged_sag` (a hanging chain's unconverged sag
// scales with 1 - factor) and docs/ruin-numerics.md §8.1 "The joint warm start" (frame3
// measurements). A stock world refuses it (tests/it/physics/stock_bullet.rs).
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
#include "solvers.h"


namespace bs_shim {

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

void WarmJointSolver::convertJoints(btTypedConstraint **constraints, int numConstraints, const btContactSolverInfo &info) {
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

// Before solveGroupCacheFriendlyFinish (which clears the pools): keep every D6 row's impulse.
void WarmJointSolver::save_joint_impulses() {
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

}  // namespace bs_shim
