//! The connections' axial rows (`fem2rbd::ruin::axial`): BCB's two one-way rows hand a
//! column's load back and forth between the compression and the tension constraint, so
//! in some substeps no row carries it (the piece loses its support for a substep); one
//! two-way row carries it in every substep. And the two-way row breaks in tension at BCB's
//! tension strength (which also checks Bullet's sign of a compressive impulse), leaving
//! BCB's compression row.

use fem2rbd::ruin::axial::{axial_offset, AxialRows, COMPRESSION_SIGN};
use fem2rbd::ruin::connection::GroupStrength;
use fem2rbd::ruin::ground::GroundSpec;
use fem2rbd::ruin::stage::{to_isometry, RuinStage, StageInput, StageSettings};

const G: f64 = 9.81;

use crate::support::{column_pieces, per_area_group, rc_box as body, rc_per_area};

fn group(name: &str, t: f64) -> GroupStrength {
    per_area_group(name, rc_per_area(t, 1.0, None))
}

/// What the axial rows of the column's joints carried, substep by substep.
struct Support {
    /// Joint-substeps in which the axial rows carried less than a quarter of the static
    /// impulse (the weight above the joint × h).
    lost: usize,
    /// Sign changes of the joints' axial offsets (in BCB's form: hand-overs between the
    /// compression and the tension row).
    sign_changes: usize,
    /// Largest change of the block's vertical velocity in one substep, m/s.
    max_dv: f64,
}

/// `pieces` 6.25 kg column pieces (0.1 × 0.1 × 0.25 m, frame3's) stacked on a fixed
/// foundation carry a 700 kg block (a frame3 slab panel's mass) under gravity for 1 s,
/// 200 substeps/s, `iterations` solver iterations.
fn column_under_block(rows: AxialRows, pieces: usize, iterations: u32) -> Support {
    let mut bodies = vec![body("foundation", [0.0, 0.0, 0.1], [0.15, 0.15, 0.1], true)];
    let mut masses = vec![0.0];
    column_pieces(&mut bodies, &mut masses, 0.2, pieces);
    let top = 0.2 + 0.25 * pieces as f64 + 0.1;
    bodies.push(body("block", [0.0, 0.0, top], [0.5, 0.5, 0.1], false));
    masses.push(700.0);
    let groups = [group("rc", 5.2), group("base", 5.2)];
    let input = StageInput::rigid_only(&bodies, &masses, &groups);
    let mut settings = StageSettings::bcb();
    settings.ruin.axial_rows = rows;
    settings.ruin.solver_iterations = iterations;
    let mut stage = RuinStage::build(&input, GroundSpec::default(), &settings).unwrap();
    let nb = bodies.len();
    assert_eq!(stage.connections().len(), pieces + 1);
    let h = stage.substep_s();
    let (mut lost, mut sign_changes, mut max_dv) = (0, 0, 0.0_f64);
    let mut signs = vec![0.0; stage.connections().len()];
    let mut vz = 0.0;
    for step in 0..200 {
        stage.substeps(1).unwrap();
        let w = stage.world();
        for (ci, c) in stage.connections().iter().enumerate() {
            let above: f64 = masses[c.b.max(c.a)..].iter().sum();
            let mut carried = 0.0;
            for &hd in &stage.constraint_handles(ci)[..2] {
                if w.constraint_enabled(hd).unwrap() {
                    carried += w.applied_impulse(hd).unwrap() * COMPRESSION_SIGN;
                }
            }
            let pa = to_isometry(&w.pose(stage.body(c.a)).unwrap());
            let pb = to_isometry(&w.pose(stage.body(c.b)).unwrap());
            let f = &c.constraints[0];
            let x = axial_offset(&pa, &pb, &f.frame_a, &f.frame_b).signum();
            // The first substeps build the load up from frames that coincide.
            if step >= 20 {
                if carried < 0.25 * above * G * h {
                    lost += 1;
                }
                if x != signs[ci] {
                    sign_changes += 1;
                }
            }
            signs[ci] = x;
        }
        let v = w.velocity(stage.body(nb - 1)).unwrap().linear[2];
        if step >= 20 {
            max_dv = max_dv.max((v - vz).abs());
        }
        vz = v;
    }
    Support {
        lost,
        sign_changes,
        max_dv,
    }
}

/// Three pieces under the block, 100 iterations (BCB's): measured, BCB's rows leave a
/// joint without axial support in 8 joint-substeps of 180 (4 sign changes of an axial
/// offset), and the block then falls freely for a substep (|Δv| = g·h = 0.049 m/s); the
/// two-way row carries every joint in every substep (|Δv| 0.001 m/s), although its
/// offsets change sign 53 times.
#[test]
fn two_way_axial_row_carries_a_column_in_every_substep() {
    let bcb = column_under_block(AxialRows::Bcb, 3, 100);
    let two = column_under_block(AxialRows::TwoWay, 3, 100);
    eprintln!(
        "BCB rows: {} joint-substeps without support, {} sign changes, largest |dv| {:.4} m/s; \
         two-way: {}, {}, {:.4} m/s",
        bcb.lost, bcb.sign_changes, bcb.max_dv, two.lost, two.sign_changes, two.max_dv
    );
    let free_fall = G * 0.005;
    assert_eq!(two.lost, 0, "the two-way row lost the support");
    assert!(two.max_dv < 0.1 * free_fall, "two-way |dv| {}", two.max_dv);
    assert!(bcb.lost > 0, "BCB's rows never lost the support");
    assert!(
        bcb.max_dv > 0.8 * free_fall,
        "BCB's rows: largest |dv| {} is no substep of free fall",
        bcb.max_dv
    );
}

