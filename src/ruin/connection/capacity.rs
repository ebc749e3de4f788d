//! The capacities, tolerances and plastic spring of every connection (module docs of
//! [`super`]: thresholds, two groups, no 90° values, spring stiffness), from the groups'
//! strengths per area or the FE-derived member capacities ([`super::member`]), and the
//! connection built on its rows ([`super::rows`]).
use super::member::{BodyCapacity, BodyStrength};
use super::rows::constraint_specs;
use super::{
    ConnectionForces, ConnectionSpec, GroupStrength, HingeEnd, ResolvedTolerances, RuinSettings,
    PRESET_TOL2_DIST, PRESET_TOL2_ROT,
};
use crate::ruin::search::Contact;
use crate::ruin::strength::{StrengthPerArea, StrengthSource};
use crate::ruin::{BodyGeom, RuinError};
use nalgebra::Isometry3;
use std::collections::BTreeMap;

/// The weaker (or stronger) of two per-area strength sets, per value; a 90° or plastic
/// value survives only if both have one (BCB: −1 if either is missing).
fn combine(a: &StrengthPerArea, b: &StrengthPerArea, weaker: bool) -> StrengthPerArea {
    let pick = |x: f64, y: f64| if weaker { x.min(y) } else { x.max(y) };
    let pick_opt = |x: Option<f64>, y: Option<f64>| match (x, y) {
        (Some(x), Some(y)) => Some(pick(x, y)),
        _ => None,
    };
    StrengthPerArea {
        c: pick(a.c, b.c),
        t: pick(a.t, b.t),
        s: pick(a.s, b.s),
        s90: pick_opt(a.s90, b.s90),
        b: pick(a.b, b.b),
        b90: pick_opt(a.b90, b.b90),
        p: pick_opt(a.p, b.p),
    }
}
/// Builds the CT 22 connection of every contact ([`build_connections_with`] without
/// FE-derived strengths: BCB's group strengths throughout).
pub fn build_connections(
    bodies: &[BodyGeom],
    groups: &[GroupStrength],
    contacts: &[Contact],
    poses_at_start: &[Isometry3<f64>],
    settings: &RuinSettings,
) -> Result<Vec<ConnectionSpec>, RuinError> {
    build_connections_with(bodies, groups, contacts, poses_at_start, settings, &[])
}

