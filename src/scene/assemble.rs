//! Validates a parsed scene file and turns it into a [`Scene`] (physics descriptions with
//! every default filled in), then into a [`World`].
use super::format::*;
use super::locate::{array_element_lines, ArrayLines};
use super::SceneError;
use crate::bullet::{
    BodyHandle, BodyKind, BoxDesc, ConstraintDesc, ConstraintHandle, ConstraintKind, Pose,
    SolverSettings, Spring, Velocity, World, WorldSettings,
};

/// What reading and building a scene returns.
type Result<T> = std::result::Result<T, SceneError>;

macro_rules! bail {
    ($($t:tt)*) => {
        return Err(SceneError::Invalid(format!($($t)*)))
    };
}
use std::collections::BTreeMap;
use std::path::Path;

/// A constraint of a validated scene (bodies by index into [`Scene::bodies`]).
#[derive(Clone, Debug, PartialEq)]
pub struct SceneConstraint {
    /// The constraint class and its class-specific settings.
    pub kind: ConstraintKind,
    /// Body A, by index into [`Scene::bodies`].
    pub body_a: usize,
    /// Body B, by index into [`Scene::bodies`] (not `body_a`).
    pub body_b: usize,
    /// The joint frame in body A's local frame.
    pub frame_a: Pose,
    /// The joint frame in body B's local frame.
    pub frame_b: Pose,
    /// Per-axis limits (0..2 linear \[m\], 3..5 angular \[rad\]); `None` keeps the class
    /// default (see [`ConstraintDesc::limits`]).
    pub limits: [Option<(f64, f64)>; 6],
    /// Breaking impulse threshold [N·s] per substep; `f64::INFINITY` = unbreakable.
    pub breaking_impulse_threshold: f64,
    /// No contacts between the two bodies.
    pub disable_collisions_between: bool,
    /// Initially enabled.
    pub enabled: bool,
    /// Solver iterations for this constraint; `None` = the world's iteration count.
    pub override_solver_iterations: Option<u32>,
}

/// A kinematic body moving at constant velocity (see [`KinematicMotion::pose_at`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KinematicMotion {
    /// Index into [`Scene::bodies`].
    pub body: usize,
    /// Its pose at t = 0.
    pub start: Pose,
    /// Constant linear [m/s] and angular [rad/s] velocity, world frame.
    pub velocity: Velocity,
}

impl KinematicMotion {
    /// The pose at time t \[s\]: position p0 + v·t; orientation q(ω·t)·q0, where q(θ) is the
    /// rotation by |θ| about θ/|θ| (exact for constant ω).
    pub fn pose_at(&self, t: f64) -> Pose {
        let p0 = self.start.position;
        let v = self.velocity.linear;
        let th = self.velocity.angular.map(|w| w * t);
        let angle = (th[0] * th[0] + th[1] * th[1] + th[2] * th[2]).sqrt();
        let q0 = self.start.orientation;
        let orientation = if angle == 0.0 {
            q0
        } else {
            let (s, c) = (0.5 * angle).sin_cos();
            let r = [c, s * th[0] / angle, s * th[1] / angle, s * th[2] / angle];
            quat_mul(r, q0)
        };
        Pose {
            position: [p0[0] + v[0] * t, p0[1] + v[1] * t, p0[2] + v[2] * t],
            orientation,
        }
    }
}

/// Hamilton product a·b of quaternions (w, x, y, z).
fn quat_mul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// A validated scene, ready to build.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// World and solver settings: the preset with the scene's overrides applied.
    pub world: WorldSettings,
    /// The fixed substep h \[s\].
    pub substep: f64,
    /// duration / h, whole.
    pub num_substeps: u64,
    /// (name, description), in creation order.
    pub bodies: Vec<(String, BoxDesc)>,
    /// Constraints, in creation order (after the bodies).
    pub constraints: Vec<SceneConstraint>,
    /// Kinematic bodies that move, in body order.
    pub kinematic_motions: Vec<KinematicMotion>,
    /// The line of the scene file where each body starts (0 when not known), for
    /// messages.
    pub body_lines: Vec<usize>,
}

