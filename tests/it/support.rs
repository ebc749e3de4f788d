//! Helpers shared by the test folders of this crate.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// The repository's top folder.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A numeric CSV table: its header and its rows.
pub fn read_csv(path: &std::path::Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let head: Vec<String> = lines
        .next()
        .expect("header")
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split(',').map(|x| x.trim().parse().unwrap()).collect())
        .collect();
    (head, rows)
}

/// Every `.rs` file under `dir`, recursively, in sorted path order (appended to `out`).
pub fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// An axis-aligned box for the ruin-stage tests: group "rc" (active) or "base" (passive),
/// centre and half extents in m.
pub fn rc_box(
    name: &str,
    centre: [f64; 3],
    he: [f64; 3],
    passive: bool,
) -> fem2rbd::ruin::BodyGeom {
    fem2rbd::ruin::BodyGeom {
        name: name.into(),
        group: if passive { "base" } else { "rc" }.into(),
        centre,
        rotation: nalgebra::UnitQuaternion::identity(),
        half_extents: he,
        passive,
    }
}

/// Pushes `count` frame3 column pieces (0.1 × 0.1 × 0.25 m, 6.25 kg; named `piece0`, …)
/// stacked on the axis x = y = 0 from the height `base_z` (m) up.
pub fn column_pieces(
    bodies: &mut Vec<fem2rbd::ruin::BodyGeom>,
    masses: &mut Vec<f64>,
    base_z: f64,
    count: usize,
) {
    for k in 0..count {
        let z = base_z + 0.125 + 0.25 * k as f64;
        bodies.push(rc_box(
            &format!("piece{k}"),
            [0.0, 0.0, z],
            [0.05, 0.05, 0.125],
            false,
        ));
        masses.push(6.25);
    }
}

/// A Generic6Dof constraint locked in all six axes between `a` and `b`, pivot at `pivot_a`
/// in A's frame and `pivot_b` in B's frame, no collisions between the two.
pub fn locked_joint(
    w: &mut fem2rbd::bullet::World,
    a: fem2rbd::bullet::BodyHandle,
    b: fem2rbd::bullet::BodyHandle,
    pivot_a: [f64; 3],
    pivot_b: [f64; 3],
) -> fem2rbd::bullet::ConstraintHandle {
    use fem2rbd::bullet::{ConstraintDesc, ConstraintKind, Pose};
    let mut d = ConstraintDesc::new(
        ConstraintKind::Generic6Dof {
            use_linear_reference_frame_a: true,
        },
        a,
        b,
        Pose::at(pivot_a),
        Pose::at(pivot_b),
    );
    d.limits = [Some((0.0, 0.0)); 6];
    d.disable_collisions_between = true;
    w.add_constraint(&d).unwrap()
}

/// The hanging chain of the joint-solver tests: a static anchor at (x, 0, 5) m, a 1 kg box
/// 1 m below it and a 100 kg box 1 m below that (0.2 m cubes), each link a
/// [`locked_joint`] with its pivot at the lower box's centre. Returns (light, heavy, top
/// link).
pub fn hanging_chain(
    w: &mut fem2rbd::bullet::World,
    x: f64,
) -> (
    fem2rbd::bullet::BodyHandle,
    fem2rbd::bullet::BodyHandle,
    fem2rbd::bullet::ConstraintHandle,
) {
    use fem2rbd::bullet::{BoxDesc, Pose};
    let anchor = w
        .add_box(&BoxDesc::fixed([0.1; 3], Pose::at([x, 0.0, 5.0])))
        .unwrap();
    let light = w
        .add_box(&BoxDesc::dynamic([0.1; 3], 1.0, Pose::at([x, 0.0, 4.0])))
        .unwrap();
    let heavy = w
        .add_box(&BoxDesc::dynamic([0.1; 3], 100.0, Pose::at([x, 0.0, 3.0])))
        .unwrap();
    let top = locked_joint(w, anchor, light, [0.0, 0.0, -1.0], [0.0; 3]);
    locked_joint(w, light, heavy, [0.0, 0.0, -1.0], [0.0; 3]);
    (light, heavy, top)
}

