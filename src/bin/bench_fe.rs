//! Benchmark: frame3 LC1 (El Centro 0.10/0.08/0.06 g), force-based fiber model, Δt =
//! 0.005 s, N steps (default 2000), in fem2rbd and in openseespy on the same model
//! exported by `fem2rbd export opensees`, in the same run. Prints ms per transient step
//! for both and the ratio, and how far the two roof-centre (node 312) histories differ.
//!
//! `cargo run --release --bin bench_fe [-- STEPS [--no-opensees]]` from the repository
//! root (needs `python3` with openseespy 3.7.1 unless `--no-opensees`).
//!
//! Time per step = (wall time of the whole run − wall time of model building, modal and
//! gravity) / steps, for both programs; both record every node's displacements at every
//! step (fem2rbd in memory, the exported script to a CSV file).
use anyhow::{bail, Context, Result};
use fem2rbd::export::{opensees_script, GroundMotionInput, OpenSeesOptions};
use fem2rbd::fe::analysis::transient::StepControl;
use fem2rbd::fe::build::{BuildOptions, Variant};
use fem2rbd::fe::run::{prepare, run_ground_motion, RunOptions};
use fem2rbd::model::Model;
use fem2rbd::motion::{Format, GroundMotion};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

const RECORDS: [&str; 3] = [
    "RSN6_IMPVALL.I_I-ELC180.AT2",
    "RSN6_IMPVALL.I_I-ELC270.AT2",
    "RSN6_IMPVALL.I_I-ELC-UP.AT2",
];
const PGA_G: [f64; 3] = [0.10, 0.08, 0.06];
const DT: f64 = 0.005;

fn python(script: &Path, args: &[&str]) -> Result<(f64, String)> {
    let t0 = Instant::now();
    let out = Command::new("python3")
        .arg(script)
        .args(args)
        .output()
        .context("cannot run python3")?;
    let wall = t0.elapsed().as_secs_f64();
    if !out.status.success() {
        bail!(
            "python3 {} {args:?} failed (is openseespy 3.7.1 installed?):\n{}",
            script.display(),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    Ok((wall, String::from_utf8_lossy(&out.stdout).into_owned()))
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let steps: usize = match args.iter().find(|a| !a.starts_with("--")) {
        Some(s) => s
            .parse()
            .with_context(|| format!("steps {s:?} is not a number"))?,
        None => 2000,
    };
    let with_opensees = !args.iter().any(|a| a == "--no-opensees");
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let model_path = root.join("data/frame3-standin/model.toml");
    let model = Model::load(&model_path)?;
    let paths: Vec<PathBuf> = RECORDS
        .iter()
        .map(|r| root.join("data/ground-motions").join(r))
        .collect();
    let mut gm = GroundMotion::from_files(
        [
            Some(paths[0].as_path()),
            Some(paths[1].as_path()),
            Some(paths[2].as_path()),
        ],
        Format::Auto,
    )?;
    gm.scale_to_pga(PGA_G.map(Some))?;
    let duration = steps as f64 * DT;
    let build = BuildOptions {
        variant: Variant::Force,
        ..Default::default()
    };

    // fem2rbd
    let t0 = Instant::now();
    let _ = prepare(&model, &build, 3)?;
    let setup = t0.elapsed().as_secs_f64();
    let t0 = Instant::now();
    let r = run_ground_motion(
        &model,
        &gm,
        &RunOptions {
            build,
            dt: DT,
            duration: Some(duration),
            ..Default::default()
        },
        &mut |_, _| StepControl::Continue,
    )?;
    let total = t0.elapsed().as_secs_f64();
    let ms_ours = (total - setup) / r.transient.steps as f64 * 1e3;
    println!(
        "fem2rbd:    {} steps, {:.3} ms/step (setup {:.3} s, {} fallback steps)",
        r.transient.steps, ms_ours, setup, r.transient.fallback_steps
    );
    if !with_opensees {
        return Ok(());
    }

    // openseespy on the exported model
    let dir = std::env::temp_dir().join(format!("fem2rbd-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let script = dir.join("frame3_lc1.py");
    let opts = OpenSeesOptions {
        ground_motions: (0..3)
            .map(|k| GroundMotionInput {
                direction: k as u8 + 1,
                path: paths[k].clone(),
                pga_g: Some(PGA_G[k]),
            })
            .collect(),
        dt: DT,
        duration: Some(duration),
        variant: Variant::Force,
        ..Default::default()
    };
    let text = opensees_script(&model, &model_path.display().to_string(), &opts)?;
    std::fs::write(&script, text)?;
    let (w_gravity, _) = python(&script, &["gravity"])?;
    let csv = dir.join("th.csv");
    let (w_th, out) = python(&script, &["th", csv.to_str().context("temp path")?])?;
    let summary: serde_json::Value = serde_json::from_str(out.lines().last().unwrap_or(""))
        .context("the exported script printed no summary")?;
    let os_steps = summary["steps"].as_u64().unwrap_or(0) as f64;
    let ms_os = (w_th - w_gravity) / os_steps * 1e3;
    println!(
        "openseespy: {} steps, {:.3} ms/step (setup {:.3} s)",
        os_steps, ms_os, w_gravity
    );
    println!("ratio (OpenSees / fem2rbd): {:.2}x", ms_os / ms_ours);

    // Same results: node 312 ux, uy over the run.
    let text = std::fs::read_to_string(&csv)?;
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let (cx, cy) = (
        head.iter().position(|h| *h == "ux_312").context("ux_312")?,
        head.iter().position(|h| *h == "uy_312").context("uy_312")?,
    );
    let k312 = r.node_tags.iter().position(|&t| t == 312).context("312")?;
    let h = &r.transient.history;
    let (mut dmax, mut peak) = (0.0f64, 0.0f64);
    for (i, l) in lines.enumerate() {
        let v: Vec<f64> = l
            .split(',')
            .map(|x| x.parse().unwrap_or(f64::NAN))
            .collect();
        let ours = h.disp[i + 1][k312];
        if (h.time[i + 1] - v[0]).abs() > 1e-6 {
            bail!(
                "time grids differ at row {i}: {} vs {}",
                h.time[i + 1],
                v[0]
            );
        }
        dmax = dmax
            .max((ours[0] - v[cx]).abs())
            .max((ours[1] - v[cy]).abs());
        peak = peak.max(v[cx].abs()).max(v[cy].abs());
    }
    println!(
        "node 312 ux/uy: max |fem2rbd - OpenSees| = {:.3e} m = {:.3} % of the peak {:.3} mm",
        dmax,
        dmax / peak * 100.0,
        peak * 1e3
    );
    let _ = std::fs::remove_dir_all(&dir);
    Ok(())
}
