//! `history.csv` and `bodies.csv`: what a run folder needs besides `keyframes.csv` to be
//! plotted or re-exported without the model (`fem2rbd plot`, `fem2rbd export gltf`).
//!
//! `history.csv`, one row per timeline frame (25 frames/s, the times of `keyframes.csv`):
//! `t,stage,roof_drift,max_drop_m,intact,plastic,broken,ground_x,ground_y,ground_z`
//!
//! * `stage` — `fe` (FE keyframe, up to Tc) or `ruin` (ruin-stage frame);
//! * `roof_drift` — horizontal displacement of the roof, relative to the ground, over the
//!   roof height: |Δxy(roof centroid) − g_xy(t)| / H. The **roof** is the bodies whose
//!   undeformed centre lies within 5 % of H below the highest centre (frame3: the roof
//!   slab panels and roof beams), their centroid mass-weighted; H is the height of that
//!   undeformed centroid above the base (the top of the passive foundations, else the
//!   lowest body bottom). Dimensionless (0.04 = 4 %);
//! * `max_drop_m` — the largest downward displacement of a body centre relative to the
//!   ground: max_i (z0_i − (z_i(t) − g_z(t))), m; passive bodies are left out. It is the
//!   rigid-body counterpart of the paper's Criterion 4 (node drop), so it is close to but
//!   not equal to the FE criterion, which follows nodes;
//! * `intact,plastic,broken` — connection counts after the frame's monitor check (empty
//!   in FE frames: the connections exist only in the ruin stage);
//! * `ground_x,ground_y,ground_z` — the ground displacement at t, m;
//! * `kinetic_j,rotational_j,potential_j,ground_work_j,damping_j,dissipated_j` — the ruin
//!   stage's energy ledger ([`crate::ruin::energy`]), J: translational and rotational
//!   kinetic energy, potential energy relative to the ground's top at rest, work done by
//!   the moving ground since the stage's start, energy taken out by Bullet's velocity
//!   damping since the start, dissipated = E(start) + W_ground − E (damping
//!   included), and injected: the energy the solver added since the start (the sum over
//!   substeps of the positive part of ΔE − ΔW_ground + Δdamping). Empty in FE frames.
//!
//! `bodies.csv`, one row per body in body order (the order of `ruins.csv` and of each
//! frame in `keyframes.csv`):
//! `name,group,type,material,element,passive,cx,cy,cz,qw,qx,qy,qz,hx,hy,hz,mass_kg` — the
//! undeformed pose (centre m, unit quaternion of the box axes), the half extents along
//! the box axes (m), mass (kg, 0 for passive foundations).
//!
//! Numbers use fixed decimals (times 4, lengths 6, ratios 8, quaternions 8), so the same
//! run gives the same bytes.
use crate::body::BodyId;
use crate::bullet::Pose;
use crate::output::csv_text::field;
use std::fmt::Write as _;

/// `history.csv` header.
pub(crate) const HISTORY_HEADER: &str = "t,stage,roof_drift,max_drop_m,intact,plastic,broken,ground_x,ground_y,ground_z,kinetic_j,rotational_j,potential_j,ground_work_j,damping_j,dissipated_j,injected_j";

/// The energy columns of a `history.csv` row (module docs), J.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EnergyRow {
    /// Translational kinetic energy.
    pub kinetic_j: f64,
    /// Rotational kinetic energy.
    pub rotational_j: f64,
    /// Potential energy relative to the ground's top at rest.
    pub potential_j: f64,
    /// Work done by the moving ground since the ruin stage's start.
    pub ground_work_j: f64,
    /// Taken out by Bullet's velocity damping since the start.
    pub damping_j: f64,
    /// E(start) + W_ground − E.
    pub dissipated_j: f64,
    /// Added by the solver since the start.
    pub injected_j: f64,
}

/// `bodies.csv` header.
pub(crate) const BODIES_HEADER: &str =
    "name,group,type,material,element,passive,cx,cy,cz,qw,qx,qy,qz,hx,hy,hz,mass_kg";

/// The identity, undeformed geometry and mass of one body, as `bodies.csv` holds it.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyRow<'a> {
    /// Identity (columns `name,group,type,material,element`).
    pub id: &'a BodyId,
    /// Passive (kinematic foundation).
    pub passive: bool,
    /// Undeformed pose.
    pub pose0: Pose,
    /// Half extents along the box axes, m.
    pub half_extents: [f64; 3],
    /// Mass, kg.
    pub mass_kg: f64,
}

impl<'a> From<&'a crate::body::Body> for BodyRow<'a> {
    /// The row of a mapped body.
    fn from(b: &'a crate::body::Body) -> Self {
        BodyRow {
            id: &b.id,
            passive: b.passive,
            pose0: b.pose0,
            half_extents: b.half_extents,
            mass_kg: b.mass_kg,
        }
    }
}

