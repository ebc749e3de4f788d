//! A snapshot of a ruin distribution, not of one run: an ensemble of frame3 LC5 hybrid
//! members at the current defaults (CI-sized: the FE to the 4 % drift hand-off at about
//! 1.53 s, the ruin stage to 3 s), summarised by the quantiles of its ruin measures and a
//! coarse debris-density grid, each value rounded to what the ensemble resolves. A change
//! that only reshuffles the chaotic pile leaves it; a change that moves the distribution
//! by more than the rounding step shows.
//!
//! How the rounding is chosen: each measure has a fixed step ([`STEPS`]), the 1-2-5 value
//! nearest to half the sample standard deviation this ensemble measured (the next finer
//! one where a value lay within 1 % of a step of its rounding edge: the overlap of slabs
//! 1–2), so a quantile moves by a step when the distribution
//! moves by about half its spread. The grid holds
//! each cell's mean number of active bodies per member, rounded to whole bodies. The
//! members are the same bits for any thread count, so a rounded value can only flip if
//! round-off (about 1e-12 of a value) crosses its rounding edge: the test prints every
//! value's distance from its edge and asserts at least 1 % of a step (micrometres, 1e6
//! times the round-off). At 3 s, 1.5 s after the hand-off, the members are close (floor
//! offsets 0.13–0.23 m with sd 7–10 mm): the snapshot resolves millimetres.
use fem2rbd::pipeline::ensemble::{member_measures, run_ensemble};
use fem2rbd::pipeline::Scenario;
use std::collections::BTreeMap;

/// Members of the ensemble (member 0 the unperturbed run).
const MEMBERS: usize = 8;

/// The ensemble's seed.
const SEED: u64 = 1;

/// Side of a debris-density cell, m.
const CELL_M: f64 = 1.0;

/// The measures (keys of `member_measures`) and their rounding steps.
const STEPS: &[(&str, f64)] = &[
    ("floors[0].horizontal_offset_m", 0.005),
    ("floors[1].horizontal_offset_m", 0.005),
    ("floors[2].horizontal_offset_m", 0.005),
    ("floors[0].centroid_displacement_m[2]", 0.0005),
    ("floors[1].centroid_displacement_m[2]", 0.0005),
    ("floors[2].centroid_displacement_m[2]", 0.0005),
    ("slab_overlap[0].overlap_ratio", 0.002),
    ("slab_overlap[1].overlap_ratio", 0.01),
    ("debris_footprint_area_m2", 0.005),
    ("max_debris_height_m", 0.0005),
    ("distance_beyond_footprint_m.p50", 0.0001),
    ("distance_beyond_footprint_m.p90", 0.005),
    ("distance_beyond_footprint_m.p100", 0.005),
];

/// The nearest-rank quantile q of sorted values.
fn quantile(sorted: &[f64], q: f64) -> f64 {
    let k = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len()) - 1;
    sorted[k]
}

fn mean_sd(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, var.sqrt())
}

/// `x` rounded to a multiple of `step`, and its distance from the nearest rounding edge in
/// steps (0.5 = exactly on a multiple, 0 = on an edge).
fn rounded(x: f64, step: f64) -> (f64, f64) {
    let k = (x / step).round();
    let margin = 0.5 - (x / step - k).abs();
    ((k * step * 1e6).round() / 1e6 + 0.0, margin)
}

#[test]
fn frame3_lc5_hybrid_ensemble_distribution() {
    let text = crate::support::frame3_lc5(
        "hybrid",
        "criterion = \"drift_4pct\"",
        "",
        "time_limit_s = 3.0",
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("lc5.toml");
    std::fs::write(&path, text).unwrap();
    let sc = Scenario::load(&path).unwrap();
    let recs = run_ensemble(&sc, MEMBERS, SEED, 2).unwrap();
    let measures: Vec<BTreeMap<String, f64>> = recs.iter().map(member_measures).collect();
    let mut snap = serde_json::Map::new();
    let mut least_margin = f64::INFINITY;
    for &(name, step) in STEPS {
        let mut v: Vec<f64> = measures
            .iter()
            .map(|m| {
                *m.get(name)
                    .unwrap_or_else(|| panic!("no measure {name}: {m:?}"))
            })
            .collect();
        v.sort_by(f64::total_cmp);
        let (mean, sd) = mean_sd(&v);
        let mut q = serde_json::Map::new();
        for (label, p) in [("p25", 0.25), ("p50", 0.5), ("p75", 0.75)] {
            let (r, margin) = rounded(quantile(&v, p), step);
            least_margin = least_margin.min(margin);
            eprintln!(
                "{name} {label}: {:.4} -> {r} (step {step}, margin {margin:.3} step)",
                quantile(&v, p)
            );
            q.insert(label.into(), r.into());
        }
        let (r, margin) = rounded(mean, step);
        least_margin = least_margin.min(margin);
        eprintln!("{name}: mean {mean:.4} -> {r}, sd {sd:.4} (step {step} = {:.2} sd, margin {margin:.2})", step / sd);
        q.insert("mean".into(), r.into());
        q.insert("step".into(), step.into());
        snap.insert(name.into(), q.into());
    }
    // The debris-density grid: mean active bodies per member in each CELL_M cell of the
    // final centres (cells by floor(x / CELL_M), floor(y / CELL_M)), whole bodies.
    let mut cells: BTreeMap<(i64, i64), f64> = BTreeMap::new();
    for rec in &recs {
        for (b, p) in rec.bodies.iter().zip(&rec.final_poses) {
            if b.passive {
                continue;
            }
            let key = (
                (p.position[0] / CELL_M).floor() as i64,
                (p.position[1] / CELL_M).floor() as i64,
            );
            *cells.entry(key).or_default() += 1.0 / MEMBERS as f64;
        }
    }
    let mut grid = serde_json::Map::new();
    for ((i, j), n) in &cells {
        let (r, margin) = rounded(*n, 1.0);
        least_margin = least_margin.min(margin);
        eprintln!("cell ({i}, {j}): {n:.3} bodies -> {r} (margin {margin:.2})");
        if r > 0.0 {
            grid.insert(format!("{i},{j}"), r.into());
        }
    }
    snap.insert("debris_cells_bodies_per_member".into(), grid.into());
    eprintln!("least margin from a rounding edge: {least_margin:.3} step");
    assert!(
        least_margin >= 0.01,
        "a rounded value lies within 1 % of a step of its rounding edge ({least_margin:.3})"
    );
    insta::assert_json_snapshot!("frame3_lc5_hybrid_ensemble", serde_json::Value::from(snap));
}