/// A world built from a scene, with the handles in scene order.
pub struct BuiltScene {
    /// The Bullet world holding the scene's bodies and constraints.
    pub world: World,
    /// Body handles; entry i is [`Scene::bodies`]\[i\].
    pub bodies: Vec<BodyHandle>,
    /// Constraint handles; entry i is [`Scene::constraints`]\[i\].
    pub constraints: Vec<ConstraintHandle>,
}

/// Where an item sits, for error messages: `body "box3" (line 14)`.
struct Locator {
    bodies: ArrayLines,
    constraints: ArrayLines,
}

impl Locator {
    fn body(&self, i: usize, name: &str) -> String {
        match self.bodies.starts.get(i) {
            Some(l) => format!("body {i} \"{name}\" (line {l})"),
            None => format!("body {i} \"{name}\""),
        }
    }
    /// ` (in body 2, which starts on line 14)` for a line inside an array element.
    fn enclosing(&self, line: usize) -> String {
        for (what, lines) in [("body", &self.bodies), ("constraint", &self.constraints)] {
            if let Some(i) = lines.element_at(line) {
                return format!(" (in {what} {i}, which starts on line {})", lines.starts[i]);
            }
        }
        String::new()
    }

    fn constraint(&self, i: usize) -> String {
        match self.constraints.starts.get(i) {
            Some(l) => format!("constraint {i} (line {l})"),
            None => format!("constraint {i}"),
        }
    }
}

impl Scene {
    /// Reads and validates a scene file.
    pub fn load(path: &Path) -> Result<Scene> {
        let text = crate::model::limits::read_input_file(path, "scene file")?;
        Scene::from_json(&text).map_err(|e| SceneError::InFile {
            path: path.to_path_buf(),
            error: Box::new(e),
        })
    }

    /// Parses and validates scene JSON. Errors name the line (syntax, unknown fields) or
    /// the item (body name / constraint index and its line).
    pub fn from_json(text: &str) -> Result<Scene> {
        let loc = Locator {
            bodies: array_element_lines(text, "bodies"),
            constraints: array_element_lines(text, "constraints"),
        };
        let file: SceneFile = serde_json::from_str(text).map_err(|e| {
            let hint = non_finite_hint(text, &e);
            let within = loc.enclosing(e.line());
            SceneError::Syntax(format!("{e}{within}{hint}"))
        })?;
        validate(&file, &loc)
    }

    /// Body i as messages name it: `body 3 "slab" (line 20)`.
    pub fn body_label(&self, i: usize) -> String {
        let name = self.bodies.get(i).map_or("", |(n, _)| n.as_str());
        match self.body_lines.get(i).copied().unwrap_or(0) {
            0 => format!("body {i} \"{name}\""),
            l => format!("body {i} \"{name}\" (line {l})"),
        }
    }

    /// Every value outside its plausible range and every pair of bodies that start
    /// inside each other ([`super::plausibility`]), as message lines; empty for a
    /// plausible scene.
    pub fn unusual(&self) -> Vec<String> {
        let label = |i: usize| self.body_label(i);
        super::plausibility::unusual(self, &label)
            .iter()
            .map(|f| f.message(&label))
            .collect()
    }

