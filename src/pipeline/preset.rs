//! Presets: a named value for every `[physics]` key ([`PhysicsSpec`]). A run starts from
//! its preset and the scenario's keys replace single values
//! ([`super::scenario::PhysicsTable::resolve`]).
//!
//! * `bcb`: the paper's physics engine settings, the ruin stage's own defaults
//!   ([`StageSettings::bcb`], each documented next to its type): BCB's Formula Assistant
//!   connections, 200 substeps/s × 100 iterations, BCB's one-way axial rows, connected
//!   pieces that never touch, no joint warm start. It keeps two plastic-spring stability
//!   fixes BCB lacks (`angular_spring = "lever"`, `spring_cap_per_body = true`,
//!   docs/scenario-format.md, "Plastic-spring stability"). The rigid-only default.
//! * `fem2rbd`: the hybrid default, `bcb` with the keys [`Preset::physics`] lists for it.

use super::scenario::{
    ConnectionModel, GroundDamping, JointRowsSpec, JointSolveSpec, Mode, PanelConnections,
    PhysicsSpec,
};
use crate::ruin::axial::AxialRows;
use crate::ruin::rest::RestTest;
use crate::ruin::separation::PairsTouch;
use crate::ruin::stage::{JointRows, StageSettings};
use serde::{Deserialize, Serialize};

/// A named set of `[physics]` values (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Preset {
    /// The paper's physics engine settings (BCB), the rigid-only default.
    Bcb,
    /// fem2rbd's hybrid default.
    Fem2rbd,
}

impl Preset {
    /// The name used in files.
    pub fn name(self) -> &'static str {
        match self {
            Preset::Bcb => "bcb",
            Preset::Fem2rbd => "fem2rbd",
        }
    }

    /// The preset of a run in `mode` that names none: `fem2rbd` for the hybrid and fe
    /// modes, `bcb` for the rigid-only mode (the paper's baseline).
    pub fn for_mode(mode: Mode) -> Preset {
        match mode {
            Mode::Rigid => Preset::Bcb,
            Mode::Hybrid | Mode::Fe => Preset::Fem2rbd,
        }
    }

    /// The preset built on the connection model `c`: `bcb` on BCB's Formula Assistant,
    /// `fem2rbd` on FE-derived strengths.
    pub fn for_connections(c: ConnectionModel) -> Preset {
        match c {
            ConnectionModel::Formula => Preset::Bcb,
            ConnectionModel::Fe => Preset::Fem2rbd,
        }
    }

    /// Every `[physics]` value of the preset.
    pub fn physics(self) -> PhysicsSpec {
        match self {
            Preset::Bcb => bcb(),
            // The hybrid default: the keys where it differs from `bcb`, and only here.
            Preset::Fem2rbd => PhysicsSpec {
                preset: Preset::Fem2rbd,
                // Strengths from the FE model's own sections (docs/handoff.md).
                connections: ConnectionModel::Fe,
                // One two-way axial row, broken in the sense it pushes (docs/handoff.md §4.1).
                axial_rows: AxialRows::TwoWay,
                // Pieces held only by a plastic spring touch (docs/ruin-numerics.md,
                // "Which bodies touch").
                connected_pairs_touch: PairsTouch::OnceYielded,
                // The base section carries the column, as in the FE (same section).
                ground_under_connected_bases: false,
                // With the two-way row the frame3 LC5 debris comes to rest in 6 of 8
                // ensemble members (docs/handoff.md §4.1).
                joint_warmstart: 0.5,
                // Four times BCB's Gauss–Seidel sweeps per second: the cheapest setting
                // whose frame3 LC5 ruin distribution is converged (docs/ruin-convergence.md
                // §5.2, docs/ruin-numerics.md, "The default's solver iterations").
                solver_iterations: 400,
                ..bcb()
            },
        }
    }
}

/// The `bcb` preset: the ruin stage's own defaults ([`StageSettings::bcb`]) read back,
/// and the values of the keys that configure the pipeline around the stage.
fn bcb() -> PhysicsSpec {
    let s = StageSettings::bcb();
    PhysicsSpec {
        preset: Preset::Bcb,
        steps_per_second: s.ruin.steps_per_second,
        solver_iterations: s.ruin.solver_iterations,
        friction: s.body.friction,
        restitution: s.body.restitution,
        linear_damping: s.body.linear_damping,
        angular_damping: s.body.angular_damping,
        spring_correction: s.ruin.spring_correction,
        linear_correction: s.ruin.linear_correction,
        bending_correction: s.ruin.bending_correction,
        spring_damping: s.ruin.spring_damping,
        spring_limit: s.ruin.spring_limit_if_needed,
        angular_spring: s.ruin.angular_spring,
        split_impulse: s.world.solver.split_impulse,
        split_impulse_threshold_m: s.world.solver.split_impulse_penetration_threshold,
        contact_erp: s.world.solver.erp2,
        joint_erp: s.world.solver.erp,
        // The ERPs hold at BCB's own rate, so at 200 substeps/s they are Bullet's per
        // substep and at any other rate they remove an error equally fast per second.
        erp_steps_per_second: s.ruin.steps_per_second,
        margin_m: s.body.margin,
        margin_max_share: s.body.margin_max_share,
        spring_rest_at_plastic_onset: s.plastic.spring_rest_at_onset,
        hinge_keeps_rotation: s.plastic.hinge_keeps_rotation,
        hinge_return_mapping: s.plastic.hinge_return_mapping,
        joint_rows: match s.joints.rows {
            JointRows::Locked => JointRowsSpec::Locked,
            JointRows::Member { .. } => JointRowsSpec::Member,
        },
        joint_modulus_pa: MEMBER_ROW_MODULUS_PA,
        joint_damping_ratio: 1.0,
        joint_warmstart: s.joints.warmstart,
        joint_iterations: s.joints.iterations,
        joint_solve: match s.joints.solve {
            crate::bullet::JointSolve::Pgs => JointSolveSpec::Pgs,
            crate::bullet::JointSolve::Direct => JointSolveSpec::Direct,
        },
        joint_solve_regularisation: s.joints.solve_regularisation,
        axial_rows: s.ruin.axial_rows,
        spring_cap_per_body: s.plastic.spring_cap_per_body,
        spring_cap_steps_per_second: s.plastic.spring_cap_steps_per_second,
        monitor_every_substep: s.monitor_every_substep,
        connected_pairs_touch: s.touch.pairs,
        ground_under_connected_bases: s.touch.ground_under_connected_bases,
        search_distance_m: s.ruin.search.search_distance,
        sleeping: !s.body.disable_deactivation,
        sweep: super::scenario::SweepSpec::of(s.speed.sweep),
        // Run to the record's end + 5 s, or until the debris is at rest.
        time_limit_s: None,
        settle_s: 5.0,
        stop_at_rest: true,
        rest: RestTest::default(),
        connections: ConnectionModel::Formula,
        panel_connections: PanelConnections::Group,
        hinge_end: s.ruin.hinge_end,
        joints: s.ruin.search.joints,
        ground_damping: GroundDamping::None,
    }
}

/// Young's modulus of `joint_rows = "member"`, Pa: frame3's Concrete02,
/// 2·f′c/ε_c0 = 2·22.5 MPa/0.0018 = 25 GPa.
const MEMBER_ROW_MODULUS_PA: f64 = 2.5e10;
