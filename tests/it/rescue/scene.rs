//! Hand-built ruins written as run folders: boxes by type, centre, half extents and a turn
//! about y, the connections between them, and the model scale.
#![allow(dead_code)]

use fem2rbd::body::{BodyId, BodyType};
use fem2rbd::bullet::Pose;
use fem2rbd::output::history::{bodies_csv, BodyRow};
use fem2rbd::output::ruins::{ruins_csv, RuinRow};
use fem2rbd::rescue::{analyse, Analysis, Ruin, Sizes};
use std::path::Path;

/// One box of a hand-built ruin.
#[derive(Debug, Clone)]
pub struct SceneBox {
    pub id: BodyId,
    pub passive: bool,
    /// Final pose.
    pub pose: Pose,
    /// Undeformed pose (the final one unless set).
    pub pose0: Pose,
    pub he: [f64; 3],
}

/// A pose at `c` turned by `deg` about +y.
pub fn turned_y(c: [f64; 3], deg: f64) -> Pose {
    let a = deg.to_radians() / 2.0;
    Pose {
        position: c,
        orientation: [a.cos(), 0.0, a.sin(), 0.0],
    }
}

fn element(t: BodyType, n: u32, c: [f64; 3], he: [f64; 3]) -> SceneBox {
    let pose = turned_y(c, 0.0);
    SceneBox {
        id: BodyId::element(t, "1", n),
        passive: false,
        pose,
        pose0: pose,
        he,
    }
}

pub fn slab(n: u32, c: [f64; 3], he: [f64; 3]) -> SceneBox {
    element(BodyType::Slab, n, c, he)
}
pub fn column(n: u32, c: [f64; 3], he: [f64; 3]) -> SceneBox {
    element(BodyType::Column, n, c, he)
}
pub fn wall(n: u32, c: [f64; 3], he: [f64; 3]) -> SceneBox {
    element(BodyType::Wall, n, c, he)
}
pub fn beam(n: u32, c: [f64; 3], he: [f64; 3]) -> SceneBox {
    element(BodyType::Beam, n, c, he)
}

/// A passive foundation block whose top is the ground at z = 0.
pub fn ground_block(node: u32, c: [f64; 2], half: f64) -> SceneBox {
    let pose = turned_y([c[0], c[1], -0.25], 0.0);
    SceneBox {
        id: BodyId::Foundation { node },
        passive: true,
        pose,
        pose0: pose,
        he: [half, half, 0.25],
    }
}

/// Writes the run folder `dir`: `bodies.csv`, `ruins.csv`, `connections.csv` (pairs of
/// box indices with their final state) and a `summary.json` holding the scale.
pub fn write_run(dir: &Path, boxes: &[SceneBox], connections: &[(usize, usize, &str)], scale: f64) {
    std::fs::create_dir_all(dir).unwrap();
    let rows: Vec<BodyRow> = boxes
        .iter()
        .map(|b| BodyRow {
            id: &b.id,
            passive: b.passive,
            pose0: b.pose0,
            half_extents: b.he,
            mass_kg: if b.passive { 0.0 } else { 100.0 },
        })
        .collect();
    std::fs::write(dir.join("bodies.csv"), bodies_csv(&rows)).unwrap();
    let ruins: Vec<RuinRow> = boxes
        .iter()
        .map(|b| RuinRow {
            id: &b.id,
            pose: b.pose,
            at_rest: Some(true),
        })
        .collect();
    std::fs::write(dir.join("ruins.csv"), ruins_csv(&ruins)).unwrap();
    let mut c = String::from(fem2rbd::rescue::input::CONNECTIONS_HEADER);
    c.push('\n');
    for (a, b, state) in connections {
        c.push_str(&format!(
            "{},{},intact,{state},,,,\n",
            boxes[*a].id.name(),
            boxes[*b].id.name()
        ));
    }
    std::fs::write(dir.join("connections.csv"), c).unwrap();
    std::fs::write(
        dir.join("summary.json"),
        format!("{{\n  \"mode\": \"rigid\",\n  \"scale\": {scale}\n}}\n"),
    )
    .unwrap();
}

