//! BCB connection type 22 ("6x GENERIC + 1x SPRING") as plain data.
//!
//! Source: BCB `builder_setc.py` (`setConstraintSettings`), docs/bcb.md §2.1, §3.1, §4, §11.4.
//! Re-implemented, not copied. Per connection (one touching pair A–B):
//!
//! | # | role | Bullet class | locked DOF (frame axes: X = normal A→B) | limits | breaking impulse |
//! |---|---|---|---|---|---|
//! | 0 | compression | `btGeneric6DofConstraint` | lin X | [0, 99999] | C·a·2.2·Δt |
//! | 1 | tension | same | lin X | [−99999, 0] | T·a·2.2·Δt |
//! | 2 | shear-h | same | lin axis ∥ h | [0, 0] | min(S,S90)·a·2.2·Δt |
//! | 3 | shear-w | same | lin axis ∥ w | [0, 0] | max(S,S90)·a·2.2·Δt |
//! | 4 | bend-h | same | ang X + ang about the w-axis | [0, 0] | min(B,B90)·a·1.5·Δt |
//! | 5 | bend-w | same | ang X + ang about the h-axis | [0, 0] | max(B,B90)·a·1.5·Δt |
//! | 6 | plastic spring | `btGeneric6DofSpring2Constraint` | springs on all 6, no limits, **disabled** | free | P·a·2·Δt |
//!
//! with Δt = time_scale / steps_per_second and a the contact area in mm² (strengths are per
//! mm²). Every unlisted DOF is free (Bullet: lower > upper, we give (0, −1) as Blender does).
//! The generics use `useLinearReferenceFrameA = true`.
//!
//! * **Thresholds** (docs/bcb.md §3.1): value × multiplier × time_scale / steps_per_second ×
//!   correction / constCount, corrections 2.2 (linear generic rows), 1.5 (bending rows),
//!   2 (spring); constCount = 1 for CT 22. The multiplier is the group's threshold
//!   multiplier, ×2 when the partner is passive (BCB's "boundary condition case").
//! * **Two groups** (both active): each value is the weaker of the two groups' values
//!   (`lowerBrkThresPriority`, default on), the 90° values only if both groups have them;
//!   the tolerances and the Formula-Assistant tol2 come from A's group (BCB's `elemGrp`
//!   when both groups use the same connection type). Active–passive: the active group.
//! * **No 90° values** for both S and B: bending rows get B·h/w and B·w/h (BCB's
//!   `btRatio`), if h and w both exceed the search distance.
//! * **Spring stiffness** (docs/bcb.md §4): k = P / (L·tol2D) · 2 / constCount / 2 (the last /2
//!   for SPRING2), N/m, the same number for the angular axes (N·m/rad); damping 20 on all
//!   six axes (SPRING2); L = the group's plastic length, or the centre distance if 0
//!   (0.1 m if that is 0). The equilibrium point is set at creation (`setEquilibriumPoint()`),
//!   which — frames coinciding at creation — is the zero offset.
//! * **Frames**: BCB places all constraints at the pivot, rotated by `rotN` (local X onto the
//!   snapped normal, Blender's `to_track_quat('X','Z')`); the spring frame is world-aligned
//!   (identity). These frames are defined on the configuration the contacts were found in
//!   (undeformed); at the hand-off time Tc each body carries them rigidly
//!   (`P_A = A_Tc·A₀⁻¹·P₀`, likewise for B), the constraint's world frame at Tc is the
//!   midpoint / half-way slerp of the two, and `frame_a = A_Tc⁻¹·P_Tc`,
//!   `frame_b = B_Tc⁻¹·P_Tc`. So both frames coincide at Tc and nothing fires at the start.
//!   With Tc poses equal to the undeformed ones this is exactly BCB's `A⁻¹·P`, `B⁻¹·P`.
//!
//! Not reproduced (off by default in BCB or irrelevant for RC frames): backlash, connection
//! priorities, the intercomponent multiplier, cylindrical areas, detonators, Mohr–Coulomb.

use super::search::Contact;
use super::strength::{StrengthPerArea, StrengthSource};
use super::{BodyGeom, RuinError};
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Bullet's "free" limit pair (lower > upper), as Blender passes for unused axes.
pub(crate) const FREE: (f64, f64) = (0.0, -1.0);
/// BCB's "unlimited" linear bound for the one-sided compression/tension rows, m.
pub const BCB_UNLIMITED: f64 = 99999.0;

/// Tolerances of the monitor as a group gives them, in BCB's convention
/// (`connectsTol`, docs/bcb.md §4): a value > 0 is used as is; **0 means automatic** for the
/// 2nd tolerances (Formula Assistant: tol2D = elu/100, tol2R = atan(tol2D·L/(h/2)); without
/// a formula BCB's preset 0.2 / 0.8); a **negative value disables** that check.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Tolerances {
    /// 1st distance tolerance (relative), elastic → plastic. BCB 0.1.
    pub dist1: f64,
    /// 1st rotation tolerance, rad, elastic → plastic. BCB 0.2 (0.4 in 2020).
    pub rot1: f64,
    /// 2nd distance tolerance (relative), plastic → broken. 0 = automatic.
    pub dist2: f64,
    /// 2nd rotation tolerance, rad, plastic → broken. 0 = automatic.
    pub rot2: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances {
            dist1: 0.1,
            rot1: 0.2,
            dist2: 0.0,
            rot2: 0.0,
        }
    }
}

