//! Large rotations: the corotational `ASDShellQ4` (`corotational = true`) against the
//! elastica and against openseespy's `ASDShellQ4 … -corotational` on the exported script.
//!
//! A cantilever strip L = 10 m, b = 1 m, h = 0.1 m, E = 1.2 MPa, ν = 0 (the Sze, Liu & Lo
//! 2004 benchmark geometry), five equal elastic layers (bending stiffness
//! EI = (1 − 1/5²) E b h³/12 = 96 N·m² with the layered midpoint rule), 16 × 1 elements,
//! root nodes fixed, loaded at the two tip nodes:
//! - an end moment M about y, in 20 load-control steps up to M = π EI / L (the strip rolls
//!   into a half circle). Elastica: curvature M/EI, so the tip sits at
//!   x = ρ sin φ, z = ρ (1 − cos φ) with ρ = EI/M, φ = M L/EI, and turns by φ;
//! - an end shear P = 4 N (PL²/EI = 4.17) in z, under displacement control of the tip
//!   deflection in both programs (OpenSees' corotational tangent has no geometric
//!   stiffness, so its load control stalls).
//!
//! Every step's tip displacements are compared with OpenSees' (limit 1e-6 of the largest
//! tip displacement; measured ≤ 1.5e-15); the moment case also with the closed form:
//! flat facets approximate the arc with an error of order (L/n)², measured 1.02e-3 L at
//! the half circle on 16 elements (limit 2e-3 L) and 2.6e-4 L on 32 (the limit asks for
//! at least a third of the 16-element error). Needs python3 with openseespy 3.7.1.
use std::fmt::Write as _;
use std::process::Command;

use fem2rbd_fe::export::{opensees_script, OpenSeesOptions};
use fem2rbd_fe::fe::analysis::static_analysis::{
    displacement_control, load_control, DisplacementControl, LoadControl,
};
use fem2rbd_fe::fe::analysis::{Algorithm, ConvergenceTest};
use fem2rbd_fe::fe::build::{build_domain, BuildOptions, BuiltDomain};
use fem2rbd_fe::model::Model;
use serde_json::Value;

const L: f64 = 10.0;
const NX: usize = 16;
/// The refined mesh of the mesh-convergence check.
const NX_FINE: usize = 32;
const E: f64 = 1.2e6;
/// Layered midpoint bending stiffness, 5 equal layers (N·m²).
const EI: f64 = (1.0 - 1.0 / 25.0) * E * 1.0 * 0.001 / 12.0;

fn strip_model(nx: usize) -> String {
    let mut t = String::from(
        r#"name = "corotational-strip"
[[section]]
tag = 10
type = "layered_shell"
layers = [
  { type = "elastic", thickness = 0.02, E = 1.2e6, nu = 0.0 },
  { type = "elastic", thickness = 0.02, E = 1.2e6, nu = 0.0 },
  { type = "elastic", thickness = 0.02, E = 1.2e6, nu = 0.0 },
  { type = "elastic", thickness = 0.02, E = 1.2e6, nu = 0.0 },
  { type = "elastic", thickness = 0.02, E = 1.2e6, nu = 0.0 },
]
"#,
    );
    for j in 0..2 {
        for i in 0..=nx {
            writeln!(
                t,
                "[[node]]\ntag = {}\nx = {:?}\ny = {:?}\nz = 0.0",
                1000 * j + i + 1,
                L * i as f64 / nx as f64,
                j as f64
            )
            .unwrap();
        }
    }
    for tag in [1, 1001] {
        writeln!(t, "[[support]]\nnode = {tag}\ndofs = [1, 1, 1, 1, 1, 1]").unwrap();
    }
    for i in 0..nx {
        writeln!(
            t,
            "[[element]]\ntag = {}\ntype_name = \"Strip\"\ngroup = 1\ntype = \"shell\"\n\
             nodes = [{}, {}, {}, {}]\nsection = 10\ncorotational = true",
            i + 1,
            i + 1,
            i + 2,
            i + 1002,
            i + 1001
        )
        .unwrap();
    }
    t
}

/// The tip nodes of an `nx`-element strip.
fn tips(nx: usize) -> [u32; 2] {
    [nx as u32 + 1, nx as u32 + 1001]
}

/// The OpenSees driver: `mode` "moment" (load control, `steps` steps, moment −M/2 about
/// y at each tip node, M = `value`) or "shear" (load P/2 in z at each tip node, P =
/// `value`, displacement control of the first tip node's uz by `incr` for `steps`).
/// Prints, per step, λ and the first tip node's ux, uz, θy.
const DRIVER: &str = r#"
import importlib.util, json, sys
spec = importlib.util.spec_from_file_location("strip", sys.argv[1])
strip = importlib.util.module_from_spec(spec)
spec.loader.exec_module(strip)
ops = strip.ops
strip.build()
mode, value, steps, incr = sys.argv[2], float(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5])
tips = [int(t) for t in sys.argv[6].split(",")]
ops.timeSeries("Linear", 1)
ops.pattern("Plain", 1, 1)
for t in tips:
    if mode == "moment":
        ops.load(t, 0.0, 0.0, 0.0, 0.0, -0.5 * value, 0.0)
    else:
        ops.load(t, 0.0, 0.0, 0.5 * value, 0.0, 0.0, 0.0)
