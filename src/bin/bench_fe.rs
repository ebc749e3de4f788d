//! Benchmark of the FE stage against openseespy on the same model exported by
//! `fem2rbd export opensees`, in the same run. Two models:
//!
//! - default: frame3 LC1 (El Centro 0.10/0.08/0.06 g), force-based fiber model, N
//!   steps (default 2000);
//! - `--frame7`: the full-scale 7-story 6 × 4-bay frame (`fem2rbd generate
//!   frame --spans-x 7.5x6 --spans-y 7.5x4 --stories 3.6x7 --column 0.7x0.7 --beam
//!   0.35x0.7 --slab-thickness 0.15 --scale 1 --ec 30e9 --fc 30e6 --added-mass 200000
//!   --formulation disp`: 1 099 nodes, 2 646 elements, 6 594 equations, corotational),
//!   El Centro 0.3 g in X and Y, N steps (default 200);
//! - `--walls`: the same frame with shear walls of layered shells on eight bays, every
//!   story (`fem2rbd generate building`, walls set to small displacements), same record.
//!
//! Δt = 0.005 s. Prints ms per transient step for both programs and the ratio, how far
//! the two roof histories differ, fem2rbd's time per phase of an equilibrium iteration
//! (element state determination, residual, tangent assembly, factorisation, solve), and
//! with `--threads` also fem2rbd on 1 thread against 2 (`BuildOptions::threads`), with a check
//! that both give the same bits.
//!
//! `cargo run --release --bin bench_fe [-- STEPS] [--frame7 | --walls] [--no-opensees]
//! [--threads]`
//! from the repository root (needs `python3` with openseespy 3.7.1 unless `--no-opensees`).
//!
//! Time per step, fem2rbd: wall time from the end of step 1 to the end of the last step
//! over the steps in between; openseespy: (wall time of the whole run − wall time of
//! model building, modal and gravity) / steps. Both record every node's displacements at
//! every step (fem2rbd in memory, the exported script to a CSV file).
use anyhow::{bail, Context, Result};
use fem2rbd::export::{opensees_script, GroundMotionInput, OpenSeesOptions};
use fem2rbd::fe::analysis::transient::StepControl;
use fem2rbd::fe::build::{BuildOptions, Variant};
use fem2rbd::fe::profile::{self, Phase};
use fem2rbd::fe::run::{run_ground_motion, RunOptions, RunResult};
use fem2rbd::model::building::{building, BuildingParams, WallSpec};
use fem2rbd::model::element::ElementKind;
use fem2rbd::model::generate::{frame, FrameParams};
use fem2rbd::model::{Formulation, Model};
use fem2rbd::motion::{Format, GroundMotion};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

const RECORDS: [&str; 3] = [
    "RSN6_IMPVALL.I_I-ELC180.AT2",
    "RSN6_IMPVALL.I_I-ELC270.AT2",
    "RSN6_IMPVALL.I_I-ELC-UP.AT2",
];
/// frame3 LC1 peak ground accelerations X, Y, Z (g).
const PGA_FRAME3: [Option<f64>; 3] = [Some(0.10), Some(0.08), Some(0.06)];
/// The 7-story frame: X and Y at 0.3 g, no vertical component.
const PGA_FRAME7: [Option<f64>; 3] = [Some(0.3), Some(0.3), None];
const DT: f64 = 0.005;

/// Runs the exported script; returns its wall time, its CPU time (NaN without procfs)
/// and what it printed.
fn python(script: &Path, args: &[&str]) -> Result<(f64, f64, String)> {
    let c0 = children_cpu_seconds();
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
    let cpu = match (c0, children_cpu_seconds()) {
        (Some(a), Some(b)) => b - a,
        _ => f64::NAN,
    };
    Ok((wall, cpu, String::from_utf8_lossy(&out.stdout).into_owned()))
}

/// The benchmark case: model, record, element variant, roof node to compare.
struct Case {
    name: &'static str,
    model: Model,
    source: String,
    pga: [Option<f64>; 3],
    variant: Variant,
    roof: u32,
}

fn frame7() -> Result<Model> {
    Ok(frame(&frame7_params())?)
}