/// BCB preset-0 2nd distance tolerance, used when a group has no formula (docs/bcb.md §8).
pub(crate) const PRESET_TOL2_DIST: f64 = 0.2;
/// BCB preset-0 2nd rotation tolerance, rad.
pub(crate) const PRESET_TOL2_ROT: f64 = 0.8;

/// Tolerances resolved for one connection; `None` = check disabled.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResolvedTolerances {
    /// 1st distance tolerance.
    pub dist1: Option<f64>,
    /// 1st rotation tolerance, rad.
    pub rot1: Option<f64>,
    /// 2nd distance tolerance.
    pub dist2: Option<f64>,
    /// 2nd rotation tolerance, rad.
    pub rot2: Option<f64>,
}

/// The strength definition of one element group.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroupStrength {
    /// Group name, as in [`BodyGeom::group`].
    pub name: String,
    /// Where the per-mm² strengths come from.
    pub strength: StrengthSource,
    /// Monitor tolerances.
    #[serde(default)]
    pub tolerances: Tolerances,
    /// Plastic length L of the spring stiffness, m; 0 = centre distance (BCB default).
    #[serde(default)]
    pub plastic_length: f64,
    /// Breaking-threshold multiplier (BCB `BTX`), 1 by default.
    #[serde(default = "one")]
    pub threshold_multiplier: f64,
}

fn one() -> f64 {
    1.0
}

impl GroupStrength {
    /// A group using the Formula Assistant, with BCB's default tolerances.
    pub fn formula(name: &str, inputs: super::strength::FormulaInputs) -> Self {
        GroupStrength {
            name: name.into(),
            strength: StrengthSource::Formula(inputs),
            tolerances: Tolerances::default(),
            plastic_length: 0.0,
            threshold_multiplier: 1.0,
        }
    }

    /// Checks the definition; the error names the group.
    pub fn validate(&self) -> Result<(), RuinError> {
        let bad = |message: String| RuinError::BadSetting {
            item: format!("group '{}'", self.name),
            message,
        };
        match &self.strength {
            StrengthSource::Formula(f) => f.validate().map_err(|e| bad(e.to_string()))?,
            StrengthSource::PerArea(p) => {
                let vals = [
                    ("C", Some(p.c)),
                    ("T", Some(p.t)),
                    ("S", Some(p.s)),
                    ("S90", p.s90),
                    ("B", Some(p.b)),
                    ("B90", p.b90),
                    ("P", p.p),
                ];
                for (n, v) in vals {
                    if let Some(v) = v {
                        if !v.is_finite() || v < 0.0 {
                            return Err(bad(format!("strength {n} = {v} must be finite and >= 0")));
                        }
                    }
                }
            }
        }
        let t = &self.tolerances;
        for (n, v) in [
            ("dist1", t.dist1),
            ("rot1", t.rot1),
            ("dist2", t.dist2),
            ("rot2", t.rot2),
            ("plastic_length", self.plastic_length),
            ("threshold_multiplier", self.threshold_multiplier),
        ] {
            if !v.is_finite() {
                return Err(bad(format!("{n} = {v} is not finite")));
            }
        }
        if self.plastic_length < 0.0 || self.threshold_multiplier < 0.0 {
            return Err(bad(
                "plastic_length and threshold_multiplier must be >= 0".into()
            ));
        }
        Ok(())
    }
}

/// How the plastic spring's three angular axes get their stiffness from BCB's linear
/// k = P/(L·tol2D)·… (N/m).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AngularSpring {
    /// BCB: the same number, read as N·m/rad (docs/bcb.md §4). Dimensionally inconsistent, so
    /// it does not scale with the model: at full size (a 0.3 m column, 3 m long) the
    /// angular spring is soft (ω ≈ 20 rad/s), at 1/4 scale 16 times stiffer relative to
    /// the members' rotational inertia (ω ∝ scale⁻²) and beyond explicit stepping.
    Bcb,
    /// k_θ,i = k·r_i², the linear spring acting at the lever arm r_i of the contact
    /// rectangle (h × w): r = w/2 for rotation about the h axis, h/2 about the w axis,
    /// √(h² + w²)/2 about the normal (torsion). It is the stiffness BCB's own tolerances
    /// imply: the moment P·h/2 is reached at the rotation tan θ = L·tol2D/(h/2), which is
    /// BCB's Formula-Assistant tol2R = atan(tol2D·L/(h/2)) (docs/bcb.md §4). Scales as
    /// k_θ ∝ scale³ with I ∝ scale⁵, so ω ∝ 1/scale like the linear axes.
    Lever,
}

