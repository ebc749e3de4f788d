//! A time and memory estimate of a run before it starts (printed before long
//! runs, `--estimate`, and the Slurm requests of studies), from the size of the work and per-unit costs. The time costs below were
//! measured with `scripts/measure-estimate.sh` (release build, CPU time), which
//! compares estimate against actual time and peak RSS (`docs/reliability.md`, "Time and
//! memory estimate").
//!
//! **Time** (s), release build:
//!
//! T = T₀ + T_FE + T_cap + T_ruin, with
//!
//! * T_FE = (n_FE + n_g + n_modal) · (k_fib · S_fib + k_sh · S_sh + k_dof · n_dof) — every
//!   FE step (n_FE = duration / Δt, the gravity load steps n_g and a modal analysis
//!   counted as [`MODAL_STEPS`] steps) costs in proportion to the fibre states
//!   S_fib = Σ over beam-columns of integration points × fibres, the shell layer points
//!   S_sh = Σ over shells of 4 Gauss points × layers (1 for a plate), and the DOFs
//!   n_dof = 6 × nodes (assembly and sparse solve);
//! * T_cap = p · k_cap · F_end — FE-derived connection strengths ([`crate::fe::capacity`]):
//!   p passes (1 at gravity, 2 in hybrid mode: gravity and Tc) of section pushes at the two
//!   end sections of every beam-column, F_end = Σ over beam-columns of 2 × the section's
//!   fibres;
//! * T_ruin = n_sub · (k_body · n_body + k_conn · n_conn · i_solver) — every Bullet
//!   substep costs in proportion to the bodies and to the connections times the solver
//!   iterations (each connection's constraint rows are visited once per iteration);
//! * T_rescue = k_cell · n_cell — the rescue analysis of the ruin (`crate::rescue`) over
//!   n_cell grid cells, estimated before the run from the building: its plan footprint
//!   L_x × L_y and height H (the undeformed active boxes) and the default cell h (0.1 m
//!   full scale, at the model's scale) with the grid's open-air pad p (the rescuer's
//!   width plus two cells), as the larger of a ruin spread by the planning rule's 2H/3 on
//!   every side (docs/rescue.md) with a pile of H/3,
//!   n = (L_x + 4H/3 + 2p)(L_y + 4H/3 + 2p)(H/3 + p)/h³, and the building left standing,
//!   n = (L_x + 2p)(L_y + 2p)(H + p)/h³; at most the grid's own bound
//!   ([`crate::rescue::grid::MAX_BYTES`] over [`crate::rescue::grid::BYTES_PER_CELL`]).
//!   Measured spreads, summed over both sides in x and y: 0.46 H and 1.24 H on frame3
//!   LC5, 1.57 H and 1.95 H on the library stand-in; piles 0.37 H and 0.33 H
//!   (docs/reliability.md, "Time and memory estimate");
//! * T₀ the process start and the model and record reading.
//!
//! A debug build (`cfg(debug_assertions)`) multiplies by [`DEBUG_FACTOR`]. The FE stage of
//! a hybrid run and a ruin stage that stops at rest take fewer steps than planned: the
//! estimate counts the planned steps, so it is an upper bound for them.
//!
//! **Peak memory** (bytes): M = M₀ + b_fib · S_fib + b_sh · S_sh + b_dof · n_dof +
//! 8 · (recorded values) + b_body · n_body + b_conn · n_conn, the recorded values being
//! the FE history the run keeps (`fe`: 6 per node per recorded step and the CSV text;
//! `run`: 25 keyframes/s of 7 pose values per body and 12 node-state values per node) and
//! the ground history (9 values per sample). The rescue analysis runs after the ruin
//! stage while the run's record is held, so its [`crate::rescue::grid::BYTES_PER_CELL`] ·
//! n_cell adds to the rest.
use crate::model::{ElementKind, Model, SectionKind};
use std::collections::BTreeMap;
use std::fmt;

