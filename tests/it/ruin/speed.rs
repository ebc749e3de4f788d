//! Speed options of the ruin stage (docs/performance.md, "Ruin stage"): the island-parallel
//! solver gives the same bytes for any thread count, and sleeping bodies wake when hit.

use fem2rbd::bullet::{BodyKind, BoxDesc, ParallelCounts, Pose, Sweep, World, WorldSettings};
use fem2rbd::motion::{Baseline, GroundHistory, GroundMotion, Record};
use fem2rbd::ruin::connection::{ConnectionState, GroupStrength, Tolerances};
use fem2rbd::ruin::ground::GroundSpec;
use fem2rbd::ruin::stage::{
    RuinResult, RuinStage, SpeedSettings, StageInput, StageSettings, StopRule,
};
use fem2rbd::ruin::strength::{StrengthPerArea, StrengthSource};
use fem2rbd::ruin::BodyGeom;
use nalgebra::UnitQuaternion;

const DT: f64 = 0.001;

/// Six towers of four 0.3 × 0.3 × 1 m boxes (CT 22 between neighbours, weak in bending),
/// 1.2 m apart in a row, on a ground shaken in X at 1 g, 2 Hz: the towers are separate
/// islands, break, topple and hit their neighbours (islands merge and split).
fn towers() -> (Vec<BodyGeom>, Vec<f64>, Vec<GroupStrength>, GroundHistory) {
    let mut bodies = Vec::new();
    for t in 0..6 {
        for k in 0..4 {
            bodies.push(BodyGeom {
                name: format!("t{t}b{k}"),
                group: "rc".into(),
                centre: [1.2 * t as f64, 0.0, 0.5 + k as f64],
                rotation: UnitQuaternion::identity(),
                half_extents: [0.15, 0.15, 0.5],
                passive: false,
            });
        }
    }
    let masses = vec![225.0; bodies.len()];
    let groups = vec![GroupStrength {
        name: "rc".into(),
        strength: StrengthSource::PerArea(StrengthPerArea {
            c: 35.0,
            t: 5.2,
            s: 155.0,
            s90: None,
            b: 0.001,
            b90: None,
            p: Some(0.001),
        }),
        tolerances: Tolerances::default(),
        plastic_length: 0.0,
        threshold_multiplier: 1.0,
    }];
    let n = 3000;
    let a: Vec<f64> = (0..n)
        .map(|i| (2.0 * std::f64::consts::PI * 2.0 * i as f64 * DT).sin())
        .collect();
    let rec = Record::new("sine", DT, 0.0, a).unwrap();
    let hist = GroundMotion::new(Some(rec), None, None)
        .integrate(DT, Baseline::None)
        .unwrap();
    (bodies, masses, groups, hist)
}

/// A wall of 8 × 6 boxes of 0.3 × 0.5 × 0.5 m (CT 22 at 5 % of its strength between
/// neighbours),
/// joined side by side (along Y) and on top of each other, on a ground shaken across its
/// plane (X) at 1 g, 2 Hz: one island of about 80 connections (more than 256 joint rows, so the packed
/// sweep runs on the solver threads) that cracks, breaks and falls.
fn wall() -> (Vec<BodyGeom>, Vec<f64>, Vec<GroupStrength>, GroundHistory) {
    let (_, _, mut groups, hist) = towers();
    groups[0].threshold_multiplier = 0.05;
    let mut bodies = Vec::new();
    for k in 0..6 {
        for i in 0..8 {
            bodies.push(BodyGeom {
                name: format!("w{i}_{k}"),
                group: "rc".into(),
                centre: [0.0, 0.5 * i as f64, 0.25 + 0.5 * k as f64],
                rotation: UnitQuaternion::identity(),
                half_extents: [0.15, 0.25, 0.25],
                passive: false,
            });
        }
    }
    let masses = vec![187.5; bodies.len()];
    (bodies, masses, groups, hist)
}

type Scene = (Vec<BodyGeom>, Vec<f64>, Vec<GroupStrength>, GroundHistory);
type SceneFn = fn() -> Scene;

fn run_towers(threads: usize, batch: u32) -> (RuinResult, fem2rbd::bullet::IslandStats) {
    let (r, s, _, _) = run_scene(towers(), threads, batch, Sweep::Packed);
    (r, s)
}