/// Simulation settings that the constraint model depends on, with BCB's (HEAD) defaults.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RuinSettings {
    /// Bullet substeps per second (BCB 200; 300 in the 2020 version).
    pub steps_per_second: f64,
    /// Solver iterations (BCB 100; Blender's 10 in 2020). Used by the Bullet layer.
    pub solver_iterations: u32,
    /// Monitor frames per second (BCB 25).
    pub frame_rate: f64,
    /// Bullet time scale (1).
    pub time_scale: f64,
    /// Correction of the linear generic rows (2.2).
    pub linear_correction: f64,
    /// Correction of the bending generic rows (1.5).
    pub bending_correction: f64,
    /// Correction of the plastic spring (2).
    pub spring_correction: f64,
    /// Threshold factor towards a passive (foundation) partner (2).
    pub passive_multiplier: f64,
    /// Use the weaker of two groups' strengths (BCB `lowerBrkThresPriority`, on).
    pub weaker_group: bool,
    /// SPRING2 damping on every axis (20).
    pub spring_damping: f64,
    /// Let Bullet cap each plastic spring's stiffness at m/(16·h²) and its damping at m/h
    /// per substep (`setStiffness(i, k, limitIfNeeded = true)`, Bullet's default, which
    /// Blender and hence BCB use; see [`crate::physics::Spring::limit_if_needed`]). On:
    /// BCB's k = P/(L·tol2D) is applied as N·m/rad on the angular axes too, which for
    /// small bodies is far beyond what explicit stepping at 200 substeps/s can carry
    /// (frame3's 1/4-scale members: ω·h up to ~50 uncapped); uncapped, the springs of
    /// plastic connections pump energy into the debris and throw it hundreds of metres.
    pub spring_limit_if_needed: bool,
    /// The plastic spring's angular stiffness (default [`AngularSpring::Lever`]).
    pub angular_spring: AngularSpring,
    /// Disable collisions between connected bodies while a constraint is enabled (on).
    pub disable_collisions: bool,
    /// The axial rows: BCB's one-way compression and tension rows (default) or one
    /// two-way row broken by the stage in the sense it pushes ([`super::axial`]).
    pub axial_rows: super::axial::AxialRows,
    /// What a ductile hinge (FE-derived connections) becomes past its 1st rotation
    /// tolerance ([`HingeEnd`]; default [`HingeEnd::Spring`], BCB's sequence).
    pub hinge_end: HingeEnd,
    /// The connection search.
    pub search: super::search::SearchSettings,
}

/// What a ductile hinge of an FE-derived connection ([`ConnectionSpec::ductile`]) does
/// once it has turned past its 1st rotation tolerance (docs/handoff.md §2.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HingeEnd {
    /// The hinge goes on holding its moment, and the connection's axial and shear rows
    /// their strengths, until BCB's 2nd tolerances (the Formula Assistant's bar-rupture
    /// rotation tol2R = atan(elu/100·L/(h/2)) and distance tol2D = elu/100, docs/bcb.md
    /// §4), where the connection breaks: the FE's fibre sections carry their gravity load
    /// far beyond the 80 %-moment rotation (Concrete02 keeps a residual strength, the bars
    /// have no rupture strain), so the FE building has no plastic-spring state. The
    /// connection has no plastic spring. Option (docs/handoff.md §2.6).
    Rupture,
    /// BCB's sequence (the default): at the 1st tolerance every generic row is switched
    /// off and BCB's plastic spring (P = f_su·ρ·A/4) takes over until the 2nd tolerances.
    #[default]
    Spring,
}

impl Default for RuinSettings {
    fn default() -> Self {
        RuinSettings {
            steps_per_second: 200.0,
            solver_iterations: 100,
            frame_rate: 25.0,
            time_scale: 1.0,
            linear_correction: 2.2,
            bending_correction: 1.5,
            spring_correction: 2.0,
            passive_multiplier: 2.0,
            weaker_group: true,
            spring_damping: 20.0,
            spring_limit_if_needed: true,
            angular_spring: AngularSpring::Lever,
            disable_collisions: true,
            axial_rows: super::axial::AxialRows::Bcb,
            hinge_end: HingeEnd::Spring,
            search: super::search::SearchSettings::default(),
        }
    }
}

impl RuinSettings {
    /// The substep Δt = time_scale / steps_per_second, s.
    pub fn substep(&self) -> f64 {
        self.time_scale / self.steps_per_second
    }

    fn validate(&self) -> Result<(), RuinError> {
        let pos = [
            ("steps_per_second", self.steps_per_second),
            ("frame_rate", self.frame_rate),
            ("time_scale", self.time_scale),
            ("linear_correction", self.linear_correction),
            ("bending_correction", self.bending_correction),
            ("spring_correction", self.spring_correction),
            ("passive_multiplier", self.passive_multiplier),
        ];
        for (n, v) in pos {
            if !(v.is_finite() && v > 0.0) {
                return Err(RuinError::BadSetting {
                    item: n.into(),
                    message: format!("{v} must be finite and > 0"),
                });
            }
        }
        if !(self.spring_damping.is_finite() && self.spring_damping >= 0.0) {
            return Err(RuinError::BadSetting {
                item: "spring_damping".into(),
                message: format!("{} must be finite and >= 0", self.spring_damping),
            });
        }
        Ok(())
    }
}

/// Which Bullet constraint class a spec stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ConstraintClass {
    /// `btGeneric6DofConstraint(A, B, frame_a, frame_b, useLinearReferenceFrameA = true)`.
    Generic6Dof,
    /// `btGeneric6DofSpring2Constraint(A, B, frame_a, frame_b)` (rotation order XYZ).
    Spring2,
}