/// Process start, model and record reading, s (`fem2rbd fe` of frame3 for one step).
pub const T0_S: f64 = 0.05;
/// FE cost per fibre state per step, s.
pub const K_FIB_S: f64 = 3.0e-7;
/// FE cost per shell layer point per step, s.
pub const K_SHELL_S: f64 = 7.0e-7;
/// FE cost per DOF per step, s.
pub const K_DOF_S: f64 = 1.0e-7;
/// A modal analysis counted as FE steps.
pub const MODAL_STEPS: f64 = 10.0;
/// Capacity pushes: cost per end-section fibre per pass, s.
pub const K_CAP_S: f64 = 1.0e-5;
/// Bullet cost per body per substep, s.
pub const K_BODY_S: f64 = 8.0e-6;
/// Bullet cost per connection per solver iteration per substep, s.
pub const K_CONN_S: f64 = 1.0e-7;
/// Rescue analysis cost per grid cell, s.
pub const K_CELL_S: f64 = 0.5e-6;
/// Debug build over release build, wall time.
pub const DEBUG_FACTOR: f64 = 3.0;

/// Baseline peak resident memory, bytes.
pub const M0_B: f64 = 20e6;
/// Bytes per fibre state (material history, section and element state).
pub const B_FIB: f64 = 200.0;
/// Bytes per shell layer point.
pub const B_SHELL: f64 = 400.0;
/// Bytes per DOF (sparse matrices, LU factors, vectors).
pub const B_DOF: f64 = 4000.0;
/// Bytes per rigid body (Bullet body, shape, broadphase proxy, records).
pub const B_BODY: f64 = 4000.0;
/// Bytes per connection (up to seven Bullet constraints and their specs).
pub const B_CONN: f64 = 8000.0;

/// The size of what a run computes on.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Size {
    /// Nodes.
    pub nodes: u64,
    /// DOFs (6 per node).
    pub dofs: u64,
    /// Elements (all kinds).
    pub elements: u64,
    /// Beam-column elements with a fibre or RC section.
    pub beam_columns: u64,
    /// Σ over beam-columns of integration points × fibres.
    pub fiber_states: u64,
    /// Σ over beam-columns of 2 × the section's fibres (the end sections the capacity
    /// pushes drive).
    pub end_section_fibers: u64,
    /// Σ over shells of 4 × layers (1 layer for a plate).
    pub shell_points: u64,
    /// Gravity load steps.
    pub gravity_steps: u64,
    /// Rigid bodies (active and passive).
    pub bodies: u64,
    /// Connections between bodies.
    pub connections: u64,
    /// Grid cells of the rescue analysis of the ruin (module docs; 0 without a ruin).
    pub rescue_cells: u64,
}

impl Size {
    /// The FE part of a model's size (bodies and connections 0).
    pub fn of_model(model: &Model) -> Size {
        let sections: BTreeMap<u32, &crate::model::Section> =
            model.sections.iter().map(|s| (s.tag, s)).collect();
        let mut s = Size {
            nodes: model.nodes.len() as u64,
            dofs: 6 * model.nodes.len() as u64,
            elements: model.elements.len() as u64,
            gravity_steps: u64::from(model.gravity.load_steps),
            ..Default::default()
        };
        for e in &model.elements {
            match &e.kind {
                ElementKind::BeamColumn {
                    points, section, ..
                } => {
                    let n = sections.get(section).map_or(0, |s| s.fiber_count());
                    if n > 0 {
                        s.beam_columns += 1;
                        s.fiber_states += u64::from(*points) * n;
                        s.end_section_fibers += 2 * n;
                    }
                }
                ElementKind::Shell { section, .. } => {
                    let layers = match sections.get(section).map(|s| &s.kind) {
                        Some(SectionKind::LayeredShell { layers, .. }) => layers.len() as u64,
                        _ => 1,
                    };
                    s.shell_points += 4 * layers;
                }
                _ => {}
            }
        }
        s
    }
}

/// The amount of work of a run.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Work {
    /// FE time steps (0 without an FE stage).
    pub fe_steps: u64,
    /// FE steps whose every node is recorded (`fem2rbd fe`: steps / `--every`; 0 for
    /// `run`, which keeps 25 frames per second instead).
    pub fe_recorded_steps: u64,
    /// Capacity passes (0: formula connections or no ruin stage; 1 physics; 2 hybrid).
    pub capacity_passes: u64,
    /// Bullet substeps (0 without a ruin stage).
    pub substeps: u64,
    /// Solver iterations per substep.
    pub solver_iterations: u64,
    /// Keyframes kept (25 per simulated second).
    pub frames: u64,
    /// Ground-history samples.
    pub ground_samples: u64,
}

