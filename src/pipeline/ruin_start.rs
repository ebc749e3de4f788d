//! The ruin stage's start state taken from the FE stage: the connections' strengths and
//! start damage, and an ensemble member's perturbation of the hand-off velocities.
//!
//! * **FE-derived connections** (`[physics] connections = "fe"`, the hybrid default;
//!   [`super::strengths`], docs/handoff.md): every connection starts elastic with the
//!   members' capacities at their gravity axial loads ([`gravity_strengths`]); at Tc with
//!   the residual capacities against those loads, and broken only where a wall body's
//!   shell lost its load path ([`damage_at_tc`]).
//! * **BCB's Formula-Assistant connections** (`"formula"`): the strengths per group, and a
//!   connection's damage at Tc is the worse of the FE damage flags of the two elements it
//!   joins (ruptured → broken, yielded → plastic, else elastic; panels and foundations
//!   count as intact; [`crate::ruin::monitor::start_state_from_damage`]).

use super::error::Result;
use super::{ensemble::Perturbation, Scenario};
use super::{scenario, strengths, ConnectionModel, FeStageOutput, Inputs, Mode, PipelineError};
use crate::body::Body;
use crate::bullet::Velocity;
use crate::fe::build::BuiltDomain;
use crate::fe::capacity::{
    gravity_capacities_of, member_capacities_against, AxialLoads, MemberCapacity, PushSettings,
};
use crate::model::{ElementKind, Model};
use crate::ruin::monitor::FeDamage;
use crate::ruin::stage::StageInput;
use std::collections::{BTreeMap, BTreeSet};

/// How the connections start, resolved once from the scenario.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ConnectionStart {
    /// FE-derived strengths: `connections = "fe"` in a mode with a ruin stage.
    pub fe_strengths: bool,
    /// The slab panels' connections stay elastic (`panel_connections = "elastic"`).
    pub elastic_panels: bool,
}

impl ConnectionStart {
    /// The connection start of scenario `sc`.
    pub(crate) fn of(sc: &Scenario) -> Self {
        ConnectionStart {
            fe_strengths: sc.mode != Mode::Fe && sc.physics.connections == ConnectionModel::Fe,
            elastic_panels: sc.physics.panel_connections == scenario::PanelConnections::Elastic,
        }
    }
}

/// The FE-derived strengths at gravity, kept for the residual capacities at Tc.
pub(crate) struct FeStrengths {
    /// Gravity axial loads, by element.
    pub gravity_n: AxialLoads,
    /// Undamaged capacities at them, by element.
    pub gravity_caps: BTreeMap<u32, MemberCapacity>,
}

/// With FE-derived connections, the members' capacities at their gravity axial loads in
/// the built domain `built` (after gravity), set as the bodies' strengths of `start`;
/// `None` (and `start` unchanged) with BCB's connections.
pub(crate) fn gravity_strengths(
    settings: ConnectionStart,
    model: &Model,
    built: &BuiltDomain,
    bodies: &[Body],
    start: &mut StageInput,
) -> Result<Option<FeStrengths>> {
    if !settings.fe_strengths {
        return Ok(None);
    }
    let (loads, caps) =
        gravity_capacities_of(model, built, &PushSettings::default()).map_err(|error| {
            PipelineError::Fe {
                stage: "FE-derived connection strengths",
                error: Box::new(error),
            }
        })?;
    start.body_strengths = strengths::body_strengths(model, bodies, &caps, settings.elastic_panels);
    Ok(Some(FeStrengths {
        gravity_n: loads,
        gravity_caps: caps,
    }))
}

/// The connections' state at Tc from the FE stage's end `fe`: with FE-derived strengths
/// (`gravity`), the residual capacities against the gravity loads and broken connections
/// only where a wall's shell lost its load path; with BCB's, the pairs' FE damage.
pub(crate) fn damage_at_tc(
    settings: ConnectionStart,
    inputs: &Inputs,
    fe: &FeStageOutput,
    gravity: Option<&FeStrengths>,
    start: &mut StageInput,
) -> Result<()> {
    let (model, bodies) = (&inputs.model, &inputs.bodies);
    let Some(g) = gravity else {
        start.start_damage = pair_damage(bodies, &element_damage(model, &fe.built));
        return Ok(());
    };
    // Residual capacities at Tc; broken only where the load path is lost.
    let caps = member_capacities_against(
        model,
        &fe.built,
        &g.gravity_n,
        &PushSettings::default(),
        Some(&g.gravity_caps),
    )
    .map_err(|error| PipelineError::Fe {
        stage: "FE-derived connection strengths at Tc",
        error: Box::new(error),
    })?;
    start.body_strengths = strengths::body_strengths(model, bodies, &caps, settings.elastic_panels);
    // Walls have no member-end capacities: a wall body's connections start broken only
    // where its shell lost its load path (docs/handoff.md §3).
    let shell_tags: BTreeSet<u32> = model
        .elements
        .iter()
        .filter(|e| matches!(e.kind, ElementKind::Shell { .. }))
        .map(|e| e.tag)
        .collect();
    let mut lost = element_damage(model, &fe.built);
    lost.retain(|tag, d| *d == FeDamage::Ruptured && shell_tags.contains(tag));
    start.start_damage = pair_damage(bodies, &lost);
    Ok(())
}

/// An ensemble member's hand-off: each mapped body's linear velocity component d gets
/// `velocity_mps × u`, u the member's uniform draw for (body, d) in [−1, 1].
pub(crate) fn perturb_velocities(p: &Perturbation, velocities: &mut [Velocity], mapped: usize) {
    for (i, v) in velocities.iter_mut().enumerate().take(mapped) {
        for (d, x) in v.linear.iter_mut().enumerate() {
            *x += p.velocity_mps * p.uniform(2, (3 * i + d) as u64);
        }
    }
}
/// FE damage per body → per connected pair (BCB's Formula-Assistant connections): the
/// worse of the two bodies' element flags; intact pairs are left out.
fn pair_damage(
    bodies: &[Body],
    damage: &BTreeMap<u32, FeDamage>,
) -> BTreeMap<(usize, usize), FeDamage> {
    let body_damage: Vec<FeDamage> = bodies
        .iter()
        .map(|b| {
            b.id.element_tag()
                .and_then(|e| damage.get(&e).copied())
                .unwrap_or(FeDamage::Intact)
        })
        .collect();
    let mut out = BTreeMap::new();
    for a in 0..bodies.len() {
        for b in a + 1..bodies.len() {
            let d = body_damage[a].max(body_damage[b]);
            if d != FeDamage::Intact {
                out.insert((a, b), d);
            }
        }
    }
    out
}

/// FE damage of every beam-column and shell element (model tag → flag) in a built
/// domain (a shell is "ruptured" only when it lost its load path:
/// [`crate::fe::shell::layers::LayeredSection::load_path_lost`]).
fn element_damage(model: &Model, built: &crate::fe::build::BuiltDomain) -> BTreeMap<u32, FeDamage> {
    let mut out = BTreeMap::new();
    for e in &model.elements {
        if !matches!(
            e.kind,
            ElementKind::BeamColumn { .. } | ElementKind::Shell { .. }
        ) {
            continue;
        }
        if let Some(&i) = built.element_index.get(&e.tag) {
            let d = built.domain.elements()[i].damage();
            let f = if d.ruptured {
                FeDamage::Ruptured
            } else if d.yielded {
                FeDamage::Yielded
            } else {
                FeDamage::Intact
            };
            out.insert(e.tag, f);
        }
    }
    out
}