/// The `bodies.csv` text.
pub fn bodies_csv(rows: &[BodyRow]) -> String {
    let mut s = String::from(BODIES_HEADER);
    s.push('\n');
    for r in rows {
        let (p, q, h) = (r.pose0.position, r.pose0.orientation, r.half_extents);
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{:.6},{:.6},{:.6},{:.8},{:.8},{:.8},{:.8},{:.6},{:.6},{:.6},{:.6}",
            field(&r.id.name()),
            field(r.id.group()),
            field(r.id.body_type().as_str()),
            field(r.id.material()),
            field(&r.id.element_field()),
            u8::from(r.passive),
            p[0] + 0.0,
            p[1] + 0.0,
            p[2] + 0.0,
            q[0] + 0.0,
            q[1] + 0.0,
            q[2] + 0.0,
            q[3] + 0.0,
            h[0],
            h[1],
            h[2],
            r.mass_kg
        );
    }
    s
}

/// The connection counts of a ruin-stage frame: (intact, plastic, broken).
pub(crate) type Counts = (usize, usize, usize);

/// One timeline frame as `history.csv` needs it.
#[derive(Debug, Clone)]
pub struct HistoryFrame<'a> {
    /// Time, s.
    pub t_s: f64,
    /// `true` for an FE keyframe, `false` for a ruin-stage frame.
    pub fe: bool,
    /// Every body's pose, body order.
    pub poses: &'a [Pose],
    /// Connection counts (ruin-stage frames).
    pub counts: Option<Counts>,
    /// Ground displacement, m.
    pub ground_m: [f64; 3],
    /// The energy ledger (ruin-stage frames).
    pub energy: Option<EnergyRow>,
}

/// The roof (module docs), or `None` when there are no active bodies.
#[derive(Debug, Clone, PartialEq)]
pub struct Roof {
    /// Body indices.
    pub ids: Vec<usize>,
    /// Their centroid weights (mass shares; equal shares if all masses are 0), sum 1.
    pub weights: Vec<f64>,
    /// Undeformed weighted centroid, m.
    pub centroid0_m: [f64; 3],
    /// Height of that centroid above the base, m.
    pub height_m: f64,
}

/// The roof of a set of bodies (module docs).
pub fn roof(rows: &[BodyRow]) -> Option<Roof> {
    let active: Vec<usize> = (0..rows.len()).filter(|&i| !rows[i].passive).collect();
    if active.is_empty() {
        return None;
    }
    let top = active
        .iter()
        .map(|&i| rows[i].pose0.position[2])
        .fold(f64::NEG_INFINITY, f64::max);
    let bottom = active
        .iter()
        .map(|&i| {
            rows[i].pose0.position[2] - rows[i].half_extents.iter().fold(0.0_f64, |a, b| a.max(*b))
        })
        .fold(f64::INFINITY, f64::min);
    let base = rows
        .iter()
        .filter(|r| r.passive)
        .map(|r| r.pose0.position[2] + r.half_extents[2])
        .fold(f64::NEG_INFINITY, f64::max);
    let base = if base.is_finite() { base } else { bottom };
    let tol = 0.05 * (top - base).max(0.0);
    let ids: Vec<usize> = active
        .iter()
        .copied()
        .filter(|&i| rows[i].pose0.position[2] >= top - tol - 1e-12)
        .collect();
    let wsum: f64 = ids.iter().map(|&i| rows[i].mass_kg.max(0.0)).sum();
    let weights: Vec<f64> = ids
        .iter()
        .map(|&i| {
            if wsum > 0.0 {
                rows[i].mass_kg.max(0.0) / wsum
            } else {
                1.0 / ids.len() as f64
            }
        })
        .collect();
    let mut c = [0.0; 3];
    for (&i, w) in ids.iter().zip(&weights) {
        for (d, cd) in c.iter_mut().enumerate() {
            *cd += w * rows[i].pose0.position[d];
        }
    }
    Some(Roof {
        ids,
        weights,
        centroid0_m: c,
        height_m: c[2] - base,
    })
}

