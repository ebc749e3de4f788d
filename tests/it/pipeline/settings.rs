//! One resolution of the ruin stage's settings: the command line (`fem2rbd run --mode`,
//! a study entry's mode) and the library resolve a scenario's `[physics]` table the same
//! way, the rigid-only default is the `bcb` preset and the ruin stage's own default
//! (`StageSettings::bcb`), and the hybrid default (`fem2rbd`) differs from it on the
//! keys its preset lists.
use fem2rbd::pipeline::preset::Preset;
use fem2rbd::pipeline::{stage_settings, ConnectionModel, Mode, Scenario};
use fem2rbd::ruin::axial::AxialRows;
use fem2rbd::ruin::separation::PairsTouch;
use fem2rbd::ruin::stage::StageSettings;
use std::path::PathBuf;

/// The shipped frame3 LC5 scenario (`mode = "hybrid"`, its `[physics]` table last).
fn lc5() -> (PathBuf, String) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/frame3/lc5.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\nmode = \"hybrid\"\n"));
    (path, text)
}

/// The LC5 scenario with `mode = mode` in the file and `physics` appended to `[physics]`.
fn lc5_in(mode: Mode, physics: &str) -> Scenario {
    let (path, text) = lc5();
    let text = text.replace(
        "\nmode = \"hybrid\"\n",
        &format!("\nmode = \"{}\"\n", mode.name()),
    ) + "\n"
        + physics
        + "\n";
    Scenario::parse(&text, &path).unwrap()
}

/// `fem2rbd run --mode M` loads the file and sets the mode ([`Scenario::set_mode`]); the
/// settings are those of the same file saying `mode = "M"`, whichever mode the file has.
#[test]
fn the_command_line_mode_resolves_as_the_file_mode() {
    let (path, _) = lc5();
    for mode in [Mode::Hybrid, Mode::Rigid, Mode::Fe] {
        let in_file = lc5_in(mode, "");
        for file_mode in [Mode::Hybrid, Mode::Rigid] {
            let mut on_command_line = lc5_in(file_mode, "");
            on_command_line.set_mode(mode);
            assert_eq!(on_command_line.mode, mode);
            assert_eq!(on_command_line.physics, in_file.physics, "{mode:?}");
            assert_eq!(
                stage_settings(&on_command_line),
                stage_settings(&in_file),
                "{mode:?} over {file_mode:?}"
            );
        }
        // The shipped file loaded from disk, as the command line reads it.
        let mut loaded = Scenario::load(&path).unwrap();
        loaded.set_mode(mode);
        assert_eq!(loaded.physics, in_file.physics);
    }
    // Keys given in the file still apply after the mode changes.
    let mut sc = lc5_in(Mode::Hybrid, "steps_per_second = 400");
    sc.set_mode(Mode::Rigid);
    assert_eq!(sc.physics.steps_per_second, 400.0);
    assert_eq!(sc.physics.preset, Preset::Bcb);
}

/// The BCB baseline: a rigid-only run that sets nothing runs the `bcb` preset, and
/// its stage settings are the ruin stage's own defaults.
#[test]
fn bcb_baseline_is_the_rigid_only_default_and_the_stage_default() {
    let sc = lc5_in(Mode::Rigid, "");
    assert_eq!(sc.physics, Preset::Bcb.physics());
    assert_eq!(sc.physics.connections, ConnectionModel::Formula);
    assert_eq!(stage_settings(&sc), StageSettings::bcb());
    let s = StageSettings::bcb();
    assert_eq!(s.ruin.steps_per_second, 200.0);
    assert_eq!(s.ruin.solver_iterations, 100);
    assert_eq!(s.ruin.axial_rows, AxialRows::Bcb);
    assert_eq!(s.joints.warmstart, 0.0);
    assert_eq!(s.touch.pairs, PairsTouch::Never);
    assert!(s.touch.ground_under_connected_bases);
}

