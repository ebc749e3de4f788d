//! Physical plausibility of a scene: values that no rigid-body scene of debris has, and
//! bodies that start inside each other. Such a scene still runs — a restitution of 2
//! creates energy at every bounce, an ERP of 5 overshoots every correction, a box 0.9 m
//! into the ground is shot out of it — and gives numbers, not an error. So `fem2rbd
//! scene` refuses it before any work ([`unusual`] lists every finding), unless the user
//! says that it is meant (`--allow-unusual`).
//!
//! The ranges ([`RANGES`]; `docs/reliability.md` lists them):
//! * speed of a body or of a kinematic motion |v| ≤ 1 000 m/s (about three times the
//!   speed of sound; debris of a collapse falls at tens of m/s), angular speed
//!   |ω| ≤ 1 000 rad/s;
//! * restitution [0, 1] (above 1 a contact creates energy);
//! * friction, rolling and spinning friction [0, 10] (the Coulomb coefficients of
//!   building materials are under 1.5; the same bound as a scenario's `friction`);
//! * the solver's error-reduction parameters `erp`, `erp2`, `friction_erp`,
//!   `split_impulse_turn_erp` [0, 1] (the share of a constraint error corrected in one
//!   substep: above 1 overshoots), `global_cfm` [0, 1] (a negative constraint-force
//!   mixing makes the constraint matrix indefinite);
//! * |gravity| [0, 100] m/s² (Earth 9.81; a centrifuge test is not a scene);
//! * the substep h ≤ 0.1 s (a run's least rate is 10 substeps/s; at 10 m/s a body moves
//!   a metre per substep and passes through slabs).
//!
//! **Start overlaps.** Two bodies that can collide (at least one dynamic, and no
//! constraint between them disables their collisions) must not start more than
//! [`OVERLAP_TOLERANCE`] = 0.01 m inside each other. Bullet's contact solver turns a
//! penetration d into a separating velocity of about ERP·d/h in the first substeps (a box
//! 0.9 m into the ground at the default ERP 0.2 and h = 1/240 s: 43 m/s), motion that the
//! scene does not describe; within a centimetre are placements that touch up to
//! round-off. The depth is the exact penetration depth of two boxes: the least overlap of
//! their projections on the 15 separating axes of two oriented boxes (the 3 + 3 face
//! normals and the 9 cross products of their edges; Gottschalk, Lin & Manocha,
//! "OBBTree", SIGGRAPH 1996).
use super::assemble::Scene;
use crate::bullet::{BodyKind, BoxDesc};
use crate::model::plausibility::{Range, Slip, Unusual};

/// The depth \[m\] by which two bodies may start inside each other (module docs).
pub const OVERLAP_TOLERANCE: f64 = 0.01;

/// The speed of a body or a kinematic motion.
pub const SPEED: Range = Range {
    what: "speed",
    unit: "m/s",
    lo: 0.0,
    hi: 1000.0,
    slip: Slip::None,
};
/// The angular speed of a body or a kinematic motion.
pub const ANGULAR_SPEED: Range = Range {
    what: "angular speed",
    unit: "rad/s",
    lo: 0.0,
    hi: 1000.0,
    slip: Slip::None,
};
/// A restitution coefficient.
pub const RESTITUTION: Range = Range {
    what: "restitution",
    unit: "",
    lo: 0.0,
    hi: 1.0,
    slip: Slip::None,
};
/// A friction coefficient (sliding, rolling, spinning).
pub const FRICTION: Range = Range {
    what: "friction coefficient",
    unit: "",
    lo: 0.0,
    hi: 10.0,
    slip: Slip::None,
};
/// An error-reduction parameter of the solver.
pub const ERP: Range = Range {
    what: "error-reduction parameter",
    unit: "",
    lo: 0.0,
    hi: 1.0,
    slip: Slip::None,
};
/// The solver's constraint-force mixing.
pub const CFM: Range = Range {
    what: "constraint-force mixing",
    unit: "",
    lo: 0.0,
    hi: 1.0,
    slip: Slip::None,
};
/// The magnitude of gravity.
pub const GRAVITY: Range = Range {
    what: "gravity",
    unit: "m/s²",
    lo: 0.0,
    hi: 100.0,
    slip: Slip::Thousand,
};
/// The substep h.
pub const SUBSTEP: Range = Range {
    what: "substep",
    unit: "s",
    lo: 0.0,
    hi: 0.1,
    slip: Slip::None,
};