/// Builds the CT 22 connection of every contact.
///
/// **FE-derived strengths** (`strengths`, one [`BodyCapacity`] per body or empty;
/// docs/handoff.md): a connection whose body (or bodies) has a [`BodyStrength`] and is
/// cut by the contact (the contact is at the member's end face, [`BodyStrength::cut_by`])
/// takes its compression, tension, shear and bending capacities from the member end
/// nearest the pivot ([`BodyStrength::forces_for`]): along the member axis the axial
/// capacity, across it the shear capacity in that direction; about the member axis the
/// weaker bending capacity (torsion), about a cross axis the moment capacity about it.
/// A member touched on its side does not limit the connection. Two such bodies:
/// the weaker of the two per value. One body with FE strengths and one active body
/// without (e.g. a slab panel): the weaker of the FE value and the group value. One with
/// FE strengths and a passive partner (foundation): the FE value, without BCB's ×2
/// boundary multiplier (the column's base section is the weak link the FE computed).
/// BCB's corrections 2.2 / 1.5 still convert the forces to Bullet thresholds. The bending
/// rows are ductile ([`ConnectionSpec::ductile`]). With [`HingeEnd::Spring`] the 1st
/// rotation tolerance becomes the larger of BCB's and the smaller remaining rotation
/// capacity of the ends where given, and the plastic spring keeps BCB's P and k and BCB's
/// 2nd tolerances; with [`HingeEnd::Rupture`] the 1st tolerances are the 2nd ones (the
/// rotation the larger of tol2R and the rotation left) and there is no spring.
///
/// A [`BodyCapacity::Elastic`] body (a slab panel the FE carries elastically) never
/// limits: against a group body that group's value alone, against a member it cuts the
/// member's values alone; against another elastic body, a member it does not cut or a
/// passive body nothing limits, and the connection is unbreakable (infinite strengths, no
/// tolerances, no spring; docs/handoff.md §2.6).
///
/// * `bodies`: the geometry the contacts were found on (undeformed).
/// * `groups`: strength definitions, looked up by [`BodyGeom::group`].
/// * `contacts`: from [`crate::ruin::search::find_contacts`].
/// * `poses_at_start`: every body's pose when the constraints are created (Tc for the
///   hybrid mode; the undeformed poses for rigid-only), one per body.
///
/// Every connection is created elastic; use [`ConnectionSpec::set_state`] for another
/// starting state.
pub fn build_connections_with(
    bodies: &[BodyGeom],
    groups: &[GroupStrength],
    contacts: &[Contact],
    poses_at_start: &[Isometry3<f64>],
    settings: &RuinSettings,
    strengths: &[BodyCapacity],
) -> Result<Vec<ConnectionSpec>, RuinError> {
    settings.validate()?;
    if !strengths.is_empty() && strengths.len() != bodies.len() {
        return Err(RuinError::LengthMismatch {
            what: "FE-derived body strengths".into(),
            expected: bodies.len(),
            got: strengths.len(),
        });
    }
    let strength_of = |i: usize| strengths.get(i).and_then(BodyCapacity::member);
    let elastic = |i: usize| matches!(strengths.get(i), Some(BodyCapacity::Elastic));
    // An active body whose own group strength limits its connections.
    let group_limited = |i: usize| !bodies[i].passive && !elastic(i) && strength_of(i).is_none();
    if poses_at_start.len() != bodies.len() {
        return Err(RuinError::LengthMismatch {
            what: "poses at the start of the ruin stage".into(),
            expected: bodies.len(),
            got: poses_at_start.len(),
        });
    }
    let mut by_name: BTreeMap<&str, &GroupStrength> = BTreeMap::new();
    for g in groups {
        g.validate()?;
        by_name.insert(g.name.as_str(), g);
    }
    let lookup = |i: usize| -> Result<&GroupStrength, RuinError> {
        let body = &bodies[i];
        by_name
            .get(body.group.as_str())
            .copied()
            .ok_or_else(|| RuinError::UnknownGroup {
                index: i,
                name: body.name.clone(),
                group: body.group.clone(),
            })
    };
    let mut out = Vec::with_capacity(contacts.len());
    for c in contacts {
        if c.a >= bodies.len() || c.b >= bodies.len() {
            return Err(RuinError::BadSetting {
                item: format!("contact ({}, {})", c.a, c.b),
                message: format!("body index out of range (there are {})", bodies.len()),
            });
        }
        let (ba, bb) = (&bodies[c.a], &bodies[c.b]);
        if ba.passive && bb.passive {
            continue;
        }
        let h_mm = c.h * 1000.0;
        let w_mm = c.w * 1000.0;
        let a_mm2 = c.area * 1.0e6;
        // Governing group and the per-area values × multipliers (BCB `mul`).
        let (group, per_area, mul, pl) = if ba.passive || bb.passive {
            let active = if ba.passive { c.b } else { c.a };
            let g = lookup(active)?;
            (
                g,
                g.strength.per_area(h_mm, w_mm),
                g.threshold_multiplier * settings.passive_multiplier,
                g.plastic_length,
            )
        } else if elastic(c.a) != elastic(c.b) {
            // An elastic panel does not limit: the partner's group alone.
            let g = lookup(if elastic(c.a) { c.b } else { c.a })?;
            (
                g,
                g.strength.per_area(h_mm, w_mm),
                g.threshold_multiplier,
                g.plastic_length,
            )
        } else {
            let ga = lookup(c.a)?;
            let gb = lookup(c.b)?;
            let pa = ga.strength.per_area(h_mm, w_mm);
            let pb = gb.strength.per_area(h_mm, w_mm);
            // BCB multiplies each group's expression by its own multiplier, then compares.
            let sa = scale(&pa, ga.threshold_multiplier);
            let sb = scale(&pb, gb.threshold_multiplier);
            let pick = |x: f64, y: f64| {
                if settings.weaker_group {
                    x.min(y)
                } else {
                    x.max(y)
                }
            };
            (
                ga,
                combine(&sa, &sb, settings.weaker_group),
                1.0,
                pick(ga.plastic_length, gb.plastic_length),
            )
        };
        let v = scale(&per_area, mul * a_mm2);

        // Shear and bending pairs (min → h, max → w), BCB's btRatio without 90° values.
        let (shear_h, shear_w) = match v.s90 {
            Some(s90) => (v.s.min(s90), v.s.max(s90)),
            None => (v.s, v.s),
        };
        let (bend_h, bend_w) = match v.b90 {
            Some(b90) => (v.b.min(b90), v.b.max(b90)),
            None => {
                let sd = settings.search.search_distance;
                let ratio = if v.s90.is_none() && c.h > sd && c.w > sd {
                    c.h / c.w
                } else {
                    1.0
                };
                (v.b * ratio, v.b / ratio)
            }
        };

        // Tolerances of the governing group.
        let formula = match &group.strength {
            StrengthSource::Formula(f) => Some(f),
            StrengthSource::PerArea(_) => None,
        };
        let t = &group.tolerances;
        let enabled = |x: f64| (x >= 0.0).then_some(x);
        let dist2 = if t.dist2 == 0.0 {
            formula.map_or(PRESET_TOL2_DIST, |f| f.tol2_dist())
        } else {
            t.dist2
        };
        let rot2 = if t.rot2 == 0.0 {
            match formula {
                Some(f) if c.h > 0.0 => f.tol2_rot(c.centre_distance, c.h),
                _ => PRESET_TOL2_ROT,
            }
        } else {
            t.rot2
        };
        let tolerances = ResolvedTolerances {
            dist1: enabled(t.dist1),
            rot1: enabled(t.rot1),
            dist2: enabled(dist2),
            rot2: enabled(rot2),
        };

        // Spring.
        let spring_length = if pl > 0.0 {
            pl
        } else if c.centre_distance > 0.0 {
            c.centre_distance
        } else {
            0.1
        };
        // A disabled 2nd distance tolerance would give BCB a negative stiffness (−1);
        // we use the preset value instead.
        let tol2_for_k = if dist2 > 0.0 { dist2 } else { PRESET_TOL2_DIST };
        let spring_stiffness =
            v.p.map(|p| p / (spring_length * tol2_for_k) * settings.spring_correction / 2.0);

        let mut forces = ConnectionForces {
            compression_n: v.c,
            tension_n: v.t,
            shear_h_n: shear_h,
            shear_w_n: shear_w,
            bend_h_nm: bend_h,
            bend_w_nm: bend_w,
            plastic_n: v.p,
            spring_stiffness,
        };
        let mut tolerances = tolerances;
        let (fa, fb) = (
            strength_of(c.a).filter(|sd| sd.cut_by(c)),
            strength_of(c.b).filter(|sd| sd.cut_by(c)),
        );
        let lost_at_start = [fa, fb]
            .into_iter()
            .flatten()
            .any(|sd| sd.end_near(c.pivot).lost);
        if fa.is_some() || fb.is_some() {
            let sides: Vec<&BodyStrength> = [fa, fb].into_iter().flatten().collect();
            let mut fe = [f64::INFINITY; 6];
            for sd in &sides {
                for (k, v) in sd.forces_for(c).into_iter().enumerate() {
                    fe[k] = fe[k].min(v);
                }
            }
            // An active partner without FE strengths: also its group value.
            // (A member with FE strengths touched on its side does not limit it.)
            let other_active_without = group_limited(c.a) || group_limited(c.b);
            let group_vals = [
                forces.compression_n,
                forces.tension_n,
                forces.shear_h_n,
                forces.shear_w_n,
                forces.bend_h_nm,
                forces.bend_w_nm,
            ];
            let val = |k: usize| {
                if other_active_without {
                    fe[k].min(group_vals[k])
                } else {
                    fe[k]
                }
            };
            forces.compression_n = val(0);
            forces.tension_n = val(1);
            forces.shear_h_n = val(2);
            forces.shear_w_n = val(3);
            forces.bend_h_nm = val(4);
            forces.bend_w_nm = val(5);
            let rot_left = sides
                .iter()
                .filter_map(|sd| sd.end_near(c.pivot).rotation_left)
                .reduce(f64::min);
            if let (Some(r), Some(t1)) = (rot_left, tolerances.rot1) {
                // The hinge holds until the larger of the FE's remaining rotation capacity
                // and BCB's tol1R (docs/handoff.md: switching earlier hands a column to
                // BCB's spring, whose P is below its gravity load).
                tolerances.rot1 = Some(r.max(t1));
            }
        }
        let ductile = !strengths.is_empty() && (fa.is_some() || fb.is_some());
        if ductile && settings.hinge_end == HingeEnd::Rupture {
            // The hinge holds to BCB's 2nd tolerances (bar rupture), then breaks; no spring.
            let rot_left = [fa, fb]
                .into_iter()
                .flatten()
                .filter_map(|sd| sd.end_near(c.pivot).rotation_left)
                .reduce(f64::min);
            tolerances.dist1 = tolerances.dist2;
            tolerances.rot1 = tolerances.rot2.map(|r2| rot_left.map_or(r2, |r| r.max(r2)));
            forces.plastic_n = None;
            forces.spring_stiffness = None;
        }
        // Nothing limits a connection of an elastic panel with another panel or with a
        // member it does not cut: unbreakable, no tolerances (the FE's slab is elastic).
        let unlimited = (elastic(c.a) || elastic(c.b))
            && fa.is_none()
            && fb.is_none()
            && !group_limited(c.a)
            && !group_limited(c.b);
        if unlimited {
            forces = ConnectionForces {
                compression_n: f64::INFINITY,
                tension_n: f64::INFINITY,
                shear_h_n: f64::INFINITY,
                shear_w_n: f64::INFINITY,
                bend_h_nm: f64::INFINITY,
                bend_w_nm: f64::INFINITY,
                plastic_n: None,
                spring_stiffness: None,
            };
            tolerances = ResolvedTolerances {
                dist1: None,
                rot1: None,
                dist2: None,
                rot2: None,
            };
        }

        let constraints = constraint_specs(
            c,
            ba,
            bb,
            &poses_at_start[c.a],
            &poses_at_start[c.b],
            &forces,
            settings,
        );
        out.push(ConnectionSpec {
            a: c.a,
            b: c.b,
            contact: *c,
            group: group.name.clone(),
            forces,
            tolerances,
            spring_length,
            disable_collisions: settings.disable_collisions,
            constraints,
            lost_at_start,
            ductile,
        });
    }
    Ok(out)
}