    /// Creates the world, the bodies and the constraints.
    pub fn build(&self) -> Result<BuiltScene> {
        let mut world = World::new(&self.world).map_err(|error| SceneError::Physics {
            item: "cannot create the Bullet world".into(),
            error,
        })?;
        let mut bodies = Vec::with_capacity(self.bodies.len());
        for (name, d) in &self.bodies {
            bodies.push(world.add_box(d).map_err(|error| SceneError::Physics {
                item: format!("body \"{name}\""),
                error,
            })?);
        }
        let mut constraints = Vec::with_capacity(self.constraints.len());
        for (i, c) in self.constraints.iter().enumerate() {
            let desc = ConstraintDesc {
                kind: c.kind,
                body_a: bodies[c.body_a],
                body_b: bodies[c.body_b],
                frame_a: c.frame_a,
                frame_b: c.frame_b,
                limits: c.limits,
                breaking_impulse_threshold: c.breaking_impulse_threshold,
                disable_collisions_between: c.disable_collisions_between,
                enabled: c.enabled,
                override_solver_iterations: c.override_solver_iterations,
            };
            constraints.push(
                world
                    .add_constraint(&desc)
                    .map_err(|error| SceneError::Physics {
                        item: format!("constraint {i}"),
                        error,
                    })?,
            );
        }
        Ok(BuiltScene {
            world,
            bodies,
            constraints,
        })
    }
}

/// JSON has no NaN or infinity; say so when the parser stopped at one.
fn non_finite_hint(text: &str, e: &serde_json::Error) -> &'static str {
    let Some(line) = text.lines().nth(e.line().saturating_sub(1)) else {
        return "";
    };
    // serde_json's column counts bytes; widen the window to char boundaries (a
    // multi-byte character next to the error must not split: found by the property
    // test in tests/it/cli/hostile_inputs.rs).
    let col = e.column().saturating_sub(1).min(line.len());
    let (mut a, mut b) = (col.saturating_sub(12), (col + 12).min(line.len()));
    while !line.is_char_boundary(a) {
        a -= 1;
    }
    while !line.is_char_boundary(b) {
        b += 1;
    }
    let around = &line[a..b];
    if ["NaN", "nan", "Infinity", "inf"]
        .iter()
        .any(|w| around.contains(w))
    {
        " (numbers must be finite: JSON has no NaN or Infinity)"
    } else {
        ""
    }
}

fn finite(v: &[f64], what: &str, item: &dyn Fn() -> String) -> Result<()> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        bail!("{}: {what} {v:?} is not finite", item())
    }
}

fn unit_quaternion(q: [f64; 4], what: &str, item: &dyn Fn() -> String) -> Result<[f64; 4]> {
    finite(&q, what, item)?;
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    if (n - 1.0).abs() > 1e-6 {
        bail!(
            "{}: {what} {q:?} is not a unit quaternion (|q| = {n}; give (w, x, y, z) with |q| = 1 to 1e-6)",
            item()
        );
    }
    Ok(q)
}

fn nonneg(v: f64, what: &str, item: &dyn Fn() -> String) -> Result<f64> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        bail!("{}: {what} {v} must be finite and >= 0", item())
    }
}

fn solver_settings(preset: &SolverSettings, s: &SolverSpec) -> SolverSettings {
    let mut out = preset.clone();
    macro_rules! over {
        ($($f:ident),*) => { $( if let Some(v) = s.$f { out.$f = v; } )* };
    }
    over!(
        num_iterations,
        erp,
        erp2,
        friction_erp,
        global_cfm,
        linear_slop,
        split_impulse,
        split_impulse_penetration_threshold,
        split_impulse_turn_erp,
        solver_mode,
        warmstarting_factor,
        least_squares_residual_threshold,
        minimum_solver_batch_size,
        restitution_velocity_threshold,
        max_error_reduction,
        sor,
        damping
    );
    out
}