/// What a constraint of a CT 22 connection models.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ConstraintRole {
    /// Compression along the normal.
    Compression,
    /// Tension along the normal.
    Tension,
    /// Shear along h.
    ShearH,
    /// Shear along w.
    ShearW,
    /// Bending about the w-axis (section depth h) plus torsion.
    BendH,
    /// Bending about the h-axis (section depth w) plus torsion.
    BendW,
    /// The plastic 6-DOF spring (2nd mode).
    PlasticSpring,
}

impl ConstraintRole {
    /// Its name in the outputs (`connections.csv`): `compression`, `tension`, `shear_h`,
    /// `shear_w`, `bend_h`, `bend_w`, `spring`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Compression => "compression",
            Self::Tension => "tension",
            Self::ShearH => "shear_h",
            Self::ShearW => "shear_w",
            Self::BendH => "bend_h",
            Self::BendW => "bend_w",
            Self::PlasticSpring => "spring",
        }
    }
}

/// One Bullet constraint as plain data. Axis index i: 0–2 linear X, Y, Z, 3–5 angular X,
/// Y, Z of the constraint frame. `lower[i] > upper[i]` means free.
#[derive(Debug, Clone, PartialEq)]
pub struct ConstraintSpec {
    /// Its role in the connection.
    pub role: ConstraintRole,
    /// The Bullet class.
    pub kind: ConstraintClass,
    /// Constraint frame in body A's local frame.
    pub frame_a: Isometry3<f64>,
    /// Constraint frame in body B's local frame.
    pub frame_b: Isometry3<f64>,
    /// Lower limits (m, rad).
    pub lower: [f64; 6],
    /// Upper limits (m, rad).
    pub upper: [f64; 6],
    /// Spring enabled per axis (Spring2 only).
    pub spring: [bool; 6],
    /// Spring stiffness per axis, N/m (linear), N·m/rad (angular).
    pub stiffness: [f64; 6],
    /// Spring damping per axis (btGeneric6DofSpring2 damping).
    pub damping: [f64; 6],
    /// `setBreakingImpulseThreshold`, N·s (linear rows) or N·m·s (bending rows).
    pub breaking_impulse: f64,
    /// Enabled at creation.
    pub enabled: bool,
    /// The row's strength is zero (an FE-derived residual capacity gone in this sense):
    /// it never carries load, so no state enables it (threshold kept at the smallest
    /// positive value Bullet accepts).
    pub no_strength: bool,
}

impl ConstraintSpec {
    /// Whether axis `i` is free (lower > upper).
    pub fn is_free(&self, i: usize) -> bool {
        self.lower[i] > self.upper[i]
    }
}

/// The capacities of one connection, N and N·m (per-mm² strength × area × multipliers).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConnectionForces {
    /// Compression C, N.
    pub compression_n: f64,
    /// Tension T, N.
    pub tension_n: f64,
    /// Shear along h, N.
    pub shear_h_n: f64,
    /// Shear along w, N.
    pub shear_w_n: f64,
    /// Bending, h-depth (about the w-axis), N·m.
    pub bend_h_nm: f64,
    /// Bending, w-depth (about the h-axis), N·m.
    pub bend_w_nm: f64,
    /// Plastic capacity P, N (None: no plastic spring).
    pub plastic_n: Option<f64>,
    /// Spring stiffness k, N/m and N·m/rad (None: no plastic spring).
    pub spring_stiffness: Option<f64>,
}

/// The state of a connection (BCB's monitor modes 0, 1, 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ConnectionState {
    /// The six generic constraints hold; the spring is off.
    Elastic,
    /// The generics are off; the plastic spring holds.
    Plastic,
    /// Nothing holds.
    Broken,
}

/// One connection: its geometry, capacities, tolerances and constraints.
#[derive(Debug, Clone, PartialEq)]
pub struct ConnectionSpec {
    /// Body A index.
    pub a: usize,
    /// Body B index.
    pub b: usize,
    /// The contact it was built from (undeformed configuration).
    pub contact: Contact,
    /// The group whose tolerances govern (A's if both are active, else the active one).
    pub group: String,
    /// Capacities.
    pub forces: ConnectionForces,
    /// Monitor tolerances.
    pub tolerances: ResolvedTolerances,
    /// Spring length L used for the stiffness, m.
    pub spring_length: f64,
    /// Disable collisions between A and B while any constraint is enabled.
    pub disable_collisions: bool,
    /// Six generics (roles in [`ConstraintRole`] order), then the plastic spring if any.
    pub constraints: Vec<ConstraintSpec>,
    /// An FE-derived end at this connection has lost its load path: the connection starts
    /// broken ([`EndStrength::lost`]).
    pub lost_at_start: bool,
    /// FE-derived connection with ductile bending rows: while the connection is elastic,
    /// a bending row (4, 5) that Bullet disabled for reaching its breaking impulse is
    /// enabled again before the next substep. Bullet clamps a row's impulse at its
    /// threshold, so the row then carries at most that moment while it rotates — a
    /// rigid–plastic hinge at the moment capacity, as the FE's fibre hinge holds its
    /// moment. The hinge ends when the rotation since the start exceeds the 1st rotation
    /// tolerance (the end's remaining rotation capacity): the monitor turns the connection
    /// plastic (BCB's spring) as usual.
    pub ductile: bool,
}