fn scale(p: &StrengthPerArea, f: f64) -> StrengthPerArea {
    StrengthPerArea {
        c: p.c * f,
        t: p.t * f,
        s: p.s * f,
        s90: p.s90.map(|v| v * f),
        b: p.b * f,
        b90: p.b90.map(|v| v * f),
        p: p.p.map(|v| v * f),
    }
}

#[cfg(test)]
mod tests {
    use super::super::member::tests::test_end;
    use super::super::member::BodyStrength;
    use super::super::ConnectionState;
    use super::super::BCB_UNLIMITED;
    use super::*;
    use nalgebra::UnitQuaternion;

    /// Two 0.2 × 0.2 × 1 m column pieces stacked on Z and their contact at z = 1 m
    /// (normal Z, h along X, w along Y).
    fn stacked_columns() -> (BodyGeom, BodyGeom, Contact) {
        let geom = |z: f64| BodyGeom {
            name: format!("Column:1:{z}"),
            group: "1".into(),
            centre: [0.0, 0.0, z],
            rotation: UnitQuaternion::identity(),
            half_extents: [0.1, 0.1, 0.5],
            passive: false,
        };
        let (ba, bb) = (geom(0.5), geom(1.5));
        let c = Contact {
            a: 0,
            b: 1,
            pivot: [0.0, 0.0, 1.0],
            normal_axis: 2,
            normal_sign: 1.0,
            h_axis: 0,
            w_axis: 1,
            h: 0.2,
            w: 0.2,
            normal_overlap: 0.0,
            area: 0.04,
            centre_distance: 1.0,
        };
        (ba, bb, c)
    }

