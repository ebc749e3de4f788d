//! The layered `ASDShellQ4` stiffness of `fem2rbd_fe::fe::shell` against openseespy 3.7.1's
//! element matrix (one free element, `printA` of the assembled system) to 1e-6 of its
//! largest entry: a square element, a distorted element in a skew plane with rebar layers
//! at 0°, 90° and 30° and a local x off its first edge, and a warped element. Needs
//! python3 with openseespy 3.7.1 and numpy.
use std::collections::BTreeMap;
use std::process::Command;

use fem2rbd_fe::fe::shell::{
    asd_shell_q4_stiffness, initial_layer_tangents, layered_section_tangent, Mat24,
};
use fem2rbd_fe::model::{Material, MaterialLaw, ShellLayer};
use serde_json::{json, Value};

/// One case: node coordinates, `-local` axis and layers.
struct Case {
    name: &'static str,
    coords: [[f64; 3]; 4],
    local_x: [f64; 3],
    layers: Vec<ShellLayer>,
}

fn concrete(t: f64) -> ShellLayer {
    ShellLayer::Elastic {
        thickness: t,
        e: 30e9,
        nu: 0.2,
    }
}

fn rebar(t: f64, angle: f64) -> ShellLayer {
    ShellLayer::Rebar {
        thickness: t,
        material: 1,
        angle,
    }
}

fn cases() -> Vec<Case> {
    // A skew plane through the origin: rotation about (1, 2, 3) by 0.7 rad.
    let axis = nalgebra::Vector3::new(1.0, 2.0, 3.0).normalize();
    let rot = nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), 0.7);
    let map = |p: [f64; 2], z: f64| {
        let v = rot * nalgebra::Vector3::new(p[0], p[1], z);
        [v[0] + 1.0, v[1] - 2.0, v[2] + 0.5]
    };
    let quad = [[0.0, 0.0], [0.9, 0.1], [1.1, 0.8], [-0.1, 0.7]];
    let layered = vec![
        concrete(0.03),
        rebar(0.0008, 90.0),
        rebar(0.0006, 0.0),
        concrete(0.09),
        rebar(0.0005, 30.0),
        rebar(0.0008, 90.0),
        concrete(0.03),
    ];
    vec![
        Case {
            name: "square, 4 elastic layers",
            coords: [
                [0.0, 0.0, 0.0],
                [0.5, 0.0, 0.0],
                [0.5, 0.5, 0.0],
                [0.0, 0.5, 0.0],
            ],
            local_x: [1.0, 0.0, 0.0],
            layers: vec![concrete(0.025); 4],
        },
        Case {
            name: "distorted, skew plane, rebar 0/90/30, local x off edge 1-2",
            coords: quad.map(|p| map(p, 0.0)),
            local_x: {
                let v = rot * nalgebra::Vector3::new(1.0, 0.3, 0.2);
                [v[0], v[1], v[2]]
            },
            layers: layered.clone(),
        },
        Case {
            name: "warped (node 3 off the plane by 2 % of the size)",
            coords: [
                map(quad[0], 0.0),
                map(quad[1], 0.0),
                map(quad[2], 0.02),
                map(quad[3], 0.0),
            ],
            local_x: {
                let v = rot * nalgebra::Vector3::new(0.0, 1.0, 0.0);
                [v[0], v[1], v[2]]
            },
            layers: layered,
        },
    ]
}

const SCRIPT: &str = r#"
import ctypes, importlib.util, json, os, sys
spec = importlib.util.find_spec("openseespylinux")
if spec is not None and spec.origin is not None:
    libdir = os.path.join(os.path.dirname(spec.origin), "lib")
    for name in ("libquadmath.so.0", "libgfortran.so.4", "libgomp.so.1",
                 "libblas.so.3", "liblapack.so.3"):
        path = os.path.join(libdir, name)
        if os.path.exists(path):
            ctypes.CDLL(path, mode=ctypes.RTLD_GLOBAL)
import openseespy.opensees as ops

out = []
for case in json.load(sys.stdin):
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for i, c in enumerate(case["coords"]):
        ops.node(i + 1, *c)
    ops.uniaxialMaterial("Elastic", 1, 200e9)
    args = []
    tag = 1
    for l in case["layers"]:
        if l["type"] == "elastic":
            ops.nDMaterial("ElasticIsotropic", tag, l["E"], l["nu"])
            ops.nDMaterial("PlateFiber", tag + 1, tag)
            args += [tag + 1, l["thickness"]]
            tag += 2
        else:
            ops.nDMaterial("PlateRebar", tag, l["material"], l["angle"])
            args += [tag, l["thickness"]]
            tag += 1
    ops.section("LayeredShell", 1, len(case["layers"]), *args)
    ops.element("ASDShellQ4", 1, 1, 2, 3, 4, 1, "-local", *case["local_x"])
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", 1e-8, 1)
    ops.algorithm("Linear")
    ops.integrator("LoadControl", 0.0)
    ops.analysis("Static")
    ops.analyze(1)
    out.append(ops.printA("-ret"))
print(json.dumps(out))
"#;

fn opensees_matrices(cases: &[Case]) -> Vec<Vec<f64>> {
    let spec: Vec<Value> = cases
        .iter()
        .map(|c| {
            json!({
                "coords": c.coords,
                "local_x": c.local_x,
                "layers": serde_json::to_value(&c.layers).unwrap(),
            })
        })
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let script = dir.path().join("k.py");
    std::fs::write(&script, SCRIPT).unwrap();
    let mut child = Command::new("python3")
        .arg(&script)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("python3 with openseespy 3.7.1");
    {
        use std::io::Write;
        let mut stdin = child.stdin.take().unwrap();
        stdin
            .write_all(serde_json::to_string(&spec).unwrap().as_bytes())
            .unwrap();
    }
    let out = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let last = stdout.lines().rfind(|l| l.starts_with('[')).unwrap();
    serde_json::from_str(last).unwrap()
}

#[test]
fn asdshellq4_layered_stiffness_matches_opensees() {
    let steel = Material {
        tag: 1,
        name: String::new(),
        density: 0.0,
        law: MaterialLaw::Elastic {
            e: 200e9,
            eta: 0.0,
            e_neg: None,
        },
    };
    let mats: BTreeMap<u32, &Material> = [(1, &steel)].into_iter().collect();
    let cases = cases();
    let reference = opensees_matrices(&cases);
    for (case, a) in cases.iter().zip(&reference) {
        assert_eq!(a.len(), 576);
        let os = Mat24::from_row_slice(a);
        let d = layered_section_tangent(&initial_layer_tangents(&case.layers, &mats).unwrap());
        let k = asd_shell_q4_stiffness(&case.coords, case.local_x, &d).unwrap();
        let scale = os.amax();
        let diff = (k - os).amax() / scale;
        let (i, j) = (0..576)
            .map(|p| (p / 24, p % 24))
            .max_by(|x, y| (k[*x] - os[*x]).abs().total_cmp(&(k[*y] - os[*y]).abs()))
            .unwrap();
        eprintln!(
            "{}: max |K - K_OpenSees| / max |K_OpenSees| = {diff:.2e} (at [{i}, {j}]: {:.6e} vs {:.6e}); K[0,0] {:.6e}, K[5,5] {:.6e}, K[2,2] {:.6e}",
            case.name,
            k[(i, j)],
            os[(i, j)],
            k[(0, 0)],
            k[(5, 5)],
            k[(2, 2)]
        );
        assert!(diff < 1e-6, "{}: {diff:e}", case.name);
    }
}
