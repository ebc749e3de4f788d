//! Speed controls of a [`World`]: island-parallel solving, sleeping, and phase timing
//! through Bullet's own profile zones (docs/performance.md, "Ruin stage").
//!
//! **Island-parallel solving** ([`World::set_solver_threads`]). Each substep Bullet's
//! `btDiscreteDynamicsWorld` splits the bodies into simulation islands (bodies joined by an
//! enabled constraint or a contact, static and kinematic bodies never joining two) and hands
//! the solver one batch of islands at a time. With n > 1 threads the shim sets up every batch
//! in order, runs the batches' Gauss–Seidel iterations (the bulk of the work: 100 sweeps
//! over every row) on up to n threads, and finishes them in order. A batch does exactly the
//! arithmetic of Bullet's sequential solver, so the results are the same bytes for every n
//! (`tests/it/ruin/speed.rs`). The speed-up is bounded by the largest batch: an intact
//! building is one island ([`IslandStats::largest_share`]).
//!
//! Debian's Bullet is built without `BT_THREADSAFE`: `btCreateDefaultTaskScheduler()` returns
//! null and `btParallelFor` runs its loop on the calling thread, so Bullet's own
//! `btDiscreteDynamicsWorldMt` and `btSequentialImpulseConstraintSolverMt` run sequentially
//! in this build. The parallelism here is the shim's own.
use super::types::PhysicsError;
use super::world::{check, World};
use bullet_sys as sys;

/// Solver work of the substeps since [`World::reset_island_stats`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct IslandStats {
    /// Substeps counted.
    pub substeps: u64,
    /// Batches of islands solved (solveGroup calls).
    pub batches: u64,
    /// Solver rows over all batches (contact, friction and joint rows).
    pub rows_total: u64,
    /// Sum over substeps of the largest batch's rows.
    pub rows_largest: u64,
    /// Sum over substeps of the dynamic bodies solved (awake).
    pub bodies_awake: u64,
}

impl IslandStats {
    /// Share of the rows in the largest batch of each substep (1 = one island holds all the
    /// work; the speed-up of the iterations on n threads is at most 1 / max(share, 1/n)).
    pub fn largest_share(&self) -> f64 {
        if self.rows_total == 0 {
            1.0
        } else {
            self.rows_largest as f64 / self.rows_total as f64
        }
    }
}

/// How the solver runs its Gauss–Seidel iterations and sets up the joints' rows
/// ([`World::set_sweep`]). All three give the same bits (docs/performance.md, "Ruin stage").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Sweep {
    /// Bullet 3.24's own `solveSingleIteration` (the "before" of the benchmarks).
    Bullet,
    /// Bullet's sweep without its per-iteration walk over every constraint for the empty
    /// `solveConstraintObsolete`: the same rows in the same order through Bullet's row
    /// functions.
    Lean,
    /// The lean sweep over packed copies of the joint rows (208 instead of 288 bytes a row,
    /// 128 bytes a solver body), in dependency-level order (every body's rows keep Bullet's
    /// order), the same arithmetic. With more than one solver thread the joints' set-up
    /// (Bullet's `getInfo1`/`getInfo2`/`convertJoint` of every constraint, each writing only
    /// its own rows) runs on one thread or on the solver threads, whichever has measured
    /// faster per unit of work (on a machine busy with other work a waiting thread is often
    /// not running).
    #[default]
    Packed,
    /// As [`Sweep::Packed`], with the set-up always on the solver threads and the sweep of a
    /// batch holding most of the substep's rows on the threads too (slabs of bodies, one per
    /// thread; a row waits for the rows before it on its bodies). Same bits; on a loaded
    /// machine far slower (docs/performance.md), so only on request.
    PackedThreads,
}

/// Solver work that ran on the solver threads ([`World::parallel_counts`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ParallelCounts {
    /// Joint set-ups (Bullet's `convertJoints` of one batch) run on the threads.
    pub joint_setups: u64,
    /// Packed sweeps (the iterations of one batch) run on the threads.
    pub sweeps: u64,
}

/// Wall time of one Bullet profile zone (`BT_PROFILE`), inclusive of the zones inside it.
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileZone {
    /// Bullet's zone name (e.g. `solveGroupCacheFriendlyIterations`).
    pub name: String,
    /// Wall time inside the zone, s.
    pub seconds: f64,
    /// Times entered.
    pub calls: u64,
    /// Nesting depth at the first entry (0 = outermost).
    pub depth: u32,
}

/// Starts recording Bullet's profile zones on the calling thread (other threads' zones,
/// e.g. the solver threads', are not recorded) and clears the previous record.
pub fn profile_start() -> Result<(), PhysicsError> {
    // SAFETY: no arguments; the hooks are installed once, the record is thread-local.
    check("profile_start", unsafe { sys::bs_profile_start() })
}

/// Stops recording on the calling thread (the record is kept for [`profile_read`]).
pub fn profile_stop() {
    // SAFETY: no arguments; touches only the thread-local record.
    unsafe {
        sys::bs_profile_stop();
    }
}

/// The calling thread's record, zones in the order they were first left.
pub fn profile_read() -> Result<Vec<ProfileZone>, PhysicsError> {
    let mut total = 0;
    // SAFETY: capacity 0 with a null buffer only counts.
    check("profile_read", unsafe {
        sys::bs_profile_read(std::ptr::null_mut(), 0, &mut total)
    })?;
    let mut buf = vec![sys::bs_profile_entry::default(); total.max(0) as usize];
    // SAFETY: buf holds `total` writable entries.
    check("profile_read", unsafe {
        sys::bs_profile_read(buf.as_mut_ptr(), total, &mut total)
    })?;
    buf.truncate(total.max(0) as usize);
    Ok(buf
        .iter()
        .map(|e| {
            let bytes: Vec<u8> = e
                .name
                .iter()
                .take_while(|&&c| c != 0)
                .map(|&c| c as u8)
                .collect();
            ProfileZone {
                name: String::from_utf8_lossy(&bytes).into_owned(),
                seconds: e.seconds,
                calls: e.calls.max(0) as u64,
                depth: e.depth.max(0) as u32,
            }
        })
        .collect())
}

