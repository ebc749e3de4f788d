//! Overlap removal (BCB step 2, `docs/bcb.md` §7.2), keeping boxes as boxes.
//!
//! BCB cuts the lower of two intersecting objects by the upper one with a boolean
//! difference. A difference of boxes is not a box, so here a box is only ever **shortened
//! along one of its own axes**, from one end, just enough that the pair no longer overlaps.
//!
//! **Who is cut.** Boxes are put in a precedence order; a box is trimmed against every box
//! before it, which is already final. The order is, first to last:
//! 1. by kind: columns, beams, walls, slabs ([`Role`]) — columns are continuous
//!    through joints, beams stop at column faces, walls are the infill of their boundary
//!    frame (cut at the column faces and at the beam soffit and top; BCB's own order puts
//!    walls before beams, docs/bcb.md §7.2, which would cut a beam between two stacked
//!    wall stories from both sides until nothing is left), slabs are reduced to the clear
//!    area between beams and walls (and lose the small corner left at a column that is
//!    wider than the beams);
//! 2. within a kind, the higher centre first (BCB: the body with the lower centroid is cut);
//! 3. then the smaller volume first (BCB: on a tie, the larger one is cut); then input order.
//!
//! **How it is cut.** For the box B being trimmed and an earlier box A with an overlap
//! volume above the tolerance, the exact intersection polyhedron A ∩ B is computed
//! ([`super::polytope`]). Expressed in B's local coordinates s, it spans
//! [min sₖ, max sₖ] on each axis k. Shortening B on axis k to [−hₖ, min sₖ] (or to
//! [max sₖ, hₖ]) removes the whole overlap with A. Of the six candidates over all
//! overlapping A, the one removing the least volume is applied, then the overlaps are
//! recomputed, until none exceeds the tolerance. A beam meeting a column thus loses the
//! length inside the column; a slab loses the strip under a beam.
//!
//! A box that would vanish entirely is an error naming both elements (BCB would delete it
//! and lose its mass).
//!
//! Candidate pairs come from a sort and sweep of the untrimmed axis-aligned bounds along X
//! (boxes only shrink), so a 2044-body seven-story frame trims in well under a second.
//!
//! Subdivided members: each FE element's box spans its own nodes, so consecutive boxes of
//! one straight member touch without overlapping and are not cut.

use super::error::{MappingError, Result};
use super::geometry::RigidBox;
use super::polytope::{intersect, overlap_volume as obb_overlap, Obb};
use crate::body::Role;
use nalgebra::Vector3;

/// The oriented box of a body.
pub(crate) fn obb(b: &RigidBox) -> Obb {
    Obb {
        centre: Vector3::from(b.centre),
        axes: b.rotation.to_rotation_matrix().into_inner(),
        half: Vector3::from(b.half_extents),
    }
}

/// Exact overlap volume of two bodies (m³).
pub fn overlap_volume(a: &RigidBox, b: &RigidBox) -> f64 {
    obb_overlap(&obb(a), &obb(b))
}

/// Pairs (i < j) whose axis-aligned bounds overlap, by sort and sweep along X
/// (O(n log n + pairs)); sorted, so the result is deterministic.
pub(crate) fn candidate_pairs(aabbs: &[([f64; 3], [f64; 3])]) -> Vec<(usize, usize)> {
    let mut order: Vec<usize> = (0..aabbs.len()).collect();
    order.sort_by(|&i, &j| aabbs[i].0[0].total_cmp(&aabbs[j].0[0]).then(i.cmp(&j)));
    let mut pairs = Vec::new();
    for (p, &i) in order.iter().enumerate() {
        for &j in &order[p + 1..] {
            if aabbs[j].0[0] >= aabbs[i].1[0] {
                break;
            }
            if aabb_overlap(&aabbs[i], &aabbs[j]) {
                pairs.push((i.min(j), i.max(j)));
            }
        }
    }
    pairs.sort_unstable();
    pairs
}

/// The largest pairwise overlap volume (m³) and the pair (indices) where it occurs.
pub fn max_pairwise_overlap(boxes: &[RigidBox]) -> (f64, Option<(usize, usize)>) {
    let aabbs: Vec<_> = boxes.iter().map(|b| obb(b).aabb()).collect();
    let mut best = (0.0, None);
    for (i, j) in candidate_pairs(&aabbs) {
        let v = overlap_volume(&boxes[i], &boxes[j]);
        if v > best.0 {
            best = (v, Some((i, j)));
        }
    }
    best
}

/// What [`trim_overlaps`] did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TrimReport {
    /// Number of cuts applied.
    pub cuts: usize,
    /// Number of boxes shortened at least once.
    pub trimmed_boxes: usize,
    /// Total volume removed (m³).
    pub removed_volume_m3: f64,
}

type Aabb = ([f64; 3], [f64; 3]);

fn aabb_overlap(a: &Aabb, b: &Aabb) -> bool {
    (0..3).all(|k| a.0[k] < b.1[k] && b.0[k] < a.1[k])
}