/// The hybrid default is the `fem2rbd` preset: BCB's stage with FE-derived connections,
/// the two-way axial row, pairs touching once yielded, bases off the ground while joined
/// and a joint warm start of 0.5 — nothing else.
#[test]
fn hybrid_default_is_bcb_with_the_fem2rbd_keys() {
    for mode in [Mode::Hybrid, Mode::Fe] {
        let sc = lc5_in(mode, "");
        assert_eq!(sc.physics, Preset::Fem2rbd.physics());
        assert_eq!(sc.physics.connections, ConnectionModel::Fe);
        let mut expected = StageSettings::bcb();
        expected.ruin.axial_rows = AxialRows::TwoWay;
        expected.touch.pairs = PairsTouch::OnceYielded;
        expected.touch.ground_under_connected_bases = false;
        expected.joints.warmstart = 0.5;
        expected.ruin.solver_iterations = 400;
        assert_eq!(stage_settings(&sc), expected);
    }
}

/// `connections` given against the preset's model brings the rows of the preset built on
/// it; a key given beside it wins.
#[test]
fn connections_given_bring_their_presets_rows() {
    let formula = lc5_in(Mode::Hybrid, "connections = \"formula\"");
    assert_eq!(formula.physics.preset, Preset::Fem2rbd);
    assert_eq!(formula.physics.axial_rows, AxialRows::Bcb);
    assert_eq!(formula.physics.connected_pairs_touch, PairsTouch::Never);
    assert!(formula.physics.ground_under_connected_bases);
    assert_eq!(formula.physics.joint_warmstart, 0.0);
    let fe = lc5_in(Mode::Rigid, "connections = \"fe\"");
    assert_eq!(fe.physics.preset, Preset::Bcb);
    assert_eq!(fe.physics.axial_rows, AxialRows::TwoWay);
    assert_eq!(fe.physics.connected_pairs_touch, PairsTouch::OnceYielded);
    assert!(!fe.physics.ground_under_connected_bases);
    assert_eq!(fe.physics.joint_warmstart, 0.5);
    let given = lc5_in(
        Mode::Hybrid,
        "connections = \"formula\"\nexperimental.axial_rows = \"two_way\"\n\
         experimental.joint_warmstart = 0.25",
    );
    assert_eq!(given.physics.axial_rows, AxialRows::TwoWay);
    assert_eq!(given.physics.joint_warmstart, 0.25);
    assert_eq!(given.physics.connected_pairs_touch, PairsTouch::Never);
}

/// The binary's options reach the ruin stage as values: threads and traces from the
/// scenario's run controls (`fem2rbd run --threads`, `--trace-body`), the sweep from
/// `[physics.experimental] sweep`; a traced body that does not exist is an error naming
/// the option and the body.
#[test]
fn threads_traces_and_sweep_reach_the_stage_as_values() {
    use fem2rbd::bullet::Sweep;
    use fem2rbd::pipeline::rigid_only_stage;
    use fem2rbd::pipeline::scenario::SweepSpec;
    use fem2rbd::ruin::stage::BodyTraceSettings;
    assert_eq!(lc5_in(Mode::Rigid, "").physics.sweep, SweepSpec::Packed);
    let mut sc = lc5_in(Mode::Rigid, "experimental.sweep = \"lean\"");
    assert_eq!(stage_settings(&sc).speed.sweep, Sweep::Lean);
    sc.threads = Some(3);
    sc.traces.body = Some(BodyTraceSettings {
        path: "t.txt".into(),
        body: "Column:99:99".into(),
        from_s: 0.5,
        to_s: 1.0,
    });
    let s = stage_settings(&sc);
    assert_eq!(s.speed.solver_threads, 3);
    assert_eq!(s.traces, sc.traces);
    let err = match rigid_only_stage(&sc, &|_| ()) {
        Ok(_) => panic!("a trace of a body that does not exist"),
        Err(e) => e.to_string(),
    };
    assert!(
        err.contains("--trace-body") && err.contains("Column:99:99"),
        "{err}"
    );
}