ops.constraints("Plain")
ops.numberer("Plain")
ops.system("FullGeneral")
ops.test("NormDispIncr", 1e-12, 1000)
ops.algorithm("Newton")
if mode == "moment":
    ops.integrator("LoadControl", 1.0 / steps)
else:
    ops.integrator("DisplacementControl", tips[0], 3, incr)
ops.analysis("Static")
out = []
for k in range(steps):
    if ops.analyze(1) != 0:
        print(json.dumps({"failed": k, "out": out}))
        sys.exit(0)
    t = tips[0]
    out.append([ops.getLoadFactor(1), ops.nodeDisp(t, 1), ops.nodeDisp(t, 3), ops.nodeDisp(t, 5)])
print(json.dumps({"out": out}))
"#;

fn opensees(model: &Model, mode: &str, value: f64, steps: usize, incr: f64) -> Vec<[f64; 4]> {
    let dir = tempfile::tempdir().unwrap();
    let script = dir.path().join("strip.py");
    std::fs::write(
        &script,
        opensees_script(model, "strip.toml", &OpenSeesOptions::default()).unwrap(),
    )
    .unwrap();
    assert!(std::fs::read_to_string(&script)
        .unwrap()
        .contains("-corotational"));
    let driver = dir.path().join("drive.py");
    std::fs::write(&driver, DRIVER).unwrap();
    let tips: Vec<String> = tips(NX).iter().map(|t| t.to_string()).collect();
    let v: Value = crate::openseespy_json(
        Command::new("python3")
            .arg(&driver)
            .arg(&script)
            .arg(mode)
            .arg(value.to_string())
            .arg(steps.to_string())
            .arg(incr.to_string())
            .arg(tips.join(",")),
    );
    assert!(v.get("failed").is_none(), "OpenSees failed: {v}");
    v["out"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            let r = r.as_array().unwrap();
            [0, 1, 2, 3].map(|k| r[k].as_f64().unwrap())
        })
        .collect()
}

fn tip_state(built: &BuiltDomain, nx: usize) -> [f64; 4] {
    let d = built.domain.displacement(built.node_index[&tips(nx)[0]]);
    [built.domain.load_factor(), d[0], d[2], d[4]]
}

fn fem2rbd_moment(model: &Model, nx: usize, m: f64, steps: usize) -> Vec<[f64; 4]> {
    let mut built = build_domain(model, &BuildOptions::default()).unwrap();
    for t in tips(nx) {
        let i = built.node_index[&t];
        built
            .domain
            .add_nodal_load(i, [0.0, 0.0, 0.0, 0.0, -0.5 * m, 0.0])
            .unwrap();
    }
    let mut out = Vec::new();
    for _ in 0..steps {
        let s = load_control(
            &mut built.domain,
            &LoadControl {
                steps: 1,
                test: ConvergenceTest {
                    tol: 1e-12,
                    max_iter: 50,
                },
                algorithms: vec![Algorithm::Newton],
            },
        );
        s.unwrap_or_else(|e| panic!("fem2rbd failed after {} steps: {e}", out.len()));
        out.push(tip_state(&built, nx));
    }
    out
}

/// The closed-form tip (ux, uz, θ) of the elastica under end moment `m`.
fn elastica_moment(m: f64) -> [f64; 3] {
    let phi = m * L / EI;
    let rho = EI / m;
    [rho * phi.sin() - L, rho * (1.0 - phi.cos()), phi]
}

