//! [`World`]: the safe owner of one Bullet `btDiscreteDynamicsWorld` and everything in it.
use super::settings::{SolverSettings, WorldSettings};
use super::types::*;
use bullet_sys as sys;
use std::ffi::CStr;
use std::ptr::NonNull;
use std::sync::atomic::{AtomicU32, Ordering};

static NEXT_WORLD_ID: AtomicU32 = AtomicU32::new(1);

/// Converts a shim status code into a `Result`, fetching the shim's message.
pub(crate) fn check(call: &'static str, code: i32) -> Result<(), PhysicsError> {
    if code == sys::BS_OK {
        return Ok(());
    }
    // SAFETY: bs_last_error returns a NUL-terminated thread-local string that stays valid
    // until the next shim call on this thread; it is copied at once.
    let message = unsafe { CStr::from_ptr(sys::bs_last_error()) }
        .to_string_lossy()
        .into_owned();
    if code == sys::BS_ERR_ABI {
        return Err(PhysicsError::Abi(message));
    }
    Err(PhysicsError::Bullet {
        call,
        code,
        message,
    })
}

/// Checks that the linked Bullet is the double-precision 3.24 build: `sizeof(btScalar) == 8`,
/// `btGetVersion() == 324`, and a `btBoxShape` built inside the library reads back the
/// expected half extents, margin and inertia through the shim's inline getters.
pub fn abi_self_check() -> Result<(), PhysicsError> {
    // SAFETY: argument-free functions without shared state.
    let (size, version, ok) = unsafe {
        (
            sys::bs_sizeof_scalar(),
            sys::bs_bullet_version(),
            sys::bs_abi_self_check(),
        )
    };
    if size != 8 {
        return Err(PhysicsError::Abi(format!(
            "sizeof(btScalar) = {size}, expected 8 (double precision)"
        )));
    }
    if version != sys::EXPECTED_BULLET_VERSION {
        return Err(PhysicsError::Abi(format!(
            "btGetVersion() = {version}, expected {}",
            sys::EXPECTED_BULLET_VERSION
        )));
    }
    if ok != 1 {
        return Err(PhysicsError::Abi(
            "a btBoxShape built by libBullet reads back wrong values: the library's btScalar \
             differs from the shim's (link bullet-float64, not bullet)"
                .into(),
        ));
    }
    Ok(())
}

/// The pkg-config version of the Bullet library linked at build time (e.g. "3.24").
pub const LINKED_BULLET_PKG_VERSION: &str = env!("FEM2RBD_BULLET_VERSION");

/// The Bullet version linked (`btGetVersion()`, e.g. 324).
pub fn bullet_version() -> i32 {
    // SAFETY: argument-free.
    unsafe { sys::bs_bullet_version() }
}

/// Sets the **process-global** `gDbvtMargin` \[m\] (broadphase AABB enlargement), shared by
/// every world in the process.
pub fn set_global_dbvt_margin(margin: f64) -> Result<(), PhysicsError> {
    // SAFETY: plain value argument; the shim validates it.
    check("set_global_dbvt_margin", unsafe {
        sys::bs_set_global_dbvt_margin(margin)
    })
}

/// The process-global `gDbvtMargin` \[m\].
pub fn global_dbvt_margin() -> f64 {
    // SAFETY: reads a global double.
    unsafe { sys::bs_get_global_dbvt_margin() }
}

/// Sets the **process-global** `gContactBreakingThreshold` \[m\]: how far apart two contact
/// points may drift before the manifold drops them. Read when manifolds are created.
pub fn set_global_contact_breaking_threshold(value: f64) -> Result<(), PhysicsError> {
    // SAFETY: plain value argument; the shim validates it.
    check("set_global_contact_breaking_threshold", unsafe {
        sys::bs_set_global_contact_breaking_threshold(value)
    })
}

/// The process-global `gContactBreakingThreshold` \[m\].
pub fn global_contact_breaking_threshold() -> f64 {
    // SAFETY: reads a global double.
    unsafe { sys::bs_get_global_contact_breaking_threshold() }
}

/// Bullet's own `btContactSolverInfo` defaults as reported by the library headers.
pub fn bullet_default_solver_settings() -> Result<SolverSettings, PhysicsError> {
    let mut p = sys::bs_solver_params::default();
    // SAFETY: p is a valid, writable struct.
    check("default_solver_params", unsafe {
        sys::bs_world_default_solver_params(&mut p)
    })?;
    Ok(from_params(&p))
}

