//! A floor landing under a column that carries the floor above (frame3's masses and
//! column pieces): how much of the landing the column passes on to the floor above, and
//! how fast, against the solver's iterations and substep (docs/ruin-numerics.md, "Landings").

use fem2rbd::bullet::JointSolve;
use fem2rbd::ruin::axial::{AxialRows, COMPRESSION_SIGN};
use fem2rbd::ruin::connection::GroupStrength;
use fem2rbd::ruin::ground::GroundSpec;
use fem2rbd::ruin::stage::{RuinStage, StageInput, StageSettings};
use fem2rbd::ruin::strength::StrengthPerArea;

use crate::support::{column_pieces, per_area_group, rc_box as body};

const G: f64 = 9.81;

fn strong(name: &str) -> GroupStrength {
    per_area_group(
        name,
        StrengthPerArea {
            c: 1e4,
            t: 1e4,
            s: 1e4,
            s90: None,
            b: 1e4,
            b90: None,
            p: None,
        },
    )
}

/// What the column passed on to the upper block in the landing of the lower one.
#[derive(Debug)]
struct Landing {
    /// The top joint's axial impulse over the 10 ms from the lower block's landing, less
    /// the upper block's weight × 10 ms, over m·v (the upper block's momentum at landing).
    share_10ms: f64,
    /// The upper block's downward speed one substep after the landing, over v.
    speed_after: f64,
}

/// A 700 kg block (a frame3 floor) falls 0.3 m onto a fixed foundation carrying four
/// 6.25 kg column pieces (0.1 × 0.1 × 0.25 m, frame3's) under another 700 kg block; every
/// connection far stronger than the landing (it is the load path, not a failure, that is
/// measured). A rigid stack stops with the lower block: the column passes the upper
/// block's whole momentum m·v (share 1) in the landing substep, and the upper block stops.
fn landing(sps: f64, iterations: u32, solve: JointSolve) -> Landing {
    let (drop, m) = (0.3, 700.0);
    let mut bodies = vec![body("foundation", [0.0, 0.0, 0.1], [0.6, 0.6, 0.1], true)];
    let mut masses = vec![0.0];
    let z1 = 0.2 + drop + 0.05;
    bodies.push(body("floor1", [0.0, 0.0, z1], [0.5, 0.5, 0.05], false));
    masses.push(m);
    column_pieces(&mut bodies, &mut masses, z1 + 0.05, 4);
    bodies.push(body(
        "floor2",
        [0.0, 0.0, z1 + 1.1],
        [0.5, 0.5, 0.05],
        false,
    ));
    masses.push(m);
    let groups = [strong("rc"), strong("base")];
    let input = StageInput::rigid_only(&bodies, &masses, &groups);
    let mut settings = StageSettings::bcb();
    settings.ruin.axial_rows = AxialRows::TwoWay;
    settings.ruin.solver_iterations = iterations;
    settings.ruin.steps_per_second = sps;
    settings.joints.solve = solve;
    let mut stage = RuinStage::build(&input, GroundSpec::default(), &settings).unwrap();
    assert_eq!(stage.connections().len(), 5, "floor1, 3 joints, floor2");
    let top = (0..5)
        .find(|&i| stage.connections()[i].a == 6 || stage.connections()[i].b == 6)
        .unwrap();
    let v = (2.0 * G * drop).sqrt();
    let h = stage.substep_s();
    let (mut landed, mut v1_prev, mut share, mut speed_after) = (None, 0.0, 0.0, None);
    for step in 0..(0.5 * sps) as usize {
        stage.substeps(1).unwrap();
        let w = stage.world();
        let v1 = w.velocity(stage.body(1)).unwrap().linear[2];
        let v2 = w.velocity(stage.body(6)).unwrap().linear[2];
        // The lower block has landed when its fall (beyond 0.8 v) stops (above 0.5 v).
        if landed.is_none() && v1_prev < -0.8 * v && v1 > -0.5 * v {
            landed = Some(step);
        }
        v1_prev = v1;
        let Some(s) = landed else { continue };
        if step == s + 1 {
            speed_after = Some(-v2 / v);
        }
        if ((step - s) as f64) * h < 0.01 {
            let lambda = w.applied_impulse(stage.constraint_handles(top)[0]).unwrap();
            share += (lambda * COMPRESSION_SIGN - m * G * h) / (m * v);
        }
    }
    let landed = landed.expect("the lower block never landed");
    // Free fall of 0.3 m: 0.247 s (to within 10 ms: the contact margin, the substep).
    assert!(((landed + 1) as f64 * h - (2.0 * drop / G).sqrt()).abs() <= 0.01);
    Landing {
        share_10ms: share,
        speed_after: speed_after.unwrap(),
    }
}

/// Measured: with BCB's 100 iterations at 200 substeps/s the column passes only 0.42 of
/// the upper block's momentum in the 10 ms after the landing, and the upper block still
/// falls at 0.58 v a substep later (the rest reaches it later, as joint error pulled back
/// by ERP·e/h); the column then seems stronger than it is, since it is judged per substep.
/// With 400 iterations it passes 1.02 and the block stops (−0.01 v), as the rigid stack
/// does; at 400 and 800 substeps/s with 100 iterations 0.74 and 1.17. How much of a
/// landing the stories above feel depends on the solver's convergence, not on the
/// building (docs/ruin-numerics.md, "Landings").
#[test]
fn a_column_passes_a_landing_on_only_with_enough_iterations() {
    let bcb = landing(200.0, 100, JointSolve::Pgs);
    let more = landing(200.0, 400, JointSolve::Pgs);
    let finer = landing(800.0, 100, JointSolve::Pgs);
    eprintln!("200/100: {bcb:?}\n200/400: {more:?}\n800/100: {finer:?}");
    assert!(
        (0.3..=0.55).contains(&bcb.share_10ms),
        "200 substeps/s, 100 iterations: {bcb:?}"
    );
    assert!(bcb.speed_after > 0.45, "200/100: {bcb:?}");
    assert!(
        (0.9..=1.15).contains(&more.share_10ms),
        "200 substeps/s, 400 iterations: {more:?}"
    );
    assert!(more.speed_after.abs() < 0.05, "200/400: {more:?}");
    assert!(
        (0.9..=1.3).contains(&finer.share_10ms),
        "800 substeps/s, 100 iterations: {finer:?}"
    );
}
