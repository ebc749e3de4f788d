//! Which bodies touch (`fem2rbd::ruin::separation`), through the ruin stage's own code path:
//! a piece whose connection is broken lands on the piece it was joined to instead of
//! passing through it (BCB/Blender's exemption, kept as `PairsTouch::Never`, lets it fall
//! through to the ground), and a base joined to its foundation block stands on that
//! connection alone until the connection no longer carries compression.

use crate::support::{per_area_group, rc_box as body, rc_per_area};
use fem2rbd::ruin::connection::{ConnectionState, GroupStrength};
use fem2rbd::ruin::ground::GroundSpec;
use fem2rbd::ruin::monitor::FeDamage;
use fem2rbd::ruin::separation::PairsTouch;
use fem2rbd::ruin::stage::{RuinStage, StageInput, StageSettings, StopRule, TouchSettings};

const G: f64 = 9.81;

fn group(name: &str) -> GroupStrength {
    per_area_group(name, rc_per_area(5.2, 1.0, None))
}

fn run_for(stage: &mut RuinStage, seconds: f64) -> fem2rbd::ruin::stage::RuinResult {
    stage
        .run(&StopRule {
            max_time_s: seconds,
            rest: None,
        })
        .unwrap()
}

/// Two 0.3 × 0.3 × 1 m boxes stacked on the ground, their connection broken from the start
/// (an FE end that lost its load path). Closed form: the upper box rests on the lower one,
/// centre at z = 1.5 m. With BCB's exemption it falls through the lower box to the ground,
/// z = 0.5 m.
#[test]
fn a_piece_whose_connection_is_broken_rests_on_the_piece_it_was_joined_to() {
    let bodies = vec![
        body("lower", [0.0, 0.0, 0.5], [0.15, 0.15, 0.5], false),
        body("upper", [0.0, 0.0, 1.5], [0.15, 0.15, 0.5], false),
    ];
    let masses = vec![225.0, 225.0];
    let groups = [group("rc")];
    let mut input = StageInput::rigid_only(&bodies, &masses, &groups);
    input.start_damage.insert((0, 1), FeDamage::Ruptured);
    let mut z = Vec::new();
    for touch in [PairsTouch::OnceBroken, PairsTouch::Never] {
        let settings = StageSettings {
            touch: TouchSettings {
                pairs: touch,
                ..TouchSettings::default()
            },
            ..StageSettings::bcb()
        };
        let mut stage = RuinStage::build(&input, GroundSpec::default(), &settings).unwrap();
        assert_eq!(stage.monitor().states(), vec![ConnectionState::Broken]);
        let (lo, up) = (stage.body(0), stage.body(1));
        assert_eq!(
            stage.world().collides_with(lo, up).unwrap(),
            touch == PairsTouch::OnceBroken
        );
        let res = run_for(&mut stage, 1.0);
        z.push(res.final_poses[1].position[2]);
    }
    eprintln!(
        "upper box centre: {:.4} m (touching), {:.4} m (BCB)",
        z[0], z[1]
    );
    assert!(
        (z[0] - 1.5).abs() < 2e-3,
        "rests on the lower box: z = {}",
        z[0]
    );
    assert!(
        (z[1] - 0.5).abs() < 2e-3,
        "BCB: through to the ground: z = {}",
        z[1]
    );
}

/// A 0.2 × 0.2 × 1 m column piece (100 kg) on a passive foundation block sunk in the
/// ground, as the pipeline builds a base (the block below the ground's top, the piece's
/// bottom face on it). While the connection carries compression the piece does not touch
/// the ground and the connection carries its whole weight, m·g; with BCB's setting the
/// ground contact takes a share. Once the connection is broken the piece stands on the
/// ground (centre at its half height, 0.5 m).
#[test]
fn a_base_joined_to_its_foundation_stands_on_the_connection_alone() {
    let bodies = vec![
        body("column", [0.0, 0.0, 0.5], [0.1, 0.1, 0.5], false),
        body("foundation", [0.0, 0.0, -0.05], [0.1, 0.1, 0.05], true),
    ];
    let m = 100.0;
    let masses = vec![m, 0.0];
    let groups = [group("rc"), group("base")];
    let ground = GroundSpec {
        top_z: Some(0.0),
        ..GroundSpec::default()
    };
    let mut input = StageInput::rigid_only(&bodies, &masses, &groups);
    let mut share = Vec::new();
    for on_ground in [false, true] {
        let settings = StageSettings {
            touch: TouchSettings {
                ground_under_connected_bases: on_ground,
                ..TouchSettings::default()
            },
            ..StageSettings::bcb()
        };
        let mut stage = RuinStage::build(&input, ground.clone(), &settings).unwrap();
        let (col, gnd) = (stage.body(0), stage.ground());
        assert_eq!(stage.world().collides_with(col, gnd).unwrap(), on_ground);
        let res = run_for(&mut stage, 0.5);
        assert_eq!(res.connections[0].state, ConnectionState::Elastic);
        assert_eq!(res.connections[0].first_row_lost, None);
        let contact = stage.world().contact(col, gnd).unwrap();
        assert_eq!(contact.num_points > 0, on_ground, "{contact:?}");
        // The weight the connection carries: the z forces of its rows on the column.
        let fz: f64 = stage
            .constraint_handles(0)
            .iter()
            .take(6)
            .map(|h| {
                let f = stage.world().joint_feedback(*h).unwrap();
                // The column is body A or B of the connection.
                if stage.connections()[0].a == 0 {
                    f.force_a[2]
                } else {
                    f.force_b[2]
                }
            })
            .sum();
        share.push(fz / (m * G));
    }
    eprintln!(
        "share of the weight on the connection: {:.4} (no ground contact), {:.4} (BCB)",
        share[0], share[1]
    );
    assert!((share[0] - 1.0).abs() < 5e-3, "{}", share[0]);
    // Measured: −0.02 (the warm-started contact takes all of it).
    assert!(
        share[1] < 0.5,
        "BCB: the ground takes a share: {}",
        share[1]
    );

    input.start_damage.insert((0, 1), FeDamage::Ruptured);
    let settings = StageSettings {
        touch: TouchSettings {
            ground_under_connected_bases: false,
            ..TouchSettings::default()
        },
        ..StageSettings::bcb()
    };
    let mut stage = RuinStage::build(&input, ground, &settings).unwrap();
    let (col, gnd) = (stage.body(0), stage.ground());
    assert!(stage.world().collides_with(col, gnd).unwrap());
    let res = run_for(&mut stage, 0.5);
    let z = res.final_poses[0].position[2];
    assert!((z - 0.5).abs() < 2e-3, "stands on the ground: z = {z}");
}