/// Every range, for the documentation's table.
pub const RANGES: [Range; 8] = [
    SPEED,
    ANGULAR_SPEED,
    RESTITUTION,
    FRICTION,
    ERP,
    CFM,
    GRAVITY,
    SUBSTEP,
];

/// One finding: a value outside its range, or two bodies that start inside each other.
#[derive(Debug, Clone, PartialEq)]
pub enum Finding {
    /// A value outside its plausible range.
    Value(Unusual),
    /// Bodies `a` and `b` (indices into [`Scene::bodies`]) start `depth` \[m\] inside
    /// each other.
    Overlap {
        /// The first body (the lower index).
        a: usize,
        /// The second body.
        b: usize,
        /// The penetration depth \[m\].
        depth: f64,
    },
}

/// |v|, scaled by the largest component so that it does not overflow: |(1e300, 0, 0)| is
/// 1e300, not infinity.
fn norm(v: [f64; 3]) -> f64 {
    let m = v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    m * v.iter().map(|x| (x / m) * (x / m)).sum::<f64>().sqrt()
}

/// Every finding of `scene` in file order (world, time, bodies, then overlaps by the
/// first body); `body(i)` names body i as messages do (`body 3 "slab" (line 20)`).
pub fn unusual(scene: &Scene, body: &dyn Fn(usize) -> String) -> Vec<Finding> {
    let mut out = Vec::new();
    let mut check = |item: &dyn Fn() -> String, value: f64, range: Range| {
        // The scene's numbers are finite (`assemble`); a value outside the range, or
        // one that is not a number, is a finding.
        if !(value >= range.lo && value <= range.hi) {
            out.push(Finding::Value(Unusual {
                item: item(),
                value,
                range,
            }));
        }
    };
    let w = &scene.world;
    check(&|| "world: |gravity|".into(), norm(w.gravity), GRAVITY);
    let s = &w.solver;
    for (key, v) in [
        ("erp", s.erp),
        ("erp2", s.erp2),
        ("friction_erp", s.friction_erp),
        ("split_impulse_turn_erp", s.split_impulse_turn_erp),
    ] {
        check(&|| format!("world.solver: {key}"), v, ERP);
    }
    check(&|| "world.solver: global_cfm".into(), s.global_cfm, CFM);
    check(&|| "substep".into(), scene.substep, SUBSTEP);
    for (i, (_, d)) in scene.bodies.iter().enumerate() {
        let it = |k: &str| format!("{}: {k}", body(i));
        check(&|| it("|linear_velocity|"), norm(d.velocity.linear), SPEED);
        check(
            &|| it("|angular_velocity|"),
            norm(d.velocity.angular),
            ANGULAR_SPEED,
        );
        check(&|| it("friction"), d.friction, FRICTION);
        check(&|| it("rolling_friction"), d.rolling_friction, FRICTION);
        check(&|| it("spinning_friction"), d.spinning_friction, FRICTION);
        check(&|| it("restitution"), d.restitution, RESTITUTION);
    }
    for m in &scene.kinematic_motions {
        let it = |k: &str| format!("{}: {k}", body(m.body));
        check(
            &|| it("|motion.linear_velocity|"),
            norm(m.velocity.linear),
            SPEED,
        );
        check(
            &|| it("|motion.angular_velocity|"),
            norm(m.velocity.angular),
            ANGULAR_SPEED,
        );
    }
    out.extend(
        overlaps(scene)
            .into_iter()
            .map(|(a, b, depth)| Finding::Overlap { a, b, depth }),
    );
    out
}

impl Finding {
    /// The message line, with bodies named by `body(i)`.
    pub fn message(&self, body: &dyn Fn(usize) -> String) -> String {
        match self {
            Finding::Value(u) => u.to_string(),
            Finding::Overlap { a, b, depth } => format!(
                "{} and {} start {} m inside each other (more than the tolerance of \
                 {OVERLAP_TOLERANCE} m: Bullet would push them apart in the first substeps)",
                body(*a),
                body(*b),
                tidy(*depth)
            ),
        }
    }
}

/// The depth with 6 significant digits (`0.9000000000000001` → `0.9`).
fn tidy(v: f64) -> f64 {
    format!("{v:.5e}").parse().unwrap_or(v)
}