fn from_params(p: &sys::bs_solver_params) -> SolverSettings {
    SolverSettings {
        num_iterations: p.num_iterations.max(0) as u32,
        erp: p.erp,
        erp2: p.erp2,
        friction_erp: p.friction_erp,
        global_cfm: p.global_cfm,
        linear_slop: p.linear_slop,
        split_impulse: p.split_impulse != 0,
        split_impulse_penetration_threshold: p.split_impulse_penetration_threshold,
        split_impulse_turn_erp: p.split_impulse_turn_erp,
        solver_mode: p.solver_mode,
        warmstarting_factor: p.warmstarting_factor,
        least_squares_residual_threshold: p.least_squares_residual_threshold,
        minimum_solver_batch_size: p.minimum_solver_batch_size.max(0) as u32,
        restitution_velocity_threshold: p.restitution_velocity_threshold,
        max_error_reduction: p.max_error_reduction,
        sor: p.sor,
        damping: p.damping,
    }
}

fn to_params(s: &SolverSettings) -> Result<sys::bs_solver_params, PhysicsError> {
    let int = |v: u32, name: &str| {
        i32::try_from(v).map_err(|_| PhysicsError::Invalid(format!("{name} {v} is too large")))
    };
    Ok(sys::bs_solver_params {
        num_iterations: int(s.num_iterations, "num_iterations")?,
        erp: s.erp,
        erp2: s.erp2,
        friction_erp: s.friction_erp,
        global_cfm: s.global_cfm,
        linear_slop: s.linear_slop,
        split_impulse: s.split_impulse as i32,
        split_impulse_penetration_threshold: s.split_impulse_penetration_threshold,
        split_impulse_turn_erp: s.split_impulse_turn_erp,
        solver_mode: s.solver_mode,
        warmstarting_factor: s.warmstarting_factor,
        least_squares_residual_threshold: s.least_squares_residual_threshold,
        minimum_solver_batch_size: int(s.minimum_solver_batch_size, "minimum_solver_batch_size")?,
        restitution_velocity_threshold: s.restitution_velocity_threshold,
        max_error_reduction: s.max_error_reduction,
        sor: s.sor,
        damping: s.damping,
    })
}

/// One Bullet dynamics world (`btDiscreteDynamicsWorld` with `btDbvtBroadphase`,
/// `btCollisionDispatcher` and `btSequentialImpulseConstraintSolver`) and all its bodies
/// (arena indexed by [`BodyHandle`]) and constraints (arena indexed by
/// [`ConstraintHandle`]). Bodies and constraints live as long as the world. Dropping the
/// world removes and frees the constraints, then the bodies, then the world (in the shim's
/// destructor, which never throws across the C boundary).
///
/// Stepping is by whole substeps of a fixed h (`stepSimulation(h, 0)` each), so Bullet's
/// semi-implicit Euler holds exactly: v ← v + g·h, x ← x + v·h, and simulated time is never
/// dropped.
pub struct World {
    raw: NonNull<sys::bs_world>,
    id: u32,
    kinds: Vec<BodyKind>,
    constraint_kinds: Vec<ConstraintKind>,
    substeps: u64,
    time: f64,
}

// SAFETY: the world is only touched through &mut self / &self of this owner; Bullet keeps no
// thread affinity. Not Sync: &World methods call into Bullet, which is not thread-safe.
unsafe impl Send for World {}

impl World {
    /// Creates an empty world after the ABI self-check ([`abi_self_check`]). Applies the
    /// process-global settings in `settings` (if `Some`) before creating the world.
    pub fn new(settings: &WorldSettings) -> Result<World, PhysicsError> {
        abi_self_check()?;
        if let Some(m) = settings.dbvt_margin {
            set_global_dbvt_margin(m)?;
        }
        if let Some(t) = settings.contact_breaking_threshold {
            set_global_contact_breaking_threshold(t)?;
        }
        let params = to_params(&settings.solver)?;
        let mut raw: *mut sys::bs_world = std::ptr::null_mut();
        // SAFETY: gravity points to 3 doubles; raw is a valid out-pointer.
        check("world_new", unsafe {
            if settings.stock_solver {
                sys::bs_world_new_stock(settings.gravity.as_ptr(), &mut raw)
            } else {
                sys::bs_world_new(settings.gravity.as_ptr(), &mut raw)
            }
        })?;
        let raw = NonNull::new(raw).ok_or_else(|| PhysicsError::Bullet {
            call: "world_new",
            code: sys::BS_ERR_NULL,
            message: "null world".into(),
        })?;
        let world = World {
            raw,
            id: NEXT_WORLD_ID.fetch_add(1, Ordering::Relaxed),
            kinds: Vec::new(),
            constraint_kinds: Vec::new(),
            substeps: 0,
            time: 0.0,
        };
        // SAFETY: raw is a live world; params is a valid struct.
        check("set_solver_params", unsafe {
            sys::bs_world_set_solver_params(world.raw.as_ptr(), &params)
        })?;
        Ok(world)
    }