/// A time and memory estimate (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Estimate {
    /// FE stage (with gravity and modal analysis), s.
    pub fe_s: f64,
    /// Capacity pushes, s.
    pub capacity_s: f64,
    /// Ruin stage, s.
    pub ruin_s: f64,
    /// Rescue analysis of the ruin, s.
    pub rescue_s: f64,
    /// Total wall time, s (one core; this build's profile).
    pub seconds: f64,
    /// Peak resident memory, bytes.
    pub peak_bytes: f64,
}

/// The estimate of `work` on `size` (module docs), for this build's profile.
pub fn estimate(size: &Size, work: &Work) -> Estimate {
    let s = size;
    let per_fe_step = K_FIB_S * s.fiber_states as f64
        + K_SHELL_S * s.shell_points as f64
        + K_DOF_S * s.dofs as f64;
    let fe_steps = if work.fe_steps > 0 || work.capacity_passes > 0 {
        work.fe_steps as f64 + s.gravity_steps as f64 + MODAL_STEPS
    } else {
        0.0
    };
    let fe_s = fe_steps * per_fe_step;
    let capacity_s = work.capacity_passes as f64 * K_CAP_S * s.end_section_fibers as f64;
    let ruin_s = work.substeps as f64
        * (K_BODY_S * s.bodies as f64
            + K_CONN_S * s.connections as f64 * work.solver_iterations as f64);
    let rescue_s = K_CELL_S * s.rescue_cells as f64;
    let factor = if cfg!(debug_assertions) {
        DEBUG_FACTOR
    } else {
        1.0
    };
    let recorded = work.fe_recorded_steps as f64 * s.nodes as f64 * 6.0 * (8.0 + 13.0)
        + work.frames as f64 * (7.0 * 8.0 * s.bodies as f64 + 12.0 * 8.0 * s.nodes as f64)
        + work.ground_samples as f64 * 9.0 * 8.0;
    let peak = M0_B
        + B_FIB * s.fiber_states as f64
        + B_SHELL * s.shell_points as f64
        + if fe_steps > 0.0 {
            B_DOF * s.dofs as f64
        } else {
            0.0
        }
        + if work.substeps > 0 {
            B_BODY * s.bodies as f64 + B_CONN * s.connections as f64
        } else {
            0.0
        }
        + recorded
        + crate::rescue::grid::BYTES_PER_CELL as f64 * s.rescue_cells as f64;
    Estimate {
        fe_s: fe_s * factor,
        capacity_s: capacity_s * factor,
        ruin_s: ruin_s * factor,
        rescue_s: rescue_s * factor,
        seconds: (T0_S + fe_s + capacity_s + ruin_s + rescue_s) * factor,
        peak_bytes: peak,
    }
}

/// A duration as `12 s`, `3.4 min`, `2.1 h`.
pub fn show_seconds(s: f64) -> String {
    if s < 90.0 {
        format!("{s:.0} s")
    } else if s < 5400.0 {
        format!("{:.1} min", s / 60.0)
    } else {
        format!("{:.1} h", s / 3600.0)
    }
}

/// Bytes as MiB or GiB.
pub fn show_bytes(b: f64) -> String {
    let mib = b / (1024.0 * 1024.0);
    if mib < 1024.0 {
        format!("{mib:.0} MiB")
    } else {
        format!("{:.1} GiB", mib / 1024.0)
    }
}

impl fmt::Display for Estimate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "about {} and {} peak memory",
            show_seconds(self.seconds),
            show_bytes(self.peak_bytes)
        )?;
        let mut parts = Vec::new();
        if self.fe_s > 0.0 {
            parts.push(format!("FE {}", show_seconds(self.fe_s)));
        }
        if self.capacity_s > 0.0 {
            parts.push(format!("capacities {}", show_seconds(self.capacity_s)));
        }
        if self.ruin_s > 0.0 {
            parts.push(format!("ruin stage {}", show_seconds(self.ruin_s)));
        }
        if self.rescue_s > 0.0 {
            parts.push(format!("rescue analysis {}", show_seconds(self.rescue_s)));
        }
        if !parts.is_empty() {
            write!(f, " ({})", parts.join(", "))?;
        }
        Ok(())
    }
}