/// The rotation matrix's columns (the box's axes in the world frame) of a unit
/// quaternion (w, x, y, z).
fn axes(q: [f64; 4]) -> [[f64; 3]; 3] {
    let [w, x, y, z] = q;
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y + w * z),
            2.0 * (x * z - w * y),
        ],
        [
            2.0 * (x * y - w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z + w * x),
        ],
        [
            2.0 * (x * z + w * y),
            2.0 * (y * z - w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The penetration depth \[m\] of two boxes, 0 when they are apart or only touch: the
/// least overlap of their projections over the 15 separating axes (module docs).
pub fn penetration_depth(a: &BoxDesc, b: &BoxDesc) -> f64 {
    let (ea, eb) = (axes(a.pose.orientation), axes(b.pose.orientation));
    let d = [
        b.pose.position[0] - a.pose.position[0],
        b.pose.position[1] - a.pose.position[1],
        b.pose.position[2] - a.pose.position[2],
    ];
    let radius = |e: &[[f64; 3]; 3], h: [f64; 3], l: [f64; 3]| -> f64 {
        (0..3).map(|i| h[i] * dot(e[i], l).abs()).sum()
    };
    let mut least = f64::INFINITY;
    let mut test = |l: [f64; 3]| {
        let n = norm(l);
        if n < 1e-9 {
            return; // parallel edges: covered by the face normals
        }
        let l = l.map(|c| c / n);
        let overlap =
            radius(&ea, a.half_extents, l) + radius(&eb, b.half_extents, l) - dot(d, l).abs();
        least = least.min(overlap);
    };
    for (u, v) in ea.iter().zip(&eb) {
        test(*u);
        test(*v);
    }
    for u in &ea {
        for v in &eb {
            test(cross(*u, *v));
        }
    }
    least.max(0.0)
}

/// The world-frame half extents of the box's bounding box.
fn aabb_half(d: &BoxDesc) -> [f64; 3] {
    let e = axes(d.pose.orientation);
    let mut h = [0.0; 3];
    for (k, hk) in h.iter_mut().enumerate() {
        *hk = (0..3).map(|i| d.half_extents[i] * e[i][k].abs()).sum();
    }
    h
}

/// The pairs (a < b) of bodies that can collide and start more than
/// [`OVERLAP_TOLERANCE`] inside each other, with their depth, ordered by (a, b). A sweep
/// over the bounding boxes along the axis of the widest spread of centres finds the
/// candidate pairs, so a scene of many separate bodies costs about n log n.
pub fn overlaps(scene: &Scene) -> Vec<(usize, usize, f64)> {
    let bodies = &scene.bodies;
    let excluded: std::collections::BTreeSet<(usize, usize)> = scene
        .constraints
        .iter()
        .filter(|c| c.disable_collisions_between)
        .map(|c| (c.body_a.min(c.body_b), c.body_a.max(c.body_b)))
        .collect();
    let half: Vec<[f64; 3]> = bodies.iter().map(|(_, d)| aabb_half(d)).collect();
    let spread = |k: usize| {
        let (lo, hi) = bodies
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |a, b| {
                (a.0.min(b.1.pose.position[k]), a.1.max(b.1.pose.position[k]))
            });
        hi - lo
    };
    let axis = (0..3)
        .max_by(|&i, &j| spread(i).total_cmp(&spread(j)))
        .unwrap_or(0);
    let lo = |i: usize| bodies[i].1.pose.position[axis] - half[i][axis];
    let hi = |i: usize| bodies[i].1.pose.position[axis] + half[i][axis];
    let mut order: Vec<usize> = (0..bodies.len()).collect();
    order.sort_by(|&i, &j| lo(i).total_cmp(&lo(j)).then(i.cmp(&j)));
    let mut found = Vec::new();
    for (k, &i) in order.iter().enumerate() {
        for &j in &order[k + 1..] {
            if lo(j) > hi(i) - OVERLAP_TOLERANCE {
                break;
            }
            let (a, b) = (i.min(j), i.max(j));
            let (da, db) = (&bodies[a].1, &bodies[b].1);
            if da.kind != BodyKind::Dynamic && db.kind != BodyKind::Dynamic {
                continue; // static and kinematic bodies do not collide with each other
            }
            if excluded.contains(&(a, b)) {
                continue;
            }
            let apart = (0..3).any(|c| {
                (da.pose.position[c] - db.pose.position[c]).abs()
                    >= half[a][c] + half[b][c] - OVERLAP_TOLERANCE
            });
            if apart {
                continue;
            }
            let depth = penetration_depth(da, db);
            if depth > OVERLAP_TOLERANCE {
                found.push((a, b, depth));
            }
        }
    }
    found.sort_by_key(|x| (x.0, x.1));
    found
}
