//! The collapse pattern of a void, read from the bodies that form its roof (the rescue
//! courses' patterns, docs/rescue.md §1).
//!
//! * **Slabs**: slab panels (`Slab:…` bodies) are pieces of one slab when their
//!   undeformed centres are at the same level (to the millimetre) and their undeformed
//!   plan rectangles touch or overlap (a floor's panels, joined transitively).
//! * **Roof pieces**: the slab panels capping at least [`ROOF_SHARE`] of the void's roof
//!   cells. When slab panels cap less than half of the roof cells, the roof is beams,
//!   columns or loose debris and the pattern is `debris`.
//! * **Tilt** of a panel: the angle between its thinnest axis and the vertical. A panel
//!   tilted less than [`FLAT_DEG`] is flat: over a 3 m bay 10° lifts one edge by 0.5 m,
//!   the depth of a sitting person's head room lost; below it a slab reads as lying flat.
//!   Its **downhill** direction is the plan direction of its upward normal.
//!
//! The rules, in this order:
//!
//! 1. **V** / **A-frame**: the largest roof piece is tilted and meets (within
//!    [`HOLD_CELLS`] cells) another tilted piece of the same slab, and their downhill
//!    directions, along the line joining their centres, point at each other (the crease
//!    is low: V) or away from each other (the crease is high, over a support: A-frame).
//!    The void may lie under one half only (a V leaves a void on each side).
//! 2. **Lean-to**: the largest roof piece is tilted. Its raised edge is the mean of the
//!    two highest corners of its underside. What holds it, looked for within [`HOLD_CELLS`] cells of the
//!    raised edge: a standing member (a column whose long axis, or a wall whose plane, is
//!    within [`STANDING_DEG`] of vertical) makes a **supported lean-to**; else a connection of the
//!    piece that still holds (intact or plastic in `connections.csv`) makes an
//!    **unsupported lean-to** (held only by its own connection); else other debris under
//!    the edge makes a supported lean-to held by debris; with nothing found it is an
//!    unsupported lean-to held by nothing found.
//! 3. **Cantilever**: the largest roof piece is flat, its holding connections all reach
//!    bodies on one side of it (within 90° of their mean direction from its centre), and
//!    under the opposite edge the free run below the panel is at least two cells: a slab
//!    still attached on one side, free end in the air.
//! 4. **Pancake**: a flat slab roof over the void otherwise (floors down on each other
//!    and held apart by something).
use super::input::{Ruin, RuinBox};
use super::voids::{Field, Void};
use crate::body::BodyType;
use nalgebra::Vector3;
use std::collections::BTreeMap;

/// Share of the void's roof cells a slab panel must cap to count as a roof piece.
pub const ROOF_SHARE: f64 = 0.1;
/// Tilt below which a panel is flat, degrees.
pub const FLAT_DEG: f64 = 10.0;
/// Tilt of a member's long axis from vertical below which it stands, degrees.
pub const STANDING_DEG: f64 = 20.0;
/// Distance (cells) from the raised edge within which a body holds it.
pub const HOLD_CELLS: f64 = 2.0;

/// A collapse pattern.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pattern {
    /// Flat slab roof.
    Pancake,
    /// Tilted slab held by a standing member or debris.
    SupportedLeanTo,
    /// Tilted slab held only by its connection (or nothing found).
    UnsupportedLeanTo,
    /// Two pieces of a slab down at a low crease.
    V,
    /// Two pieces of a slab over a high crease.
    AFrame,
    /// Flat slab attached on one side, free end in the air.
    Cantilever,
    /// The roof is not mostly slab.
    Debris,
}

impl Pattern {
    /// The name in the outputs.
    pub fn name(self) -> &'static str {
        match self {
            Pattern::Pancake => "pancake",
            Pattern::SupportedLeanTo => "supported-lean-to",
            Pattern::UnsupportedLeanTo => "unsupported-lean-to",
            Pattern::V => "v",
            Pattern::AFrame => "a-frame",
            Pattern::Cantilever => "cantilever",
            Pattern::Debris => "debris",
        }
    }
}

/// A void's pattern with what holds its roof.
#[derive(Debug, Clone, PartialEq)]
pub struct Classified {
    /// The pattern.
    pub pattern: Pattern,
    /// Tilt of the largest roof piece, degrees (`None` without a slab roof).
    pub roof_tilt_deg: Option<f64>,
    /// What holds the raised edge or the attached side (`standing Column:…`,
    /// `connection Beam:…`, `debris …`, or empty).
    pub held_by: String,
}