/// Size, work and estimate of a scenario run (`fem2rbd run`, one study run): the model
/// and the records are read, the bodies mapped and their connections found (BCB's
/// search, as the ruin stage does), but nothing is simulated. Milliseconds for frame3.
pub fn for_scenario(
    sc: &crate::pipeline::Scenario,
) -> Result<(Size, Work, Estimate), crate::pipeline::PipelineError> {
    use crate::pipeline::{self, ConnectionModel, Mode, PipelineError};
    let model = Model::load(&sc.model).map_err(|error| PipelineError::Model {
        path: sc.model.clone(),
        error: Box::new(error),
    })?;
    let gm = pipeline::ground_motion(sc)?;
    let (fe_steps, substeps) = pipeline::check_budget(sc, &gm)?;
    let mut size = Size::of_model(&model);
    let mut capacity_passes = 0;
    if sc.mode != Mode::Fe {
        let map = crate::mapping::from_model(&model)
            .and_then(|input| {
                crate::mapping::map_to_boxes(&input, &crate::mapping::MapOptions::default())
            })
            .map_err(|error| PipelineError::Mapping {
                path: sc.model.clone(),
                error: Box::new(error),
            })?;
        let bodies = crate::mapping::foundation::bodies_of(&model, &map);
        let settings = pipeline::stage_settings(sc);
        let contacts =
            crate::ruin::search::find_contacts(&pipeline::geoms(&bodies), &settings.ruin.search)?;
        size.bodies = bodies.len() as u64;
        size.connections = contacts.len() as u64;
        size.rescue_cells = rescue_cells(&bodies, model.scale);
        if sc.physics.connections == ConnectionModel::Fe {
            capacity_passes = if sc.mode == Mode::Hybrid { 2 } else { 1 };
        }
    }
    // The keyframes span the whole timeline: the FE stage's (to Tc, or to its end when
    // the building stands — a hybrid run without collapse has no ruin stage) and the ruin
    // stage's up to its time limit.
    let fe_end = sc.duration.unwrap_or_else(|| gm.duration_s());
    let limit = match sc.mode {
        Mode::Fe => fe_end,
        Mode::Hybrid => fe_end.max(pipeline::time_limit(sc, &gm)),
        Mode::Rigid => pipeline::time_limit(sc, &gm),
    };
    let work = Work {
        fe_steps,
        fe_recorded_steps: 0,
        capacity_passes,
        substeps,
        solver_iterations: u64::from(sc.physics.solver_iterations),
        frames: (limit * pipeline::FRAME_RATE).ceil() as u64,
        ground_samples: (gm.duration_s() / sc.dt).ceil() as u64,
    };
    Ok((size, work, estimate(&size, &work)))
}