/// A group with per-area strengths `s` (BCB's Formula Assistant, N/mm²), BCB's default
/// tolerances, no plastic length and threshold multiplier 1.
pub fn per_area_group(
    name: &str,
    s: fem2rbd::ruin::strength::StrengthPerArea,
) -> fem2rbd::ruin::connection::GroupStrength {
    fem2rbd::ruin::connection::GroupStrength {
        name: name.into(),
        strength: fem2rbd::ruin::strength::StrengthSource::PerArea(s),
        tolerances: fem2rbd::ruin::connection::Tolerances::default(),
        plastic_length: 0.0,
        threshold_multiplier: 1.0,
    }
}

/// RC per-area strengths with compression 35 and shear 155 N/mm², tension `t`, bending
/// `b` and plastic `p` (N/mm², or N·m per mm² for bending).
pub fn rc_per_area(t: f64, b: f64, p: Option<f64>) -> fem2rbd::ruin::strength::StrengthPerArea {
    fem2rbd::ruin::strength::StrengthPerArea {
        c: 35.0,
        t,
        s: 155.0,
        s90: None,
        b,
        b90: None,
        p,
    }
}

/// Frame3 (`data/frame3/model.toml`) under LC5 as shipped (El Centro: X ← ELC180 0.93 g,
/// Y ← ELC270 1.19 g, Z ← UP 0.57 g, time compressed by 0.5), FE step 5 ms, with the
/// `[collapse]`, extra `[fe]` and `[physics]` lines given: the scenario of the CI-sized
/// whole runs.
pub fn frame3_lc5(mode: &str, collapse: &str, extra_fe: &str, physics: &str) -> String {
    let root = env!("CARGO_MANIFEST_DIR");
    format!(
        r#"model = "{root}/data/frame3/model.toml"
mode = "{mode}"

[[ground_motion]]
file = "{root}/data/ground-motions/RSN6_IMPVALL.I_I-ELC180.AT2"
direction = "X"
pga_g = 0.93
time_scale = 0.5

[[ground_motion]]
file = "{root}/data/ground-motions/RSN6_IMPVALL.I_I-ELC270.AT2"
direction = "Y"
pga_g = 1.19
time_scale = 0.5

[[ground_motion]]
file = "{root}/data/ground-motions/RSN6_IMPVALL.I_I-ELC-UP.AT2"
direction = "Z"
pga_g = 0.57
time_scale = 0.5

[fe]
dt = 0.005
{extra_fe}

[collapse]
{collapse}

[physics]
{physics}
"#
    )
}

/// A ruin stage's result as bits: every frame's poses, the final velocities and each
/// connection's break and plastic times (0 when never), in order, for bit-for-bit
/// comparisons of two runs.
pub fn ruin_bits(r: &fem2rbd::ruin::stage::RuinResult) -> Vec<u64> {
    let mut v = Vec::new();
    for f in &r.frames {
        for p in &f.poses {
            v.extend(p.position.iter().chain(&p.orientation).map(|x| x.to_bits()));
        }
    }
    for vel in &r.final_velocities {
        v.extend(vel.linear.iter().chain(&vel.angular).map(|x| x.to_bits()));
    }
    for c in &r.connections {
        v.push(c.broke_at_s.map_or(0, f64::to_bits));
        v.push(c.plastic_at_s.map_or(0, f64::to_bits));
    }
    v
}

/// Runs `cmd`, asserts that it succeeded (its stderr in the message) and returns its
/// standard output.
pub fn stdout_of(cmd: &mut std::process::Command) -> Vec<u8> {
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// Runs an openseespy script exported by `fem2rbd export opensees` with `args` (e.g.
/// `["eigen", "6"]`), asserts that it succeeded and returns the JSON of its last line
/// that starts with `{` (the script's result).
pub fn opensees_json(script: &Path, args: &[&str]) -> serde_json::Value {
    let out = std::process::Command::new("python3")
        .arg(script)
        .args(args)
        .output()
        .expect("python3 must be installed (with openseespy 3.7.1: scripts/setup.sh)");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "python3 {} {:?} failed (is openseespy 3.7.1 installed? pip install openseespy==3.7.1.2):\n{}\n{}",
        script.display(),
        args,
        stdout,
        String::from_utf8_lossy(&out.stderr)
    );
    let last = stdout
        .lines()
        .rfind(|l| l.starts_with('{'))
        .expect("JSON line");
    serde_json::from_str(last).unwrap()
}
