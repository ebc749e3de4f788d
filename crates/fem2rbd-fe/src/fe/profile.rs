//! Process-wide phase timers of the nonlinear analyses, for benchmarks
//! (`src/bin/bench_fe.rs`): wall time spent in element state determination, residual
//! assembly, tangent assembly, numeric factorisation and triangular solves, and how many
//! times each ran. Reading them never changes a result; with several analyses running
//! at once (tests) the totals mix.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// A phase of an equilibrium iteration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Element state determination ([`crate::fe::domain::Domain::set_trial_eq`]).
    ElementUpdate,
    /// Residual: external, resisting and inertia/damping forces.
    Residual,
    /// Assembly of the effective tangent into the sparse pattern.
    Assembly,
    /// Numeric factorisation of the effective tangent.
    Factor,
    /// Forward/backward substitution.
    Solve,
}

const PHASES: usize = 5;
static NANOS: [AtomicU64; PHASES] = [const { AtomicU64::new(0) }; PHASES];
static COUNTS: [AtomicU64; PHASES] = [const { AtomicU64::new(0) }; PHASES];

/// Totals of one phase since the last [`reset`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PhaseTotal {
    /// Wall time (s).
    pub seconds: f64,
    /// Calls.
    pub calls: u64,
}

/// Runs `f` and adds its wall time to `phase`.
pub(crate) fn timed<R>(phase: Phase, f: impl FnOnce() -> R) -> R {
    let t0 = Instant::now();
    let r = f();
    let ns = t0.elapsed().as_nanos() as u64;
    NANOS[phase as usize].fetch_add(ns, Ordering::Relaxed);
    COUNTS[phase as usize].fetch_add(1, Ordering::Relaxed);
    r
}

/// Zeroes every phase total.
pub fn reset() {
    for k in 0..PHASES {
        NANOS[k].store(0, Ordering::Relaxed);
        COUNTS[k].store(0, Ordering::Relaxed);
    }
}

/// The totals of `phase` since the last [`reset`].
pub fn total(phase: Phase) -> PhaseTotal {
    PhaseTotal {
        seconds: NANOS[phase as usize].load(Ordering::Relaxed) as f64 * 1e-9,
        calls: COUNTS[phase as usize].load(Ordering::Relaxed),
    }
}
