//! The shim's solver against unmodified Bullet: the same ruin stage, driven once on a world
//! of the shim's classes and once on a world of Bullet 3.24's stock classes only
//! (`WorldSettings::stock_solver`: `btSequentialImpulseConstraintSolver` and
//! `btDiscreteDynamicsWorld` as Debian ships them, none of the shim's subclasses), gives the
//! same bits.
//!
//! What the shim's subclasses change (bullet-sys/shim/solver_*.cpp) and what the compared
//! configuration therefore switches off:
//!
//! * the island-parallel solver (`ParallelIslandSolver`): with one solver thread it runs
//!   Bullet's own `solveGroup` sequence; with more it solves the batches on threads with the
//!   kinematic bodies first in every batch. Stock Bullet has one thread, so the shim is run
//!   with one and with two;
//! * the sweep (`LeanSolver`): `Sweep::Bullet` is Bullet's own `solveSingleIteration` and
//!   `convertJoints`; `Sweep::Packed` (the default) is the same arithmetic over packed rows.
//!   Both are compared;
//! * the joint warm start (`WarmJointSolver`) and the direct joint solve
//!   (`DirectJointSolver`) are features stock Bullet does not have: they change the
//!   iterates, so they are off (the rigid-only defaults: warm start 0, projected
//!   Gauss–Seidel). A stock world refuses them.
use fem2rbd::bullet::Sweep;

/// Simulated seconds of LC5 compared: the first second of the time-compressed record
/// leaves every connection elastic; by 3 s the frame has collapsed (connections plastic
/// and broken, pieces in contact with each other and the ground).
const SECONDS: f64 = 3.0;
use fem2rbd::pipeline::{rigid_only_stage, Scenario};
use fem2rbd::ruin::connection::ConnectionState;
use fem2rbd::ruin::stage::{RuinResult, SpeedSettings, StageSettings, StopRule};

/// [`SECONDS`] of frame3 under LC5, rigid-only (BCB's CT 22 breakable 6-DoF spring connections,
/// 200 substeps/s, 100 iterations), on the given world.
fn run(sc: &Scenario, stock: bool, threads: usize, sweep: Sweep) -> RuinResult {
    let adjust = move |s: &mut StageSettings| {
        s.world.stock_solver = stock;
        s.speed = SpeedSettings {
            solver_threads: threads,
            sweep,
        };
    };
    let mut stage = rigid_only_stage(sc, &adjust).unwrap();
    assert_eq!(stage.world().is_stock(), stock);
    stage
        .run(&StopRule {
            max_time_s: SECONDS,
            rest: None,
        })
        .unwrap()
}

/// Frame3 rigid-only, 3 s of LC5: the shim's solver with Bullet's sweep on one thread,
/// and its default packed sweep on two, give every body's pose in every frame, the final
/// velocities and every connection's plastic and breaking times bit for bit as Debian's
/// unmodified Bullet does. The run is not trivial: connections turn plastic or break and
/// the frame collapses (measured: 91 of 156 connections plastic or broken, a piece
/// 3.4 m from its start).
#[test]
fn the_shims_solver_gives_stock_bullets_bits_on_frame3() {
    let text = crate::support::frame3_lc5("rigid", "criterion = \"vertical_drop\"", "", "");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("lc5.toml");
    std::fs::write(&path, text).unwrap();
    let sc = Scenario::load(&path).unwrap();
    let stock = run(&sc, true, 1, Sweep::Bullet);
    assert!(
        stock.islands.is_none(),
        "a stock world keeps no island stats"
    );
    let changed = stock
        .connections
        .iter()
        .filter(|c| c.state != ConnectionState::Elastic)
        .count();
    let first = &stock.frames[0].poses;
    let moved = stock
        .final_poses
        .iter()
        .zip(first)
        .map(|(a, b)| {
            let d: f64 = (0..3)
                .map(|k| (a.position[k] - b.position[k]).powi(2))
                .sum();
            d.sqrt()
        })
        .fold(0.0, f64::max);
    eprintln!(
        "stock Bullet, frame3 LC5 {SECONDS} s: {} bodies, {} connections, {changed} plastic or broken, \
         largest displacement {:.1} mm",
        first.len(),
        stock.connections.len(),
        moved * 1e3
    );
    assert!(changed > 0, "no connection yielded: the run is trivial");
    assert!(moved > 1.0, "the frame did not collapse: {moved} m");
    for (threads, sweep) in [(1, Sweep::Bullet), (2, Sweep::Packed)] {
        let shim = run(&sc, false, threads, sweep);
        assert!(
            crate::support::ruin_bits(&shim) == crate::support::ruin_bits(&stock),
            "the shim ({sweep:?}, {threads} thread(s)) differs from stock Bullet"
        );
    }
}

/// A stock world refuses what stock Bullet cannot do, naming it, and accepts what it does.
#[test]
fn a_stock_world_refuses_the_shims_solver_features() {
    use fem2rbd::bullet::{JointSolve, World, WorldSettings};
    let mut w = World::new(&WorldSettings {
        stock_solver: true,
        ..WorldSettings::default()
    })
    .unwrap();
    assert!(w.is_stock());
    w.set_solver_threads(1).unwrap();
    w.set_sweep(Sweep::Bullet).unwrap();
    w.set_joint_warmstart(0.0).unwrap();
    w.set_joint_solve(JointSolve::Pgs, 1e-3).unwrap();
    for (what, e) in [
        ("threads", w.set_solver_threads(2).unwrap_err()),
        ("sweep", w.set_sweep(Sweep::Packed).unwrap_err()),
        ("warm start", w.set_joint_warmstart(0.5).unwrap_err()),
        (
            "direct",
            w.set_joint_solve(JointSolve::Direct, 1e-3).unwrap_err(),
        ),
        ("island stats", w.island_stats().unwrap_err()),
    ] {
        let msg = e.to_string();
        assert!(msg.contains("stock world"), "{what}: {msg}");
    }
    assert!(!World::new(&WorldSettings::default()).unwrap().is_stock());
}