    /// Whether the world is built from Bullet's stock classes only
    /// ([`WorldSettings::stock_solver`]).
    pub fn is_stock(&self) -> bool {
        // SAFETY: raw is a live world.
        unsafe { sys::bs_world_is_stock(self.raw.as_ptr()) == 1 }
    }

    fn w(&self) -> *mut sys::bs_world {
        self.raw.as_ptr()
    }

    /// The live world's pointer, for the crate's other modules (never leaves the crate).
    pub(crate) fn raw_ptr(&self) -> *mut sys::bs_world {
        self.raw.as_ptr()
    }

    /// The shim index of body `h` of this world.
    pub(crate) fn body_index(&self, h: BodyHandle) -> Result<i32, PhysicsError> {
        self.body(h)
    }

    fn body(&self, h: BodyHandle) -> Result<i32, PhysicsError> {
        if h.world != self.id || h.index as usize >= self.kinds.len() {
            return Err(PhysicsError::ForeignHandle(format!("body {}", h.index)));
        }
        Ok(h.index as i32)
    }

    fn constraint(&self, h: ConstraintHandle) -> Result<i32, PhysicsError> {
        if h.world != self.id || h.index as usize >= self.constraint_kinds.len() {
            return Err(PhysicsError::ForeignHandle(format!(
                "constraint {}",
                h.index
            )));
        }
        Ok(h.index as i32)
    }

    /// Sets gravity [m/s²] for the world and every body in it.
    pub fn set_gravity(&mut self, g: [f64; 3]) -> Result<(), PhysicsError> {
        // SAFETY: live world, 3 doubles.
        check("set_gravity", unsafe {
            sys::bs_world_set_gravity(self.w(), g.as_ptr())
        })
    }

    /// Gravity [m/s²].
    pub fn gravity(&self) -> Result<[f64; 3], PhysicsError> {
        let mut g = [0.0; 3];
        // SAFETY: live world, 3 writable doubles.
        check("get_gravity", unsafe {
            sys::bs_world_get_gravity(self.w(), g.as_mut_ptr())
        })?;
        Ok(g)
    }

    /// Replaces the solver settings.
    pub fn set_solver(&mut self, s: &SolverSettings) -> Result<(), PhysicsError> {
        let p = to_params(s)?;
        // SAFETY: live world, valid struct.
        check("set_solver_params", unsafe {
            sys::bs_world_set_solver_params(self.w(), &p)
        })
    }

    /// The solver settings in force.
    pub fn solver(&self) -> Result<SolverSettings, PhysicsError> {
        let mut p = sys::bs_solver_params::default();
        // SAFETY: live world, writable struct.
        check("get_solver_params", unsafe {
            sys::bs_world_get_solver_params(self.w(), &mut p)
        })?;
        Ok(from_params(&p))
    }

    /// Adds a box body; its handle indexes it from now on.
    pub fn add_box(&mut self, d: &BoxDesc) -> Result<BodyHandle, PhysicsError> {
        let desc = sys::bs_body_desc {
            kind: match d.kind {
                BodyKind::Static => sys::BS_STATIC,
                BodyKind::Kinematic => sys::BS_KINEMATIC,
                BodyKind::Dynamic => sys::BS_DYNAMIC,
            } as i32,
            half_extents: d.half_extents,
            margin: d.margin,
            mass: d.mass,
            position: d.pose.position,
            orientation: d.pose.orientation,
            linear_velocity: d.velocity.linear,
            angular_velocity: d.velocity.angular,
            friction: d.friction,
            rolling_friction: d.rolling_friction,
            spinning_friction: d.spinning_friction,
            restitution: d.restitution,
            linear_damping: d.linear_damping,
            angular_damping: d.angular_damping,
            disable_deactivation: d.disable_deactivation as i32,
        };
        let mut index = -1;
        // SAFETY: live world, valid struct, writable index.
        check("add_box", unsafe {
            sys::bs_body_add_box(self.w(), &desc, &mut index)
        })?;
        debug_assert_eq!(index as usize, self.kinds.len());
        self.kinds.push(d.kind);
        Ok(BodyHandle {
            world: self.id,
            index: index as u32,
        })
    }