/// The `history.csv` text.
pub fn history_csv(rows: &[BodyRow], frames: &[HistoryFrame]) -> String {
    let mut s = String::from(HISTORY_HEADER);
    s.push('\n');
    let roof = roof(rows);
    for f in frames {
        let g = f.ground_m;
        let drift = match &roof {
            Some(r) if r.height_m > 0.0 => {
                let mut c = [0.0; 2];
                for (&i, w) in r.ids.iter().zip(&r.weights) {
                    c[0] += w * f.poses[i].position[0];
                    c[1] += w * f.poses[i].position[1];
                }
                let dx = c[0] - r.centroid0_m[0] - g[0];
                let dy = c[1] - r.centroid0_m[1] - g[1];
                format!("{:.8}", (dx * dx + dy * dy).sqrt() / r.height_m)
            }
            _ => String::new(),
        };
        let drop = rows
            .iter()
            .zip(f.poses)
            .filter(|(r, _)| !r.passive)
            .map(|(r, p)| r.pose0.position[2] - (p.position[2] - g[2]))
            .fold(f64::NEG_INFINITY, f64::max);
        let drop = if drop.is_finite() {
            format!("{:.6}", drop + 0.0)
        } else {
            String::new()
        };
        let counts = f
            .counts
            .map_or(",,".to_string(), |(a, b, c)| format!("{a},{b},{c}"));
        let energy = f.energy.map_or(",,,,,,".to_string(), |e| {
            format!(
                "{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6}",
                e.kinetic_j + 0.0,
                e.rotational_j + 0.0,
                e.potential_j + 0.0,
                e.ground_work_j + 0.0,
                e.damping_j + 0.0,
                e.dissipated_j + 0.0,
                e.injected_j + 0.0
            )
        });
        let _ = writeln!(
            s,
            "{:.4},{},{drift},{drop},{counts},{:.6},{:.6},{:.6},{energy}",
            f.t_s + 0.0,
            if f.fe { "fe" } else { "ruin" },
            g[0] + 0.0,
            g[1] + 0.0,
            g[2] + 0.0
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A body row of element `tag` (type `T`, group `g`).
    fn row(tag: u32, z: f64, passive: bool, mass: f64) -> BodyRow<'static> {
        BodyRow {
            id: Box::leak(Box::new(BodyId::element("T".into(), "g", tag))),
            passive,
            pose0: Pose {
                position: [0.0, 0.0, z],
                orientation: [1.0, 0.0, 0.0, 0.0],
            },
            half_extents: [0.5, 0.5, 0.05],
            mass_kg: mass,
        }
    }

    fn at(p: [f64; 3]) -> Pose {
        Pose {
            position: p,
            orientation: [1.0, 0.0, 0.0, 0.0],
        }
    }

    /// A 3 m "building": foundation top at 0, a middle body at 1.5 m and two roof bodies
    /// (3.0 m, mass 1 and 3). Roof moved by (0.3, 0.4) with the ground at (0.1, 0.1):
    /// relative (0.2, 0.3) → drift √0.13 / H with H = 2.9625 m (the mass-weighted roof
    /// centre); the middle body at 1.26 m with the ground 0.01 m up → max drop 0.25 m.
    #[test]
    fn drift_and_drop_by_hand() {
        let mut f = row(1, -0.05, true, 0.0);
        f.half_extents = [1.0, 1.0, 0.05];
        let rows = vec![
            f,
            row(2, 1.5, false, 5.0),
            row(3, 3.0, false, 1.0),
            row(4, 2.95, false, 3.0),
        ];
        let r = roof(&rows).unwrap();
        assert_eq!(r.ids, vec![2, 3]);
        assert_eq!(r.weights, vec![0.25, 0.75]);
        assert!((r.centroid0_m[2] - 2.9625).abs() < 1e-12);
        assert!((r.height_m - 2.9625).abs() < 1e-12);
        let g = [0.1, 0.1, 0.01];
        let poses = vec![
            at([0.1, 0.1, -0.04]),
            at([0.0, 0.0, 1.5 - 0.25 + 0.01]),
            at([0.3, 0.4, 3.01]),
            at([0.3, 0.4, 2.96]),
        ];
        let s = history_csv(
            &rows,
            &[HistoryFrame {
                t_s: 1.0,
                fe: false,
                poses: &poses,
                counts: Some((3, 2, 1)),
                ground_m: g,
                energy: Some(EnergyRow {
                    kinetic_j: 1.5,
                    rotational_j: 0.25,
                    potential_j: 100.0,
                    ground_work_j: -2.0,
                    damping_j: 0.125,
                    dissipated_j: 7.0,
                    injected_j: 0.5,
                }),
            }],
        );
        let line = s.lines().nth(1).unwrap();
        let want = format!(
            "1.0000,ruin,{:.8},0.250000,3,2,1,0.100000,0.100000,0.010000,1.500000,0.250000,100.000000,-2.000000,0.125000,7.000000,0.500000",
            0.13f64.sqrt() / 2.9625
        );
        assert_eq!(line, want);
    }

    #[test]
    fn fe_frames_have_no_counts() {
        let rows = vec![row(1, 1.0, false, 1.0)];
        let poses = vec![at([0.0, 0.0, 1.0])];
        let s = history_csv(
            &rows,
            &[HistoryFrame {
                t_s: 0.0,
                fe: true,
                poses: &poses,
                counts: None,
                ground_m: [0.0; 3],
                energy: None,
            }],
        );
        assert_eq!(
            s.lines().nth(1).unwrap(),
            "0.0000,fe,0.00000000,0.000000,,,,0.000000,0.000000,0.000000,,,,,,,"
        );
    }

    #[test]
    fn bodies_table_round_numbers() {
        let rows = vec![row(2, 1.0, false, 12.5)];
        let s = bodies_csv(&rows);
        assert_eq!(
            s.lines().nth(1).unwrap(),
            "T:g:2,g,T,g,2,0,0.000000,0.000000,1.000000,1.00000000,0.00000000,0.00000000,0.00000000,0.500000,0.500000,0.050000,12.500000"
        );
    }
}
