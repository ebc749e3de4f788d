//! Collapse criteria on closed-form (synthetic) displacement fields over frame3.
use fem2rbd_fe::collapse::{
    CollapseError, CollapseMonitor, ColumnLine, Criterion, Structure, Trigger, FEMA356_DRIFT,
    GB50011_DRIFT,
};
use fem2rbd_fe::model::Model;

const TOML: &str = concat!(
    concat!(env!("CARGO_MANIFEST_DIR"), "/../.."),
    "/data/frame3-standin/model.toml"
);

fn frame3() -> Model {
    Model::load(TOML).unwrap()
}

#[test]
fn frame3_levels_stories_and_main_nodes() {
    let m = frame3();
    let s = Structure::of_model(&m).unwrap();
    assert_eq!(s.levels, [0.0, 1.0, 2.0, 3.0]);
    assert_eq!(s.story_heights(), [1.0, 1.0, 1.0]);
    assert_eq!(
        s.stories.iter().map(Vec::len).collect::<Vec<_>>(),
        [4, 4, 4]
    );
    // story 1, first column line: base node 1 up to floor-1 corner 101 (through mid node 51)
    assert!(s.stories[0].contains(&ColumnLine {
        bottom: 1,
        top: 101
    }));
    // every node but the 3 bay centres is on a column or beam (strips/panels are not main)
    assert_eq!(s.main_nodes.len(), 43 - 3);
    assert_eq!(
        Criterion::paper_default(&m),
        Criterion::VerticalDrop { threshold_m: 0.25 }
    );
    assert_eq!(GB50011_DRIFT, 0.02);
    assert_eq!(FEMA356_DRIFT, 0.04);
}

#[test]
fn vertical_drop_triggers_exactly_at_the_threshold_step() {
    let m = frame3();
    let mut mon = CollapseMonitor::new(&m, Criterion::paper_default(&m)).unwrap();
    // node 121 sinks 0.0625 m per step; the bay centre 112 (not a main node) sinks faster
    let field = |k: usize| -> Vec<[f64; 3]> {
        m.nodes
            .iter()
            .map(|n| match n.tag {
                121 => [0.01, 0.0, -0.0625 * k as f64],
                112 => [0.0, 0.0, -(k as f64)],
                _ => [0.0, 0.0, -0.01 * k as f64],
            })
            .collect()
    };
    for k in 0..4 {
        assert!(
            mon.observe(k, 0.01 * k as f64, &field(k)).is_none(),
            "step {k}"
        );
    }
    let ev = *mon.observe(4, 0.04, &field(4)).unwrap();
    assert_eq!(ev.step, 4);
    assert_eq!(
        ev.trigger,
        Trigger::VerticalDrop {
            node: 121,
            drop_m: 0.25,
            threshold_m: 0.25
        }
    );
    assert!(ev.to_string().contains("node 121 dropped 0.25 m"));
    // later steps keep the first event
    assert_eq!(mon.observe(5, 0.05, &field(5)).unwrap().step, 4);
}

#[test]
fn uniformly_sheared_story_drifts_by_the_imposed_angle() {
    let m = frame3();
    let gamma = 0.03_f64;
    // story 2 (z in [1, 2]) sheared by gamma along a direction 30° from X; rigid above
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let u: Vec<[f64; 3]> = m
        .nodes
        .iter()
        .map(|n| {
            let d = gamma * (n.z - 1.0).clamp(0.0, 1.0);
            [d * c, d * s, 0.0]
        })
        .collect();
    let st = Structure::of_model(&m).unwrap();
    let drifts = st.story_drifts(&u);
    assert_eq!(drifts[0].0, 0.0);
    assert!((drifts[1].0 - gamma).abs() < 1e-15, "{}", drifts[1].0);
    assert!(drifts[2].0.abs() < 1e-15);

    let mut gb = CollapseMonitor::new(
        &m,
        Criterion::StoryDrift {
            ratio: GB50011_DRIFT,
        },
    )
    .unwrap();
    let ev = *gb.observe(7, 1.5, &u).unwrap();
    match ev.trigger {
        Trigger::StoryDrift {
            story,
            ratio,
            limit,
            ..
        } => {
            assert_eq!(story, 2);
            assert!((ratio - gamma).abs() < 1e-15);
            assert_eq!(limit, 0.02);
        }
        other => panic!("{other:?}"),
    }
    // FEMA 356's 4 % is not reached by 3 %
    let mut fema = CollapseMonitor::new(
        &m,
        Criterion::StoryDrift {
            ratio: FEMA356_DRIFT,
        },
    )
    .unwrap();
    assert!(fema.observe(7, 1.5, &u).is_none());
    // a rigid-body translation of the whole frame drifts nothing
    let t: Vec<[f64; 3]> = m.nodes.iter().map(|_| [0.3, -0.2, 0.1]).collect();
    assert!(st.story_drifts(&t).iter().all(|d| d.0.abs() < 1e-15));
    // closure form, by node tag
    let mut by_tag = CollapseMonitor::new(&m, Criterion::StoryDrift { ratio: 0.02 }).unwrap();
    let z: std::collections::BTreeMap<u32, f64> = m.nodes.iter().map(|n| (n.tag, n.z)).collect();
    let ev = by_tag
        .observe_with(3, 0.3, |tag| {
            [gamma * (z[&tag] - 1.0).clamp(0.0, 1.0), 0.0, 0.0]
        })
        .unwrap();
    assert!(matches!(ev.trigger, Trigger::StoryDrift { story: 2, .. }));
}

#[test]
fn bad_criteria_are_errors() {
    let m = frame3();
    let e = CollapseMonitor::new(&m, Criterion::VerticalDrop { threshold_m: 0.0 }).unwrap_err();
    assert_eq!(e, CollapseError::Threshold(0.0));
    let e = CollapseMonitor::new(&m, Criterion::StoryDrift { ratio: f64::NAN }).unwrap_err();
    assert!(
        matches!(e, CollapseError::DriftLimit(r) if r.is_nan()),
        "{e}"
    );
}
