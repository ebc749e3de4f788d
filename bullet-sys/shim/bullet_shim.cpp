// bullet_shim.cpp — the C API of bullet_shim.h over Bullet 3.24 (double precision): the
// extern "C" functions and the world, body and constraint glue. Every extern "C" function
// body runs inside guard(), which turns C++ exceptions into BS_ERR_EXCEPTION and records a
// message for bs_last_error(). A world's solver is a ParallelIslandSolver (solvers.h, one
// extension of Bullet's solver per solver_*.cpp file), or Bullet's stock
// btSequentialImpulseConstraintSolver in a stock world (bs_world_new_stock).
#include "bullet_shim.h"
#include "solvers.h"

#include <BulletDynamics/ConstraintSolver/btFixedConstraint.h>
#include <BulletDynamics/ConstraintSolver/btGeneric6DofSpring2Constraint.h>
#include <btBulletDynamicsCommon.h>

#include <LinearMath/btQuickprof.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <exception>
#include <map>
#include <memory>
#include <new>
#include <string>
#include <unordered_map>
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

using bs_shim::JointDirectSolve;
using bs_shim::JointWarmStart;
using bs_shim::ParallelIslandSolver;

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
