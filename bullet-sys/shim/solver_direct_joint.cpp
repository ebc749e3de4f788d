// solver_direct_joint.cpp — DirectJointSolver: a direct solve of the joints' bilateral rows
// at every batch's set-up (bs_world_set_joint_solve BS_JOINT_SOLVE_DIRECT; BS_JOINT_SOLVE_PGS,
// the default, is Bullet's behaviour).
//
// Changes the iterates: validated by tests/it/physics/jointsolve.rs (a heavy chain held
// without sag, a CFM chain stretched by the closed form, the same bits on 1 and 2 threads)
// and docs/ruin-numerics.md §8.3 "A direct solve of the joints' bilateral rows" and §11.1.
// A stock world refuses it (tests/it/physics/stock_bullet.rs).
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
#include "solvers.h"

#include <cmath>

namespace bs_shim {

void DirectJointSolver::convertJoints(btTypedConstraint **constraints, int numConstraints, const btContactSolverInfo &info) {
    WarmJointSolver::convertJoints(constraints, numConstraints, info);
    if (direct && direct->mode == BS_JOINT_SOLVE_DIRECT) direct_solve();
}

void DirectJointSolver::direct_solve() {
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

}  // namespace bs_shim
