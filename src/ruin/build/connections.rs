//! Build steps 4 and 5: the connections (BCB's CT 22, `crate::ruin::connection`) and their
//! Bullet constraints, each with its starting state; the plastic springs' stability cap
//! per body and the member rows' ERP and CFM.

use crate::bullet::{BodyHandle, ConstraintDesc, ConstraintKind, ConstraintParam, Spring, World};
use crate::ruin::connection::{
    build_connections_with, ConnectionSpec, ConnectionState, ConstraintClass as SpecKind,
    ConstraintSpec,
};
use crate::ruin::monitor::{start_state_from_damage, FeDamage};
use crate::ruin::record::StageError;
use crate::ruin::search::{find_contacts, Contact};
use crate::ruin::settings::{member_row_erp_cfm, JointRows, StageInput, StageSettings};
use crate::ruin::stage::bad;
use crate::ruin::world::{to_pose, Connections};

/// Finds the contacts of the undeformed bodies (none without `settings.connect`), builds
/// their connections with frames from the start poses, gives each its starting state
/// (broken when lost at the start, else from the FE damage of its body pair; plastic
/// without a spring is broken) and adds its constraints to `world` in spec order
/// (`handles`: the bodies' world handles; `h`: the substep, s).
pub(super) fn add(
    world: &mut World,
    input: &StageInput,
    handles: &[BodyHandle],
    settings: &StageSettings,
    h: f64,
) -> Result<Connections, StageError> {
    let n = input.bodies.len();
    let r = &settings.ruin;
    let contacts: Vec<Contact> = if settings.connect {
        find_contacts(input.bodies, &r.search)?
    } else {
        Vec::new()
    };
    let mut connections = build_connections_with(
        input.bodies,
        input.groups,
        &contacts,
        &input.start_poses,
        r,
        &input.body_strengths,
    )?;
    for &(a, b) in input.start_damage.keys() {
        if a >= b || b >= n {
            return Err(bad(
                "start damage",
                format!("body pair ({a}, {b}) must have a < b < {n}"),
            ));
        }
    }
    let mut start_states = Vec::with_capacity(connections.len());
    for c in connections.iter_mut() {
        let dmg = input
            .start_damage
            .get(&(c.a, c.b))
            .copied()
            .unwrap_or(FeDamage::Intact);
        let mut s = if c.lost_at_start {
            ConnectionState::Broken
        } else {
            start_state_from_damage(dmg)
        };
        if s == ConnectionState::Plastic && !c.has_spring() {
            s = ConnectionState::Broken;
        }
        c.set_state(s);
        start_states.push(s);
    }
    // Plastic springs per body (for the per-body stability cap).
    let mut springs_on = vec![0usize; n];
    for c in connections.iter().filter(|c| c.has_spring()) {
        for b in [c.a, c.b] {
            if !input.bodies[b].passive {
                springs_on[b] += 1;
            }
        }
    }
    let mut constraint_handles = Vec::with_capacity(connections.len());
    for c in &connections {
        let mut hs = Vec::with_capacity(c.constraints.len());
        for spec in &c.constraints {
            let kind = match spec.kind {
                SpecKind::Generic6Dof => ConstraintKind::Generic6Dof {
                    use_linear_reference_frame_a: true,
                },
                SpecKind::Spring2 => {
                    let mut springs = [None; 6];
                    for (k, s) in springs.iter_mut().enumerate() {
                        if spec.spring[k] {
                            let (mut stiffness, mut damping) = (spec.stiffness[k], spec.damping[k]);
                            if settings.plastic.spring_cap_per_body {
                                let (kc, dc) = body_spring_cap(
                                    world,
                                    c,
                                    spec,
                                    k,
                                    handles,
                                    input,
                                    spring_cap_step(
                                        h,
                                        settings.plastic.spring_cap_steps_per_second,
                                    ),
                                    springs_on[c.a].max(springs_on[c.b]),
                                )?;
                                stiffness = stiffness.min(kc);
                                damping = damping.min(dc);
                            }
                            *s = Some(Spring {
                                stiffness,
                                damping,
                                limit_if_needed: settings.ruin.spring_limit_if_needed,
                            });
                        }
                    }
                    ConstraintKind::Spring2 {
                        springs,
                        set_equilibrium_point: true,
                    }
                }
            };
            let mut desc = ConstraintDesc::new(
                kind,
                handles[c.a],
                handles[c.b],
                to_pose(&spec.frame_a),
                to_pose(&spec.frame_b),
            );
            for k in 0..6 {
                desc.limits[k] = Some((spec.lower[k], spec.upper[k]));
            }
            desc.breaking_impulse_threshold = spec.breaking_impulse;
            desc.disable_collisions_between = c.disable_collisions;
            desc.enabled = spec.enabled;
            if spec.kind == SpecKind::Generic6Dof {
                desc.override_solver_iterations = settings.joints.iterations;
            }
            let hnd = world.add_constraint(&desc).map_err(|e| {
                bad(
                    &format!(
                        "connection {} – {} ({:?} row)",
                        input.bodies[c.a].name, input.bodies[c.b].name, spec.role
                    ),
                    e.to_string(),
                )
            })?;
            if let (
                JointRows::Member {
                    modulus_pa,
                    damping_ratio,
                },
                SpecKind::Generic6Dof,
            ) = (settings.joints.rows, spec.kind)
            {
                for axis in (0..6).filter(|&a| spec.lower[a] <= spec.upper[a]) {
                    let (k, inv_m) = member_row(
                        world,
                        c,
                        spec,
                        axis,
                        handles,
                        input,
                        modulus_pa,
                        passive_of(input, c),
                    )?;
                    let (erp, cfm) = member_row_erp_cfm(k, inv_m, h, damping_ratio);
                    world.set_constraint_param(hnd, ConstraintParam::StopErp, axis, erp)?;
                    world.set_constraint_param(hnd, ConstraintParam::StopCfm, axis, cfm)?;
                }
            }
            hs.push(hnd);
        }
        constraint_handles.push(hs);
    }
    Ok(Connections {
        first_lost: vec![None; connections.len()],
        specs: connections,
        handles: constraint_handles,
        start_states,
    })
}

