//! An elastic layered wall (1 m × 2 m × 0.1 m, 2 × 4 elements, concrete layers plus
//! vertical and horizontal bar layers on each face) written in the model format, pushed
//! 1 mm at the top: fem2rbd's shell stiffness (`fe::shell::model_shell_stiffness`,
//! assembled here) against openseespy running the *exported* script (`build()`, then the
//! same imposed top displacement with a static linear analysis). Base shear and every
//! free displacement to 1e-6. Needs python3 with openseespy 3.7.1.
use super::support::wall_mesh;
use std::process::Command;

use fem2rbd_fe::export::{opensees_script, OpenSeesOptions};
use fem2rbd_fe::fe::shell::model_shell_stiffness;
use fem2rbd_fe::model::Model;
use nalgebra::{DMatrix, DVector};
use serde_json::Value;

const TOP_UX: f64 = 1e-3;

/// The wall in the XZ plane, base (z = 0) fixed, `nx` × `nz` elements.
fn wall_model(nx: usize, nz: usize) -> String {
    let (b, h) = (1.0, 2.0);
    let header = String::from(
        r#"name = "elastic-layered-wall"
[[material]]
tag = 1
type = "Elastic"
E = 200e9

[[section]]
tag = 10
type = "layered_shell"
density = 2500.0
layers = [
  { type = "elastic", thickness = 0.0125, E = 30e9, nu = 0.2 },
  { type = "elastic", thickness = 0.0125, E = 30e9, nu = 0.2 },
  { type = "rebar", thickness = 0.00025, material = 1, angle = 90.0 },
  { type = "rebar", thickness = 0.00025, material = 1, angle = 0.0 },
  { type = "elastic", thickness = 0.05, E = 30e9, nu = 0.2 },
  { type = "rebar", thickness = 0.00025, material = 1, angle = 0.0 },
  { type = "rebar", thickness = 0.00025, material = 1, angle = 90.0 },
  { type = "elastic", thickness = 0.0125, E = 30e9, nu = 0.2 },
  { type = "elastic", thickness = 0.0125, E = 30e9, nu = 0.2 },
]
"#,
    );
    wall_mesh(&header, b, h, nx, nz)
}

/// Imports the exported script as a module, builds, imposes ux = TOP_UX on the top nodes
/// and prints the base shear and all displacements as JSON.
const DRIVER: &str = r#"
import importlib.util, json, sys
spec = importlib.util.spec_from_file_location("wall", sys.argv[1])
wall = importlib.util.module_from_spec(spec)
spec.loader.exec_module(wall)
ops = wall.ops
wall.build()
top = [int(t) for t in sys.argv[2].split(",")]
base = [int(t) for t in sys.argv[3].split(",")]
ops.timeSeries("Linear", 1)
ops.pattern("Plain", 1, 1)
for t in top:
    ops.sp(t, 1, float(sys.argv[4]))
ops.constraints("Transformation")
ops.numberer("Plain")
ops.system("FullGeneral")
ops.test("NormDispIncr", 1e-12, 10)
ops.algorithm("Linear")
ops.integrator("LoadControl", 1.0)
ops.analysis("Static")
assert ops.analyze(1) == 0
ops.reactions()
shear = -sum(ops.nodeReaction(t, 1) for t in base)
disp = {str(t): ops.nodeDisp(t) for t in ops.getNodeTags()}
print(json.dumps({"base_shear": shear, "disp": disp}))
"#;

#[test]
fn elastic_layered_wall_pushover_matches_the_exported_opensees_model() {
    let (nx, nz) = (2, 4);
    let model = Model::parse(&wall_model(nx, nz), "wall.toml", false).unwrap();
    let index: std::collections::BTreeMap<u32, usize> = model
        .nodes
        .iter()
        .enumerate()
        .map(|(i, n)| (n.tag, i))
        .collect();
    let n = 6 * model.nodes.len();
    let mut k = DMatrix::<f64>::zeros(n, n);
    for e in &model.elements {
        let (nodes, ke) = model_shell_stiffness(&model, e).unwrap();
        for (a, na) in nodes.iter().enumerate() {
            for (b, nb) in nodes.iter().enumerate() {
                for p in 0..6 {
                    for q in 0..6 {
                        k[(6 * index[na] + p, 6 * index[nb] + q)] += ke[(6 * a + p, 6 * b + q)];
                    }
                }
            }
        }
    }
    let top: Vec<u32> = (0..=nx).map(|i| (100 * nz + i + 1) as u32).collect();
    let base: Vec<u32> = (0..=nx).map(|i| (i + 1) as u32).collect();
    // Prescribed: every base DOF (0) and the top nodes' ux (TOP_UX); the rest free.
    let mut prescribed = vec![None; n];
    for t in &base {
        for p in 0..6 {
            prescribed[6 * index[t] + p] = Some(0.0);
        }
    }
    for t in &top {
        prescribed[6 * index[t]] = Some(TOP_UX);
    }
    let free: Vec<usize> = (0..n).filter(|&i| prescribed[i].is_none()).collect();
    let fixed: Vec<usize> = (0..n).filter(|&i| prescribed[i].is_some()).collect();
    let up = DVector::from_iterator(fixed.len(), fixed.iter().map(|&i| prescribed[i].unwrap()));
    let kff = DMatrix::from_fn(free.len(), free.len(), |r, c| k[(free[r], free[c])]);
    let kfp = DMatrix::from_fn(free.len(), fixed.len(), |r, c| k[(free[r], fixed[c])]);
    let uf = kff.lu().solve(&(-(&kfp * &up))).expect("non-singular wall");
    let mut u = DVector::<f64>::zeros(n);
    for (r, &i) in free.iter().enumerate() {
        u[i] = uf[r];
    }
    for (r, &i) in fixed.iter().enumerate() {
        u[i] = up[r];
    }
    let f = &k * &u;
    let shear: f64 = base.iter().map(|t| -f[6 * index[t]]).sum();

    // openseespy on the exported script.
    let dir = tempfile::tempdir().unwrap();
    let script = dir.path().join("wall.py");
    std::fs::write(
        &script,
        opensees_script(&model, "wall.toml", &OpenSeesOptions::default()).unwrap(),
    )
    .unwrap();
    let driver = dir.path().join("push.py");
    std::fs::write(&driver, DRIVER).unwrap();
    let list = |v: &[u32]| {
        v.iter()
            .map(|t| t.to_string())
            .collect::<Vec<_>>()
            .join(",")
    };
    let v: Value = crate::openseespy_json(
        Command::new("python3")
            .arg(&driver)
            .arg(&script)
            .arg(list(&top))
            .arg(list(&base))
            .arg(format!("{TOP_UX:?}")),
    );
    let os_shear = v["base_shear"].as_f64().unwrap();
    let mut umax: f64 = 0.0;
    let mut dmax: f64 = 0.0;
    for nd in &model.nodes {
        let d = v["disp"][nd.tag.to_string()].as_array().unwrap();
        for p in 0..6 {
            let (a, b) = (u[6 * index[&nd.tag] + p], d[p].as_f64().unwrap());
            umax = umax.max(b.abs());
            dmax = dmax.max((a - b).abs());
        }
    }
    eprintln!(
        "base shear at {TOP_UX} m: fem2rbd {:.9} kN, OpenSees {:.9} kN ({:+.2e}); max displacement difference {:.2e} of {:.3e}",
        shear / 1e3,
        os_shear / 1e3,
        (shear - os_shear) / os_shear,
        dmax,
        umax
    );
    assert!(((shear - os_shear) / os_shear).abs() < 1e-6);
    assert!(dmax < 1e-6 * umax);
}