/// The rescue analysis' grid cells for the ruin of `bodies` (module docs: T_rescue) at
/// the model's `scale`.
pub fn rescue_cells(bodies: &[crate::body::Body], scale: f64) -> u64 {
    use crate::rescue::person::{DEFAULT_CELL_M, DEFAULT_RESCUER_M};
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for b in bodies.iter().filter(|b| !b.passive) {
        for c in crate::plan_geometry::corners(&b.pose0, b.half_extents) {
            for d in 0..3 {
                lo[d] = lo[d].min(c[d]);
                hi[d] = hi[d].max(c[d]);
            }
        }
    }
    if !(lo[0].is_finite() && hi[0].is_finite()) {
        return 0;
    }
    let h = DEFAULT_CELL_M * scale;
    let pad = DEFAULT_RESCUER_M * scale + 2.0 * h;
    let (lx, ly, height) = (hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
    let reach = 2.0 * height / 3.0;
    let spread =
        (lx + 2.0 * reach + 2.0 * pad) * (ly + 2.0 * reach + 2.0 * pad) * (height / 3.0 + pad);
    let standing = (lx + 2.0 * pad) * (ly + 2.0 * pad) * (height + pad);
    let cells = spread.max(standing) / (h * h * h);
    let bound = crate::rescue::grid::MAX_BYTES / crate::rescue::grid::BYTES_PER_CELL;
    (cells.ceil() as u64).min(bound)
}

/// Size, work and estimate of a JSON scene (`fem2rbd scene`): its bodies and constraints
/// (each constraint counted as a connection) over its substeps.
pub fn for_scene(scene: &crate::scene::Scene, frames_every: Option<u64>) -> (Size, Work, Estimate) {
    let size = Size {
        bodies: scene.bodies.len() as u64,
        connections: scene.constraints.len() as u64,
        ..Default::default()
    };
    let work = Work {
        substeps: scene.num_substeps,
        solver_iterations: u64::from(scene.world.solver.num_iterations),
        frames: frames_every.map_or(1, |k| scene.num_substeps / k.max(1) + 1),
        ..Default::default()
    };
    (size, work, estimate(&size, &work))
}

/// A one-line report of size, work and estimate (`--estimate`), `key=value` separated by
/// spaces: `seconds=… peak_mib=… fe_s=… capacity_s=… ruin_s=… rescue_s=… dofs=…
/// fiber_states=… shell_points=… bodies=… connections=… rescue_cells=… fe_steps=…
/// substeps=… iterations=…`.
pub fn report(size: &Size, work: &Work, e: &Estimate) -> String {
    format!(
        "seconds={:.3} peak_mib={:.1} fe_s={:.3} capacity_s={:.3} ruin_s={:.3} rescue_s={:.3} dofs={} fiber_states={} shell_points={} bodies={} connections={} rescue_cells={} fe_steps={} substeps={} iterations={}",
        e.seconds,
        e.peak_bytes / 1048576.0,
        e.fe_s,
        e.capacity_s,
        e.ruin_s,
        e.rescue_s,
        size.dofs,
        size.fiber_states,
        size.shell_points,
        size.bodies,
        size.connections,
        size.rescue_cells,
        work.fe_steps,
        work.substeps,
        work.solver_iterations
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::{Body, BodyId, BodyType, Role};
    use crate::bullet::Pose;

    fn column(x: f64, passive: bool) -> Body {
        Body {
            id: BodyId::element(BodyType::Column, "1", 1),
            kind: Some(Role::Column),
            half_extents: [0.5, 0.5, 1.5],
            pose0: Pose {
                position: [x, 0.0, 1.5],
                orientation: [1.0, 0.0, 0.0, 0.0],
            },
            mass_kg: if passive { 0.0 } else { 1000.0 },
            passive,
        }
    }

    #[test]
    fn rescue_cells_of_one_column_spread_by_two_thirds_of_its_height() {
        // 1 × 1 × 3 m at full scale: h = 0.1 m, pad = 0.6 + 0.2 = 0.8 m; spread by 2 m on
        // each side, (1 + 4 + 1.6)² · (1 + 0.8) = 78.408 m³, beats standing
        // 2.6² · 3.8 = 25.688 m³.
        // A passive box 100 m away does not widen it.
        let bodies = [column(0.0, false), column(100.0, true)];
        assert_eq!(rescue_cells(&bodies, 1.0), 78_408);
        // At scale 1/4 every length and the cell shrink alike: the same cells.
        let quarter = Body {
            half_extents: [0.125, 0.125, 0.375],
            pose0: Pose {
                position: [0.0, 0.0, 0.375],
                orientation: [1.0, 0.0, 0.0, 0.0],
            },
            ..column(0.0, false)
        };
        assert_eq!(rescue_cells(&[quarter], 0.25), 78_408);
        assert_eq!(rescue_cells(&[column(0.0, true)], 1.0), 0);
    }

    #[test]
    fn a_tall_mast_spreads_and_a_wide_low_block_stands() {
        let block = |he: [f64; 3]| Body {
            half_extents: he,
            pose0: Pose {
                position: [0.0, 0.0, he[2]],
                orientation: [1.0, 0.0, 0.0, 0.0],
            },
            ..column(0.0, false)
        };
        // 0.4 × 0.4 × 30 m: spread 42² · 10.8 = 19 051.2 m³, standing 2.0² · 30.8 = 123.2 m³.
        assert_eq!(rescue_cells(&[block([0.2, 0.2, 15.0])], 1.0), 19_051_200);
        // 100 × 100 × 3 m: standing 101.6² · 3.8 = 39 225.728 m³, spread 105.6² · 1.8
        // = 20 072.448 m³.
        assert_eq!(rescue_cells(&[block([50.0, 50.0, 1.5])], 1.0), 39_225_728);
    }

    #[test]
    fn the_rescue_analysis_adds_its_cells_to_time_and_memory() {
        let size = Size {
            rescue_cells: 1_000_000,
            ..Default::default()
        };
        let e = estimate(&size, &Work::default());
        let factor = if cfg!(debug_assertions) {
            DEBUG_FACTOR
        } else {
            1.0
        };
        assert!((e.rescue_s - K_CELL_S * 1e6 * factor).abs() < 1e-12);
        assert!((e.seconds - (T0_S + K_CELL_S * 1e6) * factor).abs() < 1e-9);
        assert_eq!(
            e.peak_bytes,
            M0_B + crate::rescue::grid::BYTES_PER_CELL as f64 * 1e6
        );
    }
}
