//! Thomsen & Wallace's wall RW2 (`tests/fixtures/rw2/model.toml`, written by
//! `scripts/rw2_model.py`; sources of every number in docs/shell-verification.md §9):
//! a 1.22 m × 3.66 m × 0.102 m cantilever wall in the XZ plane, 6 × 12 `ASDShellQ4`
//! elements, boundary-element and web `layered_shell` sections (plastic-damage concrete,
//! Steel02 smeared bars), base fixed. Self-weight plus the test's 85 kip (378.1 kN) axial
//! load on the top row (tributary widths) in 10 load-control steps, held constant; then
//! equal lateral reference loads on the top nodes (their sum is the base shear) and
//! displacement control of the top-left node's ux, Newton, ‖Δu‖ < 1e-8, in both programs.
//! OpenSees runs the script of `fem2rbd export opensees` with the same loads and
//! integrator. Needs python3 with openseespy 3.7.1.
use std::process::Command;

use fem2rbd_fe::export::{opensees_script, OpenSeesOptions};
use fem2rbd_fe::fe::analysis::static_analysis::{
    displacement_control, load_control, DisplacementControl, LoadControl,
};
use fem2rbd_fe::fe::analysis::ConvergenceTest;
use fem2rbd_fe::fe::build::{build_domain, BuildOptions};
use fem2rbd_fe::fe::shell::layers::ConcreteIntegration;
use fem2rbd_fe::model::Model;
use serde_json::Value;

/// The test's axial load, 85 kip (N).
const AXIAL: f64 = 85.0 * 4_448.221_615_260_5;
/// Height to the lateral load, 144 in (m): drift = top ux / H.
const H: f64 = 144.0 * 0.0254;

fn model() -> Model {
    Model::load(crate::repo_root().join("tests/fixtures/rw2/model.toml")).unwrap()
}

/// Top-row node tags from left to right and the axial load on each (tributary width).
fn top_row(model: &Model) -> (Vec<u32>, Vec<f64>) {
    let zmax = model.nodes.iter().map(|n| n.z).fold(f64::MIN, f64::max);
    let mut top: Vec<_> = model
        .nodes
        .iter()
        .filter(|n| (n.z - zmax).abs() < 1e-9)
        .map(|n| (n.x, n.tag))
        .collect();
    top.sort_by(|a, b| a.0.total_cmp(&b.0));
    let xs: Vec<f64> = top.iter().map(|t| t.0).collect();
    let length = xs[xs.len() - 1] - xs[0];
    let mut w = vec![0.0; xs.len()];
    for i in 0..xs.len() - 1 {
        let d = xs[i + 1] - xs[i];
        w[i] += d / 2.0;
        w[i + 1] += d / 2.0;
    }
    (
        top.iter().map(|t| t.1).collect(),
        w.iter().map(|wi| AXIAL * wi / length).collect(),
    )
}

const DRIVER: &str = r#"
import importlib.util, json, sys
spec = importlib.util.spec_from_file_location("wall", sys.argv[1])
wall = importlib.util.module_from_spec(spec)
spec.loader.exec_module(wall)
ops = wall.ops
wall.build()
top = [int(t) for t in sys.argv[2].split(",")]
axial = [float(a) for a in sys.argv[3].split(",")]
segments = json.loads(sys.argv[4])
ops.timeSeries("Linear", 1)
ops.pattern("Plain", 1, 1)
for tag, fz in wall.GRAVITY_LOADS:
    ops.load(tag, 0.0, 0.0, fz, 0.0, 0.0, 0.0)
for t, a in zip(top, axial):
    ops.load(t, 0.0, 0.0, -a, 0.0, 0.0, 0.0)
ops.constraints("Plain")
ops.numberer("Plain")
ops.system("UmfPack")
ops.test("NormDispIncr", 1e-8, 50)
ops.algorithm("Newton")
ops.integrator("LoadControl", 0.1)
ops.analysis("Static")
if ops.analyze(10) != 0:
    print(json.dumps({"failed": -1, "lambda": []}))
    sys.exit(0)
ops.loadConst("-time", 0.0)
ops.timeSeries("Linear", 2)
ops.pattern("Plain", 2, 2)
for t in top:
    ops.load(t, 1.0 / len(top), 0.0, 0.0, 0.0, 0.0, 0.0)
lam = []
for incr, n in segments:
    ops.integrator("DisplacementControl", top[0], 1, incr)
    ops.analysis("Static")
    for _ in range(n):
        if ops.analyze(1) != 0:
            print(json.dumps({"failed": len(lam), "lambda": lam}))
            sys.exit(0)
        lam.append(ops.getLoadFactor(2))
print(json.dumps({"lambda": lam}))
"#;

