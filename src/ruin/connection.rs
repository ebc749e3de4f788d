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
//! The parts, one file each: [`rows`] (the constraints as plain data, their frames and
//! breaking impulses), [`capacity`] (capacities, tolerances and the spring of a contact's
//! connection, [`build_connections`]) and [`member`] (FE-derived member-end capacities);
//! this file holds the connection itself ([`ConnectionSpec`], its [`ConnectionState`]) and
//! the settings and group strengths it is built from.
mod capacity;
mod member;
mod rows;

pub use capacity::{build_connections, build_connections_with};
pub use member::{BodyCapacity, BodyStrength, EndStrength};
pub use rows::{ConstraintClass, ConstraintRole, ConstraintSpec, BCB_UNLIMITED};

use super::search::Contact;
use super::strength::StrengthSource;
use super::RuinError;
use serde::{Deserialize, Serialize};

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
    /// Group name, as in [`super::BodyGeom::group`].
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
    /// Blender and hence BCB use; see [`crate::bullet::Spring::limit_if_needed`]). On:
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