/// A scene's run (2 s), its island statistics, the contact pairs touching at the end and
/// the solver work that ran on the threads.
fn run_scene(
    scene: Scene,
    threads: usize,
    batch: u32,
    sweep: Sweep,
) -> (
    RuinResult,
    fem2rbd::bullet::IslandStats,
    usize,
    ParallelCounts,
) {
    let (bodies, masses, groups, hist) = scene;
    let input = StageInput::rigid_only(&bodies, &masses, &groups);
    let mut settings = StageSettings {
        speed: SpeedSettings {
            solver_threads: threads,
            sweep,
        },
        ..StageSettings::bcb()
    };
    settings.world.solver.minimum_solver_batch_size = batch;
    let mut stage = RuinStage::build(&input, GroundSpec::moving(hist), &settings).unwrap();
    let r = stage
        .run(&StopRule {
            max_time_s: 2.0,
            rest: None,
        })
        .unwrap();
    let contacts = stage.world().contact_pairs().unwrap().len();
    let counts = stage.world().parallel_counts().unwrap();
    (r, stage.world().island_stats().unwrap(), contacts, counts)
}

fn bits(r: &RuinResult) -> Vec<u64> {
    let mut v = crate::support::ruin_bits(r);
    v.push(r.ledger.injected_j.to_bits());
    v
}

/// Bullet's own sequential solver (1 thread) and the island-parallel one (2 and 3 threads)
/// give the same bits for every frame's poses, the final velocities and every
/// connection's history — with every island a batch of its own (batch size 1) and with
/// Bullet's default batching (islands merged up to 128 constraints and manifolds).
#[test]
fn island_parallel_solver_gives_the_same_bits_for_any_thread_count() {
    for batch in [1, 128] {
        let (r1, s1) = run_towers(1, batch);
        let broken = r1
            .connections
            .iter()
            .filter(|c| c.state == ConnectionState::Broken)
            .count();
        eprintln!(
            "batch size {batch}: {} batches in {} substeps, largest batch {:.2} of the rows, {broken} of {} connections broken",
            s1.batches,
            s1.substeps,
            s1.largest_share(),
            r1.connections.len()
        );
        // The scene exercises what matters: several batches per substep (the parallel
        // path), breaking (done in the sequential finish), and motion.
        if batch == 1 {
            assert!(s1.batches >= 3 * s1.substeps, "{s1:?}");
        }
        assert!(broken > 0, "nothing broke");
        for threads in [2, 3] {
            let (rn, sn) = run_towers(threads, batch);
            assert_eq!(s1, sn, "same islands and rows with {threads} threads");
            assert!(
                bits(&r1) == bits(&rn),
                "{threads} threads differ from 1 (batch size {batch})"
            );
        }
    }
}

