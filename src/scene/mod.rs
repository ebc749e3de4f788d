//! Scene runner: a small JSON scene description → Bullet world → poses CSV
//! (`fem2rbd scene scene.json --out poses.csv [--frames N]`). It is the interface of the
//! pybullet cross-checks (`tests/pybullet/`); examples are in `data/scenes/`.
//!
//! # Scene format
//!
//! ```json
//! {
//!   "world": {
//!     "preset": "pybullet",
//!     "gravity": [0, 0, -9.81],
//!     "solver": { "num_iterations": 50 },
//!     "dbvt_margin": 0.0,
//!     "contact_breaking_threshold": 0.02,
//!     "default_margin": 0.001
//!   },
//!   "duration": 2.0,
//!   "substeps_per_second": 240,
//!   "bodies": [
//!     { "name": "ground", "half_extents": [10, 10, 0.5], "mass": 0,
//!       "position": [0, 0, -0.5], "friction": 1.0 },
//!     { "name": "box", "half_extents": [0.5, 0.5, 0.5], "mass": 1,
//!       "position": [0, 0, 1.5], "orientation": [1, 0, 0, 0],
//!       "linear_velocity": [0, 0, 0], "angular_velocity": [0, 0, 0],
//!       "friction": 0.5, "restitution": 0, "linear_damping": 0, "angular_damping": 0 }
//!   ],
//!   "constraints": [
//!     { "kind": "spring2", "body_a": "ground", "body_b": "box",
//!       "frame_a": { "position": [0, 0, 1] }, "frame_b": { "position": [0, 0, 0] },
//!       "limits": [[0, 0], [0, 0], [1, -1], [0, 0], [0, 0], [0, 0]],
//!       "springs": [null, null, {"stiffness": 1000, "damping": 20}, null, null, null],
//!       "breaking_impulse_threshold": 5.0 }
//!   ]
//! }
//! ```
//!
//! * **world** (optional). `preset`: `"bullet"` (default: Bullet 3.24's own
//!   `btContactSolverInfo` — 10 iterations, ERP 0.2, contact ERP 0.2, split impulse on at
//!   −0.04 m, solver mode 260, warm starting 0.85, batch size 128 — with gDbvtMargin 0.05,
//!   gContactBreakingThreshold 0.02, box margin 0.04) or `"pybullet"` (pybullet 3.2.7 for
//!   plain rigid bodies, `docs/bullet-ffi.md` §3.3: 50 iterations, contact ERP
//!   0.08, slop 1e-5, warm starting 0.1, residual threshold 1e-7, batch size 0, solver mode
//!   276 = warm starting | SIMD | two friction directions, gDbvtMargin 0, box margin 0.001).
//!   `gravity` [m/s²] defaults to (0, 0, −9.81) (z up). `solver` overrides any field of
//!   [`crate::bullet::SolverSettings`] by name. `dbvt_margin` and
//!   `contact_breaking_threshold` \[m\] are Bullet's **process-global** variables.
//!   `default_margin` \[m\] is every body's collision margin unless it gives its own.
//! * **duration** \[s\] and exactly one of **substep** \[s\] or **substeps_per_second**: the
//!   world is stepped by `stepSimulation(h, 0)` per substep; the duration must be a whole
//!   number of substeps (to 1e-9) — time is never dropped.
//! * **bodies**: boxes, created in order. `name` (unique), `half_extents` \[m\] (outer, > 0),
//!   `mass` \[kg\] (0 = static; with `"kinematic": true` a kinematic body), `position` \[m\],
//!   optional `orientation` (unit quaternion w, x, y, z), `linear_velocity` [m/s],
//!   `angular_velocity` [rad/s] (dynamic bodies only), `friction` (0.5), `rolling_friction`
//!   (0), `spinning_friction` (0), `restitution` (0), `linear_damping`, `angular_damping`
//!   (0, in [0, 1]), `margin`, `disable_deactivation` (true). Bullet combines friction of
//!   two bodies as the product. A kinematic body may have `"motion": {"linear_velocity",
//!   "angular_velocity"}`: its pose is set before every substep to (p0 + v·t, rot(ω·t)·q0)
//!   and Bullet derives its velocity from the change, which its contacts feel.
//! * **constraints** (optional), created after the bodies: `kind` `"generic6dof"`
//!   (btGeneric6DofConstraint; `use_linear_reference_frame_a`, default true), `"spring2"`
//!   (btGeneric6DofSpring2Constraint; `springs`: six entries `null` or
//!   `{"stiffness", "damping", "limit_if_needed"}`, Bullet's auto-limiting off unless
//!   `limit_if_needed` is true; `set_equilibrium_point`
//!   default true) or `"fixed"` (btFixedConstraint). `body_a`, `body_b`: body names.
//!   `frame_a`, `frame_b`: the joint frame in each body's local frame (`position`, optional
//!   `orientation`). `limits`: six entries (x, y, z \[m\], rx, ry, rz \[rad\]) `null` (class
//!   default) or `[lower, upper]` (lower > upper frees the axis, equal locks it).
//!   `breaking_impulse_threshold` [N·s per substep] (absent = unbreakable),
//!   `disable_collisions_between` (true), `enabled` (true), `override_solver_iterations`.
//!
//! * **name**, **description** (optional strings): what the scene is, for the reader;
//!   the simulation does not use them.
//!
//! Values outside their plausible ranges and bodies that start inside each other are
//! refused unless `--allow-unusual` is given ([`plausibility`]).
//!
//! Unknown fields are errors. Errors name the line (syntax, unknown field, bad type) or
//! the item (`body 3 "slab" (line 20)`, `constraint 1 (line 41)`).
//!
//! # Output
//!
//! CSV with header [`CSV_HEADER`]: one row per body (scene order) with the substep index,
//! time \[s\], name, position \[m\], quaternion (w, x, y, z), linear [m/s] and angular [rad/s]
//! velocity — for the final substep, or with `--frames N` for substeps 0, N, 2N, … and the
//! last. Reals are printed as `{:.17e}`, exact for every f64: same input, same bytes.
pub mod assemble;
pub mod format;
pub mod locate;
pub mod plausibility;
pub mod run;