#[test]
fn corotational_strip_rolls_up_under_end_moment_like_opensees_and_the_elastica() {
    let model = Model::parse(&strip_model(NX), "strip.toml", false).unwrap();
    let steps = 20;
    let m_max = std::f64::consts::PI * EI / L;
    let os = opensees(&model, "moment", m_max, steps, 0.0);
    // fem2rbd: the same reference load applied `steps` times with λ += 1 per step, so
    // the reference load is m_max / steps.
    let fr = fem2rbd_moment(&model, NX, m_max / steps as f64, steps);
    assert_eq!(os.len(), fr.len());
    let scale = os
        .iter()
        .fold(0.0f64, |a, r| a.max(r[1].abs()).max(r[2].abs()));
    let (mut worst_os, mut worst_cf, mut worst_rot) = (0.0f64, 0.0f64, 0.0f64);
    for (k, (o, f)) in os.iter().zip(&fr).enumerate() {
        let m = m_max * (k + 1) as f64 / steps as f64;
        let cf = elastica_moment(m);
        let d_os = (f[1] - o[1]).abs().max((f[2] - o[2]).abs()) / scale;
        let d_cf = (f[1] - cf[0]).abs().max((f[2] - cf[1]).abs()) / L;
        // fem2rbd's tip rotation is the additive rotation DOF (planar: exactly φ).
        let d_rot = (-f[3] - cf[2]).abs() / cf[2];
        eprintln!(
            "M = {m:.4}: tip ux/uz OpenSees {:+.9} {:+.9}, fem2rbd {:+.9} {:+.9}, \
             elastica {:+.9} {:+.9}; vs OpenSees {d_os:.2e}, vs elastica {d_cf:.2e} of L",
            o[1], o[2], f[1], f[2], cf[0], cf[1]
        );
        worst_os = worst_os.max(d_os);
        worst_cf = worst_cf.max(d_cf);
        worst_rot = worst_rot.max(d_rot);
    }
    eprintln!(
        "end moment: worst vs OpenSees {worst_os:.3e}, vs elastica {worst_cf:.3e} of L, \
         tip rotation {worst_rot:.3e}"
    );
    // Mesh convergence: the same load on 32 elements, at the half circle.
    let fine = Model::parse(&strip_model(NX_FINE), "strip.toml", false).unwrap();
    let ff = fem2rbd_moment(&fine, NX_FINE, m_max / 4.0, 4);
    let cf = elastica_moment(m_max);
    let e_fine = (ff[3][1] - cf[0]).abs().max((ff[3][2] - cf[1]).abs()) / L;
    let e_coarse = (fr[steps - 1][1] - cf[0])
        .abs()
        .max((fr[steps - 1][2] - cf[1]).abs())
        / L;
    eprintln!(
        "half circle: error {e_coarse:.3e} of L on {NX} elements, {e_fine:.3e} on {NX_FINE} \
         (ratio {:.2})",
        e_coarse / e_fine
    );
    assert!(worst_os < 1e-6, "vs OpenSees: {worst_os:e}");
    assert!(worst_cf < 2e-3, "vs elastica: {worst_cf:e} of L");
    assert!(
        e_fine < e_coarse / 3.0,
        "no mesh convergence: {e_coarse:e} -> {e_fine:e}"
    );
    assert!(worst_rot < 1e-6, "tip rotation vs elastica: {worst_rot:e}");
}

#[test]
fn corotational_strip_under_end_shear_matches_opensees() {
    let model = Model::parse(&strip_model(NX), "strip.toml", false).unwrap();
    let steps = 40;
    let incr = 0.17;
    let os = opensees(&model, "shear", 4.0, steps, incr);
    let mut built = build_domain(&model, &BuildOptions::default()).unwrap();
    for t in tips(NX) {
        let i = built.node_index[&t];
        built
            .domain
            .add_nodal_load(i, [0.0, 0.0, 2.0, 0.0, 0.0, 0.0])
            .unwrap();
    }
    let node = built.node_index[&tips(NX)[0]];
    let mut fr = Vec::new();
    for _ in 0..steps {
        displacement_control(
            &mut built.domain,
            &DisplacementControl {
                node,
                dof: 2,
                increment: incr,
                steps: 1,
                test: ConvergenceTest {
                    tol: 1e-12,
                    max_iter: 50,
                },
                fallbacks: false,
            },
        )
        .unwrap_or_else(|e| panic!("fem2rbd failed after {} steps: {e}", fr.len()));
        fr.push(tip_state(&built, NX));
    }
    let scale = os
        .iter()
        .fold(0.0f64, |a, r| a.max(r[1].abs()).max(r[2].abs()));
    let (mut worst_u, mut worst_l) = (0.0f64, 0.0f64);
    for (o, f) in os.iter().zip(&fr) {
        worst_u = worst_u.max((f[1] - o[1]).abs() / scale);
        worst_l = worst_l.max((f[0] - o[0]).abs() / o[0].abs());
    }
    let last = (os.last().unwrap(), fr.last().unwrap());
    eprintln!(
        "end shear: at uz = {:.3}: P OpenSees {:.9} fem2rbd {:.9}, ux {:.9} / {:.9}; \
         worst ux {worst_u:.3e} of max, worst P {worst_l:.3e}",
        last.0[2],
        4.0 * last.0[0],
        4.0 * last.1[0],
        last.0[1],
        last.1[1]
    );
    assert!(worst_u < 1e-6, "ux vs OpenSees: {worst_u:e}");
    assert!(worst_l < 1e-6, "P vs OpenSees: {worst_l:e}");
}