/// Moves every box by `d`.
pub fn shifted(boxes: &[SceneBox], d: [f64; 3]) -> Vec<SceneBox> {
    boxes
        .iter()
        .map(|b| {
            let mut b = b.clone();
            for k in 0..3 {
                b.pose.position[k] += d[k];
                b.pose0.position[k] += d[k];
            }
            b
        })
        .collect()
}

/// Scales every length by `s`.
pub fn scaled(boxes: &[SceneBox], s: f64) -> Vec<SceneBox> {
    boxes
        .iter()
        .map(|b| {
            let mut b = b.clone();
            for k in 0..3 {
                b.pose.position[k] *= s;
                b.pose0.position[k] *= s;
                b.he[k] *= s;
            }
            b
        })
        .collect()
}

/// A table: a 3.0 × 2.0 × 0.2 m slab on four 0.3 × 0.3 × 2.0 m columns at its corners,
/// connected to it (intact). Clear space under it: 2.0 m × (6.0 − 4 · 0.09) m².
pub fn table() -> (Vec<SceneBox>, Vec<(usize, usize, &'static str)>) {
    let mut b = vec![slab(1, [0.0, 0.0, 2.1], [1.5, 1.0, 0.1])];
    let mut n = 2;
    for x in [-1.35, 1.35] {
        for y in [-0.85, 0.85] {
            b.push(column(n, [x, y, 1.0], [0.15, 0.15, 1.0]));
            n += 1;
        }
    }
    let c = (1..5).map(|k| (0, k, "intact")).collect();
    (b, c)
}

/// A slab leaning on a wall at `deg` from the horizontal: the wall x ∈ [0, 0.2],
/// y ∈ [−1.5, 1.5], 2.0 m tall; the slab (0.2 thick, 3.0 wide) with its lower face from the
/// wall's top inner edge (0.2, 2.0) down to the ground at x = 0.2 + 2.0 / tan(deg) (and on
/// below it, into a foundation block whose top is the ground). The wedge under it has
/// the cross-section of a right triangle with legs 2.0 m and 2.0 / tan(deg) m:
/// 6.0 / tan(deg) m³.
pub fn lean_to(deg: f64) -> Vec<SceneBox> {
    let th = deg.to_radians();
    let t = 0.1;
    let p1 = [0.2, 2.0];
    let p2 = [0.2 + 2.2 / th.tan(), -0.2];
    let m = [(p1[0] + p2[0]) / 2.0, (p1[1] + p2[1]) / 2.0];
    let half = ((p2[0] - p1[0]).powi(2) + (p2[1] - p1[1]).powi(2)).sqrt() / 2.0;
    let mut slab = slab(2, [0.0; 3], [half, 1.5, t]);
    // Normal (sin θ, 0, cos θ): the centre lies t above the lower face's midpoint.
    slab.pose = turned_y([m[0] + t * th.sin(), 0.0, m[1] + t * th.cos()], deg);
    slab.pose0 = turned_y([1.3, 0.0, 3.1], 0.0);
    vec![
        ground_block(1, [1.0, 0.0], 3.0),
        wall(1, [0.1, 0.0, 1.0], [0.1, 1.5, 1.0]),
        slab,
    ]
}

/// Two slabs stacked on debris spacers: a 3.0 × 2.0 × 0.2 m slab on the ground, two
/// 0.3 × 2.0 × 0.3 m beams along its x edges, a second slab on them. The gap between the
/// slabs: 2.4 × 2.0 × 0.3 m = 1.44 m³.
pub fn pancake() -> Vec<SceneBox> {
    vec![
        slab(1, [0.0, 0.0, 0.1], [1.5, 1.0, 0.1]),
        slab(2, [0.0, 0.0, 0.6], [1.5, 1.0, 0.1]),
        beam(3, [-1.35, 0.0, 0.35], [0.15, 1.0, 0.15]),
        beam(4, [1.35, 0.0, 0.35], [0.15, 1.0, 0.15]),
    ]
}

/// A closed box: four 0.2 m walls 1.2 m tall round a 1.6 × 1.6 m room, a 0.2 m roof slab.
/// The room: 1.6 × 1.6 × 1.2 = 3.072 m³.
pub fn closed_box() -> Vec<SceneBox> {
    vec![
        wall(1, [-0.9, 0.0, 0.6], [0.1, 1.0, 0.6]),
        wall(2, [0.9, 0.0, 0.6], [0.1, 1.0, 0.6]),
        wall(3, [0.0, -0.9, 0.6], [0.8, 0.1, 0.6]),
        wall(4, [0.0, 0.9, 0.6], [0.8, 0.1, 0.6]),
        slab(5, [0.0, 0.0, 1.3], [1.0, 1.0, 0.1]),
    ]
}

/// A cantilever: a 2.0 m wall x ∈ [0, 0.2] and a flat slab x ∈ [0.2, 2.2] at 2.0–2.2 m
/// still connected (intact) to it, free end in the air.
pub fn cantilever() -> (Vec<SceneBox>, Vec<(usize, usize, &'static str)>) {
    (
        vec![
            wall(1, [0.1, 0.0, 1.0], [0.1, 1.5, 1.0]),
            slab(2, [1.2, 0.0, 2.1], [1.0, 1.5, 0.1]),
        ],
        vec![(0, 1, "intact")],
    )
}

/// A V: two halves of one slab (undeformed side by side at 3 m) down at a crease at
/// x = 0, z = 0.2, their outer ends on walls 1.2 m tall at x = ±2.
pub fn v_shape() -> Vec<SceneBox> {
    let phi = 0.5f64.atan().to_degrees();
    let (sp, cp) = (phi.to_radians().sin(), phi.to_radians().cos());
    let half = 1.25f64.sqrt();
    let t = 0.1;
    let mut a = slab(1, [0.0; 3], [half, 1.5, t]);
    a.pose = turned_y([-1.0 + t * sp, 0.0, 0.7 + t * cp], phi);
    a.pose0 = turned_y([-1.0, 0.0, 3.0], 0.0);
    let mut b = slab(2, [0.0; 3], [half, 1.5, t]);
    b.pose = turned_y([1.0 - t * sp, 0.0, 0.7 + t * cp], -phi);
    b.pose0 = turned_y([1.0, 0.0, 3.0], 0.0);
    vec![
        wall(3, [-2.1, 0.0, 0.6], [0.1, 1.5, 0.6]),
        wall(4, [2.1, 0.0, 0.6], [0.1, 1.5, 0.6]),
        a,
        b,
    ]
}

/// Two tables side by side: slabs x ∈ [−3, 0] and [0, 3] (y ∈ [−1, 1], 2.0–2.2 m), each on
/// two 0.3 m columns at its outer corners, meeting over a 0.2 m wall x ∈ [−0.1, 0.1],
/// 1.6 m tall. Under each slab: 3.0 × 2.0 × 2.0 − 2 × 0.09 × 2.0 − 0.1 × 2.0 × 1.6
/// = 11.32 m³; the two spaces meet through the 0.4 m gap over the wall.
pub fn two_tables() -> Vec<SceneBox> {
    let mut b = vec![
        slab(1, [-1.5, 0.0, 2.1], [1.5, 1.0, 0.1]),
        slab(2, [1.5, 0.0, 2.1], [1.5, 1.0, 0.1]),
        wall(3, [0.0, 0.0, 0.8], [0.1, 1.0, 0.8]),
    ];
    let mut n = 4;
    for x in [-2.85, 2.85] {
        for y in [-0.85, 0.85] {
            b.push(column(n, [x, y, 1.0], [0.15, 0.15, 1.0]));
            n += 1;
        }
    }
    b
}

/// A lean-to beside a pancake: a flat slab x ∈ [−3, 0.2], y ∈ [−1.5, 1.5] at 1.8–2.0 m on
/// two 0.3 m walls along x (y ∈ ±[1.2, 1.5]), and the lean-to's slab at `deg` resting on
/// its edge ([`lean_to`] without its wall: the lower face from (0.2, 2.0) down to the
/// ground). Under the flat slab between the walls: 3.2 × 2.4 × 1.8 = 13.824 m³, open at
/// x = 0.2 into the wedge under the leaning slab (6.0 / tan(deg) m³).
pub fn lean_to_beside_pancake(deg: f64) -> Vec<SceneBox> {
    let mut b = lean_to(deg);
    b.remove(1);
    b.push(slab(5, [-1.4, 0.0, 1.9], [1.6, 1.5, 0.1]));
    b.push(wall(6, [-1.4, -1.35, 0.9], [1.6, 0.15, 0.9]));
    b.push(wall(7, [-1.4, 1.35, 0.9], [1.6, 0.15, 0.9]));
    b
}

/// Two stories of the table (3.0 × 2.0 × 0.2 m slabs on four 0.3 m columns 2.0 m tall),
/// undeformed slabs at 2.0–2.2 and 4.2–4.4 m, whose first story pancaked: its columns lie
/// on the ground beside the building (x 3.0–5.0), its ceiling on the ground, the second
/// story standing on it unchanged. Free volume under each ceiling standing:
/// 2.0 × (6.0 − 4 · 0.09) = 11.28 m³; in the ruin 0 and 11.28 m³.
pub fn two_stories_first_pancaked() -> Vec<SceneBox> {
    let mut b = Vec::new();
    let mut first = slab(1, [0.0, 0.0, 0.1], [1.5, 1.0, 0.1]);
    first.pose0 = turned_y([0.0, 0.0, 2.1], 0.0);
    b.push(first);
    let mut second = slab(2, [0.0, 0.0, 2.3], [1.5, 1.0, 0.1]);
    second.pose0 = turned_y([0.0, 0.0, 4.3], 0.0);
    b.push(second);
    let mut n = 3;
    for (k, x) in [-1.35, 1.35].into_iter().enumerate() {
        for (l, y) in [-0.85, 0.85].into_iter().enumerate() {
            let mut lower = column(n, [0.0; 3], [0.15, 0.15, 1.0]);
            lower.pose0 = turned_y([x, y, 1.0], 0.0);
            // Lying along x on the ground, side by side at y = −0.6, −0.2, 0.2, 0.6.
            lower.pose = turned_y([4.0, -0.6 + 0.4 * (2 * k + l) as f64, 0.15], 90.0);
            b.push(lower);
            let mut upper = column(n + 4, [x, y, 1.2], [0.15, 0.15, 1.0]);
            upper.pose0 = turned_y([x, y, 3.2], 0.0);
            b.push(upper);
            n += 1;
        }
    }
    b
}

/// Writes `boxes` as a run folder and analyses it with cell `cell` (full scale).
pub fn analysed(
    boxes: &[SceneBox],
    connections: &[(usize, usize, &str)],
    scale: f64,
    cell: f64,
) -> Analysis {
    let dir = tempfile::tempdir().unwrap();
    write_run(dir.path(), boxes, connections, scale);
    let ruin = Ruin::load(dir.path()).unwrap();
    analyse(
        &ruin,
        Sizes {
            cell_m: cell,
            ..Sizes::default()
        },
    )
    .unwrap()
}

pub fn close(a: f64, b: f64, tol: f64, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a} vs {b} (tolerance {tol})");
}

/// A room at the end of a corridor: a 1.6 × 1.6 × 1.6 m room (x, y ∈ [−0.8, 0.8]) walled by
/// 0.2 m walls 1.6 m tall and roofed by a 0.2 m slab over x, y ∈ [−1, 1]; its −x wall has a
/// door 0.8 m wide (y ∈ [−0.4, 0.4]) the room's height, into a corridor x ∈ [−3, −1]
/// between 0.2 m walls at y ∈ ±[0.4, 0.6] under its own 0.2 m roof slab. The only way in
/// is along the corridor, from x = −3.
pub fn room_down_a_corridor() -> Vec<SceneBox> {
    vec![
        slab(1, [0.0, 0.0, 1.7], [1.0, 1.0, 0.1]),
        slab(2, [-2.0, 0.0, 1.7], [1.0, 0.6, 0.1]),
        wall(3, [-0.9, -0.7, 0.8], [0.1, 0.3, 0.8]),
        wall(4, [-0.9, 0.7, 0.8], [0.1, 0.3, 0.8]),
        wall(5, [0.9, 0.0, 0.8], [0.1, 1.0, 0.8]),
        wall(6, [0.0, -0.9, 0.8], [0.8, 0.1, 0.8]),
        wall(7, [0.0, 0.9, 0.8], [0.8, 0.1, 0.8]),
        wall(8, [-2.0, -0.5, 0.8], [1.0, 0.1, 0.8]),
        wall(9, [-2.0, 0.5, 0.8], [1.0, 0.1, 0.8]),
    ]
}