/// `--walls`: the 7-story frame with shear walls of layered shells (`fem2rbd generate
/// building` with the frame's options and `--wall` x0:1:1-7, x0:6:1-7, x4:1:1-7, x4:6:1-7,
/// y0:2:1-7, y0:3:1-7, y6:2:1-7, y6:3:1-7: both end bays of the long facades and both
/// middle bays of the short ones, every story; 0.25 m thick). The generator writes the
/// wall shells corotational; they are set to small displacements here (and so in the
/// exported script, written from the same model), the case this benchmark was set up
/// with before the FE solver had corotational shells.
fn walls7() -> Result<Model> {
    let walls = [
        "x0:1:1-7", "x0:6:1-7", "x4:1:1-7", "x4:6:1-7", "y0:2:1-7", "y0:3:1-7", "y6:2:1-7",
        "y6:3:1-7",
    ]
    .iter()
    .map(|w| WallSpec::parse(w))
    .collect::<Result<Vec<_>, _>>()?;
    let mut frame = frame7_params();
    frame.name = "walls7-6x4-full-scale".into();
    let mut model = building(&BuildingParams {
        frame,
        walls,
        wall_thickness: vec![0.25],
        ..Default::default()
    })?;
    for e in &mut model.elements {
        if let ElementKind::Shell { corotational, .. } = &mut e.kind {
            *corotational = false;
        }
    }
    Ok(model)
}

fn frame7_params() -> FrameParams {
    FrameParams {
        name: "frame7-6x4-full-scale".into(),
        spans_x: vec![7.5; 6],
        spans_y: vec![7.5; 4],
        story_heights: vec![3.6; 7],
        column: [0.7, 0.7],
        beam: [0.35, 0.7],
        slab_thickness: 0.15,
        scale: 1.0,
        ec: vec![30e9],
        fc: vec![30e6],
        added_mass: vec![200000.0],
        formulation: Formulation::Disp,
        ..Default::default()
    }
}

/// One fem2rbd run; returns the result, wall and CPU (all threads) ms per step (steps
/// 2..N) and the phase totals over the same steps.
#[allow(clippy::type_complexity)]
fn run_ours(
    case: &Case,
    gm: &GroundMotion,
    duration: f64,
    threads: usize,
) -> Result<(RunResult, f64, f64, Vec<(Phase, f64, u64)>, u64)> {
    let mut t_first = None;
    let mut t_last = Instant::now();
    let (mut cpu_first, mut cpu_last) = (None, None);
    let mut iterations = 0u64;
    let r = run_ground_motion(
        &case.model,
        gm,
        &RunOptions {
            build: BuildOptions {
                variant: case.variant,
                threads: Some(threads),
                ..Default::default()
            },
            dt: DT,
            duration: Some(duration),
            ..Default::default()
        },
        &mut |info, _| {
            if info.step == 1 {
                profile::reset();
                t_first = Some(Instant::now());
                cpu_first = process_cpu_seconds();
            } else {
                iterations += info.iterations as u64;
            }
            t_last = Instant::now();
            cpu_last = process_cpu_seconds();
            StepControl::Continue
        },
    )?;
    let phases = [
        Phase::ElementUpdate,
        Phase::Residual,
        Phase::Assembly,
        Phase::Factor,
        Phase::Solve,
    ]
    .map(|p| {
        let t = profile::total(p);
        (p, t.seconds, t.calls)
    })
    .to_vec();
    let first = t_first.context("no step converged")?;
    let steps = r.transient.steps.saturating_sub(1).max(1);
    let ms = (t_last - first).as_secs_f64() / steps as f64 * 1e3;
    let cpu_ms = match (cpu_first, cpu_last) {
        (Some(a), Some(b)) => (b - a) / steps as f64 * 1e3,
        _ => f64::NAN,
    };
    Ok((r, ms, cpu_ms, phases, iterations))
}

/// CPU time (user + system, all threads) of this process so far, s, from
/// `/proc/self/stat` (clock ticks of 10 ms; `None` where there is no procfs).
fn process_cpu_seconds() -> Option<f64> {
    proc_stat_seconds(11)
}

/// CPU time (user + system) of the children this process has waited for, s
/// (`/proc/self/stat` cutime + cstime).
fn children_cpu_seconds() -> Option<f64> {
    proc_stat_seconds(13)
}