/// The lean solver iterations (the shim's sweep without Bullet's per-iteration walk over
/// every constraint for the empty `solveConstraintObsolete`) and the packed sweep (the same
/// row arithmetic over packed copies of the rows, level by level; with more than one thread
/// the joints' set-up on the threads and, for a batch with most of the rows, the sweep on
/// the threads with waits that keep every body's rows in Bullet's order: `PackedThreads`;
/// `Packed` takes the threads for the set-up where they measure faster) give the bits of
/// Bullet's own `solveSingleIteration`: joint rows, contacts with the kinematic ground and
/// between bodies, friction, breaking, joints to the kinematic ground that have no rows in a
/// substep (locked exactly in place at the start). Six towers (separate islands, every
/// island its own batch and Bullet's batching up to 128 constraints and manifolds) and one
/// wall (one island), on 1, 2 and 3 threads.
#[test]
fn lean_and_packed_sweeps_give_bullets_bits() {
    let scenes: [(&str, SceneFn, u32); 3] = [
        ("towers", towers, 1),
        ("towers", towers, 128),
        ("wall", wall, 128),
    ];
    for (name, scene, batch) in scenes {
        let (bullet, sb, _, _) = run_scene(scene(), 1, batch, Sweep::Bullet);
        let broken = bullet
            .connections
            .iter()
            .filter(|c| c.state == ConnectionState::Broken)
            .count();
        eprintln!(
            "{name}: {} connections, {broken} broken",
            bullet.connections.len()
        );
        assert!(broken > 0, "{name}: nothing broke");
        for threads in [1, 2, 3] {
            for sweep in [Sweep::Lean, Sweep::Packed, Sweep::PackedThreads] {
                if sweep != Sweep::PackedThreads && threads == 3 {
                    continue;
                }
                let (r, s, contacts, counts) = run_scene(scene(), threads, batch, sweep);
                eprintln!(
                    "{name}, batch {batch}, {threads} thread(s), {sweep:?}: {} rows in {} \
                     substeps (largest batch {:.2}), {contacts} contact pairs at the end, \
                     {broken} broken, on threads: {counts:?}",
                    s.rows_total,
                    s.substeps,
                    s.largest_share()
                );
                assert!(
                    contacts > 0,
                    "no contacts: the scene does not exercise the contact rows"
                );
                if sweep == Sweep::PackedThreads && threads > 1 && batch == 128 {
                    assert!(
                        counts.joint_setups > 0,
                        "{name}: the joints' set-up never ran on the threads"
                    );
                }
                if sweep == Sweep::PackedThreads && threads > 1 && name == "wall" {
                    assert!(
                        counts.sweeps > 0,
                        "{name}: the sweep never ran on the threads"
                    );
                }
                if sweep != Sweep::PackedThreads {
                    assert_eq!(
                        counts.sweeps, 0,
                        "the sweep on threads without PackedThreads"
                    );
                }
                if threads == 1 || sweep == Sweep::Lean {
                    assert_eq!(counts, ParallelCounts::default());
                }
                assert_eq!(s, sb, "same islands and rows");
                assert!(
                    bits(&r) == bits(&bullet),
                    "{name}: {sweep:?} differs from Bullet's sweep ({threads} thread(s), batch {batch})"
                );
            }
        }
    }
}

/// A box at rest on a still ground falls asleep with sleeping on (its island is not solved
/// any more); a second box dropped onto it wakes it, and it is pushed into the ground's
/// contact as a box that was never asleep would be (the same rest height to 1 mm).
#[test]
fn sleeping_box_wakes_when_hit() {
    let run = |sleep: bool| {
        let mut w = World::new(&WorldSettings::default()).unwrap();
        let g = w
            .add_box(&BoxDesc::fixed([5.0, 5.0, 0.5], Pose::at([0.0, 0.0, -0.5])))
            .unwrap();
        assert_eq!(w.body_kind(g).unwrap(), BodyKind::Static);
        let mut d = BoxDesc::dynamic([0.5; 3], 10.0, Pose::at([0.0, 0.0, 0.5]));
        d.disable_deactivation = !sleep;
        let a = w.add_box(&d).unwrap();
        w.set_sleeping_thresholds(a, 0.025, 0.05).unwrap();
        w.advance(3.0, 1.0 / 200.0).unwrap();
        let asleep = w.num_sleeping().unwrap();
        let mut d2 = BoxDesc::dynamic([0.5; 3], 10.0, Pose::at([0.0, 0.0, 2.5]));
        d2.disable_deactivation = !sleep;
        let b = w.add_box(&d2).unwrap();
        let mut woke = false;
        for _ in 0..400 {
            w.step(1.0 / 200.0, 1).unwrap();
            woke |= w.activation_state(a).unwrap() != 2;
        }
        (
            asleep,
            woke,
            w.pose(a).unwrap().position[2],
            w.pose(b).unwrap().position[2],
        )
    };
    let (asleep, woke, za, zb) = run(true);
    let (never, _, za0, zb0) = run(false);
    eprintln!(
        "sleeping: {asleep} asleep, woke {woke}, z {za:.6} {zb:.6}; never: z {za0:.6} {zb0:.6}"
    );
    assert_eq!(asleep, 1, "the resting box should sleep after 3 s");
    assert_eq!(never, 0);
    assert!(woke, "the hit did not wake the sleeping box");
    assert!((za - za0).abs() < 1e-3 && (zb - zb0).abs() < 1e-3);
    assert!(
        (zb - 1.5).abs() < 0.01,
        "the second box rests on the first: z = {zb}"
    );
}