    /// A row whose strength is zero starts broken (disabled) with a positive threshold
    /// Bullet accepts; the others keep their impulse F·correction·h.
    #[test]
    fn a_zero_strength_row_starts_broken() {
        let s = RuinSettings::default();
        let (ba, bb, c) = stacked_columns();
        let f = ConnectionForces {
            compression_n: 3.0e6,
            tension_n: 0.0,
            shear_h_n: 1.0e5,
            shear_w_n: 0.0,
            bend_h_nm: 2.0e5,
            bend_w_nm: 2.0e5,
            plastic_n: Some(0.0),
            spring_stiffness: Some(1.0e6),
        };
        let specs = constraint_specs(&c, &ba, &bb, &ba.pose(), &bb.pose(), &f, &s);
        assert_eq!(specs.len(), 7);
        let dt = s.substep();
        for (spec, force) in specs.iter().zip([3.0e6, 0.0, 1.0e5, 0.0]) {
            assert_eq!(spec.enabled, force > 0.0, "{:?}", spec.role);
            assert_eq!(spec.no_strength, force == 0.0, "{:?}", spec.role);
            assert!(spec.breaking_impulse > 0.0, "{:?}", spec.role);
            if force > 0.0 {
                assert_eq!(spec.breaking_impulse, force * s.linear_correction * dt);
            }
        }
        assert!(specs[6].breaking_impulse > 0.0 && !specs[6].enabled);
        // An elastic start keeps the zero-strength rows off.
        let mut conn = ConnectionSpec {
            a: 0,
            b: 1,
            contact: c,
            group: "1".into(),
            forces: f,
            tolerances: ResolvedTolerances {
                dist1: None,
                rot1: None,
                dist2: None,
                rot2: None,
            },
            spring_length: 1.0,
            disable_collisions: true,
            constraints: specs,
            lost_at_start: false,
            ductile: true,
        };
        conn.set_state(ConnectionState::Elastic);
        let on: Vec<bool> = conn.constraints.iter().map(|c| c.enabled).collect();
        assert_eq!(on, [true, false, true, false, true, true, false]);
    }