/// The step the spring cap is computed for, s: max(h, 1/`rate`), or h when `rate` is 0
/// ([`crate::ruin::settings::PlasticSettings::spring_cap_steps_per_second`]). Never below
/// h: a coarser substep than the rate's needs its own, lower cap for stability.
fn spring_cap_step(h: f64, rate: f64) -> f64 {
    if rate > 0.0 {
        h.max(1.0 / rate)
    } else {
        h
    }
}

/// The per-body stability cap of plastic-spring axis `axis` (0..2 linear, 3..5 angular; the
/// spring frame is world-aligned on the undeformed bodies) of connection `c`, on which `n`
/// springs at most act per body
/// ([`crate::ruin::settings::PlasticSettings::spring_cap_per_body`]). Bullet integrates
/// each spring explicitly (`btGeneric6DofSpring2Constraint`: the force k·e·h from the error
/// at the substep's start), stable for ω·h < 2 and sampled well for ω·h ≤ 1/4 (Bullet's
/// `limitIfNeeded`: k ≤ m/(16·h²), c ≤ m/h, m the pair's mass at the centres). Here the
/// effective inverse mass of the axis at the pivot is taken with the lever arm, w =
/// Σ_bodies 1/m + (r × e)·I⁻¹(r × e) (linear, r = pivot − centre) or e·I⁻¹e (angular), and
/// the n springs on the same body share the budget: k ≤ 1/(16·h²·w·n), c ≤ 1/(h·w·n).
/// Returns (k cap, c cap).
#[allow(clippy::too_many_arguments)]
fn body_spring_cap(
    world: &World,
    c: &ConnectionSpec,
    spec: &ConstraintSpec,
    axis: usize,
    handles: &[BodyHandle],
    input: &StageInput,
    h: f64,
    n: usize,
) -> Result<(f64, f64), StageError> {
    let a0 = input.bodies[c.a].pose();
    let pivot = (a0 * spec.frame_a).translation.vector;
    let e = nalgebra::Vector3::ith(axis % 3, 1.0);
    let mut w = 0.0;
    for b in [c.a, c.b] {
        if input.bodies[b].passive {
            continue;
        }
        let (m, i) = world.mass_inertia(handles[b])?;
        let pose = input.bodies[b].pose();
        let rot_inv = pose.rotation.inverse();
        let inv_i = |v: nalgebra::Vector3<f64>| {
            let l = rot_inv * v;
            l.x * l.x / i[0] + l.y * l.y / i[1] + l.z * l.z / i[2]
        };
        if axis < 3 {
            let r = pivot - pose.translation.vector;
            w += 1.0 / m + inv_i(r.cross(&e));
        } else {
            w += inv_i(e);
        }
    }
    if w <= 0.0 {
        return Ok((f64::INFINITY, f64::INFINITY));
    }
    let n = n.max(1) as f64;
    Ok((1.0 / (16.0 * h * h * w * n), 1.0 / (h * w * n)))
}