    /// Adds a constraint between two bodies of this world.
    pub fn add_constraint(&mut self, d: &ConstraintDesc) -> Result<ConstraintHandle, PhysicsError> {
        let a = self.body(d.body_a)?;
        let b = self.body(d.body_b)?;
        let mut desc = sys::bs_constraint_desc {
            body_a: a,
            body_b: b,
            frame_a_position: d.frame_a.position,
            frame_a_orientation: d.frame_a.orientation,
            frame_b_position: d.frame_b.position,
            frame_b_orientation: d.frame_b.orientation,
            breaking_impulse_threshold: d.breaking_impulse_threshold,
            disable_collisions_between: d.disable_collisions_between as i32,
            enabled: d.enabled as i32,
            override_solver_iterations: match d.override_solver_iterations {
                None => -1,
                Some(n) => i32::try_from(n).map_err(|_| {
                    PhysicsError::Invalid(format!("override_solver_iterations {n} is too large"))
                })?,
            },
            ..Default::default()
        };
        for (i, lim) in d.limits.iter().enumerate() {
            if let Some((lo, hi)) = lim {
                desc.has_limit[i] = 1;
                desc.lower[i] = *lo;
                desc.upper[i] = *hi;
            }
        }
        desc.kind = match d.kind {
            ConstraintKind::Generic6Dof {
                use_linear_reference_frame_a,
            } => {
                desc.use_linear_reference_frame_a = use_linear_reference_frame_a as i32;
                sys::BS_GENERIC6DOF
            }
            ConstraintKind::Spring2 {
                springs,
                set_equilibrium_point,
            } => {
                for (i, s) in springs.iter().enumerate() {
                    if let Some(s) = s {
                        desc.spring_enabled[i] = 1;
                        desc.stiffness[i] = s.stiffness;
                        desc.damping[i] = s.damping;
                        desc.limit_if_needed[i] = s.limit_if_needed as i32;
                    }
                }
                desc.set_equilibrium_point = set_equilibrium_point as i32;
                sys::BS_SPRING2
            }
            ConstraintKind::Fixed => sys::BS_FIXED,
            ConstraintKind::PointToPoint => sys::BS_POINT2POINT,
        } as i32;
        let mut index = -1;
        // SAFETY: live world, valid struct, writable index.
        check("add_constraint", unsafe {
            sys::bs_constraint_add(self.w(), &desc, &mut index)
        })?;
        debug_assert_eq!(index as usize, self.constraint_kinds.len());
        self.constraint_kinds.push(d.kind);
        Ok(ConstraintHandle {
            world: self.id,
            index: index as u32,
        })
    }

    /// Runs `count` substeps of `h` seconds each (`stepSimulation(h, 0)` per substep).
    pub fn step(&mut self, h: f64, count: u32) -> Result<(), PhysicsError> {
        let n = i32::try_from(count)
            .map_err(|_| PhysicsError::Invalid(format!("step count {count} is too large")))?;
        // SAFETY: live world.
        check("step", unsafe { sys::bs_world_step(self.w(), h, n) })?;
        self.substeps += u64::from(count);
        self.time += f64::from(count) * h;
        Ok(())
    }

    /// Advances by `duration` seconds in substeps of `h`; `duration` must be a whole number
    /// of substeps (to 1e-9 relative), otherwise nothing is stepped and an error says so.
    /// Returns the number of substeps run.
    pub fn advance(&mut self, duration: f64, h: f64) -> Result<u64, PhysicsError> {
        let n = whole_substeps(duration, h)?;
        let mut left = n;
        while left > 0 {
            let chunk = left.min(1 << 20) as u32;
            self.step(h, chunk)?;
            left -= u64::from(chunk);
        }
        Ok(n)
    }

    /// Substeps run so far.
    pub fn substeps(&self) -> u64 {
        self.substeps
    }