    /// The two-way axial row (`crate::ruin::axial`): both senses with strength → constraint 0
    /// locked at [0, 0] with the smaller breaking impulse, constraint 1 without locked
    /// axes; a sense without strength → BCB's two one-way rows (that sense starts broken).
    #[test]
    fn two_way_axial_row_or_bcb_rows_when_a_sense_has_no_strength() {
        let s = RuinSettings {
            axial_rows: crate::ruin::axial::AxialRows::TwoWay,
            ..RuinSettings::default()
        };
        let (ba, bb, c) = stacked_columns();
        let forces = |t: f64| ConnectionForces {
            compression_n: 3.0e6,
            tension_n: t,
            shear_h_n: 1.0e5,
            shear_w_n: 1.0e5,
            bend_h_nm: 2.0e5,
            bend_w_nm: 2.0e5,
            plastic_n: None,
            spring_stiffness: None,
        };
        let dt = s.substep();
        let two = constraint_specs(&c, &ba, &bb, &ba.pose(), &bb.pose(), &forces(5.0e5), &s);
        assert_eq!((two[0].lower[0], two[0].upper[0]), (0.0, 0.0));
        assert_eq!(two[0].breaking_impulse, 5.0e5 * s.linear_correction * dt);
        assert!((0..6).all(|i| two[1].is_free(i)) && two[1].enabled);
        let bcb = constraint_specs(&c, &ba, &bb, &ba.pose(), &bb.pose(), &forces(0.0), &s);
        assert_eq!((bcb[0].lower[0], bcb[0].upper[0]), (0.0, BCB_UNLIMITED));
        assert!(bcb[0].enabled && !bcb[1].enabled && bcb[1].no_strength);
    }