/// The slab each slab panel belongs to (module docs): panel index → slab number (the
/// smallest panel index of the slab).
pub fn slabs(ruin: &Ruin) -> BTreeMap<usize, usize> {
    let panels: Vec<usize> = (0..ruin.boxes.len())
        .filter(|&i| ruin.boxes[i].is_slab() && !ruin.boxes[i].passive)
        .collect();
    let mut parent: BTreeMap<usize, usize> = panels.iter().map(|&i| (i, i)).collect();
    fn root(p: &mut BTreeMap<usize, usize>, i: usize) -> usize {
        let mut r = i;
        while p[&r] != r {
            r = p[&r];
        }
        p.insert(i, r);
        r
    }
    let rect = |b: &RuinBox| {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for c in b.corners_at(&b.pose0) {
            for d in 0..2 {
                lo[d] = lo[d].min(c[d]);
                hi[d] = hi[d].max(c[d]);
            }
        }
        (lo, hi)
    };
    for (n, &a) in panels.iter().enumerate() {
        for &b in &panels[n + 1..] {
            let (ba, bb) = (&ruin.boxes[a], &ruin.boxes[b]);
            if (ba.pose0.position[2] * 1000.0).round() != (bb.pose0.position[2] * 1000.0).round() {
                continue;
            }
            let (la, ha) = rect(ba);
            let (lb, hb) = rect(bb);
            let tol = 1e-3;
            if (0..2).all(|d| la[d] <= hb[d] + tol && lb[d] <= ha[d] + tol) {
                let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                if ra != rb {
                    parent.insert(ra.max(rb), ra.min(rb));
                }
            }
        }
    }
    panels.iter().map(|&i| (i, root(&mut parent, i))).collect()
}

/// The thinnest axis of a box at its final pose, pointing up, and its tilt (degrees).
fn normal_and_tilt(b: &RuinBox) -> (Vector3<f64>, f64) {
    let r = RuinBox::axes(&b.pose);
    let k = (0..3)
        .min_by(|&x, &y| b.half_extents[x].total_cmp(&b.half_extents[y]))
        .expect("3 axes");
    let mut n: Vector3<f64> = r.column(k).into();
    if n.z < 0.0 {
        n = -n;
    }
    (n, n.z.clamp(-1.0, 1.0).acos().to_degrees())
}

/// Whether box `b` stands: a column whose long axis, or a wall whose plane (its thinnest
/// axis horizontal), is within [`STANDING_DEG`] of vertical.
fn standing(b: &RuinBox) -> bool {
    if b.passive {
        return false;
    }
    let r = RuinBox::axes(&b.pose);
    let pick = |longest: bool| {
        (0..3)
            .max_by(|&x, &y| {
                let o = b.half_extents[x].total_cmp(&b.half_extents[y]);
                if longest {
                    o
                } else {
                    o.reverse()
                }
            })
            .expect("3 axes")
    };
    let limit = STANDING_DEG.to_radians();
    match b.id.body_type() {
        BodyType::Column => r[(2, pick(true))].abs() >= limit.cos(),
        BodyType::Wall => r[(2, pick(false))].abs() <= limit.sin(),
        _ => false,
    }
}