/// Fields `k` and `k + 1` (counted after the command name) of `/proc/self/stat`, in s.
fn proc_stat_seconds(k: usize) -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which is in parentheses and may hold spaces).
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = f.get(k)?.parse::<f64>().ok()? + f.get(k + 1)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// FNV-1a hash of every recorded time, displacement, velocity and acceleration bit:
/// equal digests from two builds say they computed the same bits.
fn digest(r: &RunResult) -> u64 {
    let h = &r.transient.history;
    let mut x: u64 = 0xcbf29ce484222325;
    let mut eat = |v: f64| {
        for b in v.to_bits().to_le_bytes() {
            x ^= u64::from(b);
            x = x.wrapping_mul(0x100000001b3);
        }
    };
    h.time.iter().for_each(|&t| eat(t));
    for field in [&h.disp, &h.vel, &h.acc] {
        field.iter().flatten().flatten().for_each(|&v| eat(v));
    }
    x
}

fn same_bits(a: &RunResult, b: &RunResult) -> bool {
    let (ha, hb) = (&a.transient.history, &b.transient.history);
    ha.time == hb.time
        && ha.disp.len() == hb.disp.len()
        && ha.disp.iter().zip(&hb.disp).all(|(x, y)| {
            x.iter()
                .flatten()
                .zip(y.iter().flatten())
                .all(|(p, q)| p.to_bits() == q.to_bits())
        })
}