fn passive_of(input: &StageInput, c: &ConnectionSpec) -> (bool, bool) {
    (input.bodies[c.a].passive, input.bodies[c.b].passive)
}

/// The member stiffness k and the effective inverse mass K of locked axis `axis` (0..2
/// linear, 3..5 angular, constraint frame: X = the contact normal) of a generic row of
/// connection `c` ([`JointRows::Member`]).
#[allow(clippy::too_many_arguments)]
fn member_row(
    world: &World,
    c: &ConnectionSpec,
    spec: &ConstraintSpec,
    axis: usize,
    handles: &[BodyHandle],
    input: &StageInput,
    modulus_pa: f64,
    passive: (bool, bool),
) -> Result<(f64, f64), StageError> {
    let ct = &c.contact;
    let (hh, ww) = (ct.h.max(1e-6), ct.w.max(1e-6));
    let l = ct.centre_distance.max(1e-3);
    let g = modulus_pa / 2.4;
    // The constraint frame's axis `axis % 3` in world (undeformed: frames from BCB's rotN).
    let a0 = input.bodies[c.a].pose();
    let r = (a0 * spec.frame_a).rotation;
    let e = r * nalgebra::Vector3::ith(axis % 3, 1.0);
    // Which contact direction (normal, h or w) that axis runs along.
    let comp = |i: usize| e[i].abs();
    let along = if comp(ct.normal_axis) >= comp(ct.h_axis).max(comp(ct.w_axis)) {
        0
    } else if comp(ct.h_axis) >= comp(ct.w_axis) {
        1
    } else {
        2
    };
    let area = hh * ww;
    let k = if axis < 3 {
        if along == 0 {
            modulus_pa * area / l
        } else {
            g * area / l
        }
    } else {
        match along {
            0 => g * hh * ww * (hh * hh + ww * ww) / 12.0 / l,
            // About the h axis: the section's depth across it is w.
            1 => modulus_pa * hh * ww.powi(3) / 12.0 / l,
            _ => modulus_pa * ww * hh.powi(3) / 12.0 / l,
        }
    };
    let mut inv = 0.0;
    for (b, is_passive) in [(c.a, passive.0), (c.b, passive.1)] {
        if is_passive {
            continue;
        }
        let (m, i) = world.mass_inertia(handles[b])?;
        if axis < 3 {
            inv += 1.0 / m;
        } else {
            let rb = input.bodies[b].pose().rotation;
            let el = rb.inverse() * e;
            let ie = i[0] * el.x * el.x + i[1] * el.y * el.y + i[2] * el.z * el.z;
            inv += 1.0 / ie;
        }
    }
    Ok((k, inv))
}

#[cfg(test)]
mod tests {
    use super::spring_cap_step;

    /// The spring cap's step: BCB's 1/200 s at 400 and 800 substeps/s (so k ≤ 1/(16·h²·w·n)
    /// is the same at every finer substep), the run's own at 200 and coarser, and the
    /// run's own everywhere with the rate 0.
    #[test]
    fn the_spring_cap_uses_the_reference_step_at_finer_substeps() {
        assert_eq!(spring_cap_step(1.0 / 800.0, 200.0), 1.0 / 200.0);
        assert_eq!(spring_cap_step(1.0 / 400.0, 200.0), 1.0 / 200.0);
        assert_eq!(spring_cap_step(1.0 / 200.0, 200.0), 1.0 / 200.0);
        assert_eq!(spring_cap_step(1.0 / 100.0, 200.0), 1.0 / 100.0);
        assert_eq!(spring_cap_step(1.0 / 800.0, 0.0), 1.0 / 800.0);
    }
}
