//! Initial-stiffness Rayleigh damping of the displacement-based corotational beam at
//! large rotation, against OpenSees (openseespy 3.7.1).
//!
//! OpenSees's `DispBeamColumn3d::getInitialStiff` re-evaluates `Tᵀ Tpᵀ kb0 Tp T` on every
//! call with the corotational `T` of the last `update()` (CorotCrdTransf3d.cpp
//! `getInitialGlobalStiffMatrix`), and `Element::getRayleighDampingForces` calls it each
//! time the damping force is formed: the β·K0 damping of a disp-based corotational beam
//! follows the deformed geometry (the force-based element caches its K0 once). With the
//! undeformed K0 instead, frame3's LC5 disp run left OpenSees's path at the first large
//! excursion (docs/fe-verification.md).
//!
//! Model: a 3 m vertical cantilever of two `dispBeamColumn` elements (5 Gauss-Legendre
//! points, elastic fiber section 0.3 × 0.3 m, E = 30 GPa, Corotational), a 20 t tip
//! mass in X, Y and Z, Rayleigh damping `rayleigh 0 0 a1 0` (5 % at the first mode), a
//! resonant X/Y base acceleration driving the tip to about 10 % drift; Newmark
//! (½, ¼), Newton, NormDispIncr 1e-12. Tip ux/uy/uz every step must agree to 1e-6 of the
//! peak |u| (measured 5e-10; with the undeformed K0 they differ by 0.32 of it).
//!
//! Needs `python3` with openseespy (3.7.1.2; `scripts/setup.sh` installs it). If it is
//! missing, the test fails with the Python error.

use super::support;

use fem2rbd_fe::fe::analysis::rayleigh::RayleighDamping;
use fem2rbd_fe::fe::analysis::transient::{run_transient, StepControl, TransientSettings};
use fem2rbd_fe::fe::analysis::ConvergenceTest;
use fem2rbd_fe::fe::domain::Domain;
use fem2rbd_fe::fe::element::beam::{BeamColumnSpec, Formulation};
use fem2rbd_fe::fe::section::fiber::FiberSection;
use fem2rbd_fe::fe::transform::TransformKind;
use nalgebra::Vector3;
use support::{rectangle_fibers, LinearElastic};

const E: f64 = 30e9;
const SIDE: f64 = 0.3;
const GJ: f64 = 1.0e7;
const HEIGHT: f64 = 3.0;
const MASS: f64 = 2.0e4;
const DT: f64 = 0.01;
const STEPS: usize = 300;
/// Base acceleration amplitude (m/s²), X and 0.6 × in Y.
const AMP: f64 = 4.0;

const SCRIPT: &str = r#"
import json, os, sys
sys.path.insert(0, sys.argv[2])
try:
    from ops_import import ops
except Exception as exc:
    print(f"cannot import openseespy (pip install openseespy==3.7.1.2): {exc}", file=sys.stderr)
    sys.exit(2)
c = json.load(open(sys.argv[1]))
ops.wipe()
ops.model("basic", "-ndm", 3, "-ndf", 6)
for k, z in enumerate(c["z"]):
    ops.node(k + 1, 0.0, 0.0, z)
ops.fix(1, 1, 1, 1, 1, 1, 1)
top = len(c["z"])
ops.mass(top, c["mass"], c["mass"], c["mass"], 0.0, 0.0, 0.0)
ops.uniaxialMaterial("Elastic", 1, c["E"])
ops.section("Fiber", 1, "-GJ", c["GJ"])
for y, z, a in c["fibers"]:
    ops.fiber(y, z, a, 1)
ops.geomTransf("Corotational", 1, 1.0, 0.0, 0.0)
ops.beamIntegration("Legendre", 1, 1, 5)
for k in range(top - 1):
    ops.element("dispBeamColumn", k + 1, k + 1, k + 2, 1, 1)
ops.rayleigh(0.0, 0.0, c["a1"], 0.0)
ops.timeSeries("Path", 1, "-dt", c["dt"], "-values", *c["ax"])
ops.timeSeries("Path", 2, "-dt", c["dt"], "-values", *c["ay"])
ops.pattern("UniformExcitation", 1, 1, "-accel", 1)
ops.pattern("UniformExcitation", 2, 2, "-accel", 2)
ops.system("FullGeneral")
ops.numberer("Plain")
ops.constraints("Plain")
ops.test("NormDispIncr", 1e-12, 100, 0)
ops.algorithm("Newton")
ops.integrator("Newmark", 0.5, 0.25)
ops.analysis("Transient")
hist = []
for _ in range(c["steps"]):
    if ops.analyze(1, c["dt"]) != 0:
        print("OpenSees analysis failed", file=sys.stderr)
        sys.exit(3)
    hist.append([ops.nodeDisp(top, d + 1) for d in range(3)])
print(json.dumps({"tip": hist}))
"#;

fn fibers() -> Vec<(
    f64,
    f64,
    f64,
    Box<dyn fem2rbd_fe::fe::material::UniaxialMaterial>,
)> {
    rectangle_fibers(SIDE, SIDE, 6, 6, &LinearElastic::new(E))
}

