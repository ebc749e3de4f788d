//! Build step 2: the members' boxes.

use super::ground::Extent;
use crate::bullet::{BoxDesc, World};
use crate::ruin::energy::MassProps;
use crate::ruin::record::StageError;
use crate::ruin::rest::RestBody;
use crate::ruin::settings::{BodySettings, StageInput};
use crate::ruin::stage::to_pose;
use crate::ruin::world::Bodies;
use crate::ruin::RuinError;

/// Adds every input body as a box at its start pose, in input order: an active body
/// dynamic with its mass and start velocity and the body settings `bs` (its margin capped
/// at [`BodySettings::margin_max_share`] of its smallest half extent; with sleeping on,
/// Bullet's sleeping thresholds s/2 and s/(2·r), s = [`BodySettings::sleep_speed_mps`],
/// r the half diagonal); a passive body kinematic, with the ground's friction
/// `ground_friction`. `extent`: the undeformed bodies' bounding box (the model's height).
pub(super) fn add(
    world: &mut World,
    input: &StageInput,
    ground_friction: f64,
    bs: &BodySettings,
    extent: &Extent,
) -> Result<Bodies, StageError> {
    let n = input.bodies.len();
    let mut handles = Vec::with_capacity(n);
    let mut rest = Vec::with_capacity(n);
    let mut total_mass = 0.0;
    for (i, b) in input.bodies.iter().enumerate() {
        let pose = to_pose(&input.start_poses[i]);
        let mut d = if b.passive {
            BoxDesc::kinematic(b.half_extents, pose)
        } else {
            BoxDesc::dynamic(b.half_extents, input.masses_kg[i], pose)
        };
        if !b.passive {
            d.velocity = input.start_velocities[i];
        }
        d.friction = if b.passive {
            ground_friction
        } else {
            bs.friction
        };
        d.restitution = bs.restitution;
        d.linear_damping = bs.linear_damping;
        d.angular_damping = bs.angular_damping;
        d.margin = bs.margin.min(
            bs.margin_max_share * b.half_extents.iter().copied().fold(f64::INFINITY, f64::min),
        );
        d.disable_deactivation = bs.disable_deactivation;
        let hnd = world.add_box(&d).map_err(|e| {
            StageError::Ruin(RuinError::BadBody {
                index: i,
                name: b.name.clone(),
                message: e.to_string(),
            })
        })?;
        if !b.passive && !bs.disable_deactivation {
            let he = b.half_extents;
            let r = (he[0] * he[0] + he[1] * he[1] + he[2] * he[2]).sqrt();
            let s = 0.5 * bs.sleep_speed_mps;
            world.set_sleeping_thresholds(hnd, s, s / r)?;
        }
        handles.push(hnd);
        if b.passive {
            rest.push(None);
        } else {
            let (m, inertia) = world.mass_inertia(hnd)?;
            total_mass += m;
            let he = b.half_extents;
            rest.push(Some(RestBody {
                mass_kg: m,
                inertia,
                radius_m: (he[0] * he[0] + he[1] * he[1] + he[2] * he[2]).sqrt(),
            }));
        }
    }
    let props: Vec<Option<MassProps>> = rest
        .iter()
        .map(|r: &Option<RestBody>| {
            r.map(|r| MassProps {
                mass_kg: r.mass_kg,
                inertia: r.inertia,
            })
        })
        .collect();
    Ok(Bodies {
        handles,
        passive: input.bodies.iter().map(|b| b.passive).collect(),
        start_poses: input.start_poses.clone(),
        rest,
        props,
        total_mass_kg: total_mass,
        model_height_m: extent.height_m(),
    })
}