/// A 225 kg box hangs from a fixed support by one connection: tension W = 2207 N. Its
/// two-way axial row breaks when W·h ≥ T·2.2·h (T the connection's tension capacity, ×2
/// towards a passive partner), whatever the compression capacity, and leaves BCB's
/// one-way compression row: the box falls.
fn hanging_box_drop(rows: AxialRows, t_per_mm2: f64) -> (f64, bool) {
    let bodies = [
        body("support", [0.0, 0.0, 2.1], [0.15, 0.15, 0.1], true),
        body("box", [0.0, 0.0, 1.5], [0.15, 0.15, 0.5], false),
    ];
    let masses = [0.0, 225.0];
    let groups = [group("rc", t_per_mm2), group("base", t_per_mm2)];
    let input = StageInput::rigid_only(&bodies, &masses, &groups);
    let mut settings = StageSettings::bcb();
    settings.ruin.axial_rows = rows;
    let ground = GroundSpec {
        top_z: Some(0.0),
        ..GroundSpec::default()
    };
    let mut stage = RuinStage::build(&input, ground, &settings).unwrap();
    assert_eq!(stage.connections().len(), 1);
    let axial = stage.constraint_handles(0)[0];
    stage.substeps(100).unwrap();
    let z = stage.world().pose(stage.body(1)).unwrap().position[2];
    let on = stage.world().constraint_enabled(axial).unwrap();
    (1.5 - z, on)
}

#[test]
fn two_way_axial_row_breaks_in_tension_at_the_tension_strength() {
    // T = 0.001 N/mm² · 0.09 m² · 2 = 180 N, 2.2·T = 396 N < W = 2207 N: breaks.
    // T = 1 N/mm²: 180 kN: holds. C = 35 N/mm² either way (6.3 MN).
    let (drop_weak, on_weak) = hanging_box_drop(AxialRows::TwoWay, 0.001);
    let (drop_strong, _) = hanging_box_drop(AxialRows::TwoWay, 1.0);
    let (drop_bcb, _) = hanging_box_drop(AxialRows::Bcb, 0.001);
    eprintln!(
        "hanging box after 0.5 s: two-way weak T drops {drop_weak:.4} m (axial row left on: \
         {on_weak}), strong T {drop_strong:.2e} m, BCB rows weak T {drop_bcb:.4} m"
    );
    // Free fall for ~0.5 s: 1.2 m; the bending and shear rows do not hold the axis.
    assert!(drop_weak > 0.5, "two-way row did not break in tension");
    assert!(
        on_weak,
        "the compression row must be left after a tension break"
    );
    assert!(drop_strong.abs() < 1e-3, "strong row let go: {drop_strong}");
    assert!(
        (drop_weak - drop_bcb).abs() < 0.05,
        "two-way {drop_weak} m vs BCB {drop_bcb} m"
    );
}

/// A 225 kg box stands on a fixed support (compression W = 2207 N) with a tension
/// strength far below its weight: the two-way row starts at the smaller (tension)
/// threshold, Bullet's sign-blind test trips on the compressive impulse, and the stage
/// must enable the row again (not a break: the compression strength is 6.3 MN). Collisions
/// between connected bodies are off, so a lost compression row would let the box fall
/// through the support.
#[test]
fn two_way_axial_row_is_not_broken_in_compression_by_the_tension_threshold() {
    let bodies = [
        body("support", [0.0, 0.0, 1.1], [0.15, 0.15, 0.1], true),
        body("box", [0.0, 0.0, 1.7], [0.15, 0.15, 0.5], false),
    ];
    let masses = [0.0, 225.0];
    let groups = [group("rc", 0.001), group("base", 0.001)];
    let input = StageInput::rigid_only(&bodies, &masses, &groups);
    let mut settings = StageSettings::bcb();
    settings.ruin.axial_rows = AxialRows::TwoWay;
    let ground = GroundSpec {
        top_z: Some(0.0),
        ..GroundSpec::default()
    };
    let mut stage = RuinStage::build(&input, ground, &settings).unwrap();
    let axial = stage.constraint_handles(0)[0];
    stage.substeps(100).unwrap();
    let z = stage.world().pose(stage.body(1)).unwrap().position[2];
    let on = stage.world().constraint_enabled(axial).unwrap();
    eprintln!(
        "standing box after 0.5 s: sank {:.3e} m, axial row on: {on}",
        1.7 - z
    );
    assert!(on, "the two-way row was left broken under compression");
    assert!((1.7 - z).abs() < 1e-3, "the box sank {} m", 1.7 - z);
}