/// First-mode circular frequency of the cantilever with the tip mass (rad/s).
fn omega() -> f64 {
    let i = SIDE.powi(4) / 12.0;
    (3.0 * E * i / HEIGHT.powi(3) / MASS).sqrt()
}

fn ground(t: f64) -> [f64; 3] {
    let s = AMP * (omega() * t).sin();
    [s, 0.6 * s, 0.0]
}

fn a1() -> f64 {
    2.0 * 0.05 / omega()
}

fn run_opensees() -> Vec<[f64; 3]> {
    let z: Vec<f64> = (0..=2).map(|k| HEIGHT * k as f64 / 2.0).collect();
    let fib: Vec<[f64; 3]> = fibers().iter().map(|f| [f.0, f.1, f.2]).collect();
    // Path values at t = 0, Δt, 2Δt, … (OpenSees interpolates; only the step times
    // are used by Newmark).
    let ax: Vec<f64> = (0..=STEPS + 1).map(|k| ground(k as f64 * DT)[0]).collect();
    let ay: Vec<f64> = (0..=STEPS + 1).map(|k| ground(k as f64 * DT)[1]).collect();
    let doc = serde_json::json!({
        "z": z, "mass": MASS, "E": E, "GJ": GJ, "fibers": fib, "a1": a1(),
        "dt": DT, "steps": STEPS, "ax": ax, "ay": ay,
    });
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("case.json");
    let script = dir.path().join("disp_damping_case.py");
    std::fs::write(&case, doc.to_string()).unwrap();
    std::fs::write(&script, SCRIPT).unwrap();
    let out = std::process::Command::new("python3")
        .arg(&script)
        .arg(&case)
        .arg(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../..",
            "/tests/opensees"
        ))
        .output()
        .expect("python3 must be on PATH for the OpenSees comparison");
    assert!(
        out.status.success(),
        "OpenSees run failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    let line = stdout.lines().rev().find(|l| l.starts_with('{')).unwrap();
    let v: serde_json::Value = serde_json::from_str(line).unwrap();
    v["tip"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            let a: Vec<f64> = r
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            [a[0], a[1], a[2]]
        })
        .collect()
}

fn run_fem2rbd() -> Vec<[f64; 3]> {
    let mut d = Domain::new();
    for k in 0..=2 {
        d.add_node(k + 1, [0.0, 0.0, HEIGHT * k as f64 / 2.0])
            .unwrap();
    }
    d.fix(0, [true; 6]).unwrap();
    d.set_mass(2, [MASS, MASS, MASS, 0.0, 0.0, 0.0]).unwrap();
    for k in 0..2usize {
        let el = BeamColumnSpec {
            tag: k as i64 + 1,
            nodes: [k, k + 1],
            xi: Vector3::new(0.0, 0.0, HEIGHT * k as f64 / 2.0),
            xj: Vector3::new(0.0, 0.0, HEIGHT * (k + 1) as f64 / 2.0),
            transform: TransformKind::Corotational,
            vecxz: Vector3::x(),
            formulation: Formulation::DispBased { n_ip: 5 },
            section: Some(Box::new(FiberSection::new(fibers(), GJ).unwrap())),
        }
        .build()
        .unwrap();
        d.add_element(el.into_element()).unwrap();
    }
    d.number_dofs();
    let settings = TransientSettings {
        dt: DT,
        t_end: DT * STEPS as f64,
        test: ConvergenceTest {
            tol: 1e-12,
            max_iter: 100,
        },
        ..Default::default()
    };
    let mut tip = Vec::new();
    let r = run_transient(
        &mut d,
        Some(RayleighDamping { a0: 0.0, a1: a1() }),
        &ground,
        &settings,
        &mut |_, dom| {
            let u = dom.displacement(2);
            tip.push([u[0], u[1], u[2]]);
            StepControl::Continue
        },
    )
    .unwrap();
    assert_eq!(r.fallback_steps, 0, "fem2rbd needed fallback steps");
    tip
}

#[test]
fn disp_corotational_initial_stiffness_damping_agrees_with_opensees() {
    let ops = run_opensees();
    let ours = run_fem2rbd();
    assert_eq!(ops.len(), STEPS);
    assert_eq!(ours.len(), STEPS);
    let peak = ops.iter().map(|r| r[0].hypot(r[1])).fold(0.0f64, f64::max);
    let mut worst = [0.0f64; 3];
    for (o, m) in ops.iter().zip(&ours) {
        for k in 0..3 {
            worst[k] = worst[k].max((o[k] - m[k]).abs());
        }
    }
    println!(
        "disp corotational β·K0 damping: peak tip drift {:.2} %, max |Δu| ux/uy/uz = \
         {:.3e}/{:.3e}/{:.3e} m ({:.2e} of the peak)",
        100.0 * peak / HEIGHT,
        worst[0],
        worst[1],
        worst[2],
        worst.iter().fold(0.0f64, |a, &b| a.max(b)) / peak
    );
    assert!(peak / HEIGHT > 0.05, "the tip must reach large drift");
    for k in 0..3 {
        assert!(
            worst[k] < 1e-6 * peak,
            "tip dof {k}: max |Δu| {:e} m against peak {peak:e} m",
            worst[k]
        );
    }
}