pub use assemble::{BuiltScene, KinematicMotion, Scene, SceneConstraint};
pub use run::{run_scene, run_scene_file, CSV_HEADER};

use std::path::PathBuf;

/// A scene that cannot be read, validated, built or run. Messages name the file, the
/// line and the item (body name, constraint index).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The scene file cannot be read (missing, not a file, too large, unreadable).
    #[error(transparent)]
    File(#[from] crate::model::limits::InputFileError),
    /// An error inside a scene file, under the file's name.
    #[error("scene file {}: {error}", path.display())]
    InFile {
        /// The scene file.
        path: PathBuf,
        /// The error.
        error: Box<SceneError>,
    },
    /// JSON that does not parse or does not follow the format (with its line).
    #[error("{0}")]
    Syntax(String),
    /// A value or reference that breaks a rule of the format; names the item and line.
    #[error("{0}")]
    Invalid(String),
    /// A count over its resource bound (`docs/reliability.md`).
    #[error(transparent)]
    Limit(#[from] crate::model::limits::LimitError),
    /// Bullet refused a body or constraint of the scene.
    #[error("{item}: {error}")]
    Physics {
        /// "the Bullet world", a body or a constraint.
        item: String,
        /// Bullet's error.
        error: crate::bullet::PhysicsError,
    },
    /// Stepping the world or reading its state failed.
    #[error(transparent)]
    Step(#[from] crate::bullet::PhysicsError),
    /// Values outside their plausible ranges or bodies that start inside each other
    /// ([`plausibility`]), without `--allow-unusual`.
    #[error(
        "scene file {}: {} implausible value(s) or start overlap(s) (docs/reliability.md):\n  {}\n\
         If they are meant, run again with --allow-unusual.",
        path.display(),
        findings.len(),
        findings.join("\n  ")
    )]
    Unusual {
        /// The scene file.
        path: PathBuf,
        /// One line per finding.
        findings: Vec<String>,
    },
    /// Options of the run (`--frames`).
    #[error("{0}")]
    Options(String),
    /// The output cannot be written.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
    /// Writing the poses CSV failed.
    #[error("cannot write the poses: {0}")]
    Write(#[from] std::io::Error),
    /// An error while running a scene file, under the file's name.
    #[error("running scene {}: {error}", path.display())]
    Run {
        /// The scene file.
        path: PathBuf,
        /// The error.
        error: Box<SceneError>,
    },
}