/// Constraint indices of the bending rows (ductile in FE-derived connections).
pub(crate) const BENDING_ROWS: [usize; 2] = [4, 5];

/// Number of generic constraints of a CT 22 connection.
pub(crate) const GENERIC_COUNT: usize = 6;

impl ConnectionSpec {
    /// Whether the connection has a plastic spring (index 6).
    pub fn has_spring(&self) -> bool {
        self.constraints.len() > GENERIC_COUNT
    }

    /// Sets the creation-time `enabled` flags for a starting state: elastic → generics on,
    /// spring off (BCB's start); plastic → generics off, spring on (all off if there is no
    /// spring); broken → all off.
    pub fn set_state(&mut self, state: ConnectionState) {
        let has_spring = self.has_spring();
        for (i, c) in self.constraints.iter_mut().enumerate() {
            let generic = i < GENERIC_COUNT;
            c.enabled = match state {
                ConnectionState::Elastic => generic && !c.no_strength,
                ConnectionState::Plastic => !generic && has_spring,
                ConnectionState::Broken => false,
            };
        }
    }
}

/// BCB's constraint rotation for a snapped normal: local X onto `sign·e[axis]`, as
/// Blender's `to_track_quat('X','Z')` gives it (docs/bcb.md §2.1; −Y worked out the same way):
/// +X → (X, Y, Z); −X → (−X, −Y, Z); +Y → (Y, −X, Z); −Y → (−Y, X, Z);
/// +Z → (Z, Y, −X); −Z → (−Z, Y, X) (columns = images of local X, Y, Z).
pub(crate) fn bcb_normal_rotation(axis: usize, sign: f64) -> UnitQuaternion<f64> {
    let e = |i: usize, s: f64| {
        let mut v = Vector3::zeros();
        v[i] = s;
        v
    };
    let pos = sign >= 0.0;
    let (x, y, z) = match (axis, pos) {
        (0, true) => (e(0, 1.0), e(1, 1.0), e(2, 1.0)),
        (0, false) => (e(0, -1.0), e(1, -1.0), e(2, 1.0)),
        (1, true) => (e(1, 1.0), e(0, -1.0), e(2, 1.0)),
        (1, false) => (e(1, -1.0), e(0, 1.0), e(2, 1.0)),
        (_, true) => (e(2, 1.0), e(1, 1.0), e(0, -1.0)),
        (_, false) => (e(2, -1.0), e(1, 1.0), e(0, 1.0)),
    };
    let m = Matrix3::from_columns(&[x, y, z]);
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m))
}

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

/// FE-derived strengths of one member end (from `fe::capacity`, plain
/// numbers): what the section at that end can still carry. Local axes as the member's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EndStrength {
    /// Compressive capacity along the member axis, N.
    pub compression_n: f64,
    /// Tensile capacity along the member axis, N.
    pub tension_n: f64,
    /// Shear capacity along local y and local z, N.
    pub shear_n: [f64; 2],
    /// Moment capacity about local z and about local y, N·m.
    pub moment_nm: [f64; 2],
    /// Remaining rotation capacity of the end, rad (`None`: BCB's tolerance stays).
    pub rotation_left: Option<f64>,
    /// The end has lost its load path at the start (the FE's rule, `fe::capacity`): every
    /// connection at this end starts broken.
    pub lost: bool,
}

/// FE-derived strengths of one rigid body (a whole member): its undeformed local axes and
/// its two ends. [`build_connections_with`] uses the end nearer to the contact's pivot.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyStrength {
    /// Local axes [x (member axis), y, z], unit, world components, undeformed.
    pub axes: [[f64; 3]; 3],
    /// (undeformed position of the end node, m; its strengths), end i then end j.
    pub ends: [([f64; 3], EndStrength); 2],
}

impl BodyStrength {
    /// The end nearer to `p` (undeformed world point).
    pub fn end_near(&self, p: [f64; 3]) -> &EndStrength {
        let d = |q: [f64; 3]| (0..3).map(|k| (q[k] - p[k]).powi(2)).sum::<f64>();
        if d(self.ends[0].0) <= d(self.ends[1].0) {
            &self.ends[0].1
        } else {
            &self.ends[1].1
        }
    }

    /// Whether the contact cuts this member's section: its normal runs along the member
    /// axis (an end face). A contact on the member's side (a beam end against a column,
    /// a slab on a beam) does not cut the member, so the member does not limit it.
    pub fn cut_by(&self, c: &Contact) -> bool {
        self.local_axis(c.normal_axis) == 0
    }

    /// Which local axis (0 = x, 1 = y, 2 = z) is closest to the world axis `world`.
    fn local_axis(&self, world: usize) -> usize {
        (0..3)
            .max_by(|&i, &j| {
                self.axes[i][world]
                    .abs()
                    .total_cmp(&self.axes[j][world].abs())
                    .then(j.cmp(&i))
            })
            .unwrap_or(0)
    }