/// `--probe`: the effective Newmark tangent of the final state (K_t + M/(βΔt²)),
/// its asymmetry, and the time of one numeric factorisation with faer's LU (the
/// solver in use) against faer's supernodal LDLᵀ and intranode Bunch-Kaufman LBLᵀ with
/// AMD ordering.
fn probe(domain: &mut fem2rbd::fe::domain::Domain) -> Result<()> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::sparse::linalg::cholesky::{
        factorize_symbolic_cholesky, CholeskySymbolicParams, SymmetricOrdering,
    };
    use fem2rbd::fe::linalg::{SparseLu, SparsePattern, StiffnessKind};
    let pattern = SparsePattern::new(domain);
    let mut a = pattern.zeros();
    pattern.add_stiffness(domain, StiffnessKind::Tangent, 1.0, &mut a);
    let m = domain.mass_diagonal();
    pattern.add_diagonal(&m, 1.0 / (0.25 * DT * DT), &mut a);
    let sym = pattern.symbolic();
    let (cp, ri) = (sym.col_ptr(), sym.row_idx());
    let amax = a.iter().fold(0.0f64, |x, y| x.max(y.abs()));
    let mut asym = 0.0f64;
    for c in 0..pattern.dim() {
        for p in cp[c]..cp[c + 1] {
            let r = ri[p];
            let q = cp[r] + ri[cp[r]..cp[r + 1]].binary_search(&c).unwrap();
            asym = asym.max((a[p] - a[q]).abs());
        }
    }
    println!(
        "probe: n = {}, nnz = {}, max |a_ij - a_ji| / max |a| = {:.3e}",
        pattern.dim(),
        pattern.nnz(),
        asym / amax
    );
    let reps = 5;
    let mut lu = SparseLu::new(&pattern)?;
    let t0 = Instant::now();
    for _ in 0..reps {
        lu.factor(&pattern, &a)?;
    }
    println!(
        "  LU (COLAMD, supernodal): {:.3} ms",
        t0.elapsed().as_secs_f64() / reps as f64 * 1e3
    );
    let t0 = Instant::now();
    let chol = factorize_symbolic_cholesky(
        sym,
        faer::Side::Lower,
        SymmetricOrdering::Amd,
        CholeskySymbolicParams::default(),
    )
    .map_err(|e| anyhow::anyhow!("{e:?}"))?;
    println!(
        "  Cholesky symbolic (AMD): {:.3} ms, nnz(L) = {}",
        t0.elapsed().as_secs_f64() * 1e3,
        chol.len_val()
    );
    let mut l = vec![0.0; chol.len_val()];
    let mut mem = MemBuffer::new(
        chol.factorize_numeric_ldlt_scratch::<f64>(faer::Par::Seq, Default::default()),
    );
    let t0 = Instant::now();
    for _ in 0..reps {
        chol.factorize_numeric_ldlt(
            &mut l,
            pattern.as_mat(&a),
            faer::Side::Lower,
            Default::default(),
            faer::Par::Seq,
            MemStack::new(&mut mem),
            Default::default(),
        )
        .map_err(|e| anyhow::anyhow!("{e:?}"))?;
    }
    println!(
        "  LDLt: {:.3} ms",
        t0.elapsed().as_secs_f64() / reps as f64 * 1e3
    );
    let n = pattern.dim();
    let (mut sub, mut pf, mut pi) = (vec![0.0; n], vec![0usize; n], vec![0usize; n]);
    let mut mem = MemBuffer::new(
        chol.factorize_numeric_intranode_lblt_scratch::<f64>(faer::Par::Seq, Default::default()),
    );
    let t0 = Instant::now();
    for _ in 0..reps {
        chol.factorize_numeric_intranode_lblt(
            &mut l,
            &mut sub,
            &mut pf,
            &mut pi,
            pattern.as_mat(&a),
            faer::Side::Lower,
            faer::Par::Seq,
            MemStack::new(&mut mem),
            Default::default(),
        );
    }
    println!(
        "  LBLt (Bunch-Kaufman in supernodes): {:.3} ms",
        t0.elapsed().as_secs_f64() / reps as f64 * 1e3
    );
    Ok(())
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let is_walls = args.iter().any(|a| a == "--walls");
    let is_frame7 = is_walls || args.iter().any(|a| a == "--frame7");
    let steps: usize = match args.iter().find(|a| !a.starts_with("--")) {
        Some(s) => s
            .parse()
            .with_context(|| format!("steps {s:?} is not a number"))?,
        None if is_frame7 => 200,
        None => 2000,
    };
    let with_opensees = !args.iter().any(|a| a == "--no-opensees");
    let compare_threads = args.iter().any(|a| a == "--threads");
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let case = if is_walls {
        Case {
            name: "walls7",
            model: walls7()?,
            source: "fem2rbd generate building (bench_fe --walls)".into(),
            pga: PGA_FRAME7,
            variant: Variant::Disp,
            roof: 0,
        }
    } else if is_frame7 {
        Case {
            name: "frame7",
            model: frame7()?,
            source: "fem2rbd generate frame (bench_fe --frame7)".into(),
            pga: PGA_FRAME7,
            variant: Variant::Disp,
            roof: 0,
        }
    } else {
        let model_path = root.join("data/frame3-standin/model.toml");
        Case {
            name: "frame3_lc1",
            model: Model::load(&model_path)?,
            source: model_path.display().to_string(),
            pga: PGA_FRAME3,
            variant: Variant::Force,
            roof: 312,
        }
    };
    // Roof node: the given one, else the highest node nearest the plan centre.
    let roof = if case.roof != 0 {
        case.roof
    } else {
        let n = &case.model.nodes;
        let top = n.iter().map(|n| n.z).fold(f64::MIN, f64::max);
        let (cx, cy) = {
            let tops: Vec<_> = n.iter().filter(|n| (n.z - top).abs() < 1e-6).collect();
            let k = tops.len() as f64;
            (
                tops.iter().map(|n| n.x).sum::<f64>() / k,
                tops.iter().map(|n| n.y).sum::<f64>() / k,
            )
        };
        n.iter()
            .filter(|n| (n.z - top).abs() < 1e-6)
            .min_by(|a, b| {
                let da = (a.x - cx).hypot(a.y - cy);
                let db = (b.x - cx).hypot(b.y - cy);
                da.total_cmp(&db).then(a.tag.cmp(&b.tag))
            })
            .context("no nodes")?
            .tag
    };
    let paths: Vec<PathBuf> = RECORDS
        .iter()
        .map(|r| root.join("data/ground-motions").join(r))
        .collect();
    let used = |k: usize| case.pga[k].map(|_| paths[k].as_path());
    let mut gm = GroundMotion::from_files([used(0), used(1), used(2)], Format::Auto)?;
    gm.scale_to_pga(case.pga)?;
    let duration = steps as f64 * DT;
    println!(
        "model {}: {} nodes, {} elements; {} steps of {} s",
        case.name,
        case.model.nodes.len(),
        case.model.elements.len(),
        steps,
        DT
    );

    // fem2rbd, on the default threads.
    let threads = fem2rbd::fe::domain::default_threads();
    let (r, ms_ours, cpu_ours, phases, iterations) = run_ours(&case, &gm, duration, threads)?;
    let neq = r.built.domain.num_equations();
    println!(
        "fem2rbd:    {} steps, {:.3} ms/step, CPU {:.3} ms/step ({} thread(s), {} equations, {} fallback steps, {:.2} iterations/step)",
        r.transient.steps,
        ms_ours,
        cpu_ours,
        threads,
        neq,
        r.transient.fallback_steps,
        iterations as f64 / r.transient.steps.saturating_sub(1).max(1) as f64
    );
    let per_step = r.transient.steps.saturating_sub(1).max(1) as f64;
    for (p, s, calls) in &phases {
        println!(
            "  {:<14} {:8.3} ms/step {:8.3} ms/call ({} calls)",
            format!("{p:?}"),
            s / per_step * 1e3,
            s / (*calls).max(1) as f64 * 1e3,
            calls
        );
    }
    println!("digest of the history bits: {:016x}", digest(&r));
    if args.iter().any(|a| a == "--probe") {
        let mut r = r;
        probe(&mut r.built.domain)?;
        return Ok(());
    }
    if compare_threads {
        let (r1, ms1, cpu1, _, _) = run_ours(&case, &gm, duration, 1)?;
        let (r2, ms2, cpu2, _, _) = run_ours(&case, &gm, duration, 2)?;
        println!(
            "fem2rbd threads: 1 thread {ms1:.3} ms/step (CPU {cpu1:.3}), 2 threads {ms2:.3} ms/step (CPU {cpu2:.3}), 2/1 = {:.3}; same bits: {}",
            ms2 / ms1,
            same_bits(&r1, &r2) && same_bits(&r1, &r)
        );
    }
    if !with_opensees {
        return Ok(());
    }

    // openseespy on the exported model
    let dir = std::env::temp_dir().join(format!("fem2rbd-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let script = dir.join(format!("{}.py", case.name));
    let opts = OpenSeesOptions {
        ground_motions: (0..3)
            .filter(|&k| case.pga[k].is_some())
            .map(|k| GroundMotionInput {
                direction: k as u8 + 1,
                path: paths[k].clone(),
                pga_g: case.pga[k],
            })
            .collect(),
        dt: DT,
        duration: Some(duration),
        variant: match case.variant {
            Variant::Disp => Variant::Disp,
            _ => Variant::Force,
        },
        ..Default::default()
    };
    let text = opensees_script(&case.model, &case.source, &opts)?;
    std::fs::write(&script, text)?;
    let (w_gravity, c_gravity, _) = python(&script, &["gravity"])?;
    let csv = dir.join("th.csv");
    let (w_th, c_th, out) = python(&script, &["th", csv.to_str().context("temp path")?])?;
    let summary: serde_json::Value = serde_json::from_str(out.lines().last().unwrap_or(""))
        .context("the exported script printed no summary")?;
    let os_steps = summary["steps"].as_u64().unwrap_or(0) as f64;
    let ms_os = (w_th - w_gravity) / os_steps * 1e3;
    let cpu_os = (c_th - c_gravity) / os_steps * 1e3;
    println!(
        "openseespy: {} steps, {:.3} ms/step, CPU {:.3} ms/step (setup {:.3} s)",
        os_steps, ms_os, cpu_os, w_gravity
    );
    println!(
        "ratio (OpenSees / fem2rbd): {:.2}x wall, {:.2}x CPU ({} thread(s))",
        ms_os / ms_ours,
        cpu_os / cpu_ours,
        threads
    );

    // Same results: the roof node's ux, uy over the run.
    let text = std::fs::read_to_string(&csv)?;
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let (ux, uy) = (format!("ux_{roof}"), format!("uy_{roof}"));
    let (cx, cy) = (
        head.iter().position(|h| *h == ux).context(ux.clone())?,
        head.iter().position(|h| *h == uy).context(uy.clone())?,
    );
    let k = r
        .node_tags
        .iter()
        .position(|&t| t == roof)
        .context("roof node")?;
    let h = &r.transient.history;
    let (mut dmax, mut peak) = (0.0f64, 0.0f64);
    for (i, l) in lines.enumerate() {
        let v: Vec<f64> = l
            .split(',')
            .map(|x| x.parse().unwrap_or(f64::NAN))
            .collect();
        let Some(ours) = h.disp.get(i + 1).map(|d| d[k]) else {
            break;
        };
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
        "node {roof} ux/uy: max |fem2rbd - OpenSees| = {:.3e} m = {:.3} % of the peak {:.3} mm",
        dmax,
        dmax / peak * 100.0,
        peak * 1e3
    );
    let _ = std::fs::remove_dir_all(&dir);
    Ok(())
}