fn validate(f: &SceneFile, loc: &Locator) -> Result<Scene> {
    // World: preset, then overrides.
    let (mut world, default_margin) = match f.world.preset.unwrap_or_default() {
        // Bullet's defaults; the process-globals are set to Bullet's values explicitly so a
        // scene never depends on what ran before it in the same process.
        Preset::Bullet => (
            WorldSettings {
                dbvt_margin: Some(0.05),
                contact_breaking_threshold: Some(0.02),
                ..WorldSettings::default()
            },
            0.04,
        ),
        Preset::Pybullet => (WorldSettings::pybullet(), 0.001),
    };
    let world_item = || "world".to_string();
    if let Some(g) = f.world.gravity {
        finite(&g, "gravity", &world_item)?;
        world.gravity = g;
    }
    if let Some(m) = f.world.dbvt_margin {
        world.dbvt_margin = Some(nonneg(m, "dbvt_margin", &world_item)?);
    }
    if let Some(t) = f.world.contact_breaking_threshold {
        if !(t.is_finite() && t > 0.0) {
            bail!("world: contact_breaking_threshold {t} must be finite and > 0");
        }
        world.contact_breaking_threshold = Some(t);
    }
    world.solver = solver_settings(&world.solver, &f.world.solver);
    if world.solver.num_iterations == 0 {
        bail!("world.solver: num_iterations must be >= 1");
    }
    let default_margin = match f.world.default_margin {
        Some(m) => nonneg(m, "default_margin", &world_item)?,
        None => default_margin,
    };

    // Time.
    let substep = match (f.substep, f.substeps_per_second) {
        (Some(h), None) => h,
        (None, Some(n)) => {
            if !(n.is_finite() && n > 0.0) {
                bail!("substeps_per_second {n} must be finite and > 0");
            }
            1.0 / n
        }
        _ => bail!("give exactly one of \"substep\" [s] and \"substeps_per_second\""),
    };
    if !(substep.is_finite() && substep > 0.0) {
        bail!("substep {substep} s must be finite and > 0");
    }
    let num_substeps = crate::bullet::whole_substeps(f.duration, substep)
        .map_err(|e| SceneError::Invalid(format!("duration: {e}")))?;
    // Resource bound (docs/reliability.md): a scene of 1e9 s would run for days.
    crate::model::limits::check(
        "duration / substep",
        "physics substeps",
        num_substeps,
        crate::model::limits::MAX_PHYSICS_SUBSTEPS,
    )?;

    // Bodies.
    let mut names: BTreeMap<&str, usize> = BTreeMap::new();
    let mut bodies = Vec::with_capacity(f.bodies.len());
    let mut kinematic_motions = Vec::new();
    for (i, b) in f.bodies.iter().enumerate() {
        let item = || loc.body(i, &b.name);
        if b.name.is_empty() {
            bail!("{}: name must not be empty", item());
        }
        if let Some(&j) = names.get(b.name.as_str()) {
            bail!("{}: name is already used by body {j}", item());
        }
        names.insert(&b.name, i);
        finite(&b.half_extents, "half_extents", &item)?;
        if b.half_extents.iter().any(|&h| h <= 0.0) {
            bail!(
                "{}: half_extents {:?} must all be > 0",
                item(),
                b.half_extents
            );
        }
        if !(b.mass.is_finite() && b.mass >= 0.0) {
            bail!(
                "{}: mass {} must be finite and >= 0 (0 = static)",
                item(),
                b.mass
            );
        }
        let kind = match (b.mass > 0.0, b.kinematic) {
            (true, true) => bail!("{}: a kinematic body must have mass 0", item()),
            (true, false) => BodyKind::Dynamic,
            (false, true) => BodyKind::Kinematic,
            (false, false) => BodyKind::Static,
        };
        finite(&b.position, "position", &item)?;
        let orientation = unit_quaternion(
            b.orientation.unwrap_or([1.0, 0.0, 0.0, 0.0]),
            "orientation",
            &item,
        )?;
        let linear = b.linear_velocity.unwrap_or([0.0; 3]);
        let angular = b.angular_velocity.unwrap_or([0.0; 3]);
        finite(&linear, "linear_velocity", &item)?;
        finite(&angular, "angular_velocity", &item)?;
        if kind != BodyKind::Dynamic && (linear != [0.0; 3] || angular != [0.0; 3]) {
            bail!(
                "{}: only a dynamic body (mass > 0) can have an initial velocity",
                item()
            );
        }
        let margin = nonneg(b.margin.unwrap_or(default_margin), "margin", &item)?;
        let hmin = b.half_extents.iter().cloned().fold(f64::INFINITY, f64::min);
        if margin > hmin {
            bail!(
                "{}: margin {margin} exceeds the smallest half extent {hmin}",
                item()
            );
        }
        let damping = |v: Option<f64>, what: &str| -> Result<f64> {
            let d = nonneg(v.unwrap_or(0.0), what, &item)?;
            if d > 1.0 {
                bail!("{}: {what} {d} must be <= 1", item());
            }
            Ok(d)
        };
        let desc = BoxDesc {
            kind,
            half_extents: b.half_extents,
            margin,
            mass: b.mass,
            pose: Pose {
                position: b.position,
                orientation,
            },
            velocity: Velocity { linear, angular },
            friction: nonneg(b.friction.unwrap_or(0.5), "friction", &item)?,
            rolling_friction: nonneg(b.rolling_friction.unwrap_or(0.0), "rolling_friction", &item)?,
            spinning_friction: nonneg(
                b.spinning_friction.unwrap_or(0.0),
                "spinning_friction",
                &item,
            )?,
            restitution: nonneg(b.restitution.unwrap_or(0.0), "restitution", &item)?,
            linear_damping: damping(b.linear_damping, "linear_damping")?,
            angular_damping: damping(b.angular_damping, "angular_damping")?,
            disable_deactivation: b.disable_deactivation.unwrap_or(true),
        };
        if let Some(m) = &b.motion {
            if kind != BodyKind::Kinematic {
                bail!(
                    "{}: motion is only for kinematic bodies (\"kinematic\": true)",
                    item()
                );
            }
            let velocity = Velocity {
                linear: m.linear_velocity.unwrap_or([0.0; 3]),
                angular: m.angular_velocity.unwrap_or([0.0; 3]),
            };
            finite(&velocity.linear, "motion.linear_velocity", &item)?;
            finite(&velocity.angular, "motion.angular_velocity", &item)?;
            kinematic_motions.push(KinematicMotion {
                body: i,
                start: desc.pose,
                velocity,
            });
        }
        bodies.push((b.name.clone(), desc));
    }

    // Constraints.
    let mut constraints = Vec::with_capacity(f.constraints.len());
    for (i, c) in f.constraints.iter().enumerate() {
        let item = || loc.constraint(i);
        let body = |name: &str, which: &str| -> Result<usize> {
            names.get(name).copied().ok_or_else(|| {
                SceneError::Invalid(format!(
                    "{}: {which} \"{name}\" does not exist (no body has that name)",
                    item()
                ))
            })
        };
        let body_a = body(&c.body_a, "body_a")?;
        let body_b = body(&c.body_b, "body_b")?;
        if body_a == body_b {
            bail!(
                "{}: body_a and body_b are the same body \"{}\"",
                item(),
                c.body_a
            );
        }
        let frame = |fs: &FrameSpec, what: &str| -> Result<Pose> {
            finite(&fs.position, &format!("{what}.position"), &item)?;
            let q = unit_quaternion(
                fs.orientation.unwrap_or([1.0, 0.0, 0.0, 0.0]),
                &format!("{what}.orientation"),
                &item,
            )?;
            Ok(Pose {
                position: fs.position,
                orientation: q,
            })
        };
        let frame_a = frame(&c.frame_a, "frame_a")?;
        let frame_b = frame(&c.frame_b, "frame_b")?;
        let mut limits = [None; 6];
        if let Some(ls) = &c.limits {
            for (axis, l) in ls.iter().enumerate() {
                if let Some([lo, hi]) = *l {
                    if lo.is_nan() || hi.is_nan() {
                        bail!("{}: limit of axis {axis} is NaN", item());
                    }
                    limits[axis] = Some((lo, hi));
                }
            }
        }
        let kind = match c.kind {
            ConstraintType::Generic6dof => ConstraintKind::Generic6Dof {
                use_linear_reference_frame_a: c.use_linear_reference_frame_a.unwrap_or(true),
            },
            ConstraintType::Spring2 => {
                let mut springs = [None; 6];
                if let Some(ss) = &c.springs {
                    for (axis, s) in ss.iter().enumerate() {
                        if let Some(s) = s {
                            let what = format!("springs[{axis}]");
                            springs[axis] = Some(Spring {
                                stiffness: nonneg(
                                    s.stiffness,
                                    &format!("{what}.stiffness"),
                                    &item,
                                )?,
                                damping: nonneg(s.damping, &format!("{what}.damping"), &item)?,
                                limit_if_needed: s.limit_if_needed,
                            });
                        }
                    }
                }
                ConstraintKind::Spring2 {
                    springs,
                    set_equilibrium_point: c.set_equilibrium_point.unwrap_or(true),
                }
            }
            ConstraintType::Fixed => ConstraintKind::Fixed,
            ConstraintType::PointToPoint => ConstraintKind::PointToPoint,
        };
        if c.springs.is_some() && c.kind != ConstraintType::Spring2 {
            bail!("{}: springs are only allowed on kind \"spring2\"", item());
        }
        if c.limits.is_some() && c.kind == ConstraintType::Fixed {
            bail!(
                "{}: limits are not allowed on kind \"fixed\" (all axes are locked)",
                item()
            );
        }
        if c.limits.is_some() && c.kind == ConstraintType::PointToPoint {
            bail!(
                "{}: limits are not allowed on kind \"point2point\" (the pivots are held together, rotation is free)",
                item()
            );
        }
        if c.use_linear_reference_frame_a.is_some() && c.kind != ConstraintType::Generic6dof {
            bail!(
                "{}: use_linear_reference_frame_a is only for kind \"generic6dof\"",
                item()
            );
        }
        let breaking_impulse_threshold = match c.breaking_impulse_threshold {
            None => f64::INFINITY,
            Some(t) if t.is_finite() && t > 0.0 => t,
            Some(t) => bail!(
                "{}: breaking_impulse_threshold {t} must be finite and > 0 (omit it for unbreakable)",
                item()
            ),
        };
        constraints.push(SceneConstraint {
            kind,
            body_a,
            body_b,
            frame_a,
            frame_b,
            limits,
            breaking_impulse_threshold,
            disable_collisions_between: c.disable_collisions_between.unwrap_or(true),
            enabled: c.enabled.unwrap_or(true),
            override_solver_iterations: c.override_solver_iterations,
        });
    }

    let body_lines = (0..bodies.len())
        .map(|i| loc.bodies.starts.get(i).copied().unwrap_or(0))
        .collect();
    Ok(Scene {
        world,
        substep,
        num_substeps,
        bodies,
        constraints,
        kinematic_motions,
        body_lines,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinematic_motion_pose_is_linear_plus_constant_rotation() {
        let m = KinematicMotion {
            body: 0,
            start: Pose {
                position: [1.0, 2.0, 3.0],
                orientation: [1.0, 0.0, 0.0, 0.0],
            },
            velocity: Velocity {
                linear: [0.5, 0.0, -1.0],
                angular: [0.0, 0.0, std::f64::consts::FRAC_PI_2],
            },
        };
        let p = m.pose_at(2.0);
        assert_eq!(p.position, [2.0, 2.0, 1.0]);
        // 90°/s for 2 s about z: 180° about z = (0, 0, 0, 1).
        let q = p.orientation;
        assert!(q[0].abs() < 1e-15 && q[1] == 0.0 && q[2] == 0.0 && (q[3] - 1.0).abs() < 1e-15);
        // Composition with a start rotation: 90° about x then 180° about z.
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let m2 = KinematicMotion {
            start: Pose {
                position: [0.0; 3],
                orientation: [s, s, 0.0, 0.0],
            },
            ..m
        };
        let q = m2.pose_at(2.0).orientation;
        let expected = [0.0, 0.0, s, s]; // (0,0,0,1)·(s,s,0,0)
        for (a, b) in q.iter().zip(expected) {
            assert!((a - b).abs() < 1e-15, "{q:?}");
        }
    }
}