    /// Simulated time so far \[s\] (sum of the substeps).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Handles of all bodies, in creation order.
    pub fn bodies(&self) -> impl Iterator<Item = BodyHandle> + '_ {
        (0..self.kinds.len() as u32).map(move |index| BodyHandle {
            world: self.id,
            index,
        })
    }

    /// Handles of all constraints, in creation order.
    pub fn constraints(&self) -> impl Iterator<Item = ConstraintHandle> + '_ {
        (0..self.constraint_kinds.len() as u32).map(move |index| ConstraintHandle {
            world: self.id,
            index,
        })
    }

    /// Number of bodies.
    pub fn num_bodies(&self) -> usize {
        self.kinds.len()
    }

    /// Number of constraints.
    pub fn num_constraints(&self) -> usize {
        self.constraint_kinds.len()
    }

    /// The body's kind.
    pub fn body_kind(&self, b: BodyHandle) -> Result<BodyKind, PhysicsError> {
        Ok(self.kinds[self.body(b)? as usize])
    }

    /// The body's current pose (`getWorldTransform()`, not an interpolated motion state).
    pub fn pose(&self, b: BodyHandle) -> Result<Pose, PhysicsError> {
        let i = self.body(b)?;
        let mut p = Pose::IDENTITY;
        // SAFETY: live world, checked index, writable arrays of 3 and 4 doubles.
        check("get_pose", unsafe {
            sys::bs_body_get_pose(
                self.w(),
                i,
                p.position.as_mut_ptr(),
                p.orientation.as_mut_ptr(),
            )
        })?;
        Ok(p)
    }

    /// Teleports a static or dynamic body. For a kinematic body use
    /// [`World::set_kinematic_target`].
    pub fn set_pose(&mut self, b: BodyHandle, pose: Pose) -> Result<(), PhysicsError> {
        if self.body_kind(b)? == BodyKind::Kinematic {
            return Err(PhysicsError::Invalid(
                "set_pose on a kinematic body: use set_kinematic_target".into(),
            ));
        }
        self.set_pose_raw(b, pose)
    }

    fn set_pose_raw(&mut self, b: BodyHandle, pose: Pose) -> Result<(), PhysicsError> {
        let i = self.body(b)?;
        // SAFETY: live world, checked index, arrays of 3 and 4 doubles.
        check("set_pose", unsafe {
            sys::bs_body_set_pose(
                self.w(),
                i,
                pose.position.as_ptr(),
                pose.orientation.as_ptr(),
            )
        })
    }

    /// Moves a kinematic body to `pose` for the next substep. Bullet derives the body's
    /// velocity from the pose change over the substep (`btRigidBody::saveKinematicState`);
    /// with `velocity` given, that velocity is imposed instead during the next substep's
    /// solve (e.g. the recorded ground velocity). Call before every substep.
    pub fn set_kinematic_target(
        &mut self,
        b: BodyHandle,
        pose: Pose,
        velocity: Option<Velocity>,
    ) -> Result<(), PhysicsError> {
        if self.body_kind(b)? != BodyKind::Kinematic {
            return Err(PhysicsError::Invalid(
                "set_kinematic_target needs a kinematic body".into(),
            ));
        }
        self.set_pose_raw(b, pose)?;
        if let Some(v) = velocity {
            let i = self.body(b)?;
            // SAFETY: live world, checked index, arrays of 3 doubles.
            check("set_kinematic_velocity", unsafe {
                sys::bs_body_set_kinematic_velocity(
                    self.w(),
                    i,
                    v.linear.as_ptr(),
                    v.angular.as_ptr(),
                )
            })?;
        }
        Ok(())
    }

    /// The body's velocity (world frame).
    pub fn velocity(&self, b: BodyHandle) -> Result<Velocity, PhysicsError> {
        let i = self.body(b)?;
        let mut v = Velocity::default();
        // SAFETY: live world, checked index, writable arrays of 3 doubles.
        check("get_velocity", unsafe {
            sys::bs_body_get_velocity(self.w(), i, v.linear.as_mut_ptr(), v.angular.as_mut_ptr())
        })?;
        Ok(v)
    }

    /// Sets a dynamic body's velocity.
    pub fn set_velocity(&mut self, b: BodyHandle, v: Velocity) -> Result<(), PhysicsError> {
        let i = self.body(b)?;
        // SAFETY: live world, checked index, arrays of 3 doubles.
        check("set_velocity", unsafe {
            sys::bs_body_set_velocity(self.w(), i, v.linear.as_ptr(), v.angular.as_ptr())
        })
    }

    /// Applies an impulse [N·s] at a dynamic body's centre of mass (Δv = J/m at once).
    pub fn apply_central_impulse(
        &mut self,
        b: BodyHandle,
        j: [f64; 3],
    ) -> Result<(), PhysicsError> {
        let i = self.body(b)?;
        // SAFETY: live world, checked index, 3 doubles.
        check("apply_central_impulse", unsafe {
            sys::bs_body_apply_central_impulse(self.w(), i, j.as_ptr())
        })
    }

    /// Bullet's activation state (1 active, 2 sleeping, 3 wants deactivation,
    /// 4 disable deactivation, 5 disable simulation).
    pub fn activation_state(&self, b: BodyHandle) -> Result<i32, PhysicsError> {
        let i = self.body(b)?;
        let mut s = 0;
        // SAFETY: live world, checked index, writable int.
        check("get_activation_state", unsafe {
            sys::bs_body_get_activation_state(self.w(), i, &mut s)
        })?;
        Ok(s)
    }

    /// Forces the activation state (see [`World::activation_state`]).
    pub fn set_activation_state(&mut self, b: BodyHandle, state: i32) -> Result<(), PhysicsError> {
        let i = self.body(b)?;
        // SAFETY: live world, checked index.
        check("set_activation_state", unsafe {
            sys::bs_body_set_activation_state(self.w(), i, state)
        })
    }

    /// Mass \[kg\] (0 for static/kinematic) and principal inertia [kg·m²] in the body frame.
    pub fn mass_inertia(&self, b: BodyHandle) -> Result<(f64, [f64; 3]), PhysicsError> {
        let i = self.body(b)?;
        let mut m = 0.0;
        let mut inertia = [0.0; 3];
        // SAFETY: live world, checked index, writable outputs.
        check("get_mass_inertia", unsafe {
            sys::bs_body_get_mass_inertia(self.w(), i, &mut m, inertia.as_mut_ptr())
        })?;
        Ok((m, inertia))
    }

    /// Enables or disables a constraint (a broken constraint is a disabled one).
    pub fn set_constraint_enabled(
        &mut self,
        c: ConstraintHandle,
        on: bool,
    ) -> Result<(), PhysicsError> {
        let i = self.constraint(c)?;
        // SAFETY: live world, checked index.
        check("set_enabled", unsafe {
            sys::bs_constraint_set_enabled(self.w(), i, on as i32)
        })
    }

    /// Whether the constraint is enabled (false once it broke).
    pub fn constraint_enabled(&self, c: ConstraintHandle) -> Result<bool, PhysicsError> {
        let i = self.constraint(c)?;
        let mut on = 0;
        // SAFETY: live world, checked index, writable int.
        check("is_enabled", unsafe {
            sys::bs_constraint_is_enabled(self.w(), i, &mut on)
        })?;
        Ok(on != 0)
    }

    /// `getAppliedImpulse()` [N·s]: the impulse of the constraint's **last** solver row in
    /// the last substep only — no measure of how close it is to breaking (use
    /// [`World::joint_feedback`]).
    pub fn applied_impulse(&self, c: ConstraintHandle) -> Result<f64, PhysicsError> {
        let i = self.constraint(c)?;
        let mut j = 0.0;
        // SAFETY: live world, checked index, writable double.
        check("applied_impulse", unsafe {
            sys::bs_constraint_applied_impulse(self.w(), i, &mut j)
        })?;
        Ok(j)
    }

    /// Sets the breaking impulse threshold [N·s] (+inf = unbreakable).
    pub fn set_breaking_threshold(
        &mut self,
        c: ConstraintHandle,
        t: f64,
    ) -> Result<(), PhysicsError> {
        let i = self.constraint(c)?;
        // SAFETY: live world, checked index.
        check("set_breaking_threshold", unsafe {
            sys::bs_constraint_set_breaking_threshold(self.w(), i, t)
        })
    }

    /// The breaking impulse threshold [N·s].
    pub fn breaking_threshold(&self, c: ConstraintHandle) -> Result<f64, PhysicsError> {
        let i = self.constraint(c)?;
        let mut t = 0.0;
        // SAFETY: live world, checked index, writable double.
        check("get_breaking_threshold", unsafe {
            sys::bs_constraint_get_breaking_threshold(self.w(), i, &mut t)
        })?;
        Ok(t)
    }

    /// The constraint's force and torque on each body during the last substep.
    pub fn joint_feedback(&self, c: ConstraintHandle) -> Result<JointFeedback, PhysicsError> {
        let i = self.constraint(c)?;
        let mut f = JointFeedback::default();
        // SAFETY: live world, checked index, four writable arrays of 3 doubles.
        check("feedback", unsafe {
            sys::bs_constraint_feedback(
                self.w(),
                i,
                f.force_a.as_mut_ptr(),
                f.torque_a.as_mut_ptr(),
                f.force_b.as_mut_ptr(),
                f.torque_b.as_mut_ptr(),
            )
        })?;
        Ok(f)
    }

    /// Spring2 / fixed: the current relative pose becomes the springs' rest pose.
    pub fn set_equilibrium_point(&mut self, c: ConstraintHandle) -> Result<(), PhysicsError> {
        let i = self.constraint(c)?;
        // SAFETY: live world, checked index.
        check("set_equilibrium_point", unsafe {
            sys::bs_constraint_set_equilibrium_point(self.w(), i)
        })
    }

    /// Generic6Dof / Spring2: the error reduction (`STOP_ERP`) and constraint force mixing
    /// (`STOP_CFM`) of axis `axis`'s limit row (0..2 linear, 3..5 angular),
    /// `btTypedConstraint::setParam`. Unset, a row uses the world's `m_erp` and
    /// `m_globalCfm`. Bullet's sequential-impulse solver applies a joint row's CFM
    /// relative to the row's effective mass (`btSequentialImpulseConstraintSolver::
    /// convertJoint` keeps `m_cfm` = CFM unscaled while contact rows use CFM·m_jacDiagABInv):
    /// a converged row satisfies J·v⁺ = ERP·e/h − CFM·(J M⁻¹ Jᵀ)·λ (λ the row's impulse).
    pub fn set_constraint_param(
        &mut self,
        c: ConstraintHandle,
        param: ConstraintParam,
        axis: usize,
        value: f64,
    ) -> Result<(), PhysicsError> {
        let i = self.constraint(c)?;
        if axis > 5 {
            return Err(PhysicsError::Invalid(format!(
                "constraint axis {axis} is not 0..5"
            )));
        }
        if !(value.is_finite() && value >= 0.0) {
            return Err(PhysicsError::Invalid(format!(
                "constraint {param:?} = {value} must be finite and >= 0"
            )));
        }
        let num = match param {
            ConstraintParam::StopErp => 2,
            ConstraintParam::StopCfm => 4,
        };
        // SAFETY: live world, checked index; the shim checks kind, num, axis and value.
        check("set_param", unsafe {
            sys::bs_constraint_set_param(self.w(), i, num, value, axis as i32)
        })
    }

    /// Generic6Dof: every axis in `mask` (bit i = axis i, 0..2 linear, 3..5 angular) whose
    /// limits are locked (lower = upper) is locked again at its present value (Bullet's
    /// `getRelativePivotPosition` / `getAngle` after `calculateTransforms`), so the row holds
    /// the joint where it is instead of driving it back to the old lock with the velocity
    /// bias ERP·e/h (a rigid–plastic hinge keeps its plastic rotation).
    pub fn relock_constraint(&mut self, c: ConstraintHandle, mask: u8) -> Result<(), PhysicsError> {
        let i = self.constraint(c)?;
        // SAFETY: live world, checked index; the shim checks the kind.
        check("relock", unsafe {
            sys::bs_constraint_relock(self.w(), i, i32::from(mask))
        })
    }

    /// Generic6Dof: sets axis `axis`'s limits (0..2 linear, m; 3..5 angular, rad;
    /// `btGeneric6DofConstraint::setLimit`, lower > upper frees the axis). Used to turn a
    /// two-way axial row into the one-way row that survives a break in one sense
    /// (`fem2rbd::ruin::axial`).
    pub fn set_constraint_limit(
        &mut self,
        c: ConstraintHandle,
        axis: usize,
        lower: f64,
        upper: f64,
    ) -> Result<(), PhysicsError> {
        let i = self.constraint(c)?;
        if axis > 5 || !lower.is_finite() || !upper.is_finite() {
            return Err(PhysicsError::Invalid(format!(
                "constraint limit on axis {axis}: ({lower}, {upper}) needs axis 0..5 and finite limits"
            )));
        }
        // SAFETY: live world, checked index; the shim checks the kind, axis and values.
        check("set_limit", unsafe {
            sys::bs_constraint_set_limit(self.w(), i, axis as i32, lower, upper)
        })
    }

    /// Axis `axis` of a generic 6-DOF constraint: (current value, lower limit).
    pub fn constraint_axis_value(
        &self,
        c: ConstraintHandle,
        axis: usize,
    ) -> Result<(f64, f64), PhysicsError> {
        let i = self.constraint(c)?;
        let (mut v, mut lo) = (0.0, 0.0);
        // SAFETY: live world, checked index, writable outputs.
        check("axis_value", unsafe {
            sys::bs_constraint_axis_value(self.w(), i, axis as i32, &mut v, &mut lo)
        })?;
        Ok((v, lo))
    }

    /// The poses of all bodies in creation order (one call into Bullet).
    pub fn poses(&self) -> Result<Vec<Pose>, PhysicsError> {
        let n = self.kinds.len();
        let mut pos = vec![0.0; 3 * n];
        let mut quat = vec![0.0; 4 * n];
        // SAFETY: live world; the buffers hold n entries of 3 and 4 doubles.
        check("get_poses", unsafe {
            sys::bs_world_get_poses(self.w(), n as i32, pos.as_mut_ptr(), quat.as_mut_ptr())
        })?;
        Ok((0..n)
            .map(|i| Pose {
                position: [pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]],
                orientation: [
                    quat[4 * i],
                    quat[4 * i + 1],
                    quat[4 * i + 2],
                    quat[4 * i + 3],
                ],
            })
            .collect())
    }

    /// The velocities of all bodies in creation order (one call into Bullet).
    pub fn velocities(&self) -> Result<Vec<Velocity>, PhysicsError> {
        let n = self.kinds.len();
        let mut lin = vec![0.0; 3 * n];
        let mut ang = vec![0.0; 3 * n];
        // SAFETY: live world; the buffers hold n entries of 3 doubles.
        check("get_velocities", unsafe {
            sys::bs_world_get_velocities(self.w(), n as i32, lin.as_mut_ptr(), ang.as_mut_ptr())
        })?;
        Ok((0..n)
            .map(|i| Velocity {
                linear: [lin[3 * i], lin[3 * i + 1], lin[3 * i + 2]],
                angular: [ang[3 * i], ang[3 * i + 1], ang[3 * i + 2]],
            })
            .collect())
    }

    /// Whether each constraint is enabled, in creation order (one call into Bullet).
    pub fn constraints_enabled(&self) -> Result<Vec<bool>, PhysicsError> {
        let n = self.constraint_kinds.len();
        let mut on = vec![0; n];
        // SAFETY: live world; the buffer holds n ints.
        check("get_enabled", unsafe {
            sys::bs_world_get_enabled(self.w(), n as i32, on.as_mut_ptr())
        })?;
        Ok(on.into_iter().map(|x| x != 0).collect())
    }

    /// Every pair of bodies with contact points after the last substep, one entry per
    /// persistent manifold, in Bullet's (deterministic) manifold order.
    pub fn contact_pairs(&self) -> Result<Vec<ContactPair>, PhysicsError> {
        let mut total = 0;
        // SAFETY: live world; capacity 0 with a null buffer only counts.
        check("contact_pairs", unsafe {
            sys::bs_world_contact_pairs(self.w(), std::ptr::null_mut(), 0, &mut total)
        })?;
        let mut buf = vec![sys::bs_contact_pair::default(); total.max(0) as usize];
        // SAFETY: buf holds `total` writable entries.
        check("contact_pairs", unsafe {
            sys::bs_world_contact_pairs(self.w(), buf.as_mut_ptr(), total, &mut total)
        })?;
        buf.truncate(total.max(0) as usize);
        Ok(buf
            .iter()
            .map(|p| ContactPair {
                body_a: BodyHandle {
                    world: self.id,
                    index: p.body_a as u32,
                },
                body_b: BodyHandle {
                    world: self.id,
                    index: p.body_b as u32,
                },
                contact: ContactSummary {
                    num_points: p.num_points.max(0) as usize,
                    min_distance: p.min_distance,
                    total_normal_impulse: p.total_normal_impulse,
                },
            })
            .collect())
    }

    /// The contact between bodies `a` and `b` (either order) after the last substep.
    pub fn contact(&self, a: BodyHandle, b: BodyHandle) -> Result<ContactSummary, PhysicsError> {
        let (ia, ib) = (self.body(a)? as u32, self.body(b)? as u32);
        let (lo, hi) = (ia.min(ib), ia.max(ib));
        let mut s = ContactSummary::NONE;
        for p in self.contact_pairs()? {
            if p.body_a.index == lo && p.body_b.index == hi {
                s.num_points += p.contact.num_points;
                s.min_distance = s.min_distance.min(p.contact.min_distance);
                s.total_normal_impulse += p.contact.total_normal_impulse;
            }
        }
        Ok(s)
    }

    /// Whether bodies `a` and `b` may touch (`collide`) or pass through each other.
    /// `addConstraint(c, true)` makes a constrained pair pass through each other for as
    /// long as the constraint is in the world, broken or not (Bullet 3.24,
    /// `btRigidBody::addConstraintRef`); `collide = true` undoes that. Takes effect at the
    /// next substep.
    pub fn set_collision_with(
        &mut self,
        a: BodyHandle,
        b: BodyHandle,
        collide: bool,
    ) -> Result<(), PhysicsError> {
        let (ia, ib) = (self.body(a)?, self.body(b)?);
        // SAFETY: live world, checked indices; the shim rejects a == b.
        check("set_collision_with", unsafe {
            sys::bs_body_set_collision_with(self.w(), ia, ib, collide as i32)
        })
    }

    /// Whether bodies `a` and `b` may touch ([`Self::set_collision_with`]).
    pub fn collides_with(&self, a: BodyHandle, b: BodyHandle) -> Result<bool, PhysicsError> {
        let (ia, ib) = (self.body(a)?, self.body(b)?);
        let mut c = 0;
        // SAFETY: live world, checked indices, writable int.
        check("collides_with", unsafe {
            sys::bs_body_collides_with(self.w(), ia, ib, &mut c)
        })?;
        Ok(c != 0)
    }
}

impl Drop for World {
    fn drop(&mut self) {
        // SAFETY: raw came from bs_world_new and is freed exactly once; bs_world_free
        // catches every C++ exception, so nothing unwinds from here.
        unsafe { sys::bs_world_free(self.raw.as_ptr()) }
    }
}

/// The number of substeps of `h` in `duration`, when it is whole to 1e-9 relative.
pub fn whole_substeps(duration: f64, h: f64) -> Result<u64, PhysicsError> {
    if !(h.is_finite() && h > 0.0) {
        return Err(PhysicsError::Invalid(format!(
            "substep {h} s must be finite and > 0"
        )));
    }
    if !(duration.is_finite() && duration >= 0.0) {
        return Err(PhysicsError::Invalid(format!(
            "duration {duration} s must be finite and >= 0"
        )));
    }
    let ratio = duration / h;
    let n = ratio.round();
    if (ratio - n).abs() > 1e-9 * n.max(1.0) || n > 1e15 {
        return Err(PhysicsError::NotWholeSubsteps {
            duration,
            substep: h,
            ratio,
        });
    }
    Ok(n as u64)
}