/// Sets the **process-global** `gDeactivationTime` \[s\]: how long a body must stay below
/// its sleeping thresholds before its island may sleep (Bullet's default 2 s).
pub fn set_global_deactivation_time(seconds: f64) -> Result<(), PhysicsError> {
    // SAFETY: plain value argument; the shim validates it.
    check("set_global_deactivation_time", unsafe {
        sys::bs_set_global_deactivation_time(seconds)
    })
}

/// The process-global `gDeactivationTime` \[s\].
pub fn global_deactivation_time() -> f64 {
    // SAFETY: reads a global double.
    unsafe { sys::bs_get_global_deactivation_time() }
}

impl World {
    /// Solver threads (module docs); 1 = Bullet's sequential path. Results do not depend on
    /// the number.
    pub fn set_solver_threads(&mut self, n: usize) -> Result<(), PhysicsError> {
        let n = i32::try_from(n)
            .map_err(|_| PhysicsError::Invalid(format!("solver threads {n} is too large")))?;
        // SAFETY: live world; the shim validates n.
        check("set_solver_threads", unsafe {
            sys::bs_world_set_solver_threads(self.raw_ptr(), n)
        })
    }

    /// The solver's sweep and joint set-up ([`Sweep`]; [`Sweep::Packed`] by default). Every
    /// kind gives the same bits, for any number of solver threads.
    pub fn set_sweep(&mut self, sweep: Sweep) -> Result<(), PhysicsError> {
        let code = match sweep {
            Sweep::Bullet => sys::BS_SWEEP_BULLET,
            Sweep::Lean => sys::BS_SWEEP_LEAN,
            Sweep::Packed => sys::BS_SWEEP_PACKED,
            Sweep::PackedThreads => sys::BS_SWEEP_PACKED_THREADS,
        };
        // SAFETY: live world; the shim validates the code.
        check("set_sweep", unsafe {
            sys::bs_world_set_sweep(self.raw_ptr(), code as i32)
        })
    }

    /// Joint set-ups and packed sweeps (one each per solver batch and substep) that ran on
    /// the solver threads so far (with more than one thread: the set-up of a batch of at
    /// least 64 constraints under [`Sweep::Packed`] when it measures faster, or always under
    /// [`Sweep::PackedThreads`]; the sweep of a batch with more than half of the substep's
    /// rows and at least 256 joint rows under [`Sweep::PackedThreads`]).
    pub fn parallel_counts(&self) -> Result<ParallelCounts, PhysicsError> {
        let (mut setups, mut sweeps) = (0i64, 0i64);
        // SAFETY: live world, writable integers.
        check("parallel_counts", unsafe {
            sys::bs_world_parallel_counts(self.raw_ptr(), &mut setups, &mut sweeps)
        })?;
        Ok(ParallelCounts {
            joint_setups: setups.max(0) as u64,
            sweeps: sweeps.max(0) as u64,
        })
    }

    /// The solver threads in force.
    pub fn solver_threads(&self) -> Result<usize, PhysicsError> {
        let mut n = 0;
        // SAFETY: live world, writable int.
        check("get_solver_threads", unsafe {
            sys::bs_world_get_solver_threads(self.raw_ptr(), &mut n)
        })?;
        Ok(n.max(0) as usize)
    }

    /// Solver work since the last [`World::reset_island_stats`] (or the world's creation).
    pub fn island_stats(&self) -> Result<IslandStats, PhysicsError> {
        let mut s = sys::bs_island_stats::default();
        // SAFETY: live world, writable struct.
        check("island_stats", unsafe {
            sys::bs_world_island_stats(self.raw_ptr(), &mut s)
        })?;
        let u = |x: i64| x.max(0) as u64;
        Ok(IslandStats {
            substeps: u(s.substeps),
            batches: u(s.batches),
            rows_total: u(s.rows_total),
            rows_largest: u(s.rows_largest),
            bodies_awake: u(s.bodies_awake),
        })
    }

    /// Clears the island statistics.
    pub fn reset_island_stats(&mut self) -> Result<(), PhysicsError> {
        // SAFETY: live world.
        check("reset_island_stats", unsafe {
            sys::bs_world_reset_island_stats(self.raw_ptr())
        })
    }

    /// Bullet's sleeping thresholds of body `b` (`setSleepingThresholds`): linear \[m/s\] and
    /// angular \[rad/s\] speed below which it counts as still (Bullet's defaults 0.8, 1.0).
    pub fn set_sleeping_thresholds(
        &mut self,
        b: super::types::BodyHandle,
        linear_mps: f64,
        angular_radps: f64,
    ) -> Result<(), PhysicsError> {
        let i = self.body_index(b)?;
        // SAFETY: live world, checked index; the shim validates the values.
        check("set_sleeping_thresholds", unsafe {
            sys::bs_body_set_sleeping_thresholds(self.raw_ptr(), i, linear_mps, angular_radps)
        })
    }

    /// Dynamic bodies asleep now (`ISLAND_SLEEPING`).
    pub fn num_sleeping(&self) -> Result<usize, PhysicsError> {
        let mut n = 0;
        // SAFETY: live world, writable int.
        check("num_sleeping", unsafe {
            sys::bs_world_num_sleeping(self.raw_ptr(), &mut n)
        })?;
        Ok(n.max(0) as usize)
    }
}