fn kind_rank(k: Role) -> u8 {
    match k {
        Role::Column => 0,
        Role::Beam => 1,
        Role::Wall => 2,
        Role::Slab => 3,
    }
}

/// The precedence order of the module docs (indices into `boxes`).
pub(crate) fn precedence(boxes: &[RigidBox]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..boxes.len()).collect();
    order.sort_by(|&i, &j| {
        let (a, b) = (&boxes[i], &boxes[j]);
        kind_rank(a.kind)
            .cmp(&kind_rank(b.kind))
            .then(b.centre[2].total_cmp(&a.centre[2]))
            .then(a.volume_m3().total_cmp(&b.volume_m3()))
            .then(i.cmp(&j))
    });
    order
}

/// One candidate cut of box B: keep [lo, hi] on local axis `axis`.
struct Cut {
    removed_fraction: f64,
    axis: usize,
    lo: f64,
    hi: f64,
}

/// Trims the boxes in place so that no pair overlaps by more than `tolerance_m3` (module
/// docs). Deterministic: the result depends only on the input order and values.
pub(crate) fn trim_overlaps(boxes: &mut [RigidBox], tolerance_m3: f64) -> Result<TrimReport> {
    if !(tolerance_m3 >= 0.0 && tolerance_m3.is_finite()) {
        return Err(MappingError::Options(format!(
            "overlap tolerance must be ≥ 0 m³, got {tolerance_m3}"
        )));
    }
    let order = precedence(boxes);
    let mut rank = vec![0usize; boxes.len()];
    for (r, &i) in order.iter().enumerate() {
        rank[i] = r;
    }
    // Boxes only shrink, so pairs of the untrimmed bounds are a superset of all overlaps.
    // Each box is trimmed against its neighbours earlier in the precedence order.
    let aabbs: Vec<Aabb> = boxes.iter().map(|b| obb(b).aabb()).collect();
    let mut earlier: Vec<Vec<usize>> = vec![Vec::new(); boxes.len()];
    for (i, j) in candidate_pairs(&aabbs) {
        let (a, b) = if rank[i] < rank[j] { (i, j) } else { (j, i) };
        earlier[b].push(a);
    }
    for list in &mut earlier {
        list.sort_by_key(|&a| rank[a]);
    }
    let mut report = TrimReport::default();
    let mut fin: Vec<Option<(Obb, Aabb)>> = vec![None; boxes.len()];
    for &bi in &order {
        let mut cut_here = false;
        for iteration in 0.. {
            if iteration == 1000 {
                return Err(MappingError::TooManyCuts(boxes[bi].id.clone()));
            }
            let ob = obb(&boxes[bi]);
            let bb = ob.aabb();
            let mut best: Option<Cut> = None;
            let mut best_other = 0usize;
            for &ai in &earlier[bi] {
                let Some((oa, ab)) = &fin[ai] else {
                    unreachable!("earlier boxes are final")
                };
                if !aabb_overlap(ab, &bb) {
                    continue;
                }
                let inter = intersect(oa, &ob);
                if inter.is_empty() || inter.volume() <= tolerance_m3 {
                    continue;
                }
                let mut lo = [f64::INFINITY; 3];
                let mut hi = [f64::NEG_INFINITY; 3];
                for p in inter.vertices() {
                    let s = ob.axes.transpose() * (p - ob.centre);
                    for k in 0..3 {
                        lo[k] = lo[k].min(s[k]);
                        hi[k] = hi[k].max(s[k]);
                    }
                }
                for k in 0..3 {
                    let h = ob.half[k];
                    let options = [
                        (-h, lo[k].clamp(-h, h)), // cut the + end back to min s_k
                        (hi[k].clamp(-h, h), h),  // cut the − end up to max s_k
                    ];
                    for (l, u) in options {
                        let cut = Cut {
                            removed_fraction: 1.0 - (u - l) / (2.0 * h),
                            axis: k,
                            lo: l,
                            hi: u,
                        };
                        if best
                            .as_ref()
                            .is_none_or(|b| cut.removed_fraction < b.removed_fraction)
                        {
                            best = Some(cut);
                            best_other = ai;
                        }
                    }
                }
            }
            let Some(cut) = best else { break };
            if cut.removed_fraction >= 1.0 - 1e-9 {
                return Err(MappingError::Vanishes {
                    body: boxes[bi].id.clone(),
                    within: boxes[best_other].id.clone(),
                });
            }
            let b = &mut boxes[bi];
            let axis = ob.axes.column(cut.axis).into_owned();
            let shift = axis * (0.5 * (cut.lo + cut.hi));
            report.removed_volume_m3 += b.volume_m3() * cut.removed_fraction;
            for k in 0..3 {
                b.centre[k] += shift[k];
            }
            b.half_extents[cut.axis] = 0.5 * (cut.hi - cut.lo);
            report.cuts += 1;
            cut_here = true;
        }
        if cut_here {
            report.trimmed_boxes += 1;
        }
        let ob = obb(&boxes[bi]);
        fin[bi] = Some((ob, ob.aabb()));
    }
    Ok(report)
}
