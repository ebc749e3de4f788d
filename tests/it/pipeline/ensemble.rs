//! Ensembles (`fem2rbd run --ensemble N`, `fem2rbd::pipeline::ensemble`) on frame3 LC5
//! rigid-only, CI-sized (timeline to 0.8 s): the members do not depend on the number
//! of worker threads (same bytes), member 0 is the plain run, the perturbation of the
//! other members reaches the ruin stage but stays small, and the ensemble statistics are
//! the members' own.
use fem2rbd::pipeline::ensemble::{
    ensemble_summary, member_measures, run_ensemble, write_ensemble,
};
use fem2rbd::pipeline::{self, write, Scenario, Silent};
use std::path::Path;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

fn scenario(dir: &Path) -> Scenario {
    let text = format!(
        r#"model = "{ROOT}/data/frame3/model.toml"
mode = "rigid"

[[ground_motion]]
file = "{ROOT}/data/ground-motions/RSN6_IMPVALL.I_I-ELC180.AT2"
direction = "X"
pga_g = 0.93
time_scale = 0.5

[[ground_motion]]
file = "{ROOT}/data/ground-motions/RSN6_IMPVALL.I_I-ELC-UP.AT2"
direction = "Z"
pga_g = 0.57
time_scale = 0.5

[physics]
time_limit_s = 0.8
"#
    );
    let p = dir.join("ens.toml");
    std::fs::write(&p, text).unwrap();
    Scenario::load(&p).unwrap()
}

fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let mut es: Vec<_> = std::fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        es.sort();
        for e in es {
            if e.is_dir() {
                stack.push(e);
            } else {
                let rel = e.strip_prefix(dir).unwrap().display().to_string();
                out.push((rel, std::fs::read(&e).unwrap()));
            }
        }
    }
    out.sort();
    out
}

#[test]
fn ensemble_members_are_independent_of_threads_and_member_0_is_the_plain_run() {
    let tmp = tempfile::tempdir().unwrap();
    let sc = scenario(tmp.path());
    let n = 3;
    let one = run_ensemble(&sc, n, 42, 1).unwrap();
    let two = run_ensemble(&sc, n, 42, 2).unwrap();
    write_ensemble(&sc, &one, 42, &tmp.path().join("t1")).unwrap();
    write_ensemble(&sc, &two, 42, &tmp.path().join("t2")).unwrap();
    let (a, b) = (files(&tmp.path().join("t1")), files(&tmp.path().join("t2")));
    // Per member seven tables, the three files of the rescue analysis and the marker;
    // ensemble.json, the rescue maps (rescue_map.csv, rescue.json) and the ensemble's
    // marker.
    assert_eq!(a.len(), 3 * 11 + 4);
    for ((na, ba), (nb, bb)) in a.iter().zip(&b) {
        assert_eq!(na, nb);
        assert!(ba == bb, "{na} differs between 1 and 2 threads");
    }
    // Member 0 = `fem2rbd run`.
    let plain = pipeline::run(&sc, &Silent).unwrap();
    let c0 = write::contents(&one[0], false).unwrap();
    let cp = write::contents(&plain, false).unwrap();
    assert!(c0 == cp, "member 0 differs from the plain run");
    // The perturbation (0.01 % of the ground acceleration) reaches the ruin stage: the
    // members' final poses differ, but by less than a body size after 0.8 s.
    for m in 1..n {
        let d = one[m]
            .final_poses
            .iter()
            .zip(&one[0].final_poses)
            .map(|(p, q)| {
                (0..3)
                    .map(|k| (p.position[k] - q.position[k]).powi(2))
                    .sum::<f64>()
                    .sqrt()
            })
            .fold(0.0, f64::max);
        assert!(
            d > 0.0 && d < 0.05,
            "member {m}: largest pose difference {d} m"
        );
    }
    // Statistics are those of the members.
    let s = ensemble_summary(&sc, &one, 42);
    let key = "debris_footprint_area_m2";
    let xs: Vec<f64> = one.iter().map(|r| member_measures(r)[key]).collect();
    let mean = xs.iter().sum::<f64>() / n as f64;
    let st = &s["measures"][key];
    assert!((st["mean"].as_f64().unwrap() - mean).abs() < 1e-6, "{st}");
    let mn = xs.iter().copied().fold(f64::INFINITY, f64::min);
    assert!((st["min"].as_f64().unwrap() - mn).abs() < 1e-6);
    assert_eq!(s["members"], 3);
    // The debris-density map (`fem2rbd plot` on the ensemble folder): shares are counts
    // of members; after 0.8 s the frame still stands, so its column cells hold debris in
    // every member.
    let fig = fem2rbd::plot::density::DensityFigure::load(&tmp.path().join("t1")).unwrap();
    assert_eq!(fig.members, 3);
    for v in fig.share.values() {
        let k = v * 3.0;
        assert!(
            (k - k.round()).abs() < 1e-12 && *v > 0.0 && *v <= 1.0,
            "{v}"
        );
    }
    assert!(fig.share.values().any(|v| *v == 1.0));
    let written = fem2rbd::plot::write_ensemble(
        &tmp.path().join("t1"),
        &tmp.path().join("plots"),
        fem2rbd::plot::ImageFormat::Both,
    )
    .unwrap();
    // The debris-density map and the rescue map, PNG and SVG each.
    assert_eq!(written.len(), 4);
}