/// The pattern of `void` (module docs); `slab_of` from [`slabs`].
pub fn classify(
    ruin: &Ruin,
    field: &Field,
    void: &Void,
    slab_of: &BTreeMap<usize, usize>,
) -> Classified {
    let roof_cells: usize = void.roof.iter().map(|r| r.1).sum();
    let pieces: Vec<(usize, usize)> = void
        .roof
        .iter()
        .copied()
        .filter(|(b, n)| slab_of.contains_key(b) && *n as f64 >= ROOF_SHARE * roof_cells as f64)
        .collect();
    let slab_cells: usize = void
        .roof
        .iter()
        .filter(|(b, _)| slab_of.contains_key(b))
        .map(|r| r.1)
        .sum();
    if pieces.is_empty() || 2 * slab_cells < roof_cells {
        return Classified {
            pattern: Pattern::Debris,
            roof_tilt_deg: None,
            held_by: String::new(),
        };
    }
    let name = |i: usize| ruin.boxes[i].id.name();
    let (main, _) = pieces[0];
    let (n_main, tilt_main) = normal_and_tilt(&ruin.boxes[main]);
    let out = |pattern, held_by: String| Classified {
        pattern,
        roof_tilt_deg: Some(tilt_main),
        held_by,
    };
    let reach = HOLD_CELLS * field.grid.h;
    // 1. The main piece and another tilted piece of the same slab meeting it.
    if tilt_main >= FLAT_DEG {
        let pm = &ruin.boxes[main];
        let corners = pm.corners_at(&pm.pose);
        for (o, _) in slab_of
            .iter()
            .filter(|(o, s)| **o != main && **s == slab_of[&main])
        {
            let other = &ruin.boxes[*o];
            let (no, to) = normal_and_tilt(other);
            if to < FLAT_DEG || !corners.iter().any(|c| other.distance_to(*c) <= reach) {
                continue;
            }
            let (pa, pb) = (pm.pose.position, other.pose.position);
            let u = Vector3::new(pb[0] - pa[0], pb[1] - pa[1], 0.0);
            if u.norm() == 0.0 {
                continue;
            }
            let u = u.normalize();
            let (da, db) = (n_main.x * u.x + n_main.y * u.y, -(no.x * u.x + no.y * u.y));
            let pair = format!("{} + {}", name(main), name(*o));
            if da > 0.0 && db > 0.0 {
                return out(Pattern::V, pair);
            }
            if da < 0.0 && db < 0.0 {
                return out(Pattern::AFrame, pair);
            }
        }
    }
    let holding: Vec<usize> = ruin
        .connections
        .iter()
        .filter(|c| c.holds && (c.a == main || c.b == main))
        .map(|c| if c.a == main { c.b } else { c.a })
        .collect();
    let pm = &ruin.boxes[main];
    // 2. Lean-to.
    if tilt_main >= FLAT_DEG {
        // The underside's two highest corners: where the raised edge rests.
        let c = Vector3::from(pm.pose.position);
        let mut under: Vec<[f64; 3]> = pm
            .corners_at(&pm.pose)
            .into_iter()
            .filter(|p| (Vector3::from(*p) - c).dot(&n_main) < 0.0)
            .collect();
        under.sort_by(|p, q| q[2].total_cmp(&p[2]));
        let edge = [0, 1, 2].map(|d| under[..2].iter().map(|c| c[d]).sum::<f64>() / 2.0);
        let near = |i: usize| {
            i != main && !ruin.boxes[i].passive && ruin.boxes[i].distance_to(edge) <= reach
        };
        if let Some(s) = (0..ruin.boxes.len()).find(|&i| near(i) && standing(&ruin.boxes[i])) {
            return out(Pattern::SupportedLeanTo, format!("standing {}", name(s)));
        }
        if let Some(&c) = holding.first() {
            return out(
                Pattern::UnsupportedLeanTo,
                format!("connection {}", name(c)),
            );
        }
        if let Some(d) = (0..ruin.boxes.len()).find(|&i| near(i)) {
            return out(Pattern::SupportedLeanTo, format!("debris {}", name(d)));
        }
        return out(Pattern::UnsupportedLeanTo, "nothing found".into());
    }
    // 3. Cantilever.
    if !holding.is_empty() {
        let c = Vector3::from(pm.pose.position);
        let dirs: Vec<Vector3<f64>> = holding
            .iter()
            .map(|&i| {
                let p = Vector3::from(ruin.boxes[i].pose.position) - c;
                Vector3::new(p.x, p.y, 0.0)
            })
            .filter(|p| p.norm() > 0.0)
            .map(|p| p.normalize())
            .collect();
        let mean: Vector3<f64> = dirs.iter().sum();
        if !dirs.is_empty() && mean.norm() > 0.0 && dirs.iter().all(|d| d.dot(&mean) > 0.0) {
            let m = mean.normalize();
            // The far edge: from the centre against m, 90 % of the panel's reach that way.
            let r = RuinBox::axes(&pm.pose);
            let reach_m: f64 = (0..3)
                .map(|k| pm.half_extents[k] * r.column(k).dot(&m).abs())
                .sum();
            let far = c - m * (0.9 * reach_m);
            if free_run_below(field, main, [far.x, far.y, far.z]) >= 2 {
                let who = holding
                    .iter()
                    .map(|&i| name(i))
                    .collect::<Vec<_>>()
                    .join(" ");
                return out(Pattern::Cantilever, format!("connection {who}"));
            }
        }
    }
    out(Pattern::Pancake, String::new())
}

/// Free cells right under box `b` (index) in the grid column of point `p`: from under
/// the lowest of the box's solid cells at the top of that column down to the first solid
/// cell or the ground (0 when the column holds no cell of the box).
fn free_run_below(field: &Field, b: usize, p: [f64; 3]) -> usize {
    let g = &field.grid;
    let i = ((p[0] - g.origin[0]) / g.h).floor();
    let j = ((p[1] - g.origin[1]) / g.h).floor();
    if i < 0.0 || j < 0.0 || i >= g.n[0] as f64 || j >= g.n[1] as f64 {
        return 0;
    }
    let (i, j) = (i as usize, j as usize);
    let of_b = |k: usize| {
        let idx = g.index(i, j, k);
        field.solid[idx] && field.occupancy.owner[idx] as usize == b
    };
    let Some(mut k) = (0..g.n[2]).rev().find(|&k| of_b(k)) else {
        return 0;
    };
    while k > 0 && of_b(k - 1) {
        k -= 1;
    }
    (0..k)
        .rev()
        .take_while(|&kk| !field.solid[g.index(i, j, kk)])
        .count()
}
