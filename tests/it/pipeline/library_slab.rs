//! The library stand-in's slab support (docs/case2.md, "Slab connections"): one bay of
//! the stand-in at full scale — 8 m × 7.9 m, one 2.7 m story, 0.8 m columns, 0.4 × 0.8 m
//! beams, a 0.15 m slab carrying the stand-in's 1 210 kg/m² of added mass
//! (8 · 7.9 · 1 210 = 76 472 kg) — under gravity alone, physics only, BCB's
//! Formula-Assistant connections.
//!
//! Overlap removal shortens each quarter panel by the column's half width (0.4 m) on one
//! side and by the beam's (0.2 m) on the other, so one panel edge ends 0.2 m short of its
//! beam: with BCB's 0.02 m search distance each panel hangs from one beam only (4
//! beam–slab connections for 4 panels instead of 8) and the floor falls (measured: the
//! panels drop 2 m in 1 s although the same slab holds with its self-weight alone or with
//! ≤ 316 kg/m² added). A search distance of 0.42 m bridges the gap: 8 beam–slab
//! connections and the floor stands (measured: largest drop 51 µm, all connections intact).
use fem2rbd::model::generate::{frame, FrameParams};
use fem2rbd::pipeline::{self, write, Scenario, Silent};
use std::path::Path;

fn bay() -> FrameParams {
    FrameParams {
        name: "library-bay".into(),
        spans_x: vec![8.0],
        spans_y: vec![7.9],
        story_heights: vec![2.7],
        column: [0.8, 0.8],
        beam: [0.4, 0.8],
        slab_thickness: 0.15,
        cover: 0.04,
        bar_offset: 0.05,
        column_bar_diameter: 0.025,
        beam_bar_diameter: 0.025,
        column_bars_per_face: 5,
        beam_bars: [4, 4],
        ec: vec![31.5e9],
        fc: vec![23.4e6],
        fy: 400e6,
        added_mass: vec![8.0 * 7.9 * 1210.0],
        column_elements: 1,
        beam_elements: 1,
        scale: 1.0,
        t1: 0.37,
        ..FrameParams::default()
    }
}

/// (largest drop of a body centre over the run (m), beam–slab connections, connections
/// not intact at the end) for one search distance.
fn gravity_run(dir: &Path, search_distance_m: f64) -> (f64, usize, usize) {
    let model = dir.join("bay.toml");
    std::fs::write(&model, frame(&bay()).unwrap().to_toml().unwrap()).unwrap();
    let zeros: String = (0..=200)
        .map(|i| format!("{:.3} 0.0\n", i as f64 * 0.005))
        .collect();
    std::fs::write(dir.join("zeros.txt"), zeros).unwrap();
    let text = format!(
        "model = \"{}\"\nmode = \"rigid\"\n\n[[ground_motion]]\nfile = \"{}\"\n\
         direction = \"X\"\n\n[physics]\ntime_limit_s = 1.0\nstop_at_rest = false\n\
         search_distance_m = {search_distance_m}\n",
        model.display(),
        dir.join("zeros.txt").display()
    );
    let p = dir.join("scenario.toml");
    std::fs::write(&p, text).unwrap();
    let rec = pipeline::run(&Scenario::load(&p).unwrap(), &Silent).unwrap();
    let files = write::contents(&rec, false).unwrap();
    let file = |name: &str| {
        files
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, b)| String::from_utf8(b.clone()).unwrap())
            .unwrap()
    };
    let drop = file("history.csv")
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(3).unwrap().parse::<f64>().unwrap())
        .fold(0.0, f64::max);
    let connections = file("connections.csv");
    let rows: Vec<Vec<&str>> = connections
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    let beam_slab = rows
        .iter()
        .filter(|f| f[0].starts_with("Beam:") && f[1].starts_with("Slab:"))
        .count();
    let damaged = rows.iter().filter(|f| f[3] != "intact").count();
    (drop, beam_slab, damaged)
}

#[test]
fn library_bay_slab_needs_both_beams() {
    let dir = tempfile::tempdir().unwrap();
    let (drop, beam_slab, damaged) = gravity_run(dir.path(), 0.02);
    eprintln!("search 0.02 m: drop {drop:.3} m, beam-slab {beam_slab}, damaged {damaged}");
    assert_eq!(beam_slab, 4);
    assert!(drop > 0.5, "drop {drop} m");
    let (drop, beam_slab, damaged) = gravity_run(dir.path(), 0.42);
    eprintln!("search 0.42 m: drop {drop:.6} m, beam-slab {beam_slab}, damaged {damaged}");
    assert_eq!(beam_slab, 8);
    assert!(drop < 1e-3, "drop {drop} m");
    assert_eq!(damaged, 0);
}