    /// The connection forces this body's end can carry for contact `c` (module docs of
    /// [`build_connections_with`]): [compression, tension, shear-h, shear-w, bend-h,
    /// bend-w], N and N·m.
    pub fn forces_for(&self, c: &Contact) -> [f64; 6] {
        let e = self.end_near(c.pivot);
        // A force along world axis `w`: axial along the member, else the shear capacity
        // in that local direction.
        let force = |w: usize, axial: f64| match self.local_axis(w) {
            0 => axial,
            1 => e.shear_n[0],
            _ => e.shear_n[1],
        };
        // A moment about world axis `w`: about the member axis (torsion) the weaker
        // bending capacity stands in; about local y → My, about local z → Mz.
        let moment = |w: usize| match self.local_axis(w) {
            0 => e.moment_nm[0].min(e.moment_nm[1]),
            1 => e.moment_nm[1],
            _ => e.moment_nm[0],
        };
        let n = c.normal_axis;
        let (sh, sw) = (
            force(c.h_axis, e.compression_n),
            force(c.w_axis, e.compression_n),
        );
        [
            force(n, e.compression_n),
            force(n, e.tension_n),
            sh.min(sw),
            sh.max(sw),
            moment(c.w_axis).min(moment(c.h_axis)),
            moment(c.w_axis).max(moment(c.h_axis)),
        ]
    }
}

/// What limits the connections of one body when the strengths are FE-derived
/// ([`build_connections_with`]; docs/handoff.md §2.3, §2.6).
#[derive(Debug, Clone, PartialEq)]
pub enum BodyCapacity {
    /// Its group's strength (BCB's Formula Assistant, or ACI per area for walls): bodies
    /// the FE gives no member-end capacities for, and foundation blocks.
    Group,
    /// A beam-column member: its fibre sections' capacities where a contact cuts it.
    Member(Box<BodyStrength>),
    /// A part the FE models as elastic (slab panels: in the FE lumped mass on elastic
    /// strips, or nothing): it never limits a connection. A connection that nothing
    /// limits (two panels, a panel on a member's side) is unbreakable and has no
    /// tolerances: the FE building's slab does not fail.
    Elastic,
}