/// Base shear (N) per step from openseespy, and the step it failed at, if any.
fn opensees(model: &Model, segs: &[(f64, usize)]) -> (Vec<f64>, Option<usize>) {
    let (top, axial) = top_row(model);
    let dir = tempfile::tempdir().unwrap();
    let script = dir.path().join("rw2.py");
    std::fs::write(
        &script,
        opensees_script(model, "rw2.toml", &OpenSeesOptions::default()).unwrap(),
    )
    .unwrap();
    let driver = dir.path().join("drive.py");
    std::fs::write(&driver, DRIVER).unwrap();
    let join = |v: Vec<String>| v.join(",");
    let v: Value = crate::openseespy_json(
        Command::new("python3")
            .arg(&driver)
            .arg(&script)
            .arg(join(top.iter().map(|t| t.to_string()).collect()))
            .arg(join(axial.iter().map(|a| format!("{a:?}")).collect()))
            .arg(serde_json::to_string(segs).unwrap()),
    );
    let lam = v["lambda"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    (lam, v.get("failed").map(|f| f.as_i64().unwrap() as usize))
}

/// Base shear (N) per step from fem2rbd, and the step it failed at, if any.
fn fem2rbd(model: &Model, segs: &[(f64, usize)]) -> (Vec<f64>, Option<usize>) {
    fem2rbd_with(model, segs, ConcreteIntegration::Implicit)
}

/// [`fem2rbd`] with the concrete layers integrated by `integration`.
fn fem2rbd_with(
    model: &Model,
    segs: &[(f64, usize)],
    integration: ConcreteIntegration,
) -> (Vec<f64>, Option<usize>) {
    let (top, axial) = top_row(model);
    let options = BuildOptions {
        concrete_integration: integration,
        ..Default::default()
    };
    let mut built = build_domain(model, &options).unwrap();
    let d = &mut built.domain;
    for (t, a) in top.iter().zip(&axial) {
        d.add_nodal_load(built.node_index[t], [0.0, 0.0, -a, 0.0, 0.0, 0.0])
            .unwrap();
    }
    let test = ConvergenceTest {
        tol: 1e-8,
        max_iter: 50,
    };
    load_control(
        d,
        &LoadControl {
            steps: 10,
            test,
            ..Default::default()
        },
    )
    .unwrap();
    d.load_const();
    for t in &top {
        d.add_nodal_load(
            built.node_index[t],
            [1.0 / top.len() as f64, 0.0, 0.0, 0.0, 0.0, 0.0],
        )
        .unwrap();
    }
    let node = built.node_index[&top[0]];
    let mut lam = Vec::new();
    for &(increment, steps) in segs {
        for _ in 0..steps {
            match displacement_control(
                d,
                &DisplacementControl {
                    node,
                    dof: 0,
                    increment,
                    steps: 1,
                    test,
                    fallbacks: false,
                },
            ) {
                Ok(s) => lam.push(s[0].load_factor),
                Err(e) => {
                    eprintln!("fem2rbd: step {} failed: {e}", lam.len() + 1);
                    let n = lam.len();
                    return (lam, Some(n));
                }
            }
        }
    }
    (lam, None)
}

/// Prints both curves every `every` steps; returns (worst |Δ| / OpenSees peak, common steps).
fn compare(os: &[f64], fr: &[f64], step: f64, every: usize) -> (f64, usize) {
    let n = os.len().min(fr.len());
    let peak = os[..n].iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut worst = 0.0f64;
    for k in 0..n {
        let diff = (fr[k] - os[k]) / peak;
        worst = worst.max(diff.abs());
        if (k + 1) % every == 0 || k + 1 == n {
            eprintln!(
                "{:6.2} mm ({:.3} % drift): OpenSees {:8.2} kN fem2rbd {:8.2} kN ({:+.2e} of peak)",
                (k + 1) as f64 * step * 1e3,
                (k + 1) as f64 * step / H * 100.0,
                os[k] / 1e3,
                fr[k] / 1e3,
                diff
            );
        }
    }
    (worst, n)
}

/// Monotonic push of RW2, study (`--ignored`): both programs to 2.2 % drift in 0.25 mm
/// steps, or as far as each converges.
#[test]
#[ignore]
fn rw2_monotonic_study() {
    let model = model();
    let step = 0.25e-3;
    let segs = [(step, (0.022 * H / step).round() as usize)];
    let (os, os_fail) = opensees(&model, &segs);
    let (fr, fr_fail) = fem2rbd(&model, &segs);
    eprintln!("OpenSees failed at {os_fail:?}, fem2rbd at {fr_fail:?}");
    let (worst, n) = compare(&os, &fr, step, 8);
    eprintln!("common steps {n}: worst {worst:.3e} of the peak");
    for (name, v) in [("OpenSees", &os), ("fem2rbd", &fr)] {
        let (k, p) = v
            .iter()
            .enumerate()
            .fold((0, 0.0f64), |a, (k, x)| if *x > a.1 { (k, *x) } else { a });
        eprintln!(
            "{name}: peak {:.2} kN at {:.2} mm ({:.3} % drift)",
            p / 1e3,
            (k + 1) as f64 * step * 1e3,
            (k + 1) as f64 * step / H * 100.0
        );
    }
}

/// fem2rbd against openseespy on RW2 through the axial load, the elastic range and the
/// onset of cracking at the base (0.25 mm steps to 1.75 mm, 0.048 % drift; linear to
/// 1.25 mm at 7.98 kN per step, the last step's stiffness 0.75 of that): every step
/// within 1 % of OpenSees' largest base shear (measured 6.8e-5; 3e-16 before
/// cracking). Both programs' Newton diverges within the next steps (fem2rbd at 2.0 mm,
/// OpenSees at 2.5 mm; docs/shell-verification.md §9), so this model does not reach the
/// test's measured peak (163.3 kN).
#[test]
fn rw2_axial_load_and_cracking_match_opensees() {
    let model = model();
    let step = 0.25e-3;
    let segs = [(step, 7)];
    let (os, os_fail) = opensees(&model, &segs);
    let (fr, fr_fail) = fem2rbd(&model, &segs);
    assert_eq!(os_fail, None, "OpenSees stopped at step {os_fail:?}");
    assert_eq!(fr_fail, None, "fem2rbd stopped at step {fr_fail:?}");
    let (worst, n) = compare(&os, &fr, step, 1);
    assert_eq!(n, 7);
    // Cracking has begun: the last step's stiffness is a quarter below the first's
    // (measured 0.75).
    assert!(os[6] - os[5] < 0.85 * os[0], "{os:?}");
    assert!(worst < 0.01, "worst {worst:.3e} of the peak");
}

/// Peak (N) of a base-shear curve and its step index.
fn peak(v: &[f64]) -> (usize, f64) {
    v.iter()
        .enumerate()
        .fold((0, 0.0f64), |a, (k, x)| if *x > a.1 { (k, *x) } else { a })
}

/// IMPL-EX monotonic push of RW2, study (`--ignored`): to 2.2 % drift in 0.25 mm steps,
/// and the first 40 mm again in 0.125 mm steps (step convergence), printed.
#[test]
#[ignore]
fn rw2_implex_monotonic_study() {
    let model = model();
    for step in [0.5e-3, 0.25e-3, 0.125e-3] {
        let n = (0.022 * H / step).round() as usize;
        let t0 = std::time::Instant::now();
        let (fr, fail) = fem2rbd_with(&model, &[(step, n)], ConcreteIntegration::Implex);
        let (k, p) = peak(&fr);
        eprintln!(
            "implex, {:.3} mm steps: {} of {n} steps (failed {fail:?}) in {:.1} s; peak {:.2} kN at {:.2} mm ({:.3} % drift)",
            step * 1e3,
            fr.len(),
            t0.elapsed().as_secs_f64(),
            p / 1e3,
            (k + 1) as f64 * step * 1e3,
            (k + 1) as f64 * step / H * 100.0
        );
        for (j, v) in fr.iter().enumerate() {
            let d = (j + 1) as f64 * step;
            if ((d * 1e3) % 5.0).abs() < 1e-6 || ((d * 1e3) % 5.0 - 5.0).abs() < 1e-6 {
                eprintln!(
                    "  {:6.2} mm ({:.3} %): {:8.2} kN",
                    d * 1e3,
                    d / H * 100.0,
                    v / 1e3
                );
            }
        }
    }
}

/// RW2 with IMPL-EX concrete layers (docs/shell-verification.md §10), pushed in 0.5 mm
/// steps to 2.2 % drift (161 steps, about 10 s in the debug build): the push completes
/// and its largest base shear — at the end of the push, still rising — is within 5 % of
/// the test's measured peak, 163.284 kN (source and caveats in §9; measured here
/// 161.5 kN, 0.99 of it). Before the first crack (to 1.0 mm) IMPL-EX equals the implicit
/// law (no damage to extrapolate). Not a claim for every step size: in 0.25 mm steps the
/// push stops at 0.49 % drift, where yielded Steel02 bar layers switch between loading and
/// unloading from one iteration to the next (§10).
#[test]
fn rw2_implex_push_reaches_the_measured_peak() {
    let model = model();
    let step = 0.5e-3;
    let n = (0.022 * H / step).round() as usize;
    let (fr, fail) = fem2rbd_with(&model, &[(step, n)], ConcreteIntegration::Implex);
    assert_eq!(fail, None, "IMPL-EX push stopped at step {fail:?}");
    let (imp, _) = fem2rbd_with(&model, &[(step, 2)], ConcreteIntegration::Implicit);
    for k in 0..2 {
        assert!(
            (fr[k] - imp[k]).abs() <= 1e-9 * imp[k].abs(),
            "{} mm: {} vs {}",
            (k + 1) as f64 * 0.5,
            fr[k],
            imp[k]
        );
    }
    let (k, p) = peak(&fr);
    let measured = 163.284e3;
    eprintln!(
        "RW2 IMPL-EX: peak {:.2} kN at {:.2} mm ({:.3} % drift) = {:.3} of the measured {:.3} kN",
        p / 1e3,
        (k + 1) as f64 * step * 1e3,
        (k + 1) as f64 * step / H * 100.0,
        p / measured,
        measured / 1e3
    );
    assert!((p / measured - 1.0).abs() < 0.05, "peak {p}");
}
