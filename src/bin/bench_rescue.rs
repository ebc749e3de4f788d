//! Benchmark of the rescue analysis (`fem2rbd voids`, src/rescue/): the wall time of the
//! whole analysis of a run folder's ruin at the default sizes (on two threads, as
//! `fem2rbd voids` runs it), and of its steps one by one on the calling thread, so that
//! the slowest step shows.
//!
//! ```text
//! cargo run --release --bin bench_rescue -- RUN_DIR [--rounds N] [--cell M]
//! ```
//!
//! `--rounds N`: analyses of the whole (default 3; each time and the median are printed).
//! `--cell M`: the grid cell, m at full scale (default the analysis' default). Reading the
//! run folder is not timed. Prints the machine's load average (`/proc/loadavg`) before and
//! after, since the machine may be shared, and an FNV-1a digest of `voids.csv` and
//! `voids.json` of every round, which must be the same.
use anyhow::{bail, Context, Result};
use fem2rbd::rescue::access::{breach_field, routes};
use fem2rbd::rescue::grid::grid_over;
use fem2rbd::rescue::occupancy::occupancy;
use fem2rbd::rescue::person::DEFAULT_CELL_M;
use fem2rbd::rescue::stories::{standing_shelter, story_losses_from};
use fem2rbd::rescue::voids::{find_voids, Field};
use fem2rbd::rescue::{analyse, Ruin, Sizes};
use std::time::Instant;

/// The load averages of `/proc/loadavg` (1, 5, 15 min), or "?" without procfs.
fn load() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "?".into())
}

/// FNV-1a (64 bit) of `bytes`.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3)
    })
}

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let mut dir = None;
    let mut rounds = 3usize;
    let mut cell = DEFAULT_CELL_M;
    while let Some(a) = args.next() {
        match a.as_str() {
            "--rounds" => {
                rounds = args
                    .next()
                    .context("--rounds needs a number")?
                    .parse()
                    .context("--rounds")?;
            }
            "--cell" => {
                cell = args
                    .next()
                    .context("--cell needs a size, m")?
                    .parse()
                    .context("--cell")?;
            }
            _ if dir.is_none() && !a.starts_with('-') => dir = Some(a),
            _ => {
                bail!("unknown argument {a:?}; usage: bench_rescue RUN_DIR [--rounds N] [--cell M]")
            }
        }
    }
    let Some(dir) = dir else {
        bail!("usage: bench_rescue RUN_DIR [--rounds N] [--cell M]");
    };
    if rounds == 0 {
        bail!("--rounds must be at least 1");
    }
    let sizes = Sizes {
        cell_m: cell,
        ..Sizes::default()
    };
    let ruin = Ruin::load(std::path::Path::new(&dir))?;
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    println!(
        "run folder: {dir}; {} bodies; {threads} cores",
        ruin.boxes.len()
    );
    println!("load average before: {}", load());

    // The steps one by one, on the calling thread.
    let scaled = sizes.scaled(ruin.scale)?;
    let margin = scaled.rescuer.max(scaled.sitting[0]);
    let Some(grid) = grid_over(&ruin, scaled.cell, margin, sizes.cell_m)? else {
        bail!("{dir}: no debris to analyse");
    };
    println!(
        "grid {} x {} x {} = {} cells of {} m",
        grid.n[0],
        grid.n[1],
        grid.n[2],
        grid.len(),
        grid.h
    );
    let t = Instant::now();
    let occ = occupancy(&grid, &ruin.boxes);
    println!(
        "occupancy:                {:8.3} s",
        t.elapsed().as_secs_f64()
    );
    let t = Instant::now();
    let before = standing_shelter(&ruin, grid.h, sizes.cell_m)?;
    println!(
        "standing building's shelter (its occupancy): {:6.3} s",
        t.elapsed().as_secs_f64()
    );
    let t = Instant::now();
    let field = Field::new(grid, occ);
    println!(
        "field (distance transform): {:6.3} s",
        t.elapsed().as_secs_f64()
    );
    let t = Instant::now();
    let r = routes(&field, scaled.rescuer);
    println!(
        "rescuer routes:           {:8.3} s ({} cells searched)",
        t.elapsed().as_secs_f64(),
        r.searched_cells()
    );
    let t = Instant::now();
    let c = routes(&field, scaled.camera);
    println!(
        "camera routes:            {:8.3} s ({} cells searched)",
        t.elapsed().as_secs_f64(),
        c.searched_cells()
    );
    let t = Instant::now();
    let b = breach_field(&field);
    println!(
        "breach field:             {:8.3} s ({} cells searched)",
        t.elapsed().as_secs_f64(),
        b.searched_cells()
    );
    drop((r, c, b));
    let t = Instant::now();
    let (voids, _, _) = find_voids(&field, &scaled);
    println!(
        "chambers ({} voids):     {:8.3} s",
        voids.len(),
        t.elapsed().as_secs_f64()
    );
    let t = Instant::now();
    let stories = story_losses_from(&ruin, &field, &before);
    println!(
        "story losses ({} stories): {:6.3} s",
        stories.len(),
        t.elapsed().as_secs_f64()
    );
    drop(field);

    // The whole analysis, as `fem2rbd voids` runs it.
    let mut walls = Vec::with_capacity(rounds);
    for round in 1..=rounds {
        let t = Instant::now();
        let analysis = analyse(&ruin, sizes)?;
        let files = analysis.files();
        let wall = t.elapsed().as_secs_f64();
        let digest: Vec<String> = files
            .iter()
            .filter(|f| f.0 == "voids.csv" || f.0 == "voids.json")
            .map(|f| format!("{} {:016x}", f.0, fnv1a(&f.1)))
            .collect();
        println!(
            "round {round}: whole analysis (with writing its files to memory) {wall:.3} s; {}",
            digest.join(", ")
        );
        walls.push(wall);
    }
    walls.sort_by(f64::total_cmp);
    println!(
        "median of {rounds}: {:.3} s; load average after: {}",
        walls[walls.len() / 2],
        load()
    );
    Ok(())
}