impl BodyCapacity {
    /// The member strengths, if this is a member.
    pub fn member(&self) -> Option<&BodyStrength> {
        match self {
            BodyCapacity::Member(s) => Some(s),
            _ => None,
        }
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
/// * `contacts`: from [`super::search::find_contacts`].
/// * `poses_at_start`: every body's pose when the constraints are created (Tc for the
///   hybrid mode; the undeformed poses for physics-only), one per body.
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

/// Carries a world frame `p0` defined on the undeformed bodies to the start poses and
/// returns (frame in A, frame in B) — module docs, "Frames".
pub(crate) fn frames_at_start(
    p0: &Isometry3<f64>,
    a0: &Isometry3<f64>,
    b0: &Isometry3<f64>,
    a_start: &Isometry3<f64>,
    b_start: &Isometry3<f64>,
) -> (Isometry3<f64>, Isometry3<f64>) {
    let pa = a_start * (a0.inverse() * p0);
    let pb = b_start * (b0.inverse() * p0);
    let pos = (pa.translation.vector + pb.translation.vector) * 0.5;
    let rot = pa.rotation.slerp(&pb.rotation, 0.5);
    let p = Isometry3::from_parts(Translation3::from(pos), rot);
    (a_start.inverse() * p, b_start.inverse() * p)
}

/// The seven constraint specs of a CT 22 connection (six if there is no plastic value).
fn constraint_specs(
    c: &Contact,
    ba: &BodyGeom,
    bb: &BodyGeom,
    a_start: &Isometry3<f64>,
    b_start: &Isometry3<f64>,
    f: &ConnectionForces,
    s: &RuinSettings,
) -> Vec<ConstraintSpec> {
    let rot_n = bcb_normal_rotation(c.normal_axis, c.normal_sign);
    let pivot = Translation3::new(c.pivot[0], c.pivot[1], c.pivot[2]);
    let p0 = Isometry3::from_parts(pivot, rot_n);
    let (a0, b0) = (ba.pose(), bb.pose());
    let (fa, fb) = frames_at_start(&p0, &a0, &b0, a_start, b_start);

    // Local axis (1 = Y, 2 = Z) of the constraint frame parallel to h, and the other (w).
    let m = rot_n.to_rotation_matrix();
    let h_local = if m.matrix()[(c.h_axis, 1)].abs() >= m.matrix()[(c.h_axis, 2)].abs() {
        1
    } else {
        2
    };
    let w_local = 3 - h_local;

    let dt = s.substep();
    let lin = |force: f64| force * s.linear_correction * dt;
    let ang = |moment: f64| moment * s.bending_correction * dt;
    // A row whose strength is zero (an FE-derived residual capacity that is gone in
    // that sense only, e.g. shear friction across a section pulled apart, or a residual
    // moment about one axis; docs/handoff.md §3) can carry nothing: it starts broken
    // (disabled), like a row Bullet broke in the first substep. Bullet takes only a
    // positive threshold, so the disabled row keeps the smallest one.
    let generic = |role, locks: &[(usize, f64, f64)], impulse: f64| {
        let no_strength = impulse == 0.0;
        let impulse = if no_strength {
            f64::MIN_POSITIVE
        } else {
            impulse
        };
        let mut lower = [FREE.0; 6];
        let mut upper = [FREE.1; 6];
        for &(i, lo, hi) in locks {
            lower[i] = lo;
            upper[i] = hi;
        }
        ConstraintSpec {
            role,
            kind: ConstraintClass::Generic6Dof,
            frame_a: fa,
            frame_b: fb,
            lower,
            upper,
            spring: [false; 6],
            stiffness: [0.0; 6],
            damping: [0.0; 6],
            breaking_impulse: impulse,
            enabled: !no_strength,
            no_strength,
        }
    };
    // One two-way row when both senses have a strength (Bullet's threshold the smaller of
    // the two at the start; the stage sets it per substep and checks the sense; the tension
    // constraint stays without locked axes, no solver rows); BCB's two one-way rows
    // otherwise (a sense without strength starts broken, the other one-way row is left).
    let two_way = s.axial_rows == super::axial::AxialRows::TwoWay
        && f.compression_n > 0.0
        && f.tension_n > 0.0;
    let (compression, tension) = if two_way {
        (
            generic(
                ConstraintRole::Compression,
                &[(0, 0.0, 0.0)],
                lin(f.compression_n.min(f.tension_n)),
            ),
            generic(ConstraintRole::Tension, &[], lin(f.tension_n)),
        )
    } else {
        (
            generic(
                ConstraintRole::Compression,
                &[(0, 0.0, BCB_UNLIMITED)],
                lin(f.compression_n),
            ),
            generic(
                ConstraintRole::Tension,
                &[(0, -BCB_UNLIMITED, 0.0)],
                lin(f.tension_n),
            ),
        )
    };
    let mut v = vec![
        compression,
        tension,
        generic(
            ConstraintRole::ShearH,
            &[(h_local, 0.0, 0.0)],
            lin(f.shear_h_n),
        ),
        generic(
            ConstraintRole::ShearW,
            &[(w_local, 0.0, 0.0)],
            lin(f.shear_w_n),
        ),
        generic(
            ConstraintRole::BendH,
            &[(3, 0.0, 0.0), (3 + w_local, 0.0, 0.0)],
            ang(f.bend_h_nm),
        ),
        generic(
            ConstraintRole::BendW,
            &[(3, 0.0, 0.0), (3 + h_local, 0.0, 0.0)],
            ang(f.bend_w_nm),
        ),
    ];
    if let (Some(p), Some(k)) = (f.plastic_n, f.spring_stiffness) {
        // World-aligned spring frame at the pivot (BCB never applies rotN to it).
        let p0s = Isometry3::from_parts(pivot, UnitQuaternion::identity());
        let (fsa, fsb) = frames_at_start(&p0s, &a0, &b0, a_start, b_start);
        v.push(ConstraintSpec {
            role: ConstraintRole::PlasticSpring,
            kind: ConstraintClass::Spring2,
            frame_a: fsa,
            frame_b: fsb,
            lower: [FREE.0; 6],
            upper: [FREE.1; 6],
            spring: [true; 6],
            stiffness: spring_stiffness_axes(k, c, s.angular_spring),
            damping: [s.spring_damping; 6],
            // A zero plastic strength: the spring breaks as soon as it is switched on.
            breaking_impulse: (p * s.spring_correction * dt).max(f64::MIN_POSITIVE),
            enabled: false,
            no_strength: false,
        });
    }
    v
}

/// The plastic spring's stiffness on its six world-aligned axes (0–2 N/m, 3–5 N·m/rad)
/// from the linear k (see [`AngularSpring`]). The spring frame is world-aligned in the
/// undeformed configuration, so its axis i is the contact's normal, h or w axis.
pub(crate) fn spring_stiffness_axes(k: f64, c: &Contact, rule: AngularSpring) -> [f64; 6] {
    let mut out = [k; 6];
    if rule == AngularSpring::Lever {
        for i in 0..3 {
            let r2 = if i == c.normal_axis {
                (c.h * c.h + c.w * c.w) / 4.0
            } else if i == c.h_axis {
                c.w * c.w / 4.0
            } else {
                c.h * c.h / 4.0
            };
            out[3 + i] = k * r2;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A column-on-column contact (normal Z, h along X = 0.1 m, w along Y = 0.2 m) with
    /// k = 1000 N/m: Lever gives k·(w/2)² = 10 N·m/rad about X (the h axis), k·(h/2)² = 2.5
    /// about Y (the w axis), k·(h² + w²)/4 = 12.5 about Z (torsion); BCB gives 1000 on all.
    #[test]
    fn lever_angular_spring_by_hand() {
        let c = Contact {
            a: 0,
            b: 1,
            pivot: [0.0; 3],
            normal_axis: 2,
            normal_sign: 1.0,
            h_axis: 0,
            w_axis: 1,
            h: 0.1,
            w: 0.2,
            normal_overlap: 0.0,
            area: 0.02,
            centre_distance: 0.5,
        };
        let k = spring_stiffness_axes(1000.0, &c, AngularSpring::Lever);
        let want = [1000.0, 1000.0, 1000.0, 10.0, 2.5, 12.5];
        for i in 0..6 {
            assert!(
                (k[i] - want[i]).abs() < 1e-12,
                "axis {i}: {} vs {}",
                k[i],
                want[i]
            );
        }
        assert_eq!(
            spring_stiffness_axes(1000.0, &c, AngularSpring::Bcb),
            [1000.0; 6]
        );
    }

    /// A member end with C 300 N, T 50 N, shears 40 / 45 N, moments 2 / 3 N·m and 0.05 rad
    /// of rotation left.
    fn test_end() -> EndStrength {
        EndStrength {
            compression_n: 300.0,
            tension_n: 50.0,
            shear_n: [40.0, 45.0],
            moment_nm: [2.0, 3.0],
            rotation_left: Some(0.05),
            lost: false,
        }
    }

    /// The FE-derived mapping by hand: a vertical column (local x = Z, y = X, z = Y)
    /// cut by a horizontal contact at its top end (normal Z, h along X, w along Y) gives
    /// C, T along its axis, the sliding shears, and bending about Y (local z → Mz) and X
    /// (local y → My); a contact on its side (normal X) does not cut it.
    #[test]
    fn fe_strengths_map_onto_the_contact_axes() {
        let end = test_end();
        let lost = EndStrength { lost: true, ..end };
        let col = BodyStrength {
            axes: [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            ends: [([0.0, 0.0, 0.0], lost), ([0.0, 0.0, 1.0], end)],
        };
        let mut c = Contact {
            a: 0,
            b: 1,
            pivot: [0.0, 0.0, 0.99],
            normal_axis: 2,
            normal_sign: 1.0,
            h_axis: 0,
            w_axis: 1,
            h: 0.1,
            w: 0.1,
            normal_overlap: 0.0,
            area: 0.01,
            centre_distance: 0.25,
        };
        assert!(col.cut_by(&c));
        assert!(!col.end_near(c.pivot).lost);
        // shear along X (local y) 40, along Y (local z) 45; moment about Y (local z) 2,
        // about X (local y) 3.
        assert_eq!(col.forces_for(&c), [300.0, 50.0, 40.0, 45.0, 2.0, 3.0]);
        c.pivot = [0.0, 0.0, 0.01];
        assert!(col.end_near(c.pivot).lost);
        c.normal_axis = 0;
        c.h_axis = 1;
        c.w_axis = 2;
        assert!(!col.cut_by(&c));
    }

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

    /// The two-way axial row (`super::super::axial`): both senses with strength → constraint 0
    /// locked at [0, 0] with the smaller breaking impulse, constraint 1 without locked
    /// axes; a sense without strength → BCB's two one-way rows (that sense starts broken).
    #[test]
    fn two_way_axial_row_or_bcb_rows_when_a_sense_has_no_strength() {
        let s = RuinSettings {
            axial_rows: super::super::axial::AxialRows::TwoWay,
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
            super::super::strength::FormulaInputs::default(),
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

    #[test]
    fn normal_rotation_maps_x_onto_normal_and_is_proper() {
        for axis in 0..3 {
            for sign in [1.0, -1.0] {
                let q = bcb_normal_rotation(axis, sign);
                let x = q * Vector3::x();
                let mut n = Vector3::zeros();
                n[axis] = sign;
                assert!((x - n).norm() < 1e-12, "axis {axis} sign {sign}");
                let m = q.to_rotation_matrix();
                assert!((m.matrix().determinant() - 1.0).abs() < 1e-12);
            }
        }
        // +Z: local Z → −X (Blender's to_track_quat('X','Z')).
        let q = bcb_normal_rotation(2, 1.0);
        assert!((q * Vector3::z() - Vector3::new(-1.0, 0.0, 0.0)).norm() < 1e-12);
    }

    #[test]
    fn frames_coincide_at_start() {
        let p0 = Isometry3::new(Vector3::new(0.5, 0.0, 1.0), Vector3::new(0.0, 0.3, 0.0));
        let a0 = Isometry3::new(Vector3::new(0.0, 0.0, 0.5), Vector3::zeros());
        let b0 = Isometry3::new(Vector3::new(0.5, 0.0, 1.5), Vector3::zeros());
        let a1 = Isometry3::new(Vector3::new(0.1, 0.0, 0.5), Vector3::new(0.0, 0.05, 0.0));
        let b1 = Isometry3::new(Vector3::new(0.7, 0.02, 1.45), Vector3::new(0.01, 0.08, 0.0));
        let (fa, fb) = frames_at_start(&p0, &a0, &b0, &a1, &b1);
        let wa = a1 * fa;
        let wb = b1 * fb;
        assert!((wa.translation.vector - wb.translation.vector).norm() < 1e-12);
        assert!(wa.rotation.angle_to(&wb.rotation) < 1e-12);
        // Undeformed start poses give BCB's frames A⁻¹·P exactly.
        let (fa0, fb0) = frames_at_start(&p0, &a0, &b0, &a0, &b0);
        let ea = a0.inverse() * p0;
        let eb = b0.inverse() * p0;
        assert!((fa0.translation.vector - ea.translation.vector).norm() < 1e-12);
        assert!((fb0.translation.vector - eb.translation.vector).norm() < 1e-12);
        assert!(fa0.rotation.angle_to(&ea.rotation) < 1e-12);
    }
}