    /// FE-derived connections of two stacked pieces (docs/handoff.md §2.4, §2.6): two
    /// elastic panels are unbreakable (infinite strengths, no tolerances, no spring); a
    /// member cut by the contact against an elastic panel takes the member's values alone,
    /// against a group body the weaker of the member's and the group's; a ductile hinge
    /// holds to BCB's 2nd tolerances without a spring (`Rupture`) or hands over to BCB's
    /// spring at max(rotation left, tol1R) (`Spring`).
    #[test]
    fn elastic_panels_and_ductile_hinge_ends() {
        let (ba, bb, c) = stacked_columns();
        let bodies = [ba, bb];
        let poses: Vec<_> = bodies.iter().map(|b| b.pose()).collect();
        let groups = [GroupStrength::formula(
            "1",
            crate::ruin::strength::FormulaInputs::default(),
        )];
        let end = test_end();
        let col = BodyStrength {
            axes: [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            ends: [([0.0, 0.0, 0.0], end), ([0.0, 0.0, 1.0], end)],
        };
        let build = |caps: &[BodyCapacity], s: &RuinSettings| {
            build_connections_with(&bodies, &groups, &[c], &poses, s, caps)
                .unwrap()
                .remove(0)
        };
        let s = RuinSettings {
            hinge_end: HingeEnd::Rupture,
            ..RuinSettings::default()
        };
        let bcb = build(&[], &s);
        assert!(bcb.forces.compression_n.is_finite() && bcb.has_spring());

        let panels = build(&[BodyCapacity::Elastic, BodyCapacity::Elastic], &s);
        assert!(!panels.has_spring() && !panels.ductile);
        assert_eq!(panels.constraints.len(), 6);
        assert!(panels
            .constraints
            .iter()
            .all(|k| k.breaking_impulse == f64::INFINITY && k.enabled));
        assert_eq!(
            panels.tolerances,
            ResolvedTolerances {
                dist1: None,
                rot1: None,
                dist2: None,
                rot2: None
            }
        );

        let fe = col.forces_for(&c);
        let on_panel = build(
            &[
                BodyCapacity::Member(Box::new(col.clone())),
                BodyCapacity::Elastic,
            ],
            &s,
        );
        let got = on_panel.forces;
        assert_eq!(
            [
                got.compression_n,
                got.tension_n,
                got.shear_h_n,
                got.shear_w_n,
                got.bend_h_nm,
                got.bend_w_nm
            ],
            fe
        );
        // Rupture: the hinge holds to the 2nd tolerances, no spring.
        assert!(on_panel.ductile && !on_panel.has_spring());
        let t = on_panel.tolerances;
        assert_eq!((t.dist1, t.rot1), (t.dist2, t.rot2));
        assert!(t.rot2.unwrap() > 0.05);

        // A group partner limits too: the weaker of the member's and the group's value.
        let on_group = build(
            &[
                BodyCapacity::Member(Box::new(col.clone())),
                BodyCapacity::Group,
            ],
            &s,
        );
        assert_eq!(
            on_group.forces.compression_n,
            fe[0].min(bcb.forces.compression_n)
        );

        // Spring: BCB's spring after max(rotation left, tol1R).
        let spring = RuinSettings {
            hinge_end: HingeEnd::Spring,
            ..s
        };
        let to_spring = build(
            &[BodyCapacity::Member(Box::new(col)), BodyCapacity::Elastic],
            &spring,
        );
        assert!(to_spring.has_spring());
        assert_eq!(
            to_spring.tolerances.rot1,
            bcb.tolerances.rot1.map(|t1| t1.max(0.05))
        );
        assert_ne!(to_spring.tolerances.rot1, to_spring.tolerances.rot2);
    }
}
