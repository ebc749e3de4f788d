//! Build step 1: the ground box (`crate::ruin::ground`; BCB's `Ground_Motion` object,
//! docs/bcb.md §6 and §11.6).

use crate::bullet::{BoxDesc, Pose, World};
use crate::ruin::ground::GroundSpec;
use crate::ruin::record::StageError;
use crate::ruin::settings::BodySettings;
use crate::ruin::stage::bad;
use crate::ruin::world::{shifted, Ground};
use crate::ruin::BodyGeom;

/// The undeformed bodies' axis-aligned bounding box, m (all zero without bodies).
pub(super) struct Extent {
    /// Lowest corner.
    pub(super) lo: [f64; 3],
    /// Highest corner.
    pub(super) hi: [f64; 3],
}

impl Extent {
    /// The box around `bodies`.
    pub(super) fn of(bodies: &[BodyGeom]) -> Extent {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for b in bodies {
            let bb = b.aabb();
            for k in 0..3 {
                lo[k] = lo[k].min(bb.min[k]);
                hi[k] = hi[k].max(bb.max[k]);
            }
        }
        if bodies.is_empty() {
            lo = [0.0; 3];
            hi = [0.0; 3];
        }
        Extent { lo, hi }
    }

    /// The model's height, m (≥ 0).
    pub(super) fn height_m(&self) -> f64 {
        (self.hi[2] - self.lo[2]).max(0.0)
    }
}

/// The ground's plan margin and thickness are finite and > 0.
pub(super) fn check(spec: &GroundSpec) -> Result<(), StageError> {
    for (name, v) in [
        ("ground plan_margin_m", spec.plan_margin_m),
        ("ground thickness_m", spec.thickness_m),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(bad(name, format!("{v} must be finite and > 0")));
        }
    }
    Ok(())
}

/// Adds the ground box: the bodies' plan `extent` grown by the plan margin on every
/// side, `thickness_m` thick, its top at `top_z` (default: the lowest point of the
/// bodies), displaced by d(`t0`); kinematic with a ground motion, else static. Friction
/// the ground's, margin and restitution the bodies' (`body`).
pub(super) fn add(
    world: &mut World,
    extent: &Extent,
    spec: GroundSpec,
    body: &BodySettings,
    t0: f64,
) -> Result<Ground, StageError> {
    let (lo, hi) = (extent.lo, extent.hi);
    let top = spec.top_z.unwrap_or(lo[2]);
    let half = [
        0.5 * (hi[0] - lo[0]) + spec.plan_margin_m,
        0.5 * (hi[1] - lo[1]) + spec.plan_margin_m,
        0.5 * spec.thickness_m,
    ];
    let rest = Pose::at([
        0.5 * (lo[0] + hi[0]),
        0.5 * (lo[1] + hi[1]),
        top - 0.5 * spec.thickness_m,
    ]);
    let start = shifted(&rest, spec.displacement_at(t0));
    let mut desc = if spec.history.is_some() {
        BoxDesc::kinematic(half, start)
    } else {
        BoxDesc::fixed(half, start)
    };
    desc.friction = spec.friction;
    desc.margin = body.margin;
    desc.restitution = body.restitution;
    let handle = world.add_box(&desc)?;
    Ok(Ground {
        handle,
        rest,
        half_extents: half,
        reference: [rest.position[0], rest.position[1], top],
        spec,
    })
}
